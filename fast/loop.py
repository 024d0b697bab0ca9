"""The compiled per-state event loop of the closed-form engine (``fast.batch``'s contract).

One state at a time, from ``t = 0`` to the double-double end ``t_end + t_end_lo``:

1. the start state is classified (an impact at ``t = 0``, at rest inside or on a wall) and
   handled at once (``fast.handlers``);
2. the flight segment is searched for its next event with float64 trials
   (``fast.flight.evaluate``) certified by ``fast.roots.plan`` -- no event is ever skipped,
   and a trial that lands on an accepted root is the event; a trial predicted from far away
   is first moved closer by ``fast.roots.refine``;
3. the event is moved onto its exact time and state in double-double (``fast.precise``)
   and handled: a new segment, rest until a closed-form exit time, a summed chatter tail,
   or the end;
4. a state certified at ``t_end`` in flight gets its final state in double-double (a trial
   at ``t_end`` is searched on that double-double flight: one evaluation serves both).

Bounds: ``MAX_SEGMENT_ROUNDS`` search rounds per flight segment (a few normally; after a
failed speculation the certified steps converge quadratically, linearly near a tangency),
``MAX_SAME_TIME`` events in a row without time advancing, and the caller's ``max_events``
per state: exceeding one stops the state with a status (``fast.batch``), never a hang.
"""
from __future__ import annotations

import math

import numpy as np

from . import batch
from . import dd
from . import params as p
from . import state as q
from .flight import evaluate
from .handlers import finish, flight_matrix, handle
from .jit import data_pointer, kernel
from .output import out_of_events, store
from .params import params  # noqa: F401  (the engine's params, fast.batch's contract)
from .precise import at_end, at_event, end_state, flight_at
from .roots import CRAWL_ROUNDS, plan, plan_crawl, refine

EPS = 2.0 ** -52
MAX_SEGMENT_ROUNDS = 1000
MAX_SAME_TIME = 50
_CONTINUE = -1
OK, LOOP_BOUND, NON_FINITE = batch.OK, batch.LOOP_BOUND, batch.NON_FINITE


@kernel
def _start(P, st, x, v, jac):
    """Reset the record for a state ``(x, v)`` at ``t = 0``; returns the event at ``t = 0``
    (``NONE``, ``IMPACT`` at a wall moving into it, ``VZERO`` at rest inside, ``ATWALL``)."""
    cap = st[q.CAP]
    for k in range(q.SIZE):
        st[k] = 0.0
    st[q.CAP] = cap
    st[q.TLAST] = -math.inf
    st[q.P1], st[q.P2] = math.inf, math.inf
    s = 1.0 if v >= 0.0 else -1.0
    st[q.X0], st[q.V0], st[q.S], st[q.CS0] = x, v, s, 1.0
    st[q.D0] = P[p.R] - x if s > 0.0 else x - P[p.L]
    st[q.ZV] = 1.0 if v == 0.0 else 0.0
    if jac:
        st[q.J11], st[q.J22] = 1.0, 1.0
    if (x == P[p.R] and v > 0.0) or (x == P[p.L] and v < 0.0):
        return q.IMPACT
    if v == 0.0:
        return q.ATWALL if (x == P[p.R] or x == P[p.L]) else q.VZERO
    return q.NONE


@kernel
def _finish_flight(P, st, t_end, t_end_lo, jac, known, x, v):
    """A state certified at ``t_end`` in flight: final flight matrix and state (``x, v``
    where ``known``, else from ``at_end``)."""
    if jac:
        flight_matrix(P, st, ((t_end - st[q.T0]) - st[q.T0LO]) + t_end_lo)
    if not known:
        x, v = at_end(P, st, t_end, t_end_lo)
    finish(st, x, v)


@kernel
def _at_trial(P, st, b, t_end, t_end_lo):
    """The flight at the trial ``b`` for the search: ``(dx, v, cos wt, sin wt, x_end, v_end,
    end_lo)``.  At ``b = t_end`` it comes from the double-double flight there (its high
    parts), whose state at the end is kept: a segment certified through ``t_end`` is then
    not evaluated twice."""
    if b == t_end:
        dxh, dxl, vh, vl, _, snh, _, csh, _ = flight_at(P, st, t_end, t_end_lo)
        xe, ve = end_state(P, st, dxh, dxl, vh, vl)
        return dxh, vh, csh, snh, xe, ve, t_end_lo
    dx, v, cs, sn = evaluate(P, (b - st[q.T0]) - st[q.T0LO], st[q.V0], st[q.S], st[q.SN0],
                             st[q.CS0])
    return dx, v, cs, sn, 0.0, 0.0, 0.0


@kernel
def _from_start(P, st, t_end, t_end_lo, tol, jac):
    """Plan the current segment from its known start values; a segment certified through
    ``t_end`` is finished here.  Returns ``(code, t, tl)``: ``ATWALL`` (finished), ``NONE``
    (a trial is set) or an event accepted at once at the double-double time ``t + tl``."""
    code, est = plan(P, st, 0.0, st[q.V0], st[q.CS0], st[q.SN0], t_end, tol)
    if code == q.NONE:
        refine(P, st, st[q.T0], t_end)
    if code == q.ATWALL:
        _finish_flight(P, st, t_end, t_end_lo, jac, False, 0.0, 0.0)
    t, tl = dd.two_sum(st[q.T0], est)
    return code, t, tl + st[q.T0LO]


@kernel
def _events(P, st, code, t, tl, t_end, t_end_lo, tol, jac, max_events, ev):
    """Handle the accepted event at ``t + tl`` and any events accepted at once from the
    start of the segments that follow it; returns ``OK`` (finished), ``_CONTINUE`` (a
    trial is set) or a failure status."""
    while True:
        code, t, tl, xh, xl, vh, vl, snh, snl, csh, csl = at_event(P, st, code, t, tl)
        if handle(P, st, code, t, tl, xh, xl, vh, vl, (snh, snl, csh, csl), t_end, jac, ev):
            return OK
        if st[q.NEV] > max_events:
            return out_of_events(st)
        if st[q.NSAME] > MAX_SAME_TIME:
            return LOOP_BOUND
        code, t, tl = _from_start(P, st, t_end, t_end_lo, tol, jac)
        if code == q.ATWALL:
            return OK
        if code == q.NONE:
            return _CONTINUE


def max_speed(P) -> float:
    """The largest ``|v|`` of a start this engine takes (``fast.api``): ``FAST_MAX``, like every
    constant of the scene (``fast.params``): the loop multiplies up to three such magnitudes
    (``u^2 + 2 a g`` in ``fast.precise``, ``M3 d^3`` in ``fast.roots``), which stay normal
    within ``1e+-100``; a faster start overflowed ``v^2`` near 1.3e154 and ran into a loop
    bound.  Below it a fast state only costs events: about ``|v| T/(r - l)`` impacts a period,
    within ``max_events``."""
    return p.FAST_MAX


@kernel
def run_state(P, x, v, t_end, t_end_lo, jac, max_events, st, ev):
    """Integrate one state (module docstring); returns its status."""
    tol = 0.25 * EPS * max(P[p.T], t_end)
    code = _start(P, st, x, v, jac)
    if code != q.NONE and handle(P, st, code, 0.0, 0.0, x, 0.0, v, 0.0, (0.0, 0.0, 1.0, 0.0),
                                 t_end, jac, ev):
        return OK
    code, t, tl = _from_start(P, st, t_end, t_end_lo, tol, jac)
    while True:
        if code == q.ATWALL:
            return OK
        if code != q.NONE:
            status = _events(P, st, code, t, tl, t_end, t_end_lo, tol, jac, max_events, ev)
            if status != _CONTINUE:
                return status
        if st[q.NEV] > max_events:
            return out_of_events(st)
        if st[q.NIT] > MAX_SEGMENT_ROUNDS:
            return LOOP_BOUND
        b = st[q.TT]
        dx, vv, cs, sn, xe, ve, end_lo = _at_trial(P, st, b, t_end, t_end_lo)
        if st[q.NIT] <= CRAWL_ROUNDS:
            code, est = plan(P, st, dx, vv, cs, sn, t_end, tol)
        else:
            code, est = plan_crawl(P, st, dx, vv, cs, sn, t_end, tol)
        if code == q.NONE:
            refine(P, st, b, t_end)
        elif code == q.ATWALL:
            _finish_flight(P, st, t_end, t_end_lo, jac, b == t_end, xe, ve)
        t, tl = dd.two_sum(st[q.TT], est)
        tl += end_lo


@kernel
def run_range(P, x, v, t_end, t_end_lo, jac, max_events, out_x, out_v, out_zv, out_J,
              out_nev, out_status, out_paths, log_kind, log_t, log_x, log_v, log_vb, log_cnt,
              i0, i1):
    """``fast.batch``'s engine entry: states ``i0 <= i < i1``.  The loop works on raw data
    pointers (``fast.jit.data_pointer``) to ``P`` and to its own record and event buffer,
    which this function owns until it returns."""
    cap = log_kind.shape[1]
    st_own = np.zeros(q.SIZE)
    ev_own = np.zeros(6 * cap + 1)
    st_own[q.CAP] = cap
    Pp, st, ev = data_pointer(P), data_pointer(st_own), data_pointer(ev_own)
    for i in range(i0, i1):
        status = run_state(Pp, x[i], v[i], t_end, t_end_lo, jac, max_events, st, ev)
        store(i, status, OK, NON_FINITE, st, ev, jac, out_x, out_v, out_zv, out_J, out_nev, out_status,
              out_paths, log_kind, log_t, log_x, log_v, log_vb, log_cnt)
    return st_own.size + ev_own.size                 # the owners live to the end
