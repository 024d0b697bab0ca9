"""Periodic points of the stroboscopic map: ONE Newton (``dynamics.newton``, whose names are
also this module's) and ONE classifier, over any map.

A period-``k`` point solves ``G(z) = Phi^k(z) - z = 0``, ``z = (x, v)``, by ``newton``'s damped
Newton from a grid of seeds (``find_periodic_points``), each orbit kept once at its minimal period.

Type from the multipliers ``lambda_{1,2}`` of ``J_k`` (``det = lambda_1 lambda_2``, ``tr``), the
one classifier of the suite (``classify``):

* area-preserving (``|det - 1| <= AREA_TOL``): ``centre`` if ``|tr| < 2``, ``saddle`` if
  ``tr > 2``, ``flip saddle`` if ``tr < -2``, ``parabolic`` within ``PARABOLIC_TOL`` of ``|tr| = 2``;
* otherwise ``non-isolated`` when a multiplier is 1 (a segment of fixed points, such as the
  no-impact attractor of Fig. many:wide); a complex pair is a ``focus``; real ones a ``node``
  (both on one side of the unit circle) or a ``saddle``.

``stability``: ``stable`` (both ``|lambda| < 1``), ``neutral`` (centre, parabolic,
non-isolated), ``unstable`` otherwise.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from cross_check.dynamics.newton import FAST, MAX_NEWTON, SEARCH_STEPS, Reference, map_and_jacobian, multipliers, newton
from cross_check.tolerances import tol

__all__ = [  # newton's names, re-exported: periodic is where the suite asks for them
    "FAST", "MAX_NEWTON", "SEARCH_STEPS", "Reference", "map_and_jacobian", "multipliers", "newton",
    # the classifier and the orbits
    "AREA_TOL", "PARABOLIC_TOL", "NONISOLATED_TOL", "classify", "is_saddle", "PeriodicPoint", "periodic_point",
    "orbit_points", "seed_grid", "find_periodic_points"]

#: |det J - 1| below this is area preserving (the tolerance table's ``claim_unit_det``)
AREA_TOL = tol("claim_unit_det").atol
#: |tr| within this of 2 is parabolic (float64 trace of a product of ~10 matrices, ~1e-13)
PARABOLIC_TOL = 1e-9
#: a multiplier this close to 1 on a contracting point: a segment of fixed points
NONISOLATED_TOL = 1e-7


def classify(J):
    """``(kind, stability)`` object arrays for a batch of multiplier matrices (module docstring).

    ``J`` is ``(..., 2, 2)`` (a single 2x2 gives 0-d arrays); a non-finite ``J`` is ``"undefined"``.
    """
    J = np.asarray(J, float)
    if J.shape[-2:] != (2, 2):
        raise ValueError(f"classify: J must have shape (..., 2, 2), got {J.shape}")
    finite = np.isfinite(J).all(axis=(-1, -2))
    Jf = np.where(finite[..., None, None], J, 0.0)
    tr = Jf[..., 0, 0] + Jf[..., 1, 1]
    det = np.linalg.det(Jf)
    lam = multipliers(Jf)
    mods = np.sort(np.abs(lam), axis=-1)
    kind = np.full(tr.shape, "undefined", dtype=object)
    stab = np.full(tr.shape, "undefined", dtype=object)
    area = finite & (np.abs(det - 1) <= AREA_TOL)
    para = area & (np.abs(np.abs(tr) - 2) <= PARABOLIC_TOL)
    kind[area] = np.where(np.abs(tr[area]) < 2, "centre", np.where(tr[area] > 0, "saddle", "flip saddle"))
    stab[area] = np.where(np.abs(tr[area]) < 2, "neutral", "unstable")
    kind[para], stab[para] = "parabolic", "neutral"
    rest = finite & ~area
    flat = rest & (np.min(np.abs(lam - 1), axis=-1) <= NONISOLATED_TOL)
    kind[flat], stab[flat] = "non-isolated", "neutral"
    rest &= ~flat
    hyperbolic = (mods[..., 0] < 1) & (mods[..., 1] > 1)
    kind[rest] = np.where(tr[rest] ** 2 - 4 * det[rest] < 0, "focus",
                          np.where(hyperbolic[rest], "saddle", "node"))
    stab[rest] = np.where(mods[rest][..., 1] < 1, "stable", "unstable")
    return kind, stab


def is_saddle(kind):
    """Saddle of either orientation (``saddle`` or ``flip saddle``)."""
    return np.isin(np.asarray(kind, dtype=object), ["saddle", "flip saddle"])


@dataclass
class PeriodicPoint:
    """A periodic orbit of ``Phi``: representative state, period, ``J_k``, multipliers and type.

    ``orbit`` lists the ``period`` points ``z, Phi(z), ...`` (float pairs); ``dissip`` says whether
    the orbit reaches zero velocity (``Omega_dissip``), where ``find_periodic_points`` was asked."""

    x: float
    v: float
    period: int
    J: np.ndarray
    multipliers: tuple
    trace: float
    det: float
    kind: str
    stability: str
    orbit: list = field(default_factory=list)
    dissip: bool | None = None

    @property
    def points(self):
        """The orbit as a ``(period, 2)`` array."""
        return np.asarray(self.orbit, float)

    def as_dict(self):
        return {"x": self.x, "v": self.v, "period": self.period, "trace": self.trace, "det": self.det,
                "multipliers": [complex(m) for m in self.multipliers], "kind": self.kind,
                "stability": self.stability}


def periodic_point(scene, x, v, period):
    """The ``PeriodicPoint`` at a (converged) state: its orbit, ``J_k`` and type."""
    pts = orbit_points(scene, x, v, period)
    _, _, J = map_and_jacobian(scene, [x], [v], period)
    kind, stab = classify(J[0])
    tr, det = float(J[0, 0, 0] + J[0, 1, 1]), float(np.linalg.det(J[0]))
    lam = multipliers(J[0])
    return PeriodicPoint(float(x), float(v), period, J[0], (complex(lam[0]), complex(lam[1])), tr, det,
                         str(kind), str(stab), pts)


def orbit_points(scene, x, v, period):
    """``[z, Phi(z), ..., Phi^(period-1)(z)]`` as float pairs (``fast``)."""
    import fast
    pts = [(float(x), float(v))]
    for _ in range(period - 1):
        X, V = fast.stroboscopic_map(scene, np.array([pts[-1][0]]), np.array([pts[-1][1]]))
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


def seed_grid(scene, grid, v_range, x_range=None):
    """Cell-centred ``grid = (nx, nv)`` seeds over ``x_range`` (default: the gap) times ``v_range``."""
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
    return X, V


def find_periodic_points(scene, *, period=1, v_range=(-2.0, 2.0), grid=(24, 24), x_range=None,
                         seeds=None, tol=1e-11, dedup=1e-7, max_iter=MAX_NEWTON, search_steps=None):
    """All period-``period`` orbits ``newton`` reaches from seeds (``fast``).

    Seeds: ``seeds = (x, v)`` if given, else ``seed_grid(scene, grid, v_range, x_range)``; iterates
    stay within ``v_range`` widened by half its span.  Converged orbits are kept once (a point
    within ``dedup`` of a kept orbit's point is dropped), at minimal period exactly ``period``,
    represented by their point of smallest ``(x, v)`` with wall states taken after the impact.
    ``search_steps``: ``newton``'s (a coarse search under position forcing).
    Returns ``PeriodicPoint`` objects sorted by ``(x, v)`` to ``ORDER_DECIMALS`` decimals.
    """
    l, r = scene.float("l"), scene.float("r")
    X, V = seeds if seeds is not None else seed_grid(scene, grid, v_range, x_range)
    span = v_range[1] - v_range[0]
    res = newton(scene, X, V, period=period, tol=tol, max_iter=max_iter,
                 v_bounds=(v_range[0] - span / 2, v_range[1] + span / 2), search_steps=search_steps)
    found: list[PeriodicPoint] = []
    for xi, vi in zip(res.x[res.converged], res.v[res.converged]):
        xi, vi = _canonical(l, r, float(xi), float(vi), dedup)
        if any(max(abs(xi - q[0]), abs(vi - q[1])) <= dedup for p in found for q in p.orbit):
            continue
        pts = [_canonical(l, r, a, b, dedup) for a, b in orbit_points(scene, xi, vi, period)]
        if _minimal_period(pts, dedup) != period:
            continue
        p = periodic_point(scene, *min(pts), period)
        if np.isfinite(p.J).all():
            p.orbit = pts
            found.append(p)
    return sorted(found, key=_order)


#: decimals of the order of the found points: above Newton's noise (``tol`` 1e-11), below the
#: ``dedup`` distance (1e-7).  Ordered by the raw ``(x, v)``, the symmetric centres of Fig. narrow
#: (``x`` equal, ``v = +-0.973``) swapped with the last digits of their ``x`` (2.7e-13 apart):
#: the full claims snapshot's two centres came out in the other order.
ORDER_DECIMALS = 9


def _order(p):
    return round(p.x, ORDER_DECIMALS), round(p.v, ORDER_DECIMALS)
