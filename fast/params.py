"""Float64 constants of a scene, derived once per call (``Params.from_scene``).

Only the effects the scene switches on are supported here; an effect this engine does
not implement yet raises ``NotImplementedError`` naming it (never silently ignored):

* ``damping`` (c > 0): closed-form damped flights (``fast.flight.evaluate``);
* restitution ``e < 1`` is implemented (impact ``v -> -e v``, its Table 1 matrix, and
  chatter even without friction);
* ``position_forcing`` (k x in the forcing): needs the numerical flight of
  ``fast.ode`` behind the flight interface of ``fast.flight``.

Bounds used by the certified event search (``fast.roots``), for a flight with sign s:

* wall function  ``g1 = s (W_s - x)``:  ``|g1''| = |s A - f| <= F + f``,
  ``|g1'''| = |A'| <= F w``;
* velocity function ``g2 = s v``:  ``|g2''| = |A'| <= F w``, ``|g2'''| = |A''| <= F w^2``.

With damping ``c > 0`` (``x'' = A - s f - c v``) the bounds depend on the segment's start
speed (``damped_bounds``): ``|v(t)| <= V = max(|v0|, (F + f)/c)`` for every ``t >= t0``
of the closed-form flight (where ``|v| > (F + f)/c``, ``v'`` has the sign of ``-v``), so
``|x''| <= M1 = F + f + c V``, ``|x'''| = |A' - c x''| <= M2 = F w + c M1`` and
``|v'''| = |A'' - c x'''| <= M2_3 = F w^2 + c M2``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import mpmath
import numpy as np

from .flight import split

EPS = 2.0 ** -52
L = np.longdouble
#: long double is wider than float64 on this platform (``fast.precise``)
WIDE = np.finfo(L).nmant > np.finfo(np.float64).nmant

_UNSUPPORTED = {
    "position_forcing": "position-dependent forcing needs the numerical flight of fast.ode, "
                        "not available yet",
}


@dataclass(frozen=True)
class Params:
    F: float
    f: float
    w: float
    l: float
    r: float
    T: float
    friction: bool
    #: restitution coefficient; ``chatter``: impacts can accumulate (f > 0 or e < 1)
    e: float
    chatter: bool
    #: f / F (inf when F = 0): the sticking threshold on |cos(w t)|
    c: float
    #: arccos(c) and sin(arccos(c)) when c < 1 (sticking can end), else 0
    alpha: float
    sin_alpha: float
    #: |x''|, |x'''|, |v''|, |v'''| bounds (floored away from 0 to keep divisions finite)
    M1: float
    M1_3: float
    M2: float
    M2_3: float
    #: noise floors of the two event functions (absolute)
    noise1: float
    noise2: float
    #: largest |t - t_root| over which an accepted root's state is carried by the local
    #: model of ``fast.precise.at_event``:
    #: the omitted term |A''| d^3 / 6 <= F w^2 d^3 / 6 stays below eps / 48
    d_acc: float
    #: viscous damping c (0: undamped) and the forced particular velocity
    #: ``v_p = Pd cos wt + Qd sin wt - s f / c``, ``Pd = F c/(c^2 + w^2)``, ``Qd = F w/(c^2 + w^2)``
    damp: float = 0.0
    Pd: float = 0.0
    Qd: float = 0.0
    #: double-double parts: the scene's w = w + w_lo and period 2 pi / w = T + T_lo
    #: (``T`` correctly rounded); ``w_split`` is Dekker's split of ``w`` for the error-free
    #: product ``w t`` (``fast.flight.two_prod``)
    w_lo: float = 0.0
    T_lo: float = 0.0
    w_split: tuple = (0.0, 0.0)
    #: the phases where sticking or wall contact end, ``pi - alpha`` and ``2 pi - alpha``
    #: (``alpha = arccos(f/F)`` of the exact scene), as double-doubles (``fast.modes``)
    B1: tuple = (0.0, 0.0)
    B2: tuple = (0.0, 0.0)
    #: the flight parameters in long double (``fast.precise``)
    wide: "Wide" = None

    @classmethod
    def from_scene(cls, scene) -> "Params":
        if scene.has("position_forcing"):   # flow selection: numerical flights (fast.ode)
            from .ode import OdeParams
            return OdeParams.from_scene(scene)
        for effect, message in _UNSUPPORTED.items():
            if scene.has(effect):
                raise NotImplementedError(f"fast: effect {effect!r}: {message}")
        F, f, w = scene.float("F"), scene.float("f"), scene.float("omega")
        l, r = scene.float("l"), scene.float("r")
        cd = scene.float("damping") if scene.has("damping") else 0.0
        T, T_lo, w_lo = _double_double_times(scene)
        c = f / F if F > 0 else math.inf
        alpha = math.acos(c) if c < 1 else 0.0
        tiny = 1e-300
        scale_x = max(abs(l), abs(r)) + F / w ** 2 + f * T * T
        scale_v = F / w + f * T
        return cls(
            F=F, f=f, w=w, l=l, r=r, T=T, friction=f > 0, c=c, alpha=alpha,
            e=scene.float("restitution"), chatter=f > 0 or scene.float("restitution") < 1,
            sin_alpha=math.sin(alpha) if c < 1 else 0.0,
            M1=max(F + f, tiny), M1_3=max(F * w, tiny),
            M2=max(F * w, tiny), M2_3=max(F * w * w, tiny),
            noise1=16 * EPS * scale_x, noise2=16 * EPS * scale_v,
            d_acc=0.5 * (EPS / max(F * w * w, tiny)) ** (1.0 / 3.0),
            damp=cd, Pd=F * cd / (cd * cd + w * w), Qd=F * w / (cd * cd + w * w),
            w_lo=w_lo, T_lo=T_lo, w_split=split(w),
            wide=Wide.from_scene(scene), **_exit_phases(scene, c < 1),
        )


@dataclass(frozen=True)
class Wide:
    """The flight parameters in long double (``fast.flight.evaluate`` reads these)."""

    F: np.longdouble
    f: np.longdouble
    w: np.longdouble
    damp: np.longdouble
    Pd: np.longdouble
    Qd: np.longdouble

    @classmethod
    def from_scene(cls, scene) -> "Wide":
        """Parameter conversion: the scene's exact values at 40 digits, to long double."""
        with mpmath.workdps(40):
            F, f, w = scene.mpf("F"), scene.mpf("f"), scene.mpf("omega")
            c = scene.mpf("damping") if scene.has("damping") else mpmath.mpf(0)
            vals = dict(F=F, f=f, w=w, damp=c, Pd=F * c / (c * c + w * w), Qd=F * w / (c * c + w * w))
            return cls(**{key: L(mpmath.nstr(val, 30, strip_zeros=False)) for key, val in vals.items()})


def _double_double_times(scene):
    """``(T, T_lo, w_lo)``: the exact period ``2 pi / w`` and frequency of the scene as
    double-double pairs (hi correctly rounded, lo the rounding error rounded).

    Parameter conversion, not integration: the scene's exact value of ``w`` (a rational
    or a pi expression) is read once at 40 digits.  A float period ``T`` alone misses
    up to half an ulp of ``T`` (``2 pi`` has ``T_lo = 2.4e-16``), which moves the final
    state by ``|v| T_lo``: several ulp of ``x`` over each period."""
    with mpmath.workdps(40):
        w_ex = scene.mpf("omega")
        T_ex = 2 * mpmath.pi / w_ex
        T = float(T_ex)
        return T, float(T_ex - T), float(w_ex - float(w_ex))


def _exit_phases(scene, ends: bool) -> dict:
    """``B1 = pi - alpha``, ``B2 = 2 pi - alpha`` as double-double pairs from the exact
    ``f / F`` at 40 digits (parameter conversion): the time a sticking or contact
    interval ends is ``(B + 2 pi n) / w``, computed in double-double from these
    (``fast.events_proc._exit_time``) rather than as ``t + dphi / w``, whose rounding
    (half an ulp of ``t`` and of ``dphi``) shifts every later flight."""
    if not ends:
        return {}
    with mpmath.workdps(40):
        alpha = mpmath.acos(scene.mpf("f") / scene.mpf("F"))
        return {key: (float(b), float(b - float(b)))
                for key, b in (("B1", mpmath.pi - alpha), ("B2", 2 * mpmath.pi - alpha))}


#: 2 pi as a double-double: hi = float(2 pi), lo = float(2 pi - hi) (mpmath at 40 digits)
TWO_PI = (6.283185307179586, 2.4492935982947064e-16)


def damped_bounds(P, av0):
    """Per-segment bounds ``(M1, M2, M2_3, d_acc)`` of a damped flight starting with speed
    ``|v0| = av0`` (module docstring); ``d_acc = 0.5 (eps / M2_3)^(1/3)`` as in the
    undamped case (the local model of ``fast.precise.at_event`` omits ``<= M2_3 d^3 / 6``)."""
    c = P.damp
    M1 = np.maximum((P.F + P.f) + np.maximum(c * av0, P.F + P.f), 1e-300)
    M2 = P.F * P.w + c * M1
    M2_3 = P.F * P.w * P.w + c * M2
    return M1, M2, M2_3, 0.5 * np.cbrt(EPS / M2_3)
