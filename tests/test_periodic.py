"""cross_check.dynamics: the one Newton for periodic points (fast and reference engines), the
search, the one classifier, the area classes.

Expected values come from the closed forms of reference.paper (the symmetric non-sticking
solutions and the no-impact attractor), themselves checked in tests/test_paper_formulas.py.
"""
from types import SimpleNamespace

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from cross_check.dynamics import newton as N
from cross_check.dynamics import periodic as A
from cross_check.dynamics import portraits
from cross_check.tolerances import tol
from reference import paper as P
from reference.scene import Scene

FP = tol("claim_fixed_point").atol
MULT = tol("claim_multiplier").atol
WIDE = Scene(F=1, f="0.3", omega=1, l=0, r=20)
TWO_PI = Scene(F=1, f="0.2", omega="2*pi", l=-1, r=1)


def _closed(scene, branch, m=1):
    sol = P.symmetric_solution(scene, branch, m=m)
    return [float(c) for c in sol.state0()], float(sol.trace())


@pytest.mark.parametrize("J, kind, stability", [
    ([[np.cos(1.0), -np.sin(1.0)], [np.sin(1.0), np.cos(1.0)]], "centre", "neutral"),
    ([[2.0, 0.0], [0.0, 0.5]], "saddle", "unstable"),
    ([[-2.0, 0.0], [0.0, -0.5]], "flip saddle", "unstable"),
    ([[1.0, 1.0], [0.0, 1.0]], "parabolic", "neutral"),
    ([[0.5, -0.5], [0.5, 0.5]], "focus", "stable"),
    ([[0.5, 0.0], [0.0, 0.2]], "node", "stable"),
    ([[3.0, 0.0], [0.0, 0.2]], "saddle", "unstable"),
    ([[1.0, 4.3], [0.0, 0.24]], "non-isolated", "neutral"),
    ([[1.0, 1.9], [0.0, 0.0]], "non-isolated", "neutral"),
])
def test_classify(J, kind, stability):
    got = A.classify(J)
    assert (str(got[0]), str(got[1])) == (kind, stability)


def test_classify_is_elementwise_on_a_batch():
    Js = np.array([[[2.0, 0.0], [0.0, 0.5]], [[0.5, 0.0], [0.0, 0.2]], [[np.nan, 0.0], [0.0, 1.0]]])
    kind, stab = A.classify(Js)
    assert list(kind) == ["saddle", "node", "undefined"] and list(stab) == ["unstable", "stable", "undefined"]
    assert list(A.is_saddle(kind)) == [True, False, False]


def test_classify_rejects_bad_input():
    with pytest.raises(ValueError, match=r"shape \(\.\.\., 2, 2\)"):
        A.classify([1, 2, 3])


def test_newton_converges_to_symmetric_solutions():
    for branch in (1, 2):
        (x0, v0), trace = _closed(WIDE, branch)
        res = A.newton(WIDE, [x0 + 0.05, x0 - 0.03], [v0 - 0.04, v0 + 0.02])
        assert res.converged.all()
        assert np.max(abs(res.x - x0)) < FP and np.max(abs(res.v - v0)) < FP
        assert abs(np.trace(res.J[0]) - trace) < MULT


@settings(max_examples=10)
@given(f=st.sampled_from(["0.05", "0.2", "0.4", "0.6"]), R=st.sampled_from(["3", "8", "20"]),
       branch=st.sampled_from([1, 2]))
def test_newton_on_symmetric_family(f, R, branch):
    # f = 0 excluded: then the impacts fall exactly on t = 0 (psi_1 = -pi, psi_2 = 0), the fixed point
    # sits on a wall where Phi' jumps (impact at t = 0+ or at t = T-), and Newton need not converge
    scene = Scene(F=1, f=f, omega=1, l=0, r=R)
    sol = P.symmetric_solution(scene, branch)
    if sol.min_flight_velocity()[0] <= 0:
        return      # not a genuine solution for these parameters (see test_paper_formulas)
    (x0, v0), trace = _closed(scene, branch)
    res = A.newton(scene, [x0 + 1e-3], [v0 - 1e-3])
    assert res.converged[0] and abs(res.x[0] - x0) < FP and abs(res.v[0] - v0) < FP


def test_search_finds_the_centre_and_the_saddle():
    pts = A.find_periodic_points(WIDE, v_range=(5.0, 7.5), grid=(8, 6))
    kinds = {p.kind: p for p in pts if abs(p.det - 1) < 1e-9}
    for branch, kind in ((1, "centre"), (2, "saddle")):
        (x0, v0), trace = _closed(WIDE, branch)
        p = kinds[kind]
        assert abs(p.x - x0) < FP and abs(p.v - v0) < FP and abs(p.trace - trace) < MULT
    assert len([p for p in pts if p.kind in ("centre", "saddle") and abs(p.det - 1) < 1e-9]) == 2


def test_search_period3_centre_and_orbit():
    pts = A.find_periodic_points(TWO_PI, period=3, v_range=(1.0, 2.0), grid=(6, 6))
    (x0, v0), trace = _closed(TWO_PI, 1, m=3)
    centre = [p for p in pts if p.kind == "centre"]
    assert len(centre) == 1
    c = centre[0]
    assert abs(c.x - x0) < FP and abs(c.v - v0) < FP and abs(c.trace - trace) < MULT
    assert len(c.orbit) == 3 and min(c.orbit) == (c.x, c.v)
    assert min(np.hypot(a[0] - b[0], a[1] - b[1]) for a in c.orbit for b in c.orbit if a != b) > 0.1


def test_segment_of_no_impact_fixed_points_is_non_isolated():
    closed = P.no_impact_attractor(WIDE)
    x = np.array([6.0, 10.0, 13.0])
    v = np.full(3, float(closed["v0"]))
    res = A.newton(WIDE, x, v + 1e-4)
    assert res.converged.all() and np.max(abs(res.v - float(closed["v0"]))) < FP
    kind, _ = A.classify(res.J)
    assert list(kind) == ["non-isolated"] * 3
    assert np.max(abs(np.linalg.det(res.J) - float(closed["multiplier"]))) < MULT


def test_area_classes():
    (x1, v1), _ = _closed(WIDE, 1)
    turns = float(P.no_impact_attractor(WIDE)["v0"])
    wide6 = WIDE.replace(f="0.6")
    sticks = float(P.no_impact_attractor(wide6)["v0"])
    labels, det = portraits.area_classes(WIDE, [x1, 8.0], [v1, turns])
    assert list(labels) == ["pres", "dissip"]
    assert abs(det[0] - 1) < 1e-12 and abs(det[1] - float(P.no_impact_attractor(WIDE)["multiplier"])) < 1e-8
    labels, det = portraits.area_classes(wide6, [9.0], [sticks])
    assert list(labels) == ["dissip"] and det[0] == 0


def test_dissipative_invariance_counts():
    xs, vs = np.meshgrid(np.linspace(1, 19, 7), np.linspace(-3, 8, 7))
    out = portraits.dissipative_invariance(WIDE.replace(f="0.6"), xs.ravel(), vs.ravel())
    assert out["n"] == 49 and 0 < out["n_dissip"] < 49
    assert out["n_violations"] == len(out["violations"]) == 0
    assert out["n_det_mismatch"] == 0


def test_reference_engine_refines_the_fast_point():
    # the same Newton on the reference map at 40 digits, from fast's float64 point: it must land
    # on the closed form to far below float64 (the claims' refinement)
    with mpmath.workdps(40):
        x0, v0 = P.symmetric_solution(WIDE, 1, dps=40).state0()
        res = A.newton(WIDE, [float(x0) + 1e-6], [float(v0) - 1e-6], engine=A.Reference(40))
        assert res.converged[0]
        assert abs(res.x[0] - x0) < mpmath.mpf(10) ** -30 and abs(res.v[0] - v0) < mpmath.mpf(10) ** -30


def test_canonical_wall_state():
    assert A._canonical(0.0, 0.8, 0.8, 1.2, 1e-9) == (0.8, -1.2)
    assert A._canonical(0.0, 0.8, 0.0, -0.5, 1e-9) == (0.0, 0.5)
    assert A._canonical(0.0, 0.8, 0.4, 0.5, 1e-9) == (0.4, 0.5)


def test_bad_input():
    with pytest.raises(ValueError, match="period"):
        A.newton(WIDE, [1.0], [1.0], period=0)
    with pytest.raises(ValueError, match="max_iter"):
        A.newton(WIDE, [1.0], [1.0], max_iter=0)
    with pytest.raises(ValueError, match="grid"):
        A.find_periodic_points(WIDE, grid=(0, 3))
    with pytest.raises(ValueError, match="x_range"):
        A.find_periodic_points(WIDE, x_range=(-1.0, 3.0))


XPOT_D = Scene(F=3, f="0.5", omega="0.8", l=-2, r="1.5", wavenumber="2.5")   # issue 33's scene D


def test_coarse_search_screens_seeds_and_the_default_map_finds_the_points():
    """``search_steps``: the coarse map screens the seeds and the default map polishes the ends of
    those that pass: every point found is a fixed point of the default map to ``tol``, and the
    points are those that the search without a screen finds (on D's 8 x 8 grid, all of them, each
    within the search's own ``dedup`` distance of its twin, the same kind)."""
    vmax, dedup = 3.0, 1e-7
    kw = dict(period=1, v_range=(-vmax, vmax), grid=(8, 8), dedup=dedup)
    plain = A.find_periodic_points(XPOT_D, **kw)
    found = A.find_periodic_points(XPOT_D, search_steps=A.SEARCH_STEPS, **kw)
    assert found and len(found) == len(plain)
    for p, q in zip(found, plain):
        assert max(abs(p.x - q.x), abs(p.v - q.v)) <= dedup and p.kind == q.kind
    for p in found:
        X, V, _ = A.map_and_jacobian(XPOT_D, [p.x], [p.v])
        assert max(abs(X[0] - p.x), abs(V[0] - p.v)) <= 1e-11 * max(1, abs(p.x), abs(p.v))


def test_coarse_search_changes_nothing_without_position_forcing():
    """Closed-form flights have no steps: ``search_steps`` gives the same Newton run, bit for bit."""
    x, v = np.linspace(0.1, 0.7, 5), np.linspace(-0.5, 0.5, 5)
    a = A.newton(NARROW := Scene(F=1, f="0.005", omega=1, l=0, r="0.8"), x, v)
    b = A.newton(NARROW, x, v, search_steps=A.SEARCH_STEPS)
    assert np.array_equal(a.x, b.x) and np.array_equal(a.v, b.v) and np.array_equal(a.converged, b.converged)


def test_on_family_takes_both_multipliers_near_one_of_an_area_preserving_map_only():
    """``_on_family``: ``|tr - 2|`` and ``|det - 1|`` both within ``FAMILY_SCREEN``."""
    e = N.FAMILY_SCREEN
    J = np.array([[[1.0, 3.0], [0.0, 1.0]],                    # parabolic shear: a family's member
                  [[1.0 + e / 4, 0.5], [0.0, 1.0 - e / 4]],    # within the screen
                  [[1.0 + 4 * e, 0.0], [0.0, 1.0]],            # tr 2 + 4e: an isolated point
                  [[1.0, 0.0], [0.0, 0.5]],                    # det 0.5: a segment, not a family
                  [[np.nan, 0.0], [0.0, 1.0]]])
    assert N._on_family(J).tolist() == [True, True, False, False, False]


CONSERVATIVE = Scene(F=2, f="0", omega="0.5", l=-1, r=1, wavenumber="2")    # families of fixed points


def _spy_newton(monkeypatch, fail_from_ends=False):
    """Record ``(x, v, engine, result)`` of every ``newton`` run ``_two_stage`` makes; with
    ``fail_from_ends`` the run from the coarse ends (the second) reports every seed not converged."""
    calls, plain = [], N.newton

    def spy(scene, x, v, **kw):
        res = plain(scene, x, v, **kw)
        if fail_from_ends and len(calls) == 1:
            res.converged[:] = False
        kept = SimpleNamespace(**{k: np.array(getattr(res, k)) for k in ("x", "v", "J", "converged")})
        calls.append((np.array(x, float), np.array(v, float), kw.get("engine"), kept))
        return res       # (copies kept: _two_stage writes the later runs into the coarse arrays)

    monkeypatch.setattr(N, "newton", spy)
    return calls


def _family_search(monkeypatch, fail_from_ends=False, period=1):
    X, V = A.seed_grid(CONSERVATIVE, (6, 6), (-4.0, 4.0))
    calls = _spy_newton(monkeypatch, fail_from_ends)
    res = N._two_stage(CONSERVATIVE, X, V, period, 1e-11, A.MAX_NEWTON, None, A.SEARCH_STEPS)
    coarse = calls[0][3]
    near = np.flatnonzero(coarse.converged)         # the ends polished: of no lower period
    near = near[~N._of_lower_period(CONSERVATIVE, N._Fast(A.SEARCH_STEPS), coarse.x[near], coarse.v[near], period)]
    return X, V, calls, res, coarse, near, N._on_family(coarse.J)[near]


def test_coarse_search_runs_the_default_map_from_the_coarse_ends(monkeypatch):
    """``_two_stage``: the default map runs from the coarse ends of the seeds that pass the screen
    (a family's members and the others); every point found is a fixed point of the default map to
    ``tol``; the ends it polishes to a multiplier within ``NEAR_ONE`` of 1 off a family (by the
    coarse ``J`` and by the default map's at the polished point) run again from their seeds; and
    the points off ``tr = 2`` do not depend on ``FAMILY_SCREEN``, bit for bit (without it a
    family's members run again from their seeds)."""
    X, V, calls, res, coarse, near, family = _family_search(monkeypatch)
    assert isinstance(calls[0][2], N._Fast) and calls[1][2] is None
    assert family.any() and (~family).any()
    fx, fv = calls[1][:2]
    assert np.array_equal(fx, coarse.x[near]) and np.array_equal(fv, coarse.v[near])
    fine = calls[1][3]
    J = fine.J
    tr, det = J[:, 0, 0] + J[:, 1, 1], J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    on_family = (np.abs(tr - 2) <= N.FAMILY_SCREEN) & (np.abs(det - 1) <= N.FAMILY_SCREEN)
    redo = near[~fine.converged | (N._near_one(fine.J) & ~family & ~on_family)]
    if redo.size:
        assert len(calls) == 3 and np.array_equal(calls[2][0], X[redo]) and np.array_equal(calls[2][1], V[redo])
    else:
        assert len(calls) == 2
    assert res.converged.any()
    for x, v in zip(res.x[res.converged], res.v[res.converged]):
        P, W, _ = A.map_and_jacobian(CONSERVATIVE, [x], [v])
        assert max(abs(P[0] - x), abs(W[0] - v)) <= 1e-11 * max(1, abs(x), abs(v))
    kw = dict(period=1, v_range=(-4.0, 4.0), grid=(6, 6), search_steps=A.SEARCH_STEPS)
    with_screen = A.find_periodic_points(CONSERVATIVE, **kw)
    monkeypatch.setattr(N, "FAMILY_SCREEN", -1.0)
    without = A.find_periodic_points(CONSERVATIVE, **kw)
    off = lambda pts: [(p.x, p.v, p.kind) for p in pts if abs(p.trace - 2) > 1e-8]
    assert off(with_screen) and off(with_screen) == off(without)


def test_coarse_search_keeps_an_end_the_default_map_polishes_onto_a_family(monkeypatch):
    """``_again``: an end that the coarse ``J`` does not put on a family, polished by the default
    map onto one (by its own ``J``), is kept, not run again from its seed; the search's points
    off ``tr = 2`` are those of the rule that runs such seeds again, bit for bit (period 2 of the
    6 x 6 grid: 6 such ends).  Under that rule ``_two_stage`` does run them again, so the two
    searches differ in their work and the comparison can fail."""
    X, V, calls, res, coarse, near, family = _family_search(monkeypatch, period=2)
    fine = calls[1][3]
    kept = near[fine.converged & N._near_one(fine.J) & ~family & ~N._again(fine, family)]
    assert kept.size
    rerun = lambda c: set(zip(c[2][0], c[2][1])) if len(c) == 3 else set()       # noqa: E731
    assert not set(zip(X[kept], V[kept])) & rerun(calls)
    kw = dict(period=2, v_range=(-4.0, 4.0), grid=(6, 6), search_steps=A.SEARCH_STEPS)
    off = lambda pts: [(p.x, p.v, p.kind) for p in pts if abs(p.trace - 2) > 1e-8]   # noqa: E731
    new = off(A.find_periodic_points(CONSERVATIVE, **kw))
    monkeypatch.setattr(N, "_again", lambda fine, family: ~fine.converged | (N._near_one(fine.J) & ~family))
    calls.clear()
    N._two_stage(CONSERVATIVE, X, V, 2, 1e-11, A.MAX_NEWTON, None, A.SEARCH_STEPS)
    assert set(zip(X[kept], V[kept])) <= rerun(calls)
    assert new and off(A.find_periodic_points(CONSERVATIVE, **kw)) == new


#: seed 33's R3 of the verify benchmark: most coarse ends of its period-2 search are fixed points of Phi
LOWER = Scene(F="1.39", f="0.197", omega="1.35", l="-1.38", r="1.51", wavenumber="1.681", damping="0.061",
              restitution="0.7")


def test_coarse_search_drops_the_ends_of_a_lower_period(monkeypatch):
    """``_of_lower_period``: a fixed point of ``Phi`` is of a lower period in a search of period 2,
    3 or 4, a point of a period-2 orbit in a search of period 4 but not of 2 or 3.  The period-2
    search drops such ends before the default map polishes them and finds the same points, bit
    for bit, as the search that polishes them all (which polishes more ends: the check can tell
    the two apart)."""
    kw = dict(v_range=(-3.0, 3.0), grid=(8, 8), search_steps=A.SEARCH_STEPS)
    p1 = A.find_periodic_points(LOWER, period=1, **kw)[0]
    calls = _spy_newton(monkeypatch)
    two = A.find_periodic_points(LOWER, period=2, **kw)
    polished = calls[1][0].size
    p2 = two[0]
    screen = N._Fast(A.SEARCH_STEPS)
    xs, vs = np.array([p1.x, p2.x]), np.array([p1.v, p2.v])
    for period, low in ((2, [True, False]), (3, [True, False]), (4, [True, True])):
        assert N._of_lower_period(LOWER, screen, xs, vs, period).tolist() == low
    monkeypatch.setattr(N, "_of_lower_period", lambda scene, engine, x, v, period: np.zeros(x.shape, bool))
    calls.clear()
    without = A.find_periodic_points(LOWER, period=2, **kw)
    assert calls[1][0].size > polished
    assert [(p.x, p.v, p.kind) for p in two] == [(p.x, p.v, p.kind) for p in without]


def test_near_one_takes_a_multiplier_within_near_one_of_one():
    """``_near_one``: either multiplier within ``NEAR_ONE`` of 1; a non-finite ``J`` is not."""
    e = N.NEAR_ONE
    J = np.array([[[1.0, 3.0], [0.0, 1.0]],                    # parabolic shear
                  [[1.0 - e / 2, 0.0], [0.0, 0.2]],            # a rest state's family direction
                  [[0.2, 0.0], [0.0, 1.0 + e / 2]],            # the other multiplier
                  [[1.0 + 2 * e, 0.0], [0.0, 0.2]],            # 2 NEAR_ONE away
                  [[0.0, -1.0], [1.0, 0.0]],                   # multipliers +-i
                  [[np.nan, 0.0], [0.0, 1.0]]])
    assert N._near_one(J).tolist() == [True, True, True, False, False, False]


def test_coarse_search_runs_an_end_polished_near_one_again_from_the_seed(monkeypatch):
    """On scene D (rest states: a multiplier 1 along their families) the ends that the default map
    polishes to a multiplier within ``NEAR_ONE`` of 1 run again from their seeds with those whose
    end fails, and those results are the seeds'; with ``NEAR_ONE`` below 0 only the failed ones do
    (the check can fail)."""
    X, V = A.seed_grid(XPOT_D, (6, 6), (-3.0, 3.0))
    for near_one in (N.NEAR_ONE, -1.0):
        with monkeypatch.context() as m:
            m.setattr(N, "NEAR_ONE", near_one)
            calls = _spy_newton(m)
            res = N._two_stage(XPOT_D, X, V, 1, 1e-11, A.MAX_NEWTON, None, A.SEARCH_STEPS)
        coarse, fine = calls[0][3], calls[1][3]
        near = np.flatnonzero(coarse.converged)
        family = N._on_family(coarse.J[near])
        polished_near_one = fine.converged & N._near_one(fine.J) & ~family      # at the default NEAR_ONE
        assert not family.any() and polished_near_one.any()
        again = near[~fine.converged | (polished_near_one if near_one > 0 else False)]
        assert len(calls) == 3 and np.array_equal(calls[2][0], X[again]) and np.array_equal(calls[2][1], V[again])
        third = calls[2][3]
        assert np.array_equal(res.converged[again], third.converged) and np.array_equal(res.x[again], third.x)


def test_coarse_search_runs_a_seed_again_from_the_seed_where_its_end_fails(monkeypatch):
    """A seed whose run from its coarse end does not converge runs again from the seed (an
    isolated point near ``tr = 2``: its end misses the default map's fixed point by ``|(P' -
    I)^-1|`` times the coarse map's error), and that run's result is the seed's."""
    X, V, calls, res, coarse, near, family = _family_search(monkeypatch, fail_from_ends=True)
    assert len(calls) == 3 and family.any() and (~family).any()
    ax, av, _, third = calls[2]
    assert np.array_equal(ax, X[near]) and np.array_equal(av, V[near])
    assert np.array_equal(res.converged[near], third.converged) and third.converged.any()
    assert np.array_equal(res.x[near], third.x)