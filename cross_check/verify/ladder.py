"""An orbit's proof for ``verify``: the precision ladder of Krawczyk proofs (``PROOF_LADDER``)
that ``tasks.orbits`` climbs for each periodic point that fast's search finds.

Each rung is a proof by ``paper.claims.base.prove`` (``reference.enclosure.prove_periodic``) at
``prec`` bits with a box of radius ``r``: the Krawczyk operator ``K(Z) = z - C G(z) + (I - C
P'(Z)) (Z - z)``, ``C ~ (P'(z) - I)^-1``, ``G = Phi^k - id`` on a section, proves a unique fixed
point in ``Z`` when ``K(Z)`` lies inside ``Z``.  Two things decide whether a rung can hold: the
residual ``|C G(z)|``, ``~2^(lost - prec)`` after a loss of ``lost`` bits measured on a lower rung
(:func:`_may_hold`), must fit in the box; and ``P'`` must vary little over the box (``|C| spread(P')
< 1``: :func:`_spread_at`).  The ladder climbs until one rung proves the orbit, skipping the rungs
that the measurements rule out, and stops where more bits cannot help (Newton diverging, a loss of
every bit, a spread that does not narrow).  A rung that measures ``P'`` too wide has the ladder try
next the fewest bits where that spread is predicted to be small (:func:`_aimed`), between its
fixed rungs.  The points that ``fast`` finds on or next to a family
of fixed points (``tr P' ~ 2``) are not tried or tried on the first rung only (``SINGULAR``,
:func:`_first_rung_only`), and so are rest states at the edge of a family of them
(``REST_EDGE_TOL``).

Split from ``tasks`` (which composes the rooms; this module owns the ladder's decisions).
"""
from __future__ import annotations

import math

import numpy as np

from cross_check.dynamics import periodic
from cross_check.paper.claims.base import prove


#: the precisions (bits) and Krawczyk box radii of an orbit's proof, tried in turn until one
#: proves it.  Issue 33: a proof at 320 bits spent ~90% of its time in the point integrator
#: under position forcing (the point logs of the Newton steps, the box and the section at
#: ``prec / 3.33 + 12`` digits of Taylor flights: ~5 s a period-2 orbit, 220 of the 292 CPU s of a
#: full verify of an unseen scene); at 64 bits with a box of 2^-32 the same proofs take ~0.4 s,
#: and a proof at any precision is a proof (the box radius, in the report, says how tight).  A
#: box too wide for one itinerary, or a centre that 64 bits cannot polish (multipliers ~1e3),
#: climbs: measured on scene B's period-3 saddle, (64, 2^-32) fails, (96, 2^-48) proves in 1.2 s,
#: where 320 bits takes 8.9 s.  Second pass (issue 33, profiled on two unseen scenes, D and F of
#: the issue): a rung was 2 to 4 point logs (each Newton step's enclosure, the box's, the one
#: over ``K``) and as many walks, 44% of a proof's CPU in the point logs on both (D: 70% before
#: ``reference.taylor``'s fixed-point steps).  Now one
#: point log an orbit, from the section's state at the first rung's digits, guides every walk
#: of every rung (``prove_periodic``'s ``points``: each walk proves every event from the
#: balls); the last Newton step is taken in mean-value form (no enclosure that only confirms
#: convergence); a rung whose residual ball alone is wider than its box (64 and 96 bits on D's
#: period-3 orbits: 53 bits lost) fails before its box is walked.  Point logs (periods 1-3):
#: D 53 -> 20, F 90 -> 31; walks D 81 -> 72, F 132 -> 124.  Third pass: a rung of 192 bits
#: before 320.  On scene W (``F=3 f=0.3 omega=0.5 l=-2 r=2 wavenumber=2``) two period-3 sticking
#: saddles (multipliers 1179 and 107) fail up to 128 and took 17 CPU s each at 320; at 192 each
#: takes 6.9 (W's period-3 proofs 43.7 -> 23.5 s, one run each).  An orbit that needs 320 pays
#: the failed 192 rung in addition (its Newton steps; the box is not walked).
#: Fourth pass: radii ``2^-(5/8 prec)``, not ``2^-(prec/2)``, widened to fit a loss measured on a
#: lower rung (:func:`_fitted`).  The box must hold the fixed point that the rung polishes
#: (``2^(lost - prec)``: ``_may_hold``) and be small enough that ``P'`` varies little over it; at
#: ``2^-32`` the 64-bit rung failed mostly on the second (``K(Z)`` not inside ``Z`` after a whole
#: walk of the box), and 96 bits then proved the orbit.  Issue 33, the orbits task (periods 1 to 3,
#: the two ladders alternately in one process, caches cleared, on a loaded 2-core machine): ``F=2
#: f=0 omega=0.5 l=-1 r=1 wavenumber=2`` 172.7 -> 147.3 CPU s; ``F=1.896 f=0.0929 omega=0.806 l=0.04
#: r=0.64 wavenumber=3.5937 damping=0.369 restitution=0.9`` 92.7, 89.3 -> 88.5, 82.0 (29 of its 44
#: orbits proved at 64 bits instead of 22, none at 128); the issue's first scene 15.5, 13.6, 12.3 ->
#: 14.7, 15.6, 13.0 (its orbits prove at 64 bits either way); the same orbits proved.  (Period by
#: period, with the first ladder's guides cached for the second, the gains looked 2x larger.)
PROOF_LADDER = ((64, 2.0 ** -40), (96, 2.0 ** -60), (128, 2.0 ** -80), (192, 2.0 ** -120), (320, None))


def _section(sc, x, v, period):
    """``(phase, x, v, guide)``: ``reference.enclosure.shooting.section``'s choice of the proof's
    section -- the middle of the longest quiet stretch of flight of the orbit, on the grid of ``T /
    SECTION_GRID`` -- from fast's events and flow (the proof polishes the state; the section only has
    to lie away from the events), instead of two runs of the point integrator; and the point log
    that guides every walk of the proof from there (:func:`_guide`)."""
    import fast
    from fractions import Fraction

    from reference.enclosure.shooting import SECTION_GRID, quiet_middle, rest_stretches

    T = sc.period
    log = fast.events(sc, np.array([x]), np.array([v]), period * T)
    got = [(int(k), float(t)) for k, t in zip(log.kind.reshape(-1), log.t.reshape(-1)) if k >= 0]
    times = [0.0] + [t for _, t in got] + [period * T]
    mid = quiet_middle(times, rest_stretches([fast.KINDS[k] for k, _ in got], v == 0))
    ticks = int(math.floor(SECTION_GRID * mid / T))
    guide = _guide(sc, x, v, period, ticks)
    if ticks == 0:
        return Fraction(0), x, v, guide
    xs, vs = fast.flow(sc, np.array([x]), np.array([v]), T * ticks / SECTION_GRID)
    return Fraction(ticks % SECTION_GRID, SECTION_GRID), float(xs[0]), float(vs[0]), guide


def _guide(sc, x, v, period, ticks):
    """``(log, walls)``: the point log that guides every walk of an orbit's proof (``prove_periodic``'s
    ``points``), from fast: the events of the orbit from its point ``(x, v)`` at 0 over the ``period``
    periods after the section at ``ticks T / SECTION_GRID``, their times moved back by the whole
    periods of that delay (the section's phase is ``ticks`` mod ``SECTION_GRID``), and the walls as
    fast holds them (its impacts sit on them: ``Walk._wall_side``).

    A guide only guides: each walk takes its itinerary, polishes every event time by Newton steps on
    the balls' midpoints and proves the event from the balls (``reference.enclosure.certify``), so a
    log good to float64's digits guides a proof of any precision, and a log with another itinerary
    makes the walk at the centre fail; ``prove_periodic`` then walks each centre with a point log of
    its own (``orbits.UNCENTRED``): never a proof of something else.  Issue 33: the point
    integrator's log at 20 digits (``maps.point_log``), one an orbit, was 4.0 of the 12.8 CPU s of
    the orbit proofs of the issue's first scene (periods 1-3, 34 orbits); with fast's log, on seven
    unseen scenes (103 orbits, periods 1-3, the two guides in turn in one process) and the first
    scene's period 3 (16), every orbit came out the same (proved or not, and the same radius), and
    the proofs took 7.9 -> 5.5 CPU s on the first scene's period 3, 12.7 -> 8.1 CPU s on
    ``F=1.39 f=0.197 omega=1.35 l=-1.38 r=1.51 wavenumber=1.681 damping=0.061 restitution=0.7``,
    76.2 -> 61.8 on ``F=1.896 f=0.0929 omega=0.806 l=0.04 r=0.64 wavenumber=3.5937 damping=0.369
    restitution=0.9`` and 4.1 -> 2.7 on the issue's second scene."""
    import fast
    import mpmath

    from reference.enclosure.shooting import SECTION_GRID
    from reference.integrator import Event, EventLog

    T = sc.period
    start, shift = T * ticks / SECTION_GRID, T * (ticks // SECTION_GRID)
    log = fast.events(sc, np.array([x]), np.array([v]), start + period * T)
    guide, mpf = EventLog(), mpmath.mpf
    guide.t0 = mpf(start - shift)
    for e in log[0]:
        if e.t > start:
            guide.append(Event(e.kind, mpf(e.t - shift), mpf(e.x), mpf(e.v), mpf(e.v_before),
                               e.count if e.kind == "chatter" else None))
    return guide, (mpf(sc.float("l")), mpf(sc.float("r")))


#: how much wider than its box a rung's residual may be predicted to be and the rung still be
#: tried (``_may_hold``: the prediction is ``2^(lost - prec)``, good to a few bits)
RESIDUAL_SLACK = 4.0


#: a failed rung of at least this many bits whose residual ball is at least 1 wide (every bit
#: lost) ends the climb.  A rounding loss of ``prec >= 128`` bits would be an amplification of
#: ``2^128 ~ 3e38``, which would have kept ``fast``'s float64 Newton from converging on the orbit;
#: such a loss comes from elsewhere (near-parabolic centres: ``(P' - I)^-1`` ~1e9 times an
#: enclosure that more bits do not narrow) and more bits do not shrink it.  Issue 33, scene Y
#: (``F=2 f=0 omega=0.5 l=-1 r=1 wavenumber=2``, period 3, ``tr P' = 2 - 1.2e-9``): one centre's
#: residual was 8.0 at 192 bits and 8.1 at 320 (16.4 CPU s), another's 9.5 at 128, and its rung of
#: 320 bits took 7.5 to find Newton diverging.  On eight other scenes (164 orbits, one run) no
#: rung of 128 bits or more left a residual of 1 or more.
WHOLE_LOSS_PREC = 128
#: a failed rung whose ``K(Z)`` missed ``Z`` by more than ``2^(KINK_SHARE prec)`` box radii ends the
#: climb.  The box is walked only once the residual fits in it and ``P'`` at the centre is narrow
#: enough for a box (``|C| rad P' < 1``): for ``P`` smooth over the box the miss ``|K - z~| <=
#: |C G(z~)| + |I - C P'(Z)| r`` is then a few radii ``r`` (~10 where a rung failed on rounding
#: and the next proved: the damped scene below).  A miss of ``2^16`` radii at 64 bits or ``2^24`` at
#: 96 says ``P'`` over the box is that much wider than at its centre: ``P`` is not smooth there (a
#: kink of the map, which the fixed point lies on: the rungs' shrinking boxes keep the same miss),
#: and more bits do not change it.  Issue 33, ``F=1.072 f=0.0075 omega=1.332 l=0.21 r=3.56
#: wavenumber=0.8216 restitution=0.6``: five period-1 points at rest (``v ~ 1e-15``, sticking)
#: missed by ~1.4e-3 at 96 bits (box 8.7e-19: 2^50 radii) and again at 128 (box 8.3e-25), then
#: Newton diverged at 192: 6 to 15 CPU s each, ~42 of the orbits task's ~46; on ``F=2.97 f=0.513
#: omega=1.16 l=0.04 r=0.5 wavenumber=3.553 damping=0.144 restitution=0.7`` a node at rest, (0.393,
#: 0), missed by 5.3e-4 at 96 (2^49 radii) and took 128 bits to diverge, 19 CPU s in all.
KINK_SHARE = 0.25


def _fitted(prec, radius, lost):
    """A rung's box radius: the ladder's ``radius``, widened to four times the residual that a
    loss of ``lost`` bits on a lower rung predicts (``2^(lost - prec + 2)``), but never past
    ``2^-(prec // 2)``, the radius of the ladder before its fourth pass, whose fit to that residual
    :func:`_may_hold` then decides as it did.  Issue 33: scene D's period-3 orbits lost 53 bits at
    64 when ``_may_hold`` was written; after such a loss the box at 128 bits is ``2^-73``, not
    ``2^-80``, which the residual ``2^-75`` would not fit (``None``: the default radius of
    ``prove_periodic``, unchanged)."""
    if radius is None:
        return None
    return min(2.0 ** -(prec // 2), max(radius, 2.0 ** (lost - prec + 2)))


def _spread_at(prec, wide) -> float:
    """The spread of ``P'`` predicted at ``prec`` bits from the rungs that measured it, ``wide``
    (``(bits, spread)`` pairs, in the order tried; ``reference.enclosure.orbits._spread``).

    The flights carry ``P'`` to half the precision, so the spread shrinks ~``2^-(bits / 2)``:
    from one measurement, ``spread 2^-((prec - bits) / 2)``.  From two, at the rate they show
    if that is slower (``log2(s1 / s2) / (b2 - b1)`` a bit, 0 if it grew): a ``P'`` whose width
    is not the flights' rounding -- near-parabolic centres, ``(P' - I)^-1`` ~1e9 -- does not
    narrow with more bits as the model says.  Issue 33, scene Y (``F=2 f=0 omega=0.5 l=-1 r=1
    wavenumber=2``), two period-3 centres with ``tr P' = 2 - 1.1e-9``: spreads 1.6e13 and
    3.9e13 at 64 bits, 8.5e6 and 1.4e8 at 192 (rates 0.16 and 0.14 a bit, against 0.5), and
    their rungs of 320 bits took 16.1 and 7.3 CPU s to fail (a spread of 1.1e9; Newton
    diverging); at the rates measured 320 bits would leave 4.4 and 5e2."""
    bits, spread = wide[-1]
    rate = 0.5
    if len(wide) >= 2:
        (b1, s1), (b2, s2) = wide[-2], wide[-1]
        rate = min(rate, max(0.0, math.log2(s1 / s2) / (b2 - b1)))
    return spread * 2.0 ** (-rate * (prec - bits))


#: the spread of ``P'`` that a rung inserted on a measurement aims at (:func:`_aimed`), and the
#: bits between the rungs it may insert.  Issue 33, ``F=1.896 f=0.0929 omega=0.806 l=0.04 r=0.64
#: wavenumber=3.5937 damping=0.369 restitution=0.9`` (14 of its 16 period-3 saddles fail at 64
#: bits on a spread of 1.1 to 470, and the spread falls as ``2^-(bits / 2)``: 29, 1.5 at 64, 72):
#: a saddle whose spread at 64 bits was 96 proved at 80 bits in 2.0 CPU s, at 88 in 2.6 and at 96
#: in 3.1; on ``F=2 f=0 omega=0.5 l=-1 r=1 wavenumber=2`` a period-3 saddle with a spread of 6.5e5
#: at 64 bits proved at 104 bits in 3.7 CPU s, at 128 in 5.6 (one run each).  The orbits task
#: (periods 1 to 3, the fixed ladder then this one, each in a process of its own, one run each):
#: d1 65.7 -> 58.1 CPU s (14 period-3 saddles proved at 72 to 88 bits instead of 96: their rungs
#: 34.8 -> 28.0 s), ``F=3 f=0.3 omega=0.5 l=-2 r=2 wavenumber=2`` 32.4 -> 28.6 (a saddle at 72
#: instead of 96: 3.7 -> 2.3 s), the same orbits proved, of the same kinds; on Y two period-3
#: saddles proved at 112 and 136 bits instead of 128 and 192 (~5.9 -> 4.0 and ~13 -> 8.8 s).  On
#: fourteen other scenes (the issue's two, four more of its unseen ones, eight random ones of the
#: verify benchmark's distribution) no rung was inserted.
SPREAD_AIM = 0.5
RUNG_STEP_BITS = 8


def _aimed(prec, ladder, wide) -> list:
    """``ladder`` with a rung inserted after a rung of ``prec`` bits that measured ``P'`` too wide
    (``wide``): the fewest bits, a multiple of ``RUNG_STEP_BITS``, where the spread predicted by
    :func:`_spread_at` is at most ``SPREAD_AIM``, with the ladder's box radius ``2^-(5/8 bits)``,
    if that is fewer than those of the first rung above ``prec`` where the spread is predicted
    below 1 (the next one :func:`_may_hold` lets through); else ``ladder`` as it was."""
    above = [bits for bits, _ in ladder if bits > prec and _spread_at(bits, wide) < 1]
    top = above[0] if above else prec
    for bits in range(prec + RUNG_STEP_BITS, top, RUNG_STEP_BITS):
        if _spread_at(bits, wide) <= SPREAD_AIM:
            return sorted(ladder + [(bits, 2.0 ** -(5 * bits // 8))], key=lambda rung: rung[0])
    return ladder


def _may_hold(prec, radius, lost, wide=()) -> bool:
    """Whether a rung of ``PROOF_LADDER`` may hold after a lower one lost ``lost`` bits: its
    residual ``~2^(lost - prec)`` must be within ``RESIDUAL_SLACK`` times the ``2 r`` that the
    Krawczyk test allows (``r`` the rung's box radius, ``2^-(prec // 3)`` by default).  Scene D
    (issue 33): its period-3 orbits lose 53 bits at 64, so the rung of 96 (box 2^-48) is
    skipped and 128 proves them, as it did after 96 failed.

    ``wide``: the ``(bits, spread)`` of the lower rungs that found ``P'`` too wide for any
    Krawczyk box (``reference.enclosure.orbits._spread``, ``spread >= 1``); a rung where the
    spread predicted by :func:`_spread_at` is still 1 or more is skipped.  Issue 33, period-3
    orbits of the frictionless corner (51 events): spreads 6e9, 6.5e4 and 1.2 at 64, 96 and
    128 bits (the model says 9e4 and 1.4 from 64), and 192 proves; each failed rung was a
    whole walk."""
    r = 2.0 ** -(prec // 3) if radius is None else radius
    if wide and _spread_at(prec, wide) >= 1:
        return False
    return 2.0 ** (lost - prec) <= RESIDUAL_SLACK * 2 * r


#: the reason of an orbit not attempted because ``P' - I`` is singular in float64: ``tr P'`` within
#: ``periodic.PARABOLIC_TOL`` of +2 and ``det P'`` within ``claim_unit_det`` of 1 give
#: ``|det(P' - I)| = |det - tr + 1| <= 2e-9``, so ``C = (P' - I)^-1`` is at least ~5e8 and the first
#: rung's box (``2^-32`` when this was measured) could not contract: ``C`` times the spread of ``P'``
#: over it was ~1.  Issue 33:
#: on the frictionless far corner ``F=2 f=0 omega=0.5 l=-1 r=1 wavenumber=2`` (families of fixed
#: points) the 16 such attempts took 10.2 of the orbits' ~105 CPU s; in the reports of this issue's
#: sweeps none of 936 parabolic points was ever proved.  A flip-parabolic point (``tr ~ -2``:
#: ``det(P' - I) ~ 4``) is still tried.
SINGULAR = ("not attempted: parabolic with tr P' ~ +2 in float64 (|tr - 2| <= PARABOLIC_TOL, |det - 1| "
            "<= claim_unit_det): det(P' - I) ~ 0, whose inverse the Krawczyk operator needs")

#: ``|tr P' - 2|`` in float64 within which a centre or saddle of an area-preserving map is tried on
#: the first rung only, as a parabolic one (``_first_rung_only``): the members of a family of fixed
#: points, whose ``P' - I`` is singular, scatter this far from 2 in float64 (the traces at points
#: that fast's Newton leaves up to its ``tol``, 1e-11, off the family).  Issue 33, the frictionless corners
#: ``F=2 f=0 omega=0.5 l=-1 r=1 wavenumber=2`` and ``F=3 f=0 omega=0.5 l=-2 r=2 wavenumber=2``
#: (periods 1 to 3, 647 points found): the members' ``|tr - 2|`` run from 1e-15 to 1.3e-9, past
#: ``PARABOLIC_TOL``; the next point lies at 3.6e-8 (an elliptic centre, ``1 +- 1.9e-4 i``, proved at
#: 192 bits).  The eight members between 1e-9 and 1.3e-9 were classed centres or saddles: their rungs of 192
#: and 320 bits failed (``P'`` too wide: at 192 bits ``|(P' - I)^-1|`` ~1e24 once Newton reached
#: the family, or Newton diverging), ~12 CPU s on the first scene and ~49 on the second.  In the
#: reports of this issue's sweeps (108 scenes, 1,978 orbits) the proved centres nearest ``tr = 2``
#: are that one and one at 2.3e-4.
FAMILY_TOL = 1e-8
#: ``|tr P' - 1|`` in float64 within which a point whose ``P'`` has rank one (``|det P'| <=
#: RANK_ONE_DET``: the orbit sticks and forgets its speed) is tried on the first rung only, as a
#: parabolic one (``_first_rung_only``): its other multiplier ~1 says the rest state it returns to
#: barely moves with its start -- the edge of a family of rest states (``|F cos k x| = f``), where
#: ``P`` has a kink.  Issue 33, ``F=1.072 f=0.0075 omega=1.332 l=0.21 r=3.56 wavenumber=0.8216
#: restitution=0.6``: four period-1 points at rest at ``x = 1.903`` and ``1.920`` (``F cos k x =
#: 0.0075 = f``), ``tr = 1 - 1.7e-6`` to ``1 - 6.9e-6``, ``det = 0``: two missed their boxes by
#: ``2^50`` radii at 96 bits (``KINK_SHARE``), two lost 27 and 38 bits at 64 and 96 and took 4.3 and
#: 6.1 CPU s at 128 to find Newton diverging; on ``F=2.97 f=0.513 omega=1.16 l=0.04 r=0.5
#: wavenumber=3.553 damping=0.144 restitution=0.7`` a node at rest, ``tr = 1 - 9.7e-6``, the same.
#: On fourteen other scenes (the issue's two, d1, D, W, R3 and eight random ones of the verify
#: benchmark's distribution; periods 1 to 3, 16 x 16 seeds) no isolated point had ``|det(P' -
#: I)| < 1e-4``.  The orbits task (periods 1 to 3, without the rule then with it, each in a
#: process of its own, one run each): S 19.3 -> 8.7 CPU s, P3 12.3 -> 3.5 (its node's rung of 96
#: bits took 8.0), the same orbits proved.
REST_EDGE_TOL = 1e-4
RANK_ONE_DET = 1e-12


def _first_rung_only(p) -> str | None:
    """Why an orbit is tried on the first rung alone, or None: flip-parabolic in float64 (``|tr +
    2| <= periodic.PARABOLIC_TOL``: Newton converges only linearly), a centre or saddle of an
    area-preserving map within ``FAMILY_TOL`` of ``tr = +2`` (a family's member, most likely), or
    a point of rank-one ``P'`` within ``REST_EDGE_TOL`` of ``tr = 1`` (the edge of a family of
    rest states)."""
    if p.kind == "parabolic":
        return f"parabolic in float64 (tr within {periodic.PARABOLIC_TOL:g} of +-2: det(P' - I) ~ 0)"
    if (p.kind in ("centre", "saddle") and abs(p.trace - 2) <= FAMILY_TOL
            and abs(p.det - 1) <= periodic.AREA_TOL):
        return (f"tr P' = 2 {p.trace - 2:+.1e} in float64, within {FAMILY_TOL:g} of a family of fixed "
                f"points' (det(P' - I) ~ 0; FAMILY_TOL)")
    if abs(p.det) <= RANK_ONE_DET and abs(p.trace - 1) <= REST_EDGE_TOL:
        return (f"P' of rank one with tr P' = 1 {p.trace - 1:+.1e} in float64: a rest state at the "
                f"edge of a family of them (det(P' - I) ~ 0, P not smooth; REST_EDGE_TOL)")
    return None


def proof(label, sc, p, period, seg) -> dict:
    """The Krawczyk proof record of one orbit (``paper.claims.base.prove``), up the
    ``PROOF_LADDER`` (a segment of no-impact fixed points: ``prove_segment`` at its default); a
    proof that raises is a failed one, with the reason.  One point log, fast's events from the
    section on (:func:`_guide`), guides the walks of every rung (``prove_periodic``'s ``points``).

    An orbit that ``fast`` finds flip-parabolic (``|tr P' + 2| <= periodic.PARABOLIC_TOL``: Newton
    converges only linearly) is tried on the first rung alone, and so is a centre or saddle of an
    area-preserving map within ``FAMILY_TOL`` of ``tr = +2`` and a point of rank-one ``P'`` within
    ``REST_EDGE_TOL`` of ``tr = 1`` (:func:`_first_rung_only`); one
    fast finds parabolic with ``tr P' ~ +2`` is not tried (``SINGULAR``: ``det(P' - I)`` is ~0).
    Issue 33: on the frictionless scene ``F=2
    f=0 omega=0.5 l=-1 r=1 wavenumber=2`` 127 of the 138 period-1 points are parabolic (families
    of fixed points), and each failed up the whole ladder in ~32 CPU s (128 bits: 9.9, 320: 21.9);
    ``orbits`` gives its ``max_proofs`` to the other orbits first.  Where Newton diverges
    (``reference.enclosure.orbits.DIVERGE_GROWTH``) no rung is tried after it: on that scene a
    period-2 saddle's rungs of 192 and 320 bits took 37 CPU s to fail so.  Nor after two rungs
    whose ``P'`` was too wide, narrowing at a rate that leaves the rungs above too wide
    (:func:`_spread_at`; a rung that measured the spread has the ladder try next the fewest bits
    where it is predicted to be ``SPREAD_AIM``: :func:`_aimed`), nor after a rung whose ``K(Z)``
    missed its box by more than
    ``2^(KINK_SHARE prec)`` radii (``P`` not smooth there).  A rung whose Newton converged before
    its Krawczyk test failed hands its centre to the next as the seed (``prove``'s ``centre``):
    scene Y's period-3 orbits that prove at 192 bits took three Newton walks there from the
    section's float64 state, one from the centre of 128.  The multipliers come from ``P'`` over
    the Krawczyk box where that decides the type (``prove_periodic``'s ``tight=False``: the
    report gives them to 4 digits), one walk fewer a proof."""
    if p.kind == "parabolic" and p.trace > 0:
        return {"orbit": label, "periods": period, "proved": False, "reason": SINGULAR}
    try:
        if seg is not None:
            return prove(label, sc, p.x, p.v, k=period, segment=seg)
        phase, x, v, guide = _section(sc, p.x, p.v, period)
        first_only = _first_rung_only(p)
        ladder = list(PROOF_LADDER[:1] if first_only else PROOF_LADDER)
        lost, wide, stalled, i = 0.0, [], False, -1
        while i + 1 < len(ladder):
            i += 1
            prec, radius = ladder[i]
            radius = _fitted(prec, radius, lost)
            # the last rung is tried unless two measured spreads rule it out (``_spread_at``)
            stalled = len(wide) > 1 and _spread_at(prec, wide) >= 1
            if not _may_hold(prec, radius, lost, wide) and (prec != ladder[-1][0] or stalled):
                continue
            rec = prove(label, sc, x, v, k=period, prec=prec, radius=radius, phase=phase, points=guide,
                        tight=False)
            x, v = rec.pop("centre", (x, v))                # polished: the next rung's seed
            if rec["proved"] or rec.get("diverged"):       # more bits take Newton's same path
                return rec
            if radius is not None and rec.get("miss", 0.0) > 2.0 ** (KINK_SHARE * prec) * radius:
                rec["reason"] += (f" ({rec['miss'] / radius:.1e} box radii: P is not smooth over the box, "
                                  f"which more bits do not change; no higher rung is tried)")
                return rec
            if rec.get("spread"):
                wide.append((prec, rec["spread"]))
                ladder = _aimed(prec, ladder, wide)
            if rec.get("residual"):
                lost = max(lost, math.log2(rec["residual"]) + prec)
                if prec >= WHOLE_LOSS_PREC and rec["residual"] >= 1:
                    rec["reason"] += (f" (every one of the {prec} bits lost: not a rounding loss, "
                                      f"which more bits would shrink; no higher rung is tried)")
                    return rec
        if stalled:                 # the loop ended on the last rung, skipped
            rec["reason"] += (f" (P' narrowed from {wide[-2][1]:.2g} at {wide[-2][0]} bits to "
                              f"{wide[-1][1]:.2g} at {wide[-1][0]}: at that rate {prec} bits would "
                              f"leave {_spread_at(prec, wide):.2g}; no higher rung is tried)")
        if first_only:
            rec["reason"] = f"{first_only}, tried at {ladder[0][0]} bits only: {rec['reason']}"
        return rec
    except (ValueError, RuntimeError, ArithmeticError) as exc:
        return {"orbit": label, "periods": period, "proved": False, "reason": f"{type(exc).__name__}: {exc}"}
