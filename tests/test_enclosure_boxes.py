"""Enclosures and orbit proofs over parameter boxes (issue 26): ``ParamBox``, the parameter
derivatives, the mean-value Jacobian, the parametric Krawczyk proof, covers and chains.

Every statement is checked against the point reference (mpmath, ``reference.trajectory``) at
points of the box, and every certificate is shown a box where its statement is false.
"""
from fractions import Fraction

import mpmath
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import reference
from reference.enclosure import ParamBox, enclose_map, prove_periodic
from reference.enclosure.branches import claim_check, guess, section_ticks, symmetric_cover
from reference.enclosure.continuation import prove_interval
from reference.scene import Scene

DPS = 60


# --- the point reference at a section: Newton with a finite-difference Jacobian ----------
def section_map(scene, x, v, phase, periods, dps=DPS):
    """``(x, v)`` after ``periods`` periods from ``t0 = phase T`` (the point reference)."""
    with mpmath.workdps(dps):
        T = 2 * mpmath.pi / scene.mpf("omega")
        t0 = T * phase.numerator / phase.denominator
        log = reference.trajectory(scene, x, v, t0 + periods * T, t0=t0, dps=dps)
        return log.x_end, log.v_end


def reference_fixed_point(scene, x, v, phase, periods, dps=DPS):
    """Newton on ``P(z) - z`` with a central-difference Jacobian (step 1e-25) at ``dps``
    digits; returns ``(x, v, trace)``, the trace of the finite-difference ``P'``."""
    with mpmath.workdps(dps):
        x, v, h = mpmath.mpf(x), mpmath.mpf(v), mpmath.mpf("1e-25")
        for _ in range(30):
            X, V = section_map(scene, x, v, phase, periods, dps)
            cols = []
            for dx, dv in ((h, 0), (0, h)):
                a = section_map(scene, x + dx, v + dv, phase, periods, dps)
                b = section_map(scene, x - dx, v - dv, phase, periods, dps)
                cols.append(((a[0] - b[0]) / (2 * h), (a[1] - b[1]) / (2 * h)))
            J = mpmath.matrix([[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]])
            step = mpmath.lu_solve(J - mpmath.eye(2), mpmath.matrix([X - x, V - v]))
            x, v = x - step[0], v - step[1]
            if max(abs(step[0]), abs(step[1])) < mpmath.mpf(10) ** (-40):
                return x, v, J[0, 0] + J[1, 1]
    raise AssertionError(f"reference Newton did not converge at {scene}")


def inside(ball, value):
    """``value`` (an mpf) in the arb ball, compared exactly."""
    from reference.enclosure.balls import from_mpf
    return ball.contains(from_mpf(value))


# --- ParamBox -------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, word", [
    (dict(f=("0.3", "0.2")), "f must have lo <= hi"),
    (dict(damping=(0, "0.1")), "damping"),
    (dict(l=(0, "25"), r=("20", "21")), "r must be > l"),
    (dict(f=("-0.1", "0.1")), "f must be >= 0"),
    (dict(wavenumber="pi/2"), "wavenumber"),
    (dict(restitution=("0.9", "1.1")), "restitution must be in [0, 1]"),
    (dict(f=("0.1", "0.2", "0.3")), "pair"),
])
def test_parambox_rejects_bad_boxes_naming_the_parameter(kwargs, word):
    base = dict(F=1, f="0.3", omega=1, l=0, r=20)
    with pytest.raises(ValueError, match=word.replace("[", r"\[").replace("]", r"\]")):
        ParamBox(**{**base, **kwargs})


def test_parambox_effects_midpoint_and_split():
    box = ParamBox(F=1, f=(0, "0.25"), omega="2*pi", l=-1, r=(1, "1.5"))
    assert box.has("friction") and box.friction_mixed and not box.has("restitution")
    mid = Scene(F=1, f="0.125", omega="2*pi", l=-1, r="1.25")
    assert all(box.midpoint().exact(k) == mid.exact(k) for k in ("F", "f", "omega", "l", "r"))
    low, high = box.split("r")
    assert low.hi("r") == high.lo("r") == Fraction(5, 4) and not box.is_point
    assert ParamBox(F=1, f="0.3", omega=1, l=0, r=20).scene().exact("f") == Fraction(3, 10)
    with pytest.raises(ValueError, match="not a point"):
        box.scene()
    assert box.contains(Scene(F=1, f="0.2", omega="2*pi", l=-1, r="1.1"))
    assert not box.contains(Scene(F=1, f="0.3", omega="2*pi", l=-1, r="1.1"))


def test_a_point_box_runs_the_point_code():
    sc, box = Scene(F=1, f="0.3", omega=1, l=0, r=20), ParamBox(F=1, f="0.3", omega=1, l=0, r=20)
    a, b = enclose_map(sc, "10.69", "-6.03", phase="0.3125"), enclose_map(box, "10.69", "-6.03", phase="0.3125")
    assert a.proved and b.proved
    assert all(p.mid() == q.mid() and p.rad() == q.rad() for p, q in zip(a.phi, b.phi))


# --- parameter derivatives (sensitivity) against the point reference ------------------
@pytest.mark.parametrize("base, state, kinds, names", [
    (dict(F="1.2", f="0.3", omega=1, l="-0.5", r=20, restitution="0.9"), ("10.69", "-6.03"), {"impact"},
     ("F", "f", "l", "r", "restitution")),
    (dict(F=1, f="0.2", omega=1, l=0, r="1.5"), ("0.2", "-0.3"), {"turn", "impact"}, ("F", "f", "l", "r")),
])
def test_parameter_derivatives_match_finite_differences(base, state, kinds, names):
    """``d Phi/d p`` of ``sensitivity`` (Table 1 with parameter columns) against central
    differences of the point reference at 60 digits (step 1e-20)."""
    enc = enclose_map(Scene(**base), *state, phase="0.3125", parameters=names)
    assert enc.proved and kinds <= {e.kind for e in enc.events}
    h = Fraction(1, 10 ** 20)
    for name, col in zip(names, enc.dparams):
        ends = [section_map(Scene(**{**base, name: Fraction(str(base.get(name, 1))) + s * h}),
                            *state, Fraction(5, 16), 1) for s in (1, -1)]
        with mpmath.workdps(DPS):
            fd = [(ends[0][k] - ends[1][k]) / (2 * mpmath.mpf(h.numerator) / h.denominator)
                      for k in range(2)]
        for c, d in zip(col, fd):
            assert abs(float(c.mid()) - float(d)) <= 1e-15 * (1 + abs(float(d))), (name, c, d)


# --- the mean-value Jacobian holds at every point of a wide box -------------------------
def test_centred_jacobian_holds_at_points_of_the_box():
    box = ParamBox(F=1, f=("0.3", "0.31"), omega=1, l=0, r=("20", "20.2"))
    enc = enclose_map(box, "10.69", "-6.03", x_radius="0.05", v_radius="0.02", phase="0.3125",
                      centred=True, parameters=("f", "r"))
    assert enc.proved
    for f, r, dx, dv in ((Fraction(3, 10), 20, -1, 1), (Fraction(31, 100), Fraction(101, 5), 1, -1),
                         (Fraction(61, 200), Fraction(201, 10), 0, 0)):
        x, v = Fraction("10.69") + dx * Fraction("0.05"), Fraction("-6.03") + dv * Fraction("0.02")
        point = enclose_map(box.point(f=f, r=r), x, v, phase="0.3125", parameters=("f", "r"))
        for row, prow in zip(enc.jacobian, point.jacobian):
            assert all(a.contains(b) for a, b in zip(row, prow))
        assert all(a.contains(b) for col, pcol in zip(enc.dparams, point.dparams) for a, b in zip(col, pcol))


# --- box proofs ----------------------------------------------------------------------
X1_BOX = ParamBox(F=1, f=("0.3", "0.31"), omega=1, l=0, r=("20", "20.25"))


@pytest.fixture(scope="module")
def x1_proof():
    ticks = section_ticks(X1_BOX.midpoint(), 1)
    x, v = guess(1, 1, ticks)(X1_BOX.midpoint())
    return prove_periodic(X1_BOX, x, v, phase=ticks)


def test_box_proof_holds_the_point_proofs_at_corners_and_centre(x1_proof):
    p = x1_proof
    assert p.proved and p.kind == "elliptic" and p.itinerary == ["impact", "impact"]
    corners = [X1_BOX.point(f=f, r=r) for f in (X1_BOX.lo("f"), X1_BOX.hi("f"))
               for r in (X1_BOX.lo("r"), X1_BOX.hi("r"))] + [X1_BOX.midpoint()]
    for sc in corners:
        x, v = guess(1, 1, p.phase)(sc)
        q = prove_periodic(sc, x, v, phase=p.phase)
        assert q.proved and q.kind == "elliptic"
        assert all(a.contains(b) for a, b in zip(p.point, q.point)), sc
        assert p.trace.contains(q.trace)


@settings(max_examples=6, deadline=None)
@given(u=st.fractions(0, 1), w=st.fractions(0, 1))
def test_random_points_of_a_proved_box_converge_into_its_balls(x1_proof, u, w):
    """Hypothesis: a parameter point of the proved box, run through the point reference at 60
    digits, has its fixed point (Newton) in the proved state ball and its trace in the
    proved interval."""
    p, box = x1_proof, X1_BOX
    sc = box.point(f=box.lo("f") + u * box.width("f"), r=box.lo("r") + w * box.width("r"))
    x0, v0 = guess(1, 1, p.phase)(sc)
    x, v, tr = reference_fixed_point(sc, x0, v0, p.phase, 1)
    assert inside(p.point[0], x) and inside(p.point[1], v) and inside(p.trace, tr)


def test_a_box_across_the_x2_sticking_boundary_is_not_proved():
    """x2 sticks (grazes at its impacts) below w^2 R/F = sqrt(4 - pi^2 f^2) = 1.76452 at f = 0.3:
    a box across it must not be proved, and must say why."""
    box = ParamBox(F=1, f="0.3", omega=1, l=0, r=("1.74", "1.79"))
    ticks = section_ticks(box.midpoint(), 2)
    x, v = guess(2, 1, ticks)(box.midpoint())           # the midpoint is on the non-sticking side
    p = prove_periodic(box, x, v, phase=ticks)
    assert not p.proved and "wall r" in p.reason
    got, _ = symmetric_cover(box, 2, kind="saddle", max_leaves=6)
    assert not got.proved and got.reason


def test_a_mixed_friction_box_refuses_to_stick():
    box = ParamBox(F=1, f=(0, "0.4"), omega=1, l=0, r=10)
    enc = enclose_map(box, 5, 0, phase="0.25")          # at rest where the force is 0: sticks
    assert not enc.proved and "f in [0, hi]" in enc.reason
    assert enclose_map(box.replace(f=("0.3", "0.31")), 5, 0, phase="0.25").proved     # f > 0: it may


def test_claims_that_fail_on_the_box_are_refused(x1_proof):
    assert claim_check("saddle")(x1_proof) is not None          # x1 is no saddle
    assert claim_check("elliptic", impacts=4)(x1_proof) is not None
    # x1 across the parabolic curve k h = 2, where tr = (kh - 2)^2 - 2 = -2 exactly:
    # w^2 R/F = S (pi^2/2 - 1) = 7.6480 at f = 0.15 (S = sqrt(4 - pi^2 f^2))
    box = ParamBox(F=1, f=("0.15", "0.1505"), omega=1, l=0, r=("7.63", "7.66"))
    ticks = section_ticks(box.midpoint(), 1)
    p = prove_periodic(box, *guess(1, 1, ticks)(box.midpoint()), phase=ticks)
    assert p.proved and p.trace.contains(-2)                    # the orbit exists, the trace reaches -2
    assert "elliptic not proved" in claim_check("elliptic")(p)
    beyond = ParamBox(F=1, f=("0.63", "0.64"), omega=1, l=0, r=20)       # across the fold 2/pi
    got, _ = symmetric_cover(beyond, 1, kind="elliptic", max_leaves=4)
    assert not got.proved and got.reason
    high = beyond.split("f")[1]                                            # wholly beyond it
    got, why = symmetric_cover(high, 1, kind="elliptic", max_leaves=4)
    assert got is None and "2/(1 pi)" in why


def test_a_cover_tiles_its_box_and_its_hull_holds_the_leaves():
    box = ParamBox(F=1, f=("0.3", "0.32"), omega=1, l=0, r=("20", "20.5"))
    got, _ = symmetric_cover(box, 1, kind="elliptic", max_leaves=16)
    assert got.proved
    area = sum(p.box.width("f") * p.box.width("r") for p in got.leaves)
    assert area == box.width("f") * box.width("r")
    hull = got.hull()
    assert all(hull[0].contains(p.point[0]) and hull[2].contains(p.trace) for p in got.leaves)


def test_a_chain_stops_at_a_gap_it_cannot_close():
    calls = []

    def prove_box(a, b):
        calls.append((a, b))
        return (None, "no") if b > Fraction(1, 2) else ({"ok": True}, None)

    got = prove_interval(prove_box, 0, 1, first=Fraction(1, 8), min_width=Fraction(1, 64))
    assert not got.complete and got.reason.startswith("no proof") and got.reached <= Fraction(1, 2)
    assert all(b0 == a1 for (_, b0, _), (a1, _, _) in zip(got.boxes, got.boxes[1:]))
    with pytest.raises(ValueError, match="lo < hi"):
        prove_interval(prove_box, 1, 0, first=Fraction(1, 8), min_width=Fraction(1, 64))
    assert len(calls) < 40
