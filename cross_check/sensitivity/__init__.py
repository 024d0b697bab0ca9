"""The suite's power, measured: a catalogue of faulty integrators and which check catches each.

``python -m cross_check sensitivity [--out DIR]`` runs every check of ``checks`` (golden map,
itinerary and event times, Jacobian, constructed events, threshold pairs) on the control
(``fast`` itself, with its Jacobian also rebuilt by Table 1: it must pass every check) and on
every fault of ``faults.catalogue()`` (one physics fault each: friction off by 1 % and 1e-6,
restitution twice, the period 1e-9 long, grazing impacts skipped, chatter cut short, the
reflection matrix with the velocity after the impact, the turning point's factor missing, a
1e-12 bias of the map), and writes the table: which checks caught each fault, and in how long.
Exit status 1 if a fault escapes every check or the control trips one.

May import ``cross_check.score``, ``agreement``, ``scenes``, ``tolerances`` and ``fast``; the
CLI imports it.
"""
from __future__ import annotations

import argparse
import json
import pathlib

from cross_check import outputs
from cross_check.progress import Progress
from cross_check.sensitivity import checks, faults
from cross_check.score.adapters import FAST


def table(progress=None) -> dict:
    """``{adapter name: {"what", "control", "results": [checks.Result]}}`` for the control and
    every catalogued fault."""
    out = {}
    for adapter, control in [(FAST, True), (faults.Faithful(), True)] + [(f, False) for f in faults.catalogue()]:
        results = checks.run(adapter)
        out[adapter.name] = {"what": getattr(adapter, "what", "fast itself"), "control": control,
                             "results": results}
        if progress:
            caught = [r.check for r in results if r.caught]
            progress(f"{adapter.name}: caught by {', '.join(caught) or 'nothing'}")
    return out


def verdicts(tab: dict) -> tuple[list, list]:
    """``(escaped faults, controls that tripped a check)``."""
    escaped = [n for n, row in tab.items() if not row["control"] and not any(r.caught for r in row["results"])]
    tripped = [n for n, row in tab.items() if row["control"] and any(r.caught for r in row["results"])]
    return escaped, tripped


def markdown(tab: dict) -> str:
    names = list(checks.CHECKS)
    lines = ["# Sensitivity: which check catches which fault", "",
             "Each row is `fast` with one physics fault (the first two rows: no fault, the control).  "
             "A cell gives the seconds the check took on that integrator, **bold** where it caught the "
             "fault.", "", "| integrator | fault | " + " | ".join(names) + " | caught |",
             "|---|---|" + "---|" * (len(names) + 1)]
    for name, row in tab.items():
        by = {r.check: r for r in row["results"]}
        cells = [("**%.2f s**" if by[c].caught else "%.2f s") % by[c].seconds if c in by else "n/a" for c in names]
        n = sum(r.caught for r in row["results"])
        verdict = ("yes" if n else "**no**") if not row["control"] else ("clean" if not n else "**tripped**")
        lines.append(f"| {name} | {row['what']} | " + " | ".join(cells) + f" | {verdict} |")
    escaped, tripped = verdicts(tab)
    faults_n = sum(1 for r in tab.values() if not r["control"])
    lines += ["", f"Caught: {faults_n - len(escaped)} of {faults_n} faults"
              + (f"; escaped: {', '.join(escaped)}" if escaped else "")
              + (f"; control tripped: {', '.join(tripped)}" if tripped else "; controls clean") + ".", ""]
    for name, row in tab.items():
        hits = [f"{r.check}: {r.detail}" for r in row["results"] if r.caught]
        if hits:
            lines.append(f"- {name}: " + "; ".join(hits))
    return "\n".join(lines) + "\n"


def main(argv=None) -> int:
    """``python -m cross_check sensitivity [--out DIR]``."""
    parser = argparse.ArgumentParser(
        prog="python -m cross_check sensitivity",
        description="Run the suite's checks on a catalogue of faulty integrators (fast with one physics "
                    "fault each) and on the control; write which check caught each fault and how fast.  "
                    "Exit status: 0 every fault caught and the control clean, 1 a fault escaped or the "
                    "control tripped a check, 2 bad arguments or an unwritable --out.")
    parser.add_argument("--out", default="sensitivity", type=outputs.check_folder, help="output directory (default: sensitivity/)")
    args = parser.parse_args(argv)
    tab = table(Progress())
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "sensitivity.md").write_text(markdown(tab))
    (out / "sensitivity.json").write_text(json.dumps(
        {n: {"what": r["what"], "control": r["control"], "results": [vars(x) for x in r["results"]]}
         for n, r in tab.items()}, indent=1) + "\n")
    print(out / "sensitivity.md")
    escaped, tripped = verdicts(tab)
    return 1 if escaped or tripped else 0
