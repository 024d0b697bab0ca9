"""The parameter vector ``P`` of ``fast.ode``'s compiled flights (position-dependent forcing):
its slots, ``params(scene)`` (each constant a double-double, read at 40 digits), the steps per
period ``S`` (``STEPS_PER_PERIOD``, ``with_steps``) and the largest speed the engine takes
(``max_speed``), with the range checks of ``fast.params``.
"""
from __future__ import annotations

import numpy as np

from .dd import split_exact
from .params import FAST_MAX, FAST_MIN, check_ranges, check_scene, fast_quantities

STEPS_PER_PERIOD = 128
#: slots of P
F, FF, DAMP, K, W, E, L, R, T, T_LO, K_LO, W_LO, F_LO, FF_LO, DAMP_LO, E_LO, L_LO, R_LO, XS, SPP = range(20)
SIZE = 20
#: the flight's constants and their low parts, in ``fast.compensated.constants``' order
DD_SLOTS = (F, F_LO, FF, FF_LO, DAMP, DAMP_LO, K, K_LO, W, W_LO, E, E_LO, L, L_LO, R, R_LO)


class _Slots:
    """The ``params`` slots by name, for callers that read ``P[engine.p.T]``."""

    T, T_LO, L, R = T, T_LO, L, R


p = _Slots


def params(scene):
    """``P``: ``F, f, c, k, w, e, l, r`` and the period ``T = 2 pi / w`` as double-doubles (``F + F_LO``, ..., read at 40 digits: ``fast.compensated``), after the
    range check of ``fast.params.check_ranges`` (``ValueError`` naming what float64 cannot
    hold)."""
    import mpmath

    check_scene(scene)
    with mpmath.workdps(40):
        check_ranges(scene, fast_quantities(scene, _quantities(scene)))
        period = 2 * mpmath.pi / scene.mpf("omega")
    P = np.zeros(SIZE)
    with mpmath.workdps(40):
        P[T], P[T_LO] = split_exact(period)
        for slot, lo, name in ((F, F_LO, "F"), (FF, FF_LO, "f"), (DAMP, DAMP_LO, "damping"),
                               (K, K_LO, "wavenumber"), (W, W_LO, "omega"), (E, E_LO, "restitution"),
                               (L, L_LO, "l"), (R, R_LO, "r")):
            P[slot], P[lo] = split_exact(scene.mpf(name) or mpmath.mpf(0))
    P[XS] = max(abs(P[L]), abs(P[R]), P[R] - P[L])     # the positions' scale (their float resolution)
    P[SPP] = STEPS_PER_PERIOD
    return P


def with_steps(P, steps):
    """A copy of ``P`` whose flights take ``S = steps`` steps per unit of ``2 pi / Lambda``
    (``_step_len``): the truncation grows like ``(STEPS_PER_PERIOD / S)^8`` from float64's
    floor, the cost falls like ``S`` (``fast.api``'s ``steps_per_period``)."""
    out = P.copy()
    out[SPP] = steps
    return out


#: The most fixed steps a period may need at rest, ``S max(w, sqrt(F k), c, sqrt((F + f)/X))/w``
#: (``_step_len``): a step must stay far above float64's resolution of times in ``[0, T]``
#: (``eps T``, 2^-52 T; a step below it is skipped as "below resolution"), and 2^30 steps are
#: already over six times the default event budget (1e7 events of 16 steps).
MAX_STEPS_PER_PERIOD = 2.0 ** 30


def max_speed(P) -> float:
    """The largest ``|v|`` of a start this engine takes (``fast.api``): a flight steps
    ``2 pi/(S k |v|)`` at speed ``|v|``, and a period may take at most ``MAX_STEPS_PER_PERIOD``
    steps, so ``|v| <= MAX_STEPS_PER_PERIOD w/(S k)`` (~1.1e7 w/k: more steps than the default
    event budget runs; far below, the step resolves times in ``[0, T]``), and ``FAST_MAX``."""
    return min(FAST_MAX, MAX_STEPS_PER_PERIOD * P[W] / (STEPS_PER_PERIOD * P[K])) if P[K] > 0 else FAST_MAX


def _quantities(scene):
    """This engine's derived constants (``fast.params.check_ranges``' format): the
    wavenumber, the phase ``k max(|l|, |r|)`` of ``cos(k x)``, the rate ``F k`` of the
    bounds, the steps per period at rest, and with damping the terminal speed ``(F + f)/c``."""
    import mpmath

    size = (FAST_MIN, FAST_MAX)
    Fm, fm, cd, wm = (scene.mpf(k) for k in ("F", "f", "damping", "omega"))
    km = scene.mpf("wavenumber") or mpmath.mpf(0)
    xmax = max(abs(scene.mpf("l")), abs(scene.mpf("r")))
    reach = mpmath.sqrt((Fm + fm) / max(1, xmax))
    steps = STEPS_PER_PERIOD * max(wm, mpmath.sqrt(Fm * km), cd, reach) / wm
    out = [("wavenumber", km, ("wavenumber",), *size),
           ("wavenumber max(|l|, |r|)", km * xmax, ("wavenumber", "l", "r"), None, FAST_MAX),
           ("F wavenumber", Fm * km, ("F", "wavenumber"), *size),
           ("steps per period", steps, ("F", "f", "wavenumber", "damping", "omega", "l", "r"),
            None, MAX_STEPS_PER_PERIOD, "fast.ode's fixed steps would fall toward the float64 "
            "resolution of times in a period (fast.ode.MAX_STEPS_PER_PERIOD)")]
    if cd > 0:
        out.append(("(F + f)/damping", (Fm + fm) / cd, ("F", "f", "damping"), *size))
    return out
