"""A scene's float64 constants for the compiled loop: one array ``P`` with named slots.

``params(scene)`` validates the scene's type and effects and returns ``P`` (cached per
scene: a ``Scene`` is frozen).  Slots hold plain float64 values, or double-doubles as two
slots ``X, X_LO`` (``X`` correctly rounded, ``X_LO`` the rest rounded) read at 40 digits
from the scene's exact parameters -- parameter conversion, not integration:

* ``F, f, w`` and ``F/w``, ``F/w^2`` (flight coefficients), the period ``T = 2 pi / w``;
* ``c = f/F`` and ``sin(alpha)``, ``alpha = arccos(c)``: the sticking threshold and the
  trigonometric values at the phases where sticking or wall contact ends,
  ``B1 = pi - alpha`` and ``B2 = 2 pi - alpha`` (``c >= 1``, i.e. ``F <= f``: never);
* damping ``c_d`` (and ``1/c_d``, ``1/c_d^2``, ``1/w``) and the forced particular velocity
  ``Pd cos wt + Qd sin wt - s f/c_d``, ``Pd = F c_d/(c_d^2 + w^2)``, ``Qd = F w/(c_d^2 + w^2)``.

Bounds used by the certified event search (``fast.roots``), for a flight with sign s:
wall function ``g1 = s (W_s - x)``: ``|g1''| = |s A - f| <= F + f``, ``|g1'''| <= F w``;
velocity function ``g2 = s v``: ``|g2''| = |A'| <= F w``, ``|g2'''| <= F w^2``.  With damping
``c_d > 0`` they depend on the segment's start speed (``fast.roots.damped_bounds``).

Scene check (``check_ranges``, also for ``fast.ode``): every parameter and derived constant
within ``FAST_MIN .. FAST_MAX`` (so no float64 operation of the loop overflows, underflows or
warns), the walls resolvable (``MIN_RELATIVE_GAP``), a crossing of the gap longer than the time
resolution of a period (``MIN_CROSSING``), damping within the measured range of the damped
flights; otherwise a ``ValueError`` naming the quantity and the parameters it comes from.
"""
from __future__ import annotations

import math
from functools import lru_cache

import mpmath
import numpy as np

from reference.scene import Scene

from .dd import split_exact

EPS = 2.0 ** -52
_NAMES = ("F F_LO FF FF_LO W W_LO L R T T_LO E DAMP DAMP_LO PD PD_LO QD QD_LO C C_LO ALPHA "
          "SA SA_LO B1 B1_LO B2 B2_LO FW FW_LO FW2 FW2_LO M1 M1_3 M2 M2_3 NOISE1 NOISE2 D_ACC "
          "FRICTION CHATTER XSCALE IW IW_LO ID ID_LO ID2 ID2_LO").split()
(F, F_LO, FF, FF_LO, W, W_LO, L, R, T, T_LO, E, DAMP, DAMP_LO, PD, PD_LO, QD, QD_LO, C, C_LO,
 ALPHA, SA, SA_LO, B1, B1_LO, B2, B2_LO, FW, FW_LO, FW2, FW2_LO, M1, M1_3, M2, M2_3, NOISE1,
 NOISE2, D_ACC, FRICTION, CHATTER, XSCALE, IW, IW_LO, ID, ID_LO, ID2, ID2_LO) = range(len(_NAMES))
SIZE = len(_NAMES)
#: ``F`` above ``f`` by less than this, relative (about 4 ulp), counts as ``F = f``: the force
#: then exceeds the friction for windows of ``2 acos(f/F)/w < 2 sqrt(2^-49)/w ~ 6e-8/w`` only,
#: which move the state by under ``(F - f) (6e-8/w)^2 ~ 1e-30 F/w^2`` -- below the float64
#: resolution of any state relative to ``max(1, |.|)`` -- while float64 cannot order the window's
#: ends (the threshold pairs of issue 18 found the search crawling there: F = f (1 + 2e-16))
STICK_EDGE = mpmath.mpf(2) ** -50

#: 2 pi as a double-double (mpmath at 40 digits)
TWO_PI_HI, TWO_PI_LO = 6.283185307179586, 2.4492935982947064e-16


def check_scene(scene) -> Scene:
    """``scene`` must be a ``reference.scene.Scene`` (``TypeError`` naming it otherwise)."""
    if not isinstance(scene, Scene):
        raise TypeError(f"fast: scene must be a reference.scene.Scene, got {type(scene).__name__} "
                        f"({scene!r:.80})")
    return scene


#: The magnitudes ``fast`` holds: every parameter of a scene, and every constant derived from
#: it that the compiled loop uses (``fast_quantities``), is 0 or between ``FAST_MIN`` and
#: ``FAST_MAX`` in absolute value.  float64 is normal from 2.2e-308 to 1.8e308; the loop
#: multiplies up to three such constants before it divides back (``M3 d^3`` in ``fast.roots``'
#: acceptance test, ``u^2 + 2 a g`` in ``fast.precise``, a double-double product's error
#: term), and a product of three values within ``1e+-100`` stays normal -- no overflow, no
#: underflow, no warning.  A physical scene in sensible units lies far inside.
FAST_MIN, FAST_MAX = 1e-100, 1e100
#: The smallest gap ``r - l`` relative to ``max(|l|, |r|)``: positions are float64, and the
#: loop takes a bounce below ``64 eps max(|l|, |r|)`` (``2^-46`` of it) as at float
#: resolution (``fast.handlers.chatter``); the gap must hold ``2^10`` of those.
MIN_RELATIVE_GAP = 2.0 ** -36
#: The shortest crossing of the gap from rest, ``sqrt(2 (r - l)/F)``, relative to ``T``: event
#: times are float64 in ``[0, T]``, resolved to ``eps T`` (``2^-52 T``); below it a flight
#: cannot be told from its start.  Measured: with ``(r - l) w^2/F`` down to 1e-35 (crossings of
#: 1e-18 T) every state finishes or exhausts its event budget; from 1e-40 the loop stalls.
MIN_CROSSING = 2.0 ** -52
#: The largest ``damping/omega``: the damped flights' derivative bounds grow like ``c^2`` (the
#: terminal speed ``(F + f)/c`` is reached in ``1/c << T``), so the certified steps shrink and a
#: flight needs more search rounds than ``fast.loop.MAX_SEGMENT_ROUNDS``.  Measured over gaps
#: 1e-3..1e3, ``f/F`` 0..0.9, ``e`` 0.5 and 1: every state finishes up to ``c/w = 57``; the
#: first stall is at 80.
MAX_DAMPING_RATIO = 32.0
#: The smallest nonzero ``damping/omega``: the damped flight's position carries the term
#: ``(c u - s f)(y - (1 - exp(-y)))/c^2``, ``y = c h``, from a double-double ``expm1`` good to
#: ~1e-21 relative, so below ``c T ~ 1e-16`` that term is lost.  Measured against the
#: reference (F = w = 1, f = 0.1): exact to 1e-15 down to ``c/w = 3e-16``; at 1e-17 a state
#: starting at rest ends 0.54 away.  ``2^-40`` (9e-13) keeps five decades of margin; a damping
#: that weak changes a period by less than 1e-11: give ``damping = 0``.
MIN_DAMPING_RATIO = 2.0 ** -40
#: The largest velocity scale ``(F + f)/omega`` of a damped scene: the damped event search
#: carries an event over at most ``0.5 (eps/M)^(1/3)`` (``fast.roots.bounds``, ``M >= F w^2``:
#: an absolute accuracy), which is ``0.08 (eps w/F)^(1/3) T`` and reaches float64's resolution
#: of ``T`` near ``F/w = 1e28`` (measured: the first stalls at 1e28..1e36).  1e20 keeps that
#: step 500 times above the resolution.
MAX_DAMPED_SPEED = 1e20


def check_ranges(scene: Scene, quantities) -> None:
    """``ValueError`` naming the first of ``quantities`` outside its bounds: each is ``(label,
    value, parameters, low, high[, why])``, an mpf ``value`` whose magnitude must be 0 or at
    least ``low`` (``None``: no lower bound) and at most ``high``; the message names the
    derived quantity, the scene parameters it comes from and why the bound is there."""
    for label, value, names, low, high, *why in quantities:
        size = abs(value)
        if high is not None and size > high:
            bound = f"above {high:.3g}"
        elif low is not None and size and size < low:
            bound = f"below {low:.3g}"
        else:
            continue
        given = ", ".join(f"{n} = {getattr(scene, n)!r:.60}" for n in names)
        raise ValueError(
            f"fast: {label} = {mpmath.nstr(value, 3)} (from {given}) is {bound}: "
            f"{why[0] if why else _WHY.get(label, _WHY[None])}; the reference runs this scene "
            f"(at enough dps)")


_WHY = {None: "the magnitudes fast holds are 0 and [1e-100, 1e100] (float64 with room for "
              "products of three: fast.params.FAST_MIN, FAST_MAX)",
        "(r - l)/max(|l|, |r|)": "float64 positions cannot resolve the gap between the walls "
                                 "(fast.params.MIN_RELATIVE_GAP)",
        "sqrt(2 (r - l)/F)/T": "a crossing of the gap is shorter than float64's resolution of "
                               "event times in a period (fast.params.MIN_CROSSING)",
        "damping/omega": "fast's damped flights hold for 2^-40 <= damping/omega <= 32 "
                         "(fast.params.MIN_DAMPING_RATIO, MAX_DAMPING_RATIO): weaker damping is "
                         "lost in their double-double terms (give damping = 0), stronger needs "
                         "too many certified search rounds per flight",
        "(F + f)/omega with damping": "the damped event search's accuracy is absolute and "
                                      "falls to the time resolution of a period "
                                      "(fast.params.MAX_DAMPED_SPEED)"}


def fast_quantities(scene: Scene, extra=()):
    """The parameters and the derived constants every ``fast`` engine uses (``check_ranges``'
    format) at the current mpmath precision, followed by ``extra``."""
    Fm, fm, wm, cd, em, lm, rm = (scene.mpf(k) for k in ("F", "f", "omega", "damping",
                                                          "restitution", "l", "r"))
    period, gap = 2 * mpmath.pi / wm, scene.gap()
    size = (FAST_MIN, FAST_MAX)
    out = [("F", Fm, ("F",), *size), ("f", fm, ("f",), *size), ("omega", wm, ("omega",), *size),
           ("damping", cd, ("damping",), *size), ("restitution", em, ("restitution",), *size),
           ("l", lm, ("l",), None, FAST_MAX), ("r", rm, ("r",), None, FAST_MAX),
           ("r - l", gap, ("l", "r"), *size),
           ("(r - l)/max(|l|, |r|)", gap / max(abs(lm), abs(rm)), ("l", "r"), MIN_RELATIVE_GAP, None),
           ("T = 2 pi/omega", period, ("omega",), *size), ("F + f", Fm + fm, ("F", "f"), *size),
           ("F omega", Fm * wm, ("F", "omega"), *size), ("f T", fm * period, ("f", "omega"), *size)]
    if Fm > 0:
        out.append(("sqrt(2 (r - l)/F)/T", mpmath.sqrt(2 * gap / Fm) / period,
                    ("l", "r", "F", "omega"), MIN_CROSSING, None))
    return out + list(extra)


@lru_cache(maxsize=256)
def params(scene: Scene) -> np.ndarray:
    """The constants of ``scene`` (closed-form flights: no position forcing) as ``P``."""
    check_scene(scene)
    if scene.has("position_forcing"):
        raise ValueError("fast.params: position forcing runs on fast.ode's numerical flights")
    P = np.zeros(SIZE)
    with mpmath.workdps(40):
        Fm, fm, wm, cd = (scene.mpf(k) for k in ("F", "f", "omega", "damping"))
        check_ranges(scene, fast_quantities(scene, _closed_form_quantities(Fm, fm, wm, cd)))
        exact = {F: Fm, FF: fm, W: wm, T: 2 * mpmath.pi / wm, DAMP: cd, FW: Fm / wm,
                 FW2: Fm / wm ** 2, PD: Fm * cd / (cd * cd + wm * wm),
                 QD: Fm * wm / (cd * cd + wm * wm), IW: 1 / wm}
        if cd > 0:
            exact.update({ID: 1 / cd, ID2: 1 / cd ** 2})
        ratio = fm / Fm if Fm > 0 else None
        if ratio is not None and 1 - ratio < STICK_EDGE:
            ratio = max(ratio, mpmath.mpf(1))   # slides too short for float64: sticks for good
        if ratio is not None and ratio < 1:
            alpha = mpmath.acos(ratio)
            exact.update({C: ratio, SA: mpmath.sin(alpha), B1: mpmath.pi - alpha,
                          B2: 2 * mpmath.pi - alpha})
            P[ALPHA] = float(alpha)
        else:
            P[C] = math.inf if ratio is None else float(ratio)
        for slot, value in exact.items():
            P[slot], P[slot + 1] = split_exact(value)
    P[L], P[R], P[E] = scene.float("l"), scene.float("r"), scene.float("restitution")
    _bounds(P)
    return P


def _closed_form_quantities(Fm, fm, wm, cd):
    """The closed-form loop's own derived constants (``check_ranges``' format): the flight
    coefficients, the event finder's bounds, the position scale of the noise floor, and with
    damping ``c/w``, ``1/c^2``, the terminal speed and ``Pd``, ``Qd``."""
    period, size = 2 * mpmath.pi / wm, (FAST_MIN, FAST_MAX)
    out = [("F/omega", Fm / wm, ("F", "omega"), *size),
           ("F/omega^2", Fm / wm ** 2, ("F", "omega"), *size),
           ("F omega^2", Fm * wm ** 2, ("F", "omega"), *size),
           ("f T^2", fm * period ** 2, ("f", "omega"), *size)]
    if cd > 0:
        den = cd * cd + wm * wm
        out += [("damping/omega", cd / wm, ("damping", "omega"), MIN_DAMPING_RATIO, MAX_DAMPING_RATIO),
                ("(F + f)/omega with damping", (Fm + fm) / wm, ("F", "f", "omega", "damping"),
                 None, MAX_DAMPED_SPEED),
                ("1/damping^2", 1 / cd ** 2, ("damping",), *size),
                ("(F + f)/damping", (Fm + fm) / cd, ("F", "f", "damping"), *size),
                ("F damping/(damping^2 + omega^2)", Fm * cd / den, ("F", "damping", "omega"), *size),
                ("F omega/(damping^2 + omega^2)", Fm * wm / den, ("F", "damping", "omega"), *size)]
    return out


def _bounds(P):
    """Derivative bounds, noise floors and the flags of the effects (module docstring)."""
    Fv, f, w, l, r, period = P[F], P[FF], P[W], P[L], P[R], P[T]
    tiny = 1e-300
    P[M1], P[M1_3] = max(Fv + f, tiny), max(Fv * w, tiny)
    P[M2], P[M2_3] = max(Fv * w, tiny), max(Fv * w * w, tiny)
    scale_x = max(abs(l), abs(r)) + Fv / w ** 2 + f * period * period
    P[NOISE1], P[NOISE2] = 16 * EPS * scale_x, 16 * EPS * (Fv / w + f * period)
    #: a root's state is carried by the local model of ``fast.precise`` over |d| <= d_acc:
    #: the omitted term |A''| d^3 / 6 <= F w^2 d^3 / 6 stays below eps max(1, 2^-20 F/w) / 48
    #: (eps/48 at the paper's velocity scales; relative to the velocity scale F/w where that is
    #: huge, else d_acc falls below the time resolution of T and no root is ever accepted: F =
    #: 1e27, w = 1e-9 ran into the loop bound); at most 2^-20 T (without forcing the model is
    #: exact, but an event is never moved across more)
    room = EPS * max(1.0, 2.0 ** -20 * (Fv / w))
    P[D_ACC] = min(0.5 * (room / max(Fv * w * w, tiny)) ** (1.0 / 3.0), 2.0 ** -20 * period)
    P[FRICTION] = float(f > 0)
    P[CHATTER] = float(f > 0 or P[E] < 1)
    P[XSCALE] = max(abs(l), abs(r))
