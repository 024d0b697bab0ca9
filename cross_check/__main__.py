"""The suite's front door: ``python -m cross_check COMMAND [options]``.

Commands (each has its own ``--help``):

* ``report``  -- accuracy/performance report (markdown + PNG), ``cross_check.report``;
* ``golden``  -- write the golden data from the reference, ``cross_check.golden``;
* ``claims``  -- check the paper's claims, ``cross_check.paper.claims``;
* ``figures`` -- redraw the paper's figures, ``cross_check.paper.figures``;
* ``score``   -- score an integrator against the golden data, ``cross_check.score``;
* ``sensitivity`` -- the suite's checks on a catalogue of faulty integrators, ``cross_check.sensitivity``;
* ``atlas``   -- the claims over parameter space on Dask, ``cross_check.atlas``;
* ``prove``   -- computer-assisted proofs: the golden data and the paper's orbits, ``cross_check.proofs``;
* ``verify``  -- the whole V&V on the user's scenes (a TOML scene file), ``cross_check.verify``;
* ``league``  -- the field's integrators (SUNDIALS, diffrax, MuJoCo, ...) graded side by side, ``cross_check.league``.

Bad arguments give one line on stderr and exit status 2 (argparse's convention); so does an
output that cannot be written (every ``--out`` is checked before the work starts,
``cross_check.outputs``; an ``OSError`` naming a file later on gives the same one line).
"""
from __future__ import annotations

import importlib
import sys

COMMANDS = {
    "report": ("cross_check.report", "accuracy/performance report: fast vs reference vs scipy, claims (report/)"),
    "golden": ("cross_check.golden", "write golden data from the reference at 40 digits (cross_check/data/golden/)"),
    "claims": ("cross_check.paper.claims", "check the paper's claims one by one"),
    "figures": ("cross_check.paper.figures", "redraw the paper's figures as PNG"),
    "score": ("cross_check.score", "score any integrator (MODULE:NAME) against the golden data"),
    "atlas": ("cross_check.atlas", "where each claim holds: the claims over (f/F, w^2 R/F), on Dask"),
    "sensitivity": ("cross_check.sensitivity", "which check catches which fault: a catalogue of faulty integrators"),
    "prove": ("cross_check.proofs", "computer-assisted proofs: golden data enclosures, the paper's periodic orbits"),
    "verify": ("cross_check.verify", "the whole V&V on your scenes (SCENES.toml): golden data, proofs, orbits, scores"),
    "league": ("cross_check.league", "the field's integrators graded side by side: league table and work-precision"),
}

USAGE = "usage: python -m cross_check {" + ",".join(COMMANDS) + "} [options]"


def _help() -> str:
    width = max(map(len, COMMANDS))
    lines = [USAGE, "", "Verification and validation of the vibro-impact oscillator with Coulomb friction.",
             "", "commands:"]
    lines += [f"  {name:<{width}}  {text}" for name, (_, text) in COMMANDS.items()]
    lines += ["", "`python -m cross_check COMMAND --help` shows a command's options."]
    return "\n".join(lines)


def _fail(message: str) -> int:
    print(f"python -m cross_check: error: {message}", file=sys.stderr)
    return 2


class _OneLineExit(Exception):
    pass


def _one_line_errors(argv, run):
    """Run a subcommand's ``main(argv)``, turning argparse's usage+error into one line."""
    import argparse

    original = argparse.ArgumentParser.error

    def error(self, message):
        raise _OneLineExit(f"{self.prog}: error: {message}")

    argparse.ArgumentParser.error = error
    try:
        return run(argv)
    except _OneLineExit as exc:
        print(str(exc), file=sys.stderr)
        return 2
    finally:
        argparse.ArgumentParser.error = original


def main(argv=None) -> int:
    """Dispatch to the subcommand; return its exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv:
        return _fail(f"a command is required ({', '.join(COMMANDS)}); see --help")
    cmd, rest = argv[0], argv[1:]
    if cmd in ("-h", "--help", "help"):
        print(_help())
        return 0
    if cmd not in COMMANDS:
        return _fail(f"unknown command {cmd!r}; choose from {', '.join(COMMANDS)}")
    module_name = COMMANDS[cmd][0]
    try:
        module = importlib.import_module(module_name)
    except ModuleNotFoundError as exc:
        if exc.name == module_name:
            return _fail(f"command {cmd!r} is not available ({module_name} is not installed in this tree)")
        raise
    if not hasattr(module, "main"):
        return _fail(f"command {cmd!r} is not available ({module_name} has no main(argv))")
    try:
        status = _one_line_errors(rest, module.main)
    except SystemExit as exc:   # --help of a subcommand exits 0; keep other codes
        code = exc.code
        return code if isinstance(code, int) else (0 if code is None else 2)
    except OSError as exc:      # an output the parse-time check could not foresee (cross_check.outputs)
        if exc.filename is None:
            raise
        return _fail(f"{cmd}: {exc.filename!s}: {exc.strerror or exc}")
    return 0 if status is None else int(status)


if __name__ == "__main__":
    sys.exit(main())
