"""The scorecard: any adapter against the golden data, per scene and per kind of case.

For every scored scene (those whose effects the adapter declares; the rest are listed as
skipped), on the float64 input of every golden case (``score.golden``):

* **digits** of ``Phi`` after one period against the 40-digit golden answer,
  ``-log10(|a - g| / max(1, |g|))`` (capped at 17), and the **digits lost to the one-ulp floor**
  (the exact map's own spread under one-ulp moves of the start, from the golden Jacobian);
* after ten periods (``periods`` containing 10): digits against the reference at 40 digits on
  the scene's sample states outside the band (chaotic orbits amplify every error alike: read
  them beside the floor, not as a grade);
* **itinerary**, where the adapter gives events: both logs in ``compare.canonical`` form,
  *missed* (golden kinds the adapter lacks) and *invented* (the reverse), counted per kind;
* **failures**: exceptions and non-finite results, per start;
* **time** per trajectory-period: the whole scene's batch in one ``step`` call.

Per kind, a one-line grade from the cases outside the band, on *graded digits*: the digits,
credited with what the exact map itself loses to float64 (``15.95 - floor digits`` where the
one-ulp floor is above one ulp: near a graze ``Phi`` has a square-root singularity and no float64
start fixes it better).  ``A``: worst graded error within ``score_grade_a``; ``B``:
``score_grade_b``; ``C``: ``score_flag``; ``F``: below it, or an event missed or invented, or a
failure (*flagged*).  Band cases are listed apart, never graded.
"""
from __future__ import annotations

import argparse
import collections
import importlib
import json
import math
import pathlib
import sys
import time
from dataclasses import dataclass, field

import numpy as np

from cross_check import golden, scenefile
from cross_check import scenes as scene_table
from cross_check.agreement import compare
from cross_check.score import adapters
from cross_check.score.golden import KINDS, golden_scene, scene_cases
from cross_check.tolerances import tol

TEN_DPS = 40          # the reference's digits for the ten-period truth
TEN_STATES = 2        # sample states per scene scored over ten periods
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

    @property
    def graded(self) -> float | None:
        """``digits`` credited with the exact map's own loss to float64 (module docstring)."""
        if self.digits is None:
            return None
        credit = 0.0 if self.floor_digits is None else max(0.0, FULL_DIGITS - self.floor_digits)
        return min(compare.DIGITS_CAP, self.digits + credit)


def _digits(pair, case) -> float:
    gx, gv = case.phi_mpf()
    return min(compare.digits(pair[0], gx), compare.digits(pair[1], gv))


def _itinerary(case, got, scene):
    """``(missed, invented)`` kind counts of the adapter's log against the golden one (canonical)."""
    have = collections.Counter(e.kind for e in adapters.canonical_log(got, scene))
    want = collections.Counter(e[0] for e in case.events)
    return dict(want - have), dict(have - want)


def _safe(fn, *args):
    try:
        return fn(*args), None
    except Exception as exc:  # noqa: BLE001 -- an adapter's exception is its failure, recorded
        return None, f"{type(exc).__name__}: {str(exc)[:200]}"


def _step_each(adapter, params, X, V, periods):
    """The batch in one call (timed, after an untimed warm-up call on one start: a JIT or cache
    load is not the adapter's speed); where it raises, start by start (failures recorded)."""
    _safe(adapter.step, params, X[:1], V[:1], periods)
    t0 = time.perf_counter()
    out, err = _safe(lambda: adapters.finite_pair(adapter.step(params, X, V, periods), len(X)))
    seconds = time.perf_counter() - t0
    if err is None:
        return [(out[0][i], out[1][i]) for i in range(len(X))], [None] * len(X), seconds
    pairs, errors = [], []
    for i in range(len(X)):
        one, e = _safe(lambda: adapters.finite_pair(adapter.step(params, X[i:i + 1], V[i:i + 1], periods), 1))
        pairs.append(None if one is None else (one[0][0], one[1][0]))
        errors.append(e)
    return pairs, errors, seconds


def score_scene(adapter, name: str, periods=(1, 10), golden_dir=None) -> dict:
    """Every golden case of one scene: ``{"cases": [CaseScore], "seconds_per_period", "ten"}``."""
    cases = scene_cases(name, golden_dir)
    sc = golden_scene(name, golden_dir)
    params = dict(cases[0].params)
    X, V = np.array([c.x for c in cases]), np.array([c.v for c in cases])
    pairs, errors, seconds = _step_each(adapter, params, X, V, 1)
    logs = _safe(adapter.events, params, X, V)[0] if hasattr(adapter, "events") else None
    out = []
    for i, c in enumerate(cases):
        s = CaseScore(c.id, c.kind, c.band, failure=errors[i])
        if pairs[i] is not None and not (math.isfinite(pairs[i][0]) and math.isfinite(pairs[i][1])):
            s.failure = f"non-finite result {pairs[i]}"
        elif pairs[i] is not None:
            s.digits = _digits(pairs[i], c)
            floor = c.ulp_floor()
            s.floor_digits = None if floor is None else -math.log10(floor)
        if logs is not None and s.failure is None:
            s.missed, s.invented = _itinerary(c, logs[i], sc)
        out.append(s)
    ten = _ten_periods(adapter, params, sc, cases) if 10 in periods else []
    return {"cases": out, "seconds_per_period": seconds / len(cases), "ten": ten}


def _ten_periods(adapter, params, sc, cases):
    """Digits after ten periods against the reference at ``TEN_DPS`` on sample states outside the band."""
    picked = [c for c in cases if c.name.startswith("sample") and not c.band][:TEN_STATES]
    if not picked:
        return []
    pairs, _errors, _ = _step_each(adapter, params, np.array([c.x for c in picked]),
                                   np.array([c.v for c in picked]), 10)
    out = []
    for c, pair in zip(picked, pairs):
        truth = compare.ref_map(sc, compare.Case(c.name, repr(c.x), repr(c.v), "float64", "golden input"), 10, TEN_DPS)
        out.append(None if pair is None else min(compare.digits(pair[0], truth[0]),
                                                 compare.digits(pair[1], truth[1])))
    return out


def _grade(worst: float | None, missed: int, invented: int, failures: int) -> str:
    if failures or missed or invented or worst is None or worst < -math.log10(tol("score_flag").rtol):
        return "F"
    if worst >= -math.log10(tol("score_grade_a").rtol):
        return "A"
    return "B" if worst >= -math.log10(tol("score_grade_b").rtol) else "C"


@dataclass
class Scorecard:
    """An adapter's scores: per case, per scene, and a grade per kind (module docstring)."""

    adapter: str
    cases: list
    scenes: dict            # scene -> {"seconds_per_period", "ten"}
    skipped: dict           # scene -> the effects the adapter lacks
    events_scored: bool

    def kinds(self) -> dict:
        """Per kind (in ``KINDS`` order, kinds with cases only): counts, worst digits outside the
        band, missed/invented events, failures, the grade and whether it is flagged."""
        out = {}
        for kind in KINDS:
            rows = [c for c in self.cases if c.kind == kind]
            if not rows:
                continue
            graded = [c for c in rows if not c.band]
            digits = [c.digits for c in graded if c.digits is not None]
            credited = [c.graded for c in graded if c.digits is not None]
            missed = sum(sum(c.missed.values()) for c in graded)
            invented = sum(sum(c.invented.values()) for c in graded)
            failures = sum(1 for c in graded if c.failure is not None)
            worst = min(credited) if credited else None
            grade = _grade(worst, missed, invented, failures) if graded else "-"
            floor_lost = [c.floor_digits - c.digits for c in graded
                          if c.digits is not None and c.floor_digits is not None]
            out[kind] = {"cases": len(rows), "band": len(rows) - len(graded), "worst_graded_digits": worst,
                         "worst_digits": min(digits) if digits else None,
                         "median_digits": float(np.median(digits)) if digits else None,
                         "worst_digits_lost_to_floor": max(floor_lost) if floor_lost else None,
                         "missed": missed, "invented": invented, "failures": failures,
                         "grade": grade, "flagged": grade == "F"}
        return out

    def flagged(self) -> list[str]:
        return [k for k, s in self.kinds().items() if s["flagged"]]

    def to_dict(self) -> dict:
        return {"adapter": self.adapter, "events_scored": self.events_scored, "kinds": self.kinds(),
                "skipped_scenes": {k: sorted(v) for k, v in self.skipped.items()},
                "scenes": self.scenes, "cases": [dict(vars(c), graded=c.graded) for c in self.cases]}

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=1, default=float) + "\n"

    def to_markdown(self) -> str:
        lines = [f"# Scorecard: {self.adapter}", "", "One line per kind of case, from the cases outside the "
                 "near-grazing band (band cases are listed apart, not graded).  Digits: significant correct "
                 "digits of Phi after one period against the 40-digit golden data; lost: digits below the "
                 "one-ulp floor of the exact map.", "",
                 "| kind | grade | cases (band) | worst graded digits | worst digits | median | worst lost to floor | "
                 "missed | invented | failures |", "|---|---|---|---|---|---|---|---|---|---|"]
        fmt = lambda a: "-" if a is None else f"{a:.1f}"     # noqa: E731
        for kind, s in self.kinds().items():
            lines.append(f"| {kind} | **{s['grade']}** | {s['cases']} ({s['band']}) | {fmt(s['worst_graded_digits'])} | "
                         f"{fmt(s['worst_digits'])} | "
                         f"{fmt(s['median_digits'])} | {fmt(s['worst_digits_lost_to_floor'])} | "
                         f"{s['missed'] if self.events_scored else 'n/a'} | "
                         f"{s['invented'] if self.events_scored else 'n/a'} | {s['failures']} |")
        lines += ["", "| scene | s per trajectory-period | digits after 10 periods |", "|---|---|---|"]
        lines += [f"| `{k}` | {v['seconds_per_period']:.2e} | "
                  f"{', '.join(fmt(d) for d in v['ten']) or '-'} |" for k, v in self.scenes.items()]
        if self.skipped:
            lines += ["", "Skipped (effects the adapter does not declare): "
                      + "; ".join(f"`{k}` ({', '.join(sorted(v))})" for k, v in self.skipped.items())]
        bad = [c for c in self.cases if c.failure or c.missed or c.invented]
        if bad:
            lines += ["", "Cases with failures or a different itinerary (b: in the band):", ""]
            lines += [f"- {c.id} [{c.kind}]{' (b)' if c.band else ''}: "
                      + (c.failure or f"missed {c.missed or '-'}, invented {c.invented or '-'}") for c in bad[:60]]
        return "\n".join(lines) + "\n"


def _check_adapter(adapter):
    for attr in ("name", "effects", "step"):
        if not hasattr(adapter, attr):
            raise TypeError(f"adapter {adapter!r} has no {attr!r} (protocol: cross_check.score)")
    unknown = set(adapter.effects) - set(adapters.EFFECTS)
    if unknown:
        raise ValueError(f"adapter.effects has unknown effects {sorted(unknown)}; known: {adapters.EFFECTS}")


def score(adapter, *, scenes=None, periods=(1, 10), progress=None, golden_dir=None) -> Scorecard:
    """Score ``adapter`` (protocol: ``cross_check.score``) on ``scenes`` (default: every scene with
    golden data in ``golden_dir``, by default the shipped data); ``periods`` ``(1,)`` or ``(1, 10)``."""
    _check_adapter(adapter)
    if not set(periods) <= {1, 10} or 1 not in periods:
        raise ValueError(f"periods must be (1,) or (1, 10), got {periods!r}")
    have = golden.names_in(golden_dir)
    names = have if scenes is None else list(scenes)
    unknown = [n for n in names if n not in have]
    if unknown:
        raise ValueError(f"unknown scene(s) {unknown}: no golden data for them in {golden.files(golden_dir)}; "
                         f"it has: {', '.join(have)}")
    cases, per_scene, skipped = [], {}, {}
    for name in names:
        lacking = golden_scene(name, golden_dir).effects - set(adapter.effects)
        if lacking:
            skipped[name] = lacking
            continue
        res = score_scene(adapter, name, periods, golden_dir)
        cases += res["cases"]
        per_scene[name] = {"seconds_per_period": res["seconds_per_period"], "ten": res["ten"]}
        if progress:
            progress(f"score {adapter.name}: {name}")
    return Scorecard(adapter.name, cases, per_scene, skipped, hasattr(adapter, "events"))



def load_adapter(spec: str):
    """An adapter from ``MODULE:NAME`` (an object, or a class/function called without arguments)
    or a shipped short name (``fast``, ``reference``, ``scipy``, ``heyoka``)."""
    if spec in adapters.SHIPPED:
        out = adapters.SHIPPED[spec]()
        if out is None:
            raise ValueError(f"adapter {spec!r} is not available here (pip install {spec})")
        return out
    module, sep, name = spec.partition(":")
    if not sep or not module or not name:
        raise ValueError(f"adapter must be MODULE:NAME or one of {', '.join(adapters.SHIPPED)}, got {spec!r}")
    obj = getattr(importlib.import_module(module), name)
    return obj() if callable(obj) and not hasattr(obj, "step") else obj


def main(argv=None) -> int:
    """``python -m cross_check score ADAPTER [--scenes ...] [--periods 1 [10]] [--out DIR]``."""
    parser = argparse.ArgumentParser(
        prog="python -m cross_check score",
        description="Score an integrator against the golden data (protocol: cross_check.score).  "
                    "Writes scorecard.md and scorecard.json; exit status 1 if a kind is flagged.")
    parser.add_argument("adapter", help="MODULE:NAME of an adapter, or fast | reference | scipy | heyoka")
    parser.add_argument("--scenes", nargs="+", metavar="NAME", choices=list(scene_table.SCENES),
                        help="only these built-in scenes (default: all with golden data)")
    parser.add_argument("--golden-dir", metavar="DIR", default=None,
                        help="golden data written by `golden` or `verify` (DIR/golden) instead of the shipped data")
    scenefile.add_arguments(parser, "score on")
    parser.add_argument("--periods", nargs="+", type=int, default=[1, 10], choices=[1, 10],
                        help="horizons: 1, or 1 10 (default)")
    parser.add_argument("--out", default="scorecard", help="output directory (default: scorecard/)")
    args = parser.parse_args(argv)
    try:
        names = (args.scenes or []) + scenefile.from_args(args)
        adapter = load_adapter(args.adapter)
        t0 = time.perf_counter()
        card = score(adapter, scenes=names or None, periods=tuple(args.periods), golden_dir=args.golden_dir,
                     progress=lambda m: print(f"[{time.perf_counter() - t0:6.1f}s] {m}", file=sys.stderr, flush=True))
    except (ValueError, TypeError, ImportError, AttributeError) as exc:
        print(f"score: {exc}", file=sys.stderr)
        return 2
    out = pathlib.Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    (out / "scorecard.md").write_text(card.to_markdown())
    (out / "scorecard.json").write_text(card.to_json())
    print(out / "scorecard.md")
    return 1 if card.flagged() else 0


__all__ = ["Scorecard", "CaseScore", "score", "score_scene", "load_adapter", "main"]
