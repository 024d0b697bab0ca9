"""Mean-value (centred) enclosures of ``Phi'`` and ``dPhi/dp`` over a wide box.

Over a box ``U`` of starts and parameters (``u = (x0, v0, p_1, ...)``) the walk encloses each
event's data (time, velocity before, ...) in a ball.  The Table 1 product evaluated on those
balls treats the data as independent, while they move together with ``u``: for a piece with
one impact, ``J_01 = -(h_a + h_b) + k h_a h_b`` loses that ``h_a + h_b`` is fixed, and the
impact time and speed that make ``k`` move along one curve; the ball is ~10 times the true
spread.  The mean-value form in ``u``,

    J(u) in J(u~) + D_u J(U) (U - u~),      u~ = mid U,

holds for every ``u`` in ``U`` (the mean-value theorem, entry by entry; ``J`` is smooth on
``U`` because the walk proved one transversal itinerary there), and its width is
``|D_u J| |U - u~|`` with the derivative's own cancellations kept.  ``D_u J`` comes from
evaluating the *same* code (``reference.jacobian.product_of_table1``,
``sensitivity.parameter_jacobian``) on :class:`Dual` numbers whose gradients are the event
data's derivatives with respect to ``u`` over the box: the start ``(x0, v0)`` and the
parameters are the unit directions, each flight is ``motion.Flight`` on Duals, and an event
time ``t* = t_a + h`` has ``dh/du = -g_u / g_h`` (the implicit function theorem on its event
function ``g``, ``g_h`` proved away from 0 by its Krawczyk step), ``dv-/du = v_u + a dh/du``.
``J(u~)`` is the point walk's at the box's centre.  Each entry returned is the intersection
of the plain and the centred enclosures (both hold).  Impacts and turns only (a rest, a
chatter run or damping: the plain enclosure is kept).
"""
from __future__ import annotations

from flint import arb

from reference.enclosure import motion
from reference.enclosure.dual import Dual
from reference.enclosure.sensitivity import parameter_jacobian
from reference.integrator import Event, EventLog
from reference.jacobian import product_of_table1

class DualModel:
    """The ball model with its parameters as :class:`Dual` (unit gradients for ``names``),
    the arithmetic hooks of Table 1 (``one``, ``zero``, ``exp``, ``expm1``) and ``force``."""

    _ATTR = {"F": "F", "f": "f", "omega": "w", "l": "l", "r": "r", "restitution": "e", "damping": "c"}

    def __init__(self, model, names):
        self.n = 2 + len(names)
        for name, attr in self._ATTR.items():
            value = getattr(model, attr)
            grad = [0] * self.n
            if name in names:
                grad[2 + names.index(name)] = 1
            setattr(self, attr, Dual(value, tuple(grad)))
        self.T = model.T
        for flag in ("friction", "restitution", "damping", "position_forcing"):
            setattr(self, flag, getattr(model, flag))
        self.one, self.zero = model.one, model.zero

    @staticmethod
    def exp(z):
        return z.exp()

    @staticmethod
    def expm1(z):
        return z.expm1()

    def wall(self, side):
        return self.r if side > 0 else self.l

    def force(self, x, t):
        return self.F * (self.w * t).cos()


def dual_log(model, log, names):
    """The ball log with every event's ``t, x, v, v_before`` as :class:`Dual` over
    ``u = (x0, v0, p...)`` (``names`` the parameters), or None (an event other than impacts and
    turns, damping, or a start at rest).  ``(dual_model, log)``."""
    if model.damping or model.position_forcing or not (log.v0 > 0 or log.v0 < 0 or not model.friction):
        return None
    dm = DualModel(model, list(names))
    n = dm.n
    unit = [tuple(1 if j == k else 0 for j in range(n)) for k in range(n)]
    t, x, v = Dual(log.t0, (0,) * n), Dual(log.x0, unit[0]), Dual(log.v0, unit[1])
    s = (1 if log.v0 > 0 else -1) if model.friction else 0
    out = EventLog()
    out.t0, out.x0, out.v0, out.t_end = t, x, v, log.t_end
    for ev in log:
        if ev.kind not in ("impact", "turn"):
            return None
        stack = motion.Flight(dm, t, x, v, s).stack(ev.t - t.val)     # d/du at fixed h
        if ev.kind == "impact":
            side = 1 if ev.v_before > 0 else -1
            g_u = dm.wall(side) - stack[0]            # side factors cancel in -g_u / g_h
            dh = tuple(g / stack[1].val for g in g_u.grad)
        else:
            dh = tuple(-g / stack[2].val for g in stack[1].grad)
        t = Dual(ev.t, tuple(a + b for a, b in zip(t.grad, dh)))
        v_before = Dual(ev.v_before, tuple(a + stack[2].val * b for a, b in zip(stack[1].grad, dh)))
        if ev.kind == "impact":
            x, v = dm.wall(side), -dm.e * v_before
            s = -side if model.friction else 0
        else:
            x = Dual(ev.x, tuple(a + stack[1].val * b for a, b in zip(stack[0].grad, dh)))
            v, s = Dual(arb(0), (0,) * n), -s
        x = Dual(ev.x, x.grad)
        v = Dual(ev.v, v.grad)
        out.append(Event(ev.kind, t, x, v, v_before, ev.count))
    return dm, out


def _centre(at_mid, dual, deltas, plain):
    """``value(u~) + grad(U) . (U - u~)``, intersected with the plain enclosure."""
    grad = dual.grad if isinstance(dual, Dual) else ()      # a constant entry: no gradient
    out = at_mid + sum((g * d for g, d in zip(grad, deltas)), arb(0))
    if not out.overlaps(plain):     # two enclosures of one value cannot be disjoint
        raise ArithmeticError("the centred and the plain enclosures are disjoint")
    return out.intersection(plain)


def centred(model, log, names, columns, deltas, at_mid, plain):
    """``(J, cols)``: ``Phi'`` and ``dPhi/dp`` for the parameters ``columns`` over the box in
    mean-value form in ``u = (x0, v0, names...)`` (module docstring), given their values
    ``at_mid = (J~, cols~)`` at the centre ``u~``, ``deltas = U - u~`` (balls) and the
    ``plain`` enclosures; ``plain`` where not covered."""
    got = dual_log(model, log, names)
    if got is None:
        return plain
    dm, dlog = got
    J = product_of_table1(dm, dlog)
    Jc = [[_centre(a, g, deltas, p) for a, g, p in zip(ra, rg, rp)]
          for ra, rg, rp in zip(at_mid[0], J, plain[0])]
    if not columns or plain[1] is None or at_mid[1] is None:
        return Jc, plain[1]
    cols = parameter_jacobian(dm, dlog, list(columns))[1]
    Cc = [tuple(_centre(a, g, deltas, p) for a, g, p in zip(ca, cg, cp))
          for ca, cg, cp in zip(at_mid[1], cols, plain[1])]
    return Jc, Cc
