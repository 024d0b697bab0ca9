"""Running the league: ``python -m cross_check league [--quick] [--out DIR] [--peers NAME ...]``.

For each entry (``entries``): build its adapter, time its compilation apart where it has one
(``warmup_seconds``: a fresh worker process, the first call on the scenes' warm-up start less
the second), then score it with ``cross_check.score.card.score`` in the scorer's worker process
(per-start budgets, one period), and read its row off the scorecard (``table``; the scorecard
itself goes to ``scorecards/``).  The files are rewritten after every row (``league.md``,
``league.json``, ``work_precision.png``), so a run stopped half-way leaves the rows so far.

``score_options`` pass through to ``score`` unchanged (``case_timeout``, ``first_call_timeout``,
and whatever keywords it takes); ``periods`` is always ``(1,)``.
"""
from __future__ import annotations

import argparse
import os
import pathlib
import re
import time

import numpy as np

from cross_check import outputs
from cross_check.league import entries, plot, table
from cross_check.progress import Progress
from cross_check.score import card as score_card
from cross_check.score import runner
from cross_check.score.golden import golden_scene, scene_cases, warmup_case

#: calls of the round-trip measurement (``call_floor``)
FLOOR_CALLS = 21


def warmup_seconds(adapter, scene: str, first_call_timeout: float = runner.FIRST_CALL_TIMEOUT,
                   case_timeout: float = runner.CASE_TIMEOUT) -> float | None:
    """The compilation on an adapter's first call: in a fresh worker process, the first ``step``
    on ``scene``'s warm-up start less the second (``None`` if a call failed)."""
    effects = golden_scene(scene).effects
    case = warmup_case(effects) or scene_cases(scene)[0]
    args = (dict(case.params), np.array([case.x]), np.array([case.v]), 1)
    run = runner.runner(adapter, in_process=False)
    try:
        first = run.call("step", args, first_call_timeout)
        second = run.call("step", args, case_timeout) if first.failure is None else first
    finally:
        run.close()
    if first.failure is not None or second.failure is not None:
        return None
    return max(0.0, first.seconds - second.seconds)


class Echo:
    """An adapter that does no work (``step`` returns its input): the scorer's round trip to its
    worker process, which every timed call includes, measured alone."""

    name = "echo"
    effects = frozenset({"walls", "forcing", "friction", "restitution", "damping", "position_forcing"})

    def step(self, params, x, v, periods):
        return np.asarray(x, float), np.asarray(v, float)


def call_floor(scene: str, calls: int = FLOOR_CALLS) -> float:
    """The median time of ``calls`` calls of ``Echo`` on ``scene``'s starts through the scorer's
    runner in a worker process, per start: the floor under every timed call of this run."""
    cases = scene_cases(scene)
    args = (dict(cases[0].params), np.array([c.x for c in cases]), np.array([c.v for c in cases]), 1)
    run = runner.runner(Echo(), in_process=False)
    try:
        times = [run.call("step", args, runner.CASE_TIMEOUT).seconds for _ in range(calls)]
    finally:
        run.close()
    return float(np.median(times)) / len(cases)


def run_entry(entry, scenes, score_options: dict, say):
    """``(row, scorecard)``: the adapter of ``entry`` scored on ``scenes`` (module docstring)."""
    t0 = time.perf_counter()
    adapter = entry.make()
    warm = None
    if getattr(adapter, "jit", False):
        opts = {k: score_options[k] for k in ("first_call_timeout", "case_timeout") if k in score_options}
        warm = warmup_seconds(adapter, scenes[0], **opts)
        say(f"league: {entry.peer} {entry.setting}: warm-up (compilation) "
            + ("failed" if warm is None else f"{warm:.1f} s"))

    def relay(message):        # the scorer's per-scene summaries and slow-call lines, not its "scene ..." lines
        if not message.endswith("..."):
            say(message)

    card = score_card.score(adapter, scenes=list(scenes), periods=(1,), in_process=False, progress=relay,
                            **score_options)
    return table.row(entry, card, warm, time.perf_counter() - t0), card


def league(out, quick: bool = False, groups=None, scenes=None, score_options=None, say=None) -> dict:
    """Run the league, write ``out/league.md``, ``league.json``, ``work_precision.png``; return
    the document (``table.document``)."""
    say = say or Progress()
    score_options = dict(score_options or {})
    chosen, skipped = entries.select(groups, quick)
    scenes = tuple(scenes or (entries.QUICK_SCENES if quick else entries.FULL_SCENES))
    out = pathlib.Path(out)
    for group, why in skipped.items():
        say(f"league: skipped {group}: {why}")
    t0, rows, load = time.perf_counter(), [], os.getloadavg()[0]
    floor = call_floor(scenes[0])
    say(f"league: the scorer's round trip to its worker: {floor * 1e6:.0f} us per start of a {scenes[0]} batch "
        f"({floor * len(scene_cases(scenes[0])) * 1e3:.2f} ms a call: the floor under every timed call)")
    for i, entry in enumerate(chosen, 1):
        say(f"league: [{i}/{len(chosen)}] {entry.peer} {entry.setting} ...")
        r, card = run_entry(entry, scenes, score_options, say)
        r["scorecard"] = _card_file(out, entry, card)
        rows.append(r)
        say(f"league: [{i}/{len(chosen)}] {entry.peer} {entry.setting}: median {table.fmt(r['median_digits'])} digits, "
            f"{table.fmt(r['seconds_per_start'], '.2e')} s per start-period, flagged: "
            f"{', '.join(r['kinds_flagged']) or '-'} ({r['wall_seconds']:.0f} s)")
        doc = table.document(rows, skipped, scenes, quick, time.perf_counter() - t0, score_options, load, floor)
        write(doc, out)
    doc = table.document(rows, skipped, scenes, quick, time.perf_counter() - t0, score_options, load, floor)
    write(doc, out)
    say(f"league: {doc['goal']['text']}")
    return doc


def _card_file(out: pathlib.Path, entry, card) -> str:
    """Write the row's scorecard to ``out/scorecards/`` (the cases behind the row); its path there."""
    name = "scorecards/" + re.sub(r"[^A-Za-z0-9.-]+", "-", f"{entry.peer} {entry.setting}") + ".md"
    (out / "scorecards").mkdir(parents=True, exist_ok=True)
    (out / name).write_text(card.to_markdown())
    return name


def write(doc, out: pathlib.Path):
    """The three files, each replaced whole."""
    out.mkdir(parents=True, exist_ok=True)
    for name, text in (("league.md", table.to_markdown(doc)), ("league.json", table.to_json(doc))):
        tmp = out / f".{name}.part"
        tmp.write_text(text)
        os.replace(tmp, out / name)
    if doc["rows"]:
        plot.work_precision_png(doc, out / ".work_precision.part.png")
        os.replace(out / ".work_precision.part.png", out / "work_precision.png")


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="python -m cross_check league",
        description="The league: every installed peer (SUNDIALS CVODE, diffrax, MuJoCo, scipy, heyoka), fast and "
                    "the reference, each at three or more settings, scored on the golden data by the scorecard "
                    "(per-start budgets, in its worker process).  Writes league.md, league.json and "
                    "work_precision.png.  A peer that is not installed is skipped, and said so.  Exit status: 0 the run "
                    "completed (league.md's goal line says whether fast met its goal), 2 bad arguments or an "
                    "unwritable --out.")
    parser.add_argument("--quick", action="store_true",
                        help=f"{len(entries.QUICK_SCENES)} scenes, fewer settings (about 2 minutes on 2 cores)")
    parser.add_argument("--out", default="league", type=outputs.check_folder,
                        help="output directory (default: league/)")
    parser.add_argument("--peers", nargs="+", metavar="NAME", choices=list(entries.GROUPS),
                        help=f"only these ({', '.join(entries.GROUPS)}; default: all installed)")
    parser.add_argument("--case-timeout", type=runner.positive_seconds, default=runner.CASE_TIMEOUT,
                        metavar="SECONDS", help=f"the scorer's budget per call on a start (default {runner.CASE_TIMEOUT:g})")
    return parser


def main(argv=None) -> int:
    """CLI entry; exit 0 when the run completed (the goal line says whether fast met its goal),
    2 on bad arguments or an unwritable ``--out``."""
    args = build_parser().parse_args(argv)
    out = args.out
    league(out, args.quick, args.peers, score_options={"case_timeout": args.case_timeout})
    print(out / "league.md")
    return 0


__all__ = ["build_parser", "league", "main", "run_entry", "warmup_seconds", "write"]
