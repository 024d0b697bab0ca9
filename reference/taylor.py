"""Flights under position-dependent forcing by a certified Taylor-series integrator.

The model (paper, eq. ``xpot``, with the issue 6 effects)::

    x'' = A(x, t) - s f - c x',     A(x, t) = F cos(k x) cos(w t),

in flight with a fixed friction sign ``s`` (``+1`` or ``-1``; ``k = 0`` stands for a
scene without position forcing, ``cos(0 x) = 1``). No closed form exists, so a flight
is a chain of Taylor steps at the working mpmath precision, with a dense output (the
step polynomial) valid for every ``t`` in the step and a *proved* truncation bound.

The steps -- their Taylor coefficients, the proved truncation bound, the order -- are
``reference.taylor_series``'s; their names are this module's too.

A flight is used by ``reference.model.Model`` (``make_flight``) for every scene with
``position_forcing``: ``reference.events`` locates its events with the bounds below, its
far-from-root safe steps in float64 (``evaluate_float``: ``reference.taylor_float``).

Event bounds over a window ``[ta, tb]`` (for certified event location): in flight
``d|v|/dt = sgn(v) (A - s f - c v) <= F + f - c |v|`` (``|A - s f| <= F + f``; damping only
slows), so ``|v| <= vmax = min(|v(ta)| + (F+f)(tb-ta), max(|v(ta)|, (F+f)/c))`` (the second
term for ``c > 0``: the comparison solution ``(F+f)/c + (|v(ta)| - (F+f)/c) e^{-c (tb-ta)}``
lies between ``|v(ta)|`` and ``(F+f)/c``).  Issue 33: the bound used to be
``d|v|/dt <= F + f + c |v|``, whose ``e^{c (tb-ta)}`` over a ten-period window (``c = 0.163``,
``10 T = 69``: ``vmax ~ 1e6``) shrank the safe steps until the event search gave up on an unseen
damped scene.  ``|x''| <= F + f + c vmax =: amax`` and
``|v''| = |A_t + A_x v - c a| <= F w + F k vmax + c amax``.
"""
from __future__ import annotations

import bisect

import mpmath

from reference import taylor_float
from reference.taylor_series import (EXTRA_BITS, GUARD_BITS, _fix, _fixed_horner, _main_fixed, _params,
                                     _variational_fixed, choose_step, series, step_certificate, taylor_order)

#: the steps' names that the suite reads here (``reference.taylor_series``'s)
__all__ = ["EXTRA_BITS", "GUARD_BITS", "series", "step_certificate", "taylor_order", "TaylorFlight",
           "make_flight", "equilibrium_intervals", "flight_matrix", "MAX_STEPS", "BOUND_WINDOWS"]

#: bound on the number of Taylor steps of one flight
MAX_STEPS = 200_000

#: windows a period of the event search's bounds is cut into (``max_window = T / BOUND_WINDOWS``).
#: ``_bounds`` grows ``vmax`` by ``(F + f)`` per unit of the window: over the rest of a flight
#: of ten periods (a scorecard's truths, issue 33) it bounded ``|v''|`` ~100x above its local
#: value, and the safe steps fell to ~1/10 of what a window of ``T / 8`` allows (scene D: 2,300
#: mpf steps where 83 Taylor steps carry the flight).
BOUND_WINDOWS = 8


class TaylorFlight:
    """One flight with friction sign ``s`` from ``(t0, x0, v0)`` by certified Taylor steps.

    Implements the flight interface of ``reference.flows`` (``t_start``, ``x_start``,
    ``v_start``, ``s``, ``evaluate``, ``jerk``, ``bound_x2``, ``bound_v2``, ``bound_a2``,
    ``max_window``, ``noise_x``, ``noise_v``, ``noise_a``) plus ``state``,
    ``acceleration`` and ``jacobian`` (the flight matrix, from the variational
    equations, computed lazily per step).  Steps are taken lazily and kept.  Results
    are at the caller's working precision; inside, the working precision at
    construction plus ``GUARD_BITS``.  ``s = 0`` is allowed when ``f = 0``.
    """

    def __init__(self, scene, t0, x0, v0, s, *, order=None, noise=None):
        if s not in (1, -1, 0):
            raise ValueError(f"s must be +1, -1 (or 0 without friction), got {s!r}")
        for name, val in (("t0", t0), ("x0", x0), ("v0", v0)):
            if not mpmath.isfinite(mpmath.mpf(val)):
                raise ValueError(f"{name} must be finite, got {val!r}")
        self.scene, self.s = scene, s
        self.prec = mpmath.mp.prec
        self.iprec = self.prec + GUARD_BITS
        self.order = taylor_order(self.prec) if order is None else int(order)
        if self.order < 2:
            raise ValueError(f"order must be >= 2, got {order!r}")
        with mpmath.workprec(self.iprec):
            self.prm = _params(scene)
            if s == 0 and self.prm[1] != 0:
                raise ValueError("s = 0 needs a frictionless scene (f = 0)")
            self._fl = tuple(float(p) for p in self.prm)
            t0, x0, v0 = mpmath.mpf(t0), mpmath.mpf(x0), mpmath.mpf(v0)
        self.t_start, self.x_start, self.v_start = +t0, +x0, +v0
        self.max_window = +(2 * mpmath.pi / self.prm[4] / BOUND_WINDOWS)
        eps = mpmath.ldexp(1, -self.prec + 12)
        self.noise_x, self.noise_v, self.noise_a = noise or (
            eps * (1 + abs(x0) + abs(v0)), eps * (1 + abs(v0)), eps * (1 + self.prm[0] + self.prm[1]))
        self._starts = [t0]
        self._state0 = [(x0, v0)]           # state at each step start
        self._steps = []                    # (h, X, V): the scaled ints of x and v h
        self._kept = []                     # the recurrence's (S~, P~) per step, for the columns
        self._bound_at = (None, None)       # (ta, v(ta)) of the last event bound
        self._last = (None, None, None)     # (t, x, v) of the last ``state``: see ``state``
        self._cols = []                     # variational polynomials per step (lazy)
        self._floats = []                   # float64 step polynomials (``evaluate_float``, lazy)
        self._fprm = self._fl + (float(s),) + (float(self.noise_x), float(self.noise_v))
        self._jac0 = [mpmath.eye(2)]        # flight matrix at each step start (lazy)

    # -- stepping ----------------------------------------------------------------------
    def _take_step(self):
        i = len(self._steps)
        if i >= MAX_STEPS:
            raise RuntimeError(f"taylor: more than {MAX_STEPS} steps (t={self._starts[-1]}, "
                               f"x, v={self._state0[-1]}, mode=flight s={self.s})")
        with mpmath.workprec(self.iprec):
            self._last = (None, None, None)     # a new step: a state at its start may read otherwise
            t, (x, v) = self._starts[i], self._state0[i]
            h = mpmath.mpf(choose_step(self._fl, abs(float(v)), self.order,
                                       self.prec + EXTRA_BITS, True))
            X, S, Pn = _main_fixed(self.prm, t, x, v, self.s, self.order, h, self.iprec)
            V = [(n + 1) * X[n + 1] for n in range(len(X) - 1)]      # the scaled series of v h
            self._steps.append((h, X, V))
            self._kept.append((S, Pn))
            self._starts.append(t + h)
            self._state0.append(self._pair(X, V, h, 1 << self.iprec))

    def _pair(self, Z, W, h, sig):
        """``(z, w / h)`` at ``sigma`` (``sig = sigma 2^P``) from the scaled ints ``Z``, ``W``
        (``_fixed_horner``), as mpf at the internal precision."""
        P = self.iprec
        z = mpmath.ldexp(mpmath.mpf(_fixed_horner(Z, sig, P)), -P)
        w = mpmath.ldexp(mpmath.mpf(_fixed_horner(W, sig, P)), -P)
        return z, w / h

    def _sigma(self, tau, h):
        """``tau / h`` in ``P``-bit fixed point."""
        return _fix(tau / h, self.iprec)

    def _variational_upto(self, i):
        with mpmath.workprec(self.iprec):
            while len(self._cols) <= i:
                j = len(self._cols)
                h = self._steps[j][0]
                cols = _variational_fixed(self.prm, *self._kept[j], self.order, h, self.iprec)
                self._cols.append(cols)
                self._jac0.append(self._step_matrix(cols, h, 1 << self.iprec) * self._jac0[j])

    def _step_matrix(self, cols, h, sig):
        dx1, dv1 = self._pair(cols[0], cols[1], h, sig)
        dx2, dv2 = self._pair(cols[2], cols[3], h, sig)
        return mpmath.matrix([[dx1, dx2], [dv1, dv2]])

    def _locate(self, t):
        """Index of the step containing ``t`` and ``tau = t - start`` (internal precision)."""
        with mpmath.workprec(self.iprec):
            t = mpmath.mpf(t)
            if not mpmath.isfinite(t) or t < self._starts[0]:
                raise ValueError(f"t must be finite and >= t0 = {self._starts[0]}, got {t}")
            while self._starts[-1] < t:
                self._take_step()
            i = max(0, bisect.bisect_left(self._starts, t) - 1)
            return i, t - self._starts[i]

    # -- the flight interface ----------------------------------------------------------
    def state(self, t):
        """``(x(t), v(t))`` at the working precision.

        The last ``(t, x, v)`` is kept (until the next Taylor step): the event search asks the
        state at each probe twice -- ``evaluate`` and the event bound's ``v(ta)`` (``_bounds``)
        at the same ``t`` -- and the two Horner evaluations were half of its cost (issue 33:
        two ten-period maps at 40 digits of an unseen position-forced scene, 10.8 -> 8.5 CPU s; the
        same values, bit for bit: a kept state is one this very computation gave, and a new
        step clears it)."""
        with mpmath.workprec(self.iprec):
            key = mpmath.mpf(t)._mpf_
        if self._last[0] == key:
            x, v = self._last[1], self._last[2]
        else:
            i, tau = self._locate(t)
            with mpmath.workprec(self.iprec):
                if i < len(self._steps):
                    h, X, V = self._steps[i]
                    x, v = self._pair(X, V, h, self._sigma(tau, h))
                else:
                    x, v = self._state0[i]
            self._last = (key, x, v)
        return +x, +v

    def _accel(self, x, v, t):
        F, f, c, k, w = self.prm
        return F * mpmath.cos(k * x) * mpmath.cos(w * t) - self.s * f - c * v

    def acceleration(self, t):
        """``a = F cos(k x) cos(w t) - s f - c v`` at ``(x(t), v(t))``."""
        x, v = self.state(t)
        with mpmath.workprec(self.iprec):
            a = self._accel(x, v, mpmath.mpf(t))
        return +a

    def evaluate(self, t):
        """``(x, v, a)`` at ``t`` (the ``reference.flows`` interface)."""
        x, v = self.state(t)
        with mpmath.workprec(self.iprec):
            a = self._accel(x, v, mpmath.mpf(t))
        return x, v, +a

    def evaluate_float(self, h):
        """float64 ``(x, v, a, a', ex, ev, ea, ea')`` at ``t_start + h`` (``h`` a float, taken
        exactly) with rigorous absolute error bounds (``reference.taylor_float``): the event
        search's far-from-root safe steps (``reference.flows``' optional accelerator; issue 33:
        the two ten-period maps of ``state``'s note, 8.5 -> 6.6 CPU s, the same events)."""
        with mpmath.workprec(self.iprec):
            t = self.t_start + mpmath.mpf(h)
        i, tau = self._locate(t)
        if i >= len(self._steps):               # t = t_start before any step
            self._take_step()
            i, tau = self._locate(t)
        while len(self._floats) <= i:
            h, X, V = self._steps[len(self._floats)]
            self._floats.append(taylor_float.step_floats(X, V, self.iprec, h))
        F, f, c, k, w, s, nx, nv = self._fprm
        with mpmath.workprec(self.iprec):
            sigma = tau / self._steps[i][0]
        return taylor_float.evaluate((F, f, c, k, w), s, (nx, nv), self._floats[i], sigma, t)

    def jerk(self, t, x, v, a):
        """``a' = A_t + A_x v - c a = -F w cos(kx) sin(wt) - F k sin(kx) cos(wt) v - c a``."""
        with mpmath.workprec(self.iprec):
            F, f, c, k, w = self.prm
            cx, sx = mpmath.cos_sin(k * x)
            ct, st = mpmath.cos_sin(w * t)
            da = -F * w * cx * st - F * k * sx * ct * v - c * a
        return +da

    def jacobian(self, t):
        """The flight matrix ``d(x(t), v(t)) / d(x0, v0)`` (variational equations)."""
        i, tau = self._locate(t)
        if i < len(self._steps):
            self._variational_upto(i)
        with mpmath.workprec(self.iprec):
            if i < len(self._steps):
                h = self._steps[i][0]
                m = self._step_matrix(self._cols[i], h, self._sigma(tau, h)) * self._jac0[i]
            else:
                m = self._jac0[i]
        return mpmath.matrix([[+m[0, 0], +m[0, 1]], [+m[1, 0], +m[1, 1]]])

    def _bounds(self, ta, tb):
        """``(vmax, amax, a1max)`` over ``[ta, tb]`` (module docstring)."""
        if not tb >= ta:
            raise ValueError(f"need tb >= ta, got ta={ta}, tb={tb}")
        if self._bound_at[0] is None or self._bound_at[0] != ta:    # bound_x2 and bound_v2 ask at one ta
            self._bound_at = (ta, self.state(ta)[1])
        va = self._bound_at[1]
        F, f, c, k, w = self.prm
        dt = mpmath.mpf(tb) - mpmath.mpf(ta)
        vmax = abs(va) + (F + f) * dt
        if c > 0:                  # damping only slows: |v| never climbs above (F + f) / c
            vmax = min(vmax, max(abs(va), (F + f) / c))
        amax = F + f + c * vmax
        return vmax, amax, F * w + F * k * vmax + c * amax

    def _up(self, value):
        return +(value * (1 + mpmath.ldexp(1, -self.prec + 4)))

    def bound_x2(self, ta, tb):
        """``|x''| <= F + f + c vmax`` over ``[ta, tb]``."""
        with mpmath.workprec(self.iprec):
            return self._up(self._bounds(ta, tb)[1])

    def bound_v2(self, ta, tb):
        """``|v''| = |A_t + A_x v - c a| <= F w + F k vmax + c amax`` over ``[ta, tb]``."""
        with mpmath.workprec(self.iprec):
            return self._up(self._bounds(ta, tb)[2])

    def bound_a2(self, ta, tb):
        """``|a''| = |A_tt + 2 A_xt v + A_xx v^2 + A_x a - c a'|`` over ``[ta, tb]``:
        ``<= F w^2 + 2 F k w vmax + F k^2 vmax^2 + F k amax + c a1max``."""
        with mpmath.workprec(self.iprec):
            F, f, c, k, w = self.prm
            vmax, amax, a1max = self._bounds(ta, tb)
            return self._up(F * w * w + 2 * F * k * w * vmax + F * k * k * vmax * vmax
                            + F * k * amax + c * a1max)

    def steps_taken(self):
        """Number of Taylor steps computed so far."""
        return len(self._steps)


def make_flight(model, t0, x0, v0, s):
    """The flight factory ``reference.model.Model`` calls for position-dependent forcing.

    Noise floors as ``reference.flows.BaseFlight``: ``eps (x_scale + |x0| + |v0| T)``,
    ``eps (v_scale + |v0|)``, ``eps a_scale`` with the model's ``eps`` and scales.
    """
    eps = model.eps
    noise = (eps * (model.x_scale + abs(x0) + abs(v0) * model.T),
             eps * (model.v_scale + abs(v0)), eps * model.a_scale)
    return TaylorFlight(model.scene, t0, x0, v0, s, noise=noise)


def equilibrium_intervals(scene):
    """The rest points of the scene: ``x`` in ``[l, r]`` with ``|F cos(k x)| <= f``.

    A particle at rest at ``x`` (interior: sticking; at a wall: wall contact, which holds
    while ``A >= -f`` at ``r`` / ``A <= f`` at ``l``) stays for all time iff
    ``|F cos(k x) cos(w t)| <= f`` for every ``t``, i.e. ``|F cos(k x)| <= f`` since
    ``cos(w t)`` takes every value in ``[-1, 1]``.  With ``alpha = arccos(f/F)``
    (``f < F``), ``|cos(k x)| <= f/F`` iff ``k x mod pi`` lies in ``[alpha, pi - alpha]``,
    so the set is the union over integers ``m`` of ``[(alpha + m pi)/k, (pi - alpha + m pi)/k]``
    cut to ``[l, r]``.  Without position forcing it is ``[l, r]`` if ``F <= f`` else empty.
    (For eq. ``xpot``, ``k = pi/2`` on ``[-1, 1]``: ``[-1, -eta'] U [eta', 1]`` with
    ``eta' = (2/pi) arccos(f/F)``, i.e. the wall layers have width ``(2/pi) arcsin(f/F)``.)
    Returns a list of ``(lo, hi)`` mpf pairs at the working precision, in increasing order.
    """
    F, f, _, k, _ = _params(scene)
    l, r = scene.mpf("l"), scene.mpf("r")
    if F <= f:
        return [(l, r)]
    if k == 0:
        return []
    alpha = mpmath.acos(f / F)
    m_lo = int(mpmath.floor(k * l / mpmath.pi)) - 1
    m_hi = int(mpmath.ceil(k * r / mpmath.pi)) + 1
    if m_hi - m_lo > 10**6:
        raise ValueError(f"wavenumber * (r - l) too large for an interval list: {k * (r - l)}")
    out = []
    for m in range(m_lo, m_hi + 1):
        lo = max(l, (alpha + m * mpmath.pi) / k)
        hi = min(r, (mpmath.pi - alpha + m * mpmath.pi) / k)
        if lo <= hi:
            out.append((lo, hi))
    return out


def flight_matrix(model, t0, x0, v0, t1):
    """The flight matrix over ``[t0, t1]`` of the flight starting at ``(t0, x0, v0)``.

    For ``reference.jacobian.product_of_table1`` under position forcing, where the flight
    matrix is no longer ``[[1, h], [0, 1]]`` but the solution of the variational equations
    (the impact, turn, stick and contact matrices of Table 1 are unchanged, with
    ``A = A(x*, t*)``: their saltation derivation only uses ``a+ + a- = 2 A`` at the event).
    The sign is ``sgn(v0)``, or ``sgn(A(x0, t0))`` for a flight from rest (after a turn,
    slip or release ``|A| >= f`` there), or 0 without friction.  Returns a 2x2 list.
    """
    if not model.friction:
        s = 0
    elif v0 != 0:
        s = 1 if v0 > 0 else -1
    else:
        s = 1 if model.force(x0, t0) > 0 else -1
    J = TaylorFlight(model.scene, t0, x0, v0, s).jacobian(t1)
    return [[J[0, 0], J[0, 1]], [J[1, 0], J[1, 1]]]
