"""Closed-form flights, compiled: float64 for the event search, double-double at events.

A flight segment starts at ``t0`` from ``(x0, v0)`` with velocity sign ``s`` and
``sn0 = sin(w t0)``, ``cs0 = cos(w t0)`` known.  With ``h = t - t0``, ``theta = w h`` and the
half-angle values ``S = sin(theta/2)``, ``C = cos(theta/2)`` (the only trigonometric calls)::

    Pc = cos(w t0 + theta/2) = cs0 C - sn0 S,      Qs = sin(w t0 + theta/2) = sn0 C + cs0 S
    sin(w t) = sn0 + 2 S Pc,                        cos(w t) = cs0 - 2 S Qs
    v(t) = v0 + (F/w) 2 S Pc - s f h                          (sin wt - sin wt0 = 2 S Pc)
    x(t) - x0 = v0 h + (F/w^2) (2 cs0 S^2 - sn0 D(theta)) - s f h^2 / 2

where ``cos wt0 - cos wt - theta sin wt0 = 2 cs0 S^2 - sn0 D(theta)`` and ``D(theta) =
theta - sin theta``.  Every term is computed without cancellation: in float64 ``D`` comes
from its Taylor series for ``theta <= 0.5`` (7 terms: the first omitted one is below 2^-56
relative) and as ``theta - 2 S C`` above (relative error <= 24 eps there).

Damped flight (``c > 0``: ``x'' + c x' = F cos wt - s f``), with ``y = c h``, ``E = exp(-y)``,
``em = 1 - E`` and ``phi2(y) = (E - 1 + y)/y^2``::

    v = v0 E + 2 S (Qd Pc - Pd Qs) + u(t0) em - s f em / c,      u = Pd cos wt + Qd sin wt
    x - x0 = v0 em / c + [Pd (-2 sn0 S^2 - cs0 D) + Qd (2 cs0 S^2 - sn0 D)] / w
             + (c u(t0) - s f) h^2 phi2(y)

(``Pd = F c/(c^2+w^2)``, ``Qd = F w/(c^2+w^2)``; ``h^2 phi2(y) = (y - em)/c^2``).  Each term
is ``O(h)`` (v) or ``O(h^2)`` (x) on its own: no cancellation of large terms as ``h -> 0`` or
``c -> 0``.  ``phi2`` from its series ``sum_k (-y)^k / (k+2)!`` (15 terms) for ``y <= 0.5``.

``evaluate`` is the float64 form (the search; its half-angle trig from ``fast.dd.sincos64``);
``evaluate_dd`` the same formulas in double-double (``fast.dd``: each term exact to ~1e-22
of its size) from the double-double start state and time, used where a state is handed on:
at every event and at the end of a run (``fast.precise``).  Undamped with ``theta > 1/2`` it
evaluates at the phase itself (``cos wt0 - cos wt - theta sin wt0`` as differences of
``O(1)`` double-doubles, each within ~1e-22: the same accuracy where the terms are not
small, at a third of the products).
"""
from __future__ import annotations

import math

from . import dd
from . import params as p
from .jit import kernel

#: D(theta) = theta^3 sum_k D_k theta^(2k) for theta <= 0.5
D0_, D1_, D2_, D3_, D4_, D5_, D6_ = ((-1) ** k / math.factorial(2 * k + 3) for k in range(7))
#: ``evaluate_dd`` of an undamped flight evaluates at the phase directly above this theta
DIRECT_FROM = 0.5
#: phi2(y) = sum_k (-1)^k y^k / (k+2)!  for y <= 0.5 (15 terms)
PHI2 = tuple((-1) ** k / math.factorial(k + 2) for k in range(15))
(Q0, Q1, Q2, Q3, Q4, Q5, Q6, Q7, Q8, Q9, Q10, Q11, Q12, Q13, Q14) = PHI2


@kernel
def theta_minus_sin(theta, S, C):
    """``theta - sin(theta)`` for ``theta >= 0`` given ``S, C = sin, cos(theta/2)``."""
    if theta > 0.5:
        return theta - 2.0 * S * C
    u = theta * theta
    acc = D0_ + u * (D1_ + u * (D2_ + u * (D3_ + u * (D4_ + u * (D5_ + u * D6_)))))
    return acc * u * theta


@kernel
def phi2(y):
    """``(exp(-y) - 1 + y) / y^2`` for ``y >= 0`` (``1/2`` at 0), cancellation-free."""
    if y > 0.5:
        return (math.expm1(-y) + y) / (y * y)
    acc = Q14
    for q in (Q13, Q12, Q11, Q10, Q9, Q8, Q7, Q6, Q5, Q4, Q3, Q2, Q1, Q0):
        acc = acc * y + q
    return acc


@kernel
def factors(P, h):
    """``(a1, E)`` of the flight matrix ``[[1, a1], [0, E]]``: ``(h, 1)`` undamped,
    ``((1 - exp(-c h))/c, exp(-c h))`` damped."""
    c = P[p.DAMP]
    if c == 0.0:
        return h, 1.0
    y = c * h
    return -math.expm1(-y) / c, math.exp(-y)


@kernel
def evaluate(P, h, v0, s, sn0, cs0):
    """Float64 flight values at ``t0 + h``: ``(dx, v, cos wt, sin wt)``, ``dx = x - x0``."""
    half = (0.5 * P[p.W]) * h
    S, C = dd.sincos64(half)
    Pc = cs0 * C - sn0 * S
    Qs = sn0 * C + cs0 * S
    twoS = S + S
    sn = sn0 + twoS * Pc
    cs = cs0 - twoS * Qs
    D = theta_minus_sin(half + half, S, C)
    f = P[p.FF]
    c = P[p.DAMP]
    if c > 0.0:
        y = c * h
        em = -math.expm1(-y)
        Pd, Qd = P[p.PD], P[p.QD]
        u0 = Pd * cs0 + Qd * sn0
        sf = s * f
        v = v0 * math.exp(-y) + twoS * (Qd * Pc - Pd * Qs) + u0 * em - sf * (em / c)
        S2 = twoS * S
        dx = (v0 * (em / c) + (Pd * (-sn0 * S2 - cs0 * D) + Qd * (cs0 * S2 - sn0 * D)) / P[p.W]
              + (c * u0 - sf) * ((h * h) * phi2(y)))
        return dx, v, cs, sn
    v = v0 + P[p.FW] * (twoS * Pc)
    dx = v0 * h + P[p.FW2] * (cs0 * (twoS * S) - sn0 * D)
    if f > 0.0:
        sf = s * f
        v -= sf * h
        dx -= (0.5 * sf) * (h * h)
    return dx, v, cs, sn


@kernel
def evaluate_dd(P, st_v0h, st_v0l, s, snh, snl, csh, csl, hh, hl, th, tl):
    """The flight in double-double at ``t = t0 + h`` (``h = hh + hl``, ``t = th + tl``) from
    the double-double ``v0`` and start trig: ``(dx, v, acc, sin wt, cos wt)``, each a ``(hi,
    lo)`` pair but the acceleration (its high part: ``acceleration`` gives the pair),
    flattened: ``dxh, dxl, vh, vl, ah, snh, snl, csh, csl``.  An undamped flight with
    ``theta > DIRECT_FROM`` takes ``_direct_dd``."""
    qh, ql = dd.mul(P[p.W], P[p.W_LO], hh, hl)                      # theta
    if P[p.DAMP] == 0.0 and qh > DIRECT_FROM:
        return _direct_dd(P, st_v0h, st_v0l, s, snh, snl, csh, csl, hh, hl, qh, ql, th, tl)
    Sh, Sl, Ch, Cl = dd.sincos(0.5 * qh, 0.5 * ql)
    a, b = dd.mul(csh, csl, Ch, Cl)
    c, d = dd.mul(snh, snl, Sh, Sl)
    Pch, Pcl = dd.add(a, b, -c, -d)
    a, b = dd.mul(snh, snl, Ch, Cl)
    c, d = dd.mul(csh, csl, Sh, Sl)
    Qsh, Qsl = dd.add(a, b, c, d)
    tSh, tSl = 2.0 * Sh, 2.0 * Sl
    a, b = dd.mul(tSh, tSl, Pch, Pcl)                               # sin wt - sin wt0
    n_sh, n_sl = dd.add(snh, snl, a, b)
    c, d = dd.mul(tSh, tSl, Qsh, Qsl)                               # cos wt0 - cos wt
    n_ch, n_cl = dd.add(csh, csl, -c, -d)
    e, g = dd.mul(tSh, tSl, Ch, Cl)                                 # sin theta
    Dh, Dl = dd.add(qh, ql, -e, -g)
    S2h, S2l = dd.mul(tSh, tSl, Sh, Sl)                             # 2 S^2
    if P[p.DAMP] > 0.0:
        dxh, dxl, vh, vl = _damped_dd(P, st_v0h, st_v0l, s, snh, snl, csh, csl, hh, hl,
                                      Pch, Pcl, Qsh, Qsl, tSh, tSl, S2h, S2l, Dh, Dl)
    else:
        vh, vl = dd.mul(P[p.FW], P[p.FW_LO], a, b)
        vh, vl = dd.add(vh, vl, st_v0h, st_v0l)
        a, b = dd.mul(csh, csl, S2h, S2l)
        c, d = dd.mul(snh, snl, Dh, Dl)
        a, b = dd.add(a, b, -c, -d)
        dxh, dxl, vh, vl = _undamped_rest(P, st_v0h, st_v0l, s, hh, hl, a, b, vh, vl)
    return dxh, dxl, vh, vl, acceleration_hi(P, s, n_ch, vh), n_sh, n_sl, n_ch, n_cl


@kernel
def _direct_dd(P, v0h, v0l, s, snh, snl, csh, csl, hh, hl, qh, ql, th, tl):
    """``evaluate_dd`` of an undamped flight with ``theta > DIRECT_FROM`` at the phase ``w t``
    itself: ``sin wt, cos wt`` from one ``dd.sincos`` (absolute error < 1e-22), ``sin wt - sin
    wt0`` and ``cos wt0 - cos wt - theta sin wt0`` as double-double differences.  Their
    terms are ``O(1)`` here, so that is the half-angle form's accuracy (relative to the
    terms) at a third of its products; below ``DIRECT_FROM`` the half-angle form keeps a
    short flight's terms exact to their own, small, size."""
    ph, pl = dd.mul(P[p.W], P[p.W_LO], th, tl)
    n_sh, n_sl, n_ch, n_cl = dd.sincos(ph, pl)
    a, b = dd.add(n_sh, n_sl, -snh, -snl)
    vh, vl = dd.mul(P[p.FW], P[p.FW_LO], a, b)
    vh, vl = dd.add(vh, vl, v0h, v0l)
    a, b = dd.mul(qh, ql, snh, snl)
    c, d = dd.add(csh, csl, -n_ch, -n_cl)
    a, b = dd.add(c, d, -a, -b)
    dxh, dxl, vh, vl = _undamped_rest(P, v0h, v0l, s, hh, hl, a, b, vh, vl)
    return dxh, dxl, vh, vl, acceleration_hi(P, s, n_ch, vh), n_sh, n_sl, n_ch, n_cl


@kernel
def _undamped_rest(P, v0h, v0l, s, hh, hl, a, b, vh, vl):
    """``dx = (F/w^2) (a + b) + v0 h - s f h^2 / 2`` and ``v - s f h`` in double-double, with
    ``a + b = cos wt0 - cos wt - theta sin wt0``."""
    dxh, dxl = dd.mul(P[p.FW2], P[p.FW2_LO], a, b)
    a, b = dd.mul(v0h, v0l, hh, hl)
    dxh, dxl = dd.add(dxh, dxl, a, b)
    if P[p.FF] > 0.0:
        sfh, sfl = s * P[p.FF], s * P[p.FF_LO]
        a, b = dd.mul(sfh, sfl, hh, hl)                              # s f h
        vh, vl = dd.add(vh, vl, -a, -b)
        c, d = dd.mul(a, b, hh, hl)
        dxh, dxl = dd.add(dxh, dxl, -0.5 * c, -0.5 * d)
    return dxh, dxl, vh, vl


@kernel
def acceleration(P, s, csh, csl, vh, vl):
    """``x'' = F cos wt - s f (- c v)`` in double-double."""
    ah, al = dd.mul(P[p.F], P[p.F_LO], csh, csl)
    ah, al = dd.add(ah, al, -s * P[p.FF], -s * P[p.FF_LO])
    if P[p.DAMP] > 0.0:
        a, b = dd.mul(P[p.DAMP], P[p.DAMP_LO], vh, vl)
        ah, al = dd.add(ah, al, -a, -b)
    return ah, al


@kernel
def acceleration_hi(P, s, csh, vh):
    """The high part of ``acceleration`` (the same roundings: the high part of a ``dd.mul``
    is the product of the high parts, of a ``dd.add`` the rounded sum of the high parts)
    without the low parts, which only a tangency check needs."""
    ah = P[p.F] * csh + -s * P[p.FF]
    if P[p.DAMP] > 0.0:
        ah = ah + -(P[p.DAMP] * vh)
    return ah


@kernel
def _damped_dd(P, v0h, v0l, s, snh, snl, csh, csl, hh, hl, Pch, Pcl, Qsh, Qsl, tSh, tSl,
               S2h, S2l, Dh, Dl):
    """``(dx, v)`` of the damped flight in double-double (module docstring)."""
    yh, yl = dd.mul(P[p.DAMP], P[p.DAMP_LO], hh, hl)
    m1h, m1l = dd.expm1(-yh, -yl)                                   # E - 1 = -em
    a, b = dd.mul(P[p.PD], P[p.PD_LO], csh, csl)
    c, d = dd.mul(P[p.QD], P[p.QD_LO], snh, snl)
    u0h, u0l = dd.add(a, b, c, d)
    sfh, sfl = s * P[p.FF], s * P[p.FF_LO]
    # v = v0 + v0 (E - 1) + 2S (Qd Pc - Pd Qs) - (u0 - s f / c)(E - 1)
    a, b = dd.mul(P[p.QD], P[p.QD_LO], Pch, Pcl)
    c, d = dd.mul(P[p.PD], P[p.PD_LO], Qsh, Qsl)
    a, b = dd.add(a, b, -c, -d)
    vh, vl = dd.mul(tSh, tSl, a, b)
    c, d = dd.mul(sfh, sfl, P[p.ID], P[p.ID_LO])
    c, d = dd.add(u0h, u0l, -c, -d)
    c, d = dd.add(c, d, -v0h, -v0l)                                 # u0 - s f/c - v0
    c, d = dd.mul(c, d, m1h, m1l)
    vh, vl = dd.add(vh, vl, -c, -d)
    vh, vl = dd.add(vh, vl, v0h, v0l)
    # dx = -v0 (E - 1)/c + [...]/w + (c u0 - s f)(y + (E - 1))/c^2
    a, b = dd.mul(v0h, v0l, m1h, m1l)
    dxh, dxl = dd.mul(-a, -b, P[p.ID], P[p.ID_LO])
    a, b = dd.mul(snh, snl, S2h, S2l)
    c, d = dd.mul(csh, csl, Dh, Dl)
    a, b = dd.add(-a, -b, -c, -d)
    a, b = dd.mul(P[p.PD], P[p.PD_LO], a, b)
    c, d = dd.mul(csh, csl, S2h, S2l)
    e, g = dd.mul(snh, snl, Dh, Dl)
    c, d = dd.add(c, d, -e, -g)
    c, d = dd.mul(P[p.QD], P[p.QD_LO], c, d)
    a, b = dd.add(a, b, c, d)
    a, b = dd.mul(a, b, P[p.IW], P[p.IW_LO])
    dxh, dxl = dd.add(dxh, dxl, a, b)
    a, b = dd.mul(P[p.DAMP], P[p.DAMP_LO], u0h, u0l)
    a, b = dd.add(a, b, -sfh, -sfl)
    c, d = dd.add(yh, yl, m1h, m1l)
    a, b = dd.mul(a, b, c, d)
    a, b = dd.mul(a, b, P[p.ID2], P[p.ID2_LO])
    dxh, dxl = dd.add(dxh, dxl, a, b)
    return dxh, dxl, vh, vl
