"""Hard cases under position forcing found forward, through earlier events (issue 33):
``chatter`` where the force at ``t = 0`` pushes into neither wall, and ``sticking`` where no
single flight from ``t = 0`` reaches a stop.

* ``chatter``: ``hardcases``' chatter case is explicit, a start next to the wall the force
  pushes into at ``t = 0``, with a small speed into it.  Under position forcing the push at
  ``t = 0`` is ``F cos(k r)`` into ``r`` and ``-F cos(k l)`` into ``l``, and where neither
  exceeds ``f`` there is no such start; the force then pushes into a wall later in the period
  (``cos(w t) < 0``: into ``l`` where ``cos(k l) > f/F``), and the scene chatters there.
* ``sticking``: ``hardcases_position`` builds it as one flight, run back from a stop at ``T/4``
  or ``3T/4`` (``A = 0``); on a narrow gap with a long period every such flight meets a wall
  before ``t = 0``.  A stop mid-gap where ``|A| <= STICK_SHARE f``, followed by a slip before
  ``T``, is the same kind (a stick, then slip) wherever it falls in the period.

Each case is found forward:

1. **screen** (fast, float64): the starts of ``impact_at_t``'s scans (from rest across the gap,
   then at its ``speeds``, then at ``SLOW_SPEEDS``), each run over ``[0, T]``.  A start whose log
   has the event before ``BY T`` is a candidate -- a chatter run at a wall pushed into at that
   time with bounces that shrink by at most ``rho_max`` (``hardcases.RHO_MAX``: the reference
   simulates the bounces at the golden data's 90 and 110 digits); a stop as above -- the middle
   of the longest run of neighbouring such starts first (the event is robust: an open set of
   starts), each scan made only once the one before is used up; a start from rest is nudged
   along the force (``NUDGE``: a start at rest is in the band);
2. **reference**: from the start, its ``x0`` rounded to ``X_DIGITS`` digits, the reference's log
   at ``CHECK_DPS`` digits must have the event too, with the screen's itinerary before it;
3. **certify**: ``reference.enclosure.enclose_map`` proves the start's itinerary over ``[0, T]``
   forward (``impact_at_t.forward_proof``; a chatter run's tail bounded,
   ``reference.enclosure.tails.chatter_tail``).

fast only orders the candidates; the reference and the proof decide.
"""
from __future__ import annotations

import itertools

import mpmath
import numpy as np

import reference
from cross_check.agreement import compare
from cross_check.agreement.case import HardCase, decimal_text, first_built
from cross_check.agreement.impact_at_t import (MORE_EVENTS, N_SCAN, budgeted, forward_proof, logs, scan_grid,
                                                speeds, speeds_text)
from cross_check.agreement.impact_backward import speed_scale

#: the event must come before this fraction of the period (a chatter run's contact and release,
#: a stick's slip, then fall inside the proof's ``[0, T]`` as well)
BY = 0.9
#: significant digits of a candidate's ``x0`` (a run of chattering starts is ~1e-3 of the gap wide)
X_DIGITS = 8
#: digits of the reference's check
CHECK_DPS = 30
#: candidates tried through the reference and the proof
MAX_TRIES = 3
#: significant digits of the case's event time (the reference's at ``CHECK_DPS`` digits)
T_DIGITS = 20
#: the speeds of the last scans, in units of ``V`` (``impact_at_t.speeds``): steps of ``V/8`` up
#: to ``2V``, those of ``impact_at_t.SPEEDS`` left out.  Issue 33, on unseen scenes drawn at
#: random: a chatter run later in the period needs a slow arrival at the wall, in bands of starts
#: ``~V/6`` wide that fell between ``SPEEDS`` (0.35 to 0.5 and 0.55 to 0.9 where ``V`` was 1.06
#: and 0.93)
SLOW_SPEEDS = tuple(s for j in range(1, 17) if j not in (4, 8, 16) for s in (j / 8, -j / 8))
#: a candidate from rest starts instead at ``v0 = s NUDGE V`` (``_nudged``: ``s`` the sign of the
#: force ``A(0, x0) = F cos(k x0)``, two significant digits).  A start at rest is in the band: a
#: move of an ulp in ``v`` against the force adds a turn (or a stop) at ``t ~ 1e-16``, so the
#: reference's itinerary flips under the moves (``golden_proof.band``) and fast's agreement on the
#: case is not tested.  Along the force the nudged start moves off as the start at rest does (a
#: stop soon after where ``|A| <= f`` there), and its ulps move nothing.  Issue 33, on 22 scenes:
#: the chatter case of D (``F=3 f=0.5 omega=0.8 l=-2 r=1.5 wavenumber=2.5``) and the sticking case
#: of W (``F=3 f=0.3 omega=0.5 l=-2 r=2 wavenumber=2``) came from rest and were in the band; every
#: other chatter and sticking case, from a moving start, was not
NUDGE = 1e-3
#: a sticking stop: ``|A| <= STICK_SHARE f`` there (well inside the sticking region: no
#: stick-slip boundary), at least ``WALL_SHARE`` of the gap from either wall
STICK_SHARE, WALL_SHARE = 0.5, 1 / 64


def _push(scene, side, t):
    """The push ``s A(wall, t)`` into the wall ``side`` (+1 r, -1 l) at time ``t`` (floats)."""
    F, w, k = scene.float("F"), scene.float("omega"), scene.float("wavenumber")
    wall = scene.float("r") if side > 0 else scene.float("l")
    return side * F * np.cos(k * wall) * np.cos(w * t)


def _side(scene, x):
    return 1 if abs(x - scene.float("r")) < abs(x - scene.float("l")) else -1


def _chattering(scene, x, v0, rho_max, spent=None):
    """``[(i, t_inf, side)]``: the starts ``(x[i], v0)`` whose fast log over ``[0, T]`` has a
    chatter run accumulating at ``t_inf < BY T`` at a wall pushed into with ``rho <= rho_max``."""
    T, f, e = scene.period, scene.float("f"), scene.float("restitution")
    out = []
    for i, log in enumerate(logs(scene, x, v0, T, spent)):
        ev = next((ev for ev in log if ev.kind == "chatter"), None)
        if ev is None or not ev.t < BY * T:
            continue
        side = _side(scene, ev.x)
        push = _push(scene, side, ev.t)
        if push > f and e * np.sqrt((push - f) / (push + f)) <= rho_max:
            out.append((i, ev.t, side))
    return out


def _sticking(scene, x, v0, spent=None):
    """``[(i, t, 0)]``: the starts ``(x[i], v0)`` whose fast log over ``[0, T]`` has a stop at
    ``t < BY T`` that sticks (``_sticks``), with a slip after it and no chatter or contact before
    it."""
    T, out = scene.period, []
    for i, log in enumerate(logs(scene, x, v0, T, spent)):
        for j, ev in enumerate(log):
            if ev.kind in ("chatter", "contact") or not ev.t < BY * T:
                break
            if _sticks(scene, ev) and any(later.kind == "slip" for later in log[j + 1:]):
                out.append((i, ev.t, 0))
                break
    return out


def _sticks(scene, ev) -> bool:
    """The stop ``ev`` (a log's event: floats or mpf) is mid-gap, ``WALL_SHARE`` of the gap from
    either wall, where ``|A| <= STICK_SHARE f``."""
    if ev.kind != "stick":      # most events of a scan (the scene's floats cost ~8 us a call)
        return False
    F, f, w, k = (scene.float(p) for p in ("F", "f", "omega", "wavenumber"))
    l, r = scene.float("l"), scene.float("r")
    x, t = float(ev.x), float(ev.t)
    margin = WALL_SHARE * (r - l)
    return l + margin < x < r - margin and abs(F * np.cos(k * x) * np.cos(w * t)) <= STICK_SHARE * f


def _nudged(scene, x0) -> str:
    """``v0 = s NUDGE V`` for a candidate from rest at ``x0`` (``NUDGE``), a decimal string."""
    s = 1.0 if scene.float("F") * np.cos(scene.float("wavenumber") * x0) >= 0 else -1.0
    return repr(s * float(f"{NUDGE * speed_scale(scene):.2g}"))


def candidates(scene, hits_of):
    """``(x0, v0, t, side)``, lazily: the starts that ``hits_of(scene, x, v0, spent)`` picks
    (step 1), the middle of the longest run of neighbouring ones of each scan first; scans from
    rest first, then at ``speeds``, then at ``SLOW_SPEEDS`` within fast's ``MORE_EVENTS`` (each
    made only once the one before is used up).  A candidate of the scan from rest is nudged off
    it along the force (``NUDGE``: out of the band)."""
    x, spent = scan_grid(scene), []
    first = ((v0, None) for v0 in ["0"] + speeds(scene))
    later = ((v0, spent) for v0 in budgeted(speeds(scene, SLOW_SPEEDS), spent))
    for v0, counted in itertools.chain(first, later):
        runs, run = [], []
        for hit in hits_of(scene, x, v0, counted):
            if run and hit[0] != run[-1][0] + 1:
                runs.append(run)
                run = []
            run.append(hit)
        runs += [run] if run else []
        for run in sorted(runs, key=len, reverse=True):
            i, t, side = run[len(run) // 2]
            yield x[i], _nudged(scene, x[i]) if v0 == "0" else v0, t, side


def chatter(scene, rho_max):
    """``(HardCase, None)`` or ``(None, why)``: a chatter case through earlier events; its event
    time is the accumulation time, to ``T_DIGITS`` digits."""
    return _construct(scene, "chatter", lambda sc, x, v0, spent: _chattering(sc, x, v0, rho_max, spent),
                      f"chatters before {BY} T with rho <= {mpmath.nstr(rho_max, 3)}")


def sticking(scene):
    """``(HardCase, None)`` or ``(None, why)``: a sticking case through earlier events; its event
    time is the stop's, to ``T_DIGITS`` digits."""
    return _construct(scene, "sticking", _sticking,
                      f"stops mid-gap before {BY} T where |A| <= {STICK_SHARE:g} f, then slips")


def _construct(scene, name, hits_of, wanted):
    """At most ``MAX_TRIES`` candidates, each screened only once the one before is refused."""
    case, why, _ = first_built(candidates(scene, hits_of), MAX_TRIES, lambda c: _checked(scene, name, *c))
    if case is not None:
        return case, None
    if why is None:
        return None, (f"none of the {N_SCAN - 1} starts from rest, nor at the speeds "
                      f"{speeds_text(scene, SLOW_SPEEDS)} (those within {MORE_EVENTS:,} events of fast), {wanted}")
    return None, why


#: each case's event kind in the logs, and the reason no other construction gives it
_KIND = {"chatter": ("chatter", "the push at t = 0 is below f at both walls"),
         "sticking": ("stick", "no single flight from t = 0 reaches a stop")}


def _checked(scene, name, x0, v0, t_screen, side):
    """``(HardCase, None)`` or ``(None, why)``: one candidate through steps 2 and 3.  The case's
    event: the reference's first chatter run, or its stop nearest the screen's (``t_screen``),
    which must stick (``_sticks``) and slip after, the proof's itinerary the reference's."""
    x_text, (kind, reason) = decimal_text(mpmath.mpf(x0), X_DIGITS), _KIND[name]
    with mpmath.workdps(CHECK_DPS + 10):
        T = 2 * mpmath.pi / scene.mpf("omega")
        log = reference.trajectory(scene, x_text, v0, T, dps=CHECK_DPS)
        kinds = [e.kind for e in log]
        ats = [i for i, k in enumerate(kinds) if k == kind]
        at = (ats[0] if name == "chatter" else min(ats, key=lambda i: abs(log[i].t - t_screen))) if ats else None
        if at is None or (name == "sticking" and not (_sticks(scene, log[at]) and "slip" in kinds[at:])):
            return None, f"the reference from ({x_text}, {v0}) has no {name} event where fast has: {kinds[:12]}"
        enc = forward_proof(scene, x_text, v0)
        proved = [e.kind for e in enc.events] if enc.proved else []
        itinerary = [[e.kind for e in compare.canonical_of(events, scene)] for events in (enc.events, log)]
        if kind not in proved or (name == "sticking" and itinerary[0] != itinerary[1]):
            return None, f"the forward proof from ({x_text}, {v0}) failed: {enc.reason or proved[:12]}"
        t_event, before, x_event = log[at].t, kinds[:at], log[at].x
    start = f"at v0 = {v0}" + (", from rest nudged along the force off the band"
                               if v0 == _nudged(scene, float(x0)) else "")
    what, tail = ((f"a chatter run at {'r' if side > 0 else 'l'} accumulating", ", the run's tail bounded")
                  if name == "chatter" else
                  (f"a stop at x = {mpmath.nstr(x_event, 8)} (|A| <= {STICK_SHARE:g} f there; it slips later)", ""))
    events = f"{len(before)} event{'' if len(before) == 1 else 's'}"
    return HardCase(name, x_text, v0, decimal_text(t_event, T_DIGITS), kind,
                    f"a scan of starts {start} ({reason}): through {events}, {what} at t = "
                    f"{mpmath.nstr(t_event, 12)}; certified: the itinerary proved forward (validated flights, "
                    f"enclose_map at {enc.prec} bits{tail})"), None
