"""The scorecard (``cross_check.score``): fast passes every kind, scipy shows the events it
misses in the right kinds, and a fault is flagged in its kind and nowhere else.

Faulty integrators here are ``fast`` with one physics fault at its inputs or outputs
(restitution applied twice, damping doubled, the wavenumber of the position forcing off by
1e-6, friction 1% high, impacts below a speed dropped from the log); each changes only the
scenes of its effect, so only that kind may be flagged.
"""
import json

import numpy as np
import pytest

from cross_check import __main__ as cli
from cross_check.score import adapters, load_adapter, score
from cross_check.score.adapters import FAST, SCIPY, FastAdapter
from cross_check.score.golden import KINDS, scene_cases


class Faulty(FastAdapter):
    """``fast`` with ``change`` applied to the parameters, or impacts slower than ``drop`` removed
    from its event log."""

    def __init__(self, name, change=None, drop=None):
        self.name, self.change, self.drop = name, change or {}, drop

    def _p(self, params):
        return {**params, **{k: fn(params) for k, fn in self.change.items()}}

    def step(self, params, x, v, periods):
        return super().step(self._p(params), x, v, periods)

    def events(self, params, x, v):
        evs = super().events(self._p(params), x, v)
        if self.drop is None:
            return evs
        return [[e for e in row if not (e[0] == "impact" and abs(e[4]) < self.drop)] for row in evs]


@pytest.fixture(scope="module")
def fast_card():
    return score(FAST, periods=(1,))


def test_fast_holds_14_digits_in_every_kind(fast_card):
    kinds = fast_card.kinds()
    assert set(kinds) == set(KINDS)
    for kind, s in kinds.items():
        if s["cases"] == s["band"]:
            continue            # every case of the kind is in the band (listed, not graded)
        assert s["worst_graded_digits"] >= 14, (kind, s)
        assert (s["missed"], s["invented"], s["failures"], s["grade"]) == (0, 0, 0, "A"), (kind, s)
    assert fast_card.flagged() == [] and fast_card.skipped == {}


def test_scipy_misses_grazing_impacts_and_sticks():
    card = score(SCIPY, scenes=["fig:narrow", "fig:narrow-with-friction", "fig:many:2pi/f=0.1"], periods=(1,))
    kinds = card.kinds()
    # every grazing case: the impact at the tangency is missed (the step jumps over the graze)
    assert kinds["grazing"]["flagged"] and kinds["grazing"]["cases"] == 3
    assert all(c.missed.get("impact") == 1 for c in card.cases if c.kind == "grazing")
    missed = {c.id: c.missed for c in card.cases if c.missed and not c.band}
    assert missed["fig:narrow/grazing"] == {"impact": 1}
    assert missed["fig:narrow-with-friction/sticking"] == {"turn": 1, "stick": 1, "slip": 1}
    assert kinds["sticking"]["flagged"]
    # a chatter run it ends by a threshold (below 100 atol): the accumulation, hence Phi, to 10-12 digits
    assert kinds["chatter"]["grade"] == "B" and kinds["chatter"]["worst_graded_digits"] < 13
    assert kinds["impact"]["missed"] == kinds["impact"]["invented"] == 0     # ordinary impacts it finds


@pytest.mark.parametrize("fault, kinds", [
    (Faulty("restitution twice", {"restitution": lambda p: p["restitution"] ** 2}), ["restitution"]),
    (Faulty("damping doubled", {"damping": lambda p: 2 * p["damping"]}), ["damping"]),
    (Faulty("wavenumber 1e-6 off", {"wavenumber": lambda p: p["wavenumber"] and p["wavenumber"] * (1 + 1e-6)}),
     ["position forcing"]),
    # the effect scenes' grazing cases are graded under their effect (score.golden: a scene's effect first;
    # fig:xpotno has a grazing hard case since issue 33)
    (Faulty("grazing impacts skipped", drop=1e-3), ["grazing", "restitution", "damping", "position forcing"]),
], ids=lambda a: a.name if hasattr(a, "name") else "")
def test_a_fault_is_flagged_in_its_kind_only(fault, kinds):
    assert score(fault, periods=(1,)).flagged() == kinds


def test_friction_fault_flags_every_kind_with_friction():
    card = score(Faulty("friction 1% high", {"f": lambda p: 1.01 * p["f"]}), periods=(1,))
    assert set(card.flagged()) >= {"smooth flight", "impact", "sticking", "chatter", "damping"}


def test_undeclared_effects_are_skipped_and_listed():
    class NoEffects(FastAdapter):
        name = "walls, forcing and friction only"
        effects = frozenset({"walls", "forcing", "friction"})

    card = score(NoEffects(), scenes=["fig:xpotno", "effect:damping", "fig:narrow"], periods=(1,))
    assert set(card.skipped) == {"fig:xpotno", "effect:damping"}
    assert card.skipped["fig:xpotno"] == {"position_forcing"}
    assert {c.id.split("/")[0] for c in card.cases} == {"fig:narrow"}
    assert "Skipped" in card.to_markdown()


def test_failures_and_bad_results_are_recorded_not_raised():
    class Broken(FastAdapter):
        name = "broken"

        def step(self, params, x, v, periods):
            if len(x) > 1:
                raise RuntimeError("batch refused")
            return (np.array([np.nan]), v.copy()) if x[0] > 0.4 else super().step(params, x, v, periods)

    card = score(Broken(), scenes=["fig:narrow"], periods=(1,))
    failed = [c for c in card.cases if c.failure]
    assert failed and all("non-finite" in c.failure for c in failed)
    kinds = card.kinds()
    assert kinds["impact"]["flagged"]
    assert sum(1 for c in failed if not c.band) == sum(s["failures"] for s in kinds.values())


def test_bad_adapters_and_arguments():
    with pytest.raises(TypeError, match="has no 'name'"):
        score(object())
    with pytest.raises(ValueError, match="periods"):
        score(FAST, periods=(2,))
    with pytest.raises(ValueError, match="unknown scene"):
        score(FAST, scenes=["no-such-scene"])
    with pytest.raises(ValueError, match="MODULE:NAME"):
        load_adapter("nonsense")
    assert load_adapter("cross_check.score.adapters:FAST") is FAST


def test_ten_periods_are_scored_against_the_reference():
    card = score(FAST, scenes=["fig:many:2pi/f=0.1"], periods=(1, 10))
    ten = card.scenes["fig:many:2pi/f=0.1"]["ten"]
    assert len(ten) == 2 and min(ten) > 10        # chaotic amplification over 10 periods stays modest here


@pytest.mark.parametrize("name", ["fig:xpotno", "fig:many:2pi/f=0.1"])
def test_ten_period_truth_at_ten_dps_reads_as_one_fifteen_digits_finer(name):
    """``card.TEN_DPS``: fast's ten-period digits (capped at 17) read against the truth at
    ``TEN_DPS`` are those against the truth at ``TEN_DPS + 15`` to 1e-3 digits, on the first two
    ten-period states of a position-forced scene and of a closed-form one; a truth at 15 digits
    would misread them (the check can fail)."""
    from cross_check import scenes
    from cross_check.agreement import compare
    from cross_check.score.card import TEN_DPS
    from cross_check.score.golden import ten_period_cases

    sc, cases = scenes.scene(name), scene_cases(name)
    off = []
    for i in ten_period_cases(cases)[:2]:
        c = cases[i]
        case = compare.Case(c.name, repr(c.x), repr(c.v), "float64", "golden input")
        X, V = compare.fast_map(sc, np.array([c.x]), np.array([c.v]), 10)
        read = lambda dps: [compare.digits(float(a[0]), b) for a, b in zip((X, V), compare.ref_map(sc, case, 10, dps))]
        fine = read(TEN_DPS + 15)
        assert max(abs(a - b) for a, b in zip(read(TEN_DPS), fine)) <= 1e-3
        off.append(max(abs(a - b) for a, b in zip(read(15), fine)))
    assert max(off) > 1e-3


def test_cli_writes_markdown_and_json(tmp_path, capsys):
    out = tmp_path / "card"
    # in process: the worker process's path is tested on its own (tests/test_score_budget.py)
    status = cli.main(["score", "fast", "--scenes", "fig:narrow", "stuck/F<f", "--periods", "1", "--out", str(out),
                       "--in-process"])
    assert status == 0, capsys.readouterr().err
    data = json.loads((out / "scorecard.json").read_text())
    assert data["adapter"] == "fast" and data["kinds"]["impact"]["grade"] == "A"
    assert (out / "scorecard.md").read_text().startswith("# Scorecard: fast")
    assert cli.main(["score", "no.such.module:X"]) == 2


def test_heyoka_adapter_when_installed():
    pytest.importorskip("heyoka", reason="heyoka.py is optional (pip install heyoka): its adapter is skipped")
    card = score(adapters.heyoka(), scenes=["fig:narrow", "fig:many:wide/f=0.2"], periods=(1,))
    kinds = card.kinds()
    assert kinds["impact"]["worst_graded_digits"] > 12 and kinds["impact"]["missed"] == 0


def test_golden_cases_have_their_kinds():
    kinds = {c.name: c.kind for c in scene_cases("fig:narrow-with-friction")}
    assert kinds["grazing"] == "grazing" and kinds["crossing_pair"] == "crossing pair"
    assert kinds["sticking"] == "sticking" and kinds["sample-0"] == "impact"
    assert {c.name: c.kind for c in scene_cases("fig:many:wide/f=0.3")}["chatter"] == "chatter"
    assert {c.name: c.kind for c in scene_cases("fig:narrow")}["impact_at_T"] == "root at t = kT"
    assert {c.kind for c in scene_cases("fig:xpotno")} == {"position forcing"}
