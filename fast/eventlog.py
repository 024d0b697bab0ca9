"""Event itineraries for the cross-check: ``fast.events(scene, x, v, t_end=None)``.

Returns an ``EventLog``: for a batch of ``shape`` states, padded arrays of shape
``shape + (m,)`` (``m`` the largest number of events of a state):

* ``kind``: int8 codes into ``KINDS`` (``-1`` pads), ``kinds(i)`` gives the strings;
* ``t``, ``x``, ``v`` (velocity just after the event), ``v_before``, ``count``
  (impacts simulated before a chatter tail was summed; 0 for other kinds), NaN pads;
* ``n``: the number of events per state;

and ``log[i]`` (``i`` a flat index or an index tuple) gives the list of ``Event``
records of state ``i`` with the attributes of SEMANTICS.md (``kind`` a string).
The motion runs from ``t = 0`` to ``t_end`` (default one period ``T``) in one pass.
Meant for modest batches (the log is gathered in Python lists).
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np

from . import kernel
from .api import _params, _validate
from .events_proc import KINDS
from .params import Params


class Event(NamedTuple):
    kind: str
    t: float
    x: float
    v: float
    v_before: float
    count: int


class EventLog:
    """Padded per-state event arrays (see the module docstring)."""

    def __init__(self, shape, records, n_states, x_end, v_end):
        self.shape = shape
        if records:
            idx, code, t, x, v, vb, cnt = (np.concatenate(c) for c in zip(*records))
        else:
            idx = np.zeros(0, np.int64)
            code = np.zeros(0, np.int8)
            t = x = v = vb = cnt = np.zeros(0)
        order = np.argsort(idx, kind="stable")
        idx = idx[order]
        self.n = np.bincount(idx, minlength=n_states)
        m = int(self.n.max()) if n_states else 0
        first = np.concatenate([[0], np.cumsum(self.n)[:-1]]) if n_states else np.zeros(0, int)
        pos = np.arange(idx.size) - first[idx]
        self.kind = np.full((n_states, m), -1, np.int8)
        self.kind[idx, pos] = code[order]
        for name, arr in (("t", t), ("x", x), ("v", v), ("v_before", vb), ("count", cnt)):
            pad = np.full((n_states, m), np.nan)
            pad[idx, pos] = arr[order]
            setattr(self, name, pad.reshape(shape + (m,)))
        self.kind = self.kind.reshape(shape + (m,))
        self.n = self.n.reshape(shape)
        self.x_end = x_end.reshape(shape)
        self.v_end = v_end.reshape(shape)

    def _flat(self, i):
        return np.ravel_multi_index(i, self.shape) if isinstance(i, tuple) else int(i)

    def kinds(self, i):
        """The event kind strings of state ``i``."""
        return [e.kind for e in self[i]]

    def __getitem__(self, i):
        j = self._flat(i)
        flat = lambda a: a.reshape(len(self), a.shape[-1])[j]  # noqa: E731
        n = int(self.n.ravel()[j])
        k, t, x, v, vb, c = (flat(a)[:n] for a in (self.kind, self.t, self.x, self.v,
                                                    self.v_before, self.count))
        return [Event(KINDS[k[e]], float(t[e]), float(x[e]), float(v[e]), float(vb[e]), int(c[e]))
                for e in range(n)]

    def __len__(self):
        return int(np.prod(self.shape))


def events(scene, x, v, t_end=None):
    """The event itinerary of each state over ``[0, t_end]`` (default ``T``)."""
    P = _params(scene)
    if not isinstance(P, Params):
        raise NotImplementedError(f"fast.events: event logs for effects {sorted(scene.effects)} "
                                  "(numerical flights of fast.ode) are not implemented")
    x, v = _validate(P, x, v)
    t_end, t_end_lo = (P.T, P.T_lo) if t_end is None else (float(t_end), 0.0)
    if not (t_end >= 0 and np.isfinite(t_end)):
        raise ValueError(f"fast: t_end must be finite and >= 0, got {t_end!r}")
    records = []
    xs, vs, _, _ = kernel.run(P, x.ravel().copy(), v.ravel().copy(), t_end, log=records,
                                t_end_lo=t_end_lo)
    return EventLog(x.shape, records, x.size, xs, vs)
