"""The front door: ``python -m cross_check``.

--help lists every command with a one-line description; bad arguments give one clear line
on stderr and exit status 2; claims/figures are dispatched lazily (and reported as not
available if their module is missing); a quick report runs end to end into a tmp dir.
"""
from __future__ import annotations

import pathlib
import re
import subprocess
import sys
import types

import pytest

from cross_check import __main__ as cli

ROOT = pathlib.Path(__file__).resolve().parents[1]


def run(*args, timeout=300):
    return subprocess.run([sys.executable, "-m", "cross_check", *args], cwd=ROOT, capture_output=True,
                          text=True, timeout=timeout)


def test_help_lists_each_command_on_one_line():
    proc = run("--help")
    assert proc.returncode == 0, proc.stderr
    lines = proc.stdout.splitlines()
    for name in ("report", "golden", "claims", "figures"):
        hits = [ln for ln in lines if ln.strip().startswith(name + " ")]
        assert len(hits) == 1, (name, proc.stdout)
        assert len(hits[0].split(maxsplit=1)[1]) > 10, hits[0]


@pytest.mark.parametrize("command", list(cli.COMMANDS))
def test_every_command_documents_its_exit_status(command, capsys):
    """Each command's --help says what its exit statuses mean (in process: argparse prints, exits 0)."""
    assert cli.main([command, "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert re.search(r"exit\b.{0,200}?\b2\b", text, re.IGNORECASE | re.DOTALL), (command, text[-300:])


@pytest.mark.parametrize("args, fragment", [
    ((), "a command is required"),
    (("bogus",), "unknown command 'bogus'"),
    (("report", "--bogus"), "unrecognized arguments: --bogus"),
    (("golden", "--n-sample", "-1"), "--n-sample must be >= 0"),
    (("golden", "--scenes", "fig:nope"), "invalid choice: 'fig:nope'"),
])
def test_bad_arguments_give_one_line_and_status_2(args, fragment):
    proc = run(*args)
    assert proc.returncode == 2, (proc.returncode, proc.stderr)
    assert len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert fragment in proc.stderr and "error:" in proc.stderr
    assert proc.stdout == ""


def test_missing_subcommand_module_is_reported_not_available(monkeypatch, capsys):
    monkeypatch.setitem(cli.COMMANDS, "claims", ("cross_check._no_such_module_", "check the claims"))
    assert cli.main(["claims"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "is not available" in err[0]


def test_subcommands_are_dispatched_with_their_arguments(monkeypatch):
    seen = {}
    fake = types.ModuleType("cross_check._fake_figures_")
    fake.main = lambda argv: seen.setdefault("argv", argv) and 0
    monkeypatch.setitem(sys.modules, fake.__name__, fake)
    monkeypatch.setitem(cli.COMMANDS, "figures", (fake.__name__, "redraw the figures"))
    assert cli.main(["figures", "--only", "fig:narrow"]) == 0
    assert seen["argv"] == ["--only", "fig:narrow"]


def test_subcommand_argparse_errors_become_one_line(monkeypatch, capsys):
    import argparse

    fake = types.ModuleType("cross_check._fake_claims_")

    def main(argv):
        argparse.ArgumentParser(prog="python -m cross_check claims").parse_args(argv)
        return 0

    fake.main = main
    monkeypatch.setitem(sys.modules, fake.__name__, fake)
    monkeypatch.setitem(cli.COMMANDS, "claims", (fake.__name__, "check the claims"))
    assert cli.main(["claims", "--nope"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["python -m cross_check claims: error: unrecognized arguments: --nope"]


def test_quick_report_runs_end_to_end(tmp_path):
    out = tmp_path / "rep"
    # the claims table has its own tests (and takes ~25 s of CPU even in quick mode): skipped here;
    # its rendering is checked by test_report_renders_the_claims_table_of_run_claims
    proc = run("report", "--quick", "--skip-claims", "--out", str(out), timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    text = (out / "report.md").read_text()
    for section in ("## Agreement of fast with reference", "## Hard cases", "## Work-precision",
                    "## The paper's claims", "## Machine, versions, seeds"):
        assert section in text, section
    assert (out / "work_precision.png").stat().st_size > 10_000
    assert "fig:narrow-with-friction" in text and "grazing" in text
    assert len([ln for ln in proc.stderr.splitlines() if ln.startswith("[")]) >= 4   # progress lines
    # where the time went: a row per section with its seconds, and the total
    table = text[text.index("## Where the time went"):].splitlines()
    rows = {ln.split("|")[1].strip(): float(ln.split("|")[2].strip("* ")) for ln in table if ln.startswith("| ")
            and not ln.startswith("| section")}
    for section in ("agreement", "hard cases", "work-precision: timed runs", "scipy itineraries"):
        assert section in rows, (section, rows)
    assert 0 < sum(v for k, v in rows.items() if k != "**total** (wall)") <= rows["**total** (wall)"] + 0.5


class _FakeClaim:
    def __init__(self, row):
        self.row = row

    def run(self, quick):
        if self.row is None:
            raise ZeroDivisionError("division by zero")
        return dict(self.row, note="quick" if quick else "full")


def test_report_renders_one_row_per_registered_claim():
    from cross_check.report import sections

    good = _FakeClaim({"id": "fold", "statement": "f/F = 2/pi |fold|", "verdict": "reproduced",
                       "corrected": None, "numbers": {}})
    seen = []
    lines = sections.claims_section(True, seen.append, claims={"fold": good, "broken": _FakeClaim(None)})
    assert lines[0] == "| id | verdict | statement | corrected | note | seconds |"
    assert lines[2].startswith("| fold | reproduced | f/F = 2/pi /fold/ |  | quick | ")
    # a claim that raises is a FAILED row with its error, and the others still run
    assert lines[3].startswith("| broken | FAILED | ZeroDivisionError: division by zero |")
    assert seen == ["claim fold: reproduced", "claim broken: FAILED"]


def test_the_report_runs_its_claims_in_a_worker_process_or_in_line(monkeypatch):
    """The claims run in one spawned process beside the untimed sections; where no process can
    be started they run in line, with the same rows."""
    import importlib

    build = importlib.import_module("cross_check.report.build")     # the package exports build()

    fake = {"fold": _FakeClaim({"id": "fold", "statement": "s", "verdict": "reproduced",
                                "corrected": None, "numbers": {}})}
    seen = []
    pool, future = build._claims_process(True, seen.append, fake)
    with pool:
        lines, seconds, compiled = future.result(timeout=120)
    assert lines[2].startswith("| fold | reproduced | s |  | quick | ") and seconds >= compiled >= 0
    assert seen == []                     # the worker's progress went to its own stderr

    def refuse(*args, **kwargs):
        raise OSError("no processes here")

    monkeypatch.setattr(build, "ProcessPoolExecutor", refuse)
    assert build._claims_process(True, seen.append, fake) == (None, None)
    assert "they run in line" in seen[-1]


def test_claims_listed_first_are_computed_first_and_shown_in_the_registry_order():
    from cross_check.report import sections

    order = []

    class Claim(_FakeClaim):
        def run(self, quick):
            order.append(self.row["id"])
            return super().run(quick)

    claims = {cid: Claim({"id": cid, "statement": "s", "verdict": "reproduced", "corrected": None})
              for cid in ("a", "b", "c")}
    lines = sections.claims_section(True, lambda msg: None, claims=claims, first=("c",))
    assert order == ["c", "a", "b"]
    assert [ln.split("|")[1].strip() for ln in lines[2:5]] == ["a", "b", "c"]


def test_report_iterates_the_claims_registry():
    from cross_check.paper.claims import CLAIMS
    from cross_check.report import sections

    lines = sections.claims_section(True, lambda msg: None, claims={k: CLAIMS[k] for k in ("lift",)})
    assert len(lines) == 3 and lines[2].startswith("| lift | erratum |")


def test_the_claims_worker_runs_the_scipy_itineraries_after_the_claims_on_a_users_scene():
    """The untimed solve_ivp itineraries run in the claims worker (``build._scipy_timed``), the
    user's scenes registered there first: the same table as in line; with no pool, nothing is
    submitted (the report then runs them in line)."""
    import importlib

    from cross_check import scenefile, scenes

    build = importlib.import_module("cross_check.report.build")
    found = scenefile.collect([], ["F=1 f=0.3 omega=1.3 l=-0.5 r=0.7"])
    name = scenefile.register_all(found)[0]
    pool, future = build._claims_process(True, [].append, {})
    with pool:
        future.result(timeout=120)
        worker = build._submitted(pool, build._scipy_timed, (name,), 2, None, [scenes.scene(name)])
        lines, seconds = worker.result(timeout=300)
    assert lines == build.sections.scipy_itineraries((name,), 2, None) and seconds > 0
    assert len(lines) == 6 and all(f"| {m} rtol" in "".join(lines) for m in ("RK45", "DOP853"))
    assert build._submitted(None, build._scipy_timed, (name,), 2, None) is None
