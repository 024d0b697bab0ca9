"""reference's public API: argument checks, input conversion, precision context, results."""
from fractions import Fraction

import mpmath
import pytest

import reference
from reference import Scene
from tests.strategies import REFERENCE_SCENES

NARROW = REFERENCE_SCENES["narrow_f0005"]


@pytest.mark.parametrize("dps", [14, 0, -3, 15.0, "50", True, None, 10001])
def test_bad_dps(dps):
    for call in (lambda: reference.stroboscopic_map(NARROW, "0.3", "0.5", dps=dps),
                 lambda: reference.jacobian(NARROW, "0.3", "0.5", dps=dps),
                 lambda: reference.trajectory(NARROW, "0.3", "0.5", 1, dps=dps)):
        with pytest.raises(ValueError, match=r"dps must be an integer >= 15"):
            call()


@pytest.mark.parametrize("periods, error", [(-1, ValueError), (1.0, TypeError), ("2", TypeError),
                                           (True, TypeError), (None, TypeError)])
def test_bad_periods(periods, error):
    with pytest.raises(error, match=r"periods must be an integer >= 0"):
        reference.stroboscopic_map(NARROW, "0.3", "0.5", periods=periods)


def test_zero_periods_is_the_identity_as_in_fast():
    """``periods = 0`` returns the start, rounded to ``dps`` (``fast`` does the same)."""
    for dps, x0, v0 in ((20, "0.3", "-0.5"), (30, "0.1", "1e-25")):
        x, v = reference.stroboscopic_map(NARROW, x0, v0, periods=0, dps=dps)
        with mpmath.workdps(dps):
            assert (x, v) == (mpmath.mpf(x0), mpmath.mpf(v0))


@pytest.mark.parametrize("max_events, error", [(0, ValueError), (-5, ValueError),
                                               (2.5, TypeError), (None, TypeError)])
def test_bad_event_budget(max_events, error):
    for call in (lambda: reference.stroboscopic_map(NARROW, "0.3", "0.5", max_events=max_events),
                 lambda: reference.jacobian(NARROW, "0.3", "0.5", max_events=max_events),
                 lambda: reference.trajectory(NARROW, "0.3", "0.5", 1, max_events=max_events)):
        with pytest.raises(error, match=r"max_events must be an integer >= 1"):
            call()


def test_event_budget_stops_a_state_that_needs_many_impacts():
    """A gap of 1e-9 with v = 1: ~6e9 impacts per period; the budget stops it at once,
    naming the budget, the events logged and the state."""
    tiny = Scene(F=1, f=0, omega=1, l=0, r="1e-9")
    with pytest.raises(RuntimeError, match=r"more than max_events = 100 events .*100 logged\) "
                                           r".*\(t, x, v, mode\) = \("):
        reference.stroboscopic_map(tiny, "5e-10", "1", dps=20, max_events=100)


@pytest.mark.parametrize("x", ["-0.0000001", "0.8000001", 0.8, -1e-300, "1e9"])
def test_state_outside_the_walls(x):
    # 0.8 as a float is 0.8000000000000000444 > 4/5: outside the exact wall r = "0.8"
    for call in (lambda: reference.stroboscopic_map(NARROW, x, "0.5"),
                 lambda: reference.jacobian(NARROW, x, "0.5"),
                 lambda: reference.trajectory(NARROW, x, "0.5", 1)):
        with pytest.raises(ValueError, match=r"x must lie in the closed gap \[l, r\] = \[0, 0.8\]"):
            call()


@pytest.mark.parametrize("name,value", [("x", float("nan")), ("x", float("inf")),
                                        ("v", float("nan")), ("v", float("-inf")),
                                        ("v", "inf"), ("x", "abc"), ("v", [1]), ("x", True)])
def test_non_finite_or_bad_state(name, value):
    args = {"x": "0.3", "v": "0.5", name: value}
    with pytest.raises(ValueError, match=rf"^{name} must"):
        reference.stroboscopic_map(NARROW, args["x"], args["v"])


def test_bad_times_and_scene():
    with pytest.raises(ValueError, match=r"t_end must be >= t0"):
        reference.trajectory(NARROW, "0.3", "0.5", 1, t0=2)
    with pytest.raises(ValueError, match=r"t_end must be finite"):
        reference.trajectory(NARROW, "0.3", "0.5", float("inf"))
    with pytest.raises(ValueError, match=r"t0 must be"):
        reference.trajectory(NARROW, "0.3", "0.5", 1, t0="x")
    with pytest.raises(TypeError, match=r"scene must be a reference.Scene, got dict"):
        reference.stroboscopic_map({"F": 1}, "0.3", "0.5")


def test_walls_are_in_the_closed_gap():
    for x in ("0", "0.8", 0, Fraction(4, 5)):
        reference.stroboscopic_map(NARROW, x, "0", dps=15)


def test_no_precision_leak():
    before = (mpmath.mp.prec, mpmath.mp.dps)
    reference.stroboscopic_map(NARROW, "0.3", "0.5", dps=40)
    reference.jacobian(NARROW, "0.3", "0.5", dps=40)
    reference.trajectory(NARROW, "0.3", "0.5", 3, dps=40)
    with pytest.raises(ValueError):
        reference.stroboscopic_map(NARROW, "0.9", "0.5", dps=40)
    assert (mpmath.mp.prec, mpmath.mp.dps) == before
    with mpmath.workdps(100):                       # a caller at another precision
        reference.stroboscopic_map(NARROW, "0.3", "0.5", dps=20)
        assert mpmath.mp.dps == 100
    assert (mpmath.mp.prec, mpmath.mp.dps) == before


def test_results_are_rounded_to_dps():
    x, v = reference.stroboscopic_map(NARROW, "0.3", "0.5", dps=20)
    with mpmath.workdps(20):
        assert +x == x and +v == v
    with mpmath.workdps(60):
        x60, v60 = reference.stroboscopic_map(NARROW, "0.3", "0.5", dps=60)
        assert abs(x60 - x) <= mpmath.mpf(10) ** -19 and abs(v60 - v) <= mpmath.mpf(10) ** -19


def test_inputs_converted_exactly():
    """A float is its binary value; a string is its decimal value (they differ)."""
    with mpmath.workdps(60):
        a = reference.stroboscopic_map(NARROW, 0.3, "0.5", dps=40)
        b = reference.stroboscopic_map(NARROW, "0.3", "0.5", dps=40)
        c = reference.stroboscopic_map(NARROW, mpmath.mpf(0.3), Fraction(1, 2), dps=40)
        assert a == c
        # 0.3 - float(0.3) = 1.1e-17, carried through Phi (entries of Phi' up to ~5 here)
        assert 1e-15 > abs(a[0] - b[0]) > 1e-18


def test_event_log_shape():
    log = reference.trajectory(NARROW, "0.3", "0.5", 7, dps=20)
    assert isinstance(log, list) and log
    assert all(isinstance(e, reference.Event) and e.kind in reference.KINDS for e in log)
    assert [e.t for e in log] == sorted(e.t for e in log)
    with pytest.raises(Exception):
        log[0].t = 0                                 # frozen
    assert log.t_end == 7 and log.mode_end in ("flight", "stick", "contact")
    J = reference.jacobian(NARROW, "0.3", "0.5", dps=20)
    assert J[1][0] == J[1][0] and len(J) == 2 and len(J[0]) == 2


def test_scene_effects_are_never_ignored():
    """Each effect of the scene changes the result of the map and of the Jacobian."""
    base = Scene(F=1, f="0.1", omega=1, l=0, r=1)
    plain = reference.stroboscopic_map(base, "0.5", "0.3", dps=20)
    for change in ({"damping": "0.1"}, {"restitution": "0.9"}):
        other = reference.stroboscopic_map(base.replace(**change), "0.5", "0.3", dps=20)
        assert other != plain, change
    xpot = base.replace(wavenumber="pi/2")
    assert reference.stroboscopic_map(xpot, "0.5", "0.3", dps=20) != plain
    assert reference.jacobian(xpot, "0.5", "0.3", dps=20) != reference.jacobian(base, "0.5", "0.3", dps=20)
