"""Periodic points of the stroboscopic map and their continuation in a parameter.

Everything here works on the float64 engine ``fast`` (imported lazily, so this module
imports without it) and is vectorised over a batch of states.

* ``newton_periodic`` solves ``Phi^k(z) = z`` by Newton's method,
  ``z <- z - (D Phi^k(z) - I)^{-1} (Phi^k(z) - z)``, where ``D Phi^k`` is the product
  of ``fast.jacobian`` along the orbit (later matrices on the left).
* ``classify`` names a periodic point by its multipliers: for an area-preserving map
  (``det = 1``, non-sticking orbits) ``|tr| < 2`` is a centre, ``|tr| > 2`` a saddle;
  ``det < 1`` with both ``|lambda| < 1`` is an attractor (focus or node).
* ``continue_branch`` follows a curve of fixed points ``G(z, p) = Phi_p(z) - z = 0``
  by pseudo-arclength continuation: tangent ``t`` spans ``ker DG``, predictor
  ``u + ds t``, corrector Newton on ``[G(u); t.(u - u_pred)] = 0``.  ``dG/dp`` is a
  central difference (the map is smooth in ``f`` and ``r`` along non-sticking orbits).
* ``locate_fold`` finds the saddle-centre point on a branch, where a multiplier is 1,
  i.e. ``tr D Phi = 2`` (``det = 1``), by bisection in arclength.
"""
from __future__ import annotations

import numpy as np

#: Newton stops when ``|Phi^k(z) - z|_inf <= NEWTON_TOL * max(1, |z|_inf)``
NEWTON_TOL = 1e-11
NEWTON_MAX_ITER = 40
#: ``||tr| - 2|`` below this: a parabolic point (multiplier 1 within the float64 trace of a product
#: of ~10 saltation/flight matrices, ~1e-12, times the 1e-11 Newton residual's conditioning)
PARABOLIC_TOL = 1e-7


def engine():
    """The float64 engine ``fast`` (imported on first use)."""
    import fast
    return fast


def phi(scene, x, v, periods=1):
    """``Phi^periods`` on a batch as a pair of float arrays."""
    x, v = engine().stroboscopic_map(scene, np.asarray(x, float), np.asarray(v, float), periods=periods)
    return np.asarray(x, float), np.asarray(v, float)


def scene_walls(scene):
    return scene.float("l"), scene.float("r")


def orbit_jacobian(scene, x, v, k=1):
    """``Phi^k(z)`` and ``D Phi^k(z)`` for a 1-D batch: ``(xk, vk, J)``, ``J`` (n, 2, 2).

    The chain rule over ``k`` periods is ``fast.analysis.map_and_jacobian``'s (one place).
    """
    from fast.analysis import map_and_jacobian

    return map_and_jacobian(scene, x, v, period=k)


def newton_periodic(scene, x, v, k=1, tol=NEWTON_TOL, max_iter=NEWTON_MAX_ITER):
    """Solve ``Phi^k(z) = z`` from a batch of starts.

    Returns ``(x, v, ok, J)``: the points, a convergence mask (residual within ``tol``
    relative to ``max(1, |z|)``, finite Jacobian), and ``D Phi^k`` at the points.
    Steps that would leave the strip ``l <= x <= r`` are clipped to it; starts that
    diverge (non-finite Jacobian, e.g. grazing) are marked not ok and frozen.
    """
    if k < 1:
        raise ValueError(f"newton_periodic: k must be >= 1, got {k}")
    l, r = scene_walls(scene)
    x = np.clip(np.array(x, float, ndmin=1), l, r)
    v = np.array(v, float, ndmin=1)
    alive = np.ones(x.shape, bool)
    ok = np.zeros(x.shape, bool)
    J = np.full(x.shape + (2, 2), np.nan)
    for _ in range(max_iter):
        idx = np.nonzero(alive & ~ok)[0]
        if idx.size == 0:
            break
        xk, vk, Jk = orbit_jacobian(scene, x[idx], v[idx], k)
        res = np.stack([xk - x[idx], vk - v[idx]], -1)
        scale = np.maximum(1.0, np.maximum(np.abs(x[idx]), np.abs(v[idx])))
        finite = np.isfinite(Jk).all(axis=(-1, -2)) & np.isfinite(res).all(-1)
        J[idx] = Jk
        done = finite & (np.abs(res).max(-1) <= tol * scale)
        ok[idx[done]] = True
        step_idx = finite & ~done
        A = Jk[step_idx] - np.eye(2)
        with np.errstate(all="ignore"):
            det = A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0]
            good = np.abs(det) > 1e-14
            rr = res[step_idx]
            dx = (A[:, 1, 1] * rr[:, 0] - A[:, 0, 1] * rr[:, 1]) / np.where(good, det, 1.0)
            dv = (-A[:, 1, 0] * rr[:, 0] + A[:, 0, 0] * rr[:, 1]) / np.where(good, det, 1.0)
        sid = idx[step_idx]
        x[sid] = np.clip(x[sid] - np.where(good, dx, 0.0), l, r)
        v[sid] = v[sid] - np.where(good, dv, 0.0)
        alive[sid[~good]] = False
        alive[idx[~finite]] = False
    return x, v, ok, J


def multipliers(J):
    """Eigenvalues of a batch of 2x2 matrices (complex, shape (..., 2))."""
    return np.linalg.eigvals(np.asarray(J, float))


def classify(J, det_tol=1e-6):
    """Type of periodic points from ``D Phi^k``: 'centre', 'saddle', 'parabolic', 'attractor', 'other'.

    ``det = 1`` (within ``det_tol``): area-preserving, ``|tr| < 2`` centre (elliptic),
    ``|tr| > 2`` saddle (hyperbolic), ``|tr| = 2`` (within ``PARABOLIC_TOL``) parabolic.  Otherwise: all ``|lambda| < 1`` attractor,
    some ``|lambda| > 1`` with ``det < 1`` saddle, else other.
    """
    J = np.asarray(J, float)
    tr = J[..., 0, 0] + J[..., 1, 1]
    det = J[..., 0, 0] * J[..., 1, 1] - J[..., 0, 1] * J[..., 1, 0]
    mod = np.abs(multipliers(J)).max(-1)
    out = np.full(tr.shape, "other", dtype=object)
    cons = np.abs(det - 1) <= det_tol
    out[cons & (np.abs(tr) < 2)] = "centre"
    out[cons & (np.abs(tr) > 2)] = "saddle"
    out[cons & (np.abs(np.abs(tr) - 2) <= PARABOLIC_TOL)] = "parabolic"
    out[~cons & (mod < 1)] = "attractor"
    out[~cons & (mod > 1)] = "saddle"
    return out


def find_periodic_orbits(scene, window, k=1, n_seeds=(24, 24), dedup=1e-6, seeds=None, max_iter=20):
    """All period-``k`` orbits Newton finds from a grid of starts in ``window``.

    ``window = (x0, x1, v0, v1)``.  Orbits are deduplicated: a found point belonging to
    the orbit of an accepted point (within ``dedup``) is dropped; points of minimal
    period below ``k`` are dropped too.  Newton converges quadratically from a good seed
    in a few steps; seeds not converged after ``max_iter`` steps are dropped.  Returns a list of dicts with the orbit points
    ``(k, 2)``, ``J`` (``D Phi^k`` at the first point), ``type`` and ``multipliers``.
    """
    if seeds is None:
        xs = np.linspace(window[0], window[1], n_seeds[0] + 2)[1:-1]
        vs = np.linspace(window[2], window[3], n_seeds[1] + 2)[1:-1]
        X, V = np.meshgrid(xs, vs)
        seeds = (X.ravel(), V.ravel())
    x, v, ok, J = newton_periodic(scene, seeds[0], seeds[1], k, max_iter=max_iter)
    inside = ok & (x >= window[0]) & (x <= window[1]) & (v >= window[2]) & (v <= window[3])
    orbits = []
    fe = engine()
    for i in np.nonzero(inside)[0]:
        z = np.array([x[i], v[i]])
        if any(np.min(np.abs(o["points"] - z).max(-1)) < dedup * max(1, np.abs(z).max()) for o in orbits):
            continue
        ox, ov = fe.orbit(scene, np.array([x[i]]), np.array([v[i]]), k - 1) if k > 1 else (
            np.array([[x[i]]]), np.array([[v[i]]]))
        pts = np.stack([np.asarray(ox)[:, 0], np.asarray(ov)[:, 0]], -1)
        if k > 1 and np.min(np.abs(pts[1:] - pts[0]).max(-1)) < dedup * max(1, np.abs(z).max()):
            continue  # minimal period is a divisor of k
        orbits.append({"points": pts, "J": J[i], "type": str(classify(J[i][None])[0]),
                       "multipliers": multipliers(J[i])})
    return orbits


def _G(make_scene, u):
    """Residual ``Phi_p(z) - z`` and the full Jacobian ``[D_z Phi - I | d Phi/dp]`` at ``u = (x, v, p)``."""
    fe = engine()
    sc = make_scene(u[2])
    x1, v1 = phi(sc, [u[0]], [u[1]])
    Jz = np.asarray(fe.jacobian(sc, np.array([u[0]]), np.array([u[1]])), float)[0]
    h = 1e-6 * max(1.0, abs(u[2]))
    xp, vp = phi(make_scene(u[2] + h), [u[0]], [u[1]])
    xm, vm = phi(make_scene(u[2] - h), [u[0]], [u[1]])
    dp = np.array([(xp[0] - xm[0]) / (2 * h), (vp[0] - vm[0]) / (2 * h)])
    res = np.array([x1[0] - u[0], v1[0] - u[1]])
    D = np.column_stack([Jz - np.eye(2), dp])
    return res, D, Jz


def _tangent(D, prev=None):
    """Unit null vector of the 2x3 matrix ``D``, oriented along ``prev``."""
    t = np.linalg.svd(D)[2][-1]
    if prev is not None and t @ prev < 0:
        t = -t
    return t


def _correct(make_scene, u_pred, t, tol=NEWTON_TOL, max_iter=NEWTON_MAX_ITER):
    """Newton on ``[G(u); t.(u - u_pred)] = 0``.  Returns ``(u, D, Jz)`` or raises RuntimeError."""
    u = u_pred.copy()
    for _ in range(max_iter):
        res, D, Jz = _G(make_scene, u)
        if not (np.isfinite(res).all() and np.isfinite(D).all()):
            raise RuntimeError(f"continuation: non-finite map/Jacobian at u={u}")
        if np.abs(res).max() <= tol * max(1.0, np.abs(u[:2]).max()) and abs(t @ (u - u_pred)) <= 1e-12:
            return u, D, Jz
        M = np.vstack([D, t])
        rhs = -np.concatenate([res, [t @ (u - u_pred)]])
        u = u + np.linalg.solve(M, rhs)
    raise RuntimeError(f"continuation: corrector did not converge in {max_iter} steps at u={u}")


def continue_branch(make_scene, z0, p0, *, ds=0.02, p_min=0.0, p_max=np.inf, n_max=400,
                    direction=1.0, ds_max=0.2, ds_min=1e-6):
    """Pseudo-arclength continuation of ``Phi_p(z) = z`` from a fixed point ``z0`` at ``p0``.

    ``make_scene(p)`` builds the scene at parameter ``p``.  The branch is followed with
    adaptive steps (halved on corrector failure, grown when the corrector is quick) until
    ``p`` leaves ``[p_min, p_max]`` or ``n_max`` steps.  Returns arrays ``u`` (n, 3) and
    ``trace`` (n,) of ``D_z Phi`` and ``det`` (n,).
    """
    res, D, Jz = _G(make_scene, np.array([z0[0], z0[1], p0]))
    u = np.array([z0[0], z0[1], p0], float)
    t = _tangent(D, np.array([0.0, 0.0, direction]))
    us, trs, dets = [u.copy()], [np.trace(Jz)], [np.linalg.det(Jz)]
    for _ in range(n_max):
        if ds < ds_min:
            raise RuntimeError(f"continuation: step size fell below {ds_min} at u={u}")
        if not (p_min <= u[2] + ds * t[2] <= p_max):
            if ds > 1e-3:  # approach the end of the parameter range in smaller steps
                ds /= 2
                continue
            break
        try:
            u_new, D_new, Jz_new = _correct(make_scene, u + ds * t, t)
        except (RuntimeError, ValueError, np.linalg.LinAlgError):
            ds /= 2
            continue
        if not (p_min <= u_new[2] <= p_max):
            break
        t = _tangent(D_new, t)
        u = u_new
        us.append(u.copy())
        trs.append(np.trace(Jz_new))
        dets.append(np.linalg.det(Jz_new))
        ds = min(ds * 1.3, ds_max)
    # after n_max steps the branch is returned as far as it got
    return np.array(us), np.array(trs), np.array(dets)


def locate_fold(make_scene, us, trs, n_bisect=50):
    """The fold (``tr D Phi = 2``) on a computed branch, refined by bisection in arclength.

    Finds consecutive branch points with ``tr - 2`` of opposite signs, then bisects the
    arclength ``sigma`` of the predictor from the first of them (each trial point is
    corrected onto the branch).  Returns ``u`` (x, v, p) at the fold, or None if the
    branch does not cross ``tr = 2``.
    """
    s = np.sign(trs - 2)
    cross = np.nonzero(s[:-1] * s[1:] < 0)[0]
    if cross.size == 0:
        return None
    i = cross[0]
    u0, u1 = us[i], us[i + 1]
    chord = u1 - u0
    length = np.linalg.norm(chord)
    t = chord / length
    lo, hi = 0.0, length
    s_lo = s[i]
    u_mid = u0
    for _ in range(n_bisect):
        mid = 0.5 * (lo + hi)
        u_mid, _D, Jz = _correct(make_scene, u0 + mid * t, t)
        if np.sign(np.trace(Jz) - 2) == s_lo:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-13 * max(1.0, length):
            break
    return u_mid


def continue_in_f(make_scene, pts, f_to, k=1, n_steps=5):
    """Natural-parameter continuation of a period-``k`` point from ``f = 0`` to ``f_to`` (Newton each step)."""
    x, v = np.array(pts[:, 0], float), np.array(pts[:, 1], float)
    for f in np.linspace(0, f_to, n_steps + 1)[1:]:
        x, v, ok, J = newton_periodic(make_scene(f), x, v, k)
        if not ok.all():
            raise RuntimeError(f"continue_in_f: Newton failed at f={f} from {pts}")
    return x, v, J
