"""The scorecard as data: one row per golden case, a grade per kind, JSON and markdown.

Per kind, a one-line grade from the cases outside the band, on *graded digits*: the digits,
credited with what the exact map itself loses to float64 (``15.95 - floor digits`` where the
one-ulp floor is above one ulp: near a graze ``Phi`` has a square-root singularity and no float64
start fixes it better).  ``A``: worst graded error within ``score_grade_a``; ``B``:
``score_grade_b``; ``C``: ``score_flag``; ``F``: below it, or an event missed or invented, or a
failure (*flagged*).  Band cases are listed apart, never graded.

A failure has a kind: ``exception``, ``non-finite``, ``timeout`` (no result within the budget;
the card says what usually causes it for the case's kind, ``golden.CAUSES``) or ``crash`` (the
worker process died).  A start the per-kind cut-off did not run (``cutoff``: its kind timed out K
times in the scene) has the failure kind ``not run``: it counts as failed in its kind's grade but
is counted apart (``not_run``), listed apart, and the card adds up the time it saved (those
starts times the budget each would have had).  A card written while the run goes on is marked incomplete (``complete``
false in the JSON, a line at the top of the markdown) until the last scene is scored.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass, field

import numpy as np

from cross_check.agreement import compare
from cross_check.score.cutoff import NOT_RUN
from cross_check.score.golden import CAUSES, KINDS
from cross_check.tolerances import tol

FULL_DIGITS = -math.log10(2.0 ** -53)    # 15.95: one ulp, relative


@dataclass
class CaseScore:
    """One golden case as the adapter did it."""

    id: str
    kind: str
    band: bool
    digits: float | None = None          # None: failed
    floor_digits: float | None = None
    missed: dict = field(default_factory=dict)
    invented: dict = field(default_factory=dict)
    failure: str | None = None
    failure_kind: str | None = None      # exception | non-finite | timeout | crash | not run
    budget: float | None = None          # seconds the call on it had (or would have had: not run)

    @property
    def graded(self) -> float | None:
        """``digits`` credited with the exact map's own loss to float64 (module docstring)."""
        if self.digits is None:
            return None
        credit = 0.0 if self.floor_digits is None else max(0.0, FULL_DIGITS - self.floor_digits)
        return min(compare.DIGITS_CAP, self.digits + credit)


def _grade(worst: float | None, missed: int, invented: int, failures: int) -> str:
    if failures or missed or invented or worst is None or worst < -math.log10(tol("score_flag").rtol):
        return "F"
    if worst >= -math.log10(tol("score_grade_a").rtol):
        return "A"
    return "B" if worst >= -math.log10(tol("score_grade_b").rtol) else "C"


def _kind_line(rows) -> dict:
    graded = [c for c in rows if not c.band]
    digits = [c.digits for c in graded if c.digits is not None]
    credited = [c.graded for c in graded if c.digits is not None]
    missed = sum(sum(c.missed.values()) for c in graded)
    invented = sum(sum(c.invented.values()) for c in graded)
    not_run = sum(1 for c in graded if c.failure_kind == NOT_RUN)
    failures = sum(1 for c in graded if c.failure is not None) - not_run
    worst = min(credited) if credited else None
    grade = _grade(worst, missed, invented, failures + not_run) if graded else "-"
    floor_lost = [c.floor_digits - c.digits for c in graded if c.digits is not None and c.floor_digits is not None]
    return {"cases": len(rows), "band": len(rows) - len(graded), "worst_graded_digits": worst,
            "worst_digits": min(digits) if digits else None,
            "median_digits": float(np.median(digits)) if digits else None,
            "worst_digits_lost_to_floor": max(floor_lost) if floor_lost else None,
            "missed": missed, "invented": invented, "failures": failures,
            "timeouts": sum(1 for c in graded if c.failure_kind == "timeout"), "not_run": not_run,
            "grade": grade, "flagged": grade == "F"}


@dataclass
class Scorecard:
    """An adapter's scores: per case, per scene, and a grade per kind (module docstring).
    ``planned``: the scenes asked for; ``complete``: all of them done; ``stopped``: why not."""

    adapter: str
    cases: list
    scenes: dict            # scene -> {"seconds_per_period", "ten", "mode", ...}
    skipped: dict           # scene -> the effects the adapter lacks
    events_scored: bool
    planned: list = field(default_factory=list)
    complete: bool = True
    stopped: str | None = None
    budget: dict = field(default_factory=dict)    # case_timeout, first_call_timeout, isolation, restarts

    def kinds(self) -> dict:
        """Per kind (in ``KINDS`` order, kinds with cases only): counts, worst digits outside the
        band, missed/invented events, failures and timeouts and starts not run (outside the band;
        ``failures`` does not count those not run), the grade and whether it is flagged."""
        return {kind: _kind_line(rows) for kind in KINDS
                if (rows := [c for c in self.cases if c.kind == kind])}

    def flagged(self) -> list[str]:
        return [k for k, s in self.kinds().items() if s["flagged"]]

    def not_done(self) -> list[str]:
        return [n for n in self.planned if n not in self.scenes and n not in self.skipped]

    def timeouts(self) -> list:
        return [c for c in self.cases if c.failure_kind == "timeout"]

    def not_run(self) -> list:
        """The starts the per-kind cut-off did not run (band starts included)."""
        return [c for c in self.cases if c.failure_kind == NOT_RUN]

    def seconds_saved(self) -> float:
        """The time the cut-off saved: the starts not run times the budget each would have had."""
        return float(sum(c.budget or 0.0 for c in self.not_run()))

    def to_dict(self) -> dict:
        return {"adapter": self.adapter, "complete": self.complete, "stopped": self.stopped,
                "scenes_not_scored": self.not_done(), "budget": self.budget,
                "not_run": len(self.not_run()), "seconds_saved": self.seconds_saved(),
                "events_scored": self.events_scored, "kinds": self.kinds(),
                "skipped_scenes": {k: sorted(v) for k, v in self.skipped.items()},
                "scenes": self.scenes,
                "cases": [dict(vars(c), graded=c.graded,
                               cause=CAUSES.get(c.kind) if c.failure_kind == "timeout" else None)
                          for c in self.cases]}

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=1, default=float) + "\n"

    def _head(self) -> list[str]:
        lines = [f"# Scorecard: {self.adapter}", ""]
        if not self.complete:
            lines += [f"**INCOMPLETE**: {self.stopped or 'the run is still going'} -- "
                      f"{len(self.scenes)} of {len(self.planned) - len(self.skipped)} scene(s) scored; not scored: "
                      f"{', '.join(f'`{n}`' for n in self.not_done()) or '-'}.", ""]
        if self.budget:
            lines += [self._budget_line(), ""]
        if self.not_run():
            lines += [f"Per-kind cut-off: {len(self.not_run())} start(s) not run (their kind timed out "
                      f"{self.budget.get('kind_timeouts', '?')} times in the scene, or its probe did): "
                      f"{self.seconds_saved():.0f} s saved (starts not run x their budget).", ""]
        return lines

    def _budget_line(self) -> str:
        b = self.budget
        line = (f"Time budget: {b['case_timeout']:g} s per call on a start ({b['first_call_timeout']:g} s for the "
                f"warm-up call of step and of events on each set of effects); {b['isolation']}"
                + (f"; {b['restarts']} worker restart(s)" if b.get("restarts") else ""))
        if b.get("short_budget") is not None:
            line += (f".  After the first timeout: {b['short_budget']:.3g} s per call (max(floor "
                     f"{b['budget_floor']:g} s, {b['budget_multiple']:g} x the median start "
                     + (f"{b['median_seconds']:.2g} s" if b.get("median_seconds") is not None else "(too few yet)")
                     + ")) for starts in the band, of kinds already failed, and over ten periods; the cap for the rest")
        if b.get("kind_timeouts") == 0:
            line += ".  Per-kind cut-off: off (every start runs)"
        return line + "."

    def to_markdown(self) -> str:
        lines = self._head() + [
            "One line per kind of case, from the cases outside the near-grazing band (band cases are listed "
            "apart, not graded).  Digits: significant correct digits of Phi after one period against the 40-digit "
            "golden data; lost: digits below the one-ulp floor of the exact map.", "",
            "| kind | grade | cases (band) | worst graded digits | worst digits | median | worst lost to floor | "
            "missed | invented | failures (timeouts) | not run |", "|---|---|---|---|---|---|---|---|---|---|---|"]
        fmt = lambda a: "-" if a is None else f"{a:.1f}"     # noqa: E731
        na = lambda n: n if self.events_scored else "n/a"    # noqa: E731
        for kind, s in self.kinds().items():
            lines.append(f"| {kind} | **{s['grade']}** | {s['cases']} ({s['band']}) | {fmt(s['worst_graded_digits'])} | "
                         f"{fmt(s['worst_digits'])} | {fmt(s['median_digits'])} | "
                         f"{fmt(s['worst_digits_lost_to_floor'])} | {na(s['missed'])} | {na(s['invented'])} | "
                         f"{s['failures']} ({s['timeouts']}) | {s['not_run']} |")
        lines += ["", "| scene | s per trajectory-period | digits after 10 periods | budget s (short) |",
                  "|---|---|---|---|"]
        lines += [f"| `{k}` | {v['seconds_per_period']:.2e}{' (start by start)' if v.get('mode') == 'start by start' else ''} | "
                  f"{', '.join(fmt(d) if d is not None else 'failed' for d in v['ten']) or '-'} | {_budgets(v)} |"
                  for k, v in self.scenes.items()]
        if self.skipped:
            lines += ["", "Skipped (effects the adapter does not declare): "
                      + "; ".join(f"`{k}` ({', '.join(sorted(v))})" for k, v in self.skipped.items())]
        lines += self._timeout_lines()
        lines += self._not_run_lines()
        bad = [c for c in self.cases if (c.failure and c.failure_kind not in ("timeout", NOT_RUN)) or c.missed
               or c.invented]
        if bad:
            lines += ["", "Cases with failures or a different itinerary (b: in the band):", ""]
            lines += [f"- {c.id} [{c.kind}]{' (b)' if c.band else ''}: "
                      + (c.failure or f"missed {c.missed or '-'}, invented {c.invented or '-'}") for c in bad[:60]]
        return "\n".join(lines) + "\n"

    def _timeout_lines(self) -> list[str]:
        out = self.timeouts()
        if not out:
            return []
        lines = ["", "Timeouts (no result within the budget), by kind, with what usually causes them:", ""]
        for kind in KINDS:
            rows = [c for c in out if c.kind == kind]
            if rows:
                lines.append(f"- **{kind}** ({len(rows)}): " + ", ".join(f"{c.id}{' (b)' if c.band else ''}" for c in rows)
                             + f" -- usually {CAUSES[kind]}")
        return lines

    def _not_run_lines(self) -> list[str]:
        out = self.not_run()
        if not out:
            return []
        lines = ["", "Not run (the per-kind cut-off; counted as failed, apart from the failures above), by scene "
                 "and kind:", ""]
        groups: dict = {}
        for c in out:
            groups.setdefault((c.id.rsplit("/", 1)[0], c.kind, c.failure), []).append(c)
        for (scene, kind, why), rows in groups.items():
            lines.append(f"- `{scene}` **{kind}** ({len(rows)}): " + ", ".join(
                c.id.rsplit("/", 1)[1] + (" (b)" if c.band else "") for c in rows) + f" -- {why}")
        return lines


def _budgets(scene: dict) -> str:
    b = scene.get("budget") or {}
    if "cap" not in b:
        return "-"
    return f"{b['cap']:g}" + (f" ({b['short']:.3g})" if b.get("short") is not None else "")


__all__ = ["CaseScore", "FULL_DIGITS", "Scorecard"]
