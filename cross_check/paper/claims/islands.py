"""Claims about the islands and attractors of the portraits: the focus and period-5 orbit of
Fig. narrow-with-friction, island A and the central island of Fig. narrow, the no-impact
attractor of Fig. many:wide and the subharmonic islands of Fig. many:2pi.

Periodic points are found on ``fast`` and refined (and continued in ``f``) on the reference.
"""
from __future__ import annotations

import functools

import mpmath
import numpy as np

from reference import paper as P
from cross_check.paper.claims import intervals
from cross_check.paper.claims.base import (SHIFT, Outcome, claim, fast_points, fl, itinerary, pick, prove,
                                           ref_newton, refined)
from cross_check.scenes import narrow, two_pi, wide


def _continuation(make_scene, fs, x, v, k=1):
    """Follow a periodic point along parameter values ``fs`` with ``ref_newton``."""
    path = []
    for f in fs:
        x, v, J, _ = ref_newton(make_scene(f), x, v, k=k)
        path.append((f, x, v, J))
    return path


@claim("focus-and-period5",
       "for f = 0.005 (Fig. narrow-with-friction) trajectories are attracted to an asymptotically stable "
       "focus and a stable period-5 orbit, with turning points, traced back to the neutral fixed point "
       "and period-5 orbit of Fig. zoom",
       {"scene": "F=1, f=0.005, w=1, l=0, r=0.8"})
def focus_period5(quick):
    sc = narrow("0.005")
    box = dict(x_range=(0.4, 0.6), v_range=(-0.1, 0.1), grid=(5, 5)) if quick else dict(v_range=(-1.5, 1.5), grid=(24, 24))
    out, proofs = {}, []
    p1 = [p for p in fast_points(sc, period=1, **box) if p.stability == "stable"]
    p5 = [p for p in fast_points(sc, period=5, **box) if p.stability == "stable"]
    for label, pts in (("fixed", p1), ("period5", p5)):
        out[f"stable_{label}"] = []
        for p in pts:
            ref = refined(sc, p)
            proofs.append(prove(f"stable {label} ({fl(ref['x']):.5f}, {fl(ref['v']):.5f})", sc,
                                ref["x"], ref["v"], p.period))
            out[f"stable_{label}"].append({"x": fl(ref["x"]), "v": fl(ref["v"]), "kind": ref["kind"],
                                           "multipliers": [fl(z) for z in ref["multipliers"]],
                                           "abs_multipliers": [fl(abs(z)) for z in ref["multipliers"]],
                                           "itinerary": ref["itinerary"]})
    # continuation of the focus back to the neutral centre of Fig. zoom (f = 0.005 -> 0); upward from
    # f = 0 Newton would start at v = 0, where Phi is not smooth once f > 0
    foc = [s for s in out["stable_fixed"] if s["kind"] == "focus"]
    c0 = [p for p in fast_points(narrow(0), period=1, x_range=(0.4, 0.6), v_range=(-0.1, 0.1), grid=(6, 6))
          if p.kind == "centre"]
    if foc and c0:
        path = _continuation(narrow, [mpmath.mpf(j) / 1000 for j in range(5, -1, -1)], foc[0]["x"], foc[0]["v"])
        out["continuation_f0.005_to_f0"] = [[fl(f), fl(x), fl(v), fl(J[0, 0] + J[1, 1]), fl(mpmath.det(J))]
                                            for f, x, v, J in path]
        out["continuation_end_minus_fast_centre_f0"] = fl(max(abs(path[-1][1] - c0[0].x), abs(path[-1][2] - c0[0].v)))
    ok = bool(foc) and bool(out["stable_period5"]) and all(s["itinerary"].get("turn", 0) > 0 for s in foc + out["stable_period5"])
    return Outcome("reproduced" if ok else "not reproduced", out, proved=proofs)


@functools.lru_cache(maxsize=2)
def narrow_centres(quick):
    """Islands of Fig. narrow (f = 0): centre A (2 impacts, no turning) and Fig. zoom's centre (4 impacts, 2 turns)."""
    grid = (16, 16) if quick else (30, 30)
    centres = []
    for f in ("0", "0.005"):
        for p in pick(fast_points(narrow(f), v_range=(-2.0, 2.0), grid=grid), "centre"):
            try:
                ref = refined(narrow(f), p)
            except (ValueError, ZeroDivisionError, RuntimeError) as exc:
                centres.append({"f": f, "x": p.x, "v": p.v, "refinement_failed": f"{type(exc).__name__}: {exc}"})
                continue
            its = itinerary(narrow(f), ref["x"], ref["v"], shift=SHIFT)
            centres.append({"f": f, "x": fl(ref["x"]), "v": fl(ref["v"]), "trace": fl(ref["trace"]),
                            "det": fl(ref["det"]), "impacts": its.get("impact", 0), "turns": its.get("turn", 0),
                            "other_events": sum(n for k, n in its.items() if k not in ("impact", "turn"))})
    return centres


@claim("island-A",
       "island A of Fig. narrow (f = 0, R = 0.8) is centred at a fixed point with two impacts per period "
       "and no other turning points (non-sticking); it persists for f = 0.005",
       {"scene": "F=1, w=1, l=0, r=0.8, f in {0, 0.005}; search box |v| <= 2"},
       note="the only non-sticking centre that persists at f = 0.005 (det = 1, the island A of Fig. "
            "narrow-with-friction) has 6 impacts per period and no turning point; at f = 0 it sits at the "
            "wall (impact at t = 0). A one-round-trip non-sticking orbit cannot exist here: the "
            "symmetric one needs R w^2 > (pi - 2) F = 1.14 > 0.8 (eq. nonstick:cond at f = 0); none "
            "was found by the search (also with |v| <= 4)")
def island_a(quick):
    centres = narrow_centres(quick)
    two = [c for c in centres if c.get("impacts") == 2 and c.get("turns") == 0]
    a = [c for c in centres if c["f"] == "0.005" and c.get("turns") == 0 and abs(c.get("det", 0) - 1) < 1e-9]
    out = {"centres": centres, "centres_with_2_impacts_0_turns": len(two),
           "nonsticking_centres_at_f0.005": len(a), "impacts_of_island_A_centre": a[0]["impacts"] if a else None}
    if a:   # follow island A's centre towards f = 0: it runs into the wall x = r
        path = _continuation(narrow, [mpmath.mpf(j) / 10000 for j in range(50, 0, -5)],
                             a[0]["x"], a[0]["v"])
        out["continuation_to_small_f"] = [[fl(f), fl(x), fl(v), fl(J[0, 0] + J[1, 1])] for f, x, v, J in path]
        wall = [p for p in fast_points(narrow(0), x_range=(0.7, 0.8), v_range=(-1.5, -1.1), grid=(6, 6))
                if p.kind == "centre" and p.x > 0.7]
        out["f0_wall_centre"] = [[p.x, p.v, p.trace] for p in wall]
    proofs = [prove(f"island A centre, f = 0.005 ({c['x']:.5f}, {c['v']:.5f})", narrow("0.005"), c["x"], c["v"])
              for c in a]
    proofs += [prove(f"island A centre, f = 0, at the wall ({x:.5f}, {v:.5f})", narrow(0), min(x, 0.8), v)
               for x, v, _ in out.get("f0_wall_centre", [])]
    if two:
        return Outcome("reproduced", out, proved=proofs)
    if len(a) == 1:
        return Outcome("erratum", out, corrected=f"{a[0]['impacts']} impacts per period "
                                                 f"({a[0]['impacts'] // 2} round trips), no turning point",
                       proved=proofs)
    return Outcome("not reproduced", out, proved=proofs)


@claim("fig1b-centre",
       "the fixed point of the central island (Fig. zoom) corresponds to a periodic solution with four "
       "impacts and two turning points per period",
       {"scene": "F=1, f=0, w=1, l=0, r=0.8"},
       note="events counted over [0.3183 T, 1.3183 T]; without friction a turning point is a zero of "
            "the velocity in flight")
def fig1b_centre(quick):
    centres = [c for c in narrow_centres(quick) if c["f"] == "0"]
    four = [c for c in centres if c.get("impacts") == 4 and c.get("turns") == 2]
    proofs = [prove(f"fig:zoom centre ({c['x']:.5f}, {c['v']:.5f})", narrow(0), c["x"], c["v"]) for c in four]
    return Outcome("reproduced" if four else "not reproduced", {"centres": centres, "matching": four},
                   proved=proofs)


@claim("fig3-attractor",
       "the attractor of Fig. many:wide (periodic solutions without impacts) corresponds to periodic "
       "orbits with two intervals of sticking per period",
       {"scene": "F=1, w=1, l=0, r=20, f = 0.1 ... 0.6"},
       corrected="two turning points per period (no sticking) for f/F < 1/sqrt(1 + pi^2/4) = 0.53703 "
                 "(panels a-e); two sticking intervals only for f/F >= 0.53703 (panel f, f = 0.6)",
       note="a no-impact orbit reached from rest (60 periods of fast.orbit), refined by reference Newton; "
            "closed forms in reference.paper.no_impact_attractor")
def fig3_attractor(quick):
    import fast
    out, proofs = {}, []
    fs = ("0.3", "0.6") if quick else ("0.1", "0.2", "0.3", "0.4", "0.5", "0.6")
    for f in fs:
        sc = wide(f)
        x0 = np.linspace(2.0, 18.0, 9)
        X, V = fast.orbit(sc, x0, np.zeros_like(x0), 60)
        x, v = ref_newton(sc, X[-1][4], V[-1][4])[:2]
        its = itinerary(sc, x, v, shift=SHIFT)
        closed = P.no_impact_attractor(sc)
        out[f"f{f}"] = {"x": fl(x), "v": fl(v), "v_closed_form": fl(closed["v0"]), "closed_form_kind": closed["kind"],
                        "itinerary": its, "sticking_intervals": its.get("slip", 0), "turns": its.get("turn", 0),
                        "impacts": its.get("impact", 0), "spread_of_final_v_over_starts": float(np.ptp(V[-1]))}
        # translation-invariant away from the walls: a segment of fixed points, proved as one
        proofs.append(prove(f"no-impact attractor, f = {f}, x0 in [5, 15]", sc, x, v, segment=(5, 15)))
    out["stick_threshold_f_over_F"] = fl(P.stick_threshold())
    return Outcome("erratum", out, proved=proofs)


@claim("subharmonic-islands",
       "for F = 1, w = 2 pi, l = -1, r = 1 the period-1 island and three islands of a non-sticking "
       "period-3 solution survive up to f = 0.2 (Fig. many:2pi c-e) and the latter vanish at f = 0.3",
       {"scene": "F=1, w=2pi, l=-1, r=1", "boxes": "period 1: |v| <= 6; period 3: |v| <= 3"},
       note="the period-3 centre is the symmetric solution with one flight per 3 pi/w (m = 3); it exists "
            "iff f/F <= 2/(3 pi) = 0.2122, between the figure's 0.2 and 0.3")
def subharmonic(quick):
    fs = ("0.2", "0.3") if quick else ("0.005", "0.01", "0.05", "0.1", "0.2", "0.3")
    grid = (8, 8) if quick else (30, 40)
    # quick: boxes around the bands where the full search finds the centres (|v| 3.5-4.5, 1-2)
    boxes = ((1, (3.0, 5.0)), (3, (0.5, 2.5))) if quick else ((1, (-6.0, 6.0)), (3, (-3.0, 3.0)))
    out, proofs = {}, []
    for f in fs:
        sc = two_pi(f)
        row = {}
        for k, vr in boxes:
            pts = fast_points(sc, period=k, v_range=vr, grid=grid)
            row[f"period{k}_centres"] = [[p.x, p.v, p.trace] for p in pts if p.kind == "centre"]
            proofs += [prove(f"period-{k} centre, f = {f} ({p.x:.5f}, {p.v:.5f})", sc, p.x, p.v, k)
                       for p in pts if p.kind == "centre" and k == 3]
            sol = P.symmetric_solution(sc, 1, m=k)
            row[f"period{k}_symmetric_closed_form"] = None if sol is None else {
                "state0": [fl(a) for a in sol.state0()], "trace": fl(sol.trace()),
                "min_velocity": fl(sol.min_flight_velocity()[0])}
        out[f"f{f}"] = row
    out["period3_symmetric_existence_bound_2F_over_3pi"] = fl(P.existence_bound(3))
    ok = bool(out["f0.2"]["period3_centres"]) and not out["f0.3"]["period3_centres"]
    return Outcome("reproduced" if ok else "not reproduced", out, proved=proofs,
                   proved_on=intervals.lines("subharmonic-islands"))
