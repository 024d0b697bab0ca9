"""Work-precision: what accuracy costs in time, for every method the report measures.

For each horizon (1 and 10 periods) and each state of the work-precision scenes: the error of
``Phi^n`` against the reference at ``TRUTH_DPS`` digits (``compare.map_error``) and the time per
trajectory-period (best of 2), for the reference at dps 16 ... 100, ``fast`` (on a batch of
~4096 copies, time divided), scipy's RK45/DOP853 at rtol 1e-3 ... 1e-12 and heyoka.py's Taylor
integrator at tol 1e-9 ... 1e-15 when it is installed, all through the scoring protocol
(``cross_check.score.adapters``).  Beside them the
one-ulp floor (the spread of the exact map under one-ulp moves of the start) and the rounding
floor, and fast's error in units of both (``compare.map_floors``).
"""
from __future__ import annotations

import functools
import math
import time

import numpy as np

from cross_check import scenes
from cross_check.agreement import baseline, compare
from cross_check.report.sections import REF_DPS, TRUTH_DPS
from cross_check.score import adapters
from cross_check.tolerances import tol


#: a call taking at least this many seconds is timed once; a shorter one is repeated
REPEAT_BELOW = 0.02


def _timed(fn, *args, repeat: int = 2, **kw):
    """Result and best-of-``repeat`` wall time (the machine is shared: the minimum is the
    least disturbed measurement) for a call shorter than ``REPEAT_BELOW``; a longer call is
    timed once: a disturbance of a few milliseconds is then within a few percent, and the
    repeats were half of the section's time (the 10-period solve_ivp runs at tight rtol)."""
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn(*args, **kw)
        best = min(best, time.perf_counter() - t0)
        if best >= REPEAT_BELOW:
            break
    return out, best


@functools.lru_cache(maxsize=None)
def peers(rtols: tuple) -> list:
    """The peers of the work-precision diagram, as scoring-protocol adapters (``cross_check.score``):
    solve_ivp RK45/DOP853 at each ``rtol``, and heyoka.py at 1e-9, 1e-12, 1e-15 when installed (built
    once per run: each heyoka integrator compiles its Taylor series)."""
    out = [adapters.BaselineAdapter(f"{m} rtol {r:.0e}", m, r) for m in baseline.METHODS for r in rtols]
    try:
        out += [adapters.BaselineAdapter(f"heyoka tol {t:.0e}", flight=adapters.HeyokaFlight(t))
                for t in (1e-9, 1e-12, 1e-15)]
    except ImportError:
        pass            # heyoka is optional: the report says so
    return out


def _peer_points(pts, sc, X, V, truths, periods, rtols):
    params = sc.floats()
    for peer in peers(tuple(rtols)):
        for X0, V0, tr in zip(X, V, truths):
            try:
                (bx, bv), sec = _timed(peer.step, params, np.array([X0]), np.array([V0]), periods)
                pts.setdefault(peer.name, []).append((compare.map_error((bx[0], bv[0]), tr), sec / periods))
            except RuntimeError:
                pts.setdefault(peer.name, []).append((1.0, math.nan))


def truths(plan) -> dict:
    """The untimed part of the section, ``{(periods, scene): (cases, X, V, truths, floors)}``:
    the reference at ``TRUTH_DPS`` and the one-ulp and rounding floors per state.  Nothing here
    is timed, so the report computes it while the claims still run beside it."""
    out = {}
    for periods in plan.wp_periods:
        for name in plan.wp_scenes:
            sc = scenes.scene(name)
            cases = scenes.sample_states(name, plan.wp_states)
            X = np.array([c.float()[0] for c in cases])
            V = np.array([c.float()[1] for c in cases])
            exact = [compare.ref_map(sc, c, periods, TRUTH_DPS) for c in cases]
            floors = [compare.map_floors(sc, X0, V0, tr, periods, REF_DPS) for X0, V0, tr in zip(X, V, exact)]
            out[periods, name] = (cases, X, V, exact, floors)
    return out


def _scene_points(name, plan, periods, prepared, pts, floors, ratios):
    """One scene's contribution: floors per state, then every method's (error, s/period)."""
    sc = scenes.scene(name)
    cases, X, V, exact, state_floors = prepared
    start = len(floors["ulp"])
    for floor, rfloor in state_floors:
        floors["ulp"].append(floor)
        floors["rounding"].append(rfloor)
    for dps in plan.wp_dps:
        for c, tr in zip(cases, exact):
            res, sec = _timed(compare.ref_map, sc, c, periods, dps)
            pts.setdefault(f"reference dps {dps}", []).append((compare.map_error(res, tr), sec / periods))
    reps = max(64, 4096 // len(X))   # fast is a batch engine: time it on a batch of ~4096
    (fx, fv), sec = _timed(compare.fast_map, sc, np.repeat(X, reps), np.repeat(V, reps), periods)
    for i, tr in enumerate(exact):
        err = compare.map_error((fx[i * reps], fv[i * reps]), tr)
        pts.setdefault("fast", []).append((err, sec / (reps * len(X) * periods)))
        ratios["ulp"].append(err / floors["ulp"][start + i])
        ratios["rounding"].append(err / floors["rounding"][start + i])
    _peer_points(pts, sc, X, V, exact, periods, plan.wp_rtols)


def work_precision(plan, progress, prepared=None) -> dict:
    """Median error and time per trajectory-period for each method and horizon (``prepared``:
    :func:`truths` of the plan, computed here if not given)."""
    prepared = truths(plan) if prepared is None else prepared
    data = {}
    for periods in plan.wp_periods:
        pts, floors, ratios = {}, {"ulp": [], "rounding": []}, {"ulp": [], "rounding": []}
        for name in plan.wp_scenes:
            _scene_points(name, plan, periods, prepared[periods, name], pts, floors, ratios)
            progress(f"work-precision: {name}, {periods} period(s)")
        data[periods] = {"points": {k: (float(np.median([e for e, _ in v])), float(np.max([e for e, _ in v])),
                                        float(np.nanmedian([s for _, s in v]))) for k, v in pts.items()},
                         "ulp_floor": float(np.median(floors["ulp"])), "ulp_floor_worst": float(np.max(floors["ulp"])),
                         "fast_over_floor": _ratio_stats(ratios["ulp"]),
                         "rounding_floor": float(np.median(floors["rounding"])),
                         "fast_over_rounding_floor": _ratio_stats(ratios["rounding"])}
    return data


def _ratio_stats(ratios) -> tuple:
    """``(median, worst, fraction above fast_ten_period_ulp_factor)``."""
    r = np.asarray(ratios, float)
    return float(np.median(r)), float(np.max(r)), float(np.mean(r > tol("fast_ten_period_ulp_factor").rtol))


def wp_table(data: dict) -> list[str]:
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
