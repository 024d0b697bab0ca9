"""Regenerate the paper's figures: ``python -m cross_check figures [--out DIR] [--only NAME] [--quick]``.

One PNG per figure of the paper, named after its label (``fig:nofriction`` ->
``fig_nofriction.png``), panels as in the paper, a one-line caption with the
parameters under each figure and a note where what we compute contradicts the
caption.  Everything is computed on the float64 engine ``fast``:

* phase portraits: orbits of a grid of starts (plus lines of starts through the
  centres found by Newton), classified as regular / chaotic / dissipative by
  ``cross_check.portraits`` (weighted Birkhoff averages; ``fast.zero_velocity``);
* fixed and periodic points by Newton, their type by the multipliers, the fold by
  pseudo-arclength continuation (``cross_check.continuation``);
* ``Omega_dissip`` and ``det Phi'`` on a pixel grid (``fast.zero_velocity``,
  ``fast.jacobian``).

Progress lines go to stderr; the figure set takes about 35 s on two cores (``--quick``: seconds).
"""
from __future__ import annotations

import argparse
import os
import sys
import time
from dataclasses import dataclass

import numpy as np

from reference.scene import Scene
from cross_check import continuation as cont
from cross_check import portraits as por
from cross_check.continuation import continue_in_f
from cross_check.portraits import (centre_line_starts, classify, island_box, island_window, mark, nonsticking,
                                   periodic_points, regular_threshold, saddle_centre_pair)


@dataclass(frozen=True)
class Quality:
    """Resolution of a run: iterates per orbit, start grid, starts per line, pixels."""

    n_iter: int
    grid: tuple
    n_line: int
    pixels: int
    newton_seeds: tuple
    name: str


FULL = Quality(n_iter=1000, grid=(30, 36), n_line=120, pixels=200, newton_seeds=(10, 14), name="full")
QUICK = Quality(n_iter=80, grid=(5, 6), n_line=8, pixels=32, newton_seeds=(5, 6), name="quick")


def log(msg):
    print(f"[figures] {msg}", file=sys.stderr, flush=True)


# ----------------------------------------------------------------------------- scenes
def narrow(f=0, r="0.8"):
    return Scene(F=1, f=f, omega=1, l=0, r=r)


def wide(f=0, r=20):
    return Scene(F=1, f=f, omega=1, l=0, r=r)


def two_pi(f):
    return Scene(F=1, f=f, omega="2*pi", l=-1, r=1)


def resonance(r):
    return Scene(F="(2*pi)**2", f="24.65", omega="2*pi", l=0, r=r)


def xpot():
    return Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2")


def caption(scene, extra=""):
    p = scene.floats()
    text = (f"F={scene.F}, f={scene.f}, omega={scene.omega}, l={scene.l}, r={scene.r}"
            + (f", wavenumber={scene.wavenumber}" if p["wavenumber"] is not None else ""))
    return text + (f"; {extra}" if extra else "")


# ----------------------------------------------------------------------------- helpers
def portrait(ax, scene, window, q, extra_starts=None, grid=None, draw_attractor=True, n_iter=None):
    """Orbits of a start grid plus ``extra_starts`` drawn on ``ax``; returns the run's data."""
    l, r = scene.float("l"), scene.float("r")
    gx, gv = por.grid_starts(window, *(grid or q.grid), l, r)
    if extra_starts is not None:
        gx = np.concatenate([gx, extra_starts[0]])
        gv = np.concatenate([gv, extra_starts[1]])
    n = n_iter or q.n_iter
    t0 = time.perf_counter()
    xs, vs, first = por.run_orbits(scene, np.clip(gx, l, r), gv, n)
    cls, digits = classify(scene, xs, vs, first)
    log(f"  portrait f={scene.f} r={scene.r}: {gx.size} orbits x {n} in {time.perf_counter() - t0:.1f} s: "
        f"{counts(cls)}")
    por.draw_orbits(ax, xs, vs, cls)
    diss = cls == "dissip"
    if draw_attractor and diss.any():
        ax.plot(xs[-1, diss], vs[-1, diss], "o", color="k", ms=1.5, zorder=5)
    por.draw_walls(ax, scene)
    ax.set_xlim(window[0], window[1])
    ax.set_ylim(window[2], window[3])
    ax.set_xlabel("x")
    ax.set_ylabel("v")
    return {"xs": xs, "vs": vs, "cls": cls, "digits": digits, "first": first}


def counts(cls):
    return ", ".join(f"{k} {int((cls == k).sum())}" for k in ("regular", "chaotic", "dissip"))


def new_figure(nrows, ncols, size=(4.2, 3.6)):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(nrows, ncols, figsize=(size[0] * ncols, size[1] * nrows),
                             squeeze=False)
    return fig, axes.ravel()


def finish(fig, path, cap, notes=()):
    """Caption and notes (wrapped to the figure width) under the figure, then save."""
    import textwrap

    import matplotlib.pyplot as plt

    w_in, h_in = fig.get_size_inches()
    lines = []
    for i, text in enumerate([cap] + [f"NOTE: {n}" for n in notes]):
        lines += [(part, "black" if i == 0 else "darkred")
                  for part in textwrap.wrap(text, width=int(w_in * 15.5), subsequent_indent="    ")]
    line_h = 0.15
    extra = line_h * len(lines) + 0.15
    fig.set_size_inches(w_in, h_in + extra)
    fig.tight_layout(rect=(0, (extra + 0.05) / (h_in + extra), 1, 1))
    for i, (line, colour) in enumerate(lines):
        y = (extra - 0.05 - line_h * (i + 1)) / (h_in + extra)
        fig.text(0.01, y, line, fontsize=8, ha="left", va="bottom", color=colour)
    fig.savefig(path, dpi=100)
    plt.close(fig)


def label(ax, text):
    ax.set_title(text, fontsize=9, loc="left")


# ----------------------------------------------------------------------------- figures
def central_centre(centres):
    """The centre of the central island of the r = 0.8 scene: the one whose orbit has turning
    points (paper: four impacts and two turning points a period), of smallest ``|v|``."""
    turning = [o for o in centres if o["dissip"]]
    if not turning:
        raise RuntimeError("no centre with turning points found in the r = 0.8 scene")
    return min(turning, key=lambda o: abs(o["points"][0, 1]))


def narrow_data(q, ctx):
    """The frictionless r = 0.8 scene's fixed points, central island (probe run, zoom window)
    and its elliptic period-5 orbits, computed once per run (shared with fig:narrow-with-friction)."""
    if "narrow" in ctx:
        return ctx["narrow"]
    sc = narrow()
    win = (-0.05, 0.85, -2.6, 2.6)
    fps = periodic_points(sc, win, q)
    zc = central_centre([o for o in fps if o["type"] == "centre"])["points"][0]
    px, pv = centre_line_starts(sc, zc, win, q.n_line)
    probe = por.run_orbits(sc, px, pv, q.n_iter)
    pcls, _ = classify(sc, *probe)
    zwin = island_box(probe[0], probe[1], pcls, zc, pad=0.4)
    # the elliptic period-5 orbit of the island is symmetric under the time reversal (x, v) -> (x, -v)
    # of the frictionless map, so it crosses v = 0: seeds on that line suffice
    p5 = [o for o in periodic_points(sc, zwin, q, k=5, grid=False) if o["type"] == "centre"]
    ctx["narrow"] = {"centre": zc, "zoom": zwin, "p5": [o["points"] for o in p5], "fps": fps,
                     "probe": probe, "probe_cls": pcls, "window": win}
    return ctx["narrow"]


def fig_nofriction(q, ctx):
    fig, axes = new_figure(2, 2)
    sc = narrow()
    d = narrow_data(q, ctx)
    win, zc, zwin = d["window"], d["centre"], d["zoom"]
    run = portrait(axes[0], sc, win, q)
    por.draw_orbits(axes[0], d["probe"][0], d["probe"][1], d["probe_cls"])
    label(axes[0], f"(a) R = 0.8: {counts(run['cls'])}")
    # (b) the central island (its centre: 4 impacts + 2 turning points a period)
    zx, zv = por.line_starts(zc, np.array([zwin[1], zc[1]]), q.n_line)
    run = portrait(axes[1], sc, zwin, q, (zx, zv), grid=(q.grid[0] // 2, q.grid[1] // 2))
    por.draw_orbits(axes[1], d["probe"][0], d["probe"][1], d["probe_cls"])
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
    return fig, cap, []


def island_a_centres(sc, fps0):
    """Island A's centres at the scene's friction: Newton from the f = 0 non-sticking centres (two impacts
    a period, ``|tr| < 1.9``), moved off the wall, with both velocity signs; the distinct non-sticking
    centres found."""
    l, r = sc.float("l"), sc.float("r")
    a0 = [o["points"][0] for o in fps0 if o["type"] == "centre" and not o["dissip"]
          and abs(np.trace(o["J"])) < 1.9]
    sx = np.array([min(z[0], r - 0.02 * (r - l)) for z in a0 for _s in (1, -1)])
    sv = np.array([sg * abs(z[1]) for z in a0 for sg in (1, -1)])
    if sx.size == 0:
        return []
    ax_, av_, aok, aJ = cont.newton_periodic(sc, sx, sv)
    zvA = np.asarray(cont.engine().zero_velocity(sc, ax_, av_), bool)
    found = []
    for i in np.nonzero(aok & ~zvA & (cont.classify(aJ) == "centre"))[0]:
        z = np.array([ax_[i], av_[i]])
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
        hx, hv = centre_line_starts(sc, z, win, q.n_line // 2)
        vv = np.geomspace(1e-5, 0.5, q.n_line // 4)
        probes += [(hx, hv), (np.full(vv.shape, z[0]), z[1] + vv), (np.full(vv.shape, z[0]), z[1] - vv)]
    # the attractors, continued from the f = 0 centre and elliptic period-5 orbits
    fx, fv, fJ = continue_in_f(lambda f: narrow(f), d["centre"][None, :], 0.005)
    focus = np.array([fx[0], fv[0]])
    lam = np.abs(cont.multipliers(fJ[0]))
    p5s = []
    for pts in d["p5"]:
        try:
            px, pv, pJ = continue_in_f(lambda f: narrow(f), pts[:1], 0.005, k=5, n_steps=2)
        except RuntimeError as exc:
            notes.append(f"period-5 continuation failed: {exc}")
            continue
        xs5, vs5 = cont.engine().orbit(sc, px, pv, 4)
        p5s.append((np.stack([np.asarray(xs5)[:, 0], np.asarray(vs5)[:, 0]], -1),
                    np.abs(cont.multipliers(pJ[0])).max()))
    # one batch: the grid of (a), the probes of island A, the grid of the zoom (b); twice the iterates
    zwin = d["zoom"]
    gx, gv = por.grid_starts(win, *q.grid, l, r)
    zx, zv = por.grid_starts(zwin, q.grid[0] // 2, q.grid[1] // 2, l, r)
    x0 = np.concatenate([gx] + [p[0] for p in probes] + [zx])
    v0 = np.concatenate([gv] + [p[1] for p in probes] + [zv])
    n = q.n_iter
    t0 = time.perf_counter()
    xs, vs, first = por.run_orbits(sc, np.clip(x0, l, r), v0, n)
    cls, _ = classify(sc, xs, vs, first)
    log(f"  narrow f=0.005: {x0.size} orbits x {n} in {time.perf_counter() - t0:.1f} s: {counts(cls)}")
    nz = zx.size
    por.draw_orbits(axes[0], xs[:, :-nz], vs[:, :-nz], cls[:-nz])
    axes[1].plot(xs[: q.n_iter // 2, -nz:].ravel(), vs[: q.n_iter // 2, -nz:].ravel(), ".", color="0.6",
                 ms=1.0, mew=0, rasterized=True, zorder=1)
    for ax, w in ((axes[0], win), (axes[1], zwin)):
        for z in a_cen:
            mark(ax, z, "k*", ms=7)
        mark(ax, focus, "ko", ms=5)
        for pts, _m in p5s:
            mark(ax, pts, "ro", ms=4)
        por.draw_walls(ax, sc)
        ax.set_xlim(w[0], w[1])
        ax.set_ylim(w[2], w[3])
        ax.set_xlabel("x")
        ax.set_ylabel("v")
    label(axes[0], f"(a) r = 0.8, f = 0.005: {counts(cls)}")
    label(axes[1], "(b) zoom as Fig. 1b: transients (grey)")
    notes += basin_notes(xs, vs, cls, focus, lam, p5s, n)
    cap = ("fig:narrow-with-friction -- F=1, f=0.005, omega=1, l=0, r=0.8; white: basin of the attractors; "
           "colour: invariant curves (island A); black dot: focus; red dots: period-5 orbit")
    return fig, cap, notes


def friction_panel(ax, sc, win, q, tag, extra_centres=()):
    """A portrait with friction: island(s) around non-sticking centres (fixed points, plus the points
    ``extra_centres`` of other periodic orbits), the attractor in black."""
    fps = periodic_points(sc, win, q)
    cen = nonsticking(fps, "centre")
    starts = [centre_line_starts(sc, o["points"][0], win, q.n_line) for o in cen]
    starts += [centre_line_starts(sc, z, win, max(4, q.n_line // 4)) for z in extra_centres]
    extra = (np.concatenate([s[0] for s in starts]), np.concatenate([s[1] for s in starts])) if starts else None
    run = portrait(ax, sc, win, q, extra)
    for o in cen:
        mark(ax, o["points"], "k*", ms=6)
    for o in nonsticking(fps, "saddle"):
        mark(ax, o["points"], "r*", ms=6)
    if len(extra_centres):
        mark(ax, np.asarray(extra_centres), "kD", ms=3)
    label(ax, f"({tag}) f = {sc.f}: {counts(run['cls'])}")
    return run, cen


def period3_centres(sc, seed):
    """The non-sticking elliptic period-3 orbit continued from ``seed`` (3 points), or [] if lost."""
    x, v, ok, J = cont.newton_periodic(sc, seed[:1, 0], seed[:1, 1], k=3)
    if not ok[0] or cont.classify(J)[0] != "centre":
        return []
    ox, ov = cont.engine().orbit(sc, x, v, 2)
    if np.asarray(cont.engine().zero_velocity(sc, ox.ravel(), ov.ravel())).any():
        return []
    return list(np.stack([ox[:, 0], ov[:, 0]], -1))


def attractor_note(run, scene):
    """Whether the dissipative orbits have ended on fixed points (``Phi(z) = z`` within 1e-9): the attractor."""
    diss = run["cls"] == "dissip"
    if not diss.any():
        return f"f={scene.f}: no start reached Omega_dissip"
    ex, ev = run["xs"][-1, diss], run["vs"][-1, diss]
    fx, fv = cont.phi(scene, ex, ev)
    fixed = np.maximum(np.abs(np.asarray(fx) - ex), np.abs(np.asarray(fv) - ev)) < 1e-9
    n = run["xs"].shape[0] - 1
    if not fixed.any():
        return f"f={scene.f}: none of {int(diss.sum())} dissipative orbits has settled on a fixed point in {n} periods"
    return (f"f={scene.f}: {int(fixed.sum())}/{int(diss.sum())} dissipative orbits end on fixed points "
            f"(x in [{ex[fixed].min():.3f}, {ex[fixed].max():.3f}]) in {n} periods")


def fig_many_wide(q, ctx):
    fig, axes = new_figure(2, 3, size=(4.0, 3.4))
    notes = []
    win = (-1.0, 21.0, -10.0, 10.0)
    for ax, f, tag in zip(axes, ("0.1", "0.2", "0.3", "0.4", "0.5", "0.6"), "abcdef"):
        sc = wide(f)
        run, cen = friction_panel(ax, sc, win, q, tag)
        notes.append(attractor_note(run, sc) + f"; {len(cen)} non-sticking centre(s)")
        log(f"  fig_many_wide f={f}: {counts(run['cls'])}")
    cap = ("fig:many:wide -- F=1, omega=1, l=0, r=20, f=0.1..0.6; colour: invariant curves, grey: chaotic, "
           "black dots: where dissipative orbits end (attractor), stars: non-sticking centre (black) / saddle (red)")
    return fig, cap, [" | ".join(notes[:3]), " | ".join(notes[3:])]


def fig_many_2pi(q, ctx):
    fig, axes = new_figure(2, 3, size=(4.0, 3.4))
    notes = []
    win = (-1.1, 1.1, -7.0, 7.0)
    # the elliptic period-3 orbit of the subharmonic islands (paper: they survive up to panel e);
    # seed: its point at f = 0.05 as found by fig:three:per's Newton search, continued panel to panel
    seed3 = np.array([[-0.4066, 1.3805]])
    for ax, f, tag in zip(axes, ("0.005", "0.01", "0.05", "0.1", "0.2", "0.3"), "abcdef"):
        sc = two_pi(f)
        p3 = period3_centres(sc, seed3)
        run, cen = friction_panel(ax, sc, win, q, tag, p3)
        if p3:
            seed3 = np.asarray(p3)
        notes.append(attractor_note(run, sc) + f"; period-3 centre {'found' if p3 else 'absent'}")
        log(f"  fig_many_2pi f={f}: {counts(run['cls'])}")
    cap = ("fig:many:2pi -- F=1, omega=2pi, l=-1, r=1, f=0.005, 0.01, 0.05, 0.1, 0.2, 0.3; colours as "
           "fig:many:wide; black diamonds: the non-sticking elliptic period-3 orbit (Newton, continued in f)")
    return fig, cap, [" | ".join(notes[:3]), " | ".join(notes[3:])]


def fold_branch(q):
    """The branch of non-sticking fixed points of the r = 20 scene through the fold, and the fold.

    Starts from the closest centre/saddle pair Newton finds at f = 0.6 (just below the fold),
    continues the centre down to f = 0.01 and up through the fold back along the saddles.
    Returns ``(u, trace, fold_u)`` with ``u`` rows ``(x, v, f)`` in arclength order.
    """
    make = lambda f: wide(float(f))
    sc = wide("0.6")
    fps = periodic_points(sc, (0.0, 20.0, 0.5, 12.0), q)
    cen, sad = nonsticking(fps, "centre"), nonsticking(fps, "saddle")
    if not cen or not sad:
        raise RuntimeError(f"fold_branch: no non-sticking centre/saddle pair at f=0.6 ({len(cen)}, {len(sad)})")
    c = min(cen, key=lambda o: min(np.abs(s["points"][0] - o["points"][0]).sum() for s in sad))["points"][0]
    down, trd, _ = cont.continue_branch(make, c, 0.6, ds=0.05, p_min=0.002, p_max=0.7, direction=-1.0,
                                        ds_max=0.3)
    up, tru, _ = cont.continue_branch(make, c, 0.6, ds=0.01, p_min=0.002, p_max=0.7, direction=1.0,
                                      ds_max=0.3)
    u = np.concatenate([down[::-1], up[1:]])
    tr = np.concatenate([trd[::-1], tru[1:]])
    fold = cont.locate_fold(make, up, tru)
    return u, tr, fold


def closed_form_fold(F=1.0):
    """The paper's fold ``f = 2F/pi`` (eq. ``fold:bif``): from the claims module's paper formulas
    (``reference.paper.fold_friction`` via ``cross_check.claims``) when present, else the formula."""
    try:
        from cross_check import claims# lazy: written by another helper
        return float(claims.P.fold_friction(Scene(F=F, f=0, omega=1, l=0, r=20)))
    except (ImportError, AttributeError):
        return 2.0 * F / np.pi


def fig_fold(q, ctx):
    fig, axes = new_figure(1, 2, size=(4.6, 3.6))
    u, tr, fold = fold_branch(q)
    ctx["fold"] = (u, tr, fold)
    centre = np.abs(tr) < 2
    for ax, j, name in ((axes[0], 0, "x(0)"), (axes[1], 1, "v(0)")):
        for mask, colour in ((centre, "k"), (~centre, "r")):
            y = np.where(mask, u[:, j], np.nan)
            ax.plot(u[:, 2], y, "-", color=colour, lw=1.8)
            ax.plot(u[mask, 2], u[mask, j], ".", color=colour, ms=3)
        if fold is not None:
            ax.plot(fold[2], fold[j], "b*", ms=9, zorder=5)
        ax.axvline(closed_form_fold(), color="0.5", ls=":", lw=1)
        ax.set_xlabel("f")
        ax.set_ylabel(name)
    ff = fold[2] if fold is not None else np.nan
    label(axes[0], f"(a) black: centres, red: saddles; fold at f = {ff:.10f}")
    label(axes[1], "(b) dotted: closed form f = 2F/pi (eq. fold:bif)")
    notes = [f"pseudo-arclength continuation of Phi(z)=z in f ({len(u)} points); fold (tr Phi' = 2) at "
             f"f = {ff:.12f}, closed form 2F/pi = {closed_form_fold():.12f}, difference {ff - closed_form_fold():.2e}"]
    cap = "fig:fold -- F=1, omega=1, l=0, r=20; fixed points of Phi continued in f (not the closed form)"
    return fig, cap, notes


def fig_three_per(q, ctx):
    fig, axes = new_figure(1, 2, size=(5.0, 4.2))
    sc = two_pi("0.05")
    win = (-1.1, 1.1, -7.0, 7.0)
    c, s, _ = saddle_centre_pair(sc, win, q)
    p3 = [o for o in periodic_points(sc, win, q, k=3) if not o["dissip"]]
    zc, zs = c["points"][0], s["points"][0]
    # one batch: probes of the fixed point's and the period-3 islands, and perturbations of the
    # unstable period-3 points (8 each, 1e-3, seeded)
    starts = [centre_line_starts(sc, zc, win, q.n_line)]
    starts += [centre_line_starts(sc, o["points"][0], (-1, 1, -2.5, 2.5), q.n_line // 2)
               for o in p3 if o["type"] == "centre"]
    rng = np.random.default_rng(7)
    n_probe = sum(st[0].size for st in starts)
    for o in p3:
        if o["type"] == "saddle":
            pts = np.repeat(o["points"], 8, axis=0)
            d = 1e-3 * rng.standard_normal(pts.shape)
            starts.append((np.clip(pts[:, 0] + d[:, 0], -1, 1), pts[:, 1] + d[:, 1]))
    xs, vs, first = por.run_orbits(sc, np.concatenate([st[0] for st in starts]),
                                   np.concatenate([st[1] for st in starts]), q.n_iter)
    cls, _ = classify(sc, xs[:, :n_probe], vs[:, :n_probe], first[:n_probe])
    mx, mv, mfirst = por.unstable_manifold(sc, zs, s["J"], n_seeds=max(20, q.n_line * 4),
                                           n_iter=max(10, q.n_iter // 20))
    keep = np.arange(mx.shape[0])[:, None] < mfirst[None, :]
    for ax in axes:
        por.draw_orbits(ax, xs[:, :n_probe], vs[:, :n_probe], cls)
        ax.plot(xs[:, n_probe:].ravel(), vs[:, n_probe:].ravel(), ".", color="k", ms=1.0, mew=0, zorder=3,
                rasterized=True)
        ax.plot(mx[keep], mv[keep], "o", color="k", ms=1.6, mew=0, zorder=4, rasterized=True)
        mark(ax, zc, "k*", ms=12)
        mark(ax, zs, "r*", ms=12)
        for o in p3:
            mark(ax, o["points"], "kD" if o["type"] == "centre" else "rD", ms=6)
        por.draw_walls(ax, sc)
        ax.set_xlabel("x")
        ax.set_ylabel("v")
    axes[0].set_xlim(win[0], win[1])
    axes[0].set_ylim(win[2], win[3])
    axes[1].set_xlim(-1.05, 1.05)
    axes[1].set_ylim(-2.5, 2.5)
    label(axes[0], "(a) stars: fixed points, diamonds: period 3, big dots: unstable manifold")
    label(axes[1], "(b) the period-3 orbits (zoom on |v| < 2.5)")
    lam = np.abs(cont.multipliers(s["J"]))
    conv = first[n_probe:] <= q.n_iter
    notes = [f"centre ({zc[0]:.5f}, {zc[1]:.5f}), saddle ({zs[0]:.5f}, {zs[1]:.5f}) multipliers "
             f"{lam.min():.4f}, {lam.max():.4f}; period-3 non-sticking orbits: "
             + ", ".join(f"{o['type']} at ({o['points'][0, 0]:.4f}, {o['points'][0, 1]:.4f})" for o in p3)
             + f"; {int(conv.sum())}/{conv.size} perturbed unstable period-3 starts reach Omega_dissip "
               f"within {q.n_iter} periods"]
    cap = ("fig:three:per -- F=1, f=0.05, omega=2pi, l=-1, r=1; black/red stars: centre/saddle, "
           "black/red diamonds: stable/unstable period 3, small dots: orbits started near unstable period 3")
    return fig, cap, notes


#: fig:fig's scene: the caption gives only the saddle's multipliers 0.3159, 3.1659 (tr 3.4818).
#: On the fold branch of the r = 20 scene (fig:fold) the saddle has tr = 3.48 at f ~ 0.60, while
#: in the 2 pi scenes of fig:many:2pi its multipliers stay near 0.367, 2.72 for every f: so the
#: figure is fig:many:wide's panel (f) scene, F = 1, f = 0.6, omega = 1, l = 0, r = 20.
FIGFIG = {"make": lambda: wide("0.6"), "window": (0.0, 20.0, -10.0, 10.0)}


def fig_fig(q, ctx):
    fe = cont.engine()
    fig, axes = new_figure(1, 2, size=(5.0, 4.2))
    sc = FIGFIG["make"]()
    win = FIGFIG["window"]
    l, r = sc.float("l"), sc.float("r")
    c, s, _ = saddle_centre_pair(sc, win, q)
    P = q.pixels
    xg = l + (np.arange(P) + 0.5) / P * (r - l)
    vg = win[2] + (np.arange(P) + 0.5) / P * (win[3] - win[2])
    X, V = np.meshgrid(xg, vg)
    zv = np.asarray(fe.zero_velocity(sc, X.ravel(), V.ravel()), bool).reshape(X.shape)
    J = np.asarray(fe.jacobian(sc, X.ravel(), V.ravel()), float)
    with np.errstate(invalid="ignore"):
        det = (J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]).reshape(X.shape)
    shade = np.where(zv, 0.35 + 0.5 * np.clip(np.nan_to_num(det, nan=0.0), 0, 1), 1.0)
    ext = (l, r, win[2], win[3])
    axes[0].imshow(shade, origin="lower", extent=ext, cmap="gray", vmin=0, vmax=1, aspect="auto")
    zs = s["points"][0]
    lam, vec = np.linalg.eig(s["J"])
    eu = np.real(vec[:, int(np.argmax(np.abs(lam)))])
    traj = por.run_orbits(sc, np.clip(zs[0] + 1e-4 * eu[0] * np.array([1, -1]), l, r),
                          zs[1] + 1e-4 * eu[1] * np.array([1, -1]), min(q.n_iter, 60))
    axes[0].plot(traj[0].ravel(), traj[1].ravel(), "k.", ms=3, zorder=4)
    mark(axes[0], zs, "r*", ms=12)
    mark(axes[0], c["points"][0], "k*", ms=12)
    # (b) Omega_dissip and its image
    img_x, img_v = cont.phi(sc, X[zv], V[zv])
    H, _, _ = np.histogram2d(img_v, img_x, bins=(P, P), range=((win[2], win[3]), (l, r)))
    panel_b = np.where(zv, 0.75, 1.0)
    panel_b = np.where(H > 0, 0.3, panel_b)
    axes[1].imshow(panel_b, origin="lower", extent=ext, cmap="gray", vmin=0, vmax=1, aspect="auto")
    inside = np.asarray(fe.zero_velocity(sc, img_x, img_v), bool)
    offscreen = (img_v < win[2]) | (img_v > win[3])
    for ax in axes:
        por.draw_walls(ax, sc)
        ax.set_xlim(l - 0.05 * (r - l), r + 0.05 * (r - l))
        ax.set_ylim(win[2], win[3])
        ax.set_xlabel("x")
        ax.set_ylabel("v")
    lam_s = np.sort(np.abs(lam))
    label(axes[0], "(a) white: Omega_pres; grey (darker: smaller det Phi'): Omega_dissip")
    label(axes[1], "(b) light grey: Omega_dissip; dark grey: Phi(Omega_dissip)")
    frac = inside.mean() if inside.size else np.nan
    ctx["figfig_multipliers"] = lam_s
    notes = [f"Phi(Omega_dissip) in Omega_dissip for {frac:.4%} of {inside.size} pixel centres "
             f"({int((~inside).sum())} images in Omega_pres, {int(offscreen.sum())} images off the v range); "
             f"the saddle's multipliers are {lam_s[0]:.4f}, {lam_s[1]:.4f} (caption: 0.3159, 3.1659)"]
    if inside.size and not inside.all():
        notes.append("caption claims Phi(Omega_dissip) is inside Omega_dissip: not for every computed point")
    ends = np.stack([traj[0][-1], traj[1][-1]], -1)
    e1x, e1v = cont.phi(sc, ends[:, 0], ends[:, 1])
    notes.append("the two unstable branches of the saddle (black dots) end at "
                 + ", ".join(f"({a:.3f}, {b:.3f})" for a, b in ends)
                 + f" after {traj[0].shape[0] - 1} periods, fixed points: "
                 + ", ".join(str(bool(np.abs(a - e[0]) + np.abs(b - e[1]) < 1e-9))
                             for a, b, e in zip(e1x, e1v, ends)))
    cap = ("fig:fig -- " + caption(sc, "pixels: " + str(P) + "x" + str(P))
           + "; red/black star: saddle/centre (the scene is fig:many:wide (f): it is the one whose saddle has the "
             "caption's multipliers)")
    return fig, cap, notes


def resonance_centre(R, z0=None, q=QUICK):
    """The non-sticking fixed point of the resonance scene at ``r = R`` (Newton) and ``D Phi`` there."""
    sc = resonance(R)
    if z0 is None:
        fps = [o for o in periodic_points(sc, (0.0, float(R), -8.0, 8.0), q) if not o["dissip"]]
        if not fps:
            raise RuntimeError(f"resonance_centre: no non-sticking fixed point at R={R}")
        o = min(fps, key=lambda o: abs(np.trace(o["J"]) + 1))
        return o["points"][0], o["J"]
    x, v, ok, J = cont.newton_periodic(sc, [z0[0]], [z0[1]])
    if not ok[0]:
        raise RuntimeError(f"resonance_centre: Newton failed at R={R} from {z0}")
    return np.array([x[0], v[0]]), J[0]


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


def fig_resonance(q, ctx):
    fig, axes = new_figure(1, 3, size=(4.0, 3.6))
    R_star, z_star = resonance_R_star(q=q)
    ctx["R_star"], ctx["R_star_z"] = R_star, z_star
    notes = []
    z = None
    half = None
    for ax, R, tag in zip(axes, ("0.89", "0.8932", "0.895"), "abc"):
        sc = resonance(R)
        z, J = resonance_centre(R, z_star)
        if half is None:
            w = island_window(sc, z, q, pad=0.4)
            half = (max(z[0] - w[0], w[1] - z[0]), max(z[1] - w[2], w[3] - z[1]))
        win = (z[0] - half[0], z[0] + half[0], z[1] - half[1], z[1] + half[1])
        lines = centre_line_starts(sc, z, win, q.n_line)
        run = portrait(ax, sc, win, q, lines, grid=(q.grid[0] // 2, q.grid[1] // 2))
        p3 = [o for o in periodic_points(sc, win, q, k=3) if not o["dissip"]]
        for o in p3:
            mark(ax, o["points"], "rD" if o["type"] == "saddle" else "kD", ms=4)
        tr = np.trace(J)
        mark(ax, z, "k*" if abs(tr) < 2 else "r*", ms=9)
        label(ax, f"({tag}) R = {R}: tr Phi' = {tr:.5f}")
        notes.append(f"R={R}: fixed point ({z[0]:.5f}, {z[1]:.5f}), tr {tr:.6f}, {len(p3)} period-3 orbit(s)")
    notes.append(f"tr Phi' = -1 (3:1 resonance) at R* = {R_star:.8f}: the caption's R* ~ 0.8932 is this value "
                 f"truncated (rounded it is {R_star:.4f}); panel (b) at R = 0.8932 is just below R*")
    cap = "fig:resonance -- F=omega^2, f=24.65, omega=2pi, l=0, r=R; red diamonds: period-3 saddles"
    return fig, cap, [" | ".join(notes[:3]), notes[3]]


def xpot_supported():
    """Whether ``fast`` integrates the position-dependent forcing (paper eq. ``xpot``); reason if not."""
    try:
        x, v = cont.phi(xpot(), np.array([0.0]), np.array([1.0]))
        if not np.isfinite(np.asarray(x)).all():
            return False, "fast returned non-finite states"
        return True, ""
    except (NotImplementedError, ValueError, TypeError, AttributeError) as exc:
        return False, f"{type(exc).__name__}: {exc}"


def fig_xpotno(q, ctx):
    """Position-dependent forcing (eq. xpot): its flights are numerical (fast.ode), ~50x dearer than
    the closed-form ones, so this figure runs at a quarter of the iterates and a small grid."""
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
        return fig, cap, [f"NOT COMPUTED: the engine does not support wavenumber yet ({why})"]
    xq = Quality(n_iter=max(20, q.n_iter // 4), grid=(max(3, q.grid[0] // 2), max(3, q.grid[1] // 2)),
                 n_line=max(6, q.n_line // 2), pixels=q.pixels,
                 newton_seeds=(4, 6) if q.name == "full" else (3, 3), name=q.name)
    win = (-1.05, 1.05, -6.0, 6.0)
    fps = periodic_points(sc, win, xq)
    cen = nonsticking(fps, "centre")
    probes = [centre_line_starts(sc, o["points"][0], win, xq.n_line) for o in cen]
    n_probe = sum(p[0].size for p in probes)
    gx, gv = por.grid_starts(win, *xq.grid, -1.0, 1.0)
    x0 = np.concatenate([p[0] for p in probes] + [gx])
    v0 = np.concatenate([p[1] for p in probes] + [gv])
    t0 = time.perf_counter()
    xs, vs, first = por.run_orbits(sc, x0, v0, xq.n_iter)
    log(f"  xpot: {x0.size} orbits x {xq.n_iter} in {time.perf_counter() - t0:.1f} s")
    cls, _ = classify(sc, xs, vs, first)
    diss = cls == "dissip"
    kept = ~diss
    por.draw_orbits(axes[0], xs[:, kept], vs[:, kept], np.full(int(kept.sum()), "regular", dtype=object))
    for o in cen:
        mark(axes[0], o["points"], "k*", ms=8)
    for o in nonsticking(fps, "saddle"):
        mark(axes[0], o["points"], "r*", ms=8)
    label(axes[0], f"(a) colour: orbits never at zero velocity in {xq.n_iter} periods ({int(kept.sum())})")
    axes[1].plot(xs[:, diss].ravel(), vs[:, diss].ravel(), ".", color="k", ms=1.0, mew=0, rasterized=True)
    for a, b in ((-1, -1 + eta), (1 - eta, 1)):
        axes[1].plot((a, b), (0, 0), "-", color="orange", lw=4, zorder=5)
    label(axes[1], f"(b) orbits reaching zero velocity ({int(diss.sum())}, black), the set E (orange)")
    for ax in axes:
        por.draw_walls(ax, sc)
        ax.set_xlim(win[0], win[1])
        ax.set_ylim(win[2], win[3])
        ax.set_xlabel("x")
        ax.set_ylabel("v")
    ends_x, ends_v = xs[-1, diss], vs[-1, diss]
    at_rest = ends_v == 0
    inE = np.abs(ends_x) >= 1 - eta - 1e-12
    regular = int((cls[kept] == "regular").sum())
    notes = [f"E = {{|x| >= 1 - eta}}, eta = (2/pi) arcsin(f/F) = {eta:.4f}: |F cos(pi x/2)| <= f there. "
             f"The paper's eta = (2/pi) arccos(f/F) = {2 / np.pi * np.arccos(f / F):.4f} is 1 - eta (misprint)",
             f"{int(diss.sum())} starts reach zero velocity; after {xq.n_iter} periods {int(at_rest.sum())} are at "
             f"rest at t = 0, {int((at_rest & inE).sum())} of them in E; {len(cen)} non-sticking centre(s); "
             f"{regular} of the {int(kept.sum())} coloured orbits pass the Birkhoff test at this length"]
    return fig, cap, notes


FIGURES = {
    "fig:nofriction": fig_nofriction,
    "fig:narrow-with-friction": fig_narrow_with_friction,
    "fig:many:wide": fig_many_wide,
    "fig:fold": fig_fold,
    "fig:many:2pi": fig_many_2pi,
    "fig:three:per": fig_three_per,
    "fig:fig": fig_fig,
    "fig:resonance": fig_resonance,
    "fig:xpotno": fig_xpotno,
}


def file_name(label_):
    """``fig:many:wide`` -> ``fig_many_wide.png``."""
    return label_.replace(":", "_").replace("-", "_") + ".png"


def resolve(name):
    """A figure label from ``fig:many:wide``, ``fig_many_wide`` or ``many:wide``."""
    norm = lambda s: s.replace(":", "_").replace("-", "_").removesuffix(".png")
    for key in FIGURES:
        if norm(name) in (norm(key), norm(key).removeprefix("fig_")):
            return key
    return None


def render(names, out, q, ctx=None):
    """Render ``names`` into ``out``; returns ``{label: (path, seconds, notes)}``.

    ``ctx`` collects the numbers behind the figures (fold, ``R*``, ...), shared between them.
    """
    import matplotlib

    matplotlib.use("Agg")
    os.makedirs(out, exist_ok=True)
    ctx = {} if ctx is None else ctx
    done = {}
    for name in names:
        t0, c0 = time.perf_counter(), time.process_time()
        log(f"{name}: start ({q.name})")
        fig, cap, notes = FIGURES[name](q, ctx)
        path = os.path.join(out, file_name(name))
        finish(fig, path, cap, notes)
        dt = time.perf_counter() - t0
        done[name] = (path, dt, notes)
        log(f"{name}: {path} in {dt:.1f} s wall, {time.process_time() - c0:.1f} s CPU")
        for n in notes:
            log(f"  note: {n}")
    return done


class _Parser(argparse.ArgumentParser):
    """An argument parser that reports a bad argument in one line and exits with status 2."""

    def error(self, message):
        print(f"figures: {message} (usage: figures [--out DIR] [--only NAME] [--quick])", file=sys.stderr)
        raise SystemExit(2)


def main(argv=None):
    """``figures [--out DIR] [--only NAME] [--quick]``; exit status 0, or 2 on bad arguments."""
    parser = _Parser(prog="python -m cross_check figures",
                     description="Regenerate the paper's figures as PNG files.")
    parser.add_argument("--out", default="figures", help="output directory (default: ./figures)")
    parser.add_argument("--only", default=None, help="one figure label, e.g. fig:fold or fig_fold")
    parser.add_argument("--quick", action="store_true", help="low resolution (seconds, for tests)")
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return int(exc.code or 0)
    names = list(FIGURES)
    if args.only is not None:
        key = resolve(args.only)
        if key is None:
            print(f"figures: --only must be one of {', '.join(FIGURES)}; got {args.only!r}", file=sys.stderr)
            return 2
        names = [key]
    t0, c0 = time.perf_counter(), time.process_time()
    render(names, args.out, QUICK if args.quick else FULL)
    log(f"all done in {time.perf_counter() - t0:.1f} s wall, {time.process_time() - c0:.1f} s CPU")
    return 0


if __name__ == "__main__":
    sys.exit(main())
