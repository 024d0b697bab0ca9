"""Double-double arithmetic in compiled code: a value is an unevaluated sum ``hi + lo`` of
two float64 with ``|lo| <= ulp(hi) / 2`` (about 32 significant digits).

numba has no ``long double``; where float64 is not enough -- event times, the state carried
from event to event, the period, the flight re-evaluated at an event -- ``fast`` works in
double-double instead.  The building blocks are the error-free transformations (Knuth's
``two_sum``, the FMA product ``two_prod``: ``a + b = s + e`` and ``a b = p + e`` exactly)
and the "sloppy" double-double sum and product (Dekker; Joldes, Muller & Popescu, ACM TOMS
44 (2017), algorithms 5 and 10) without the final renormalisation: absolute error of a few
``u^2 (|a| + |b|)`` for a sum and ``u^2 |a b|`` for a product, ``u = 2^-53``.  That is absolute accuracy relative to the
operands, which is what a flight formula needs: each term is then exact to ~1e-32 of its
own size, so cancellation between terms costs nothing at float64 output.

``sincos`` of a double-double angle: reduction by ``pi/32`` (the exact product ``k pi/32``
from ``two_prod`` and a three-part ``pi/32``; ``a_hi - k p_hi`` is exact by Sterbenz's
lemma), a table of ``sin, cos(k pi/32)`` as double-doubles (mpmath at 40 digits, built once
at import), and Taylor series for ``|r| <= pi/64``: the first correction term (``r^3/6``,
``r^2/2``) in double-double, the rest (``< 2.4e-9 |r|`` and ``< 2.4e-7``) in float64.
Measured against mpmath: absolute error below 1e-22 (the float64 tail of the cosine), a
thousand times below the long double (1.1e-19) the numpy engine used.  ``expm1`` of a
double-double argument (damped flights) halves the argument to ``|y| <= 2^-6``, sums the
series (three terms in double-double), and doubles back with ``expm1(2y) = expm1(y) (2 +
expm1(y))``: relative error below 1e-21 for ``|y| <= 10``.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np

from .jit import fma, kernel


@kernel
def two_sum(a, b):
    """``a + b = s + e`` exactly (Knuth)."""
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


@kernel
def fast_two_sum(a, b):
    """``a + b = s + e`` exactly, for ``|a| >= |b|`` (or ``a = 0``) (Dekker)."""
    s = a + b
    return s, b - (s - a)


@kernel
def two_prod(a, b):
    """``a b = p + e`` exactly (FMA)."""
    p = a * b
    return p, fma(a, b, -p)


@kernel
def add(ah, al, bh, bl):
    """``(ah + al) + (bh + bl)`` (sloppy sum, not renormalised: ``|lo|`` may reach a few
    ulp of ``hi``, which costs nothing in the next operation and saves a dependent
    ``fast_two_sum`` on every step)."""
    s, e = two_sum(ah, bh)
    return s, e + (al + bl)


@kernel
def add_d(ah, al, b):
    """``(ah + al) + b``."""
    s, e = two_sum(ah, b)
    return s, e + al


@kernel
def mul(ah, al, bh, bl):
    """``(ah + al)(bh + bl)``: the exact product of the high parts plus the cross terms
    (two independent FMA chains), not renormalised."""
    p = ah * bh
    return p, fma(ah, bh, -p) + fma(ah, bl, al * bh)


@kernel
def mul_d(ah, al, b):
    """``(ah + al) b``."""
    p = ah * b
    return p, fma(ah, b, -p) + al * b


@kernel
def norm(ah, al):
    """The renormalised pair (``|lo| <= ulp(hi)/2``)."""
    return fast_two_sum(ah, al)


def split_exact(value):
    """``(hi, lo)`` of an mpmath value: ``hi`` correctly rounded, ``lo`` the rest rounded
    (call it inside a ``workdps`` of at least 35 digits: ``lo`` needs them)."""
    hi = float(value)
    return hi, float(value - hi)


def _tables():
    """``sin, cos(k pi/32)``, ``k = 0..63``, as double-doubles, and ``pi/32`` in three
    parts (``p1`` correctly rounded, ``p2 + p3`` the rest): 40 digits of mpmath."""
    with mpmath.workdps(40):
        step = mpmath.pi / 32
        sin_t = np.array([split_exact(mpmath.sin(k * step)) for k in range(64)])
        cos_t = np.array([split_exact(mpmath.cos(k * step)) for k in range(64)])
        p1 = float(step)
        p2, p3 = split_exact(step - p1)
    return sin_t, cos_t, (p1, p2, p3)


_SIN_T, _COS_T, _PI32 = _tables()
SIN_HI, SIN_LO = _SIN_T[:, 0].copy(), _SIN_T[:, 1].copy()
COS_HI, COS_LO = _COS_T[:, 0].copy(), _COS_T[:, 1].copy()
PI32_1, PI32_2, PI32_3 = _PI32
INV_PI32 = 32.0 / math.pi
#: Taylor coefficients of the float64 tails: sin r = r - r^3/6 + r^5 S(r^2),
#: cos r = 1 - r^2/2 + r^4 C(r^2) (|r| <= pi/64: the first omitted terms are < 1e-24)
_S = (1.0 / 120, -1.0 / 5040, 1.0 / 362880, -1.0 / 39916800, 1.0 / 6227020800)
_C = (1.0 / 24, -1.0 / 720, 1.0 / 40320, -1.0 / 3628800, 1.0 / 479001600)
S0, S1, S2, S3, S4 = _S
C0, C1, C2, C3, C4 = _C
#: -1/6 as a double-double
with mpmath.workdps(40):
    M6_HI, M6_LO = split_exact(-mpmath.mpf(1) / 6)
    P6_HI, P6_LO = -M6_HI, -M6_LO


@kernel
def _sincos_small(rh, rl):
    """``sin r``, ``cos r`` as double-doubles for ``|r| <= pi/64``."""
    r2h, r2l = mul(rh, rl, rh, rl)
    r3h, r3l = mul(r2h, r2l, rh, rl)
    th, tl = mul(r3h, r3l, M6_HI, M6_LO)                  # -r^3/6
    z = r2h
    tail_s = r3h * z * (S0 + z * (S1 + z * (S2 + z * (S3 + z * S4))))
    sh, sl = add(rh, rl, th, tl)
    sh, sl = add_d(sh, sl, tail_s)
    tail_c = z * z * (C0 + z * (C1 + z * (C2 + z * (C3 + z * C4))))
    ch, cl = add_d(1.0, 0.0, -0.5 * r2h)                  # 1 - r^2/2 (halving is exact)
    ch, cl = add_d(ch, cl, -0.5 * r2l)
    ch, cl = add_d(ch, cl, tail_c)
    return sh, sl, ch, cl


@kernel
def sincos(ah, al):
    """``(sin a, cos a)`` of the double-double ``a = ah + al``: ``(sh, sl, ch, cl)``."""
    k = np.rint(ah * INV_PI32)
    if k == 0.0:
        return _sincos_small(ah, al)
    p, e = two_prod(k, PI32_1)
    rh = ah - p                                            # exact (Sterbenz)
    rh, rl = add_d(rh, 0.0, -e)
    rh, rl = add_d(rh, rl, -k * PI32_2)
    rh, rl = add_d(rh, rl, al - k * PI32_3)
    sh, sl, ch, cl = _sincos_small(rh, rl)
    j = int(k) & 63
    a1, a2 = mul(SIN_HI[j], SIN_LO[j], ch, cl)
    b1, b2 = mul(COS_HI[j], COS_LO[j], sh, sl)
    c1, c2 = mul(COS_HI[j], COS_LO[j], ch, cl)
    d1, d2 = mul(SIN_HI[j], SIN_LO[j], sh, sl)
    s_h, s_l = add(a1, a2, b1, b2)
    c_h, c_l = add(c1, c2, -d1, -d2)
    return s_h, s_l, c_h, c_l


@kernel
def sincos64(a):
    """``(sin a, cos a)`` in float64 for the event search (within 2 ulp; no libm call):
    the same reduction and table as ``sincos``, the series in float64."""
    k = np.rint(a * INV_PI32)
    r = (a - k * PI32_1) - k * PI32_2
    z = r * r
    s = r + r * z * (-1.0 / 6.0 + z * (S0 + z * (S1 + z * S2)))
    c = 1.0 - 0.5 * z + z * z * (C0 + z * (C1 + z * C2))
    j = int(k) & 63
    return SIN_HI[j] * c + COS_HI[j] * s, COS_HI[j] * c - SIN_HI[j] * s


@kernel
def expm1(yh, yl):
    """``exp(y) - 1`` of a double-double ``y`` with ``|y| <= 40`` (damped flights)."""
    m = 0
    while abs(yh) > 0.015625 and m < 16:
        yh *= 0.5
        yl *= 0.5
        m += 1
    # series y + y^2/2 + y^3/6 + ...: the first three terms in double-double, the rest
    # (< 2.5e-9 |y|) in float64
    z = yh
    tail = z * z * z * z * (1.0 / 24 + z * (1.0 / 120 + z * (1.0 / 720 + z * (
        1.0 / 5040 + z * (1.0 / 40320 + z * (1.0 / 362880))))))
    q2h, q2l = mul(yh, yl, yh, yl)
    q3h, q3l = mul(q2h, q2l, yh, yl)
    q3h, q3l = mul(q3h, q3l, P6_HI, P6_LO)
    eh, el = add(yh, yl, 0.5 * q2h, 0.5 * q2l)
    eh, el = add(eh, el, q3h, q3l)
    eh, el = add_d(eh, el, tail)
    for _ in range(m):                                     # expm1(2y) = expm1(y)(2 + expm1(y))
        t2h, t2l = add_d(eh, el, 2.0)
        eh, el = mul(eh, el, t2h, t2l)
    return eh, el
