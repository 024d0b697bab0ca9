"""Certified location of the first root of an event function (one point at a time).

For an event function ``g`` with known ``g, g', g''`` at a point ``b`` and bounds
``|g''| <= M`` (everywhere) and ``|g'''| <= M3``:

* forward certificate: ``g(b+h) >= g + g' h - M h^2/2`` for all ``h`` (global minorant),
  first positive root ``hg = (g' + sqrt(g'^2 + 2 M g)) / M`` (written ``2 g / (sqrt(.) -
  g')`` when ``g' <= 0``: no cancellation); on ``[0, H]`` also ``g(b+h) >= g + g' h +
  m h^2/2`` with ``m = max(g'' - M3 H, -M)`` (local minorant), ``H = min(max(2 hg,
  |g''| / (2 M3)), H_cap)``; ``safe`` = the first root of the local one, capped by ``H``
  (>= ``hg``).  No root of ``g`` lies in ``[b, b + safe)``.
* backward certificate: the same global minorant run backwards from ``b`` gives a window
  ``(b - back, b)`` free of roots when ``g(b) > 0``; when ``g(b) <= 0`` (the trial
  overshot a crossing), ``g`` is strictly decreasing on ``(b - |g'|/M, b]`` and positive
  at its left end if ``g >= -g'^2/(2M)``: exactly one root there.
* prediction: the root of the exact-curvature quadratic ``g + g' d + g'' d^2/2`` nearest
  to 0 in the crossing direction (``d < 0`` after an overshoot); error
  ``<= M3 |d|^3 / (6 |g'|)`` near a simple root.  It is *accepted* when that bound is
  below ``tol`` and ``|d| <= d_acc`` (the caller carries the state over ``d`` by the
  flight's local model, ``fast.precise.at_event``), or when ``|g|`` is below its noise floor while
  ``g' <= 0`` (a tangential zero at working precision: ``d = 0``).

The kernel jumps to predictions (speculative trials) and keeps a trial only when the
backward windows at it reach back to the forward-certified ends of the last certified
point, so no root is ever skipped; otherwise it retreats to the certified step.
"""
from __future__ import annotations

import numpy as np

_TINY = 1e-300


def analyze(g, g1, g2, M, M3, H_cap, tol, noise, d_acc, fresh=None):
    """Certified steps and a root prediction for one event function at a point ``b``.

    Returns ``(safe, est, acc, back)``:

    * ``safe``: ``g`` has no root on ``[b, b + safe)`` (global and local minorants, see
      the module docstring); 0 when ``g <= 0``;
    * ``est``: the root of the exact-curvature quadratic ``g + g' d + g'' d^2/2`` nearest
      to 0 in the direction of the crossing (negative after an overshoot, ``g < 0``),
      ``inf`` when the model has none;
    * ``acc``: the root ``b + est`` is accepted: a simple crossing (``g' < 0``), ``|est|
      <= d_acc`` (the state carried over ``est`` by ``fast.precise.at_event``) and the
      model error ``M3 |est|^3 / (6 |g'|) <= tol``; or ``g`` below its noise floor while
      ``g' <= 0`` (a near-tangential zero, ``est = 0``);
    * ``back``: a window ``(b - back, b)`` certified root-free when ``g > 0`` (the global
      minorant run backwards); when ``g <= 0``, ``-`` the length ``|g'|/M`` of the window
      ``(b - |g'|/M, b]`` on which ``g`` is strictly decreasing and crosses 0 exactly once
      (needs ``g' < 0`` and ``g >= -g'^2 / (2 M)``; else ``nan``: no certificate).
    """
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        pos = g > 0
        if fresh is not None:           # v = 0 at a segment start: the flight leaves it
            pos |= fresh
        gp = np.maximum(g, 0.0)
        g1sq = g1 * g1
        sq = np.sqrt(g1sq + (2.0 * M) * gp)
        up = g1 > 0
        neg = g1 < 0
        # global minorant roots, forwards and backwards (cancellation-free branches)
        fwd = np.where(up, (g1 + sq) * (1.0 / M), (gp + gp) / np.maximum(sq - g1, _TINY))
        bwd = np.where(neg, (sq - g1) * (1.0 / M), (gp + gp) / np.maximum(sq + g1, _TINY))
        # local minorant on [0, H]: curvature m = max(g'' - M3 H, -M)
        H = np.minimum(np.maximum(fwd + fwd, np.abs(g2) * (0.5 / M3)), H_cap)
        m = np.maximum(g2 - M3 * H, -M)
        dl = g1sq - (m + m) * gp
        sl = np.sqrt(np.maximum(dl, 0.0))
        has = (m < 0) | (neg & (dl >= 0))
        hl = np.where(up, (g1 + sl) / np.maximum(-m, _TINY), (gp + gp) / np.maximum(sl - g1, _TINY))
        safe = np.where(pos, np.minimum(np.where(has, hl, np.inf), H), 0.0)
        mono = neg & (g * (2.0 * M) >= -g1sq)
        back = np.where(pos, bwd, np.where(mono, g1 * (1.0 / M), np.nan))
        # prediction: the exact-curvature quadratic
        disc = g1sq - (g2 + g2) * g
        sd = np.sqrt(np.maximum(disc, 0.0))
        est = np.where(neg, np.where(disc >= 0, (g + g) / (sd - g1), g / (-g1)),
                       np.where(pos & (g2 < 0), (g1 + sd) / np.maximum(-g2, _TINY), np.inf))
        ae = np.abs(est)
        acc = neg & (ae <= d_acc) & (M3 * ae * ae * ae <= (6.0 * tol) * (-g1))
        graze = (g1 <= 0) & (np.abs(g) <= noise) & ~acc
        if fresh is not None:
            graze &= ~fresh
            est = np.where(fresh, np.inf, est)
            acc &= ~fresh
        est = np.where(graze, 0.0, est)
        return safe, est, acc | graze, back
