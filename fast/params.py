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

import numpy as np

EPS = 2.0 ** -52

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
    #: largest |t - t_root| over which an accepted root's state is Taylor-extrapolated:
    #: the omitted term |A''| d^3 / 6 <= F w^2 d^3 / 6 stays below eps / 48
    d_acc: float
    #: viscous damping c (0: undamped) and the forced particular velocity
    #: ``v_p = Pd cos wt + Qd sin wt - s f / c``, ``Pd = F c/(c^2 + w^2)``, ``Qd = F w/(c^2 + w^2)``
    damp: float = 0.0
    Pd: float = 0.0
    Qd: float = 0.0

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
        T = 2.0 * math.pi / w
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
        )


def damped_bounds(P, av0):
    """Per-segment bounds ``(M1, M2, M2_3, d_acc)`` of a damped flight starting with speed
    ``|v0| = av0`` (module docstring); ``d_acc = 0.5 (eps / M2_3)^(1/3)`` as in the
    undamped case (the Taylor step of ``kernel._extrapolate`` omits ``<= M2_3 d^3 / 6``)."""
    c = P.damp
    M1 = np.maximum((P.F + P.f) + np.maximum(c * av0, P.F + P.f), 1e-300)
    M2 = P.F * P.w + c * M1
    M2_3 = P.F * P.w * P.w + c * M2
    return M1, M2, M2_3, 0.5 * np.cbrt(EPS / M2_3)
