"""Derivatives of a section map with respect to the parameters, from a ball event log.

Treat the parameters ``p`` as states with ``p' = 0``; the derivative of the extended map
``(x, v, p) -> (x(t1), v(t1), p)`` between fixed times ``t0, t1`` is the ordered product of the
extended flow and saltation matrices, ``[[J, J_p], [0, I]]``, so that along the log

    J <- M J,      J_p <- M J_p + M_p

for each factor ``(M, M_p)``.  ``M`` is the paper's Table 1 matrix (``reference.jacobian``: the
same code); ``M_p`` its parameter columns:

* flight over ``h = t_b - t_a`` with velocity sign ``s`` from ``t_a`` (``C0, S0 = cos, sin(w t_a)``,
  ``theta = w h``; the closed form of ``reference.enclosure.motion``, differentiated at fixed
  ``t_a, t_b`` and start state):
  ``d/dF = ((C0 (1 - cos theta) - S0 (theta - sin theta)) / w^2, (C0 sin theta - S0 (1 - cos theta)) / w)``,
  ``d/df = (-s h^2 / 2, -s h)``, nothing for the walls or ``e``;
* impact at the wall ``W`` (guard ``x - W``, reset ``v -> -e v``): the saltation matrix of the
  extended system ``S = DR + (f+ - DR f-) grad(g)^T / (grad(g) . f-)`` has the parameter
  columns ``((1 + e) W_p, -L W_p)`` with ``L = ((1 + e) A + (1 - e) s f) / v-`` (Table 1's
  lower entry) and ``W_p = dW/dp`` (1 for the wall's own parameter), plus ``(0, -v-)`` for ``e``
  (the reset's own derivative);
* turn (guard ``v``, which no parameter enters): no parameter column.

Sticking, wall contact and damping are not covered (``None``: the caller falls back to
plain ball evaluation).  Over a box of parameters and starts, the same product over the ball
log encloses ``J_p`` at every point of the box (every factor is a ball over the box).
"""
from __future__ import annotations

from reference.jacobian import flight_matrix, impact_matrix, mat_mul, turn_matrix

#: the parameters whose derivatives are available (``omega`` moves the sections: not here)
PARAMETERS = ("F", "f", "l", "r", "restitution")


def _flight_columns(model, names, t_a, h, s):
    w = model.w
    S0, C0 = (w * t_a).sin_cos()
    theta = w * h
    sn, cs = theta.sin_cos()
    omc = 1 - cs
    cols = []
    for name in names:
        if name == "F":
            cols.append(((C0 * omc - S0 * (theta - sn)) / (w * w), (C0 * sn - S0 * omc) / w))
        elif name == "f":
            cols.append((-s * h * h / 2, -s * h))
        else:
            cols.append((model.zero, model.zero))
    return cols


def _impact_columns(model, names, side, lower, v_before):
    cols = []
    for name in names:
        wall = 1 if (name == "r" and side > 0) or (name == "l" and side < 0) else 0
        if name == "restitution":
            cols.append((model.zero, -v_before))
        else:
            cols.append(((1 + model.e) * wall, -lower * wall))
    return cols


def _apply(J, Jp, M, cols):
    """``J <- M J``, ``J_p <- M J_p + M_p`` (``J_p`` and ``M_p`` as lists of columns)."""
    new = []
    for (a, b), (ca, cb) in zip(Jp, cols):
        new.append((M[0][0] * a + M[0][1] * b + ca, M[1][0] * a + M[1][1] * b + cb))
    return mat_mul(M, J), new


def parameter_jacobian(model, log, names):
    """``(J, J_p)`` of the log's map (``J_p`` a list of columns ``(dx/dp, dv/dp)``, one per name
    in ``names``), or ``None`` if the log has an event other than impacts and turns, the
    model has damping, or a name is not in :data:`PARAMETERS`."""
    if model.damping or model.position_forcing or any(n not in PARAMETERS for n in names):
        return None
    one, zero = model.one, model.zero
    J, Jp = [[one, zero], [zero, one]], [(zero, zero) for _ in names]
    t_a = log.t0
    s = (1 if log.v0 > 0 else -1) if model.friction else 0
    if model.friction and not (log.v0 > 0 or log.v0 < 0):
        return None
    for ev in log:
        if ev.kind not in ("impact", "turn"):
            return None
        h = ev.t - t_a
        J, Jp = _apply(J, Jp, flight_matrix(model, h), _flight_columns(model, names, t_a, h, s))
        A = model.force(ev.x, ev.t)
        if ev.kind == "impact":
            side = 1 if ev.v_before > 0 else -1
            M = impact_matrix(model, A, ev.v_before, ev.t)
            J, Jp = _apply(J, Jp, M, _impact_columns(model, names, side, M[1][0], ev.v_before))
            s = -side if model.friction else 0
        else:
            J, Jp = _apply(J, Jp, turn_matrix(model, A), [(zero, zero) for _ in names])
            s = -s
        t_a = ev.t
    h = log.t_end - t_a
    return _apply(J, Jp, flight_matrix(model, h), _flight_columns(model, names, t_a, h, s))
