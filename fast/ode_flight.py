"""One flight of ``fast.ode`` (position-dependent forcing), compiled: fixed compensated DOP853
steps to the flight's first event, certified on each step's dense output.

A flight is integrated by fixed DOP853 steps (``fast.dop853``) of
length ``h = 2 pi / (S Lambda)``, ``Lambda = max(w, k |v|, sqrt(F k), c)`` at the step start,
the last one ending at ``t_end``; ``S = STEPS_PER_PERIOD`` (a search may ask for fewer:
``fast.api``'s ``steps_per_period``, the slot ``SPP`` of ``P``).  The steps are compensated
(``fast.compensated``, issue 33): the state, the clock, the period, the parameters and the
trigonometry of each step's start are double-doubles, each stage's acceleration carries its
own rounding, and an event's state comes from a step onto it plus one Newton step of its
time; so the one-period error is that of float64 rounding, not of its accumulation over the
~100 steps of a period.  Measured against the reference at 40 digits as ``|fast - ref| /
max(1, |ref|) / (eps max(1, |Phi'|))`` (``golden_fast_phi_per_cond``'s measure; eps =
2^-52): with ``S = 96`` and float64 steps mean 13 / max 208 over 40 random position-forced
scenes x 8 states (0.87 / 1.8 on ``fig:xpotno``); compensated, 0.21 / 1.5 (0.08 / 0.23), the
closed-form loop's standard.  ``S``: the truncation reaches that floor at ``S = 128`` (``S =
96``: mean 0.40, max 10 where the forcing's amplitude ``F / Lambda^2`` exceeds the gap; 160
and 256 change nothing).

Events (the first of them in a step): the wall ``g = s (W_s - x)`` and the velocity ``g = s v``,
both positive before their event.  Root exclusion per step: with ``M >= |g''| h^2`` over the
step (``|x''| <= F + f + c vmax``, ``|v''| <= F w + F k vmax + c amax``, ``vmax`` from ``d|v|/dt
<= F + f + c |v|``), ``g(theta) >= g(0) + g'(0) theta - M theta^2/2``: a step with that
minorant positive at ``theta = 1`` has no root.  Flagged steps are cut into ``SUBDIV``
pieces of the dense output, each with the same test; a sign change is bracketed and
polished by safeguarded Newton (bisection when Newton leaves the bracket); a piece
without one whose test fails, and which rises above ``TANGENT_FLOOR`` (times the scale) at
an end, is searched for a close pair or a tangency by golden section for the minimum of
``g``: below minus the floor -- or below zero from a start above the floor -- the first
root lies between the piece's start and the minimum; otherwise within the floor the minimum is
the (tangential) root.  (A dip below zero but within the floor is a close pair too: taking its
minimum for the root put the impact half the pair's width late, 1.5e-7 at a depth of 1.2e-14
on a constructed crossing pair; its first root is as well conditioned as the dip.)  (A piece flat at noise
level -- a flight leaving rest under a force of rounding size -- has no dip to find.)
"""
from __future__ import annotations

import math

import numpy as np

from . import compensated as cs
from . import dop853 as dp
from . import state as q
from .jit import data_pointer, kernel
from .ode_params import DAMP, DD_SLOTS, FF, K, L, L_LO, R, R_LO, SPP, W, F, params

EPS = 2.0 ** -52
SUBDIV = 8
NEWTON_ITERS = 60
GOLDEN_ITERS = 40
TANGENT_FLOOR = 64 * EPS
#: the event codes of a flight
NO_EVENT, WALL, VZERO, TOO_FAST = 0, 1, 2, -2


# --- the flight: steps, and the certified first event on the dense output ----------------
@kernel
def _force(P, x, t):
    return P[F] * math.cos(P[K] * x) * math.cos(P[W] * t)


@kernel
def _g(P, s, wall, t, x, v, which):
    """Event function ``which`` (0: wall, 1: velocity) and its time derivative."""
    if which == 0:
        return s * (wall - x), -s * v
    return s * v, s * (_force(P, x, t) - s * P[FF] - P[DAMP] * v)


@kernel
def _step_len(P, av):
    """``h = 2 pi / (S Lambda)``, ``Lambda = max(w, k |v|, sqrt(F k), c, sqrt((F + f) / X))``:
    the fastest of the forcing, the phase rate of ``cos(k x)``, the linearised ``x'' = F cos(k
    x)``, damping, and the forcing's reach against the scale ``X = max(1, |l|, |r|)`` of ``x``
    (the position's truncation ``~ (h w)^7 h^2 (F + f)`` is measured relative to ``X``: with
    ``F / w^2 >> X`` -- flights between walls far shorter than a period -- ``h w`` alone lost
    up to 3 eps a period at ``S = 128``, issue 33)."""
    reach = math.sqrt((P[F] + P[FF]) / max(max(1.0, abs(P[L])), abs(P[R])))
    lam = max(max(P[W], P[K] * av), max(max(math.sqrt(P[F] * P[K]), P[DAMP]), reach))
    return 2 * math.pi / (P[SPP] * lam)


@kernel
def _bounds(P, av, h):
    """``(max |x''|, max |v''|)`` over a step of length ``h`` from speed ``av``."""
    Ff, c = P[F] + P[FF], P[DAMP]
    vmax = (av + Ff / c) * math.exp(c * h) - Ff / c if c > 0.0 else av + Ff * h
    amax = Ff + c * vmax
    return amax, P[F] * P[W] + P[F] * P[K] * vmax + c * amax


@kernel
def _g_at(P, s, wall, t, h, wk, n, which, theta):
    """Event function ``which`` on the dense output at ``theta``: ``(g, dg/dtheta)``."""
    dp.dense_eval(wk, theta, n)
    g, dg = _g(P, s, wall, t + theta * h, wk[dp.YD], wk[dp.YD + 1], which)
    return g, dg * h


@kernel
def _newton_bisect(P, s, wall, t, h, wk, n, which, lo, hi):
    """Root in ``[lo, hi]`` of a function with ``g(lo) > 0 >= g(hi)``: Newton from the middle,
    bisection whenever Newton leaves the shrinking bracket (bounded by ``NEWTON_ITERS``)."""
    th = 0.5 * (lo + hi)
    for _ in range(NEWTON_ITERS):
        g, dg = _g_at(P, s, wall, t, h, wk, n, which, th)
        if g == 0.0:
            return th
        if g > 0.0:
            lo = th
        else:
            hi = th
        nt = th - g / dg if dg != 0.0 else math.nan
        if not (lo < nt < hi):
            nt = 0.5 * (lo + hi)
        if abs(nt - th) <= 2 * EPS * abs(th) or hi - lo <= 4 * EPS * abs(hi):
            return nt
        th = nt
    return hi


@kernel
def _golden_min(P, s, wall, t, h, wk, n, which, lo, hi):
    """The minimiser of ``g`` on ``[lo, hi]`` by golden section: ``(theta, g_min)``."""
    r = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    for _ in range(GOLDEN_ITERS):
        c1, c2 = b - r * (b - a), a + r * (b - a)
        if _g_at(P, s, wall, t, h, wk, n, which, c1)[0] <= _g_at(P, s, wall, t, h, wk, n, which, c2)[0]:
            b = c2
        else:
            a = c1
    th = 0.5 * (a + b)
    return th, _g_at(P, s, wall, t, h, wk, n, which, th)[0]


@kernel
def _first_root(P, s, wall, t, h, wk, n, which, M, g0, d0, floor):
    """``theta`` of the earliest root of event ``which`` in ``(0, 1]`` (``inf``: none), on
    ``SUBDIV`` pieces of the dense output (module docstring)."""
    d = 1.0 / SUBDIV
    for j in range(SUBDIV):
        g1, d1 = _g_at(P, s, wall, t, h, wk, n, which, (j + 1) * d)
        if not (g0 >= 0.0 and g0 + d0 * d - M * d * d / 2 > 0.0):
            if g1 <= 0.0:                             # a sign change: bracketed
                return _newton_bisect(P, s, wall, t, h, wk, n, which, j * d, (j + 1) * d)
            if not max(g0, g1) > floor:
                g0, d0 = g1, d1                       # flat at noise level: no dip to find
                continue
            th, gmin = _golden_min(P, s, wall, t, h, wk, n, which, j * d, (j + 1) * d)
            if th > 1e-6 and (gmin < -floor or (gmin < 0.0 and g0 > floor)):
                return _newton_bisect(P, s, wall, t, h, wk, n, which, j * d, th)  # a close pair: its first root
            if th > 1e-6 and abs(gmin) <= floor:      # a tangential zero
                return th
        g0, d0 = g1, d1
    return math.inf


@kernel
def _fly(P, st, wk, t_end, n, max_steps):
    """Integrate the flight from ``(st[TT], wk[Y0])`` with sign ``st[S]`` to its first event
    or ``t_end``: returns ``(code, steps)`` with the time reached in ``st[TT]`` and the state
    there in ``wk[Y0]`` (``x = W`` at a wall event, ``v = 0`` at a velocity zero); code
    ``-1``: ``max_steps`` exhausted; ``TOO_FAST``: the step ``2 pi/(S k |v|)`` fell below
    the resolution of the double-double clock at ``t_end`` (``4 eps^2 |t_end|``: no step would
    move it; with a float64 clock such a step was taken as the end of the flight and the
    state came back unchanged, ``|v| = 1e50`` under ``k = 1``)."""
    s = st[q.S]
    wall = P[R] if s > 0.0 else P[L]
    xs = max(1.0, abs(wall))
    no_v = P[F] == 0.0 and P[FF] == 0.0            # no force: v never changes sign
    cs.begin(wk, st[q.TT], P, DD_SLOTS)
    for k in range(max_steps):
        t = st[q.TT]
        x, v = wk[dp.Y0], wk[dp.Y0 + 1]
        step = _step_len(P, abs(v))
        if not step > 4 * EPS * EPS * abs(t_end):       # below the double-double clock's resolution
            return TOO_FAST, k
        h, last = cs.length(step, t, t_end, wk)
        if not h > 0.0:                                 # nothing is left (the clock is exact)
            st[q.TT] = t_end
            return NO_EVENT, k
        gw, dgw = _g(P, s, wall, t, x, v, 0)
        gv, dgv = _g(P, s, wall, t, x, v, 1)
        mx, mv = _bounds(P, abs(v), h)
        safe = (gw >= 0.0 and gw + dgw * h - mx * h * h / 2 > 0.0) and (no_v or (
            gv >= 0.0 and gv + dgv * h - mv * h * h / 2 > 0.0))
        cs.step(P, DD_SLOTS, s, t, h, wk, n, not safe)
        th, thw, thv = math.inf, math.inf, math.inf
        if not safe:
            thw = _first_root(P, s, wall, t, h, wk, n, 0, mx * h * h, gw, dgw * h, TANGENT_FLOOR * xs)
            if not no_v:
                thv = _first_root(P, s, wall, t, h, wk, n, 1, mv * h * h, gv, dgv * h,
                                  TANGENT_FLOOR * max(1.0, abs(v)))
            th = min(thw, thv)
        if th < math.inf:
            cs.step(P, DD_SLOTS, s, t, th * h, wk, n, True)       # the event's state: a step
            wall_lo = P[R_LO] if s > 0.0 else P[L_LO]
            st[q.TT] = cs.event(wk, t, th * h, h, n, wall, wall_lo, thw <= thv)
            return (WALL if thw <= thv else VZERO), k + 1
        st[q.TT] = cs.advance(wk, t, h, last, t_end, n)
        if last:
            return NO_EVENT, k + 1
    return -1, max_steps


@kernel
def _flights(P, t0, x0, v0, s, t_end, jac, out_t, out_x, out_v, out_ev, out_J):
    st_own, wk_own = np.zeros(q.SIZE), np.zeros(cs.SIZE)
    Pp, st, wk = data_pointer(P), data_pointer(st_own), data_pointer(wk_own)
    n = 6 if jac else 2
    for i in range(t0.size):
        cs.reset(wk, 0.0)
        st[q.TT], st[q.S] = t0[i], s[i]
        wk[dp.Y0], wk[dp.Y0 + 1] = x0[i], v0[i]
        wk[dp.Y0 + 2], wk[dp.Y0 + 3], wk[dp.Y0 + 4], wk[dp.Y0 + 5] = 1.0, 0.0, 0.0, 1.0
        out_ev[i] = _fly(Pp, st, wk, t_end[i], n, 1 << 40)[0]
        out_t[i], out_x[i], out_v[i] = st[q.TT], wk[dp.Y0], wk[dp.Y0 + 1]
        if jac:
            for k in range(4):
                out_J[i, k] = wk[dp.Y0 + 2 + k]
    return st_own.size + wk_own.size


def flight(scene, t0, x0, v0, s, t_end, *, jac=False):
    """One flight per element from ``(t0, x0, v0)`` with sign ``s`` to its first event or
    ``t_end``: ``(t, x, v, event, J)`` (``event``: ``NO_EVENT``, ``WALL`` or ``VZERO``; ``J`` the
    flight matrices, shape ``(n, 2, 2)``, or ``None``).  Arrays of one length ``n``."""
    P = params(scene)
    arrays = {}
    n = np.size(x0)
    for name, a in (("t0", t0), ("x0", x0), ("v0", v0), ("s", s), ("t_end", t_end)):
        a = np.atleast_1d(np.asarray(a, dtype=np.float64))
        if a.shape != (n,):
            raise ValueError(f"fast.ode.flight: {name} must have shape ({n},), got {a.shape}")
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise ValueError(f"fast.ode.flight: {name} must be finite; offending indices {bad[:10].tolist()}")
        arrays[name] = a
    bad = np.flatnonzero(np.abs(arrays["s"]) != 1)
    if bad.size:
        raise ValueError(f"fast.ode.flight: s must be +1 or -1; offending indices {bad[:10].tolist()}")
    out = (np.empty(n), np.empty(n), np.empty(n), np.zeros(n, np.int64), np.zeros((n, 4)))
    _flights(P, arrays["t0"], arrays["x0"], arrays["v0"], arrays["s"], arrays["t_end"], bool(jac),
             *out)
    return out[0], out[1], out[2], out[3], (out[4].reshape(n, 2, 2) if jac else None)
