"""Certified location of the next event of a flight.

Event functions are positive before their event and reach zero at it:

* :class:`WallHit` ``side=+1``: ``g = r - x`` (``g' = -v``, ``|g''| <= bound_x2``);
  ``side=-1``: ``g = x - l`` (``g' = v``);
* :class:`VelocityZero`: ``g = s v`` (``g' = s a``, ``|g''| <= bound_v2``); only in scenes
  with friction (a frictionless flight passes smoothly through ``v = 0``).

Safe steps
----------
If ``g(ta) >= 0`` and ``|g''| <= M`` on the window, then
``g(ta + h) >= g(ta) + g'(ta) h - M h^2 / 2 > 0`` for ``0 <= h < h*``,
``h* = (g' + sqrt(g'^2 + 2 M g)) / M = 2 g / (sqrt(g'^2 + 2 M g) - g')``,
so stepping by the smallest ``h*`` over the active functions can never jump over a root of
any of them.  Near a simple root the step is a Newton step taken from the safe side
(quadratic convergence, never crossing); the iteration stops when a ``g`` falls below its
noise floor (``noise_x`` for walls, ``noise_v`` for velocity): that is the event, located to
working precision.  Consequences, each pinned by a test:

* two roots closer than any resolution are never skipped: the first is found;
* a tangential zero (grazing) is declared a root when ``g`` falls below the noise floor,
  i.e. when the minimum of ``g`` is indistinguishable from 0 at the working precision;
  a near-miss above the floor is passed in a number of steps logarithmic in the distance;
* a root at exactly the end time is found: the last step lands on ``t_end`` exactly and
  ``g`` is tested there;
* at the start of a flight, a function already at ``g ~ 0`` with ``g'`` clearly positive
  is leaving its zero (e.g. ``r - x`` just after an impact at ``r``): not an event.

Two speed-ups keep the certificate
----------------------------------
* far from roots the safe steps run in float64 on ``flight.evaluate_float`` with rigorous
  error bounds subtracted (``_float_advance``); the mpf steps take over within ~1e-14 of a
  possible root, where Newton-from-the-safe-side needs 2-3 steps to reach 1e-60;
* ``safe_step`` forms the step in float64 when precision does not matter (far) and as a
  Newton step shortened by ``2 M g / g'^2`` (provably below ``h*``) near a simple root.
* a flight with a ``max_window`` has its bounds asked over windows of at most that length,
  and no step leaves the window its bound was asked over (the float steps move to the next
  window, with its own bounds, once nothing can happen up to the window's end).  Issue 33:
  a Taylor flight's bounds grow with the window (``vmax``); over the rest of a ten-period
  run they were ~100x too loose, and scene D's ten-period truths took 7.7 CPU s for four
  states where windows of ``T / 8`` take 2.7, the same values.
* a root declared where ``g'`` is tiny too (tangency) is moved by Newton on ``g'`` to the
  touching point (``_tangency``), so that a grazing contact is located with ``g' ~ 0`` to
  working precision rather than ``sqrt(noise)``.

Flights from rest
-----------------
A flight that starts with ``v = 0`` (after a turn, slip or release) has ``g = s v = 0`` and
possibly ``g' = s a = 0`` (slip exactly where ``|A| = f``).  Its velocity function is then
tracked through ``q = s a`` instead (``q' = s a'`` by ``flight.jerk``, ``|q''| <= bound_a2``):
while ``q > 0`` the speed ``|v|`` grows, so no velocity event can happen; at the first zero of
``q`` (found by the same safe steps) ``g = s v`` is strictly positive and is tracked from there.
The same holds for the wall a frictionless flight leaves from rest (``g = r - x``,
``g' = -v = 0``, ``g'' = -a``: tracked through ``q = -a``).
"""
from __future__ import annotations

import math

import mpmath

_EPS = 2.0 ** -52
#: Bound on the float64 pre-steps per flight (then the mpf steps take over).
MAX_FLOAT_STEPS = 400
#: Bound on safe steps per flight (a near-tangency costs ~log of the miss distance).
MAX_STEPS = 20000
#: Steps of one search after which the cubic step (``_crawl_step``) joins the quadratic one.
CRAWL_STEPS = 64


class WallHit:
    """``g = r - x`` (side +1) or ``x - l`` (side -1).

    ``from_rest``: the flight starts at rest on this wall (frictionless release); the
    watched quantity is then ``q = -side a`` (``g'' = q``) until it first vanishes.
    """

    __slots__ = ("side", "wall", "kind", "from_rest")

    def __init__(self, side, wall, from_rest=False):
        self.side, self.wall, self.kind, self.from_rest = side, wall, "wall", from_rest

    def value(self, x, v, a):
        if self.side > 0:
            return self.wall - x, -v
        return x - self.wall, v

    def rest_value(self, a, jerk):
        return -self.side * a, -self.side * jerk

    def second(self, a, jerk):
        """``g''``."""
        return -self.side * a

    def float_lower(self, rest, fx, wall_f):
        """Lower bounds ``(g, g')`` from a float evaluation ``fx`` (see ``_float_advance``)."""
        x, v, a, j, ex, ev, ea, ej = fx
        sd = self.side
        if rest:
            return -sd * a - ea, -sd * j - ej
        g = (wall_f - x) if sd > 0 else (x - wall_f)
        return g - ex - abs(wall_f) * _EPS, -sd * v - ev

    def bound(self, flight, ta, tb):
        return flight.bound_x2(ta, tb)

    def bound3(self, flight, ta, tb):
        """A bound of the third derivative, |a'| (``_crawl_step``)."""
        return flight.bound_v2(ta, tb)

    def noise(self, flight):
        return flight.noise_x, flight.noise_v


class VelocityZero:
    """``g = s v``: the velocity of a flight with sign ``s`` reaches zero."""

    __slots__ = ("s", "kind", "from_rest")

    def __init__(self, s, from_rest=False):
        self.s, self.kind, self.from_rest = s, "velocity", from_rest

    def value(self, x, v, a):
        return self.s * v, self.s * a

    def rest_value(self, a, jerk):
        return self.s * a, self.s * jerk

    def second(self, a, jerk):
        """``g''``."""
        return self.s * jerk

    def float_lower(self, rest, fx, wall_f):
        """Lower bounds ``(g, g')`` from a float evaluation ``fx`` (see ``_float_advance``)."""
        x, v, a, j, ex, ev, ea, ej = fx
        if rest:
            return self.s * a - ea, self.s * j - ej
        return self.s * v - ev, self.s * a - ea

    def bound(self, flight, ta, tb):
        return flight.bound_v2(ta, tb)

    def bound3(self, flight, ta, tb):
        """A bound of the third derivative, |a''| (``_crawl_step``)."""
        return flight.bound_a2(ta, tb)

    def noise(self, flight):
        return flight.noise_v, flight.noise_a


#: float64 evaluation of the step only for values whose squares and products stay normal.
_FLOAT_SAFE_LO, _FLOAT_SAFE_HI = 1e-140, 1e140


def safe_step(g, dg, M):
    """A step ``h`` with ``g + dg h - M h^2/2 > 0`` on ``[0, h)`` (``g >= 0``, ``M >= 0``).

    The exact bound is ``h* = (dg + sqrt(dg^2 + 2 M g))/M``.  Any smaller step is safe, so
    the step is formed cheaply:

    * approaching a root (``dg < 0``, ``d = M g / dg^2 <= 1e-3``): the Newton step
      ``g/|dg|`` shortened by the factor ``1 - d``.  Since
      ``h* = (g/|dg|) * 2/(1 + sqrt(1 + 2 d)) >= (g/|dg|) (1 - d/2)``, this is below ``h*``
      and keeps Newton's quadratic convergence (the next ``g`` is ``~ d g``);
    * otherwise ``h*`` evaluated in float64 and shrunk by ``1e-9`` (far from a root the
      step's precision does not matter, only its safety) -- but only while ``g``, ``g'`` and
      their squares are normal float64 numbers: a subnormal ``float(g)`` carries up to 50 %
      relative error, far beyond the ``1e-9`` margin, so such values take the working-precision
      path, which shortens ``h*`` by 16 ulp (its own rounding is a few ulp).
    """
    gf, dgf, Mf = float(g), float(dg), float(M) * (1 + 1e-12)
    if g > 0 and not (_FLOAT_SAFE_LO < gf < _FLOAT_SAFE_HI and (dgf == 0 or _FLOAT_SAFE_LO < abs(dgf) < _FLOAT_SAFE_HI)):
        return _safe_step_mp(g, dg, M)
    if g <= 0:                              # leaving a zero (start of a flight): h* = 2 g'/M
        if dgf <= 0:
            return mpmath.mpf(0)
        return mpmath.inf if Mf == 0 else mpmath.mpf(2 * dgf / Mf * (1 - 1e-9))
    if dgf < 0 and gf > 0 and Mf * gf <= 1e-3 * (dgf * dgf):
        d = Mf * gf / (dgf * dgf)
        if d <= 1e-3:
            newton = g / -dg
            # (1 - 2d) without rounding 2d away; at least 16 ulp below the Newton step
            cut = max(newton * mpmath.mpf(2 * d), mpmath.ldexp(newton, 4 - mpmath.mp.prec))
            return newton - cut
    if not (gf > 0 and math.isfinite(gf) and math.isfinite(dgf)):
        return _safe_step_mp(g, dg, M)
    if Mf == 0:
        return mpmath.inf if dgf >= 0 else mpmath.mpf(gf / -dgf * (1 - 1e-9))
    root = math.sqrt(dgf * dgf + 2 * Mf * gf)
    h = (dgf + root) / Mf if dgf >= 0 else 2 * gf / (root - dgf)
    return mpmath.mpf(h * (1 - 1e-9))


def _safe_step_mp(g, dg, M):
    """``h*`` at the working precision, shortened by 16 ulp (values outside float64's
    comfortable range; the few roundings of this formula are within a few ulp of ``h*``,
    and a step that lands one rounding past ``h*`` would not be safe)."""
    shrink = 1 - mpmath.ldexp(1, 4 - mpmath.mp.prec)
    if M == 0:
        return mpmath.inf if dg >= 0 else g / -dg * shrink
    root = mpmath.sqrt(dg * dg + 2 * M * g)
    if dg >= 0:
        return (dg + root) / M * shrink
    return 2 * g / (root - dg) * shrink


def _crawl_step(g, dg, d2g, M3):
    """A root-free step from the cubic minorant ``g + g' h + g'' h^2/2 - M3 h^3/6`` (``g > 0``,
    ``M3`` a bound of the third derivative): each of ``min(g', 0) h``, ``min(g'', 0) h^2/2`` and
    ``M3 h^3/6`` stays below ``g/3`` under the step, so the minorant stays positive.  Where ``g``,
    ``g'`` and ``g''`` are all near zero together (a slip toward a wall a hair away, ``|A| = f``
    at its start: the threshold pairs of issue 18) the quadratic step shrinks with ``g`` and the
    search crawls (20000 steps did not reach a wall 1e-19 away); this step is
    ``(2 g/M3)^(1/3)`` there.  Used after ``CRAWL_STEPS`` steps of one search."""
    h = mpmath.cbrt(2 * g / M3) if M3 > 0 else mpmath.inf
    if dg < 0:
        h = min(h, g / (-3 * dg))
    if d2g < 0:
        h = min(h, mpmath.sqrt(2 * g / (-3 * d2g)))
    return h * mpmath.mpf("0.999")


class _Tracked:
    """Per-function state of one search: which quantity is watched (g itself, or s a)."""

    __slots__ = ("fn", "rest")

    def __init__(self, fn):
        self.fn = fn
        self.rest = getattr(fn, "from_rest", False)


def _probe(item, flight, t, x, v, a, first):
    """Return ``(is_root, value, derivative)`` for one function at ``t``."""
    fn = item.fn
    if item.rest:
        q, dq = fn.rest_value(a, flight.jerk(t, x, v, a))
        if q <= flight.noise_a and not (first and dq > 0):
            item.rest = False          # s a has reached 0: |v| stops growing; watch s v now
        else:
            return False, q, dq
    g, dg = fn.value(x, v, a)
    noise, noise_d = fn.noise(flight)
    if g <= noise:
        if first and dg > noise_d:
            return False, g, dg        # leaving its zero at the start of the flight
        return True, g, dg
    return False, g, dg


def find_next_event(flight, functions, t_end):
    """Earliest event of ``functions`` along ``flight`` in ``[t_start, t_end]``.

    Returns ``(fn, t, (x, v, a))`` with ``fn`` the event function that fired (``None`` if
    none fired before ``t_end``; then ``t == t_end``).  Raises ``RuntimeError`` with the
    state if ``MAX_STEPS`` safe steps do not settle it.
    """
    t = flight.t_start
    items = [_Tracked(fn) for fn in functions]
    use_float = hasattr(flight, "evaluate_float")
    cap = flight.max_window
    for step in range(MAX_STEPS):
        if step == 1 and use_float:
            t = _float_advance(flight, items, t, t_end)
        x, v, a = flight.evaluate(t)
        remaining = t_end - t
        window = remaining if cap is None else min(remaining, cap)
        h, nearest = remaining, None
        for item in items:
            is_root, g, dg = _probe(item, flight, t, x, v, a, step == 0)
            if is_root:
                # the tangency test keeps its bound over the rest of the flight (its calibration)
                M = item.fn.bound(flight, t, t_end) if remaining > 0 else 0
                if step > 0 and dg * dg <= 32 * M * g + 32 * M * item.fn.noise(flight)[0]:
                    return _tangency(item.fn, flight, t, x, v, a, t_end)
                return item.fn, t, (x, v, a)
            if remaining <= 0:
                continue
            tb = t + window
            M = flight.bound_a2(t, tb) if item.rest else item.fn.bound(flight, t, tb)
            h_item = safe_step(g, dg, M)
            if step > CRAWL_STEPS and not item.rest and g > 0:
                d2g = item.fn.second(a, flight.jerk(t, x, v, a))
                h_item = max(h_item, _crawl_step(g, dg, d2g, item.fn.bound3(flight, t, tb)))
            if h_item < h:
                h, nearest = h_item, item
        if remaining <= 0:
            return None, t, (x, v, a)
        h = min(h, window)              # the bounds hold on [t, t + window]
        if h >= remaining:
            t = t_end
        elif t + h == t:
            # the step is below the resolution of t: the root is located to that resolution
            return nearest.fn, t, (x, v, a)
        else:
            t = t + h
    raise RuntimeError(
        f"event search did not settle in {MAX_STEPS} safe steps: "
        f"(t, x, v, mode) = ({t}, {x}, {v}, flight s={flight.s})")


def _float_advance(flight, items, t, t_end):
    """Safe steps in float64 from ``t``; returns the mpf time up to which nothing happens.

    Optional accelerator (flights offering ``evaluate_float(h)``, ``h = t - t_start`` a
    float): ``evaluate_float`` returns ``(x, v, a, a', ex, ev, ea, ea')`` with rigorous
    absolute error bounds of each value for the exact flight at ``t_start + h`` (``h`` taken
    exactly).  Each function's value and derivative are lowered by their error bounds
    (``float_lower``), which keeps the quadratic lower bound of the safe step valid; steps
    are shrunk by ``1e-10`` relative to cover their own rounding, and ``M`` raised by as
    much.  The phase stops as soon as any lowered value reaches 0 (a root may be within
    float resolution: the mpf steps take over from the last certified point), when a step
    would reach ``t_end``, or when steps stagnate (near-tangency).  Far from roots this
    replaces mpf evaluations by float ones; near them, the mpf steps start from ~1e-14.
    """
    t0 = flight.t_start
    h_end = float(t_end - t0)
    if mpmath.mpf(h_end) > t_end - t0:
        h_end = math.nextafter(h_end, -math.inf)
    h = float(t - t0)
    if mpmath.mpf(h) > t - t0:
        h = math.nextafter(h, -math.inf)
    start = h
    walls = [float(getattr(item.fn, "wall", 0)) for item in items]
    cap = flight.max_window
    w_end = h_end if cap is None else min(h_end, h + float(cap))
    bounds = _float_bounds(flight, items, t, _until(t0, w_end, h_end, t_end))
    for _ in range(MAX_FLOAT_STEPS):
        fx = flight.evaluate_float(h)
        safe = math.inf
        for item, wall_f, M in zip(items, walls, bounds):
            g, dg = item.fn.float_lower(item.rest, fx, wall_f)
            if g <= 0:
                safe = -1.0
                break
            root = math.sqrt(dg * dg + 2 * M * g)
            safe = min(safe, (dg + root) / M if dg >= 0 else 2 * g / (root - dg))
        if w_end < h_end and safe * (1 - 1e-10) >= w_end - h:
            # nothing happens up to the window's end: the next window, with its own bounds
            h, w_end = w_end, min(h_end, w_end + float(cap))
            bounds = _float_bounds(flight, items, mpmath.fadd(t0, h, exact=True),
                                   _until(t0, w_end, h_end, t_end))
            continue
        step = min(h_end - h, safe) * (1 - 1e-10)          # below w_end - h if a window binds
        if step <= 1e-12 * (1 + abs(h)) or h + step >= h_end:
            break
        h += step
    if h <= start:
        return t
    return max(t, t0 + mpmath.mpf(h))


def _until(t0, w_end, h_end, t_end):
    """The exact end of a window of ``_float_advance``: ``t0 + w_end``, or ``t_end`` for the last."""
    return t_end if w_end >= h_end else mpmath.fadd(t0, w_end, exact=True)


def _float_bounds(flight, items, ta, tb):
    """Each function's ``M`` over ``[ta, tb]`` as a float, raised to cover its rounding."""
    out = []
    for item in items:
        M = flight.bound_a2(ta, tb) if item.rest else item.fn.bound(flight, ta, tb)
        out.append(float(M) * (1 + 1e-10) + 1e-300)
    return out


def _tangency(fn, flight, t, x, v, a, t_end):
    """A root declared where ``g'`` is small too: move to the stationary point of ``g``.

    Near a tangential zero the safe steps stop where ``g`` first falls below its noise
    floor, up to ``sqrt(2 noise / M)`` before the touching point, where ``|g'|`` is still
    ``~ sqrt(2 M noise)``.  Newton's method on ``g'`` (``g''`` from ``fn.second``) moves the
    event to the point where ``g' = 0`` (``g`` is below the noise floor all the way), so
    that a grazing touch is located with ``g' ~ 0`` to working precision instead of
    ``sqrt(noise)``.  If that point lies beyond ``t_end``, nothing happens before ``t_end``.
    """
    noise_d = fn.noise(flight)[1]
    last_step = mpmath.inf
    for _ in range(60):
        g, dg = fn.value(x, v, a)
        if abs(dg) <= noise_d:
            break
        g2 = fn.second(a, flight.jerk(t, x, v, a))
        if g2 == 0 or abs(dg / g2) >= last_step:
            break                      # Newton no longer contracts: at the noise level
        last_step = abs(dg / g2)
        t_new = t - dg / g2
        if t_new > t_end:
            x, v, a = flight.evaluate(t_end)
            return None, t_end, (x, v, a)
        t = t_new
        x, v, a = flight.evaluate(t)
    return fn, t, (x, v, a)
