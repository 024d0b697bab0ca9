"""The hand-off of a validated flight's set through an event, in mean-value form.

Without it an event hands the next flight balls: the event time ``T`` (over every start of
the box) and the state after the event, each enclosed on its own.  The next flight moves
that box from ``T`` to the exact ``base = T.lower()`` along the flow
(``lohner.ValidatedFlight._shift``), which adds ``|f| rad T`` to both coordinates; and the
speed before an impact is the hull over ``T`` and the set, where the true spread nearly
cancels.  Each event multiplies the widths by ~4 (issue 33: on a point start at 192 bits the
event times' radii grow from 1e-57 to 1e-38 over 33 events of an unseen scene), whatever the
true sensitivity of the motion.

Here the set keeps its dependence on the start.  The flight's set at the step of the event is
``{m + A r : r in R}``, and ``z(tau; r)`` lies in ``centre(tau) + M(tau) r`` with ``M`` the
flow derivative over the step (``lohner``).  The event's local time ``tau*(r)`` is a zero of
``g(z) = const + coef z[j]`` (``j = 0`` an impact, ``j = 1`` a turn), simple and unique on the
ball ``tau`` for every ``r`` (the walk's Krawczyk certificate and its check that
``g' != 0``), so by the implicit function theorem

    d tau* / dr = -M[j] / z'[j]            (z' = (v, a) before the event),

and the state of the next flight at ``base``, ``z_b(r) = Psi(base; t*(r), J(z(tau*(r); r)))``
(``Psi`` the next flight's flow, run back from the event to ``base``; ``J`` the jump:
``(wall, -e v)`` for an impact, ``(x, 0)`` for a turn), has the derivative

    d z_b / dr = D (DJ (M + z'- (d tau*/dr)) - z'+ (d tau*/dr)),

``DJ = [[0, 0], [0, -e]]`` (impact) or ``[[1, 0], [0, 0]]`` (turn), ``z'+ = (v+, a+)`` the next
flight's field after the event, ``D`` the derivative of ``Psi`` over ``[base, T]``
(``I +- (exp(L rad) - 1)``, the next flight's ``shift``).  Enclosing every factor over the
whole set and the ball ``tau`` gives a ball matrix ``G`` with ``dz_b/dr in G`` for every ``r``
of the convex ``R``; the mean value theorem, componentwise, then puts

    z_b(r)  in  z_b(r0) + G (r - r0)                         (r0 = mid R),

and ``z_b(r0)`` is the centre's own event, located by an interval Newton step on its
polynomial, jumped, and run back to ``base`` by the next flight's Taylor series with a
Lagrange remainder over a Picard box.  The parallelogram is re-framed as a Lohner step does
(``lohner.reframe``) and starts the next flight at the exact ``base``: the next
event's time is ``base + sigma`` (no ``rad T`` added), and the speed's cancellation survives.

The start the flights track (``lohner.ValidatedFlight.point_state``), with offsets ``Rp`` in
``R``, goes through by the same form: ``z_b(Rp) in z_b(r0) + G (Rp - r0)``.  At a stop, which no
flight follows at once, its own zero of ``v`` is located by the same interval Newton on its own
offsets (:meth:`Handoff.tracked_stop`), the start of its own rest (``walk.Walk._track_rest``).

Every enclosure is a ball statement for every start of the set, so the hand-off is sound for a
parameter box as well.  It is used only where its area is no more than the old hand-off's box's
(:func:`smaller`); an event whose ball ``tau`` straddles two Taylor steps keeps the box.
"""
from __future__ import annotations

from flint import arb

from reference.enclosure.lohner import reframe
from reference.enclosure.picard import interval as _interval
from reference.enclosure.picard import picard_box
from reference.jacobian import mat_mul

#: The order of the Taylor series that runs the centre's state back from its event to
#: ``base`` (over ``rad T``, at most ~1e-5 on the widest boxes the proofs walk: the remainder
#: ``~ rad^(ORDER + 1)`` is far below any working precision).
BACK_ORDER = 16
#: Interval Newton steps that locate the centre's own event time in the ball ``tau``.
NEWTON_STEPS = 3


class Handoff:
    """The set of the flight ``flight`` at its event ``tau`` (local time ``u``, a ball in one
    Taylor step), of event function ``fn``, kind ``kind`` (``"impact"`` or ``"turn"``), at the
    absolute time ``T``; :meth:`start` gives the next flight's set at its ``base``."""

    def __init__(self, flight, fn, u, kind, side, T):
        self.flight, self.fn, self.kind, self.side, self.T, self.u = flight, fn, kind, side, T, u
        pieces = flight._pieces(u) if kind in ("impact", "turn", "stick") else []
        self.ok = len(pieces) == 1
        if self.ok:
            self.step, self.tau = pieces[0]

    def start(self, post, base, D, box):
        """``(mid, A, R, Rp)``: the next flight's set at ``base`` (``post``: its ``Field``;
        ``D``: the derivative of its flow over ``[base, T]``) and the offsets ``Rp`` of the start
        the flight tracks (``lohner.ValidatedFlight.point_state``; ``None`` if none): ``z_b(r) in
        z_b(r0) + G (r - r0)`` for every ``r`` of ``R``, the tracked one among them.  None where
        no hand-off applies or where the old hand-off's box ``box`` at ``base`` is smaller
        (:func:`smaller`)."""
        if not self.ok or self.kind == "stick":
            return None
        fl, st, j = self.flight, self.step, self.fn.offset
        R = st.R
        r0 = [b.mid() for b in R]
        _, M, _ = fl._at(st, self.tau)
        before = fl.stack(self.u)           # the set's stack over the event's ball
        if before[j + 1].contains(0):
            return None
        after = self._jump(before[:2])
        G = mat_mul(D, gradient(M, j, self._jump_derivative(), before[1:3],
                                post.stack(self.T, *after)[1:3]))
        c = self._centre(post, base, r0)
        if c is None:
            return None
        Rp = None if st.Rp is None else [st.Rp[k] - r0[k] for k in range(2)]
        carried = reframe(c, G, [R[k] - r0[k] for k in range(2)], Rp)
        return carried if smaller(carried, box) else None

    def _jump(self, z):
        m = self.flight.m
        if self.kind == "impact":
            return [m.wall(self.side), -m.e * z[1]]
        return [z[0], arb(0)]

    def _jump_derivative(self):
        zero, one = arb(0), arb(1)
        if self.kind == "impact":
            return [[zero, zero], [zero, -self.flight.m.e]]
        return [[one, zero], [zero, zero]]

    def _centre(self, post, base, r0):
        """``z_b(r0)``: the centre's event (:meth:`_located`), its jump, and the next flight's
        series back to ``base``; None if Newton does not contract inside ``tau``."""
        got = self._located(r0)
        if got is None:
            return None
        t_star, before = got
        return _back(post, t_star, self._jump(before), base)

    def _located(self, r):
        """``(t*, z(t*))``, the event of the starts with offsets ``r`` in the step's frame
        (exact: the centre ``r0``; balls: the tracked start's ``Rp``, each of whose starts has
        its own zero in the ball): interval Newton on ``g`` along ``centre + M r``, whose slope
        over ``tau`` and the whole set has no zero; None if it does not contract inside ``tau``."""
        fl, st, j, fn = self.flight, self.step, self.fn.offset, self.fn

        def state(tau):
            centre, M, _ = fl._at(st, tau)
            return [centre[i] + M[i][0] * r[0] + M[i][1] * r[1] for i in range(2)]

        tau = self.tau
        slope = fn.coef * fl.field.stack(st.t + tau, *state(tau))[j + 1]
        if slope.contains(0):
            return None
        for _ in range(NEWTON_STEPS):
            m = tau.mid()
            g = fn.const + fn.coef * state(m)[j]
            step = m - g / slope
            if not step.overlaps(tau):
                return None
            tau = step.intersection(tau)
        return fl.base + st.sigma + tau, state(tau)

    def tracked_stop(self):
        """``(t*, x*)`` of the tracked start's stop (a ``"stick"``: ``v = 0`` there), or None
        (no tracked start, or its zero not located): the start of its rest."""
        if not (self.ok and self.kind == "stick") or self.step.Rp is None:
            return None
        got = self._located(self.step.Rp)
        return None if got is None else (got[0], got[1][0])


def gradient(M, j, DJ, pre, post):
    """``d z_b / dr`` before the factor ``D`` (module docstring): ``DJ (M + z'- dtau) - z'+ dtau``
    with ``dtau = -M[j] / z'-[j]`` (the event function is ``+-z[j]`` plus a constant),
    ``pre = z'- = (v-, a-)``, ``post = z'+ = (v+, a+)``."""
    dtau = [-M[j][k] / pre[j] for k in range(2)]
    return [[sum(DJ[i][n] * (M[n][k] + pre[n] * dtau[k]) for n in range(2)) - post[i] * dtau[k]
             for k in range(2)] for i in range(2)]


def _back(post, t, z, base):
    """The state at ``base`` of the flight (field ``post``) through ``z`` at the ball ``t``
    (``t >= base``): its Taylor series of order ``BACK_ORDER`` in ``-(t - base)`` plus the
    Lagrange remainder over a Picard box of ``[base, t]``."""
    d = t - base
    dmax = d.upper()
    if dmax.is_zero():
        return list(z)
    n = BACK_ORDER
    xs, _ = post.series(t, z[0], z[1], n + 2)
    B = picard_box(post, base + _interval(dmax), list(z), -_interval(dmax))
    if B is None:
        return None
    bx, _ = post.series(base + _interval(dmax), B[0], B[1], n + 2)
    h = -d
    x = sum((xs[k] * h ** k for k in range(n + 1)), arb(0)) + bx[n + 1] * h ** (n + 1)
    v = (sum(((k + 1) * xs[k + 1] * h ** k for k in range(n + 1)), arb(0))
         + (n + 2) * bx[n + 2] * h ** (n + 1))
    return [x, v]


def smaller(carried, box):
    """True if the parallelogram ``carried = (mid, A, R, ...)`` (``A`` a rotation up to rounding)
    has no more area than the axis box ``box``.  Its hull may be wider than the box where the
    set is a thin slanted strip, which is the point: the area is what the next flight's Lohner
    steps carry."""
    A, R = carried[1], carried[2]
    det = abs(A[0][0] * A[1][1] - A[0][1] * A[1][0])
    return not (det * R[0].rad() * R[1].rad()).lower() > (box[0].rad() * box[1].rad()).upper()
