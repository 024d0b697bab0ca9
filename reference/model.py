"""The scene at the working precision: parameters, scales, noise floors, flight factory.

A :class:`Model` is built inside the caller's ``workdps`` context; every mpf it holds is
at that precision.  The event set and the flight class are chosen from
``scene.effects`` (effects as data): a frictionless scene gets no velocity events and no
stick/turn handling; damping selects the damped flight; position-dependent forcing the
Taylor flight of ``reference.taylor``.
"""
from __future__ import annotations

import math
from functools import lru_cache

import mpmath
from mpmath.libmp import dps_to_prec

from reference import events, flows

#: Guard digits added to the caller's ``dps`` inside every public call.
GUARD_DIGITS = 12
#: Bits by which the working precision must resolve the scene's own scales (the gap against
#: the position scale, the forcing's velocity ``F/w`` against the velocity scale, a period
#: against the time span of a call) above the noise floor ``eps = 2^(-prec + NOISE_BITS)``:
#: below that the noise floors, which decide "at the wall" and "at rest", swallow the motion
#: (measured: l = 1e30, r = l + 1 at dps = 15 returned the wall, silently; w = 1e20 at dps =
#: 15 stalled in stick/slip: with friction, turns and stops are velocity zeros, decided against
#: the velocity noise).
RESOLVED_BITS = 20
#: Scale ratios up to ``10^FREE_DIGITS`` are absorbed by the guard digits; beyond, the public
#: calls add ``log10(ratio) - FREE_DIGITS`` working digits (``extra_digits``), so that the
#: caller's ``dps`` digits stay right.  Measured on l = 1e30, r = l + 1: with the gap resolved
#: only by ``RESOLVED_BITS``, v came out right to 5 digits at dps = 27; with the extra digits,
#: to every digit asked for.  The paper's scenes have ratios below 30: no extra digit.
FREE_DIGITS = 3
#: The most digits ``extra_digits`` adds: an event's cost grows like digits^1.7
#: (``reference.api.MAX_DPS``), so 200 more digits make a 50-digit call's events about 12
#: times dearer; a scene that needs more (``F = 1e300, omega = 1e-300``: 900) is refused by
#: name, as it would spend minutes on the event budget of one call.
MAX_EXTRA_DIGITS = 200
#: The largest ``damping/omega`` the reference takes: a damped flight's certified event search
#: steps through the fast relaxation (time ``1/c``) and its bounds grow with ``c``; measured
#: at F = w = 1, f = 0.1, dps = 15 (one period): c = 100 takes 3 s, c = 250 about 18 s, and
#: from c = 500 the search exceeds its budget of safe steps (a RuntimeError after ~15 s).
MAX_DAMPING_RATIO = 128


def scales(F, f, w, l, r, gap):
    """``(x_scale, v_scale)``: the magnitudes against which absolute noise is measured, the
    position scale ``max(|l|, |r|, r - l, F/w^2)`` and the velocity scale
    ``F/w + (r - l) w + f T`` (``T = 2 pi / w``; ``gap = r - l``)."""
    return max(abs(l), abs(r), gap, F / w ** 2), F / w + gap * w + f * (2 * mpmath.pi / w)


def scale_ratios(scene):
    """``[(ratio, what)]``: the scene's scales (:func:`scales`) over the quantities the noise
    floors must resolve (at the current precision): the position scale over the gap and,
    where a resting particle moves with friction (``F > f > 0``), the velocity scale over the
    forcing's velocity ``F/w``."""
    F, f, w = scene.mpf("F"), scene.mpf("f"), scene.mpf("omega")
    l, r, gap = scene.mpf("l"), scene.mpf("r"), scene.gap()
    x_scale, v_scale = scales(F, f, w, l, r, gap)
    out = [(x_scale / gap,
            "the gap r - l (from l, r) against the position scale max(|l|, |r|, F/omega^2)")]
    if F > f > 0:
        out.append((v_scale / (F / w),
                    "the forcing's velocity F/omega (from F, omega) against the velocity scale "
                    "F/omega + (r - l) omega + f T"))
    return out


@lru_cache(maxsize=256)
def _scene_ratio(scene):
    with mpmath.workdps(30):
        return max(scale_ratios(scene), key=lambda item: item[0])


def extra_digits(scene, span_ratio=1):
    """``(digits, what)``: the working digits a call adds to ``dps + GUARD_DIGITS`` so that
    the largest of ``scale_ratios`` and of ``span_ratio`` (a call's time span over ``T``)
    costs none of the caller's digits (``FREE_DIGITS``); ``what`` names that quantity."""
    ratio, what = _scene_ratio(scene)
    if span_ratio > ratio:
        ratio, what = span_ratio, "the period T (from omega) against the time span of the call"
    with mpmath.workdps(30):
        digits = math.ceil(float(mpmath.log10(ratio))) - FREE_DIGITS
    return max(0, digits), what


def needed_dps(ratio) -> int:
    """The least ``dps`` (at least 15) whose working precision, ``dps + GUARD_DIGITS`` digits,
    resolves a quantity ``ratio`` times below the noise floor's scale by ``RESOLVED_BITS``."""
    bits = float(mpmath.log(ratio, 2)) + RESOLVED_BITS + flows.NOISE_BITS
    dps = max(15, math.floor(bits / math.log2(10)) - GUARD_DIGITS - 2)
    while dps_to_prec(dps + GUARD_DIGITS) < bits:
        dps += 1
    return dps


def check_resolution(eps, ratio, what: str) -> None:
    """``ValueError`` unless ``eps * ratio <= 2^-RESOLVED_BITS``: a quantity ``ratio`` times
    below its noise floor's scale stands out of the noise (the public calls add the digits
    for it, ``extra_digits``; this guards any other caller)."""
    if eps * ratio > mpmath.ldexp(1, -RESOLVED_BITS):
        raise ValueError(
            f"reference: {what}: a ratio of {mpmath.nstr(ratio, 3)}, which the working precision "
            f"of {mpmath.mp.dps} digits cannot resolve; needs dps >= {needed_dps(ratio)} "
            f"(+{GUARD_DIGITS} guard digits)")


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
        self.x_scale, self.v_scale = scales(self.F, self.f, self.w, self.l, self.r, gap)
        self.a_scale = self.F + self.f + gap * self.w ** 2
        if self.c > MAX_DAMPING_RATIO * self.w:
            raise ValueError(
                f"reference: damping/omega = {mpmath.nstr(self.c / self.w, 3)} (from damping = "
                f"{scene.damping!r:.60}, omega = {scene.omega!r:.60}) is above "
                f"reference.model.MAX_DAMPING_RATIO = {MAX_DAMPING_RATIO}: the certified event "
                f"search of a damped flight steps through relaxations of time 1/damping and "
                f"exceeds its budget of safe steps")
        for ratio, what in scale_ratios(scene):
            check_resolution(self.eps, ratio, what)
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

    def check_span(self, t0, t_end) -> None:
        """``ValueError`` unless the period ``T`` stands out of the noise of times of size
        ``max(|t0|, |t_end|)`` (a call's time span) by ``RESOLVED_BITS``."""
        check_resolution(self.eps, max(abs(t0), abs(t_end), self.T) / self.T,
                         "the period T (from omega) against the time span of the call")

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
