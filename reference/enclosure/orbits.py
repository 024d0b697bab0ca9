"""Computer-assisted proofs of periodic orbits: the Krawczyk operator on ``Phi^k(z) - z``.

For a box ``Z`` around an approximate fixed point ``z~`` of ``P = Phi^k`` with a fixed
itinerary, and any real matrix ``C`` (here ``(P'(z~) - I)^-1`` from midpoints),

    K(Z) = z~ - C (P(z~) - z~) + (I - C (P'(Z) - I)) (Z - z~).

If ``K(Z)`` lies in the interior of ``Z``, then ``P`` has exactly one fixed point in ``Z``, and
it lies in ``K(Z)`` (Krawczyk 1969; Neumaier, *Interval Methods for Systems of Equations*,
1990, Thm 5.1.8).  ``P(z~)`` and ``P'(Z)`` are enclosures of ``reference.enclosure.maps`` (the
latter over the whole box, which also proves that every state of the box has the same
itinerary, so that ``P`` is smooth there).  Under position forcing one walk over ``Z`` gives
both, ``P(z~)`` from the centre that its validated flights track (``_tracked``), with ``C``
from ``mid P'(Z)``; where that test fails, Newton goes on from it by walks from points.

The multipliers are the eigenvalues of ``P'`` at the fixed point, enclosed by those of ``P'(K)``
through ``tr`` and ``det``: ``lambda = (tr +- sqrt(tr^2 - 4 det)) / 2``.  The type follows when
the enclosures decide it: a saddle (real, ``|l1| > 1 > |l2|``), an attracting focus or node
(``|l| < 1``: hyperbolic, so attracting for the map too, by Hartman-Grobman), or -- without
friction, restitution and damping, where every Table 1 factor has determinant 1, so ``det P' = 1``
exactly -- an elliptic point (non-real multipliers on the unit circle).  Whether an elliptic
point is *nonlinearly* stable is not decided here (that needs KAM-type arguments); and a fixed
point that is not isolated (``det(P' - I) = 0``, a family of fixed points) cannot pass the test.
"""
from __future__ import annotations

import time
from fractions import Fraction

from flint import arb, arb_mat

from reference.api import check_count
from reference.enclosure.balls import DEFAULT_PREC, from_number, workprec
from reference.enclosure.shooting import krawczyk, section
from reference.enclosure.balls import span as span_ball
from reference.enclosure.kinds import UNDECIDED, OrbitProof, classify
from reference.enclosure.maps import MapEnclosure, check_phase, enclose_map, point_log
from reference.enclosure.params import ParamBox

#: Newton steps on the midpoints before the proof (each one enclosure of ``P`` at a point).
NEWTON_STEPS = 30
#: The last Newton step ``s`` is taken in mean-value form (no enclosure at the new centre,
#: ``_krawczyk``) once ``|s| <= r / STEP_SHARE``: the box widens by that much, the head by
#: ~``1 / STEP_SHARE`` of the Krawczyk tail.  (Taking it from ``|s| <= 16 r``, with a retry at
#: ``r / 4`` when that wider box failed, saved a point log a proof before one log guided them
#: all; with it, 5 walks of 70 on scene F's period 3 and a failed box on D's: no gain.)
STEP_SHARE = 4
#: the reason of a centre whose walk fails: with a shared point log, the log may have misled it
UNCENTRED = "at the centre is not proved"
#: Newton diverges (``_newton``) when a step is more than ``DIVERGE_GROWTH`` times the one before
#: and that one was at most ``DIVERGE_AFTER`` (the iteration had converged to a few digits: the
#: first steps of a wide seed may grow).  Then ``P' - I`` is near-singular or ``P`` is not smooth
#: near the seed, and more bits take the same path, to the same failure.  Issue 33, the
#: frictionless scene ``F=2 f=0 omega=0.5 l=-1 r=1 wavenumber=2``: a period-2 saddle's steps fell
#: to 1.7e-6 and then jumped to 0.2, the next one out of the gap; with the walk of each far iterate
#: and a second pass without the point log, its rungs of 192 and 320 bits took 12 and 25 CPU s.
DIVERGE_GROWTH = 1e3
DIVERGE_AFTER = 2.0 ** -12
DIVERGES = "Newton diverges"


class _Diverged(Exception):
    """``_newton``'s iteration diverges (``DIVERGE_GROWTH``)."""


class _TooWide(Exception):
    """``P'`` at a Newton centre is too wide for a Krawczyk box at this precision
    (:func:`_spread`): the next rung's bits narrow it."""

    def __init__(self, spread: float, message: str):
        super().__init__(message)
        self.spread = spread


def _spread(J, C):
    """``max_i sum_j (|C| rad P')_ij`` with ``C = (mid (P' - I))^-1`` (Newton's own, ``_newton``)
    and ``J = P'``.

    Krawczyk's ``I - C (P'(B) - I)`` has entrywise radii at least ``|C| rad P'(B)``, and
    ``P'(B)`` over a box holds ``P'`` at its centre: at a spread of 1 or more no box contracts,
    whatever Newton does.  Issue 33: with the walk's set handed through events
    (``reference.enclosure.handoff``) a 51-event period-3 walk of the frictionless scene
    ``F=2 f=0 omega=0.5 l=-1 r=1 wavenumber=2`` proves at 96 bits, where it failed before, but
    its ``P'`` (the flights' derivative to half the precision, wrapped over 51 factors) is
    +-0.5 wide; Newton on its midpoint wandered for 50 CPU s and was declared divergent, so the
    192-bit rung that proves the orbit was never tried."""
    return max(sum(abs(C[i][k]) * J[k][j].rad() for k in range(2) for j in range(2))
               for i in range(2))


def _mat_sub_identity(J):
    return [[J[0][0] - 1, J[0][1]], [J[1][0], J[1][1] - 1]]


def _newton_matrix(J):
    """``(M, det M)`` with ``M = mid(P' - I)``, ``P' = J``: Newton's and Krawczyk's ``C = M^-1``."""
    M = _mid(_mat_sub_identity(J))
    return M, M[0][0] * M[1][1] - M[0][1] * M[1][0]


def _inverse(M):
    det = M[0][0] * M[1][1] - M[0][1] * M[1][0]
    return [[M[1][1] / det, -M[0][1] / det], [-M[1][0] / det, M[0][0] / det]]


def _mid(M):
    return [[M[i][j].mid() for j in range(2)] for i in range(2)]


def _matvec(M, z):
    return [M[0][0] * z[0] + M[0][1] * z[1], M[1][0] * z[0] + M[1][1] * z[1]]


def _newton(scene, z, periods, phase, prec, small=None, points=None, first=None):
    """Polish ``z`` on midpoints: ``z <- z - s``, ``s = (P' - I)^-1 (P(z) - z)``, one enclosure
    of ``P`` at a point (a walk guided by ``points``, else by a point log of its own) per step.
    Returns ``(z, enc, ahead)``: the last centre, the enclosure there and the next iterate
    ``z - s`` computed from it but not enclosed (``None`` if none: ``enc`` unproved or ``P' - I``
    singular).  The loop ends once the step is at most ``small`` or within the enclosure's own
    noise: ``_krawczyk`` then takes it in mean-value form over the box around ``z`` (issue 33:
    the enclosure at ``z - s`` only confirmed convergence).  Raises ``_Diverged`` where the
    steps, once small, grow by ``DIVERGE_GROWTH``: the far iterate is not walked; ``_TooWide``
    where ``P'`` is too wide for any Krawczyk box at ``prec`` (:func:`_spread`).  ``first``:
    an enclosure at ``z`` already made (:func:`_tracked`), in place of the first walk."""
    last = None
    for i in range(NEWTON_STEPS):
        enc = first if i == 0 and first is not None else enclose_map(
            scene, z[0], z[1], periods=periods, phase=phase, prec=prec, max_prec=prec, points=points)
        if not enc.proved:
            return z, enc, None
        M, det = _newton_matrix(enc.jacobian)
        if det.is_zero():
            return z, enc, None
        C = _inverse(M)
        spread = _spread(enc.jacobian, C)
        if not spread < 1:
            spread = float(spread.upper())
            raise _TooWide(spread, f"P' at the centre is too wide for a Krawczyk box at {prec} "
                                   f"bits: |(P' - I)^-1| rad P' = {spread:.2g} >= 1 (more bits "
                                   f"narrow it)")
        step = _matvec(C, [enc.phi[0].mid() - z[0], enc.phi[1].mid() - z[1]])
        new = [(z[0] - step[0]).mid(), (z[1] - step[1]).mid()]
        if (new == z or all(abs(step[i]) <= 4 * enc.phi[i].rad() for i in range(2))
                or (small is not None and all(abs(step[i]) <= small for i in range(2)))):
            return z, enc, new      # converged: the step is within the noise, or small enough
        size = float(max(abs(step[0]), abs(step[1])).upper())
        if last is not None and last <= DIVERGE_AFTER and size > DIVERGE_GROWTH * last:
            raise _Diverged(f"{DIVERGES}: its step grew from {last:.1e} to {size:.1e} at "
                            f"({float(z[0]):.6g}, {float(z[1]):.6g}) (P' - I near-singular, or P "
                            f"not smooth there; more bits take the same path)")
        z, last = new, size
    return z, enc, None


def prove_periodic(scene, x, v, *, periods=1, phase=None, radius=None,
                   prec=DEFAULT_PREC, points=None, tight=True) -> OrbitProof:
    """Prove a fixed point of ``Phi^periods`` near ``(x, v)`` (numbers as in ``enclose_map``).

    ``phase`` (rational in ``[0, 1)``) takes the section ``t = phase T`` instead of ``t = 0``
    (an orbit with an impact or a stop at ``t = 0`` has no box there with one itinerary; the
    orbit is the same, the fixed point is its state at that phase); ``None`` (default) picks
    it in the longest stretch between events (``(x, v)`` is then the state at ``t = 0``).  ``radius``: the
    half-width of the box (default ``2^(-prec/3)``: wide enough to hold the fixed point after
    Newton, narrow enough that the wrapping of a long itinerary stays small).  ``points``: the
    point log (``maps.point_log``, from the seed at ``phase``, at any precision) that guides the
    walk of every enclosure of the proof (``enclose_map``'s ``points``: each walk proves every
    event from the balls); None: made here from the seed.  One log serves the Newton iterates,
    the box and the orbit's ball (issue 33: the point integrator was 44% to 70% of a
    position-forced proof, a log per centre); if the walk of a Newton centre fails with it (a log from too far,
    with another itinerary), the proof is made again with a log per centre.  ``tight``: the
    multipliers from ``P'`` over ``K`` (one more walk); False: from ``P'`` over the Krawczyk box
    where that decides the type (``_krawczyk``), their balls wider by about the box's radius.

    ``scene`` may be a :class:`~reference.enclosure.params.ParamBox`: the proof then holds for
    every parameter of the box (``reference.enclosure.boxes``: the state boxes are found by
    epsilon-inflation, so ``radius`` must be None); a point box is its scene.
    """
    if isinstance(scene, ParamBox):
        if scene.is_point:
            scene = scene.scene()
        else:
            if radius is not None:
                raise ValueError("prove_periodic: over a parameter box the state box is found by "
                                 "inflation; radius must be None")
            from reference.enclosure.boxes import prove_periodic_box  # boxes builds on this module
            return prove_periodic_box(scene, x, v, periods=periods, phase=phase, prec=prec)
    check_count("periods", periods, 1)
    start = time.perf_counter()
    with workprec(prec):
        if phase is None:
            phase, x, v = section(scene, x, v, periods, prec)
        phase = check_phase(phase)
        r = arb(2) ** (-(prec // 3)) if radius is None else from_number(radius)
        seed = [from_number(x).mid(), from_number(v).mid()]
        guide = points if points is not None else point_log(scene, *seed, periods, phase, prec)
        proof = _polished(scene, seed, r, periods, phase, prec, guide, tight)
        if not proof.proved and UNCENTRED in proof.reason:     # misled by the guide? each its own
            proof = _polished(scene, seed, r, periods, phase, prec, None, tight)
        proof.phase = phase
        proof.seconds = time.perf_counter() - start
        return proof


def _polished(scene, seed, r, periods, phase, prec, points, tight=True):
    """The Krawczyk test on the box around ``seed`` alone where its walk tracks the centre
    (:func:`_tracked`), else Newton from ``seed`` (from that walk's enclosure at the centre, if
    made) until its step is at most ``r / STEP_SHARE``, then the Krawczyk test (a diverging
    Newton is a failed proof, with ``diverged``)."""
    box, centre = _tracked(scene, seed, r, periods, phase, prec, points)
    if centre is not None:
        proof = _in_box(scene, seed, r, periods, phase, prec, box, centre, points, tight)
        if proof is not None:
            return proof
    try:
        z, enc, ahead = _newton(scene, seed, periods, phase, prec, r / STEP_SHARE, points, centre)
    except _Diverged as exc:
        return OrbitProof(False, periods, reason=str(exc), prec=prec, radius=float(r), diverged=True)
    except _TooWide as exc:
        return OrbitProof(False, periods, reason=str(exc), prec=prec, radius=float(r),
                          spread=exc.spread)
    return _krawczyk(scene, z, r, periods, phase, prec, enc, ahead, points, tight)


#: the events a box walk tracks its centre through (``reference.enclosure.walk``: flights, the
#: hand-offs of impacts and turns, stops and slips); another in the guide, and it is not tried
TRACKED_KINDS = frozenset(("impact", "turn", "stick", "slip"))


def _tracked(scene, z, r, periods, phase, prec, points):
    """``(box, centre)``: the walk over ``Z = z +- r`` and, from the centre it tracks
    (``MapEnclosure.phi_at_centre``), an enclosure at ``z`` with ``P'(Z)`` for ``P'``
    (``P'(z)`` lies in it: Newton's ``C`` may be any real matrix); ``(None, None)`` where no
    such walk applies: without position forcing (the closed-form flights track nothing), without
    a guide, or with a guide whose events the walk does not track through (``TRACKED_KINDS``);
    ``(box, None)`` where the walk failed or lost its centre, or where ``P'(Z)`` is too wide for
    Newton's test (:func:`_spread`, which measures the precision's share at a point: Newton then
    walks the point).

    Issue 33: a proof took one walk from the point ``z`` (Newton's first, which found it
    converged) and one over the box; the box's walk alone now gives ``P(z)`` to within a point
    walk's width (the doubleton sets of ``lohner.ValidatedFlight.point_state``)."""
    if not points or not scene.has("position_forcing"):
        return None, None
    if any(ev.kind not in TRACKED_KINDS for ev in points[0]):
        return None, None
    box = enclose_map(scene, z[0], z[1], periods=periods, phase=phase, x_radius=r, v_radius=r,
                      prec=prec, max_prec=prec, points=points)
    if not box.proved or box.phi_at_centre is None:
        return box, None
    M, det = _newton_matrix(box.jacobian)
    if det.is_zero() or not _spread(box.jacobian, _inverse(M)) < 1:
        return box, None        # P'(Z) too wide for Newton's own test: it walks the point (_TooWide)
    return box, MapEnclosure(True, phi=box.phi_at_centre, jacobian=box.jacobian,
                             events=box.events, prec=prec, pieces=box.pieces)


def _in_box(scene, z, r, periods, phase, prec, box, centre, points, tight):
    """The Krawczyk test on ``Z = z +- r`` from its walk ``box`` alone: ``P(z)`` from
    ``centre`` (:func:`_tracked`), ``C = (mid P'(Z) - I)^-1``, ``K = z - C (P(z) - z) + (I - C
    (P'(Z) - I)) (Z - z)``.  The proof if ``K`` lies in the interior of ``Z``, else None (then
    Newton goes on from ``centre``)."""
    M, det = _newton_matrix(box.jacobian)
    if abs(det) < arb(2) ** (-prec // 2):
        return None
    C = arb_mat(_mid(_inverse(M)))
    head = C * arb_mat([[centre.phi[0] - z[0]], [centre.phi[1] - z[1]]])
    K, inside = krawczyk(z, head, C, arb_mat(_mat_sub_identity(box.jacobian)), [r, r])
    if not inside:
        return None
    return _typed(scene, K, periods, phase, prec, r, centre, box, points, tight)


def _krawczyk(scene, z, r, periods, phase, prec, enc_mid, ahead=None, points=None, tight=True):
    """The Krawczyk test on ``Z = z~ +- r`` with ``enc_mid`` the enclosure of ``P`` at the
    point ``z``, and ``z~ = ahead`` (a last Newton step from ``z``, not enclosed) or ``z``.

    No enclosure at ``z~`` (issue 33: it only confirmed convergence): the box ``B = z +- (r +
    |z~ - z|)``, which holds ``Z`` and the segment ``[z, z~]``, gives ``P'(B)``, hence ``F(z~) in
    F(z) + (P'(B) - I)(z~ - z)`` (mean value, ``F = P - id``) and the tail ``(I - C (P'(B) -
    I))(Z - z~)``: Krawczyk's operator with ``P'`` enclosed over a box that contains ``Z``, still
    a proof.  The multipliers come from ``P'`` over ``K`` (the orbit's state; ``P'(B)`` if that
    walk fails; ``tight=False``: ``P'(B)`` where its enclosures decide the type, one walk fewer:
    issue 33, the walks over ``K`` were 2.0 of 13.8 and 2.9 of 27.0 CPU s of two unseen scenes'
    orbit proofs).  The test cannot pass if ``C F(z)`` alone is wider than ``Z`` (``K`` holds
    it): then the box is not walked.  ``points``: the point log that guides every walk.  A test
    that fails once the centre is proved and ``P' - I`` invertible there gives ``z~`` as
    ``centre``: a seed for more bits (issue 33: a rung of 192 bits from the seed took three
    Newton walks before its box, scene Y's period-3 orbits, where one does from a centre
    polished at 128)."""
    fail = OrbitProof(False, periods, prec=prec, radius=float(r))
    if not enc_mid.proved:
        fail.reason = f"Phi^{periods} {UNCENTRED}: {enc_mid.reason}"
        return fail
    M, det_m = _newton_matrix(enc_mid.jacobian)
    if abs(det_m) < arb(2) ** (-prec // 2):
        fail.reason = ("det(P' - I) vanishes at the centre: the fixed point is not isolated "
                       "(a family of fixed points), which no Krawczyk box can single out")
        return fail
    zt = z if ahead is None else ahead
    fail.centre = tuple(zt)
    C = arb_mat(_mid(_inverse(M)))
    head = C * arb_mat([[enc_mid.phi[0] - z[0]], [enc_mid.phi[1] - z[1]]])
    if any(head[i, 0].rad() > 2 * r for i in range(2)):     # rad K >= rad head > 2 r
        radii = [float(head[i, 0].rad()) for i in range(2)]
        fail.reason = (f"K(Z) is not inside Z (radius {float(r):.1e}): the residual alone, "
                       f"|C (P(z) - z)|, has radii {radii}")
        fail.residual = max(radii)
        return fail
    d = [zt[0] - z[0], zt[1] - z[1]]
    box = enclose_map(scene, z[0], z[1], periods=periods, phase=phase, x_radius=(r + abs(d[0])).upper(),
                      v_radius=(r + abs(d[1])).upper(), prec=prec, max_prec=prec, points=points)
    if not box.proved:
        fail.reason = f"the itinerary is not proved constant on the box of radius {float(r):.1e}: {box.reason}"
        return fail
    DF = arb_mat(_mat_sub_identity(box.jacobian))
    if ahead is not None:
        head = head + C * (DF * arb_mat([[d[0]], [d[1]]]))
    K, inside = krawczyk(zt, head, C, DF, [r, r])
    if not inside:
        miss = [float(abs(K[i] - zt[i]).upper()) for i in range(2)]
        fail.reason = f"K(Z) is not inside Z (radius {float(r):.1e}): |K - z| = {miss}"
        fail.miss = max(miss)
        return fail
    return _typed(scene, K, periods, phase, prec, r, enc_mid, box, points, tight)


def _typed(scene, K, periods, phase, prec, r, enc_mid, box, points, tight):
    """The proof of the fixed point in ``K``: its multipliers from ``P'`` over ``K`` (one more
    walk), or over the Krawczyk box's walk ``box`` where ``tight`` is False and that decides
    the type (or the walk over ``K`` fails)."""
    if not tight:
        loose = _multipliers(scene, K, periods, prec, r, enc_mid, box)
        if loose.kind not in UNDECIDED:
            return loose
    over_k = enclose_map(scene, K[0].mid(), K[1].mid(), periods=periods, phase=phase, x_radius=K[0].rad(),
                         v_radius=K[1].rad(), prec=prec, max_prec=prec, points=points)
    return _multipliers(scene, K, periods, prec, r, enc_mid, over_k if over_k.proved else box)


def _multipliers(scene, K, periods, prec, r, enc_mid, enc):
    J = enc.jacobian
    tr = J[0][0] + J[1][1]
    det = J[0][0] * J[1][1] - J[0][1] * J[1][0]
    kind, stability, mults = classify(scene, tr, det, [e.kind for e in enc.events])
    return OrbitProof(True, periods, point=tuple(K), radius=float(r), multipliers=mults,
                      trace=tr, det=det, kind=kind, stability=stability,
                      itinerary=[e.kind for e in enc_mid.events], prec=prec)


def prove_segment(scene, x_lo, x_hi, v, *, prec=DEFAULT_PREC) -> OrbitProof:
    """Prove a segment of fixed points ``[x_lo, x_hi] x {v*}`` of ``Phi``: the no-impact orbits.

    Away from the walls the motion is translation-invariant, so the fixed points of ``Phi`` are
    never isolated and :func:`prove_periodic` cannot single one out.  Instead, with ``H`` the
    half-period map and ``X = [x_lo, x_hi]``:

    1. a 1D Krawczyk step proves a unique ``v*`` in a ball ``V`` with ``H_v(x0, v*) = -v*`` for
       every ``x0`` in ``X`` (``H_v`` does not depend on ``x0``; no wall is reached from ``X x V``);
    2. the equation is odd under ``x -> -x(t + T/2) + c`` (friction odd, forcing anti-periodic),
       so by forward uniqueness that solution satisfies ``x(t + T/2) = x(0) + x(T/2) - x(t)``,
       hence ``Phi(x0, v*) = (x0, v*)`` for every ``x0`` in ``X``;
    3. a second 1D Krawczyk step on ``Phi_v(x0, v) - v`` proves ``v*`` the only ``v`` in ``V``
       with ``Phi_v = v``: the fixed points of ``Phi`` in ``X x V`` are exactly the segment.

    The multipliers are ``1`` (along the segment, exactly) and ``dPhi_v/dv`` (enclosed).
    """
    start = time.perf_counter()
    with workprec(prec):
        X = span_ball(from_number(x_lo), from_number(x_hi))
        v = from_number(v).mid()
        half = Fraction(1, 2)
        fail = OrbitProof(False, 1, prec=prec)
        for _ in range(NEWTON_STEPS):          # polish v on H_v(v) + v = 0
            enc = enclose_map(scene, X.mid(), v, periods=half, prec=prec, max_prec=prec)
            if not enc.proved:
                fail.reason = f"the half-period map is not proved: {enc.reason}"
                return fail
            step = ((enc.phi[1] + v) / (enc.jacobian[1][1] + 1)).mid()
            if step.is_zero() or abs(step) < abs(v) * arb(2) ** (-prec + 8):
                break
            v = (v - step).mid()
        r = arb(2) ** (-(prec // 3))
        V = arb(v, r)
        for periods, sign in ((half, 1), (1, -1)):      # H_v + v = 0, then Phi_v - v = 0
            box = enclose_map(scene, X.mid(), v, periods=periods, x_radius=X.rad(), v_radius=r,
                              prec=prec, max_prec=prec)
            centre = enclose_map(scene, X.mid(), v, periods=periods, x_radius=X.rad(),
                                 prec=prec, max_prec=prec)
            if not (box.proved and centre.proved) or any(e.kind == "impact" for e in box.events):
                fail.reason = (f"the {'half-' if periods == half else ''}period map over the "
                               f"segment box is not proved without impacts: {box.reason}")
                return fail
            slope = box.jacobian[1][1] + sign
            Y = 1 / (centre.jacobian[1][1] + sign).mid()
            K = v - Y * (centre.phi[1] + sign * v) + (1 - Y * slope) * (V - v)
            if not V.contains_interior(K):
                fail.reason = f"1D Krawczyk for v* failed ({'H_v + v' if sign > 0 else 'Phi_v - v'})"
                return fail
        mult = box.jacobian[1][1]
        kind = "segment of fixed points (no impact)"
        stability = ("normally attracting: multipliers 1 (along the segment) and "
                     f"{'< 1' if abs(mult) < 1 else 'not < 1'} in |.| (proved)")
        return OrbitProof(True, 1, point=(X, K), radius=float(r), multipliers=[arb(1), mult],
                          trace=1 + mult, det=mult, kind=kind, stability=stability,
                          itinerary=[e.kind for e in box.events], prec=prec,
                          seconds=time.perf_counter() - start)
