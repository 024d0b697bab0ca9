"""``Phi'`` rebuilt from an event log with the paper's Table 1 -- the faithful product, and the
faults of the catalogue that live in it.

Walking the log of ``[0, T]`` (later on the left), with the mode between events: a flight over
``h`` is ``[[1, h], [0, 1]]``, a sticking interval ``[[1, 0], [0, 0]]``, wall contact the zero
matrix; an impact ``[[-e, 0], [((1+e) A + (1-e) s f)/v-, -e]]`` with ``v-`` the velocity before
it (``s = sgn v-``); a turn ``[[1, 0], [0, (|A| - f)/(|A| + f)]]`` (``reference.jacobian``
derives each).  ``A(t) = F cos(w t)``: the base model with restitution, no damping, no position
forcing (``SUPPORTED``).  The faults (``fault=``): ``"reflection with v+"`` puts the velocity
after the impact in the reflection matrix; ``"no turn factor"`` drops the turning point's factor.
"""
from __future__ import annotations

import math

import numpy as np

SUPPORTED = frozenset({"walls", "forcing", "friction", "restitution"})
_AFTER = {"impact": "flight", "turn": "flight", "slip": "flight", "release": "flight",
          "stick": "stick", "contact": "contact", "chatter": "contact"}


def _interval(mode, h):
    if mode == "flight":
        return np.array([[1.0, h], [0.0, 1.0]])
    if mode == "stick":
        return np.array([[1.0, 0.0], [0.0, 0.0]])
    return np.zeros((2, 2))


def _event(params, kind, t, v_after, v_before, fault):
    F, f, w, e = params["F"], params["f"], params["omega"], params["restitution"]
    A = F * math.cos(w * t)
    if kind == "impact":
        v = v_after if fault == "reflection with v+" else v_before
        s = 1.0 if v_before > 0 else -1.0
        return np.array([[-e, 0.0], [((1 + e) * A + (1 - e) * s * f) / v, -e]])
    if kind == "turn" and f > 0 and fault != "no turn factor":
        return np.array([[1.0, 0.0], [0.0, (abs(A) - f) / (abs(A) + f)]])
    return np.eye(2)


def jacobian(params: dict, events, start_mode: str = "flight", fault: str | None = None) -> np.ndarray:
    """``Phi'`` over one period from the log ``events`` (tuples ``(kind, t, x, v after, v before)``)."""
    T = 2 * math.pi / params["omega"]
    J, t_prev, mode = np.eye(2), 0.0, start_mode
    for kind, t, _x, v_after, v_before in events:
        J = _event(params, kind, t, v_after, v_before, fault) @ _interval(mode, t - t_prev) @ J
        t_prev, mode = t, _AFTER.get(kind, mode)
    return _interval(mode, T - t_prev) @ J
