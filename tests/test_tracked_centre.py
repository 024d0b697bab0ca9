"""``Phi`` at a box's centre from the box's own walk (``MapEnclosure.phi_at_centre``), and the
orbit proofs it takes from one walk (``reference.enclosure.orbits._tracked``, issue 33).

The validated flights carry the offsets of one start of the box -- its centre -- by the set's
own Lohner recurrence (``lohner.ValidatedFlight.point_state``), through the hand-offs of impacts
and turns (``handoff.Handoff.start``) and through the centre's own stops and slips
(``handoff.Handoff.tracked_stop``, ``walk.Walk._track_rest``, ``ValidatedFlight._point_shift``).
Checked against an independent point run of the reference integrator (15 digits beyond the
balls' precision) and against a
walk from the centre alone; each check is seen to fail: the image of a corner of the box lies
outside the centre's balls, and two mutants of the recurrence (no step errors on the tracked
offsets; a slip's start not moved back to the flight's base) leave the true value outside.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath
import pytest
from flint import arb
from hypothesis import assume, given, settings, strategies as st

import reference
from cross_check.tolerances import tol
from cross_check.verify import ladder
from reference.enclosure import enclose_map, lohner, orbits, prove_periodic
from reference.enclosure.balls import from_mpf, workprec
from tests.ladder_pairs import first_orbits
from tests.strategies import position_forced_scenes, states

#: the heaviest of the ten position-forced scenes of issue 33's closing notes
SCENE = reference.Scene(F="2.74", f="0.54", omega="1.06", l="-0.54", r="0.91", wavenumber="1.22")
#: boxes of ``SCENE`` whose walks have these events, measured: (x, v, radius, bits, kinds)
STICKS_THEN_FLIES = (0.5, 0.9, 2.0 ** -90, 192, ["impact", "turn", "stick", "slip", "impact", "turn", "turn"])
ENDS_AFTER_A_SLIP = (0.1, 0.3, 2.0 ** -40, 64, ["impact", "impact", "turn", "impact", "turn", "stick", "slip"])
FLIES_ONLY = (-0.2, -1.0, 2.0 ** -50, 128, ["turn", "impact", "impact", "impact", "turn"])


def _walks(sc, x, v, r, prec):
    """The walk over the box of half-width ``r`` and the walk from its centre alone."""
    box = enclose_map(sc, x, v, x_radius=r, v_radius=r, prec=prec, max_prec=prec)
    return box, enclose_map(sc, x, v, prec=prec, max_prec=prec)


def _holds_truth(sc, x, v, balls, prec) -> bool:
    """``balls`` hold ``Phi(x, v)`` of a run of the reference's point integrator with 15 digits
    beyond the balls' ``prec`` bits (40 at 64 bits)."""
    truth = reference.stroboscopic_map(sc, x, v, dps=max(40, int(prec * 0.302) + 15))
    with workprec(2 * prec):
        return all(b.contains(from_mpf(t)) for b, t in zip(balls, truth))


def _width(balls) -> float:
    return max(float(b.rad()) for b in balls)


@st.composite
def _boxes(draw):
    sc = draw(position_forced_scenes())
    x, v = draw(states(sc))
    prec = draw(st.sampled_from((64, 128)))
    # at most 2^-(prec/3 + 8) (tracked_centre_width_factor: the box's third order stays below)
    return sc, x, v, 2.0 ** -draw(st.integers(prec // 3 + 8, prec // 3 + 22)), prec


@settings(max_examples=12, deadline=None)
@given(_boxes())
def test_the_tracked_centre_holds_the_point_map_as_narrow_as_its_own_walk(case):
    sc, x, v, r, prec = case
    box, alone = _walks(sc, x, v, r, prec)
    assume(box.proved and alone.proved and box.phi_at_centre is not None)
    at = box.phi_at_centre
    assert _holds_truth(sc, x, v, at, prec)
    assert all(a.overlaps(b) for a, b in zip(at, box.phi)) and _width(at) < _width(box.phi)
    factor = tol("tracked_centre_width_factor").rtol
    assert _width(at) <= factor * _width(alone.phi), (_width(at), _width(alone.phi))


@pytest.mark.parametrize("case", [STICKS_THEN_FLIES, ENDS_AFTER_A_SLIP, FLIES_ONLY],
                         ids=["sticks-then-flies", "ends-after-a-slip", "flies-only"])
def test_the_centre_is_tracked_through_stops_slips_impacts_and_turns_and_no_corner_is_in_it(case):
    """The corner ``(x + r, v + r)`` is a start of the box: its image lies in the box's balls,
    ``|Phi'| r`` away from the centre's, outside the tracked balls (which are not the box's)."""
    x, v, r, prec, kinds = case
    box, alone = _walks(SCENE, x, v, r, prec)
    assert box.proved and [e.kind for e in box.events] == kinds
    at = box.phi_at_centre
    assert at is not None and _holds_truth(SCENE, x, v, at, prec)
    assert _width(at) <= tol("tracked_centre_width_factor").rtol * _width(alone.phi)
    corner = enclose_map(SCENE, Fraction(x) + Fraction(r), Fraction(v) + Fraction(r), prec=prec,
                         max_prec=prec).phi        # exact (x + r rounds to x in float64 at 2^-90)
    assert all(c.overlaps(b) for c, b in zip(corner, box.phi))
    assert not any(c.overlaps(a) for c, a in zip(corner, at)), (corner, at)


def test_a_walk_that_ends_at_rest_gives_the_centre_s_own_stop():
    """A box whose walk ends stuck: the centre's state at ``T`` is its own stop, ``(x*, 0)``."""
    sc = reference.Scene(F="1", f="0.5", omega="2", l="-1", r="1", wavenumber="1.5")
    box, alone = _walks(sc, 0.46, 0.25, 2.0 ** -40, 64)
    assert box.proved and alone.proved and [e.kind for e in box.events] == ["stick"]
    at = box.phi_at_centre
    assert at is not None and at[1] == 0 and _holds_truth(sc, 0.46, 0.25, at, 64)
    assert _width(at) <= tol("tracked_centre_width_factor").rtol * _width(alone.phi)


_real_reframe = lohner.reframe


def _midpoints_only(centre, M, R, Rp=None):
    """``lohner.reframe`` whose tracked offsets keep their midpoints and drop their radii: the
    steps' truncation and rounding, carried so far, are lost at every step."""
    mid, A, R2, Rp2 = _real_reframe(centre, M, R, Rp)
    return mid, A, R2, None if Rp2 is None else [b.mid() for b in Rp2]


@pytest.mark.parametrize("case", [STICKS_THEN_FLIES, ENDS_AFTER_A_SLIP, FLIES_ONLY],
                         ids=["sticks-then-flies", "ends-after-a-slip", "flies-only"])
def test_a_mutant_that_drops_the_tracked_errors_leaves_the_truth_outside(case, monkeypatch):
    """Seen to fail: the containment check says no to tracked balls that have lost the errors
    they carry (each Taylor step's truncation and rounding).  (Mutants that take the slip's start
    at its own time instead of the flight's base, or that drop only the last flight's step errors,
    are not caught: the acceleration vanishes at a slip, and each hand-off rebuilds the centre's
    ball from the set's own centre event.)"""
    x, v, r, prec, _ = case
    monkeypatch.setattr(lohner, "reframe", _midpoints_only)
    at = enclose_map(SCENE, x, v, x_radius=r, v_radius=r, prec=prec, max_prec=prec).phi_at_centre
    assert at is not None and not _holds_truth(SCENE, x, v, at, prec)


@pytest.fixture(scope="module")
def orbit():
    """A period-1 orbit of ``SCENE`` (fast's search), its section as ``ladder.proof`` takes it."""
    p = first_orbits(SCENE, n=1)[0]
    return ladder._section(SCENE, p.x, p.v, 1)


def _counted(monkeypatch):
    walks, real = [], orbits.enclose_map
    monkeypatch.setattr(orbits, "enclose_map",
                        lambda *a, **k: walks.append(bool(k.get("x_radius"))) or real(*a, **k))
    return walks


def test_an_orbit_proof_takes_the_box_s_walk_alone_and_proves_what_newton_s_walks_prove(orbit, monkeypatch):
    phase, x, v, guide = orbit
    walks = _counted(monkeypatch)
    one = prove_periodic(SCENE, x, v, phase=phase, prec=64, radius=2.0 ** -40, points=guide, tight=False)
    assert one.proved and walks == [True], (one.reason, walks)
    walks.clear()
    monkeypatch.setattr(orbits, "TRACKED_KINDS", frozenset())      # Newton's point walk first
    two = prove_periodic(SCENE, x, v, phase=phase, prec=64, radius=2.0 ** -40, points=guide, tight=False)
    assert two.proved and walks == [False, True], walks
    assert one.kind == two.kind and one.itinerary == two.itinerary
    assert all(a.overlaps(b) for a, b in zip(one.point, two.point))
    assert all(a.overlaps(b) for a, b in zip(one.multipliers, two.multipliers))


def test_the_box_test_refuses_a_seed_or_a_centre_that_is_off_and_newton_goes_on(orbit, monkeypatch):
    """Seen to fail: the Krawczyk test on the box's walk alone says no to a box around a seed
    ``4 r`` off the fixed point, and to the right box with ``P(z)`` moved by ``4 r``; the proof
    then goes on by Newton from that walk's own enclosure at the seed (one point walk, one box)
    and proves the orbit."""
    phase, x, v, guide = orbit
    r = arb(2) ** -40
    with workprec(64):
        z = [arb(mpmath.mpf(x)).mid(), arb(mpmath.mpf(v)).mid()]
        box, centre = orbits._tracked(SCENE, z, r, 1, phase, 64, guide)
        assert orbits._in_box(SCENE, z, r, 1, phase, 64, box, centre, guide, False) is not None
        moved = orbits.MapEnclosure(True, phi=(centre.phi[0] + 4 * r, centre.phi[1]),
                                    jacobian=centre.jacobian, events=centre.events, prec=64)
        assert orbits._in_box(SCENE, z, r, 1, phase, 64, box, moved, guide, False) is None
        off = [(z[0] + 4 * r).mid(), z[1]]
        box, centre = orbits._tracked(SCENE, off, r, 1, phase, 64, guide)
        assert centre is not None
        assert orbits._in_box(SCENE, off, r, 1, phase, 64, box, centre, guide, False) is None
    walks = _counted(monkeypatch)
    proof = prove_periodic(SCENE, off[0], off[1], phase=phase, prec=64, radius=r, points=guide, tight=False)
    assert proof.proved and walks == [True, False, True], walks
    right = prove_periodic(SCENE, z[0], z[1], phase=phase, prec=64, radius=r, points=guide, tight=False)
    assert right.proved and all(a.overlaps(b) for a, b in zip(proof.point, right.point))


@settings(max_examples=4, deadline=None)
@given(position_forced_scenes(restitutions=("1", "0.8")))
def test_the_ladder_proves_the_same_orbits_on_the_same_rungs_with_and_without_the_tracked_centre(sc):
    """On random position-forced scenes, fast's first two period-1 orbits: ``ladder.proof`` with
    the box's walk alone and with Newton's point walk first proves the same orbits, on the same
    rung, with overlapping balls."""
    for p in first_orbits(sc, n=2):
        tracked = ladder.proof("o", sc, p, 1, None)
        kept = orbits.TRACKED_KINDS
        orbits.TRACKED_KINDS = frozenset()
        try:
            newton = ladder.proof("o", sc, p, 1, None)
        finally:
            orbits.TRACKED_KINDS = kept
        assert tracked["proved"] == newton["proved"], (tracked, newton)
        if tracked["proved"]:
            assert tracked["radius"] == newton["radius"] and tracked["kind"] == newton["kind"]
            for (m0, r0), (m1, r1) in zip(tracked["point"], newton["point"]):
                assert abs(mpmath.mpf(m0) - mpmath.mpf(m1)) <= mpmath.mpf(r0) + mpmath.mpf(r1)
