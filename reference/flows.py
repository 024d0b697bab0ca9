"""Closed-form motions per mode, at the working mpmath precision.

The model is ``x'' + c x' + f sgn(x') = A(x, t)``, ``A(x, t) = F cos(k x) cos(w t)``
(``cos(k x) = 1`` when the scene has no wavenumber).  Between events the motion is one of

* a **flight** with velocity sign ``s`` (``v`` keeps the sign ``s``; ``s = 0`` for a
  frictionless scene, where the flow does not depend on the sign of ``v``):
  ``a = A(x, t) - s f - c v``;
* **sticking** (interior, ``v = 0``) or **wall contact** (``x = l`` or ``r``, ``v = 0``):
  nothing moves; these modes only need the times at which the force first exceeds a level,
  which :class:`CosineForcing` gives in closed form.

The flight interface (what the event finder of ``reference.events`` uses)
--------------------------------------------------------------------------
Any object with these members is a flight and plugs into the event finder unchanged
(``reference.taylor`` implements one for position-dependent forcing):

``t_start``, ``x_start``, ``v_start``, ``s``
    the initial time and state (mpf) and the velocity sign (``+1``, ``-1``; ``0`` if f = 0).
``evaluate(t) -> (x, v, a)``
    position, velocity and acceleration at any ``t >= t_start`` (mpf, working precision).
``jerk(t, x, v, a) -> a'``
    ``da/dt`` along the flight at ``t`` (used only when a flight starts from rest, ``v = 0``,
    to certify that ``|v|`` grows until ``s a`` first vanishes).
``bound_x2(ta, tb)``, ``bound_v2(ta, tb)``, ``bound_a2(ta, tb)``
    certified upper bounds on ``|x''|``, ``|v''|`` and ``|a''|`` over ``[ta, tb]`` (mpf).
    They are what makes the event location certified; they must be true bounds
    (e.g. ``|x''| <= F + f + c |v|``, ``|v''| <= |dA/dt| + |dA/dx| |v| + c |a|``).
``max_window``
    ``None``, or the longest window ``tb - ta`` over which the event search asks the bounds
    for its steps (``events.find_next_event`` then steps at most that far on one bound): the
    bounds must hold over any window, and a flight whose bounds loosen with the window's
    length (``reference.taylor``'s, ``vmax`` growing with it) keeps them tight this way.
``noise_x``, ``noise_v``, ``noise_a``
    the absolute noise floors of ``x``, ``v``, ``a`` at the working precision
    (a value whose magnitude is below its floor is indistinguishable from zero).
``evaluate_float(h)`` (optional accelerator)
    float64 ``(x, v, a, a', ex, ev, ea, ea')`` at ``t_start + h`` (``h`` a float, taken
    exactly) with *rigorous* absolute error bounds ``ex, ...``; if present, the event finder
    takes its far-from-root safe steps in float64 (see ``events._float_advance``).

A flight is created as ``cls(model, t0, x0, v0, s)`` (``model``: ``reference.model.Model``,
the scene at the working precision: ``F, f, w, c, e, k, l, r, T, eps, x_scale, v_scale,
a_scale``).

The base flight (c = 0, no wavenumber), h = t - t0, theta = w h
----------------------------------------------------------------
    v(t) = v0 + (F/w) (sin wt - sin wt0) - s f h
    x(t) = x0 + v0 h + (F/w^2) (cos wt0 - cos wt - w h sin wt0) - s f h^2 / 2
evaluated without cancellation through the half angle:
    sin wt - sin wt0           = cos wt0 sin theta - 2 sin wt0 sin^2(theta/2)
    cos wt0 - cos wt - theta sin wt0 = 2 cos wt0 sin^2(theta/2) - sin wt0 (theta - sin theta)
with ``theta - sin theta`` computed at raised precision when ``theta`` is small (the
subtraction then loses ``log2(6/theta^2)`` bits, which the raised precision restores).
Bounds: ``|x''| <= F + f``, ``|v''| = |A'| <= F w``, ``|a''| <= F w^2``.

The damped flight (c > 0, no wavenumber): :class:`DampedFlight`
---------------------------------------------------------------
``x'' + c x' = F cos wt - s f``: with ``E = exp(-c h)`` and the particular solution
``v_p(t) = P cos wt + Q sin wt - s f / c``, ``P = F c/(c^2+w^2)``, ``Q = F w/(c^2+w^2)``:
    v(t) = v_p(t) + (v0 - v_p(t0)) E
    x(t) = x0 + X_p(t) - X_p(t0) + (v0 - v_p(t0)) (1 - E)/c,
    X_p(t) = (P sin wt - Q cos wt)/w - s f t / c   (an antiderivative of v_p)
regrouped (see the class docstring) so that no bracket cancels for short flights:
``1 - E = -expm1(-c h)``, ``exp(-ch) - 1 + ch`` and ``theta - sin theta`` at raised
precision.  Bounds: along a flight ``d|v|/dt <= F - c|v|``, so ``|v| <= V = max(|v0|, F/c)``;
``|x''| <= F + f + c V``, ``|v''| <= F w + c |x''|max``, ``|a''| <= F w^2 + c |v''|max``.
"""
from __future__ import annotations

import math

import mpmath
from mpmath import mpf
from mpmath.libmp import mpf_add as _add
from mpmath.libmp import mpf_cos_sin as _cos_sin
from mpmath.libmp import mpf_mul as _mul
from mpmath.libmp import mpf_pos as _pos
from mpmath.libmp import mpf_shift as _shift
from mpmath.libmp import mpf_sub as _sub

_RND = "n"
_make = mpmath.mp.make_mpf

#: Bits above the last bit of the working precision that count as noise (see ``noise_*``).
NOISE_BITS = 12


class CosineForcing:
    """``A(x, t) = F cos(k x) cos(w t)`` (``cos(k x) = 1`` if ``k`` is None)."""

    __slots__ = ("F", "w", "k", "two_pi")

    def __init__(self, F, w, k=None):
        self.F, self.w, self.k = F, w, k
        self.two_pi = 2 * mpmath.pi

    def amplitude(self, x):
        """The signed amplitude ``F cos(k x)`` at a fixed position."""
        return self.F if self.k is None else self.F * mpmath.cos(self.k * x)

    def value(self, x, t):
        """``A(x, t)``."""
        return self.amplitude(x) * mpmath.cos(self.w * t)

    def first_above(self, t, x, sigma, level, force_noise=0):
        """First ``tau >= t`` with ``sigma A(x, tau) > level`` on a right-neighbourhood of tau.

        ``x`` is fixed (sticking or wall contact).  With ``b = sigma F cos(k x)``:
        ``b cos(w tau) > level`` needs ``|b| > level``; then, with ``alpha = arccos(level/|b|)``
        and the phase ``phi = (w tau + (0 if b > 0 else pi)) mod 2 pi``, the set is
        ``phi in (-alpha, alpha) mod 2 pi``.  At ``phi = 2 pi - alpha`` the force is rising
        through the level (leave now); at ``phi = alpha`` it is falling (stay).  Phases
        within the phase noise of a boundary count as on it (no stick/slip ping-pong).
        ``force_noise``: the caller's noise in the force (``Model.noise_a``, the level within which a
        flight's velocity zero is located), as a phase ``noise / (|b| sin alpha)``, if wider:
        a stick entered by a flight where the force is leaving the level but still that close
        above it is *at* the boundary, not a slip at once (issue 33: an unseen scene's
        stick-slip boundary at 50 digits entered its stick 7.8e-59 inside the slip region,
        below the flight's ``noise_a`` 5e-58 but above this phase noise, and slipped, stuck and
        slipped again at the same instant until the integrator's bound stopped it).
        Returns ``None`` if the force never exceeds the level.  Under position forcing an
        amplitude ``F cos(k x)`` within its rounding noise of 0 is 0 (a rest where
        ``cos(k x) = 0``, e.g. at a wall ``k x = pi/2``: the force vanishes for all time, and a
        frictionless particle there stays; rounding must not make it leave and land again).
        """
        b = sigma * self.amplitude(x)
        noise = 0 if self.k is None else self.F * mpmath.ldexp(abs(self.k * x) + 8, -mpmath.mp.prec + NOISE_BITS)
        if abs(b) <= level + noise:
            return None
        alpha = mpmath.acos(level / abs(b))
        theta = self.w * t + (0 if b > 0 else mpmath.pi)
        phi = theta - self.two_pi * mpmath.floor(theta / self.two_pi)
        # phase noise: a phase within `tol` of a boundary is *at* the boundary, so that a
        # stick entered exactly where the force falls through the level is not left at once
        tol = mpmath.ldexp(abs(theta) + 8, -mpmath.mp.prec + NOISE_BITS)
        if force_noise:
            tol = max(tol, force_noise / (abs(b) * mpmath.sin(alpha)))
        if phi < alpha - tol or phi >= self.two_pi - alpha - tol:
            return t
        return max(t, t + (self.two_pi - alpha - phi) / self.w)


class _ConstantBounds:
    """Flights whose certified bounds ``Mx``, ``Mv``, ``Ma`` hold over the whole flight."""

    def bound_x2(self, ta, tb):
        return self.Mx

    def bound_v2(self, ta, tb):
        return self.Mv

    def bound_a2(self, ta, tb):
        return self.Ma


class BaseFlight(_ConstantBounds):
    """Closed-form flight of ``x'' = F cos(w t) - s f`` (no damping, no wavenumber).

    ``evaluate`` runs on mpmath's raw ``libmp`` tuples (the formulas of the module
    docstring, one ``cos_sin`` of ``theta/2`` per call, raised by ``2 log2(1/theta) + 10``
    bits when ``|theta| < 1`` so that ``theta - sin theta`` keeps full relative precision).
    """

    __slots__ = ("t_start", "x_start", "v_start", "s", "w", "F", "sf", "C0", "S0",
                 "Fw", "Fw2", "Mx", "Mv", "Ma", "noise_x", "noise_v", "noise_a", "max_window",
                 "_floats", "_raw", "_prec")

    def __init__(self, model, t0, x0, v0, s):
        self.t_start, self.x_start, self.v_start, self.s = t0, x0, v0, s
        F, f, w = model.F, model.f, model.w
        self.w, self.F = w, F
        self.sf = f if s > 0 else (-f if s < 0 else mpf(0))
        self.C0, self.S0 = mpmath.cos_sin(w * t0)
        self.Fw, self.Fw2 = model.Fw, model.Fw2
        self.Mx, self.Mv, self.Ma = model.Mx, model.Mv, model.Ma
        self.max_window = None
        eps = model.eps
        self.noise_x = eps * (model.x_scale + abs(x0) + abs(v0) * model.T)
        self.noise_v = eps * (model.v_scale + abs(v0))
        self.noise_a = model.noise_a
        self._floats = None
        self._prec = mpmath.mp.prec
        self._raw = tuple(q._mpf_ for q in (t0, x0, v0, self.C0, self.S0, self.Fw, self.Fw2,
                                            F, self.sf, w))

    def evaluate_float(self, h):
        """Float64 ``(x, v, a, a', ex, ev, ea, ea')`` at ``t_start + h`` with error bounds.

        Each value is a short sum of products of float-converted inputs (relative error
        ``eps/2`` each), ``sin``/``cos`` (1 ulp) and ~10 roundings; ``64 eps`` times the sum
        of the magnitudes of the terms bounds the absolute error (``theta - sin theta`` is
        formed by subtraction: its absolute error ``~eps |theta|`` is inside that bound).
        """
        if self._floats is None:
            self._floats = tuple(float(q) for q in (
                self.x_start, self.v_start, self.C0, self.S0, self.Fw, self.Fw2, self.F,
                self.sf, self.w))
        x0, v0, C0, S0, Fw, Fw2, F, sf, w = self._floats
        th = w * h
        sh, ch = math.sin(th / 2), math.cos(th / 2)
        sn, omc = 2 * sh * ch, 2 * sh * sh
        v = v0 + Fw * (C0 * sn - S0 * omc) - sf * h
        x = x0 + v0 * h + Fw2 * (C0 * omc - S0 * (th - sn)) - sf * h * h / 2
        cw, sw = C0 * (1 - omc) - S0 * sn, S0 * (1 - omc) + C0 * sn
        E = 64 * 2.0 ** -52
        ah = abs(h)
        return (x, v, F * cw - sf, -F * w * sw,
                E * (abs(x0) + abs(v0) * ah + Fw2 * (3 + abs(th)) + abs(sf) * h * h) + 1e-300,
                E * (abs(v0) + Fw * 3 + abs(sf) * ah) + 1e-300,
                E * (F + abs(sf)) + 1e-300, E * F * w * 2 + 1e-300)

    def evaluate(self, t):
        """``(x, v, a)`` at ``t``."""
        if t == self.t_start:
            return self.x_start, self.v_start, self.F * self.C0 - self.sf
        p = self._prec
        t0, x0, v0, C0, S0, Fw, Fw2, F, sf, w = self._raw
        h = _sub(t._mpf_, t0, p, _RND)
        th = _mul(w, h, p, _RND)
        mag = th[2] + th[3]
        pe = p if (mag > 0 or not th[1]) else p + 2 * (1 - mag) + 10
        ch, sh = _cos_sin(_shift(th, -1), pe, _RND)
        sn_e = _shift(_mul(sh, ch, pe, _RND), 1)
        tms = _sub(th, sn_e, p, _RND)                                   # theta - sin theta
        sn = _pos(sn_e, p, _RND)
        omc = _shift(_mul(sh, sh, p, _RND), 1)                          # 1 - cos theta
        dv = _sub(_mul(C0, sn, p, _RND), _mul(S0, omc, p, _RND), p, _RND)
        v = _sub(_add(v0, _mul(Fw, dv, p, _RND), p, _RND), _mul(sf, h, p, _RND), p, _RND)
        dx = _sub(_mul(C0, omc, p, _RND), _mul(S0, tms, p, _RND), p, _RND)
        x = _add(_add(x0, _mul(v0, h, p, _RND), p, _RND), _mul(Fw2, dx, p, _RND), p, _RND)
        x = _sub(x, _shift(_mul(sf, _mul(h, h, p, _RND), p, _RND), -1), p, _RND)
        cos_wt = _sub(_sub(C0, _mul(C0, omc, p, _RND), p, _RND), _mul(S0, sn, p, _RND), p, _RND)
        a = _sub(_mul(F, cos_wt, p, _RND), sf, p, _RND)
        return _make(x), _make(v), _make(a)

    def jerk(self, t, x, v, a):
        """``a' = -F w sin(w t)``."""
        if t == self.t_start:
            return -self.F * self.w * self.S0
        return -self.F * self.w * mpmath.sin(self.w * t)


def _guarded(z, leading_cancels):
    """``leading_cancels(z)``, a difference whose leading terms cancel to ``O(z^2)``: for small
    ``z`` it loses ``log2(1/z^2)`` bits, which as many guard bits (plus 10) restore."""
    if z == 0:
        return mpf(0)
    mag = mpmath.mag(z)
    with mpmath.extraprec(10 if mag > 0 else 2 * (1 - mag) + 10):
        value = leading_cancels(z)
    return +value


def _exp_defect(z):
    """``exp(-z) - 1 + z`` without cancellation."""
    return _guarded(z, lambda u: mpmath.expm1(-u) + u)


def _theta_minus_sin(theta):
    """``theta - sin theta`` without cancellation."""
    return _guarded(theta, lambda u: u - mpmath.sin(u))


class DampedFlight(_ConstantBounds):
    """Closed-form flight of ``x'' + c x' = F cos(w t) - s f`` (``c > 0``, no wavenumber).

    With ``phi1 = (1 - E)/c``, ``E = exp(-c h)``, ``theta = w h``, ``P = F c/(c^2 + w^2)``,
    ``Q = F w/(c^2 + w^2)``, ``C0, S0 = cos, sin(w t0)``,
    ``sigma = (exp(-c h) - 1 + c h)/c - (theta - sin theta)/w`` (``= sin(theta)/w - phi1``):

        x = x0 + v0 phi1 + P (C0 sigma - S0 (1 - cos theta)/w)
                         + Q (C0 (1 - cos theta)/w + S0 sigma) - s f (exp(-ch) - 1 + ch)/c^2
        v = v0 E + P (C0 (c phi1 - (1 - cos theta)) - S0 sin theta)
                 + Q (S0 (c phi1 - (1 - cos theta)) + C0 sin theta) - s f phi1

    (the module docstring's particular solution, regrouped so that every bracket is
    of its true size: no cancellation for short flights).  Bounds: ``|v| <= V =
    max(|v0|, F/c)`` along the flight (``d|v|/dt <= F - c |v|``), ``|x''| <= F + f + c V``,
    ``|v''| <= F w + c |x''|max``, ``|a''| <= F w^2 + c |v''|max``.
    """

    __slots__ = ("t_start", "x_start", "v_start", "s", "w", "F", "c", "sf", "C0", "S0",
                 "P", "Q", "Mx", "Mv", "Ma", "noise_x", "noise_v", "noise_a", "max_window")

    def __init__(self, model, t0, x0, v0, s):
        self.t_start, self.x_start, self.v_start, self.s = t0, x0, v0, s
        F, f, w, c = model.F, model.f, model.w, model.c
        self.w, self.F, self.c = w, F, c
        self.sf = f if s > 0 else (-f if s < 0 else mpf(0))
        self.C0, self.S0 = mpmath.cos_sin(w * t0)
        self.P, self.Q = F * c / (c * c + w * w), F * w / (c * c + w * w)
        V = max(abs(v0), F / c)
        self.Mx = F + f + c * V
        self.Mv = F * w + c * self.Mx
        self.Ma = F * w * w + c * self.Mv
        self.max_window = None
        eps = model.eps
        self.noise_x = eps * (model.x_scale + abs(x0) + V * model.T)
        self.noise_v = eps * (model.v_scale + V)
        self.noise_a = eps * (model.a_scale + c * V)

    def evaluate(self, t):
        """``(x, v, a)`` at ``t``."""
        h = t - self.t_start
        c, w, P, Q, C0, S0, sf = self.c, self.w, self.P, self.Q, self.C0, self.S0, self.sf
        theta = w * h
        ch, sh = mpmath.cos_sin(theta / 2)
        sn, omc = 2 * sh * ch, 2 * sh * sh
        E = mpmath.exp(-c * h)
        phi1 = -mpmath.expm1(-c * h) / c
        defect = _exp_defect(c * h)
        sigma = defect / c - _theta_minus_sin(theta) / w
        x = (self.x_start + self.v_start * phi1 + P * (C0 * sigma - S0 * omc / w)
             + Q * (C0 * omc / w + S0 * sigma) - sf * defect / (c * c))
        cphi = c * phi1 - omc
        v = self.v_start * E + P * (C0 * cphi - S0 * sn) + Q * (S0 * cphi + C0 * sn) - sf * phi1
        cos_wt = C0 - C0 * omc - S0 * sn
        a = self.F * cos_wt - sf - c * v
        return x, v, a

    def jerk(self, t, x, v, a):
        """``a' = -F w sin(w t) - c a``."""
        return -self.F * self.w * mpmath.sin(self.w * t) - self.c * a
