"""``Phi'`` as the ordered product of the paper's Table 1 matrices (later on the left).

Walking the event log of ``[0, T]``, with the mode between events:

* flight over ``h``:            ``[[1, h], [0, 1]]``
* impact at ``t*``:             ``[[-1, 0], [2 A(t*) / v-, -1]]`` with ``v-`` the velocity
  **before** the impact.  Derivation (the saltation matrix of the reset, written out here):
  ``S = DR + (f+ - DR f-) grad(h)^T / (grad(h) . f-)`` with ``h(x) = x - r``,
  ``DR = diag(1, -1)``, ``f- = (v-, a-)``, ``f+ = (-v-, a+)`` gives the lower-left entry
  ``(a+ + a-)/v-``; friction cancels in ``a+ + a- = (A + s f) + (A - s f) = 2 A``.  The
  paper writes ``x'(t*)``: with ``x'(t*+) = -v-`` that would flip the sign of the entry.
  ``test_reference_jacobian`` pins the choice against finite differences.
  With restitution: ``[[-e, 0], [((1+e) A + (1-e) s f)/v-, -e]]``, ``s = sgn v-``.
* turn at ``t~``:               ``[[1, 0], [0, (|A| - f)/(|A| + f)]]``
* a sticking interval:          ``[[1, 0], [0, 0]]`` (``stick`` ... ``slip``, or ... ``T``)
* wall contact:                 ``[[0, 0], [0, 0]]`` (``contact``/``chatter`` ... ``release``)

Frictionless scenes log no event at ``v = 0`` (a turn with factor 1: nothing to multiply).
The matrices take their arithmetic from the model (mpf or arb balls: one product, two
number types).  The Jacobian does not exist on grazing orbits (``1/v-`` blows up) and at chatter the
exit state does not depend on the entry (the zero matrix).
"""
from __future__ import annotations

import mpmath

_MODE_AFTER = {"impact": "flight", "turn": "flight", "slip": "flight", "release": "flight",
               "stick": "stick", "contact": "contact", "chatter": "contact"}


def mat_mul(P, Q):
    """The 2x2 product ``P Q`` (any number type)."""
    return [[P[0][0] * Q[0][0] + P[0][1] * Q[1][0], P[0][0] * Q[0][1] + P[0][1] * Q[1][1]],
            [P[1][0] * Q[0][0] + P[1][1] * Q[1][0], P[1][0] * Q[0][1] + P[1][1] * Q[1][1]]]


def flight_matrix(model, h):
    """Flight over ``h`` (damping: ``[[1, (1 - exp(-c h))/c], [0, exp(-c h)]]``)."""
    one, zero = model.one, model.zero
    if model.damping:
        E = model.exp(-model.c * h)
        return [[one, -model.expm1(-model.c * h) / model.c], [zero, E]]
    return [[one, h], [zero, one]]


def impact_matrix(model, A, v_before, t=None):
    """Reflection saltation matrix, with the velocity BEFORE the impact.

    At a grazing impact (``v- = 0``) the entry ``2 A / v-`` is infinite: ``Phi'`` does not
    exist there (the paper's footnote on grazing), and a ``ValueError`` says so.
    """
    if v_before == 0:
        raise ValueError(
            f"jacobian: Phi' does not exist on this orbit: a grazing impact at t = "
            f"{mpmath.nstr(t, 20) if t is not None else '?'} with zero velocity before impact "
            f"(the reflection matrix has 1/v-)")
    e, zero = model.e, model.zero
    s = 1 if v_before > 0 else -1
    lower = ((1 + e) * A + (1 - e) * s * model.f) / v_before
    return [[-e, zero], [lower, -e]]


def turn_matrix(model, A):
    """Turning point: the speed after is scaled by ``(|A| - f)/(|A| + f)``."""
    one, zero = model.one, model.zero
    return [[one, zero], [zero, (abs(A) - model.f) / (abs(A) + model.f)]]


def _flight(model, start, t):
    """Flight matrix from ``start = (t0, x0, v0)`` to ``t``.

    Closed-form flows have ``[[1, h], [0, 1]]`` (damped: see :func:`flight_matrix`); under
    position forcing the flight matrix solves the variational equations along the Taylor
    flow (``reference.taylor.flight_matrix``).  The event matrices of Table 1 are unchanged
    there (their derivation only uses ``a+ + a- = 2 A(x*, t*)``), and so is the sticking
    matrix: the exit time of a stick now depends on ``x``, but the flow vector at the exit
    is ``(v, a) = (0, 0)`` (the force just equals friction), so that dependence drops out.
    """
    if model.position_forcing:
        validated = getattr(model, "flow_derivative", None)
        if validated is not None:        # reference.enclosure: the validated flight's own
            return validated(start, t)   # enclosure of the variational equations
        from reference import taylor  # only scenes with position forcing reach the Taylor flow

        return taylor.flight_matrix(model, start[0], start[1], start[2], t)
    return flight_matrix(model, t - start[0])


def product_of_table1(model, log):
    """The Jacobian of the map ``(x0, v0) -> (x(t_end), v(t_end))`` of an event log.

    The arithmetic is the model's (``model.one``, ``.zero``, ``.exp``, ``.expm1``): mpf for
    ``reference.model.Model``, arb balls for ``reference.enclosure`` (the same Table 1 product
    over enclosures of the event data is an enclosure of ``Phi'``).
    """
    one, zero = model.one, model.zero
    J = [[one, zero], [zero, one]]
    stick = [[one, zero], [zero, zero]]
    nothing = [[zero, zero], [zero, zero]]
    mode, start = "flight", (log.t0, log.x0, log.v0)
    for ev in log:
        if mode == "flight":
            J = mat_mul(_flight(model, start, ev.t), J)
        elif mode == "stick" and ev.kind == "slip":
            J = mat_mul(stick, J)
        elif mode == "contact" and ev.kind == "release":
            J = nothing
        if ev.kind == "impact":
            J = mat_mul(impact_matrix(model, model.force(ev.x, ev.t), ev.v_before, ev.t), J)
        elif ev.kind == "turn":
            J = mat_mul(turn_matrix(model, model.force(ev.x, ev.t)), J)
        mode, start = _MODE_AFTER[ev.kind], (ev.t, ev.x, ev.v)
    if mode == "flight":
        J = mat_mul(_flight(model, start, log.t_end), J)
    elif mode == "stick":
        J = mat_mul(stick, J)
    else:
        J = nothing
    return J
