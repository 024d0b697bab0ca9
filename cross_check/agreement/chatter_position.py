"""``chatter`` under position forcing where the force at ``t = 0`` pushes into neither wall
(issue 33).

``hardcases``' chatter case is explicit: a start next to the wall the force pushes into at
``t = 0``, with a small speed into it.  Under position forcing the push at ``t = 0`` is
``F cos(k r)`` into ``r`` and ``-F cos(k l)`` into ``l``, and where neither exceeds ``f`` there
is no such start; the force then pushes into a wall later in the period (``cos(w t) < 0``: into
``l`` where ``cos(k l) > f/F``), and the scene chatters there.  The case is found forward:

1. **screen** (fast, float64): the starts of ``impact_at_t``'s scans (from rest across the gap,
   then at its ``speeds``, then at ``CHATTER_SPEEDS``), each run over ``[0, T]``.  A start whose log has a chatter run
   accumulating before ``CHATTER_BY T``, at a wall pushed into at that time with bounces that
   shrink by at most ``rho_max`` (``hardcases.RHO_MAX``: the reference simulates the bounces at
   the golden data's 90 and 110 digits), is a candidate; candidates in the middle of the longest
   run of neighbouring chattering starts (a chatter run is robust: an open set of starts) first;
2. **reference**: from the start, its ``x0`` rounded to ``X_DIGITS`` digits, the reference's log
   at ``CHECK_DPS`` digits must have the chatter run too;
3. **certify**: ``reference.enclosure.enclose_map`` proves the start's itinerary over ``[0, T]``
   forward, the chatter run's tail bounded (``reference.enclosure.walk.chatter_tail``).

fast only orders the candidates; the reference and the proof decide.
"""
from __future__ import annotations

import mpmath
import numpy as np

import fast
import reference
from cross_check.agreement.case import HardCase, decimal_text
from cross_check.agreement.impact_at_t import (MORE_SPEEDS, N_SCAN, PROOF_MAX_PREC, scan_grid, speeds,
                                                speeds_text)
from reference.enclosure import enclose_map

#: a chatter run must accumulate before this fraction of the period (its contact and release
#: then fall inside the proof's ``[0, T]`` as well)
CHATTER_BY = 0.9
#: significant digits of a candidate's ``x0`` (a run of chattering starts is ~1e-3 of the gap wide)
X_DIGITS = 8
#: digits of the reference's check
CHECK_DPS = 30
#: candidates tried through the reference and the proof
MAX_TRIES = 3
#: significant digits of the case's event time, the accumulation time (the reference's at
#: ``CHECK_DPS`` digits)
T_DIGITS = 20


def _push(scene, side, t):
    """The push ``s A(wall, t)`` into the wall ``side`` (+1 r, -1 l) at time ``t`` (floats)."""
    F, w, k = scene.float("F"), scene.float("omega"), scene.float("wavenumber")
    wall = scene.float("r") if side > 0 else scene.float("l")
    return side * F * np.cos(k * wall) * np.cos(w * t)


def _chattering(scene, x, v0, rho_max):
    """``[(i, t_inf, side)]``: the starts ``(x[i], v0)`` whose fast log over ``[0, T]`` has a
    chatter run accumulating at ``t_inf < CHATTER_BY T`` at a wall pushed into with ``rho <=
    rho_max``."""
    l, r, T, f = scene.float("l"), scene.float("r"), scene.period, scene.float("f")
    e = scene.float("restitution")
    out = []
    for i, log in enumerate(fast.events(scene, x, np.full_like(x, float(v0)), T)):
        ev = next((ev for ev in log if ev.kind == "chatter"), None)
        if ev is None or not ev.t < CHATTER_BY * T:
            continue
        side = 1 if abs(ev.x - r) < abs(ev.x - l) else -1
        push = _push(scene, side, ev.t)
        if push > f and e * np.sqrt((push - f) / (push + f)) <= rho_max:
            out.append((i, ev.t, side))
    return out


#: the speeds of the last scans (``impact_at_t.MORE_SPEEDS`` up to ``2V``): a chatter run needs
#: a slow arrival at the wall
CHATTER_SPEEDS = tuple(s for s in MORE_SPEEDS if abs(s) <= 2)


def candidates(scene, rho_max):
    """``(x0, v0, t_inf, side)``, lazily: starts whose fast log chatters (step 1), the middle of
    the longest run of neighbouring chattering starts of each scan first; scans from rest first,
    then at ``speeds``, then at ``CHATTER_SPEEDS`` (each made only once the one before is used
    up)."""
    x = scan_grid(scene)
    for v0 in ["0"] + speeds(scene) + speeds(scene, CHATTER_SPEEDS):
        hits = _chattering(scene, x, v0, rho_max)
        runs, run = [], []
        for hit in hits:
            if run and hit[0] != run[-1][0] + 1:
                runs.append(run)
                run = []
            run.append(hit)
        runs += [run] if run else []
        for run in sorted(runs, key=len, reverse=True):
            i, t_inf, side = run[len(run) // 2]
            yield x[i], v0, t_inf, side


def construct(scene, rho_max):
    """``(HardCase, None)`` or ``(None, why)``: a chatter case through earlier events (module
    docstring); its event time is the accumulation time, to ``T_DIGITS`` digits.  At most
    ``MAX_TRIES`` candidates, each screened only once the one before is refused."""
    found, why = candidates(scene, rho_max), None
    for _ in range(MAX_TRIES):
        try:
            candidate = next(found, None)
        except (ValueError, RuntimeError) as exc:          # fast refused a scan: no candidates
            return None, f"fast's scan failed ({exc})"
        if candidate is None:
            break
        case, why = _checked(scene, *candidate)
        if case is not None:
            return case, None
    if why is None:
        return None, (f"none of the {N_SCAN - 1} starts from rest, nor at the speeds "
                      f"{speeds_text(scene, CHATTER_SPEEDS)}, chatters before {CHATTER_BY} T with rho <= "
                      f"{mpmath.nstr(rho_max, 3)}")
    return None, why


def _checked(scene, x0, v0, t_screen, side):
    """``(HardCase, None)`` or ``(None, why)``: one candidate through steps 2 and 3."""
    x_text = decimal_text(mpmath.mpf(x0), X_DIGITS)
    with mpmath.workdps(CHECK_DPS + 10):
        T = 2 * mpmath.pi / scene.mpf("omega")
        log = reference.trajectory(scene, x_text, v0, T, dps=CHECK_DPS)
        runs = [e for e in log if e.kind == "chatter"]
        if not runs:
            return None, f"the reference from ({x_text}, {v0}) does not chatter: {[e.kind for e in log][:12]}"
        enc = enclose_map(scene, x_text, v0, max_prec=PROOF_MAX_PREC)
        if not enc.proved or "chatter" not in [e.kind for e in enc.events]:
            return None, f"the forward proof from ({x_text}, {v0}) failed: {enc.reason}"
        kinds = [e.kind for e in log]
        t_inf, before = runs[0].t, kinds[:kinds.index("chatter")]
    wall = "r" if side > 0 else "l"
    start = "from rest" if v0 == "0" else f"at v0 = {v0}"
    return HardCase("chatter", x_text, v0, decimal_text(t_inf, T_DIGITS), "chatter",
                    f"a scan of starts {start} (the push at t = 0 is below f at both walls): through "
                    f"{len(before)} events, a chatter run at {wall} accumulating at t = {mpmath.nstr(t_inf, 12)}; "
                    f"certified: the itinerary proved forward (validated flights, enclose_map at {enc.prec} bits, "
                    f"the run's tail bounded)"), None
