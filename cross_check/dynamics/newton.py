"""Newton's method for the periodic points of the stroboscopic map, over any map (the ONE Newton
of the suite; ``periodic`` classifies what it finds).

A period-``k`` point solves ``G(z) = Phi^k(z) - z = 0``, ``z = (x, v)``, by Newton's method::

    z <- z - lambda (J_k - I)^+ G(z),    J_k = Phi'(z_{k-1}) ... Phi'(z_1) Phi'(z_0)   (later on the left)

with ``Phi'`` the product of the paper's Table 1 matrices.  ``Phi`` is only piecewise smooth,
so each step is damped (``lambda`` halved up to ``MAX_HALVINGS`` times until ``|G|`` decreases;
a start without descent is dropped) and ``x`` is kept in the gap.  ``(J_k - I)^+`` is the
inverse, or where ``J_k - I`` is singular (a continuum of fixed points: the no-impact and
stick-slip segments, a multiplier 1) the pseudo-inverse of the rank-one matrix, ``A^T /
|A|_F^2``: the minimum-norm step.  The 2x2 algebra is written out, so the same code runs on
numpy float64 batches and on numpy object arrays of mpf.

Engines give ``Phi^k`` and ``J_k`` on a batch (``map_jac``) inside their precision
(``context``):

* ``FAST``: ``fast.map_and_jacobian``, float64, vectorised over the seeds;
* ``Reference(dps)``: ``reference.stroboscopic_map`` and ``reference.jacobian`` at ``dps``
  digits, one seed at a time (mpf objects).

Under position forcing ``fast``'s search first screens the seeds on its coarse map
(``search_steps``, ``SEARCH_TOL``) and polishes the screen's ends on the default one
(``_two_stage``, ``FAMILY_SCREEN``, ``NEAR_ONE``).  ``multipliers`` are the eigenvalues of ``J_k``.
"""
from __future__ import annotations

import contextlib
from dataclasses import dataclass

import mpmath
import numpy as np


MAX_NEWTON = 30
MAX_HALVINGS = 5
#: ``newton``'s screen of the seeds under position forcing (``search_steps``): ``fast``'s flights
#: at ``S = 32`` steps (``fast.api``'s ``steps_per_period``: 0.29 of the default's CPU, the map
#: within 1.2e-9 of it over 2,000 random states of an unseen scene, 5e-11 at the 99th
#: percentile); a seed passes when its coarse Newton run reaches ``|G| / max(1, |z|) <=
#: SEARCH_TOL``, two decades above that error.  Measured (issue 33, 16 x 16 seeds, periods 1, 2,
#: 3, one run): on D (``F=3 f=0.5 omega=0.8 l=-2 r=1.5 wavenumber=2.5``) 8.8 -> 3.6 CPU s, the same
#: 24 points bit for bit; on F (``F=1 f=0.2 omega=1 l=-1 r=1 wavenumber=1``) 2.4 -> 1.5 s, 30 of
#: its 31 points (one period-3 orbit was reached by a single seed, 1 of 129 that converge, whose
#: coarse run wandered off); on A, B and C the same points, bit for bit (that pass ran the default
#: map from the seeds; it now polishes the screen's ends: ``NEAR_ONE``).
SEARCH_STEPS = 32
SEARCH_TOL = 1e-7
#: ``_two_stage``: a seed whose coarse end has ``|tr - 2|`` and ``|det - 1|`` within this (the coarse
#: map's ``J``) most likely ends on a family of fixed points of an area-preserving map, and the
#: default map runs from that end, not from the seed: a family member is as good as another, and
#: from the seed Newton crawled along the family's neutral direction.  Where that run does not
#: converge (an isolated point near ``tr = 2``, whose default-map fixed point the coarse end misses
#: by ``|(P' - I)^-1|`` times the coarse map's error), the seed runs as alone, as before.  Issue 33,
#: periods 1 to 3, 16 x 16 seeds, one run: the search on the frictionless corners ``F=3 f=0
#: omega=0.5 l=-2 r=2 wavenumber=2`` 45.4 -> 28.8 CPU s and ``F=2 f=0 omega=0.5 l=-1 r=1
#: wavenumber=2`` 27.3 -> 20.1, every point found outside ``verify.ladder.FAMILY_TOL`` the same bit for
#: bit (the first scene's isolated centre at ``tr = 2 - 3.6e-8`` among them, which the search lost
#: without the fall-back to the seed); on ``F=1.5 f=0 omega=0.9 l=-0.8 r=0.6 wavenumber=2.2`` and the
#: issue's first scene without friction the same points, the same time to 0.5 s.  With friction (W,
#: the issue's first scene, ``F=1 f=0.2 omega=1 l=-1 r=1 wavenumber=1``) no seed ends so.  The
#: members' coarse ends lie up to ~1e-3 from ``tr = 2`` (the coarse map's error): a wider
#: screen takes more of them, and more isolated points that then run twice.
FAMILY_SCREEN = 1e-6
#: ``_two_stage``: a seed whose coarse end the default map polishes to a point with a multiplier
#: within this of 1 (off a family of an area-preserving map) runs again from the seed, as the search
#: without a screen runs it.  Issue 33, scene D (``F=3 f=0.5 omega=0.8 l=-2 r=1.5 wavenumber=2.5``):
#: 149 of the 269 coarse ends of periods 1 to 3 polish to rest states (a multiplier 1 along their
#: family); polished from the ends, two at the family's edge (a multiplier 2e-7 from 1, a residual
#: of 8e-12 on a drift) passed for fixed points, and their proofs failed up the whole ladder for
#: 22 CPU s.  With the fall-back D finds the points of the search from the seeds (17, 5 and 2 of
#: periods 1 to 3, within 1e-8), its search 10.8 -> 8.1 CPU s; the issue's first scene 5.1 -> 2.4
#: (3.4 -> 2.4 with the old search second in the process; the same 34 points), ``F=1.896 f=0.0929
#: omega=0.806 l=0.04 r=0.64 wavenumber=3.5937 damping=0.369 restitution=0.9`` 16.0 -> 7.6 (the
#: same 20 and 12 points of periods 1 and 2; of period 3, 16 of 19 the same and three other
#: saddles: a seed's coarse end and its default-map path from the seed may reach different
#: orbits); one run each, on a loaded 2-core machine.
NEAR_ONE = 1e-4
#: ``_two_stage``: a coarse end of a period-``k`` search within this of a fixed point of ``Phi^d``
#: (``d`` a proper divisor of ``k``; ``|Phi^d(z) - z| / max(1, |z|)`` on the coarse map) is an
#: orbit of the lower period (``_of_lower_period``), dropped before the default map polishes it.
#: Ten times ``SEARCH_TOL``, the coarse run's own tolerance on ``Phi^k``; ``find_periodic_points``
#: drops a point whose orbit repeats within ``dedup`` (1e-7) anyway.
LOWER_PERIOD_TOL = 1e-6


class _Fast:
    """``fast``'s map, float64 batches (``steps``: ``fast``'s ``steps_per_period``)."""

    tol = 1e-11

    def __init__(self, steps=None):
        self.steps = steps

    def context(self):
        return contextlib.nullcontext()

    def map_jac(self, scene, x, v, k):
        import fast
        x, v, J, _ = fast.map_and_jacobian(scene, x, v, periods=k, steps_per_period=self.steps)
        return np.asarray(x, float), np.asarray(v, float), np.asarray(J, float)

    def asarray(self, a):
        return np.atleast_1d(np.asarray(a, float)).copy()

    def walls(self, scene):
        return scene.float("l"), scene.float("r")

    def finite(self, a):
        return np.isfinite(a)


class Reference:
    """``reference``'s map at ``dps`` digits: mpf objects, one seed at a time."""

    def __init__(self, dps=50):
        self.dps = dps

    @property
    def tol(self):
        return mpmath.mpf(10) ** (-(self.dps - 8))

    def context(self):
        return mpmath.workdps(self.dps)

    def asarray(self, a):
        """mpf objects at the working precision (inside ``context()``)."""
        flat = [mpmath.mpf(z) for z in np.ravel(np.asarray(a, object))]
        return np.array(flat + [None], object)[:-1].reshape(np.shape(a) or (1,))

    def map_jac(self, scene, x, v, k):
        import reference
        X, V, J = np.empty(x.shape, object), np.empty(x.shape, object), np.empty(x.shape + (2, 2), object)
        for i in range(x.size):
            xi, vi, Ji = x[i], v[i], mpmath.eye(2)
            for _ in range(k):
                Ji = mpmath.matrix(reference.jacobian(scene, xi, vi, dps=self.dps)) * Ji
                xi, vi = reference.stroboscopic_map(scene, xi, vi, dps=self.dps)
            X[i], V[i] = xi, vi
            J[i] = np.array(Ji.tolist(), dtype=object)
        return X, V, J

    def walls(self, scene):
        """The walls rounded inward by 2 ulp (an exact ``"0.8"`` rounds up at working precision)."""
        eps = mpmath.mpf(2) ** (-mpmath.mp.prec + 2)
        l, r = scene.mpf("l"), scene.mpf("r")
        return l + abs(l) * eps, r - abs(r) * eps

    def finite(self, a):
        return np.vectorize(lambda z: bool(mpmath.isfinite(z)), otypes=[bool])(a)


FAST = _Fast()


def map_and_jacobian(scene, x, v, period=1, engine=FAST):
    """``Phi^period(z)`` and ``J_period`` for a batch (the chain rule, later on the left)."""
    with engine.context():
        return engine.map_jac(scene, engine.asarray(x), engine.asarray(v), period)


def solve_step(J, gx, gv):
    """``d = -(J - I)^+ g`` per item: ``(dx, dv)``.

    float64: LAPACK's solve where ``cond(A) < 1e12``, else the pseudo-inverse (singular values
    below ``1e-10`` of the largest dropped); mpf objects: the SVD pseudo-inverse, singular
    values below ``1e-30`` of the largest dropped.  On a segment of fixed points (a multiplier
    1, ``J - I`` of rank one) the pseudo-inverse gives the minimum-norm step, and Newton still
    converges, onto the segment."""
    if J.dtype != object:
        return _solve_float(J, gx, gv)
    dx, dv = np.empty(gx.shape, object), np.empty(gv.shape, object)
    for i in range(gx.size):
        A = mpmath.matrix(J[i].tolist()) - mpmath.eye(2)
        U, S, Vt = mpmath.svd_r(A)
        cut = max(S) * mpmath.mpf(10) ** -30
        y = U.T * mpmath.matrix([-gx[i], -gv[i]])
        for j in range(len(S)):
            y[j] = y[j] / S[j] if S[j] > cut else 0
        d = Vt.T * y
        dx[i], dv[i] = d[0], d[1]
    return dx, dv


def _solve_float(J, gx, gv):
    A = J - np.eye(2)
    g = np.stack([gx, gv], axis=-1)[..., None]
    ok = np.isfinite(A).all(axis=(-1, -2)) & np.isfinite(g).all(axis=(-1, -2))
    d = np.full(g.shape, np.nan)
    if ok.any():
        Ao, go = A[ok], g[ok]
        good = np.linalg.cond(Ao) < 1e12
        do = np.empty_like(go)
        if good.any():
            do[good] = np.linalg.solve(Ao[good], -go[good])
        if (~good).any():
            do[~good] = -np.linalg.pinv(Ao[~good], rcond=1e-10) @ go[~good]
        d[ok] = do
    return d[..., 0, 0], d[..., 1, 0]


@dataclass
class NewtonResult:
    """Final states, their ``J_k``, residuals ``|G| / max(1, |z|)`` and convergence flags of a batch."""

    x: np.ndarray
    v: np.ndarray
    J: np.ndarray
    residual: np.ndarray
    converged: np.ndarray
    iterations: int
    gx: np.ndarray = None
    gv: np.ndarray = None


def newton(scene, x, v, *, period=1, engine=FAST, tol=None, max_iter=MAX_NEWTON, v_bounds=None,
           search_steps=None):
    """Damped Newton for ``Phi^period(z) = z`` on a batch of seeds (module docstring).

    ``tol`` (default the engine's: 1e-11 in float64, ``10^(8 - dps)`` for the reference) is on
    ``|G| / max(1, |z|)`` (max norm).  ``v_bounds = (lo, hi)`` keeps iterates there (a wild
    step to a huge speed would cost millions of impacts per period); ``lo, hi`` are numbers or
    arrays of the seeds' shape (one interval per seed: a batch then runs each seed exactly as
    alone); default ``|v| <= 10 (max |v0| + F/w)`` over the batch.  Items without descent or with a non-finite Jacobian stop (not
    converged).  Each iteration costs one ``map_jac`` per trial point (the Jacobian of an
    accepted trial is kept for the next step).

    ``search_steps`` (``FAST`` under position forcing; else ignored): screen the seeds on the
    coarse map of ``fast``'s ``steps_per_period = search_steps`` (down to ``SEARCH_TOL``), then
    polish the ends of those that got there on the default map (``_two_stage``).
    """
    if not (isinstance(period, int) and period >= 1):
        raise ValueError(f"period must be a positive int, got {period!r}")
    if not (isinstance(max_iter, int) and 1 <= max_iter <= 1000):
        raise ValueError(f"max_iter must be an int in [1, 1000], got {max_iter!r}")
    if search_steps is not None and engine is FAST and scene.has("position_forcing"):
        return _two_stage(scene, x, v, period, tol, max_iter, v_bounds, search_steps)
    with engine.context():
        tol = engine.tol if tol is None else tol
        l, r = engine.walls(scene)
        clip = lambda a: np.minimum(np.maximum(a, l), r)          # noqa: E731
        x = clip(engine.asarray(x))
        v = engine.asarray(v)
        bounds = v_bounds if v_bounds is not None else _default_v_bounds(scene, v)
        state = _State(scene, engine, x, v, period, clip, bounds)
        it = 0
        for it in range(1, max_iter + 1):
            if not state.iterate(tol):
                break
        done = engine.finite(state.res) & (state.res <= tol)
        return NewtonResult(state.x, state.v, state.J, state.res, done.astype(bool), it, state.gx, state.gv)


def _default_v_bounds(scene, v):
    """``newton``'s default ``v_bounds``: ``|v| <= 10 (max |v0| + F/w)`` over the batch."""
    vmax = 10 * (np.max(np.abs(v.astype(float)), initial=0.0) + scene.float("F") / scene.float("omega"))
    return -vmax, vmax


def _two_stage(scene, x, v, period, tol, max_iter, v_bounds, steps):
    """``newton`` on ``fast``'s coarse map (``steps`` per period) to ``SEARCH_TOL`` screens the
    seeds; the default map then polishes the coarse ends of the seeds that got there, each
    exactly as alone (per-seed ``v_bounds``), but for the ends of a lower period
    (``_of_lower_period``: reported not converged, as ``find_periodic_points`` would drop their
    points for their minimal period).  From the seed instead, as alone (the default map's
    whole Newton path, as the search without a screen runs it): a seed whose run from its end does
    not converge -- an isolated point near ``tr = 2`` whose coarse end misses the default map's
    fixed point by ``|(P' - I)^-1|`` times the coarse map's error -- and one whose end converges
    to a point with a multiplier within ``NEAR_ONE`` of 1 off a family of an area-preserving map
    (``_on_family`` of the coarse ``J`` or of the default map's: ``_again``): the edge of a family
    of rest states, where a drift too slow for the tolerance passes for a fixed point.  The others
    are reported not converged, where the screen left them.  Issue 33: the default map ran every
    seed from the seed before, ~10 iterations with their line searches where a coarse end takes
    one or two (``NEAR_ONE``)."""
    x, v = FAST.asarray(x), FAST.asarray(v)
    bounds = v_bounds if v_bounds is not None else _default_v_bounds(scene, v)
    lo, hi = (np.broadcast_to(np.asarray(b, float), x.shape) for b in bounds)
    screen = _Fast(steps)
    coarse = newton(scene, x, v, period=period, engine=screen, tol=max(SEARCH_TOL, tol or 0.0),
                    max_iter=max_iter, v_bounds=(lo, hi))
    near = np.flatnonzero(coarse.converged)
    near = near[~_of_lower_period(scene, screen, coarse.x[near], coarse.v[near], period)]
    out = NewtonResult(coarse.x, coarse.v, coarse.J, coarse.residual, np.zeros(x.shape, bool),
                       coarse.iterations, coarse.gx, coarse.gv)
    if near.size:
        family = _on_family(coarse.J[near])
        fine = newton(scene, coarse.x[near], coarse.v[near], period=period, tol=tol, max_iter=max_iter,
                      v_bounds=(lo[near], hi[near]))     # (fancy indexing: copies, as newton's iterates need)
        _merge(out, fine, near)
        again = near[_again(fine, family)]
        if again.size:
            _merge(out, newton(scene, x[again], v[again], period=period, tol=tol, max_iter=max_iter,
                               v_bounds=(lo[again], hi[again])), again)
    return out


def _of_lower_period(scene, engine, x, v, period):
    """Which of the states ``(x, v)`` (coarse ends of a period-``period`` search) are fixed points
    of ``Phi^d`` on ``engine``'s map for a proper divisor ``d`` of ``period``, within
    ``LOWER_PERIOD_TOL`` of ``max(1, |z|)``: orbits of a lower period, which the search of that
    period finds and ``find_periodic_points`` drops here (its ``_minimal_period``)."""
    low = np.zeros(x.shape, bool)
    for d in (d for d in range(1, period) if period % d == 0 and x.size):
        X, V, _ = engine.map_jac(scene, x, v, d)
        with np.errstate(invalid="ignore"):
            low |= (np.maximum(np.abs(X - x), np.abs(V - v))
                    <= LOWER_PERIOD_TOL * np.maximum(1, np.maximum(np.abs(x), np.abs(v))))
    return low


def _again(fine, family):
    """Which of the coarse ends that the default map polished (``fine``, a ``NewtonResult``;
    ``family``: ``_on_family`` of their coarse ``J``) run again from their seeds: those whose run
    did not converge, and those polished to a multiplier within ``NEAR_ONE`` of 1 that is on no
    family of an area-preserving map by the coarse ``J`` nor by the default map's own ``J`` at the
    polished point (``_on_family``).  The second screen is the first's on the default map: a
    member polished from the end is as good as one polished from the seed.  Issue 33, periods 1
    to 3, 16 x 16 seeds, one run each: on ``F=2 f=0 omega=0.5 l=-1 r=1 wavenumber=2`` 15, 34 and
    34 ends polished onto a family by the default map's ``J`` alone (the coarse map's lies up to
    ~1e-3 off); run again, every one of them converged onto a family too, and the search's points
    off ``tr = 2`` are the same bit for bit without those runs (also on ``F=3 f=0 omega=0.5 l=-2
    r=2 wavenumber=2``: 18, 33 and 28 ends)."""
    return ~fine.converged | (_near_one(fine.J) & ~family & ~_on_family(fine.J))


def _merge(out, part, idx):
    """Write the ``newton`` result ``part`` of the seeds ``idx`` into ``out``."""
    for mine, theirs in ((out.x, part.x), (out.v, part.v), (out.J, part.J), (out.residual, part.residual),
                         (out.converged, part.converged), (out.gx, part.gx), (out.gv, part.gv)):
        mine[idx] = theirs
    out.iterations = max(out.iterations, part.iterations)


def _on_family(J):
    """Which of a batch of ``J`` (``(n, 2, 2)``) are within ``FAMILY_SCREEN`` of ``tr = 2`` and ``det
    = 1`` (both multipliers ~1 on an area-preserving map: a family of fixed points, most likely)."""
    J = np.asarray(J, float)
    tr = J[:, 0, 0] + J[:, 1, 1]
    det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
    with np.errstate(invalid="ignore"):
        return (np.abs(tr - 2) <= FAMILY_SCREEN) & (np.abs(det - 1) <= FAMILY_SCREEN)


def _near_one(J):
    """Which of a batch of ``J`` (``(n, 2, 2)``) have a multiplier within ``NEAR_ONE`` of 1 (a
    non-finite ``J``: False)."""
    J = np.asarray(J, float)
    finite = np.isfinite(J).all(axis=(-1, -2))
    mu = multipliers(np.where(finite[:, None, None], J, 0.0))
    return finite & (np.abs(mu - 1) <= NEAR_ONE).any(axis=-1)


class _State:
    """The batch of a ``newton`` run: iterates, residuals, ``J_k`` there, who is still active."""

    def __init__(self, scene, engine, x, v, period, clip, v_bounds):
        self.scene, self.engine, self.period, self.clip = scene, engine, period, clip
        self.v_lo, self.v_hi = (np.broadcast_to(np.asarray(b, x.dtype), x.shape) for b in v_bounds)
        self.x, self.v = x, v
        self.gx, self.gv, self.J = self._residual(x, v)
        self.res = self._norm(self.gx, self.gv, x, v)
        self.active = np.ones(x.shape, bool)

    def _residual(self, x, v):
        X, V, J = self.engine.map_jac(self.scene, x, v, self.period)
        return X - x, V - v, J

    @staticmethod
    def _norm(gx, gv, x, v):
        return np.maximum(np.abs(gx), np.abs(gv)) / np.maximum(1, np.maximum(np.abs(x), np.abs(v)))

    def iterate(self, tol):
        """One damped step for the active items; returns whether any is left."""
        self.active &= self.engine.finite(self.res) & np.asarray(self.res > tol, bool)
        if not self.active.any():
            return False
        idx = np.flatnonzero(self.active)
        dx, dv = solve_step(self.J[idx], self.gx[idx], self.gv[idx])
        bad = ~(self.engine.finite(dx) & self.engine.finite(dv))
        self.active[idx[bad]] = False
        self._line_search(idx[~bad], dx[~bad], dv[~bad])
        return True

    def _line_search(self, idx, dx, dv):
        lam = np.ones(idx.size)
        pending = np.ones(idx.size, bool)
        for _ in range(MAX_HALVINGS + 1):
            if not pending.any():
                return
            p = np.flatnonzero(pending)
            xn = self.clip(self.x[idx[p]] + lam[p] * dx[p])
            q = idx[p]
            vn = np.minimum(np.maximum(self.v[q] + lam[p] * dv[p], self.v_lo[q]), self.v_hi[q])
            nx, nv, nJ = self._residual(xn, vn)
            rn = self._norm(nx, nv, xn, vn)
            take = self.engine.finite(rn) & (rn < self.res[idx[p]])
            tk = idx[p[take]]
            self.x[tk], self.v[tk], self.gx[tk], self.gv[tk], self.res[tk], self.J[tk] = (
                xn[take], vn[take], nx[take], nv[take], rn[take], nJ[take])
            stuck = ~take & (lam[p] <= 2.0 ** -MAX_HALVINGS)
            self.active[idx[p[stuck]]] = False          # no descent along the step: give up
            pending[p[take | stuck]] = False
            lam[p[~(take | stuck)]] /= 2


def multipliers(J):
    """Eigenvalues of a batch of 2x2 matrices ``(..., 2, 2)``: complex ``(..., 2)`` (float64)."""
    return np.linalg.eigvals(np.asarray(J, float))


