"""Two-impact orbits proved in impact coordinates (``reference.enclosure.impacts``, issue 26).

Every statement is checked against code that shares nothing with the prover's equations: the
paper's closed form (``reference.paper``), the stroboscopic point proof (``prove_periodic``:
the walk's Table 1) and the point reference's own Newton at 60 digits.  Every refusal is shown
on a box where the statement is false: across x2's grazing boundary, across x1's sticking
boundary (the Krawczyk step succeeds there, so the itinerary check is what must say no, and
the test shows that it does), beyond the fold, too wide, a section on an impact.
"""
from fractions import Fraction

import mpmath
import pytest
from flint import arb, arb_mat
from hypothesis import given, settings
from hypothesis import strategies as st

from reference import paper as P
from reference.enclosure import ParamBox, prove_periodic
from reference.enclosure import impacts as I
from reference.enclosure.balls import from_number, span, workprec
from reference.enclosure.branches import common_ticks, guess, section_ticks, symmetric_cover
from reference.enclosure.dual import Dual
from tests.test_enclosure_boxes import inside, reference_fixed_point

#: x2 where its impacts are slow (0.2 - 0.4): the stroboscopic proof needed > 512 sub-boxes here
SLOW_X2 = ParamBox(F=1, f=("0.3125", "0.34375"), omega=1, l=0, r=("2.75", "3.25"))
#: x1 across its sticking boundary: at f = 0.3 the interior minimum of its speed is 0 at
#: w^2 R/F = pi sqrt(1 - f^2) - sqrt(4 - pi^2 f^2) - pi f (asin(pi f/2) - asin f) = 1.0582
X1_STICKS = ParamBox(F=1, f="0.3", omega=1, l=0, r=("1.04", "1.08"))


def impact_guess(box, branch, m=1):
    return guess(branch, m, None, impacts=True)(box.midpoint())


def prove(box, branch, m=1):
    ticks = section_ticks(box.midpoint(), branch, m)
    return I.prove_two_impacts(box, impact_guess(box, branch, m), periods=m, ticks=ticks), ticks


def test_dual_numbers_carry_exact_derivatives():
    with workprec(128):
        x, y = Dual.variable(arb("0.7"), 0, 2), Dual.variable(arb("1.3"), 1, 2)
        g = (x * y).sin() / (2 - x.cos()) - 3 * y
        # d/dx and d/dy of sin(xy)/(2 - cos x) - 3y, by hand
        xv, yv = arb("0.7"), arb("1.3")
        s, c, den = (xv * yv).sin(), (xv * yv).cos(), 2 - xv.cos()
        dx = (yv * c * den - s * xv.sin()) / den ** 2
        dy = xv * c / den - 3
        assert g.grad[0].overlaps(dx) and g.grad[1].overlaps(dy) and g.grad[0].rad() < 1e-30


@pytest.mark.parametrize("branch, m, fF, R", [(1, 1, "0.3", "20"), (2, 1, "0.3", "3"), (1, 3, "0.08", "45")])
def test_the_equations_vanish_on_the_closed_form(branch, m, fF, R):
    """``G`` at the paper's closed form (an independent solution) is 0 to the working precision."""
    sc = ParamBox(F=1, f=fF, omega=1, l=0, r=R).midpoint()
    with workprec(256):
        u = [from_number(g) for g in guess(branch, m, None, impacts=True)(sc)]
        G = I.equations(u, I._params(sc), m)
        assert all(abs(g) < arb(10) ** -55 for g in G), G


@pytest.mark.parametrize("branch, fF, R, kind", [(1, "0.3", "20", "elliptic"), (2, "0.3", "3", "saddle"),
                                                 (2, "0.1", "60", "saddle")])
def test_a_point_agrees_with_the_stroboscopic_point_proof(branch, fF, R, kind):
    """At a point, the impact proof's state and trace overlap those of ``prove_periodic``
    (the walk and Table 1: no code in common with the impact equations)."""
    sc = ParamBox(F=1, f=fF, omega=1, l=0, r=R)            # a point box: the point code
    p, ticks = prove(sc, branch)
    q = prove_periodic(sc, *guess(branch, 1, ticks)(sc.midpoint()), phase=ticks)
    assert p.proved and q.proved and p.kind == q.kind == kind
    assert all(a.overlaps(b) for a, b in zip(p.point, q.point)) and p.trace.overlaps(q.trace)
    assert p.trace.rad() < 1e-20 and p.itinerary == ["impact", "impact"]


def test_the_state_on_the_down_flight_agrees_with_the_point_proof():
    """A section in the down-flight (the atlas's is in the up-flight), against ``prove_periodic``."""
    sc = ParamBox(F=1, f="0.3", omega=1, l=0, r="20")
    up = section_ticks(sc.midpoint(), 1)
    down = (up + Fraction(1, 2)) % 1
    p = I.prove_two_impacts(sc, impact_guess(sc, 1), ticks=down)
    q = prove_periodic(sc, *guess(1, 1, down)(sc.midpoint()), phase=down)
    assert p.proved and q.proved and float(q.point[1].mid()) < 0           # moving left: down
    assert all(a.overlaps(b) and a.rad() < 1e-20 for a, b in zip(p.point, q.point))


def test_flights_of_negative_duration_are_refused():
    """The itinerary check on impacts in the wrong order (``b < a``): every other condition
    holds, the durations' does not."""
    sc = ParamBox(F=1, f="0.3", omega=1, l=0, r="20")
    with workprec(128):
        a, A, b, B = (from_number(g) for g in impact_guess(sc, 1))
        assert I._itinerary([a, A, b, B], I._params(sc), 1) is None
        why = I._itinerary([b, A, a, B], I._params(sc), 1)
        assert why is not None and "durations" in why


@pytest.fixture(scope="module")
def slow_x2():
    got, ticks = symmetric_cover(SLOW_X2, 2, kind="saddle", max_leaves=256, method="impacts")
    assert got.proved, got.reason
    return got, ticks


@settings(max_examples=8, deadline=None)
@given(u=st.fractions(0, 1), w=st.fractions(0, 1))
def test_random_points_of_the_slow_x2_box_land_in_their_balls(slow_x2, u, w):
    """Hypothesis: parameters of the proved box, the point reference's Newton at 60 digits from
    the closed form: the fixed point lies in the cover's hull and in the proved ball of the
    leaf that holds the parameters, the trace in that leaf's interval."""
    got, ticks = slow_x2
    box = SLOW_X2
    f, r = box.lo("f") + u * box.width("f"), box.lo("r") + w * box.width("r")
    sc = box.point(f=f, r=r)
    x0, v0 = guess(2, 1, ticks)(sc)
    x, v, tr = reference_fixed_point(sc, x0, v0, got.phase, 1)
    hull = got.hull()
    assert inside(hull[0], x) and inside(hull[1], v) and inside(hull[2], tr)
    leaf = next(p for p in got.leaves if p.box.contains(sc))
    assert inside(leaf.point[0], x) and inside(leaf.point[1], v) and inside(leaf.trace, tr)
    assert leaf.trace > 2


def test_the_period_3_centre_over_a_box():
    box = ParamBox(F=1, f=("0.0625", "0.09375"), omega=1, l=0, r=("43.75", "51.5"))
    got, ticks = symmetric_cover(box, 1, 3, kind="elliptic", max_leaves=512, method="impacts")
    assert got.proved and all(p.kind == "elliptic" for p in got.leaves)
    sc = box.point(f=Fraction(5, 64), r=Fraction(47))
    x, v, tr = reference_fixed_point(sc, *guess(1, 3, ticks)(sc), got.phase, 3)
    leaf = next(p for p in got.leaves if p.box.contains(sc))
    assert inside(leaf.point[0], x) and inside(leaf.point[1], v) and inside(leaf.trace, tr)


def test_a_box_across_the_x2_grazing_boundary_is_refused():
    """Below w^2 R/F = sqrt(4 - pi^2 f^2) = 1.76452 (f = 0.3) x2's impact speed is negative:
    the closed-form zero continues smoothly, the impact is not a true one."""
    box = ParamBox(F=1, f="0.3", omega=1, l=0, r=("1.74", "1.79"))
    p, _ = prove(box, 2)
    assert not p.proved and "grazing" in p.reason
    assert not symmetric_cover(box, 2, kind="saddle", max_leaves=16, method="impacts")[0].proved


def test_the_itinerary_check_is_what_refuses_x1_across_its_sticking_boundary(monkeypatch):
    p, _ = prove(X1_STICKS, 1)
    assert not p.proved and ("up-flight's velocity" in p.reason or "down-flight's velocity" in p.reason)
    # the Krawczyk step succeeds on this box: without the velocity check it would say "proved"
    monkeypatch.setattr(I, "_one_sign", lambda v_of, sign: True)
    wrong, _ = prove(X1_STICKS, 1)
    assert wrong.proved


def test_a_point_on_the_sticking_side_is_refused():
    sc = ParamBox(F=1, f="0.3", omega=1, l=0, r="1.045")
    assert P.nonstick_margin(sc.midpoint(), 1) < 0      # the closed form says: it sticks
    assert "sticks" in impact_guess(sc, 1)              # so the guess refuses; the prover must too
    sol = P.symmetric_solution(sc.midpoint(), 1, dps=60)
    p = I.prove_two_impacts(sc, (sol.psi, sol.v_impact, sol.tau, sol.v_impact),
                            ticks=section_ticks(sc.midpoint(), 1))
    assert not p.proved and "velocity" in p.reason


def test_beyond_the_fold_too_wide_and_an_impact_on_the_section_are_refused():
    near_fold = ParamBox(F=1, f=("0.62", "0.6366"), omega=1, l=0, r=20)    # 2/pi = 0.63662
    p, _ = prove(near_fold, 1)
    assert not p.proved and p.reason
    wide = ParamBox(F=1, f=("0.05", "0.55"), omega=1, l=0, r=("2", "80"))
    p, _ = prove(wide, 1)
    assert not p.proved and "K(Z) is not inside Z" in p.reason and p.split in ("f", "r")
    frictionless = ParamBox(F=1, f=0, omega=1, l=0, r=20)    # x1 hits l at w t = -pi: the section T/2
    with mpmath.workdps(60):
        assert abs(impact_guess(frictionless, 1)[0] + mpmath.pi) < 1e-50
    p = I.prove_two_impacts(frictionless, impact_guess(frictionless, 1), ticks=Fraction(1, 2))
    assert not p.proved and "section" in p.reason
    assert I.prove_two_impacts(frictionless, impact_guess(frictionless, 1), ticks=Fraction(1, 4)).proved


def test_damping_and_a_malformed_guess_are_refused_by_name():
    with pytest.raises(ValueError, match="damping"):
        I.prove_two_impacts(ParamBox(F=1, f="0.3", omega=1, l=0, r=20, damping="0.1"), (0, 1, 3, 1))
    with pytest.raises(TypeError, match="guess"):
        I.prove_two_impacts(ParamBox(F=1, f="0.3", omega=1, l=0, r=20), "no symmetric solution")


# --- uniqueness in the state ball ---------------------------------------------------------
def _both(fF="0.6", R="5"):
    """x1 and x2 at one point, proved at one section where both move right."""
    box = ParamBox(F=1, f=fF, omega=1, l=0, r=R)
    ticks = common_ticks(box.midpoint(), (1, 2))
    return box, ticks, [I.prove_two_impacts(box, impact_guess(box, b), ticks=ticks) for b in (1, 2)]


def test_a_point_orbit_is_the_only_fixed_point_in_its_ball():
    _, _, (x1, x2) = _both()
    assert x1.unique_in_point and x2.unique_in_point
    tiny = ParamBox(F=1, f=("0.3", "0.300001"), omega=1, l=0, r=("20", "20.00001"))
    assert prove(tiny, 1)[0].unique_in_point


def test_a_ball_that_holds_both_orbits_is_not_called_unique():
    """The union of x1's and x2's states (both moving right) holds two fixed points: from
    neither orbit's impact box may the check say that every orbit of it enters."""
    box, ticks, (x1, x2) = _both()
    with workprec(128):
        assert x1.point[1] > 0 and x2.point[1] > 0
        both = tuple(a.union(b) for a, b in zip(x1.point, x2.point))
        for proof in (x1, x2):
            for scale in I.UNIQUE_SCALES:
                U = [arb(k.mid(), r * scale) for k, r in zip(proof.impacts, proof.impact_radii)]
                assert I.every_orbit_enters(U, I._params(box), 1, ticks, proof.point)
                assert not I.every_orbit_enters(U, I._params(box), 1, ticks, both)


@pytest.fixture(scope="module")
def x1_point():
    box = ParamBox(F=1, f="0.3", omega=1, l=0, r="20")
    ticks = section_ticks(box.midpoint(), 1)
    proof = I.prove_two_impacts(box, impact_guess(box, 1), ticks=ticks)
    return box, ticks, proof, P.symmetric_solution(box.midpoint(), 1, dps=60)


def test_a_leg_finds_the_closed_forms_impact_and_refuses_wrong_windows(x1_point):
    box, ticks, proof, sol = x1_point
    with workprec(128):
        p = I._params(box)
        a, A, b, B = (arb(k.mid(), 4 * r) for k, r in zip(proof.impacts, proof.impact_radii))
        ts, up = I._section([a, A, b, B], 1, ticks)
        X, V = proof.point
        assert up
        theta, hit = I.leg(ts, X, V, 1, p[5], b, B, p)
        tau = from_number(sol.tau)                       # the paper's impact on r (independent)
        assert theta.overlaps(tau) and hit.overlaps(from_number(sol.v_impact)) and theta.rad() < 1e-25
        assert I.leg(ts, X, V, 1, p[5], b + arb("0.3"), B, p) is None      # crossed before the window
        assert I.leg(ts, X, V, 1, p[5], b - arb("0.3"), B, p) is None      # not yet at the window
        assert I.leg(ts, X, V, 1, p[5], b, B + 1, p) is None               # the speed is not in U
        assert I.leg(ts, X, -V, 1, p[5], b, B, p) is None                  # moving the other way


def test_a_flight_to_the_section_refuses_an_impact_or_a_turn_on_the_way(x1_point):
    box, ticks, proof, _ = x1_point
    with workprec(128):
        p = I._params(box)
        a, A, b, B = proof.impacts
        ts = I._section(proof.impacts, 1, ticks)[0]
        e, l = p[3], p[4]
        assert I.flies_to(a, l, e * A, 1, ts, p)                       # the orbit's own flight
        assert not I.flies_to(a, l, e * A, 1, b + arb("0.1"), p)         # past the impact on r
        assert not I.flies_to(a, l, arb("0.01"), 1, ts, p)              # friction turns it first


def test_uniqueness_needs_the_krawczyk_test_of_the_wide_box(x1_point):
    """The orbit chain of the point's ball enters its impact box, but with a wrong residual
    (``head`` off by 1) the Krawczyk test fails, and uniqueness must not be claimed."""
    box, ticks, proof, _ = x1_point
    with workprec(128):
        P_ = I._params(box)
        u = [k.mid() for k in proof.impacts]
        C = I._jacobian(u, [arb(0)] * 4, P_, 1).mid().inv().mid()
        head = C * arb_mat([[g] for g in I.equations(u, P_, 1)])
        rho = [arb(r) for r in proof.impact_radii]
        assert I._unique_in_state(u, head, C, P_, 1, rho, ticks, proof.point)
        off = head + arb_mat([[1]] * 4)
        assert not I._unique_in_state(u, off, C, P_, 1, rho, ticks, proof.point)


def test_a_leg_or_a_flight_through_a_stop_is_refused():
    """x1's closed form at f = 0.3, w^2 R/F = 1.045 (the sticking side): its up-flight velocity
    dips below 0 at w t = -arccos(f/F) and recovers, so the closed form still meets the walls at
    the impacts -- but the motion sticks there.  The ends of the legs alone would pass; the
    velocity's sign must refuse them."""
    box = ParamBox(F=1, f="0.3", omega=1, l=0, r="1.045")
    sol = P.symmetric_solution(box.midpoint(), 1, dps=60)
    with workprec(128):
        p = I._params(box)
        psi, tau, V = (from_number(x) for x in (sol.psi, sol.tau, sol.v_impact))
        dip = -(arb("0.3").acos())
        assert psi < dip and dip < tau
        assert I.flight(psi, p[4], V, 1, dip, *p[:3])[1] < 0              # the closed form turns
        end = dip + arb("0.3")
        x_end = I.flight(psi, p[4], V, 1, end, *p[:3])[0]
        assert p[4] < x_end and x_end < p[5]                                # the ends look fine
        assert not I.flies_to(psi, p[4], V, 1, end, p)
        t0 = psi + arb("0.1")
        x0, u0 = I.flight(psi, p[4], V, 1, t0, *p[:3])
        window, speed = arb(tau.mid(), 1e-6), arb(V.mid(), 1e-3)
        lo, hi = window.lower(), window.upper()
        assert I.flight(t0, x0, u0, 1, lo, *p[:3])[0] < p[5] < I.flight(t0, x0, u0, 1, hi, *p[:3])[0]
        assert I.leg(t0, x0, u0, 1, p[5], window, speed, p) is None


def test_the_crossing_narrows_an_off_centre_window(x1_point):
    box, ticks, proof, sol = x1_point
    with workprec(128):
        p = I._params(box)
        ts = I._section(proof.impacts, 1, ticks)[0]
        tau = from_number(sol.tau)
        window = span(tau - arb("0.01"), tau + arb("0.05"))
        theta = I._crossing(ts, *proof.point, 1, p[5], window, p)
        assert theta.contains(tau) and theta.rad() < 1e-3


def test_a_box_proof_holds_the_point_proofs_at_its_corners_and_centre():
    """One impact proof over a whole box, against ``prove_periodic`` (the walk, Table 1) at its
    four corners and its centre: the box's balls contain the points' balls."""
    box = ParamBox(F=1, f=("0.3125", "0.34375"), omega=1, l=0, r=("62", "66"))
    p, ticks = prove(box, 2)
    assert p.proved and p.kind == "saddle"
    corners = [box.point(f=f, r=r) for f in (box.lo("f"), box.hi("f")) for r in (box.lo("r"), box.hi("r"))]
    for sc in corners + [box.midpoint()]:
        q = prove_periodic(sc, *guess(2, 1, ticks)(sc), phase=ticks)
        assert q.proved and q.kind == "saddle"
        assert all(a.contains(b) for a, b in zip(p.point, q.point)) and p.trace.contains(q.trace), sc


@pytest.mark.parametrize("e, fF, R, branch, kind", [("0.9", "0.2", "20", 1, "attracting focus"),
                                                    ("0.95", "0.3", "10", 2, "saddle")])
def test_restitution_below_1_agrees_with_the_stroboscopic_point_proof(e, fF, R, branch, kind):
    """``e < 1`` enters the equations (``e A``, ``-e B``) and the saltation matrices
    (``det = e^4``): against ``prove_periodic`` at the same point, from the ``e = 1`` closed
    form's impacts as the guess (the closed form is for ``e = 1`` only)."""
    box = ParamBox(F=1, f=fF, omega=1, l=0, r=R, restitution=e)
    base = box.replace(restitution=1)
    ticks = section_ticks(base.midpoint(), branch)
    p = I.prove_two_impacts(box, impact_guess(base, branch), ticks=ticks)
    q = prove_periodic(box, p.point[0].mid(), p.point[1].mid(), phase=ticks)
    assert p.proved and q.proved and p.kind == q.kind == kind
    assert all(a.overlaps(b) for a, b in zip(p.point, q.point)) and p.trace.overlaps(q.trace)
    assert p.det.overlaps(q.det) and abs(float(p.det.mid()) - float(Fraction(e)) ** 4) < 1e-15


def test_an_asymmetric_period_2_orbit_agrees_with_the_stroboscopic_point_proof():
    """Two impacts in two periods with flights of unequal length (d1 = 0.90 T, d2 = 1.10 T:
    found by Newton on the impact equations from a guess with unequal flights), against
    ``prove_periodic`` on ``Phi^2``: on the symmetric orbits the two flights' lengths are equal,
    and an exchange of them would go unseen."""
    box = ParamBox(F=1, f="0.1", omega=1, l=0, r=10)
    p = I.prove_two_impacts(box, ("-2.6426", "1.5585", "2.9913", "1.6234"), periods=2, ticks=0)
    a, A, b, B = p.impacts
    assert p.proved and abs(float((b - a).mid()) / (2 * mpmath.pi) - 0.897) < 1e-3
    q = prove_periodic(box, p.point[0].mid(), p.point[1].mid(), periods=2, phase=0)
    assert q.proved and q.itinerary == ["impact", "impact"] and p.kind == q.kind == "saddle"
    assert all(x.overlaps(y) for x, y in zip(p.point, q.point)) and p.trace.overlaps(q.trace)
