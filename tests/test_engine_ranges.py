"""What each engine can hold (issue 29): ``fast`` refuses by name at scene check what float64
cannot hold, never with a loop bound or a warning; the reference adds the digits a scene's
scales cost, and refuses by name where it cannot help."""
import re
import warnings
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings

import fast
import reference
from cross_check.tolerances import tol
from fast import ode
from fast import params as fast_params
from reference import model as ref_model
from reference.scene import Scene
from tests.strategies import extreme_scenes

BASE = dict(F=1, f=0, omega=1, l=0, r=1)


def _scene(**change):
    return Scene(**{**BASE, **change})


def _fast_params(scene):
    """The engine's scene check with every floating-point warning an error."""
    with warnings.catch_warnings(), np.errstate(all="raise"):
        warnings.simplefilter("error")
        return (ode.params if scene.has("position_forcing") else fast_params.params)(scene)


# --- fast ------------------------------------------------------------------------------------
@pytest.mark.parametrize("wavenumber", [None, 1], ids=["closed-form", "position-forcing"])
def test_a_speed_above_v_max_is_refused_by_name_and_v_max_itself_only_costs_events(wavenumber):
    """Issue 36: ``|v| = 1e300`` was accepted and ran into a loop bound (``v^2`` overflows near
    1.3e154).  Above ``V_MAX`` a ``ValueError`` names the bound; at it the state runs and only
    spends its event budget (impacts about ``|v| T / (r - l)`` a period), never a loop bound."""
    sc = _scene(f="0.1", omega=2, wavenumber=wavenumber)
    engine, P = fast.api._engine(sc)
    vmax = engine.max_speed(P)
    # the closed-form loop holds FAST_MAX; a numerical flight steps 2 pi/(S k |v|), at most 2^30 a period
    assert vmax == (1e100 if wavenumber is None else 2.0 ** 30 * 2 / (ode.STEPS_PER_PERIOD * 1))
    for v in (1e300, -1e101, np.nextafter(vmax, np.inf)):
        with pytest.raises(ValueError, match=r"is above \|v\| <= " + re.escape(f"{vmax:.6g}") + ", the largest speed"):
            fast.stroboscopic_map(sc, np.array([0.5, 0.5]), np.array([0.0, v]))
    with pytest.raises(RuntimeError, match=r"more than max_events = 1000 events") as info:
        fast.stroboscopic_map(sc, 0.5, -vmax, max_events=1000)
    assert "inner loop bound" not in str(info.value)


def test_a_numerical_flight_too_fast_for_float64_time_raises_instead_of_standing_still():
    """At ``|v| = 1e50`` under ``k = 1`` the step ``2 pi/(S k |v|)`` is far below the
    resolution of ``t``: with a float64 clock the flight was taken as finished and the start
    came back unchanged after a period (a silent wrong answer); the double-double clock does
    not resolve it either.  A start so fast is refused (``max_speed``); a
    motion that reaches such speeds raises ``TOO_FAST`` with the state (the kernel, driven
    directly past the API's check)."""
    sc = _scene(f="0.1", wavenumber=1)
    engine, P = fast.api._engine(sc)
    with pytest.raises(RuntimeError, match=r"fell below the resolution of its clock"):
        fast.batch.run(engine, P, np.array([0.5]), np.array([1e50]), P[ode.T], max_events=1000)


def test_elastic_bounces_at_a_wall_spend_the_event_budget_and_say_so():
    """Issue 36: elastic, frictionless bounces against a wall the (position-dependent) force
    pushes into do not shrink, so no tail can be summed: a start 1e-12 from the wall bounces
    ~2e5 times before the force turns.  They ran into a cap of 5000 bounces, raised as a loop
    bound; each is now an event of the caller's budget ``max_events``, and running out of it in
    such a run says so.  The same holds for the closed-form engine."""
    for sc in (_scene(wavenumber=1), _scene()):
        with pytest.raises(RuntimeError, match=r"more than max_events = 20000 events, the last of them a run of "
                                               r"bounces at one wall that does not sum to rest.*raise max_events"):
            fast.stroboscopic_map(sc, 1 - 1e-12, 0.0, max_events=20_000)
    x, v = fast.stroboscopic_map(_scene(wavenumber=1), 1 - 1e-12, 0.0, max_events=400_000)
    log = fast.events(_scene(wavenumber=1), 1 - 1e-12, 0.0, max_events=400_000)[0]
    impacts = [e for e in log if e.kind == "impact"]
    assert len(impacts) > 100_000 and {e.x for e in impacts[:100_000]} == {1.0}    # bounce by bounce at r
    assert np.isfinite(x) and x < 0.5 and v < 0                            # then the force turned
def test_the_issue_examples_are_refused_by_name_without_a_warning():
    with pytest.raises(ValueError, match=r"^fast: F = 1\.0e\+309 \(from F = '1e308\*10'\)"):
        fast.stroboscopic_map(_scene(F="1e308*10"), 0.5, 0.0)       # was a loop-bound RuntimeError
    with pytest.raises(ValueError, match=r"^fast: F = 1\.0e\+300 \(from F = 1e\+300\)"):
        _fast_params(_scene(F=1e300, omega=1e-300))                  # was an overflow warning


@pytest.mark.parametrize("change, label", [
    (dict(F="1e101"), "F"),
    (dict(F="1e-200"), "F"),
    (dict(f="1e101"), "f"),
    (dict(r="1e-120"), "r - l"),
    (dict(F="1e60", omega="1e-30", r="1e95"), "F/omega^2"),
    (dict(omega="1e-100"), "omega"),
    (dict(omega="2e-100"), "T = 2 pi/omega"),
    (dict(l=1, r="1 + 1e-12"), "(r - l)/max(|l|, |r|)"),
    (dict(F="1e99", omega="0.1"), "sqrt(2 (r - l)/F)/T"),
    (dict(damping="40"), "damping/omega"),
    (dict(damping="1e-13"), "damping/omega"),
    (dict(F="1e25", r="1e20", damping=1), "(F + f)/omega with damping"),
    (dict(wavenumber="1e50", r="1e60"), "wavenumber max(|l|, |r|)"),
    (dict(wavenumber="1e17"), "steps per period"),
])
def test_fast_refuses_each_quantity_by_name(change, label):
    with pytest.raises(ValueError, match=rf"^fast: {re.escape(label)} = .* \(from .*\) is (above|below)"):
        _fast_params(_scene(**change))


@pytest.mark.parametrize("change", [
    dict(F="2e-100"), dict(F="1e100", r="1e100"), dict(damping="30"), dict(damping="1e-12"),
    dict(l=1, r="1 + 2**-35"), dict(F="1e19", r="1e20", damping=1), dict(wavenumber="1e13"),
])
def test_fast_runs_the_scenes_just_inside_its_bounds(change):
    scene = _scene(f="0.1", **change)       # friction: chatter is summed, a state comes to rest
    P = _fast_params(scene)
    assert np.isfinite(P).all()
    if scene.has("position_forcing"):
        return                              # 3e8 fixed steps a period: beyond a test's budget
    l, r = scene.float("l"), scene.float("r")
    x, v = fast.stroboscopic_map(scene, np.array([l, 0.5 * (l + r)]), np.zeros(2), max_events=10 ** 5)
    assert np.all((l <= x) & (x <= r)) and np.isfinite(v).all()


@settings(max_examples=60)
@given(extreme_scenes())
def test_no_floating_point_warning_escapes_fast_params_on_any_scene(scene):
    try:
        P = _fast_params(scene)
    except ValueError as err:
        assert str(err).startswith("fast: ")
        return
    assert np.isfinite(P).all()


@settings(max_examples=15)
@given(extreme_scenes(position_forcing=True))
def test_no_floating_point_warning_escapes_the_position_forced_params(scene):
    try:
        assert np.isfinite(_fast_params(scene)).all()
    except ValueError as err:
        assert str(err).startswith("fast: ")


def test_a_huge_velocity_scale_no_longer_stalls_the_event_search():
    """The event-carrying step ``d_acc`` is relative to ``F/w`` where that is huge: with the
    absolute one it fell below the resolution of ``T`` and the loop bound ended the state."""
    scene = Scene(F="1e27", f=0, omega="1e-9", l="0.1", r="0.1 + 1e29", restitution="0.5")
    x, v = fast.stroboscopic_map(scene, np.array([0.1, 3e28]), np.array([0.0, 1e36]))
    assert np.isfinite(x).all() and np.isfinite(v).all()


# --- the issue's extreme but legal scenes, in both engines -----------------------------------
_EXTREME = {
    "F = 1e-200": dict(F="1e-200", f="0.1"),
    "omega = 1e6": dict(f="0.1", omega="1e6"),
    "gap 1e-12": dict(f="0.1", r="1e-12"),
    "gap 1e-12 at l = 1": dict(f="0.1", l=1, r="1 + 1e-12"),
}


def _scale(scene):
    """The scene's position and velocity scales (both engines' noise floors are relative to
    them): ``max(|l|, |r|, r - l, F/w^2)`` and ``F/w + (r - l) w + f T``."""
    F, f, w, l, r = (float(scene.mpf(k)) for k in ("F", "f", "omega", "l", "r"))
    return max(abs(l), abs(r), r - l, F / w ** 2), F / w + (r - l) * w + f * 2 * np.pi / w


@pytest.mark.parametrize("name", sorted(_EXTREME))
def test_extreme_scenes_are_answered_alike_or_refused_by_name_in_both_engines(name):
    scene = _scene(**_EXTREME[name])
    l, r = scene.exact("l"), scene.exact("r")
    states = [(l + (r - l) * u, 0) for u in (0, Fraction(3, 10), 1)]
    answers = {}
    for x, v in states:
        try:
            answers["reference"] = reference.stroboscopic_map(scene, x, v, dps=30)
        except ValueError as err:
            assert str(err).startswith("reference: ")
            continue
        try:
            answers["fast"] = fast.stroboscopic_map(scene, float(x), float(v))
        except ValueError as err:
            assert str(err).startswith("fast: ") and "from" in str(err)
            continue
        xs, vs = _scale(scene)
        t = tol("engines_scaled_one_period")
        assert abs(float(answers["fast"][0]) - float(answers["reference"][0])) <= t.atol * xs
        assert abs(float(answers["fast"][1]) - float(answers["reference"][1])) <= t.atol * vs
    assert answers, f"{name}: neither engine answered"


# --- reference -------------------------------------------------------------------------------
def test_the_reference_adds_the_digits_a_tiny_gap_costs_and_is_wrong_without_them(monkeypatch):
    scene = _scene(f="0.1", l="1e30", r="1e30 + 1")
    x30, v30 = reference.stroboscopic_map(scene, "1e30", 0, dps=30)
    x50, v50 = reference.stroboscopic_map(scene, "1e30", 0, dps=50)
    assert abs(v30 - v50) <= tol("ref_self_dps30").atol
    # without the extra digits the safety net refuses, and at the dps it asks for, only
    # about 5 digits of v are right: the extra digits are what makes dps = 30 hold
    monkeypatch.setattr(ref_model, "FREE_DIGITS", 10 ** 6)
    with pytest.raises(ValueError, match=r"^reference: the gap r - l .*needs dps >= (\d+)") as info:
        reference.stroboscopic_map(scene, "1e30", 0, dps=15)
    needed = int(re.search(r"needs dps >= (\d+)", str(info.value)).group(1))
    x_n, v_n = reference.stroboscopic_map(scene, "1e30", 0, dps=needed)
    assert abs(v_n - v50) > 1e6 * tol("ref_self_dps30").atol


@pytest.mark.parametrize("change, fragment", [
    (dict(F="1e300", omega="1e-300"), "the gap r - l"),
    (dict(f="0.1", l="-1e1000", r="1e1000"), "the forcing's velocity F/omega"),
    (dict(damping="129"), "damping/omega"),
])
def test_the_reference_refuses_by_name_where_it_cannot_help(change, fragment):
    with pytest.raises(ValueError, match=rf"^reference: {re.escape(fragment)}"):
        reference.stroboscopic_map(_scene(**change), "0", 0, dps=15)


def test_a_time_span_of_many_periods_costs_digits_not_accuracy():
    scene = _scene(f="0.1", omega="2*pi")
    extra, what = ref_model.extra_digits(scene, 10 ** 40)
    assert extra == 37 and "time span" in what
    assert ref_model.extra_digits(scene, 10)[0] == 0
