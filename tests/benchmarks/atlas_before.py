"""The atlas's per-point path before issue 27, kept as the benchmark's baseline (not an engine).

``cross_check.atlas.claims`` as it was: each claim on its own, one Newton per (branch, period)
seeded from the closed form (the period-1 ones run twice, for ``symmetric`` and
``subharmonic``), one event log per period in the round-trip check, on ``fast``'s wrappers as they
were (``fast_before``).  ``evaluate`` gives the
same flat dict as ``claims.evaluate`` so the two can be compared value for value.
"""
import math

import mpmath
import numpy as np

from cross_check.atlas.claims import FOLD, N_ITER, NO_IMPACT_STARTS, DISSIP_GRID, V_SPAN, _ZERO_V, scene
from cross_check.dynamics import periodic
from reference import paper as P

import fast_before as fast


def _kinds(sc, x, v):
    from cross_check.agreement.compare import normalize_fast_events
    return [e.kind for e in normalize_fast_events(fast.events(sc, np.array([x]), np.array([v])), 1)[0]]


def _periodic_centre(sc, fF, R, branch, m, want):
    """A non-sticking symmetric period-``m`` point of ``kind`` ``want`` found by Newton from the
    closed form at ``min(f, 0.98 f_fold(m))``; ``None`` if there is none."""
    fold = 2 / (m * math.pi)
    sol = P.symmetric_solution(scene(min(fF, 0.98 * fold), R), branch, m=m, dps=20)
    if sol is None:
        return None
    with mpmath.workdps(20):
        x0, v0 = (float(c) for c in sol.state0())
    if not (0.0 <= x0 <= R):
        return None
    try:
        res = periodic.newton(sc, [x0], [v0], period=m, max_iter=25, engine=fast.FAST_ENGINE)
    except RuntimeError:
        return None
    if not res.converged[0]:
        return None
    kind, _ = periodic.classify(res.J)
    if str(kind[0]) not in want:
        return None
    x, v = float(res.x[0]), float(res.v[0])
    kinds = []
    for _ in range(m):
        kinds += _kinds(sc, x, v)
        x, v = (float(a[0]) for a in fast.stroboscopic_map(sc, np.array([x]), np.array([v])))
    if any(k in _ZERO_V for k in kinds) or kinds.count("impact") != 2:     # one round trip in m periods
        return None
    return float(np.trace(res.J[0]))


def _printed(fF, R):
    """The printed non-sticking condition (eq. ``nonstick:cond``) holds (``None`` beyond the fold)."""
    if fF > FOLD:
        return None
    return bool(P.nonstick_condition_printed(scene(fF, R), dps=20) > 0)


def symmetric(fF, R):
    sc = scene(fF, R)
    x1 = _periodic_centre(sc, fF, R, 1, 1, ("centre", "parabolic"))
    x2 = _periodic_centre(sc, fF, R, 2, 1, ("saddle", "parabolic"))
    return {"x1": x1 is not None, "x2": x2 is not None, "x1_trace": x1, "x2_trace": x2,
            "printed": _printed(fF, R)}


def subharmonic(fF, R):
    sc = scene(fF, R)
    out = {}
    for m in (1, 3, 5):
        trs = [_periodic_centre(sc, fF, R, branch, m, ("centre",)) for branch in (1, 2)]
        out[f"m{m}"] = any(tr is not None and abs(tr) < 2 for tr in trs)
    return out


def no_impact(fF, R):
    """From ``NO_IMPACT_STARTS`` starts ``(x_j, v0)`` across the gap, ``v0`` the attractor's speed at
    ``t = 0`` (its closed form, ``paper.no_impact_attractor``: the orbit's shape, not its place),
    ``N_ITER`` periods: a start that has settled on a no-impact periodic orbit shows one exists,
    and whether it sticks or turns."""
    sc = scene(fF, R)
    with mpmath.workdps(20):
        v0 = float(P.no_impact_attractor(sc, dps=20)["v0"]) if fF > 0 else 0.0
    # the wall l itself, then across the gap (without friction the no-impact orbits from rest
    # fill [l, r - 2F/w^2]: l is the one start that finds them all the way down to R = 2F/w^2)
    xs = np.concatenate([[0.0], (np.arange(NO_IMPACT_STARTS) + 0.5) / NO_IMPACT_STARTS * R])
    try:
        x, v = fast.stroboscopic_map(sc, xs, np.full(xs.shape, v0), periods=N_ITER)
        X, V = fast.stroboscopic_map(sc, x, v)
    except RuntimeError:
        return {"exists": False, "sticks": None}
    settled = np.abs(X - x) + np.abs(V - v) <= 1e-8 * (1 + np.abs(x) + np.abs(v))
    for i in np.flatnonzero(settled):
        kinds = _kinds(sc, float(x[i]), float(v[i]))
        if "impact" not in kinds and "chatter" not in kinds:
            return {"exists": True, "sticks": "stick" in kinds}
    return {"exists": False, "sticks": None}


def _reference_confirms(sc, x, v):
    """The reference (30 digits): the start's period reaches zero velocity, its image's does not."""
    import reference
    with mpmath.workdps(30):
        T = 2 * mpmath.pi
        first = [e.kind for e in reference.trajectory(sc, x, v, T, dps=30)]
        X, V = reference.stroboscopic_map(sc, x, v, dps=30)
        second = [e.kind for e in reference.trajectory(sc, X, V, T, dps=30)]
    return any(k in _ZERO_V for k in first) and not any(k in _ZERO_V for k in second) and V != 0


def _dissipative_invariance(scene, x, v):
    """``cross_check.dynamics.portraits.dissipative_invariance`` on the old wrappers."""
    zero = np.asarray(fast.zero_velocity(scene, x, v), bool)
    X, V = fast.stroboscopic_map(scene, x, v)
    zero_img = np.asarray(fast.zero_velocity(scene, X, V), bool)
    J = np.asarray(fast.jacobian(scene, x, v), float)
    with np.errstate(invalid="ignore"):
        det = np.linalg.det(np.where(np.isfinite(J), J, 0.0))
    det = np.where(np.isfinite(J).all(axis=(-1, -2)), det, np.nan)
    labels = np.full(x.shape, "undefined", dtype=object)
    labels[np.abs(np.abs(det) - 1) <= periodic.AREA_TOL] = "pres"
    labels[np.abs(det) < 1 - periodic.AREA_TOL] = "dissip"
    viol = zero & ~zero_img
    return {"n_dissip": int(zero.sum()), "n_violations": int(viol.sum()),
            "violations": list(zip(x[viol].tolist(), v[viol].tolist())),
            "n_det_mismatch": int(((labels != "undefined") & (zero != (labels == "dissip"))).sum())}


def dissip(fF, R):
    if fF <= 0:
        return {"fraction": None, "n_dissip": 0, "confirmed": None, "counterexamples": []}
    sc = scene(fF, R)
    nx, nv = DISSIP_GRID
    xs = (np.arange(nx) + 0.5) / nx * R
    vs = -V_SPAN + (np.arange(nv) + 0.5) / nv * 2 * V_SPAN
    X, V = (a.ravel() for a in np.meshgrid(xs, vs, indexing="ij"))
    out = _dissipative_invariance(sc, X, V)
    frac = out["n_violations"] / out["n_dissip"] if out["n_dissip"] else None
    ex = out["violations"][:3]
    confirmed = _reference_confirms(sc, *ex[0]) if ex else None
    return {"fraction": frac, "n_dissip": out["n_dissip"], "confirmed": confirmed,
            "counterexamples": [[repr(a), repr(b)] for a, b in ex]}


def area(fF, R):
    sc = scene(fF, R)
    xs = (np.arange(4) + 0.5) / 4 * R
    vs = np.array([-1.7, -0.6, 0.6, 1.7])
    X, V = (a.ravel() for a in np.meshgrid(xs, vs, indexing="ij"))
    zero = np.asarray(fast.zero_velocity(sc, X, V), bool)
    if zero.all():
        return {"max_det_minus_1": None}
    J = np.asarray(fast.jacobian(sc, X[~zero], V[~zero]), float)
    det = np.linalg.det(J)
    ok = np.isfinite(det)
    return {"max_det_minus_1": float(np.max(np.abs(det[ok] - 1))) if ok.any() else None}


def evaluate(fF, R):
    """Every claim at one point, the old way, as the new flat dict."""
    sym, sub, noi = symmetric(fF, R), subharmonic(fF, R), no_impact(fF, R)
    dis, are = dissip(fF, R), area(fF, R)
    return {**sym, **{f"period{m}": sub[f"m{m}"] for m in (1, 3, 5)},
            "no_impact": noi["exists"], "sticks": noi["sticks"],
            "dissip_fraction": dis["fraction"], "dissip_starts": dis["n_dissip"],
            "dissip_confirmed": dis["confirmed"],
            "dissip_examples": [(float(a), float(b)) for a, b in dis["counterexamples"]],
            "area_defect": are["max_det_minus_1"]}
