"""The point log that guides an orbit proof's walks: fast's events of the orbit
(``verify.ladder._guide``, issue 33).

A guide only guides: each walk takes the log's itinerary, polishes every event time by Newton
steps on the balls' midpoints and proves the event from the balls (``reference.enclosure.certify``).
So a log good to float64's digits guides a proof of any precision, without the point integrator's
cost under position forcing.  Checked here on the period-1 orbits of the issue's first unseen
scene (found by ``fast``'s search):

* fast's log has the point integrator's itinerary, its times to float64's digits, and its
  impacts sit on the walls it gives (``Walk._wall_side``);
* ``verify``'s orbit proof runs no point integrator, and proves at 64 and at 192 bits the same
  balls as with the point integrator's log;
* fast's log of another orbit misleads the walk, which then proves nothing, and the proof is
  made again with a log per centre (never a proof of the wrong orbit);
* ``maps.point_log`` runs at the digits asked (at least ``MIN_POINT_DPS``).
"""
from __future__ import annotations

import mpmath
import pytest
from hypothesis import given, settings

from cross_check.dynamics import periodic
from cross_check.paper.claims.base import prove
from cross_check.verify import ladder, tasks
from reference import Scene
from reference.enclosure import maps, orbits, prove_periodic
from reference.enclosure.balls import workprec
from tests.ladder_pairs import first_orbits, proofs_under
from tests.strategies import position_forced_scenes

SCENE = Scene(F=1, f="0.15", omega="1.7", l="-0.4", r="0.9", wavenumber="1.3")
#: the rungs checked: the first (where most orbits prove) and the one scene Y's centres need
RUNGS = ((64, 2.0 ** -32), (192, 2.0 ** -96))


@pytest.fixture(scope="module")
def found():
    """The period-1 orbits of ``SCENE``: ``[(point, (phase, x, v, guide))]``, the section as
    ``ladder.proof`` takes it."""
    vmax = tasks.velocity_range(SCENE)
    points = periodic.find_periodic_points(SCENE, period=1, v_range=(-vmax, vmax), grid=(8, 8),
                                           search_steps=periodic.SEARCH_STEPS)
    assert len(points) >= 2, points
    return [(p, ladder._section(SCENE, p.x, p.v, 1)) for p in points]


def test_fast_s_log_has_the_point_integrator_s_itinerary_to_float64_s_digits(found):
    for _, (phase, x, v, (guide, walls)) in found:
        point, _ = maps.point_log(SCENE, x, v, 1, phase, 64)
        assert [e.kind for e in guide] == [e.kind for e in point] and len(point) > 0
        assert all(e.x in walls for e in guide if e.kind == "impact")      # ``Walk._wall_side``
        gaps = [abs(a.t - b.t) / abs(b.t) for a, b in zip(guide, point)]
        assert max(gaps) < 1e-13, gaps
        assert abs(guide.t0 - point.t0) < 1e-15 * abs(point.t0) + 1e-300


def test_the_log_runs_at_the_digits_asked_with_the_same_itinerary(found):
    for _, (phase, x, v, _) in found:
        default, walls = maps.point_log(SCENE, x, v, 1, phase, 64)
        coarse, walls_c = maps.point_log(SCENE, x, v, 1, phase, 64, dps=maps.MIN_POINT_DPS)
        assert [e.kind for e in coarse] == [e.kind for e in default] and len(default) > 0
        # each log holds the walls at its own digits, and its impacts sit on them
        for log, held in ((default, walls), (coarse, walls_c)):
            assert all(e.x in held for e in log if e.kind == "impact")
        gaps = [abs(a.t - b.t) / abs(b.t) for a, b in zip(coarse, default)]
        assert max(gaps) < 1e-18, gaps                           # float64's digits and a guard
        assert max(gaps) > 1e-28, gaps                           # but not the default's 31 digits


@pytest.mark.parametrize("dps, error", [(maps.MIN_POINT_DPS - 1, ValueError), (20.0, TypeError),
                                        (True, TypeError)])
def test_too_few_digits_are_refused(found, dps, error):
    _, (phase, x, v, _) = found[0]
    with pytest.raises(error, match="dps must be an integer >= 20"):
        maps.point_log(SCENE, x, v, 1, phase, 64, dps=dps)


def test_verify_proves_with_fast_s_log_the_balls_of_the_point_integrator_s(found, monkeypatch):
    asked = []
    real = maps.point_log
    monkeypatch.setattr(maps, "point_log", lambda *a, **k: asked.append(k.get("dps")) or real(*a, **k))
    monkeypatch.setattr(orbits, "point_log", maps.point_log)
    p, (phase, x, v, guide) = next((p, s) for p, s in found if p.kind == "saddle")
    rec = ladder.proof("period 1 orbit 0", SCENE, p, 1, None)
    assert asked == [] and rec["proved"] and rec["kind"] == "saddle", (asked, rec)
    for prec, radius in RUNGS:
        balls = []
        for points in (maps.point_log(SCENE, x, v, 1, phase, 64), guide):     # the spy sees this one
            got = prove("o", SCENE, x, v, k=1, prec=prec, radius=radius, phase=phase, points=points, tight=False)
            assert got["proved"], got["reason"]
            balls.append([(mpmath.mpf(m), r) for m, r in got["point"]])
        for (m1, r1), (m2, r2) in zip(*balls):          # the same fixed point, to the balls' radii
            assert abs(m1 - m2) <= r1 + r2 and max(r1, r2) < 2.0 ** -(prec // 2), (prec, balls)
    assert asked == [None, None]


def test_fast_s_log_of_another_orbit_proves_nothing_wrong(found):
    (_, (phase, x, v, _)), (_, (_, _, _, wrong)) = found[0], found[1]
    prec = RUNGS[0][0]
    with workprec(prec):
        misled = orbits._polished(SCENE, [mpmath.mpf(x), mpmath.mpf(v)], 2.0 ** -32, 1, phase, prec, wrong)
    assert not misled.proved and orbits.UNCENTRED in misled.reason, misled.reason
    right = prove_periodic(SCENE, x, v, phase=phase, prec=prec, points=wrong)
    alone = prove_periodic(SCENE, x, v, phase=phase, prec=prec)
    assert right.proved and alone.proved, (right.reason, alone.reason)
    assert all(right.point[i].overlaps(alone.point[i]) for i in range(2))


#: the strongly damped narrow scene of issue 33 and a period-2 saddle of it (``tr P' = -43.6``),
#: the first point fast's search finds (16 x 16 seeds), here to six digits: Newton polishes it
D1 = "F=1.896 f=0.0929 omega=0.806 l=0.04 r=0.64 wavenumber=3.5937 damping=0.369 restitution=0.9"
D1_SADDLE = (0.350284, 0.031347)


def test_the_first_rung_s_box_proves_at_64_bits_what_a_box_of_2_to_the_minus_32_left_to_96(monkeypatch):
    """``ladder.PROOF_LADDER``: the first rung's box (``2^-40``) proves this saddle at 64 bits; with
    the ladder of before (radii ``2^-(prec/2)``) the 64-bit test fails (``P'`` varies too much over
    the box of ``2^-32``) and 96 bits prove it, the same orbit."""
    import fast
    from cross_check import scenefile

    sc = scenefile.collect([], [D1], check=fast.validate_scene)[0]
    res = periodic.newton(sc, [D1_SADDLE[0]], [D1_SADDLE[1]], period=2)
    assert res.converged[0]
    p = periodic.periodic_point(sc, float(res.x[0]), float(res.v[0]), 2)
    assert p.kind == "saddle"
    real, log = ladder.prove, []

    def spy(*a, **kw):
        rec = real(*a, **kw)
        log.append((kw["prec"], kw["radius"], rec["proved"]))
        return rec

    monkeypatch.setattr(ladder, "prove", spy)
    assert ladder.PROOF_LADDER[0] == (64, 2.0 ** -40)
    before = tuple((prec, 2.0 ** -(prec // 2)) for prec in (64, 96, 128, 192)) + ((320, None),)
    balls = []
    for rungs, tried in ((ladder.PROOF_LADDER, [(64, 2.0 ** -40, True)]),
                          (before, [(64, 2.0 ** -32, False), (96, 2.0 ** -48, True)])):
        monkeypatch.setattr(ladder, "PROOF_LADDER", rungs)
        log.clear()
        rec = ladder.proof("o", sc, p, 2, None)
        assert rec["proved"] and log == tried
        balls.append(rec)
    assert balls[0]["itinerary"] == balls[1]["itinerary"] and balls[0]["kind"] == balls[1]["kind"] == "saddle"
    for (m0, r0), (m1, r1) in zip(balls[0]["point"], balls[1]["point"]):    # [mid, radius] balls
        assert abs(mpmath.mpf(m0) - mpmath.mpf(m1)) <= r0 + r1                  # that overlap


def test_a_rung_s_box_is_widened_to_fit_a_measured_loss():
    """``ladder._fitted``: the ladder's radius without a measured loss; four times the residual
    ``2^(lost - prec)`` a loss predicts where that is wider; never past ``2^-(prec // 2)`` (then
    ``_may_hold`` decides as before the fourth pass); the last rung's ``None`` stays."""
    assert ladder._fitted(128, 2.0 ** -80, 0.0) == 2.0 ** -80
    assert ladder._fitted(128, 2.0 ** -80, 53.0) == 2.0 ** -73             # scene D's period 3
    assert ladder._fitted(96, 2.0 ** -60, 53.0) == 2.0 ** -48              # capped: 96 is then skipped
    assert ladder._may_hold(96, ladder._fitted(96, 2.0 ** -60, 53.0), 53.0) is False
    assert ladder._may_hold(128, ladder._fitted(128, 2.0 ** -80, 53.0), 53.0) is True
    assert ladder._may_hold(128, 2.0 ** -80, 53.0) is False                # unfitted, 128 would be
    assert ladder._fitted(320, None, 53.0) is None


@pytest.mark.slow
@settings(max_examples=20, deadline=None)
@given(position_forced_scenes(restitutions=("1", "0.9", "0.6")))
def test_fast_s_log_proves_what_the_point_integrator_s_proves_on_random_scenes(sc):
    """On random position-forced scenes (every effect drawn: ``tests.strategies``), the period-1
    orbits fast's search finds (8 x 8 seeds, the first three): the proof guided by fast's log
    (``ladder.proof`` as ``verify`` runs it) and the one guided by the point integrator's log at
    20 digits come out the same, proved or not, and where proved on the same rung with overlapping
    balls (the walks polish the event times from different guesses, so the last bits differ)."""
    ours = ladder._section

    def point_integrators(sc, x, v, period):
        phase, xs, vs, _ = ours(sc, x, v, period)
        return phase, xs, vs, maps.point_log(sc, xs, vs, period, phase, 64, dps=maps.MIN_POINT_DPS)

    for p in first_orbits(sc):
        fast_rec, point_rec = proofs_under(sc, p, "_section", (ours, point_integrators))
        assert fast_rec["proved"] == point_rec["proved"], (sc, p.x, p.v, fast_rec, point_rec)
        if fast_rec["proved"]:          # on the same rung (box), the same fixed point: the balls overlap
            assert (fast_rec["radius"], fast_rec["kind"]) == (point_rec["radius"], point_rec["kind"])
            for (m1, r1), (m2, r2) in zip(fast_rec["point"], point_rec["point"]):
                assert abs(mpmath.mpf(m1) - mpmath.mpf(m2)) <= r1 + r2, (sc, fast_rec, point_rec)
