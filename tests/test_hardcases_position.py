"""Hard cases under position forcing (issue 33), built backward with the reference's Taylor flight
and certified by a validated one (``cross_check.agreement.hardcases_position``).

For every kind on two unseen scenes (``A``: no damping, no restitution; ``B``: both) and eq. xpot
(whose walls see no force, so it has rest intervals and no chatter) -- together every kind of
``hardcases.NAMES``:

* the reference, integrating forward from the decimal state, finds the constructed event first,
  at the constructed time (to what the state's 30 digits allow), as the certificate says;
* fast, on the float64 rounding, finds the reference's first event (from the same rounding) at
  its time, outside the near-grazing band (``golden_proof.band``);
* the certificate refuses an event state whose backward flight meets a wall or ``v = 0`` before
  ``t = 0``, and accepts the states the construction certified.
"""
from __future__ import annotations

import functools

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings

import reference
from cross_check import golden, golden_proof
from cross_check.agreement import compare, hardcases, impact_at_t, impact_backward
from cross_check.agreement import hardcases_position as HP
from cross_check.agreement.case import Case, ConstructionError, decimal_text
from cross_check.tolerances import tol
from reference.enclosure.maps import MapEnclosure
from reference.scene import Scene
from tests.hardcase_checks import assert_impact_at_T
from tests.strategies import position_forced_scenes

SCENES = {
    "A": Scene(F=1, f="0.15", omega="1.7", l="-0.4", r="0.9", wavenumber="1.3"),
    "B": Scene(F=2, f="0.3", omega="1.2", l=-1, r=1, restitution="0.8", damping="0.05", wavenumber="0.7"),
    "xpot": Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2"),
    # l = -0.7 rounds outward at the candidates' precision: its wall kinds were refused as
    # "outside the gap" before the certificate started from the wall's own ball
    "C": Scene(F="1.5", f="0.2", omega="2.3", l="-0.7", r="0.6", restitution="0.9", damping="0.02",
               wavenumber="2.1"),
}
DPS = 30


@functools.lru_cache(maxsize=None)
def built(name):
    return hardcases.construct(SCENES[name])


def _case(name, case_name):
    return next(c for c in built(name)[0] if c.name == case_name)


def test_every_kind_is_built_on_some_scene_and_the_rest_say_why():
    kinds = {c.name for n in SCENES for c in built(n)[0]}
    assert kinds == set(hardcases.NAMES), set(hardcases.NAMES) - kinds
    for name in SCENES:
        cases, why = built(name)
        assert {c.name for c in cases} | set(why) == set(hardcases.NAMES)
        assert all("position-dependent forcing" not in w for w in why.values())
        assert all("certified:" in c.how for c in cases if c.name not in ("at_rest", "chatter"))


@pytest.mark.parametrize("name, case_name", [(n, k) for n in SCENES for k in hardcases.NAMES])
def test_the_reference_finds_the_constructed_event_at_the_constructed_time(name, case_name):
    cases, why = built(name)
    if case_name not in {c.name for c in cases}:
        assert case_name in why      # not admitted here: the scene says why (another scene builds it)
        return
    sc, c = SCENES[name], _case(name, case_name)
    with mpmath.workdps(DPS + 10):
        t_star = mpmath.mpf(c.t_event)
        end = max(t_star, mpmath.mpf("0.5")) * (1 + mpmath.mpf("1e-6")) + mpmath.mpf("1e-6")
        log = reference.trajectory(sc, c.x, c.v, end, dps=DPS)
        kinds = [e.kind for e in compare.canonical(log, sc)]
        walls = (sc.mpf("l"), sc.mpf("r"))
        first = log[0] if len(log) else None
        at_wall = first is not None and min(abs(first.x - w) for w in walls) < mpmath.mpf(10) ** -25
        if case_name in ("grazing", "crossing_pair"):
            # the 30-digit state moves a near-tangential impact by its rounding over the speed
            assert first.kind == "impact" and at_wall
            slack = mpmath.mpf(10) ** -(HP.STATE_DIGITS - 5) / abs(first.v_before)
            assert abs(first.t - t_star) < slack, (first, t_star)
        elif case_name == "turn_at_wall":
            # within 1e-30 of the tangency: a near miss (a turn, or a stop where |A| <= f) or a graze
            assert first.kind in ("turn", "stick", "contact", "impact") and at_wall
            assert abs(first.t - t_star) < mpmath.mpf(10) ** -12
        elif case_name == "impact_at_T":
            # the first event, or on a narrow gap (impact_at_t: from rest) the impact nearest T
            T = 2 * mpmath.pi / sc.mpf("omega")
            near = min((e for e in log if e.kind == "impact"), key=lambda e: abs(e.t - T))
            assert min(abs(near.x - w) for w in walls) < mpmath.mpf(10) ** -25 and abs(near.t - T) < mpmath.mpf(10) ** -20
            through = "from rest through" if c.v == "0" else f"from x0 at v0 = {c.v} through"
            assert near is first or through in c.how, (list(log), c.how)
        elif case_name == "stick_slip_boundary":
            assert first.kind in ("turn", "stick") and abs(first.t - t_star) < mpmath.mpf(10) ** -12
        elif case_name in ("sticking", "stopping"):
            assert first.kind == "stick" and abs(first.t - t_star) < mpmath.mpf(10) ** -20
            if case_name == "stopping":
                assert kinds == ["stick"] and log.v_end == 0
            else:
                assert "slip" in [e.kind for e in reference.trajectory(sc, c.x, c.v, 2 * sc.period, dps=DPS)]
        elif case_name == "at_rest":
            assert kinds in ([], ["stick"]) and log.v_end == 0
            assert abs(log.x_end - mpmath.mpf(c.x)) < mpmath.mpf(10) ** -25
        elif case_name == "chatter":
            assert "chatter" in kinds


#: the corner of the random scenes (issue 33): a gap of 0.2, a period of 12.6, ``F = 3``; a flight of
#: ~0.35 crosses the gap, and every flight run back from ``t* >= 3T/64 = 0.59`` meets a wall
NARROW_LONG = Scene(F=3, f="0.3", omega="0.5", l=0, r="0.2", wavenumber=2, restitution="0.6")


def test_wall_kinds_early_in_the_period_on_a_narrow_gap(monkeypatch):
    """The graze, the crossing pair and the turn at a wall are built at ``t* = T / 2^m``
    (``HP.EARLY``), each a single flight from ``t = 0`` certified by its backward flight; the
    reference from the start at 30 digits meets the wall at ``t*`` first (a near-tangential
    impact within its rounding over the speed, the turn within 1e-12).  Without the early
    times none of them is built, and each says why."""
    sc = NARROW_LONG
    monkeypatch.setattr(impact_at_t, "construct", lambda scene, digits: (None, "not in this test"))
    walls = ("grazing", "crossing_pair", "turn_at_wall")
    with mpmath.workdps(HP.CONSTRUCT_DPS):
        built, notes = {}, {}
        HP._wall_kinds(sc, built, notes)
    for name in walls:
        c = built.get(name)
        assert c is not None and "certified" in c.how, notes.get(name)
        with mpmath.workdps(DPS + 10):
            t_star, T = mpmath.mpf(c.t_event), 2 * mpmath.pi / sc.mpf("omega")
            assert any(abs(t_star - T / 2 ** m) < mpmath.mpf(10) ** -20 for m in HP.EARLY)
            first = reference.trajectory(sc, c.x, c.v, 2 * t_star, dps=DPS)[0]
            assert first.kind in ("impact", "turn", "contact") and abs(first.x - sc.mpf("l")) < mpmath.mpf(10) ** -25
            slack = mpmath.mpf(10) ** -12 if name == "turn_at_wall" else \
                mpmath.mpf(10) ** -(HP.STATE_DIGITS - 5) / abs(first.v_before)
            assert abs(first.t - t_star) < slack, (name, first, t_star)
    monkeypatch.setattr(HP, "EARLY", ())
    with mpmath.workdps(HP.CONSTRUCT_DPS):
        built, notes = {}, {}
        HP._wall_kinds(sc, built, notes)
    assert not any(built.get(name) for name in walls)
    assert all("no single flight from t = 0 reaches it" in notes[name] for name in walls)


@pytest.mark.parametrize("name", list(SCENES))
def test_fast_finds_the_reference_events_outside_the_band(name):
    """fast against the reference on the same float64 state: the first canonical event (the
    constructed one, or what the rounding made of it), its kind and time -- the time within
    ``golden_fast_phi_per_cond`` times the conditioning ``max(1, |Phi'|, kappa)`` (the golden
    standard; ``kappa = (F/w)/|v-|`` of the impacts, ``golden.kappa``: an impact time moves by the
    position's error over the speed; chatter within ``golden_fast_chatter_time``) -- unless the
    reference's itinerary is in the band."""
    sc = SCENES[name]
    cases = [c for c in built(name)[0]]
    X = np.array([float(c.x) for c in cases])
    V = np.array([float(c.v) for c in cases])
    f_logs = compare.fast_events(sc, X, V)
    J = compare.fast_jacobian(sc, X, V)
    problems = []
    for i, c in enumerate(cases):
        fc = Case(c.name, repr(float(X[i])), repr(float(V[i])), "float64", c.how)
        if golden_proof.band(sc, fc):
            continue
        ref_log = compare.ref_events(sc, fc, None, DPS)
        ref = compare.canonical(ref_log, sc)
        cond = max(1.0, float(np.abs(J[i]).max()), golden.kappa(sc, {"events": ref_log}))
        got = compare.canonical(f_logs[i], sc)
        # the constructed event: the first one; of a chatter case, its accumulation too
        last = next(j for j, r in enumerate(ref) if r.kind == "chatter") if c.name == "chatter" else 0
        if [e.kind for e in got[:last + 1]] != [r.kind for r in ref[:last + 1]]:
            problems.append(f"{name}/{c.name}: fast {[e.kind for e in got[:3]]} != "
                            f"reference {[e.kind for e in ref[:3]]}")
            continue
        for e, r in zip(got[:last + 1], ref):
            rtol = (tol("golden_fast_chatter_time").rtol if e.kind == "chatter"
                    else tol("golden_fast_phi_per_cond").rtol * cond)
            dt, allowed = abs(float(e.t) - float(r.t)), rtol * max(1.0, abs(float(r.t)))
            if dt > allowed:
                problems.append(f"{name}/{c.name}: {e.kind} at {float(e.t)!r}, reference {float(r.t)!r} "
                                f"(|dt| = {dt:.1e}, tolerance {allowed:.1e})")
    assert not problems, "\n".join(problems)


def test_the_certificate_refuses_a_backward_flight_that_meets_an_earlier_event():
    """An impact at r arrived at so fast that the flight, run back, crosses l before ``t = 0``; a
    stop mid-gap whose backward flight passes ``v = 0`` (a turn the case would hide): both refused
    by the validated exclusion; the short, clean versions of the same states are certified."""
    sc = SCENES["A"]
    with mpmath.workdps(HP.CONSTRUCT_DPS):
        T, r = 2 * mpmath.pi / sc.mpf("omega"), sc.mpf("r")
        x0, _ = HP.start(sc, T * 9 / 10, r, mpmath.mpf(3), 1)
        assert x0 < sc.mpf("l")                                # it really leaves the gap
        with pytest.raises(ConstructionError, match="certificate refused"):
            HP.certify_flight(sc, T * 9 / 10, r, mpmath.mpf(3), 1)
        with pytest.raises(ConstructionError, match="certificate refused"):
            HP.certify_flight(sc, T * 9 / 10, mpmath.mpf("0.2"), mpmath.mpf(0), -1)
        good = HP.certify_flight(sc, T / 20, r, mpmath.mpf(3), 1)
        x0, v0 = HP.start(sc, T / 20, r, mpmath.mpf(3), 1)
        assert good.pieces > 0 and HP._inside(x0, good.x0, 50) and HP._inside(v0, good.v0, 50)
        HP.certify_flight(sc, T / 20, mpmath.mpf("0.2"), mpmath.mpf(0), -1)


def test_an_event_state_on_a_wall_is_certified_from_the_wall_and_one_off_it_is_refused():
    """The wall kinds are built on scene C whichever way its walls round (``l = -0.7`` rounds
    outward at 30 digits); a point 1e-25 outside the gap is not a wall and is refused."""
    sc = SCENES["C"]
    cases, why = built("C")
    assert {"grazing", "crossing_pair", "turn_at_wall"} <= {c.name for c in cases}, why
    with mpmath.workdps(HP.CONSTRUCT_DPS):
        l, T = sc.mpf("l"), 2 * mpmath.pi / sc.mpf("omega")
        assert HP.wall_side(sc, l) == -1 and HP.wall_side(sc, sc.mpf("r")) == 1
        assert HP.wall_side(sc, l - mpmath.mpf("1e-25")) == 0
        with pytest.raises(ConstructionError, match="outside the gap"):
            HP.certify_flight(sc, T / 20, l - mpmath.mpf("1e-25"), mpmath.mpf("-0.5"), -1)


def test_impact_at_T_from_rest_needs_its_bracket_and_its_forward_proof(monkeypatch):
    """Scene C's gap is too narrow for a flight of a whole period: ``impact_at_t`` builds the
    case from rest through a turn.  Refused: a bracket whose ends both impact before ``T``, and a
    start whose forward proof fails (``enclose_map`` made to say no: the certificate decides)."""
    sc = SCENES["C"]
    case = _case("C", "impact_at_T")
    assert case.v == "0" and "from rest through" in case.how and "certified" in case.how
    x0 = float(case.x)
    with mpmath.workdps(impact_at_t.REFINE_DPS + 10):
        T = 2 * mpmath.pi / sc.mpf("omega")
        with pytest.raises(ConstructionError, match="does not bracket"):
            impact_at_t._refine(sc, x0 - 2e-3, x0 - 1e-3, T, HP.STATE_DIGITS)
    bits = []
    monkeypatch.setattr(impact_at_t, "enclose_map",
                        lambda *a, **k: bits.append(k["max_prec"]) or MapEnclosure(False, "a failure, injected"))
    case, why = impact_at_t.construct(sc, HP.STATE_DIGITS)
    assert case is None and "the forward proof failed: a failure, injected" in why
    first, most = impact_at_t.PROOF_FIRST_PREC, impact_at_t.PROOF_MAX_PREC
    assert bits[:2] == [first, most] and set(bits) == {first, most}     # no climb to 1280 bits


def test_a_forward_proof_takes_its_first_bits_and_more_only_where_they_fail(monkeypatch):
    """``impact_at_t.forward_proof``: the proof at ``PROOF_FIRST_PREC`` bits where it holds; where
    it fails, the one from ``DEFAULT_PREC`` up to ``PROOF_MAX_PREC``, proved or not."""
    calls = []

    def fake(scene, x, v, prec=320, max_prec=320, holds=()):
        calls.append((prec, max_prec))
        return MapEnclosure(prec in holds, None if prec in holds else "no")

    for holds, tried, proved in (((128,), [(128, 128)], True), ((320,), [(128, 128), (320, 320)], True),
                                 ((), [(128, 128), (320, 320)], False)):
        calls[:] = []
        monkeypatch.setattr(impact_at_t, "enclose_map", lambda *a, holds=holds, **k: fake(*a, holds=holds, **k))
        assert impact_at_t.forward_proof(SCENES["C"], "0.1", "0").proved is proved and calls == tried


def test_impact_at_T_at_restitution_0_through_plastic_impacts(monkeypatch):
    """At restitution 0 an impact leaves the particle at rest at the wall, off at once where the
    force pulls it away (``reference.enclosure.walk``: proved).  On this unseen scene (drawn by
    hypothesis) no start reaches ``T``'s impact without one: the case is built from rest through
    two plastic impacts, proved forward, and the reference meets the impact at ``T``.  Without
    impacts among the kinds allowed before it (as it was while the walk refused them) it is
    not built."""
    sc = Scene(F="1.28", f="0.124", omega="0.501", l="-1.14", r="1.18", wavenumber="2.214", restitution=0)
    case, why = impact_at_t.construct(sc, HP.STATE_DIGITS)
    assert why is None and "through impact, impact (event 3)" in case.how and "certified" in case.how, why
    assert_impact_at_T(sc, case)
    monkeypatch.setattr(impact_at_t, "PREFIX_KINDS", impact_at_t.PREFIX_KINDS - {"impact"})
    case, why = impact_at_t.construct(sc, HP.STATE_DIGITS)
    assert case is None and "brackets an impact at T" in why


def test_impact_at_T_refinement_refuses_a_jump_and_keeps_a_steep_root(monkeypatch):
    """``impact_at_t._refine`` on model ``h = t_j(x0) - T`` (the reference's runs replaced): a
    jump (``h`` = +1.1 left of ``x = 0.3``, -1.1 right of it, as an earlier event grazing makes
    on the frictionless far corner of issue 33) is refused as a jump in fewer than
    ``MAX_REFINE`` runs, and without ``JUMP_SLOPE`` it takes them all; a root where ``h`` is
    ~220 times steeper than across the bracket is found (``|h| < 10^-(digits + 3)``)."""
    from types import SimpleNamespace

    runs = []

    def model(h):
        def trajectory(scene, x0, t_end, v0="0"):
            runs.append(x0)
            return [SimpleNamespace(kind="impact", t=h(x0) + T)]
        return trajectory

    T = mpmath.mpf(10)
    jump = model(lambda x: mpmath.mpf("1.1") if x < mpmath.mpf("0.3") else mpmath.mpf("-1.1"))
    monkeypatch.setattr(impact_at_t, "_trajectory", jump)
    with mpmath.workdps(impact_at_t.REFINE_DPS + 10):
        with pytest.raises(ConstructionError, match="jumps in"):
            impact_at_t._refine(None, 0.25, 0.32, T, HP.STATE_DIGITS)
        assert len(runs) < impact_at_t.MAX_REFINE
        monkeypatch.setattr(impact_at_t, "JUMP_SLOPE", mpmath.inf)
        runs.clear()
        with pytest.raises(ConstructionError, match="no start"):
            impact_at_t._refine(None, 0.25, 0.32, T, HP.STATE_DIGITS)
        assert len(runs) == impact_at_t.MAX_REFINE + 2          # the two ends, then the bound
        monkeypatch.undo()
        # steep near its root, shallow elsewhere: ~220 times the bracket's secant slope at x = 0.3
        steep = model(lambda x: mpmath.atan(10000 * (mpmath.mpf("0.3") - x)) / 10)
        monkeypatch.setattr(impact_at_t, "_trajectory", steep)
        x0, kinds, j = impact_at_t._refine(None, 0.25, 0.32, T, HP.STATE_DIGITS)
        assert abs(x0 - mpmath.mpf("0.3")) < mpmath.mpf(10) ** -(HP.STATE_DIGITS + 3) and kinds == ["impact"]


def test_a_jump_that_fast_narrows_to_is_not_refined_again_and_a_root_is(monkeypatch):
    """``impact_at_t._fast_jump``: on the frictionless far corner of issue 33 the bracket from rest
    ``[-0.078125, -0.0703125]`` straddles a jump of the fourth impact's time (an earlier event
    grazes); fast narrows it to ~5e-10 around the jump, with ``t_j - T`` still ~1.1 at both ends:
    a jump, which ``_refined`` refuses before any run of the reference.  Scene C's bracket
    narrows around its root: not a jump."""
    sc = Scene(F=2, f=0, omega="0.5", l=-1, r=1, wavenumber=2, name="test: impact at T jump")
    xa, xb = -0.078125, -0.0703125
    na, nb = impact_at_t._narrowed(sc, xa, xb)
    assert xa < na < nb < xb and nb - na < 1e-8
    assert impact_at_t._fast_jump(sc, (xa, xb), (na, nb), "0")
    runs = []
    monkeypatch.setattr(impact_at_t, "_trajectory", lambda *a, **k: runs.append(a) or [])
    with mpmath.workdps(impact_at_t.REFINE_DPS + 10), pytest.raises(ConstructionError, match="jumps in fast's"):
        impact_at_t._refined(sc, xa, xb, 2 * mpmath.pi / sc.mpf("omega"), HP.STATE_DIGITS)
    assert runs == []
    monkeypatch.undo()
    sc = SCENES["C"]
    x0 = float(_case("C", "impact_at_T").x)
    (xa, xb, _), = [b for b in impact_at_t._brackets(sc) if b[0] <= x0 <= b[1] and b[2] == "0"]
    assert not impact_at_t._fast_jump(sc, (xa, xb), impact_at_t._narrowed(sc, xa, xb), "0")


def test_impact_at_T_narrowed_by_fast_gives_the_same_start_or_falls_back(monkeypatch):
    """fast narrows scene C's bracket (``_narrowed``) to one that still brackets in fast, ~1e7
    times narrower, around the start the reference places; a narrowed bracket in which the
    reference finds no crossing falls back to the bracket itself, and the start is the same."""
    sc = SCENES["C"]
    x0 = float(_case("C", "impact_at_T").x)
    (xa, xb, _), = [b for b in impact_at_t._brackets(sc) if b[0] <= x0 <= b[1] and b[2] == "0"]
    na, nb = impact_at_t._narrowed(sc, xa, xb)
    assert xa <= na < nb <= xb and (nb - na) < (xb - xa) * 1e-6 and na <= x0 <= nb
    assert impact_at_t._crossings(sc, np.array([na, nb])) == [0]
    with mpmath.workdps(impact_at_t.REFINE_DPS + 10):
        T = 2 * mpmath.pi / sc.mpf("omega")
        good = impact_at_t._refined(sc, xa, xb, T, HP.STATE_DIGITS)
        tried, real = [], impact_at_t._refine
        monkeypatch.setattr(impact_at_t, "_refine", lambda *a: tried.append(a[1:3]) or real(*a))
        monkeypatch.setattr(impact_at_t, "_narrowed", lambda sc, a, b, v0: (a, a + (b - a) * 1e-3))
        again = impact_at_t._refined(sc, xa, xb, T, HP.STATE_DIGITS)
    assert tried == [(xa, xa + (xb - xa) * 1e-3), (xa, xb)]          # refused, then the bracket
    for x in (good[0], again[0]):
        assert decimal_text(x, HP.STATE_DIGITS) == _case("C", "impact_at_T").x


#: an unseen scene (issue 33, drawn at random) where no start from rest brackets an impact at T
MOVING = Scene(F="0.78", f="0.305", omega="1.83", l="-1.07", r="0.43", wavenumber="2.275", damping="0.044",
               restitution="0.7", name="test: impact at T from a moving start")


def test_impact_at_T_from_a_moving_start_where_none_from_rest_brackets_it(monkeypatch):
    """No start from rest brackets an impact at ``T`` on this scene; a scan at one of
    ``impact_at_t.speeds`` does, and the case is built from that speed, certified forward: the
    reference from it meets an impact at a wall within 1e-20 of ``T``.  Without the other speeds
    (``SPEEDS = ()``) it is not built, and the reason says why.  Where the scan from rest gives the
    case (scene C) the other speeds are never scanned."""
    sc = MOVING
    assert impact_at_t._scan(sc, "0") == []
    case, why = impact_at_t.construct(sc, HP.STATE_DIGITS)
    assert why is None and case.v in impact_at_t.speeds(sc) and case.v != "0", why
    assert f"from x0 at v0 = {case.v} through" in case.how and "certified" in case.how
    assert_impact_at_T(sc, case)
    monkeypatch.setattr(impact_at_t, "SPEEDS", ())
    monkeypatch.setattr(impact_at_t, "FAST_SPEEDS", ())
    monkeypatch.setattr(impact_backward, "proposals", lambda scene: ([], []))
    case, why = impact_at_t.construct(sc, HP.STATE_DIGITS)
    assert case is None and "brackets an impact at T" in why
    monkeypatch.undo()
    scans, scan = [], impact_at_t._scan
    monkeypatch.setattr(impact_at_t, "_scan", lambda sc, v0: scans.append(v0) or scan(sc, v0))
    case, why = impact_at_t.construct(SCENES["C"], HP.STATE_DIGITS)
    assert why is None and case.v == "0" and scans == ["0"]


#: an unseen scene (issue 33, drawn at random: restitution 0.6 and damping) where every start up
#: to 2V, from rest or moving, chatters into contact before T
FAST_START = Scene(F="2.45", f="0.803", omega="1.63", l="-1.3", r="-0.31", wavenumber="1.455",
                   damping="0.171", restitution="0.6", name="test: impact at T from a fast start")


def test_impact_at_T_from_a_fast_start_where_every_slower_one_dies_into_contact(monkeypatch):
    """No scan of ``SPEEDS`` (up to ``2V``) brackets an impact at ``T``; a speed the backward
    screen proposes (``impact_backward``, ~5.5 V) does, and the case is built from it,
    certified: the reference from it meets an impact at a wall within 1e-20 of ``T``.  Without
    the screen (and ``FAST_SPEEDS``, which find it too) it is not built, and says why."""
    sc = FAST_START
    assert all(impact_at_t._scan(sc, v0) == [] for v0 in ["0"] + impact_at_t.speeds(sc))
    case, why = impact_at_t.construct(sc, HP.STATE_DIGITS)
    assert why is None and case.v in impact_backward.proposals(sc)[0], why
    assert_impact_at_T(sc, case)
    monkeypatch.setattr(impact_backward, "proposals", lambda scene: ([], []))
    monkeypatch.setattr(impact_at_t, "FAST_SPEEDS", ())
    case, why = impact_at_t.construct(sc, HP.STATE_DIGITS)
    assert case is None and "brackets an impact at T" in why


#: an unseen scene (issue 33, drawn as the verify benchmark draws them, seed 107) whose impact at T
#: comes after 14 impacts, a stop and a slip, from a band of fast starts near 3.5 V
THROUGH_A_STOP = Scene(F="2.02", f="1.202", omega="1.01", l="-0.73", r="0.9", wavenumber="0.951",
                       damping="0.113", restitution="0.9", name="test: impact at T through a stop")


def test_impact_at_T_through_a_stop_from_a_fast_start_within_the_event_budget(monkeypatch):
    """The backward screen stops at the stop (``v = 0``: the forward motion forgets how it came),
    and no scan of ``SPEEDS`` brackets the impact; a scan of ``FAST_SPEEDS`` does, within
    ``MORE_EVENTS`` of fast's events, and the case holds in the reference.  With no budget
    (``MORE_EVENTS = 0``) only the first of those scans is made, and the case is not built."""
    sc = THROUGH_A_STOP
    assert impact_backward.proposals(sc)[0] == []
    case, why = impact_at_t.construct(sc, HP.STATE_DIGITS)
    assert why is None and case.v in impact_at_t.speeds(sc, impact_at_t.FAST_SPEEDS), why
    assert "stick, slip" in case.how
    assert_impact_at_T(sc, case)
    scans, scan = [], impact_at_t._scan
    monkeypatch.setattr(impact_at_t, "_scan", lambda sc, v0, spent=None: scans.append(v0) or scan(sc, v0, spent))
    monkeypatch.setattr(impact_at_t, "MORE_EVENTS", 0)
    case, why = impact_at_t.construct(sc, HP.STATE_DIGITS)
    fastest = impact_at_t.speeds(sc, impact_at_t.FAST_SPEEDS)
    assert case is None and "within 0 events of fast" in why
    assert [v for v in scans if v in fastest] == fastest[:1]


#: an unseen scene (issue 33, drawn at random) whose force at t = 0 pushes into neither wall
#: beyond friction; it chatters at l later in the period
LATE_CHATTER = Scene(F="1.11", f="0.645", omega="2.82", l="-0.41", r="2.32", wavenumber="0.729",
                     damping="0.095", restitution="0.9", name="test: chatter later in the period")


def test_chatter_later_in_the_period_where_the_push_at_t0_is_below_friction(monkeypatch):
    """``hardcases``' explicit chatter start needs a push beyond ``f`` at ``t = 0``; here there is
    none, and ``forward_position`` finds a start whose chatter run comes later: the reference from
    it at 30 digits has the run, accumulating at the case's time, and the forward proof holds.
    Refused: a candidate whose reference does not chatter (the screen pointed at a start from rest
    mid-gap), and one whose proof fails (``enclose_map`` made to say no).  No speed is scanned
    after the one that gives the case."""
    from cross_check.agreement import forward_position

    sc = LATE_CHATTER
    built, notes = {}, {}
    with mpmath.workdps(hardcases.CONSTRUCT_DPS):
        hardcases._chatter_case(sc, built, notes)
    case = built.get("chatter")
    assert case is not None and "chatter run at l" in case.how and "certified" in case.how, notes
    with mpmath.workdps(DPS + 10):
        t_inf = mpmath.mpf(case.t_event)
        log = reference.trajectory(sc, case.x, case.v, t_inf * (1 + mpmath.mpf("1e-6")), dps=DPS)
        run = next(e for e in log if e.kind == "chatter")
        assert abs(run.t - t_inf) < mpmath.mpf(10) ** -15 and abs(run.x - sc.mpf("l")) < mpmath.mpf(10) ** -25
    monkeypatch.setattr(forward_position, "candidates", lambda sc, hits_of: iter([(0.9, "0", 1.0, 1)]))
    refused, why = forward_position.chatter(sc, hardcases.RHO_MAX)
    assert refused is None and "has no chatter event" in why
    monkeypatch.undo()
    monkeypatch.setattr(impact_at_t, "enclose_map", lambda *a, **k: MapEnclosure(False, "a failure, injected"))
    refused, why = forward_position.chatter(sc, hardcases.RHO_MAX)
    assert refused is None and "a failure, injected" in why
    monkeypatch.undo()
    scanned, chattering = [], forward_position._chattering      # no scan after the case's speed
    monkeypatch.setattr(forward_position, "_chattering", lambda sc, x, v0, rho, spent=None: scanned.append(v0) or chattering(sc, x, v0, rho, spent))
    again, _ = forward_position.chatter(sc, hardcases.RHO_MAX)
    assert again == case and scanned == (["0"] + impact_at_t.speeds(sc))[:len(scanned)] and scanned[-1] == case.v


#: an unseen scene (issue 33, drawn at random: restitution 0.9, no damping) whose push at t = 0 is
#: below friction at both walls, and whose chatter runs start from a band of slow starts that
#: falls between ``impact_at_t.SPEEDS``
SLOW_CHATTER = Scene(F="1.21", f="0.219", omega="1.3", l="-0.69", r="1.05", wavenumber="1.991",
                     restitution="0.9", name="test: chatter from a slow start")


def test_chatter_from_a_slow_start_between_the_coarse_speeds(monkeypatch):
    """No start from rest or at ``speeds`` chatters before ``CHATTER_BY T``; one at
    ``SLOW_SPEEDS`` does: the reference from it has the run at ``r``, accumulating at the
    case's time.  Without ``SLOW_SPEEDS`` it is not built, and says why."""
    from cross_check.agreement import forward_position

    sc = SLOW_CHATTER
    case, why = forward_position.chatter(sc, hardcases.RHO_MAX)
    assert why is None and case.v in impact_at_t.speeds(sc, forward_position.SLOW_SPEEDS), why
    with mpmath.workdps(DPS + 10):
        t_inf = mpmath.mpf(case.t_event)
        log = reference.trajectory(sc, case.x, case.v, t_inf * (1 + mpmath.mpf("1e-6")), dps=DPS)
        run = next(e for e in log if e.kind == "chatter")
        assert abs(run.t - t_inf) < mpmath.mpf(10) ** -15 and abs(run.x - sc.mpf("r")) < mpmath.mpf(10) ** -25
    monkeypatch.setattr(forward_position, "SLOW_SPEEDS", ())
    case, why = forward_position.chatter(sc, hardcases.RHO_MAX)
    assert case is None and "chatters before" in why


def test_no_chatter_where_the_force_never_pushes_into_a_wall_beyond_friction(monkeypatch):
    """``|F cos(k l)|`` and ``|F cos(k r)|`` at most ``f``: no push into a wall ever exceeds
    friction, so no scene chatters and none is scanned for; with one wall above ``f`` the scan
    runs (here it finds none, and says so)."""
    from cross_check.agreement import forward_position

    calls = []
    monkeypatch.setattr(forward_position, "chatter", lambda sc, rho: calls.append(sc) or (None, "none found"))
    quiet = Scene(F=1, f="0.5", omega=1, l=-1, r=1, wavenumber="1.266", restitution="0.9")    # |cos(k)| ~ 0.30
    loud = Scene(F=1, f="0.5", omega=1, l=-1, r=2, wavenumber="1.266", restitution="0.9")     # |cos(2k)| ~ 0.82
    for sc in (quiet, loud):
        built, notes = {}, {}
        with mpmath.workdps(hardcases.CONSTRUCT_DPS):
            hardcases._chatter_case(sc, built, notes)
        assert built.get("chatter") is None
        assert ("never pushes into a wall beyond friction" in notes["chatter"]) == (sc is quiet), notes
    assert calls == [loud]


@settings(max_examples=4, deadline=None)
@given(position_forced_scenes())
def test_hard_cases_on_random_scenes_are_built_or_say_why_and_hold(sc):
    """Every parameter and effect drawn: each kind is built or not admitted with its reason
    (never an exception), and the reference, from each built start at 30 digits, meets the
    case's event at its time: the first event of a single flight, or the impact nearest ``T``
    of an ``impact_at_T`` through earlier events (from rest or a moving start)."""
    cases, why = hardcases.construct(sc)
    assert {c.name for c in cases} | set(why) == set(hardcases.NAMES), why
    with mpmath.workdps(DPS + 10):
        for c in cases:
            if c.name not in ("impact_at_T", "sticking", "grazing", "crossing_pair"):
                continue
            t_star = mpmath.mpf(c.t_event)
            log = reference.trajectory(sc, c.x, c.v, t_star * (1 + mpmath.mpf("1e-6")) + mpmath.mpf("1e-6"), dps=DPS)
            near = min(log, key=lambda e: abs(e.t - t_star))
            assert abs(near.t - t_star) < mpmath.mpf(10) ** -12, (c.name, c.how, list(log))
            assert near.kind == ("stick" if c.name == "sticking" else "impact"), (c.name, list(log))


def test_a_case_is_refused_when_its_backward_flight_meets_a_wall(monkeypatch):
    """``build`` tries the candidates in turn and refuses those the certificate refuses: with the
    float64 screen passing everything, the long flight into r is skipped for the next."""
    sc = SCENES["A"]
    monkeypatch.setattr(HP, "_float_screen", lambda scene, candidates: list(range(len(candidates))))
    with mpmath.workdps(HP.CONSTRUCT_DPS):
        T, r = 2 * mpmath.pi / sc.mpf("omega"), sc.mpf("r")
        bad, fine = (T * 9 / 10, r, mpmath.mpf(3), 1), (T / 20, r, mpmath.mpf(3), 1)
        case, why = HP.build(sc, "fast_impact", [bad], "impact", "test")
        assert case is None and "certificate refused" in why
        case, why = HP.build(sc, "fast_impact", [bad, fine], "impact", "test")
        assert why is None and abs(mpmath.mpf(case.t_event) - T / 20) < mpmath.mpf(10) ** -25
