"""Assemble the V&V report: ``python -m cross_check report [--out DIR] [--quick] [--skip-claims]
[--scenes-file FILE] [--scene "F=1 f=0.3 omega=1 l=0 r=3"]`` (user scenes, ``cross_check.scenefile``:
the agreement and hard-case sections run on them instead of the built-in scenes).

Writes ``report.md`` and ``work_precision.png`` into ``--out`` (default ``report/``), section by
section (``sections``, ``precision``, ``plots``):

0. fast's kernels compiled (or loaded from numba's cache): the closed-form loop here, the
   position-forcing flights in the claims worker, at the same time;
1. per scene, fast against the reference at dps 50 on the seeded sample (itinerary first, then
   event and map digits, the near-grazing band);
2. the hard cases, built exactly (``cross_check.agreement.hardcases``);
3. work-precision: digits against seconds per trajectory-period for every method, with the
   one-ulp floor;
4. where solve_ivp misses events;
5. the paper's claims, one registered claim at a time (``cross_check.paper.claims.CLAIMS``), in
   one worker process beside sections 1-2 and the untimed part of 3, followed there by section 4
   (both collected before the timed part of 3, whose timings want both cores);
6. where the claims hold: the atlas's maps (``python -m cross_check atlas``) when one exists;
7. the league's table (``python -m cross_check league``) when one exists, read from disk
   (``league_link``: the report runs no peer);
8. machine, versions, seeds; where the time went (a row per section, with seconds).

One failing part does not take the report down: it is listed under "Failures" at the top and
the exit status is 1.  Progress goes to stderr, one line per step.  The full report takes under
a minute on two cores, ``--quick`` about 10 s.
"""
from __future__ import annotations

import dataclasses
import multiprocessing
import pathlib
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

from cross_check import outputs, scenefile, scenes
from cross_check.agreement import baseline, compare
from cross_check.progress import Progress
from cross_check.report import plots, precision, sections
from cross_check.report.league_link import league_section
from cross_check.report.sections import REF_DPS, TRUTH_DPS
from cross_check.tolerances import tol

WP_DPS = (16, 20, 30, 50, 100)


@dataclass(frozen=True)
class Plan:
    """How much work a report does."""

    scenes: tuple
    n_sample: int
    n_ten: int            # states per scene also compared after 10 periods
    hard_scenes: tuple
    wp_scenes: tuple
    wp_states: int
    wp_rtols: tuple
    wp_dps: tuple
    wp_periods: tuple


_WP_SCENES = ("fig:narrow-with-friction", "fig:many:2pi/f=0.1", "fig:resonance/R=0.8932")
FULL = Plan(tuple(scenes.SCENES), 12, 4, scenes.QUICK_SCENES, _WP_SCENES, 4, baseline.RTOLS, WP_DPS, (1, 10))
QUICK = Plan(_WP_SCENES, 4, 1, ("fig:narrow-with-friction",), ("fig:narrow-with-friction",), 2,
             (1e-3, 1e-6, 1e-9, 1e-12), (16, 30, 50), (1, 10))


def _guarded(progress, errors: list, what: str, fn, *args):
    """``fn(*args)``, or ``None`` with the error recorded (one failing part -- e.g. an integrator
    raising on one scene -- must not take the rest of the report down; it is listed at the top)."""
    try:
        return fn(*args)
    except Exception as exc:  # noqa: BLE001 -- reported in the report and on stderr
        msg = f"{what}: {type(exc).__name__}: {str(exc)[:300]}"
        errors.append(msg)
        progress(f"FAILED {msg}")
        return None


#: claims computed first in the claims worker: they need the reference alone (validated flights
#: included), so they keep the worker's core busy while the main process compiles fast's
#: closed-form loop; the claims after them load that loop from numba's cache instead of
#: compiling it a second time (a cold first run in a fresh clone, issue 36)
CLAIMS_FIRST = ("xpot-equilibria",)


def _compile(progress, where: str, closed_form: bool, position_forcing: bool) -> float:
    """``fast.warm_up`` of the engines asked for, with a progress line; its seconds."""
    import fast

    engines = {"closed_form": closed_form, "position_forcing": position_forcing}
    seconds = sum(fast.warm_up(**engines).values())
    progress(f"fast's kernels ({', '.join(k for k, on in engines.items() if on)}) ready in {seconds:.1f} s "
             f"({where}; compiled on a first run, loaded from numba's cache after)")
    return seconds


def _claims_timed(quick: bool, progress, claims=None) -> tuple[list, float, float]:
    """The claims section (``claims``: the registry by default), its wall time and, of that, the
    seconds that compiled fast's position-forcing flights (run in a worker process, beside the
    main process that compiles the closed-form loop: :func:`_measure`)."""
    t0 = time.perf_counter()
    compiled = _compile(progress, "claims worker", False, True)
    return sections.claims_section(quick, progress, claims, first=CLAIMS_FIRST), time.perf_counter() - t0, compiled


def _claims_process(quick: bool, progress, claims=None):
    """The claims section started in one spawned worker process, so that it shares the two
    cores with the agreement and hard-case sections (which time nothing); ``(pool, future)``,
    or ``(None, None)`` where no process can be started (the claims then run in line)."""
    try:
        pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn"))
        return pool, pool.submit(_claims_timed, quick, progress, claims)
    except (OSError, RuntimeError) as exc:
        progress(f"claims: no worker process ({type(exc).__name__}: {exc}); they run in line")
        return None, None


def _scipy_timed(hard_scenes, n_sample, progress, users=()) -> tuple[list, float]:
    """The solve_ivp itinerary table (``sections.scipy_itineraries``: nothing in it is timed) and
    its wall seconds; the claims worker runs it after the claims, with the user's scenes among
    ``hard_scenes`` registered there first (``users``: their ``Scene`` objects)."""
    t0 = time.perf_counter()
    for sc in users:
        scenes.register(sc)
    return sections.scipy_itineraries(hard_scenes, n_sample, progress), time.perf_counter() - t0


def _submitted(pool, fn, *args):
    """``pool.submit(fn, *args)``, or ``None`` where the pool cannot take it (the work then runs
    in line)."""
    try:
        return pool.submit(fn, *args) if pool is not None else None
    except RuntimeError:
        return None


def _measure(plan: Plan, out: pathlib.Path, claims: bool, quick: bool, progress,
             atlas_dir="atlas", league_dir="league") -> tuple[dict, dict, list]:
    """Run every section; return ``(markdown pieces, timings, errors)``.

    The schedule for two cores: the claims, then the solve_ivp itineraries (untimed), run in a
    worker process (which first compiles fast's position-forcing flights) beside the main
    process (which first compiles the closed-form loop, then runs the agreement, the hard cases
    and the untimed reference work of work-precision); both are collected before the timed part
    of work-precision, whose timings must have the machine to themselves.  (The itineraries
    took 5.7 s after the timed part in the main process, while the worker sat idle: a cold
    first run in a fresh clone, 90.6 s of wall time.)"""
    timings, errors, parts = {}, [], {}
    pool, claims_future = _claims_process(quick, progress) if claims else (None, None)
    users = [scenes.scene(n) for n in plan.hard_scenes if n not in scenes.SCENES]
    scipy_future = _submitted(pool, _scipy_timed, plan.hard_scenes, plan.n_sample, progress, users)
    timings["starting the claims worker"] = progress.lap()
    _guarded(progress, errors, "compiling fast", _compile, progress, "main process", True, False)
    timings["fast's closed-form loop: compiled, or loaded from the cache"] = progress.lap()
    agreement = {}
    for name in plan.scenes:
        agreement[name] = _guarded(progress, errors, f"agreement {name}", sections.scene_agreement,
                                   name, plan.n_sample, plan.n_ten)
        if agreement[name] is not None:
            progress(f"agreement: {name}: {agreement[name]['map_raw']} digits (median/worst)")
    parts["agreement"], timings["agreement"] = sections.agreement_table(agreement), progress.lap()
    hard = []
    for name in plan.hard_scenes:
        hard += _guarded(progress, errors, f"hard cases {name}", sections.hard_case_rows, name) or []
        progress(f"hard cases: {name}")
    parts["hard"], timings["hard cases"] = sections.hard_table(hard), progress.lap()
    prepared = _guarded(progress, errors, "work-precision", precision.truths, plan)
    timings["work-precision: the reference's truths and floors"] = progress.lap()
    parts["claims"] = ["(skipped: `--skip-claims`)"]
    if claims:
        if claims_future is None:
            got = _claims_timed(quick, progress)
        else:
            with pool:
                got = _guarded(progress, errors, "claims", claims_future.result)
                scipy = scipy_future and _guarded(progress, errors, "scipy itineraries", scipy_future.result)
        if got is not None:
            parts["claims"], timings["claims (in parallel, worker process)"], compiled = got
            timings["of which fast's position-forcing flights: compiled, or loaded"] = compiled
        if scipy_future is not None:
            parts["scipy"], timings["scipy itineraries (worker process, after the claims)"] = scipy or ([], 0.0)
        timings["waiting for the claims"] = progress.lap()
    wp = None if prepared is None else _guarded(progress, errors, "work-precision", precision.work_precision,
                                                plan, progress, prepared)
    if wp is not None:
        plots.work_precision_plot(wp, out / "work_precision.png", TRUTH_DPS)
    parts["wp"] = precision.wp_table(wp) if wp is not None else ["(failed: see Failures)", ""]
    timings["work-precision: timed runs"] = progress.lap()
    if "scipy" not in parts:
        parts["scipy"] = _guarded(progress, errors, "scipy itineraries", sections.scipy_itineraries,
                                  plan.hard_scenes, plan.n_sample, progress) or []
        timings["scipy itineraries"] = progress.lap()
    errors += [f"claim {line.split('|')[1].strip()}: FAILED" for line in parts["claims"] if "| FAILED |" in line]
    parts["atlas"] = sections.atlas_section(atlas_dir, out)
    parts["league"] = league_section(league_dir, out)
    return parts, timings, errors


_HEAD = ["# Cross-check report: reference (mpmath) vs fast (float64) vs scipy", "",
         "Digits are significant correct digits, `-log10(|a - ref| / max(1, |ref|))` (capped at 17), "
         "given as median / worst.  Itineraries are compared first; event times and states only on "
         "the common prefix of identical event kinds; never one norm across an impact.", ""]


def _markdown(parts: dict, errors: list, plan: Plan, quick: bool) -> list[str]:
    lines = list(_HEAD)
    if errors:
        lines += ["## Failures", "", "These parts could not be computed (the rest of the report stands):", ""]
        lines += [f"- {e}" for e in errors] + [""]
    lines += ["## Agreement of fast with reference (dps 50), one period", ""] + parts["agreement"]
    lines += ["", f"Tolerances (`cross_check/tolerances.py`): fast_one_period_max = "
              f"{tol('fast_one_period_max').rtol:g} (13 digits), fast_one_period_median = "
              f"{tol('fast_one_period_median').rtol:g} (14.5 digits).  `band` = states whose fast itinerary "
              "changes under a few-ulp move (near-grazing band): listed, not hidden.", "",
              "## Hard cases", "", "Constructed exactly by closed-form backward flights "
              "(`cross_check/agreement/hardcases.py`); fast and scipy see the float64 rounding of the decimal "
              "state, so they are compared with the reference on that same float64 state.", ""]
    lines += parts["hard"]
    lines += ["", "## Work-precision", "", "![work-precision](work_precision.png)", "",
              f"Significant correct digits of Phi^n against the reference at dps {TRUTH_DPS} (no clamp: the "
              "reference at dps d reaches about d digits) versus time per trajectory-period (best of 2 runs "
              f"for a call under {precision.REPEAT_BELOW:g} s, one run above; "
              "fast: the states repeated into a batch of ~4096, time divided).  "
              "scipy: `cross_check/agreement/baseline.py`.", ""]
    lines += parts["wp"]
    lines += ["## Where solve_ivp misses events", "",
              f"One period from the sample and hard states (float64) of the hard-case scenes; itineraries in "
              f"canonical form (`compare.canonical`) against the reference at dps {REF_DPS}.  A careful user's "
              "event handling (`cross_check/agreement/baseline.py`): restart at each event, stick and wall "
              "contact by threshold events, chatter cut-off below 100 atol.", ""] + parts["scipy"] + [""]
    lines += ["## The paper's claims", ""] + parts["claims"]
    lines += ["", "## Proofs of the golden data", ""] + sections.golden_proofs_section()
    lines += ["", "## Where the claims hold: the atlas", ""] + parts["atlas"]
    lines += ["", "## The league: the field's integrators", ""] + parts["league"]
    return lines + ["", "## Machine, versions, seeds", ""] + sections.machine_section(plan.n_sample, quick)


def time_section(timings: dict, total: float) -> list[str]:
    """Where the report's time went: one row per section, wall seconds, in the order they ran
    (the claims' rows are the worker process's own, spent beside the main process's rows)."""
    rows = [f"| {name} | {seconds:.1f} |" for name, seconds in timings.items()]
    return ["", "## Where the time went", "", "| section | seconds |", "|---|---|"] + rows + [
        f"| **total** (wall) | **{total:.1f}** |"]


def build(out_dir, quick: bool = False, claims: bool = True, atlas_dir="atlas",
          scene_names=None, league_dir="league") -> tuple[pathlib.Path, list]:
    """Compute everything and write ``report.md`` + PNGs into ``out_dir``; return the path
    and the list of parts that failed (they are listed in the report too).

    ``claims=False`` leaves the claims section out (they have their own tests and command);
    ``scene_names`` (registered scenes: ``cross_check.scenefile``) replaces the plan's scenes of
    the agreement and hard-case sections."""
    plan = QUICK if quick else FULL
    if scene_names:
        plan = dataclasses.replace(plan, scenes=tuple(scene_names), hard_scenes=tuple(scene_names))
    progress = Progress()
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    for pkg in ("reference", "fast"):
        if not compare.available(pkg):
            raise RuntimeError(f"the {pkg} integrator is not available ({pkg}.stroboscopic_map)")
    parts, timings, errors = _measure(plan, out, claims, quick, progress, atlas_dir, league_dir)
    lines = _markdown(parts, errors, plan, quick)
    lines += time_section(timings, progress.elapsed)
    progress(f"the report took {progress.elapsed:.1f} s: " + ", ".join(f"{k} {v:.1f} s" for k, v in timings.items()))
    path = out / "report.md"
    path.write_text("\n".join(lines) + "\n")
    progress(f"wrote {path}" + (f" ({len(errors)} part(s) FAILED)" if errors else ""))
    return path, errors


def main(argv=None) -> int:
    """CLI entry: ``report [--out DIR] [--quick] [--skip-claims]``; exit 1 if a part failed."""
    import argparse

    parser = argparse.ArgumentParser(
        prog="python -m cross_check report",
        description="The V&V report: fast vs reference vs scipy on every scene, the hard cases, "
                    "work-precision (digits against seconds), solve_ivp's missed events and the "
                    "paper's claims.  Writes report.md and work_precision.png.  Exit status: 0 every part ran, "
                    "1 a part failed (the report says which), 2 bad arguments or an unwritable --out.")
    parser.add_argument("--out", default="report", type=outputs.check_folder, help="output directory (default: report/)")
    parser.add_argument("--quick", action="store_true", help="small run (3 scenes, fewer states), about 10 s")
    parser.add_argument("--atlas", default="atlas", help="where an atlas was written (python -m cross_check "
                        "atlas); its maps are shown when present (default: atlas/)")
    parser.add_argument("--league", default="league", help="where a league was written (python -m cross_check "
                        "league); its table is included when present (default: league/)")
    parser.add_argument("--skip-claims", action="store_true",
                        help="leave out the claims table (python -m cross_check claims runs it alone)")
    scenefile.add_arguments(parser, "agreement and hard cases on")
    args = parser.parse_args(argv)
    try:
        user = scenefile.from_args(args)
    except scenefile.SceneFileError as exc:
        print(f"report: {exc}", file=sys.stderr)
        return 2
    try:
        path, errors = build(args.out, args.quick, claims=not args.skip_claims, atlas_dir=args.atlas,
                             scene_names=user, league_dir=args.league)
    except RuntimeError as exc:
        print(f"report: {exc}", file=sys.stderr)
        return 1
    print(path)
    return 1 if errors else 0
