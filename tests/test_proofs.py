"""Computer-assisted proofs end to end (issue 17): the claims' orbits and ``prove``.

The default run proves the orbits of two claims (the caption's saddle, the focus and period-5
orbit; fig:xpotno's centre is checked with its claim in tests/test_claims.py) and re-proves the
golden data of two scenes through the CLI and one position-forced input; ``slow`` proves
everything (every golden input of every scene, every orbit of the full claims table).
"""
import json

import pytest

from cross_check import golden, proofs, scenes
from cross_check.paper import claims as C


def _proofs(cid, quick=True):
    (row,) = C.run_claims(quick=quick, ids=[cid])
    return row["proved"]


def test_the_caption_saddle_is_proved_with_its_multipliers():
    """eigenvalues-fig7: the paper's 0.3159 and 3.1659 lie in the proved multipliers' 4-decimal
    rounding, and the point is a saddle."""
    wide = [p for p in _proofs("eigenvalues-fig7") if p["orbit"].startswith("wide_f0.6")]
    assert wide and all(p["proved"] and p["kind"] == "saddle" for p in wide)
    mults = sorted(float(m[0]) for m in wide[0]["multipliers"])
    assert round(mults[0], 4) == 0.3159 and round(mults[1], 4) == 3.1659
    assert all(m[1] < 1e-40 for m in wide[0]["multipliers"])


def test_the_focus_and_the_period5_orbit_are_proved_attracting():
    got = _proofs("focus-and-period5")
    assert {p["periods"] for p in got} == {1, 5}
    for p in got:
        assert p["proved"], p.get("reason")
        assert p["kind"] == "attracting focus" and p["itinerary"].get("turn", 0) > 0


def test_the_no_impact_attractor_is_proved_as_a_segment_of_fixed_points():
    """Translation-invariant away from the walls: no isolated fixed point, but the segment is
    proved (half-period symmetry), one multiplier exactly 1, the other ((c - f)/(c + f))^2 with
    friction turning points and 0 when the orbit sticks (f = 0.6)."""
    got = {p["orbit"].split(",")[1].strip(): p for p in _proofs("fig3-attractor")}
    assert set(got) == {"f = 0.3", "f = 0.6"}
    for p in got.values():
        one = p["multipliers"][0]
        assert p["proved"] and p["kind"].startswith("segment") and float(one[0]) == 1 and one[1] == 0
    assert got["f = 0.6"]["multipliers"][1] == ["0", 0.0] and "stick" in got["f = 0.6"]["itinerary"]
    assert 0 < float(got["f = 0.3"]["multipliers"][1][0]) < 1


def test_prove_cli_golden_one_scene(tmp_path, capsys):
    out = tmp_path / "proofs.json"
    assert proofs.main(["--golden", "--scenes", "stuck/F<f", "effect:zeno", "--json", str(out)]) == 0
    text = capsys.readouterr().out
    assert "golden: 32 of 32 inputs proved, 24 of 24 cases" in text
    data = json.loads(out.read_text())
    assert not data["golden"]["mismatch"] and not data["golden"]["outside"]


def test_a_position_forced_golden_record_is_its_proof():
    """fig:xpotno / sample-6 (two turns on validated flights), re-proved now: the stored record
    is what the proof gives, and it is a proof (``prove --golden`` does this for all 490)."""
    data = golden.load("fig:xpotno")
    case = next(c for c in data["cases"] if c["name"] == "sample-6")
    inp = case["inputs"]["exact"]
    as_case = scenes.Case(case["name"], inp["x"], inp["v"], case["exact"], case["how"])
    record = golden.input_proof(scenes.scene("fig:xpotno"), as_case)
    assert record["proved"] and record == inp["enclosure"]


def test_prove_cli_help_and_bad_scene(capsys):
    with pytest.raises(SystemExit) as exc:
        proofs.main(["--help"])
    assert exc.value.code == 0 and "--orbits" in capsys.readouterr().out
    with pytest.raises(SystemExit) as exc:
        proofs.main(["--golden", "--scenes", "no-such-scene"])
    assert exc.value.code == 2


@pytest.mark.slow
def test_everything_proves():
    """All golden inputs (~6 s) and all orbits of the full claims table (~10 s)."""
    totals = proofs.prove_golden(progress=lambda m: None)
    assert not totals["mismatch"] and not totals["outside"]
    # every input of every shipped golden file (issue 25; 532 since issue 23's scenes)
    shipped = sum(len(case["inputs"]) for name in golden.names_in(None)
                  for case in golden.load(name, None)["cases"])
    assert totals["proved"] == totals["inputs"] == shipped >= 532, totals["unproved"]
    rows = proofs.prove_orbits(progress=lambda m: None)
    listed = [p for r in rows for p in r["proved"]]
    unproved = [p for p in listed if not p["proved"]]
    # x1, x2 of the narrow scenes: the closed form is no solution there (R w^2 < (pi - 2) F)
    assert {p["orbit"].split(" x")[0] for p in unproved} == {"fig:narrow", "fig:narrow-with-friction"}
    assert all("not a solution" in p["reason"] for p in unproved)
    assert len(listed) - len(unproved) >= 50
