"""What the atlas computes at one point of parameter space, and the closed forms it is held to.

A point is ``(f/F, w^2 R/F)``; the scene is ``F = 1, w = 1, l = 0, r = R`` (the dimensionless
parameters fix the dynamics up to scale).  Each evaluator takes a ``Point`` and returns a flat
dict of plain numbers (the store's variables, ``None`` where undefined), computed on ``fast``
(``cross_check.dynamics``), the reference confirming what it reports as a violation; ``evaluate``
runs the listed claims at one point.  The claims of a point share its Newton solutions (a
period-``m`` batch holds both branches, each seed with its own bounds, so each converges exactly
as alone), and each orbit's round trip is checked on one batch of event logs:

* ``symmetric`` (claims ``existence-condition``, ``nonstick-condition``): whether the map has
  the symmetric solutions ``x1`` (a centre) and ``x2`` (a saddle) as non-sticking 2-impact fixed
  points -- Newton on ``Phi`` from the closed form at the nearest ``f`` where it exists (inside
  the fold, ``f <= 0.98 (2/pi) F``): beyond the fold or where the solution would stick, Newton
  finds no such point.  At ``f = 0`` a solution whose impacts sit on the section ``t = 0`` is
  taken from the closed form, confirmed on ``fast`` (``_on_the_impact``: Newton has nothing to
  converge to where ``Phi`` jumps).  Closed forms: the fold ``f/F = 2/pi``; ``x2`` non-sticking iff
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

import functools
import math

import mpmath
import numpy as np

from cross_check.dynamics import periodic, portraits
from cross_check.tolerances import tol
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


class Point:
    """One point ``(f/F, w^2 R/F)`` of parameter space: its scene, and the periodic centres that
    ``symmetric`` and ``subharmonic`` share (computed once per period ``m``, cached)."""

    def __init__(self, fF: float, R: float):
        self.fF, self.R = float(fF), float(R)
        self.scene = scene(fF, R)
        self._centres = {}

    def centres(self, m):
        """``{branch: (kind, trace, round_trip)}`` of the Newton solutions of period ``m`` (absent:
        no start in the gap or no convergence); ``round_trip()`` says whether the orbit is one
        non-sticking round trip (2 impacts in ``m`` periods, no zero velocity)."""
        if m not in self._centres:
            self._centres[m] = _centres(self.scene, self.fF, self.R, m)
        return self._centres[m]

    def centre(self, branch, m, want):
        """The trace of the branch's period-``m`` solution if its kind is in ``want`` and it is one
        non-sticking round trip, else ``None``."""
        got = self.centres(m).get(branch)
        if got is None or got[0] not in want or not got[2]():
            return None
        return got[1]


def _start(fF, R, branch, m):
    """Newton's seed: the closed form at ``min(f, 0.98 f_fold(m))`` as float64 (``None`` if there
    is none, or it lies outside the gap).  Beyond the fold every point of a row ``R`` has the same
    seed: it is computed once per worker (``_closed_form``'s cache)."""
    return _closed_form(min(fF, 0.98 * (2 / (m * math.pi))), R, branch, m)


@functools.lru_cache(maxsize=4096)
def _closed_form(fF, R, branch, m):
    sol = P.symmetric_solution(scene(fF, R), branch, m=m, dps=20)
    if sol is None:
        return None
    with mpmath.workdps(20):
        x0, v0 = (float(c) for c in sol.state0())
    return (x0, v0) if 0.0 <= x0 <= R else None


def _newton(sc, seeds, m):
    """Newton for period ``m`` from the seeds as one batch, each seed with its own speed bound
    ``|v| <= 10 (|v0| + F/w)`` (so each runs exactly as alone); a batch that raises (an event
    budget exceeded) is rerun seed by seed, a seed that raises has no solution."""
    x0 = np.array([s[0] for s in seeds])
    v0 = np.array([s[1] for s in seeds])
    vmax = 10 * (np.abs(v0) + sc.float("F") / sc.float("omega"))
    try:
        res = periodic.newton(sc, x0, v0, period=m, max_iter=25, v_bounds=(-vmax, vmax))
        return [(res.converged[i], res.x[i], res.v[i], res.J[i]) for i in range(len(seeds))]
    except RuntimeError:
        if len(seeds) == 1:
            return [None]
    return [one for s in seeds for one in _newton(sc, [s], m)]


def _centres(sc, fF, R, m):
    starts = {b: s for b in (1, 2) if (s := _start(fF, R, b, m)) is not None}
    on_wall = {b for b, s in starts.items() if fF == 0 and s[0] in (0.0, R)}
    newton = [s for b, s in starts.items() if b not in on_wall]
    found = {b: got for b, got in zip([b for b in starts if b not in on_wall],
                                      _newton(sc, newton, m) if newton else [])
             if got is not None and got[0]}
    trips = {b: _lazy(_round_trip, sc, float(got[1]), float(got[2]), m) for b, got in found.items()}
    for b in sorted(on_wall):
        got = _on_the_impact(sc, R, b, m, starts[b])
        if got is not None:
            found[b], trips[b] = got
    if not found:
        return {}
    kinds, _ = periodic.classify(np.array([got[3] for got in found.values()]))
    return {b: (str(kind), float(np.trace(got[3])), trips[b]) for kind, (b, got) in zip(kinds, found.items())}


def _on_the_impact(sc, R, branch, m, seed):
    """``f = 0``: the symmetric solution's impacts fall on the section ``t = 0`` (``psi = 0``,
    eq. ``nonstick``: ``sin psi = -m pi f / (2F)``), where ``Phi`` jumps (the strobe at
    ``t = mT`` sees the particle at the wall just before or just after its impact): float64
    Newton has no fixed point to converge to.  The closed form is the solution, confirmed on
    ``fast``: from its state at the wall, ``m`` periods come back to the wall with the same
    speed (either side of the impact, ``claim_fixed_point``).  ``(Newton-like result, round
    trip)``: the trace from the closed form (a monodromy's trace does not depend on the
    section; ``det = 1``), non-sticking from its margin (``paper.nonstick_margin > 0``: the
    flights' speed never vanishes), else None."""
    import fast
    x0, v0 = seed
    X, V = fast.stroboscopic_map(sc, np.array([x0]), np.array([v0]), periods=m)
    atol = tol("claim_fixed_point").atol
    if not (abs(X[0] - x0) <= atol * (1 + R) and abs(abs(V[0]) - abs(v0)) <= atol * (1 + abs(v0))):
        return None
    with mpmath.workdps(20):
        tr = float(P.symmetric_solution(sc, branch, m=m, dps=20).trace())
        moving = bool(P.nonstick_margin(sc, branch, m=m, dps=20) > 0)
    return (True, x0, v0, np.array([[tr, -1.0], [1.0, 0.0]])), (lambda: moving)


def _lazy(fn, *args):
    cache = []

    def value():
        if not cache:
            cache.append(fn(*args))
        return cache[0]
    return value


def _round_trip(sc, x, v, m):
    """The orbit through ``(x, v)`` over ``m`` periods has exactly 2 impacts and never reaches zero
    velocity (one non-sticking round trip): its ``m`` points in one batch of event logs."""
    import fast
    X, V = fast.orbit(sc, np.array([x]), np.array([v]), m - 1)
    kinds = [k for row in _kinds(fast.events(sc, X[:, 0], V[:, 0])) for k in row]
    return not any(k in _ZERO_V for k in kinds) and kinds.count("impact") == 2


def _kinds(log):
    """The event kinds of each state of a ``fast.EventLog`` (its codes read off directly)."""
    import fast
    return [[fast.KINDS[c] for c in row[:n]] for row, n in zip(log.kind.tolist(), log.n.tolist())]


@functools.lru_cache(maxsize=4096)
def _attractor_speed(fF):
    """``x'(0)`` of the no-impact attractor (``paper.no_impact_attractor``, ``0 < f < F``): a
    function of ``f/F`` alone (``F = w = 1``; away from the walls), so once per column."""
    with mpmath.workdps(20):
        return float(P.no_impact_attractor(scene(fF, 1.0), dps=20)["v0"])


def _printed(fF, R):
    """The printed non-sticking condition (eq. ``nonstick:cond``) holds (``None`` beyond the fold)."""
    if fF > FOLD:
        return None
    return bool(P.nonstick_condition_printed(scene(fF, R), dps=20) > 0)


def symmetric(pt: Point) -> dict:
    x1 = pt.centre(1, 1, ("centre", "parabolic"))
    x2 = pt.centre(2, 1, ("saddle", "parabolic"))
    return {"x1": x1 is not None, "x2": x2 is not None, "x1_trace": x1, "x2_trace": x2,
            "printed": _printed(pt.fF, pt.R)}


def subharmonic(pt: Point) -> dict:
    out = {}
    for m in (1, 3, 5):
        trs = [pt.centre(branch, m, ("centre",)) for branch in (1, 2)]
        out[f"period{m}"] = any(tr is not None and abs(tr) < 2 for tr in trs)
    return out


def no_impact(pt: Point) -> dict:
    """From ``NO_IMPACT_STARTS`` starts ``(x_j, v0)`` across the gap, ``v0`` the attractor's speed at
    ``t = 0`` (its closed form, ``paper.no_impact_attractor``: the orbit's shape, not its place),
    ``N_ITER`` periods: a start that has settled on a no-impact periodic orbit shows one exists,
    and whether it sticks or turns."""
    import fast
    sc, fF, R = pt.scene, pt.fF, pt.R
    v0 = _attractor_speed(fF) if fF > 0 else 0.0
    # the wall l itself, then across the gap (without friction the no-impact orbits from rest
    # fill [l, r - 2F/w^2]: l is the one start that finds them all the way down to R = 2F/w^2)
    xs = np.concatenate([[0.0], (np.arange(NO_IMPACT_STARTS) + 0.5) / NO_IMPACT_STARTS * R])
    try:
        x, v = fast.stroboscopic_map(sc, xs, np.full(xs.shape, v0), periods=N_ITER)
        X, V = fast.stroboscopic_map(sc, x, v)
    except RuntimeError:
        return {"no_impact": False, "sticks": None}
    settled = np.flatnonzero(np.abs(X - x) + np.abs(V - v) <= 1e-8 * (1 + np.abs(x) + np.abs(v)))
    if settled.size:
        for kinds in _kinds(fast.events(sc, x[settled], v[settled])):   # the first settled start
            if "impact" not in kinds and "chatter" not in kinds:            # without impacts
                return {"no_impact": True, "sticks": "stick" in kinds}
    return {"no_impact": False, "sticks": None}


def _reference_confirms(sc, x, v):
    """The reference (30 digits): the start's period reaches zero velocity, its image's does not.

    Both periods end at the reference's own ``T = 2 pi`` (at its working precision, 30 digits
    plus its guard digits), so the first period's end state is the stroboscopic image
    ``reference.stroboscopic_map`` gives: one integration gives the first period's events and
    the image."""
    import reference
    from reference.model import GUARD_DIGITS
    with mpmath.workdps(30 + GUARD_DIGITS):
        T = 2 * mpmath.pi / sc.mpf("omega")
    log = reference.trajectory(sc, x, v, T, dps=30)
    X, V = log.x_end, log.v_end
    second = [e.kind for e in reference.trajectory(sc, X, V, T, dps=30)]
    return any(e.kind in _ZERO_V for e in log) and not any(k in _ZERO_V for k in second) and V != 0


def dissip(pt: Point) -> dict:
    if pt.fF <= 0:
        return {"dissip_fraction": None, "dissip_starts": 0, "dissip_confirmed": None, "dissip_examples": []}
    sc, R = pt.scene, pt.R
    nx, nv = DISSIP_GRID
    xs = (np.arange(nx) + 0.5) / nx * R
    vs = -V_SPAN + (np.arange(nv) + 0.5) / nv * 2 * V_SPAN
    X, V = (a.ravel() for a in np.meshgrid(xs, vs, indexing="ij"))
    out = portraits.dissipative_invariance(sc, X, V)
    frac = out["n_violations"] / out["n_dissip"] if out["n_dissip"] else None
    ex = out["violations"][:3]
    confirmed = _reference_confirms(sc, *ex[0]) if ex else None
    return {"dissip_fraction": frac, "dissip_starts": out["n_dissip"], "dissip_confirmed": confirmed,
            "dissip_examples": [(float(a), float(b)) for a, b in ex]}


def area(pt: Point) -> dict:
    import fast
    sc, R = pt.scene, pt.R
    xs = (np.arange(4) + 0.5) / 4 * R
    vs = np.array([-1.7, -0.6, 0.6, 1.7])
    X, V = (a.ravel() for a in np.meshgrid(xs, vs, indexing="ij"))
    zero = np.asarray(fast.zero_velocity(sc, X, V), bool)
    if zero.all():
        return {"area_defect": None}
    J = np.asarray(fast.jacobian(sc, X[~zero], V[~zero]), float)
    det = np.linalg.det(J)
    ok = np.isfinite(det)
    return {"area_defect": float(np.max(np.abs(det[ok] - 1))) if ok.any() else None}


#: claim id -> evaluator of a ``Point`` (a flat dict: the store's variables, ``None`` where undefined)
CLAIMS = {"symmetric": symmetric, "subharmonic-islands": subharmonic, "no-impact": no_impact,
          "dissip-invariance": dissip, "area-preservation": area}


def evaluate(fF: float, R: float, claims) -> dict:
    """Every listed claim at the point ``(f/F, w^2 R/F)``: one flat dict (the claims share a ``Point``)."""
    pt = Point(fF, R)
    out = {}
    for c in claims:
        out.update(CLAIMS[c](pt))
    return out
