"""fast's event search is certified only while its float64 flight values stay within the noise
floors it declares (issue 24).

``fast.roots._plan`` certifies the next event from float64 values of the flight
(``fast.flight.evaluate``: ``dx = x - x0``, ``v``, ``cos wt``, ``sin wt``) and treats an event
function within its noise floor of zero as zero:

    |g1| <= n1 = min(8 eps (D0 + |v0| h + M1 h^2/2), NOISE1),   g1 = D0 - s dx,
    |g2| <= n2 = min(8 eps (|v0| + M1 h), NOISE2),              g2 = s v,

(``M1`` from ``fast.roots.bounds``, ``NOISE1``, ``NOISE2`` from ``fast.params``).  The
certificates (no root skipped) hold only if the float64 values are that close to the exact
ones.  Tested here directly, for each flight kind -- undamped and damped, with and without
friction -- on many random flights (``t0`` in ``[0, T)``, ``|v0| <= 2 F/w``, ``h``
log-uniform in ``[1e-9 T, T]``, plus a dense set where the series of ``theta - sin theta``
and of ``phi2`` work hardest): ``dx`` within ``n1`` taken with ``D0 = 0`` (the distance to the
wall adds only its own rounding to ``g1``), ``v`` within ``n2``, against the reference's
closed forms (``reference.flows`` at 40 digits) from the same start.  The series behind them
(``theta - sin theta``, ``phi2``, ``sincos64``) are checked against mpmath to their own
rounding level, so a series truncated by a few terms turns this module red; and the
double-double path (``fast.flow``, the states fast hands on) against the reference.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import fast
from cross_check.tolerances import tol
from fast import dd
from fast import flight as ff
from fast import params as fp
from fast import roots
from reference.model import Model
from reference.scene import Scene

EPS = 2.0 ** -52
#: one scene per flight kind (the resonance scene: friction against strong forcing, terms of
#: x(t) - x0 three to four times the result; a strongly damped one: y = c h reaches the
#: series' end y = 1/2 within a period)
KINDS = {
    "undamped, frictionless": Scene(F=1, f=0, omega=1, l=0, r="0.8"),
    "undamped, friction": Scene(F="(2*pi)**2", f="24.65", omega="2*pi", l=0, r="0.8932"),
    "damped, frictionless": Scene(F=1, f=0, omega="2*pi", l=-1, r=1, damping="0.05"),
    "damped, friction": Scene(F=1, f="0.9", omega=1, l=-1, r=1, damping="1.5"),
}
N_FLIGHTS = 200


def _flights(scene, n, seed):
    """``n`` random flights ``(t0, v0, s, h)`` (module docstring): half with ``h`` log-uniform in
    ``[1e-9 T, T]``, half where the series end (``theta`` or ``y = c h`` in ``[0.3, 0.5]``) with
    ``|v0| <= 0.1 F/w`` (where the series' terms are not hidden behind ``v0 h``)."""
    rng = np.random.default_rng(seed)
    F, w, c = scene.float("F"), scene.float("omega"), scene.float("damping")
    T = 2 * math.pi / w
    out = []
    for k in range(n):
        t0 = rng.uniform(0, T)
        if k % 2:
            v0, h = rng.uniform(-2, 2) * F / w, T * 10 ** rng.uniform(-9, 0)
        else:
            v0 = rng.uniform(-0.1, 0.1) * F / w
            h = rng.uniform(0.3, 0.5) / (c if c > 0 and rng.random() < 0.5 else w)
            h = min(h, T)
        out.append((t0, v0, 1.0 if v0 >= 0 else -1.0, h))
    return out


def _reference(model, scene, t0, v0, s, h):
    """``(dx, v, cos wt, sin wt)`` of the reference's closed-form flight at 40 digits, and the
    correctly rounded ``sin, cos(w t0)`` that fast's state carries at the start."""
    with mpmath.workdps(40):
        T0 = mpmath.mpf(t0)
        flight = model.flight(T0, mpmath.mpf(0), mpmath.mpf(v0), int(s) if scene.has("friction") else 0)
        x, v, _ = flight.evaluate(T0 + mpmath.mpf(h))
        wt0, wt = model.w * T0, model.w * (T0 + mpmath.mpf(h))
        return (x, v, mpmath.cos(wt), mpmath.sin(wt)), (float(mpmath.sin(wt0)), float(mpmath.cos(wt0)))


@pytest.mark.parametrize("kind", list(KINDS))
def test_float64_flight_values_stay_within_the_declared_noise(kind):
    scene = KINDS[kind]
    P = fp.params(scene)
    with mpmath.workdps(40):
        model = Model(scene)
    trig = tol("fast_flight_trig_abs").atol
    worst = 0.0
    for t0, v0, s, h in _flights(scene, N_FLIGHTS, seed=24):
        exact, (sn0, cs0) = _reference(model, scene, t0, v0, s, h)
        dx, v, cs, sn = ff.evaluate(P, h, v0, s, sn0, cs0)
        M1 = roots.bounds(P, abs(v0))[0]
        n1 = min(8 * EPS * (abs(v0) * h + 0.5 * M1 * h * h), P[fp.NOISE1])
        n2 = min(8 * EPS * (abs(v0) + M1 * h), P[fp.NOISE2])
        errors = [abs(dx - float(exact[0])) / n1, abs(v - float(exact[1])) / n2,
                  abs(cs - float(exact[2])) / trig, abs(sn - float(exact[3])) / trig]
        assert max(errors) <= 1, (kind, dict(t0=t0, v0=v0, s=s, h=h), errors)
        worst = max(worst, *errors)
    assert worst > 1e-3          # the floors are not vacuous: the errors are seen


@pytest.mark.parametrize("kind", list(KINDS))
def test_the_double_double_flight_matches_the_reference(kind):
    """``fast.flow`` (no event: a flight from ``t = 0``, walls far away) hands on the
    double-double flight rounded once: within ``fast_flow_flight`` of the reference."""
    scene = KINDS[kind]
    F, f, w = (scene.float(k) for k in ("F", "f", "omega"))
    far = Scene(F=scene.F, f=scene.f, omega=scene.omega, l=-10 ** 6, r=10 ** 6, damping=scene.damping)
    T = 2 * math.pi / w
    rng = np.random.default_rng(7)
    with mpmath.workdps(40):
        model = Model(far)
    bound = tol("fast_flow_flight")
    c = scene.float("damping")
    longest = min(T, 1 / c) if c > 0 else T       # damped: |v| falls by e at most: no zero
    for _ in range(12):
        v0 = (3 + rng.uniform(0, 1)) * (F / w + f * T) * rng.choice((-1, 1))  # no velocity zero
        h = longest * 10 ** rng.uniform(-9, 0)
        x, v = fast.flow(far, 0.0, v0, h)
        (xe, ve, _, _), _ = _reference(model, far, 0.0, v0, 1.0 if v0 > 0 else -1.0, h)
        for got, want in ((float(x), xe), (float(v), ve)):
            assert abs(got - want) <= bound.atol + bound.rtol * abs(want), (kind, v0, h, got, want)


# --- the series behind the flight values ------------------------------------------------------
def _exact_tms(theta):
    with mpmath.workdps(50):
        t = mpmath.mpf(theta)
        return t - mpmath.sin(t)


def _exact_phi2(y):
    with mpmath.workdps(50):
        y = mpmath.mpf(y)
        return (mpmath.expm1(-y) + y) / (y * y)


def _points(lo, hi, n, seed, edge):
    """``n`` log-uniform points in ``[lo, hi]`` and ``n / 4`` uniform in ``[edge, hi]``."""
    rng = np.random.default_rng(seed)
    return np.concatenate([lo * (hi / lo) ** rng.uniform(0, 1, n), rng.uniform(edge, hi, n // 4)])


def test_theta_minus_sin_keeps_relative_precision():
    """Series (7 terms) for ``theta <= 1/2``, ``theta - 2 S C`` above."""
    series, direct = tol("fast_flight_series_rel").rtol, tol("fast_theta_minus_sin_direct_rel").rtol
    for theta in np.concatenate([_points(1e-9, 0.5, 800, 1, 0.45), _points(0.5, 2 * math.pi, 200, 2, 0.5)]):
        S, C = dd.sincos64(0.5 * theta)
        got, want = ff.theta_minus_sin(theta, S, C), _exact_tms(theta)
        bound = series if theta <= 0.5 else direct
        assert abs(got - want) <= bound * want, (theta, float(abs(got - want) / want / EPS))


def test_phi2_keeps_relative_precision():
    """``(exp(-y) - 1 + y)/y^2``: series (15 terms) for ``y <= 1/2``, ``expm1`` above."""
    series, direct = tol("fast_flight_series_rel").rtol, tol("fast_phi2_direct_rel").rtol
    for y in np.concatenate([_points(1e-9, 0.5, 800, 3, 0.4), _points(0.5, 40.0, 200, 4, 0.5)]):
        got, want = ff.phi2(y), _exact_phi2(y)
        bound = series if y <= 0.5 else direct
        assert abs(got - want) <= bound * want, (y, float(abs(got - want) / want / EPS))


def test_sincos64_is_within_its_rounding():
    """On the half angles ``w h / 2`` of flights up to two periods (its reduction is in float64:
    far beyond, the error grows with the argument)."""
    bound = tol("fast_sincos64_abs").atol
    rng = np.random.default_rng(5)
    for a in np.concatenate([rng.uniform(-1, 2 * math.pi, 800), rng.uniform(-1e-6, 1e-6, 50)]):
        s, c = dd.sincos64(a)
        with mpmath.workdps(40):
            es, ec = mpmath.sin(mpmath.mpf(a)), mpmath.cos(mpmath.mpf(a))
        assert abs(s - es) <= bound and abs(c - ec) <= bound, (a, float(s - es), float(c - ec))
