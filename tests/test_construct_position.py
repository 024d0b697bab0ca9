"""fast finds every constructed event under position forcing (issue 33): starts built backward
from a known first event by ``cross_check.agreement.construct_position`` (a float64 Taylor flight
of its own, ``backflight``, independent of both integrators), over 1e3 in the default run and
1e5 in a ``slow`` test, on two unseen scenes, eq. xpot and random scenes.  Outside the band (the
start's rounding and the construction's error, carried to the event) the constructed event must
come first, of its kind, at its time; everywhere nothing may be invented before it.

A chatter run's end is its ``chatter`` event or, equivalently in ``compare.canonical``, the
``contact`` that closes the run of impacts.
"""
import mpmath
import numpy as np
import pytest
from hypothesis import given, settings

import reference
from cross_check.agreement import backflight, construct as C, construct_position as CP
from reference.scene import Scene
from reference.taylor import TaylorFlight
from tests.strategies import position_forced_scenes

SCENES = {
    "A": Scene(F=1, f="0.15", omega="1.7", l="-0.4", r="0.9", wavenumber="1.3"),
    "B": Scene(F=2, f="0.3", omega="1.2", l=-1, r=1, restitution="0.8", damping="0.05", wavenumber="0.7"),
    "xpot": Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2"),
}


def first_events(scene, cases):
    """fast's first events; a chatter run ends at its ``chatter`` or its closing ``contact``."""
    return C.first_events(scene, cases, run_ends=("chatter", "contact"))


def _check(scene, n, seed):
    cases = CP.construct(scene, n, seed=seed)
    result = C.verify(cases, *first_events(scene, cases))
    for name in ("missed", "invented", "wrong_time"):
        idx = result[name][:5]
        assert not idx.size, (name, [(C.KINDS[cases.kind[i]], cases.x[i], cases.v[i], cases.t_star[i])
                                     for i in idx])
    return cases, result


@pytest.mark.parametrize("name", list(SCENES))
def test_every_constructed_event_is_found(name):
    """Over 1e3 cases in all (120 of each kind a scene admits, three scenes)."""
    cases, result = _check(SCENES[name], 120, seed=21)
    kinds = set(np.array(C.KINDS)[cases.kind])
    assert len(cases) >= 480 and result["band"] < len(cases)
    assert {"crossing_pair", "tangency", "turn", "stick"} <= kinds


@pytest.mark.slow
@pytest.mark.parametrize("name", list(SCENES))
def test_a_hundred_thousand_constructed_events_are_found(name):
    """1e5 cases in all (7000 of each kind a scene admits, three scenes)."""
    _check(SCENES[name], 7000, seed=22)


@settings(max_examples=6)
@given(position_forced_scenes(restitutions=("1", "0.9", "0.6")))
def test_constructed_events_are_found_on_random_scenes(scene):
    """Every parameter and effect drawn (``position_forced_scenes``), 30 cases of each kind."""
    _check(scene, 30, seed=23)


def test_a_close_pair_shallower_than_the_tangent_floor_is_timed_at_its_first_root():
    """Case 4801 of the slow run on scene A (seed 22): a crossing pair 1.2e-14 deep, out of the
    band but within fast's tangent floor (64 eps).  fast took the dip's minimum for the root, half
    the pair's width (1.5e-7) late; the reference, forward at 30 digits, puts the impact at t*."""
    scene = SCENES["A"]
    x, v, t_star, tol = -0.37653766598553956, -0.21829192222162155, 0.21762580636873952, 4.156358153904848e-09
    first = reference.trajectory(scene, x, v, 0.3, dps=30)[0]
    assert first.kind == "impact" and abs(float(first.t) - t_star) <= tol / 8, first
    cases = C.Cases(np.array([C.KINDS.index("crossing_pair")]), np.array([x]), np.array([v]), np.array([t_star]),
                    np.array([1.2458524476591591e-14]), np.array([False]), np.array([tol]))
    result = C.verify(cases, *first_events(scene, cases))
    assert not any(result[k].size for k in ("missed", "invented", "wrong_time")), result


def test_the_construction_agrees_with_the_reference():
    """A sample of the non-band cases, integrated forward by the reference at 30 digits: the
    same first event at the constructed time (chatter: an accumulation before the push ends)."""
    for scene in (SCENES["A"], SCENES["B"]):
        cases = CP.construct(scene, 30, seed=24)
        kinds = np.array(C.KINDS)[cases.kind]
        for k in C.KINDS:
            for i in np.flatnonzero((kinds == k) & ~cases.in_band)[:2]:
                end = cases.t_star[i] + cases.margin[i] if k == "chatter" else scene.period
                got = reference.trajectory(scene, float(cases.x[i]), float(cases.v[i]), float(end), dps=30)
                names = [e.kind for e in got]
                if k == "chatter":
                    assert "chatter" in names or names[-1:] == ["contact"], (i, names)
                else:
                    assert names[0] == C.FIRST_EVENT[k], (k, i, names)
                    assert abs(float(got[0].t) - cases.t_star[i]) <= cases.time_tol[i], (k, i, got[0])


def _reversed(scene):
    class Reversed:
        def mpf(self, name):
            return -scene.mpf(name) if name == "damping" else scene.mpf(name)
    return Reversed()


def _event_states(scene, seed, n):
    """``n`` event states ``(t*, x*, v*, s)`` across the gap and the period (arrays)."""
    rng = np.random.default_rng(seed)
    t = rng.uniform(0.05, 1.0, n) * scene.period
    x = scene.float("l") + (scene.float("r") - scene.float("l")) * rng.uniform(0.05, 0.95, n)
    v = rng.uniform(-1, 1, n) * scene.float("F") / scene.float("omega")
    return t, x, v, np.where(v >= 0, 1.0, -1.0)


@settings(max_examples=8)
@given(position_forced_scenes(restitutions=("1", "0.9", "0.6")))
def test_the_construction_error_bound_holds(scene):
    """``backflight``'s claim: the forward flight from its float64 start reaches the event
    state within ``(dx, dv)`` -- checked by the reference's Taylor flight at 40 digits, forward
    from the float64 start (exact binary numbers), on event states across the gap."""
    t, x, v, s = _event_states(scene, 25, 6)
    bk = backflight.run(backflight.Params.of(scene), t, x, v, s, C.SAMPLES)
    checked = 0
    for i in np.flatnonzero(bk.ok):
        with mpmath.workdps(40):
            xe, ve = TaylorFlight(scene, 0, mpmath.mpf(bk.x0[i]), mpmath.mpf(bk.v0[i]), int(s[i])).state(
                mpmath.mpf(t[i]))
            assert abs(xe - x[i]) <= bk.dx[i] and abs(ve - v[i]) <= bk.dv[i], (i, float(xe - x[i]), bk.dx[i],
                                                                                float(ve - v[i]), bk.dv[i])
        checked += 1
    assert checked >= 1


@settings(max_examples=6)
@given(position_forced_scenes())
def test_a_screen_without_the_flight_matrices_is_the_same_flight(scene):
    """``backflight.run(..., matrices=False)`` (the hard cases' float screen) gives the same
    samples, Gronwall errors, ``vmax``, start and ``ok`` bit for bit, and no event-state error
    (NaN): the certificate reads none of it, so it passes the same candidates."""
    t, x, v, s = _event_states(scene, 26, 5)
    P = backflight.Params.of(scene)
    full, screen = (backflight.run(P, t, x, v, s, C.SAMPLES, matrices=m) for m in (True, False))
    for name in ("x", "v", "err", "vmax", "x0", "v0", "ok"):
        assert np.array_equal(getattr(full, name), getattr(screen, name), equal_nan=True), name
    assert np.isnan(screen.dx).all() and np.isnan(screen.dv).all() and np.isfinite(full.dx[full.ok]).all()


def test_the_certificate_refuses_a_backward_flight_that_meets_an_earlier_event():
    """Event states whose backward flight leaves the gap (an impact at r arrived at so fast that
    the flight crosses l before t = 0) or passes v = 0 (a turn before t*) are refused; the same
    states made harmless (short flights) pass: the certificate is not vacuous."""
    scene = SCENES["A"]
    F, f, w, l, r, c, k, _ = CP.params(scene)
    T = scene.period
    t = np.array([0.9 * T, 0.05 * T, 0.9 * T, 0.05 * T])
    x = np.array([r, r, 0.2, 0.2])
    v = np.array([3.0, 3.0, 0.0, 0.0])
    s = np.array([1.0, 1.0, -1.0, -1.0])                  # x'' < 0 into r; -A - f < 0 at the stops
    decel = s * F * np.cos(k * x) * np.cos(w * t) - f - c * np.abs(v)
    bk, ok = CP.backward(scene, t, x, v, s, decel)
    assert bk.x0[0] < l                                   # the flight really crosses l
    assert not ok[0] and ok[1]
    ref = [e.kind for e in reference.trajectory(scene, float(bk.x0[2]), float(bk.v0[2]), float(t[2]), dps=20)
           if e.kind != "stick"] if l <= bk.x0[2] <= r else ["outside"]
    assert ref, "the long velocity case must meet an earlier event (or leave the gap)"
    assert not ok[2] and ok[3]


def _refused_rows(scene, t, s, bk):
    """Per flight, whether ``construct_position._refused`` refuses it on all its samples (given in
    turn, as ``backflight.run`` gives them, with the run's final ``vmax``: the certificate's)."""
    lost, lanes = CP._refused(scene, t, s), np.arange(t.size)
    for j in range(1, bk.x.shape[0]):
        out = lost(bk.x[j], bk.v[j], bk.err[j], bk.vmax, lanes)
    return out


@settings(max_examples=8)
@given(position_forced_scenes(restitutions=("1", "0.9", "0.6")))
def test_a_flight_the_screen_gives_up_on_fails_the_whole_certificate(scene):
    """``_refused`` (the screen's early stop) says no only to flights that the whole run's
    certificate refuses too, on event states across the gap and the period; a screen that gives
    up on some flights refuses them, and runs the others to a start within both runs' error
    bounds of the whole run's (fewer substeps where the flights given up needed more)."""
    F, f, w, l, r, c, k, _ = CP.params(scene)
    t, x, v, s = _event_states(scene, 27, 40)
    decel = s * F * np.cos(k * x) * np.cos(w * t) - f - c * np.abs(v)
    bk, ok = CP.backward(scene, t, x, v, s, decel, matrices=False)
    assert not (_refused_rows(scene, t, s, bk) & ok).any()
    screen, screened = CP.backward(scene, t, x, v, s, decel, matrices=False, give_up=True)
    ran = np.isfinite(screen.x0)
    assert not screened[~ran].any()
    assert not (~ran & ok).any()
    bound = screen.err[-1] + bk.err[-1]
    both = ran & np.isfinite(bk.x0)
    assert (np.abs(screen.x0 - bk.x0)[both] <= bound[both]).all()
    assert (np.abs(screen.v0 - bk.v0)[both] <= bound[both]).all()


def test_the_screen_gives_up_on_the_flights_that_fail_and_runs_the_others():
    """Two impacts at r so fast that they cross l before t = 0 (the wall behind them) and a stop
    whose flight turns before t* (``s v`` below the floor) are given up on, early: their rows after
    that and their starts are NaN, ``ok`` False, as the whole run's certificate says; a harmless
    flight among them runs to ``t = 0`` and passes, as in the whole run."""
    scene = SCENES["A"]
    F, f, w, l, r, c, k, _ = CP.params(scene)
    T = scene.period
    t = np.array([0.9 * T, 0.8 * T, 0.9 * T, 0.05 * T])
    x = np.array([r, r, 0.2, r])
    v = np.array([3.0, 3.5, 0.0, 3.0])
    s = np.array([1.0, 1.0, -1.0, 1.0])
    decel = s * F * np.cos(k * x) * np.cos(w * t) - f - c * np.abs(v)
    whole, ok = CP.backward(scene, t, x, v, s, decel, matrices=False)
    assert list(ok) == [False, False, False, True]
    assert list(_refused_rows(scene, t, s, whole)) == [True, True, True, False]
    behind = np.where(s > 0, whole.x[1:] + whole.err[1:] < l, whole.x[1:] - whole.err[1:] > r)
    assert behind[:, :2].any(axis=0).all() and not behind[:, 2].any()     # two by the wall, one by the floor
    screen, verdict = CP.backward(scene, t, x, v, s, decel, matrices=False, give_up=True)
    assert list(verdict) == list(ok)
    assert np.isnan(screen.x0[:3]).all() and np.isnan(screen.v[-1, :3]).all()
    assert np.isfinite(screen.v[:, 3]).all() and np.isfinite(screen.x0[3])
    with pytest.raises(ValueError, match="matrices=False"):
        backflight.run(backflight.Params.of(scene), t, x, v, s, C.SAMPLES, True, lost=CP._refused(scene, t, s))


def test_bad_arguments():
    with pytest.raises(ValueError, match="position forcing"):
        CP.params(Scene(F=1, f="0.1", omega=1, l=0, r=1))
    with pytest.raises(ValueError, match="unknown kind"):
        CP.construct(SCENES["A"], 5, kinds=("bounce",))
    with pytest.raises(ValueError, match="n must be an integer >= 1"):
        CP.construct(SCENES["A"], 0)
