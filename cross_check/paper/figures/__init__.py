"""Regenerate the paper's figures: ``python -m cross_check figures [--out DIR] [--only NAME] [--quick]``.

``FIGURES`` is the registry, label -> ``draw(q, ctx) -> base.Drawn``, one module per figure:

* ``narrow``     -- fig:nofriction, fig:narrow-with-friction;
* ``many``       -- fig:many:wide, fig:many:2pi;
* ``fold``       -- fig:fold;
* ``three_per``  -- fig:three:per;
* ``regions``    -- fig:fig (the regions Omega_pres, Omega_dissip);
* ``resonance``  -- fig:resonance;
* ``xpot``       -- fig:xpotno.

One PNG per figure of the paper, named after its label (``fig:nofriction`` ->
``fig_nofriction.png``), panels as in the paper, a one-line caption with the parameters under
each figure and a note where what we compute contradicts the caption.  Everything is computed
on the float64 engine ``fast``, through ``cross_check.dynamics``: phase portraits classified
regular / chaotic / dissipative (weighted Birkhoff averages, ``fast.zero_velocity``), periodic
points by Newton and their type by the multipliers, the fold by pseudo-arclength continuation,
``Omega_dissip`` and ``det Phi'`` on a pixel grid.

Progress lines go to stderr; the figure set takes about 35 s on two cores (``--quick``: seconds).
"""
from __future__ import annotations

import argparse
import os
import sys
import time

from cross_check import outputs
from cross_check.paper.figures import fold, many, narrow, regions, resonance, three_per, xpot  # noqa: F401
from cross_check.paper.figures.base import FULL, QUICK, REGISTRY, Drawn, Quality, finish, log

#: the paper's order
ORDER = ("fig:nofriction", "fig:narrow-with-friction", "fig:many:wide", "fig:fold", "fig:many:2pi",
         "fig:three:per", "fig:fig", "fig:resonance", "fig:xpotno")
if set(ORDER) != set(REGISTRY):
    raise ImportError(f"figure registry and ORDER differ: {sorted(set(ORDER) ^ set(REGISTRY))}")

#: every figure by label, in the paper's order
FIGURES = {label: REGISTRY[label] for label in ORDER}

__all__ = ["FIGURES", "FULL", "QUICK", "Quality", "Drawn", "render", "file_name", "resolve", "main"]


def file_name(label_):
    """``fig:many:wide`` -> ``fig_many_wide.png``."""
    return label_.replace(":", "_").replace("-", "_") + ".png"


def resolve(name):
    """A figure label from ``fig:many:wide``, ``fig_many_wide`` or ``many:wide``."""
    norm = lambda s: s.replace(":", "_").replace("-", "_").removesuffix(".png")     # noqa: E731
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
        drawn = FIGURES[name](q, ctx)
        path = os.path.join(out, file_name(name))
        finish(drawn, path)
        dt = time.perf_counter() - t0
        done[name] = (path, dt, drawn.notes)
        log(f"{name}: {path} in {dt:.1f} s wall, {time.process_time() - c0:.1f} s CPU")
        for n in drawn.notes:
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
                     description="Regenerate the paper's figures as PNG files.  Exit status: 0 written, 2 bad "
                                 "arguments or an unwritable --out.")
    parser.add_argument("--out", default="figures", type=outputs.check_folder, help="output directory (default: ./figures)")
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
