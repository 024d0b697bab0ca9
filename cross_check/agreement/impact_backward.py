"""``impact_at_T``'s backward screen (issue 33): the motion that hits a wall at ``t = T``, run back
to ``t = 0`` through the impacts before it, in float64.

The forward scans of ``impact_at_t`` look for a start whose impact time crosses ``T``.  Where
every start's bounces die before ``T`` (restitution ``e < 1``, friction, damping: the time the
bounces take to die, ``~ gap / v_c / (1 - e)``, does not grow with the start's speed) no scan
finds one.  Backward, the same motion is well defined until it stops: from the state just before
an impact at wall ``W`` at ``t = T`` with speed ``v*`` into it, the forward equation

    x'' = F cos(k x) cos(w t) - f sgn(x') - c x'

is integrated with ``t`` decreasing (scipy's DOP853, ``RTOL``), and at each wall met the impact
is inverted: the speed just before it was the speed after it over ``e``.  Backward the speeds
grow (by ``1/e`` at each wall, and friction and damping give energy back), so the run either
reaches ``t = 0`` -- its state is a start whose impact is at ``T`` -- or its speed passes
``MAX_SPEED V`` first (``V = max(F/w, f T)``, as ``impact_at_t.speeds``), or it meets ``v = 0``
(a stop, where the forward motion forgets how it came: no backward continuation).

A start found so only proposes a speed for ``impact_at_t``'s scans (``v0`` to two significant
digits): the scan brackets, the reference refines and ``enclose_map`` proves, as for any other
speed.  Where every backward run passes ``MAX_SPEED V`` or stops, the refusal says so.

Issue 33, on 40 unseen scenes drawn as the verify benchmark draws them (seeds 100 to 109): 11
had no ``impact_at_T`` from the scans from rest and at ``impact_at_t.SPEEDS``.  On four the
screen proposes the speed of the case (``v0`` = -35, 9.3, 4.4 and 5.6: ``9.3`` is ``15 V``,
beyond any forward scan up to ``8V``); on one the case comes through a stop, from
``impact_at_t.FAST_SPEEDS``; on the other six, all with restitution 0.7, every backward run
passes ``64 V`` within 10 to 15 impacts, or stops.  The screen costs 0.02 to 0.07 CPU s a scene.
"""
from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

#: the speeds ``v*`` into the wall at ``t = T`` (units of ``V``), slowest first
EVENT_SPEEDS = (1 / 64, 1 / 16, 1 / 4, 1)
#: a backward run whose speed passes this (units of ``V``) is given up: no such start is scanned
MAX_SPEED = 64.0
#: the walls met backward before a run is given up (the speed grows by ``1/e`` at each)
MAX_IMPACTS = 400
#: DOP853's tolerances (a screen: it proposes a speed, the reference and the proof decide)
RTOL, ATOL = 1e-10, 1e-12
#: a backward flight starts this far (relative to the gap) inside the wall it leaves
LEAVE = 1e-12


def speed_scale(scene) -> float:
    """``V = max(F/w, f T)``: the forced speed, or the speed that friction takes a period to stop
    (the unit of every scan speed of ``impact_at_t`` and of ``EVENT_SPEEDS``, ``MAX_SPEED``)."""
    return max(scene.float("F") / scene.float("omega"), scene.float("f") * scene.period)


def _rhs(scene):
    F, f, w, k, c = (scene.float(p) for p in ("F", "f", "omega", "wavenumber", "damping"))

    def rhs(t, y):
        return [y[1], F * np.cos(k * y[0]) * np.cos(w * t) - f * np.sign(y[1]) - c * y[1]]
    return rhs


def _events(scene):
    """The terminal events of a backward flight: wall ``l``, wall ``r``, ``v = 0``."""
    l, r = scene.float("l"), scene.float("r")
    out = [lambda t, y: y[0] - l, lambda t, y: y[0] - r, lambda t, y: y[1]]
    for ev in out:
        ev.terminal = True
    return out


def start(scene, side, v_star):
    """``((x0, v0), None)``: the start at ``t = 0`` of the motion that hits wall ``side`` (+1 ``r``,
    -1 ``l``) at ``t = T`` with speed ``v_star`` (float), run backward (module docstring); or
    ``(None, why)``: it stops, or its speed passes ``MAX_SPEED V``, or it meets ``MAX_IMPACTS``
    walls, before ``t = 0``."""
    l, r, e = scene.float("l"), scene.float("r"), scene.float("restitution")
    if e == 0:
        return None, "restitution 0: an impact leaves no speed to run back from"
    V = speed_scale(scene)
    rhs, events, inset = _rhs(scene), _events(scene), LEAVE * (r - l)
    t, x, v = scene.period, (r - inset if side > 0 else l + inset), side * v_star
    for n in range(MAX_IMPACTS):
        sol = solve_ivp(rhs, (t, 0.0), [x, v], method="DOP853", rtol=RTOL, atol=ATOL, events=events)
        if sol.status == 0:
            return (float(sol.y[0, -1]), float(sol.y[1, -1])), None
        if sol.status != 1:
            return None, f"DOP853 failed at t = {t:.6g}: {sol.message}"
        which = max((i for i in range(3) if len(sol.t_events[i])), key=lambda i: sol.t_events[i][0])
        t, (x, v) = float(sol.t_events[which][0]), sol.y_events[which][0]
        if which == 2:
            return None, f"it stops (v = 0) at t = {t:.4g}"
        x, v = (l + inset if which == 0 else r - inset), -v / e      # the impact, inverted
        if abs(v) > MAX_SPEED * V:
            return None, f"its speed passes {MAX_SPEED:g} V = {MAX_SPEED * V:.3g} at t = {t:.4g}, after {n + 1} impacts"
    return None, f"it meets {MAX_IMPACTS} walls before t = 0"


def proposals(scene):
    """``([v0, ...], [why, ...])``: the speeds (decimal strings, two significant digits, as
    ``impact_at_t.speeds``) of the starts found backward from both walls at ``EVENT_SPEEDS``, in
    that order and without repeats; and the reason of each run that found none."""
    V = speed_scale(scene)
    found, whys = [], []
    for u in EVENT_SPEEDS:
        for side, name in ((1, "r"), (-1, "l")):
            got, why = start(scene, side, u * V)
            if got is None:
                whys.append(f"from {name} at v* = {u:g} V: {why}")
            elif (v0 := repr(float(f"{got[1]:.2g}"))) not in found:
                found.append(v0)
    return found, whys
