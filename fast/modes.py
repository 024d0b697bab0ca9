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


def chatter_tail(P, p, u):
    """Frozen-force tail of a chatter sequence after an impact (speed ``u`` after it).

    ``p = side * A > f`` is the force pushing into the wall.  A bounce out (deceleration
    ``p + f``) and back (acceleration ``p - f``) from speed ``u`` lasts ``u tau``,
    ``tau = (1 + 1/q)/(p + f)``, and returns with speed ``q u``, ``q = sqrt((p - f)/(p +
    f))``, i.e. ``rho u`` after the impact, ``rho = e q``.  Summing the geometric series::

        Delta = u tau / (1 - rho),     1 - rho = (1 - e) + e 2 f / ((p + f)(1 + q))

    (the second form is free of cancellation; ``e = 1``: ``Delta = u (1 + q)^2/(2 f q)``).
    The force changes by at most ``F w Delta`` over the tail; it perturbs each bounce by
    a relative ``O(F w Delta / (p - f))``, so the neglected terms in ``Delta`` are
    ``<= err = 2 F w Delta^2 / (p - f)``.  Returns ``(Delta, rho, err, tau, 1 - rho)``.
    """
    f, e = P.f, P.e
    q = np.sqrt((p - f) / (p + f))
    tau = (1.0 + 1.0 / q) / (p + f)
    one_m = (1.0 - e) + e * (2.0 * f) / ((p + f) * (1.0 + q))
    delta = u * tau / one_m
    err = 2.0 * P.F * P.w * delta * delta / (p - f)
    return delta, e * q, err, tau, one_m


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
