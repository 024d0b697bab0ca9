"""One scalar Dormand-Prince 8(5,3) step with dense output, compiled, in compensated
arithmetic (``fast.ode``'s flights, driven by ``fast.compensated``).

In flight with friction sign ``s`` the state ``y = (x, v[, J11, J12, J21, J22])`` obeys::

    x' = v,   v' = A(x, t) - s f - c v,   A = F cos(k x) cos(w t)          (k = 0: no position
    J' = [[0, 1], [A_x, -c]] J,            A_x = -F k sin(k x) cos(w t)      forcing)

(the variational equations give the flight matrix ``J``, integrated by the same tableau, so
the returned matrix is the exact derivative of the discrete flow).  DOP853 (Hairer, Norsett,
Wanner I, II.5) with its own 7th-order continuous extension (three extra stages): the
right-hand side is analytic between events, so a high-order one-step method reaches float64
accuracy in few steps.  Coefficients: ``scipy.integrate._ivp.dop853_coefficients``, read at
import into module constants.

Rounding (issue 33).  Once the truncation is below float64's resolution the step loses to
rounding, and DOP853 amplifies the rounding of its stage rates: its weights reach -5.8
(``||b||_2 = 7.6``), so independent half-ulp errors of the 12 accelerations make ~4 ulp of
``h a`` per step, a random walk of about an ulp of ``v`` per unit time at ``F ~ 2`` (measured:
the result moved by 1-2 ulp with the start time of a flight).  Hence:

* the state is a double-double ``Y0 + L0``; the step's end ``Y1 + L1 = Y0 + L0 + dy`` exactly
  (``fast.dd.two_sum``).  For the velocity ``dy = h sum (b_i + b_lo_i)(a_i + a_lo_i)`` by a
  compensated dot product (Ogita, Rump & Oishi's Dot2), with the weights' low parts (from 30
  digits: their float64 roundings sum to 1 only within ~eps, a consistency error that no step
  count removes) and the accelerations' (``AL``).  For the components whose rate is another
  component (``x' = v``, ``J1' = J2``) the Nystrom form of the same step, ``dy = h v0 + h^2 sum
  bbar_j a_j`` with ``bbar = b A`` to 30 digits, and the stages' positions likewise, ``x_i =
  x0 + c_i h v0 + h^2 sum (A^2)_ij a_j`` (the same step in exact arithmetic: the roundings of
  the stage velocities drop out, and so does the cancellation in ``h sum a_ij v_j`` -- rows of
  ``|A|`` sum to 96 -- which moved the stage's ``cos(k x)`` by ~100 eps ``h |v|``);
* the trigonometry at the step's start in double-double, ``cos, sin(w t0)`` and ``cos, sin(k
  x0)`` (``TRIG``, ``fast.compensated``), and per stage the rotation by the small angles ``u =
  w c_i h`` and ``delta = k (x_i - x0)`` (``|u|, |delta| <~ 2 pi / S``: series ``_small`` to
  ~1e-20), so the acceleration ``F cos(k x) cos(w t) - s f - c v`` comes with its own rounding
  (``fast.dd.two_prod``, ``two_sum``) and the parameters' low parts: ~1e-18 relative, no libm
  call per stage.

Work buffer (``fast.ode`` owns it, passed as a raw pointer): ``K`` (16 stages of 6), ``Y0``
(the step's start), ``Y1`` (its end), ``YS`` (stage argument), ``Q`` (7 x 6 dense-output
coefficients), ``YD`` (a dense-output value), ``L0``, ``L1`` (the low parts of ``Y0``, ``Y1``),
``AL`` (the low parts of the 16 accelerations), ``TRIG`` (``cos w t0, sin w t0, cos k x0, sin
k x0``, each a double-double), ``DX1`` (``x1 - x0``).
"""
from __future__ import annotations

import math

import mpmath
import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _dop

from . import dd
from .jit import kernel

#: the weights b_i to 30 digits (Hairer's dop853.f, as written in scipy's source)
_B30 = {0: "5.42937341165687622380535766363e-2", 5: "4.45031289275240888144113950566",
        6: "1.89151789931450038304281599044", 7: "-5.8012039600105847814672114227",
        8: "3.1116436695781989440891606237e-1", 9: "-1.52160949662516078556178806805e-1",
        10: "2.01365400804030348374776537501e-1", 11: "4.47106157277725905176885569043e-2"}
#: the Nystrom weights bbar = b A (below) to 30 digits, from the 30-digit tableau of the same
#: source: with float64's A they sum to 1/2 only within 8e-16, which moved x by ~0.5 eps a
#: flight (bbar_3, bbar_4 are 0 to 30 digits, 7e-17 and -2e-17 from float64's A)
_BB30 = {0: "5.42937341165687622380535766366e-2", 5: "2.96687526183493925429409300378",
         6: "1.41863842448587528728211199283", 7: "-4.01621812616117407947730021572",
         8: "1.08508599759650014460545088417e-1", 9: "-6.08643798650064314224715227204e-2",
         10: "2.87664858291471926249680767858e-2"}
NS = _dop.N_STAGES                                   # 12
NK = _dop.A.shape[0]                                 # 16 with the dense-output stages
A = np.ascontiguousarray(_dop.A, dtype=np.float64)
B = np.ascontiguousarray(_dop.B, dtype=np.float64)
C = np.ascontiguousarray(_dop.C, dtype=np.float64)
D = np.ascontiguousarray(_dop.D, dtype=np.float64)
with mpmath.workdps(40):
    assert all(float(mpmath.mpf(b)) == B[j] for j, b in _B30.items()), "scipy's DOP853 weights changed"
    B_LO = np.array([float(mpmath.mpf(_B30[j]) - B[j]) if j in _B30 else 0.0 for j in range(NS)])
    _bb = [mpmath.mpf(_BB30.get(j, 0)) for j in range(NS)]
    assert abs(sum(_bb) - mpmath.mpf(1) / 2) < 1e-28, "bbar must sum to 1/2"
    assert all(abs(_bb[j] - sum(mpmath.mpf(b) * mpmath.mpf(A[i, j]) for i, b in _B30.items())) < 1e-14
               for j in range(NS)), "bbar is not b A of scipy's tableau"
    #: the Nystrom weights of the position-like components, high and low parts
    BB = np.array([float(b) for b in _bb])
    BB_LO = np.array([float(b - float(b)) for b in _bb])
#: the stages' positions in Nystrom form, ``x_i = x0 + c_i h v0 + h^2 sum_j (A^2)_ij a_j``: the
#: same stages, without the cancellation in ``h sum_j a_ij v_j`` (rows of ``|A|`` sum to 96)
with mpmath.workdps(40):
    AA = np.array([[float(sum(mpmath.mpf(A[i, l]) * mpmath.mpf(A[l, j]) for l in range(NK)))
                    for j in range(NK)] for i in range(NK)])
#: the component that is the rate of each component (x' = v, J1' = J2), -1 where none is
RATE_OF = np.array([1, -1, 4, 5, -1, -1])
#: 1/n! with alternating signs: cos d - 1 = d^2 (C2 + d^2 (C4 + ...)), sin d = d + d^3 (S3 + ...)
C2, C4, C6, C8, C10, C12 = (-0.5, 1 / 24, -1 / 720, 1 / 40320, -1 / 3628800, 1 / 479001600)
S3, S5, S7, S9, S11, S13 = (-1 / 6, 1 / 120, -1 / 5040, 1 / 362880, -1 / 39916800, 1 / 6227020800)
#: the series are used up to this |d| (first omitted terms below 1e-19); libm beyond
SMALL = 0.25

#: offsets of the work buffer (6 components each)
K, Y0, Y1, YS, Q, YD = 0, 6 * NK, 6 * NK + 6, 6 * NK + 12, 6 * NK + 18, 6 * NK + 60
L0, L1, AL, TRIG, DX1 = 6 * NK + 66, 6 * NK + 72, 6 * NK + 78, 7 * NK + 78, 7 * NK + 86
CW, CWL, SW, SWL, CK, CKL, SK, SKL = range(TRIG, TRIG + 8)
SIZE = 7 * NK + 87


@kernel
def _small(d):
    """``(cos d - 1, sin d)`` for a small angle ``d`` (series; libm above ``SMALL``)."""
    if abs(d) > SMALL:
        return math.cos(d) - 1.0, math.sin(d)
    z = d * d
    cm = z * (C2 + z * (C4 + z * (C6 + z * (C8 + z * (C10 + z * C12)))))
    return cm, d + d * z * (S3 + z * (S5 + z * (S7 + z * (S9 + z * (S11 + z * S13)))))


@kernel
def rhs(cst, s, u, dk, wk, src, i, n):
    """Stage ``i``'s rates ``wk[K + 6 i:] <- y'`` for the state at ``wk[src:src+n]`` (``n`` = 2 or
    6) at ``w t = w t0 + u``, ``k x = k x0 + dk`` (``TRIG``); the acceleration's low part in
    ``wk[AL + i]``.  ``cst``: ``(F, F_lo, f, f_lo, c, c_lo, k, k_lo, w, w_lo)``."""
    F, F_lo, f, f_lo, c, c_lo, k = cst[0], cst[1], cst[2], cst[3], cst[4], cst[5], cst[6]
    dst = K + 6 * i
    v = wk[src + 1]
    cm, sn = _small(u)
    cw, cw_lo = wk[CW], wk[CWL] + (wk[CW] * cm - wk[SW] * sn)          # cos(w t) = cw + cw_lo
    cm, sn = _small(dk)
    ck, ck_lo = wk[CK], wk[CKL] + (wk[CK] * cm - wk[SK] * sn)          # cos(k x) = ck + ck_lo
    p1, e1 = dd.two_prod(F, ck)
    e1 += F * ck_lo + F_lo * ck
    p2, e2 = dd.two_prod(p1, cw)
    e2 += e1 * cw + (p1 + e1) * cw_lo
    a, e3 = dd.two_sum(p2, -s * f)
    p3, e4 = dd.two_prod(c, v)
    a, e5 = dd.two_sum(a, -p3)
    a, lo = dd.two_sum(a, ((e2 + e3) + (e5 - e4)) - (s * f_lo + c_lo * v))
    wk[dst], wk[dst + 1], wk[AL + i] = v, a, lo
    if n == 6:
        sk = wk[SK] + (wk[SKL] + wk[SK] * cm + wk[CK] * sn)
        ax = -F * k * sk * (cw + cw_lo)
        wk[dst + 2], wk[dst + 3] = wk[src + 4], wk[src + 5]
        wk[dst + 4] = ax * wk[src + 2] - c * wk[src + 4]
        wk[dst + 5] = ax * wk[src + 3] - c * wk[src + 5]


@kernel
def step(cst, s, h, wk, n, dense):
    """One step of length ``h`` from ``wk[Y0] + wk[L0]`` (``TRIG`` at its start; ``cst`` as in
    ``rhs``): ``wk[Y1] + wk[L1]`` the new state; with ``dense`` also ``wk[Q]`` for
    ``dense_eval`` (and the rates at ``Y1``, the first dense stage, in ``wk[K + 6 NS:]``)."""
    k, w = cst[6], cst[8]
    rhs(cst, s, 0.0, 0.0, wk, Y0, 0, n)
    last = NK if dense else NS
    for i in range(1, last):
        if i == NS:                                   # the first dense stage: y1 itself
            _end(h, wk, n)
            rhs(cst, s, w * h, k * wk[DX1], wk, Y1, NS, n)
            continue
        dx = 0.0
        for m in range(n):
            acc = 0.0
            if m == 0:                                # x_i - x0 in Nystrom form
                for j in range(i):
                    acc += AA[i, j] * wk[K + 6 * j + 1]
                dx = C[i] * h * (wk[Y0 + 1] + wk[L0 + 1]) + h * h * acc
                wk[YS] = wk[Y0] + (wk[L0] + dx)
                continue
            for j in range(i):
                if A[i, j] != 0.0:
                    acc += A[i, j] * wk[K + 6 * j + m]
            wk[YS + m] = wk[Y0 + m] + (wk[L0 + m] + h * acc)
        rhs(cst, s, w * (C[i] * h), k * dx, wk, YS, i, n)
    if not dense:
        _end(h, wk, n)
        return
    for m in range(n):
        dy = (wk[Y1 + m] - wk[Y0 + m]) + (wk[L1 + m] - wk[L0 + m])
        k0, k12 = wk[K + m], wk[K + 6 * NS + m]
        wk[Q + m] = dy
        wk[Q + 6 + m] = h * k0 - dy
        wk[Q + 12 + m] = 2 * dy - h * (k12 + k0)
        for j in range(4):
            acc = 0.0
            for i in range(NK):
                if D[j, i] != 0.0:
                    acc += D[j, i] * wk[K + 6 * i + m]
            wk[Q + 18 + 6 * j + m] = h * acc


@kernel
def _end(h, wk, n):
    """``Y1 + L1 = Y0 + L0 + dy`` (module docstring): ``dy = dh + dl``, the sum exact up to the
    rounding of ``L0 + dl``; ``DX1 <- x1 - x0``."""
    for m in range(n):
        p = RATE_OF[m]
        if p >= 0:                                    # Nystrom: h v0 + h^2 sum bbar_j a_j
            acc, lo = 0.0, 0.0
            for j in range(NS):
                acc += BB[j] * wk[K + 6 * j + p]
                lo += BB_LO[j] * wk[K + 6 * j + p]
            dh, dl = dd.two_prod(h, wk[Y0 + p])
            dl += h * wk[L0 + p] + h * h * (acc + lo)
        elif m == 1:                                  # Dot2 of the weights and accelerations
            acc, lo = 0.0, 0.0
            for j in range(NS):
                pj, ej = dd.two_prod(B[j], wk[K + 6 * j + 1])
                acc, e = dd.two_sum(acc, pj)
                lo += (ej + e) + (B_LO[j] * wk[K + 6 * j + 1] + B[j] * wk[AL + j])
            dh, dl = dd.two_prod(h, acc)
            dl += h * lo
        else:
            acc = 0.0
            for j in range(NS):
                acc += B[j] * wk[K + 6 * j + m]
            dh, dl = h * acc, 0.0
        if m == 0:
            wk[DX1] = dh + dl
        y1, e = dd.two_sum(wk[Y0 + m], dh)
        wk[Y1 + m], wk[L1 + m] = dd.two_sum(y1, e + (wk[L0 + m] + dl))


@kernel
def dense_eval(wk, theta, n):
    """``wk[YD] <-`` the continuous extension at ``theta`` in ``[0, 1]`` (rounded)."""
    for m in range(n):
        y = 0.0
        for i in range(7):                            # Q6, Q5, ..., Q0
            y += wk[Q + 6 * (6 - i) + m]
            y *= theta if i % 2 == 0 else 1.0 - theta
        wk[YD + m] = wk[Y0 + m] + (y + wk[L0 + m])
