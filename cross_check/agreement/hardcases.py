"""Hard cases constructed exactly, independently of both integrators.

Each hard case is a state ``(x0, v0)`` at ``t = 0`` whose trajectory hits a delicate event
at a chosen time ``t*`` (a grazing impact, a crossing pair, an impact at exactly ``t = T``,
a turning point exactly on the stick-slip boundary ``|F cos w t| = f``, a turning point at a
wall, a stick).  It is made by choosing the *left* state at ``t*`` (position, velocity just
before, flight sign ``s``) and running this module's own closed-form flight **backward** in
time to ``t = 0`` (base model, ``c = 0``, ``e = 1``, ``k = None``)::

    v(t) = v* + (F/w)(sin wt - sin wt*) - s f (t - t*)
    x(t) = x* + v* h + (F/w^2)(cos wt* - cos wt - w h sin wt*) - s f h^2/2,   h = t - t*.

Going backward, the segment with sign ``s`` ends (at its forward start) where ``x`` reaches
the wall behind (``l`` for ``s = +1``: forward, an impact there, ``v -> -v``) or where
``v = 0`` (forward, a turning point; accepted only if ``s A > f`` there, so that the forward
motion is unambiguous; otherwise the candidate ``t*`` is rejected).  Roots are located by
the certified step of ``reference.events`` ("Safe steps"): with ``G(u) = g(t - u) >= 0`` and ``|G''| <= M``
(``M = F + f`` for ``x``, ``F w`` for ``v``), ``G(u + h) >= G + G' h - M h^2 / 2``, so the
step ``h = (G' + sqrt(G'^2 + 2 M G)) / M`` never jumps over a root.  The construction runs
at ``CONSTRUCT_DPS`` digits; the state is then rounded to ``STATE_DIGITS`` significant
digits (a decimal string: the exact definition of the hard case from then on).

The chattering case is explicit (no backward run): ``x0 = r - 1/1000``, ``v0 = 1/100`` at
``t = 0``, where ``A = F > f > 0`` pushes into ``r``: the bounces shrink geometrically by
``rho = sqrt((A - f)/(A + f)) < 1`` (with ``f = 0`` they do not: no chatter case there).
With ``F <= f`` two explicit cases: at rest mid-gap, and moving mid-gap (it stops for good).
"""
from __future__ import annotations

from dataclasses import dataclass

import mpmath

from reference.scene import Scene

CONSTRUCT_DPS = 60
STATE_DIGITS = 40
_MAX_STEPS = 20000
_MAX_EVENTS = 400


class ConstructionError(ValueError):
    """The chosen event cannot be reached backward unambiguously from ``t = 0``."""


@dataclass(frozen=True)
class HardCase:
    """A state at ``t = 0`` (decimal strings, exact) and the event it was built around."""

    name: str
    x: str
    v: str
    t_event: str
    kind: str
    how: str


def _params(scene: Scene):
    return tuple(scene.mpf(k) for k in ("F", "f", "omega", "l", "r"))


def flight(scene: Scene, t0, x0, v0, s, t):
    """Closed-form base flight with sign ``s`` from ``(t0, x0, v0)``: ``(x, v, a)`` at ``t``."""
    F, f, w, _, _ = _params(scene)
    h = t - t0
    v = v0 + (F / w) * (mpmath.sin(w * t) - mpmath.sin(w * t0)) - s * f * h
    x = (x0 + v0 * h + (F / w ** 2) * (mpmath.cos(w * t0) - mpmath.cos(w * t) - w * h * mpmath.sin(w * t0))
         - s * f * h * h / 2)
    a = F * mpmath.cos(w * t) - s * f
    return x, v, a


def force(scene: Scene, t):
    """``A(t) = F cos(w t)``."""
    F, _, w, _, _ = _params(scene)
    return F * mpmath.cos(w * t)


def _backward_segment(scene, t1, x1, v1, s, t_stop):
    """Run the flight of sign ``s`` backward from ``t1`` to its forward start or ``t_stop``.

    Returns ``(tau, kind)`` with kind ``"wall"``, ``"zero_velocity"`` or ``"stop"``.
    """
    F, f, w, l, r = _params(scene)
    wall = l if s > 0 else r
    eps = mpmath.mpf(10) ** (-(mpmath.mp.dps - 8))
    bounds = {"wall": F + f, "zero_velocity": F * w}
    u = mpmath.mpf(0)
    for _ in range(_MAX_STEPS):
        t = t1 - u
        x, v, a = flight(scene, t1, x1, v1, s, t)
        # G >= 0 on the safe side, dG/du = -dg/dt.
        G = {"wall": s * (x - wall), "zero_velocity": s * v}
        dG = {"wall": -s * v, "zero_velocity": -s * a}
        if u > 0:
            for name in ("wall", "zero_velocity"):
                if G[name] < -eps:
                    raise RuntimeError(f"backward flight crossed {name} unseen at t={t}, x={x}, v={v}, s={s}")
                if G[name] <= eps * (1 + abs(x) + abs(v)):   # the evaluation noise floor
                    return t, name
        step = t - t_stop
        for name in ("wall", "zero_velocity"):
            g, dg, M = max(G[name], 0), dG[name], bounds[name]
            if u == 0 and g == 0 and dg <= 0:
                raise ConstructionError(f"{name} is not left going backward from t={t1}")
            root = mpmath.sqrt(dg * dg + 2 * M * g)
            # the same root, written without cancellation on the approaching side (dg < 0)
            h = (dg + root) / M if dg >= 0 else 2 * g / (root - dg)
            step = min(step, max(h, eps / 1000))
        if t - t_stop <= eps:
            return t_stop, "stop"
        u += min(step, t - t_stop)
    raise RuntimeError(f"backward flight: more than {_MAX_STEPS} steps from t={t1}, x={x1}, v={v1}, s={s}")


def construct_backward(scene: Scene, t_star, x_star, v_before, s):
    """The state at ``t = 0`` whose forward flight arrives at ``(t*, x*, v_before)`` with sign ``s``.

    Returns ``(x0, v0, log)``; ``log`` lists the forward events passed on the way
    (``(kind, t)``, latest first).  Raises ``ConstructionError`` if the backward run meets an
    ambiguous point (``v = 0`` with ``|A| <= f``) or leaves the gap.
    """
    _, f, _, l, r = _params(scene)
    t, x, v = mpmath.mpf(t_star), mpmath.mpf(x_star), mpmath.mpf(v_before)
    log = []
    for _ in range(_MAX_EVENTS):
        tau, kind = _backward_segment(scene, t, x, v, s, mpmath.mpf(0))
        xt, vt, _ = flight(scene, t, x, v, s, tau)
        if not (l <= xt <= r):
            raise ConstructionError(f"backward flight leaves the gap at t={tau}")
        if kind == "stop":
            return xt, vt, log
        if kind == "wall":
            log.append(("impact", tau))
            t, x, v, s = tau, (l if s > 0 else r), -vt, -s
            continue
        A = force(scene, tau)
        if not s * A > f * (1 + mpmath.mpf(10) ** -6):
            raise ConstructionError(f"backward run reaches v = 0 at t={tau} with |A| near or below f")
        log.append(("turn", tau))
        t, x, v, s = tau, xt, mpmath.mpf(0), -s
    raise RuntimeError(f"backward construction: more than {_MAX_EVENTS} events from t*={t_star}")


def _dec(value) -> str:
    return mpmath.nstr(value, STATE_DIGITS, strip_zeros=False, min_fixed=-mpmath.inf, max_fixed=mpmath.inf) \
        if value != 0 else "0"


def _first_valid(scene, candidates, left_state, name, kind, how):
    """Try candidate event times until the backward construction succeeds."""
    for t_star in candidates:
        try:
            x0, v0, log = construct_backward(scene, t_star, *left_state(t_star))
        except ConstructionError:
            continue
        path = ", ".join(f"{k}@{mpmath.nstr(t, 6)}" for k, t in reversed(log)) or "no earlier event"
        return HardCase(name, _dec(x0), _dec(v0), _dec(t_star), kind,
                        f"{how}; backward from t*={mpmath.nstr(t_star, 12)} ({path})")
    return None


def hard_cases(scene: Scene) -> list[HardCase]:
    """All hard cases constructible for ``scene`` (friction cases need ``f > 0``)."""
    with mpmath.workdps(CONSTRUCT_DPS):
        F, f, w, l, r = _params(scene)
        T = 2 * mpmath.pi / w
        grid = [T * k / 64 for k in range(3, 62)]
        decel = [t for t in grid if F * mpmath.cos(w * t) < -f - F / 20]   # a < 0 coming to r
        out = []

        def at_r(speed):
            return lambda t: (r, speed(t), 1)

        out.append(_first_valid(scene, decel, at_r(lambda t: mpmath.mpf("1e-6")), "grazing", "impact",
                                "near-grazing impact at r with v- = 1e-6 while decelerating (A < -f)"))
        out.append(_first_valid(
            scene, decel, at_r(lambda t: (f - force(scene, t)) * mpmath.mpf("5e-14")), "crossing_pair", "impact",
            "x - r has two roots 1e-13 apart: impact at r with v- = |a| * 5e-14 (a = A - f < 0)"))
        out.append(_first_valid(scene, decel, lambda t: (r, mpmath.mpf(0), 1), "turn_at_wall", "contact",
                                "v reaches 0 exactly at x = r with A < -f (contact and release at once, "
                                "or a turn)"))
        out.append(_first_valid(scene, [T], at_r(lambda t: F / w / 2), "impact_at_T", "impact",
                                "impact at r at exactly t = T with v- = F/(2w)"))
        if f > 0 and F > f:
            t_b = mpmath.acos(-f / F) / w                       # A(t_b) = -f, |A| grows after
            mids = [l + (r - l) * k / 8 for k in (4, 3, 5, 2, 6, 1, 7)]
            out.append(_boundary_case(scene, t_b, mids))
            out.append(_stick_case(scene, T / 4, mids))
        if F <= f:
            out.append(HardCase("at_rest", _dec((l + r) / 2), "0", "0", "stick",
                                "explicit: v0 = 0 mid-gap with F <= f: the particle never moves"))
            out.append(HardCase("stopping", _dec((l + r) / 2), _dec(F / w), "0", "stick",
                                "explicit: v0 = F/w mid-gap with F <= f: it stops, then stays stopped"))
        if 0 < f < F:   # f = 0, e = 1: bounces do not shrink (rho = 1), no chatter
            out.append(HardCase("chatter", _dec(r - mpmath.mpf(1) / 1000), "0.01", "0", "chatter",
                                "explicit: x0 = r - 1/1000, v0 = 1/100 at t = 0 where A = F > f pushes into r"))
        return [c for c in out if c is not None]


def _stop_case(scene, t_star, mids, name, where):
    """``v`` reaches 0 at ``t_star`` at the first mid-gap position that a backward flight
    (``s = +1``, ``v = 0``) reaches from ``t = 0``; ``where`` says what the force is there."""
    for xm in mids:
        try:
            x0, v0, log = construct_backward(scene, t_star, xm, 0, 1)
        except ConstructionError:
            continue
        return HardCase(name, _dec(x0), _dec(v0), _dec(t_star), "stick",
                        f"v reaches 0 at x = {mpmath.nstr(xm, 8)} at {where}; "
                        f"backward with {len(log)} earlier events")
    return None


def _boundary_case(scene, t_b, mids):
    """Turning point exactly at ``A = -f`` (stick of zero length, then slip)."""
    return _stop_case(scene, t_b, mids, "stick_slip_boundary", "t* = acos(-f/F)/w where A = -f exactly")


def _stick_case(scene, t_s, mids):
    """A stick: ``v`` reaches 0 at ``t* = T/4`` where ``A = 0``, inside ``|A| <= f``."""
    return _stop_case(scene, t_s, mids, "sticking", "t* = T/4 where A = 0 < f")
