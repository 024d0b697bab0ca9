"""Event-driven trajectory, the stroboscopic map and the event log.

The event log is a list of :class:`Event` (``kind, t, x, v, v_before, count``), in time
order; ``v`` is the velocity just *after* the event.  Kinds (defined here, once, for every
engine and test; the motions between events are ``reference.flows``'):

``"impact"``   x reaches the wall the flight moves toward; ``v = -e v_before``.  A grazing
               touch (``|v_before|`` below the noise floor) at a wall the force pulls away
               from is an impact too.
``"turn"``     v reaches 0 in flight with sign s and ``s A < -f``: the motion reverses.
               Only with friction.  **Frictionless scenes log nothing when v passes 0**: the
               flow ``x'' = A`` does not depend on the sign of v, so the motion is smooth
               there (a turn with factor 1 in Table 1); no event exists physically.
``"stick"``    v reaches 0 with ``-f <= s A``: sticking (interior) begins; also logged at
               ``t0`` for an initial interior state at rest that does not leave at once.
``"slip"``     sticking ends (``|A| > f`` on a right-neighbourhood); flight from rest.
``"contact"``  the particle comes to rest at a wall with the force holding it there
               (``v`` reaching 0 at the wall, a touch at a wall the force pushes into, an
               impact with ``e = 0``, or an initial state at a wall at rest).
``"chatter"``  the accumulation point of a run of impacts at one wall (``.count`` =
               impacts simulated one by one); wall contact follows.  See ``chatter.py``.
``"release"``  wall contact ends; flight from rest away from the wall.

Stick and contact may have zero length (``stick`` and ``slip`` at the same time) when
the force is exactly at the friction level and rising.  Events at exactly ``t_end`` are
processed; the returned state is the right limit.  The log also carries the final state
(``log.t_end``, ``log.x_end``, ``log.v_end``, ``log.mode_end``) and the start
(``log.t0``, ``log.x0``, ``log.v0``).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Optional

import mpmath

from reference import chatter, events
from reference.model import Model

#: Default budget of events of one call (a chatter run counts its simulated impacts): an
#: event costs ~0.3 ms at 30-110 digits (measured: 785 impacts in 0.23-0.30 s), so the
#: default bounds a call to about 6 s; ``max_events`` of the public functions sets it.
MAX_EVENTS = 20000
#: Bound on consecutive transitions at one instant (impact, turn, stick, slip, ... at t).
MAX_SAME_TIME = 50
KINDS = ("impact", "turn", "stick", "slip", "contact", "chatter", "release")


@dataclass(frozen=True)
class Event:
    """One event: ``kind`` (see module doc), time, position, velocity after and before."""

    kind: str
    t: mpmath.mpf
    x: mpmath.mpf
    v: mpmath.mpf
    v_before: mpmath.mpf
    count: Optional[int] = None


class EventLog(list):
    """A list of :class:`Event` with the start and final state as attributes."""

    t0 = x0 = v0 = t_end = x_end = v_end = None
    mode_end = None


class _Machine:
    """The core loop's state: mode is 'flight' (sign s), 'stick' or 'contact' (side)."""

    def __init__(self, model: Model, t_end):
        self.m, self.t_end = model, t_end
        self.log = EventLog()
        self.run = chatter.BounceRun()
        self.mode, self.s = "flight", 0
        self.from_rest = False

    # -- bookkeeping -------------------------------------------------------------------
    def emit(self, kind, v_before, count=None):
        self.log.append(Event(kind, self.t, self.x, self.v, v_before, count))
        if kind != "impact":
            self.run.observe(kind)

    def to_flight(self, s, from_rest):
        self.mode, self.s, self.from_rest = "flight", (s if self.m.friction else 0), from_rest

    def state_repr(self):
        return f"(t, x, v, mode) = ({self.t}, {self.x}, {self.v}, {self.mode} {self.s:+d})"

    # -- starting state ----------------------------------------------------------------
    def start(self, t, x, v):
        m = self.m
        self.t, self.x, self.v = t, x, v
        if (x == m.r and v > 0) or (x == m.l and v < 0):
            self.impact(1 if v > 0 else -1)
        elif v != 0:
            self.to_flight(1 if v > 0 else -1, False)
        elif x == m.r or x == m.l:
            self.rest_at_wall(1 if x == m.r else -1, mpmath.mpf(0), None)
        elif m.friction:
            if self.slip_time() == t:
                self.to_flight(self._slip_sign, True)     # leaves at once: no sticking
            else:
                self.mode = "stick"
                self.emit("stick", mpmath.mpf(0))
        else:
            self.to_flight(0, True)

    # -- transitions -------------------------------------------------------------------
    def impact(self, side):
        m, v_before = self.m, self.v
        self.x = m.wall(side)
        self.v = -m.e * v_before
        self.run.observe("impact", side)
        self.run.add_impact(self.t, abs(v_before))
        self.emit("impact", v_before)
        if abs(self.v) <= m.eps * m.v_scale:
            self.rest_at_wall(side, self.v, "contact-only")
            return
        self.to_flight(-side, False)
        self.check_chatter(side)

    def rest_at_wall(self, side, v_before, arrival):
        """``v = 0`` at a wall: contact if the force holds it there, else leave at once."""
        m = self.m
        self.x, self.v = m.wall(side), mpmath.mpf(0)
        release = m.forcing.first_above(self.t, self.x, -side, m.f, m.noise_a)
        if release == self.t:
            if arrival is not None and arrival != "contact-only":
                self.emit(arrival, v_before)
            self.to_flight(-side, True)
            return
        self.emit("contact", v_before)
        self.mode, self.s = "contact", side

    def check_chatter(self, side):
        m, run = self.m, self.run
        if not (m.friction or m.restitution):
            return        # elastic and frictionless: bounce speeds do not shrink (rho = 1)
        if run.count < chatter.MIN_RUN or side * m.force(self.x, self.t) <= m.f:
            return
        t_inf = run.estimate(m.chatter_tol, m.chatter_tol_loose)
        if t_inf is None:
            noise_floor = mpmath.sqrt(2 * m.eps * m.x_scale * (m.F + m.f))
            if run.speeds[-1] > noise_floor or run.latest() is None:
                return
            t_inf = max(run.latest(), self.t)   # bounces below the noise floor: take the sum
        if t_inf > self.t_end:
            if t_inf - self.t_end > m.chatter_tol:
                return
            t_inf = self.t_end
        if side * m.force(m.wall(side), t_inf) <= m.f:
            return
        count = run.count
        self.t, self.x, self.v = t_inf, m.wall(side), mpmath.mpf(0)
        self.emit("chatter", mpmath.mpf(0), count)
        self.mode, self.s = "contact", side

    def velocity_zero(self):
        m, s = self.m, self.s
        v_before = mpmath.mpf(0)          # v is continuous through a turn or a stop
        for side in (1, -1):
            if abs(self.x - m.wall(side)) <= m.eps * m.x_scale:
                self.rest_at_wall(side, v_before, "turn")
                return
        self.v = mpmath.mpf(0)
        if s * m.force(self.x, self.t) < -m.f:
            self.emit("turn", v_before)
            self.to_flight(-s, True)
        else:
            self.emit("stick", v_before)
            self.mode = "stick"

    def slip_time(self):
        """First time >= t at which sticking at x ends, and the new sign (or None)."""
        m = self.m
        up = m.forcing.first_above(self.t, self.x, 1, m.f, m.noise_a)
        down = m.forcing.first_above(self.t, self.x, -1, m.f, m.noise_a)
        if up is None and down is None:
            return None
        if down is None or (up is not None and up <= down):
            self._slip_sign = 1
            return up
        self._slip_sign = -1
        return down

    # -- one step of the core loop ------------------------------------------------------
    def step(self):
        """Advance to the next event or to ``t_end``; return True when done."""
        if self.mode == "flight":
            return self.fly()
        if self.mode == "stick":
            t_next, kind = self.slip_time(), "slip"
            sign = getattr(self, "_slip_sign", 0)
        else:
            t_next, kind = self.m.forcing.first_above(self.t, self.x, -self.s, self.m.f,
                                                      self.m.noise_a), "release"
            sign = -self.s
        if t_next is None or t_next > self.t_end:
            self.t = self.t_end
            return True
        self.t = t_next
        self.emit(kind, mpmath.mpf(0))
        self.to_flight(sign, True)
        return False

    def fly(self):
        m = self.m
        side = self.run.wall_side
        if side and self.x == m.wall(side) and -side * self.v > 0 and (m.friction or m.restitution):
            bounce = chatter.wall_bounce(m, self.t, side, -side * self.v, self.t_end)
            if bounce is not None:          # a certified bounce of a run, wall-relative
                return self.bounce(side, bounce)
        flight = m.flight(self.t, self.x, self.v, self.s)
        fns = m.event_functions(self.s, self.x, self.v, self.from_rest)
        fn, t, (x, v, _a) = events.find_next_event(flight, fns, self.t_end)
        self.t, self.x, self.v = t, x, v
        if fn is None:
            return True
        if fn.kind == "velocity":
            self.velocity_zero()
        elif abs(v) <= flight.noise_v:
            # v reaches 0 at the wall: a turn there (friction) or a grazing touch (f = 0)
            self.rest_at_wall(fn.side, v, "turn" if m.friction else "impact")
        else:
            self.impact(fn.side)
        return False

    def bounce(self, side, b):
        """Log a bounce of ``chatter.wall_bounce``: the turn (friction) and the impact."""
        m = self.m
        if b.t_turn is not None:
            self.t, self.x, self.v = b.t_turn, m.wall(side) - side * b.height, mpmath.mpf(0)
            self.emit("turn", mpmath.mpf(0))
        self.t, self.x, self.v = b.t_impact, m.wall(side), side * b.speed
        self.impact(side)
        return False


def integrate(model: Model, t0, x, v, t_end, max_events=None) -> EventLog:
    """Run the core loop from ``(t0, x, v)`` to ``t_end`` (all mpf at working precision).

    Cost: one certified event search per event.  The costly physical case is an elastic
    frictionless particle (``e = 1``, ``f = 0``) at a wall the force ``P`` pushes it into,
    with a tiny speed ``u``: its bounces do not shrink (``rho = 1``, no accumulation), each
    lasts ``~2 u / P``, so a push ``int P dt`` brings ``~int P dt / (2 u)`` genuine impacts
    (``~0.5 / u`` for ``F = w = 1`` from the start of the push), each located one by one
    (~0.3 ms each at 50 digits).  Beyond ``max_events`` events (default ``MAX_EVENTS``) a
    ``RuntimeError`` names the budget, the events logged and the state ``(t, x, v, mode)``.
    """
    max_events = MAX_EVENTS if max_events is None else max_events
    machine = _Machine(model, t_end)
    machine.start(t0, x, v)
    same_time, last_t = 0, None
    for _ in range(max_events):
        if len(machine.log) > max_events:
            break
        same_time = same_time + 1 if machine.t == last_t else 0
        last_t = machine.t
        if same_time > MAX_SAME_TIME:
            raise RuntimeError(f"no progress in time after {MAX_SAME_TIME} transitions: "
                               f"{machine.state_repr()}")
        if machine.step():
            log = machine.log
            log.t0, log.x0, log.v0 = t0, x, v
            log.t_end = machine.t
            log.x_end = min(max(machine.x, model.l), model.r)   # rounding at a touch
            log.v_end = machine.v if machine.mode == "flight" else mpmath.mpf(0)
            log.mode_end = machine.mode
            return log
    raise RuntimeError(f"more than max_events = {max_events} events (the event budget of one "
                       f"call; {len(machine.log)} logged) before t_end = {t_end}: "
                       f"{machine.state_repr()}")
