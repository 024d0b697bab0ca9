"""The ground truth: event-driven, closed-form flights, certified event location, any precision.

Public API (each call works at ``dps`` + guard digits and restores the caller's precision):

* ``stroboscopic_map(scene, x, v, *, periods=1, dps=50) -> (x, v)``
* ``jacobian(scene, x, v, *, dps=50) -> J`` (``J[i][j]``, Table 1 product over ``[0, T]``)
* ``trajectory(scene, x, v, t_end, *, t0=0, dps=50) -> EventLog`` (a list of ``Event``)

Modules: ``flows`` (closed-form motions, the flight interface), ``events`` (certified event
location), ``chatter`` (accumulation of impacts), ``integrator`` (the core loop, event kinds),
``jacobian`` (Table 1), ``model`` (the scene at working precision), ``api`` (entry points).
"""
from reference.api import jacobian, stroboscopic_map, trajectory
from reference.integrator import KINDS, Event, EventLog
from reference.scene import Scene

__all__ = ["Scene", "stroboscopic_map", "jacobian", "trajectory", "Event", "EventLog", "KINDS"]
