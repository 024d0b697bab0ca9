"""The general-purpose baseline: scipy's ``solve_ivp`` driven as a careful user would.

The user does not know the closed forms; they integrate the smooth flight
``x' = v, v' = A(x, t) - s f - c v`` with ``A = F cos(k x) cos(w t)`` (sign ``s`` frozen per
flight, never ``sgn(v)``, which would make the right-hand side discontinuous) by RK45 or
DOP853 at ``rtol`` with ``atol = rtol * (R, F/w)`` (the natural position and velocity
scales), with terminal events for the walls (``x - r`` upward, ``x - l`` downward) and for
``v = 0`` (crossing toward zero), restarting after each event:

* wall: ``v -> -e v`` and ``x`` set exactly to the wall.  If the impact speed is below
  ``100 atol_v`` or the bounce height ``v^2 / 2(|A| + f)`` below ``100 atol_x`` (float64
  positions next to the wall are quantized: bounces stop shrinking there), and the force pushes
  into the wall (``A >= -f`` at ``r``,
  ``A <= f`` at ``l``), the user declares the particle at rest against the wall (a careful
  user's chatter cut-off; the bounces would otherwise never end);
* ``v = 0``: a turn if ``s A < -f`` (new ``s = -s``), otherwise a stick (``v = 0`` exactly);
* stick and wall contact are integrated as ``y' = 0`` with an event on the friction threshold
  (``|A| - f`` upward for a stick, ``A + f`` downward at ``r``, ``A - f`` upward at ``l``)
  and ``max_step = T/16`` so the threshold crossing cannot hide inside one step.

Every run is bounded (``max_events``); exceeding it raises ``RuntimeError`` with the state.
What the baseline misses (a crossing pair of ``x - r`` inside one step, an impact at a
turning point) shows up in the comparison with the reference's itinerary.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from cross_check.agreement.compare import Event

METHODS = ("RK45", "DOP853")
RTOLS = tuple(10.0 ** -k for k in range(3, 13))


@dataclass
class BaselineRun:
    """Result of one baseline trajectory."""

    x: float
    v: float
    events: list = field(default_factory=list)
    nfev: int = 0
    seconds: float = 0.0


class _Params:
    def __init__(self, scene):
        fl = scene.floats()
        self.F, self.f, self.w, self.l, self.r = fl["F"], fl["f"], fl["omega"], fl["l"], fl["r"]
        self.e, self.c = fl["restitution"], fl["damping"]
        self.k = fl["wavenumber"]
        self.T = 2 * math.pi / self.w

    def A(self, t, x):
        pos = 1.0 if self.k is None else math.cos(self.k * x)
        return self.F * pos * math.cos(self.w * t)


def _event(fun, direction):
    fun.terminal = True
    fun.direction = direction
    return fun


def _flight(p, t0, x0, v0, s, t_end, method, rtol, atol):
    def rhs(t, y):
        return [y[1], p.A(t, y[0]) - s * p.f - p.c * y[1]]

    # only the wall ahead: the one behind cannot be reached before v = 0 ends the flight,
    # and its zero at the restart point would fire a spurious event at t0
    wall = _event(lambda t, y: y[0] - p.r, 1.0) if s > 0 else _event(lambda t, y: y[0] - p.l, -1.0)
    evs = [wall, _event(lambda t, y: y[1], -float(s))]
    sol = solve_ivp(rhs, (t0, t_end), [x0, v0], method=method, rtol=rtol, atol=atol, events=evs)
    if sol.status == -1:
        raise RuntimeError(f"solve_ivp failed: {sol.message} at t={t0}, x={x0}, v={v0}, s={s}")
    for i, name in enumerate(("r" if s > 0 else "l", "v0")):
        if len(sol.t_events[i]):
            return sol.t_events[i][0], sol.y_events[i][0], name, sol.nfev
    return t_end, sol.y[:, -1], "end", sol.nfev


def _rest(p, t0, x, threshold, direction, t_end):
    """Stick / wall contact: ``y' = 0`` until ``threshold(t)`` crosses zero (``direction``)."""
    sol = solve_ivp(lambda t, y: [0.0, 0.0], (t0, t_end), [x, 0.0], method="RK45",
                    max_step=p.T / 16, events=[_event(lambda t, y: threshold(t), direction)])
    if len(sol.t_events[0]):
        return sol.t_events[0][0], sol.nfev
    return t_end, sol.nfev


def run(scene, x0: float, v0: float, t_end: float, method: str = "DOP853", rtol: float = 1e-10,
        max_events: int = 20000, flight=None, rest=None) -> BaselineRun:
    """Integrate from ``(x0, v0)`` at ``t = 0`` to ``t_end`` (see the module docstring).

    ``flight(p, t0, x0, v0, s, t_end, rtol, atol) -> (t, (x, v), name, nfev)`` replaces
    solve_ivp's smooth flight (``name``: ``"r"``, ``"l"``, ``"v0"`` or ``"end"``), and
    ``rest(p, t0, x, threshold, direction, t_end) -> (t, nfev)`` its rest phases (the first
    crossing of ``threshold(t)`` through zero in ``direction`` after ``t0``, ``t_end`` if none):
    the same careful event handling around another integrator (``cross_check.score.adapters``'
    heyoka, ``cross_check.league.peers``' SUNDIALS)."""
    if flight is None and method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    if flight is None:
        flight = lambda *a: _flight(*a[:6], method, *a[6:])      # noqa: E731
    if not 1e-14 <= rtol <= 1e-1:
        raise ValueError(f"rtol must be in [1e-14, 1e-1], got {rtol}")
    p = _Params(scene)
    if not (p.l <= x0 <= p.r and math.isfinite(v0)):
        raise ValueError(f"x0 must be in [{p.l}, {p.r}] and v0 finite, got x0={x0}, v0={v0}")
    atol = rtol * np.array([p.r - p.l, max(p.F / p.w, p.f / p.w, 1e-300)])
    chatter_speed = 100 * atol   # (height, speed) below which bounces are declared chatter
    t0 = time.perf_counter()
    out = BaselineRun(x0, v0)
    t, x, v = 0.0, float(x0), float(v0)
    mode, s = _initial_mode(p, t, x, v)
    for _ in range(max_events):
        if t >= t_end:
            break
        if mode == "flight":
            te, ye, name, nfev = flight(p, t, x, v, s, t_end, rtol, atol)
            out.nfev += nfev
            t, x, v = float(te), float(ye[0]), float(ye[1])
            if name == "end":
                break
            mode, s = _after_flight_event(p, out, name, t, x, v, s, chatter_speed)
            x, v = out.events[-1].x, out.events[-1].v
        else:
            t, mode, s = _after_rest(p, out, mode, t, x, t_end, rest or _rest)
    else:
        raise RuntimeError(f"baseline: more than {max_events} events; state t={t}, x={x}, v={v}, mode={mode}")
    out.x, out.v, out.seconds = x, v, time.perf_counter() - t0
    return out


def _initial_mode(p, t, x, v):
    if v > 0:
        return "flight", 1
    if v < 0:
        return "flight", -1
    A = p.A(t, x)
    if x >= p.r and A >= -p.f:
        return "contact_r", 0
    if x <= p.l and A <= p.f:
        return "contact_l", 0
    if abs(A) > p.f:
        return "flight", (1 if A > 0 else -1)
    return "stick", 0


def _after_flight_event(p, out, name, t, x, v, s, chatter_speed):
    """Apply an event of the flight; append it to ``out.events``; return the new (mode, s)."""
    A = p.A(t, x)
    if name in ("r", "l"):
        wall, push = (p.r, A >= -p.f) if name == "r" else (p.l, A <= p.f)
        # chatter cut-off: the bounce (speed, or height v^2 / 2(|A| + f)) is below tolerance
        if push and (abs(v) <= chatter_speed[1] or v * v <= 2 * (abs(A) + p.f) * chatter_speed[0]):
            out.events.append(Event("chatter", t, wall, 0.0, v))
            return f"contact_{name}", 0
        out.events.append(Event("impact", t, wall, -p.e * v, v))
        return "flight", -s
    if s * A < -p.f:
        out.events.append(Event("turn", t, x, 0.0, v))
        return "flight", -s
    if x >= p.r - 1e-12 * (p.r - p.l) and A >= -p.f:
        out.events.append(Event("contact", t, p.r, 0.0, v))
        return "contact_r", 0
    if x <= p.l + 1e-12 * (p.r - p.l) and A <= p.f:
        out.events.append(Event("contact", t, p.l, 0.0, v))
        return "contact_l", 0
    out.events.append(Event("stick", t, x, 0.0, v))
    return "stick", 0


def _after_rest(p, out, mode, t, x, t_end, rest=_rest):
    """Integrate a stick or a wall contact to its end by ``rest``; return ``(t, mode, s)``."""
    if mode == "stick":
        if p.F <= p.f:
            return t_end, mode, 0
        te, nfev = rest(p, t, x, lambda tt: abs(p.A(tt, x)) - p.f, 1.0, t_end)
        kind = "slip"
    elif mode == "contact_r":
        te, nfev = rest(p, t, x, lambda tt: p.A(tt, x) + p.f, -1.0, t_end)
        kind = "release"
    else:
        te, nfev = rest(p, t, x, lambda tt: p.A(tt, x) - p.f, 1.0, t_end)
        kind = "release"
    out.nfev += nfev
    if te >= t_end:
        return t_end, mode, 0
    if mode == "stick":
        s = 1 if p.A(te, x) > 0 else -1
    else:
        s = -1 if mode == "contact_r" else 1   # released away from the wall
    out.events.append(Event(kind, float(te), x, 0.0, 0.0))
    return float(te), "flight", s


def stroboscopic(scene, x0: float, v0: float, periods: int = 1, method: str = "DOP853",
                 rtol: float = 1e-10, flight=None, rest=None) -> BaselineRun:
    """``Phi^periods(x0, v0)`` by the baseline (one ``run`` to ``periods * T``)."""
    if periods < 1:
        raise ValueError(f"periods must be >= 1, got {periods}")
    return run(scene, x0, v0, periods * 2 * math.pi / scene.float("omega"), method, rtol, flight=flight, rest=rest)
