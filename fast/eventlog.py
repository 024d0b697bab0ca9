"""Event itineraries for the cross-check: ``fast.events(scene, x, v, t_end=None)``.

Returns an ``EventLog``: for a batch of ``shape`` states, padded arrays of shape
``shape + (m,)`` (``m`` the largest number of events of a state):

* ``kind``: int8 codes into ``KINDS`` (``-1`` pads), ``kinds(i)`` gives the strings;
* ``t``, ``x``, ``v`` (velocity just after the event), ``v_before``, ``count`` (impacts
  simulated before a chatter tail was summed; 0 for other kinds), NaN pads;
* ``n``: the number of events per state; ``x_end``, ``v_end``: the final state;

and ``log[i]`` (``i`` a flat index or an index tuple) gives the list of ``Event`` records
of state ``i`` (``kind`` a string: the kinds of ``reference.integrator``).  The motion runs
from ``t = 0`` to ``t_end`` (default one period ``T``) in one pass.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import api
from .state import KINDS


class Event(NamedTuple):
    kind: str
    t: float
    x: float
    v: float
    v_before: float
    count: int


class EventLog:
    """Padded per-state event arrays (see the module docstring)."""

    def __init__(self, shape, result):
        self.shape = shape
        kind, t, x, v, vb, cnt = result.log
        m = int(result.n_events.max()) if result.n_events.size else 0
        self.n = result.n_events.reshape(shape)
        self.kind = kind[:, :m].reshape(shape + (m,))
        for name, arr in (("t", t), ("x", x), ("v", v), ("v_before", vb)):
            setattr(self, name, arr[:, :m].reshape(shape + (m,)))
        self.count = np.where(kind[:, :m] >= 0, cnt[:, :m], np.nan).reshape(shape + (m,))
        self.x_end = result.x.reshape(shape)
        self.v_end = result.v.reshape(shape)

    def _flat(self, i):
        return np.ravel_multi_index(i, self.shape) if isinstance(i, tuple) else int(i)

    def kinds(self, i):
        """The event kind strings of state ``i``."""
        return [e.kind for e in self[i]]

    def __getitem__(self, i):
        j = self._flat(i)
        n = int(self.n.ravel()[j])
        # one ``tolist`` per column (Python floats, exact), not a numpy scalar per value: the
        # hard cases' scans read ~10^4 logs of up to ~100 events (issue 33, the narrow corner)
        k, t, x, v, vb, c = (a.reshape(len(self), a.shape[-1])[j, :n].tolist()
                             for a in (self.kind, self.t, self.x, self.v, self.v_before, self.count))
        return list(map(Event, map(KINDS.__getitem__, k), t, x, v, vb, map(int, c)))

    def __len__(self):
        return int(np.prod(self.shape))


def events(scene, x, v, t_end=None, *, max_events=api.MAX_EVENTS, threads=None):
    """The event itinerary of each state over ``[0, t_end]`` (default one period); ``threads``
    as in ``fast.api``."""
    engine, P, x, v, max_events, threads = api._setup(scene, x, v, max_events, threads)
    if t_end is None:
        t_end, t_end_lo = api._period(engine, P)
    else:
        t_end, t_end_lo = api.check_t_end(t_end), 0.0
    res = api._run(engine, P, x, v, t_end, t_end_lo, max_events, threads, log=True)
    return EventLog(x.shape, res)
