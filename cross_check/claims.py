"""The claims table: every numerically checkable statement of the paper, with a verdict.

``run_claims(quick=False)`` returns one dict per claim: ``id``, ``statement`` (the paper's words),
``verdict`` (``reproduced`` | ``not reproduced`` | ``erratum``), ``corrected`` (for errata),
``parameters`` and ``numbers`` (named values), plus a ``note``.  Closed forms come from
``reference.paper``; fixed points are searched with ``fast.analysis`` (float64 Newton from a grid)
and refined with a Newton iteration on the reference integrator at 50 digits (``ref_newton``);
thresholds (f_crit, R*) solve an extended system (fixed point + a multiplier condition) by Newton
on the reference map.  ``python -m cross_check claims [--json FILE] [--quick] [--only ID ...]``.
"""
from __future__ import annotations

import functools
import json
import time
from collections import Counter

import mpmath
import numpy as np

import reference
from reference import paper as P
from reference.scene import Scene

DPS = 50
MAX_NEWTON = 60
#: event counts of a periodic orbit are taken over [SHIFT T, (SHIFT + 1) T] (no event at the window ends)
SHIFT = mpmath.mpf("0.3183")


def claim(cid, statement, verdict, parameters, numbers, corrected=None, note=""):
    """One row of the table (``verdict`` checked)."""
    if verdict not in ("reproduced", "not reproduced", "erratum"):
        raise ValueError(f"verdict must be reproduced|not reproduced|erratum, got {verdict!r}")
    if (verdict == "erratum") != (corrected is not None):
        raise ValueError(f"claim {cid}: 'corrected' is required exactly for an erratum")
    return {"id": cid, "statement": statement, "verdict": verdict, "corrected": corrected,
            "parameters": parameters, "numbers": numbers, "note": note}


def fl(value):
    """An mpf as a float (JSON-friendly); complex as [re, im]."""
    if isinstance(value, (mpmath.mpc, complex)):
        return [float(mpmath.re(value)), float(mpmath.im(value))]
    return float(value)


def period(scene):
    return 2 * mpmath.pi / scene.mpf("omega")


# --- reference-based tools ---------------------------------------------------------------
def ref_map_jac(scene, x, v, k=1, dps=DPS):
    """``Phi^k(z)`` and ``J_k`` on the reference integrator (mpmath matrix)."""
    J = mpmath.eye(2)
    for _ in range(k):
        Jj = reference.jacobian(scene, x, v, dps=dps)
        J = mpmath.matrix(Jj) * J
        x, v = reference.stroboscopic_map(scene, x, v, dps=dps)
    return x, v, J


def _clip(scene, x):
    """Clip into the gap; the walls rounded inward by 2 ulp (an exact "0.8" rounds up at 50 digits)."""
    l, r = scene.mpf("l"), scene.mpf("r")
    eps = mpmath.mpf(2) ** (-mpmath.mp.prec + 2)
    return min(max(x, l + abs(l) * eps), r - abs(r) * eps)


def _pinv_solve(A, b):
    """Minimum-norm least-squares solution by SVD (singular values below 1e-30 |A| dropped):
    Newton on a segment of fixed points (a multiplier 1, ``J - I`` of rank 1) still converges."""
    U, S, V = mpmath.svd_r(A)
    cut = max(S) * mpmath.mpf(10) ** -30
    y = U.T * b
    for i in range(len(S)):
        y[i] = y[i] / S[i] if S[i] > cut else 0
    return V.T * y


def ref_newton(scene, x, v, *, k=1, dps=DPS):
    """Newton on ``Phi^k(z) = z`` with the reference map and Jacobian; returns ``(x, v, J, residual)``."""
    with mpmath.workdps(dps):
        x, v = _clip(scene, mpmath.mpf(x)), mpmath.mpf(v)
        goal = mpmath.mpf(10) ** (-(dps - 8))
        for _ in range(MAX_NEWTON):
            X, V, J = ref_map_jac(scene, x, v, k, dps)
            g = mpmath.matrix([X - x, V - v])
            res = max(abs(g[0]), abs(g[1]))
            if res < goal:
                return x, v, J, res
            d = _pinv_solve(J - mpmath.eye(2), -g)
            x, v = _clip(scene, x + d[0]), v + d[1]
        raise RuntimeError(f"ref_newton: no convergence from x={x}, v={v}, k={k}, residual={res}")


def extended_newton(make_scene, p0, x0, v0, condition, *, dps=DPS, h=None):
    """Solve ``Phi(z; p) = z`` and ``condition(J) = 0`` for ``(x, v, p)`` (Newton, FD Jacobian).

    ``make_scene(p)`` builds the scene for parameter ``p``; ``condition(J)`` is e.g. ``tr J - 2``
    (a fold) or ``tr J + 1`` (3:1 resonance).  Returns ``(p, x, v, J)``.
    """
    with mpmath.workdps(dps):
        h = h or mpmath.mpf(10) ** (-(dps // 3))
        u = mpmath.matrix([x0, v0, p0])

        def F(u):
            sc = make_scene(u[2])
            X, V, J = ref_map_jac(sc, u[0], u[1], 1, dps)
            return mpmath.matrix([X - u[0], V - u[1], condition(J)]), J

        for _ in range(MAX_NEWTON):
            r, J = F(u)
            if mpmath.norm(r, mpmath.inf) < mpmath.mpf(10) ** (-(dps - 10)):
                return u[2], u[0], u[1], J
            D = mpmath.matrix(3, 3)
            for j in range(3):
                e = mpmath.matrix(3, 1)
                e[j] = h
                D[:, j] = (F(u + e)[0] - F(u - e)[0]) / (2 * h)
            u = u - mpmath.lu_solve(D, r)
        raise RuntimeError(f"extended_newton: no convergence, p={u[2]}, residual={mpmath.norm(r)}")


def itinerary(scene, x, v, periods=1, dps=30, shift=None):
    """Event counts over ``[0, periods T]``; frictionless velocity zeros counted as ``"turn"``.

    The reference logs no event when ``v`` passes 0 without friction; there the flight
    ``v(t) = v_a + F/w (sin wt - sin wt_a)`` between events is sampled (256 points) for sign changes.
    ``shift = s``: count over ``[s T, (s + periods) T]`` instead (for a periodic orbit with an event
    exactly at ``t = 0``, which a window starting at 0 would count ambiguously).
    """
    T = period(scene)
    if shift is not None:
        pre = reference.trajectory(scene, x, v, shift * T, dps=dps)
        log = reference.trajectory(scene, pre.x_end, pre.v_end, (shift + periods) * T, t0=pre.t_end, dps=dps)
    else:
        log = reference.trajectory(scene, x, v, periods * T, dps=dps)
    counts = Counter(e.kind for e in log)
    if not scene.has("friction"):
        F, w = scene.mpf("F"), scene.mpf("omega")
        marks = [(log.t0, log.v0)] + [(e.t, e.v) for e in log] + [(log.t_end, None)]
        zeros = 0
        for (ta, va), (tb, _) in zip(marks, marks[1:]):
            vs = [va + F / w * (mpmath.sin(w * (ta + (tb - ta) * j / 256)) - mpmath.sin(w * ta))
                  for j in range(1, 256)]
            zeros += sum(1 for a, b in zip(vs, vs[1:]) if a * b < 0)
        counts["turn"] += zeros
    return dict(counts)


def zero_velocity_free(counts):
    """True when an itinerary has no zero velocity (non-sticking)."""
    return not any(counts.get(k, 0) for k in ("turn", "stick", "slip", "contact", "chatter", "release"))


def _fast_points(scene, period=1, v_range=(-2.0, 2.0), grid=(24, 24), x_range=None):
    from fast import analysis  # imported lazily: the claims that need no fast run without it
    return analysis.find_periodic_points(scene, period=period, v_range=v_range, grid=grid,
                                         x_range=x_range)


def _refined(scene, p, dps=DPS):
    """Refine a fast periodic point with ``ref_newton``; multipliers and itinerary."""
    x, v, J, res = ref_newton(scene, p.x, p.v, k=p.period, dps=dps)
    with mpmath.workdps(dps):
        lam = mpmath.eig(J)[0]
        out = {"x": x, "v": v, "residual": res, "trace": J[0, 0] + J[1, 1], "det": mpmath.det(J),
               "multipliers": sorted(lam, key=lambda z: (float(mpmath.re(z)), float(mpmath.im(z))))}
    out["itinerary"] = itinerary(scene, x, v, periods=p.period)
    out["kind"], out["stability"] = p.kind, p.stability
    return out


# --- scenes -----------------------------------------------------------------------------------
def wide(f):
    """Fig. wide:b / many:wide: F = 1, w = 1, l = 0, r = 20."""
    return Scene(F=1, f=f, omega=1, l=0, r=20)


def two_pi(f):
    """Fig. many:2pi: F = 1, w = 2 pi, l = -1, r = 1."""
    return Scene(F=1, f=f, omega="2*pi", l=-1, r=1)


def narrow(f):
    """Fig. narrow / narrow-with-friction: F = 1, w = 1, l = 0, r = 0.8."""
    return Scene(F=1, f=f, omega=1, l=0, r="0.8")


def resonance(r):
    """Fig. resonance: w = 2 pi, F = w^2, f = 24.65, l = 0."""
    return Scene(F="(2*pi)**2", f="24.65", omega="2*pi", l=0, r=r)


# --- claims from the closed forms -------------------------------------------------------------
def c_symmetric_solutions(quick):
    out = {}
    with mpmath.workdps(DPS):
        for name, sc in (("wide_f0.3", wide("0.3")), ("2pi_f0.05", two_pi("0.05"))):
            for b in (1, 2):
                sol = P.symmetric_solution(sc, b)
                x0, v0 = sol.state0()
                X, V = reference.stroboscopic_map(sc, x0, v0, dps=DPS)
                out[f"{name}_x{b}_fixed_point_residual"] = fl(max(abs(X - x0), abs(V - v0)))
                out[f"{name}_x{b}_itinerary"] = itinerary(sc, x0, v0)
                out[f"{name}_x{b}_printed_minus_true_at_0"] = fl(P.printed_nonstick(sc, b, 0) - x0)
        sc = wide("0.3")
        k = P.printed_nonstick_constants(sc, 2)
        eps = mpmath.mpf(10) ** -40
        out["wide_f0.3_printed_x2_after_impact"] = fl(P.printed_nonstick(sc, 2, k["tau"] + eps))
        out["wide_f0.3_r"] = 20.0
    return claim(
        "symmetric-solutions",
        "symmetric periodic solutions x(t) = -x(t + pi/w) + r + l are defined by eq. (nonstick) "
        "with psi_1 = pi + arcsin(pi f/2F), psi_2 = -arcsin(pi f/2F), tau_{1,2} = psi_{1,2} -+ pi, C, D",
        "erratum", {"scenes": {"wide_f0.3": "F=1,f=0.3,w=1,l=0,r=20", "2pi_f0.05": "F=1,f=0.05,w=2pi,l=-1,r=1"}},
        out,
        corrected="second piece: r + l - F/w^2 cos wt + f/2 (t - (psi+pi)/w)^2 - C (t - (psi+pi)/w) - D "
                  "(the printed one lacks r + l); psi_1 = arcsin(pi f/2F) - pi (printed psi_1 is one "
                  "period late); tau_{1,2} = psi_{1,2} + pi (same values as printed); C, D, psi_2 right",
        note="corrected orbits are fixed points of the reference map to ~1e-45 with exactly 2 impacts "
             "and no zero velocity; printed x_2 is right only when l = -r (Fig. many:2pi)")


def c_existence(quick):
    with mpmath.workdps(DPS):
        bound = P.existence_bound()
        out = {"bound_2_over_pi": fl(bound)}
        for label, f in (("below", bound * (1 - mpmath.mpf(10) ** -6)), ("above", bound * (1 + mpmath.mpf(10) ** -6))):
            sc = wide(f)
            sols = [P.symmetric_solution(sc, b) for b in (1, 2)]
            out[f"{label}_exists"] = sols[0] is not None
            if sols[0] is not None:
                x0, v0 = sols[0].state0()
                X, V = reference.stroboscopic_map(sc, x0, v0, dps=DPS)
                out[f"{label}_fixed_point_residual"] = fl(max(abs(X - x0), abs(V - v0)))
    return claim("existence-condition", "necessary condition for x_{1,2}: f/F <= 2/pi",
                 "reproduced", {"scene": "F=1,w=1,l=0,r=20, f = (2/pi)(1 -+ 1e-6)"}, out,
                 note="derived: the velocity must repeat after a half period, -2F sin psi = pi f")


def c_nonstick_condition(quick):
    out = {}
    with mpmath.workdps(DPS):
        diffs = []
        for sc in (wide("0.3"), two_pi("0.05"), resonance("0.8932"), Scene(F=1, f="0.1", omega=1, l=0, r="1.8")):
            lhs = P.nonstick_condition_printed(sc)
            diffs.append(abs(lhs - P.nonstick_margin(sc, 1)))
        out["max_abs_printed_lhs_minus_pi_w_vmin_x1"] = fl(max(diffs))
        sc = Scene(F=1, f="0.1", omega=1, l=0, r="1.8")
        out["counterexample_printed_lhs"] = fl(P.nonstick_condition_printed(sc))
        out["counterexample_x2_min_velocity"] = fl(P.symmetric_solution(sc, 2).min_flight_velocity()[0])
        out["counterexample_x1_min_velocity"] = fl(P.symmetric_solution(sc, 1).min_flight_velocity()[0])
        for b in (1, 2):
            x0, v0 = P.symmetric_solution(sc, b).state0()
            X, V = reference.stroboscopic_map(sc, x0, v0, dps=DPS)
            out[f"counterexample_x{b}_fixed_point_residual"] = fl(max(abs(X - x0), abs(V - v0)))
    return claim(
        "nonstick-condition",
        "non-sticking condition (eq. nonstick:cond): sqrt(4F^2 - pi^2 f^2) - pi sqrt(F^2 - f^2) + "
        "pi f (arcsin(pi f/2F) - arcsin(f/F)) + R w^2 > 0",
        "erratum", {"counterexample": "F=1,f=0.1,w=1,l=0,r=1.8"}, out,
        corrected="eq. nonstick:cond is exactly pi w min x_1' > 0 (the condition for x_1); x_2 needs "
                  "min over its up-flight of x_2' > 0, i.e. R w^2 > sqrt(4F^2 - pi^2 f^2) and, when "
                  "arccos(f/F) <= arcsin(pi f/2F), the interior minimum positive (paper.nonstick_margin)",
        note="counterexample: the printed side is > 0 but x_2 would start at l moving left; it is not "
             "a fixed point of Phi (residual O(1)) while x_1 is (~1e-45)")


def c_fold_reduced(quick):
    out = {}
    with mpmath.workdps(DPS):
        bound = P.fold_reduced_bound()
        out["bound"] = fl(bound)
        for label, fac in (("above", 1 + mpmath.mpf("0.01")), ("below", 1 - mpmath.mpf("0.01"))):
            sc = Scene(F=1, f="2/pi", omega=1, l=0, r=bound * fac)
            sol = P.symmetric_solution(sc, 1)
            x0, v0 = sol.state0()
            X, V = reference.stroboscopic_map(sc, x0, v0, dps=DPS)
            out[f"{label}_min_velocity"] = fl(sol.min_flight_velocity()[0])
            out[f"{label}_fixed_point_residual"] = fl(max(abs(X - x0), abs(V - v0)))
            out[f"{label}_itinerary"] = itinerary(sc, x0, v0)
    return claim("fold-reduced-condition",
                 "at the fold f/F = 2/pi, eq. nonstick:cond reduces to w^2 R/F > sqrt(pi^2 - 4) - 2 arccos(2/pi)",
                 "reproduced", {"scene": "F=1, f=2/pi, w=1, l=0, R = bound (1 +- 0.01)"}, out,
                 note="fold orbit: a non-sticking fixed point of Phi above the bound; below it its "
                      "velocity vanishes and it is no solution")


def c_no_impact(quick):
    out = {"printed_condition_F1_w1_R1.5": P.no_impact_condition_printed(Scene(F=1, f=0, omega=1, l=0, r="1.5"))}
    n = 6 if quick else 16
    for R in ("1.5", "4"):
        sc = Scene(F=1, f=0, omega=1, l=0, r=R)
        fixed_no_impact = []
        for j in range(n + 1):
            x = mpmath.mpf(R) * j / n
            counts = itinerary(sc, x, 0)
            X, V = reference.stroboscopic_map(sc, x, 0, dps=30)
            if not counts.get("impact") and abs(X - x) + abs(V) < 1e-20:
                fixed_no_impact.append(fl(x))
        out[f"R{R}_fixed_no_impact_starts"] = fixed_no_impact
        out[f"R{R}_grid_points"] = n + 1
    out["R4_segment_closed_form"] = [0.0, 2.0]
    return claim("no-impact-solutions",
                 "when R > F/w^2, the system has periodic solutions without impacts x = -F/w^2 cos wt + C",
                 "erratum", {"scenes": "F=1,f=0,w=1,l=0, r in {1.5, 4}; starts (x, 0) on a grid"}, out,
                 corrected="R >= 2F/w^2 (the excursion of -F/w^2 cos wt is 2F/w^2); l + F/w^2 <= C <= r - F/w^2",
                 note="R = 1.5 satisfies the printed condition, but no start (x, 0) is a no-impact fixed point")


# --- claims needing fixed points ---------------------------------------------------------------
def _pick(points, kind):
    return [p for p in points if p.kind == kind]


def c_fold_fcrit(quick):
    grid = (12, 8) if quick else (40, 24)
    out = {"closed_form_2F_over_pi": fl(P.fold_friction(wide(1)))}
    counts = {}
    for f in (("0.6",) if quick else ("0.1", "0.2", "0.3", "0.4", "0.5", "0.6")) + ("0.63", "0.64"):
        pts = _fast_points(wide(f), v_range=(0.0, 12.0), grid=grid)
        counts[f] = {k: sum(1 for p in _pick(pts, k) if abs(p.det - 1) < 1e-9) for k in ("centre", "saddle")}
    out["fast_nonsticking_fixed_points_by_f"] = counts
    pts = _fast_points(wide("0.63"), v_range=(0.0, 12.0), grid=grid)
    c, s = _pick(pts, "centre")[0], _pick(pts, "saddle")[0]
    with mpmath.workdps(DPS):
        fc, x, v, J = extended_newton(wide, mpmath.mpf("0.63"), (c.x + s.x) / 2, (c.v + s.v) / 2,
                                      lambda J: J[0, 0] + J[1, 1] - 2)
        sol = P.symmetric_solution(wide(P.fold_friction(wide(1))), 1)
        out.update(f_crit_from_fixed_points=fl(fc), f_crit_minus_2_over_pi=fl(fc - 2 / mpmath.pi),
                   fold_point=[fl(x), fl(v)], fold_point_closed_form=[fl(a) for a in sol.state0()],
                   fold_det=fl(mpmath.det(J)))
    ok = abs(out["f_crit_minus_2_over_pi"]) < 1e-12 and counts["0.64"]["centre"] == 0 and counts["0.63"]["centre"] == 1
    return claim("fold-fcrit",
                 "the island disappears in a saddle-centre bifurcation of two non-sticking periodic orbits at "
                 "f = f_crit (Fig. fold; all parameters but f as in Fig. wide:b)",
                 "reproduced" if ok else "not reproduced", {"scene": "F=1, w=1, l=0, r=20"}, out,
                 note="f_crit solves Phi(z; f) = z with tr Phi' = 2 (Newton on the reference map, FD "
                      "Jacobian) from the fast centre/saddle pair at f = 0.63; it equals 2F/pi (eq. fold:bif)")


def c_resonance(quick):
    grid = (10, 10) if quick else (24, 24)
    out = {}
    with mpmath.workdps(DPS):
        closed = P.resonance_gaps(resonance("0.8932"))[0]
        for r in ("0.89", "0.8932", "0.895"):
            pts = _pick(_fast_points(resonance(r), v_range=(0.0, 3.0), grid=grid), "centre")
            out[f"R{r}_centres"] = len(pts)
            if pts:
                ref = _refined(resonance(r), pts[0])
                out[f"R{r}_fixed_point"] = [fl(ref["x"]), fl(ref["v"])]
                out[f"R{r}_trace"] = fl(ref["trace"])
                out[f"R{r}_itinerary"] = ref["itinerary"]
        p0 = _pick(_fast_points(resonance("0.8932"), v_range=(0.0, 3.0), grid=grid), "centre")[0]
        R, x, v, J = extended_newton(resonance, mpmath.mpf("0.8932"), p0.x, p0.v, lambda J: J[0, 0] + J[1, 1] + 1)
        lam = mpmath.eig(J)[0]
        out.update(R_star=fl(R), R_star_closed_form=fl(closed), R_star_minus_closed=fl(R - closed),
                   fixed_point_at_R_star=[fl(x), fl(v)], multipliers_at_R_star=[fl(z) for z in lam],
                   multiplier_angle_over_2pi=fl(abs(mpmath.arg(lam[0])) / (2 * mpmath.pi)))
    if not quick:
        out["nonlinear_escape"] = _resonance_escape()
    return claim("resonance-3-1",
                 "when R = R* ~ 0.8932 three separatrices meet at a non-sticking fixed point (3:1 resonance); "
                 "the fixed point is neutrally stable near R* (Fig. resonance: w = 2 pi, F = w^2, f = 24.65)",
                 "reproduced", {"scene": "F=(2pi)^2, f=24.65, w=2pi, l=0, r=R"}, out,
                 note="R* from Phi(z; R) = z with tr Phi' = -1 (multipliers exp(+-2 pi i/3)); closed form "
                      "R* = S (pi^2/3 - 1)/w^2, S = sqrt(4F^2 - pi^2 f^2) (reference.paper.resonance_gaps). "
                      "The paper's 0.8932 is R* = 0.89330 truncated to 4 decimals. Full run: orbits from "
                      "1e-4 off the fixed point stay within ~8e-4 for R = 0.89, 0.895 and escape to O(0.4) at "
                      "R* (nonlinear instability at the resonance)")


def _resonance_escape(delta=1e-4, n=1200, directions=8):
    """Nonlinear stability: max over ``n`` iterates (fast.orbit) of |z_k - z*| / delta from
    ``z* + delta (cos a, sin a)``; bounded (~5-8, elliptic invariant curves) near R*, escaping at R*."""
    import fast
    out = {}
    for r in ("0.89", "R*", "0.895"):
        with mpmath.workdps(DPS):
            R = P.resonance_gaps(resonance("0.8932"))[0] if r == "R*" else mpmath.mpf(r)
            sc = resonance(R)
            x0, v0 = (float(c) for c in P.symmetric_solution(sc, 1).state0())
        a = np.linspace(0, 2 * np.pi, directions, endpoint=False)
        X, V = fast.orbit(sc, np.clip(x0 + delta * np.cos(a), 0, float(R)), v0 + delta * np.sin(a), n)
        out[r] = [round(float(d), 1) for d in np.hypot(X - x0, V - v0).max(axis=0) / delta]
    return {"delta": delta, "iterations": n, "max_distance_over_delta": out}


def c_eigenvalues(quick):
    grid = (12, 12) if quick else (30, 30)
    out = {}
    for label, sc, vr in (("f005_scene", two_pi("0.05"), (-6.0, 6.0)), ("wide_f0.6", wide("0.6"), (0.0, 12.0))):
        saddles = [p for p in _fast_points(sc, v_range=vr, grid=grid) if p.kind == "saddle" and abs(p.det - 1) < 1e-9]
        out[f"{label}_saddles"] = []
        for p in saddles:
            ref = _refined(sc, p)
            out[f"{label}_saddles"].append({"x": fl(ref["x"]), "v": fl(ref["v"]),
                                            "multipliers": sorted(fl(mpmath.re(z)) for z in ref["multipliers"]),
                                            "itinerary": ref["itinerary"]})
    target = (0.3159, 3.1659)
    hit = lambda lst: any(abs(s["multipliers"][0] - target[0]) < 5e-5 and abs(s["multipliers"][1] - target[1]) < 5e-5 for s in lst)
    out["matches_in_f005_scene"] = hit(out["f005_scene_saddles"])
    out["matches_in_wide_f0.6"] = hit(out["wide_f0.6_saddles"])
    return claim("eigenvalues-fig7",
                 "the unstable fixed point (red star, Fig. fig:regions) has eigenvalues 0.3159 and 3.1659",
                 "reproduced" if out["matches_in_wide_f0.6"] else "not reproduced",
                 {"identified_scene": "F=1, f=0.6, w=1, l=0, r=20 (Fig. many:wide f)",
                  "also_tried": "F=1, f=0.05, w=2pi, l=-1, r=1 (Fig. f005)"}, out,
                 note="the caption names no parameters; for the f005 scene the saddle has 0.36757/2.72054, "
                      "for Fig. many:wide f (f = 0.6) 0.315865/3.165911 = the paper's values to 4 decimals; "
                      "product 1 (non-sticking, det = 1)")


def _grid(scene, n, v_range):
    l, r = scene.float("l"), scene.float("r")
    xs = l + (np.arange(n) + 0.5) / n * (r - l)
    vs = v_range[0] + (np.arange(n) + 0.5) / n * (v_range[1] - v_range[0])
    X, V = np.meshgrid(xs, vs, indexing="ij")
    return X.ravel(), V.ravel()


def _confirm_violation(sc, x, v):
    """Reference check of a state in Omega_dissip whose image is in Omega_pres: zero velocity on
    [0, T], none on [T, 2T] (event logs at 30 digits)."""
    zero = ("turn", "stick", "contact", "chatter")
    T = period(sc)
    first = reference.trajectory(sc, x, v, T, dps=30)
    second = reference.trajectory(sc, first.x_end, first.v_end, 2 * T, t0=first.t_end, dps=30)
    return any(e.kind in zero for e in first) and not any(e.kind in zero for e in second) and second.v_end != 0


def c_dissip_invariance(quick):
    from fast import analysis
    n = 40 if quick else 150
    out = {}
    for label, sc, vr in (("wide_f0.6", wide("0.6"), (-4.0, 10.0)), ("2pi_f0.05", two_pi("0.05"), (-6.0, 6.0)),
                          ("narrow_f0.005", narrow("0.005"), (-2.0, 2.0))):
        res = analysis.dissipative_invariance(sc, *_grid(sc, n, vr))
        res["violations"] = res["violations"][:5]
        if res["violations"]:
            res["reference_confirms_first_violation"] = _confirm_violation(sc, *res["violations"][0])
        out[label] = res
    ok = out["wide_f0.6"]["n_violations"] == 0
    return claim("dissip-invariance",
                 "Phi(Omega_dissip) is a subset of Omega_dissip (Fig. fig:regs): a solution with zero velocity "
                 "during one period has zero velocity at least once in each later period",
                 "reproduced" if ok else "not reproduced",
                 {"grid": f"{n} x {n} states (cell centres) per scene; fig:regs scene identified as wide f=0.6"}, out,
                 note="membership by definition (fast.zero_velocity). Holds on the grid for the scene of Fig. fig "
                      "(identified by its eigenvalues); NOT a general property: in the scenes of Fig. f005 and "
                      "narrow-with-friction some dissipative states map to non-sticking ones (first one confirmed "
                      "by reference event logs)")


def c_area_preservation(quick):
    import fast
    n = 40 if quick else 120
    out = {}
    for label, sc, vr in (("wide_f0.6", wide("0.6"), (-4.0, 10.0)), ("2pi_f0.05", two_pi("0.05"), (-6.0, 6.0)),
                          ("narrow_f0.005", narrow("0.005"), (-2.0, 2.0))):
        x, v = _grid(sc, n, vr)
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
    return claim("area-preservation",
                 "for non-sticking trajectories det Phi' = 1 (area preservation); a turning point gives "
                 "|det Phi'| < 1, a sticking interval det Phi' = 0",
                 "reproduced" if ok else "not reproduced", {"grid": f"{n} x {n} per scene"}, out)


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


def c_table1(quick):
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
    return claim("table1-matrices",
                 "Phi' is the time-ordered product of Table 1's matrices: flight [[1, dt], [0, 1]], sticking "
                 "[[1, 0], [0, 0]], reflection [[-1, 0], [2F cos(w t*)/x'(t*), -1]], turning point "
                 "[[1, 0], [0, (|F cos w t~| - f)/(|F cos w t~| + f)]]",
                 "reproduced" if ok else "not reproduced",
                 {"fd": "central differences of the reference map, 60 digits, step 1e-22"}, out,
                 note="x'(t*) in the reflection matrix must be read as the velocity BEFORE the impact: with the "
                      "velocity after it the product misses the finite-difference Jacobian by O(1)")


def c_lift(quick):
    out = {}
    sc = wide("0.3")
    with mpmath.workdps(DPS):
        R, l, r = 20, sc.mpf("l"), sc.mpf("r")
        d = mpmath.mpf(10) ** -12
        starts = [P.symmetric_solution(sc, 1).state0(), (mpmath.mpf(5), mpmath.mpf(7))]
        res_c, res_p = [], []
        for x0, v0 in starts:
            for t in ((mpmath.mpf("1.3"), mpmath.mpf("4.1")) if quick else (mpmath.mpf(k) / 3 for k in range(1, 18))):
                qs = []
                for tt in (t - d, t, t + d):
                    log = reference.trajectory(sc, x0, v0, tt, dps=DPS)
                    k = sum(1 for e in log if e.kind == "impact")
                    if any(e.kind != "impact" for e in log):
                        raise RuntimeError("c_lift: the sample trajectory is not non-sticking")
                    up = (k % 2 == 0) == (v0 > 0)
                    base = (log.x_end - l) / R if up else (r - log.x_end) / R
                    qs.append(k + base if v0 > 0 else -k - base)
                qdd = (qs[2] - 2 * qs[1] + qs[0]) / d ** 2
                qd = (qs[2] - qs[0]) / (2 * d)
                res_c.append(abs(qdd - P.lift_rhs_corrected(sc, t, qs[1], qd)))
                res_p.append(abs(qdd - P.lift_rhs_printed(sc, t, qs[1])))
        out.update(max_residual_corrected=fl(max(res_c)), min_residual_printed=fl(min(res_p)),
                   max_residual_printed=fl(max(res_p)), samples=len(res_c))
    return claim("lift",
                 "non-sticking solutions of q'' + dV/dq = f/R, V = (F/R) cos(wt) W(q), map to non-sticking "
                 "solutions of (main)-(impact) by x = R W(q) + l (eqs. hamilsys, map)",
                 "erratum", {"scene": "F=1, f=0.3, w=1, l=0, r=20; starts: x_1 and (5, 7)"}, out,
                 corrected="q'' = (F/R) cos(wt) W'(q) - (f/R) sgn(q'), i.e. V = -(F/R) cos(wt) W(q) and "
                           "q'' + dV/dq = -(f/R) sgn q' (= -f/R for q' > 0)",
                 note="q(t) unfolded from reference trajectories (impact count), q'' by central differences "
                      "(step 1e-12, error ~1e-24); the printed equation has the forcing sign flipped")


def c_xpot(quick):
    sc = Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2")
    n = 20 if quick else 200
    out = {}
    with mpmath.workdps(30):
        (_, e_left), (e_right, _) = P.equilibrium_set(sc)
        eta = P.eta_printed(1, "0.1")
        out.update(eta_printed=fl(eta), E_corrected=[[-1.0, fl(e_left)], [fl(e_right), 1.0]],
                   E_printed=[[-1.0, fl(-1 + eta)], [fl(1 - eta), 1.0]])
        wrong_c = wrong_p = stays_n = 0
        for j in range(n + 1):
            x = -1 + 2 * mpmath.mpf(j) / n
            log = reference.trajectory(sc, x, 0, period(sc), dps=30)
            stays = log.x_end == x and log.v_end == 0 and not any(e.kind in ("slip", "turn", "release") for e in log)
            stays_n += stays
            wrong_c += stays != (x <= e_left or x >= e_right)
            wrong_p += stays != (x <= -1 + eta or x >= 1 - eta)
        out.update(grid_points=n + 1, n_stay_at_rest=stays_n, mismatches_corrected=wrong_c, mismatches_printed=wrong_p)
    return claim("xpot-equilibria",
                 "E consists of points with zero velocity at -1 <= x <= -1 + eta and 1 - eta <= x <= 1, "
                 "eta = (2/pi) arccos(f/F) (eq. xpot, F = 1, f = 0.1, w = 2 pi)",
                 "erratum", {"scene": "F=1, f=0.1, w=2pi, walls -1, 1, force F cos(pi x/2) cos(wt)"}, out,
                 corrected="E = [-1, -eta] U [eta, 1] with eta = (2/pi) arccos(f/F); equivalently the printed "
                           "intervals with eta = (2/pi) arcsin(f/F)",
                 note="rest at x persists iff |F cos(pi x/2)| <= f; checked by reference trajectories (position-"
                      "dependent forcing) from (x, 0) over one period on a grid")


def _continuation(make_scene, fs, x, v, k=1):
    """Follow a periodic point along parameter values ``fs`` with ``ref_newton``."""
    path = []
    for f in fs:
        x, v, J, _ = ref_newton(make_scene(f), x, v, k=k)
        path.append((f, x, v, J))
    return path


def c_focus_period5(quick):
    sc = narrow("0.005")
    box = dict(x_range=(0.4, 0.6), v_range=(-0.1, 0.1), grid=(5, 5)) if quick else dict(v_range=(-1.5, 1.5), grid=(24, 24))
    out = {}
    p1 = [p for p in _fast_points(sc, period=1, **box) if p.stability == "stable"]
    p5 = [p for p in _fast_points(sc, period=5, **box) if p.stability == "stable"]
    for label, pts in (("fixed", p1), ("period5", p5)):
        out[f"stable_{label}"] = []
        for p in pts:
            ref = _refined(sc, p)
            out[f"stable_{label}"].append({"x": fl(ref["x"]), "v": fl(ref["v"]), "kind": ref["kind"],
                                           "multipliers": [fl(z) for z in ref["multipliers"]],
                                           "abs_multipliers": [fl(abs(z)) for z in ref["multipliers"]],
                                           "itinerary": ref["itinerary"]})
    # continuation of the focus back to the neutral centre of Fig. zoom (f = 0.005 -> 0); upward from
    # f = 0 Newton would start at v = 0, where Phi is not smooth once f > 0
    foc = [s for s in out["stable_fixed"] if s["kind"] == "focus"]
    c0 = [p for p in _fast_points(narrow(0), period=1, x_range=(0.4, 0.6), v_range=(-0.1, 0.1), grid=(6, 6))
          if p.kind == "centre"]
    if foc and c0:
        path = _continuation(narrow, [mpmath.mpf(j) / 1000 for j in range(5, -1, -1)], foc[0]["x"], foc[0]["v"])
        out["continuation_f0.005_to_f0"] = [[fl(f), fl(x), fl(v), fl(J[0, 0] + J[1, 1]), fl(mpmath.det(J))]
                                            for f, x, v, J in path]
        out["continuation_end_minus_fast_centre_f0"] = fl(max(abs(path[-1][1] - c0[0].x), abs(path[-1][2] - c0[0].v)))
    ok = bool(foc) and bool(out["stable_period5"]) and all(s["itinerary"].get("turn", 0) > 0 for s in foc + out["stable_period5"])
    return claim("focus-and-period5",
                 "for f = 0.005 (Fig. narrow-with-friction) trajectories are attracted to an asymptotically stable "
                 "focus and a stable period-5 orbit, with turning points, traced back to the neutral fixed point "
                 "and period-5 orbit of Fig. zoom",
                 "reproduced" if ok else "not reproduced", {"scene": "F=1, f=0.005, w=1, l=0, r=0.8"}, out)


@functools.lru_cache(maxsize=2)
def c_narrow_centres(quick):
    """Islands of Fig. narrow (f = 0): centre A (2 impacts, no turning) and Fig. zoom's centre (4 impacts, 2 turns)."""
    grid = (16, 16) if quick else (30, 30)
    centres = []
    for f in ("0", "0.005"):
        for p in _pick(_fast_points(narrow(f), v_range=(-2.0, 2.0), grid=grid), "centre"):
            try:
                ref = _refined(narrow(f), p)
            except (ValueError, ZeroDivisionError, RuntimeError) as exc:
                centres.append({"f": f, "x": p.x, "v": p.v, "refinement_failed": f"{type(exc).__name__}: {exc}"})
                continue
            its = itinerary(narrow(f), ref["x"], ref["v"], shift=SHIFT)
            centres.append({"f": f, "x": fl(ref["x"]), "v": fl(ref["v"]), "trace": fl(ref["trace"]),
                            "det": fl(ref["det"]), "impacts": its.get("impact", 0), "turns": its.get("turn", 0),
                            "other_events": sum(n for k, n in its.items() if k not in ("impact", "turn"))})
    return centres


def c_island_a(quick):
    centres = c_narrow_centres(quick)
    two = [c for c in centres if c.get("impacts") == 2 and c.get("turns") == 0]
    a = [c for c in centres if c["f"] == "0.005" and c.get("turns") == 0 and abs(c.get("det", 0) - 1) < 1e-9]
    out = {"centres": centres, "centres_with_2_impacts_0_turns": len(two),
           "nonsticking_centres_at_f0.005": len(a), "impacts_of_island_A_centre": a[0]["impacts"] if a else None}
    if a:   # follow island A's centre towards f = 0: it runs into the wall x = r
        path = _continuation(narrow, [mpmath.mpf(j) / 10000 for j in range(50, 0, -5)],
                             a[0]["x"], a[0]["v"])
        out["continuation_to_small_f"] = [[fl(f), fl(x), fl(v), fl(J[0, 0] + J[1, 1])] for f, x, v, J in path]
        wall = [p for p in _fast_points(narrow(0), x_range=(0.7, 0.8), v_range=(-1.5, -1.1), grid=(6, 6))
                if p.kind == "centre" and p.x > 0.7]
        out["f0_wall_centre"] = [[p.x, p.v, p.trace] for p in wall]
    if two:
        verdict, corrected = "reproduced", None
    elif len(a) == 1:
        verdict, corrected = "erratum", f"{a[0]['impacts']} impacts per period ({a[0]['impacts'] // 2} round trips), no turning point"
    else:
        verdict, corrected = "not reproduced", None
    return claim("island-A",
                 "island A of Fig. narrow (f = 0, R = 0.8) is centred at a fixed point with two impacts per period "
                 "and no other turning points (non-sticking); it persists for f = 0.005",
                 verdict, {"scene": "F=1, w=1, l=0, r=0.8, f in {0, 0.005}; search box |v| <= 2"}, out,
                 corrected=corrected,
                 note="the only non-sticking centre that persists at f = 0.005 (det = 1, the island A of Fig. "
                      "narrow-with-friction) has 6 impacts per period and no turning point; at f = 0 it sits at the "
                      "wall (impact at t = 0). A one-round-trip non-sticking orbit cannot exist here: the "
                      "symmetric one needs R w^2 > (pi - 2) F = 1.14 > 0.8 (eq. nonstick:cond at f = 0); none "
                      "was found by the search (also with |v| <= 4)")


def c_fig1b_centre(quick):
    centres = [c for c in c_narrow_centres(quick) if c["f"] == "0"]
    four = [c for c in centres if c.get("impacts") == 4 and c.get("turns") == 2]
    return claim("fig1b-centre",
                 "the fixed point of the central island (Fig. zoom) corresponds to a periodic solution with four "
                 "impacts and two turning points per period",
                 "reproduced" if four else "not reproduced", {"scene": "F=1, f=0, w=1, l=0, r=0.8"},
                 {"centres": centres, "matching": four},
                 note="events counted over [0.3183 T, 1.3183 T]; without friction a turning point is a zero of "
                      "the velocity in flight")


def c_fig3_attractor(quick):
    import fast
    out = {}
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
    out["stick_threshold_f_over_F"] = fl(P.stick_threshold())
    return claim("fig3-attractor",
                 "the attractor of Fig. many:wide (periodic solutions without impacts) corresponds to periodic "
                 "orbits with two intervals of sticking per period",
                 "erratum", {"scene": "F=1, w=1, l=0, r=20, f = 0.1 ... 0.6"}, out,
                 corrected="two turning points per period (no sticking) for f/F < 1/sqrt(1 + pi^2/4) = 0.53703 "
                           "(panels a-e); two sticking intervals only for f/F >= 0.53703 (panel f, f = 0.6)",
                 note="a no-impact orbit reached from rest (60 periods of fast.orbit), refined by reference Newton; "
                      "closed forms in reference.paper.no_impact_attractor")


def c_subharmonic(quick):
    fs = ("0.2", "0.3") if quick else ("0.005", "0.01", "0.05", "0.1", "0.2", "0.3")
    grid = (8, 8) if quick else (30, 40)
    # quick: boxes around the bands where the full search finds the centres (|v| 3.5-4.5, 1-2)
    boxes = ((1, (3.0, 5.0)), (3, (0.5, 2.5))) if quick else ((1, (-6.0, 6.0)), (3, (-3.0, 3.0)))
    out = {}
    for f in fs:
        sc = two_pi(f)
        row = {}
        for k, vr in boxes:
            pts = _fast_points(sc, period=k, v_range=vr, grid=grid)
            row[f"period{k}_centres"] = [[p.x, p.v, p.trace] for p in pts if p.kind == "centre"]
            sol = P.symmetric_solution(sc, 1, m=k)
            row[f"period{k}_symmetric_closed_form"] = None if sol is None else {
                "state0": [fl(a) for a in sol.state0()], "trace": fl(sol.trace()),
                "min_velocity": fl(sol.min_flight_velocity()[0])}
        out[f"f{f}"] = row
    out["period3_symmetric_existence_bound_2F_over_3pi"] = fl(P.existence_bound(3))
    ok = bool(out["f0.2"]["period3_centres"]) and not out["f0.3"]["period3_centres"]
    return claim("subharmonic-islands",
                 "for F = 1, w = 2 pi, l = -1, r = 1 the period-1 island and three islands of a non-sticking "
                 "period-3 solution survive up to f = 0.2 (Fig. many:2pi c-e) and the latter vanish at f = 0.3",
                 "reproduced" if ok else "not reproduced",
                 {"scene": "F=1, w=2pi, l=-1, r=1", "boxes": "period 1: |v| <= 6; period 3: |v| <= 3"}, out,
                 note="the period-3 centre is the symmetric solution with one flight per 3 pi/w (m = 3); it exists "
                      "iff f/F <= 2/(3 pi) = 0.2122, between the figure's 0.2 and 0.3")


# --- the table -------------------------------------------------------------------------------
CLAIMS = {
    "symmetric-solutions": c_symmetric_solutions,
    "existence-condition": c_existence,
    "nonstick-condition": c_nonstick_condition,
    "fold-reduced-condition": c_fold_reduced,
    "fold-fcrit": c_fold_fcrit,
    "resonance-3-1": c_resonance,
    "eigenvalues-fig7": c_eigenvalues,
    "dissip-invariance": c_dissip_invariance,
    "area-preservation": c_area_preservation,
    "table1-matrices": c_table1,
    "no-impact-solutions": c_no_impact,
    "lift": c_lift,
    "xpot-equilibria": c_xpot,
    "focus-and-period5": c_focus_period5,
    "island-A": c_island_a,
    "fig1b-centre": c_fig1b_centre,
    "fig3-attractor": c_fig3_attractor,
    "subharmonic-islands": c_subharmonic,
}


def run_claims(quick=False, ids=None, progress=None) -> list[dict]:
    """Compute the claims (all, or those in ``ids``); each row gets ``seconds``.

    ``progress(row)`` is called as each row completes (the CLI prints it at once).
    """
    ids = list(CLAIMS) if ids is None else list(ids)
    unknown = [i for i in ids if i not in CLAIMS]
    if unknown:
        raise ValueError(f"unknown claim id(s) {unknown}; known: {', '.join(CLAIMS)}")
    rows = []
    for cid in ids:
        t = time.perf_counter()
        row = CLAIMS[cid](quick)
        row["seconds"] = round(time.perf_counter() - t, 2)
        rows.append(row)
        if progress is not None:
            progress(row)
    return rows


def _short(numbers, width=70):
    text = json.dumps(numbers, default=str)
    return text if len(text) <= width else text[: width - 3] + "..."


def main(argv=None) -> int:
    """``python -m cross_check claims [--quick] [--json FILE] [--only ID ...]``: print the table."""
    import argparse
    ap = argparse.ArgumentParser(prog="python -m cross_check claims", description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="small grids (the test-suite settings)")
    ap.add_argument("--json", metavar="FILE", help="write the full table as JSON")
    ap.add_argument("--only", nargs="+", metavar="ID", choices=list(CLAIMS), help=f"claim ids: {', '.join(CLAIMS)}")
    args = ap.parse_args(argv)
    print(f"{'id':24} {'verdict':15} {'s':>6}  numbers", flush=True)

    def show(row):
        print(f"{row['id']:24} {row['verdict']:15} {row['seconds']:6.1f}  {_short(row['numbers'])}", flush=True)
        if row["corrected"]:
            print(f"{'':24} corrected: {row['corrected']}", flush=True)

    rows = run_claims(quick=args.quick, ids=args.only, progress=show)
    if args.json:
        with open(args.json, "w") as fh:
            json.dump(rows, fh, indent=1, default=str)
        print(f"wrote {args.json}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
