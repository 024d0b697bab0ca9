"""One scalar Dormand-Prince 8(5,3) step with dense output, compiled (``fast.ode``'s flights).

In flight with friction sign ``s`` the state ``y = (x, v[, J11, J12, J21, J22])`` obeys::

    x' = v,   v' = A(x, t) - s f - c v,   A = F cos(k x) cos(w t)          (k = 0: no position
    J' = [[0, 1], [A_x, -c]] J,            A_x = -F k sin(k x) cos(w t)      forcing)

(the variational equations give the flight matrix ``J``, integrated by the same tableau, so
the returned matrix is the exact derivative of the discrete flow).  DOP853 (Hairer, Norsett,
Wanner I, II.5) with its own 7th-order continuous extension (three extra stages): the
right-hand side is analytic between events, so a high-order one-step method reaches float64
accuracy in few steps.  Coefficients: ``scipy.integrate._ivp.dop853_coefficients``, read at
import into module constants.

Work buffer (``fast.ode`` owns it, passed as a raw pointer): ``K`` (16 stages of 6), ``Y0``
(the step's start), ``Y1`` (its end), ``YS`` (stage argument), ``Q`` (7 x 6 dense-output
coefficients), ``YD`` (a dense-output value).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _dop

from .jit import kernel

NS = _dop.N_STAGES                                   # 12
NK = _dop.A.shape[0]                                 # 16 with the dense-output stages
A = np.ascontiguousarray(_dop.A, dtype=np.float64)
B = np.ascontiguousarray(_dop.B, dtype=np.float64)
C = np.ascontiguousarray(_dop.C, dtype=np.float64)
D = np.ascontiguousarray(_dop.D, dtype=np.float64)
#: offsets of the work buffer (6 components each)
K, Y0, Y1, YS, Q, YD = 0, 6 * NK, 6 * NK + 6, 6 * NK + 12, 6 * NK + 18, 6 * NK + 60
SIZE = 6 * NK + 66


@kernel(inline=True)
def rhs(F, f, c, k, w, s, t, wk, src, dst, n):
    """``dst <- y'(t)`` for the state at ``wk[src:src+n]`` (``n`` = 2 or 6)."""
    x, v = wk[src], wk[src + 1]
    cw = math.cos(w * t)
    wk[dst] = v
    wk[dst + 1] = F * math.cos(k * x) * cw - s * f - c * v
    if n == 6:
        ax = -F * k * math.sin(k * x) * cw
        wk[dst + 2], wk[dst + 3] = wk[src + 4], wk[src + 5]
        wk[dst + 4] = ax * wk[src + 2] - c * wk[src + 4]
        wk[dst + 5] = ax * wk[src + 3] - c * wk[src + 5]


@kernel
def step(F, f, c, k, w, s, t, h, wk, n, dense):
    """One step of length ``h`` from ``(t, wk[Y0])``: ``wk[Y1]`` the new state; with
    ``dense`` also ``wk[Q]`` for ``dense_eval``."""
    rhs(F, f, c, k, w, s, t, wk, Y0, K, n)
    last = NK if dense else NS
    for i in range(1, last):
        if i == NS:                                   # the first dense stage: y1 itself
            for m in range(n):
                acc = 0.0
                for j in range(NS):
                    acc += B[j] * wk[K + 6 * j + m]
                wk[Y1 + m] = wk[Y0 + m] + h * acc
            rhs(F, f, c, k, w, s, t + h, wk, Y1, K + 6 * NS, n)
            continue
        for m in range(n):
            acc = 0.0
            for j in range(i):
                if A[i, j] != 0.0:
                    acc += A[i, j] * wk[K + 6 * j + m]
            wk[YS + m] = wk[Y0 + m] + h * acc
        rhs(F, f, c, k, w, s, t + C[i] * h, wk, YS, K + 6 * i, n)
    if not dense:
        for m in range(n):
            acc = 0.0
            for j in range(NS):
                acc += B[j] * wk[K + 6 * j + m]
            wk[Y1 + m] = wk[Y0 + m] + h * acc
        return
    for m in range(n):
        dy = wk[Y1 + m] - wk[Y0 + m]
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


@kernel(inline=True)
def dense_eval(wk, theta, n):
    """``wk[YD] <-`` the continuous extension at ``theta`` in ``[0, 1]``."""
    for m in range(n):
        y = 0.0
        for i in range(7):                            # Q6, Q5, ..., Q0
            y += wk[Q + 6 * (6 - i) + m]
            y *= theta if i % 2 == 0 else 1.0 - theta
        wk[YD + m] = y + wk[Y0 + m]
