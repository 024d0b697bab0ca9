"""Every command given an output it cannot write exits with status 2 and one line naming the path
and the reason, before any work (issue 36; ``cross_check.outputs``).

The unwritable outputs: an existing file where a folder is wanted, a read-only folder (mode
``a-w``: refused for root too), a path under ``/proc``.  Every command of ``__main__.COMMANDS``
must appear in ``RUNS`` (a new command without its row fails ``test_every_command_is_covered``),
and every output option of each command is probed.  In process (each command's ``main``
through the dispatcher: a traceback would fail the test), and three times by subprocess for the
real exit status.
"""
from __future__ import annotations

import os
import pathlib
import subprocess
import sys

import pytest

from cross_check import __main__ as cli
from cross_check import outputs

ROOT = pathlib.Path(__file__).resolve().parents[1]
EXAMPLE = str(ROOT / "cross_check" / "data" / "scenes" / "example.toml")

#: per command: its arguments before the output option, and its output options (folder or file)
RUNS = {
    "report": [((), "--out", "folder")],
    "golden": [(("--scenes", "fig:narrow"), "--out", "folder")],
    "claims": [(("--only", "lift"), "--out", "folder"), (("--only", "lift"), "--json", "file")],
    "figures": [((), "--out", "folder")],
    "score": [(("fast",), "--out", "folder")],
    "atlas": [(("--grid", "2"), "--out", "folder")],
    "sensitivity": [((), "--out", "folder")],
    "prove": [(("--golden",), "--out", "folder"), (("--golden",), "--json", "file"),
              (("--atlas", "--grid", "2"), "--out", "folder"), (("--intervals",), "--out", "file"),
              (("--claim", "dissip-invariance", "--scenes", "fig:narrow"), "--out", "folder"),
              (("--atlas", "--claim", "dissip-invariance", "--grid", "2"), "--out", "folder")],
    "verify": [((EXAMPLE, "--quick"), "--out", "folder")],
    "league": [(("--quick",), "--out", "folder")],
}


@pytest.fixture
def unwritable(tmp_path):
    """``name -> path``: a file, a read-only folder, a path under /proc."""
    a_file = tmp_path / "a-file"
    a_file.write_text("not a folder\n")
    read_only = tmp_path / "read-only"
    read_only.mkdir()
    read_only.chmod(0o555)
    yield {"file": a_file, "read-only folder": read_only / "out", "proc": pathlib.Path("/proc/vibro-impact/out")}
    read_only.chmod(0o755)


def test_every_command_is_covered():
    assert set(RUNS) == set(cli.COMMANDS), "a command without its --out probe: add it to RUNS"


@pytest.mark.parametrize("command", sorted(RUNS))
def test_unwritable_output_is_one_line_and_status_2(command, unwritable, capsys, monkeypatch):
    checked = []                  # the check ran at parse time, before any work (not a late OSError)
    for name in ("check_folder", "check_file"):
        check = getattr(outputs, name)
        monkeypatch.setattr(outputs, name, lambda text, check=check: (checked.append(str(text)), check(text))[1])
    for before, option, kind in RUNS[command]:
        for what, path in unwritable.items():
            if what == "file" and kind == "file":
                path = path.parent        # a folder where a file is wanted
            status = cli.main([command, *before, option, str(path)])
            err = capsys.readouterr().err.strip().splitlines()
            assert status == 2, (command, option, what, err)
            assert len(err) == 1 and str(path) in err[0] and "cannot write" in err[0], (command, option, what, err)
            assert str(path) in checked, (command, option, "not checked when parsed")


@pytest.mark.parametrize("what", ["file", "read-only folder", "proc"])
def test_the_real_command_exits_2_without_a_traceback(what, unwritable):
    proc = subprocess.run([sys.executable, "-m", "cross_check", "report", "--out", str(unwritable[what])],
                          cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2, proc.stderr
    assert "Traceback" not in proc.stderr and len(proc.stderr.strip().splitlines()) == 1, proc.stderr
    assert str(unwritable[what]) in proc.stderr


def test_writable_outputs_pass_and_nothing_is_created(tmp_path):
    new = tmp_path / "new" / "deeper"
    assert outputs.check_folder(new) == new and not new.exists()
    assert outputs.check_file(tmp_path / "x.json") == tmp_path / "x.json"
    assert os.listdir(tmp_path) == []             # the probe file is gone


@pytest.mark.parametrize("make, reason", [
    (lambda p: p.write_text("x"), "it is a file, not a folder"),
    (lambda p: (p.mkdir(), p.chmod(0o500)), "read-only"),
])
def test_the_check_says_why(tmp_path, make, reason):
    path = tmp_path / "out"
    make(path)
    try:
        with pytest.raises(outputs.Unwritable, match=reason):
            outputs.check_folder(path)
    finally:
        path.chmod(0o755)


def test_an_oserror_naming_a_file_later_is_one_line(monkeypatch, capsys):
    def main(argv):
        raise PermissionError(13, "Permission denied", "/somewhere/report.md")
    monkeypatch.setattr(cli.importlib.import_module("cross_check.report"), "main", main)
    assert cli.main(["report"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "/somewhere/report.md: Permission denied" in err[0]
