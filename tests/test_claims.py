"""The claims registry (``cross_check.paper.claims.CLAIMS``, quick settings): one parametrized
case per claim, asserting its verdict and its numbers; and the snapshot that keeps the whole
claims JSON unchanged.

Expected numbers are recomputed here from the closed forms of reference.paper (checked in
tests/test_paper_formulas.py) or derived in the comment next to them; a change that alters a
verdict or moves a fixed point, multiplier or threshold beyond the acceptance tolerances fails.
The snapshots ``tests/data/claims/{quick,full}.json`` come from the pre-registry code (their
README); ``claims_snapshot`` says how far a float may move.
"""
import functools
import json
import math
import pathlib

import mpmath
import pytest

import reference
from cross_check import scenes
from cross_check.paper import claims as C
from cross_check.paper.claims import closed_forms
from cross_check.tolerances import tol
from reference import paper as P

FP = tol("claim_fixed_point").atol
MULT = tol("claim_multiplier").atol
THR = tol("claim_threshold").atol
ID50 = tol("paper_identity_dps50").atol
SNAPSHOTS = pathlib.Path(__file__).parent / "data" / "claims"


@functools.lru_cache(maxsize=None)
def row(cid):
    (r,) = C.run_claims(quick=True, ids=[cid])
    return r


def test_table_covers_every_claim_of_the_brief():
    assert set(C.CLAIMS) == set(EXPECTED) == {
        "symmetric-solutions", "existence-condition", "nonstick-condition", "fold-reduced-condition",
        "fold-fcrit", "resonance-3-1", "eigenvalues-fig7", "dissip-invariance", "area-preservation",
        "table1-matrices", "no-impact-solutions", "lift", "xpot-equilibria", "focus-and-period5",
        "island-A", "fig1b-centre", "fig3-attractor", "subharmonic-islands"}
    with pytest.raises(ValueError, match="unknown claim"):
        C.run_claims(ids=["no-such-claim"])


# --- one check of the numbers per claim --------------------------------------------------
def symmetric_solutions(n):
    for key in ("wide_f0.3", "2pi_f0.05"):
        for b in (1, 2):
            assert n[f"{key}_x{b}_fixed_point_residual"] < ID50
            assert n[f"{key}_x{b}_itinerary"] == {"impact": 2}
        assert n[f"{key}_x2_printed_minus_true_at_0"] == 0      # x_2's first piece is printed right
        assert abs(n[f"{key}_x1_printed_minus_true_at_0"]) > 1  # psi_1 one period late
    assert abs(n["wide_f0.3_printed_x2_after_impact"]) < 1e-30   # printed: -l = 0, true: r = 20


def existence_condition(n):
    assert n["below_exists"] and not n["above_exists"] and n["below_fixed_point_residual"] < ID50


def fold_reduced_condition(n):
    # sqrt(pi^2 - 4) - 2 arccos(2/pi), by mpmath here
    assert abs(n["bound"] - float(mpmath.sqrt(mpmath.pi ** 2 - 4) - 2 * mpmath.acos(2 / mpmath.pi))) < 1e-15
    assert n["above_itinerary"] == {"impact": 2} and n["above_fixed_point_residual"] < 1e-40
    assert n["below_itinerary"].get("stick", 0) > 0 and n["below_min_velocity"] < 0


def nonstick_condition(n):
    assert n["max_abs_printed_lhs_minus_pi_w_vmin_x1"] < ID50
    assert n["counterexample_printed_lhs"] > 0 > n["counterexample_x2_min_velocity"]
    assert n["counterexample_x1_fixed_point_residual"] < ID50 < 0.1 < n["counterexample_x2_fixed_point_residual"]


def fold_fcrit(n):
    assert abs(n["f_crit_from_fixed_points"] - 2 / float(mpmath.pi)) < THR     # eq. fold:bif, F = 1
    assert all(abs(a - b) < FP for a, b in zip(n["fold_point"], n["fold_point_closed_form"]))
    # above the fold no centre; below it exactly one non-sticking centre/saddle pair (the x_1, x_2)
    assert n["fast_nonsticking_fixed_points_by_f"]["0.64"]["centre"] == 0
    assert n["fast_nonsticking_fixed_points_by_f"]["0.63"] == {"centre": 1, "saddle": 1}


def resonance_3_1(n):
    F, w, f = (2 * mpmath.pi) ** 2, 2 * mpmath.pi, mpmath.mpf("24.65")
    S = mpmath.sqrt(4 * F ** 2 - mpmath.pi ** 2 * f ** 2)
    R_star = S * (mpmath.pi ** 2 / 3 - 1) / w ** 2        # k h = 3 (paper.py module docstring)
    assert abs(n["R_star"] - float(R_star)) < THR and abs(n["R_star_minus_closed"]) < THR
    assert f"{n['R_star']:.4f}" == "0.8933" and str(n["R_star"]).startswith("0.8932")   # paper: ~0.8932
    assert abs(n["multiplier_angle_over_2pi"] - 1 / 3) < MULT
    for z in n["multipliers_at_R_star"]:
        assert abs(z[0] + 0.5) < MULT and abs(abs(z[1]) - 3 ** 0.5 / 2) < MULT
    for r in ("0.89", "0.895"):
        sc = scenes.resonance(r)
        x0, v0 = (float(c) for c in P.symmetric_solution(sc, 1).state0())
        assert abs(n[f"R{r}_fixed_point"][0] - x0) < FP and abs(n[f"R{r}_fixed_point"][1] - v0) < FP
        assert abs(n[f"R{r}_trace"] - float(P.symmetric_solution(sc, 1).trace())) < MULT
        assert -2 < n[f"R{r}_trace"] < 2 and n[f"R{r}_itinerary"] == {"impact": 2}


def eigenvalues_fig7(n):
    for key, sc in (("wide_f0.6", scenes.wide("0.6")), ("f005_scene", scenes.two_pi("0.05"))):
        (s,) = n[f"{key}_saddles"]
        lam = sorted(float(mpmath.re(z)) for z in P.symmetric_solution(sc, 2).multipliers())
        assert all(abs(a - b) < MULT for a, b in zip(s["multipliers"], lam))
    assert [f"{m:.4f}" for m in n["wide_f0.6_saddles"][0]["multipliers"]] == ["0.3159", "3.1659"]
    assert not n["matches_in_f005_scene"]


def area_preservation(n):
    for scene in n.values():
        assert scene["max_abs_det_minus_1_nonsticking"] < tol("claim_unit_det").atol
        assert scene["n_zero_velocity_with_unit_det"] == 0 and scene["n_undefined"] == 0


def dissip_invariance(n):
    assert n["wide_f0.6"]["n_violations"] == 0 and n["wide_f0.6"]["n_dissip"] > 0
    # not general: other scenes have dissipative states whose image is non-sticking for a period
    for key in ("narrow_f0.005", "2pi_f0.05"):
        assert n[key]["n_violations"] > 0 and n[key]["reference_confirms_first_violation"]


def table1_matrices(n):
    for key, value in n.items():
        if key.endswith("reference_minus_fd") or key.endswith("v_before_minus_fd"):
            assert value < 1e-30, key
        if key.endswith("fast_minus_reference"):
            assert value < 1e-12, key
    assert n["x2_wide_f0.3_table1_v_after_minus_fd"] > 1


def no_impact_solutions(n):
    assert n["printed_condition_F1_w1_R1.5"] and n["R1.5_fixed_no_impact_starts"] == []
    # grid x = 4 j/6: j = 0, 1, 2 lie in [0, r - 2F/w^2) = [0, 2); j = 3 (x = 2) grazes the wall
    assert n["R4_fixed_no_impact_starts"] == pytest.approx([0.0, 2 / 3, 4 / 3], abs=1e-15)


def lift(n):
    assert n["max_residual_corrected"] < 1e-20 < 1e-3 < n["min_residual_printed"]


def xpot_equilibria(n):
    assert n["mismatches_corrected"] == 0 < n["mismatches_printed"]
    assert abs(n["E_corrected"][1][0] - float(2 / mpmath.pi * mpmath.acos(mpmath.mpf("0.1")))) < 1e-15


def focus_and_period5(n):
    (foc,) = [s for s in n["stable_fixed"] if s["kind"] == "focus"]
    assert max(foc["abs_multipliers"]) < 1 and foc["itinerary"] == {"impact": 4, "turn": 2}
    assert n["stable_period5"] and all(max(s["abs_multipliers"]) < 1 and s["itinerary"].get("turn", 0) > 0
                                       for s in n["stable_period5"])
    assert n["continuation_end_minus_fast_centre_f0"] < FP
    assert abs(n["continuation_f0.005_to_f0"][-1][4] - 1) < MULT      # det 1 at f = 0


def island_a(n):
    assert n["centres_with_2_impacts_0_turns"] == 0 and n["impacts_of_island_A_centre"] == 6
    (a,) = [c for c in n["centres"] if c["f"] == "0.005"]
    assert a["impacts"] == 6 and a["turns"] == 0 and abs(a["det"] - 1) < MULT
    # towards f = 0 the centre runs into the wall r = 0.8, where a centre of the same trace sits
    f_last, x_last, _, tr_last = n["continuation_to_small_f"][-1]
    (wall,) = n["f0_wall_centre"]
    assert abs(wall[0] - 0.8) < FP and x_last > 0.77 and abs(wall[2] - tr_last) < 0.01


def fig1b_centre(n):
    (c,) = n["matching"]
    assert abs(c["v"]) < FP and abs(c["det"] - 1) < MULT


def fig3_attractor(n):
    assert abs(n["f0.3"]["v"] - n["f0.3"]["v_closed_form"]) < FP
    assert n["f0.3"]["turns"] == 2 and n["f0.3"]["sticking_intervals"] == 0 == n["f0.3"]["impacts"]
    assert abs(n["f0.6"]["v"] - n["f0.6"]["v_closed_form"]) < FP
    assert n["f0.6"]["sticking_intervals"] == 2 and n["f0.6"]["impacts"] == 0
    assert abs(n["stick_threshold_f_over_F"] - 1 / float(mpmath.sqrt(1 + mpmath.pi ** 2 / 4))) < 1e-15


def subharmonic_islands(n):
    for f in ("0.2", "0.3"):
        (c1,) = n[f"f{f}"]["period1_centres"]
        closed = n[f"f{f}"]["period1_symmetric_closed_form"]
        assert abs(c1[0] - closed["state0"][0]) < FP and abs(c1[1] - closed["state0"][1]) < FP
        assert abs(c1[2] - closed["trace"]) < MULT
    (c3,) = n["f0.2"]["period3_centres"]
    closed = n["f0.2"]["period3_symmetric_closed_form"]
    assert abs(c3[0] - closed["state0"][0]) < FP and abs(c3[2] - closed["trace"]) < MULT
    assert n["f0.3"]["period3_centres"] == [] and n["f0.3"]["period3_symmetric_closed_form"] is None
    assert abs(n["period3_symmetric_existence_bound_2F_over_3pi"] - 2 / (3 * float(mpmath.pi))) < 1e-15


#: claim id -> (the verdict, the check of its numbers)
EXPECTED = {
    "symmetric-solutions": ("erratum", symmetric_solutions),
    "existence-condition": ("reproduced", existence_condition),
    "nonstick-condition": ("erratum", nonstick_condition),
    "fold-reduced-condition": ("reproduced", fold_reduced_condition),
    "fold-fcrit": ("reproduced", fold_fcrit),
    "resonance-3-1": ("reproduced", resonance_3_1),
    "eigenvalues-fig7": ("reproduced", eigenvalues_fig7),
    "dissip-invariance": ("reproduced", dissip_invariance),
    "area-preservation": ("reproduced", area_preservation),
    "table1-matrices": ("reproduced", table1_matrices),
    "no-impact-solutions": ("erratum", no_impact_solutions),
    "lift": ("erratum", lift),
    "xpot-equilibria": ("erratum", xpot_equilibria),
    "focus-and-period5": ("reproduced", focus_and_period5),
    "island-A": ("erratum", island_a),
    "fig1b-centre": ("reproduced", fig1b_centre),
    "fig3-attractor": ("erratum", fig3_attractor),
    "subharmonic-islands": ("reproduced", subharmonic_islands),
}


@pytest.mark.parametrize("cid", list(C.CLAIMS))
def test_claim(cid):
    """The claim's verdict (an erratum carries its correction) and its numbers."""
    verdict, check = EXPECTED[cid]
    r = row(cid)
    assert r["verdict"] == verdict, (cid, r["verdict"], r["numbers"])
    assert (r["corrected"] is not None) == (verdict == "erratum")
    check(r["numbers"])


def test_the_xpot_centre_is_proved_elliptic_on_validated_flights():
    """fig:xpotno's non-sticking centre (position forcing, issue 25): a unique fixed point of
    Phi in its box, two impacts a period, multipliers proved non-real on the unit circle.  The
    point reference's Phi' at the seed (mpmath Taylor flights, not the balls) has the same
    trace within ``claim_multiplier``."""
    (p,) = row("xpot-equilibria")["proved"]
    assert p["proved"], p.get("reason")
    assert p["kind"] == "elliptic" and p["itinerary"] == {"impact": 2}
    (m,) = p["multipliers"]
    re, im = float(m["re"][0]), float(m["im"][0])
    assert m["re"][1] < 1e-40 and m["im"][1] < 1e-40 and abs(re * re + im * im - 1) < 1e-15
    J = reference.jacobian(scenes.scene("fig:xpotno"), *closed_forms.XPOT_CENTRE, dps=30)
    assert abs(float(J[0][0] + J[1][1]) / 2 - re) < tol("claim_multiplier").atol


# --- the snapshot: the claims JSON does not move -----------------------------------------
def _same(a, b, path=""):
    """Every difference between two JSON values: exact, but floats within ``claims_snapshot``."""
    t = tol("claims_snapshot")
    if isinstance(a, float) and isinstance(b, (int, float)) and not isinstance(b, bool):
        ok = (math.isnan(a) and math.isnan(b)) or abs(a - b) <= t.atol + t.rtol * abs(b)
        return [] if ok else [f"{path}: {a!r} != {b!r}"]
    if type(a) is not type(b):
        return [f"{path}: {type(a).__name__} != {type(b).__name__}"]
    if isinstance(a, dict):
        if list(a) != list(b):
            return [f"{path}: keys {list(a)} != {list(b)}"]
        return [d for k in a for d in _same(a[k], b[k], f"{path}/{k}")]
    if isinstance(a, list):
        if len(a) != len(b):
            return [f"{path}: length {len(a)} != {len(b)}"]
        return [d for i, (p, q) in enumerate(zip(a, b)) for d in _same(p, q, f"{path}[{i}]")]
    return [] if a == b else [f"{path}: {a!r} != {b!r}"]


def _as_json(rows):
    rows = json.loads(json.dumps(rows, default=str))
    for r in rows:
        r.pop("seconds", None)
        r.pop("proved", None)       # newer than the snapshots; tests/test_proofs.py checks it
        r.pop("proved_on", None)    # newer too; tests/test_proved_intervals.py checks it
    return rows


def _assert_snapshot(rows, name):
    want = json.loads((SNAPSHOTS / name).read_text())
    got = _as_json(rows)
    assert [r["id"] for r in got] == [r["id"] for r in want]
    diffs = [d for g, w in zip(got, want) for d in _same(g, w, g["id"])]
    assert not diffs, f"{len(diffs)} difference(s) from {name}: " + "; ".join(diffs[:10])


def test_quick_claims_match_the_snapshot():
    _assert_snapshot([row(cid) for cid in C.CLAIMS], "quick.json")


def test_snapshot_comparison_sees_a_moved_number():
    rows = _as_json([row("lift")])
    rows[0]["numbers"]["max_residual_corrected"] = 1e-3
    with pytest.raises(AssertionError, match="max_residual_corrected"):
        want = json.loads((SNAPSHOTS / "quick.json").read_text())
        diffs = _same(rows[0], next(w for w in want if w["id"] == "lift"), "lift")
        assert not diffs, "; ".join(diffs)


def test_main_prints_table(tmp_path, capsys):
    out = tmp_path / "claims.json"
    assert C.main(["--quick", "--only", "lift", "existence-condition", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "lift" in text and "erratum" in text and out.exists()


@pytest.mark.slow
def test_resonance_nonlinear_instability_full():
    """Full settings (~1 min): bounded near R*, escaping at R* (the paper: unstable at R*)."""
    (r,) = C.run_claims(quick=False, ids=["resonance-3-1"])
    esc = r["numbers"]["nonlinear_escape"]["max_distance_over_delta"]
    assert max(esc["0.89"]) < 20 and max(esc["0.895"]) < 20   # elliptic invariant curves (ratio ~7)
    assert max(esc["R*"]) > 1000                              # distance O(0.4) / 1e-4


@pytest.mark.slow
def test_full_table_verdicts_and_snapshot():
    """Full settings (~1 min): the verdicts do not depend on the grid sizes, and the full
    claims JSON matches its snapshot."""
    rows = C.run_claims(quick=False)
    assert {r["id"]: r["verdict"] for r in rows} == {cid: row(cid)["verdict"] for cid in C.CLAIMS}
    _assert_snapshot(rows, "full.json")
