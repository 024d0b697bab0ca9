"""Constructed events in bulk under position forcing (issue 33): ``construct``'s kinds, band and
verdict for ``x'' + c x' + f sgn(x') = F cos(k x) cos(w t)``, with any damping and restitution.

The flight has no closed form: the event state ``(t*, x*, v*)`` with sign ``s`` is run back to
``t = 0`` by ``backflight`` (a float64 Taylor flight of this room, double-double state,
independent of ``fast`` and of ``reference``), which also gives the samples of the certificate,
their error and the error of the event state that the construction and the start's rounding to
float64 cause (``dx, dv``).

Certificate (no event of the forward flight from ``t = 0`` before ``t*``): as in ``construct``,
on the grid of ``SAMPLES`` intervals of ``D`` a function with ``|g''| <= M`` lies above its chord
minus ``M D^2 / 8``; here each sample of ``g2 = s v`` must clear that floor *plus* its own error
bound ``E_j``, with the bound of position forcing (``reference.taylor``) ``|v''| <= M2 = F w + F k
vmax + |c| (F + f + |c| vmax)``, ``vmax`` the a-priori bound of ``|v|`` of every substep.  On the
last interval ``g2`` either clears the floor at both ends or decreases to ``s v* >= 0`` at ``t*``
(``s a(t*) + M2 D < 0``, as ``|a'| <= M2``).  Then ``s v > 0`` on ``[0, t*)``: ``x`` moves
monotonically from ``x(0)`` (inside ``[l, r]`` by its error bound) to ``x*`` (a wall or a point
of the gap), so it meets no wall before ``t*`` -- no sampled wall distance is needed (``construct``
samples it too; near a tangency, where the wall distance falls like ``|a| t^2 / 2`` below the
floor ``(F + f) D^2 / 8``, the chord test refuses every case with ``|a| < (F + f) / 4``, e.g. all of
eq. xpot, whose walls see ``A = 0``).

Kinds (``construct.KINDS``), with ``A(x, t) = F cos(k x) cos(w t)``:

* ``crossing_pair``, ``tangency``, ``impact_at_T``: at the wall ``W_s`` (``r`` for ``s = +1``,
  ``l`` for ``-1``), decelerating (``s x''(t*) < -0.02 (F + f)``), speeds and margins as in
  ``construct``;
* ``turn``: ``v = 0`` mid-gap with ``s A(x*, t*) = -f (1 + delta)`` (needs ``|F cos k x*| >=
  f (1 + delta)``); ``stick``: ``|A(x*, t*)| = f (1 - delta)``, or where ``|F cos k x*|`` is
  below that, any ``t*`` in ``(0.05 T, 0.95 T)`` (not the phase 0 of ``construct``, which puts
  the stop at exactly ``t = T``, the end of the itinerary fast is asked for);
* ``chatter``: a start just off a wall ``W`` the force pushes into at ``t = 0``
  (``P = side F cos(k W) > f``), bounces accumulating within a fifth of the push, the
  frozen-force estimate of ``construct`` with the push ``P`` and the restitution ``e``
  (``rho = e sqrt((P - f)/(P + f))``).

The band (``construct``'s rule): a wall kind's margin within ``BAND_FACTOR dx``; a velocity
kind's within ``BAND_FACTOR (F w dt + F k dx)`` -- under position forcing the force at the turn
moves with its position too (``|A_x| <= F k``).  ``time_tol = TIME_FACTOR dt + 8 eps t*``.
"""
from __future__ import annotations

import numpy as np

from cross_check.agreement import backflight
from cross_check.agreement import construct as base
from reference.scene import Scene

EPS = base.EPS


def params(scene: Scene):
    """``(F, f, w, l, r, c, k, e)`` as floats of a position-forced scene with ``F > 0``."""
    if not (scene.has("position_forcing") and scene.has("forcing")):
        raise ValueError(f"construct_position: scene must have position forcing (wavenumber) and F > 0, "
                         f"got {scene!r}")
    return tuple(scene.float(k) for k in ("F", "f", "omega", "l", "r", "damping", "wavenumber", "restitution"))


def _bound_v2(scene, vmax):
    """``M2``, the bound of ``|v''|`` on a flight whose ``|v|`` stays below ``vmax`` (module
    docstring); it grows with ``vmax``."""
    F, f, w, _, _, c, k, _ = params(scene)
    return F * w + F * k * vmax + c * (F + f + c * vmax)


def _no_earlier_event(scene, t_star, s, bk, decel):
    """The certificate of the module docstring on the backward samples ``bk``; ``decel`` is
    ``s x''(t*)`` (used where ``v* = 0``)."""
    l, r = scene.float("l"), scene.float("r")
    n = base.SAMPLES
    v, E = bk.v[::-1].T, bk.err[::-1].T                 # row j at t = t* j / n
    D = t_star / n
    M2 = _bound_v2(scene, bk.vmax)
    g2 = s[:, None] * v - E
    floor2 = M2 * D * D / 8
    decreasing = decel + M2 * D < 0
    last2 = ((g2[:, -2] > floor2) & (g2[:, -1] > floor2)) | (decreasing & (s * bk.v[0] >= 0))
    ok = np.all(g2[:, :-1] > floor2[:, None], axis=1) & last2
    ok &= (bk.x0 - E[:, 0] >= l) & (bk.x0 + E[:, 0] <= r)
    return ok & bk.ok


def backward(scene, t_star, x_star, v_star, s, decel, matrices=True, give_up=False):
    """The backward flights (``backflight.run``; ``matrices``: with the event-state error) from
    the event states and the certificate of each (``decel = s x''(t*)``): ``(Backward, ok)``.

    ``give_up`` (a screen, without ``matrices``): run no further a flight that has a sample
    failing the certificate already (``_refused``): its ``ok`` is False, as the whole run's would
    be, and its start NaN.  Issue 33: most candidates of the kinds a scene does not admit from
    one flight leave the gap or turn early, and were run to ``t = 0`` (on ``F=2.74 f=0.54
    omega=1.06 l=-0.54 r=0.91 wavenumber=1.22`` three such kinds took 3.1 of the hard cases' 3.6
    CPU s of float screens).  The states task, old and new one after the other: 7.2 -> 6.0 CPU s
    on that scene, 11.0 -> 7.5 on ``F=2.91 f=0.37 omega=1.23 l=-1.1 r=0.66 wavenumber=2.01
    damping=0.23``, 24.1 -> 14.6 on ``F=1.896 f=0.0929 omega=0.806 l=0.04 r=0.64
    wavenumber=3.5937 damping=0.369 restitution=0.9``, and the same cases and notes on 13
    scenes (eight drawn over the issue's ranges, the issue's two, three corners).  The flights
    still running take the substeps they need, which may be fewer than the batch's had: a screen
    only screens (the validated certificate decides)."""
    lost = _refused(scene, t_star, s) if give_up else None
    bk = backflight.run(backflight.Params.of(scene), t_star, x_star, v_star, s, base.SAMPLES,
                        matrices, lost=lost)
    return bk, _no_earlier_event(scene, t_star, s, bk, decel)


def _refused(scene, t_star, s):
    """``lost(x, v, err, vmax, lanes)`` for ``backflight.run``, called with each sample after the
    event's in turn (``x, v, err`` of the flights ``lanes``): the flights with a sample so far that
    fails the certificate of the whole run already --

    * ``s v - E`` at most the floor ``M2 D^2 / 8`` with the ``vmax`` so far (its ``v`` and ``E``
      are final, and the floor only grows with ``vmax``), or
    * ``x`` beyond the wall behind the motion by more than its ``E`` (``x + E < l`` for ``s = 1``,
      ``x - E > r`` for ``s = -1``): were every sample to pass, ``x`` would be monotone, so the
      true ``x(0)`` would lie beyond that wall too, and the start's test ``l <= x0 -+ E_0 <= r``
      (``E_0``, the last error, is the largest) would fail."""
    D = t_star / base.SAMPLES
    l, r = scene.float("l"), scene.float("r")
    lowest, behind = np.full(t_star.shape, np.inf), np.zeros(t_star.shape, bool)     # over the rows so far

    def lost(x, v, err, vmax, lanes):
        sign = s[lanes]
        lowest[lanes] = np.fmin(lowest[lanes], sign * v - err)
        behind[lanes] |= np.where(sign > 0, x + err < l, x - err > r)
        return (lowest[lanes] <= _bound_v2(scene, vmax) * D[lanes] ** 2 / 8) | behind[lanes]
    return lost


def _wall_candidates(scene, rng, n, kind):
    F, f, w, l, r, c, k, _ = params(scene)
    T = 2 * np.pi / w
    s = rng.choice([-1.0, 1.0], n)
    W = np.where(s > 0, r, l)
    t = np.full(n, T) if kind == "impact_at_T" else rng.uniform(0.05, 1.0, n) * T
    a = s * F * np.cos(k * W) * np.cos(w * t) - f            # s x'' at t* (v* -> 0)
    if kind == "impact_at_T":
        speed = 10 ** rng.uniform(-2, 0.5, n) * (F / w + f * T + (r - l) / T)
        keep, margin = np.ones(n, bool), np.full(n, np.nan)
    else:
        delta = 10 ** rng.uniform(-13, -1, n) if kind == "crossing_pair" else np.zeros(n)
        keep = a < -0.02 * (F + f)
        speed, margin = np.abs(a) * delta, np.abs(a) * delta * delta / 2
    decel = a - c * speed
    return t[keep], W[keep], (s * speed)[keep], s[keep], margin[keep], speed[keep], decel[keep]


def _velocity_candidates(scene, rng, n, kind):
    F, f, w, l, r, c, k, _ = params(scene)
    x = l + (r - l) * rng.uniform(0.1, 0.9, n)
    amp = np.abs(F * np.cos(k * x))
    delta = 10 ** rng.uniform(-10, 0, n)
    if kind == "turn":
        delta[rng.random(n) < 0.1] = 0.0
    with np.errstate(divide="ignore"):
        cval = f * (1 + delta) / amp if kind == "turn" else np.minimum(f * (1 - delta) / amp, 1.0)
    t, sign_cos = base.phase_times(scene, np.nan_to_num(cval, nan=2.0, posinf=2.0), rng)
    if kind == "stick":         # |F cos k x*| <= f (1 - delta): a stop at any time, but not at t = T
        t = np.where(cval >= 1, rng.uniform(0.05, 0.95, n) * 2 * np.pi / w, t)
    keep = (cval <= 1) & (t > 0.02 * 2 * np.pi / w)
    A = F * np.cos(k * x) * np.cos(w * t)
    if kind == "stick":
        delta = np.where(cval >= 1, 1 - np.abs(A) / f, delta)
    s = -np.sign(A) if kind == "turn" else rng.choice([-1.0, 1.0], n)
    s = np.where(s == 0, 1.0, s)
    decel = s * A - f
    return (t[keep], x[keep], np.zeros(keep.sum()), s[keep], (f * delta)[keep], np.abs(decel)[keep],
            decel[keep])


def _chatter_candidates(scene, rng, n):
    """``construct``'s chatter starts at a wall the force pushes into at ``t = 0``."""
    F, f, w, l, r, c, k, e = params(scene)
    pushes = [(side, wall, side * F * np.cos(k * wall)) for side, wall in ((1, r), (-1, l))]
    pushes = [(side, wall, P) for side, wall, P in pushes if P > f]
    if not pushes or e == 0 or (f == 0 and e == 1):
        return (np.zeros(0),) * 6
    pick = rng.integers(0, len(pushes), n)
    side = np.array([pushes[i][0] for i in pick], float)
    wall = np.array([pushes[i][1] for i in pick])
    P = np.array([pushes[i][2] for i in pick])
    h = (r - l) * 10 ** rng.uniform(-9, -4, n)
    a, b = P + f, P - f
    u = rng.uniform(-1, 1, n) * np.sqrt(2 * b * h)          # speed towards the wall
    v1 = np.sqrt(u * u + 2 * b * h)
    rho = e * np.sqrt(b / a)
    t_inf = (v1 - u) / b + e * v1 * (1 / a + 1 / np.sqrt(a * b)) / (1 - rho)
    push = np.arccos(f / P) / w
    keep = t_inf < 0.2 * push
    return (t_inf[keep], (wall - side * h)[keep], (side * u)[keep], side[keep], (push - t_inf)[keep],
            v1[keep])


def build(scene, rng, n, kind):
    """Candidates of one kind, certified (``construct._build``'s counterpart)."""
    F, f, w, l, r, c, k, _ = params(scene)
    if kind == "chatter":
        t, x0, v0, s, margin, _ = _chatter_candidates(scene, rng, n)
        cases = base.Cases(np.full(t.size, base.KINDS.index(kind)), x0, v0, t, margin,
                           np.zeros(t.size, bool), t.copy())
        return cases
    wall = kind in ("crossing_pair", "tangency", "impact_at_T")
    gen = _wall_candidates if wall else _velocity_candidates
    t, x_s, v_s, s, margin, slope, decel = gen(scene, rng, n, kind)
    bk, ok = backward(scene, t, x_s, v_s, s, decel)
    dt = (bk.dx if wall else bk.dv) / np.maximum(slope, 1e-300)
    moved = bk.dx if wall else F * w * dt + F * k * bk.dx
    band = ~(margin > base.BAND_FACTOR * moved)
    tol = base.TIME_FACTOR * dt + 8 * EPS * t
    cases = base.Cases(np.full(t.size, base.KINDS.index(kind)), bk.x0, bk.v0, t, margin, band, tol)
    return cases.select(ok)


def construct(scene: Scene, n: int, *, seed: int = 0, kinds=base.KINDS) -> base.Cases:
    """Up to ``n`` cases of each kind in ``kinds`` (``construct.construct``'s rounds of draws)."""
    base.check_count(n)
    params(scene)
    return base.draw(scene, n, seed, kinds, build, lambda kind: admitted(scene, kind))


def admitted(scene, kind) -> bool:
    """Whether a kind can occur at all: turns and sticks need friction, chatter a wall pushed
    into beyond friction with ``e > 0`` (and ``e < 1`` without friction)."""
    F, f, w, l, r, c, k, e = params(scene)
    if kind in ("turn", "stick"):
        return f > 0
    if kind == "chatter":
        return e > 0 and not (f == 0 and e == 1) and any(
            side * F * np.cos(k * wall) > f for side, wall in ((1, r), (-1, l)))
    return True
