"""What both compiled loops (``fast.loop``, ``fast.ode``) write: the event log of a state and
its row of the batch's outputs.

``record`` appends ``(kind, t, x, v after, v before, count)`` to the state's log ``ev`` (kept
up to its capacity ``st[CAP]``; ``st[NEV]`` counts every event, so a truncated log is known);
``store`` copies a finished state's record ``st`` and log into row ``i`` of the outputs, with
a non-finite end state turned into ``NON_FINITE``; ``out_of_events`` says how a state ran out
of events.
"""
from __future__ import annotations

import math

from . import state as q
from .batch import BOUNCE_BUDGET, EVENT_BUDGET
from .jit import kernel

#: impacts in one run at one wall (``st[CHN]``) from which a state whose event budget ran out
#: is said to have spent it on bounces (``BOUNCE_BUDGET``): a run of bounces that does not
#: shrink (restitution 1, no friction: elastic bounces at a wall the force pushes into, a
#: gap of 1e-12 makes millions a period) never sums to rest, and every bounce is an event
BOUNCE_RUN = 1000


@kernel
def out_of_events(st):
    """The status of a state whose event budget (``max_events``) ran out: ``BOUNCE_BUDGET`` in a
    run of at least ``BOUNCE_RUN`` impacts at one wall, else ``EVENT_BUDGET``."""
    return BOUNCE_BUDGET if abs(st[q.CHN]) >= BOUNCE_RUN else EVENT_BUDGET


@kernel
def record(ev, st, kind, t, x, v, vb, cnt):
    """Append an event to the state's log ``ev`` (kept up to its capacity; ``NEV`` counts
    them all)."""
    k = int(st[q.NEV])
    st[q.NEV] += 1.0
    if k < st[q.CAP]:
        j = 6 * k
        ev[j], ev[j + 1], ev[j + 2], ev[j + 3], ev[j + 4], ev[j + 5] = kind, t, x, v, vb, cnt


@kernel
def store(i, status, ok, non_finite, st, ev, jac, out_x, out_v, out_zv, out_J, out_nev, out_status,
          out_paths, log_kind, log_t, log_x, log_v, log_vb, log_cnt):
    """Row ``i`` of the outputs from the finished state's record and log (``status`` becomes
    ``non_finite`` when an ``ok`` run ended on a non-finite state)."""
    xf, vf = st[q.XF], st[q.VF]
    if status == ok and not (math.isfinite(xf) and math.isfinite(vf)):
        status = non_finite
    out_status[i], out_paths[i] = status, int(st[q.PATHS])
    out_x[i], out_v[i] = xf, vf
    out_zv[i] = 1 if st[q.ZV] != 0.0 else 0
    if jac:
        for k in range(4):
            out_J[i, k] = st[q.J11 + k]
    nev = int(st[q.NEV])
    out_nev[i] = nev
    for k in range(min(nev, log_kind.shape[1])):
        log_kind[i, k] = int(ev[6 * k])
        log_t[i, k], log_x[i, k] = ev[6 * k + 1], ev[6 * k + 2]
        log_v[i, k], log_vb[i, k] = ev[6 * k + 3], ev[6 * k + 4]
        log_cnt[i, k] = int(ev[6 * k + 5])
