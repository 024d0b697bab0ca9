"""The league as data: one row per engine and setting, read off its ``Scorecard``, and the table.

Nothing is graded here: the kinds passed and flagged are the scorecard's grades
(``Scorecard.kinds``), the digits its per-case digits.  A row summarises, over the starts
outside the near-grazing band (the ones the scorecard grades):

* ``median_digits``, ``worst_digits`` -- significant correct digits of ``Phi`` after one
  period against the 40-digit golden data; a failed start (exception, timeout, non-finite)
  counts as 0 digits;
* ``worst_graded_digits`` -- the scorecard's worst, credited with what the exact map itself
  loses to float64 near a graze (``sheet.CaseScore.graded``);
* ``events`` -- the golden events of the graded starts (``expected``, in ``compare.canonical``
  form), how many the engine ``found`` (expected less ``missed``) and ``invented``; ``None``
  for an engine without event logs (MuJoCo);
* ``seconds_per_start`` -- the scorer's timed calls (each scene's batch in one ``step`` call,
  after the warm-up), per start and period: the median over the scenes (one call per scene is
  one sample: on a shared machine a call of fast's 0.3 ms is now and then preempted for ten
  times as long, which a mean over 13 calls would carry), ``seconds_per_start_mean`` the total
  over the starts; ``warmup_seconds`` -- where the engine compiles on its first call (``jit``:
  diffrax's XLA program, heyoka's LLVM Taylor integrator, fast's numba kernels loaded from their
  cache), that first call less the second one, in a fresh worker process.

The goal line: fast reaches ``GOAL_DIGITS`` (median) and its time per start (``fast threads
1``) is below that of every other row with at least ``PEER_DIGITS``; the ratio of the two times
is printed, and beside it (reported, not judged) the ratio net of the scorer's round trip to
its worker process (``run.call_floor``), which every timed call includes.
"""
from __future__ import annotations

import importlib.metadata
import json
import math
import os
import platform

import numpy as np

from cross_check.score.golden import scene_cases

GOAL_DIGITS, PEER_DIGITS = 15.0, 10.0
GOAL_ROW = ("fast", "threads 1")
FORMAT_VERSION = 1
#: the distributions whose versions a league records
PEER_DISTRIBUTIONS = ("numpy", "scipy", "mpmath", "numba", "heyoka", "scikit-sundae", "diffrax", "jax",
                      "optimistix", "mujoco")


def _expected_events(scenes) -> dict:
    return {c.id: len(c.events) for name in scenes for c in scene_cases(name)}


def row(entry, card, warmup_seconds, wall_seconds) -> dict:
    """The league row of ``entry`` from its scorecard (module docstring)."""
    graded = [c for c in card.cases if not c.band]
    digits = [0.0 if c.digits is None else c.digits for c in graded]
    credited = [c.graded for c in graded if c.graded is not None]
    kinds = card.kinds()
    events = None
    if card.events_scored:
        want = _expected_events(card.scenes)
        scored = [c for c in graded if c.failure is None]
        expected = sum(want[c.id] for c in scored)
        missed = sum(sum(c.missed.values()) for c in scored)
        events = {"expected": expected, "found": expected - missed, "missed": missed,
                  "invented": sum(sum(c.invented.values()) for c in scored)}
    per_scene = [v["seconds_per_period"] for v in card.scenes.values()]
    timed = sum(v["seconds_per_period"] * sum(1 for c in card.cases if c.id.startswith(k + "/"))
                for k, v in card.scenes.items())
    n_starts = len(card.cases)
    return {"group": entry.group, "peer": entry.peer, "setting": entry.setting, "name": card.adapter,
            "kinds": {k: s["grade"] for k, s in kinds.items() if s["grade"] != "-"},
            "kinds_passed": [k for k, s in kinds.items() if s["grade"] in "ABC"],
            "kinds_flagged": card.flagged(),
            "starts": n_starts, "graded_starts": len(graded),
            "median_digits": float(np.median(digits)) if digits else None,
            "worst_digits": min(digits) if digits else None,
            "worst_graded_digits": min(credited) if credited else None,
            "failures": sum(1 for c in graded if c.failure is not None),
            "timeouts": sum(1 for c in card.cases if c.failure_kind == "timeout"),
            "events": events,
            "seconds_per_start": float(np.median(per_scene)) if per_scene else None,
            "seconds_per_start_mean": timed / n_starts if n_starts else None,
            "warmup_seconds": warmup_seconds, "wall_seconds": wall_seconds,
            "skipped_scenes": {k: sorted(v) for k, v in card.skipped.items()},
            "complete": card.complete}


def goal(rows, floor: float | None = None) -> dict:
    """Whether fast met the league's goal (module docstring), and the time ratio; with the
    scorer's round trip per start ``floor``, also the ratio net of it (reported, not judged)."""
    fast = next((r for r in rows if (r["group"], r["setting"]) == GOAL_ROW), None)
    peers = [r for r in rows if r["group"] != "fast" and (r["median_digits"] or 0) >= PEER_DIGITS
             and r["seconds_per_start"]]
    if fast is None or not fast["seconds_per_start"]:
        return {"fast": None, "met": None, "text": "fast was not run: no goal line"}
    best = min(peers, key=lambda r: r["seconds_per_start"]) if peers else None
    ratio = fast["seconds_per_start"] / best["seconds_per_start"] if best else None
    met = fast["median_digits"] >= GOAL_DIGITS and (ratio is None or ratio < 1)
    net = None
    if best and floor is not None and best["seconds_per_start"] > floor:
        net = max(fast["seconds_per_start"] - floor, 0.0) / (best["seconds_per_start"] - floor)
    text = (f"fast ({GOAL_ROW[1]}): median {fast['median_digits']:.1f} digits (goal >= {GOAL_DIGITS:g}), "
            f"{fast['seconds_per_start']:.2e} s per start-period; "
            + (f"fastest peer setting with >= {PEER_DIGITS:g} digits: {best['name']} at "
               f"{best['seconds_per_start']:.2e} s: time ratio fast / it = {ratio:.2g}"
               if best else f"no peer setting reached {PEER_DIGITS:g} digits")
            + (f" ({net:.2g} net of the scorer's round trip, {floor:.1e} s per start)" if net is not None else "")
            + f" -- goal {'met' if met else 'NOT met'}")
    return {"fast": fast["name"], "fast_digits": fast["median_digits"], "fastest_10_digit_peer": best and best["name"],
            "ratio": ratio, "ratio_net_of_round_trip": net, "met": met, "text": text}


def machine(load_at_start=None) -> dict:
    """Where the times were taken: cores, load averages (1 min) at the start and now, and the
    versions of the installed peers (read from their metadata, nothing imported)."""
    versions = {}
    for dist in PEER_DISTRIBUTIONS:
        try:
            versions[dist] = importlib.metadata.version(dist)
        except importlib.metadata.PackageNotFoundError:
            pass
    return {"cores": os.cpu_count(), "load_at_start": load_at_start, "load_now": os.getloadavg()[0],
            "python": platform.python_version(), "versions": versions}


def document(rows, skipped, scenes, quick, seconds, score_options, load_at_start=None, floor=None) -> dict:
    """The whole league as JSON-ready data (``floor``: the scorer's round trip per start)."""
    return {"format_version": FORMAT_VERSION, "quick": quick, "scenes": list(scenes),
            "score_options": {k: v for k, v in score_options.items()}, "rows": rows,
            "skipped_peers": skipped, "goal": goal(rows, floor), "seconds": seconds,
            "round_trip_seconds_per_start": floor, "machine": machine(load_at_start)}


def to_json(doc) -> str:
    return json.dumps(doc, indent=1, default=float) + "\n"


def fmt(a, spec=".1f"):
    """``a`` formatted by ``spec``, ``-`` for None or a non-finite number."""
    return "-" if a is None or (isinstance(a, float) and not math.isfinite(a)) else format(a, spec)


def table_lines(doc) -> list[str]:
    """The league table (markdown), one line per row: what the report includes."""
    lines = ["| peer | setting | kinds passed | flagged | median digits | worst digits | worst graded | "
             "events found / expected (missed, invented) | failures | s per start-period | warm-up s |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in doc["rows"]:
        ev = r["events"]
        events = "n/a" if ev is None else f"{ev['found']} / {ev['expected']} ({ev['missed']}, {ev['invented']})"
        lines.append(f"| {r['peer']} | {r['setting']} | {len(r['kinds_passed'])} of {len(r['kinds'])} | "
                     f"{', '.join(r['kinds_flagged']) or '-'} | {fmt(r['median_digits'])} | {fmt(r['worst_digits'])} | "
                     f"{fmt(r['worst_graded_digits'])} | {events} | {r['failures']} ({r['timeouts']} timeouts) | "
                     f"{fmt(r['seconds_per_start'], '.2e')} | {fmt(r['warmup_seconds'])} |")
    return lines


def to_markdown(doc) -> str:
    rows = doc["rows"]
    lines = ["# The league: the field's integrators on the golden data", "",
             f"{'Quick run' if doc['quick'] else 'Full run'}: {len(rows)} engine settings on {len(doc['scenes'])} "
             f"scenes ({', '.join(f'`{s}`' for s in doc['scenes'])}), one period, graded by "
             "`python -m cross_check score`'s scorecard in its worker process (per-start budgets).  Digits: "
             "significant correct digits of Phi against the 40-digit golden data, over the starts outside the "
             "near-grazing band (a failed start counts 0).  Kinds: the scorecard's grades (A/B/C passed, F flagged).  "
             "Time: the scorer's timed batch calls, per start and period, median over the scenes; warm-up: "
             "the first call's compilation, apart.", ""]
    lines += table_lines(doc) + ["", f"**Goal**: {doc['goal']['text']}.", "",
                                 "Each row's scorecard (the cases behind it): `scorecards/`.", ""]
    if doc["skipped_peers"]:
        lines += ["Skipped (not installed): " + "; ".join(f"{g}: {why}" for g, why in doc["skipped_peers"].items()), ""]
    scene_skips = {f"{r['peer']} {r['setting']}": r["skipped_scenes"] for r in rows if r["skipped_scenes"]}
    if scene_skips:
        lines += ["Scenes an engine does not model (skipped by the scorer, listed): "
                  + "; ".join(f"{k}: {', '.join(f'`{s}`' for s in v)}" for k, v in scene_skips.items()), ""]
    m = doc["machine"]
    load = f"{m['load_at_start']:.1f} at the start, " if m["load_at_start"] is not None else ""
    lines += ["![work-precision](work_precision.png)", "",
              f"League run time: {doc['seconds']:.0f} s on {m['cores']} cores (load average {load}"
              f"{m['load_now']:.1f} at the end).  Every timed call includes the scorer's round trip to its worker "
              "process: "
              + (f"{doc['round_trip_seconds_per_start']:.1e} s per start, measured at the start with an adapter that "
                 "does nothing" if doc.get("round_trip_seconds_per_start") else "not measured")
              + " (on a loaded machine it grows to milliseconds a call, the floor under the fastest engines' times).  "
              "Versions: "
              + ", ".join(f"{k} {v}" for k, v in m["versions"].items()) + "."]
    return "\n".join(lines) + "\n"


__all__ = ["GOAL_DIGITS", "PEER_DIGITS", "document", "fmt", "goal", "row", "table_lines", "to_json", "to_markdown"]
