"""The accumulation times of a position-forced golden input's chatter runs, by a pair of short
reference runs restarted from its proof (issue 33).

A chatter input's proof (``golden.first_proof``: 192 bits) pins ``Phi``, ``Phi'`` and every
event to ~1e-54 but the accumulation time ``t_inf`` of each chatter run only to ~1e-11: the
walk bounds the tail of the run to second order in the last bounce's speed
(``reference.enclosure.tails.chatter_tail``) and closes it at ``2^-40 T``.  The rest after it
forgets ``t_inf`` (the particle waits at the wall for the force), so ``t_inf`` is the one value
the proof leaves to the reference.  Before, such an input took the dps 90 / 110 pair over the
whole period: two full runs, ~2.3 CPU s an input on the narrow corner ``F=3 f=0.3 omega=0.5
l=0 r=0.2 wavenumber=2 restitution=0.6`` where every input chatters 3 to 5 times a period.

Here each ``t_inf`` comes from the reference restarted at the proof's latest bounce of the run
whose balls are still within ``RESTART_RADIUS`` (``restarts``; the walk's balls grow ~17-fold a
bounce along a run), at ``RESTART_DPS[0]`` digits from the balls' midpoints and at
``RESTART_DPS[1]`` from their upper ends: the two runs differ in their digits and in their start
within the proof's balls, and must agree within ``golden_self_agreement`` (what the full pair
asks of every value) and lie in the proof's ball of ``t_inf``.  Where any check fails the input
takes the full pair (``golden._self_checked``), as before.  Measured on the narrow corner (one
run): a restart pair takes 0.27 CPU s, the two ``t_inf`` agree to ~2e-51 (the start's spread), and
every string written is the full pair's; its eight samples took 3.9 to 4.3 CPU s an input, now
2.0 to 2.1.  A run that starts near grazing has no bounce within ``RESTART_RADIUS``; it restarts at
its tightest bounce if that is within ``RESTART_LOOSE``.  On a random unseen scene where every state
ends in a chatter run, this took the golden task from 31.4 and 25.5 to 17.7 and 20.5 CPU s (old and
new alternating in fresh processes), and five inputs off the full pair.  Four of them wrote the
pair's strings; the fifth differs in its dps-50 run's speed of ~1e-13 at a grazing impact, by
2.8e-50, which the proof certifies within ``golden_proved_agreement`` (1e-40 max(1, |v|)).
"""
from __future__ import annotations

import mpmath

import reference
from cross_check.agreement import compare
from cross_check.tolerances import tol
from reference.enclosure.balls import from_mpf, to_mpf

#: the digits of a restart pair: the run that gives ``t_inf`` and the one that checks it.  The
#: full pair's 90 / 110 carry 50 guard digits for a period that loses up to 50 (``golden_self_
#: agreement``); a restart loses next to none -- it starts from the proof's balls, and a chatter
#: run contracts (``rho < 1``) -- and the reference's accumulation test at 60 digits is
#: ``10^(12 - 60) T``, 8 digits below the 40 written.  On the narrow corner a pair took 0.27 CPU s
#: at 60 / 80 and 0.57 at 90 / 110, with the same ``t_inf`` to 1e-50 (the start's own spread)
RESTART_DPS = (60, 80)
#: the golden file's word on an input with ``"chatter_dps"`` (``golden.document``)
PROVENANCE = ("an input with \"chatter_dps\": [60, 80] has the time of each chatter event from a run of "
              "the reference restarted at its enclosure's last bounce with balls within 1e-50 (a run with "
              "none: its tightest bounce, if within 1e-43), at 60 digits from their midpoints, checked at "
              "80 from their upper ends (golden_self_agreement, and within the enclosure's ball of that "
              "time); its other values as for \"dps\": 50")
#: how far past the upper end of the proof's ``t_inf`` ball a restart runs, in periods (the
#: reference must see the run accumulate; the rest after it is not needed)
PAST = mpmath.mpf(2) ** -20


#: the widest (relative) balls of time and speed a restart may start from: the restart's start
#: error reaches ``t_inf`` times ~``1 / (1 - rho)``.  The walk's balls grew ~17-fold a bounce
#: along a chatter run (narrow corner: 1e-54 at the run's first impact, 1e-32 at its last) until
#: its sets were handed through the events (``reference.enclosure.handoff``): they now stay
#: within ~1e-52, so the restart is at the run's last bounce; a run whose first impact is near
#: grazing (a speed of ~6e-16: balls of ~2e-42 from the start) still takes the dps 90 / 110 pair
RESTART_RADIUS = 1e-50
#: a run none of whose impacts is within ``RESTART_RADIUS`` restarts at its tightest impact if that
#: one is within this (``restarts``).  The pair still decides: its two runs start from the balls'
#: midpoints and upper ends, so a start radius that reaches the written digits shows as a
#: disagreement beyond ``golden_self_agreement`` (1e-40) and the input takes the full pair.  At
#: 1e-43 the start's share of ``t_inf`` is ~1e-43 / (1 - rho), three decades below it for ``rho <=
#: 0.9``.  Issue 33, the unseen ``F=2.41 f=0.987 omega=1.32 l=-1.55 r=-0.08 wavenumber=0.459
#: restitution=0.7`` (drawn at random; every state ends its period in a chatter run): five hard-case
#: inputs whose run starts near grazing (its impacts' balls 1.2e-50 to 9e-44) took the full pair,
#: 15.5 of the golden task's 40 profiled CPU s
RESTART_LOOSE = 1e-43


def _radius(e) -> float:
    """The wider relative radius of an event's time and speed balls."""
    return max(float(b.rad()) / max(1.0, abs(float(b.mid()))) for b in (e.t, e.v))


def restarts(sc, enc) -> list:
    """``[(i, k)]``: for each chatter event of the proof ``enc`` (``i`` its index among the
    canonical events, ``compare.canonical_of``), ``k`` the index in ``enc.events`` of the run's
    latest impact whose balls are within ``RESTART_RADIUS`` (the restart's state), or where it has
    none its tightest impact, if within ``RESTART_LOOSE``.  Empty where the proof has no chatter
    run, or a run has no such impact."""
    out = []
    for k, e in enumerate(enc.events):
        if e.kind != "chatter":
            continue
        j = k
        while j > 0 and enc.events[j - 1].kind in ("impact", "turn"):
            j -= 1              # back to the run's first impact
        run = [m for m in range(j, k) if enc.events[m].kind == "impact"]
        tight = [m for m in run if _radius(enc.events[m]) <= RESTART_RADIUS]
        if tight:
            j = tight[-1]       # the latest bounce whose balls are still tight (they grow along a run)
        else:                   # else the tightest, if within RESTART_LOOSE (near grazing)
            j = min(run, key=lambda m: _radius(enc.events[m]), default=None)
            if j is None or _radius(enc.events[j]) > RESTART_LOOSE:
                return []
        canon = compare.canonical_of(enc.events[:k + 1], sc)
        out.append((len(canon) - 1, j))
    return out


def restart(sc, enc, k, upper: bool, dps: int):
    """The reference's first accumulation time from the proof's impact ``enc.events[k]`` (the
    particle at the wall, leaving it), at ``dps`` digits, from the balls' midpoints or
    (``upper``) their upper ends; ``None`` where the restart logs no chatter before the end."""
    e, t_inf = enc.events[k], next(ev for ev in enc.events[k:] if ev.kind == "chatter").t
    side = "r" if float(e.x.mid()) > (sc.float("l") + sc.float("r")) / 2 else "l"
    wall = sc.exact(side)           # read at the run's own precision, as its model reads it
    with mpmath.workdps(dps + 10):
        t0, v0 = ((to_mpf(b) + to_mpf(b.rad()) if upper else to_mpf(b)) for b in (e.t, e.v))
        t_end = to_mpf(t_inf) + to_mpf(t_inf.rad()) + PAST * sc.period
        log = reference.trajectory(sc, wall, v0, t_end, t0=t0, dps=dps)
    chatter = [q for q in compare.canonical_of(log, sc) if q.kind == "chatter"]
    return chatter[0].t if chatter else None


def chatter_times(sc, res, enc, pairs=None):
    """``(res', indices)``: the run ``res`` (``golden.compute``'s, canonical events) with the
    time of each chatter event replaced by its restart pair's (``restart``), and the canonical
    indices of those events; ``pairs``: ``restarts(sc, enc)`` if the caller has them.  ``None``
    where the proof has no chatter run, a restart finds none,
    the pair disagrees beyond ``golden_self_agreement`` or the time is outside the proof's ball
    (then the full pair decides)."""
    pairs = restarts(sc, enc) if pairs is None else pairs
    if not pairs:
        return None
    events = list(compare.canonical(res["events"], sc))
    proved = compare.canonical_of(enc.events, sc)
    rtol = tol("golden_self_agreement").rtol
    for i, k in pairs:
        if i >= len(events) or events[i].kind != "chatter" or proved[i].kind != "chatter":
            return None
        a, b = restart(sc, enc, k, False, RESTART_DPS[0]), restart(sc, enc, k, True, RESTART_DPS[1])
        if a is None or b is None:
            return None
        with mpmath.workdps(RESTART_DPS[1]):
            if abs(a - b) > rtol * max(1, abs(b)) or not proved[i].t.contains(from_mpf(a)):
                return None
        events[i] = events[i]._replace(t=a)
    return {**res, "events": events}, [i for i, _ in pairs]
