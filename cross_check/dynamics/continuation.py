"""Branches of fixed points in a parameter: pseudo-arclength continuation, folds, thresholds.

* ``continue_branch`` follows a curve of fixed points ``G(z, p) = Phi_p(z) - z = 0``
  (``fast``) by pseudo-arclength continuation: tangent ``t`` spans ``ker DG``, predictor
  ``u + ds t``, corrector Newton on ``[G(u); t.(u - u_pred)] = 0``.  ``dG/dp`` is a
  central difference (the map is smooth in ``f`` and ``r`` along non-sticking orbits).
* ``locate_fold`` finds the saddle-centre point on a branch, where a multiplier is 1,
  i.e. ``tr D Phi = 2`` (``det = 1``), by bisection in arclength.
* ``continue_in_f`` is natural-parameter continuation: ``periodic.newton`` at each step.
* ``extended_newton`` solves the extended system ``Phi_p(z) = z``, ``c(D Phi) = 0`` for
  ``(x, v, p)`` on the reference map (a fold ``c = tr - 2``, a 3:1 resonance ``c = tr + 1``):
  Newton with a central-difference Jacobian at ``dps`` digits.
"""
from __future__ import annotations

import mpmath
import numpy as np

from cross_check.dynamics import periodic

#: the corrector stops when ``|Phi(z) - z|_inf <= NEWTON_TOL * max(1, |z|_inf)``
NEWTON_TOL = 1e-11
NEWTON_MAX_ITER = 40
#: ``extended_newton``'s iteration bound
MAX_EXTENDED = 60


def _phi(scene, x, v):
    import fast
    X, V = fast.stroboscopic_map(scene, np.asarray(x, float), np.asarray(v, float))
    return np.asarray(X, float), np.asarray(V, float)


def _G(make_scene, u):
    """Residual ``Phi_p(z) - z`` and the full Jacobian ``[D_z Phi - I | d Phi/dp]`` at ``u = (x, v, p)``."""
    import fast
    sc = make_scene(u[2])
    x1, v1 = _phi(sc, [u[0]], [u[1]])
    Jz = np.asarray(fast.jacobian(sc, np.array([u[0]]), np.array([u[1]])), float)[0]
    h = 1e-6 * max(1.0, abs(u[2]))
    xp, vp = _phi(make_scene(u[2] + h), [u[0]], [u[1]])
    xm, vm = _phi(make_scene(u[2] - h), [u[0]], [u[1]])
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
        res = periodic.newton(make_scene(f), x, v, period=k)
        if not res.converged.all():
            raise RuntimeError(f"continue_in_f: Newton failed at f={f} from {pts}")
        x, v, J = res.x, res.v, res.J
    return x, v, J


def extended_newton(make_scene, p0, x0, v0, condition, *, dps=50, h=None):
    """Solve ``Phi(z; p) = z`` and ``condition(J) = 0`` for ``(x, v, p)`` (reference map, ``dps`` digits).

    ``make_scene(p)`` builds the scene for parameter ``p``; ``condition(J)`` of the 2x2 mpmath
    matrix ``D Phi`` is e.g. ``tr J - 2`` (a fold) or ``tr J + 1`` (3:1 resonance).  Newton with a
    central-difference Jacobian (step ``h``, default ``10^(-dps/3)``) until the residual is below
    ``10^(10 - dps)``; ``RuntimeError`` after ``MAX_EXTENDED`` steps.  Returns ``(p, x, v, J)``.
    """
    engine = periodic.Reference(dps)
    with mpmath.workdps(dps):
        h = h or mpmath.mpf(10) ** (-(dps // 3))
        u = mpmath.matrix([x0, v0, p0])

        def F(u):
            X, V, J = periodic.map_and_jacobian(make_scene(u[2]), u[0], u[1], engine=engine)
            J = mpmath.matrix(J[0].tolist())
            return mpmath.matrix([X[0] - u[0], V[0] - u[1], condition(J)]), J

        for _ in range(MAX_EXTENDED):
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
