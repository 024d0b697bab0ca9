"""Vectorised float64 flights under position-dependent forcing (issue 6).

In flight with friction sign ``s`` (per element, ``+1``/``-1``)::

    x' = v,   v' = a = F cos(k x) cos(w t) - s f - c v     (k = 0: no position forcing)

plus, on request, the variational equations ``J' = [[0, 1], [A_x, -c]] J`` with
``A_x = -F k sin(k x) cos(w t)``, ``J(t0) = I`` (the flight matrix of the Jacobian).

Method: Dormand-Prince 8(5,3) (``DOP853``, Hairer-Norsett-Wanner II.5) with *fixed* steps,
vectorised over the batch (batch axis last inside, first at the interface), and its
own 7th-order continuous extension (3 extra stages) as dense output.  Why this one:
the right-hand side is smooth (analytic) between events, so a high-order one-step
method reaches float64 accuracy with few steps; a fixed step keeps every element of
the batch in lock-step (no per-element step control, no masking of rejected steps);
the variational equations are integrated by the same tableau, so the returned matrix
is the exact derivative of the discrete flow.  It is independent of the reference's
Taylor-series integrator (different method, different error mechanism), which is what
the cross-check needs.  Coefficients from ``scipy.integrate._ivp.dop853_coefficients``.

Step: ``h = 2 pi / (steps_per_period Lambda)`` with the local frequency scale
``Lambda = max(w, k |v|, sqrt(F k), c)`` at the step start (``T / steps_per_period`` when
the forcing is the fastest), last step shortened to hit ``t_end``.  The local error of
DOP853 is ``O((Lambda h)^9)``-ish: measured against ``reference`` (tests), 64 steps per
``2 pi / Lambda`` give ~1e-15 per period at the paper's xpot parameters but ~3e-13 on a
long period (w = 1, F = 2, k = 0.7, gap 3.5: 32 -> 1e-10, 64 -> 3e-13, 128 -> 3e-14, the
rounding floor); the default ``STEPS_PER_PERIOD = 96`` sits near that floor.

Events (the first of, per element, in ``(t0, t_end]``):
``"wall"``: ``g = s (wall_s - x) = 0`` with ``wall_s = r`` if ``s = 1`` else ``l``;
``"vzero"``: ``g = s v = 0``.  Both are ``> 0`` before the event (up to a start on the
boundary).  Root exclusion per step (in ``theta = (t - t_a)/h``): with ``M >= |g''| h^2``
over the step (``|x''| <= F + f + c vmax``, ``|v''| <= F w + F k vmax + c amax``, ``vmax``
from ``d|v|/dt <= F + f + c |v|``), ``g(theta) >= g(0) + g'(0) theta - M theta^2 / 2``,
so a step (or a sub-interval of the dense output) with that lower bound positive at its
right end has no root.  Flagged steps are cut into ``SUBDIV`` pieces on the dense output;
a sign change is bracketed and polished by safeguarded Newton (bisection when Newton
leaves the bracket); a piece without a sign change whose exclusion test fails is
searched for a pair of close roots or a tangential one: golden section for the minimum
of ``g``; below ``-TANGENT_FLOOR`` times the scale, the first root is bracketed between
the piece's start and the minimum; within the floor, the minimum is the (tangential) root.
Every loop is bounded; exceeding raises RuntimeError with the state.

The period map (``ode_map``): the event loop of SEMANTICS.md around ``flight`` --
impacts (Table 1's matrix with ``A = A(wall, t*)``), turns, sticking and wall contact
with closed-form exit times for the amplitude ``F cos(k x)`` of the resting position
(``first_above``); the Jacobian is the product of the variational flight matrices and
Table 1's event matrices.  ``fast.api`` routes position-forcing scenes here
(``Params.from_scene`` returns an ``OdeParams``, ``_run_all`` calls ``run_all``).
Chatter: a run of impacts at a wall the force pushes into is summed by ``chatter_tail``
(frozen force, geometric series) as soon as the neglected variation of the force over the
tail is below float resolution; then wall contact (eq. ``xpot`` has none: its force
vanishes at the walls).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.integrate._ivp import dop853_coefficients as _dop

_NS = _dop.N_STAGES                    # 12
_A, _B, _C, _D = _dop.A, _dop.B, _dop.C, _dop.D
SUBDIV = 8
NEWTON_ITERS = 60
GOLDEN_ITERS = 40
TANGENT_FLOOR = 64 * 2.0 ** -52
STEPS_PER_PERIOD = 96


def ode_params(scene):
    """``(F, f, c, k, w)`` as float64 (``k = 0`` without position forcing)."""
    k = scene.float("wavenumber")
    return (scene.float("F"), scene.float("f"), scene.float("damping"),
            0.0 if k is None else k, scene.float("omega"))


def rhs(p, t, Y, s):
    """Right-hand side for ``Y`` of shape ``(2, n)`` or ``(6, n)`` (with ``J`` row-major)."""
    F, f, c, k, w = p
    x, v = Y[0], Y[1]
    cw = np.cos(w * t)
    out = np.empty_like(Y)
    out[0] = v
    out[1] = F * np.cos(k * x) * cw - s * f - c * v
    if Y.shape[0] == 6:
        ax = -F * k * np.sin(k * x) * cw
        out[2], out[3] = Y[4], Y[5]
        out[4] = ax * Y[2] - c * Y[4]
        out[5] = ax * Y[3] - c * Y[5]
    return out


def _comb(coefs, K):
    """``sum_j coefs[j] K[j]`` in a fixed order, skipping zero coefficients (elementwise,
    so an element's result never depends on the batch it travels in)."""
    acc = np.zeros_like(K[0])
    for cj, Kj in zip(coefs, K):
        if cj != 0.0:
            acc += cj * Kj
    return acc


def rk_step(p, t, Y, s, h, dense=False):
    """One DOP853 step of length ``h`` (array) from ``(t, Y)``.

    Returns ``Y_new`` and, with ``dense``, the interpolation array ``Q`` of shape
    ``(7, m, n)`` for ``dense_eval``.
    """
    K = np.empty((_A.shape[0],) + Y.shape)
    K[0] = rhs(p, t, Y, s)
    for i in range(1, _NS):
        K[i] = rhs(p, t + _C[i] * h, Y + _comb(_A[i, :i], K[:i]) * h, s)
    Y_new = Y + h * _comb(_B, K[:_NS])
    if not dense:
        return Y_new, None
    K[_NS] = rhs(p, t + h, Y_new, s)
    for i in range(_NS + 1, _A.shape[0]):
        K[i] = rhs(p, t + _C[i] * h, Y + _comb(_A[i, :i], K[:i]) * h, s)
    dY = Y_new - Y
    Q = np.empty((7,) + Y.shape)
    Q[0] = dY
    Q[1] = h * K[0] - dY
    Q[2] = 2 * dY - h * (K[_NS] + K[0])
    for j in range(4):
        Q[3 + j] = h * _comb(_D[j], K)
    return Y_new, Q


def dense_eval(Y0, Q, theta):
    """The continuous extension at ``theta`` in ``[0, 1]`` (array over the batch)."""
    y = np.zeros_like(Y0)
    for i, q in enumerate(Q[::-1]):
        y += q
        y *= theta if i % 2 == 0 else 1 - theta
    return y + Y0


def second_derivative_bounds(p, vabs, h):
    """``(max |x''|, max |v''|)`` over a step of length ``h`` from speed ``vabs`` (arrays)."""
    F, f, c, k, w = p
    if c > 0:
        vmax = (vabs + (F + f) / c) * np.exp(c * h) - (F + f) / c
    else:
        vmax = vabs + (F + f) * h
    amax = F + f + c * vmax
    return amax, F * w + F * k * vmax + c * amax


def _g(p, t, Y, s, wall):
    """Event functions ``(g_wall, g_v)`` and their time derivatives at ``(t, Y)``."""
    a = rhs(p, t, Y[:2], s)[1]
    return s * (wall - Y[0]), -s * Y[1], s * Y[1], s * a


def _newton_bisect(fun, lo, hi):
    """Root of ``fun`` in ``[lo, hi]`` with ``fun(lo) > 0 >= fun(hi)`` (arrays): Newton
    from the midpoint, bisection whenever Newton leaves the shrinking bracket; stops when
    the step or the bracket is a few ulp (or ``g == 0``) for every element."""
    th = 0.5 * (lo + hi)
    res, done = hi.copy(), np.zeros(lo.shape, bool)
    for _ in range(NEWTON_ITERS):
        g, dg = fun(th)
        pos = g > 0
        lo, hi = np.where(pos, th, lo), np.where(pos, hi, th)
        with np.errstate(divide="ignore", invalid="ignore"):
            nt = th - g / dg
        bad = ~np.isfinite(nt) | (nt <= lo) | (nt >= hi)
        nt = np.where(bad, 0.5 * (lo + hi), nt)
        small = (np.abs(nt - th) <= 2 * np.spacing(th)) | (hi - lo <= 4 * np.spacing(hi))
        conv = ~done & (small | (g == 0))           # frozen once converged: batch-independent
        res[conv] = np.where(g == 0, th, nt)[conv]
        done |= conv
        if np.all(done):
            return res
        th = nt
    return np.where(done, res, hi)


def _golden_min(fun, lo, hi):
    """Minimiser of a unimodal ``fun`` on ``[lo, hi]`` (arrays), by golden section."""
    r = (math.sqrt(5) - 1) / 2
    a, b = lo.copy(), hi.copy()
    for _ in range(GOLDEN_ITERS):
        c1, c2 = b - r * (b - a), a + r * (b - a)
        left = fun(c1) <= fun(c2)
        b, a = np.where(left, c2, b), np.where(left, a, c1)
    return 0.5 * (a + b)


def _pieces_roots(p, t, h, Y0, Q, s, wall, which, M, scale):
    """Earliest root in ``(0, 1]`` of event ``which`` (0 wall, 1 v) on the dense output.

    Returns ``theta`` (``inf`` where none).
    """
    n = Y0.shape[1]
    grid = np.linspace(0.0, 1.0, SUBDIV + 1)
    vals, ders = np.empty((SUBDIV + 1, n)), np.empty((SUBDIV + 1, n))
    for j, th in enumerate(grid):
        g = _g(p, t + th * h, dense_eval(Y0, Q, th), s, wall)
        vals[j], ders[j] = g[2 * which], g[2 * which + 1] * h
    out = np.full(n, np.inf)
    d = 1.0 / SUBDIV
    floor = TANGENT_FLOOR * np.broadcast_to(scale, (n,))

    def fun_on(k):
        def fun(th):
            g = _g(p, t[k] + th * h[k], dense_eval(Y0[:, k], Q[:, :, k], th), s[k], wall[k])
            return g[2 * which], g[2 * which + 1] * h[k]
        return fun

    for j in range(SUBDIV):
        todo = ~np.isfinite(out)
        safe = (vals[j] >= 0) & (vals[j] + ders[j] * d - M * d * d / 2 > 0)
        k = np.nonzero(todo & ~safe & (vals[j + 1] <= 0))[0]          # sign change: bracket
        if k.size:
            out[k] = _newton_bisect(fun_on(k), np.full(k.size, grid[j]), np.full(k.size, grid[j + 1]))
        k = np.nonzero(todo & ~safe & (vals[j + 1] > 0))[0]           # possible tangency
        if k.size:
            fun = fun_on(k)
            th = _golden_min(lambda z: fun(z)[0], np.full(k.size, grid[j]), np.full(k.size, grid[j + 1]))
            gmin = fun(th)[0]
            touch = (np.abs(gmin) <= floor[k]) & (th > 1e-6)     # tangential zero
            out[k[touch]] = th[touch]
            dip = np.nonzero((gmin < -floor[k]) & (th > 1e-6))[0]  # a close pair: first root
            if dip.size:
                kk = k[dip]
                out[kk] = _newton_bisect(fun_on(kk), np.full(kk.size, grid[j]), th[dip])
    return out


#: event codes of ``flight``
NO_EVENT, WALL, VZERO = 0, 1, 2


def _check(name, arr, n):
    arr = np.asarray(arr, dtype=float)
    if arr.shape != (n,):
        raise ValueError(f"{name} must have shape ({n},), got {arr.shape}")
    bad = np.nonzero(~np.isfinite(arr))[0]
    if bad.size:
        raise ValueError(f"{name} must be finite; offending indices {bad[:10].tolist()}")
    return arr


def flight(p, t0, x0, v0, s, t_end, walls, *, jac=False, steps_per_period=STEPS_PER_PERIOD):
    """Integrate every element from ``t0`` to its first event or ``t_end``.

    ``p`` from ``ode_params``; ``t0, x0, v0, s, t_end`` arrays of one length ``n``;
    ``walls = (l, r)``.  Returns ``(t, x, v, event, J)``: the time and state reached
    (``x`` set to the wall exactly at a ``WALL`` event, ``v = 0`` at ``VZERO``), the
    event code (``NO_EVENT`` when ``t_end`` was reached first) and, with ``jac``, the
    flight matrices ``J`` of shape ``(n, 2, 2)`` (else ``None``).
    """
    x0 = np.atleast_1d(np.asarray(x0, dtype=float))
    n = x0.shape[0]
    x0 = _check("x0", x0, n)
    t, v0, t_end = (_check(nm, a, n) for nm, a in (("t0", t0), ("v0", v0), ("t_end", t_end)))
    s = _check("s", s, n)
    if np.any((s != 1) & (s != -1)):
        raise ValueError(f"s must be +1 or -1; offending indices {np.nonzero(np.abs(s) != 1)[0][:10].tolist()}")
    if not int(steps_per_period) >= 4:
        raise ValueError(f"steps_per_period must be >= 4, got {steps_per_period}")
    l, r = walls
    wall = np.where(s > 0, float(r), float(l))
    Y = np.zeros((6 if jac else 2, n))
    Y[0], Y[1] = x0, v0
    if jac:
        Y[2] = Y[5] = 1.0
    t = t.copy()
    event = np.zeros(n, dtype=int)
    S = int(steps_per_period)
    active = t < t_end
    span = float(np.max(t_end - t, initial=0.0))
    vmax = float(np.max(np.abs(v0), initial=0.0)) + (p[0] + p[1]) * span   # |v'| <= F + f in flight
    max_iter = int(math.ceil(span / float(_step_len(p, np.array(vmax), S)))) + 8
    for _ in range(max_iter):
        if not np.any(active):
            break
        idx = np.nonzero(active)[0]
        _advance(p, idx, t, Y, s, t_end, wall, event, active, S)
    else:
        if np.any(active):
            i = int(np.nonzero(active)[0][0])
            raise RuntimeError(f"ode.flight: {max_iter} steps exceeded at element {i}: t={t[i]}, "
                               f"x={Y[0, i]}, v={Y[1, i]}, mode=flight s={s[i]}")
    J = None
    if jac:
        J = np.stack([Y[2], Y[3], Y[4], Y[5]], axis=-1).reshape(n, 2, 2)
    return t, Y[0].copy(), Y[1].copy(), event, J


def _step_len(p, vabs, S):
    """``h = 2 pi / (S Lambda)``, ``Lambda = max(w, k |v|, sqrt(F k), c)``: the fastest of the
    forcing, the phase rate of ``cos(k x)``, the linearised ``x'' = F cos(k x)`` and damping
    (per element, so batching never changes a step)."""
    F, f, c, k, w = p
    lam = np.maximum(np.maximum(w, k * vabs), max(math.sqrt(F * k), c))
    return 2 * math.pi / (S * lam)


def _advance(p, idx, t, Y, s, t_end, wall, event, active, S):
    """One step for the elements ``idx`` (updates the arrays in place)."""
    tt, YY, ss, ww = t[idx], Y[:, idx], s[idx], wall[idx]
    h = np.minimum(_step_len(p, np.abs(YY[1]), S), t_end[idx] - tt)
    Y1, _ = rk_step(p, tt, YY, ss, h)
    gw, dgw, gv, dgv = _g(p, tt, YY, ss, ww)
    mx, mv = second_derivative_bounds(p, np.abs(YY[1]), h)
    safe_w = (gw >= 0) & (gw + dgw * h - mx * h * h / 2 > 0)
    safe_v = (gv >= 0) & (gv + dgv * h - mv * h * h / 2 > 0)
    theta = np.full(idx.shape, np.inf)
    flag = np.nonzero(~(safe_w & safe_v))[0]
    if flag.size:
        sub = (tt[flag], h[flag], YY[:, flag], ss[flag], ww[flag])
        _, Q = rk_step(p, sub[0], sub[2], sub[3], sub[1], dense=True)
        xs = np.maximum(1.0, np.abs(sub[4]))
        th_w = _pieces_roots(p, sub[0], sub[1], sub[2], Q, sub[3], sub[4], 0,
                             mx[flag] * sub[1] ** 2, xs)
        vs = np.maximum(1.0, np.abs(sub[2][1]))
        th_v = _pieces_roots(p, sub[0], sub[1], sub[2], Q, sub[3], sub[4], 1,
                             mv[flag] * sub[1] ** 2, vs)
        th = np.minimum(th_w, th_v)
        hit = np.isfinite(th)
        if np.any(hit):
            k = flag[hit]
            Yh = dense_eval(sub[2][:, hit], Q[:, :, hit], th[hit])
            Y1[:, k] = Yh
            wall_first = th_w[hit] <= th_v[hit]
            Y1[0, k] = np.where(wall_first, ww[k], Y1[0, k])
            Y1[1, k] = np.where(wall_first, Y1[1, k], 0.0)
            event[idx[k]] = np.where(wall_first, WALL, VZERO)
            theta[k] = th[hit]
    done_t = np.where(np.isfinite(theta), tt + theta * h, tt + h)
    reached = h >= t_end[idx] - tt
    done_t = np.where(reached & ~np.isfinite(theta), t_end[idx], done_t)
    t[idx] = done_t
    Y[:, idx] = Y1
    active[idx] = ~(np.isfinite(theta) | reached)


# --- the event loop on numerical flights (SEMANTICS.md, vectorised): position forcing, damping -
FLIGHT, STICK, CONTACT, DONE = 0, 1, 2, 3
MAX_ROUNDS = 10_000
#: bound on the impacts of one run at one wall before its tail is summed (RuntimeError)
MAX_BOUNCES = 5000


def first_above(amp, level, w, t):
    """First ``tau >= t`` with ``amp cos(w tau) > level`` on a right-neighbourhood (``inf`` if
    ``|amp| <= level``): with ``alpha = arccos(level/|amp|)`` and the phase
    ``phi = (w t + (0 if amp > 0 else pi)) mod 2 pi``, the set is ``(-alpha, alpha) mod 2 pi``;
    ``phi >= 2 pi - alpha`` is the rising crossing (leave now), ``phi = alpha`` the falling one."""
    ok = np.abs(amp) > level
    alpha = np.arccos(np.where(ok, level / np.where(ok, np.abs(amp), 1.0), 1.0))
    phi = np.mod(w * t + np.where(amp > 0, 0.0, math.pi), 2 * math.pi)
    now = (phi < alpha) | (phi >= 2 * math.pi - alpha)
    return np.where(ok, np.where(now, t, t + (2 * math.pi - alpha - phi) / w), np.inf)


def _validated_states(scene, x, v):
    x, v = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(v, dtype=float))
    x, v = x.ravel().copy(), v.ravel().copy()
    l, r = scene.float("l"), scene.float("r")
    for name, a in (("x", x), ("v", v)):
        bad = np.nonzero(~np.isfinite(a))[0]
        if bad.size:
            raise ValueError(f"{name} must be finite; offending indices {bad[:10].tolist()}")
    bad = np.nonzero((x < l) | (x > r))[0]
    if bad.size:
        raise ValueError(f"x must be in [l, r] = [{l}, {r}]; offending indices {bad[:10].tolist()}")
    return x, v


def ode_map(scene, x, v, *, t_end=None, jac=False, steps_per_period=STEPS_PER_PERIOD,
            zero_velocity=None):
    """The state at ``t_end`` (default ``T``) from ``(x, v)`` at ``t = 0``, any scene.

    Flights by ``flight`` (DOP853), events and modes by SEMANTICS.md: impact
    ``v -> -e v`` (Table 1 matrix with ``A = A(wall, t*)``), turn (``s A < -f``), stick,
    slip and release at the closed-form times of ``first_above`` with the amplitude
    ``F cos(k x)`` of the resting position, contact at a wall.  Frictionless scenes pass
    through ``v = 0`` (a turn with factor 1).  Returns ``(x, v, J)``, ``J`` of shape
    ``(n, 2, 2)`` (the flight matrices from the variational equations times Table 1's
    event matrices) or ``None``.  Chatter runs end at their summed accumulation point
    (``chatter_tail``); ``MAX_BOUNCES`` impacts in one run or ``MAX_ROUNDS`` events raise
    RuntimeError naming the states.
    ``zero_velocity`` (a list) receives the boolean array "v was 0 at some time in
    ``[0, t_end]``" (turn, stick, contact, a smooth reversal when ``f = 0``, or ``v0 = 0``).
    """
    p = ode_params(scene)
    F, f, c, k, w = p
    e, l, r = scene.float("restitution"), scene.float("l"), scene.float("r")
    x, v = _validated_states(scene, x, v)
    n, T = x.size, 2 * math.pi / w
    t_end = T if t_end is None else float(t_end)
    t, s = np.zeros(n), np.where(v >= 0, 1.0, -1.0)
    J = np.tile(np.eye(2), (n, 1, 1))
    tiny_x = 16 * 2.0 ** -52 * max(abs(l), abs(r), r - l)
    tiny_v = 16 * 2.0 ** -52 * (F / w + (r - l) * w + f * T)
    mode = np.where(v == 0, STICK, FLIGHT)
    mode = np.where((v == 0) & ((x == r) | (x == l)), CONTACT, mode)
    side = np.where(x == r, 1.0, -1.0)                 # the wall of a contact
    bounces = np.zeros(n, dtype=int)
    zv = v == 0
    pre = ((x == r) & (v > 0)) | ((x == l) & (v < 0))
    _impact(p, e, np.nonzero(pre)[0], t, x, v, s, J, mode, side, bounces, tiny_v, (l, r), t_end)
    if jac:
        J[mode == STICK] = np.array([[1.0, 0.0], [0.0, 0.0]]) @ J[mode == STICK]
        J[mode == CONTACT] = 0.0
    for _ in range(MAX_ROUNDS):
        if np.all(mode == DONE):
            break
        idx = np.nonzero(mode == FLIGHT)[0]
        if idx.size:
            tt, xx, vv, ev, Js = flight(p, t[idx], x[idx], v[idx], s[idx], np.full(idx.size, t_end),
                                        (l, r), jac=jac, steps_per_period=steps_per_period)
            t[idx], x[idx], v[idx] = tt, xx, vv
            if jac:
                J[idx] = Js @ J[idx]
            mode[idx[ev == NO_EVENT]] = DONE
            zv[idx[ev == VZERO]] = True
            _impact(p, e, idx[ev == WALL], t, x, v, s, J, mode, side, bounces, tiny_v, (l, r), t_end)
            _velocity_zero(p, idx[ev == VZERO], t, x, v, s, J, mode, side, bounces, tiny_x, (l, r))
        resting = (mode == STICK) | (mode == CONTACT)
        zv |= resting
        bounces[resting] = 0
        _rest(p, t_end, t, x, v, s, J, mode, side)
    else:
        bad = np.nonzero(mode != DONE)[0][:5]
        raise RuntimeError(f"ode_map: more than {MAX_ROUNDS} events; states {bad.tolist()} at "
                           f"t={t[bad].tolist()}, x={x[bad].tolist()}, v={v[bad].tolist()}, "
                           f"mode={mode[bad].tolist()}")
    if zero_velocity is not None:
        zero_velocity.append(zv)
    return x, v, (J if jac else None)


def _force(p, x, t):
    F, f, c, k, w = p
    return F * np.cos(k * x) * np.cos(w * t)


def chatter_tail(p, e, push, u):
    """Frozen-force tail of a chatter run after an impact with speed ``u`` (leaving the wall),
    ``push = side A > f`` the force into the wall: out with deceleration ``push + f``, back
    with ``push - f``, return speed ``q u``, ``q = sqrt((push - f)/(push + f))``, ratio
    ``rho = e q``; the bounces last ``u tau rho^j``, ``tau = (1 + 1/q)/(push + f)``, so the
    run ends after ``Delta = u tau / (1 - rho)``, ``1 - rho = (1 - e) + 2 e f/((push+f)(1+q))``
    (cancellation-free).  Over ``Delta`` the force moves by ``<= (F w + F k u) Delta`` and
    damping adds ``c u``: each bounce is perturbed by a relative
    ``(F w Delta + F k u Delta + c u)/(push - f)``, so ``err = 2 Delta (F w Delta + F k u
    Delta + c u)/(push - f)`` bounds the neglected part of ``Delta``.  Returns ``(Delta, err)``
    (``Delta = inf`` where ``rho = 1``: elastic frictionless bouncing does not accumulate).
    """
    F, f, c, k, w = p
    q = np.sqrt((push - f) / (push + f))
    one_m = (1.0 - e) + e * 2.0 * f / ((push + f) * (1.0 + q))
    with np.errstate(divide="ignore", invalid="ignore"):
        delta = np.where(one_m > 0, u * (1.0 + 1.0 / q) / (push + f) / np.where(one_m > 0, one_m, 1.0), np.inf)
        err = 2.0 * delta * (F * w * delta + F * k * u * delta + c * u) / (push - f)
    return delta, err


def _impact(p, e, i, t, x, v, s, J, mode, side, bounces, tiny_v, walls, t_end):
    """Wall events of the flights ``i`` (moving toward the wall ``s``): impact, contact, or
    the end of a chatter run (summed by ``chatter_tail`` once its error is below float
    resolution of ``t`` and it ends before ``t_end``; wall contact from then on)."""
    if not i.size:
        return
    f = p[1]
    vb, sd = v[i], s[i]
    x[i] = np.where(sd > 0, walls[1], walls[0])
    A = _force(p, x[i], t[i])
    bounces[i] = np.where(side[i] == sd, bounces[i] + 1, 1)      # a run at one wall
    side[i] = sd
    many = i[bounces[i] > MAX_BOUNCES]
    if many.size:
        raise RuntimeError(
            f"ode_map: more than {MAX_BOUNCES} impacts in a run at one wall without reaching the "
            f"summation regime; states {many[:5].tolist()} at t={t[many[:5]].tolist()}, "
            f"v_before={vb[np.isin(i, many)][:5].tolist()}")
    push = sd * A
    pushing = push > f
    delta, err = chatter_tail(p, e, np.where(pushing, push, f + 1.0), e * np.abs(vb))
    summed = pushing & (err <= 2.0 ** -52 * max(1.0, abs(t_end))) & (t[i] + delta <= t_end)
    rest = (np.abs(vb) <= tiny_v) | (e == 0) | summed
    with np.errstate(divide="ignore", invalid="ignore"):
        low = ((1 + e) * A + (1 - e) * sd * f) / vb
    M = np.zeros((i.size, 2, 2))
    M[:, 0, 0] = M[:, 1, 1] = -e
    M[:, 1, 0] = np.where(rest, 0.0, low)
    J[i] = np.where(rest[:, None, None], 0.0, M @ J[i])
    t[i] = np.where(summed, t[i] + delta, t[i])
    v[i] = np.where(rest, 0.0, -e * vb)
    s[i] = -sd
    mode[i] = np.where(rest, CONTACT, FLIGHT)


def _velocity_zero(p, i, t, x, v, s, J, mode, side, bounces, tiny_x, walls):
    """``v = 0`` in flight: contact at a wall, turn (``s A < -f``) or stick."""
    if not i.size:
        return
    f = p[1]
    v[i] = 0.0
    at_r, at_l = np.abs(x[i] - walls[1]) <= tiny_x, np.abs(x[i] - walls[0]) <= tiny_x
    wall = at_r | at_l
    x[i] = np.where(at_r, walls[1], np.where(at_l, walls[0], x[i]))
    side[i] = np.where(at_r, 1.0, -1.0)
    A = _force(p, x[i], t[i])
    if f == 0:                                       # frictionless: pass through v = 0
        turn, stick = ~wall, np.zeros(i.size, bool)
        s_new, factor = np.where(A >= 0, 1.0, -1.0), np.ones(i.size)
    else:
        turn = ~wall & (s[i] * A < -f)
        stick = ~wall & ~turn
        s_new, factor = -s[i], (np.abs(A) - f) / (np.abs(A) + f)
    bounces[i] = np.where(turn, bounces[i], 0)
    M = np.zeros((i.size, 2, 2))
    M[:, 0, 0] = 1.0
    M[:, 1, 1] = np.where(turn, factor, 0.0)
    J[i] = np.where(wall[:, None, None], 0.0, M @ J[i])
    s[i] = np.where(turn, s_new, s[i])
    mode[i] = np.where(wall, CONTACT, np.where(stick, STICK, FLIGHT))


def _rest(p, t_end, t, x, v, s, J, mode, side):
    """Sticking and wall contact: leave at the closed-form time, or stay until ``t_end``."""
    F, f, c, k, w = p
    i = np.nonzero((mode == STICK) | (mode == CONTACT))[0]
    if not i.size:
        return
    amp = F * np.cos(k * x[i])
    contact = mode[i] == CONTACT
    up, down = first_above(amp, f, w, t[i]), first_above(-amp, f, w, t[i])
    t_stick, s_stick = np.minimum(up, down), np.where(up <= down, 1.0, -1.0)
    t_rel = first_above(-side[i] * amp, f, w, t[i])
    t_next = np.where(contact, t_rel, t_stick)
    s_next = np.where(contact, -side[i], s_stick)
    leave = t_next <= t_end
    t[i] = np.where(leave, t_next, t_end)
    v[i] = 0.0
    s[i] = np.where(leave, s_next, s[i])
    mode[i] = np.where(leave, FLIGHT, DONE)


class OdeParams:
    """What ``fast.api`` needs of a position-forcing scene (``l``, ``r``, ``T``), plus the
    scene itself: the flow-selection token that routes ``fast.api`` to ``run_all``."""

    def __init__(self, scene):
        self.scene = scene
        self.l, self.r = scene.float("l"), scene.float("r")
        self.T = 2 * math.pi / scene.float("omega")
        self.T_lo = 0.0        # fast.ode's fixed-step flights run to the float T

    @classmethod
    def from_scene(cls, scene):
        return cls(scene)


def run_all(P, x, v, t_end, jac=False, log=None):
    """``fast.api._run_all``'s contract for an ``OdeParams``: ``(x, v, zero_velocity, J)``
    over ``[0, t_end]`` with ``J`` of shape ``(n, 4)`` (row-major 2x2) or ``None``."""
    if log is not None:
        raise NotImplementedError("fast.ode: event logs under position forcing are not implemented")
    zv = []
    xs, vs, J = ode_map(P.scene, x, v, t_end=t_end, jac=jac, zero_velocity=zv)
    return xs, vs, zv[0], (J.reshape(-1, 4) if jac else None)
