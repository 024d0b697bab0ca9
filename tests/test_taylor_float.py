"""``TaylorFlight.evaluate_float`` (``reference.taylor_float``): float64 values of a position-forced
flight with *rigorous* error bounds, the event search's far-from-root accelerator; and the flight's
kept last state (``TaylorFlight.state``).  The bound check is seen to fail on a bound without its
rounding allowance, and the kept state by its comparison with a fresh flight."""
from __future__ import annotations

import mpmath
from hypothesis import given, settings, strategies as st

from reference import taylor_float
from reference.taylor import TaylorFlight
from tests.strategies import flight_starts, position_forced_scenes


def _violations(scene, t0, x0, v0, s, offsets):
    """The offsets ``h`` at which a float value lies farther from the flight (mpf at 30 digits,
    evaluated at 50) than its bound: ``[(h, which)]``."""
    bad = []
    with mpmath.workdps(30):
        fl = TaylorFlight(scene, t0, x0, v0, s)
        for h in offsets:
            x, v, a, da, ex, ev, ea, eda = fl.evaluate_float(h)
            t = fl.t_start + mpmath.mpf(h)
            X, V, A = fl.evaluate(t)
            DA = fl.jerk(t, X, V, A)
            for name, got, want, err in (("x", x, X, ex), ("v", v, V, ev), ("a", a, A, ea), ("a'", da, DA, eda)):
                if not abs(mpmath.mpf(got) - want) <= err:
                    bad.append((h, name))
    return bad


@settings(max_examples=15, deadline=None)
@given(data=st.data())
def test_float_values_lie_within_their_bounds(data):
    scene = data.draw(position_forced_scenes())
    t0, x0, v0, s = data.draw(flight_starts(scene))
    offsets = [0.0] + [data.draw(st.floats(0.0, 1.0)) * scene.period / 4 for _ in range(4)]
    assert _violations(scene, t0, x0, v0, s, offsets) == []


def test_a_bound_without_its_rounding_allowance_is_caught(monkeypatch):
    """The check says no when the Horner and libm allowances are dropped (noise floors only)."""
    from cross_check.scenes import scene

    sc = scene("fig:xpotno")
    offsets = [0.0, 0.13, 0.41, 0.77]
    assert _violations(sc, 0.1, 0.3, 1.7, 1, offsets) == []
    monkeypatch.setattr(taylor_float, "U", 0.0)
    monkeypatch.setattr(taylor_float, "E", 0.0)
    assert _violations(sc, 0.1, 0.3, 1.7, 1, offsets) != []


def test_the_kept_state_is_the_state():
    """``state`` keeps its last ``(t, x, v)``: asked again at ``t`` it gives the same values, at
    another ``t`` (before and after new Taylor steps) those of a flight that keeps nothing yet."""
    from cross_check.scenes import scene

    sc = scene("fig:xpotno")
    with mpmath.workdps(30):
        fl = TaylorFlight(sc, 0, "0.3", "1.7", 1)
        times = [mpmath.mpf(t) for t in ("0", "0.2", "0.2", "0.9", "0.35", "0.35", "0")]
        for t in times:
            assert fl.state(t) == TaylorFlight(sc, 0, "0.3", "1.7", 1).state(t)
        assert fl.state(times[1]) != fl.state(times[3])
