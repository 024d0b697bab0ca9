"""fast: the float64 ensemble engine for the stroboscopic map of the vibro-impact oscillator
with Coulomb friction: numpy arrays in and out, ONE compiled per-state event loop (numba).

Shares no code with ``reference`` (only the ``Scene`` definition).  Modules, in the order
a state meets them: ``api`` (validation, public functions) and ``eventlog`` (``events``);
``batch`` (the driver: threads over chunks); ``loop`` (the per-state event loop),
``roots`` (certified event location), ``flight`` (closed-form flights), ``precise``
(double-double states at events), ``handlers`` (impact, turn, stick, contact, chatter),
``modes`` (closed-form exits and the chatter tail); ``ode`` (numerical flights for
position-dependent forcing); ``params``, ``state``, ``dd`` (double-double arithmetic) and
``jit`` (compile options, in one place).

Every function runs on every core available to the process (``default_threads()``; the
environment variable ``VIBRO_THREADS`` or a ``threads=`` keyword overrides it).
"""
from .api import (MAX_EVENTS, flow, jacobian, map_and_jacobian, map_and_zero_velocity, orbit, stroboscopic_map,
                  validate_scene, warm_up, zero_velocity)
from .batch import default_threads
from .eventlog import Event, EventLog, events
from .state import KINDS

__all__ = ["stroboscopic_map", "jacobian", "orbit", "zero_velocity", "events", "map_and_jacobian",
           "map_and_zero_velocity", "flow", "Event", "EventLog", "KINDS", "MAX_EVENTS", "default_threads",
           "validate_scene", "warm_up"]
