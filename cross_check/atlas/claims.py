"""What the atlas computes at one point of parameter space, and the closed forms it is held to.

A point is ``(f/F, w^2 R/F)``; the scene is ``F = 1, w = 1, l = 0, r = R`` (the dimensionless
parameters fix the dynamics up to scale).  Each evaluator returns plain numbers for its claim,
computed on ``fast`` (``cross_check.dynamics``), the reference confirming what it reports as a
violation:

* ``symmetric`` (claims ``existence-condition``, ``nonstick-condition``): whether the map has
  the symmetric solutions ``x1`` (a centre) and ``x2`` (a saddle) as non-sticking 2-impact fixed
  points -- Newton on ``Phi`` from the closed form at the nearest ``f`` where it exists (inside
  the fold, ``f <= 0.98 (2/pi) F``): beyond the fold or where the solution would stick, Newton
  finds no such point.  Closed forms: the fold ``f/F = 2/pi``; ``x2`` non-sticking iff
  ``w^2 R > sqrt(4F^2 - pi^2 f^2)`` (corrected); the printed condition (``x1``'s alone);
* ``subharmonic`` (``subharmonic-islands``): period-``m`` symmetric centres (``m = 1, 3, 5``; either
  branch), non-sticking, one round trip (2 impacts) in ``m`` periods, elliptic (``|tr| < 2``),
  against ``f/F <= 2/(m pi)``;
* ``no_impact`` (``fig3-attractor``, ``no-impact-solutions``): starts across the gap, ``N_ITER``
  periods: whether one has settled on a no-impact periodic orbit, and whether that orbit sticks
  or turns -- against ``R >= 2F/w^2`` (``f = 0``) and ``f/F >= 1/sqrt(1 + pi^2/4)``;
* ``dissip`` (``dissip-invariance``): the fraction of ``Omega_dissip`` starts (a ``DISSIP_GRID``
  grid) whose image leaves it, each reported violation's first confirmed by the reference at
  30 digits (and up to 3 stored, exact float64 states);
* ``area`` (``area-preservation``): ``max |det Phi' - 1|`` over non-sticking starts.
"""
from __future__ import annotations

import math

import mpmath
import numpy as np

from cross_check.dynamics import periodic, portraits
from reference import paper as P
from reference.scene import Scene

FOLD = 2 / math.pi
STICK_ATTRACTOR = 1 / math.sqrt(1 + math.pi ** 2 / 4)
N_ITER = 80
NO_IMPACT_STARTS = 5
DISSIP_GRID = (6, 6)
V_SPAN = 2.0
_ZERO_V = ("turn", "stick", "slip", "contact", "release", "chatter")


def scene(fF: float, R: float) -> Scene:
    """The scene of a point: ``F = 1, f = fF, w = 1, l = 0, r = R``."""
    return Scene(F=1, f=float(fF), omega=1, l=0, r=float(R))


def x2_nonstick_boundary(fF):
    """``w^2 R/F`` above which ``x2`` does not stick (corrected condition; nan beyond the fold)."""
    return math.sqrt(4 - math.pi ** 2 * fF ** 2) if fF <= FOLD else math.nan


def _kinds(sc, x, v):
    import fast
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
        res = periodic.newton(sc, [x0], [v0], period=m, max_iter=25)
    except RuntimeError:
        return None
    if not res.converged[0]:
        return None
    kind, _ = periodic.classify(res.J)
    if str(kind[0]) not in want:
        return None
    import fast
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
    import fast
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


def dissip(fF, R):
    if fF <= 0:
        return {"fraction": None, "n_dissip": 0, "confirmed": None, "counterexamples": []}
    sc = scene(fF, R)
    nx, nv = DISSIP_GRID
    xs = (np.arange(nx) + 0.5) / nx * R
    vs = -V_SPAN + (np.arange(nv) + 0.5) / nv * 2 * V_SPAN
    X, V = (a.ravel() for a in np.meshgrid(xs, vs, indexing="ij"))
    out = portraits.dissipative_invariance(sc, X, V)
    frac = out["n_violations"] / out["n_dissip"] if out["n_dissip"] else None
    ex = out["violations"][:3]
    confirmed = _reference_confirms(sc, *ex[0]) if ex else None
    return {"fraction": frac, "n_dissip": out["n_dissip"], "confirmed": confirmed,
            "counterexamples": [[repr(a), repr(b)] for a, b in ex]}


def area(fF, R):
    import fast
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


#: claim id -> (evaluator, the grid's parameter ranges are shared)
CLAIMS = {"symmetric": symmetric, "subharmonic-islands": subharmonic, "no-impact": no_impact,
          "dissip-invariance": dissip, "area-preservation": area}
