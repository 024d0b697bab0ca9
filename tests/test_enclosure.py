"""reference.enclosure: balls that provably contain Phi, Phi' and the event times.

Every proved ball is checked against the *point* reference at higher precision (an
independent code path: mpmath closed forms and the certified point event finder, not the
ball walk), for one state of each kind of itinerary: flights and impacts, turns, sticking,
chatter (its accumulation time too), restitution, damping, several periods, and a box of
start states.  Unprovable states must say why; bad input must raise.
"""
import random

import mpmath
import pytest
from flint import arb, ctx

import reference
from cross_check import scenes
from cross_check.tolerances import tol
from reference.enclosure import enclose_map, motion
from reference.enclosure import certify
from reference.enclosure.balls import BallModel, from_number, workprec
from reference.scene import Scene
from tests.enclosure_checks import DPS, assert_map_contains_the_point_reference, inside


#: (scene, x, v, what the itinerary holds) -- one per kind of itinerary
STATES = [
    ("fig:narrow", "0.3", "0.2", "impacts, frictionless"),
    ("fig:narrow-with-friction", 0.27689242730111235, -0.5784993511404171, "impacts and turns"),
    ("fig:many:wide/f=0.3", "10", "0", "sticking from the start, then slip"),
    ("fig:many:wide/f=0.3", "10.47213719194537815912224858428482513296",
     "-1.099498551433351625825033558234472341516", "turn, stick, slip, turn"),
    ("fig:many:wide/f=0.3", "19.999", "0.01", "chatter at r, contact, release"),
    ("effect:restitution", "0.5", "1.5", "restitution"),
    ("effect:damping", "-0.25", "0.75", "damping"),
    ("effect:zeno", "0.7", "0.1", "frictionless chatter with restitution"),
    ("stuck/F<f", "0.4", "0.3", "stops for good"),
]


@pytest.mark.parametrize("name, x, v, what", STATES, ids=[s[3] for s in STATES])
def test_map_and_jacobian_contain_the_point_reference(name, x, v, what):
    sc = scenes.scene(name)
    enc = enclose_map(sc, x, v)
    assert enc.proved, enc.reason
    assert_map_contains_the_point_reference(enc, sc, x, v)
    assert enc.rel_radius() <= tol("golden_enclosure_rel").rtol


def test_event_times_and_kinds_match_the_point_log():
    sc = scenes.scene("fig:many:wide/f=0.3")
    x, v = "10.47213719194537815912224858428482513296", "-1.099498551433351625825033558234472341516"
    enc = enclose_map(sc, x, v)
    log = reference.trajectory(sc, x, v, sc.period and mpmath.mpf(2) * mpmath.pi, dps=DPS)
    assert [e.kind for e in enc.events] == [e.kind for e in log]
    with workprec(enc.prec):
        for ball, point in zip(enc.events, log):
            assert inside(ball.t, point.t), (ball, point)


def test_the_chatter_accumulation_time_is_enclosed():
    sc = scenes.scene("fig:many:wide/f=0.3")
    enc = enclose_map(sc, "19.999", "0.01")
    log = reference.trajectory(sc, "19.999", "0.01", 2 * mpmath.pi, dps=DPS)
    ball = next(e for e in enc.events if e.kind == "chatter")
    point = next(e for e in log if e.kind == "chatter")
    with workprec(enc.prec):
        assert inside(ball.t, point.t)
    # two-sided tail bounds, second order in the last speed followed: ~1e-7 here, not 40 digits
    assert float(ball.t.rad()) < 1e-6


def test_several_periods_are_one_walk():
    sc = scenes.scene("fig:narrow-with-friction")
    enc = enclose_map(sc, "0.3", "0.2", periods=3)
    assert enc.proved, enc.reason
    xr, vr = reference.stroboscopic_map(sc, "0.3", "0.2", periods=3, dps=DPS)
    with workprec(enc.prec):
        assert inside(enc.phi[0], xr) and inside(enc.phi[1], vr)


def test_a_box_encloses_every_start_in_it():
    sc = scenes.scene("fig:narrow")
    centre, radius = (mpmath.mpf("0.3"), mpmath.mpf("0.2")), mpmath.mpf("1e-12")
    enc = enclose_map(sc, centre[0], centre[1], x_radius=radius, v_radius=radius)
    assert enc.proved, enc.reason
    rng = random.Random(17)
    with workprec(enc.prec):
        for _ in range(6):
            x = centre[0] + radius * (2 * rng.random() - 1)
            v = centre[1] + radius * (2 * rng.random() - 1)
            xr, vr = reference.stroboscopic_map(sc, x, v, dps=DPS)
            assert inside(enc.phi[0], xr) and inside(enc.phi[1], vr)
            J = reference.jacobian(sc, x, v, dps=DPS)
            assert all(inside(enc.jacobian[i][j], J[i][j]) for i in range(2) for j in range(2))


@pytest.mark.parametrize("x, v, x_radius, v_radius, words", [
    ("0.3", "0", 0, "1e-30", "velocity encloses 0"),
    ("0.3", "0.2", "0.01", 0, ""),            # the itinerary changes inside a wide box
])
def test_unprovable_boxes_say_why(x, v, x_radius, v_radius, words):
    sc = scenes.scene("fig:narrow-with-friction")
    enc = enclose_map(sc, x, v, x_radius=x_radius, v_radius=v_radius, max_prec=320)
    assert not enc.proved
    assert words in enc.reason and len(enc.reason) > 20


#: a frictionless scene under position forcing (not shipped): v = 0 is no event there either
FRICTIONLESS_POSITION = Scene(F=1, f=0, omega=1, l=-1, r=1, wavenumber="0.8", name="test: frictionless position-forced")


def _scene_named(name):
    sc = FRICTIONLESS_POSITION
    return scenes.scene(name if name != sc.name else
                        (scenes.register(sc) if sc.name not in scenes.SCENES else sc.name))


@pytest.mark.parametrize("name", ["fig:narrow", FRICTIONLESS_POSITION.name])
def test_a_frictionless_box_whose_velocity_encloses_0_mid_gap_is_proved(name):
    """Without friction ``v = 0`` is no event (one flight on both sides of it), so a box whose
    velocity straddles 0 strictly inside the gap is a box like any other: proved, and its balls
    hold the point reference's ``Phi`` and ``Phi'`` from its centre and from its corners.  The
    false twins stay refused: the same box with friction (``test_unprovable_boxes_say_why``), and
    a frictionless one on a wall, where the sign of ``v`` decides between an impact and a flight."""
    sc = _scene_named(name)
    radius = mpmath.mpf("1e-30")
    enc = enclose_map(sc, "0.3", "0", v_radius=radius)
    assert enc.proved, enc.reason
    for v in ("0", "-1e-30", "1e-30"):
        assert_map_contains_the_point_reference(enc, sc, "0.3", v)
    on_wall = enclose_map(sc, sc.exact("l"), "0", v_radius=radius)     # a dyadic wall: exact
    assert not on_wall.proved and "velocity encloses 0" in on_wall.reason, on_wall.reason


@pytest.mark.parametrize("kwargs, error", [
    ({"periods": 0}, ValueError),
    ({"periods": 1.5}, TypeError),
    ({"prec": 10}, ValueError),
    ({"x_radius": "-1e-3"}, ValueError),
    ({"max_prec": 100}, ValueError),
    ({"phase": 1}, ValueError),
    ({"phase": 0.5}, ValueError),
    ({"x_radius": float("nan")}, ValueError),
])
def test_bad_arguments_raise(kwargs, error):
    with pytest.raises(error):
        enclose_map(scenes.scene("fig:narrow"), "0.3", "0.2", **kwargs)


def test_wrong_types_are_refused():
    with pytest.raises(TypeError, match="scene"):
        enclose_map("fig:narrow", "0.3", "0.2")
    with pytest.raises(TypeError, match="x and x_radius"):
        enclose_map(scenes.scene("fig:narrow"), [0.3], "0.2")
    with pytest.raises(ValueError, match="v and v_radius"):
        enclose_map(scenes.scene("fig:narrow"), "0.3", float("inf"))


def test_precision_does_not_leak():
    before = ctx.prec
    enclose_map(scenes.scene("fig:narrow"), "0.3", "0.2", rel_radius=1e-150)
    enclose_map(scenes.scene("fig:narrow-with-friction"), "0.3", "0", v_radius="1e-30")
    assert ctx.prec == before


def test_krawczyk_encloses_a_closed_form_root_and_exclusion_refuses_a_root():
    """The slip time of sticking from t = 0 is acos(f/F)/w in closed form (mpmath)."""
    sc = scenes.scene("fig:many:wide/f=0.3")
    with workprec(320):
        m = BallModel(sc)
        rest = motion.Rest(m, arb(10))
        up = motion.slip(m, 1)          # f - A: positive while A < f
        # A = cos t first rises through f at t = 2 pi - acos(f)
        with mpmath.workdps(100):
            exact = 2 * mpmath.pi - mpmath.acos(mpmath.mpf("0.3"))
        wide, tight = certify.root(rest, up, from_number(5.0), arb(1), "test")
        assert inside(tight, exact, tol("enclosure_vs_reference_dps60"))
        assert float(tight.rad()) < 1e-80 and wide.contains(tight)
        assert certify.exclude(rest, up, arb(2), wide.lower(), "test") > 0
        with pytest.raises(certify.Unproved, match="slip up"):
            certify.exclude(rest, up, arb(2), arb(6), "test")


# --- periodic orbits (reference.enclosure.orbits) --------------------------------------------
from reference import paper  # noqa: E402
from reference.enclosure.orbits import prove_periodic  # noqa: E402


@pytest.mark.parametrize("name, branch, kind", [
    ("fig:many:wide/f=0.3", 1, "elliptic"), ("fig:many:wide/f=0.3", 2, "saddle"),
    ("fig:wide:b", 1, "elliptic"), ("fig:many:2pi/f=0.1", 2, "saddle"),
])
def test_symmetric_solutions_are_proved_with_the_closed_form_multipliers(name, branch, kind):
    """The paper's symmetric solutions (closed forms of reference.paper, corrected): a unique
    fixed point in a small box, its multipliers enclosing the closed-form ones."""
    sc = scenes.scene(name)
    sol = paper.symmetric_solution(sc, branch, dps=DPS)
    proof = prove_periodic(sc, *sol.state0())
    assert proof.proved, proof.reason
    assert proof.kind == kind and proof.itinerary == ["impact", "impact"]
    expected = sol.multipliers()
    with workprec(proof.prec):
        if kind == "saddle":
            got = sorted(proof.multipliers, key=lambda b: float(b.mid()))
            want = sorted((e.real for e in expected), key=float)
            assert all(inside(b, w) for b, w in zip(got, want)), (got, want)
        else:
            (re, im), = proof.multipliers
            im_ref = expected[0].imag if expected[0].imag > 0 else -expected[0].imag  # exact
            assert inside(re, expected[0].real) and inside(im, im_ref)


def test_a_family_of_fixed_points_is_refused_with_the_reason():
    """Without walls in reach and without friction every state at rest in phase is periodic
    (v(T) = v0, x(T) = x0 + v0 T): the fixed points form a line, none is isolated."""
    sc = scenes.scene("fig:wide:b")
    proof = prove_periodic(sc, "10", "-0.15915494309189533576888376337251436203445964574046", phase=0)
    assert not proof.proved and "not isolated" in proof.reason


# --- properties (hypothesis) ------------------------------------------------------------------
from hypothesis import given, settings  # noqa: E402

from tests.strategies import chattering_orbits, reference_cases  # noqa: E402


@settings(max_examples=25)
@given(reference_cases())
def test_property_a_proved_ball_contains_the_point_reference(case):
    """On any scene and exact state the proof either holds -- and then its map contains the
    point reference at dps 60 -- or says why not."""
    sc, x, v = case
    enc = enclose_map(sc, x, v, max_prec=640)
    if not enc.proved:
        assert len(enc.reason) > 20
        return
    assert_map_contains_the_point_reference(enc, sc, x, v, jacobian=False)


@settings(max_examples=15)
@given(chattering_orbits())
def test_property_chatter_accumulates_inside_its_bound(orbit):
    """A chatter run from the wall: the proved accumulation time contains the reference's
    (extrapolated to its digits, golden_reference_chatter_time), and Phi is proved."""
    sc, x, v = orbit
    enc = enclose_map(sc, x, v)
    assert enc.proved, enc.reason
    log = reference.trajectory(sc, x, v, 2 * mpmath.pi / sc.mpf("omega"), dps=DPS)
    ball = [e for e in enc.events if e.kind == "chatter"]
    point = [e for e in log if e.kind == "chatter"]
    assert len(ball) == len(point) == 1
    slack = tol("ref_chatter_time_dps50")
    with workprec(enc.prec):
        assert inside(ball[0].t, point[0].t, slack)


def test_a_written_ball_contains_the_proved_ball():
    """decimal_ball (golden data, claims JSON): the written interval covers the ball's ends,
    the midpoint's rounding included, and an exact value keeps radius 0."""
    from fractions import Fraction

    from reference.enclosure.balls import decimal_ball
    with workprec(320):
        ball = arb(1) / 3 + arb(0, arb(2) ** -200)
        for digits in (5, 20, 50):
            mid, radius = decimal_ball(ball, digits)
            low, high = Fraction(mid) - Fraction(radius), Fraction(mid) + Fraction(radius)
            assert from_number(low) <= ball.lower() and from_number(high) >= ball.upper()
            assert radius < 10.0 ** (1 - digits)
        assert decimal_ball(arb(1), 50)[1] == 0.0
