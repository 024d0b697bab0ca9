"""The scene at the working precision: parameters, scales, noise floors, flight factory.

A :class:`Model` is built inside the caller's ``workdps`` context; every mpf it holds is
at that precision.  The event set and the flight class are chosen from
``scene.effects`` (effects as data): a frictionless scene gets no velocity events and no
stick/turn handling; damping selects the damped flight; position-dependent forcing the
Taylor flight of ``reference.taylor``.
"""
from __future__ import annotations

import mpmath

from reference import events, flows

#: Guard digits added to the caller's ``dps`` inside every public call.
GUARD_DIGITS = 12


class Model:
    """Scene parameters as mpf at the current precision, plus derived scales.

    ``eps = 2**(-prec + NOISE_BITS)`` is the relative noise floor; ``x_scale``,
    ``v_scale``, ``a_scale`` are the magnitudes against which absolute noise is measured:
    ``max(|l|, |r|, r - l, F/w^2)``, ``F/w + (r - l) w + f T`` and ``F + f``.
    """

    def __init__(self, scene):
        self.scene = scene
        mpf = scene.mpf
        self.F, self.f, self.w = mpf("F"), mpf("f"), mpf("omega")
        self.l, self.r = mpf("l"), mpf("r")
        self.e, self.c, self.k = mpf("restitution"), mpf("damping"), mpf("wavenumber")
        self.T = 2 * mpmath.pi / self.w
        self.friction = scene.has("friction")
        self.restitution = scene.has("restitution")
        self.damping = scene.has("damping")
        self.position_forcing = scene.has("position_forcing")
        self.eps = mpmath.ldexp(1, -mpmath.mp.prec + flows.NOISE_BITS)
        gap = self.r - self.l
        self.x_scale = max(abs(self.l), abs(self.r), gap, self.F / self.w ** 2)
        self.v_scale = self.F / self.w + gap * self.w + self.f * self.T
        self.a_scale = self.F + self.f + gap * self.w ** 2
        self.forcing = flows.CosineForcing(self.F, self.w, self.k)
        # constants of the base flight (shared by all flights of a run)
        self.Fw = self.F / self.w
        self.Fw2 = self.Fw / self.w
        self.Mx, self.Mv, self.Ma = self.F + self.f, self.F * self.w, self.F * self.w ** 2
        self.noise_a = self.eps * self.a_scale
        #: agreement of successive chatter estimates: the caller's digits, in units of T
        self.chatter_tol = mpmath.mpf(10) ** (GUARD_DIGITS - mpmath.mp.dps) * self.T
        #: accepted when the noise of tiny bounces stalls the agreement (half the digits)
        self.chatter_tol_loose = mpmath.mpf(10) ** ((GUARD_DIGITS - mpmath.mp.dps) // 2) * self.T
        self._flight_class = self._choose_flight()
        # the arithmetic of Table 1 (reference.jacobian): mpf here, arb in reference.enclosure
        self.one, self.zero = mpmath.mpf(1), mpmath.mpf(0)
        self.exp, self.expm1 = mpmath.exp, mpmath.expm1

    def _choose_flight(self):
        if self.position_forcing:
            try:
                from reference import taylor  # written by another helper
            except ImportError as exc:  # pragma: no cover - depends on the other helper
                raise NotImplementedError(
                    "position_forcing (wavenumber) needs reference.taylor") from exc
            return taylor.make_flight
        if self.damping:
            return flows.DampedFlight
        return flows.BaseFlight

    def flight(self, t0, x0, v0, s):
        """A flight from ``(t0, x0, v0)`` with velocity sign ``s`` (0 when frictionless)."""
        return self._flight_class(self, t0, x0, v0, s)

    def event_functions(self, s, x, v, from_rest):
        """The event set of a flight: walls (and the velocity zero with friction)."""
        if self.friction:
            return [events.WallHit(s, self.wall(s)), events.VelocityZero(s, from_rest)]
        at_rest = from_rest and v == 0
        return [events.WallHit(1, self.r, at_rest and x == self.r),
                events.WallHit(-1, self.l, at_rest and x == self.l)]

    def force(self, x, t):
        """``A(x, t)``."""
        return self.forcing.value(x, t)

    def wall(self, side):
        """The wall position for ``side`` = +1 (r) or -1 (l)."""
        return self.r if side > 0 else self.l
