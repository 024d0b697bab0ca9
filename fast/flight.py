"""Closed-form flights of the base model (c = 0, no position forcing), vectorised.

A flight segment starts at ``t0`` from ``(x0, v0)`` with velocity sign ``s`` and
``sn0 = sin(w t0)``, ``cs0 = cos(w t0)`` computed once per segment.  With ``h = t - t0``,
``theta = w h`` and the half-angle values ``S = sin(theta/2)``, ``C = cos(theta/2)``
(the only trigonometric calls per trial time)::

    P = cos(w t0 + theta/2) = cs0 C - sn0 S,      Q = sin(w t0 + theta/2) = sn0 C + cs0 S
    sin(w t) = sn0 + 2 S P,                        cos(w t) = cs0 - 2 S Q
    v(t) = v0 + (F/w) 2 S P - s f h                          (sin wt - sin wt0 = 2 S P)
    x(t) - x0 = v0 h + (F/w^2) (2 cs0 S^2 - sn0 D(theta)) - s f h^2 / 2

where ``cos wt0 - cos wt - theta sin wt0 = 2 cs0 S^2 - sn0 D(theta)`` and
``D(theta) = theta - sin theta``.  Every term is computed without cancellation: ``D`` by
its Taylor series for ``theta <= 0.5`` (7 terms: the first omitted one is below 2^-56
relative) and as ``theta - 2 S C`` above (relative error <= 6 eps / theta^2 <= 24 eps
there, absolute (F/w^2) eps theta, below the rounding of the other terms of x).

Damped flight (``c > 0``: ``x'' + c x' = F cos wt - s f``), with ``y = c h``,
``E = exp(-y)``, ``a1 = (1 - E)/c = -expm1(-y)/c`` and ``phi2(y) = (E - 1 + y)/y^2``::

    v = v_p(t) + (v0 - v_p(t0)) E,   v_p = Pd cos wt + Qd sin wt - s f / c
      = v0 E + [u(t) - u(t0)] + u(t0) (1 - E) - s f a1,        u = Pd cos wt + Qd sin wt
    x - x0 = v0 a1 + [Pd (-2 sn0 S^2 - cs0 D) + Qd (2 cs0 S^2 - sn0 D)] / w
             + (c u(t0) - s f) h^2 phi2(y)

(``Pd = F c/(c^2+w^2)``, ``Qd = F w/(c^2+w^2)``; ``u(t) - u(t0) = 2 S (Qd P - Pd Q)``;
the bracket is ``int_0^h u(t0 + r) - u(t0) dr``, and ``int_0^h (1 - exp(-c r)) dr = c h^2
phi2``).  Every term is ``O(h)`` (v) or ``O(h^2)`` (x) on its own: no cancellation of
large terms as ``h -> 0`` or ``c -> 0`` (the friction and ``u(t0)`` terms are not divided
by ``c``); ``c -> 0`` gives the undamped forms.  ``phi2`` by its series ``sum_k (-y)^k /
(k+2)!`` (15 terms, first omitted one below 2^-60 relative) for ``y <= 0.5`` and
directly above (``E - 1 + y >= 0.1 y^2``: relative error a few eps).

This module is the flight interface: a numerical flight (``fast.ode``, position
forcing) would provide the same ``evaluate`` signature.
"""
from __future__ import annotations

import math

import numpy as np

#: D(theta) = theta^3 * sum_k _D_COEF[k] * theta^(2k) for theta <= _D_SWITCH
_D_SWITCH = 0.5
_D_COEF = tuple((-1) ** k / math.factorial(2 * k + 3) for k in range(7))
#: phi2(y) = sum_k _PHI2_COEF[k] y^k for y <= _PHI2_SWITCH
_PHI2_SWITCH = 0.5
_PHI2_COEF = tuple((-1) ** k / math.factorial(k + 2) for k in range(15))


def phi2(y: np.ndarray) -> np.ndarray:
    """``(exp(-y) - 1 + y) / y^2`` for ``y >= 0`` (``1/2`` at 0), cancellation-free."""
    acc = np.full_like(y, _PHI2_COEF[-1])
    for a in _PHI2_COEF[-2::-1]:
        acc *= y
        acc += a
    with np.errstate(invalid="ignore", divide="ignore"):
        direct = (np.expm1(-y) + y) / (y * y)
    return np.where(y <= _PHI2_SWITCH, acc, direct)


def damped_factors(P, h):
    """``(a1, E) = ((1 - exp(-c h))/c, exp(-c h))``: the damped flight matrix
    ``[[1, a1], [0, E]]`` (``(h, 1)`` without damping)."""
    if P.damp == 0:
        return h, 1.0
    y = P.damp * h
    return -np.expm1(-y) / P.damp, np.exp(-y)


def theta_minus_sin(theta: np.ndarray, S: np.ndarray, C: np.ndarray) -> np.ndarray:
    """``theta - sin(theta)`` for ``theta >= 0`` given ``S, C = sin, cos(theta/2)``.

    In long double (``fast.precise``) the direct form alone: its cancellation costs
    ``eps_L theta`` absolute (1e-19 theta), far below the float64 rounding of ``x``, and
    the series would cost a dozen long-double operations per event for nothing."""
    direct = theta - 2.0 * S * C
    if np.finfo(theta.dtype).eps < 1e-17:
        return direct
    u = theta * theta
    acc = np.full_like(theta, _D_COEF[-1])
    for a in _D_COEF[-2::-1]:
        acc *= u
        acc += a
    acc *= u
    acc *= theta
    return np.where(theta <= _D_SWITCH, acc, direct)


def evaluate(P, h, x0, v0, s, sn0, cs0):
    """Flight values at ``t0 + h`` (``h >= 0``): ``(dx, v, cos wt, sin wt)``.

    ``dx = x(t) - x0`` (kept apart from ``x0`` so that distances to a wall stay
    accurate), ``v = x'(t)``; ``cos wt``, ``sin wt`` give the force
    ``A = F cos wt`` and its rate ``A' = -F w sin wt``.
    """
    w, F, f = P.w, P.F, P.f
    if P.damp > 0:
        return _evaluate_damped(P, h, x0, v0, s, sn0, cs0)
    S, twoS, Pc, Qs, sn, cs, D = _half_angle(w, h, sn0, cs0)
    v = v0 + (F / w) * (twoS * Pc)
    dx = v0 * h + (F / (w * w)) * (cs0 * (twoS * S) - sn0 * D)
    if f > 0:
        sf = s * f
        v -= sf * h
        dx -= (0.5 * sf) * (h * h)
    return dx, v, cs, sn


def _half_angle(w, h, sn0, cs0):
    """The half-angle pieces shared by the flights, ``theta = w h``, ``S = sin(theta/2)``:
    ``sin wt - sin wt0 = 2 S Pc`` and ``cos wt0 - cos wt = 2 S Qs`` (no cancellation),
    ``Pc = cos(w (t + t0)/2)``, ``Qs = sin(w (t + t0)/2)``, the new ``sin wt``, ``cos wt``,
    and ``D = theta - sin theta`` (series for small ``theta``)."""
    half = (0.5 * w) * h
    S = np.sin(half)
    C = np.cos(half)
    Pc = cs0 * C - sn0 * S
    Qs = sn0 * C + cs0 * S
    twoS = S + S
    return S, twoS, Pc, Qs, sn0 + twoS * Pc, cs0 - twoS * Qs, theta_minus_sin(half + half, S, C)


def _evaluate_damped(P, h, x0, v0, s, sn0, cs0):
    """``evaluate`` for ``c > 0`` (module docstring, damped flight)."""
    w, f, c, Pd, Qd = P.w, P.f, P.damp, P.Pd, P.Qd
    S, twoS, Pc, Qs, sn, cs, D = _half_angle(w, h, sn0, cs0)
    y = c * h
    em = -np.expm1(-y)                  # 1 - E
    u0 = Pd * cs0 + Qd * sn0
    sf = s * f
    v = v0 * np.exp(-y) + twoS * (Qd * Pc - Pd * Qs) + u0 * em - sf * (em / c)
    S2 = twoS * S
    dx = (v0 * (em / c) + (Pd * (-sn0 * S2 - cs0 * D) + Qd * (cs0 * S2 - sn0 * D)) / w
          + (c * u0 - sf) * ((h * h) * phi2(y)))
    return dx, v, cs, sn


def two_sum(a, b):
    """Knuth's error-free sum: ``a + b = s + e`` exactly (``s`` the rounded sum)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def split(a):
    """Dekker's split ``a = a1 + a2``, ``a1`` carrying 26 bits: products of halves are exact."""
    c = 134217729.0 * a
    a1 = c - (c - a)
    return a1, a - a1


def two_prod(a, b, b_split):
    """Dekker's error-free product: ``a b = p + e`` exactly (``p`` the rounded product),
    with ``b_split = split(b)`` (a scene constant, split once)."""
    p = a * b
    a1, a2 = split(a)
    b1, b2 = b_split
    return p, ((a1 * b1 - p) + a1 * b2 + a2 * b1) + a2 * b2


def phase_trig(P, t, t_lo):
    """``(cos w t, sin w t)`` at the double-double time ``t + t_lo`` with the scene's
    double-double ``w + w_lo`` (``fast.params``), to about an ulp of each value.

    The phase ``w t`` is formed error-free (``two_prod``) plus the small terms ``w t_lo +
    w_lo t``, and the trig of the rounded phase is corrected to first order: ``cos(p +
    q) = cos p - q sin p`` (``|q| <~ 1e-15``: the omitted ``q^2/2`` is below 1e-30).  A
    phase rounded to float64 instead is off by up to half an ulp of ``w t`` (4e-16 near
    2 pi), which moves the force ``F cos wt`` by ``F`` times that: several ulp of ``v``
    per flight when ``F / w`` is large."""
    p, q = two_prod(t, P.w, P.w_split)
    q += P.w * t_lo + P.w_lo * t
    cp, sp = np.cos(p), np.sin(p)
    return cp - q * sp, sp + q * cp
