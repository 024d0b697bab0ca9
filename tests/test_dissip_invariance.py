"""``Phi(Omega_dissip) in Omega_dissip`` proved or refuted by proof (issue 35).

The checks are independent of the prover: every proved box's return-time bound is checked at
random rest states ``(x, 0)`` at random times ``tau`` of the box against the point reference
(its first event with ``v = 0`` after ``tau``), every proved counterexample at random starts
of its ball (a zero of ``v`` in ``[0, T]``, none in ``[T, 2T]``).  Negative tests: the cover
does not prove a scene where the claim is false; bounds shortened by a mutation are caught by
the reference check; a counterexample ball widened past the boundary of ``Omega_pres`` is
refused.  The f = 0 column of a small numerical atlas against the closed forms.  ``slow``: the
shipped proofs redone, every box of fig:regs checked, random scenes at length.
"""
import json
import random
from fractions import Fraction

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings

import reference
from cross_check import __main__ as cli
from cross_check import proofs_dissip, scenes
from cross_check.dynamics import violations
from cross_check.paper.claims import regions
from reference import paper as P
from reference.enclosure import invariance, rest
from reference.enclosure.balls import BallModel, workprec
from reference.enclosure.invariance import cover, prove_counterexample
from reference.scene import Scene
from tests.strategies import rest_scenes

FIG_REGS = scenes.scene("fig:many:wide/f=0.6")
ATLAS_POINT = dict(regions.PROOF_SCENES)["atlas_f0.0234_R4.48"]


def first_zero(scene, x, tau, bound):
    """The reference's first event with ``v = 0`` after ``tau`` (relative time), on
    ``[tau, tau + bound]``; None if there is none."""
    with mpmath.workdps(40):
        t_end = mpmath.mpf(tau) + mpmath.mpf(bound)
    log = reference.trajectory(scene, x, 0, t_end, t0=tau, dps=20)
    for ev in log:
        if ev.kind in invariance.ZERO_KINDS:
            return float(ev.t - mpmath.mpf(tau))
    return None


def late_boxes(scene, boxes, rng, count):
    """The boxes (JSON form) of ``count`` drawn where a random rest state does not return by
    its bound (the reference), with the state."""
    late = []
    for b in rng.sample(boxes, min(count, len(boxes))):
        x, tau = rng.uniform(*b["x"]), rng.uniform(*b["tau"])
        if first_zero(scene, x, tau, b["return_within"]) is None:
            late.append((b, x, tau))
    return late


def proved_boxes(scene, cov):
    with workprec(invariance.PREC):
        m = BallModel(scene)
        return [proofs_dissip.box_record(m, leaf) for leaf in cov.leaves if leaf.result.proved]


@pytest.fixture(scope="module")
def fig_regs():
    return cover(FIG_REGS)


def test_fig_regs_is_proved_and_every_bound_holds_at_random_rest_states(fig_regs):
    assert fig_regs.proved and len(fig_regs.leaves) > 16
    boxes = proved_boxes(FIG_REGS, fig_regs)
    T = 2 * np.pi
    assert all(b["return_within"] + b["tau"][1] <= 2 * T for b in boxes)
    assert any(b["stuck"] for b in boxes) and any(b["return_within"] > T for b in boxes)
    assert late_boxes(FIG_REGS, boxes, random.Random(35), 60) == []


def _every_proved_bound_holds(scene, max_boxes, phase_boxes, seed, n):
    """The cover's proved (non-stuck) boxes, ``n`` random rest states each against the reference."""
    cov = cover(scene, max_boxes=max_boxes, phase_boxes=phase_boxes)
    boxes = [b for b in proved_boxes(scene, cov) if not b["stuck"]]
    assert late_boxes(scene, boxes, random.Random(seed), n) == []


@settings(max_examples=8)
@given(rest_scenes())
def test_random_scenes_every_proved_bound_holds(scene):
    _every_proved_bound_holds(scene, 60, 8, 1, 6)


def test_a_shortened_bound_is_caught(monkeypatch):
    """The mutation: every stage bound of ``rest`` 20 % short (the prover's search returns
    ``0.8 H``): the reference finds rest states that return after the (wrong) bound."""
    found = rest.first_negative
    monkeypatch.setattr(rest, "first_negative",
                        lambda *a: None if (h := found(*a)) is None else (h * 4 / 5).mid())
    boxes = [b for b in proved_boxes(FIG_REGS, cover(FIG_REGS)) if not b["stuck"]]
    assert len(late_boxes(FIG_REGS, boxes, random.Random(35), 40)) >= 3


def test_the_claim_is_not_proved_where_it_is_false():
    """At the atlas point (an independent check found violations; the shipped proof refutes
    it) the cover must leave boxes undecided: a wrong stage proof closes it at once."""
    cov = cover(ATLAS_POINT, max_boxes=400)
    assert cov.undecided() and not cov.proved


# -- counterexamples ----------------------------------------------------------------------------
def shipped():
    return {rec["label"]: rec for rec in json.loads(regions.PROOF_PATH.read_text())["scenes"]}


def confirm(scene, ball, rng, count):
    """Random starts of the ball: ``(in Omega_dissip, image in Omega_pres)`` by the reference."""
    T = 2 * mpmath.pi / scene.mpf("omega")
    out = []
    for _ in range(count):
        x = ball["x"][0] + rng.uniform(-1, 1) * ball["x"][1]
        v = ball["v"][0] + rng.uniform(-1, 1) * ball["v"][1]
        first = reference.trajectory(scene, x, v, T, dps=30)
        second = reference.trajectory(scene, first.x_end, first.v_end, 2 * T, t0=T, dps=30)
        out.append((any(e.kind in invariance.ZERO_KINDS for e in first),
                    not any(e.kind in invariance.ZERO_KINDS for e in second) and second.v_end != 0))
    return out


def test_shipped_verdicts_and_counterexamples():
    """The claims table's scenes: fig:regs proved, the others refuted; each ball re-proved and
    confirmed by the reference at random starts."""
    data = shipped()
    assert data["wide_f0.6"]["verdict"] == "proved" and data["wide_f0.6"]["counterexample"] is None
    rng = random.Random(7)
    for label, scene in regions.PROOF_SCENES[1:]:
        ce = data[label]["counterexample"]
        assert data[label]["verdict"] == "refuted" and ce["zero_before"] <= float(2 * mpmath.pi / scene.mpf("omega"))
        assert prove_counterexample(scene, ce["x"][0], ce["v"][0], ce["x"][1], ce["v"][1]).proved
        assert all(a and b for a, b in confirm(scene, ce, rng, 4)), label


def test_a_widened_ball_is_refused():
    """Widened until it holds a start the reference puts outside the violations (its image
    reaches v = 0 in [T, 2T], or the start never does in [0, T]), the ball is refused."""
    scene = dict(regions.PROOF_SCENES)["2pi_f0.05"]
    ce = shipped()["2pi_f0.05"]["counterexample"]
    xs, vs, mask = violations.violations(scene, 80)
    i, j = min(((i, j) for i, j in zip(*np.nonzero(~mask))),
               key=lambda ij: (xs[ij[0]] - ce["x"][0]) ** 2 + (vs[ij[1]] - ce["v"][0]) ** 2)
    x, v = float(xs[i]), float(vs[j])
    assert not all(confirm(scene, {"x": [x, 0], "v": [v, 0]}, random.Random(0), 1)[0])
    rx, rv = abs(x - ce["x"][0]) * 1.01, abs(v - ce["v"][0]) * 1.01
    got = prove_counterexample(scene, ce["x"][0], ce["v"][0], rx, rv)
    assert not got.proved and got.reason


def test_frictionless_counterexample():
    """f = 0 (Fig. narrow): the zero of v in [0, T] is a smooth reversal inside a flight (no
    event of the walk); the ball found is proved, and fast, independently, puts random starts
    of it in Omega_dissip and their images in Omega_pres."""
    import fast
    scene = scenes.scene("fig:narrow")
    got, _ = violations.refute(lambda x, v, rx, rv: prove_counterexample(scene, x, v, rx, rv), scene)
    assert got is not None and got.proved
    rng = np.random.default_rng(3)
    x = got.x[0] + rng.uniform(-1, 1, 20) * got.x[1]
    v = got.v[0] + rng.uniform(-1, 1, 20) * got.v[1]
    X, V = fast.stroboscopic_map(scene, x, v)
    assert fast.zero_velocity(scene, x, v).all() and not fast.zero_velocity(scene, X, V).any()


# -- parameter boxes, the atlas ----------------------------------------------------------------
def test_a_parameter_box_above_the_fold_holds_at_random_parameters():
    from cross_check.atlas import proved_dissip
    from reference.enclosure.params import ParamBox
    box = ParamBox(F=1, f=("3/4", "13/16"), omega=1, l=0, r=("1/2", "713/1024"))
    rec = proved_dissip.prove_box(box)
    assert rec["status"] == "proved" and rec["inside_numerical"] is True
    cov = cover(box)
    rng = random.Random(5)
    for leaf in rng.sample([lf for lf in cov.leaves if not lf.result.stuck], 8):
        p = leaf.params
        f = Fraction(rng.uniform(float(p.lo("f")), float(p.hi("f"))))
        r = Fraction(rng.uniform(float(p.lo("r")), float(p.hi("r"))))
        sc = Scene(F=1, f=f, omega=1, l=0, r=r)
        x = float(r) * rng.uniform(float(leaf.xi[0]), float(leaf.xi[1])) * (1 - 1e-12)
        tau = 2 * np.pi * rng.uniform(float(leaf.phi[0]), float(leaf.phi[1]))
        assert first_zero(sc, x, tau, float(leaf.result.within)) is not None


def test_atlas_boxes_at_the_violation_are_refuted_for_every_parameter():
    """The proved atlas zoomed on f/F = 0.0234, w^2 R/F = 4.48: each box refuted by one ball
    for all its parameters; the reference confirms the ball at random parameters and starts."""
    from cross_check.atlas import proved, proved_dissip
    window = (Fraction("0.0232"), Fraction("0.0236"), Fraction("4.47"), Fraction("4.49"))
    rng = random.Random(11)
    for i, j in ((0, 0), (1, 1)):
        rec = proved_dissip.prove_box(proved.box_of(2, i, j, window))
        assert rec["status"] == "refuted" and rec["inside_numerical"] is False
        f, r = rng.uniform(*rec["f_over_F"]), rng.uniform(*rec["w2R_over_F"])
        sc = Scene(F=1, f=Fraction(f), omega=1, l=0, r=Fraction(r))
        assert all(a and b for a, b in confirm(sc, rec["counterexample"], rng, 2))


def test_the_f0_column_of_a_small_atlas_agrees_with_the_closed_form(client, tmp_path):
    """The numerical atlas at f = 0: x1 and x2 exist (non-sticking) exactly where the closed
    forms say (``paper.nonstick_margin > 0``; x1 a centre, ``|tr| < 2``), with their traces --
    also above w^2 R/F = 2, where their impacts sit on the section t = 0."""
    pytest.importorskip("xarray", reason="the atlas store needs xarray (the atlas extra)")
    from cross_check.atlas import Grid, compute, open_atlas
    grid = Grid(2, 24)
    compute(["symmetric"], grid, tmp_path, client=client, chunk=8)
    ds = open_atlas(tmp_path).load()
    column = ds.sel(f_over_F=0.0)
    assert float(ds["f_over_F"][0]) == 0.0
    for k, R in enumerate(column["w2R_over_F"].values):
        sc = Scene(F=1, f=0, omega=1, l=0, r=float(R))
        sol2, sol1 = P.symmetric_solution(sc, 2), P.symmetric_solution(sc, 1)
        x2 = P.nonstick_margin(sc, 2) > 0
        x1 = P.nonstick_margin(sc, 1) > 0 and abs(sol1.trace()) < 2
        assert bool(column["x2"].values[k]) == x2 == (R > 2), R
        assert bool(column["x1"].values[k]) == x1, R
        if x2:
            assert abs(column["x2_trace"].values[k] - float(sol2.trace())) <= 1e-9 * abs(float(sol2.trace()))
        if x1:
            assert abs(column["x1_trace"].values[k] - float(sol1.trace())) <= 1e-9


# -- the command ---------------------------------------------------------------------------------
def test_the_command_writes_the_certificate(tmp_path, capsys):
    assert cli.main(["prove", "--claim", "dissip-invariance", "--scene", "F=1 f=0.8 omega=1 l=0 r=3 name=high",
                     "--out", str(tmp_path)]) == 0
    rec = json.loads((tmp_path / "dissip_invariance.json").read_text())
    assert rec["verdict"] == "proved" and rec["counterexample"] is None and rec["format_version"] == 1
    assert rec["scene"]["f"] == "0.8" and rec["boxes"]
    for b in rec["boxes"]:
        assert set(b) >= {"x", "tau", "stuck", "return_within"} and b["x"][0] <= b["x"][1]
        assert 0 <= b["tau"][0] <= b["tau"][1] < rec["T"] and b["return_within"] is not None
    assert "high: proved" in capsys.readouterr().out


def test_undecided_exits_1_and_bad_input_exits_2(tmp_path, capsys):
    args = ["prove", "--claim", "dissip-invariance", "--out", str(tmp_path)]
    assert cli.main(args + ["--scenes", "fig:many:wide/f=0.6", "--max-boxes", "1", "--no-search"]) == 1
    rec = json.loads((tmp_path / "dissip_invariance.json").read_text())
    assert rec["verdict"] == "undecided" and all(b["reason"] for b in rec["boxes"] if b["return_within"] is None)
    capsys.readouterr()
    assert cli.main(args + ["--scene", "F=1 f=-1 omega=1 l=0 r=3"]) == 2
    assert cli.main(args + ["--scenes", "fig:narrow", "--max-boxes", "0"]) == 2
    assert cli.main(args) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err and "max-boxes" in err


def test_cover_rejects_bad_budgets():
    with pytest.raises(ValueError, match="max_boxes"):
        cover(FIG_REGS, max_boxes=0)
    with pytest.raises(ValueError, match="phase_boxes"):
        cover(FIG_REGS, phase_boxes=True)


# -- slow ------------------------------------------------------------------------------------------
@pytest.mark.slow
def test_every_box_of_fig_regs_holds_at_random_rest_states(fig_regs):
    boxes = proved_boxes(FIG_REGS, fig_regs)
    rng = random.Random(350)
    assert late_boxes(FIG_REGS, boxes * 4, rng, 4 * len(boxes)) == []


@pytest.mark.slow
def test_the_shipped_file_is_what_the_proofs_give(tmp_path):
    data = shipped()
    for label, scene in regions.PROOF_SCENES:
        rec = proofs_dissip.decide(scene, progress=lambda m: None)
        assert rec["verdict"] == data[label]["verdict"], label
        assert rec["counterexample"] == data[label]["counterexample"], label
        assert len(rec["boxes"]) == len(data[label]["boxes"]), label


@pytest.mark.slow
@settings(max_examples=60)
@given(rest_scenes())
def test_random_scenes_at_length(scene):
    _every_proved_bound_holds(scene, 600, 16, 2, 20)
