"""SUNDIALS CVODE (through scikit-sundae) as a peer: BDF and Adams with CVODE's root functions,
written as a careful user of CVODE would write it (protocol: ``cross_check.score``).

How the library is used
-----------------------
The event loop is the careful user's of ``cross_check.agreement.baseline`` (the one the scipy
and heyoka adapters use: restart after every event, the friction sign frozen per flight); what
CVODE brings is the integration and the root finding of both phases:

* **flight** (``CvodeFlight``): ``x' = v, v' = F cos(k x) cos(w t) - s f - c v`` from the event
  state, ``sksundae.cvode.CVODE`` with ``method`` BDF or Adams, ``rtol`` and the baseline's
  ``atol = rtol * (R, max(F, f)/w)``, ``max_num_steps`` 10^5 per call, advanced by ``step(t_end,
  tstop=t_end)``, which returns at the first root of two root functions (``eventsfn``, both
  terminal, directions fixed at construction):

  - the wall ahead, ``g1 = s (x - W_s)`` rising (``W_+ = r``, ``W_- = l``): an **impact**;
  - the end of the flight, ``g2 = s v`` falling: a **turn**, a **stick** or a **wall contact**
    (decided by the baseline from the force there).  CVODE does not report a root at the
    initial point, so a flight that starts at ``v = 0`` (after a turn or a release) does not
    stop at its own start.

  CVODE locates a root on its interpolant to ``100 * uround * (|t| + |h|)`` in time; the state
  returned there is that interpolant's.  The parameters and ``s`` travel in ``userdata``, so one
  solver per scene and tolerance is built and re-initialised (``init_step``) per flight;
* **rest** (``CvodeRest``): sticking and wall contact integrate ``y' = 0`` with one root
  function, the baseline's threshold (``|a cos(w t)| - f`` rising for a **stick**, ending in a
  **slip**; ``A + f`` falling at ``r``, ``A - f`` rising at ``l`` for a **wall contact**, ending
  in a **release**), with ``max_step = T/16`` so that no crossing hides inside one step.

Per kind: **impact** ``v -> -e v`` with ``x`` set to the wall; **chatter**: at a wall the force
pushes into, a bounce below ``100 atol`` (speed or height) is declared the end of the chatter
run (wall contact from there, the baseline's cut-off); **grazing**: found only if ``g1``
changes sign between two steps (CVODE checks the sign at step ends: a tangency inside one step
is missed).  A failing CVODE call raises ``RuntimeError`` with its message (a failure of that
start, recorded by the scorer).

Settings: ``method`` ``"BDF"`` or ``"Adams"``, ``rtol`` in ``[1e-14, 1e-3]``.  Map and events;
every effect (restitution, damping and position forcing enter the right-hand side and the
threshold).
"""
from __future__ import annotations

import math

import numpy as np

from cross_check.score import adapters

METHODS = ("BDF", "Adams")
MAX_NUM_STEPS = 100_000
#: the rest phases' largest step, as a fraction of the period (the baseline's choice)
REST_STEPS_PER_PERIOD = 16
#: CVODE's return status when a root function stopped the step (scikit-sundae ``CVODEResult.status``)
ROOT_RETURN = 2


def _flight_rhs(t, y, yp, ud):
    F, f, w, c, k, s = ud[:6]
    yp[0] = y[1]
    yp[1] = F * math.cos(k * y[0]) * math.cos(w * t) - s * f - c * y[1]


def _flight_roots(t, y, events, ud):
    s = ud[5]
    events[0] = s * (y[0] - ud[6])
    events[1] = s * y[1]


_flight_roots.terminal = [True, True]
_flight_roots.direction = [1, -1]


def _rest_rhs(t, y, yp, ud):
    yp[0] = 0.0
    yp[1] = 0.0


def _rest_root(t, y, events, ud):
    events[0] = ud[0](t)


class CvodeFlight:
    """The baseline's ``flight`` by CVODE (module docstring); one solver per (rtol, atol),
    re-initialised per flight."""

    def __init__(self, method: str):
        self.method = method
        self.solvers: dict = {}
        self.ud = [0.0] * 7

    def __getstate__(self):
        return {"method": self.method, "solvers": {}, "ud": [0.0] * 7}

    def _solver(self, rtol, atol):
        from sksundae.cvode import CVODE
        key = (rtol, tuple(atol))
        if key not in self.solvers:
            self.solvers[key] = CVODE(_flight_rhs, userdata=self.ud, method=self.method, rtol=rtol,
                                      atol=np.asarray(atol, float), eventsfn=_flight_roots, num_events=2,
                                      max_num_steps=MAX_NUM_STEPS)
        return self.solvers[key]

    def __call__(self, p, t0, x0, v0, s, t_end, rtol, atol):
        solver = self._solver(rtol, atol)
        self.ud[:] = [p.F, p.f, p.w, p.c, 0.0 if p.k is None else p.k, float(s), p.r if s > 0 else p.l]
        solver.init_step(t0, np.array([x0, v0]))
        res = solver.step(t_end, tstop=t_end)
        if not res.success:
            raise RuntimeError(f"CVODE {self.method}: {res.message} (status {res.status}) at t={t0}, x={x0}, "
                               f"v={v0}, s={s}")
        if res.status == ROOT_RETURN and res.i_events is not None and len(res.i_events):
            which = np.asarray(res.i_events)[-1]
            name = ("r" if s > 0 else "l") if which[0] else "v0"
            return float(res.t), np.asarray(res.y, float).copy(), name, int(res.nfev)
        return t_end, np.asarray(res.y, float).copy(), "end", int(res.nfev)


class CvodeRest:
    """The baseline's ``rest`` by a CVODE root function on ``y' = 0`` (module docstring)."""

    def __init__(self, method: str):
        self.method = method
        self.solvers: dict = {}
        self.ud = [None]

    def __getstate__(self):
        return {"method": self.method, "solvers": {}, "ud": [None]}

    def __call__(self, p, t0, x, threshold, direction, t_end):
        from sksundae.cvode import CVODE

        key = (direction, p.T)
        if key not in self.solvers:
            root = lambda t, y, events, ud: _rest_root(t, y, events, ud)       # noqa: E731
            root.terminal, root.direction = [True], [int(direction)]
            self.solvers[key] = CVODE(_rest_rhs, userdata=self.ud, method=self.method, eventsfn=root, num_events=1,
                                      max_step=p.T / REST_STEPS_PER_PERIOD, max_num_steps=MAX_NUM_STEPS)
        solver = self.solvers[key]
        self.ud[0] = threshold
        solver.init_step(t0, np.array([x, 0.0]))
        res = solver.step(t_end, tstop=t_end)
        if not res.success:
            raise RuntimeError(f"CVODE {self.method} (rest): {res.message} (status {res.status}) at t={t0}, x={x}")
        if res.status == ROOT_RETURN:
            return float(res.t), int(res.nfev)
        return t_end, int(res.nfev)


class SundialsAdapter(adapters.BaselineAdapter):
    """CVODE ``method`` at ``rtol`` in the careful user's event loop (module docstring): the
    baseline's adapter with CVODE's flight and rest.  Pickles as its settings; the solvers are
    built in the process that calls it."""

    def __init__(self, method: str = "BDF", rtol: float = 1e-10):
        if method not in METHODS:
            raise ValueError(f"method must be one of {METHODS}, got {method!r}")
        if not (isinstance(rtol, (int, float)) and 1e-14 <= rtol <= 1e-3):
            raise ValueError(f"rtol must be a number in [1e-14, 1e-3], got {rtol!r}")
        super().__init__(f"sundials {method} rtol {rtol:.0e}", rtol=float(rtol), flight=CvodeFlight(method),
                         rest=CvodeRest(method))
        self.method = method


__all__ = ["CvodeFlight", "CvodeRest", "METHODS", "SundialsAdapter"]
