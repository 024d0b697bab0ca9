"""A float64 flight under position forcing, run *backward* in bulk (numpy, one array lane per
case), for the constructed events of ``construct_position``: independent of ``fast`` (its own
Taylor series, no DOP853) and of ``reference`` (no mpmath).

The flight ``x'' = A(x, t) - s f - c x'``, ``A = F cos(k x) cos(w t)``, run backward from
``(t*, x*, v*)`` is the forward flight of the reversed motion ``y(tau) = x(-tau)``:
``y'' = F cos(k y) cos(w tau) - s f + c y'`` (``y' = -v``; damping becomes ``-c``) from
``tau = -t*`` to ``tau = 0``.  It is taken in ``SAMPLES`` equal intervals of ``D = t*/SAMPLES``
(the certificate's grid, ``construct``), each in ``m`` Taylor substeps of order ``ORDER``.

A substep of length ``h`` computes the scaled coefficients ``Y_n = y_n h^n`` by the recurrence
of ``reference.taylor``'s docstring (``n C_n = -sum j U_j S_{n-j}``, ``n S_n = sum j U_j
C_{n-j}``, ``(n+1)(n+2) Y_{n+2} = h^2 (F (C*P)_n - s f [n = 0]) - c h (n+1) Y_{n+1}``, written
again here on arrays) and the flight matrix of the step from the variational series
(``B_n = -F k h^2 (S*P)_n``, order ``VAR_ORDER``).

Error of one substep (the model the band rests on; ``tests/test_construct_position.py`` holds
it against mpmath's Taylor flight at 40 digits):

* truncation: with ``rho = h / Q``, an a-priori bound ``(X, V)`` of ``|y - y0|, |y' - y0'|`` on
  the complex disc ``|tau| <= rho`` (conditions (E1), (E2) of ``reference.taylor``, with
  ``|c|``: the reversed damping is negative) gives ``|y_n h^n| <= X Q^n`` and the remainders
  ``X Q^(N+2) / (1 - Q)``, ``V Q^(N+1) / (1 - Q)``: below ``1e-19`` of the scale at ``N = 20``,
  ``Q = 1/8``.  A case whose (E1), (E2) fail even at ``MAX_SUB`` substeps is dropped (``ok``);
* rounding: the state and the time are carried as double-double sums (``hi + lo``; the product
  ``y' h`` exact by Dekker's split), so the only roundings are those of the increments' higher
  terms ``Y_n``, ``n >= 2``: each is at most ``|a|max h^2 Q^(n-2)`` (Cauchy's estimate of the
  acceleration, ``|a| <= Amax = V / rho`` on the disc) and carries at most ``~4 n`` roundings
  of its own magnitude, so ``sum_n 4 n Q^(n-2) <= ROUND``: ``ROUND eps Amax h^2`` in ``y`` and
  ``ROUND eps Amax h`` in ``y'``;

and both are carried to the constructed event by the flight matrices: an error ``l`` made at
time ``t_j`` moves the event state by ``|M_j| l``, ``M_j`` the forward flight matrix from
``t_j`` to ``t*`` (the inverse of the backward product).  The rounding of the start to float64
(``eps |x0|``, ``eps |v0|``, by ``M_0``) is added: ``(dx, dv)``, what the band of
``construct`` is made of.  For the certificate the samples carry a cruder bound ``E_j``
(Gronwall: ``E <- E exp(L h) + l``, ``L = max(1, F k + |c|)``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

EPS = 2.0 ** -52
ORDER = 20
VAR_ORDER = 12
#: a substep is ``Q`` of the radius on which its a-priori bound holds
Q = 0.125
#: roundings of the higher terms, in units of ``eps Amax h^2`` (``sum_n 4 n Q^(n-2)`` = 9.2)
ROUND = 10.0
#: most substeps of one grid interval (a case that needs more is dropped)
MAX_SUB = 64
_SPLIT = 134217729.0                 # 2^27 + 1: Dekker's split


def _two_sum(a, b):
    s = a + b
    bb = s - a
    return s, (a - (s - bb)) + (b - bb)


def _two_prod(a, b):
    p = a * b
    a1 = _SPLIT * a
    ah = a1 - (a1 - a)
    b1 = _SPLIT * b
    bh = b1 - (b1 - b)
    al, bl = a - ah, b - bh
    return p, ((ah * bh - p) + ah * bl + al * bh) + al * bl


@dataclass(frozen=True)
class Params:
    """``F, f, w, k`` and the *reversed* damping ``c = -damping`` (floats)."""

    F: float
    f: float
    w: float
    k: float
    c: float

    @staticmethod
    def of(scene):
        k = scene.float("wavenumber") if scene.has("position_forcing") else 0.0
        return Params(scene.float("F"), scene.float("f"), scene.float("omega"), k, -scene.float("damping"))

    @property
    def lipschitz(self):
        return max(1.0, self.F * self.k + abs(self.c))


def _dot(a, b_rev):
    return np.einsum("ij,ij->j", a, b_rev)


def series(P: Params, tau, y, yd, s, h, variational=False):
    """Scaled coefficients ``Y_0 .. Y_{ORDER+1}`` (rows) of the reversed flight through
    ``(tau, y, y')`` for substeps ``h`` (arrays), and with ``variational`` the step's flight
    matrix ``(m11, m12, m21, m22)`` at ``h``."""
    N, m = ORDER, y.size
    Y = np.zeros((N + 2, m))
    Y[0], Y[1] = y, yd * h
    JU = np.zeros((N + 2, m))
    JU[1] = P.k * Y[1]
    C, S = np.empty((N + 1, m)), np.empty((N + 1, m))
    C[0], S[0] = np.cos(P.k * y), np.sin(P.k * y)
    ct, st = np.cos(P.w * tau), np.sin(P.w * tau)
    cyc = (ct, -st, -ct, st)
    Pn, pw, wh = np.empty((N, m)), np.ones(m), P.w * h
    Fh2, ch, sfh2 = P.F * h * h, P.c * h, s * P.f * h * h
    for n in range(N):
        Pn[n] = cyc[n % 4] * pw
        pw = pw * wh / (n + 1)
        if n >= 1:
            C[n] = -_dot(JU[1:n + 1], S[n - 1::-1]) / n
            S[n] = _dot(JU[1:n + 1], C[n - 1::-1]) / n
        a = Fh2 * _dot(C[:n + 1], Pn[n::-1]) - ch * (n + 1) * Y[n + 1]
        if n == 0:
            a = a - sfh2
        Y[n + 2] = a / ((n + 1) * (n + 2))
        JU[n + 2] = P.k * (n + 2) * Y[n + 2]
    if not variational:
        return Y, None
    K = VAR_ORDER
    B = np.array([-P.F * P.k * h * h * _dot(S[:n + 1], Pn[n::-1]) for n in range(K)])
    cols = []
    for dx0, dv0 in ((np.ones(m), np.zeros(m)), (np.zeros(m), h.copy())):
        DX, DV = [dx0], [dv0]
        for n in range(K):
            DX.append(DV[n] / (n + 1))
            DV.append((_dot(B[:n + 1], np.array(DX[n::-1])) - ch * DV[n]) / (n + 1))
        cols.append((sum(DX), sum(DV) / h))
    return Y, (cols[0][0], cols[1][0], cols[0][1], cols[1][1])


def enclosure(P: Params, vabs, rho):
    """``(X, V, ok)``: (E1) ``rho (|v0| + V) <= X``, (E2) ``rho (F cosh(k X) cosh(w rho) + f
    + |c| (|v0| + V)) <= V`` (``reference.taylor``), by a bounded fixed-point iteration."""
    c = abs(P.c)
    chw = np.cosh(np.minimum(P.w * rho, 700.0))
    V = rho * (P.F * chw + P.f + c * vabs)
    ok = np.zeros(vabs.shape, bool)
    for _ in range(60):
        speed = vabs + V
        X = rho * speed
        kX = P.k * X
        need = rho * (P.F * np.cosh(np.minimum(kX, 700.0)) * chw + P.f + c * speed)
        good = (need * (1 + 1e-9) <= V) & (kX < 700) & np.isfinite(need)
        ok |= good
        if ok.all():
            break
        V = np.where(ok, V, 1.05 * need)
    return X, V, ok


@dataclass
class Backward:
    """The backward flights of a batch: samples ``x, v`` on the grid (row ``j`` at
    ``t = t* (1 - j / SAMPLES)``, row 0 the event), their Gronwall error ``err`` (max norm),
    ``vmax`` (bound of ``|v|`` on ``[0, t*]``), the start ``x0, v0`` (float64), the error of
    the event state ``(dx, dv)`` caused by the construction and the start's rounding, and
    ``ok`` (every substep had its a-priori bound)."""

    x: np.ndarray
    v: np.ndarray
    err: np.ndarray
    vmax: np.ndarray
    x0: np.ndarray
    v0: np.ndarray
    dx: np.ndarray
    dv: np.ndarray
    ok: np.ndarray


def _substeps(P, vabs, D, active):
    """The fewest substeps (a power of two up to ``MAX_SUB``) whose radius ``D / (m Q)`` has an
    a-priori bound for every active case (with ``|v|`` grown by the interval's ``Amax D``)."""
    m = 1
    while m < MAX_SUB:
        rho = D / m / Q
        grow = vabs + (P.F + P.f + abs(P.c) * vabs) * D
        _, _, ok = enclosure(P, grow, rho)
        if ok[active].all():
            return m
        m *= 2
    return MAX_SUB


def run(P: Params, t_star, x_star, v_star, s, samples, matrices=True, lost=None):
    """Backward flights from the event states (arrays) to ``t = 0`` (module docstring).
    ``matrices=False``: without the flight matrices, so without the event-state error ``(dx,
    dv)`` (NaN): what a screen by the certificate needs (samples, their Gronwall error, ``vmax``,
    the start), at ~60% of the cost (issue 33: the hard cases' float screen of the narrow
    corner, 12 batches, 6.0 -> 4.2 CPU s under a profiler; the same cases).

    ``lost(x, v, err, vmax, lanes)`` (a screen, without ``matrices``): called with each sample
    in turn (``x, v, err`` of the flights ``lanes``, indices into the batch, and their ``vmax``),
    which of those flights the screen has refused already.  Those are run no further (their
    rows not reached and their start are NaN, their ``ok`` False), and the number of substeps
    of a grid interval is then that of the flights still running."""
    if lost is not None and matrices:
        raise ValueError("backflight.run: lost (a screen's early stop) needs matrices=False")
    n = t_star.size
    D = t_star / samples
    yh, yl = x_star.astype(float).copy(), np.zeros(n)
    dh, dl = -v_star.astype(float), np.zeros(n)
    th, tl = -t_star.astype(float), np.zeros(n)
    xs, vs, errs = np.empty((samples + 1, n)), np.empty((samples + 1, n)), np.zeros((samples + 1, n))
    xs[0], vs[0] = yh, -dh
    err, vmax, ok = np.zeros(n), np.abs(v_star).astype(float), np.ones(n, bool)
    M = [np.ones(n), np.zeros(n), np.zeros(n), np.ones(n)]          # backward product
    ex, ev = np.zeros(n), np.zeros(n)                                   # event-state error
    L = P.lipschitz
    lanes, vmax_all, s = np.arange(n), vmax.copy(), np.asarray(s, float)
    for j in range(samples):
        m = _substeps(P, np.abs(dh), D, ok)
        h = D / m
        for _ in range(m):
            X, V, good = enclosure(P, np.abs(dh), h / Q)
            ok &= good
            Y, step = series(P, th, yh, dh, s, h, variational=matrices)
            amax = V * Q / h
            lx = X * Q ** (ORDER + 2) / (1 - Q) + ROUND * EPS * amax * h * h
            lv = V * Q ** (ORDER + 1) / (1 - Q) + ROUND * EPS * amax * h
            vmax = np.maximum(vmax, np.abs(dh) + V)
            p, pe = _two_prod(dh, h)
            rest = Y[:1:-1].sum(axis=0) + dl * h + pe
            dvel = (np.arange(ORDER + 1, 1, -1)[:, None] * Y[:1:-1]).sum(axis=0) / h
            yh, e1 = _two_sum(yh, p)
            yh, yl = _two_sum(yh, yl + e1 + rest)
            dh, e2 = _two_sum(dh, dvel)
            dh, dl = _two_sum(dh, dl + e2)
            th, e3 = _two_sum(th, h)
            th, tl = _two_sum(th, tl + e3)
            if matrices:
                M = [step[0] * M[0] + step[1] * M[2], step[0] * M[1] + step[1] * M[3],
                     step[2] * M[0] + step[3] * M[2], step[2] * M[1] + step[3] * M[3]]
                det = np.abs(M[0] * M[3] - M[1] * M[2])
                ex += (np.abs(M[3]) * lx + np.abs(M[1]) * lv) / det
                ev += (np.abs(M[2]) * lx + np.abs(M[0]) * lv) / det
            err = err * np.exp(L * h) + np.maximum(lx, lv)
        xs[j + 1, lanes], vs[j + 1, lanes], errs[j + 1, lanes] = yh, -dh, err
        if lost is not None:
            keep = ~lost(yh, -dh, err, vmax, lanes)
            if not keep.all():
                xs[j + 2:, lanes[~keep]] = vs[j + 2:, lanes[~keep]] = errs[j + 2:, lanes[~keep]] = np.nan
                vmax_all[lanes[~keep]] = vmax[~keep]
                lanes = lanes[keep]
                yh, yl, dh, dl, th, tl, err, vmax, ok, D, s = (
                    a[keep] for a in (yh, yl, dh, dl, th, tl, err, vmax, ok, D, s))
                if not lanes.size:
                    break
    vmax_all[lanes] = vmax
    if lanes.size < n:              # a screen that gave up on some flights
        return _partial(P, n, lanes, xs, vs, errs, vmax_all, (yh, yl, dh, dl, th, tl, s), ok)
    x0, v0 = _start(P, yh, yl, dh, dl, th, tl, s)
    if matrices:
        det = np.abs(M[0] * M[3] - M[1] * M[2])
        rx, rv = EPS * np.abs(x0), EPS * np.abs(v0)
        ex += (np.abs(M[3]) * rx + np.abs(M[1]) * rv) / det
        ev += (np.abs(M[2]) * rx + np.abs(M[0]) * rv) / det
    else:
        ex, ev = np.full(n, np.nan), np.full(n, np.nan)
    ok &= np.isfinite(x0) & np.isfinite(v0)
    return Backward(xs, vs, errs, vmax, x0, v0, ex, ev, ok)


def _start(P, yh, yl, dh, dl, th, tl, s):
    """The state at exactly ``t = 0`` from the end of the backward run (the clock ends at
    ``th + tl ~ 0``, a few ulp of ``t*``)."""
    r = th + tl
    acc = P.F * np.cos(P.k * yh) * np.cos(P.w * r) - s * P.f + P.c * dh
    return yh + (yl - dh * r), -(dh + (dl - acc * r))


def _partial(P, n, lanes, xs, vs, errs, vmax, end, ok_lanes):
    """The ``Backward`` of a screen whose flights outside ``lanes`` were given up: their start
    NaN and their ``ok`` False."""
    x0, v0, ok = np.full(n, np.nan), np.full(n, np.nan), np.zeros(n, bool)
    if lanes.size:
        x0[lanes], v0[lanes] = _start(P, *end)
        ok[lanes] = ok_lanes & np.isfinite(x0[lanes]) & np.isfinite(v0[lanes])
    return Backward(xs, vs, errs, vmax, x0, v0, np.full(n, np.nan), np.full(n, np.nan), ok)
