"""A scene's portrait for ``verify``: the stroboscopic map's phase plane in one PNG.

* shaded: ``Omega_pres`` (``|det Phi'| = 1``: no zero velocity on ``[0, T]``, white) and
  ``Omega_dissip`` (``|det Phi'| < 1``, grey), pixel by pixel (``dynamics.portraits.area_classes``);
  red where ``Phi'`` is not defined (a grazing start);
* orbits of a grid of starts, coloured when Birkhoff-regular, grey when chaotic, faint cyan when
  they reach zero velocity (dissipative), with their last iterate in black (``dynamics.portraits``, drawn as the paper's
  figures are: ``paper.figures.base``);
* the periodic points found (``verify.tasks.orbits``): filled markers where the Krawczyk proof
  holds, open ones where it does not; a proved segment of no-impact fixed points as a thick line.
"""
from __future__ import annotations

import io

import numpy as np

from cross_check.dynamics import portraits as por
from cross_check.paper.figures.base import draw_orbits, frame

#: marker per period of an orbit
_MARKERS = {1: "o", 2: "s", 3: "^"}

#: ``fast``'s ``steps_per_period`` of the shading's first look (``dynamics.portraits.area_classes``;
#: position forcing, issue 33).  The 120 x 120 pixels' Jacobians were 7.6 of the portrait's ~9
#: CPU s on scene D (``F=3 f=0.5 omega=0.8 l=-2 r=1.5 wavenumber=2.5``: ~3,000 fixed steps a
#: period at its fastest pixels).  A pixel needs its class, not ``Phi'``, and the second look on
#: the default map takes every pixel the coarse map does not class clearly, so ``S`` is a cost:
#: at 48, 32 and 24 steps D's shading took 2.97, 2.06 and 1.65 CPU s, scene W's (``F=3 f=0.3
#: omega=0.5 l=-2 r=2 wavenumber=2``) 7.1, 4.8 and 3.8, with 0, 1 and 2 pixels looked at again,
#: the same classes (also on ``F=1 f=0.2 omega=1 l=-1 r=1 wavenumber=1`` and issue 33's first
#: scene, and, where the default map is clear, on 120 random scenes; one run each).  The largest
#: ``|det - 1|`` on ``Omega_pres`` is 2.0e-10 and 1.6e-11 on D and F at ``S = 48``, 2.1e-10 and
#: 8.4e-12 at the default 128 (rounding, not truncation, sets it); at ``S = 16``, 1.6e-9 and 3.9e-9.
PORTRAIT_STEPS = 24
#: ``fast``'s ``steps_per_period`` of the orbits drawn over the shading (``_orbits``: 81 starts,
#: ``n_iter`` periods each; position forcing).  On the frictionless ``F=2 f=0 omega=0.5 l=-1 r=1
#: wavenumber=2`` (issue 33), whose orbits neither stick nor stop, they were 20.3 of the
#: portrait's 24.5 CPU s on the default map (~40 impacts a period of 12.6).  A picture needs the
#: iterates to a pixel, not to an ulp: one period at ``S = 32`` errs ~5e-11 (1e-13 at 64), and
#: the orbits take 5.7 CPU s there (10.5 at 64).  On seven position-forced scenes (567 orbits,
#: one run each) the classes (regular, chaotic, dissipative) and the first dissipative iterates
#: are those of the default map but for one orbit, which also changes class at ``S = 64``: a
#: Birkhoff average at the regular threshold, which a move of 1e-13 tips.
PORTRAIT_ORBIT_STEPS = 32


def pixel_centres(window, pixels):
    """``(X, V)``: the centres of the ``pixels x pixels`` grid over ``window = (l, r, v_lo, v_hi)``
    (rows of equal ``v``)."""
    xg = window[0] + (np.arange(pixels) + 0.5) / pixels * (window[1] - window[0])
    vg = window[2] + (np.arange(pixels) + 0.5) / pixels * (window[3] - window[2])
    return np.meshgrid(xg, vg)


def _shade(ax, sc, window, pixels):
    l, r = window[0], window[1]
    X, V = pixel_centres(window, pixels)
    labels, _ = por.area_classes(sc, X.ravel(), V.ravel(), steps=PORTRAIT_STEPS)
    rgb = np.ones(X.shape + (3,))
    lab = labels.reshape(X.shape)
    rgb[lab == "dissip"] = (0.87, 0.87, 0.87)
    rgb[lab == "undefined"] = (1.0, 0.55, 0.55)
    ax.imshow(rgb, origin="lower", extent=(l, r, window[2], window[3]), aspect="auto", zorder=0,
              interpolation="nearest")
    return {k: int((lab == k).sum()) for k in ("pres", "dissip", "undefined")}


def _orbits(ax, sc, window, depth):
    l, r = sc.float("l"), sc.float("r")
    side = max(3, int(round(np.sqrt(depth.n_iter / 4))))
    gx, gv = por.grid_starts(window, side, side, l, r)
    xs, vs, first = por.run_orbits(sc, np.clip(gx, l, r), gv, depth.n_iter, steps=PORTRAIT_ORBIT_STEPS)
    cls, _ = por.orbit_classes(sc, xs, vs, first)
    draw_orbits(ax, xs, vs, cls)
    diss = cls == "dissip"
    if diss.any():                  # their iterates faint, where they end (the attractors) in black
        ax.plot(xs[:, diss].ravel(), vs[:, diss].ravel(), ".", color="tab:cyan", ms=2.2, mew=0, alpha=0.8,
                rasterized=True, zorder=1)
        ax.plot(xs[-1, diss], vs[-1, diss], "o", color="k", ms=1.5, zorder=5)


def _points(ax, rows):
    for row in rows:
        proved = row["proof"]["proved"]
        colour = "tab:red" if proved else "tab:blue"
        if row["what"] == "segment":
            lo, hi = row["segment"]
            ax.plot([lo, hi], [row["v"], row["v"]], "-", color=colour, lw=3 if proved else 1.5, zorder=7)
            continue
        pts = np.asarray(row["orbit"], float)
        ax.plot(pts[:, 0], pts[:, 1], _MARKERS.get(row["period"], "D"), ms=6, zorder=8,
                mfc=colour if proved else "none", mec=colour, mew=1.3)


def png(sc, orbit_rows, depth, vmax) -> bytes:
    """The portrait (module docstring) as PNG bytes."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.lines import Line2D

    window = (sc.float("l"), sc.float("r"), -vmax, vmax)
    fig, ax = plt.subplots(figsize=(7.0, 5.0))
    counts = _shade(ax, sc, window, depth.pixels)
    _orbits(ax, sc, window, depth)
    _points(ax, orbit_rows)
    frame(ax, sc, window)
    n = max(1, sum(counts.values()))
    ax.set_title(f"{sc.name}: Omega_pres {100 * counts['pres'] / n:.0f}% (white), Omega_dissip "
                 f"{100 * counts['dissip'] / n:.0f}% (grey)", fontsize=9, loc="left")
    handles = [Line2D([], [], ls="none", marker=_MARKERS[k], color="k", mfc="none", label=f"period {k}")
               for k in sorted({row["period"] for row in orbit_rows} & set(_MARKERS))]
    handles += [Line2D([], [], ls="none", marker="o", color="tab:red", label="proved (Krawczyk)"),
                Line2D([], [], ls="none", marker="o", mfc="none", color="tab:blue", label="not proved")]
    ax.legend(handles=handles, fontsize=7, loc="upper right", framealpha=0.85)
    fig.tight_layout()
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=110)
    plt.close(fig)
    return buf.getvalue()
