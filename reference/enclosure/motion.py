"""The motions between events in ball arithmetic, and the event functions on them.

A motion gives a *stack* of derivatives at a local parameter ``u`` (a ball: a point or a
whole interval), and an event function is a fixed linear form of the stack, so that one
certification code (``reference.enclosure.certify``) serves every motion:

* a **flight** from ``(t0, x0, v0)`` with velocity sign ``s``, ``u = h = t - t0``; the stack
  is ``[x, v, a, a', a'']`` (``a = x''``), from the closed forms of ``reference.flows``
  (base flight and damped flight, re-evaluated here on balls; for an interval ``h`` every
  term is a ball over the whole interval and the start's own uncertainty):

      x = x0 + v0 h + (F/w^2)(C0 (1 - cos theta) - S0 (theta - sin theta)) - s f h^2/2
      v = v0 + (F/w)(C0 sin theta - S0 (1 - cos theta)) - s f h,    theta = w h,
      a = F cos(w t) - s f - c v,  a' = -F w sin(w t) - c a,  a'' = -F w^2 cos(w t) - c a';

* a **rest** (sticking at ``x``, or wall contact), ``u = t`` (absolute time: the end of a
  rest does not depend on when it began), stack ``[A, A', A'', A''']`` (under position
  forcing ``A = F cos(k x) cos(w t)`` at the rest's ``x``);
* a flight under position forcing has no closed form: the validated flight of
  ``reference.enclosure.lohner`` gives the same stack from its Taylor steps.

Event functions ``g = const + coef * stack[offset]`` (so ``g^(k) = coef * stack[offset + k]``
for ``k >= 1``), each positive while the motion lasts:

* ``distance(side)``: ``side (wall - x)``, the distance to the wall ``side``;
* ``velocity(s)``: ``s v`` (a turn or a stop when it reaches 0);
* ``slip(sigma)``: ``f - sigma A`` (sticking ends upward, sigma = +1, or downward);
* ``release(side)``: ``f + side A`` (contact at wall ``side`` ends when the force pulls away).

``order`` is the number of derivatives of ``g`` that vanish *exactly* at ``u = 0`` on the true
motion (a structural fact: ``x = wall`` after an impact, ``v = 0`` after a turn, ``a = 0`` at
a slip, where the force equals friction); ``reference.enclosure.certify`` uses it to prove
``g > 0`` just after the start from the sign of ``g^(order)`` alone.
"""
from __future__ import annotations

from dataclasses import dataclass

from flint import arb


@dataclass(frozen=True)
class EventFunction:
    """``g(u) = const + coef * stack[offset]`` with ``order`` exact zeros at the start."""

    name: str
    offset: int
    coef: int
    const: object
    order: int = 0

    def derivative(self, stack, k: int):
        """``g^(k)`` from a stack (``k = 0``: the value)."""
        value = self.coef * stack[self.offset + k]
        return self.const + value if k == 0 else value


def wall_name(side: int) -> str:
    """The name of the distance function of the wall ``side`` (+1 r, -1 l)."""
    return "wall r" if side > 0 else "wall l"


def distance(model, side: int, order: int = 0) -> EventFunction:
    """``side (wall - x)``: zero when the particle reaches the wall ``side``."""
    return EventFunction(wall_name(side), 0, -side, side * model.wall(side), order)


def velocity(s: int, order: int = 0) -> EventFunction:
    """``s v``: zero at a turning point or a stop."""
    return EventFunction("velocity", 1, s, 0, order)


def slip(model, sigma: int) -> EventFunction:
    """``f - sigma A``: sticking ends when ``sigma A`` exceeds friction."""
    return EventFunction("slip up" if sigma > 0 else "slip down", 0, -sigma, model.f)


def release(model, side: int) -> EventFunction:
    """``f + side A``: contact at wall ``side`` ends when ``-side A`` exceeds friction."""
    return EventFunction("release", 0, side, model.f)


class Flight:
    """Closed-form flight (base or damped) from the balls ``t0, x0, v0``, sign ``s``."""

    def __init__(self, model, t0, x0, v0, s: int):
        self.m, self.t0, self.x0, self.v0, self.s = model, t0, x0, v0, s
        self.sf = model.f * s if s else arb(0)
        self.S0, self.C0 = (model.w * t0).sin_cos()
        if model.damping:
            c, w, F = model.c, model.w, model.F
            self.P, self.Q = F * c / (c * c + w * w), F * w / (c * c + w * w)

    def stack(self, h):
        """``[x, v, a, a', a'']`` at ``h`` (a ball)."""
        m = self.m
        w, F = m.w, m.F
        theta = w * h
        sn, cs = theta.sin_cos()
        omc = 1 - cs
        x, v = self._xv(h, theta, sn, omc)
        cos_wt = self.C0 * cs - self.S0 * sn
        sin_wt = self.S0 * cs + self.C0 * sn
        c = m.c
        a = F * cos_wt - self.sf - c * v
        a1 = -F * w * sin_wt - c * a
        a2 = -F * w * w * cos_wt - c * a1
        return [x, v, a, a1, a2]

    def _xv(self, h, theta, sn, omc):
        m, C0, S0, sf = self.m, self.C0, self.S0, self.sf
        if not m.damping:
            Fw = m.F / m.w
            v = self.v0 + Fw * (C0 * sn - S0 * omc) - sf * h
            x = self.x0 + self.v0 * h + (Fw / m.w) * (C0 * omc - S0 * (theta - sn)) - sf * h * h / 2
            return x, v
        c, w, P, Q = m.c, m.w, self.P, self.Q
        E = (-c * h).exp()
        phi1 = -(-c * h).expm1() / c
        defect = (-c * h).expm1() + c * h               # exp(-ch) - 1 + ch
        sigma = defect / c - (theta - sn) / w
        x = (self.x0 + self.v0 * phi1 + P * (C0 * sigma - S0 * omc / w)
             + Q * (C0 * omc / w + S0 * sigma) - sf * defect / (c * c))
        cphi = c * phi1 - omc
        v = self.v0 * E + P * (C0 * cphi - S0 * sn) + Q * (S0 * cphi + C0 * sn) - sf * phi1
        return x, v


class Rest:
    """Sticking at ``x`` or contact at a wall: nothing moves; the stack is the force's."""

    def __init__(self, model, x):
        self.m, self.x = model, x

    def stack(self, t):
        """``[A, A', A'', A''']`` at absolute time ``t`` (a ball); under position forcing the
        amplitude is ``F cos(k x)`` at the rest's ``x`` (a ball: every start of the box)."""
        m = self.m
        sn, cs = (m.w * t).sin_cos()
        F, w = m.amplitude(self.x), m.w
        return [F * cs, -F * w * sn, -F * w * w * cs, F * w * w * w * sn]
