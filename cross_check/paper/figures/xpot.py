"""Fig. xpotno: position-dependent forcing ``F cos(pi x/2) cos(w t)`` (eq. xpot), the orbits that
never reach zero velocity, those that do, and the set E of rest states (the printed eta is 1 - eta).

Its flights are numerical (``fast.ode``), ~10x dearer than the closed-form ones, so this figure
runs at a quarter of the iterates and a small grid.
"""
from __future__ import annotations

import time

import numpy as np

from cross_check.dynamics import portraits as por
from cross_check.paper.figures.base import (Drawn, Quality, caption, draw_orbits, figure, frame, label, log,
                                            mark, new_figure)
from cross_check.scenes import xpot


def xpot_supported():
    """Whether ``fast`` integrates the position-dependent forcing (paper eq. ``xpot``); reason if not."""
    try:
        x, v = por.phi(xpot(), np.array([0.0]), np.array([1.0]))
        if not np.isfinite(np.asarray(x)).all():
            return False, "fast returned non-finite states"
        return True, ""
    except (NotImplementedError, ValueError, TypeError, AttributeError) as exc:
        return False, f"{type(exc).__name__}: {exc}"


def _quality(q):
    return Quality(n_iter=max(20, q.n_iter // 4), grid=(max(3, q.grid[0] // 2), max(3, q.grid[1] // 2)),
                   n_line=max(6, q.n_line // 2), pixels=q.pixels,
                   newton_seeds=(4, 6) if q.name == "full" else (3, 3), name=q.name)


def _notes(xs, vs, cls, eta, f_over_F, n_centres, n_iter):
    diss = cls == "dissip"
    kept = ~diss
    ends_x, ends_v = xs[-1, diss], vs[-1, diss]
    at_rest = ends_v == 0
    inE = np.abs(ends_x) >= 1 - eta - 1e-12
    regular = int((cls[kept] == "regular").sum())
    return [f"E = {{|x| >= 1 - eta}}, eta = (2/pi) arcsin(f/F) = {eta:.4f}: |F cos(pi x/2)| <= f there. "
            f"The paper's eta = (2/pi) arccos(f/F) = {2 / np.pi * np.arccos(f_over_F):.4f} is 1 - eta (misprint)",
            f"{int(diss.sum())} starts reach zero velocity; after {n_iter} periods {int(at_rest.sum())} are at "
            f"rest at t = 0, {int((at_rest & inE).sum())} of them in E; {n_centres} non-sticking centre(s); "
            f"{regular} of the {int(kept.sum())} coloured orbits pass the Birkhoff test at this length"]


@figure("fig:xpotno")
def fig_xpotno(q, ctx):
    fig, axes = new_figure(1, 2, size=(5.0, 4.0))
    sc = xpot()
    ok, why = xpot_supported()
    cap = "fig:xpotno -- " + caption(sc)
    F, f = sc.float("F"), sc.float("f")
    eta = 2 / np.pi * np.arcsin(f / F)
    if not ok:
        for ax in axes:
            ax.text(0.5, 0.5, "fast does not support\nposition-dependent forcing yet\n" + why[:80],
                    ha="center", va="center", transform=ax.transAxes)
        return Drawn(fig, cap, [f"NOT COMPUTED: the engine does not support wavenumber yet ({why})"])
    xq = _quality(q)
    win = (-1.05, 1.05, -6.0, 6.0)
    fps = por.periodic_points(sc, win, xq.newton_seeds)
    cen = por.nonsticking(fps, "centre")
    probes = [por.centre_line_starts(sc, o.points[0], win, xq.n_line) for o in cen]
    gx, gv = por.grid_starts(win, *xq.grid, -1.0, 1.0)
    x0 = np.concatenate([p[0] for p in probes] + [gx])
    v0 = np.concatenate([p[1] for p in probes] + [gv])
    t0 = time.perf_counter()
    xs, vs, first = por.run_orbits(sc, x0, v0, xq.n_iter)
    log(f"  xpot: {x0.size} orbits x {xq.n_iter} in {time.perf_counter() - t0:.1f} s")
    cls, _ = por.orbit_classes(sc, xs, vs, first)
    diss = cls == "dissip"
    kept = ~diss
    draw_orbits(axes[0], xs[:, kept], vs[:, kept], np.full(int(kept.sum()), "regular", dtype=object))
    for o in cen:
        mark(axes[0], o.points, "k*", ms=8)
    for o in por.nonsticking(fps, "saddle"):
        mark(axes[0], o.points, "r*", ms=8)
    label(axes[0], f"(a) colour: orbits never at zero velocity in {xq.n_iter} periods ({int(kept.sum())})")
    axes[1].plot(xs[:, diss].ravel(), vs[:, diss].ravel(), ".", color="k", ms=1.0, mew=0, rasterized=True)
    for a, b in ((-1, -1 + eta), (1 - eta, 1)):
        axes[1].plot((a, b), (0, 0), "-", color="orange", lw=4, zorder=5)
    label(axes[1], f"(b) orbits reaching zero velocity ({int(diss.sum())}, black), the set E (orange)")
    for ax in axes:
        frame(ax, sc, win)
    return Drawn(fig, cap, _notes(xs, vs, cls, eta, f / F, len(cen), xq.n_iter))
