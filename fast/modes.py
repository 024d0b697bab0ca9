"""Closed forms of the non-flight modes: end of sticking, end of wall contact, chatter.

All of them act on the phase ``phi = w t`` through ``cs = cos(phi)``, ``sn = sin(phi)`` so
that no phase is reduced modulo 2 pi.  With ``c = f/F < 1`` and ``alpha = arccos(c)``:

* sticking (``|cos phi| <= c``) happens on ``[alpha, pi - alpha]`` (``sin phi >= 0``) and
  ``[pi + alpha, 2 pi - alpha]`` (``sin phi < 0``); it ends at ``pi - alpha`` (slip with
  ``s = -1``) or at ``2 pi - alpha`` (``s = +1``), or at once (``s = sgn cos phi``) when
  ``|cos phi| > c`` already;
* contact at ``r`` holds while ``cos phi >= -c`` and ends at ``pi - alpha`` (``s = -1``);
  at ``l`` it holds while ``cos phi <= c`` and ends at ``-alpha`` (``s = +1``).

The angle from ``phi`` to a boundary ``b`` is ``atan2(sin(b - phi), cos(b - phi))``
expanded with the exact ``cos b = +-c``, ``sin b = +-sin(alpha)``: no cancellation.
With ``c >= 1`` (``F <= f``) neither sticking nor contact ever ends (returned as ``inf``).
"""
from __future__ import annotations

import math

import numpy as np


def stick_exit(P, cs, sn):
    """Phase advance to the end of sticking and the new flight sign: ``(dphi, s)``."""
    if P.c >= 1:
        return np.full_like(cs, np.inf), np.ones_like(cs)
    c, sa = P.c, P.sin_alpha
    upper = sn >= 0
    # boundary pi - alpha (cos = -c, sin = sa) or 2 pi - alpha (cos = c, sin = -sa)
    sgn = np.where(upper, 1.0, -1.0)
    y = sgn * (sa * cs + c * sn)
    x = sgn * (-c * cs + sa * sn)
    dphi = np.maximum(np.arctan2(y, x), 0.0)
    s = -sgn
    now = np.abs(P.F * cs) > P.f
    dphi = np.where(now, 0.0, dphi)
    s = np.where(now, np.sign(cs), s)
    return dphi, s


def wall_exit(P, cs, sn, side):
    """Phase advance to the release from wall ``side`` (+1: r, -1: l) (``inf``: never)."""
    if P.c >= 1:
        return np.full_like(cs, np.inf)
    c, sa = P.c, P.sin_alpha
    # boundary at r: pi - alpha (cos -c, sin sa); at l: -alpha (cos c, sin -sa)
    y = side * (sa * cs + c * sn)
    x = side * (-c * cs + sa * sn)
    raw = np.arctan2(y, x)
    # raw in [-alpha, 0): already inside the release zone up to rounding -> release now
    dphi = np.where(raw < -P.alpha, raw + 2 * math.pi, np.maximum(raw, 0.0))
    pulled = side * (P.F * cs) < -P.f
    return np.where(pulled, 0.0, dphi)


def chatter_tail(P, p, u, p1=None):
    """Tail of a chatter sequence after an impact (speed ``u`` after it), to second order.

    ``p = side * A > f`` is the force pushing into the wall, ``p1 = side * A'`` its rate.
    Frozen force: a bounce out (deceleration ``a = p + f``) and back (acceleration ``b = p
    - f``) from speed ``u`` lasts ``u tau``, ``tau = 1/a + 1/sqrt(a b)``, and returns with
    speed ``q u``, ``q = sqrt(b/a)``, i.e. ``rho u`` after the impact, ``rho = e q``; the
    geometric series gives ``Delta_0 = g1 u``, ``g1 = tau / (1 - rho)``, ``1 - rho = (1 - e)
    + e 2 f / (a (1 + q))`` (cancellation-free).

    First order in the bounce (force ``p + p1 h`` over it: the distance from the wall is
    ``u h - a h^2/2 - p1 h^3/6`` out to the turn at ``h_u = u/a - p1 u^2/(2 a^3)``, height
    ``H = u^2/(2 a) - p1 u^3/(6 a^3)``, then ``H - b' s^2/2 - p1 s^3/6`` back, ``b' = b +
    p1 h_u``, impact at ``s = s0 - p1 s0^2/(6 b')``, ``s0 = sqrt(2 H/b')``, with speed ``b'
    s0 + p1 s0^2/3``; each to first order in ``u``): the bounce lasts ``D = tau u + d2 u^2``
    and returns ``R = rho u (1 + r1 u)`` with::

        d2 = -p1 [1/(2 a^3) + (1/(6 a^2) + 1/(2 a b)) / sqrt(a b) + 1/(6 a b^2)]
        r1 =  p1 [1/(2 a b) - 1/(6 a^2) + 1/(3 a b q)]

    The time to the accumulation ``G(t, u) = g1(t) u + g2(t) u^2 + O(u^3)`` solves ``G(t,
    u) = D + G(t + D, R)``; order ``u^2``: ``g2 = (d2 + g1 rho r1 + g1' tau rho) / (1 -
    rho^2)`` with ``g1' = p1 dg1/dp``.  ``Delta = g1 u + g2 u^2``.

    Neglected: the ``u^3`` terms.  With ``z = |g2| u / g1`` (the ratio of successive
    orders) and the curvature of the force over the tail, ``F w^2 Delta^3 / (p - f)``, the
    estimate is ``err = 2 |g2| u^2 (z + F w Delta / (p - f)) + 2 F w^2 Delta^3 / (p - f)``
    (factor 2 margin on a geometric continuation of the series); used where ``z <= 1/8``,
    else (``p`` near ``f``: the expansion does not converge) the frozen tail.  Damping ``c > 0`` is not
    in the bounce model: a bounce from ``u_k`` loses ``c u_k^2 / a <= c u_k (u_k tau)``, a
    relative ``c u_k tau`` of its speed and duration, so the later speeds are off by a
    relative ``<= c sum_k u_k tau = c Delta``, the summed time by ``<= 2 c Delta^2`` to first
    order: ``err += 4 c Delta^2`` (factor 2 margin).  Without ``p1`` (``None``) the frozen
    tail is returned with ``err = 2 F w Delta^2 / (p - f) + 4 c Delta^2``.

    Limitation (rho -> 1, e.g. f = 0.005 against A ~ 1): the force's energy input per
    bounce, ``r1 u ~ 2 A' u / (3 A^2)``, is then comparable to the dissipation ``1 - rho ~
    f / A`` until ``u`` is small, the series in ``u`` converges like ``(r1 u / (1 -
    rho))^n``, and ``err`` reaches ``4 eps T`` only after many bounces (the caller also
    sums once the bounces are within 64 ulp of the wall, where this tail is accurate to
    ~1e-15 T: ~900 bounces at rho = 0.99, ~1600 at 0.995 from ``u ~ 1.4e-3``).

    Returns ``(Delta, rho, err, tau, 1 - rho)``.
    """
    f, e = P.f, P.e
    a = p + f
    b = p - f
    q = np.sqrt(b / a)
    sab = np.sqrt(a * b)
    tau = 1.0 / a + 1.0 / sab
    one_m = (1.0 - e) + e * (2.0 * f) / (a * (1.0 + q))
    rho = e * q
    g1 = tau / one_m
    d0 = u * g1
    if p1 is None:
        delta = d0
        err = (2.0 * P.F * P.w / b + 4.0 * P.damp) * (delta * delta)
        return delta, rho, err, tau, one_m
    d2 = -p1 * (0.5 / (a * a * a) + (1.0 / (6.0 * a * a) + 0.5 / (a * b)) / sab + 1.0 / (6.0 * a * b * b))
    r1 = p1 * (0.5 / (a * b) - 1.0 / (6.0 * a * a) + 1.0 / (3.0 * a * b * q))
    # g1' = p1 (tau_p (1 - rho) + tau rho_p) / (1 - rho)^2
    tau_p = -1.0 / (a * a) - (a + b) / (2.0 * sab * (a * b))
    rho_p = e * f / (q * a * a)
    g1p = p1 * (tau_p * one_m + tau * rho_p) / (one_m * one_m)
    g2 = (d2 + g1 * rho * r1 + g1p * tau * rho) / (one_m * (1.0 + rho))
    corr = g2 * (u * u)
    delta = d0 + corr
    z = np.abs(g2) * u / g1
    err = (2.0 * np.abs(corr) * (z + P.F * P.w * delta / b)
           + 2.0 * P.F * P.w * P.w * delta * delta * delta / b + 4.0 * P.damp * delta * delta)
    # outside the expansion's range (z > 1/8: e.g. p -> f) keep the frozen tail and its bound
    ok = z <= 0.125
    err0 = (2.0 * P.F * P.w / b + 4.0 * P.damp) * (d0 * d0)
    return np.where(ok, delta, d0), rho, np.where(ok, err, err0), tau, one_m


def chatter_state(P, p, u, rho, tau, one_m, remaining):
    """State ``(y, vy)`` (distance from the wall, its rate) ``remaining`` after the impact.

    Frozen-force bounces: bounce ``n`` starts at ``u tau (1 - rho^n)/(1 - rho)`` with
    speed ``u rho^n``.
    """
    f = P.f
    frac = np.clip(1.0 - remaining * one_m / (u * tau), 1e-300, 1.0)
    n = np.floor(np.log(frac) / np.log(np.maximum(rho, 1e-300)))
    rn = rho ** n
    q = np.maximum(remaining - u * tau * (1.0 - rn) / one_m, 0.0)
    un = u * rn
    t_up = un / (p + f)
    up = q <= t_up
    q2 = np.maximum(q - t_up, 0.0)
    y = np.where(up, un * q - 0.5 * (p + f) * q * q, un * un / (2 * (p + f)) - 0.5 * (p - f) * q2 * q2)
    vy = np.where(up, un - (p + f) * q, -(p - f) * q2)
    return np.maximum(y, 0.0), vy
