"""Closed forms of the non-flight modes: end of sticking, end of wall contact, chatter.

All of them act on the phase ``phi = w t`` through ``cs = cos(phi)``, ``sn = sin(phi)`` so
that no phase is reduced modulo 2 pi.  With ``c = f/F < 1`` and ``alpha = arccos(c)``:

* sticking (``|cos phi| <= c``) happens on ``[alpha, pi - alpha]`` (``sin phi >= 0``) and
  ``[pi + alpha, 2 pi - alpha]`` (``sin phi < 0``); it ends at ``pi - alpha`` (slip with
  ``s = -1``) or at ``2 pi - alpha`` (``s = +1``), or at once (``s = sgn cos phi``) when
  ``|cos phi| > c`` already and the slide lasts (``slides``);
* contact at ``r`` holds while ``cos phi >= -c`` and ends at ``pi - alpha`` (``s = -1``);
  at ``l`` it holds while ``cos phi <= c`` and ends at ``-alpha`` (``s = +1``).

The angle from ``phi`` to a boundary ``b`` is ``atan2(sin(b - phi), cos(b - phi))``
expanded with the exact ``cos b = +-c``, ``sin b = +-sin(alpha)``: no cancellation; it only
picks the boundary crossing, whose time ``(B + 2 pi n)/w`` is then formed in double-double
(``exit_time``).  With ``c >= 1`` (``F <= f``) neither sticking nor contact ever ends.
"""
from __future__ import annotations

import math

from . import dd
from . import params as p
from .jit import kernel

EPS = 2.0 ** -52


@kernel
def slides(P, s, cs, sn):
    """Whether a flight of sign ``s`` leaving rest at the phase ``(cos, sin)`` slides: its
    acceleration ``a = s F cos - f`` is positive and, where it falls (``a' = -s F w sin <
    0``), lasts beyond the time resolution, ``a >= |a'| tau`` with ``tau = 64 eps T`` (the
    slide ends after ``~a / |a'|``).  A shorter slide -- a turn or slip exactly at ``|A| = f``
    while ``|A|`` falls -- lies below what float64 times resolve, and sticking follows it
    at once: the particle sticks (the same rule decides turns, slips and releases, so no
    zero-length loop of stick and slip can arise)."""
    a = s * (P[p.F] * cs) - P[p.FF]
    if not a > 0.0:
        return False
    a1 = -s * (P[p.F] * P[p.W]) * sn
    return a1 >= 0.0 or a >= -a1 * (64 * EPS * P[p.T])


@kernel
def stick_exit(P, cs, sn):
    """Phase advance to the end of sticking and the new flight sign: ``(dphi, s)``."""
    c, sa = P[p.C], P[p.SA]
    if c >= 1.0:
        return math.inf, 1.0
    now = 1.0 if cs > 0.0 else -1.0
    if slides(P, now, cs, sn):
        return 0.0, now
    # boundary pi - alpha (cos -c, sin sa) or 2 pi - alpha (cos c, sin -sa)
    sgn = 1.0 if sn >= 0.0 else -1.0
    y = sgn * (sa * cs + c * sn)
    x = sgn * (-c * cs + sa * sn)
    return max(math.atan2(y, x), 0.0), -sgn


@kernel
def wall_exit(P, cs, sn, side):
    """Phase advance to the release from wall ``side`` (+1: r, -1: l); ``inf``: never."""
    c, sa = P[p.C], P[p.SA]
    if c >= 1.0:
        return math.inf
    if slides(P, -side, cs, sn):
        return 0.0                                   # pulled off the wall at once
    # boundary at r: pi - alpha (cos -c, sin sa); at l: -alpha (cos c, sin -sa)
    y = side * (sa * cs + c * sn)
    x = side * (-c * cs + sa * sn)
    raw = math.atan2(y, x)
    # raw in [-alpha, 0): already inside the release zone up to rounding -> release now
    return raw + 2.0 * math.pi if raw < -P[p.ALPHA] else max(raw, 0.0)


@kernel
def exit_time(P, t, t_lo, dphi, upper):
    """The double-double time at which sticking or wall contact that began at ``t + t_lo``
    ends ``dphi / w`` later: exactly the phase ``B + 2 pi n`` with ``B = pi - alpha``
    where ``upper`` (stick exit with ``s = -1``, release from ``r``), else ``2 pi - alpha``,
    ``n`` the nearest integer to ``(w t + dphi - B) / 2 pi``; ``t = (B + 2 pi n) / w`` in
    double-double (``fast.dd``).  ``dphi = 0`` keeps ``t``, ``inf`` gives ``inf``."""
    if dphi == 0.0:
        return t, t_lo
    if not math.isfinite(dphi):
        return math.inf, 0.0
    b_hi, b_lo = (P[p.B1], P[p.B1_LO]) if upper else (P[p.B2], P[p.B2_LO])
    w = P[p.W]
    n = math.floor((w * t + dphi - b_hi) * (1.0 / p.TWO_PI_HI) + 0.5)
    nh, nl = dd.two_prod(n, p.TWO_PI_HI)
    ph, pl = dd.add(b_hi, b_lo, nh, nl + n * p.TWO_PI_LO)
    # (ph + pl) / (w + w_lo) in double-double
    q1 = ph / w
    prod, err = dd.two_prod(q1, w)
    rem = ((ph - prod) - err) + (pl - q1 * P[p.W_LO])
    return dd.two_sum(q1, rem / w)


@kernel
def chatter_tail(P, pu, u, p1):
    """Tail of a chatter sequence after an impact (speed ``u`` after it), to second order.

    ``pu = side * A > f`` is the force pushing into the wall, ``p1 = side * A'`` its rate.
    Frozen force: a bounce out (deceleration ``a = pu + f``) and back (acceleration ``b =
    pu - f``) from speed ``u`` lasts ``u tau``, ``tau = 1/a + 1/sqrt(a b)``, and returns
    with speed ``q u``, ``q = sqrt(b/a)``, i.e. ``rho u`` after the impact, ``rho = e q``;
    the geometric series gives ``Delta_0 = g1 u``, ``g1 = tau / (1 - rho)``, ``1 - rho =
    (1 - e) + e 2 f / (a (1 + q))`` (cancellation-free).  First order in the bounce
    (force ``pu + p1 h``): the bounce lasts ``tau u + d2 u^2`` and returns ``rho u (1 + r1
    u)`` with::

        d2 = -p1 [1/(2 a^3) + (1/(6 a^2) + 1/(2 a b)) / sqrt(a b) + 1/(6 a b^2)]
        r1 =  p1 [1/(2 a b) - 1/(6 a^2) + 1/(3 a b q)]

    and the time to the accumulation is ``Delta = g1 u + g2 u^2`` with ``g2 = (d2 + g1 rho
    r1 + g1' tau rho) / (1 - rho^2)``, ``g1' = p1 dg1/dp``.  Error estimate (neglected
    ``u^3`` terms, the force's curvature over the tail, damping's ``c u_k^2/a`` per
    bounce): ``err = 2 |g2| u^2 (z + F w Delta / b) + 2 F w^2 Delta^3 / b + 4 c Delta^2``
    with ``z = |g2| u / g1``; where ``z > 1/8`` (``pu -> f``: no convergence) the frozen
    tail with ``err = (2 F w / b + 4 c) Delta_0^2``.

    Returns ``(Delta, rho, err, tau, 1 - rho)``.
    """
    f, e, Fw = P[p.FF], P[p.E], P[p.F] * P[p.W]
    a = pu + f
    b = pu - f
    qq = math.sqrt(b / a)
    sab = math.sqrt(a * b)
    tau = 1.0 / a + 1.0 / sab
    one_m = (1.0 - e) + e * (2.0 * f) / (a * (1.0 + qq))
    rho = e * qq
    g1 = tau / one_m
    d0 = u * g1
    err0 = (2.0 * Fw / b + 4.0 * P[p.DAMP]) * (d0 * d0)
    d2 = -p1 * (0.5 / (a * a * a) + (1.0 / (6.0 * a * a) + 0.5 / (a * b)) / sab
                + 1.0 / (6.0 * a * b * b))
    r1 = p1 * (0.5 / (a * b) - 1.0 / (6.0 * a * a) + 1.0 / (3.0 * a * b * qq))
    tau_p = -1.0 / (a * a) - (a + b) / (2.0 * sab * (a * b))
    rho_p = e * f / (qq * a * a)
    g1p = p1 * (tau_p * one_m + tau * rho_p) / (one_m * one_m)
    g2 = (d2 + g1 * rho * r1 + g1p * tau * rho) / (one_m * (1.0 + rho))
    corr = g2 * (u * u)
    delta = d0 + corr
    z = abs(g2) * u / g1
    if not z <= 0.125:
        return d0, rho, err0, tau, one_m
    err = (2.0 * abs(corr) * (z + Fw * delta / b) + 2.0 * Fw * P[p.W] * delta * delta * delta / b
           + 4.0 * P[p.DAMP] * delta * delta)
    return delta, rho, err, tau, one_m


@kernel
def chatter_state(P, pu, u, rho, tau, one_m, remaining):
    """State ``(y, vy)`` (distance from the wall, its rate) ``remaining`` after the impact:
    frozen-force bounces, bounce ``n`` starting at ``u tau (1 - rho^n)/(1 - rho)`` with
    speed ``u rho^n``."""
    f = P[p.FF]
    frac = min(max(1.0 - remaining * one_m / (u * tau), 1e-300), 1.0)
    n = math.floor(math.log(frac) / math.log(max(rho, 1e-300)))
    rn = rho ** n
    qrem = max(remaining - u * tau * (1.0 - rn) / one_m, 0.0)
    un = u * rn
    t_up = un / (pu + f)
    if qrem <= t_up:
        return max(un * qrem - 0.5 * (pu + f) * qrem * qrem, 0.0), un - (pu + f) * qrem
    q2 = max(qrem - t_up, 0.0)
    return max(un * un / (2.0 * (pu + f)) - 0.5 * (pu - f) * q2 * q2, 0.0), -(pu - f) * q2
