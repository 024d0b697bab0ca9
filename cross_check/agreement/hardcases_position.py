"""Hard cases under position forcing (issue 33): ``hardcases``' kinds for
``x'' + c x' + f sgn(x') = F cos(k x) cos(w t)`` (any damping ``c`` and restitution ``e``), built
backward with the reference's Taylor flight and certified by a validated one.

Construction.  As in ``hardcases``, the *event state* is chosen -- time ``t*``, position ``x*``,
velocity ``v*`` just before, flight sign ``s`` -- and the flight through it is run back to
``t = 0``.  With ``A(x, t) = F cos(k x) cos(w t)``:

* at a wall ``W`` (``r`` with ``s = +1``, ``l`` with ``s = -1``), on the grid ``t* = T j / 64``,
  ``j = 3 .. 61``, where the flight decelerates into it (``s x''(t*) < -(F + f)/20``):
  ``grazing`` (``|v*| = 1e-6``), ``crossing_pair`` (``|v*| = |x''| 5e-14``), ``turn_at_wall``
  (``v* = 0``: a turn if ``s A < -f`` there, else contact); ``impact_at_T``: ``t* = T`` with
  ``|v*| = (F / w) 2^(-j/2)``, ``j = -4 .. 16``;
* mid-gap (``x* = l + (r - l) i / 64``, from the middle out) with ``v* = 0``:
  ``stick_slip_boundary`` at ``s A(x*, t*) = -f`` exactly, ``|A|`` growing after (a stick of zero
  length, then slip), else falling after (then a stick) -- needs ``|F cos k x*| > f``;
  ``sticking`` at ``t* = T/4`` or ``3T/4`` (``A = 0``) where ``|F cos k x*| > f`` (the particle
  slips again later);
  ``stopping`` in the middle of the widest rest interval ``|F cos k x| <= f``
  (``reference.taylor.equilibrium_intervals``: there a stop is final); ``at_rest`` is explicit
  (``v0 = 0`` there).  Chatter is ``hardcases``' explicit start, at the wall the force pushes
  into at ``t = 0`` (where it pushes into neither, a start whose chatter run comes later,
  ``forward_position``).

A case is a *single flight* from ``t = 0`` to ``t*``: the certificate below says there is no
other event before ``t*`` (but ``impact_at_T`` on a gap too narrow for a flight of a whole
period, which ``impact_at_t`` builds from rest, or from a moving start, through earlier events and
proves forward; and ``sticking`` where no single flight reaches a stop, which ``forward_position``
builds as a stop later in the period, proved forward).  Candidates are screened in float64 first (``construct_position``'s
backward flight and grid certificate: cheap, and it only orders and drops candidates); the first
``MAX_TRIES`` that pass are tried in full:

1. the reference's Taylor flight (``reference.taylor.TaylorFlight``) runs the *reversed* motion
   ``y(tau) = x(-tau)``, ``y'' = F cos(k y) cos(w tau) - s f + c y'`` (``y' = -v``: damping turns
   into ``-c``; ``_Reversed`` hands the scene to it so) from ``tau = -t*`` to ``0`` at
   ``CONSTRUCT_DPS`` digits: the start, rounded to ``STATE_DIGITS`` (30) digits, is the case;
2. the certificate: a validated flight (``reference.enclosure.lohner.ValidatedFlight``: Taylor
   series in Arb balls, a Picard box, a Lohner QR frame; independent code) of the same reversed
   motion from the exact event state (binary ``mpf`` values: exact balls), at ``CERT_PREC``
   bits, on which ``reference.enclosure.certify.exclude`` proves every event function of the
   forward flight positive on ``[0, t*)``: both wall distances ``side (W - x)`` and, with
   friction, ``s v``.  The enclosure of ``(x, v)`` at ``t = 0`` must contain the Taylor flight's
   start (to its ``CONSTRUCT_DPS`` digits), else the case is refused too.

Why backward, and not a validated flight forward from the rounded start: the event state is
exact, so the event functions that vanish at ``t*`` do so *structurally*, with a known order
``m`` (``x* = W``: the wall distance, order 1, or 2 at a turn at the wall; ``v* = 0``: the
velocity, order 1), and ``exclude`` proves ``g > 0`` right up to ``t*`` from the sign of
``g^(m)`` alone (Taylor's theorem).  A forward enclosure from the decimal start, ``1e-40`` off
the constructed trajectory, could say nothing near a tangency, a grazing speed of ``5e-14`` or the
friction boundary -- the very places the cases are about.  A candidate whose backward flight
meets a wall (or ``v = 0``) before ``t = 0`` fails the exclusion: ``ConstructionError``, and the
next is tried.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass

import mpmath
import numpy as np
from flint import arb

from cross_check.agreement import construct_position, forward_position, impact_at_t
from cross_check.agreement.case import CONSTRUCT_DPS, ConstructionError, HardCase, decimal_text
from reference.enclosure import certify, lohner, motion
from reference.enclosure.balls import BallModel, from_mpf, workprec
from reference.enclosure.certify import Unproved
from reference.taylor import TaylorFlight, equilibrium_intervals

#: bits of the validated certificate (~77 digits: the 60-digit construction must lie inside)
CERT_PREC = 256
#: candidates of one kind that pass the float64 screen and are tried in full (each ~0.1-1 s)
MAX_TRIES = 6
#: candidates screened first (``_passing``); the rest only if these give no case.  The screen's
#: cost is per substep of its batch (numpy lanes), the substeps set by the batch's hardest
#: candidate: on D (``F=3 f=0.5 omega=0.8 l=-2 r=1.5 wavenumber=2.5``) 64 candidates took 0.37
#: CPU s, their first 8 0.06 (issue 33)
SCREEN_FIRST = 8
#: the Taylor flight's start must lie within this many units of its last digit of the enclosure
START_SLACK_DIGITS = 10
#: significant digits of the cases' decimal states (``hardcases``: 40).  The golden data proves
#: every input (``reference.enclosure.enclose_map``), whose point log under position forcing
#: carries at most 40 digits (``maps.POINT_DPS_TAYLOR``): a start rounded to 40 digits leaves a
#: turn at the wall or an impact at ``T`` within ~1e-40 of its tangency, which that log cannot
#: place on either side (measured: both exact inputs unproved at every precision up to 1280 bits);
#: at 30 digits it can, and the cases stay 14 digits below what float64 resolves
STATE_DIGITS = 30


class _Reversed:
    """The scene run backward in time, as ``TaylorFlight`` reads it (``mpf``): damping ``-c``."""

    def __init__(self, scene):
        self.scene = scene

    def mpf(self, name):
        value = self.scene.mpf(name)
        return -value if name == "damping" else value


class _ReversedBalls:
    """A ``BallModel`` with the damping negated (what ``ValidatedFlight``'s field reads)."""

    def __init__(self, model):
        self.model, self.c, self.damping = model, -model.c, True

    def __getattr__(self, name):
        return getattr(self.model, name)


def start(scene, t_star, x_star, v_star, s):
    """``(x0, v0)`` at ``t = 0`` of the flight with sign ``s`` through ``(t*, x*, v*)``: the
    reference's Taylor flight of the reversed motion (current mpmath precision)."""
    y, yd = TaylorFlight(_Reversed(scene), -t_star, x_star, -v_star, s).state(0)
    return y, -yd


@dataclass(frozen=True)
class Certificate:
    """What the validated backward flight proved: ``x0, v0`` (balls) at ``t = 0``, the pieces of
    the exclusions and their precision."""

    x0: arb
    v0: arb
    pieces: int
    prec: int


def wall_side(scene, x_star) -> int:
    """``+1`` / ``-1`` when ``x*`` is the wall ``r`` / ``l`` (the scene's value at the current
    mpmath precision, as the candidates are built), else 0."""
    return next((side for side, name in ((1, "r"), (-1, "l")) if x_star == scene.mpf(name)), 0)


def event_functions(model, on, v_star, s):
    """The forward flight's event functions in the reversed time ``u = t* - t`` (the stack of the
    reversed motion is ``[y, y', y'', ...]``, ``y' = -v``), each with the order of its structural
    zero at ``u = 0``: the wall distances (``on``: the wall ``x*`` is at, 0 for none) and, with
    friction, ``s v = -s y'``."""
    fns = []
    for side in (1, -1):
        fns.append(motion.distance(model, side, (1 if v_star != 0 else 2) if on == side else 0))
    if model.friction:
        fns.append(motion.velocity(-s, 1 if v_star == 0 else 0))
    return fns


def certify_flight(scene, t_star, x_star, v_star, s, prec=CERT_PREC) -> Certificate:
    """Prove that the flight with sign ``s`` through the exact ``(t*, x*, v*)`` (mpf) meets no
    wall and (with friction) no ``v = 0`` on ``[0, t*)`` (module docstring); ``ConstructionError``
    with the reason if it cannot be proved (e.g. the backward flight crosses a wall).

    An ``x*`` on a wall starts the validated flight from the wall's own ball (the scene's exact
    wall, a structural zero of its distance): the wall's mpf, rounded at the candidates'
    precision, lies ~1e-31 inside or outside the exact wall, and outside it was refused as
    "outside the gap" (every wall kind of a hidden scene with ``l = -0.7``)."""
    on = wall_side(scene, x_star)
    with workprec(prec):
        model = BallModel(scene)
        T, V = from_mpf(mpmath.mpf(t_star)), from_mpf(mpmath.mpf(v_star))
        X = model.wall(on) if on else from_mpf(mpmath.mpf(x_star))
        if not (on or (X >= model.l and X <= model.r)):
            raise ConstructionError(f"certificate refused: x* = {mpmath.nstr(x_star, 12)} is outside the gap")
        flight = lohner.ValidatedFlight(_ReversedBalls(model), -T, X, -V, s)
        pieces = 0
        try:
            for fn in event_functions(model, on, v_star, s):
                pieces += certify.exclude(flight, fn, arb(0), T, f"backward flight from t* = {T.mid().str(12)}")
            x0, yd0 = flight.state(T)
        except Unproved as exc:
            raise ConstructionError(f"certificate refused: {exc}") from None
        return Certificate(x0, -yd0, pieces, prec)


def _inside(value, ball, digits) -> bool:
    """``value`` (mpf) within ``10^-digits (1 + |value|)`` of the ball (a certain comparison)."""
    with workprec(CERT_PREC):
        return bool(abs(from_mpf(value) - ball) < arb(10) ** -digits * (1 + abs(ball)))


def _float_screen(scene, candidates):
    """Indices of the candidates whose float64 backward flight passes ``construct_position``'s
    certificate, in order (a cheap filter: the validated certificate decides)."""
    F, f, w, _, _, c, k, _ = construct_position.params(scene)
    t, x, v, s = (np.array([float(z[i]) for z in candidates]) for i in range(4))
    decel = s * F * np.cos(k * x) * np.cos(w * t) - f - c * np.abs(v)
    _, ok = construct_position.backward(scene, t, x, v, s, decel, matrices=False, give_up=True)
    return list(np.flatnonzero(ok))


def _passing(scene, candidates):
    """The indices of the candidates that pass the float screen, in order, screened lazily: the
    first ``SCREEN_FIRST``, then the rest."""
    for lo, hi in ((0, SCREEN_FIRST), (SCREEN_FIRST, len(candidates))):
        if lo < hi:
            yield from (lo + int(i) for i in _float_screen(scene, candidates[lo:hi]))


def build(scene, name, candidates, kind, how):
    """The first candidate ``(t*, x*, v*, s)`` (mpf) that the float screen passes and that is
    constructed and certified: ``(HardCase, None)``, or ``(None, why)``."""
    if not candidates:
        return None, "no candidate event state"
    why = (f"no single flight from t = 0 reaches it: each of the {len(candidates)} candidate event states, "
           f"run backward (float64 screen), meets a wall or v = 0 before t = 0 or leaves the gap")
    for i in itertools.islice(_passing(scene, candidates), MAX_TRIES):
        t_star, x_star, v_star, s = candidates[i]
        try:
            x0, v0 = start(scene, t_star, x_star, v_star, int(s))
            cert = certify_flight(scene, t_star, x_star, v_star, int(s))
            digits = CONSTRUCT_DPS - START_SLACK_DIGITS
            if not (_inside(x0, cert.x0, digits) and _inside(v0, cert.v0, digits)):
                raise ConstructionError("the Taylor flight's start lies outside the validated enclosure")
        except ConstructionError as exc:
            why = str(exc)
            continue
        radius = max(float(cert.x0.rad()), float(cert.v0.rad()))
        return HardCase(name, decimal_text(x0, STATE_DIGITS), decimal_text(v0, STATE_DIGITS),
                        decimal_text(t_star, STATE_DIGITS), kind,
                        f"{how}; backward from t*={mpmath.nstr(t_star, 12)} (a single flight); certified: "
                        f"no wall and no v = 0 on [0, t*) (validated Taylor flight backward, {cert.pieces} "
                        f"pieces, {cert.prec} bits; start enclosed to {radius:.0e})"), None
    return None, why


def construct(scene):
    """``(built, notes)``: every kind of ``hardcases.NAMES`` but chatter (``hardcases`` builds it)
    for a scene with position forcing and ``F > 0``."""
    with mpmath.workdps(CONSTRUCT_DPS):
        built, notes = {}, {}
        _wall_kinds(scene, built, notes)
        _friction_kinds(scene, built, notes)
        return built, notes


def _force(scene, x, t):
    F, w, k = scene.mpf("F"), scene.mpf("omega"), scene.mpf("wavenumber")
    return F * mpmath.cos(k * x) * mpmath.cos(w * t)


#: the wall kinds' event times ``t* = T / 2^m`` tried after the grid ``T j / 64``: on a narrow gap
#: with a long period every flight run back from ``3T/64`` or later meets a wall (issue 33: the
#: corner of the random scenes, ``F=3 f=0.3 omega=0.5 l=0 r=0.2 wavenumber=2 restitution=0.6``,
#: where a flight of 0.35 crosses the gap and ``3T/64`` is 0.59), and a graze, a crossing pair or
#: a turn at a wall comes early in the period or not at all from a single flight
EARLY = (7, 8, 9, 10, 11)


def _wall_kinds(scene, built, notes):
    F, f, w, c = (scene.mpf(p) for p in ("F", "f", "omega", "damping"))
    walls = ((scene.mpf("r"), 1), (scene.mpf("l"), -1))
    T = 2 * mpmath.pi / w
    grid = [T * j / 64 for j in range(3, 62)] + [T / 2 ** m for m in EARLY]

    def at_walls(speed):
        out = []
        for t in grid:
            for W, s in walls:
                a = s * _force(scene, W, t) - f
                if a - c * speed(a) < -(F + f) / 20:
                    out.append((t, W, s * speed(a), s))
        return out

    kinds = (("grazing", at_walls(lambda a: mpmath.mpf("1e-6")), "impact",
              "near-grazing impact at a wall with |v-| = 1e-6 while decelerating into it"),
             ("crossing_pair", at_walls(lambda a: abs(a) * mpmath.mpf("5e-14")), "impact",
              "the wall distance has two roots 1e-13 apart: impact with |v-| = |x''| * 5e-14"),
             ("turn_at_wall", at_walls(lambda a: mpmath.mpf(0)), "contact",
              "v reaches 0 exactly at a wall while decelerating into it (a turn if s A < -f there, else contact)"),
             ("impact_at_T", [(T, W, s * F / w * mpmath.mpf(2) ** (-j / 2), s) for j in range(-4, 17)
                              for W, s in walls], "impact", "impact at a wall at exactly t = T"))
    for name, candidates, kind, how in kinds:
        if not candidates:
            notes[name] = ("the flight never decelerates into a wall by more than (F + f)/20 on the grid "
                           "t = T j/64, nor at t = T/2^m, m = 7 .. 11")
            continue
        built[name], why = build(scene, name, candidates, kind, how)
        if why and name == "impact_at_T":             # a narrow gap: through earlier events
            built[name], more = impact_at_t.construct(scene, STATE_DIGITS)
            why = more and f"{why}; {more}"
        if why:
            notes[name] = why


def _mids(scene):
    """Mid-gap positions ``l + (r - l) i / 64``, ``i = 1 .. 63``, from the middle outwards."""
    l, r = scene.mpf("l"), scene.mpf("r")
    return [l + (r - l) * i / 64 for i in sorted(range(1, 64), key=lambda i: (abs(i - 32), i))]


def _friction_kinds(scene, built, notes):
    """Stick-slip boundary, sticking, at rest and stopping (module docstring)."""
    F, f, w, k = (scene.mpf(p) for p in ("F", "f", "omega", "wavenumber"))
    T = 2 * mpmath.pi / w
    moving = [x for x in _mids(scene) if abs(F * mpmath.cos(k * x)) > f]
    if f == 0:
        notes["stick_slip_boundary"] = notes["sticking"] = ("frictionless (f = 0): no sticking and no stick-slip "
                                                            "boundary")
    elif not moving:
        notes["stick_slip_boundary"] = notes["sticking"] = (
            "|F cos(k x)| <= f at every mid-gap position tried: a stop there is final (at_rest and stopping "
            "stand for it)")
    else:
        boundary = []
        for falling in (True, False):
            for x in moving:
                for s in (1, -1):
                    g = s * F * mpmath.cos(k * x)             # s A = g cos(w t) = -f at t*
                    phase = mpmath.acos(-f / g) if g > 0 else mpmath.acos(f / -g)
                    if falling == (g < 0):                    # s A falling through -f: phase in (pi, 2 pi)
                        phase = 2 * mpmath.pi - phase
                    boundary.append((phase / w, x, mpmath.mpf(0), s))
        sticks = [(t, x, mpmath.mpf(0), s) for x in moving for t in (T / 4, 3 * T / 4) for s in (1, -1)]
        for name, candidates, how in (
                ("stick_slip_boundary", boundary, "v reaches 0 mid-gap exactly where s A = -f (|A| growing "
                                                  "after: a stick of zero length, then slip; falling: a stick)"),
                ("sticking", sticks, "v reaches 0 mid-gap where A = 0 (cos w t* = 0) and |F cos k x*| > f "
                                     "(a stick, then slip)")):
            built[name], why = build(scene, name, candidates, "stick", how)
            if why and name == "sticking":          # a stop later, through earlier events
                built[name], later = forward_position.sticking(scene)
                why = None if built[name] else f"{why}; nor through earlier events: {later}"
            if why:
                notes[name] = why
    _rest_kinds(scene, built, notes, T)


def _rest_kinds(scene, built, notes, T):
    rests = [(hi - lo, lo, hi) for lo, hi in equilibrium_intervals(scene) if hi > lo]
    if not rests:
        notes["at_rest"] = notes["stopping"] = (
            "|F cos(k x)| > f in the gap (but at isolated points): the force moves a particle at rest "
            "(no permanent rest)")
        return
    _, lo, hi = max(rests)
    x = (lo + hi) / 2
    built["at_rest"] = HardCase("at_rest", decimal_text(x, STATE_DIGITS), "0", "0", "stick",
                                f"explicit: v0 = 0 at x = {mpmath.nstr(x, 8)}, the middle of the rest interval "
                                f"[{mpmath.nstr(lo, 8)}, {mpmath.nstr(hi, 8)}] where |F cos(k x)| <= f: it never moves")
    grid = [T * j / 64 for j in range(3, 62)]
    built["stopping"], why = build(scene, "stopping", [(t, x, mpmath.mpf(0), s) for t in grid for s in (1, -1)],
                                   "stick", f"v reaches 0 at x = {mpmath.nstr(x, 8)}, inside the rest interval "
                                            "|F cos(k x)| <= f: it stops, then stays stopped")
    if why:
        notes["stopping"] = why
