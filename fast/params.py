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
          "FRICTION CHATTER XSCALE IW IW_LO ID ID_LO ID2 ID2_LO U_CHATTER").split()
(F, F_LO, FF, FF_LO, W, W_LO, L, R, T, T_LO, E, DAMP, DAMP_LO, PD, PD_LO, QD, QD_LO, C, C_LO,
 ALPHA, SA, SA_LO, B1, B1_LO, B2, B2_LO, FW, FW_LO, FW2, FW2_LO, M1, M1_3, M2, M2_3, NOISE1,
 NOISE2, D_ACC, FRICTION, CHATTER, XSCALE, IW, IW_LO, ID, ID_LO, ID2, ID2_LO,
 U_CHATTER) = range(len(_NAMES))
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


@lru_cache(maxsize=256)
def params(scene: Scene) -> np.ndarray:
    """The constants of ``scene`` (closed-form flights: no position forcing) as ``P``."""
    check_scene(scene)
    if scene.has("position_forcing"):
        raise ValueError("fast.params: position forcing runs on fast.ode's numerical flights")
    P = np.zeros(SIZE)
    with mpmath.workdps(40):
        Fm, fm, wm, cd = (scene.mpf(k) for k in ("F", "f", "omega", "damping"))
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


def _bounds(P):
    """Derivative bounds, noise floors and the flags of the effects (module docstring)."""
    Fv, f, w, l, r, period = P[F], P[FF], P[W], P[L], P[R], P[T]
    tiny = 1e-300
    P[M1], P[M1_3] = max(Fv + f, tiny), max(Fv * w, tiny)
    P[M2], P[M2_3] = max(Fv * w, tiny), max(Fv * w * w, tiny)
    scale_x = max(abs(l), abs(r)) + Fv / w ** 2 + f * period * period
    P[NOISE1], P[NOISE2] = 16 * EPS * scale_x, 16 * EPS * (Fv / w + f * period)
    #: a root's state is carried by the local model of ``fast.precise`` over |d| <= d_acc:
    #: the omitted term |A''| d^3 / 6 <= F w^2 d^3 / 6 stays below eps / 48; at most 2^-20 T
    #: (without forcing the model is exact, but an event is never moved across more)
    P[D_ACC] = min(0.5 * (EPS / max(Fv * w * w, tiny)) ** (1.0 / 3.0), 2.0 ** -20 * period)
    P[FRICTION] = float(f > 0)
    P[CHATTER] = float(f > 0 or P[E] < 1)
    P[XSCALE] = max(abs(l), abs(r))
    P[U_CHATTER] = chatter_speed(Fv, f, w, period, P[XSCALE])


def chatter_speed(F, f, w, period, xscale):
    """A speed above which no impact starts a summed chatter tail (``fast.handlers.chatter``
    rejects it), so that the common impact skips that test: after an impact leaving with speed
    ``u`` against a push ``p = s A`` in ``(f, F]``, the bounce height ``u^2 / (2 (p + f)) >=
    u^2 / (2 (F + f))`` and the tail's error bound ``min(2 F w d^2, 2 F w^2 (7 d / 8)^3) / (p -
    f)`` with ``d = u / (p + f) >= u / (F + f)`` and ``p - f <= F - f`` exceed their thresholds
    ``64 eps xscale`` and ``4 eps T`` once ``u`` passes each of three speeds; the largest,
    doubled (the thresholds then hold with a factor 4 to spare for rounding), is returned.
    ``inf`` where the forcing never pushes (``F w = 0``: the tail's bound is 0), 0 where it
    never beats the friction (``F <= f``: no push ``p > f`` exists)."""
    if not F > f:
        return 0.0
    Fw = F * w
    if not Fw > 0.0:
        return math.inf
    thr = 4 * EPS * period * (F - f)
    u_res = math.sqrt(2.0 * (F + f) * 64 * EPS * xscale)
    u_sq = (F + f) * math.sqrt(thr / (2.0 * Fw))
    u_cube = (F + f) / 0.875 * (thr / (2.0 * Fw * w)) ** (1.0 / 3.0)
    return 2.0 * max(u_res, u_sq, u_cube)
