"""Fig. three:per (w = 2 pi, f = 0.05): the fixed points' and the period-3 orbits' islands, the
unstable manifold of the saddle, and where starts near the unstable period-3 orbit go."""
from __future__ import annotations

import numpy as np

from cross_check.dynamics import periodic
from cross_check.dynamics import portraits as por
from cross_check.paper.figures.base import Drawn, draw_orbits, draw_walls, figure, label, mark, new_figure
from cross_check.scenes import two_pi


def _starts(sc, zc, p3, win, q):
    """Probes of the fixed point's and the period-3 islands, then perturbations of the unstable
    period-3 points (8 each, 1e-3, seeded); returns the starts and how many are probes."""
    starts = [por.centre_line_starts(sc, zc, win, q.n_line)]
    starts += [por.centre_line_starts(sc, o.points[0], (-1, 1, -2.5, 2.5), q.n_line // 2)
               for o in p3 if o.kind == "centre"]
    rng = np.random.default_rng(7)
    n_probe = sum(st[0].size for st in starts)
    for o in p3:
        if periodic.is_saddle(o.kind):
            pts = np.repeat(o.points, 8, axis=0)
            d = 1e-3 * rng.standard_normal(pts.shape)
            starts.append((np.clip(pts[:, 0] + d[:, 0], -1, 1), pts[:, 1] + d[:, 1]))
    return np.concatenate([st[0] for st in starts]), np.concatenate([st[1] for st in starts]), n_probe


@figure("fig:three:per")
def fig_three_per(q, ctx):
    fig, axes = new_figure(1, 2, size=(5.0, 4.2))
    sc = two_pi("0.05")
    win = (-1.1, 1.1, -7.0, 7.0)
    c, s, _ = por.saddle_centre_pair(sc, win, q.newton_seeds)
    p3 = [o for o in por.periodic_points(sc, win, q.newton_seeds, k=3) if not o.dissip]
    zc, zs = c.points[0], s.points[0]
    x0, v0, n_probe = _starts(sc, zc, p3, win, q)
    xs, vs, first = por.run_orbits(sc, x0, v0, q.n_iter)
    cls, _ = por.orbit_classes(sc, xs[:, :n_probe], vs[:, :n_probe], first[:n_probe])
    mx, mv, mfirst = por.unstable_manifold(sc, zs, s.J, n_seeds=max(20, q.n_line * 4),
                                           n_iter=max(10, q.n_iter // 20))
    keep = np.arange(mx.shape[0])[:, None] < mfirst[None, :]
    for ax in axes:
        draw_orbits(ax, xs[:, :n_probe], vs[:, :n_probe], cls)
        ax.plot(xs[:, n_probe:].ravel(), vs[:, n_probe:].ravel(), ".", color="k", ms=1.0, mew=0, zorder=3,
                rasterized=True)
        ax.plot(mx[keep], mv[keep], "o", color="k", ms=1.6, mew=0, zorder=4, rasterized=True)
        mark(ax, zc, "k*", ms=12)
        mark(ax, zs, "r*", ms=12)
        for o in p3:
            mark(ax, o.points, "kD" if o.kind == "centre" else "rD", ms=6)
        draw_walls(ax, sc)
        ax.set_xlabel("x")
        ax.set_ylabel("v")
    axes[0].set_xlim(win[0], win[1])
    axes[0].set_ylim(win[2], win[3])
    axes[1].set_xlim(-1.05, 1.05)
    axes[1].set_ylim(-2.5, 2.5)
    label(axes[0], "(a) stars: fixed points, diamonds: period 3, big dots: unstable manifold")
    label(axes[1], "(b) the period-3 orbits (zoom on |v| < 2.5)")
    lam = np.abs(periodic.multipliers(s.J))
    conv = first[n_probe:] <= q.n_iter
    notes = [f"centre ({zc[0]:.5f}, {zc[1]:.5f}), saddle ({zs[0]:.5f}, {zs[1]:.5f}) multipliers "
             f"{lam.min():.4f}, {lam.max():.4f}; period-3 non-sticking orbits: "
             + ", ".join(f"{o.kind} at ({o.points[0, 0]:.4f}, {o.points[0, 1]:.4f})" for o in sorted(p3, key=lambda o: o.kind))
             + f"; {int(conv.sum())}/{conv.size} perturbed unstable period-3 starts reach Omega_dissip "
               f"within {q.n_iter} periods"]
    cap = ("fig:three:per -- F=1, f=0.05, omega=2pi, l=-1, r=1; black/red stars: centre/saddle, "
           "black/red diamonds: stable/unstable period 3, small dots: orbits started near unstable period 3")
    return Drawn(fig, cap, notes)
