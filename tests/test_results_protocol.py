"""The results-file protocol (issue 32): an integrator in any language, graded as an adapter.

* the export: ``problems.csv`` / ``problems.json`` / ``FORMAT.md``, every number read back as the
  same double, ids stable under a narrower selection;
* the round trip through a script that does not import the project (run with ``python -I -S``:
  no site-packages, no PYTHONPATH): a perfect file passes every kind; a file perturbed on one
  kind's rows flags that kind and only that kind; its event logs are graded too;
* a missing id is a failed start, named; ``status`` failed / timeout are failures of their kind;
* every malformed file exits 2 with one line naming the line and the field, never a traceback;
* the C example (``cross_check/data/examples/vibro_impact.c``), compiled with ``cc``, graded from
  its file and -- the same numbers -- through a Python adapter: the same card, kind by kind.
"""
import csv
import json
import shutil
import subprocess
import sys
from importlib import resources

import numpy as np
import pytest

from cross_check import __main__ as cli
from cross_check.score import problems, score
from cross_check.score.golden import scene_cases
from reference.scene import EFFECTS

#: scenes holding every kind of case (damping, restitution and position forcing are their
#: scenes' kinds), so a fault in one kind has every other kind beside it to stay unflagged
SCENES = ["fig:narrow", "fig:narrow-with-friction", "fig:many:wide/f=0.3", "fig:many:wide/f=0.5", "stuck/F<f",
          "effect:restitution", "effect:damping", "fig:xpotno"]
SELECT = ["--scenes", *SCENES, "--periods", "1"]

#: the integrator of a third party: reads problems.csv, writes results.csv -- the project never
#: imported (it runs with ``python -I -S``) -- from answers keyed by scene, case and periods, the
#: rows of the cases named in ``perturb`` moved by a relative 1e-6 in x
SCRIPT = r'''
import csv, json, sys
problems, answers, perturb, out = sys.argv[1:5]
answers, perturb = json.load(open(answers)), set(json.load(open(perturb)))
with open(problems, newline="") as f, open(out, "w", newline="") as g:
    w = csv.writer(g, lineterminator="\n")
    w.writerow(["id", "x", "v", "seconds", "status"])
    for row in csv.DictReader(f):
        key = "|".join((row["scene"], row["case"], row["periods"]))
        if key not in answers:
            continue
        x, v = (float(a) for a in answers[key])
        if row["scene"] + "/" + row["case"] in perturb:
            x += 1e-6 * max(1.0, abs(x))
        w.writerow([row["id"], "%.17g" % x, "%.17g" % v, "0.001", "ok"])
'''


@pytest.fixture(scope="module")
def exported(tmp_path_factory):
    out = tmp_path_factory.mktemp("problems")
    assert cli.main(["score", "--export-problems", str(out), *SELECT]) == 0
    return out


def third_party(tmp_path, exported, perturb=(), drop=()):
    """results.csv as the standalone script writes it, from the golden answers."""
    answers = {f"{c.scene}|{c.name}|1": list(c.phi) for n in SCENES for c in scene_cases(n) if c.id not in drop}
    (tmp_path / "answers.json").write_text(json.dumps(answers))
    (tmp_path / "perturb.json").write_text(json.dumps(sorted(perturb)))
    (tmp_path / "script.py").write_text(SCRIPT)
    out = tmp_path / "results.csv"
    subprocess.run([sys.executable, "-I", "-S", str(tmp_path / "script.py"), str(exported / "problems.csv"),
                    str(tmp_path / "answers.json"), str(tmp_path / "perturb.json"), str(out)], check=True, timeout=60)
    return out


def grade(results, tmp_path, capsys, *extra):
    status = cli.main(["score", "--results", str(results), *SELECT, "--out", str(tmp_path / "card"), *extra])
    err = capsys.readouterr().err
    return status, json.loads((tmp_path / "card" / "scorecard.json").read_text()), err


def test_the_export_reads_back_as_the_same_doubles(exported):
    rows = list(csv.DictReader(open(exported / "problems.csv", newline="")))
    assert list(rows[0]) == list(problems.COLUMNS)
    doc = json.loads((exported / "problems.json").read_text())
    assert doc["version"] == problems.VERSION and doc["format"] == problems.FORMAT
    assert len(doc["problems"]) == len(rows) == sum(len(scene_cases(n)) for n in SCENES)
    for row, entry, p in zip(rows, doc["problems"], problems.problems(SCENES, (1,))):
        c = p.case
        assert (row["scene"], row["case"], row["input"], int(row["id"])) == (c.scene, c.name, c.input, p.id)
        for k in problems.PARAMETERS + ("x", "v"):
            want = c.params[k] if k in c.params else getattr(c, k)
            assert (row[k] == "" if want is None else float(row[k]) == want), (row["id"], k)
            assert entry[k] == want
        assert all(len(row[k].replace("-", "").replace(".", "").split("e")[0].lstrip("0")) <= 17
                   for k in ("x", "v") if row[k])
    assert {r["input"] for r in rows} == {"exact", "float64"}
    assert {r["wavenumber"] != "" for r in rows if r["scene"] == "fig:xpotno"} == {True}
    assert doc["scenes"]["fig:many:wide/f=0.3"]["f"] == "0.3" and doc["scenes"]["fig:narrow"]["omega"] == "1"
    assert (exported / "FORMAT.md").read_text() == problems.format_text()
    # a narrower selection keeps the ids; ten-period rows come after each scene's one-period rows
    full = {(p.case.id, p.periods): p.id for p in problems.problems()}
    assert all(full[(p.case.id, p.periods)] == p.id for p in problems.problems(["stuck/F<f"], (1, 10)))
    assert sorted(full.values()) == list(range(1, len(full) + 1))


def test_a_perfect_file_passes_every_kind(tmp_path, exported, capsys):
    status, card, err = grade(third_party(tmp_path, exported), tmp_path, capsys)
    assert status == 0, err
    graded = {k: s for k, s in card["kinds"].items() if s["band"] < s["cases"]}
    assert set(graded) >= {"impact", "grazing", "sticking", "chatter", "restitution", "damping", "position forcing"}
    assert all(s["grade"] == "A" and s["failures"] == 0 for s in graded.values()), graded
    assert card["adapter"] == "results file results.csv"


@pytest.mark.parametrize("kind", ["sticking", "impact", "restitution", "position forcing"])
def test_a_fault_on_one_kinds_rows_flags_that_kind_only(kind, tmp_path, exported, capsys):
    rows = {c.id for n in SCENES for c in scene_cases(n) if c.kind == kind}
    status, card, err = grade(third_party(tmp_path, exported, perturb=rows), tmp_path, capsys)
    assert status == 1, err
    assert [k for k, s in card["kinds"].items() if s["flagged"]] == [kind]


def test_a_missing_id_is_a_failed_start_named_in_the_card(tmp_path, exported, capsys):
    status, card, _ = grade(third_party(tmp_path, exported, drop={"fig:narrow/grazing"}), tmp_path, capsys)
    (case,) = [c for c in card["cases"] if c["failure"]]
    assert status == 1 and case["id"] == "fig:narrow/grazing" and card["kinds"]["grazing"]["flagged"]
    assert "no result for id" in case["failure"] and "(fig:narrow/grazing, 1 period(s))" in case["failure"]
    assert "no result for id" in (tmp_path / "card" / "scorecard.md").read_text()


def test_status_failed_and_timeout_are_failures_of_their_kind(tmp_path, exported, capsys):
    results = third_party(tmp_path, exported)
    lines = results.read_text().splitlines()
    ids = {int(r["id"]): r for r in csv.DictReader(open(exported / "problems.csv", newline=""))}
    first = {ids[int(line.split(",")[0])]["case"]: i for i, line in reversed(list(enumerate(lines[1:], 1)))}
    for case, status in (("grazing", "failed"), ("sticking", "timeout")):
        i = first[case]
        lines[i] = lines[i].split(",")[0] + ",,,," + status
    results.write_text("\n".join(lines) + "\n")
    status, card, _ = grade(results, tmp_path, capsys)
    failed = {c["kind"]: c for c in card["cases"] if c["failure"]}
    assert status == 1 and set(failed) == {"grazing", "sticking"}
    assert failed["grazing"]["failure_kind"] == "exception" and "reports status failed" in failed["grazing"]["failure"]
    assert failed["sticking"]["failure_kind"] == "timeout" and "reports status timeout" in failed["sticking"]["failure"]


def test_event_logs_of_results_json_are_graded(tmp_path, exported, capsys):
    """results.json with every golden event log: no kind flagged; the impacts of the grazing cases
    dropped from their logs: grazing flagged, its missed impacts counted, nothing else."""
    ids = {(r["scene"], r["case"]): int(r["id"]) for r in csv.DictReader(open(exported / "problems.csv", newline=""))}

    def doc(drop_kind=None):
        out = []
        for n in SCENES:
            for c in scene_cases(n):
                events = [[e[0], float(e[1]), float(e[2]), float(e[4]), float(e[3])] for e in c.events
                          if not (c.kind == drop_kind and e[0] == "impact")]
                out.append({"id": ids[(n, c.name)], "x": float(c.phi[0]), "v": float(c.phi[1]), "events": events})
        return {"results": out}

    path = tmp_path / "results.json"
    path.write_text(json.dumps(doc(), indent=1))
    status, card, err = grade(path, tmp_path, capsys)
    assert status == 0 and card["events_scored"], err
    path.write_text(json.dumps(doc("grazing"), indent=1))
    status, card, err = grade(path, tmp_path, capsys)
    assert status == 1 and [k for k, s in card["kinds"].items() if s["flagged"]] == ["grazing"]
    assert card["kinds"]["grazing"]["missed"] > 0


GOOD = "id,x,v\n1,0.5,0.25\n"
MALFORMED = [  # (file name, content, what the one line must say)
    ("results.csv", "id,x,v\n999999,0.5,0.25\n", "line 2, field 'id': unknown id 999999"),
    ("results.csv", "id,x,v\n1,nan,0.25\n", "line 2, field 'x': NaN"),
    ("results.csv", "id,x,v\n1,0.5,inf\n", "line 2, field 'v': infinite"),
    ("results.csv", "id,x,v\n1,0.5\n", "line 2, field 'v': missing: the row has 2 of 3 fields"),
    ("results.csv", "id,x,v\n1,0.5,0.25,7\n", "line 2: 4 fields, expected 3"),
    ("results.csv", "id,x,v\n1,0.5,0.2", "line 2: truncated: the last line has no newline"),
    ("results.csv", "id,x,velocity\n1,0.5,0.25\n", "line 1, field 'velocity': unknown column"),
    ("results.csv", "id,x\n1,0.5\n", "line 1, field 'v': missing column"),
    ("results.csv", "id,x,v,x\n1,0.5,0.25,0.5\n", "line 1, field 'x': column given twice"),
    ("results.csv", "id,x,v,status\n1,0.5,0.25,done\n", "line 2, field 'status': 'done' is not a status"),
    ("results.csv", "id,x,v\n1,0.5,0.25\n1,0.5,0.25\n", "line 3, field 'id': id 1 given twice (first on line 2)"),
    ("results.csv", "id,x,v\none,0.5,0.25\n", "line 2, field 'id': 'one' is not an integer id"),
    ("results.csv", "id,x,v\n1,0.5,1_0\n", "line 2, field 'v': '1_0' is not a number"),
    ("results.csv", "id,x,v,seconds\n1,0.5,0.25,-1\n", "line 2, field 'seconds': must be >= 0"),
    ("results.csv", "id,x,v,j11,j12\n1,0.5,0.25,1,0\n", "line 1, field 'j21': missing column"),
    ("results.csv", "id,x,v\n\n", "line 2: an empty row"),
    ("results.csv", "", "line 1: empty: no header"),
    ("results.csv", "\ufeffid,x,v\n1,0.5,0.25\n1,0.5,0.25\n", "line 3, field 'id': id 1 given twice"),
    ("results.json", '{"results": [{"id": 1, "x": 0.5, "v": NaN}]}', "line 1, field 'v': NaN"),
    ("results.json", '{"results": [\n{"id": 1, "x": 0.5, "v": 0.25},\n{"id": 2, "x": 0.5, "w": 1}\n]}',
     "line 3, field 'w': results[1]: unknown field"),
    ("results.json", '{"results": [\n{"id": 1, "x": 0.5, "v": 0.25, "events": [["bounce", 0, 0, 1, -1]]}]}',
     "line 2, field 'events[0]': id 1: ['bounce', 0, 0, 1, -1] is not [kind, t, x, v_before, v_after]"),
    ("results.json", '{"results": [\n{"id": 1, "x": 0.5,', "line 2: not JSON"),
    ("results.json", '[1, 2]', "line 1, field 'results': expected an object"),
]


@pytest.mark.parametrize("name, content, message", MALFORMED, ids=[m[2].split(": ", 1)[-1][:40] for m in MALFORMED])
def test_a_malformed_file_exits_2_with_one_line(name, content, message, tmp_path, capsys):
    path = tmp_path / name
    path.write_text(content)
    status = cli.main(["score", "--results", str(path), "--scenes", "fig:narrow", "--periods", "1",
                       "--out", str(tmp_path / "card")])
    err = capsys.readouterr().err
    assert status == 2 and err == f"score: {path}: {message}" + err[len(f"score: {path}: {message}"):], err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert not (tmp_path / "card" / "scorecard.json").exists()


def test_bad_invocations_and_unwritable_outputs_exit_2(tmp_path, capsys):
    (tmp_path / "results.csv").write_text(GOOD)
    blocker = tmp_path / "a-file"
    blocker.write_text("")
    for argv in (["fast", "--results", str(tmp_path / "results.csv")],
                 ["--scenes", "fig:narrow"],
                 ["--results", str(tmp_path / "none.csv"), "--scenes", "fig:narrow"],
                 ["--results", str(tmp_path / "results.csv"), "--scenes", "fig:narrow", "--out", str(blocker / "x")],
                 ["--export-problems", str(blocker / "x"), "--scenes", "fig:narrow"],
                 ["fast", "--scenes", "fig:narrow", "--out", str(blocker / "x")]):
        assert cli.main(["score", *argv]) == 2, argv
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and "Traceback" not in err, (argv, err)


# --- the C example --------------------------------------------------------------------------
class FromNumbers:
    """A Python adapter answering from given numbers (the C program's, read here with the csv
    module): what ``score`` makes of the same numbers given the adapter way."""

    name = "the C example's numbers"
    effects = frozenset(EFFECTS)

    def __init__(self, answers):
        self.answers = answers          # (scene params, x, v, periods) -> (x, v) or None (failed)

    def step(self, params, x, v, periods):
        out = [self.answers[(problems.params_key(params), float(a), float(b), periods)] for a, b in zip(x, v)]
        if any(o is None for o in out):
            raise RuntimeError("the C example reports a failure")
        return np.array([o[0] for o in out]), np.array([o[1] for o in out])


def test_the_c_example_compiled_and_graded_as_its_numbers_through_an_adapter(tmp_path, exported, capsys):
    cc = shutil.which("cc")
    if cc is None:
        pytest.skip("no C compiler (cc) on PATH: the C example cannot be compiled here")
    source = resources.files("cross_check") / "data" / "examples" / "vibro_impact.c"
    exe = tmp_path / "vibro_impact"
    subprocess.run([cc, "-std=c99", "-O2", "-Wall", "-Werror", "-o", str(exe), str(source), "-lm"], check=True,
                   timeout=120)
    results = tmp_path / "results.csv"
    subprocess.run([str(exe), str(exported / "problems.csv"), str(results)], check=True, timeout=120)
    status, card, err = grade(results, tmp_path, capsys)
    assert status == 1, err              # damping and position forcing: status failed, not modelled
    flagged = [k for k, s in card["kinds"].items() if s["flagged"]]
    assert flagged == ["damping", "position forcing"], card["kinds"]
    graded = {k: s for k, s in card["kinds"].items() if s["band"] < s["cases"] and k not in flagged}
    assert all(s["grade"] == "A" for s in graded.values()), graded
    by_id = {p.id: p for p in problems.problems(SCENES, (1,))}
    answers = {}
    for row in csv.DictReader(open(results, newline="")):
        p = by_id[int(row["id"])]
        answers[p.key()] = (float(row["x"]), float(row["v"])) if row["status"] == "ok" else None
    same = score(FromNumbers(answers), scenes=SCENES, periods=(1,))
    assert json.loads(json.dumps(same.kinds(), default=float)) == card["kinds"]
