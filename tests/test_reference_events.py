"""The pieces the certification rests on: safe steps, float error bounds, flight closed
forms, tail extrapolation of chatter."""
import importlib

import mpmath
import pytest
from hypothesis import example, given
from hypothesis import strategies as st
from mpmath import mpf

from reference import chatter
from reference.model import Model
from tests.strategies import REFERENCE_SCENES, exact_states
from tests.test_reference_properties import naive_flight

events = importlib.import_module("reference.events")
SCENES = sorted(REFERENCE_SCENES)


@given(st.floats(0, 10), st.floats(-10, 10), st.floats(1e-6, 100),
       st.integers(-60, 0))
@example(g=1.0, dg=-1.383950664005721e-169, M=1.0, e=0)     # dg^2 underflows in float64
@example(g=5e-324, dg=0.0, M=1.0, e=-1)   # g below float64's range: h* itself, unshrunk, overshot
@example(g=3.0, dg=0.0, M=1.0, e=-324)   # g = 3e-324: float(g) = 5e-324, 66 % high
def test_safe_step_never_jumps_a_root_of_the_quadratic_bound(g, dg, M, e):
    """``g + dg h - M h^2/2 >= 0`` at the returned ``h`` (exactly, at 100 digits)."""
    with mpmath.workdps(60):
        g = mpf(g) * mpf(10) ** e                            # down to 1e-60: near a root
        h = events.safe_step(g, mpf(dg), mpf(M))
        assert h >= 0
        if h != mpmath.inf:
            with mpmath.workdps(100):
                assert g + dg * h - M * h * h / 2 >= 0


def test_safe_step_converges_quadratically_to_a_simple_root():
    with mpmath.workdps(80):
        root, M = mpf(1) / 3, mpf(1)
        g = lambda t: (root - t) * (1 + (root - t) / 4)        # g'' = 1/2 <= M
        dg = lambda t: -1 - (root - t) / 2
        t, steps = mpf(0), 0
        while g(t) > mpf(10) ** -70:
            t += events.safe_step(g(t), dg(t), M)
            steps += 1
            assert t <= root
        assert steps <= 8


@pytest.mark.parametrize("name", SCENES)
@given(data=st.data())
def test_flight_formulas_and_float_error_bounds(name, data):
    """BaseFlight.evaluate equals the plain closed form; evaluate_float is within its bounds."""
    scene = REFERENCE_SCENES[name]
    x0, v0 = data.draw(exact_states(scene, vmax=3.0))
    t0 = data.draw(st.floats(0, 50))
    h = data.draw(st.one_of(st.floats(0, 8), st.floats(0, 1e-6)))
    s = 0 if scene.f == "0" else (1 if float(v0) >= 0 else -1)
    with mpmath.workdps(62):
        model = Model(scene)
        flight = model.flight(mpf(t0), mpf(x0), mpf(v0), s)
        x, v, a = flight.evaluate(mpf(t0) + mpf(h))
        fx = flight.evaluate_float(h)
        with mpmath.workdps(100):
            F, f, w = (scene.mpf(k) for k in ("F", "f", "omega"))
            xe, ve = naive_flight(F, f, w, mpf(t0), mpf(x0), mpf(v0), s, mpf(t0) + mpf(h))
            ae = F * mpmath.cos(w * (mpf(t0) + h)) - s * f
            je = -F * w * mpmath.sin(w * (mpf(t0) + h))
            scale = 1 + abs(mpf(x0)) + abs(mpf(v0)) * (1 + h) + F * (1 + h) ** 2
            assert abs(x - xe) < mpf(10) ** -55 * scale and abs(v - ve) < mpf(10) ** -55 * scale
            assert abs(a - ae) < mpf(10) ** -55 * scale
            for value, err, exact in zip(fx[:4], fx[4:], (xe, ve, ae, je)):
                assert abs(value - exact) <= err, (value, exact, err)


def test_theta_minus_sin_keeps_relative_precision_for_tiny_steps():
    """A flight of length 1e-20: x - x0 - v0 h is ~1e-40 and must keep its digits."""
    scene = REFERENCE_SCENES["narrow_f0"]
    with mpmath.workdps(50):
        flight = Model(scene).flight(mpf("0.7"), mpf("0.4"), mpf("0.1"), 0)
        h = mpf("1e-20")
        x, v, a = flight.evaluate(mpf("0.7") + h)
    with mpmath.workdps(120):
        exact = naive_flight(1, 0, 1, mpf("0.7"), mpf("0.4"), mpf("0.1"), 0, mpf("0.7") + h)[0]
        assert abs(x - exact) < mpf(10) ** -49


def test_tail_extrapolation_of_a_geometric_bounce_sequence():
    """Points on an analytic fibre t = t_inf + R(u): Neville at u = 0 recovers t_inf, and
    Wynn's epsilon agrees on the same times."""
    with mpmath.workdps(60):
        t_inf, lam = mpf("0.123"), mpf("0.6")
        us = [lam ** n / 10 for n in range(25)]
        ts = [t_inf - 3 * u - u ** 2 + 5 * u ** 3 for u in us]      # R(u) analytic
        assert abs(chatter.extrapolate_to_zero(us[-15:], ts[-15:]) - t_inf) < mpf(10) ** -50
        assert abs(chatter.wynn_epsilon(ts[-21:]) - t_inf) < mpf(10) ** -30


def test_chatter_run_detection_resets_on_other_events():
    run = chatter.BounceRun()
    for k in range(4):
        run.observe("impact", 1)
        run.add_impact(mpf(k), mpf(1) / (k + 1))
        run.observe("turn")
    assert run.count == 4
    run.observe("stick")
    assert run.count == 0
    run.observe("impact", 1)
    run.add_impact(mpf(5), mpf(1))
    run.observe("impact", -1)                                # other wall: a new run
    run.add_impact(mpf(6), mpf(1))
    assert run.count == 1 and run.wall_side == -1


class _Quartic:
    """``x(t) = c t^4`` toward a wall at ``R``, with event bounds that hold only over the first
    ``W`` of any window asked for (``|x''| = 12 c t^2 <= 12 c (ta + min(tb - ta, W))^2``): the
    search is certified on it only if it keeps its steps within ``max_window``."""

    def __init__(self, W, floats):
        self.c, self.W, self.max_window = mpf(1), mpf(W), mpf(W)
        self.t_start, self.s = mpf(0), 1
        self.noise_x = self.noise_v = self.noise_a = mpf(2) ** (-mpmath.mp.prec + 8)
        if floats:
            self.evaluate_float = self._float

    def evaluate(self, t):
        return self.c * t ** 4, 4 * self.c * t ** 3, 12 * self.c * t ** 2

    def jerk(self, t, x, v, a):
        return 24 * self.c * t

    def _top(self, ta, tb):
        return ta + min(tb - ta, self.W)

    def bound_x2(self, ta, tb):
        return 12 * self.c * self._top(ta, tb) ** 2

    def bound_v2(self, ta, tb):
        return 24 * self.c * self._top(ta, tb)

    def bound_a2(self, ta, tb):
        return 24 * self.c

    def _float(self, h):
        x, v, a, j = (float(q) for q in self.evaluate(mpf(h)) + (self.jerk(mpf(h), 0, 0, 0),))
        return x, v, a, j, *(abs(q) * 4e-16 + 1e-300 for q in (x, v, a, j))


@pytest.mark.parametrize("floats", [False, True])
def test_the_search_keeps_its_steps_within_the_window_of_its_bounds(floats):
    """``find_next_event`` with ``max_window`` (``reference.taylor``'s flights: ``T / 8``) asks
    its bounds over windows of at most that length and steps no further: on a flight whose
    bounds hold only so far, it finds the wall at ``t* = R^(1/4)``.  Had it stepped by the
    bound of a window longer than its own (the same flight, its window not declared), it
    jumps the wall: the cap is what keeps the certificate."""
    R = mpf(16)
    with mpmath.workdps(40):
        fl = _Quartic(mpf("0.3"), floats)
        fn, t, _ = events.find_next_event(fl, [events.WallHit(1, R)], mpf(10))
        assert fn is not None and abs(t - 2) < mpf(10) ** -30
        liar = _Quartic(mpf("0.3"), floats)
        liar.max_window = None          # bounds still cut at W, but the search is not told
        fn, t, _ = events.find_next_event(liar, [events.WallHit(1, R)], mpf(10))
        assert fn is None or t > 2
