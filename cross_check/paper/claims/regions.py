"""Claims about the regions of phase space and the derivative of the map: the invariance of
Omega_dissip, area preservation off it, and Table 1's matrices against finite differences.
"""
from __future__ import annotations

import json
import pathlib

import mpmath
import numpy as np

import reference
from reference import paper as P
from cross_check.dynamics.portraits import dissipative_invariance
from cross_check.paper.claims.base import Outcome, cell_grid, claim, fl, itinerary, period
from cross_check.scenes import narrow, scene, two_pi, wide
from reference.scene import Scene

#: the three scenes of the region claims, with the velocity window of their grids
REGION_SCENES = (("wide_f0.6", wide("0.6"), (-4.0, 10.0)), ("2pi_f0.05", two_pi("0.05"), (-6.0, 6.0)),
                 ("narrow_f0.005", narrow("0.005"), (-2.0, 2.0)))
#: the scenes of the proof of ``dissip-invariance`` (``prove --claim dissip-invariance --shipped``):
#: the region scenes by their registry names, and the atlas point where an independent check
#: found a violation (f/F = 0.0234, w^2 R/F = 4.48; the atlas's F = w = 1, l = 0)
PROOF_SCENES = (("wide_f0.6", scene("fig:many:wide/f=0.6")), ("2pi_f0.05", scene("fig:many:2pi/f=0.05")),
                ("narrow_f0.005", scene("fig:narrow-with-friction")),
                ("atlas_f0.0234_R4.48", Scene(name="atlas:f/F=0.0234,w2R/F=4.48", F=1, f="0.0234",
                                              omega=1, l=0, r="4.48")))
#: the shipped results of that proof (read by the claim, written by ``--shipped``)
PROOF_PATH = pathlib.Path(__file__).resolve().parents[2] / "data" / "dissip_invariance.json"


def _confirm_violation(sc, x, v):
    """Reference check of a state in Omega_dissip whose image is in Omega_pres: zero velocity on
    [0, T], none on [T, 2T] (event logs at 30 digits)."""
    zero = ("turn", "stick", "contact", "chatter")
    T = period(sc)
    first = reference.trajectory(sc, x, v, T, dps=30)
    second = reference.trajectory(sc, first.x_end, first.v_end, 2 * T, t0=first.t_end, dps=30)
    return any(e.kind in zero for e in first) and not any(e.kind in zero for e in second) and second.v_end != 0


def proof_lines(path=None) -> dict:
    """Per scene of ``PROOF_SCENES``, what ``prove --claim dissip-invariance --shipped`` proved
    (the shipped ``PROOF_PATH``): ``PROVED`` (a cover of the rest states, each box returning
    to rest within one period), ``REFUTED BY PROOF`` (a counterexample ball) or ``UNDECIDED``,
    with the statement; one line saying how to make the file if it is missing."""
    path = PROOF_PATH if path is None else pathlib.Path(path)
    if not path.exists():
        return {"missing": f"not computed: python -m cross_check prove --claim dissip-invariance --shipped "
                           f"writes {path.name}"}
    words = {"proved": "PROVED", "refuted": "REFUTED BY PROOF", "undecided": "UNDECIDED"}
    out = {}
    for rec in json.loads(path.read_text())["scenes"]:
        line = {"verdict": words[rec["verdict"]], "scene": rec["scene"]["name"], "statement": rec["reason"]}
        if rec["verdict"] == "proved":
            line["boxes"] = len(rec["boxes"])
            line["longest_return_bound"] = max(b["return_within"] for b in rec["boxes"])
        ce = rec["counterexample"]
        if ce is not None:
            line["statement"] = (f"every start of x = {ce['x'][0]!r} +- {ce['x'][1]:.3g}, v = "
                                 f"{ce['v'][0]!r} +- {ce['v'][1]:.3g} has v = 0 before t = "
                                 f"{ce['zero_before']:.6g} <= T and v != 0 on all of [T, 2T]")
        out[rec["label"]] = line
    return out


@claim("dissip-invariance",
       "Phi(Omega_dissip) is a subset of Omega_dissip (Fig. fig:regs): a solution with zero velocity "
       "during one period has zero velocity at least once in each later period",
       {"grid": "n x n states (cell centres) per scene; fig:regs scene identified as wide f=0.6"},
       note="membership by definition (fast.zero_velocity). Holds on the grid for the scene of Fig. fig "
            "(identified by its eigenvalues); NOT a general property: in the scenes of Fig. f005 and "
            "narrow-with-friction some dissipative states map to non-sticking ones (first one confirmed "
            "by reference event logs). numbers.proof: per scene PROVED (every rest state returns to rest "
            "within one period, a cover by boxes) or REFUTED BY PROOF (a counterexample ball), from the "
            "shipped cross_check/data/dissip_invariance.json (prove --claim dissip-invariance --shipped)")
def dissip_invariance(quick):
    n = 40 if quick else 150
    out = {}
    for label, sc, vr in REGION_SCENES:
        res = dissipative_invariance(sc, *cell_grid(sc, n, vr))
        res["violations"] = res["violations"][:5]
        if res["violations"]:
            res["reference_confirms_first_violation"] = _confirm_violation(sc, *res["violations"][0])
        out[label] = res
    out["proof"] = proof_lines()
    ok = out["wide_f0.6"]["n_violations"] == 0
    return Outcome("reproduced" if ok else "not reproduced", out, parameters={
        "grid": f"{n} x {n} states (cell centres) per scene; fig:regs scene identified as wide f=0.6"})


@claim("area-preservation",
       "for non-sticking trajectories det Phi' = 1 (area preservation); a turning point gives "
       "|det Phi'| < 1, a sticking interval det Phi' = 0",
       {"grid": "n x n per scene"})
def area_preservation(quick):
    import fast
    n = 40 if quick else 120
    out = {}
    for label, sc, vr in REGION_SCENES:
        x, v = cell_grid(sc, n, vr)
        _, _, J, zv = fast.map_and_jacobian(sc, x, v)
        det = np.linalg.det(np.where(np.isfinite(J), J, 0.0))
        fin = np.isfinite(J).all(axis=(-1, -2))
        pres, dis = fin & ~zv, fin & zv
        out[label] = {"n": int(x.size), "n_nonsticking": int(pres.sum()), "n_zero_velocity": int(dis.sum()),
                      "n_undefined": int((~fin).sum()),
                      "max_abs_det_minus_1_nonsticking": float(np.max(abs(det[pres] - 1), initial=0.0)),
                      "max_abs_det_zero_velocity": float(np.max(abs(det[dis]), initial=0.0)),
                      "n_zero_velocity_with_unit_det": int((abs(abs(det[dis]) - 1) <= 1e-9).sum())}
    ok = all(o["max_abs_det_minus_1_nonsticking"] < 1e-9 and o["n_zero_velocity_with_unit_det"] == 0 for o in out.values())
    return Outcome("reproduced" if ok else "not reproduced", out, parameters={"grid": f"{n} x {n} per scene"})


def _fd_ref_jacobian(scene, x, v, dps=60, step=None):
    """Central differences of the reference map at ``dps`` digits (step 1e-22)."""
    with mpmath.workdps(dps):
        h = step or mpmath.mpf(10) ** -22
        cols = []
        for dx, dv in ((h, 0), (0, h)):
            p = reference.stroboscopic_map(scene, x + dx, v + dv, dps=dps)
            m = reference.stroboscopic_map(scene, x - dx, v - dv, dps=dps)
            cols.append([(p[i] - m[i]) / (2 * h) for i in range(2)])
        return mpmath.matrix([[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]])


def _table1_symmetric(sc, sign):
    """Table 1 product over [0, T] along the corrected x_2 (impact at r then l); ``sign = -1``
    uses the velocity AFTER each impact in the reflection matrix."""
    sol = P.symmetric_solution(sc, 2)
    F, w, T = sc.mpf("F"), sc.mpf("omega"), period(sc)
    t_r = sol.tau / w
    t_l = t_r + sol.half_period
    Ir = P.reflection_matrix(F, w, t_r, sign * sol.v_impact)
    Il = P.reflection_matrix(F, w, t_l, -sign * sol.v_impact)
    return P.flight_matrix(T - t_l) * Il * P.flight_matrix(t_l - t_r) * Ir * P.flight_matrix(t_r), sol.state0()


@claim("table1-matrices",
       "Phi' is the time-ordered product of Table 1's matrices: flight [[1, dt], [0, 1]], sticking "
       "[[1, 0], [0, 0]], reflection [[-1, 0], [2F cos(w t*)/x'(t*), -1]], turning point "
       "[[1, 0], [0, (|F cos w t~| - f)/(|F cos w t~| + f)]]",
       {"fd": "central differences of the reference map, 60 digits, step 1e-22"},
       note="x'(t*) in the reflection matrix must be read as the velocity BEFORE the impact: with the "
            "velocity after it the product misses the finite-difference Jacobian by O(1)")
def table1(quick):
    import fast
    out = {}
    with mpmath.workdps(60):
        sc = wide("0.3")
        for label, sign in (("v_before", 1), ("v_after", -1)):
            M, (x0, v0) = _table1_symmetric(sc, sign)
            out[f"x2_wide_f0.3_table1_{label}_minus_fd"] = fl(mpmath.mnorm(M - _fd_ref_jacobian(sc, x0, v0), 1))
        states = [("impacts_x2_wide_f0.3", sc, x0, v0),
                  ("turns_wide_f0.3", sc, mpmath.mpf(8), P.no_impact_attractor(sc)["v0"]),
                  ("sticks_wide_f0.6", wide("0.6"), mpmath.mpf(9), P.no_impact_attractor(wide("0.6"))["v0"]),
                  ("mixed_narrow_f0.005", narrow("0.005"), mpmath.mpf("0.3"), mpmath.mpf("0.5"))]
        for label, s, x, v in states:
            J = mpmath.matrix(reference.jacobian(s, x, v, dps=60))
            Jf = np.asarray(fast.jacobian(s, float(x), float(v)), float)
            out[f"{label}_reference_minus_fd"] = fl(mpmath.mnorm(J - _fd_ref_jacobian(s, x, v), 1))
            out[f"{label}_fast_minus_reference"] = float(np.max(abs(Jf - np.array(J.tolist(), dtype=float))))
            out[f"{label}_itinerary"] = itinerary(s, x, v)
    ok = all(out[k] < 1e-25 for k in out if k.endswith("reference_minus_fd")) and out["x2_wide_f0.3_table1_v_before_minus_fd"] < 1e-25
    return Outcome("reproduced" if ok else "not reproduced", out)
