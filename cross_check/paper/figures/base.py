"""What every figure shares: run quality, the figure registry, drawing helpers.

A figure is a function ``draw(q, ctx) -> Drawn`` registered with ``@figure(label)``: ``q`` is
the run's ``Quality`` (``FULL`` or ``QUICK``), ``ctx`` a dict of numbers shared between figures
of one run (the fold, ``R*``, the narrow scene's islands).  ``Drawn`` holds the matplotlib
Figure, its one-line caption and the notes where the computation contradicts the caption.
"""
from __future__ import annotations

import sys
import time
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from cross_check.dynamics import portraits as por


@dataclass(frozen=True)
class Quality:
    """Resolution of a run: iterates per orbit, start grid, starts per line, pixels, Newton seeds."""

    n_iter: int
    grid: tuple
    n_line: int
    pixels: int
    newton_seeds: tuple
    name: str


FULL = Quality(n_iter=1000, grid=(30, 36), n_line=120, pixels=200, newton_seeds=(10, 14), name="full")
QUICK = Quality(n_iter=80, grid=(5, 6), n_line=8, pixels=32, newton_seeds=(5, 6), name="quick")


@dataclass
class Drawn:
    """A drawn figure: the matplotlib ``figure``, its ``caption`` and ``notes``."""

    figure: object
    caption: str
    notes: list = field(default_factory=list)


#: label -> draw function, in registration order (``cross_check.paper.figures`` orders the set)
REGISTRY: dict[str, Callable] = {}


def figure(label):
    """Register the decorated ``draw(q, ctx) -> Drawn`` as the paper's figure ``label``."""
    def register(draw):
        if label in REGISTRY:
            raise ValueError(f"figure {label!r} registered twice")
        REGISTRY[label] = draw
        return draw
    return register


def log(msg):
    print(f"[figures] {msg}", file=sys.stderr, flush=True)


def caption(scene, extra=""):
    p = scene.floats()
    text = (f"F={scene.F}, f={scene.f}, omega={scene.omega}, l={scene.l}, r={scene.r}"
            + (f", wavenumber={scene.wavenumber}" if p["wavenumber"] is not None else ""))
    return text + (f"; {extra}" if extra else "")


def new_figure(nrows, ncols, size=(4.2, 3.6)):
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(nrows, ncols, figsize=(size[0] * ncols, size[1] * nrows), squeeze=False)
    return fig, axes.ravel()


def label(ax, text):
    ax.set_title(text, fontsize=9, loc="left")


def counts(cls):
    return ", ".join(f"{k} {int((cls == k).sum())}" for k in ("regular", "chaotic", "dissip"))


def mark(ax, pts, style, **kw):
    pts = np.atleast_2d(pts)
    ax.plot(pts[:, 0], pts[:, 1], style, zorder=6, **kw)


def draw_orbits(ax, xs, vs, cls, *, chaotic_color="0.62", ms=1.4, cmap="turbo"):
    """Regular orbits in colour (ordered by their mean ``v^2`` so nested curves differ), chaotic in grey."""
    import matplotlib

    reg = np.nonzero(cls == "regular")[0]
    cha = np.nonzero(cls == "chaotic")[0]
    if cha.size:
        ax.plot(xs[:, cha].ravel(), vs[:, cha].ravel(), ".", color=chaotic_color, ms=ms * 0.6, mew=0,
                rasterized=True, zorder=1)
    if reg.size:
        order = np.argsort(np.argsort((vs[:, reg] ** 2).mean(0) + xs[:, reg].mean(0) * 1e-3))
        colors = matplotlib.colormaps[cmap](0.05 + 0.9 * order / max(1, reg.size - 1))
        for j, i in enumerate(reg):
            ax.plot(xs[:, i], vs[:, i], ".", color=colors[j], ms=ms, mew=0, rasterized=True, zorder=2)


def draw_walls(ax, scene):
    """The walls ``x = l, r`` as dashed blue lines."""
    for w in (scene.float("l"), scene.float("r")):
        ax.axvline(w, color="b", ls="--", lw=1.0, zorder=3)


def frame(ax, scene, window):
    """Walls, the window as limits, axis labels."""
    draw_walls(ax, scene)
    ax.set_xlim(window[0], window[1])
    ax.set_ylim(window[2], window[3])
    ax.set_xlabel("x")
    ax.set_ylabel("v")


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
    cls, digits = por.orbit_classes(scene, xs, vs, first)
    log(f"  portrait f={scene.f} r={scene.r}: {gx.size} orbits x {n} in {time.perf_counter() - t0:.1f} s: "
        f"{counts(cls)}")
    draw_orbits(ax, xs, vs, cls)
    diss = cls == "dissip"
    if draw_attractor and diss.any():
        ax.plot(xs[-1, diss], vs[-1, diss], "o", color="k", ms=1.5, zorder=5)
    frame(ax, scene, window)
    return {"xs": xs, "vs": vs, "cls": cls, "digits": digits, "first": first}


def finish(drawn, path):
    """Caption and notes (wrapped to the figure width) under the figure, then save it as PNG."""
    import textwrap

    import matplotlib.pyplot as plt

    fig = drawn.figure
    w_in, h_in = fig.get_size_inches()
    lines = []
    for i, text in enumerate([drawn.caption] + [f"NOTE: {n}" for n in drawn.notes]):
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
