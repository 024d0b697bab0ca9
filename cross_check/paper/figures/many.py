"""Fig. many:wide (R = 20, f = 0.1 ... 0.6) and Fig. many:2pi (w = 2 pi, f = 0.005 ... 0.3):
portraits with friction, their non-sticking centres and saddles, the attractor, and in the
2 pi scenes the elliptic period-3 orbit of the subharmonic islands continued panel to panel.
"""
from __future__ import annotations

import numpy as np

from cross_check.dynamics import periodic
from cross_check.dynamics import portraits as por
from cross_check.paper.figures.base import Drawn, counts, figure, label, log, mark, new_figure, portrait
from cross_check.scenes import two_pi, wide


def friction_panel(ax, sc, win, q, tag, extra_centres=()):
    """A portrait with friction: island(s) around non-sticking centres (fixed points, plus the points
    ``extra_centres`` of other periodic orbits), the attractor in black."""
    fps = por.periodic_points(sc, win, q.newton_seeds)
    cen = por.nonsticking(fps, "centre")
    starts = [por.centre_line_starts(sc, o.points[0], win, q.n_line) for o in cen]
    starts += [por.centre_line_starts(sc, z, win, max(4, q.n_line // 4)) for z in extra_centres]
    extra = (np.concatenate([s[0] for s in starts]), np.concatenate([s[1] for s in starts])) if starts else None
    run = portrait(ax, sc, win, q, extra)
    for o in cen:
        mark(ax, o.points, "k*", ms=6)
    for o in por.nonsticking(fps, "saddle"):
        mark(ax, o.points, "r*", ms=6)
    if len(extra_centres):
        mark(ax, np.asarray(extra_centres), "kD", ms=3)
    label(ax, f"({tag}) f = {sc.f}: {counts(run['cls'])}")
    return run, cen


def period3_centres(sc, seed):
    """The non-sticking elliptic period-3 orbit continued from ``seed`` (3 points), or [] if lost."""
    import fast
    res = periodic.newton(sc, seed[:1, 0], seed[:1, 1], period=3)
    if not res.converged[0] or periodic.classify(res.J)[0][0] != "centre":
        return []
    ox, ov = fast.orbit(sc, res.x, res.v, 2)
    if np.asarray(fast.zero_velocity(sc, ox.ravel(), ov.ravel())).any():
        return []
    return list(np.stack([ox[:, 0], ov[:, 0]], -1))


def attractor_note(run, scene):
    """Whether the dissipative orbits have ended on fixed points (``Phi(z) = z`` within 1e-9): the attractor."""
    diss = run["cls"] == "dissip"
    if not diss.any():
        return f"f={scene.f}: no start reached Omega_dissip"
    ex, ev = run["xs"][-1, diss], run["vs"][-1, diss]
    fx, fv = por.phi(scene, ex, ev)
    fixed = np.maximum(np.abs(fx - ex), np.abs(fv - ev)) < 1e-9
    n = run["xs"].shape[0] - 1
    if not fixed.any():
        return f"f={scene.f}: none of {int(diss.sum())} dissipative orbits has settled on a fixed point in {n} periods"
    return (f"f={scene.f}: {int(fixed.sum())}/{int(diss.sum())} dissipative orbits end on fixed points "
            f"(x in [{ex[fixed].min():.3f}, {ex[fixed].max():.3f}]) in {n} periods")


@figure("fig:many:wide")
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
    return Drawn(fig, cap, [" | ".join(notes[:3]), " | ".join(notes[3:])])


@figure("fig:many:2pi")
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
    return Drawn(fig, cap, [" | ".join(notes[:3]), " | ".join(notes[3:])])
