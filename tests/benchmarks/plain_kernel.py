"""A plain float64 compiled event loop of the stroboscopic map: the per-core baseline of
issue 27 (``test_bench_per_core.py``).  A benchmark baseline, not an engine: nothing in the
package imports it, and it shares no code with ``fast``.

The same physics as ``fast`` (``x'' + f sgn(x') = F cos(w t)`` between walls ``l <= x <= r``,
impacts ``v -> -e v``, Filippov sticking, rest on a wall) and the same kind of search, but
everything in float64: no double-double (times, states and phases are float64), no event
log, no Jacobian, no state record (locals only), no summed chatter tail (a run of impacts is
followed bounce by bounce until the rebound height is at float resolution, then the particle
rests on the wall), no damping.  The velocity function is skipped on a segment that starts
faster than the forcing and friction can stop it before ``t_end`` (``|v(t) - v0| <= 2 F/w + f
(t_end - t0)``).

Flight with sign ``s`` from ``(t0, x0, v0)``, ``h = t - t0``, ``sn = sin w t``, ``cs = cos w t``
(two libm calls per evaluation)::

    v  = v0 + (F/w)(sn - sin w t0) - s f h
    x  = x0 + v0 h + (F/w^2)(cos w t0 - cs - w h sin w t0) - s f h^2 / 2

The events are the roots of the wall function ``g1 = s (W_s - x)`` and the velocity function
``g2 = s v``, known at a point with three derivatives (``A = F cos wt``, ``a = s A - f``)::

    g1' = -s v,  g1'' = -a,  g1''' = -s A'    (|g1''| <= F + f, |g1'''| <= F w)
    g2' = a,     g2'' = s A', g2''' = s A''   (|g2''| <= F w,   |g2'''| <= F w^2)

The search (per flight segment), from a certified end ``C`` (no root of either function on
``[t0, C]``) and a point ``p >= C`` where both are evaluated:

* *forward certificate*: on ``[0, H]`` ``g(p + h) >= g + g' h + m h^2/2``, ``m = max(g'' - M3
  H, -M)``; its first positive root (or ``H``) is a root-free step;
* *prediction*: the root of the quadratic model nearest to ``p`` in the crossing direction,
  refined by one Newton step on the cubic model; it is *accepted* as the event when the
  cubic term's effect ``M3 |d|^3 / 6`` is below ``tol |g'|``;
* *speculation*: the next trial is the earliest prediction (beyond the certified steps); a
  trial is kept only when each function's backward window reaches ``C``: ``g > 0`` and the
  global minorant run backwards stays positive down to ``C``, or ``g <= 0`` with ``g`` strictly
  decreasing from ``C`` on (``|g'| / M`` reaches back to ``C``): exactly one crossing, then
  refined inside the bracket.  A refuted trial falls back to the certified step (and after
  two refutations the segment stops speculating), so no event is ever skipped.

Rest (sticking inside, or on a wall after an impact at rest speed): the force beats friction
in direction ``+1`` on the phases ``(-alpha, alpha)`` and in direction ``-1`` on ``(pi - alpha,
pi + alpha)``, ``alpha = arccos(f/F)``; the particle slides off at once inside an allowed
zone, else at the next allowed zone's start (a wall allows only the direction away from it).
"""
from __future__ import annotations

import math

import numba
import numpy as np

EPS = 2.0 ** -52
TWO_PI = 2.0 * math.pi
TINY = 1e-300
#: status codes: finished, more than ``max_events`` events, a segment's search exceeded its rounds
OK, EVENT_BUDGET, ROUND_BOUND = 0, 1, 2
MAX_ROUNDS = 1000
#: what the search returns: the end reached, an impact, a velocity zero, a failure
END, IMPACT, VZERO, FAIL = 0, 1, 2, 3
_JIT = dict(cache=True, nogil=True, error_model="numpy")


def constants(F, f, w, l, r, e=1.0):
    """The float64 constants of a scene, one array: ``F, f, w, l, r, e, F/w, F/w^2, T, c =
    f/F, alpha``."""
    c = f / F if F > 0 else math.inf
    alpha = math.acos(c) if c < 1.0 else 0.0
    return np.array([F, f, w, l, r, e, F / w, F / w ** 2, TWO_PI / w, c, alpha])


@numba.njit(**_JIT)
def _forward(g, d1, d2, M, M3, cap):
    """Root-free step of ``g >= 0`` from ``g, g', g''`` (module docstring), at most ``cap``."""
    disc = d1 * d1 + 2.0 * M * g
    hM = (d1 + math.sqrt(disc)) / M if d1 > 0.0 else 2.0 * g / max(math.sqrt(disc) - d1, TINY)
    H = min(max(2.0 * hM, abs(d2) / (2.0 * M3)), cap)
    m = max(d2 - M3 * H, -M)
    disc = d1 * d1 - 2.0 * m * g
    if m < 0.0 or (d1 < 0.0 and disc >= 0.0):
        sq = math.sqrt(max(disc, 0.0))
        h = (d1 + sq) / -m if d1 > 0.0 else 2.0 * g / max(sq - d1, TINY)
        return min(max(h, hM), H)
    return H


@numba.njit(**_JIT)
def _backward_ok(g, d1, M, span):
    """Whether ``g`` (value and slope at ``p``) certifiably has no root on ``[p - span, p)``
    (``g > 0``) or exactly one on ``(p - span, p]`` (``g <= 0``)."""
    if g > 0.0:
        sq = math.sqrt(d1 * d1 + 2.0 * M * g)
        back = (sq - d1) / M if d1 < 0.0 else 2.0 * g / max(sq + d1, TINY)
        return back >= span
    return d1 < 0.0 and -d1 >= M * span and 2.0 * M * g >= -d1 * d1


@numba.njit(**_JIT)
def _predict(g, d1, d2, d3, M3, tol):
    """``(d, accepted)``: the predicted root offset (``inf``: none) and its acceptance."""
    if d1 < 0.0:
        disc = d1 * d1 - 2.0 * d2 * g
        if disc < 0.0:
            return g / -d1, False
        d = 2.0 * g / (math.sqrt(disc) - d1)
    elif d2 < 0.0 and g > 0.0:
        d = (d1 + math.sqrt(d1 * d1 - 2.0 * d2 * g)) / -d2
    else:
        return math.inf, False
    if d != 0.0:
        c = g + d * (d1 + d * (0.5 * d2 + d * (d3 / 6.0)))
        step = c / (d1 + d * (d2 + d * (0.5 * d3)))
        if abs(step) < 0.5 * abs(d):
            d -= step
    return d, d1 < 0.0 and M3 * abs(d) ** 3 <= 6.0 * tol * -d1


@numba.njit(**_JIT)
def _jets(K, s, D0, dx, v, sn, cs):
    """``(g, g', g'', g''')`` of the wall and the velocity function."""
    F, f, w = K[0], K[1], K[2]
    a = s * F * cs - f
    sA1 = -s * F * w * sn
    return (D0 - s * dx, -s * v, -a, -sA1), (s * v, a, sA1, -s * F * w * w * cs)


@numba.njit(**_JIT)
def _flight(K, t0, v0, s, sn0, cs0, t):
    """``(dx, v, sn, cs)`` of the flight at ``t`` (module docstring)."""
    f, w, FW, FW2 = K[1], K[2], K[6], K[7]
    h = t - t0
    sn, cs = math.sin(w * t), math.cos(w * t)
    v = v0 + FW * (sn - sn0) - s * f * h
    dx = v0 * h + FW2 * ((cs0 - cs) - w * h * sn0) - 0.5 * s * f * h * h
    return dx, v, sn, cs


@numba.njit(**_JIT)
def _search(K, t0, x0, v0, s, sn0, cs0, t_end, tol):
    """The next event of the segment from ``(t0, x0, v0)`` with sign ``s`` and ``sin, cos(w
    t0)``: ``(what, t, dx, v, sn, cs)`` (``what``: ``END`` at ``t_end``, ``IMPACT``, ``VZERO`` or
    ``FAIL``)."""
    F, f, w, l, r = K[0], K[1], K[2], K[3], K[4]
    M = (F + f, F * w)
    M3 = (max(F * w, TINY), max(F * w * w, TINY))
    D0 = r - x0 if s > 0.0 else x0 - l
    noise = (8.0 * EPS * (D0 + abs(v0) * (t_end - t0) + 2.0 * K[7] + f * (t_end - t0) ** 2),
             8.0 * EPS * (abs(v0) + 2.0 * K[6] + f * (t_end - t0)))
    fresh = v0 == 0.0                              # leaving rest: g2 = 0 at t0, not a root
    # |v(t) - v0| <= 2 F/w + f (t_end - t0): a segment that starts faster cannot stop
    turns = not s * v0 > 2.0 * K[6] + f * (t_end - t0)
    C, p, dx, v, sn, cs = t0, t0, 0.0, v0, sn0, cs0
    fails = 0
    for _ in range(MAX_ROUNDS):
        start = fresh and p == t0
        jets = _jets(K, s, D0, dx, v, sn, cs)
        if start:
            jets = (jets[0], (0.0, max(jets[1][1], 0.0), jets[1][2], jets[1][3]))
        if p > C and not (_backward_ok(jets[0][0], jets[0][1], M[0], p - C) and (
                not turns or _backward_ok(jets[1][0], jets[1][1], M[1], p - C))):
            fails += 1                             # refuted: back to the certified end
            p = C
            dx, v, sn, cs = _flight(K, t0, v0, s, sn0, cs0, p)
            continue
        bracket = jets[0][0] <= 0.0 or (turns and jets[1][0] <= 0.0 and not start)
        if not bracket:
            C = p
        best, kind, acc, trial = math.inf, END, False, math.inf
        steps = (0.0, math.inf)
        for i in range(2 if turns else 1):
            g, d1, d2, d3 = jets[i]
            leaving = start and i == 1
            if abs(g) <= noise[i] and d1 <= 0.0 and not leaving:
                d, ok = 0.0, True                  # at the root within rounding
            else:
                d, ok = _predict(g, d1, d2, d3, M3[i], tol)
            step = 0.0
            if g > 0.0 or leaving:
                step = _forward(max(g, 0.0), d1, d2, M[i], M3[i], t_end - p)
            steps = (step, steps[1]) if i == 0 else (steps[0], step)
            if d < best and p + d >= C:
                best, kind, acc = d, IMPACT if i == 0 else VZERO, ok
            trial = min(trial, max(d, step) if d != math.inf else step)
        safe = min(steps[0], steps[1])
        other = steps[1] if kind == IMPACT else steps[0]
        if acc and p + best <= t_end and (bracket or best <= other):
            t = p + best
            dx, v, sn, cs = _flight(K, t0, v0, s, sn0, cs0, t)
            return kind, t, dx, v, sn, cs
        if not bracket and p + safe >= t_end:
            if p < t_end:
                dx, v, sn, cs = _flight(K, t0, v0, s, sn0, cs0, t_end)
            return END, t_end, dx, v, sn, cs
        if bracket:
            q = p + best
            p = q if C < q < p else 0.5 * (C + p)
        else:
            C = p + safe                           # root-free up to here
            p = p + (safe if fails >= 2 else min(trial, t_end - p))
            p = min(max(p, C), t_end)
        dx, v, sn, cs = _flight(K, t0, v0, s, sn0, cs0, p)
    return FAIL, p, dx, v, sn, cs


@numba.njit(**_JIT)
def _rest(K, t, side):
    """Leaving rest at ``t`` (``side``: 0 inside, +1 on ``r``, -1 on ``l``): ``(t_exit, s)``;
    ``t_exit = inf`` where the force never beats friction (``F <= f``)."""
    w, c, alpha = K[2], K[9], K[10]
    if not c < 1.0:
        return math.inf, 0.0
    phase = (w * t) % TWO_PI
    cs = math.cos(phase)
    if cs > c and side <= 0.0:
        return t, 1.0
    if cs < -c and side >= 0.0:
        return t, -1.0
    best, s_best = math.inf, 0.0
    for s, start in ((1.0, TWO_PI - alpha), (-1.0, math.pi - alpha)):
        if s * side <= 0.0:
            dt = ((start - phase) % TWO_PI) / w
            if dt < best:
                best, s_best = dt, s
    return t + best, s_best


@numba.njit(**_JIT)
def _state(K, x, v, t_end, max_events):
    """One state from ``t = 0`` to ``t_end``: ``(x, v, status)``."""
    F, f, w, l, r, e = K[0], K[1], K[2], K[3], K[4], K[5]
    xres = 16.0 * EPS * max(abs(l), abs(r), r - l)
    tol = 0.5 * EPS * max(K[8], t_end)
    t0, x0, v0, t, sn, cs = 0.0, x, v, 0.0, 0.0, 1.0
    if v == 0.0:
        t0, s = _rest(K, 0.0, 1.0 if x == r else (-1.0 if x == l else 0.0))
    else:
        s = 1.0 if v > 0.0 else -1.0
        if (x == r and s > 0.0) or (x == l and s < 0.0):
            v0, s = -e * v, -s                     # an impact at t = 0
    for _ in range(max_events + 1):
        if not t0 < t_end:
            return x0, v0, OK
        if t0 != t:                                # the phase at a rest exit
            sn, cs = math.sin(w * t0), math.cos(w * t0)
        what, t, dx, vb, sn, cs = _search(K, t0, x0, v0, s, sn, cs, t_end, tol)
        if what == END:
            return min(max(x0 + dx, l), r), vb, OK
        if what == FAIL:
            return np.nan, np.nan, ROUND_BOUND
        if what == IMPACT:
            W, u, pu = (r if s > 0.0 else l), e * abs(vb), s * F * cs
            if u * u <= 2.0 * max(pu + f, TINY) * xres:    # rebounds at float resolution
                t0, s_new = _rest(K, t, s)
                x0, v0, s = W, 0.0, s_new
            else:
                t0, x0, v0, s = t, W, -e * vb, -s
        else:                                      # a turn or sticking
            x0, v0 = min(max(x0 + dx, l), r), 0.0
            t0, s = _rest(K, t, 0.0)
    return np.nan, np.nan, EVENT_BUDGET


@numba.njit(**_JIT)
def strobe(K, x, v, out_x, out_v, out_status, max_events=10_000_000):
    """``Phi`` over one period ``T = K[8]`` for every state ``(x[i], v[i])``, one thread.  The
    constants travel as a tuple (by value: no reference counting in the loop)."""
    Kt = (K[0], K[1], K[2], K[3], K[4], K[5], K[6], K[7], K[8], K[9], K[10])
    for i in range(x.size):
        out_x[i], out_v[i], out_status[i] = _state(Kt, x[i], v[i], Kt[8], max_events)
