"""Where ``Phi(Omega_dissip)`` leaves ``Omega_dissip`` numerically: candidate balls for a proof.

On an ``n x n`` grid of starts (cell centres over the gap times ``[-V, V]``, ``V = VELOCITY
(F/w + f T)`` unless given), ``fast`` marks the violations: starts in ``Omega_dissip``
(``fast.zero_velocity``) whose image is not.  A proof needs a *ball* of violations, so the
candidates are ranked by their depth inside the violating set: the chessboard distance, in
cells, to the nearest grid start that is not a violation (or to the grid's edge).  A start of
depth ``d`` has ``(2d - 1) x (2d - 1)`` violating cells around it; the suggested radii are
``RADIUS_FRACTION (d - 1/2)`` cells, so that the ball stays inside them.  Numbers only: the
proof is ``reference.enclosure.invariance.prove_counterexample``.
"""
from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from cross_check.dynamics.portraits import engine, phi

#: The velocity window, in units of ``F/w + f T`` (the forced speed scale).
VELOCITY = 2.0
#: Share of the violating cells around a candidate the suggested ball takes.
RADIUS_FRACTION = 0.5
#: The zoom: an ``n x n`` grid over ``+-cells`` grid cells around a candidate.
ZOOM_N, ZOOM_CELLS = 64, 2
#: Radii tried per candidate: each ``SHRINK`` times smaller, ``TRIES`` of them.
SHRINK, TRIES = 8, 12


class Candidate(NamedTuple):
    """A start ``(x, v)`` of ``depth`` cells inside the violating set, the suggested radii,
    and the grid's cell sizes."""

    x: float
    v: float
    x_radius: float
    v_radius: float
    depth: int
    cell_x: float
    cell_v: float


def _candidate(xs, vs, d, i, j):
    dx, dv = xs[1] - xs[0], vs[1] - vs[0]
    rad = RADIUS_FRACTION * (d[i, j] - 0.5)
    return Candidate(float(xs[i]), float(vs[j]), float(rad * dx), float(rad * dv), int(d[i, j]),
                     float(dx), float(dv))


def grid(scene, n, v_span=None):
    """``(xs, vs)``: the cell centres over ``(l, r)`` and ``[-v_span, v_span]``."""
    l, r = scene.float("l"), scene.float("r")
    if v_span is None:
        F, f, w = scene.float("F"), scene.float("f"), scene.float("omega")
        v_span = VELOCITY * (F / w + f * 2 * math.pi / w)
    xs = l + (np.arange(n) + 0.5) / n * (r - l)
    vs = -v_span + (np.arange(n) + 0.5) / n * 2 * v_span
    return xs, vs


def violations(scene, n=160, v_span=None):
    """``(xs, vs, mask)``: the grid and its violations (``mask[i, j]``: start ``(xs[i],
    vs[j])`` in ``Omega_dissip``, its image not)."""
    if not (isinstance(n, int) and not isinstance(n, bool) and 4 <= n <= 4096):
        raise ValueError(f"n must be an int in [4, 4096], got {n!r}")
    xs, vs = grid(scene, n, v_span)
    return xs, vs, _mask(scene, xs, vs)


def _mask(scene, xs, vs):
    X, V = (a.ravel() for a in np.meshgrid(xs, vs, indexing="ij"))
    fast = engine()
    zero = np.asarray(fast.zero_velocity(scene, X, V), bool)
    X1, V1 = phi(scene, X, V)
    image_zero = np.asarray(fast.zero_velocity(scene, X1, V1), bool)
    return (zero & ~image_zero).reshape(xs.size, vs.size)


def depth(mask):
    """The chessboard distance of each violation to the nearest non-violation or the edge, in
    cells (1: a violation with a non-violating neighbour); 0 off the violations."""
    d = np.zeros(mask.shape, int)
    inside = mask.copy()
    level = 0
    while inside.any():
        level += 1
        d[inside] = level
        padded = np.pad(inside, 1, constant_values=False)
        shrunk = np.ones(mask.shape, bool)
        for di in (0, 1, 2):
            for dj in (0, 1, 2):
                shrunk &= padded[di:di + mask.shape[0], dj:dj + mask.shape[1]]
        inside = shrunk
    return d


def candidates(scene, n=160, v_span=None, count=4):
    """Up to ``count`` :class:`Candidate`, deepest first (ties: the grid order), none inside
    the violating cells of an earlier one; [] if the grid has no violation."""
    xs, vs, mask = violations(scene, n, v_span)
    d = depth(mask)
    taken = []
    for k in np.argsort(-d, axis=None, kind="stable"):
        i, j = np.unravel_index(k, d.shape)
        if d[i, j] == 0 or len(taken) >= count:
            break
        if not any(abs(i - a) < d[a, b] and abs(j - b) < d[a, b] for a, b in taken):
            taken.append((i, j))
    return [_candidate(xs, vs, d, i, j) for i, j in taken]


def zoom(scene, candidate, n=ZOOM_N, cells=ZOOM_CELLS):
    """The deepest violation on an ``n x n`` grid over the ``+-cells`` grid cells around a
    candidate (the violating sets of small-friction scenes are thin strips: a ball fits
    inside only at a finer resolution), as a candidate; None if the window has none."""
    c = candidate
    xs = c.x - cells * c.cell_x + (np.arange(n) + 0.5) / n * 2 * cells * c.cell_x
    vs = c.v - cells * c.cell_v + (np.arange(n) + 0.5) / n * 2 * cells * c.cell_v
    xs = xs[(xs > scene.float("l")) & (xs < scene.float("r"))]
    if xs.size < 2:
        return None
    d = depth(_mask(scene, xs, vs))
    i, j = np.unravel_index(np.argmax(d), d.shape)
    return _candidate(xs, vs, d, i, j) if d[i, j] else None


def refute(prove, scene, *, n=160, count=4, shrink=SHRINK, tries=TRIES, zoomed=True, progress=None):
    """The first counterexample ``prove(x, v, x_radius, v_radius)`` proves (its result has
    ``proved``), trying each candidate (then its zoom, if ``zoomed``) at radii shrunk
    ``shrink`` times per try (``tries`` tries: the ball's enclosure widens by the map's
    stretching at every impact); ``(result, tried)`` with ``result`` None if none is proved."""
    tried = 0
    for cand in candidates(scene, n, count=count):
        for c in (cand, zoom(scene, cand) if zoomed else None):
            if c is None:
                continue
            x, v, rx, rv = c[:4]
            for k in range(tries):
                tried += 1
                got = prove(x, v, rx / shrink ** k, rv / shrink ** k)
                if got.proved:
                    return got, tried
            if progress:
                progress(f"counterexample: candidate ({x:.6g}, {v:.6g}) not proved ({got.reason[:100]})")
    return None, tried
