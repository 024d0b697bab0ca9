"""Fig. nofriction (the frictionless portraits, R = 0.8, 4, 20) and Fig. narrow-with-friction
(R = 0.8, f = 0.005: island A, the focus and the stable period-5 orbit with their basins).

The r = 0.8 scene's fixed points, central island and period-5 orbits are computed once per run
(``narrow_data``) and shared by both figures.
"""
from __future__ import annotations

import time

import numpy as np

from cross_check.dynamics import periodic
from cross_check.dynamics import portraits as por
from cross_check.dynamics.continuation import continue_in_f
from cross_check.paper.figures.base import (Drawn, counts, draw_orbits, figure, frame, label, log, mark,
                                            new_figure, portrait)
from cross_check.scenes import narrow, wide


def central_centre(centres):
    """The centre of the central island of the r = 0.8 scene: the one whose orbit has turning
    points (paper: four impacts and two turning points a period), of smallest ``|v|``."""
    turning = [o for o in centres if o.dissip]
    if not turning:
        raise RuntimeError("no centre with turning points found in the r = 0.8 scene")
    return min(turning, key=lambda o: abs(o.points[0, 1]))


def narrow_data(q, ctx):
    """The frictionless r = 0.8 scene's fixed points, central island (probe run, zoom window)
    and its elliptic period-5 orbits, computed once per run (shared with fig:narrow-with-friction)."""
    if "narrow" in ctx:
        return ctx["narrow"]
    sc = narrow()
    win = (-0.05, 0.85, -2.6, 2.6)
    fps = por.periodic_points(sc, win, q.newton_seeds)
    zc = central_centre([o for o in fps if o.kind == "centre"]).points[0]
    px, pv = por.centre_line_starts(sc, zc, win, q.n_line)
    probe = por.run_orbits(sc, px, pv, q.n_iter)
    pcls, _ = por.orbit_classes(sc, *probe)
    zwin = por.island_box(probe[0], probe[1], pcls, zc, pad=0.4)
    # the elliptic period-5 orbit of the island is symmetric under the time reversal (x, v) -> (x, -v)
    # of the frictionless map, so it crosses v = 0: seeds on that line suffice
    p5 = [o for o in por.periodic_points(sc, zwin, q.newton_seeds, k=5, grid=False) if o.kind == "centre"]
    ctx["narrow"] = {"centre": zc, "zoom": zwin, "p5": [o.points for o in p5], "fps": fps,
                     "probe": probe, "probe_cls": pcls, "window": win}
    return ctx["narrow"]


@figure("fig:nofriction")
def fig_nofriction(q, ctx):
    fig, axes = new_figure(2, 2)
    sc = narrow()
    d = narrow_data(q, ctx)
    win, zc, zwin = d["window"], d["centre"], d["zoom"]
    run = portrait(axes[0], sc, win, q)
    draw_orbits(axes[0], d["probe"][0], d["probe"][1], d["probe_cls"])
    label(axes[0], f"(a) R = 0.8: {counts(run['cls'])}")
    # (b) the central island (its centre: 4 impacts + 2 turning points a period)
    zx, zv = por.line_starts(zc, np.array([zwin[1], zc[1]]), q.n_line)
    run = portrait(axes[1], sc, zwin, q, (zx, zv), grid=(q.grid[0] // 2, q.grid[1] // 2))
    draw_orbits(axes[1], d["probe"][0], d["probe"][1], d["probe_cls"])
    mark(axes[1], zc, "k+", ms=8)
    for pts in d["p5"]:
        mark(axes[1], pts, "kx", ms=6)
    label(axes[1], f"(b) zoom: + centre ({zc[0]:.4f}, {zc[1]:.4f}), x period 5 ({len(d['p5'])})")
    for ax, R, win, tag in ((axes[2], 4, (-0.3, 4.3, -3.0, 3.0), "c"), (axes[3], 20, (-1.0, 21.0, -9.0, 9.0), "d")):
        sc = wide(0, R)
        run = portrait(ax, sc, win, q)
        seg = por.no_impact_segment(sc)
        ax.plot(seg, (0, 0), "k-", lw=2.0, zorder=7)
        label(ax, f"({tag}) R = {R}: {counts(run['cls'])}")
    cap = ("fig:nofriction -- F=1, f=0, omega=1, l=0; (a) r=0.8, (b) zoom of (a)'s central island "
           "(+: fixed point, x: elliptic period-5 orbit), (c) r=4, (d) r=20; colour: invariant curves, grey: "
           "chaotic sea, black: segment of fixed points without impacts v=0, l<=x<=r-2F/omega^2")
    return Drawn(fig, cap, [])


def island_a_centres(sc, fps0):
    """Island A's centres at the scene's friction: Newton from the f = 0 non-sticking centres (two impacts
    a period, ``|tr| < 1.9``), moved off the wall, with both velocity signs; the distinct non-sticking
    centres found."""
    import fast
    l, r = sc.float("l"), sc.float("r")
    a0 = [o.points[0] for o in fps0 if o.kind == "centre" and not o.dissip and abs(np.trace(o.J)) < 1.9]
    sx = np.array([min(z[0], r - 0.02 * (r - l)) for z in a0 for _s in (1, -1)])
    sv = np.array([sg * abs(z[1]) for z in a0 for sg in (1, -1)])
    if sx.size == 0:
        return []
    res = periodic.newton(sc, sx, sv)
    zvA = np.asarray(fast.zero_velocity(sc, res.x, res.v), bool)
    kind, _ = periodic.classify(res.J)
    found = []
    for i in np.nonzero(res.converged & ~zvA & (kind == "centre"))[0]:
        z = np.array([res.x[i], res.v[i]])
        if all(np.abs(z - w).max() > 1e-6 for w in found):
            found.append(z)
    return found


def basin_notes(xs, vs, cls, focus, lam, p5s, n):
    """Where the white region's orbits go: the nearest attractor point of the last iterate (within 2e-2)."""
    diss = cls == "dissip"
    ends = np.stack([xs[-1, diss], vs[-1, diss]], -1)
    targets = [focus] + [p for pts, _m in p5s for p in pts]
    dist = np.stack([np.abs(ends - t).max(-1) for t in targets], -1)
    near = dist.min(-1) < 2e-2
    at_focus = near & (dist.argmin(-1) == 0)
    at_p5 = near & (dist.argmin(-1) > 0)
    pm = ", ".join(f"{m:.4f}" for _p, m in p5s)
    notes = [f"focus ({focus[0]:.5f}, {focus[1]:.5f}), |multipliers| {lam[0]:.4f}, {lam[1]:.4f}; stable "
             f"period-5 orbit(s) max |multiplier| {pm}; of {int(diss.sum())} white-region starts after {n} "
             f"periods: {int(at_focus.sum())} within 2e-2 of the focus, {int(at_p5.sum())} of the period-5 "
             f"orbit, {int((~near).sum())} still in transit"]
    if at_p5.any():
        notes.append("the caption says ALL white-region starts are attracted to the focus; computed: the white "
                     "region is the union of the basins of the focus and of the stable period-5 orbit (as the "
                     "text says)")
    return notes


def _attractors(sc, d, notes):
    """The focus (continued from the f = 0 centre) and the stable period-5 orbits (from the elliptic ones)."""
    import fast
    fx, fv, fJ = continue_in_f(lambda f: narrow(f), d["centre"][None, :], 0.005)
    focus = np.array([fx[0], fv[0]])
    lam = np.abs(periodic.multipliers(fJ[0]))
    p5s = []
    for pts in d["p5"]:
        try:
            px, pv, pJ = continue_in_f(lambda f: narrow(f), pts[:1], 0.005, k=5, n_steps=2)
        except RuntimeError as exc:
            notes.append(f"period-5 continuation failed: {exc}")
            continue
        xs5, vs5 = fast.orbit(sc, px, pv, 4)
        p5s.append((np.stack([np.asarray(xs5)[:, 0], np.asarray(vs5)[:, 0]], -1),
                    np.abs(periodic.multipliers(pJ[0])).max()))
    return focus, lam, p5s


@figure("fig:narrow-with-friction")
def fig_narrow_with_friction(q, ctx):
    d = narrow_data(q, ctx)
    fig, axes = new_figure(1, 2)
    notes = []
    sc = narrow("0.005")
    win = d["window"]
    l, r = sc.float("l"), sc.float("r")
    a_cen = island_a_centres(sc, d["fps"])
    probes = []
    for z in a_cen:
        hx, hv = por.centre_line_starts(sc, z, win, q.n_line // 2)
        vv = np.geomspace(1e-5, 0.5, q.n_line // 4)
        probes += [(hx, hv), (np.full(vv.shape, z[0]), z[1] + vv), (np.full(vv.shape, z[0]), z[1] - vv)]
    focus, lam, p5s = _attractors(sc, d, notes)
    # one batch: the grid of (a), the probes of island A, the grid of the zoom (b); twice the iterates
    zwin = d["zoom"]
    gx, gv = por.grid_starts(win, *q.grid, l, r)
    zx, zv = por.grid_starts(zwin, q.grid[0] // 2, q.grid[1] // 2, l, r)
    x0 = np.concatenate([gx] + [p[0] for p in probes] + [zx])
    v0 = np.concatenate([gv] + [p[1] for p in probes] + [zv])
    n = q.n_iter
    t0 = time.perf_counter()
    xs, vs, first = por.run_orbits(sc, np.clip(x0, l, r), v0, n)
    cls, _ = por.orbit_classes(sc, xs, vs, first)
    log(f"  narrow f=0.005: {x0.size} orbits x {n} in {time.perf_counter() - t0:.1f} s: {counts(cls)}")
    nz = zx.size
    draw_orbits(axes[0], xs[:, :-nz], vs[:, :-nz], cls[:-nz])
    axes[1].plot(xs[: q.n_iter // 2, -nz:].ravel(), vs[: q.n_iter // 2, -nz:].ravel(), ".", color="0.6",
                 ms=1.0, mew=0, rasterized=True, zorder=1)
    for ax, w in ((axes[0], win), (axes[1], zwin)):
        for z in a_cen:
            mark(ax, z, "k*", ms=7)
        mark(ax, focus, "ko", ms=5)
        for pts, _m in p5s:
            mark(ax, pts, "ro", ms=4)
        frame(ax, sc, w)
    label(axes[0], f"(a) r = 0.8, f = 0.005: {counts(cls)}")
    label(axes[1], "(b) zoom as Fig. 1b: transients (grey)")
    notes += basin_notes(xs, vs, cls, focus, lam, p5s, n)
    cap = ("fig:narrow-with-friction -- F=1, f=0.005, omega=1, l=0, r=0.8; white: basin of the attractors; "
           "colour: invariant curves (island A); black dot: focus; red dots: period-5 orbit")
    return Drawn(fig, cap, notes)
