"""The compensated flights of ``fast.ode``: a double-double clock, the trigonometry of each
step's start, the event's state from a step onto it; around ``fast.dop853``'s compensated step.

Why (issue 33).  With the truncation of a step below float64's resolution, a flight's error
is its rounding, and over the ~130 steps of a period five roundings accumulated to 10-90
eps (``|fast - ref| / max(1, |ref|) / (eps max(1, |Phi'|))``, the golden tests' measure),
each found by removing it against the reference at 40 digits:

* the clock: ``t + h`` rounds to an ulp of ``t`` while the step integrated ``h``, so a flight
  drifted from its own clock by ``~sqrt(n) eps t / 2``, the state by that times its rate
  (the largest: ``F T`` mattered, not the step count);
* the phases ``w (t + c_i h)`` and ``k x`` rounded to an ulp of themselves, and ``F, f, c, k,
  w``, the period and the event times rounded to float64;
* the update ``y + dy`` rounded to an ulp of ``y``, and the weights ``b_i`` to float64 (they
  then sum to 1 only within ~eps);
* the stage accelerations' own roundings (libm's half ulp, the products), amplified by
  DOP853's weights (``||b||_2 = 7.6``): a random walk of ~1 eps per unit time;
* the event's state from the dense output (order 7: 20 eps off where ``F / Lambda^2 ~ 1``) and
  the end of a flight within ``4 eps t_end`` of ``t_end`` left unintegrated.

The clock: a flight's time is ``t + wk[TLO]`` with ``t = st[TT]`` (float64, what the event
loop reads and logs), the low part valid while ``wk[THI] == t`` -- a time set by the loop
(the exit time from rest, the end of a summed chatter tail) starts with low part 0.  A step
of length ``h`` advances it exactly (``fast.dd.two_sum``), an event at ``t + d`` keeps its
low part (the next flight starts where the last one ended), and a run ends at ``t_end +
wk[TEND_LO]`` (the period as a double-double: ``t_end_lo`` of ``fast.batch``'s engine
interface).  The state after an event keeps its low parts into the next flight (``begin``).

Each step's start: ``cos, sin`` of ``(w + w_lo)(t + TLO)`` and of ``(k + k_lo)(x + L0)`` as
double-doubles (``_trig``: reduced by ``2 pi``, ``fast.dd.sincos``, ~1e-22); the stages rotate
them by small angles (``fast.dop853``).

Cost (one run, 6 scenes x 2000 states, one thread, CPU time): 1.7 times the float64 engine's
per state-period (1.33 of it the steps, ``S = 128`` instead of 96); the Jacobian 1.25 times.
"""
from __future__ import annotations

import math

import numpy as np

from . import dd
from . import dop853 as dp
from .jit import kernel
from .params import EPS, TWO_PI_HI, TWO_PI_LO

#: work-buffer slots after ``fast.dop853``'s: the clock's high part and its low part, the
#: low part of the run's end time, and the state after the last event as double-doubles
THI, TLO, TEND_LO, EXH, EXL, EVH, EVL = range(dp.SIZE, dp.SIZE + 7)
SIZE = dp.SIZE + 7


@kernel
def reset(wk, t_end_lo):
    """A new state (or flight of ``fast.ode.flight``): no low part of the clock is valid, the
    run ends at ``t_end + t_end_lo``."""
    wk[THI], wk[EXH], wk[EVH] = math.nan, math.nan, math.nan
    wk[TEND_LO] = t_end_lo


@kernel
def begin(wk, t, P, slots):
    """A flight from the float64 state ``wk[Y0]`` at ``t``: the low part of ``x`` is the last
    event's if ``x`` is its position (a turn, or rest there since), else the wall's if ``x``
    is a wall (contact: fast's walls are ``l, r`` as float64); if ``t`` is the time the last
    flight reached (no rest in between), the clock's low part is kept, and so is that of
    ``v`` if ``v`` is the event's or its reflection ``-(e + e_lo) v`` (rounded; the rest goes
    into the low part); all other low parts are 0.  ``slots`` as in ``constants``."""
    cst = constants(P, slots)
    for m in range(6):
        wk[dp.L0 + m] = 0.0
    x = wk[dp.Y0]
    if x == wk[EXH]:
        wk[dp.L0] = wk[EXL]
    elif x == cst[12]:
        wk[dp.L0] = cst[13]
    elif x == cst[14]:
        wk[dp.L0] = cst[15]
    if wk[THI] != t:
        wk[THI], wk[TLO] = t, 0.0
        return
    v, e, e_lo = wk[dp.Y0 + 1], cst[10], cst[11]
    if v == wk[EVH]:
        wk[dp.L0 + 1] = wk[EVL]
    else:
        p, err = dd.two_prod(-e, wk[EVH])
        if v == p:
            wk[dp.L0 + 1] = err - (e * wk[EVL] + e_lo * wk[EVH])


@kernel
def length(h_max, t, t_end, wk):
    """``(h, last)``: the step, ``h_max``, or what is left to ``t_end + wk[TEND_LO]`` (``last``)
    where that is shorter or exceeds it by less than the time resolution ``4 eps |t_end|``
    (no step of a few ulp of ``t`` at the end: each is a full step of the flight)."""
    rh, rl = dd.add(t_end, wk[TEND_LO], -t, -wk[TLO])
    rem = rh + rl
    if h_max >= rem - 4.0 * EPS * abs(t_end):
        return rem, True
    return h_max, False


@kernel
def _trig(ah, al):
    """``(cos a, its low part, sin a, its low part)`` of the double-double ``a``, reduced by the
    nearest multiple of ``2 pi`` first (``fast.dd.sincos``: ~1e-22 absolute)."""
    j = np.rint(ah * (1.0 / TWO_PI_HI))
    nh, nl = dd.two_prod(j, TWO_PI_HI)
    rh, rl = dd.add(ah, al, -nh, -nl - j * TWO_PI_LO)
    rh, rl = dd.norm(rh, rl)
    sh, sl, ch, cl = dd.sincos(rh, rl)
    return ch, cl, sh, sl


@kernel
def constants(P, slots):
    """The scene's constants as double-doubles, ``(F, F_lo, f, f_lo, c, c_lo, k, k_lo, w, w_lo,
    e, e_lo, l, l_lo, r, r_lo)`` (the first ten are ``fast.dop853.rhs``' ``cst``), from the
    slots ``slots`` (in that order) of ``P``."""
    return (P[slots[0]], P[slots[1]], P[slots[2]], P[slots[3]], P[slots[4]], P[slots[5]],
            P[slots[6]], P[slots[7]], P[slots[8]], P[slots[9]], P[slots[10]], P[slots[11]],
            P[slots[12]], P[slots[13]], P[slots[14]], P[slots[15]])


@kernel
def step(P, slots, s, t, h, wk, n, dense):
    """``fast.dop853.step`` from the clock ``t + wk[TLO]`` and the state ``wk[Y0] + wk[L0]``,
    with the trigonometry of ``w t`` and ``k x`` there in double-double (``fast.dop853.TRIG``)."""
    cst = constants(P, slots)
    ph, pl = dd.mul(cst[8], cst[9], t, wk[TLO])
    wk[dp.CW], wk[dp.CWL], wk[dp.SW], wk[dp.SWL] = _trig(ph, pl)
    kh, kl = dd.mul(cst[6], cst[7], wk[dp.Y0], wk[dp.L0])
    wk[dp.CK], wk[dp.CKL], wk[dp.SK], wk[dp.SKL] = _trig(kh, kl)
    dp.step(cst, s, h, wk, n, dense)


@kernel
def event(wk, t, d, h, n, wall, wall_lo, at_wall):
    """The event that the search found at ``t + d`` on the dense output, after a ``step`` of
    length ``d`` with ``dense`` from the same start (order 8, compensated: the dense output
    is of order 7, 20 eps off at ``F/Lambda^2 ~ 1``) and its rate at the end (the first dense
    stage): one Newton step of the event's time, ``dt = (W - x)/v`` at the wall ``W = wall +
    wall_lo``, ``-v/a`` at a velocity zero (none where it exceeds ``2^-20 h``: a tangency).
    ``wk[Y0]`` gets the state there (``x = wall`` or ``v = 0``), ``EXH .. EVL`` the same as
    double-doubles; returns the time's high part (``at``)."""
    v, a = wk[dp.Y1 + 1] + wk[dp.L1 + 1], wk[dp.K + 6 * dp.NS + 1]
    dt = ((wall - wk[dp.Y1]) + (wall_lo - wk[dp.L1])) / v if at_wall else -v / a
    if not abs(dt) <= 2.0 ** -20 * h:
        dt = 0.0
    for m in range(n):                              # (the flight matrix moved by dt as well)
        wk[dp.Y0 + m] = wk[dp.Y1 + m] + (wk[dp.L1 + m] + wk[dp.K + 6 * dp.NS + m] * dt)
    if at_wall:
        wk[EXH], wk[EXL] = wall, wall_lo
        wk[EVH], wk[EVL] = dd.two_sum(wk[dp.Y1 + 1], wk[dp.L1 + 1] + a * dt)
    else:
        wk[EXH], wk[EXL] = dd.two_sum(wk[dp.Y1], wk[dp.L1] + v * dt)
        wk[EVH], wk[EVL] = 0.0, 0.0
    wk[dp.Y0], wk[dp.Y0 + 1] = wk[EXH], wk[EVH]
    return at(wk, t, d + dt)


@kernel
def at(wk, t, d):
    """The clock moved to ``t + wk[TLO] + d``: returns its high part (``wk[THI]``)."""
    hi, lo = dd.two_sum(t, d)
    hi, lo = dd.fast_two_sum(hi, lo + wk[TLO])
    wk[THI], wk[TLO] = hi, lo
    return hi


@kernel
def advance(wk, t, h, last, t_end, n):
    """Accept the step: ``Y0 + L0 <- Y1 + L1``, the clock ``+ h`` (``t_end + TEND_LO`` after
    the last step).  Returns the new ``t``."""
    for m in range(n):
        wk[dp.Y0 + m], wk[dp.L0 + m] = wk[dp.Y1 + m], wk[dp.L1 + m]
    if last:
        wk[THI], wk[TLO] = t_end, wk[TEND_LO]
        return t_end
    return at(wk, t, h)
