"""``python -m cross_check verify``: user scenes, the one scene-file reader, user golden data.

One quick verify run (module fixture, on a 2-worker Dask cluster reached through ``--scheduler``)
covers the shipped example file (restitution and damping), an inline scene with ``F <= f``
(unnamed: ``inline``) and an inline frictionless one; the golden directory it writes is read back
by ``score``, ``prove`` and the pytest plugin.  Malformed scene files exit with status 2 and name
the file, the scene and the field, without a traceback.
"""
from __future__ import annotations

import json
import re
import textwrap

import pytest

from cross_check import __main__ as cli
from cross_check import golden, scenefile, scenes
from cross_check.verify import document, ladder, tasks

pytest_plugins = ["pytester"]

distributed = pytest.importorskip("distributed", reason="verify runs on dask.distributed (pip install -e '.[atlas]')")

EXAMPLE = golden.files().parent / "scenes" / "example.toml"
STUCK = "F=1 f=1.2 omega=1 l=0 r=1"                       # F <= f, unnamed: "inline"
FRICTIONLESS = "name=frictionless F=1 f=0 omega=2*pi l=-1 r=1"


@pytest.fixture(scope="module")
def run(client, tmp_path_factory):
    out = tmp_path_factory.mktemp("verify")
    status = cli.main(["verify", str(EXAMPLE), "--scene", STUCK, "--scene", FRICTIONLESS, "--quick",
                       "--out", str(out), "--scheduler", client.scheduler.address])
    return status, out


def _report(out):
    return (out / "report.md").read_text()


def test_the_example_file_and_inline_scenes_verify_quick(run):
    status, out = run
    report = _report(out)
    assert status == 0, report[:3000]
    names = [sc.name for sc in scenefile.read(EXAMPLE)] + ["inline", "frictionless"]
    assert {sc.has("restitution") and sc.has("damping") for sc in scenefile.read(EXAMPLE)} >= {True}
    for name in names:
        row = next(line for line in report.splitlines() if line.startswith(f"| `{name}` |"))
        assert row.endswith("| ok |") and "(100%)" in row, row
        assert (out / "scenes" / scenes.slug(name) / "portrait.png").read_bytes()[:4] == b"\x89PNG"
        assert json.loads((out / "scenes" / scenes.slug(name) / "scorecard-fast.json").read_text())["adapter"] == "fast"
        data = golden.load(name, out)                 # verify's --out: golden/ found inside it
        assert data["provenance"]["dps"] == golden.GOLDEN_DPS and data["scene"]["name"] == name
        assert all(i["enclosure"]["proved"] for c in data["cases"] for i in c["inputs"].values())
    assert "Every check holds" in report


def test_one_kernels_task_per_engine_and_its_cpu_in_the_report(run):
    """``fast``'s engines are compiled once per run, each beside the first scene that needs it
    (``verify.run._first_of_each_engine``), and that task's CPU counts in its scene's line."""
    from cross_check.verify import run as verify_run

    recs = [{"name": "a", "wavenumber": None}, {"name": "b", "wavenumber": "1"}, {"name": "c"},
            {"name": "d", "wavenumber": "2"}]
    assert list(verify_run._first_of_each_engine(recs)) == ["a", "b"]
    status, out = run
    lines = [line for line in _report(out).splitlines() if line.startswith("CPU seconds by task:")]
    assert sum("kernels" in line for line in lines) == 1, lines


def test_f_le_f_and_frictionless_have_different_hard_cases_and_the_report_says_why(run):
    _, out = run
    built = {n: {c["name"] for c in golden.load(n, out)["cases"] if c["exact"] == "decimal"}
             for n in ("inline", "frictionless")}
    assert {"at_rest", "stopping"} <= built["inline"] and not built["inline"] & {"grazing", "sticking", "chatter"}
    assert {"grazing", "crossing_pair", "turn_at_wall"} <= built["frictionless"]
    assert not built["frictionless"] & {"sticking", "stick_slip_boundary", "chatter", "at_rest"}
    report = _report(out)
    inline = report[report.index("## `inline`"):report.index("## `frictionless`")]
    frictionless = report[report.index("## `frictionless`"):]
    assert "- chatter: F <= f: the force never pushes into a wall beyond friction" in inline
    assert "- grazing: the force never decelerates a flight into r beyond friction" in inline
    assert "- sticking: frictionless (f = 0): no sticking and no stick-slip boundary" in frictionless
    assert "- chatter: f = 0 and e = 1: the bounces do not shrink" in frictionless
    gear = report[report.index("## `gear-rattle`"):report.index("## `soft-stops`")]
    assert "- chatter: explicit" in gear and "- stick_slip_boundary: v reaches 0" in gear


def test_score_and_prove_read_the_golden_directory_of_verify(run, tmp_path, capsys):
    _, out = run
    assert cli.main(["score", "fast", "--golden-dir", str(out), "--periods", "1", "--out", str(tmp_path)]) == 0
    card = json.loads((tmp_path / "scorecard.json").read_text())
    assert {c["id"].split("/")[0] for c in card["cases"]} == {"gear-rattle", "soft-stops", "inline", "frictionless"}
    assert cli.main(["prove", "--golden-dir", str(out / "golden"), "--scene", STUCK]) == 0
    assert re.search(r"golden: (\d+) of \1 inputs proved", capsys.readouterr().out)
    assert cli.main(["score", "fast", "--golden-dir", str(out), "--scene", "name=other F=1 f=0 omega=1 l=0 r=5"]) == 2
    assert "no golden data" in capsys.readouterr().err


def test_the_pytest_plugin_reads_the_golden_directory_of_verify(run, pytester):
    _, out = run
    pytester.makepyfile(test_mine=textwrap.dedent("""
        import numpy as np
        from cross_check.score.adapters import FAST

        def test_fast(golden_case):
            x, v = FAST.step(golden_case.params, np.array([golden_case.x]), np.array([golden_case.v]), 1)
            golden_case.assert_close(x[0], v[0])
    """))
    result = pytester.runpytest("--golden-dir", str(out / "golden"), "-p", "no:cacheprovider")
    n = sum(len(golden.load(name, out)["cases"]) for name in golden.names_in(out))
    outcomes = result.parseoutcomes()
    assert outcomes.get("failed", 0) == 0 and outcomes["passed"] + outcomes.get("skipped", 0) == n
    ids = [line for line in result.outlines if "golden_case" in line or "frictionless/" in line]
    assert result.ret == 0 and outcomes["passed"] > n // 2, ids


# --- malformed scene files: exit 2, the file, the scene and the field named --------------
GOOD = 'name = "a"\nF = 1\nf = 0.3\nomega = 1\nl = 0\nr = 3\n'
MALFORMED = [
    ("[[scene]]\n" + GOOD.replace("omega = 1\n", ""), r"scene 1 \('a'\): missing field 'omega'"),
    ("[[scene]]\n" + GOOD + "frction = 0.1\n", r"scene 1 \('a'\): unknown key 'frction'"),
    ("[[scene]]\n" + GOOD.replace("F = 1", "F = -1"), r"field 'F': Scene: F must be >= 0"),
    ("[[scene]]\n" + GOOD.replace("r = 3", "r = 0"), r"field 'r': Scene: r must be > l"),
    ("[[scene]]\n" + GOOD + "restitution = 1.5\n", r"field 'restitution': Scene: restitution must be in \[0, 1\]"),
    ("[[scene]]\n" + GOOD.replace('"a"', '"fig:narrow"'), r"field 'name': 'fig:narrow' is a built-in"),
    ("[[scene]]\n" + GOOD + "[[scene]]\n" + GOOD, r"scene 'a': field 'name': duplicate name"),
    ("[[scene]]\n" + GOOD.replace("f = 0.3", "f = = 0.3"), r"not TOML: .*line 4"),
    ("[[scene]]\n" + GOOD.replace('name = "a"\n', ""), r"scene 1: missing field 'name'"),
    ('[[scene]]\n' + GOOD.replace("f = 0.3", 'f = "0.3 + x"'), r"field 'f': Scene: f must be a number"),
    ("[scene]\n" + GOOD, r"no scenes: write one \[\[scene\]\] table"),
    # issue 29: a hostile value is refused before it is computed, a scene fast cannot hold by name
    ('[[scene]]\n' + GOOD.replace("F = 1", 'F = "9**9**9**9"'), r"field 'F': Scene: F = .* MAX_POWER_EXPONENT"),
    ("[[scene]]\n" + GOOD.replace("F = 1", "F = 1e300").replace("omega = 1", "omega = 1e-300"),
     r"scene 'a': fast: F = 1\.0e\+300 \(from F = .*\) is above 1e\+100"),
]


@pytest.mark.parametrize("text, message", MALFORMED, ids=[m[1][:30] for m in MALFORMED])
def test_a_malformed_scene_file_exits_2_naming_the_field(tmp_path, capsys, text, message):
    path = tmp_path / "scenes.toml"
    path.write_text(text)
    assert cli.main(["verify", str(path), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and re.search(message, err), err
    assert "Traceback" not in err and len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("command", [["golden"], ["report", "--quick"], ["prove", "--golden"], ["score", "fast"]])
def test_every_command_takes_user_scenes_and_rejects_bad_ones(tmp_path, capsys, command):
    path = tmp_path / "bad.toml"
    path.write_text("[[scene]]\n" + GOOD.replace("omega = 1", "omega = 0"))
    assert cli.main(command + ["--scenes-file", str(path)]) == 2
    assert "field 'omega': Scene: omega must be > 0" in capsys.readouterr().err
    assert cli.main(command + ["--scene", "F=1 f=0.3 omega=1 l=0"]) == 2
    assert "missing field 'r'" in capsys.readouterr().err


def test_golden_writes_a_user_scene_where_score_finds_it(tmp_path, capsys):
    out = tmp_path / "g"
    assert cli.main(["golden", "--scene", "name=resting " + STUCK, "--n-sample", "1", "--out", str(out)]) == 0
    assert golden.names_in(out) == ["resting"] and golden.load("resting", out)["scene"]["f"] == "1.2"
    assert cli.main(["score", "fast", "--golden-dir", str(out), "--periods", "1", "--out", str(tmp_path)]) == 0
    assert not (golden.DEFAULT_DIR / "resting.json").exists()          # never into the shipped data


def test_inline_scenes_are_read_exactly_and_named():
    a, b = scenefile.collect(inline=["F=1 f=0.3 omega=2*pi l=-1 r=(2*pi)**2/10", "name=mine F=1 f=0 omega=1 l=0 r=1"])
    assert (a.name, b.name) == ("inline", "mine")
    assert a.exact("f") == scenes.scene("fig:many:2pi/f=0.3").exact("f") and a.exact("omega").text == "2*pi"
    toml = scenefile.read(EXAMPLE)[0]
    assert str(toml.f) == "0.1" and toml.exact("restitution").numerator == 17   # 0.85 read as 17/20
    with pytest.raises(scenefile.SceneFileError, match="'F=1' .*given twice|given twice"):
        scenefile.parse_inline("F=1 F=2 f=0 omega=1 l=0 r=1")
    with pytest.raises(scenefile.SceneFileError, match="is not key=value"):
        scenefile.parse_inline("F=1 f omega=1 l=0 r=1")


def test_the_registry_has_the_built_ins_first_then_user_scenes():
    sc = scenefile.parse_inline("name=reg-test F=1 f=0.2 omega=1 l=0 r=2")
    scenefile.register_all([sc])
    assert scenes.names()[:len(scenes.SCENES)] == list(scenes.SCENES) and "reg-test" in scenes.names()
    assert scenes.scene("reg-test") is sc and "reg-test" not in scenes.SCENES
    assert [c.name for c in scenes.hard_states("reg-test")][:2] == ["grazing", "crossing_pair"]
    with pytest.raises(ValueError, match="built-in"):
        scenes.register(scenes.SCENES["fig:narrow"].replace(name="fig:narrow", F=2))


def _result(**over):
    """A verify result of one scene with every check holding, then ``over`` changes."""
    inp = {"enclosure": {"proved": True, "radius": "1e-70"}}
    got = {"golden file": ({"document": {"cases": [{"name": "sample-0", "inputs": {"exact": inp}}]},
                            "dropped": []}, 1.0),
           "agreement": ({"samples": {"mismatch_outside_band": []}, "hard": []}, 1.0),
           "scorecard fast": ({"flagged": []}, 1.0)}
    got.update(over)
    return got


def test_each_check_of_verify_fails_when_its_statement_is_false():
    assert document.checks(_result()) == []
    bad = {"enclosure": {"proved": False, "reason": "a grazing start"}}
    cases = {"golden file": ({"document": {"cases": [{"name": "sample-0", "inputs": {"exact": bad}}]},
                              "dropped": ["s / sample-3 / exact: dps 90 vs 110: value 1 != 2"]}, 1.0),
             "agreement": ({"samples": {"mismatch_outside_band": ["sample-1"]},
                            "hard": [{"case": "grazing", "same": False, "stable": True, "ref_band": False}]}, 1.0),
             "scorecard fast": ({"flagged": ["chatter"]}, 1.0),
             "orbits 1": RuntimeError("boom")}
    for what, value in cases.items():
        failed = document.checks(_result(**{what: value}))
        assert failed, what
    assert len(document.checks(_result(**{"golden file": cases["golden file"]}))) == 2
    hard_only = ({"document": {"cases": []}, "dropped": ["s / grazing / exact: dps 90 vs 110: ..."]}, 1.0)
    assert document.checks(_result(**{"golden file": hard_only})) == []   # a hard case left out: listed, not failed


def test_the_report_says_what_each_scenes_data_proves():
    """Issue 33: no blanket sentence about position forcing; per scene, what its data proves --
    and an unproved input, or an orbit left unproved, shows in the count."""
    assert document.proves(_result()) == "1/1 golden inputs proved (widest relative radius of Phi 1.0e-70)."
    bad = {"enclosure": {"proved": False, "reason": "a grazing start"}}
    two = {"document": {"cases": [{"name": "sample-0", "inputs": {"exact": bad, "float64": bad}}]}, "dropped": []}
    orbits = [{"proof": {"proved": True}, "what": "orbit"}, {"proof": {"proved": False}, "what": "orbit"}]
    said = document.proves(_result(**{"golden file": (two, 1.0), "orbits 1": (orbits, 1.0)}))
    assert said.startswith("0/2 golden inputs proved;") and "1/2 periodic orbits proved" in said
    rec = {"name": "forced", "F": "1", "f": "0.1", "omega": "1", "l": "0", "r": "1", "effects": ["position_forcing"]}
    boom = RuntimeError("not run here")
    got = _result(agreement=boom, **{"scorecard fast": boom})
    text, _ = document.render([rec], {"scenes": {"forced": got}, "workers": 1, "seconds": 1.0}, tasks.FULL)
    assert "- `forced`: 1/1 golden inputs proved" in text and "self-agreement alone" not in text


def test_the_report_says_what_each_scenes_golden_values_rest_on():
    """``document.sources``: per scene, how many inputs have their values from their proofs' balls
    (``"guide_dps"``), from a dps-50 run their proofs certify (``"dps"``), from the dps 90 / 110
    pair (neither key), and how many have chatter times from restart pairs -- counted, so another
    mix says other numbers; a closed-form scene's file names the pair alone."""
    doc = {"cases": [{"name": "sample-0", "inputs": {"exact": {"guide_dps": 20}}},
                     {"name": "chatter", "inputs": {"exact": {"dps": 50, "chatter_dps": [60, 80]},
                                                    "float64": {"guide_dps": 20}}},
                     {"name": "grazing", "inputs": {"exact": {}, "float64": {"guide_dps": 20}}}]}
    said = document.sources(doc)
    assert said.startswith("Golden values: 3 from the midpoints of the input's own proof's balls")
    assert "; 1 from a dps-50 run that the input's proof certifies" in said
    assert "; 1 from a dps-90 run checked at dps 110" in said and "chatter times of 1 of them" in said
    doc["cases"][1]["inputs"]["exact"] = {}
    assert "2 from a dps-90 run" in document.sources(doc) and "dps-50" not in document.sources(doc)
    closed = {"cases": [{"name": "sample-0", "inputs": {"exact": {}}}]}
    assert document.sources(closed) == "Golden values: 1 from a dps-90 run checked at dps 110."
    inp = {"guide_dps": 20, "enclosure": {"proved": True, "radius": "1e-55"}}
    one = {"document": {"cases": [{"name": "sample-0", "inputs": {"exact": inp}}]}, "dropped": []}
    assert "Golden values: 1 from the midpoints" in "\n".join(document._golden_section(one))


@pytest.fixture
def faked_orbit(monkeypatch):
    """``(scene, point)``: a saddle of ``fig:xpotno`` for ``ladder.proof`` with ``prove`` faked by the
    test, its section at ``t = 0`` and no guide."""
    monkeypatch.setattr(ladder, "_section", lambda sc, x, v, k: (0, x, v, None))
    return scenes.scene("fig:xpotno"), type("P", (), {"x": 0.3, "v": 0.2, "kind": "saddle", "trace": 3.0, "det": 1.0})()


def test_an_orbit_proof_skips_the_rungs_its_measured_loss_rules_out(monkeypatch, faked_orbit):
    """``ladder.proof``: a rung that failed on its residual alone (``residual``: ~2^(lost - prec))
    rules out the rungs whose box that loss cannot fit (``_may_hold``), not the others; a failure
    of another kind rules out nothing, and the last rung is always tried.  An orbit that fast
    finds parabolic is tried on the first rung alone, and its reason says so; after a rung whose
    Newton diverged (``diverged``) none is tried, nor after a rung of ``WHOLE_LOSS_PREC`` bits or
    more whose residual ball is 1 wide (every bit lost: not rounding)."""
    sc, p = faked_orbit
    precs = [prec for prec, _ in ladder.PROOF_LADDER]
    for residual, tried in ((2.0 ** -11, [64, 128, 192, 320]),      # 53 bits lost: 96's box 2^-48 is out
                            (2.0 ** 40, [64, 320]),                 # 104 bits lost: only 320 remains
                            (None, precs)):                         # another failure: every rung
        calls = []

        def fake(label, sc, x, v, k, prec, radius, phase, points, tight, residual=residual):
            calls.append(prec)
            rec = {"orbit": label, "periods": k, "proved": False, "reason": "test"}
            return {**rec, "residual": residual} if residual and prec == 64 else rec

        monkeypatch.setattr(ladder, "prove", fake)
        assert ladder.proof("o", sc, p, 1, None)["proved"] is False and calls == tried
    assert ladder._may_hold(96, 2.0 ** -48, 53) is False and ladder._may_hold(128, 2.0 ** -64, 53) is True
    p.kind, p.trace, calls[:] = "parabolic", -2.0 + 1e-10, []     # flip-parabolic: det(P' - I) ~ 4
    rec = ladder.proof("o", sc, p, 1, None)
    assert calls == [64] and "parabolic" in rec["reason"]
    p.trace = 2.0 - 1e-10                                           # det(P' - I) ~ 0: not attempted
    rec = ladder.proof("o", sc, p, 1, None)
    assert calls == [64] and rec["reason"] == ladder.SINGULAR and rec["proved"] is False
    p.kind, p.trace, calls[:] = "saddle", 3.0, []

    def every_bit_lost(label, sc, x, v, k, prec, radius, phase, points, tight):
        calls.append(prec)
        return {"orbit": label, "periods": k, "proved": False, "reason": "test",
                "residual": 8.0 if prec >= 128 else None}

    monkeypatch.setattr(ladder, "prove", every_bit_lost)    # a whole loss at 128 bits ends the climb
    calls[:] = []
    rec = ladder.proof("o", sc, p, 1, None)
    assert calls == [64, 96, 128] and "every one of the 128 bits lost" in rec["reason"]
    monkeypatch.setattr(ladder, "WHOLE_LOSS_PREC", 192)     # below the threshold the climb goes on
    calls[:] = []
    ladder.proof("o", sc, p, 1, None)
    assert calls == [64, 96, 128, 320], calls
    calls[:] = []

    def diverging(label, sc, x, v, k, prec, radius, phase, points, tight):
        calls.append(prec)
        return {"orbit": label, "periods": k, "proved": False, "reason": "Newton diverges", "diverged": True}

    monkeypatch.setattr(ladder, "prove", diverging)      # no rung after a diverging Newton
    assert ladder.proof("o", sc, p, 1, None)["diverged"] and calls == [64]


@pytest.mark.parametrize("radii, tried", [(2.0 ** 50, [64]),           # a kink: the sticking points' miss
                                          (2.0 ** 17, [64]),           # just past 2^(64 / 4)
                                          (2.0 ** 15, [64, 96, 128, 192, 320]),   # within: rounding may
                                          (10.0, [64, 96, 128, 192, 320])])      # the damped scene's
def test_a_rung_whose_krawczyk_image_misses_its_box_by_far_ends_the_climb(radii, tried, monkeypatch, faked_orbit):
    """``ladder.proof``: a rung whose ``K(Z)`` missed ``Z`` by more than ``2^(KINK_SHARE prec)`` box
    radii (``miss``: ``P`` not smooth over the box) ends the climb, and its reason says so; a miss
    of fewer radii rules out nothing."""
    sc, p = faked_orbit
    calls = []

    def missing(label, sc, x, v, k, prec, radius, phase, points, tight):
        calls.append(prec)
        rec = {"orbit": label, "periods": k, "proved": False, "reason": "K(Z) is not inside Z"}
        return {**rec, "miss": radii * radius} if radius is not None else rec

    monkeypatch.setattr(ladder, "prove", missing)
    rec = ladder.proof("o", sc, p, 1, None)
    assert rec["proved"] is False and calls == tried, calls
    assert ("P is not smooth over the box" in rec["reason"]) is (tried == [64])


@pytest.mark.parametrize("kind, trace, det, tried", [
    ("centre", 2 - 1.2e-9, 1.0, [64]),              # scene Y's family members beyond PARABOLIC_TOL
    ("saddle", 2 + 1.3e-9, 1.0 + 1e-13, [64]),
    ("centre", 2 - 3.6e-8, 1.0, None),               # the elliptic centre proved at 192 bits
    ("saddle", 2 + 1.2e-9, 0.5, None),               # not area-preserving: no family of this kind
    ("node", 2 - 1.2e-9, 1.0, None),
    ("node", 1 - 6.9e-6, 0.0, [64]),                # scene S's rest states at |F cos k x| = f
    ("node", 1 - 9.7e-6, -2.2e-19, [64]),            # P3's
    ("node", 1 - 2e-4, 0.0, None),                   # beyond REST_EDGE_TOL
    ("node", 1 - 6.9e-6, 1e-6, None)])               # not of rank one
def test_a_near_parabolic_orbit_of_an_area_preserving_map_is_tried_on_the_first_rung_only(
        kind, trace, det, tried, monkeypatch):
    """``ladder.proof``: a centre or saddle of an area-preserving map within ``FAMILY_TOL`` of
    ``tr = +2`` in float64 (a family's member: its rungs of 192 and 320 bits failed on the
    frictionless corners) is tried at 64 bits only, and so is a point of rank-one ``P'`` within
    ``REST_EDGE_TOL`` of ``tr = 1`` (the edge of a family of rest states), and the reason says
    why; outside those bands, off ``det = 1`` or ``det = 0``, the whole ladder."""
    sc = scenes.scene("fig:xpotno")
    p = type("P", (), {"x": 0.3, "v": 0.2, "kind": kind, "trace": trace, "det": det})()
    monkeypatch.setattr(ladder, "_section", lambda sc, x, v, k: (0, x, v, None))   # no guide: `prove` is faked
    calls = []

    def fake(label, sc, x, v, k, prec, radius, phase, points, tight):
        calls.append(prec)
        return {"orbit": label, "periods": k, "proved": False, "reason": "test"}

    monkeypatch.setattr(ladder, "prove", fake)
    rec = ladder.proof("o", sc, p, 3, None)
    assert calls == (tried or [prec for prec, _ in ladder.PROOF_LADDER])
    rule = "FAMILY_TOL" if kind != "node" else "REST_EDGE_TOL"
    assert (rule in rec["reason"] and "tried at 64 bits only" in rec["reason"]) == bool(tried)


@pytest.mark.parametrize("spreads, tried", [({64: 6e9}, [64, 192, 320]),     # 9e4 at 96, 1.4 at 128
                                             ({64: 1e4}, [64, 96, 128, 192, 320]),   # 0.15 at 96: tried
                                             ({64: 3e40}, [64, 320]),   # no rung holds; 320 is tried
                                             # two rungs: 2^-0.25 a bit from 192 leaves 2^-31 at 320
                                             ({64: 6e9, 192: 2.0}, [64, 192, 320]),
                                             # scene Y's centre: 2^-0.16 a bit leaves 4.4 at 320
                                             ({64: 1.6e13, 192: 8.5e6}, [64, 192]),
                                             ({64: 1e10, 192: 1e12}, [64, 192])])    # it grew
def test_an_orbit_proof_skips_the_rungs_whose_jacobian_stays_too_wide(spreads, tried, monkeypatch, faked_orbit):
    """``ladder.proof``: a rung that found ``P'`` too wide for any Krawczyk box (``spread``, ``>=
    1``) rules out the rungs where ``spread 2^-((prec - 64) / 2)`` is still 1 or more
    (``_may_hold``), and tries the others; the last rung is tried unless two rungs measured the
    spread and the rate they show (``_spread_at``) leaves it 1 or more there, which the reason
    then says.  (No rung is inserted here, ``SPREAD_AIM = 0``: that rule has its own test.)"""
    sc, p = faked_orbit
    monkeypatch.setattr(ladder, "SPREAD_AIM", 0.0)
    calls = []

    def fake(label, sc, x, v, k, prec, radius, phase, points, tight):
        calls.append(prec)
        rec = {"orbit": label, "periods": k, "proved": False, "reason": "test"}
        return {**rec, "spread": spreads[prec]} if prec in spreads else rec

    monkeypatch.setattr(ladder, "prove", fake)
    rec = ladder.proof("o", sc, p, 1, None)
    assert rec["proved"] is False and calls == tried
    assert ("no higher rung is tried" in rec["reason"]) == (tried[-1] != 320)
    assert ladder._may_hold(128, 2.0 ** -64, 0, [(64, 6e9)]) is False
    if spreads == {64: 1e4}:    # two spreads that allow 320, and a residual loss that rules it out
        spreads[96], calls[:] = 1.5, []
        monkeypatch.setattr(ladder, "prove", lambda *a, **k: {**fake(*a, **k), "residual": 2.0 ** 125}
                            if k["prec"] == 96 else fake(*a, **k))
        rec = ladder.proof("o", sc, p, 1, None)
        assert calls == [64, 96, 320] and "no higher rung" not in rec["reason"]   # the last is tried
    assert ladder._may_hold(192, 2.0 ** -96, 0, [(64, 6e9)]) is True
    assert ladder._spread_at(320, [(64, 1.6e13), (192, 8.5e6)]) == pytest.approx(4.4, rel=0.05)
    assert ladder._spread_at(320, [(64, 6e9), (192, 6e9 * 2.0 ** -64)]) == pytest.approx(6e9 * 2.0 ** -128)


@pytest.mark.parametrize("spread, at", [(29.0, 80), (96.0, 80), (467.0, 88), (1.1, 72),   # scene d1's
                                        (6.5e5, 112), (5.97e9, 136),     # scene Y's period-3 saddles
                                        (1e4, None)])                    # 96 bits: 0.15, no rung below
def test_a_measured_spread_inserts_the_rung_it_predicts_to_hold(spread, at, monkeypatch, faked_orbit):
    """``ladder.proof``: after a rung of 64 bits found ``P'`` too wide (``spread``), the fewest bits
    (a multiple of ``RUNG_STEP_BITS``) where ``_spread_at`` predicts at most ``SPREAD_AIM`` are
    tried next, with the box ``2^-(5/8 bits)``, if that is fewer than the next rung the ladder
    would try (``_aimed``); the measured spreads of issue 33's damped scene d1 and frictionless
    scene Y give the rungs where those orbits proved (``SPREAD_AIM = 0``: the fixed ladder)."""
    sc, p = faked_orbit
    calls = []

    def fake(label, sc, x, v, k, prec, radius, phase, points, tight):
        calls.append((prec, radius))
        rec = {"orbit": label, "periods": k, "proved": prec > 64, "reason": "test"}
        return {**rec, "spread": spread} if prec == 64 else rec

    monkeypatch.setattr(ladder, "prove", fake)
    assert ladder.proof("o", sc, p, 1, None)["proved"]
    fixed = next(prec for prec, _ in ladder.PROOF_LADDER if ladder._spread_at(prec, [(64, spread)]) < 1)
    rung = (at, 2.0 ** -(5 * at // 8)) if at else (fixed, dict(ladder.PROOF_LADDER)[fixed])
    assert calls == [(64, 2.0 ** -40), rung], calls
    calls.clear()
    monkeypatch.setattr(ladder, "SPREAD_AIM", 0.0)
    assert ladder.proof("o", sc, p, 1, None)["proved"] and calls[1][0] == fixed


def test_an_orbit_proof_seeds_each_rung_with_the_centre_the_one_below_polished(monkeypatch, faked_orbit):
    """``ladder.proof``: a rung whose test failed after Newton converged (``centre``) hands that
    centre to the next rung as its seed; a rung without one leaves the seed as it was; the
    record returned has no ``centre``."""
    sc, p = faked_orbit
    seeds, centres = [], {64: ["0.31", "0.21"], 128: ["0.32", "0.22"]}

    def fake(label, sc, x, v, k, prec, radius, phase, points, tight):
        seeds.append((prec, x, v))
        rec = {"orbit": label, "periods": k, "proved": prec == 192, "reason": "test"}
        return {**rec, "centre": centres[prec]} if prec in centres else rec

    monkeypatch.setattr(ladder, "prove", fake)
    rec = ladder.proof("o", sc, p, 1, None)
    assert rec["proved"] and "centre" not in rec
    assert seeds == [(64, 0.3, 0.2), (96, "0.31", "0.21"), (128, "0.31", "0.21"), (192, "0.32", "0.22")]
    centres[192] = ["0.33", "0.23"]                 # a last rung that fails: no centre in its record
    monkeypatch.setattr(ladder, "prove", lambda *a, **k: {**fake(*a, **k), "proved": False})
    assert "centre" not in ladder.proof("o", sc, p, 1, None)


def test_the_proofs_go_to_the_other_orbits_before_the_parabolic_ones():
    """``tasks._attempted``: ``max_proofs`` orbits in order, those fast finds parabolic last."""
    kinds = ["parabolic", "saddle", "parabolic", "centre", "saddle"]
    assert tasks._attempted(kinds, 3) == {1, 3, 4}
    assert tasks._attempted(kinds, 4) == {0, 1, 3, 4}
    assert tasks._attempted(kinds[1:2], 16) == {0}


def test_a_reason_with_bars_stays_in_its_cell_of_the_orbit_table():
    """``document._orbit_section``: a failed proof's reason such as ``|C (P(z) - z)|`` has its bars
    escaped, so its row has the header's columns (it had two more)."""
    row = {"period": 1, "what": "orbit", "x": 0.5, "v": -0.25, "kind": "saddle", "dissip": False, "sticks": False,
           "segment": None, "proof": {"proved": False, "reason": "the residual alone, |C (P(z) - z)|, has radii [1, 2]"}}
    head, _, line = document._orbit_section([row])
    cells = lambda text: len(re.findall(r"(?<!\\)\|", text))      # noqa: E731
    assert cells(line) == cells(head) == 10 and "\\|C (P(z) - z)\\|" in line


def test_a_proofs_section_lies_in_flight_not_in_a_rest():
    """``shooting.quiet_middle``: the longest stretch that is not a rest (after a stick, contact or
    chatter; from the start if the motion starts at rest until a slip or release), the longest
    of all only if every stretch rests.  On an unseen scene's period-1 orbits that stick (issue
    33), the longest stretch is the stick, where ``v = 0`` and no box of starts has one
    itinerary; ``ladder._section`` now puts the section in flight."""
    from cross_check.agreement import compare
    from cross_check.dynamics import periodic
    from reference.enclosure.shooting import quiet_middle, rest_stretches
    from reference.scene import Scene

    times = [0.0, 1.0, 5.0, 6.0, 7.0]
    assert rest_stretches(["impact", "contact", "release"], False) == [False, False, True, False]
    assert quiet_middle(times, rest_stretches(["impact", "contact", "release"], False)) == 3.0
    assert quiet_middle(times, rest_stretches(["contact", "release", "impact"], False)) == 6.5
    assert rest_stretches(["slip"], True) == [True, False] and rest_stretches([], True) == [True]
    assert quiet_middle([0.0, 2.0], [True]) == 1.0                 # every stretch rests
    sc = Scene(F="1.072", f="0.0075", omega="1.332", l="0.21", r="3.56", wavenumber="0.8216",
               restitution="0.6")
    vmax = tasks.velocity_range(sc)
    nodes = [p for p in periodic.find_periodic_points(sc, period=1, v_range=(-vmax, vmax), grid=(16, 16),
                                                     search_steps=periodic.SEARCH_STEPS) if p.kind == "node"]
    assert nodes
    for p in nodes:
        kinds = {e.kind for evs in compare.fast_events(sc, p.points[:, 0], p.points[:, 1]) for e in evs}
        assert "stick" in kinds
        _, x, v, (guide, _) = ladder._section(sc, p.x, p.v, 1)
        assert v != 0 and sc.float("l") < x < sc.float("r")
        assert "stick" in {e.kind for e in guide}           # the proof's guide (fast's log) sticks too
