"""The league (``python -m cross_check league``): a thin composer over the scorecard.

The default run has a small league on fast and the reference only (seconds), the rows read off
hand-made scorecards (so the aggregation is seen to be right, and the goal line to say no), the
command line's ``--out`` and ``--peers``, a peer that is not installed (skipped and said so), and
the report's section read from disk.  The full league runs in the slow set.
"""
import json
import pathlib

import pytest

from cross_check import __main__ as cli
from cross_check.league import entries, run, table
from cross_check.report.league_link import league_section
from cross_check.score.sheet import CaseScore, Scorecard

SCENE = "fig:many:2pi/f=0.2"


@pytest.fixture(scope="module")
def small_league(tmp_path_factory):
    out = tmp_path_factory.mktemp("league")
    said = []
    doc = run.league(out, quick=True, groups=["fast", "reference"], scenes=[SCENE], say=said.append)
    return out, doc, said


def test_small_league_on_fast_and_the_reference(small_league):
    out, doc, said = small_league
    assert [(r["peer"], r["setting"]) for r in doc["rows"]] == [("fast", "threads 1"), ("reference", "dps 16"),
                                                                 ("reference", "dps 30")]
    for r in doc["rows"]:
        assert r["kinds_flagged"] == [] and r["failures"] == 0 and r["complete"]
        assert r["events"]["missed"] == r["events"]["invented"] == 0 and r["events"]["found"] > 0
        assert (out / r["scorecard"]).read_text().startswith("# Scorecard:")
    fast = doc["rows"][0]
    assert fast["median_digits"] >= table.GOAL_DIGITS and fast["warmup_seconds"] is not None
    assert 0 < doc["round_trip_seconds_per_start"] < fast["seconds_per_start"] * 10
    assert doc["goal"]["met"] and doc["goal"]["ratio"] < 1 and "time ratio fast / it" in doc["goal"]["text"]
    assert json.loads((out / "league.json").read_text())["rows"][0]["name"] == "fast threads 1"
    md = (out / "league.md").read_text()
    assert "| fast | threads 1 |" in md and "**Goal**" in md
    assert (out / "work_precision.png").stat().st_size > 10_000
    assert any(m.startswith("league: [3/3] reference dps 30: median") for m in said)


def _card(cases, events_scored=True, seconds=1e-3):
    return Scorecard("x", cases, {SCENE: {"seconds_per_period": seconds, "ten": [], "mode": "batch"}}, {},
                     events_scored)


def test_row_reads_the_scorecard():
    golden = {c.name: c for c in __import__("cross_check.score.golden", fromlist=["x"]).scene_cases(SCENE)}
    cases = [CaseScore(f"{SCENE}/sample-0", "smooth flight", False, digits=12.0),
             CaseScore(f"{SCENE}/sample-1", "impact", False, digits=9.0, missed={"impact": 1}),
             CaseScore(f"{SCENE}/sample-2", "smooth flight", False, failure="boom", failure_kind="exception"),
             CaseScore(f"{SCENE}/crossing_pair", "crossing pair", True, digits=1.0)]
    entry = entries.Entry("x", "x", "s", None)
    r = table.row(entry, _card(cases), None, 1.0)
    # the band case is left out; the failure counts as 0 digits
    assert (r["median_digits"], r["worst_digits"], r["failures"], r["graded_starts"]) == (9.0, 0.0, 1, 3)
    assert r["kinds_flagged"] == ["smooth flight", "impact"] and r["kinds_passed"] == []
    want = len(golden["sample-0"].events) + len(golden["sample-1"].events)
    assert r["events"] == {"expected": want, "found": want - 1, "missed": 1, "invented": 0}
    assert r["seconds_per_start"] == pytest.approx(1e-3)
    assert table.row(entry, _card(cases, events_scored=False), None, 1.0)["events"] is None


def _row(group, setting, digits, seconds):
    return {"group": group, "peer": group, "setting": setting, "name": f"{group} {setting}",
            "median_digits": digits, "seconds_per_start": seconds}


def test_goal_line_says_no_when_fast_is_slower_or_short_of_digits():
    rows = [_row("fast", "threads 1", 16.5, 2e-5), _row("reference", "dps 16", 16.5, 7e-3),
            _row("heyoka", "tol 1e-15", 14.6, 8e-4), _row("mujoco", "dt 1e-03", 3.7, 1e-5)]
    g = table.goal(rows)
    assert g["met"] and g["fastest_10_digit_peer"] == "heyoka tol 1e-15" and g["ratio"] == pytest.approx(0.025)
    assert not table.goal([_row("fast", "threads 1", 16.5, 2e-3)] + rows[1:])["met"]       # slower than heyoka
    assert not table.goal([_row("fast", "threads 1", 14.0, 2e-5)] + rows[1:])["met"]       # short of 15 digits
    assert table.goal(rows[1:])["met"] is None
    # net of the scorer's round trip (reported beside the verdict, which stays on the raw times)
    net = table.goal(rows, floor=1e-5)
    assert net["ratio_net_of_round_trip"] == pytest.approx((2e-5 - 1e-5) / (8e-4 - 1e-5)) and net["met"]
    assert not table.goal([_row("fast", "threads 1", 16.5, 9e-4)] + rows[1:], floor=5e-4)["met"]


def test_a_missing_peer_is_skipped_and_said_so(tmp_path, monkeypatch):
    monkeypatch.setitem(entries.GROUPS, "mujoco", ("no_such_package_for_the_league",))
    chosen, skipped = entries.select(["mujoco", "fast"], quick=True)
    assert {e.group for e in chosen} == {"fast"} and list(skipped) == ["mujoco"]
    assert "no_such_package_for_the_league not installed" in skipped["mujoco"]
    said = []
    doc = run.league(tmp_path, quick=True, groups=["mujoco"], say=said.append)
    assert doc["rows"] == [] and doc["skipped_peers"] == skipped
    assert [m for m in said if m.startswith("league: skipped mujoco:")] != []
    assert "Skipped (not installed): mujoco:" in (tmp_path / "league.md").read_text()


def test_every_engine_has_three_settings_and_a_quick_one():
    for group in entries.GROUPS:
        settings = [e for e in entries.ENTRIES if e.group == group]
        assert len(settings) >= 3 and any(e.quick for e in settings), group
    with pytest.raises(ValueError, match="unknown peer"):
        entries.select(["matlab"])


def test_cli_out_unwritable_and_bad_peers(tmp_path, capsys):
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    assert cli.main(["league", "--out", str(blocker / "sub"), "--peers", "fast"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "league: error: argument --out: cannot write to" in err[0]
    assert cli.main(["league", "--peers", "matlab"]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
    assert "league" in cli.COMMANDS


def test_report_includes_the_league_table_from_disk(small_league, tmp_path):
    out, doc, _ = small_league
    lines = league_section(out, tmp_path / "report")
    assert any(line.startswith("| fast | threads 1 |") for line in lines)
    assert any(line.startswith("**Goal**") for line in lines)
    assert any("work_precision.png" in line for line in lines)
    assert league_section(tmp_path / "none", tmp_path)[0].startswith("No league in")


@pytest.mark.slow
def test_full_league(tmp_path):
    """The full league (~5 minutes): every installed peer at three or more settings, every row
    complete, fast at 15 digits with every golden event.  Its time goal is a speed target:
    ``tests/benchmarks/test_bench_league.py``."""
    doc = run.league(tmp_path, quick=False, say=lambda m: None)
    chosen, skipped = entries.select()
    assert [(r["peer"], r["setting"]) for r in doc["rows"]] == [(e.peer, e.setting) for e in chosen]
    assert all(r["complete"] and r["starts"] for r in doc["rows"])
    for r in doc["rows"]:
        if r["group"] == "fast":
            assert r["median_digits"] >= table.GOAL_DIGITS and r["kinds_flagged"] == [], r
            assert r["events"]["missed"] == r["events"]["invented"] == 0, r
    assert pathlib.Path(tmp_path / "work_precision.png").exists()
