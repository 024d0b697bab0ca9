"""The itinerary of the point integrator, re-proved event by event in ball arithmetic.

The point integrator (``reference.integrator``) says *which* events happen and roughly when;
the walk proves it for every start state of a box, with the semantics of
``reference.integrator`` (the same modes, kinds and transitions):

1. each event time is enclosed, and its existence and uniqueness proved, by a Krawczyk step
   on its event function (``certify.root``);
2. no other event happens before it: every event function of the motion is positive from
   the start of the motion to the event (``certify.exclude``), and none reaches zero after
   the last event before ``t_end``;
3. the kind of each event is proved by certain comparisons: an impact has ``side v- > 0``
   (not grazing); a zero of the velocity is a turn if ``s A < -f`` and a stop if
   ``-f < s A``; each with the point integrator's kind, or the walk stops; at restitution 0
   an impact leaves the particle at rest at the wall, in contact where the point integrator
   holds it there (the hold proved up to the release), else off at once (the flight's start
   proves that the force pulls it away beyond friction);
4. a chatter run is followed bounce by bounce as long as the point integrator did, then its
   tail is bounded (:func:`chatter_tail`) and wall contact follows;
5. after the last event the state at ``t_end`` is the motion's closed form at ``t_end``;
6. under position forcing a flight after an impact or a turn starts from the last flight's set
   handed through the event (``reference.enclosure.handoff``) at the exact ``base`` below the
   event's time ball; the next event must then lie beyond that ball (``floor`` in :meth:`fly`),
   where the last event's own zero lies;
7. one start of a box (its centre: ``enclose_map``'s ``phi_at_centre``) may be tracked through
   the flights and their hand-offs, and through its own stops (located on its own offsets) and
   slips (its own rest's zero): its state at ``t_end`` comes from the box's walk, as narrow as a
   walk from it alone; any other event (contact, chatter, a hand-off that does not apply) loses it.

Any certificate that fails raises :class:`~reference.enclosure.certify.Unproved` with the
reason: a grazing impact, a tangency, a stick-slip boundary, an event at ``t = kT``.
"""
from __future__ import annotations

from flint import arb

from reference.enclosure import certify, handoff, lohner, motion
from reference.enclosure.balls import from_mpf, span
from reference.enclosure.certify import Unproved
from reference.enclosure.tails import chatter_tail
from reference.integrator import Event, EventLog

#: A chatter run is closed as soon as its accumulation time is bounded to this fraction of T
#: (else the walk follows more bounces, falling back to the last bounded tail if one fails).
CHATTER_CLOSE = arb(2) ** -40


class Walk:
    """One walk: the point log ``points`` re-proved from balls ``(t0, x0, v0)`` to ``t_end``."""

    def __init__(self, model, points, t_end, point_walls, full_derivative=False, track=None):
        self.m, self.points, self.t_end = model, list(points), t_end
        self.full_derivative = full_derivative   # flights' Phi' to the working precision (lohner)
        self.point_t0 = points.t0
        self.point_walls = point_walls          # (l, r) as the point integrator holds them
        self.i = 0
        self.log = EventLog()
        self.mode, self.s, self.side, self.orders = "flight", 0, 0, {}
        self.pieces = 0
        self.fallback = None          # the last impact of a chatter run with a bounded tail
        self.flights = {}             # validated flights by id of their start time (Table 1)
        self.ahead = None             # (side, index) of the chatter event ending the current run
        self.handoff = None           # the last event's set for the next flight (handoff)
        #: one start ``(x, v)`` of the box (exact balls) whose own state at ``t_end`` the
        #: validated flights track (``lohner.ValidatedFlight.point_state``) through the hand-offs
        #: of their events and through its own stops and slips (``_track_rest``): ``track`` is
        #: ``(t, x, v)`` for the flight that starts from the set ``track_for`` (the objects
        #: ``(t, x, v)`` of the walk), ``rest_track`` ``(t, x)`` of its stop; ``point_end`` its
        #: state at ``t_end``, or None where a start, an event or a rest lost it
        self.start_track, self.track, self.track_for, self.rest_track = track, None, (), None
        self.point_end = None

    # -- point events -------------------------------------------------------------------
    def peek(self):
        return self.points[self.i] if self.i < len(self.points) else None

    def take(self, kind):
        ev = self.peek()
        if ev is None or ev.kind != kind:
            raise Unproved(f"the itinerary disagrees with the point integrator: expected "
                           f"{kind}, point integrator has {ev.kind if ev else 'nothing'}")
        self.i += 1
        return ev

    def emit(self, kind, v_before, count=None):
        self.log.append(Event(kind, self.t, self.x, self.v, v_before, count))

    def _wall_side(self, x_point):
        """The wall a point event sits on (+1 r, -1 l; the point integrator puts the particle
        exactly there), else 0."""
        l, r = self.point_walls
        return 1 if x_point == r else (-1 if x_point == l else 0)

    # -- start ----------------------------------------------------------------------------
    def start(self, t0, x0, v0):
        m = self.m
        self.t, self.x, self.v = t0, x0, v0
        self.log.t0, self.log.x0, self.log.v0 = t0, x0, v0
        if self.start_track is not None:
            self.track, self.track_for = (t0,) + tuple(self.start_track), (t0, x0, v0)
        if not (x0 >= m.l and x0 <= m.r):
            raise Unproved("the start box is not inside the closed gap [l, r]")
        at = [side for side in (1, -1) if x0.is_exact() and x0 == m.wall(side)]
        if v0.is_zero():
            return self._start_at_rest(at[0] if at else 0)
        if v0.contains(0):
            if not (m.friction or at):      # v = 0 is no event without friction: one flight
                return self.to_flight(0, {})
            raise Unproved("the start's velocity encloses 0 (a start at rest or a grazing start)")
        sign = 1 if v0 > 0 else -1
        if at and at[0] == sign:
            self.take("impact")
            return self.impact(sign)
        self.to_flight(sign, {motion.wall_name(at[0]): 1} if at else {})

    def _start_at_rest(self, side):
        if side:
            return self._at_rest_at_wall(side, self.point_t0)
        m, ev = self.m, self.peek()
        held = ev is not None and ev.kind in ("stick", "contact") and ev.t == self.point_t0
        if held:
            self._refuse_mixed_stick("a start that sticks")
            self.take("stick")
            self.emit("stick", arb(0))
            self.mode = "stick"
            return
        if not m.friction:
            return self.to_flight(0, {})
        A = m.force(self.x, self.t)
        sign = 1 if A > m.f else (-1 if A < -m.f else 0)
        if not sign:
            raise Unproved("a start at rest where the force is at the friction level")
        self.to_flight(sign, {"velocity": 1})

    def _at_rest_at_wall(self, side, t_point):
        """At rest at the wall ``side`` at the point time ``t_point`` (a start there, or an impact
        at restitution 0), as ``reference.integrator.rest_at_wall``: wall contact where the point
        integrator has one at ``t_point`` -- ``rest`` then proves the hold, ``f + side A > 0``,
        up to the release -- else a flight away from the wall, whose exclusions prove it leaves
        at once: the first derivative that does not vanish at the start must be positive, ``s a
        = -side A - f > 0`` with friction (``velocity``, a simple zero), ``-side A > 0`` without
        (the wall's distance, a double zero).  A log with the other choice fails one of them."""
        ev = self.peek()
        if ev is not None and ev.kind == "contact" and ev.t == t_point:
            self.take("contact")
            self.v = arb(0)
            self.emit("contact", arb(0))
            self.mode, self.side = "contact", side
            return False
        self.to_flight(-side, {"velocity": 1} if self.m.friction else {motion.wall_name(side): 2})
        return False

    def to_flight(self, s, orders):
        self.mode, self.s, self.orders = "flight", (s if self.m.friction else 0), orders

    # -- flights --------------------------------------------------------------------------
    def functions(self):
        m, s, orders = self.m, self.s, self.orders
        if m.friction:
            fns = [motion.distance(m, s), motion.velocity(s)]
        else:
            fns = [motion.distance(m, 1), motion.distance(m, -1)]
        return [motion.EventFunction(fn.name, fn.offset, fn.coef, fn.const, orders.get(fn.name, 0))
                for fn in fns]

    def new_flight(self):
        """The flight from the current state: the closed form, or under position forcing a
        validated Taylor flight (kept for its flow derivative, ``lohner.FlightFactors``)."""
        m = self.m
        if not m.position_forcing:
            return motion.Flight(m, self.t, self.x, self.v, self.s)
        carried = self.handoff if self.handoff is not None and self.handoff.T is self.t else None
        here = len(self.track_for) == 3 and all(a is b for a, b in zip((self.t, self.x, self.v),
                                                                        self.track_for))
        point, self.track = (self.track if here else None), None
        flight = lohner.ValidatedFlight(m, self.t, self.x, self.v, self.s,
                                        full_derivative=self.full_derivative, carried=carried,
                                        point=point)
        self.flights[id(self.t)] = flight
        return flight

    def fly(self):
        m = self.m
        flight = self.new_flight()
        start = getattr(flight, "start", self.t)     # a handed-off set starts at its base
        fns = self.functions()
        h_end = self.t_end - start
        ev = self.peek()
        what = f"flight from t = {self.t.mid().str(15)}"
        if ev is None:
            for fn in fns:
                self.pieces += certify.exclude(flight, fn, arb(0), h_end.upper(), what)
            stack = flight.stack(h_end)
            self.t, self.x, self.v = self.t_end, stack[0], stack[1]
            if m.position_forcing:
                self.point_end = flight.point_state(self.t_end)
            return True
        side = self._wall_side(ev.x)
        ahead = [fn for fn in fns if side and fn.name == motion.wall_name(side)]
        if ev.kind == "impact" and ahead:
            fired = ahead[0]
        elif ev.kind in ("turn", "stick") and not side and m.friction:
            fired = fns[1]
        else:
            raise Unproved(f"a {ev.kind} at t = {mpstr(ev.t)} at x = {mpstr(ev.x)} reached from "
                           f"flight (a grazing touch, a turning point at a wall, or an impact at "
                           f"the wall the flight moves away from)")
        guess = (from_mpf(ev.t) - start.mid()).mid()
        # a handed set starts at its base, before the last event's time ball: the next event
        # must lie after the whole ball (inside it is the last event's own zero)
        floor = (self.t - start).upper() if start is not self.t else arb(0)
        if not guess > floor:       # e.g. a turn logged at the instant a plastic impact leaves
            raise Unproved(f"{what}: the point integrator's {ev.kind} at t = {mpstr(ev.t)} is not after "
                           f"the flight's start")
        wide, tight = certify.root(flight, fired, guess, floor, what)
        if not tight < h_end:
            raise Unproved(f"{what}: the {ev.kind} at t = {mpstr(ev.t)} may be at t_end "
                           f"(an event at t = kT)")
        for fn in fns:
            hi = wide.lower() if fn is fired else tight.upper()
            self.pieces += certify.exclude(flight, fn, arb(0), hi, what)
        stack = flight.stack(tight)
        self.t, self.x, self.v = start + tight, stack[0], stack[1]
        self.i += 1
        if m.position_forcing:
            self.handoff = handoff.Handoff(flight, fired, tight, ev.kind, side, self.t)
        if ev.kind == "impact":
            return self.impact_from_flight(side)
        return self.velocity_zero(ev.kind)

    def impact_from_flight(self, side):
        if not side * self.v > 0:
            raise Unproved(f"grazing impact at t = {self.t.mid().str(15)}: the velocity before "
                           f"it encloses 0")
        return self.impact(side)

    def impact(self, side):
        m = self.m
        v_before = self.v
        self.x, self.v = m.wall(side), -m.e * v_before
        self.emit("impact", v_before)
        if m.e.is_zero():                   # plastic: at rest at the wall, held or off at once
            self.v = arb(0)
            return self._at_rest_at_wall(side, self.points[self.i - 1].t)
        if not side * self.v < 0:
            raise Unproved(f"impact at t = {self.t.mid().str(15)} leaves no speed (contact)")
        ahead = self._chatter_ahead(side)
        if ahead is not None:
            try:
                tail = chatter_tail(m, self.t, side, -side * self.v)
            except Unproved:
                if ahead == self.i:         # the point integrator stops here: so must we
                    raise
            else:
                if tail[1] - tail[0] < CHATTER_CLOSE * m.T or ahead == self.i:
                    return self.close_chatter(side, ahead, tail)
                self.fallback = (self.t, self.v, len(self.log), side, ahead, tail)
        self.to_flight(-side, {} if m.friction else {motion.wall_name(side): 1})
        return False

    def velocity_zero(self, kind):
        m, s = self.m, self.s
        self.v = arb(0)
        sA = s * m.force(self.x, self.t)
        if kind == "turn" and sA < -m.f:
            self.emit("turn", arb(0))
            self.to_flight(-s, {"velocity": 1})
            return False
        if kind == "stick" and sA > -m.f:
            self._refuse_mixed_stick(f"a stop at t = {self.t.mid().str(15)}")
            self.emit("stick", arb(0))
            self.mode = "stick"
            if m.position_forcing and self.handoff is not None:
                self.rest_track = self.handoff.tracked_stop()
            return False
        raise Unproved(f"a zero of the velocity at t = {self.t.mid().str(15)} where the force "
                       f"may be at the friction level (a stick-slip boundary)")

    def _refuse_mixed_stick(self, what):
        """A parameter box with ``f`` in ``[0, hi]`` has no sticking at ``f = 0``: refused."""
        if self.m.friction_mixed:
            raise Unproved(f"{what} in a parameter box with f in [0, hi]: the frictionless "
                           f"scene (f = 0) of the box cannot stick (split the box at f > 0)")

    def _chatter_ahead(self, side):
        """The index of the point integrator's chatter event if the run at ``side`` ends in
        one (only turns and impacts at this wall before it), else None.  Scanned once per run:
        the answer holds for every later bounce of the run (cached until passed)."""
        if self.ahead is not None and self.i <= self.ahead[1] and self.ahead[0] == side:
            return self.ahead[1]
        for j in range(self.i, len(self.points)):
            ev = self.points[j]
            if ev.kind == "chatter":
                self.ahead = (side, j)
                return j
            if not (ev.kind == "turn" or (ev.kind == "impact" and self._wall_side(ev.x) == side)):
                return None
        return None

    def close_chatter(self, side, index, tail):
        """Close the run at ``side`` now with the tail bounds ``tail`` (:func:`chatter_tail`),
        skip the point integrator's remaining bounces (the bound covers them) and its chatter
        event, and rest at the wall from the accumulation time on."""
        m = self.m
        self.fallback = None
        t_inf = span((self.t + tail[0]).lower(), (self.t + tail[1]).upper())
        if not t_inf < self.t_end:
            raise Unproved("the chatter accumulates at t_end (an event at t = kT)")
        simulated = 0
        for ev in reversed(self.log):
            if ev.kind not in ("impact", "turn"):
                break
            simulated += ev.kind == "impact"
        self.i = index + 1
        self.t, self.x, self.v = t_inf, m.wall(side), arb(0)
        self.emit("chatter", arb(0), simulated)
        self.mode, self.side = "contact", side
        return False

    # -- rests ----------------------------------------------------------------------------
    def rest(self):
        m = self.m
        rest = motion.Rest(m, self.x)
        stuck_for_good = m.F <= m.f or abs(m.amplitude(self.x)) <= m.f
        if self.mode == "stick":
            fns = [] if stuck_for_good else [motion.slip(m, 1), motion.slip(m, -1)]
            kind = "slip"
        else:
            fns = [] if stuck_for_good else [motion.release(m, self.side)]
            kind = "release"
        lo = self.t.lower()
        what = f"{self.mode} from t = {self.t.mid().str(15)}"
        ev = self.peek()
        tracked, self.rest_track = self.rest_track, None
        if ev is None:
            for fn in fns:
                self.pieces += certify.exclude(rest, fn, lo, self.t_end.upper(), what)
            self.t, self.v = self.t_end, arb(0)
            self.point_end = None if tracked is None else (tracked[1], arb(0))
            return True
        self.take(kind)
        if not fns:
            raise Unproved(f"{what}: |F cos(k x)| <= f at the rest (F <= f without position "
                           f"forcing), so the rest never ends; the point integrator has a "
                           f"{kind} at t = {mpstr(ev.t)}")
        guess = from_mpf(ev.t)
        if not guess > self.t.upper():
            raise Unproved(f"{what}: it ends as it begins (the force at the friction level: "
                           f"a stick-slip boundary)")
        if self.mode == "stick":
            sigma = 1 if m.force(self.x, guess) > 0 else -1
            fired = fns[0] if sigma > 0 else fns[1]
        else:
            sigma, fired = -self.side, fns[0]
        wide, tight = certify.root(rest, fired, guess, self.t.upper(), what)
        if not tight < self.t_end:
            raise Unproved(f"{what}: the {kind} may be at t_end (an event at t = kT)")
        for fn in fns:
            hi = wide.lower() if fn is fired else tight.upper()
            self.pieces += certify.exclude(rest, fn, lo, hi, what)
        self.t, self.v = tight, arb(0)
        self.emit(kind, arb(0))
        if tracked is not None:
            self._track_rest(tracked, fired, guess, wide)
        if m.friction:
            self.to_flight(sigma, {"velocity": 2})
        else:
            self.to_flight(0, {motion.wall_name(self.side): 3})
        return False

    def _track_rest(self, tracked, fired, guess, wide):
        """The tracked start's own slip (``rest_track``: its stop ``(t, x)``): the zero of
        ``fired`` on its rest at ``x``, near ``guess`` (``certify.root``), inside the set's ball
        ``wide`` (where every start of the set has one zero, and none before it: the same zero);
        the next flight then tracks it from there.  Lost (no ``track``) where that zero is not
        proved or not inside ``wide``."""
        t, x = tracked
        try:
            _, slip = certify.root(motion.Rest(self.m, x), fired, guess, t.upper(), "the tracked slip")
        except Unproved:
            return
        if wide.contains(slip):
            self.track, self.track_for = (slip, x, arb(0)), (self.t, self.x, self.v)

    def restore_fallback(self):
        """A bounce of a chatter run could not be proved (late bounces are too short for
        absolute coordinates): close the run at the last impact whose tail was bounded."""
        t, v, length, side, index, tail = self.fallback
        del self.log[length:]
        self.t, self.x, self.v = t, self.m.wall(side), v
        return self.close_chatter(side, index, tail)

    # -- the loop -------------------------------------------------------------------------
    def step(self):
        try:
            return self.fly() if self.mode == "flight" else self.rest()
        except Unproved:
            if self.fallback is None:
                raise
            return self.restore_fallback()

    def run(self, t0, x0, v0):
        """Walk from ``(t0, x0, v0)`` to ``t_end``; returns the ball ``EventLog``."""
        self.start(t0, x0, v0)
        for _ in range(len(self.points) + 2):
            done = self.step()
            if done:
                log = self.log
                log.t_end, log.x_end, log.v_end = self.t_end, self.x, self.v
                log.mode_end = self.mode
                if self.i != len(self.points):
                    raise Unproved("the point integrator logged events the walk did not reach")
                return log
        raise Unproved("the walk did not finish within the point integrator's events")


def mpstr(value) -> str:
    """A point value, 15 digits."""
    return from_mpf(value).mid().str(15)
