"""Fig. fig (fig:regions): Omega_pres and Omega_dissip shaded by det Phi', the saddle's unstable
branches, and the image of Omega_dissip (the caption claims it stays inside).

The caption gives only the saddle's multipliers 0.3159, 3.1659 (tr 3.4818).  On the fold branch
of the r = 20 scene (fig:fold) the saddle has tr = 3.48 at f ~ 0.60, while in the 2 pi scenes of
fig:many:2pi its multipliers stay near 0.367, 2.72 for every f: so the figure is fig:many:wide's
panel (f) scene, F = 1, f = 0.6, omega = 1, l = 0, r = 20 (``FIGFIG``).
"""
from __future__ import annotations

import numpy as np

from cross_check.dynamics import portraits as por
from cross_check.paper.figures.base import Drawn, caption, draw_walls, figure, label, mark, new_figure
from cross_check.scenes import wide

FIGFIG = {"make": lambda: wide("0.6"), "window": (0.0, 20.0, -10.0, 10.0)}


def _pixels(sc, win, P):
    """Pixel centres over the gap times the window's v range, their zero-velocity flags and det Phi'."""
    import fast
    l, r = sc.float("l"), sc.float("r")
    xg = l + (np.arange(P) + 0.5) / P * (r - l)
    vg = win[2] + (np.arange(P) + 0.5) / P * (win[3] - win[2])
    X, V = np.meshgrid(xg, vg)
    zv = np.asarray(fast.zero_velocity(sc, X.ravel(), V.ravel()), bool).reshape(X.shape)
    J = np.asarray(fast.jacobian(sc, X.ravel(), V.ravel()), float)
    with np.errstate(invalid="ignore"):
        det = (J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]).reshape(X.shape)
    return X, V, zv, det


def _branch_note(sc, traj):
    ends = np.stack([traj[0][-1], traj[1][-1]], -1)
    e1x, e1v = por.phi(sc, ends[:, 0], ends[:, 1])
    return ("the two unstable branches of the saddle (black dots) end at "
            + ", ".join(f"({a:.3f}, {b:.3f})" for a, b in ends)
            + f" after {traj[0].shape[0] - 1} periods, fixed points: "
            + ", ".join(str(bool(np.abs(a - e[0]) + np.abs(b - e[1]) < 1e-9)) for a, b, e in zip(e1x, e1v, ends)))


@figure("fig:fig")
def fig_fig(q, ctx):
    import fast
    fig, axes = new_figure(1, 2, size=(5.0, 4.2))
    sc = FIGFIG["make"]()
    win = FIGFIG["window"]
    l, r = sc.float("l"), sc.float("r")
    c, s, _ = por.saddle_centre_pair(sc, win, q.newton_seeds)
    P = q.pixels
    X, V, zv, det = _pixels(sc, win, P)
    shade = np.where(zv, 0.35 + 0.5 * np.clip(np.nan_to_num(det, nan=0.0), 0, 1), 1.0)
    ext = (l, r, win[2], win[3])
    axes[0].imshow(shade, origin="lower", extent=ext, cmap="gray", vmin=0, vmax=1, aspect="auto")
    zs = s.points[0]
    lam, vec = np.linalg.eig(s.J)
    eu = np.real(vec[:, int(np.argmax(np.abs(lam)))])
    traj = por.run_orbits(sc, np.clip(zs[0] + 1e-4 * eu[0] * np.array([1, -1]), l, r),
                          zs[1] + 1e-4 * eu[1] * np.array([1, -1]), min(q.n_iter, 60))
    axes[0].plot(traj[0].ravel(), traj[1].ravel(), "k.", ms=3, zorder=4)
    mark(axes[0], zs, "r*", ms=12)
    mark(axes[0], c.points[0], "k*", ms=12)
    # (b) Omega_dissip and its image
    img_x, img_v = por.phi(sc, X[zv], V[zv])
    H, _, _ = np.histogram2d(img_v, img_x, bins=(P, P), range=((win[2], win[3]), (l, r)))
    panel_b = np.where(H > 0, 0.3, np.where(zv, 0.75, 1.0))
    axes[1].imshow(panel_b, origin="lower", extent=ext, cmap="gray", vmin=0, vmax=1, aspect="auto")
    inside = np.asarray(fast.zero_velocity(sc, img_x, img_v), bool)
    offscreen = (img_v < win[2]) | (img_v > win[3])
    for ax in axes:
        draw_walls(ax, sc)
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
    notes.append(_branch_note(sc, traj))
    cap = ("fig:fig -- " + caption(sc, "pixels: " + str(P) + "x" + str(P))
           + "; red/black star: saddle/centre (the scene is fig:many:wide (f): it is the one whose saddle has the "
             "caption's multipliers)")
    return Drawn(fig, cap, notes)
