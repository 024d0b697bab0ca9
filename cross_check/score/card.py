"""The scorecard: any adapter against the golden data, per scene and per kind of case.

For every scored scene (those whose effects the adapter declares; the rest are listed as
skipped), on the float64 input of every golden case (``score.golden``):

* **digits** of ``Phi`` after one period against the 40-digit golden answer,
  ``-log10(|a - g| / max(1, |g|))`` (capped at 17), and the **digits lost to the one-ulp floor**
  (the exact map's own spread under one-ulp moves of the start, from the golden Jacobian);
* after ten periods (``periods`` containing 10): digits against the reference at ``TEN_DPS`` digits on
  the scene's sample states outside the band (chaotic orbits amplify every error alike: read
  them beside the floor, not as a grade);
* **itinerary**, where the adapter gives events: both logs in ``compare.canonical`` form,
  *missed* (golden kinds the adapter lacks) and *invented* (the reverse), counted per kind;
* **failures**: exceptions, non-finite results, and **timeouts**, per start;
* **time** per trajectory-period: the whole scene's batch in one ``step`` call.

Grades per kind: ``sheet``.  **Time budget**: every call on a start has ``case_timeout``
seconds; a start without a result in time is a failure of kind ``timeout`` and the run goes on.
The first call of ``step`` and of ``events`` on each set of effects in a run is a warm-up on a
start that neither sticks nor chatters, with ``first_call_timeout`` (a JIT may compile a new
code path there), its outcome thrown away (``runner``).  An adapter given by its
``MODULE:NAME`` spec runs in a worker process that is killed when a call runs over (``runner``,
``isolate``); an adapter object runs in process, where the budget is checked after each call.
A start whose one-period call ran out of time is not tried over ten periods (the same work
comes first there).  **Fail fast** (issue 37): after ``kind_timeouts`` timeouts of one kind in a
scene the kind's other starts there are not run (``cutoff``: failed, counted apart, the time saved
on the card), and after the adapter's first timeout the starts whose outcome cannot change a grade
get a short budget (``runner.Budget``): a broken kind costs a few budgets, a correct adapter --
one that never runs out of time -- is scored exactly as without either.
"""
from __future__ import annotations

import argparse
import collections
import contextlib
import math
import os
import pathlib
import signal
import sys
import threading
import time
import traceback

import numpy as np

from cross_check import golden, outputs, scenefile
from cross_check import scenes as scene_table
from cross_check.agreement import compare
from cross_check.progress import Progress
from cross_check.score import adapters, isolate, runner
from cross_check.score.cutoff import KIND_TIMEOUTS, NOT_RUN, SCENES_RUNNING, KindCutoff, kind_timeouts_arg
from cross_check.score.golden import (easiest, golden_scene, scene_cases, ten_period_cases, timeout_message,
                                      warmup_case)
from cross_check.score.protocol import BadAdapter, load_adapter
from cross_check.score.sheet import CaseScore, Scorecard

#: the reference's digits for the ten-period truth.  The reading is of a float64 answer, capped at
#: 17 digits, and the truth's error and the answer's are amplified by the same ten-period
#: conditioning: at ``d`` digits the truth stays ``10^(16 - d)`` below the answer's rounding alone,
#: whatever that amplification.  Issue 33 (one run each): the first three sample states of three
#: unseen position-forced scenes (``F=1 f=0.15 omega=1.7 l=-0.4 r=0.9 wavenumber=1.3``, ``F=2 f=0
#: omega=0.5 l=-1 r=1 wavenumber=2``, ``F=1.896 f=0.0929 omega=0.806 l=0.04 r=0.64 wavenumber=3.5937
#: damping=0.369 restitution=0.9``) read the same digits to 3 decimals at 40, 25 and 20 digits,
#: and the nine truths took 44.0 -> 29.7 CPU s at 25 (the frictionless scene's three: 35.3 -> 24.2)
TEN_DPS = 25
TEN = "ten periods"   # the ten-period calls' kind for the budget and the cut-off (never graded)
CASE_TIMEOUT, FIRST_CALL_TIMEOUT = runner.CASE_TIMEOUT, runner.FIRST_CALL_TIMEOUT


def _digits(pair, case) -> float:
    gx, gv = case.phi_mpf()
    return min(compare.digits(pair[0], gx), compare.digits(pair[1], gv))


def _itinerary(case, got, scene):
    """``(missed, invented)`` kind counts of the adapter's log against the golden one (canonical)."""
    have = collections.Counter(e.kind for e in adapters.canonical_log(got, scene))
    want = collections.Counter(e[0] for e in case.events)
    return dict(want - have), dict(have - want)


def _failed(s: CaseScore, out: runner.Outcome, what: str = "") -> CaseScore:
    s.failure_kind, s.budget = out.kind, out.budget
    if out.kind == "timeout":
        s.failure = timeout_message(s.id, s.kind, out.budget, what + out.failure)
    else:
        s.failure = f"{what}{out.kind}: {out.failure}" if out.kind == "crash" else what + out.failure
    return s


def _case_score(case, out: runner.Outcome) -> CaseScore:
    s = CaseScore(case.id, case.kind, case.band, budget=out.budget)
    if out.failure is not None:
        return _failed(s, out)
    x, v = (float(a) for a in out.value)
    if not (math.isfinite(x) and math.isfinite(v)):
        s.failure, s.failure_kind = f"non-finite result {(x, v)}", "non-finite"
        return s
    s.digits = _digits((x, v), case)
    floor = case.ulp_floor()
    s.floor_digits = None if floor is None else -math.log10(floor)
    return s


def score_scene(adapter, name: str, periods=(1, 10), *, run=None, budget=None, say=None,
                golden_dir=None, cut=None) -> dict:
    """Every golden case of one scene: ``{"cases": [CaseScore], "seconds_per_period", "ten", "mode",
    "budget"}``.  ``run``: a ``runner`` (default: one for ``adapter``, closed after); ``budget``: a
    ``runner.Budget`` (default: the module's); ``golden_dir``: the golden data (default: shipped);
    ``cut``: the run's ``cutoff.KindCutoff`` (default: none, every start runs)."""
    own = run is None
    run = runner.runner(adapter) if own else run
    budget = budget or runner.Budget(CASE_TIMEOUT, FIRST_CALL_TIMEOUT, ungraded=(TEN,))
    try:
        cases = scene_cases(name, golden_dir)
        sc = golden_scene(name, golden_dir)
        params = dict(cases[0].params)
        X, V = np.array([c.x for c in cases]), np.array([c.v for c in cases])
        names = [f"{c.id} [{c.kind}]" for c in cases]
        tags = [(c.kind, not c.band) for c in cases]
        scene_cut = cut.scene(name, tags) if cut is not None else None
        for method in ("step", "events") if run.meta["events"] else ("step",):
            if budget.first_time((method, sc.effects)):
                w = warmup_case(sc.effects, golden_dir) or cases[easiest(cases)]
                runner.warm_up(run, method, w.params, w.x, w.v, budget, f"{w.id} [{w.kind}]", say)
        steps, seconds, mode = runner.run_starts(run, "step", params, X, V, 1, budget, names, say, easiest(cases),
                                                 tags=tags, cut=scene_cut)
        out = [_case_score(c, o) for c, o in zip(cases, steps)]
        ok = [i for i, s in enumerate(out) if s.failure is None]
        if run.meta["events"] and ok:
            logs, _, _ = runner.run_starts(run, "events", params, X[ok], V[ok], None, budget,
                                           [names[i] for i in ok], say, easiest([cases[i] for i in ok]),
                                           tags=[tags[i] for i in ok], cut=scene_cut)
            for i, log in zip(ok, logs):
                if log.failure is None:
                    out[i].missed, out[i].invented = _itinerary(cases[i], log.value, sc)
                elif log.kind in ("timeout", "crash", NOT_RUN):    # an exception there: the itinerary is not scored
                    _failed(out[i], log, "events: ")
        ten = _ten_periods(run, params, sc, cases, out, budget, say, scene_cut) if 10 in periods else []
        if scene_cut is not None:
            scene_cut.close()
    finally:
        if own:
            run.close()
    shorts = [o.budget for o in steps if o.budget is not None and o.budget < budget.per_start]
    return {"cases": out, "seconds_per_period": seconds / len(cases), "ten": ten, "mode": mode,
            "budget": {"cap": budget.per_start, "short": min(shorts) if shorts else None}}


def _ten_periods(run, params, sc, cases, scores, budget, say, cut=None):
    """Digits after ten periods against the reference at ``TEN_DPS`` on sample states outside the
    band (``None``: failed, or not tried because its first period ran out of time or was not run).
    For the budget and the cut-off the ten-period calls are one kind of their own, ``TEN``: never
    graded (``runner.Budget``'s ``ungraded``: the short budget once the adapter has timed out)."""
    picked = ten_period_cases(cases)
    tried = [i for i in picked if scores[i].failure_kind not in ("timeout", "crash", NOT_RUN)]
    got = {}
    if tried:
        outs, _, _ = runner.run_starts(run, "step", params, np.array([cases[i].x for i in tried]),
                                       np.array([cases[i].v for i in tried]), 10, budget,
                                       [f"{cases[i].id} [{cases[i].kind}] x10" for i in tried], say,
                                       tags=[(TEN, True)] * len(tried), cut=cut)
        got = {i: o.value for i, o in zip(tried, outs) if o.failure is None}
    out = []
    for i in picked:
        if i not in got or not all(math.isfinite(float(a)) for a in got[i]):
            out.append(None)
            continue
        c = cases[i]
        truth = compare.ref_map(sc, compare.Case(c.name, repr(c.x), repr(c.v), "float64", "golden input"), 10, TEN_DPS)
        out.append(min(compare.digits(float(got[i][0]), truth[0]), compare.digits(float(got[i][1]), truth[1])))
    return out


def _check_effects(meta, who):
    unknown = set(meta["effects"]) - set(adapters.EFFECTS)
    if unknown:
        raise BadAdapter(f"adapter {who}: effects has unknown effects {sorted(unknown)}; known: {adapters.EFFECTS}")


def score(adapter, *, scenes=None, periods=(1, 10), progress=None, case_timeout: float = CASE_TIMEOUT,
          first_call_timeout: float = FIRST_CALL_TIMEOUT, in_process: bool | None = None,
          checkpoint=None, golden_dir=None, kind_timeouts: int = KIND_TIMEOUTS,
          budget_multiple: float = runner.BUDGET_MULTIPLE, budget_floor: float = runner.BUDGET_FLOOR) -> Scorecard:
    """Score ``adapter`` (an object, or a ``MODULE:NAME`` spec; protocol: ``cross_check.score``) on
    ``scenes`` (default: every scene with golden data in ``golden_dir``, by default the shipped
    data); ``periods`` ``(1,)`` or ``(1, 10)``.

    A spec runs in a worker process killed at the budget, an object in process (budget checked
    after each call); ``in_process`` overrides (``False`` with an object: it must pickle).
    ``progress(message)`` gets a line per scene and per slow start; ``checkpoint(card)`` gets the
    card before the first scene and after each one (``complete`` false until the end).  A
    protocol violation is a ``BadAdapter`` (a ``TypeError``), bad arguments a ``ValueError``.

    ``kind_timeouts``: the per-kind cut-off K (``cutoff``; 0: every start runs);
    ``budget_multiple``, ``budget_floor``: the short budget (``runner.Budget``; multiple 0: every
    start has ``case_timeout``)."""
    if not set(periods) <= {1, 10} or 1 not in periods:
        raise ValueError(f"periods must be (1,) or (1, 10), got {periods!r}")
    have = golden.names_in(golden_dir)
    names = have if scenes is None else list(scenes)
    unknown = [n for n in names if n not in have]
    if unknown:
        raise ValueError(f"unknown scene(s) {unknown}: no golden data for them in {golden.files(golden_dir)}; "
                         f"it has: {', '.join(have)}")
    budget = runner.Budget(case_timeout, first_call_timeout, multiple=budget_multiple, floor=budget_floor,
                           ungraded=(TEN,))
    cut = KindCutoff(kind_timeouts)
    say = progress or (lambda m: None)
    run = runner.runner(adapter, in_process, setup_budget=max(budget.first, isolate.SETUP_BUDGET))
    try:
        meta = run.meta
        _check_effects(meta, run.who)
        card = Scorecard(meta["name"], [], {}, {}, meta["events"], planned=names, complete=False,
                         budget={**budget.describe(), "kind_timeouts": kind_timeouts,
                                 "isolated": run.isolated, "isolation": run.note, "restarts": 0})
        if checkpoint:
            checkpoint(card)
        for name in names:
            lacking = golden_scene(name, golden_dir).effects - set(meta["effects"])
            if lacking:
                card.skipped[name] = lacking
                continue
            t0 = time.perf_counter()
            say(f"score {meta['name']}: {name} ...")
            res = score_scene(None, name, periods, run=run, budget=budget, say=say, golden_dir=golden_dir, cut=cut)
            card.cases += res["cases"]
            card.scenes[name] = {k: res[k] for k in ("seconds_per_period", "ten", "mode", "budget")}
            card.budget.update(budget.describe(), restarts=run.restarts)
            failed = [c for c in res["cases"] if c.failure]
            skipped = sum(c.failure_kind == NOT_RUN for c in failed)
            say(f"score {meta['name']}: {name}: {len(res['cases'])} starts, {len(failed) - skipped} failed "
                f"({sum(c.failure_kind == 'timeout' for c in failed)} timeouts)"
                + (f", {skipped} not run (kind cut off)" if skipped else "") + f", {time.perf_counter() - t0:.1f} s")
            if checkpoint:
                checkpoint(card)
        card.complete = True
    finally:
        run.close()
    return card


# --- the command line ---------------------------------------------------------------------
class Stopped(BaseException):
    """A signal (SIGINT, SIGTERM) asked the run to stop; ``main`` keeps the scorecard so far."""

    def __init__(self, signame: str):
        super().__init__(signame)
        self.signame = signame


@contextlib.contextmanager
def _stop_on_signals():
    """SIGINT and SIGTERM raise in the main thread while the run goes on (restored after)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def raise_stopped(signum, frame):
        raise Stopped(signal.Signals(signum).name)

    old = {s: signal.signal(s, raise_stopped) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for s, handler in old.items():
            signal.signal(s, handler)


def build_parser() -> argparse.ArgumentParser:
    """The ``score`` command's options (one place: add new ones here)."""
    parser = argparse.ArgumentParser(
        prog="python -m cross_check score",
        description="Score an integrator against the golden data (protocol: cross_check.score).  The adapter "
                    "runs in a worker process, killed and restarted when a call on a start runs over "
                    "--case-timeout: that start fails with kind timeout and the run goes on.  Writes "
                    "scorecard.md and scorecard.json after every scene (marked incomplete until the last).  "
                    "Exit status: 0 every kind passes, 1 a kind is flagged, 2 bad arguments or a bad adapter, "
                    "130/143 interrupted by SIGINT/SIGTERM (the scorecard so far is kept).")
    parser.add_argument("adapter", nargs="?", help="MODULE:NAME of an adapter, or fast | reference | scipy | heyoka "
                        "(or, instead, --results FILE or --export-problems DIR)")
    parser.add_argument("--export-problems", metavar="DIR", default=None, type=outputs.check_folder,
                        help="write the selected problems for an integrator in any language (DIR/problems.csv, "
                             "problems.json, FORMAT.md) and exit")
    parser.add_argument("--results", metavar="FILE", default=None,
                        help="grade a results file (results.csv or results.json, FORMAT.md) written for the "
                             "problems of the same selection flags, as an adapter")
    parser.add_argument("--scenes", nargs="+", metavar="NAME", choices=list(scene_table.SCENES),
                        help="only these built-in scenes (default: all with golden data)")
    parser.add_argument("--golden-dir", metavar="DIR", default=None,
                        help="golden data written by `golden` or `verify` (DIR/golden) instead of the shipped data")
    scenefile.add_arguments(parser, "score on")
    parser.add_argument("--periods", nargs="+", type=int, default=[1, 10], choices=[1, 10],
                        help="horizons: 1, or 1 10 (default)")
    parser.add_argument("--out", default="scorecard", type=outputs.check_folder, help="output directory (default: scorecard/)")
    parser.add_argument("--case-timeout", type=runner.positive_seconds, default=CASE_TIMEOUT, metavar="SECONDS",
                        help=f"budget of each call on a start (default {CASE_TIMEOUT:g}); a start over it is a "
                             "failure of kind timeout and the run goes on")
    parser.add_argument("--first-call-timeout", type=runner.positive_seconds, default=FIRST_CALL_TIMEOUT,
                        metavar="SECONDS", help="budget of the warm-up call of step and of events on each set of "
                        "effects, on a start that neither sticks nor chatters, where a JIT may compile "
                        f"(default {FIRST_CALL_TIMEOUT:g})")
    parser.add_argument("--kind-timeouts", type=kind_timeouts_arg, default=KIND_TIMEOUTS, metavar="K",
                        help=f"per-kind cut-off: after K timeouts of one kind in a scene its other starts there are "
                             f"not run (failed, 'not run', counted apart); a kind cut in {SCENES_RUNNING} scenes "
                             f"running gets one probe start per later scene (default {KIND_TIMEOUTS}; 0: every start "
                             "runs)")
    parser.add_argument("--budget-multiple", type=float, default=runner.BUDGET_MULTIPLE, metavar="M",
                        help="after the adapter's first timeout, starts whose outcome cannot change a grade (band, "
                             "kinds already failed, ten periods) get min(cap, max(floor, M x the median start)) "
                             f"(default {runner.BUDGET_MULTIPLE:g}; 0: every start has the cap)")
    parser.add_argument("--budget-floor", type=runner.positive_seconds, default=runner.BUDGET_FLOOR, metavar="SECONDS",
                        help=f"the floor of that short budget (default {runner.BUDGET_FLOOR:g})")
    parser.add_argument("--in-process", action="store_true",
                        help="call the adapter in this process, not in a worker process (for adapters that "
                             "cannot be loaded there); the budget is then checked after each call, so a "
                             "start that never returns hangs the run")
    parser.add_argument("--debug", action="store_true", help="show the traceback behind a bad adapter")
    return parser


def _write(card: Scorecard, out: pathlib.Path):
    """Both files, each replaced whole (an interrupted write never leaves half a file)."""
    out.mkdir(parents=True, exist_ok=True)
    for name, text in (("scorecard.md", card.to_markdown()), ("scorecard.json", card.to_json())):
        tmp = out / f".{name}.part"
        tmp.write_text(text)
        os.replace(tmp, out / name)


def _source(args, names):
    """What ``main`` scores: the adapter spec, or a results file read as an adapter (``results``),
    with the keywords that go with it; ``ValueError`` for a bad combination or a malformed file."""
    given = [a for a in (args.adapter, args.results, args.export_problems) if a is not None]
    if len(given) != 1:
        raise ValueError("give exactly one of ADAPTER, --results FILE, --export-problems DIR")
    if args.results is None:
        return args.adapter, {}
    from cross_check.score import problems, results
    rows = problems.problems(names or None, tuple(args.periods), args.golden_dir)
    # every row of the file is graded: nothing to save by cutting kinds, no time to budget
    return results.ResultsAdapter(args.results, rows), {"in_process": True, "kind_timeouts": 0, "budget_multiple": 0}


def main(argv=None) -> int:
    """``python -m cross_check score ADAPTER|--results FILE|--export-problems DIR [--scenes ...]
    [--scenes-file FILE] [--scene "..."] [--golden-dir DIR] [--periods 1 [10]] [--out DIR]
    [--case-timeout S] [--first-call-timeout S] [--kind-timeouts K] [--in-process] [--debug]``."""
    args = build_parser().parse_args(argv)
    out, last = pathlib.Path(args.out), []
    say = Progress()

    def checkpoint(card):
        last[:] = [card]
        _write(card, out)

    def stop(reason, status):
        if last:
            last[0].stopped = reason
            _write(last[0], out)
            print(f"score: {reason}; the scorecard so far (marked incomplete): {out / 'scorecard.md'}", file=sys.stderr)
        return status

    try:
        names = (args.scenes or []) + scenefile.from_args(args)
        adapter, keywords = _source(args, names)
        if args.export_problems is not None:
            from cross_check.score import problems
            for path in problems.export(args.export_problems, names or None, tuple(args.periods), args.golden_dir):
                print(path)
            return 0
        settings = {"in_process": args.in_process or None, "kind_timeouts": args.kind_timeouts,
                    "budget_multiple": args.budget_multiple, **keywords}
        with _stop_on_signals():
            card = score(adapter, scenes=names or None, periods=tuple(args.periods), progress=say,
                         golden_dir=args.golden_dir, case_timeout=args.case_timeout,
                         first_call_timeout=args.first_call_timeout, checkpoint=checkpoint,
                         budget_floor=args.budget_floor, **settings)
    except (KeyboardInterrupt, Stopped) as exc:
        name = getattr(exc, "signame", "SIGINT")
        return stop(f"interrupted by {name}", 128 + signal.Signals[name].value)
    except (ValueError, BadAdapter) as exc:
        print(f"score: {exc}", file=sys.stderr)
        if args.debug:
            traceback.print_exc()
            if getattr(exc, "detail", None):
                print(f"behind it:\n{exc.detail}", file=sys.stderr)
        return stop(f"stopped: {exc}", 2)
    _write(card, out)
    print(out / "scorecard.md")
    return 1 if card.flagged() else 0


__all__ = ["CASE_TIMEOUT", "CaseScore", "FIRST_CALL_TIMEOUT", "Scorecard", "build_parser", "load_adapter",
           "main", "score", "score_scene"]
