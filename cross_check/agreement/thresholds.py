"""Threshold pairs: starts just inside and just outside every regime switch, at a known
relative distance ``delta``, with the regime each side must take from the closed-form condition.

A test that reaches a threshold only at random states almost never lands near it, and one built
exactly *on* it lands in the near-grazing band, where either answer is right in float64.  A
pair at ``delta`` in {1e-3, 1e-6, 1e-9} (far beyond the band, ~1e-15) has one right answer on
each side.  The switches (``SWITCHES``), for the base model (``hardcases.flight``) unless said:

* ``stick or turn``        -- ``v = 0`` mid-gap at ``t*`` with ``|A(t*)| = f (1 + side delta)``:
  a turn (``|A| > f``) or a stick;
* ``slip time``            -- a stick at ``t*`` (``A = f/2``) ends when ``|A|`` rises through
  ``f`` at ``t_s``; over ``[0, t_s (1 + side delta)]`` a ``slip`` is logged iff ``side > 0``;
* ``impact or graze``      -- a flight decelerating toward ``r`` whose apex (``v = 0``) lies at
  ``r + side delta (r - l)``: an impact iff ``side > 0``, else a turn at the apex;
* ``rest or leave a wall`` -- at rest on ``l`` at ``t = 0`` with ``F = f (1 + side delta)``: leaves
  iff ``F > f``, else stays, ``Phi = (l, 0)``;
* ``stick or slip at rest``-- at rest mid-gap at ``t = 0``, the same scenes: slips iff ``F > f``;
* ``release from a wall``  -- in contact with ``r`` at ``t = 0`` (``A(0) = F`` pushes into it):
  released at ``t_r``, ``A(t_r) = -f``; over ``[0, t_r (1 + side delta)]`` a ``release`` iff
  ``side > 0``;
* ``e = 0 held or released`` -- restitution 0, an impact at ``r`` at ``t*`` with ``A(t*) = -f
  (1 + side delta)``: released at once iff ``side > 0``, else held (``contact``).

``damping`` variants (``c = 0.1``) of the rest, slip-at-rest and release pairs: the thresholds
sit at ``v = 0``, where the damping force vanishes, so the same closed forms decide.  The
starts of flights come from ``hardcases.construct_backward`` at 40 digits (the construction of
the hard cases and of ``construct``), from a point of the closed-form flight before the switch.
"""
from __future__ import annotations

from dataclasses import dataclass

import mpmath

from cross_check.agreement.hardcases import construct_backward, flight
from reference.scene import Scene

DELTAS = ("1e-3", "1e-6", "1e-9")
DPS = 40
SWITCHES = ("stick or turn", "slip time", "impact or graze", "rest or leave a wall", "stick or slip at rest",
            "release from a wall", "e = 0 held or released")
_FLIGHT_SCENES = (dict(F=1, f="0.3", omega=1, l=0, r=20), dict(F=1, f="0.1", omega="2*pi", l=-1, r=1))


@dataclass(frozen=True)
class Pair:
    """One side of a threshold pair.

    ``expect`` is ``("event", i, kind)`` (the i-th logged event has ``kind``), ``("has", kind,
    bool)`` (``kind`` is logged, or not) or ``("rest", bool)`` (``Phi`` is the start at rest, or
    not); the log covers ``[0, t_end]`` (``None``: one period).
    """

    switch: str
    variant: str
    delta: str
    side: int
    scene: Scene
    x: str
    v: str
    t_end: object
    expect: tuple

    def verdict(self, kinds=None, at_rest=None) -> tuple[bool, str]:
        """Whether what an integrator did -- the event ``kinds`` it logged over the pair's window,
        or whether its ``Phi`` is the start ``at_rest`` -- is the regime this side must take."""
        if self.expect[0] == "rest":
            return at_rest == self.expect[1], f"at rest: {at_rest}"
        if self.expect[0] == "event":
            _, i, kind = self.expect
            return len(kinds) > i and kinds[i] == kind, f"events {kinds[:i + 3]}"
        _, kind, present = self.expect
        return (kind in kinds) == present, f"events {kinds}"

    @property
    def id(self) -> str:
        return f"{self.switch} [{self.variant}] delta={self.delta} {'+' if self.side > 0 else '-'}"


def _s(value) -> str:
    return mpmath.nstr(value, DPS, min_fixed=-mpmath.inf, max_fixed=mpmath.inf)


def _via_flight(scene, t_star, x_star, v_star, s, lead):
    """The start at ``t = 0`` whose flight passes the closed-form point ``lead`` before ``t*``
    (``(t*, x*, v*)`` on the flight of sign ``s``); returns ``(x0, v0, events before)``."""
    t_b = t_star - lead
    x_b, v_b, _ = flight(scene, t_star, x_star, v_star, s, t_b)
    x0, v0, log = construct_backward(scene, t_b, x_b, v_b, s)
    return x0, v0, len(log)


def _stick_or_turn(base, d, side):
    sc = Scene(**base)
    F, f, w, l, r = (sc.mpf(k) for k in ("F", "f", "omega", "l", "r"))
    t_star = mpmath.acos(f * (1 + side * d) / F) / w         # A(t*) = f (1 + side delta) > 0, s = -1
    x0, v0, n = _via_flight(sc, t_star, (l + r) / 2, 0, -1, t_star / 2)
    return sc, x0, v0, None, ("event", n, "turn" if side > 0 else "stick")


def _slip_time(base, d, side):
    sc = Scene(**base)
    F, f, w, l, r = (sc.mpf(k) for k in ("F", "f", "omega", "l", "r"))
    t_star = mpmath.acos(f / (2 * F)) / w                     # a stick at A = f/2
    x0, v0, _ = _via_flight(sc, t_star, (l + r) / 2, 0, -1, t_star / 2)
    t_slip = mpmath.acos(-f / F) / w                           # |A| rises through f
    return sc, x0, v0, t_slip * (1 + side * d), ("has", "slip", side > 0)


def _impact_or_graze(base, d, side):
    sc = Scene(**base)
    F, f, w, l, r = (sc.mpf(k) for k in ("F", "f", "omega", "l", "r"))
    t_apex = mpmath.acos(-(f + (F - f) / 2) / F) / w           # A < -f at the apex: a turn there
    x_apex = r + side * d * (r - l)
    x0, v0, n = _via_flight(sc, t_apex, x_apex, 0, 1, mpmath.pi / (20 * w))
    return sc, x0, v0, None, ("event", n, "impact" if side > 0 else "turn")


def _at_rest(where):
    def build(base, d, side):
        f = mpmath.mpf(base["f"])
        sc = Scene(**{**base, "F": _s(f * (1 + side * d))})
        l, r = sc.mpf("l"), sc.mpf("r")
        return sc, (l if where == "wall" else (l + r) / 2), 0, None, ("rest", side < 0)
    return build


def _release(base, d, side):
    sc = Scene(**base)
    F, f, w = (sc.mpf(k) for k in ("F", "f", "omega"))
    return sc, sc.mpf("r"), 0, mpmath.acos(-f / F) / w * (1 + side * d), ("has", "release", side > 0)


def _held(base, d, side):
    sc = Scene(**{**base, "restitution": 0})
    F, f, w, r = (sc.mpf(k) for k in ("F", "f", "omega", "r"))
    t_star = mpmath.acos(-f * (1 + side * d) / F) / w
    x0, v0, n = _via_flight(sc, t_star, r, mpmath.mpf("0.5"), 1, t_star / 4)
    return sc, x0, v0, None, ("has", "contact", side < 0)


_REST_SCENE = dict(F=1, f="0.3", omega=1, l=0, r=20)
_BUILDERS = {
    "stick or turn": (_stick_or_turn, {"wide": _FLIGHT_SCENES[0], "2pi": _FLIGHT_SCENES[1]}),
    "slip time": (_slip_time, {"wide": _FLIGHT_SCENES[0], "2pi": _FLIGHT_SCENES[1]}),
    "impact or graze": (_impact_or_graze, {"wide": _FLIGHT_SCENES[0], "2pi": _FLIGHT_SCENES[1]}),
    "rest or leave a wall": (_at_rest("wall"), {"base": _REST_SCENE, "damping": {**_REST_SCENE, "damping": "0.1"}}),
    "stick or slip at rest": (_at_rest("mid"), {"base": _REST_SCENE, "damping": {**_REST_SCENE, "damping": "0.1"}}),
    "release from a wall": (_release, {"base": _REST_SCENE, "damping": {**_REST_SCENE, "damping": "0.1"},
                                       "e = 0": {**_REST_SCENE, "restitution": 0}}),
    "e = 0 held or released": (_held, {"wide": _FLIGHT_SCENES[0], "2pi": _FLIGHT_SCENES[1]}),
}


def pairs(switches=SWITCHES, deltas=DELTAS) -> list[Pair]:
    """Both sides of every switch, variant and ``delta`` (strings of 40 digits for the starts)."""
    out = []
    with mpmath.workdps(DPS + 10):
        for switch in switches:
            build, variants = _BUILDERS[switch]
            for variant, base in variants.items():
                for delta in deltas:
                    for side in (-1, 1):
                        sc, x0, v0, t_end, expect = build(base, mpmath.mpf(delta), side)
                        out.append(Pair(switch, variant, delta, side, sc, _s(x0), _s(v0),
                                        None if t_end is None else _s(t_end), expect))
    return out


def _log(pair: Pair, engine: str, dps: int):
    from cross_check.agreement import compare
    from cross_check.agreement.case import Case

    case = Case(pair.id, pair.x, pair.v, "decimal", "threshold pair")
    if engine == "reference":
        with mpmath.workdps(dps):
            t_end = None if pair.t_end is None else mpmath.mpf(pair.t_end)
        return [e.kind for e in compare.ref_events(pair.scene, case, t_end, dps)]
    import fast
    import numpy as np

    x, v = (np.array([a]) for a in case.float())
    raw = fast.events(pair.scene, x, v) if pair.t_end is None else fast.events(pair.scene, x, v, float(pair.t_end))
    return [e.kind for e in compare.normalize_fast_events(raw, 1)[0]]


def _at_rest(pair: Pair, engine: str, dps: int) -> bool:
    from cross_check.agreement import compare
    from cross_check.agreement.case import Case

    case = Case(pair.id, pair.x, pair.v, "decimal", "threshold pair")
    if engine == "reference":
        x, v = compare.ref_map(pair.scene, case, 1, dps)
        with mpmath.workdps(dps):
            return x == mpmath.mpf(pair.x) and v == 0
    x, v = compare.fast_map(pair.scene, *(([a]) for a in case.float()))
    return float(x[0]) == float(pair.x) and float(v[0]) == 0.0


def observe(pair: Pair, engine: str, dps: int = 30) -> tuple[bool, str]:
    """Whether ``engine`` (``"fast"`` or ``"reference"`` at ``dps``) takes the expected regime,
    and what it did (the event kinds, or whether ``Phi`` is the start at rest)."""
    if pair.expect[0] == "rest":
        return pair.verdict(at_rest=_at_rest(pair, engine, dps))
    return pair.verdict(kinds=_log(pair, engine, dps))
