"""Fixed points, period-k points and the area classes of the stroboscopic map (float64, vectorised).

Periodic points.  A period-``k`` point solves ``G(z) = Phi^k(z) - z = 0``, ``z = (x, v)``.  Newton::

    z <- z - (J_k - I)^{-1} G(z),    J_k = Phi'(z_{k-1}) ... Phi'(z_1) Phi'(z_0)   (later on the left)

with ``Phi'`` the saltation product of ``fast.map_and_jacobian`` (paper Table 1).  ``Phi`` is only piecewise
smooth, so each step is damped (halved up to ``MAX_HALVINGS`` times until ``|G|`` decreases; a seed
without descent is dropped) and
``x`` is clipped to the gap; a singular ``J_k - I`` (a continuum of fixed points such as the
no-impact/stick-slip segments, ``det Phi' = 0``) falls back to the least-squares (pseudo-inverse)
step.  ``find_periodic_points`` seeds Newton on a grid over a box of states and keeps the converged
distinct orbits (deduplicated up to ``dedup``; a period-k orbit is one entry, represented by its
point of smallest ``x``, and orbits of smaller minimal period are dropped).

Type from the multipliers ``lambda_{1,2}`` of ``J_k`` (``det = lambda_1 lambda_2``, ``tr``):

* area-preserving (``|det - 1| <= AREA_TOL``): ``centre`` if ``|tr| < 2``, ``saddle`` if ``|tr| > 2``
  (``flip saddle`` for ``tr < -2``), ``parabolic`` within ``PARABOLIC_TOL`` of ``|tr| = 2``;
* contracting: complex pair -> ``focus``; real -> ``node`` (both ``|lambda| < 1`` or both > 1) or
  ``saddle``; ``non-isolated`` when a multiplier is 1 (a segment of fixed points, such as the
  no-impact attractor of Fig. many:wide).
``stability``: ``stable`` (both ``|lambda| < 1``), ``neutral`` (centre, parabolic, non-isolated),
``unstable`` otherwise.

Area classes (paper, Fig. fig:fig): ``Omega_pres`` = ``|det Phi'| = 1`` (no zero velocity on
``[0, T]``), ``Omega_dissip`` = ``|det Phi'| < 1``; ``undefined`` where ``Phi'`` is not finite (grazing).
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

import fast
from reference.scene import Scene

#: |det J - 1| below this is area preserving (see cross_check/tolerances.py "claim_unit_det").
AREA_TOL = 1e-9
#: |tr| within this of 2 is parabolic (float64 trace of a product of ~10 matrices, ~1e-13).
PARABOLIC_TOL = 1e-9
#: a contracting point with a multiplier this close to 1 lies on a segment of fixed points
#: (the no-impact attractor: translation along the segment is neutral).
NONISOLATED_TOL = 1e-7
#: Newton: iterations, step halvings.
MAX_NEWTON = 30
MAX_HALVINGS = 5


def _map(scene: Scene, x, v, periods: int = 1):
    X, V = fast.stroboscopic_map(scene, x, v, periods=periods)
    return np.asarray(X, dtype=float), np.asarray(V, dtype=float)


def map_and_jacobian(scene: Scene, x, v, period: int = 1):
    """``Phi^period(z)`` and ``J_period`` for a batch (1-D arrays ``x``, ``v``)."""
    x, v = np.atleast_1d(np.asarray(x, float)), np.atleast_1d(np.asarray(v, float))
    J = np.broadcast_to(np.eye(2), x.shape + (2, 2)).copy()
    for _ in range(period):
        x, v, Jj, _ = fast.map_and_jacobian(scene, x, v)
        J = np.asarray(Jj, dtype=float) @ J
    return np.asarray(x, float), np.asarray(v, float), J


def _clip(scene: Scene, x):
    return np.clip(x, scene.float("l"), scene.float("r"))


def _residual(scene, x, v, period):
    X, V = _map(scene, x, v, period)
    return X - x, V - v


def _newton_step(J, gx, gv):
    """Solve (J - I) d = -g per item; pseudo-inverse where singular or ill-conditioned."""
    A = J - np.eye(2)
    g = np.stack([gx, gv], axis=-1)[..., None]
    ok = np.isfinite(A).all(axis=(-1, -2)) & np.isfinite(g).all(axis=(-1, -2))
    d = np.full(g.shape, np.nan)
    if ok.any():
        Ao, go = A[ok], g[ok]
        cond = np.linalg.cond(Ao)
        good = cond < 1e12
        do = np.empty_like(go)
        if good.any():
            do[good] = np.linalg.solve(Ao[good], -go[good])
        if (~good).any():
            do[~good] = -np.linalg.pinv(Ao[~good], rcond=1e-10) @ go[~good]
        d[ok] = do
    return d[..., 0, 0], d[..., 1, 0]


@dataclass
class NewtonResult:
    """Converged flags, final states and residual norms of a batch of Newton runs."""

    x: np.ndarray
    v: np.ndarray
    residual: np.ndarray
    converged: np.ndarray
    iterations: int


def newton(scene: Scene, x, v, *, period: int = 1, tol: float = 1e-11, max_iter: int = MAX_NEWTON,
           v_bounds=None):
    """Damped Newton for ``Phi^period(z) = z`` on a batch of seeds (module docstring).

    ``tol`` is on ``|G| / max(1, |z|)`` (max norm).  ``v_bounds = (lo, hi)``: iterates are clipped into
    it (a wild step to a huge speed would cost millions of impacts per period); default
    ``|v| <= 10 (max|v0| + F/w)``.  Returns a ``NewtonResult``; items without descent or with a
    non-finite Jacobian are dropped (marked not converged).
    """
    if not (isinstance(period, int) and period >= 1):
        raise ValueError(f"period must be a positive int, got {period!r}")
    if not (isinstance(max_iter, int) and 1 <= max_iter <= 1000):
        raise ValueError(f"max_iter must be an int in [1, 1000], got {max_iter!r}")
    x = _clip(scene, np.atleast_1d(np.asarray(x, float)).copy())
    v = np.atleast_1d(np.asarray(v, float)).copy()
    if v_bounds is None:
        vmax = 10 * (np.max(np.abs(v), initial=0.0) + scene.float("F") / scene.float("omega"))
        v_bounds = (-vmax, vmax)
    gx, gv = _residual(scene, x, v, period)
    norm = lambda a, b, xx, vv: np.maximum(abs(a), abs(b)) / np.maximum(1, np.maximum(abs(xx), abs(vv)))
    res = norm(gx, gv, x, v)
    active = np.isfinite(res) & (res > tol)
    it = 0
    for it in range(1, max_iter + 1):
        if not active.any():
            break
        idx = np.flatnonzero(active)
        _, _, J = map_and_jacobian(scene, x[idx], v[idx], period)
        dx, dv = _newton_step(J, gx[idx], gv[idx])
        bad = ~(np.isfinite(dx) & np.isfinite(dv))
        active[idx[bad]] = False
        idx, dx, dv = idx[~bad], dx[~bad], dv[~bad]
        lam = np.ones(idx.size)
        pending = np.ones(idx.size, bool)
        for _ in range(MAX_HALVINGS + 1):
            if not pending.any():
                break
            p = np.flatnonzero(pending)
            xn = _clip(scene, x[idx[p]] + lam[p] * dx[p])
            vn = np.clip(v[idx[p]] + lam[p] * dv[p], *v_bounds)
            nx, nv = _residual(scene, xn, vn, period)
            rn = norm(nx, nv, xn, vn)
            take = np.isfinite(rn) & (rn < res[idx[p]])
            tk = idx[p[take]]
            x[tk], v[tk], gx[tk], gv[tk], res[tk] = xn[take], vn[take], nx[take], nv[take], rn[take]
            stuck = ~take & (lam[p] <= 2.0 ** -MAX_HALVINGS)
            active[idx[p[stuck]]] = False       # no descent along the Newton direction: give up
            pending[p[take | stuck]] = False
            lam[p[~(take | stuck)]] /= 2
        active &= np.isfinite(res) & (res > tol)
    return NewtonResult(x, v, res, np.isfinite(res) & (res <= tol), it)


@dataclass
class PeriodicPoint:
    """A periodic orbit of ``Phi``: representative state, period, multipliers and type."""

    x: float
    v: float
    period: int
    multipliers: tuple
    trace: float
    det: float
    kind: str
    stability: str
    orbit: list = field(default_factory=list)

    def as_dict(self):
        return {"x": self.x, "v": self.v, "period": self.period, "trace": self.trace, "det": self.det,
                "multipliers": [complex(m) for m in self.multipliers], "kind": self.kind,
                "stability": self.stability}


def classify(J):
    """``(kind, stability, multipliers, trace, det)`` of a 2x2 multiplier matrix (module docstring)."""
    J = np.asarray(J, float)
    if J.shape != (2, 2) or not np.isfinite(J).all():
        raise ValueError(f"classify: J must be a finite 2x2 matrix, got {J!r}")
    tr, det = float(np.trace(J)), float(np.linalg.det(J))
    lam = np.linalg.eigvals(J)
    mods = np.sort(abs(lam))
    if abs(det - 1) <= AREA_TOL:
        if abs(abs(tr) - 2) <= PARABOLIC_TOL:
            kind, stab = "parabolic", "neutral"
        elif abs(tr) < 2:
            kind, stab = "centre", "neutral"
        else:
            kind, stab = ("saddle" if tr > 0 else "flip saddle"), "unstable"
    elif np.min(abs(lam - 1)) <= NONISOLATED_TOL:
        kind, stab = "non-isolated", "neutral"
    else:
        complex_pair = tr * tr - 4 * det < 0
        if complex_pair:
            kind = "focus"
        else:
            kind = "saddle" if mods[0] < 1 < mods[1] else "node"
        stab = "stable" if mods[1] < 1 else "unstable"
    return kind, stab, (complex(lam[0]), complex(lam[1])), tr, det


def _orbit_points(scene, x, v, period):
    pts = [(x, v)]
    for _ in range(period - 1):
        X, V = _map(scene, np.array([pts[-1][0]]), np.array([pts[-1][1]]))
        pts.append((float(X[0]), float(V[0])))
    return pts


def _canonical(l, r, x, v, tol):
    """A state at a wall is stored after its impact: ``(r, v > 0)`` is the same orbit as ``(r, -v)``."""
    if abs(x - r) <= tol and v > 0:
        return r, -v
    if abs(x - l) <= tol and v < 0:
        return l, -v
    return x, v


def _minimal_period(pts, dedup):
    for p in range(1, len(pts)):
        if len(pts) % p == 0 and all(
                max(abs(pts[i][0] - pts[i % p][0]), abs(pts[i][1] - pts[i % p][1])) <= dedup
                for i in range(len(pts))):
            return p
    return len(pts)


def find_periodic_points(scene: Scene, *, period: int = 1, v_range=(-2.0, 2.0), grid=(24, 24),
                         x_range=None, tol: float = 1e-11, dedup: float = 1e-7):
    """All period-``period`` orbits Newton reaches from a grid of seeds in the box.

    The box is ``x_range`` (default: the gap, walls excluded by a half grid step) times ``v_range``.
    Returns a list of ``PeriodicPoint`` (minimal period exactly ``period``), sorted by ``(x, v)``.
    """
    l, r = scene.float("l"), scene.float("r")
    nx, nv = grid
    if not (isinstance(nx, int) and isinstance(nv, int) and 1 <= nx <= 2000 and 1 <= nv <= 2000):
        raise ValueError(f"grid must be two ints in [1, 2000], got {grid!r}")
    x0, x1 = x_range if x_range is not None else (l, r)
    if not (l <= x0 < x1 <= r) or not v_range[0] < v_range[1]:
        raise ValueError(f"x_range must lie in [l, r] = [{l}, {r}] and be increasing; v_range increasing")
    xs = x0 + (np.arange(nx) + 0.5) / nx * (x1 - x0)
    vs = v_range[0] + (np.arange(nv) + 0.5) / nv * (v_range[1] - v_range[0])
    X, V = (a.ravel() for a in np.meshgrid(xs, vs, indexing="ij"))
    span = v_range[1] - v_range[0]
    res = newton(scene, X, V, period=period, tol=tol,
                 v_bounds=(v_range[0] - span / 2, v_range[1] + span / 2))
    found: list[PeriodicPoint] = []
    for xi, vi in zip(res.x[res.converged], res.v[res.converged]):
        xi, vi = _canonical(l, r, float(xi), float(vi), dedup)
        if any(max(abs(xi - q[0]), abs(vi - q[1])) <= dedup for p in found for q in p.orbit):
            continue
        pts = [_canonical(l, r, a, b, dedup) for a, b in _orbit_points(scene, xi, vi, period)]
        if _minimal_period(pts, dedup) != period:
            continue
        rep = min(pts)
        _, _, J = map_and_jacobian(scene, np.array([rep[0]]), np.array([rep[1]]), period)
        if not np.isfinite(J).all():
            continue
        kind, stab, lam, tr, det = classify(J[0])
        found.append(PeriodicPoint(rep[0], rep[1], period, lam, tr, det, kind, stab, pts))
    return sorted(found, key=lambda p: (p.x, p.v))


def area_classes(scene: Scene, x, v):
    """``(labels, det)``: per state ``"pres"`` (|det Phi'| = 1), ``"dissip"`` (< 1) or ``"undefined"``."""
    x, v = np.atleast_1d(np.asarray(x, float)), np.atleast_1d(np.asarray(v, float))
    J = np.asarray(fast.jacobian(scene, x, v), float).reshape(x.shape + (2, 2))
    with np.errstate(invalid="ignore"):
        det = np.linalg.det(np.where(np.isfinite(J), J, 0.0))
    det = np.where(np.isfinite(J).all(axis=(-1, -2)), det, np.nan)
    labels = np.full(x.shape, "undefined", dtype=object)
    labels[np.abs(np.abs(det) - 1) <= AREA_TOL] = "pres"
    labels[np.abs(det) < 1 - AREA_TOL] = "dissip"
    return labels, det


def dissipative_invariance(scene: Scene, x, v):
    """Counts for ``Phi(Omega_dissip) subset Omega_dissip`` on the given states (paper, Fig. fig:regs).

    Membership is by definition (``fast.zero_velocity``: the velocity vanishes somewhere on
    ``[0, T]``).  Returns a dict: ``n``, ``n_dissip``, ``n_violations`` (dissip states whose image is
    not dissip), the violating states, and ``n_det_mismatch`` (states where the definition and
    the ``|det Phi'| < 1`` test disagree, grazing excluded).
    """
    x, v = np.atleast_1d(np.asarray(x, float)), np.atleast_1d(np.asarray(v, float))
    zero = np.asarray(fast.zero_velocity(scene, x, v), bool)
    X, V = _map(scene, x, v)
    zero_img = np.asarray(fast.zero_velocity(scene, X, V), bool)
    labels, _ = area_classes(scene, x, v)
    defined = labels != "undefined"
    viol = zero & ~zero_img
    return {"n": int(x.size), "n_dissip": int(zero.sum()), "n_violations": int(viol.sum()),
            "violations": list(zip(x[viol].tolist(), v[viol].tolist())),
            "n_det_mismatch": int((defined & (zero != (labels == "dissip"))).sum())}
