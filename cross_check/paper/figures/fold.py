"""Fig. fold: the branch of non-sticking fixed points of the R = 20 scene continued in f through
the saddle-centre fold, against the closed form f = 2F/pi (eq. fold:bif)."""
from __future__ import annotations

import numpy as np

from reference import paper as P
from cross_check.dynamics import continuation as cont
from cross_check.dynamics import portraits as por
from cross_check.paper.figures.base import Drawn, figure, label, new_figure
from cross_check.scenes import wide


def fold_branch(q):
    """The branch of non-sticking fixed points of the r = 20 scene through the fold, and the fold.

    Starts from the closest centre/saddle pair Newton finds at f = 0.6 (just below the fold),
    continues the centre down to f = 0.01 and up through the fold back along the saddles.
    Returns ``(u, trace, fold_u)`` with ``u`` rows ``(x, v, f)`` in arclength order.
    """
    make = lambda f: wide(float(f))      # noqa: E731
    c, _s, _ = por.saddle_centre_pair(wide("0.6"), (0.0, 20.0, 0.5, 12.0), q.newton_seeds)
    c = c.points[0]
    down, trd, _ = cont.continue_branch(make, c, 0.6, ds=0.05, p_min=0.002, p_max=0.7, direction=-1.0,
                                        ds_max=0.3)
    up, tru, _ = cont.continue_branch(make, c, 0.6, ds=0.01, p_min=0.002, p_max=0.7, direction=1.0,
                                      ds_max=0.3)
    u = np.concatenate([down[::-1], up[1:]])
    tr = np.concatenate([trd[::-1], tru[1:]])
    fold = cont.locate_fold(make, up, tru)
    return u, tr, fold


def closed_form_fold(F=1.0):
    """The paper's fold ``f = 2F/pi`` (eq. ``fold:bif``, ``reference.paper.fold_friction``)."""
    return float(P.fold_friction(wide(0).replace(F=F)))


@figure("fig:fold")
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
    return Drawn(fig, cap, notes)
