"""The V&V report: ``python -m cross_check report [--out DIR] [--quick]``.

Writes ``report.md`` and PNGs (default ``report/``):

1. per scene, the agreement of ``fast`` with ``reference`` (dps 50) on the seeded sample:
   share of identical one-period itineraries, event-time and event-state digits, ``Phi`` and
   ``Phi^10`` digits (median / worst; ``cross_check.agreement.compare``), the near-grazing band;
2. the hard cases (``cross_check.agreement.hardcases``): the reference on the exact decimal state and on
   its float64 rounding, ``fast``, scipy DOP853 (rtol 1e-10), and whether ``fast``'s itinerary
   is stable under a ``compare_band_ulps`` move;
3. a work-precision diagram (``work_precision``): error of ``Phi`` and ``Phi^10`` against the
   reference at ``TRUTH_DPS`` versus time per trajectory-period (best of 2), for the reference
   at dps 16 ... 100, ``fast`` and ``solve_ivp`` RK45/DOP853 at rtol 1e-3 ... 1e-12
   (``cross_check.agreement.baseline``), with the one-ulp floor (the spread of the exact map under
   one-ulp moves of the start) and fast's error in units of that floor;
4. where solve_ivp misses events (``baseline.itinerary_misses``);
5. the paper's claims (``cross_check.claims.run_claims(quick)``), if that module exists;
6. machine, versions, seeds, timings.

Progress goes to stderr, one line per step.  The full report takes under a minute on two
cores (measured 44 s), ``--quick`` about 7 s (fewer scenes, states and configurations).
"""
from __future__ import annotations

import importlib
import inspect
import math
import os
import pathlib
import platform
import sys
import time
from dataclasses import dataclass

import mpmath
import numpy as np

from cross_check.agreement import baseline, compare
from cross_check import scenes
from cross_check.agreement.compare import Summary
from cross_check.tolerances import tol

REF_DPS = 50
TRUTH_DPS = 120
WP_DPS = (16, 20, 30, 50, 100)
FLOOR_PLOT = 1e-22   # errors below this are drawn on it (the reference reaches 1e-100)


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


FULL = Plan(tuple(scenes.SCENES), 12, 4, scenes.QUICK_SCENES,
            ("fig:narrow-with-friction", "fig:many:2pi/f=0.1", "fig:resonance/R=0.8932"), 4,
            baseline.RTOLS, WP_DPS, (1, 10))
QUICK = Plan(("fig:narrow-with-friction", "fig:many:2pi/f=0.1", "fig:resonance/R=0.8932"), 4, 1,
             ("fig:narrow-with-friction",), ("fig:narrow-with-friction",), 2,
             (1e-3, 1e-6, 1e-9, 1e-12), (16, 30, 50), (1, 10))


class Progress:
    """Timestamped progress lines on stderr."""

    def __init__(self):
        self.t0 = time.perf_counter()

    def __call__(self, msg: str):
        print(f"[{time.perf_counter() - self.t0:6.1f}s] {msg}", file=sys.stderr, flush=True)

    @property
    def elapsed(self) -> float:
        return time.perf_counter() - self.t0


# --- 1. per-scene agreement -----------------------------------------------------------
def scene_agreement(name: str, plan: Plan) -> dict:
    """Fast vs reference on the sample states of one scene (see ``compare``)."""
    sc = scenes.scene(name)
    cases = scenes.sample_states(name, plan.n_sample)
    X = np.array([c.float()[0] for c in cases])
    V = np.array([c.float()[1] for c in cases])
    phis, fail = compare.fast_safe(compare.fast_map, sc, X, V)
    f_evs, fail_e = compare.fast_safe(compare.fast_events, sc, X, V)
    band = compare.band_mask(sc, X, V)
    rows, raw = [], []
    for i, c in enumerate(cases):
        r_phi = compare.ref_map(sc, c, 1, REF_DPS)
        r_evs = compare.ref_events(sc, c, None, REF_DPS)
        ca = compare.compare_case(c.name, r_evs, f_evs[i], r_phi, phis[i], scene=sc)
        ca.in_band = bool(band[i])
        rows.append(ca)
        if phis[i] is not None:
            raw.append(min(compare.digits(phis[i][0], r_phi[0]), compare.digits(phis[i][1], r_phi[1])))
    out = compare.summarize(rows)
    out["failures"] = {cases[i].name: msg for i, msg in {**fail_e, **fail}.items()}
    ten = []
    for c in cases[:plan.n_ten]:
        got, _ = compare.fast_safe(compare.fast_map, sc, *map(np.array, zip(c.float())), periods=10)
        if got[0] is not None:
            ref10 = compare.ref_map(sc, c, 10, REF_DPS)
            ten.append(min(compare.digits(got[0][0], ref10[0]), compare.digits(got[0][1], ref10[1])))
    out["map10"] = Summary.of(ten)
    out["map_raw"] = Summary.of(raw)
    return out


def _agreement_table(results: dict) -> list[str]:
    lines = ["| scene | states | same itinerary | band | event t (med/worst) | event state | "
             "Phi digits | Phi^10 digits | mismatches outside band | fast failed |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for name, s in results.items():
        if s is None:
            lines.append(f"| `{name}` | FAILED (see Failures) |" + " |" * 8)
            continue
        share = f"{100 * s['itinerary_share']:.0f}%"
        lines.append(f"| `{name}` | {s['n']} | {share} | {len(s['band'])} | "
                     f"{s['event_time']} | {s['event_state']} | {s['map_raw']} | {s['map10']} | "
                     f"{', '.join(s['mismatch_outside_band']) or '-'} | {len(s['failures']) or '-'} |")
    failures = [f"- `{name}` / {case}: {msg}" for name, s in results.items() if s is not None
                for case, msg in s["failures"].items()]
    if failures:
        lines += ["", "fast raised on these states:", ""] + failures
    return lines


# --- 2. hard cases --------------------------------------------------------------------
def hard_case_rows(name: str) -> list[dict]:
    """Both integrators (and scipy) on the hard cases of a scene."""
    sc = scenes.scene(name)
    cases = scenes.hard_states(name)
    X = np.array([c.float()[0] for c in cases])
    V = np.array([c.float()[1] for c in cases])
    phis, _ = compare.fast_safe(compare.fast_map, sc, X, V)
    f_evs, _ = compare.fast_safe(compare.fast_events, sc, X, V)
    band = compare.band_mask(sc, X, V)
    rows = []
    for i, c in enumerate(cases):
        fc = c.rounded()
        r_exact = compare.ref_events(sc, c, None, REF_DPS)
        r_float = compare.ref_events(sc, fc, None, REF_DPS)
        r_phi = compare.ref_map(sc, fc, 1, REF_DPS)
        ca = compare.compare_case(c.name, r_float, f_evs[i], r_phi, phis[i], scene=sc)
        try:
            b = baseline.stroboscopic(sc, X[i], V[i], 1, "DOP853", 1e-10)
            scipy_same = "yes" if tuple(e.kind for e in compare.canonical(b.events, sc)) == ca.ref_kinds else "**no**"
            scipy_digits = min(compare.digits(b.x, r_phi[0]), compare.digits(b.v, r_phi[1]))
        except RuntimeError as exc:
            scipy_same, scipy_digits = f"failed: {exc}"[:40], math.nan
        text = compare.itinerary_text
        rows.append({"scene": name, "case": c.name, "built": c.kind, "ref_exact": text(r_exact, sc),
                     "ref_float": text(r_float, sc), "fast": text(f_evs[i], sc), "same": ca.same_itinerary,
                     "digits": min(ca.map_digits), "stable": not band[i], "scipy_same": scipy_same,
                     "scipy_digits": scipy_digits, "ref_band": compare.reference_in_band(sc, fc)})
    return rows


def _hard_table(rows) -> list[str]:
    lines = ["| scene | case | built around | reference (exact state) | reference (float64 state) | fast | "
             "fast = ref? | fast Phi digits | exact itinerary stable (+-ulps)? | fast stable? | "
             "scipy DOP853 1e-10 same? (digits) |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        lines.append(f"| `{r['scene']}` | {r['case']} | {r['built']} | {r['ref_exact']} | {r['ref_float']} | "
                     f"{r['fast']} | {'yes' if r['same'] else '**no**'} | {r['digits']:.1f} | "
                     f"{'**no** (band)' if r['ref_band'] else 'yes'} | {'yes' if r['stable'] else '**no**'} | "
                     f"{r['scipy_same']} ({r['scipy_digits']:.1f}) |")
    return lines


# --- 3. work-precision ----------------------------------------------------------------
def _timed(fn, *args, repeat: int = 2, **kw):
    """Result and best-of-``repeat`` wall time (the machine is shared: the minimum is the
    least disturbed measurement)."""
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn(*args, **kw)
        best = min(best, time.perf_counter() - t0)
    return out, best


def work_precision(plan: Plan, progress) -> dict:
    """Median error and time per trajectory-period for each method and horizon."""
    data = {}
    for periods in plan.wp_periods:
        pts = {}
        # per state: the one-ulp and rounding floors (compare.map_floors), fast's error over each
        floors, rfloors, ratios, rratios = [], [], [], []
        for name in plan.wp_scenes:
            sc = scenes.scene(name)
            cases = scenes.sample_states(name, plan.wp_states)
            X = np.array([c.float()[0] for c in cases])
            V = np.array([c.float()[1] for c in cases])
            truths = [compare.ref_map(sc, c, periods, TRUTH_DPS) for c in cases]
            for X0, V0, tr in zip(X, V, truths):
                floor, rfloor = compare.map_floors(sc, X0, V0, tr, periods, REF_DPS)
                floors.append(floor)
                rfloors.append(rfloor)
            for dps in plan.wp_dps:
                for c, tr in zip(cases, truths):
                    res, sec = _timed(compare.ref_map, sc, c, periods, dps)
                    pts.setdefault(f"reference dps {dps}", []).append(
                        (compare.map_error(res, tr), sec / periods))
            reps = max(64, 4096 // len(X))   # fast is a batch engine: time it on a batch of ~4096
            (fx, fv), sec = _timed(compare.fast_map, sc, np.repeat(X, reps), np.repeat(V, reps), periods)
            for i, tr in enumerate(truths):
                pts.setdefault("fast", []).append((compare.map_error((fx[i * reps], fv[i * reps]), tr),
                                                   sec / (reps * len(X) * periods)))
                rratios.append(pts["fast"][-1][0] / rfloors[len(ratios)])
                ratios.append(pts["fast"][-1][0] / floors[len(ratios)])
            for method in baseline.METHODS:
                for rtol in plan.wp_rtols:
                    for X0, V0, tr in zip(X, V, truths):
                        try:
                            b, sec = _timed(baseline.stroboscopic, sc, X0, V0, periods, method, rtol)
                            pts.setdefault(f"{method} rtol {rtol:.0e}", []).append(
                                (compare.map_error((b.x, b.v), tr), sec / periods))
                        except RuntimeError:
                            pts.setdefault(f"{method} rtol {rtol:.0e}", []).append((1.0, math.nan))
            progress(f"work-precision: {name}, {periods} period(s)")
        data[periods] = {"points": {k: (float(np.median([e for e, _ in v])), float(np.max([e for e, _ in v])),
                                        float(np.nanmedian([s for _, s in v]))) for k, v in pts.items()},
                         "ulp_floor": float(np.median(floors)), "ulp_floor_worst": float(np.max(floors)),
                         "fast_over_floor": _ratio_stats(ratios),
                         "rounding_floor": float(np.median(rfloors)),
                         "fast_over_rounding_floor": _ratio_stats(rratios)}
    return data


def _ratio_stats(ratios) -> tuple:
    """``(median, worst, fraction above fast_ten_period_ulp_factor)``."""
    r = np.asarray(ratios, float)
    return float(np.median(r)), float(np.max(r)), float(np.mean(r > tol("fast_ten_period_ulp_factor").rtol))


def scipy_itineraries(plan: Plan, progress) -> list[str]:
    """Where solve_ivp misses or invents events (``baseline.itinerary_misses``), as a table."""
    runs = baseline.itinerary_misses(plan.hard_scenes, plan.n_sample, progress)
    lines = ["| solver | states | same itinerary | fewer impacts (missed) | more impacts | other difference | "
             "failed | examples of misses |", "|---|---|---|---|---|---|---|---|"]
    for (method, rtol), rows in runs.items():
        same = sum(1 for _, a, b in rows if a == b)
        failed = [w for w, _, b in rows if b is None]
        fewer = [w for w, a, b in rows if b is not None and b.count("impact") < a.count("impact")]
        more = [w for w, a, b in rows if b is not None and b.count("impact") > a.count("impact")]
        other = len(rows) - same - len(failed) - len(fewer) - len(more)
        lines.append(f"| {method} rtol {rtol:.0e} | {len(rows)} | {same} | {len(fewer)} | {len(more)} | {other} | "
                     f"{len(failed)} | {', '.join(fewer[:3]) or '-'} |")
    return lines


def _wp_plot(data: dict, path: pathlib.Path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, len(data), figsize=(6 * len(data), 4.8), squeeze=False)
    for ax, (periods, d) in zip(axes[0], data.items()):
        for family, marker in (("reference", "o"), ("RK45", "s"), ("DOP853", "^"), ("fast", "*")):
            keys = [k for k in d["points"] if k.startswith(family)]
            if not keys:
                continue
            true_err = [d["points"][k][0] for k in keys]
            err = [max(e, FLOOR_PLOT) for e in true_err]     # below 1e-22: drawn on the floor, labelled
            sec = [d["points"][k][2] for k in keys]
            ax.loglog(sec, err, marker=marker, ms=9 if family == "fast" else 5,
                      ls="-" if family != "fast" else "none", label=family)
            if family == "reference":
                for k, s, e, te in zip(keys, sec, err, true_err):
                    ax.annotate(f"dps {k.split()[-1]}: {te:.0e}", (s, e), fontsize=7, xytext=(3, 3),
                                textcoords="offset points")
        ax.axhline(d["ulp_floor"], color="k", ls=":", label="one-ulp floor")
        ax.set_xlabel("seconds per trajectory-period")
        ax.set_ylabel("median error of Phi (relative, max(1,|.|)); floor 1e-22")
        ax.set_title(f"after {periods} period(s)")
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _wp_table(data: dict) -> list[str]:
    lines = []
    for periods, d in data.items():
        med, worst, above = d["fast_over_floor"]
        rmed, rworst, rabove = d["fast_over_rounding_floor"]
        factor = tol('fast_ten_period_ulp_factor').rtol
        lines += [f"**After {periods} period(s)** (one-ulp floor -- the spread of the exact map under one-ulp "
                  f"moves of x0 or v0, at least 1e-17: median {d['ulp_floor']:.1e}, "
                  f"largest {d['ulp_floor_worst']:.1e}; "
                  f"fast's error / that floor per state: median {med:.2g}, worst {worst:.2g}, "
                  f"{above:.0%} above `fast_ten_period_ulp_factor` = {factor:g}. "
                  f"Rounding floor -- the larger of that and the error of the exact map rounded to float64 "
                  f"after every period (median {d['rounding_floor']:.1e}): fast's error over it: median "
                  f"{rmed:.2g}, worst {rworst:.2g}, {rabove:.0%} above {factor:g}. On a neutral or contracting "
                  f"direction (sticking, wall contact) the one-ulp floor is below the rounding that every "
                  f"float64 result carries, so no float64 engine meets it there; chaotic orbits amplify "
                  f"both floors alike, by up to ~1e7 over ten periods.)", "",
                  "| method | median error | worst error | s per trajectory-period |", "|---|---|---|---|"]
        for k, (med, worst, sec) in d["points"].items():
            lines.append(f"| {k} | {med:.1e} | {worst:.1e} | {sec:.2e} |")
        lines.append("")
    return lines


# --- 4. claims, 5. machine --------------------------------------------------------------
def claims_section(quick: bool, progress) -> list[str]:
    """The table of ``cross_check.claims.run_claims(quick)`` if that module exists."""
    try:
        claims = importlib.import_module("cross_check.claims")
    except ModuleNotFoundError:
        return ["`cross_check.claims` is not available in this tree."]
    if not hasattr(claims, "run_claims"):
        return ["`cross_check.claims` has no `run_claims(quick)` (yet)."]
    try:
        ids = list(getattr(claims, "CLAIMS", {}))
        if ids and "ids" in inspect.signature(claims.run_claims).parameters:
            rows = []
            for cid in ids:           # one at a time, for progress lines
                rows += list(claims.run_claims(quick, ids=[cid]))
                progress(f"claim {cid}: {rows[-1].get('verdict', '?') if rows else '?'}")
        else:
            rows = list(claims.run_claims(quick))
    except Exception as exc:  # noqa: BLE001 -- another module's failure is reported, not fatal
        progress(f"claims FAILED: {type(exc).__name__}: {exc}")
        return [f"**run_claims failed**: `{type(exc).__name__}: {str(exc)[:300]}`"]
    progress(f"claims: {len(rows)} rows")
    if not rows:
        return ["(no claims)"]
    as_dict = [r if isinstance(r, dict) else (r._asdict() if hasattr(r, "_asdict") else vars(r)) for r in rows]
    preferred = [k for k in ("id", "verdict", "statement", "corrected", "note", "seconds") if k in as_dict[0]]
    keys = preferred or list(as_dict[0])
    def cell(d, k):
        return " ".join(str("" if d.get(k) is None else d[k]).split())[:160].replace("|", "/")

    out = ["| " + " | ".join(keys) + " |", "|" + "---|" * len(keys)]
    out += ["| " + " | ".join(cell(d, k) for k in keys) + " |" for d in as_dict]
    return out


def machine_section(plan: Plan, quick: bool) -> list[str]:
    import matplotlib
    import scipy

    return [f"- machine: {platform.machine()}, {os.cpu_count()} cores, {platform.platform()}",
            f"- python {platform.python_version()}, numpy {np.__version__}, scipy {scipy.__version__}, "
            f"mpmath {mpmath.__version__} (backend {mpmath.libmp.BACKEND}), matplotlib {matplotlib.__version__}",
            f"- mode: {'quick' if quick else 'full'}; sample seed {scenes.SEED} (+crc32 of the scene name); "
            f"{plan.n_sample} sample states per scene, reference at dps {REF_DPS}, truth at dps {TRUTH_DPS}",
            f"- near-grazing band: itinerary change under {tol('compare_band_ulps').rtol:g} ulps "
            f"(`compare_band_ulps`)"]


# --- the whole report -----------------------------------------------------------------
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


def build(out_dir, quick: bool = False, claims: bool = True) -> tuple[pathlib.Path, list]:
    """Compute everything and write ``report.md`` + PNGs into ``out_dir``; return the path
    and the list of parts that failed (they are listed in the report too).

    ``claims=False`` leaves the claims section out (they have their own tests and command)."""
    plan = QUICK if quick else FULL
    progress = Progress()
    out = pathlib.Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    for pkg in ("reference", "fast"):
        if not compare.available(pkg):
            raise RuntimeError(f"the {pkg} integrator is not available ({pkg}.stroboscopic_map)")
    timings, errors = {}, []
    agreement = {}
    for name in plan.scenes:
        agreement[name] = _guarded(progress, errors, f"agreement {name}", scene_agreement, name, plan)
        if agreement[name] is not None:
            progress(f"agreement: {name}: {agreement[name]['map_raw']} digits (median/worst)")
    timings["agreement"] = progress.elapsed
    hard = []
    for name in plan.hard_scenes:
        hard += _guarded(progress, errors, f"hard cases {name}", hard_case_rows, name) or []
        progress(f"hard cases: {name}")
    timings["hard cases"] = progress.elapsed - sum(timings.values())
    wp = _guarded(progress, errors, "work-precision", work_precision, plan, progress)
    if wp is not None:
        _wp_plot(wp, out / "work_precision.png")
    timings["work-precision"] = progress.elapsed - sum(timings.values())
    scipy_lines = _guarded(progress, errors, "scipy itineraries", scipy_itineraries, plan, progress) or []
    timings["scipy itineraries"] = progress.elapsed - sum(timings.values())
    claims = claims_section(quick, progress) if claims else ["(skipped: `--skip-claims`)"]
    if claims[0].startswith("**run_claims failed"):
        errors.append("claims: " + claims[0])
    timings["claims"] = progress.elapsed - sum(timings.values())
    lines = ["# Cross-check report: reference (mpmath) vs fast (float64) vs scipy", "",
             "Digits are significant correct digits, `-log10(|a - ref| / max(1, |ref|))` (capped at 17), "
             "given as median / worst.  Itineraries are compared first; event times and states only on "
             "the common prefix of identical event kinds; never one norm across an impact.", "",
             ]
    if errors:
        lines += ["## Failures", "", "These parts could not be computed (the rest of the report stands):", ""]
        lines += [f"- {e}" for e in errors] + [""]
    lines += ["## Agreement of fast with reference (dps 50), one period", ""]
    lines += _agreement_table(agreement)
    lines += ["", f"Tolerances (`cross_check/tolerances.py`): fast_one_period_max = "
              f"{tol('fast_one_period_max').rtol:g} (13 digits), fast_one_period_median = "
              f"{tol('fast_one_period_median').rtol:g} (14.5 digits).  `band` = states whose fast itinerary "
              "changes under a few-ulp move (near-grazing band): listed, not hidden.", "",
              "## Hard cases", "", "Constructed exactly by closed-form backward flights "
              "(`cross_check/agreement/hardcases.py`); fast and scipy see the float64 rounding of the decimal state, "
              "so they are compared with the reference on that same float64 state.", ""]
    lines += _hard_table(hard)
    lines += ["", "## Work-precision", "", "![work-precision](work_precision.png)", "",
              f"Error of Phi^n against the reference at dps {TRUTH_DPS}; time per trajectory-period "
              "(best of 2 runs; fast: the states repeated into a batch of ~4096, time divided).  "
              "scipy: `cross_check/agreement/baseline.py`.", ""]
    lines += _wp_table(wp) if wp is not None else ["(failed: see Failures)", ""]
    lines += ["## Where solve_ivp misses events", "",
              "One period from the sample and hard states (float64) of the hard-case scenes; itineraries in "
              "canonical form (`compare.canonical`) against the reference at dps 50.  A careful user's "
              "event handling (`cross_check/agreement/baseline.py`): restart at each event, stick and wall contact "
              "by threshold events, chatter cut-off below 100 atol.", ""] + scipy_lines + [""]
    lines += ["## The paper's claims", ""] + claims
    lines += ["", "## Machine, versions, seeds", ""] + machine_section(plan, quick)
    lines += [f"- timings: " + ", ".join(f"{k} {v:.0f}s" for k, v in timings.items())
              + f", total {progress.elapsed:.0f}s"]
    path = out / "report.md"
    path.write_text("\n".join(lines) + "\n")
    progress(f"wrote {path}" + (f" ({len(errors)} part(s) FAILED)" if errors else ""))
    return path, errors


def main(argv=None) -> int:
    """CLI entry: ``report [--out DIR] [--quick]``."""
    import argparse

    parser = argparse.ArgumentParser(prog="python -m cross_check report",
                                     description="accuracy/performance report (markdown + PNG)")
    parser.add_argument("--out", default="report", help="output directory (default: report/)")
    parser.add_argument("--quick", action="store_true", help="small run, about 7 s")
    parser.add_argument("--skip-claims", action="store_true",
                        help="leave out the claims table (python -m cross_check claims runs it alone)")
    args = parser.parse_args(argv)
    try:
        path, errors = build(args.out, args.quick, claims=not args.skip_claims)
    except RuntimeError as exc:
        print(f"report: {exc}", file=sys.stderr)
        return 1
    print(path)
    return 1 if errors else 0
