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

This module is the flight interface: a numerical flight (``fast.ode``, position
forcing) would provide the same ``evaluate`` signature.
"""
from __future__ import annotations

import math

import numpy as np

#: D(theta) = theta^3 * sum_k _D_COEF[k] * theta^(2k) for theta <= _D_SWITCH
_D_SWITCH = 0.5
_D_COEF = tuple((-1) ** k / math.factorial(2 * k + 3) for k in range(7))


def theta_minus_sin(theta: np.ndarray, S: np.ndarray, C: np.ndarray) -> np.ndarray:
    """``theta - sin(theta)`` for ``theta >= 0`` given ``S, C = sin, cos(theta/2)``."""
    u = theta * theta
    acc = np.full_like(theta, _D_COEF[-1])
    for a in _D_COEF[-2::-1]:
        acc *= u
        acc += a
    acc *= u
    acc *= theta
    direct = theta - 2.0 * S * C
    return np.where(theta <= _D_SWITCH, acc, direct)


def evaluate(P, h, x0, v0, s, sn0, cs0):
    """Flight values at ``t0 + h`` (``h >= 0``): ``(dx, v, cos wt, sin wt)``.

    ``dx = x(t) - x0`` (kept apart from ``x0`` so that distances to a wall stay
    accurate), ``v = x'(t)``; ``cos wt``, ``sin wt`` give the force
    ``A = F cos wt`` and its rate ``A' = -F w sin wt``.
    """
    w, F, f = P.w, P.F, P.f
    half = (0.5 * w) * h
    S = np.sin(half)
    C = np.cos(half)
    Pc = cs0 * C - sn0 * S
    Qs = sn0 * C + cs0 * S
    twoS = S + S
    sn = sn0 + twoS * Pc
    cs = cs0 - twoS * Qs
    theta = half + half
    D = theta_minus_sin(theta, S, C)
    v = v0 + (F / w) * (twoS * Pc)
    dx = v0 * h + (F / (w * w)) * (cs0 * (twoS * S) - sn0 * D)
    if f > 0:
        sf = s * f
        v -= sf * h
        dx -= (0.5 * sf) * (h * h)
    return dx, v, cs, sn
