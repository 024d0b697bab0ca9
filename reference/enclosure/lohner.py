"""Validated flights under position forcing: Taylor steps with a rigorous remainder, carried
across steps in a Lohner QR frame, with the flow derivative (the C^1-Lohner algorithm).

A flight ``x'' = F cos(k x) cos(w t) - s f - c x'`` (``reference.enclosure.series``) has no
closed form.  :class:`ValidatedFlight` encloses it, for every start of a box, by the
interval Taylor method of Lohner (R. J. Lohner, *Enclosing the solutions of ordinary
initial and boundary value problems*, 1987; N. S. Nedialkov, K. R. Jackson and G. F.
Corliss, *Validated solutions of initial value problems for ordinary differential
equations*, Appl. Math. Comput. 105, 1999, and their VNODE) with the derivative of the
flow of Zgliczynski's C^1-Lohner algorithm (P. Zgliczynski, *C^1 Lohner algorithm*, Found.
Comput. Math. 2, 2002; the CAPD library).  Taylor models (M. Berz and K. Makino, Reliable
Computing 4, 1998) would carry the start's dependence to higher order; here it is linear
(the boxes are ~1e-30 wide: the linear term is the whole story).

One step from a set ``{m + A r : r in R}`` at the exact time ``t_j`` (``m`` exact, ``A`` an
exact nearly orthogonal matrix, ``R`` balls) to ``t_j + h``:

1. *a priori enclosure* (Picard, :func:`contracts`): a box ``B`` with
   ``N = Y + [0, h] f([t_j, t_j + h], B)`` inside ``B`` (``Y`` the hull of the set), found by
   iterating and widening and verified by a certain comparison: then every solution from
   ``Y`` exists on ``[0, h]`` and stays in ``N`` (the Picard operator maps the continuous
   paths in ``B`` into those in ``N``; Lipschitz ``f``: one solution);
2. *Taylor series* of order ``p`` at the centre ``m`` (``series``), so that for every start
   ``m + A r``

       z(t_j + tau) in sum_n c_n(m) tau^n + rem tau^(p+1) + V(tau) A r,

   ``rem`` the Lagrange remainder (the coefficient of order ``p + 1`` evaluated over ``B`` and
   the times of the step) and the last term the mean value theorem on the flow, ``V(tau)`` the
   enclosure of its derivative over every start of ``Y`` (step 3);
3. *the flow derivative* of the step, ``V(tau)``, is the variational series of order
   ``q = p/2`` over ``Y`` (from the centre's ``sin(k x)`` series and its gradient over ``B``:
   ``series.Field.variational_near``) plus its Lagrange remainder ``G_{q+1}(B) W tau^(q+1)``:
   ``G_{q+1}`` the variational coefficient with identity start (``V^{(q+1)} = (q+1)! G_{q+1}(y) V``), ``W``
   the box ``|V - I|_inf <= exp(L h) - 1`` (Gronwall on ``B``, ``L = max(1, |A_x| + c)``).  Half
   the order carries ``Phi'`` to about half the working precision (~1e-48 at 320 bits: the
   Krawczyk proofs need less) at a quarter of the cost.  ``full_derivative`` takes ``q = p``
   and the derivative's remainder below ``2^-tol_bits`` too: ``Phi'`` to ~1e-47 at 192 bits,
   where half the order gives ~1e-25, so that a golden input's proof certifies the 40 digits
   of its Jacobian (``cross_check.golden``), for 1.37x the CPU (12 inputs of an unseen
   position-forced scene, one run);
4. *the step size*: from the decay of the centre's coefficients (times the ratio the last
   step needed), rounded down to a short dyadic number (so the step times stay exact), and
   shortened until the Picard box exists, the state's remainder is below ``2^-tol_bits``
   (default ``2^-prec``) of the state's scale and the derivative's below the square root of
   that; the order ``p`` is :func:`taylor_order`;
5. *the Lohner frame* against the wrapping effect: ``M = V(h) A``, the new
   ``A`` the QR frame of ``mid M`` (its dominant column, weighted by ``R``, first; exact
   entries), ``R <- (A^-1 M) R + A^-1 (c(h) + rem - m)``, ``m`` the new midpoint.  An axis
   box would rotate with the flow and wrap at every step; the frame turns with it.

The derivative of the flow from the flight's start, ``D``, is the product of the steps'
``V(h)`` (ball matrices).

A start time that is a ball (an event time) is moved to the exact ``base = t0.lower()``:
the start box becomes the set of states at ``base`` of the solutions through the box at
``t0`` (``z0 - [0, t0 - base] f``, over its own Picard box), and the flow derivative gets
the factor ``I +- (exp(L (t0 - base)) - 1)``.  A local time ``u`` of the walk is then
``sigma = u + (t0 - base)``, a ball.  A flight after an event of a validated flight gets its
start from the event instead (``carried``, ``reference.enclosure.handoff``): the states at
``base`` as a parallelogram in mean-value form over the last flight's set, which keeps the
dependence on the start that the box loses (~4x an event).  Its local times then count from
``base`` (``start``; ``lead = 0``): the next event's time is ``base + sigma``, no ``rad t0``
added; the flight factor of Table 1 still counts from ``t0`` (``delta``).

One start of the box -- its centre, for an orbit proof's Krawczyk test -- may be *tracked*
(``point``): its offsets ``Rp`` in each step's frame follow the set's own recurrence
``Rp <- (A^-1 M) Rp + A^-1 (c(h) + rem - m)``, so ``point_state`` encloses that start's motion
as narrowly as a walk from it alone, from the box's one walk (the doubleton sets of CAPD,
Zgliczynski 2002, for a single start).  It is handed through impacts and turns with the set
(``reference.enclosure.handoff``), and through its own stops and slips by the walk.

``stack(u)`` is the derivative stack ``[x, v, a, a', a'']`` of ``reference.enclosure.motion``
(``a``, ``a'``, ``a''`` from the equation of motion at the enclosed state), so that
``reference.enclosure.certify`` excludes and locates events on a validated flight as on a
closed-form one; ``derivative(u)`` the flight factor of Table 1 (``FlightFactors`` hands
it to ``reference.jacobian.product_of_table1``).  Both enclose the flight for every ``u`` of
the ball from the flight's start on (``u >= 0``: a ball ``[0, b]`` reaches below 0 by the
rounding of its radius only, and the certificates never need earlier times).  Steps are
taken lazily, at most ``max_steps`` of them.
"""
from __future__ import annotations

import math
from bisect import bisect_right

from flint import arb, arb_poly, ctx

from reference.enclosure.balls import workprec
from reference.enclosure.certify import Unproved
from reference.enclosure.picard import interval as _interval
from reference.enclosure.picard import near_identity as _near_identity
from reference.enclosure.picard import picard_box
from reference.enclosure.series import Field
from reference.jacobian import mat_mul

#: Bound on the steps of one flight (a step budget; exceeding it leaves the flight unproved):
#: a period of eq. xpot takes ~15 steps, ~20 ms each at 320 bits, so 2000 is ~100 periods.
MAX_STEPS = 2000
#: Bound on the halvings of one step (``picard.PICARD_TRIES`` bounds an a priori box's tries).
HALVINGS = 30
#: Significant bits of a step size (a short dyadic number keeps the step times exact).
STEP_BITS = 12
#: The longest step, in units of the flight's natural time scale (``_step_cap``).
CAP = 2
#: Bits of the remainders' arithmetic (``_remainder``: the a priori box and the series over it).
#: A remainder is a bound, needed to a few digits: the series over the box ``B`` is as wide as
#: ``B`` (the whole step's motion) at any precision, and ball arithmetic encloses at every
#: precision.  At 64 bits an arb product costs 0.67 of one at 192 (Python's overhead stays): a
#: 192-bit proof's CPU falls by a ninth (issue 33, 6 golden inputs of scene D, one run each: 5.96 ->
#: 5.29 s, every radius the same to two digits).
REMAINDER_PREC = 64
#: The first step's fraction of the centre's guess (the a priori box widens the remainder's
#: coefficient; measured ~0.85 of the guess passes on eq. xpot); later steps learn it.
SHRINK = 0.8


def taylor_order(prec: int) -> int:
    """The order ``p`` of the Taylor steps at ``prec`` bits, ``p = prec ln 2 / 2``.

    A step costs ``~p^2`` ball operations and, for a series of radius ``rho``, reaches
    ``h = rho q`` with ``q^p = 2^-prec``: the cost per unit time ``p^2 / h`` is least at
    ``ln(1/q) = 2``, i.e. ``p = prec ln 2 / 2`` (111 at 320 bits, ``h ~ rho / 7``)."""
    return max(12, round(prec * math.log(2) / 2))


def _mat_vec(M, z):
    return [M[0][0] * z[0] + M[0][1] * z[1], M[1][0] * z[0] + M[1][1] * z[1]]


class _Step:
    """One Taylor step: ``sigma`` (exact start, from ``base``), ``h`` (exact), the centre
    polynomials, the variational polynomials over the hull, the remainders, the frame at
    its start ``(A, R)`` and the flow derivative ``D`` at its start."""

    __slots__ = ("sigma", "end", "h", "t", "cx", "cv", "J", "rem", "E", "A", "R", "D", "Rp")

    def __init__(self, **kw):
        for k, val in kw.items():
            setattr(self, k, val)


class ValidatedFlight:
    """The flight with sign ``s`` from the balls ``(t0, x0, v0)`` (module docstring)."""

    def __init__(self, model, t0, x0, v0, s: int, *, order=None, tol_bits=None,
                 max_steps=MAX_STEPS, full_derivative=False, carried=None, point=None):
        if not model.position_forcing:
            raise ValueError("ValidatedFlight: needs a scene with position forcing (wavenumber)")
        if s not in (1, -1, 0) or (s == 0 and model.friction):
            raise ValueError(f"s must be +1 or -1 (0 only without friction), got {s!r}")
        for name, value, low in (("order", order, 2), ("tol_bits", tol_bits, 8),
                                 ("max_steps", max_steps, 1)):
            if value is not None and (isinstance(value, bool) or not isinstance(value, int)
                                      or value < low):
                raise ValueError(f"{name} must be an int >= {low} (or None), got {value!r}")
        self.m, self.t0, self.x0, self.v0, self.s = model, t0, x0, v0, s
        self.field = Field(model, s)
        self.p = taylor_order(ctx.prec) if order is None else order
        #: the order of the flow derivative's series: half the state's (``Phi'`` to about half
        #: the precision), or all of it with ``full_derivative``
        self.q = self.p if full_derivative else max(2, (self.p + 1) // 2)
        self.full_derivative = bool(full_derivative)
        #: each step's remainder is below ``2^-tol_bits`` of the state's scale
        self.tol_bits = ctx.prec if tol_bits is None else tol_bits
        self.max_steps = max_steps
        self.base = t0.lower()
        self.delta = t0 - self.base
        x, v, self.shift = self._shift(x0, v0)
        one, zero = arb(1), arb(0)
        start = None if carried is None else carried.start(self.field, self.base, self.shift,
                                                             (x, v))
        handed = start is not None
        if start is None:
            mid = [x.mid(), v.mid()]
            tracked = None if point is None else self._point_shift(point)
            start = (mid, [[one, zero], [zero, one]], [x - mid[0], v - mid[1]],
                     None if tracked is None else [tracked[i] - mid[i] for i in range(2)])
        #: the time the walk's local times count from: the exact ``base`` for a set handed
        #: through an event (``reference.enclosure.handoff``), else the start ball ``t0``
        self.start, self.lead = (self.base, arb(0)) if handed else (t0, self.delta)
        self._state = (arb(0),) + start[:3] + ([[one, zero], [zero, one]], start[3])
        self.steps, self._starts = [], []
        self._cap = self._step_cap()
        self._shrink = SHRINK

    # -- the start -----------------------------------------------------------------------
    def _shift(self, x0, v0):
        """The start box moved from the ball ``t0`` to the exact ``base`` (module docstring):
        ``(x, v, factor)``."""
        one, zero = arb(1), arb(0)
        if self.delta.is_zero():
            return x0, v0, [[one, zero], [zero, one]]
        d = self.delta.upper()
        span = self.base + _interval(d)
        N = picard_box(self.field, span, [x0, v0], -_interval(d))
        if N is None:
            raise Unproved(f"flight from t = {self.t0.mid().str(15)}: no a priori enclosure "
                           f"over the start time's ball")
        self._span_box = (span, N)
        e = ((self.field.lipschitz(span, N[0]) * d).exp() - 1).upper()
        return N[0], N[1], _near_identity(e)

    def _point_shift(self, point):
        """The state at ``base`` of the solution through ``point = (t, x, v)`` (one start of the
        box at its own time ``t``, a ball: its true time lies in ``t0`` too), by Taylor's
        theorem on each coordinate with ``d = t - base``:

            z(base) in z - d z'(t, z) + d^2 / 2 z''(N),

        ``z' = (v, a)`` at the point, ``z'' = (a, a')`` over ``N``, the enclosure of every
        solution from the box over ``[base, t0]`` (``_shift``'s Picard box).  (The first-order
        form ``z - d z'(N)`` is ``|d| rad z'(N)`` wide: the square of the box's width after a
        stop, whose slip times spread over the box; this one leaves its cube.)  ``(x, v)``
        itself at an exact ``t0``; None if ``t`` misses ``t0``."""
        t, x, v = point
        if self.delta.is_zero():
            return [x, v]
        span, N = self._span_box
        if not t.overlaps(span):
            return None
        d = (t - self.base).intersection(_interval(self.delta.upper()))
        slope = self.field.stack(t, x, v)[1:3]
        curve = self.field.stack(span, N[0], N[1])[2:4]
        return [z - d * s + d * d / 2 * c for z, s, c in zip((x, v), slope, curve)]

    def _step_cap(self):
        """The natural time scale of the flight: ``1 / (w + k (|v0| + 1) + sqrt(F (k+1) + f)
        + c + 1)`` (no Taylor step of this equation reaches much further)."""
        fl, m = self.field, self.m
        scale = (fl.w + fl.k * (abs(self.v0) + 1) + (m.F * (fl.k + 1) + m.f).sqrt() + fl.c + 1)
        return self._dyadic(CAP / scale.upper())

    @staticmethod
    def _dyadic(h):
        """``h`` rounded down to ``STEP_BITS`` significant bits (an exact ball)."""
        value = float(h.lower()) if isinstance(h, arb) else float(h)
        if not value > 0:
            raise Unproved("validated flight: the step size underflows")
        e = math.floor(math.log2(value)) - STEP_BITS
        return arb((int(value / 2.0 ** e), e))

    # -- stepping ------------------------------------------------------------------------
    def _tol(self, mid):
        return (1 + abs(mid[0]) + abs(mid[1])) * arb(2) ** (-self.tol_bits)

    def _guess(self, xs, tol):
        """The step that makes the last terms of the centre's series ``~tol``."""
        p, best = self.p, self._cap
        for n, c in ((p, xs[p]), (p + 1, xs[p + 1]), (p, (p + 1) * xs[p + 1])):
            mag = abs(c.mid())
            if mag > 0:
                h = float(((tol / mag).log() / n).exp().mid())
                if h < float(best):
                    best = self._dyadic(h)
        return best

    def _advance(self):
        if len(self.steps) >= self.max_steps:
            raise Unproved(f"flight from t = {self.t0.mid().str(15)}: more than "
                           f"{self.max_steps} Taylor steps (the step budget)")
        sigma, mid, A, R, D, Rp = self._state
        p, fl = self.p, self.field
        t = self.base + sigma
        Y = [(mid[i] + A[i][0] * R[0] + A[i][1] * R[1]).union(mid[i]) for i in range(2)]
        xs, _, S, P = fl.trig_series(t, mid[0], mid[1], p + 1)
        tol = self._tol(mid)
        guess = self._guess(xs, tol)
        h = self._dyadic(guess * self._shrink)
        for tries in range(HALVINGS):
            got = self._remainder(t, Y, h, tol)
            if not isinstance(got, arb):
                break
            h = self._dyadic(h * got)
        else:
            raise Unproved(f"flight from t = {self.t0.mid().str(15)}: no Taylor step at "
                           f"t = {t.mid().str(15)} (no a priori enclosure with a small "
                           f"remainder: the box is too wide)")
        h, rem, shortened = got
        cols = fl.variational_near(S, P, rem[2], [Y[i] - mid[i] for i in range(2)], self.q)
        J = [[arb_poly(cols[0]), arb_poly(cols[2])], [arb_poly(cols[1]), arb_poly(cols[3])]]
        step = _Step(sigma=sigma, end=sigma + h, h=h, t=t, cx=arb_poly(xs[:p + 1]),
                     cv=arb_poly([(n + 1) * xs[n + 1] for n in range(p + 1)]), J=J,
                     rem=rem[0], E=rem[1], A=A, R=R, D=D, Rp=Rp)
        if not step.end.is_exact():
            raise Unproved("validated flight: a step time is not exact at this precision")
        self.steps.append(step)
        self._starts.append(float(sigma))
        # the next guess starts where this one ended (a try without a Picard box costs a series)
        self._shrink = min(1.0, float(h / guess) * (0.97 if tries or shortened else 1.03))
        self._state = self._next(step)

    def _remainder(self, t, Y, h, tol):
        """``(h', ((rx, rv), E, dS), shortened)``: the Lagrange remainders' coefficients over the
        a priori box ``B`` of the step ``[t, t + h]`` from ``Y``, and the gradient of
        ``sin(k x)``'s coefficients over ``B`` (``series.Field.sin_gradient``, orders below ``q``:
        the step's columns over ``Y``), with ``h' <= h`` the step they allow: ``|rem| h'^(p+1) <=
        tol`` and ``|E| h'^(q+1) <= sqrt(tol)`` (``tol`` with ``full_derivative``).  Where ``h``
        is too long for those bounds it is shortened by ``(tol / 2|rem|)^(1/(p+1))`` (at most
        0.9; ``shortened``) on the same coefficients: ``B`` is an a priori box of the shorter
        step too (``Y + [0, h'] f(B)`` lies in ``Y + [0, h] f(B)``), the coefficients over its
        times enclose those over the shorter step's, and ``E``'s Gronwall factor
        ``exp(L h) - 1`` bounds ``exp(L h') - 1``.  (A shortened step took another series over
        ``B`` before, on ~1 step in 5: the six golden proofs of
        ``series.Field.variational_near``, three runs each, 4.2, 4.7, 4.8 -> 4.2, 4.0, 4.7 CPU s; 2472 -> 2051 remainder series for
        2051 steps in the golden task of that scene; the step sizes the same, the remainders'
        balls those of the longer step's box, still below the bounds: a proof's radius 3.85e-55
        -> 3.90e-55.)  Without a box: the factor 1/2 (a ball) to retry with."""
        p, q, fl = self.p, self.q, self.field
        hball = _interval(h)
        with workprec(min(ctx.prec, REMAINDER_PREC)):
            span = t + hball
            B = picard_box(fl, span, Y, hball)
            if B is None:
                return arb(0.5)
            bx, C, S, P = fl.trig_series(span, B[0], B[1], p + 2)
            cols = fl.variational(S, P, q + 1)
            rx, rv = bx[p + 1], (p + 2) * bx[p + 2]
            e = ((fl.lipschitz(span, B[0]) * h).exp() - 1).upper()
            E = mat_mul([[cols[0][q + 1], cols[2][q + 1]], [cols[1][q + 1], cols[3][q + 1]]],
                        _near_identity(e))
        coefficients = [(abs(rx).upper(), tol, p), (abs(rv).upper(), tol, p),
                        (max(abs(b).upper() for row in E for b in row),
                         tol if self.full_derivative else tol.sqrt(), q)]
        for shortened in range(HALVINGS):
            factors = [((bound / (2 * c * h ** (n + 1))).log() / (n + 1)).exp().mid()
                       for c, bound, n in coefficients if not c * h ** (n + 1) <= bound]
            if not factors:
                break
            h = self._dyadic(h * min([arb(0.9)] + factors))
        else:
            return arb(0.5)
        with workprec(min(ctx.prec, REMAINDER_PREC)):
            return h, ((rx, rv), E, fl.sin_gradient(C, cols, q)), shortened > 0

    def _next(self, step):
        """The set, frame, flow derivative and tracked point at the end of ``step`` (the Lohner
        QR step)."""
        centre, M, V = self._at(step, step.h)
        mid, A, R, Rp = reframe(centre, M, step.R, step.Rp)
        return step.end, mid, A, R, mat_mul(V, step.D), Rp

    @staticmethod
    def _frame(M, R):
        """The QR frame of ``mid M``: its column of largest ``|M e_i| rad(R_i)`` first (exact
        entries, orthogonal up to rounding; the inverse is taken in balls)."""
        cols = [[M[0][j].mid(), M[1][j].mid()] for j in range(2)]
        weight = [(c[0] * c[0] + c[1] * c[1]).sqrt() * (R[j].rad() + abs(R[j].mid()))
                  for j, c in enumerate(cols)]
        q = cols[1] if weight[1] > weight[0] else cols[0]
        norm = (q[0] * q[0] + q[1] * q[1]).sqrt()
        if not norm > 0:
            return [[arb(1), arb(0)], [arb(0), arb(1)]]
        c, s = (q[0] / norm).mid(), (q[1] / norm).mid()
        return [[c, -s], [s, c]]

    def _at(self, step, tau):
        """``(centre, M, V)`` at ``tau`` in ``step``: the centre's polynomial plus remainder
        (balls), the step's flow derivative ``V`` at ``tau`` over every start of ``Y`` (the
        variational series of order ``q`` plus its Lagrange remainder) and ``M = V A``: by the
        mean value theorem on the flow itself, ``z(tau; m + A r)`` lies in ``centre + M r``.
        (The variational series alone, without its remainder, would leave out the orders
        ``q + 1 ... p`` of the polynomial's derivative.)"""
        tp, tq = tau ** (self.p + 1), tau ** (self.q + 1)
        centre = [step.cx(tau) + step.rem[0] * tp, step.cv(tau) + step.rem[1] * tp]
        V = [[step.J[i][j](tau) + step.E[i][j] * tq for j in range(2)] for i in range(2)]
        return centre, mat_mul(V, step.A), V

    # -- queries -------------------------------------------------------------------------
    def _pieces(self, u, lead=None):
        """``(step, tau)`` for the parts of the local time ``u`` (``sigma = u + lead``; the
        walk's ``lead`` by default, ``delta`` for the flight factor from ``t0``)."""
        sigma = u + (self.lead if lead is None else lead)
        lo, hi = sigma.lower(), sigma.upper()
        if lo < 0:          # a ball [0, b] reaches below 0 by the rounding of its radius only
            if lo < -(hi - lo) * arb(2) ** -16:
                raise Unproved("validated flight: a time before the flight's start was asked for")
            lo = arb(0)
        while not self.steps or not self.steps[-1].end > hi:
            self._advance()
        i = max(0, bisect_right(self._starts, float(lo)) - 1)
        while i > 0 and self.steps[i].sigma > lo:
            i -= 1
        while not self.steps[i].end > lo:
            i += 1
        out = []
        while i < len(self.steps) and self.steps[i].sigma <= hi:
            st = self.steps[i]
            a = (lo - st.sigma) if lo > st.sigma else arb(0)
            b = (hi - st.sigma) if hi < st.end else st.h
            out.append((st, a if sigma.is_exact() else a.union(b)))
            i += 1
        return out

    def state(self, u):
        """``(x, v)`` at the local time ``u`` (a ball), for every start of the box."""
        return tuple(self.stack(u)[:2])

    def stack(self, u):
        """``[x, v, a, a', a'']`` at the local time ``u`` (the motion interface)."""
        out = None
        for st, tau in self._pieces(u):
            centre, M, _ = self._at(st, tau)
            z = _mat_vec(M, st.R)
            s = self.field.stack(st.t + tau, centre[0] + z[0], centre[1] + z[1])
            out = s if out is None else [a.union(b) for a, b in zip(out, s)]
        return out

    def point_state(self, t):
        """``(x, v)`` at the absolute time ``t`` of the one start the flight tracks (``point``,
        or handed through its events: ``reference.enclosure.handoff``), ``None`` if it tracks
        none.  (Its time from ``base`` is ``t - base``, not the set's ``u + lead``: a start
        ball ``t0`` enters the set's local times twice, which widens them by ``rad t0``.)
        Its offsets ``Rp`` in each step's frame follow the set's own recurrence, ``Rp <- (A^-1 M)
        Rp + A^-1 (c(h) + rem - m)``: ``z(tau; m + A r) in centre + M r`` holds for every ``r``
        of ``R``, the point's among them, so the balls hold the point's motion, as narrow as a
        walk from the point alone (the centre ``m`` follows the box's centre, the point's
        offsets stay at the steps' errors: the doubleton sets of CAPD, Zgliczynski 2002)."""
        out = None
        for st, tau in self._pieces(t - self.base, arb(0)):
            if st.Rp is None:
                return None
            centre, M, _ = self._at(st, tau)
            z = [centre[i] + M[i][0] * st.Rp[0] + M[i][1] * st.Rp[1] for i in range(2)]
            out = z if out is None else [a.union(b) for a, b in zip(out, z)]
        return out

    def derivative(self, u):
        """The flight factor ``d(x, v)(t0 + u) / d(x0, v0)`` at a fixed start time (Table 1)."""
        out = None
        for st, tau in self._pieces(u, self.delta):
            _, _, V = self._at(st, tau)
            Dm = mat_mul(mat_mul(V, st.D), self.shift)
            out = Dm if out is None else [[a.union(b) for a, b in zip(r, q)] for r, q in zip(out, Dm)]
        return out


def reframe(centre, M, R, Rp=None):
    """``{centre + M r : r in R}`` (balls ``centre``, ball matrix ``M``) as a Lohner set
    ``(mid, A, R', Rp')``: ``mid`` the exact midpoint, ``A`` the QR frame of ``mid M``
    (``ValidatedFlight._frame``), ``R' = (A^-1 M) R + A^-1 (centre - mid)``; a step's end
    (``ValidatedFlight._next``) and a set handed through an event (``handoff``).  ``Rp``: the
    offsets of one tracked start (a part of ``R``), carried by the same map (``Rp' = None``
    without)."""
    mid = [centre[0].mid(), centre[1].mid()]
    A = ValidatedFlight._frame(M, R)
    det = A[0][0] * A[1][1] - A[0][1] * A[1][0]
    Ainv = [[A[1][1] / det, -A[0][1] / det], [-A[1][0] / det, A[0][0] / det]]
    AM, shift = mat_mul(Ainv, M), _mat_vec(Ainv, [centre[i] - mid[i] for i in range(2)])
    R2 = [a + b for a, b in zip(_mat_vec(AM, R), shift)]
    Rp2 = None if Rp is None else [a + b for a, b in zip(_mat_vec(AM, Rp), shift)]
    return mid, A, R2, Rp2


class FlightFactors:
    """A ``BallModel`` whose Table 1 flight factor is the flow derivative of the walk's
    validated flights (``reference.jacobian`` asks ``flow_derivative(start, t)``); every other
    attribute is the model's."""

    def __init__(self, model, flights):
        self.model, self.flights = model, flights

    def __getattr__(self, name):
        return getattr(self.model, name)

    def flow_derivative(self, start, t):
        """``d(x, v)(t) / d(x, v)(t0)`` of the flight that began at ``start = (t0, x0, v0)``.

        A flight of length zero (a start at rest) is the identity.  A flight the walk did not
        take -- the bounces of a chatter run closed by its tail bound -- is followed by wall
        contact, whose zero matrix replaces the product (``product_of_table1``): its factor is
        the whole plane (balls of infinite radius), never a claim."""
        one, zero = arb(1), arb(0)
        if t is start[0] or (t - start[0]).is_zero():
            return [[one, zero], [zero, one]]
        flight = self.flights.get(id(start[0]))
        if flight is None or flight.t0 is not start[0]:
            anything = arb(0, math.inf)
            return [[anything, anything], [anything, anything]]
        return flight.derivative(t - start[0])
