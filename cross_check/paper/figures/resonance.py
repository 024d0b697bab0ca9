"""Fig. resonance (w = 2 pi, F = w^2, f = 24.65, r = R): the non-sticking fixed point through the
3:1 resonance ``tr Phi' = -1`` at R*, its island and the period-3 orbits around it."""
from __future__ import annotations

import numpy as np

from cross_check.dynamics import periodic
from cross_check.dynamics import portraits as por
from cross_check.paper.figures.base import QUICK, Drawn, figure, label, mark, new_figure, portrait
from cross_check.scenes import resonance


def resonance_centre(R, z0=None, q=QUICK):
    """The non-sticking fixed point of the resonance scene at ``r = R`` (Newton) and ``D Phi`` there."""
    sc = resonance(R)
    if z0 is None:
        fps = [o for o in por.periodic_points(sc, (0.0, float(R), -8.0, 8.0), q.newton_seeds) if not o.dissip]
        if not fps:
            raise RuntimeError(f"resonance_centre: no non-sticking fixed point at R={R}")
        o = min(fps, key=lambda o: abs(np.trace(o.J) + 1))
        return o.points[0], o.J
    res = periodic.newton(sc, [z0[0]], [z0[1]])
    if not res.converged[0]:
        raise RuntimeError(f"resonance_centre: Newton failed at R={R} from {z0}")
    return np.array([res.x[0], res.v[0]]), res.J[0]


def resonance_R_star(lo=0.89, hi=0.895, q=QUICK, xtol=1e-12):
    """``R*`` where the non-sticking fixed point has ``tr Phi' = -1`` (multipliers exp(+-2 pi i/3)).

    Brent's method on ``R -> tr D Phi(z(R)) + 1``, with ``z(R)`` Newton-continued from
    the previous evaluation.  Returns ``(R*, z(R*))``.
    """
    from scipy.optimize import brentq

    z, _J = resonance_centre(lo, q=q)
    state = {"z": z}

    def g(R):
        zz, J = resonance_centre(R, state["z"])
        state["z"] = zz
        return np.trace(J) + 1.0

    R = brentq(g, lo, hi, xtol=xtol, rtol=4 * np.finfo(float).eps, maxiter=100)
    return R, state["z"]


@figure("fig:resonance")
def fig_resonance(q, ctx):
    fig, axes = new_figure(1, 3, size=(4.0, 3.6))
    R_star, z_star = resonance_R_star(q=q)
    ctx["R_star"], ctx["R_star_z"] = R_star, z_star
    notes = []
    half = None
    for ax, R, tag in zip(axes, ("0.89", "0.8932", "0.895"), "abc"):
        sc = resonance(R)
        z, J = resonance_centre(R, z_star)
        if half is None:
            w = por.island_window(sc, z, q.n_line, q.n_iter, pad=0.4)
            half = (max(z[0] - w[0], w[1] - z[0]), max(z[1] - w[2], w[3] - z[1]))
        win = (z[0] - half[0], z[0] + half[0], z[1] - half[1], z[1] + half[1])
        lines = por.centre_line_starts(sc, z, win, q.n_line)
        portrait(ax, sc, win, q, lines, grid=(q.grid[0] // 2, q.grid[1] // 2))
        p3 = [o for o in por.periodic_points(sc, win, q.newton_seeds, k=3) if not o.dissip]
        for o in p3:
            mark(ax, o.points, "rD" if periodic.is_saddle(o.kind) else "kD", ms=4)
        tr = np.trace(J)
        mark(ax, z, "k*" if abs(tr) < 2 else "r*", ms=9)
        label(ax, f"({tag}) R = {R}: tr Phi' = {tr:.5f}")
        notes.append(f"R={R}: fixed point ({z[0]:.5f}, {z[1]:.5f}), tr {tr:.6f}, {len(p3)} period-3 orbit(s)")
    notes.append(f"tr Phi' = -1 (3:1 resonance) at R* = {R_star:.8f}: the caption's R* ~ 0.8932 is this value "
                 f"truncated (rounded it is {R_star:.4f}); panel (b) at R = 0.8932 is just below R*")
    cap = "fig:resonance -- F=omega^2, f=24.65, omega=2pi, l=0, r=R; red diamonds: period-3 saddles"
    return Drawn(fig, cap, [" | ".join(notes[:3]), notes[3]])
