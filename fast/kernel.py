"""The event-driven kernel: one batch of states from t = 0 to ``t_end``, vectorised.

Every state is a flight segment ``(t0, x0, v0, s, sin wt0, cos wt0)`` plus a trial time
``b`` and the certified ends ``C1, C2`` of its two event functions (the wall ahead,
``g1 = s (W_s - x)``, and the velocity, ``g2 = s v``: no root of ``g_i`` in
``[t0, C_i)``).  One round of the loop, over the states still running (compacted with
index arrays, so finished states cost nothing):

1. evaluate the closed-form flight at the trial times (``fast.flight``: two trig calls);
2. states with a pending event (initial states only, or rare segment-start events) are
   processed at the exact evaluation (``fast.events_proc``);
3. ``_plan`` (``fast.roots.analyze`` for both functions): a trial beyond ``min(C1, C2)``
   (speculative) is kept only if the backward windows at it reach back to ``C1, C2``,
   else the state retreats to ``min(C1, C2)``; at a kept point the accepted root (if it
   is earlier than the other function's certified end and ``t_end``) is processed at
   once, the state being recomputed at the event in long double (``fast.precise``: one
   or two local-model steps onto the exact event, |d| <= d_acc) and the trig at the
   double-double event time; otherwise the next trial is the
   predicted crossing (exact-curvature quadratic) or ``t_end``.  A state certified at
   ``t_end`` with no event there is finished (events exactly at ``t_end`` are processed).

Typical cost: 1-2 evaluations per impact, 2-4 per turn (against ~5 for plain certified
stepping).  Each state's numbers depend on that state only (no batch-wide adaptive
decision), so results are identical for every batch size and order.

Bounds: ``MAX_SEGMENT_ROUNDS`` rounds per flight segment (a few normally; after a failed
speculation the certified steps converge quadratically, linearly near a tangency) and
``MAX_EVENTS`` events per state; exceeding either raises ``RuntimeError`` with the
offending states.
"""
from __future__ import annotations

import numpy as np

from . import events_proc as ep
from . import precise
from .flight import evaluate, phase_trig, two_sum
from .params import EPS, damped_bounds
from .roots import analyze

MAX_SEGMENT_ROUNDS = 1000
MAX_EVENTS = 1_000_000

# rows of the state table
(T0, X0, V0, S, SN0, CS0, TT, D0, IDX, PEND, NIT, NEV, FRESH, CHN, ZV, C1, C2, SPEC, NFAIL,
 T0LO, X0LO, V0LO, J11, J12, J21, J22) = range(26)
N_ROWS = 26
# pending codes
NONE, IMPACT, VZERO, END, ATWALL = 0, 1, 2, 3, 4


def run(P, x, v, t_end, *, jac=False, log=None, offset=0, t_end_lo=0.0):
    """Integrate 1-d float arrays ``x, v`` from 0 to ``t_end`` (+ ``t_end_lo``: the end
    as a double-double, e.g. the period ``P.T + P.T_lo``).

    Times are double-doubles where an error of one ulp of ``t`` would show: a segment
    starts at ``T0 + T0LO`` (an event at ``b + d`` is stored error-free with
    ``two_sum``), and a trial time ``b`` is a float, evaluated at ``h = (b - T0) - T0LO``
    (+ ``t_end_lo`` at ``b = t_end``).  An event time rounded to float64 would move the
    state after an impact by ``2 |v|`` times half an ulp of ``t``: several ulp of ``x``.

    Returns ``(x, v, zero_velocity, J)`` with ``J`` of shape ``(n, 4)`` (row-major
    2x2) or ``None``.  ``log`` (a list) receives the event records when given.
    """
    n = x.size
    out = np.zeros((7, n))
    st = _initial(P, x, v, jac)
    tol = 0.25 * EPS * max(P.T, t_end)
    rounds = 0
    while st.shape[1]:
        rounds += 1
        _check_bounds(P, st, rounds, offset)
        h = _offset(st, t_end, t_end_lo)
        dx, vv, cs, sn = evaluate(P, h, st[X0], st[V0], st[S], st[SN0], st[CS0])
        pi = np.flatnonzero(st[PEND])
        if pi.size:
            sub = st[:, pi]
            fin = ep.process(P, sub, dx[pi], vv[pi], cs[pi], sn[pi], t_end, out, log, jac,
                             t_lo=_end_lo(sub, t_end, t_end_lo), exact_trig=False)
            st[:, pi] = sub
            dx[pi] = 0.0
            vv[pi] = sub[V0]
            cs[pi] = sub[CS0]
            sn[pi] = sub[SN0]
            if fin.any():
                keep = np.ones(st.shape[1], bool)
                keep[pi[fin]] = False
                st, dx, vv, cs, sn = st[:, keep], dx[keep], vv[keep], cs[keep], sn[keep]
        if st.shape[1]:
            st = _advance(P, st, dx, vv, cs, sn, t_end, tol, out, jac, log, t_end_lo)
    bad = ~(np.isfinite(out[0]) & np.isfinite(out[1]))
    if bad.any():
        idx = np.flatnonzero(bad)[:5]
        raise RuntimeError(f"fast: non-finite result for states {(idx + offset).tolist()} "
                           f"(x0={x[idx].tolist()}, v0={v[idx].tolist()})")
    xs, vs, zv = out[0], out[1], out[2] != 0
    return xs, vs, zv, (out[3:7].T.copy() if jac else None)


def _initial(P, x, v, jac):
    n = x.size
    st = np.zeros((N_ROWS if jac else J11, n))
    st[X0] = x
    st[V0] = v
    st[SN0] = 0.0
    st[CS0] = 1.0
    st[IDX] = np.arange(n)
    s = np.sign(v)
    zero = v == 0
    # v = 0 inside: the sticking rule (with s A(0) = F >= -f) decides stick or slip at once
    s[zero] = 1.0
    st[S] = s
    at_r, at_l = x == P.r, x == P.l
    st[D0] = np.where(s > 0, P.r - x, x - P.l)
    pend = np.where(zero, VZERO, NONE)
    pend = np.where(zero & (at_r | at_l), ATWALL, pend)
    pend = np.where((at_r & (v > 0)) | (at_l & (v < 0)), IMPACT, pend)
    st[PEND] = pend
    st[FRESH] = 1.0
    st[ZV] = zero
    if jac:
        st[J11] = 1.0
        st[J22] = 1.0
    return st


def _end_lo(st, t_end, t_end_lo):
    """The low part of each trial time ``TT``: ``t_end_lo`` where the trial is the end
    (``t_end + t_end_lo``), else 0."""
    return np.where(st[TT] == t_end, t_end_lo, 0.0) if t_end_lo else 0.0


def _offset(st, t_end, t_end_lo):
    """Flight time ``h`` from the segment start ``T0 + T0LO`` to the trial time."""
    return ((st[TT] - st[T0]) - st[T0LO]) + _end_lo(st, t_end, t_end_lo)


def _check_bounds(P, st, rounds, offset=0):
    bad = (st[NIT] > MAX_SEGMENT_ROUNDS) | (st[NEV] > MAX_EVENTS)
    if bad.any():
        cols = st[:, bad][:, :5]
        desc = "; ".join(
            f"state {int(c[IDX]) + offset}: t={c[TT]!r} t0={c[T0]!r} x0={c[X0]!r} v0={c[V0]!r} s={c[S]:+.0f}"
            for c in cols.T)
        raise RuntimeError(
            f"fast: event loop bound exceeded (>{MAX_SEGMENT_ROUNDS} rounds in one flight or "
            f">{MAX_EVENTS} events) for {int(bad.sum())} state(s): {desc}")


def _values(P, st, dx, v, cs, sn, M1):
    """Both event functions and their first two derivatives at the trial times
    (with damping ``s x'' = s A - f - c s v`` and ``s x''' = s A' - c s x''``)."""
    s = st[S]
    a = s * (P.F * cs) - P.f                      # s x'' = s A - f (- c s v)
    h = st[TT] - st[T0]                           # for the noise floors only
    av0 = np.abs(st[V0])
    # noise floors: 8 ulp of the largest term of x(t) - x0 (resp. v), capped by the scene's
    n1 = np.minimum((8 * EPS) * (st[D0] + av0 * h + (0.5 * M1) * (h * h)), P.noise1)
    n2 = np.minimum((8 * EPS) * (av0 + M1 * h), P.noise2)
    a3 = -s * (P.F * P.w) * sn                    # s x''' = s A' (- c s x'')
    if P.damp > 0:
        a = a - P.damp * (s * v)
        a3 = a3 - P.damp * a
    w1 = (st[D0] - s * dx, -s * v, -a, n1)                  # g1 = s (W_s - x)
    w2 = (s * v, a, a3, n2)                                 # g2 = s v
    return w1, w2


def _plan(P, st, dx, v, cs, sn, t_end, tol):
    """Certify the trial point, detect an accepted event, choose the next trial.

    A trial beyond the certified ends ``C1, C2`` of the last certified point is
    *speculative*: it is kept only if the backward windows at the trial reach back to
    ``C1, C2`` (then nothing was skipped); otherwise the state retreats to
    ``min(C1, C2)`` (the plain certified step).  Returns ``(code, est, fin)``: event
    code (IMPACT / VZERO / NONE) and its offset ``est`` from the trial time, and the
    states certified at ``t_end`` with no event (finished).
    """
    b = st[TT]
    H_cap = t_end - b
    if P.damp > 0:                  # per-segment bounds (fast.params.damped_bounds)
        M1, M2, M2_3, d_acc = damped_bounds(P, np.abs(st[V0]))
        M1_3 = M2
    else:
        M1, M1_3, M2, M2_3, d_acc = P.M1, P.M1_3, P.M2, P.M2_3, P.d_acc
    w1, w2 = _values(P, st, dx, v, cs, sn, M1)
    safe1, est1, acc1, back1 = analyze(w1[0], w1[1], w1[2], M1, M1_3, H_cap, tol, w1[3], d_acc)
    g2 = w2[0]
    fresh = (st[FRESH] != 0) & (g2 <= 0)
    if P.F == 0 and P.f == 0:                    # v is constant: no velocity event at all
        safe2 = np.full_like(b, np.inf)
        est2, acc2, back2 = safe2, np.zeros(b.shape, bool), safe2
        pos2 = np.ones(b.shape, bool)
    else:
        d2 = np.where(fresh, np.maximum(w2[1], 0.0), w2[1])
        safe2, est2, acc2, back2 = analyze(g2, d2, w2[2], M2, M2_3, H_cap, tol, w2[3], d_acc, fresh)
        pos2 = (g2 > 0) | fresh
    pos1 = w1[0] > 0
    lo1, lo2 = b - np.abs(back1), b - np.abs(back2)
    spec = st[SPEC] != 0
    cert = ~spec | ((lo1 <= st[C1]) & (lo2 <= st[C2]))
    c1 = np.where(pos1, b + safe1, np.where(np.isnan(lo1), b, lo1))
    c2 = np.where(pos2, b + safe2, np.where(np.isnan(lo2), b, lo2))
    t1 = b + est1
    t2 = b + est2
    e1 = cert & acc1 & (t1 <= np.minimum(c2, t_end))
    e2 = cert & acc2 & (t2 <= np.minimum(c1, t_end)) & ~(e1 & (t1 <= t2))
    e1 &= ~e2
    code = np.where(e1, IMPACT, np.where(e2, VZERO, NONE))
    est = np.where(e1, est1, est2)
    fin = cert & (code == NONE) & (H_cap <= 0) & pos1 & pos2
    # next trial: the predicted crossing (ahead, or behind after an overshoot), or t_end
    p1 = np.where(pos1 & (est1 <= 0), np.inf, t1)
    p2 = np.where(pos2 & (est2 <= 0), np.inf, t2)
    pred = np.minimum(np.minimum(p1, p2), t_end)
    cmin = np.minimum(c1, c2)
    pred = np.where(st[NFAIL] >= 2, np.minimum(pred, np.minimum(cmin, t_end)), pred)
    retreat = np.minimum(np.minimum(st[C1], st[C2]), t_end)
    go = (code == NONE) & ~fin
    st[TT] = np.where(go, np.where(cert, pred, retreat), b)
    gc = go & cert
    st[SPEC] = np.where(gc, pred > cmin, 0.0)
    st[NFAIL] += go & ~cert
    st[C1] = np.where(gc, c1, st[C1])
    st[C2] = np.where(gc, c2, st[C2])
    st[NIT] += 1
    st[FRESH] = np.where(go, 0.0, st[FRESH])
    return code, est, fin


def _advance(P, st, dx, v, cs, sn, t_end, tol, out, jac, log, t_end_lo=0.0):
    """Plan every running flight; process the accepted events at once (the state
    recomputed at the event in long double, ``fast.precise.at_event``; the trig at the
    double-double event time, ``fast.flight.phase_trig``) and plan the new
    segments from their start values.  Returns the table of the states still running:
    the ones without an event, then the ones with one (a state's numbers never depend
    on its column, and the event log is ordered per state by ``IDX``).  Rebuilding the
    table costs two gathers and a contiguous copy, against a scatter of every row back
    into place plus a compaction (measured 3-4 times dearer)."""
    code, est, fin = _plan(P, st, dx, v, cs, sn, t_end, tol)
    if fin.any():
        ep.finish_flight(P, st[:, fin], out, jac, t_end, t_end_lo)
    ev = code != NONE
    ei = np.flatnonzero(ev)
    if not ei.size:
        return st.compress(~fin, axis=1) if fin.any() else st
    sub = st.take(ei, axis=1)
    # the event time b + d, error-free: b + t_lo (b = TT, t_lo: the end's lo part when
    # the trial was the end), then + d; snapped onto the exact event in long double
    t_hi, t_lo = two_sum(sub[TT], est[ei])
    t_lo += _end_lo(sub, t_end, t_end_lo)
    code_e, x_e, dx_e, v_e, t_hi, t_lo, lo_e = precise.at_event(P, sub, code[ei], t_hi, t_lo)
    sub[TT] = t_hi
    cs_e, sn_e = phase_trig(P, t_hi, t_lo)
    sub[PEND] = code_e
    fin_e = ep.process(P, sub, dx_e, v_e, cs_e, sn_e, t_end, out, log, jac, t_lo=t_lo, x=x_e,
                       lo=lo_e)
    # plan the new segments from their start values (finished rows are dropped)
    zero = np.zeros(ei.size)
    with np.errstate(all="ignore"):         # finished rows hold stale values
        code2, est2, fin2 = _plan(P, sub, zero, sub[V0], sub[CS0], sub[SN0], t_end, tol)
    fin2 &= ~fin_e
    if fin2.any():
        ep.finish_flight(P, sub[:, fin2], out, jac, t_end, t_end_lo)
        fin_e |= fin2
    # an event at a segment start (rare): evaluated exactly next round
    sub[TT] = np.where(code2 != NONE, sub[TT] + est2, sub[TT])
    sub[PEND] = code2
    rest = st.compress(~(ev | fin), axis=1)
    if fin_e.any():
        sub = sub.compress(~fin_e, axis=1)
    return np.concatenate((rest, sub), axis=1)
