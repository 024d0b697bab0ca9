"""fast: a vectorised float64 engine for the stroboscopic map of the vibro-impact
oscillator with Coulomb friction (issue 3).

Shares no code with ``reference`` (only the ``Scene`` definition): see
``fast.kernel`` for the event loop, ``fast.flight`` for the closed-form flights,
``fast.roots`` for the certified event location, ``fast.modes`` for sticking, wall
contact and chatter, ``fast.events_proc`` for the event handling and the Jacobian.
"""
from .api import flow, jacobian, map_and_jacobian, orbit, stroboscopic_map, zero_velocity
from .eventlog import Event, EventLog, events
from .events_proc import KINDS

__all__ = ["stroboscopic_map", "jacobian", "orbit", "zero_velocity", "events",
           "map_and_jacobian", "flow", "Event", "EventLog", "KINDS"]
