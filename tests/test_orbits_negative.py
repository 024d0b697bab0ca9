"""Orbit proofs refuse false statements (issue 24): ``reference.enclosure.orbits``.

* A centre displaced outside its Krawczyk ball (the fixed point is not in the box): refused.
  ``prove_periodic`` always polishes its centre by Newton steps, so the displaced centre is
  posed one level down, to ``orbits._krawczyk`` (centre and radius given), which
  ``prove_periodic`` calls with the polished centre.
* The last Newton step taken in mean-value form (``_krawczyk``'s ``ahead``: its residual from
  the enclosure at the previous centre, no point log of its own; issue 33): an iterate more than
  the box radius from the fixed point is refused, one a quarter of it away is proved with the
  closed-form multipliers; a residual ball wider than the box is refused before any box walk;
  a point log from elsewhere (``points``, the guide of every walk of a proof) proves nothing
  wrong, and the proof is made again with a log per centre.
* A box wide enough to hold two fixed points (x1 and x2 near the fold ``f/F -> 2/pi``, one
  itinerary): refused by the public ``prove_periodic(..., radius=...)``.
* The type comes from the multiplier enclosures only: the saddle handed over as if it were the
  centre is proved a saddle; a dissipative itinerary (turns, restitution, damping) never gets
  the conservative ``det = 1`` and so never "elliptic"; a trace ball straddling 2 or -2, a
  real multiplier straddling +-1, or ``det`` straddling 1 leave the type undecided.
* A segment of fixed points with the wrong velocity: refused (``prove_segment``'s Newton
  polish switched off, as the only way to pose it).
* A box proof (``enclose_map`` over a box: ``P'(Z)`` of the Krawczyk step) holds the images of
  the box's corners, so a proof over a smaller box than the one claimed is caught.

Each false statement has a true twin, one step away, that the same call proves.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath
import pytest
from flint import arb

import reference
from cross_check import scenes
from reference import paper
from reference.enclosure import enclose_map, orbits, prove_periodic, prove_segment
from reference.enclosure.balls import DEFAULT_PREC, from_mpf, workprec
from reference.enclosure.orbits import classify

PREC = DEFAULT_PREC
#: the default box half-width of prove_periodic, 2^-(prec/3)
R = arb(2) ** -(PREC // 3)
DECIDED = {"saddle", "elliptic", "attracting node", "repelling node", "attracting focus",
           "repelling focus"}


@pytest.fixture(scope="module")
def symmetric():
    """x1 (elliptic) and x2 (saddle) of fig:many:wide/f=0.3, proved, from the paper's closed
    forms (reference.paper, corrected)."""
    sc = scenes.scene("fig:many:wide/f=0.3")
    out = {}
    for branch, kind in ((1, "elliptic"), (2, "saddle")):
        proof = prove_periodic(sc, *paper.symmetric_solution(sc, branch, dps=60).state0())
        assert proof.proved and proof.kind == kind, proof.reason
        out[kind] = proof
    return sc, out


def _krawczyk_at(sc, proof, dx, dv, r=R):
    """``orbits._krawczyk`` on the box ``z +- r`` whose centre ``z`` is the proved fixed point's
    midpoint moved by ``(dx, dv)`` (no Newton polish)."""
    with workprec(PREC):
        z = [(proof.point[0].mid() + dx).mid(), (proof.point[1].mid() + dv).mid()]
        centre = enclose_map(sc, z[0], z[1], phase=proof.phase, prec=PREC, max_prec=PREC)
        return orbits._krawczyk(sc, z, r, 1, proof.phase, PREC, centre)


@pytest.mark.parametrize("kind", ["elliptic", "saddle"])
@pytest.mark.parametrize("dx, dv", [(1.5, 0), (0, 1.5), (-1.1, 1.1), (10, -10), (1e12, 0)])
def test_a_centre_displaced_outside_the_krawczyk_ball_is_refused(symmetric, kind, dx, dv):
    sc, proofs = symmetric
    proof = proofs[kind]
    with workprec(PREC):
        moved = _krawczyk_at(sc, proof, arb(dx) * R, arb(dv) * R)
    assert not moved.proved and "K(Z) is not inside Z" in moved.reason, moved.reason


@pytest.mark.parametrize("kind", ["elliptic", "saddle"])
def test_a_centre_displaced_inside_the_ball_is_proved_and_encloses_the_fixed_point(symmetric, kind):
    """The true twin: moved by a quarter of the radius, the fixed point is still in the box."""
    sc, proofs = symmetric
    proof = proofs[kind]
    with workprec(PREC):
        moved = _krawczyk_at(sc, proof, R / 4, -R / 4)
        assert moved.proved and moved.kind == kind, moved.reason
        assert all(moved.point[i].overlaps(proof.point[i]) for i in range(2))


def _ahead_at(sc, proof, at, ahead, r=R):
    """``orbits._krawczyk`` with the enclosure at ``z``, the proved fixed point's midpoint moved by
    ``at``, and the last Newton iterate (``ahead``: its residual taken in mean-value form over
    the box around ``z``, no enclosure of its own) at the fixed point's midpoint moved by
    ``ahead``: ``Z`` is ``ahead +- r``."""
    with workprec(PREC):
        fixed = [proof.point[0].mid(), proof.point[1].mid()]
        z = [(fixed[i] + at[i]).mid() for i in range(2)]
        centre = enclose_map(sc, z[0], z[1], phase=proof.phase, prec=PREC, max_prec=PREC)
        return orbits._krawczyk(sc, z, r, 1, proof.phase, PREC, centre,
                                [(fixed[i] + ahead[i]).mid() for i in range(2)])


@pytest.mark.parametrize("kind", ["elliptic", "saddle"])
@pytest.mark.parametrize("dx, dv", [(1.5, 0), (0, -1.5), (1.1, 1.1)])
def test_a_last_newton_step_that_leaves_the_fixed_point_outside_its_box_is_refused(symmetric, kind, dx, dv):
    """The mean-value last step (issue 33): ``Z`` around the iterate ``ahead``, more than ``r``
    from the fixed point in one coordinate, does not hold it: refused, though the enclosure at
    ``z`` (the fixed point itself) is as good as it gets."""
    sc, proofs = symmetric
    with workprec(PREC):
        moved = _ahead_at(sc, proofs[kind], (0, 0), (arb(dx) * R, arb(dv) * R))
    assert not moved.proved and "K(Z) is not inside Z" in moved.reason, moved.reason


@pytest.mark.parametrize("kind", ["elliptic", "saddle"])
def test_a_last_newton_step_inside_the_box_is_proved_with_the_closed_form_multipliers(symmetric, kind):
    """The true twin: the enclosed centre ``z`` a quarter of ``r`` from the fixed point, the
    iterate ``ahead`` on it; the point ball holds the proved one and the multipliers (``P'``
    over ``K``, far from ``z``: ``P'`` at ``z`` is ~1e-33 off) hold the closed forms
    (``reference.paper``) to 1e-50."""
    sc, proofs = symmetric
    with workprec(PREC):
        moved = _ahead_at(sc, proofs[kind], (R / 4, -R / 4), (0, 0))
        assert moved.proved and moved.kind == kind, moved.reason
        assert all(moved.point[i].overlaps(proofs[kind].point[i]) for i in range(2))
        with mpmath.workdps(60):
            want = sorted(((w.real, abs(w.imag)) for w in
                           paper.symmetric_solution(sc, 1 if kind == "elliptic" else 2, dps=60).multipliers()),
                          key=lambda w: float(w[0]))
        slack = arb(0, arb(10) ** -50)
        if kind == "saddle":
            got = sorted(moved.multipliers, key=lambda b: float(b.mid()))
            assert all(b.overlaps(from_mpf(w[0]) + slack) for b, w in zip(got, want))
        else:
            (re, im), = moved.multipliers
            assert re.overlaps(from_mpf(want[0][0]) + slack) and im.overlaps(from_mpf(want[0][1]) + slack)


@pytest.mark.parametrize("start", [("10", "0.5"), ("19", "3")])
def test_a_misleading_point_log_never_makes_a_wrong_proof(symmetric, start):
    """``points``: one point log guides every walk of a proof.  A log from another start (a
    turn alone, or an impact then a stick: not the saddle's two impacts) misleads the centre's
    walk, which then proves nothing (never a wrong itinerary: each walk proves every event from
    the balls); ``prove_periodic`` then gives every centre its own log, and proves the saddle."""
    sc, proofs = symmetric
    saddle = proofs["saddle"]
    with workprec(PREC):
        z = [b.mid() for b in saddle.point]
        wrong = orbits.point_log(sc, *start, 1, saddle.phase, PREC)
        misled = orbits._polished(sc, z, R, 1, saddle.phase, PREC, wrong)
        assert not misled.proved and orbits.UNCENTRED in misled.reason, misled.reason
        got = prove_periodic(sc, *z, phase=saddle.phase, points=wrong)
        assert got.proved and got.kind == "saddle" and got.itinerary == ["impact", "impact"], got.reason
        assert all(got.point[i].overlaps(saddle.point[i]) for i in range(2))


def test_a_residual_wider_than_the_box_is_refused_before_the_box_is_walked(symmetric):
    """At 64 bits the enclosure of ``P(z) - z`` is ~1e-17 wide: no box of radius 1e-25 can hold
    ``K``, which holds that residual (refused without walking the box); the default box of
    64 bits is proved."""
    sc, proofs = symmetric
    x, v = (b.mid() for b in proofs["saddle"].point)
    tiny = prove_periodic(sc, x, v, phase=proofs["saddle"].phase, prec=64, radius="1e-25")
    assert not tiny.proved and "the residual alone" in tiny.reason, tiny.reason
    fine = prove_periodic(sc, x, v, phase=proofs["saddle"].phase, prec=64)
    assert fine.proved and fine.kind == "saddle", fine.reason


def test_a_test_failed_after_newton_converged_hands_on_its_centre(symmetric):
    """A Krawczyk test that fails once Newton has converged gives its polished centre
    (``OrbitProof.centre``; ``paper.claims.base.prove``'s ``centre``, decimal strings): a seed
    from which a proof with more bits starts converged, and proves the same fixed point.  The
    failures before convergence give none (the diverging and the too-wide tests above)."""
    from cross_check.paper.claims.base import prove
    sc, proofs = symmetric
    saddle = proofs["saddle"]
    x, v = (float(b.mid()) + 1e-9 for b in saddle.point)      # a float seed 1e-9 off
    tiny = prove_periodic(sc, x, v, phase=saddle.phase, prec=64, radius="1e-25")
    assert not tiny.proved and len(tiny.centre) == 2
    assert all(abs(c - p.mid()) < 1e-15 for c, p in zip(tiny.centre, saddle.point))   # polished
    rec = prove("saddle", sc, x, v, prec=64, radius="1e-25", phase=saddle.phase)
    assert not rec["proved"] and len(rec["centre"]) == 2
    again = prove_periodic(sc, *rec["centre"], phase=saddle.phase, prec=96)
    assert again.proved and again.kind == "saddle", again.reason
    assert all(again.point[i].overlaps(saddle.point[i]) for i in range(2))


def _fold_states():
    """x1 and x2 of ``fold/near`` (``f = 2/pi - 10^-6``: 0.0226 apart) at ``t = T/2``."""
    sc = scenes.scene("fold/near")
    out = []
    for branch in (1, 2):
        x0, v0 = paper.symmetric_solution(sc, branch, dps=60).state0()
        with mpmath.workdps(60):
            half = +mpmath.pi / sc.mpf("omega")
        log = reference.trajectory(sc, x0, v0, half, dps=60)
        out.append((log.x_end, log.v_end))
    return sc, out


def test_a_box_holding_two_fixed_points_is_refused():
    sc, (z1, z2) = _fold_states()
    with mpmath.workdps(60):
        gap = max(abs(z1[i] - z2[i]) for i in range(2))
    assert gap < mpmath.mpf("0.03")
    for z, kind in ((z1, "elliptic"), (z2, "saddle")):
        wide = prove_periodic(sc, *z, phase=Fraction(1, 2), radius=gap * mpmath.mpf("1.5"))
        assert not wide.proved and "K(Z) is not inside Z" in wide.reason, wide.reason
        alone = prove_periodic(sc, *z, phase=Fraction(1, 2))          # the default box: one
        assert alone.proved and alone.kind == kind, alone.reason


def test_the_saddle_handed_over_as_the_centre_is_proved_a_saddle(symmetric):
    """The caller hands over x2 where it expects the centre: the type is the enclosures'.
    Its multipliers hold the closed-form ones (reference.paper), real, one inside and one
    outside the unit circle, and ``classify`` of its trace and determinant agrees."""
    sc, proofs = symmetric
    saddle = proofs["saddle"]
    want = sorted((m.real for m in paper.symmetric_solution(sc, 2, dps=60).multipliers()), key=float)
    with workprec(PREC):
        got = sorted(saddle.multipliers, key=lambda b: float(b.mid()))
        assert all(isinstance(b, arb) for b in got)
        assert abs(got[0]) < 1 and abs(got[1]) > 1
        assert all(b.overlaps(from_mpf(w) + arb(0, arb(10) ** -50)) for b, w in zip(got, want))
        assert classify(sc, saddle.trace, saddle.det, ["impact", "impact"])[0] == "saddle"
        # the centre's trace with the saddle's itinerary is still the centre: nothing but the
        # enclosures decide
        centre = proofs["elliptic"]
        assert classify(sc, centre.trace, centre.det, saddle.itinerary)[0] == "elliptic"


def _ball(mid, rad=0):
    return arb(mid) + arb(0, rad) if rad else arb(mid)


CONSERVATIVE = scenes.scene("fig:wide:b")                     # f = 0, e = 1, c = 0
IMPACTS = ["impact", "impact"]


@pytest.mark.parametrize("tr", [(2, 1e-30), (-2, 1e-30), (2 + 1e-25, 1e-20), (-2 - 1e-25, 1e-20),
                                (2, 0), (-2, 0)])
def test_a_trace_straddling_2_or_minus_2_leaves_the_type_undecided(tr):
    """``det = 1`` exactly (flights and elastic impacts), so the multipliers are real iff
    ``|tr| > 2``: a trace ball holding 2 or -2 (or equal to it: a double multiplier +-1) decides
    nothing.  The twins 10^-20 inside and outside are elliptic and a saddle."""
    with workprec(PREC):
        kind, stability, _ = classify(CONSERVATIVE, _ball(*tr), arb(1), IMPACTS)
        assert kind not in DECIDED and "not" in stability, (kind, stability)
        edge = _ball(tr[0]).mid()
        sign = 1 if edge > 0 else -1
        inside = classify(CONSERVATIVE, edge - sign * arb("1e-15") + arb(0, arb("1e-30")), arb(1), IMPACTS)
        outside = classify(CONSERVATIVE, edge + sign * arb("1e-15") + arb(0, arb("1e-30")), arb(1), IMPACTS)
        assert inside[0] == "elliptic" and outside[0] == "saddle"


@pytest.mark.parametrize("what, scene, kinds, tr, det", [
    # real multipliers 1.5 and 1 +- 1e-20 (tr = l1 + l2, det = l1 l2): the second straddles 1
    ("a real multiplier straddling 1", scenes.scene("fig:many:wide/f=0.3"), ["impact", "turn"],
     (2.5, 1e-20), (1.5, 1.5e-20)),
    ("a real multiplier straddling -1", scenes.scene("fig:many:wide/f=0.3"), ["turn", "turn"],
     (-2.5, 1e-20), (1.5, 1.5e-20)),
    # complex pair with |lambda|^2 = det straddling 1
    ("det straddling 1, complex", scenes.scene("effect:restitution"), IMPACTS, (0.5, 1e-20), (1, 1e-20)),
    ("tr^2 - 4 det straddling 0", scenes.scene("effect:damping"), IMPACTS, (1, 1e-20), (0.25, 1e-20)),
])
def test_a_multiplier_on_the_unit_circle_edge_leaves_the_type_undecided(what, scene, kinds, tr, det):
    with workprec(PREC):
        kind, stability, _ = classify(scene, _ball(*tr), _ball(*det), kinds)
    assert kind not in DECIDED, (what, kind)


@pytest.mark.parametrize("scene, kinds", [
    (scenes.scene("fig:many:wide/f=0.3"), ["impact", "turn", "impact", "turn"]),    # friction
    (scenes.scene("effect:zeno"), IMPACTS),                                          # e = 0.8
    (scenes.scene("effect:damping"), IMPACTS),                                       # c = 0.05
])
def test_a_dissipative_orbit_is_never_elliptic(scene, kinds):
    """Only flights and elastic impacts without damping have ``det P' = 1`` exactly; with a
    turn, restitution or damping the determinant is the enclosure's: ``det = 0.5`` and a trace
    in ``(-2, 2)`` is an attracting focus, never a centre."""
    with workprec(PREC):
        kind, _, _ = classify(scene, arb("0.3"), arb("0.5"), kinds)
    assert kind == "attracting focus"


def test_a_segment_with_the_wrong_velocity_is_refused(monkeypatch):
    """The no-impact attractor of fig:many:wide/f=0.3 over x0 in [9, 11]: proved at v*; with
    Newton's polish off (``NEWTON_STEPS = 0``: the caller's ``v`` is the centre), ``v* + 1e-20``
    (far outside the ball ``v +- 2^-106``) is refused, ``v*`` moved by ``2^-112`` is proved."""
    sc = scenes.scene("fig:many:wide/f=0.3")
    proof = prove_segment(sc, "9", "11", "0.5")
    assert proof.proved, proof.reason
    with workprec(PREC):
        v_star = proof.point[1].mid()
        monkeypatch.setattr(orbits, "NEWTON_STEPS", 0)
        wrong = prove_segment(sc, "9", "11", v_star + arb("1e-20"))
        assert not wrong.proved and "1D Krawczyk" in wrong.reason, wrong.reason
        near = prove_segment(sc, "9", "11", v_star + arb(2) ** -112)
        assert near.proved and near.point[1].overlaps(proof.point[1]), near.reason


def test_a_segment_that_reaches_a_wall_is_refused():
    sc = scenes.scene("fig:many:wide/f=0.3")
    proof = prove_segment(sc, "18", "19.9", "0.5")
    assert not proof.proved and "without impacts" in proof.reason


# --- boxes: what Krawczyk's P'(Z) rests on ----------------------------------------------------
@pytest.mark.parametrize("name, x, v", [
    ("fig:narrow", "0.3", "0.2"),
    ("fig:narrow-with-friction", "0.27689242730111235", "-0.5784993511404171"),
    ("effect:damping", "0.2", "0.3"),
])
def test_a_box_proof_holds_the_corners_of_its_box(name, x, v):
    """``enclose_map`` over ``x +- 10^-30``, ``v +- 10^-30`` claims ``Phi`` and ``Phi'`` for every
    start of the box; at a box this small the balls are barely wider than the image of the box
    (``|Phi'| 10^-30``), so a proof over a smaller box than claimed misses the corners' images.
    The corners against the point reference at 60 digits (error ~1e-55)."""
    sc = scenes.scene(name)
    r = mpmath.mpf("1e-30")
    enc = enclose_map(sc, x, v, x_radius=r, v_radius=r)
    assert enc.proved, enc.reason
    with mpmath.workdps(60):
        x0, v0 = mpmath.mpf(x), mpmath.mpf(v)
    slack = arb(0, arb(10) ** -50)
    for dx in (-1, 1):
        for dv in (-1, 1):
            with mpmath.workdps(60):
                corner = (x0 + dx * r, v0 + dv * r)
            xr, vr = reference.stroboscopic_map(sc, *corner, dps=60)
            J = reference.jacobian(sc, *corner, dps=60)
            with workprec(enc.prec):
                assert enc.phi[0].overlaps(from_mpf(xr) + slack), (dx, dv, enc.phi[0], xr)
                assert enc.phi[1].overlaps(from_mpf(vr) + slack), (dx, dv, enc.phi[1], vr)
                assert all(enc.jacobian[i][j].overlaps(from_mpf(J[i][j]) + slack)
                           for i in range(2) for j in range(2))


def _scripted_map(steps, calls):
    """A fake ``enclose_map`` whose Newton step at its ``n``-th call is ``(steps[n], 0)``: ``P - id
    = (d s, 0)`` with ``P' - I = diag(d, 1)``, ``d`` small at the calls whose step is large (a
    near-singular ``P' - I``, as at a kink of ``P``)."""
    from reference.enclosure.maps import MapEnclosure

    def fake(scene, x, v, **kw):
        n = len(calls)
        calls.append((x, v))
        s = arb(steps[min(n, len(steps) - 1)])
        d = arb(2) ** -30 if s.mid() > 0.01 else arb(1)
        return MapEnclosure(True, phi=(x + d * s, arb(v)), jacobian=[[1 + d, arb(0)], [arb(0), arb(2)]], prec=64)
    return fake


def test_a_newton_that_converges_then_jumps_away_is_refused_as_diverging(monkeypatch):
    """Newton's steps fall to 1e-5 and then jump to 0.1 (``P' - I`` near-singular at a kink:
    issue 33's frictionless scene, period-2 saddle at (-0.506, 1.321), whose iterate then left the
    gap).  Refused as diverging before the far iterate is walked, and without the second pass
    that a centre failing on its point log gets; its true twin, a wide seed whose first steps
    grow (from 1e-3 to 0.1: not yet converging), is followed to convergence."""
    sc = scenes.scene("fig:xpotno")
    calls = []
    monkeypatch.setattr(orbits, "enclose_map", _scripted_map([1e-2, 1e-4, 1e-5, 0.1, 1e-9], calls))
    proof = prove_periodic(sc, "0.1", "0.2", periods=1, phase=Fraction(0), prec=64, points=[])
    assert not proof.proved and proof.diverged and "Newton diverges" in proof.reason, proof.reason
    assert len(calls) == 4 and proof.centre == ()      # the iterate 0.1 away is never walked, nor handed on
    calls.clear()
    monkeypatch.setattr(orbits, "enclose_map", _scripted_map([1e-3, 0.1, 1e-4, 1e-5, 1e-9], calls))
    with workprec(64):
        z, enc, ahead = orbits._newton(sc, [arb("0.1").mid(), arb("0.2").mid()], 1, Fraction(0), 64,
                                       arb(2) ** -23, [])
    assert enc.proved and ahead is not None and len(calls) == 5


@pytest.mark.parametrize("kind", ["elliptic", "saddle"])
def test_multipliers_over_the_box_where_they_decide_the_type_and_over_K_where_not(symmetric, kind, monkeypatch):
    """``tight=False`` (verify's orbits): the multipliers from ``P'`` over the Krawczyk box, one
    walk fewer, where they decide the type -- the same kind, the balls still holding the closed
    forms (``reference.paper``).  Where the box's enclosures leave the type undecided (its
    ``classify`` made to say so), the walk over ``K`` is made, as with ``tight=True``."""
    sc, proofs = symmetric
    x, v = paper.symmetric_solution(sc, 1 if kind == "elliptic" else 2, dps=60).state0()
    walks, real_map = [], orbits.enclose_map
    monkeypatch.setattr(orbits, "enclose_map", lambda *a, **k: walks.append(k.get("x_radius")) or real_map(*a, **k))
    loose = prove_periodic(sc, x, v, tight=False)
    boxes = sum(w is not None for w in walks)
    assert loose.proved and loose.kind == kind and boxes == 1            # the box walk, none over K
    with workprec(PREC), mpmath.workdps(60):
        want = paper.symmetric_solution(sc, 1 if kind == "elliptic" else 2, dps=60).multipliers()
        slack = arb(0, arb(10) ** -20)
        if kind == "saddle":
            got = sorted(loose.multipliers, key=lambda b: float(b.mid()))
            assert all(b.overlaps(from_mpf(w.real) + slack) for b, w in zip(got, sorted(want, key=lambda w: float(w.real))))
        else:
            (re, im), = loose.multipliers
            assert re.overlaps(from_mpf(want[0].real) + slack) and im.overlaps(from_mpf(abs(want[0].imag)) + slack)
    walks.clear()
    calls, decide = [], orbits.classify
    monkeypatch.setattr(orbits, "classify", lambda *a: ("undecided", "forced", []) if not calls.append(a) and len(calls) == 1
                        else decide(*a))
    again = prove_periodic(sc, x, v, tight=False)
    assert len(calls) == 2 and sum(w is not None for w in walks) == 2 and again.kind == kind    # the walk over K too


@pytest.mark.parametrize("radius, refused", [(1.2, True), (0.8, False)])
def test_a_centre_whose_jacobian_is_too_wide_for_any_krawczyk_box_is_refused_at_once(radius, refused, monkeypatch):
    """``P' = diag(3, 3) +- radius`` entrywise: ``C = (mid P' - I)^-1 = I/2``, so ``I - C (P'(B) -
    I)`` has row radii ``2 radius / 2``: at 1.2 no box contracts (``orbits._spread`` 1.2 >= 1), and the rung
    is refused at its first walk, not Newton-stepped (issue 33: 50 CPU s of a wandering Newton on
    a 96-bit ``P'`` 0.5 wide) nor declared divergent (which would stop the ladder); at 0.8 (spread
    0.8) Newton goes on to convergence."""
    from reference.enclosure.maps import MapEnclosure
    sc = scenes.scene("fig:xpotno")
    calls = []

    def fake(scene, x, v, **kw):
        calls.append((x, v))
        d = arb(2) ** -40 if len(calls) < 3 else arb(0)
        wide = [[3 + arb(0, radius), arb(0, radius)], [arb(0, radius), 3 + arb(0, radius)]]
        return MapEnclosure(True, phi=(x + d, v + d), jacobian=wide, prec=64)

    monkeypatch.setattr(orbits, "enclose_map", fake)
    with workprec(64):
        z0 = [arb("0.1").mid(), arb("0.2").mid()]
        if refused:
            with pytest.raises(orbits._TooWide, match="too wide for a Krawczyk box at 64 bits"):
                orbits._newton(sc, z0, 1, Fraction(0), 64, None, [])
            proof = prove_periodic(sc, "0.1", "0.2", periods=1, phase=Fraction(0), prec=64, points=[])
            assert not proof.proved and not proof.diverged and "too wide" in proof.reason
            assert len(calls) == 2 and proof.centre == ()    # one walk each: no Newton step was taken
        else:
            z, enc, ahead = orbits._newton(sc, z0, 1, Fraction(0), 64, None, [])
            assert enc.proved and len(calls) == 3


def test_the_jacobian_spread_is_row_sums_of_abs_inverse_times_radii():
    J = [[3 + arb(0, 0.25), arb(0, 0.5)], [arb(0, 0.1), 3 + arb(0, 0.1)]]
    C = orbits._inverse([[arb(2), arb(0)], [arb(0), arb(4)]])     # mid (P' - I)^-1 = diag(1/2, 1/4)
    spread = float(orbits._spread(J, C).mid())        # radii are stored rounded up (30 bits)
    assert max(0.5 * 0.75, 0.25 * 0.2) <= spread <= 0.375 * (1 + 1e-8)
