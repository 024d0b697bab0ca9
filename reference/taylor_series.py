"""The Taylor steps of ``reference.taylor``'s flights under position-dependent forcing: their
coefficients (``series``, ``series_fixed``), their proved truncation bound (``step_certificate``)
and the cost-optimal order (``taylor_order``).

The model: ``x'' = A(x, t) - s f - c x'``, ``A(x, t) = F cos(k x) cos(w t)``, in flight with a
fixed friction sign ``s`` (``reference.taylor``'s module docstring).

Taylor coefficients (automatic differentiation)
-----------------------------------------------
Write ``x(t0 + tau) = sum x_n tau^n``, ``u = k x``, ``C = cos u``, ``S = sin u``,
``P(tau) = cos(w (t0 + tau)) = sum P_n tau^n`` with ``P_n = w^n / n! cos(w t0 + n pi / 2)``.
From ``C' = -S u'`` and ``S' = C u'``::

    n C_n = - sum_{j=1..n} j u_j S_{n-j},      n S_n = sum_{j=1..n} j u_j C_{n-j},

and the ODE gives ``(n+1)(n+2) x_{n+2} = F (C*P)_n - c (n+1) x_{n+1} - s f [n = 0]``
(``*`` is the Cauchy product).  The variational equations
``dx' = dv, dv' = A_x dx - c dv`` with ``A_x = -F k sin(k x) cos(w t)`` have the
coefficient series ``-F k (S*P)`` and are integrated by the same recurrence, column by
column, from the identity: their value is the flight matrix (no longer ``[[1, h], [0, 1]]``).

Truncation bound (the proof)
----------------------------
Let ``D = {|tau| <= rho}`` in the complex plane and ``X, V > 0`` satisfy::

    (E1)  rho (|v0| + V) <= X,
    (E2)  rho (F cosh(k X) cosh(w rho) + f + c (|v0| + V)) <= V.

*Claim:* the flight extends analytically to ``D`` with ``|x - x0| <= X`` and
``|v - v0| <= V`` there.  Proof: on the closed set ``B`` of pairs ``(x, v)`` of functions
continuous on ``D``, analytic inside, with those bounds, the Picard map
``(x0 + int_0^tau v, v0 + int_0^tau a)`` (straight-line integrals, ``a`` the right-hand
side) maps ``B`` into ``B``: for real ``x0`` and ``|x - x0| <= X``,
``|cos(k x)| <= cosh(k |Im x|) <= cosh(k X)``, ``|cos(w (t0 + tau))| <= cosh(w rho)``, so
``|a| <= F cosh(k X) cosh(w rho) + f + c (|v0| + V)`` and (E1), (E2) give the bounds.  It
is Lipschitz in the sup norm with ``L = max(1, F k cosh(k X) cosh(w rho) + c)`` (because
``|sin z| <= cosh(Im z)``), so its iterates satisfy ``|T^n p - T^n q|(tau) <= (L|tau|)^n/n!
|p - q|`` and converge uniformly to a fixed point in ``B``: an analytic solution, equal on
the real segment to the real flight by uniqueness.  Cauchy's estimate on ``|tau| = rho``
gives ``|x_n| <= X / rho^n`` and ``|v_n| <= V / rho^n`` (``n >= 1``), hence for real
``0 <= tau <= h = q rho``::

    |x(t0 + tau) - sum_{n <= N+1} x_n tau^n| <= X q^{N+2} / (1 - q),
    |v(t0 + tau) - sum_{n <= N} v_n tau^n|   <= V q^{N+1} / (1 - q).

The variational matrix satisfies, along each ray, ``|dx|, |dv| <= exp(Lv rho)`` with
``Lv = max(1, F k cosh(k X) cosh(w rho) + c)`` (integral Gronwall on the column max-norm),
so its polynomials obey the same bound with ``J = exp(Lv rho)``.  A step takes the
``rho`` (from a few candidates) that gives the longest ``h`` with
``(X + V + J) q^{N+1} / (1 - q) <= 2^-(prec + EXTRA_BITS)``, ``q <= 1/2`` -- the
truncation is then below ``2^-prec`` per step with ``EXTRA_BITS`` to spare for the
~10^2 steps of a period.  (E1)/(E2) are checked in float64 with a relative margin of
``1e-9``, far above float rounding.  The step's coefficients are computed in
``prec + GUARD_BITS``-bit fixed point on the scaled series ``x(t0 + h sigma)``
(``series_fixed``; ``series`` is the same recurrence in mpf, used for the variational
columns and by the tests); rounding is controlled by the guard bits (not by interval
arithmetic): ``~N^2 2^-(prec+GUARD_BITS)`` per step, below the truncation target.

Order: a step costs ``a N^2 + b`` (``~2 N^2`` fixed-point multiplications, ``b`` the
step choice and conversions) and advances ``h ~ rho exp(-L/(N+1))`` with
``L = (prec + EXTRA_BITS) ln 2``.  With ``b = 0`` the cost per unit time would be least at
``N + 1 = L / 2``; measured (xpot, dps 30/50/100) the optimum is flat between ``0.75 L``
and ``L``, which ``taylor_order`` takes as ``N + 1 = 0.75 L`` (N = 92 at 50 digits,
``q ~ e^-4/3``; 0.6 dps = 30 would take 8x more steps).
"""
from __future__ import annotations

import math
from operator import mul

import mpmath
from mpmath.libmp import MPZ, from_int, mpf_mul, mpf_shift


#: bits carried beyond the working precision in the recurrences and the dense output
GUARD_BITS = 32
#: bits by which each step's truncation bound undercuts the working precision
EXTRA_BITS = 12


def taylor_order(prec: int) -> int:
    """The cost-optimal order ``N`` for ``prec`` working bits (module docstring)."""
    if prec < 10:
        raise ValueError(f"prec must be >= 10 bits, got {prec}")
    return max(8, math.ceil(0.75 * (prec + EXTRA_BITS) * math.log(2)) - 1)


def _params(scene):
    """``(F, f, c, k, w)`` as mpf at the current precision (``k = 0`` without position forcing)."""
    k = scene.mpf("wavenumber")
    return (scene.mpf("F"), scene.mpf("f"), scene.mpf("damping"),
            mpmath.mpf(0) if k is None else k, scene.mpf("omega"))


def series(prm, t0, x0, v0, s, N, variational=False):
    """Taylor coefficients of one flight step at ``t0`` (current precision).

    Returns ``xs`` (``x_0 .. x_{N+1}``) and, with ``variational``, the four coefficient
    lists ``(dx1, dv1, dx2, dv2)`` (``0 .. N``) of the columns of the flight matrix.
    """
    F, f, c, k, w = prm
    xs = [x0, v0] + [mpmath.mpf(0)] * N
    ju = [mpmath.mpf(0), k * v0]                      # j u_j, u = k x
    C, S = [mpmath.cos(k * x0)], [mpmath.sin(k * x0)]
    cw, sw = mpmath.cos(w * t0), mpmath.sin(w * t0)
    cyc, P, wn = (cw, -sw, -cw, sw), [], mpmath.mpf(1)
    for n in range(N):
        P.append(cyc[n % 4] * wn)
        wn = wn * w / (n + 1)
        if n >= 1:
            C.append(-mpmath.fdot(ju[1:n + 1], S[n - 1::-1]) / n)
            S.append(mpmath.fdot(ju[1:n + 1], C[n - 1::-1]) / n)
        a_n = F * mpmath.fdot(C, P[::-1]) - c * (n + 1) * xs[n + 1]
        if n == 0:
            a_n -= s * f
        xs[n + 2] = a_n / ((n + 1) * (n + 2))
        ju.append(k * (n + 2) * xs[n + 2])
    if not variational:
        return xs, None
    B = [-F * k * mpmath.fdot(S[:n + 1], P[n::-1]) for n in range(N)]
    cols = []
    for dx0, dv0 in ((1, 0), (0, 1)):
        dx, dv = [mpmath.mpf(dx0)], [mpmath.mpf(dv0)]
        for n in range(N):
            dx.append(dv[n] / (n + 1))
            dv.append((mpmath.fdot(B[:n + 1], dx[n::-1]) - c * dv[n]) / (n + 1))
        cols += [dx, dv]
    return xs, tuple(cols)


def _fix(a, P):
    """``round(a 2^P)`` as an int: gmpy2's ``mpz`` where mpmath runs on gmpy2 (``MPZ``).  The
    fixed-point recurrences are sums of products of ~200-bit ints, ~60 ns each on ``mpz``
    against ~140 on Python's ints (one run); ``_main_fixed`` at order 113 takes 843 us against
    970, the same integers, so the same bits."""
    return MPZ(int(mpmath.nint(mpmath.ldexp(a, P))))


def series_fixed(prm, t0, x0, v0, s, N, h, P, variational=False):
    """``series`` for one step of length ``h``, computed in ``P``-bit fixed point on the
    *scaled* coefficients ``X_n = x_n h^n`` (the series of ``x(t0 + h sigma)``).

    The recurrences are homogeneous in ``h`` (``n C_n = -sum j U_j S_{n-j}`` etc. hold for
    the scaled series; the ODE's terms get ``h^2 F`` and ``h c``).  For ``|tau| <= h`` every
    scaled quantity is bounded (``|X_n| <= X q^n``, module docstring), so absolute
    rounding of ``2^-P`` per operation costs at most ``~N^2 2^-P`` in a term ``x_n tau^n``:
    ``P = prec + GUARD_BITS`` keeps it far below the truncation bound.  Python's integers
    make this ~20x faster than mpf arithmetic.  Returns ``(xs, cols)`` as ``series`` does:
    the unscaled ``x_0 .. x_{N+1}`` (mpf, current precision) and
    the variational columns or ``None``.  Scaled variational series: ``DX_n = dx_n h^n``,
    ``DV_n = dv_n h^(n+1)``, ``DX_{n+1} = DV_n/(n+1)``,
    ``DV_{n+1} = (h^2 (B~*DX)_n - c h DV_n)/(n+1)`` with ``B~ = -F k (S~*P~)``.
    """
    X, S, Pn = _main_fixed(prm, t0, x0, v0, s, N, h, P)
    out = _unscale(X, P, 1 / h, mpmath.mpf(1))
    return out, (_columns(_variational_fixed(prm, S, Pn, N, h, P), P, h) if variational else None)


def _main_fixed(prm, t0, x0, v0, s, N, h, P):
    """``series_fixed``'s recurrence: the scaled ``X_n`` (ints) and the ``S~``, ``P~`` that the
    variational columns reuse (``TaylorFlight`` keeps them per step: issue 33, a Jacobian used to
    run this recurrence a second time per step, a quarter of a golden input's cost)."""
    F, f, c, k, w = prm
    one = MPZ(1) << P
    kf, Fh2, ch = _fix(k, P), _fix(F * h * h, P), _fix(c * h, P)
    X = [_fix(x0, P), _fix(v0 * h, P)] + [0] * N
    JU = [0, (kf * X[1]) >> P]
    C, S = [_fix(mpmath.cos(k * x0), P)], [_fix(mpmath.sin(k * x0), P)]
    cw, sw = _fix(mpmath.cos(w * t0), P), _fix(mpmath.sin(w * t0), P)
    cyc, wh, pw, Pn = (cw, -sw, -cw, sw), _fix(w * h, P), one, []
    sfh2 = _fix(s * f * h * h, P)
    for n in range(N):
        Pn.append((cyc[n % 4] * pw) >> P)
        pw = (pw * wh >> P) // (n + 1)
        if n >= 1:
            C.append(-((sum(map(mul, JU[1:n + 1], reversed(S))) >> P) // n))
            S.append((sum(map(mul, JU[1:n + 1], reversed(C[:n]))) >> P) // n)
        q = sum(map(mul, C, reversed(Pn))) >> P
        a_n = ((Fh2 * q) >> P) - ((ch * (n + 1) * X[n + 1]) >> P) - (sfh2 if n == 0 else 0)
        X[n + 2] = a_n // ((n + 1) * (n + 2))
        JU.append((kf * (n + 2) * X[n + 2]) >> P)
    return X, S, Pn


def _variational_fixed(prm, S, Pn, N, h, P):
    """The variational columns of ``series_fixed`` from the step's ``S~``, ``P~``: the scaled
    ``(DX, DV)`` of each column, ints (``_columns`` unscales them)."""
    F, f, c, k, w = prm
    one, ch, Fkh2 = MPZ(1) << P, _fix(c * h, P), -_fix(F * k * h * h, P)
    Bh2 = [(Fkh2 * (sum(map(mul, S[:n + 1], reversed(Pn[:n + 1]))) >> P)) >> P for n in range(N)]
    cols = []
    for DX, DV in (([one], [0]), ([0], [_fix(h, P)])):
        for n in range(N):
            DX.append(DV[n] // (n + 1))
            DV.append(((sum(map(mul, Bh2[:n + 1], reversed(DX[:n + 1]))) >> P)
                       - ((ch * DV[n]) >> P)) // (n + 1))
        cols += [DX, DV]
    return tuple(cols)


def _columns(scaled, P, h):
    """``series_fixed``'s unscaled columns ``(dx1, dv1, dx2, dv2)`` from the scaled ints."""
    hinv = 1 / h
    return tuple(_unscale(Z, P, hinv, mpmath.mpf(1) if i % 2 == 0 else hinv) for i, Z in enumerate(scaled))


def _unscale(Z, P, hinv, scale):
    """``[Z_n 2^-P scale hinv^n]``: fixed-point scaled coefficients back to mpf (``ldexp(z, -P)``
    is exact, then one rounded product, and ``scale *= hinv``, as on mpf; on the raw values)."""
    prec, rnd = mpmath.mp._prec_rounding
    h, s, out = mpmath.mpf(hinv)._mpf_, mpmath.mpf(scale)._mpf_, []
    for z in Z:
        out.append(mpmath.mp.make_mpf(mpf_mul(mpf_shift(from_int(z), -P), s, prec, rnd)))
        s = mpf_mul(s, h, prec, rnd)
    return out


def _fixed_horner(Z, sig, P):
    """``sum Z_n sigma^n`` in ``P``-bit fixed point (``Z`` scaled ints, ``sig = sigma 2^P``,
    ``0 <= sigma <= 1``): each of the ``N`` steps rounds by at most ``2^-P`` of the scaled
    quantity's unit, so the sum is good to ``~N 2^-P`` -- below the recurrences' own rounding
    (``series_fixed``).  Issue 33: the event search evaluates the step polynomials thousands of
    times a period; mpf Horner steps (a rounded product and sum each) were a third of a
    reference run's CPU under position forcing, integer ones cost a tenth of that."""
    if sig == 1 << P:
        return sum(Z)
    acc = Z[-1]
    for z in reversed(Z[:-1]):
        acc = ((acc * sig) >> P) + z
    return acc


def _enclosure(fl, v0abs, rho):
    """``(X, V)`` satisfying (E1), (E2) of the module docstring, or ``None``."""
    F, f, c, k, w = fl
    chw = math.cosh(w * rho)
    V = rho * (F * chw + f + c * v0abs)
    for _ in range(80):
        X = rho * (v0abs + V)
        if k * X > 700:
            return None
        need = rho * (F * math.cosh(k * X) * chw + f + c * (v0abs + V))
        if need * (1 + 1e-9) <= V:
            return X, V
        V = 1.05 * need
    return None


def step_certificate(fl, v0abs, N, bits, variational=True):
    """The step and its proof data: ``dict(h, rho, q, X, V, J)`` (module docstring).

    Tries ``rho = rho0 2^(j/3)``, ``j = -12..8``, around the natural scale
    ``rho0 = 1 / max(w, k (|v0| + 1), sqrt(F (k + 1) + f), c)`` and keeps the one with the
    longest step ``h = q rho``, ``q = min(1/2, (2^-bits / (2 M))^(1/(N+1)))``,
    ``M = X + V (+ J)``, so that ``M q^(N+1) / (1 - q) <= 2^-bits``.
    """
    F, f, c, k, w = fl
    rho0 = 1.0 / max(w, k * (v0abs + 1.0), math.sqrt(F * (k + 1.0) + f), c, 1e-300)
    best = None
    for j in range(-12, 9):
        rho = rho0 * 2.0 ** (j / 3)
        enc = _enclosure(fl, v0abs, rho)
        if enc is None:
            continue
        X, V = enc
        J = math.exp(max(1.0, F * k * math.cosh(k * X) * math.cosh(w * rho) + c) * rho)
        M = X + V + (J if variational else 0.0)
        q = min(0.5, math.exp((-bits * math.log(2) - math.log(2 * M)) / (N + 1)))
        h = q * rho * (1 - 1e-12)          # below q rho despite float rounding
        if best is None or h > best["h"]:
            best = dict(h=h, rho=rho, q=q, X=X, V=V, J=J)
    if best is None:
        raise RuntimeError(f"taylor: no a-priori enclosure found (|v0|={v0abs}, params={fl})")
    return best


def choose_step(fl, v0abs, N, bits, variational=True):
    """A step ``h`` whose truncation bound is below ``2**-bits`` (``step_certificate``)."""
    return step_certificate(fl, v0abs, N, bits, variational)["h"]
