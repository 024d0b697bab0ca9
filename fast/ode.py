"""Numerical flights under position-dependent forcing, compiled: ``fast.batch``'s second engine.

The forcing ``F cos(k x) cos(w t)`` (the paper's last section, eq. ``xpot``: ``k = pi/2``)
has no closed-form flight; ``fast.api`` routes such scenes here (the only path to a
numerical ODE solver).  A flight is integrated by fixed DOP853 steps (``fast.dop853``) of
length ``h = 2 pi / (S Lambda)``, ``Lambda = max(w, k |v|, sqrt(F k), c)`` at the step start,
the last one ending at ``t_end``; ``S = STEPS_PER_PERIOD`` (a search may ask for fewer:
``fast.api``'s ``steps_per_period``, the slot ``SPP`` of ``P``).  The steps are compensated
(``fast.compensated``, issue 33): the state, the clock, the period, the parameters and the
trigonometry of each step's start are double-doubles, each stage's acceleration carries its
own rounding, and an event's state comes from a step onto it plus one Newton step of its
time; so the one-period error is that of float64 rounding, not of its accumulation over the
~100 steps of a period.  Measured against the reference at 40 digits as ``|fast - ref| /
max(1, |ref|) / (eps max(1, |Phi'|))`` (``golden_fast_phi_per_cond``'s measure; eps =
2^-52): with ``S = 96`` and float64 steps mean 13 / max 208 over 40 random position-forced
scenes x 8 states (0.87 / 1.8 on ``fig:xpotno``); compensated, 0.21 / 1.5 (0.08 / 0.23), the
closed-form loop's standard.  ``S``: the truncation reaches that floor at ``S = 128`` (``S =
96``: mean 0.40, max 10 where the forcing's amplitude ``F / Lambda^2`` exceeds the gap; 160
and 256 change nothing).

Events (the first of them in a step): the wall ``g = s (W_s - x)`` and the velocity ``g = s v``,
both positive before their event.  Root exclusion per step: with ``M >= |g''| h^2`` over the
step (``|x''| <= F + f + c vmax``, ``|v''| <= F w + F k vmax + c amax``, ``vmax`` from ``d|v|/dt
<= F + f + c |v|``), ``g(theta) >= g(0) + g'(0) theta - M theta^2/2``: a step with that
minorant positive at ``theta = 1`` has no root.  Flagged steps are cut into ``SUBDIV``
pieces of the dense output, each with the same test; a sign change is bracketed and
polished by safeguarded Newton (bisection when Newton leaves the bracket); a piece
without one whose test fails, and which rises above ``TANGENT_FLOOR`` (times the scale) at
an end, is searched for a close pair or a tangency by golden section for the minimum of
``g``: below minus the floor -- or below zero from a start above the floor -- the first
root lies between the piece's start and the minimum; otherwise within the floor the minimum is
the (tangential) root.  (A dip below zero but within the floor is a close pair too: taking its
minimum for the root put the impact half the pair's width late, 1.5e-7 at a depth of 1.2e-14
on a constructed crossing pair; its first root is as well conditioned as the dip.)  (A piece flat at noise
level -- a flight leaving rest under a force of rounding size -- has no dip to find.)

The event loop: impacts (``v -> -e v``, Table 1's matrix with ``A = A(W, t*)``), turns
(``s A < -f``) and sticking, wall contact, and the closed-form exit times of rest for the
amplitude ``F cos(k x)`` of the resting position (``first_above``); a run of impacts at a
wall the force pushes into is summed by ``chatter_tail`` (frozen force, geometric series)
once its neglected variation is below float resolution.  Frictionless scenes pass
through ``v = 0`` (a sign flip, no event).  Every loop is bounded; 16 steps count as one
event against ``max_events``.
"""
from __future__ import annotations

import math

import numpy as np

from . import batch
from . import compensated as cs
from . import dop853 as dp
from . import state as q
from .dd import split_exact
from .jit import data_pointer, kernel
from .output import out_of_events, record, store
from .params import FAST_MAX, FAST_MIN, check_ranges, check_scene, fast_quantities

EPS = 2.0 ** -52
SUBDIV = 8
NEWTON_ITERS = 60
GOLDEN_ITERS = 40
TANGENT_FLOOR = 64 * EPS
STEPS_PER_PERIOD = 128
#: steps that count as one event against the budget
STEPS_PER_EVENT = 16
OK, LOOP_BOUND, NON_FINITE = batch.OK, batch.LOOP_BOUND, batch.NON_FINITE
#: slots of P
F, FF, DAMP, K, W, E, L, R, T, T_LO, K_LO, W_LO, F_LO, FF_LO, DAMP_LO, E_LO, L_LO, R_LO, XS, SPP = range(20)
SIZE = 20
#: the flight's constants and their low parts, in ``fast.compensated.constants``' order
DD_SLOTS = (F, F_LO, FF, FF_LO, DAMP, DAMP_LO, K, K_LO, W, W_LO, E, E_LO, L, L_LO, R, R_LO)
#: modes of the loop, and the event codes of a flight
FLIGHT, STICK, CONTACT = 0, 1, 2
NO_EVENT, WALL, VZERO, TOO_FAST = 0, 1, 2, -2


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


# --- the flight: steps, and the certified first event on the dense output ----------------
@kernel(inline=True)
def _force(P, x, t):
    return P[F] * math.cos(P[K] * x) * math.cos(P[W] * t)


@kernel(inline=True)
def _g(P, s, wall, t, x, v, which):
    """Event function ``which`` (0: wall, 1: velocity) and its time derivative."""
    if which == 0:
        return s * (wall - x), -s * v
    return s * v, s * (_force(P, x, t) - s * P[FF] - P[DAMP] * v)


@kernel(inline=True)
def _step_len(P, av):
    """``h = 2 pi / (S Lambda)``, ``Lambda = max(w, k |v|, sqrt(F k), c, sqrt((F + f) / X))``:
    the fastest of the forcing, the phase rate of ``cos(k x)``, the linearised ``x'' = F cos(k
    x)``, damping, and the forcing's reach against the scale ``X = max(1, |l|, |r|)`` of ``x``
    (the position's truncation ``~ (h w)^7 h^2 (F + f)`` is measured relative to ``X``: with
    ``F / w^2 >> X`` -- flights between walls far shorter than a period -- ``h w`` alone lost
    up to 3 eps a period at ``S = 128``, issue 33)."""
    reach = math.sqrt((P[F] + P[FF]) / max(max(1.0, abs(P[L])), abs(P[R])))
    lam = max(max(P[W], P[K] * av), max(max(math.sqrt(P[F] * P[K]), P[DAMP]), reach))
    return 2 * math.pi / (P[SPP] * lam)


@kernel(inline=True)
def _bounds(P, av, h):
    """``(max |x''|, max |v''|)`` over a step of length ``h`` from speed ``av``."""
    Ff, c = P[F] + P[FF], P[DAMP]
    vmax = (av + Ff / c) * math.exp(c * h) - Ff / c if c > 0.0 else av + Ff * h
    amax = Ff + c * vmax
    return amax, P[F] * P[W] + P[F] * P[K] * vmax + c * amax


@kernel(inline=True)
def _g_at(P, s, wall, t, h, wk, n, which, theta):
    """Event function ``which`` on the dense output at ``theta``: ``(g, dg/dtheta)``."""
    dp.dense_eval(wk, theta, n)
    g, dg = _g(P, s, wall, t + theta * h, wk[dp.YD], wk[dp.YD + 1], which)
    return g, dg * h


@kernel
def _newton_bisect(P, s, wall, t, h, wk, n, which, lo, hi):
    """Root in ``[lo, hi]`` of a function with ``g(lo) > 0 >= g(hi)``: Newton from the middle,
    bisection whenever Newton leaves the shrinking bracket (bounded by ``NEWTON_ITERS``)."""
    th = 0.5 * (lo + hi)
    for _ in range(NEWTON_ITERS):
        g, dg = _g_at(P, s, wall, t, h, wk, n, which, th)
        if g == 0.0:
            return th
        if g > 0.0:
            lo = th
        else:
            hi = th
        nt = th - g / dg if dg != 0.0 else math.nan
        if not (lo < nt < hi):
            nt = 0.5 * (lo + hi)
        if abs(nt - th) <= 2 * EPS * abs(th) or hi - lo <= 4 * EPS * abs(hi):
            return nt
        th = nt
    return hi


@kernel
def _golden_min(P, s, wall, t, h, wk, n, which, lo, hi):
    """The minimiser of ``g`` on ``[lo, hi]`` by golden section: ``(theta, g_min)``."""
    r = (math.sqrt(5.0) - 1.0) / 2.0
    a, b = lo, hi
    for _ in range(GOLDEN_ITERS):
        c1, c2 = b - r * (b - a), a + r * (b - a)
        if _g_at(P, s, wall, t, h, wk, n, which, c1)[0] <= _g_at(P, s, wall, t, h, wk, n, which, c2)[0]:
            b = c2
        else:
            a = c1
    th = 0.5 * (a + b)
    return th, _g_at(P, s, wall, t, h, wk, n, which, th)[0]


@kernel
def _first_root(P, s, wall, t, h, wk, n, which, M, g0, d0, floor):
    """``theta`` of the earliest root of event ``which`` in ``(0, 1]`` (``inf``: none), on
    ``SUBDIV`` pieces of the dense output (module docstring)."""
    d = 1.0 / SUBDIV
    for j in range(SUBDIV):
        g1, d1 = _g_at(P, s, wall, t, h, wk, n, which, (j + 1) * d)
        if not (g0 >= 0.0 and g0 + d0 * d - M * d * d / 2 > 0.0):
            if g1 <= 0.0:                             # a sign change: bracketed
                return _newton_bisect(P, s, wall, t, h, wk, n, which, j * d, (j + 1) * d)
            if not max(g0, g1) > floor:
                g0, d0 = g1, d1                       # flat at noise level: no dip to find
                continue
            th, gmin = _golden_min(P, s, wall, t, h, wk, n, which, j * d, (j + 1) * d)
            if th > 1e-6 and (gmin < -floor or (gmin < 0.0 and g0 > floor)):
                return _newton_bisect(P, s, wall, t, h, wk, n, which, j * d, th)  # a close pair: its first root
            if th > 1e-6 and abs(gmin) <= floor:      # a tangential zero
                return th
        g0, d0 = g1, d1
    return math.inf


@kernel
def _fly(P, st, wk, t_end, n, max_steps):
    """Integrate the flight from ``(st[TT], wk[Y0])`` with sign ``st[S]`` to its first event
    or ``t_end``: returns ``(code, steps)`` with the time reached in ``st[TT]`` and the state
    there in ``wk[Y0]`` (``x = W`` at a wall event, ``v = 0`` at a velocity zero); code
    ``-1``: ``max_steps`` exhausted; ``TOO_FAST``: the step ``2 pi/(S k |v|)`` fell below
    the resolution of the double-double clock at ``t_end`` (``4 eps^2 |t_end|``: no step would
    move it; with a float64 clock such a step was taken as the end of the flight and the
    state came back unchanged, ``|v| = 1e50`` under ``k = 1``)."""
    s = st[q.S]
    wall = P[R] if s > 0.0 else P[L]
    xs = max(1.0, abs(wall))
    no_v = P[F] == 0.0 and P[FF] == 0.0            # no force: v never changes sign
    cs.begin(wk, st[q.TT], P, DD_SLOTS)
    for k in range(max_steps):
        t = st[q.TT]
        x, v = wk[dp.Y0], wk[dp.Y0 + 1]
        step = _step_len(P, abs(v))
        if not step > 4 * EPS * EPS * abs(t_end):       # below the double-double clock's resolution
            return TOO_FAST, k
        h, last = cs.length(step, t, t_end, wk)
        if not h > 0.0:                                 # nothing is left (the clock is exact)
            st[q.TT] = t_end
            return NO_EVENT, k
        gw, dgw = _g(P, s, wall, t, x, v, 0)
        gv, dgv = _g(P, s, wall, t, x, v, 1)
        mx, mv = _bounds(P, abs(v), h)
        safe = (gw >= 0.0 and gw + dgw * h - mx * h * h / 2 > 0.0) and (no_v or (
            gv >= 0.0 and gv + dgv * h - mv * h * h / 2 > 0.0))
        cs.step(P, DD_SLOTS, s, t, h, wk, n, not safe)
        th, thw, thv = math.inf, math.inf, math.inf
        if not safe:
            thw = _first_root(P, s, wall, t, h, wk, n, 0, mx * h * h, gw, dgw * h, TANGENT_FLOOR * xs)
            if not no_v:
                thv = _first_root(P, s, wall, t, h, wk, n, 1, mv * h * h, gv, dgv * h,
                                  TANGENT_FLOOR * max(1.0, abs(v)))
            th = min(thw, thv)
        if th < math.inf:
            cs.step(P, DD_SLOTS, s, t, th * h, wk, n, True)       # the event's state: a step
            wall_lo = P[R_LO] if s > 0.0 else P[L_LO]
            st[q.TT] = cs.event(wk, t, th * h, h, n, wall, wall_lo, thw <= thv)
            return (WALL if thw <= thv else VZERO), k + 1
        st[q.TT] = cs.advance(wk, t, h, last, t_end, n)
        if last:
            return NO_EVENT, k + 1
    return -1, max_steps


#: phases (radians) of a closing window of ``first_above`` too short to leave rest in
SLIVER = 16 * EPS * 2 * math.pi


@kernel(inline=True)
def first_above(amp, level, w, t):
    """First ``tau >= t`` with ``amp cos(w tau) > level`` on a right-neighbourhood (``inf`` if
    ``|amp| <= level``): with ``alpha = arccos(level/|amp|)`` and the phase ``phi = (w t + (0
    if amp > 0 else pi)) mod 2 pi`` the set is ``(-alpha, alpha) mod 2 pi``; ``phi >= 2 pi -
    alpha`` is the rising crossing (leave now), ``phi = alpha`` the falling one.  A window
    closing within ``SLIVER`` of ``phi`` is no window: its rounding decides nothing, and the
    flight out of it would stop at once (the excess of the force over the level, ``< F w
    SLIVER``, moves the mass by ~1e-40 before it falls below): the next rising crossing.
    Leaving "now" there made stick, slip and stick again at one instant until the loop bound
    (a constructed turn at ``|A| = f`` on fig:xpotno)."""
    if not abs(amp) > level:
        return math.inf
    alpha = math.acos(level / abs(amp))
    phi = (w * t + (0.0 if amp > 0.0 else math.pi)) % (2 * math.pi)
    if phi >= 2 * math.pi - alpha or phi < alpha - SLIVER:
        return t
    return t + (2 * math.pi - alpha - phi) / w


@kernel(inline=True)
def _times(st, a11, a12, a21, a22):
    """``J <- M J`` with ``M = [[a11, a12], [a21, a22]]``."""
    j11, j12, j21, j22 = st[q.J11], st[q.J12], st[q.J21], st[q.J22]
    st[q.J11], st[q.J12] = a11 * j11 + a12 * j21, a11 * j12 + a12 * j22
    st[q.J21], st[q.J22] = a21 * j11 + a22 * j21, a21 * j12 + a22 * j22


@kernel
def chatter_tail(P, push, u):
    """Frozen-force tail of a run of impacts after one with speed ``u`` leaving the wall,
    ``push = side A > f`` the force into it: out with deceleration ``push + f``, back with
    ``push - f``, return speed ``q u``, ``q = sqrt((push - f)/(push + f))``, ratio ``rho = e
    q``; the bounces last ``u tau rho^j``, ``tau = (1 + 1/q)/(push + f)``, so the run ends
    after ``Delta = u tau / (1 - rho)``, ``1 - rho = (1 - e) + 2 e f/((push + f)(1 + q))``.
    Over ``Delta`` the force moves by ``<= (F w + F k u) Delta`` and damping adds ``c u``:
    ``err = 2 Delta (F w Delta + F k u Delta + c u)/(push - f)`` bounds the neglected part.
    Returns ``(Delta, err)`` (``inf`` where ``rho = 1``: no accumulation)."""
    f, e = P[FF], P[E]
    qq = math.sqrt((push - f) / (push + f))
    one_m = (1.0 - e) + e * 2.0 * f / ((push + f) * (1.0 + qq))
    if not one_m > 0.0:
        return math.inf, math.inf
    delta = u * (1.0 + 1.0 / qq) / (push + f) / one_m
    err = 2.0 * delta * (P[F] * P[W] * delta + P[F] * P[K] * u * delta + P[DAMP] * u) / (push - f)
    return delta, err


# --- the event loop ---------------------------------------------------------------------
@kernel
def _impact(P, st, ev, t, vb, t_end, jac):
    """A wall event with velocity ``vb`` towards the wall ``s``.  Returns ``(mode, t)``:
    ``FLIGHT`` away from the wall, or ``CONTACT`` (a graze, ``e = 0`` held by the force, or a
    summed chatter tail, whose accumulation time is returned).  A run of impacts that cannot be
    summed yet (or ever: no friction and ``e = 1`` give ``rho = 1``) goes on bounce by bounce,
    each an event within ``max_events`` (``fast.output.out_of_events`` names such a run when
    the budget runs out; an earlier cap of 5000 bounces ended elastic bounces at a gap of 1e-12,
    millions a period, as a loop bound)."""
    s, e, f = st[q.S], P[E], P[FF]
    wall = P[R] if s > 0.0 else P[L]
    A = _force(P, wall, t)
    tiny_v = 16 * EPS * (P[F] / P[W] + (P[R] - P[L]) * P[W] + f * P[T])
    chn = st[q.CHN]
    st[q.CHN] = chn + s if chn != 0.0 and (chn > 0.0) == (s > 0.0) else s
    st[q.S] = -s
    if abs(vb) <= tiny_v:                           # a graze: at rest on the wall reached
        record(ev, st, q.K_CONTACT, t, wall, 0.0, vb, 0)
        return _rest_on(P, st, jac, s), t
    record(ev, st, q.K_IMPACT, t, wall, -e * vb, vb, 0)
    if e == 0.0 and s * A >= -f:                    # at rest, held against the wall
        record(ev, st, q.K_CONTACT, t, wall, 0.0, 0.0, 0)
        return _rest_on(P, st, jac, s), t
    if s * A > f and e > 0.0:
        u = e * abs(vb)
        delta, err = chatter_tail(P, s * A, u)
        # as in the closed-form loop (fast.handlers.chatter): a bounce at float resolution of
        # the positions is summed whatever the estimate (which falls like delta^2 and would
        # reach a few ulp only at bounces ~1e-18 high: a turn within 16 eps of the wall ended
        # the run as a contact first, without its tail, 3e-7 early on scenes A and B of issue 33)
        at_resolution = u * u / (2.0 * (s * A + f)) <= 64 * EPS * P[XS]
        if (err <= EPS * max(1.0, abs(t_end)) or at_resolution) and t + delta <= t_end:
            st[q.PATHS] = float(int(st[q.PATHS]) | q.PATH_CHATTER)
            record(ev, st, q.K_CHATTER, t + delta, wall, 0.0, 0.0, int(abs(st[q.CHN])))
            return _rest_on(P, st, jac, s), t + delta
    if jac:
        _times(st, -e, 0.0, ((1.0 + e) * A + (1.0 - e) * s * f) / vb, -e)
    return FLIGHT, t


@kernel(inline=True)
def _rest_on(P, st, jac, side):
    """At rest on wall ``side`` (the contact matrix: ``Phi'`` is zero)."""
    st[q.ZV] = 1.0
    st[q.CHN] = 0.0
    st[q.S] = side                                  # the wall's side while in contact
    st[q.PATHS] = float(int(st[q.PATHS]) | q.PATH_WALL)
    if jac:
        _times(st, 0.0, 0.0, 0.0, 0.0)
    return CONTACT


@kernel
def _velocity_zero(P, st, ev, t, x, jac):
    """``v = 0`` in flight: rest on a wall reached at zero speed, a smooth reversal (``f =
    0``), a turn (``s A < -f``) or sticking.  Returns the new mode."""
    s, f = st[q.S], P[FF]
    st[q.ZV] = 1.0
    tiny_x = 16 * EPS * P[XS]
    for side in (1.0, -1.0):
        if abs(x - (P[R] if side > 0.0 else P[L])) <= tiny_x:
            record(ev, st, q.K_CONTACT, t, P[R] if side > 0.0 else P[L], 0.0, 0.0, 0)
            return _rest_on(P, st, jac, side)
    A = _force(P, x, t)
    if f == 0.0:
        st[q.S] = 1.0 if A >= 0.0 else -1.0
        return FLIGHT
    st[q.PATHS] = float(int(st[q.PATHS]) | q.PATH_FRICTION)
    if s * A < -f:
        record(ev, st, q.K_TURN, t, x, 0.0, 0.0, 0)
        st[q.S] = -s
        if jac:
            _times(st, 1.0, 0.0, 0.0, (abs(A) - f) / (abs(A) + f))
        return FLIGHT
    record(ev, st, q.K_STICK, t, x, 0.0, 0.0, 0)
    st[q.CHN] = 0.0
    if jac:
        _times(st, 1.0, 0.0, 0.0, 0.0)
    return STICK


@kernel
def _leave_rest(P, st, ev, mode, t, x, t_end):
    """Sticking at ``x``, or contact with wall ``st[S]``: the closed-form exit time for the
    amplitude ``F cos(k x)`` of the resting position.  Returns the time of leaving (a
    flight from rest with its sign in ``st[S]``) or ``inf`` (rest to the end)."""
    amp = P[F] * math.cos(P[K] * x)
    if mode == CONTACT:
        side = st[q.S]
        t_next, s_next, kind = first_above(-side * amp, P[FF], P[W], t), -side, q.K_RELEASE
    else:
        up, down = first_above(amp, P[FF], P[W], t), first_above(-amp, P[FF], P[W], t)
        t_next, s_next, kind = min(up, down), (1.0 if up <= down else -1.0), q.K_SLIP
    if not t_next <= t_end:
        return math.inf
    record(ev, st, kind, t_next, x, 0.0, 0.0, 0)
    st[q.S] = s_next
    return t_next


@kernel
def _start(P, st, ev, x, v, t_end, jac):
    """The state at ``t = 0``: ``(mode, t, x, v)`` after any event there (an impact into a
    wall, rest on a wall, sticking; a frictionless rest just flies off with the force)."""
    cap = st[q.CAP]
    for k in range(q.SIZE):
        st[k] = 0.0
    st[q.CAP], st[q.TLAST] = cap, -math.inf
    st[q.J11], st[q.J22] = 1.0, 1.0
    st[q.S] = 1.0 if v >= 0.0 else -1.0
    if (x == P[R] and v > 0.0) or (x == P[L] and v < 0.0):
        mode, t = _impact(P, st, ev, 0.0, v, t_end, jac)
        return mode, t, x, (-P[E] * v if mode == FLIGHT else 0.0)
    if v != 0.0:
        return FLIGHT, 0.0, x, v
    st[q.ZV] = 1.0
    if x == P[R] or x == P[L]:
        side = 1.0 if x >= 0.5 * (P[L] + P[R]) else -1.0
        record(ev, st, q.K_CONTACT, 0.0, x, 0.0, 0.0, 0)
        return _rest_on(P, st, jac, side), 0.0, x, 0.0
    if P[FF] == 0.0:
        st[q.S] = 1.0 if _force(P, x, 0.0) >= 0.0 else -1.0
        return FLIGHT, 0.0, x, 0.0
    record(ev, st, q.K_STICK, 0.0, x, 0.0, 0.0, 0)
    if jac:
        _times(st, 1.0, 0.0, 0.0, 0.0)
    return STICK, 0.0, x, 0.0


@kernel
def run_state(P, x, v, t_end, jac, max_events, st, wk, ev):
    """Integrate one state over ``[0, t_end]`` (module docstring); returns its status."""
    n = 6 if jac else 2
    mode, t, x, v = _start(P, st, ev, x, v, t_end, jac)
    steps = 0
    while True:
        if mode < 0:
            return LOOP_BOUND
        budget = (max_events - st[q.NEV]) * STEPS_PER_EVENT - steps
        if budget <= 0:
            return out_of_events(st)
        if t == st[q.TLAST]:
            st[q.NSAME] += 1.0
            if st[q.NSAME] > 50:
                return LOOP_BOUND
        else:
            st[q.TLAST], st[q.NSAME] = t, 0.0
        if mode != FLIGHT:
            t = _leave_rest(P, st, ev, mode, t, x, t_end)
            if not t < math.inf:
                st[q.XF], st[q.VF] = x, 0.0
                return OK
            x, v, mode = (P[R] if st[q.S] < 0.0 else P[L]) if mode == CONTACT else x, 0.0, FLIGHT
            continue
        wk[dp.Y0], wk[dp.Y0 + 1] = x, v
        wk[dp.Y0 + 2], wk[dp.Y0 + 3], wk[dp.Y0 + 4], wk[dp.Y0 + 5] = 1.0, 0.0, 0.0, 1.0
        st[q.TT] = t
        t_fly, s_fly = t, st[q.S]
        code, k = _fly(P, st, wk, t_end, n, int(min(budget, 2.0 ** 62)))
        steps += k
        if code == TOO_FAST:
            return batch.TOO_FAST
        if code < 0:
            return out_of_events(st)
        t, x, v = st[q.TT], wk[dp.Y0], wk[dp.Y0 + 1]
        if jac:
            _times(st, wk[dp.Y0 + 2], wk[dp.Y0 + 3], wk[dp.Y0 + 4], wk[dp.Y0 + 5])
        if code == NO_EVENT:
            st[q.XF], st[q.VF] = min(max(x, P[L]), P[R]), v
            return OK
        if code == WALL:
            x = P[R] if st[q.S] > 0.0 else P[L]       # the wall hit (st[S] changes in _impact)
            mode, t = _impact(P, st, ev, t, v, t_end, jac)
            v = -P[E] * v if mode == FLIGHT else 0.0
        else:
            mode = _velocity_zero(P, st, ev, t, x, jac)
            v = 0.0
            if mode == CONTACT:
                x = P[R] if st[q.S] > 0.0 else P[L]
            elif mode == FLIGHT and P[FF] == 0.0 and t == t_fly:
                # frictionless rest where the force is zero to rounding (x at a zero of cos(k x)):
                # the flight's own acceleration turned it back at once, against the sign of the
                # float64 force; without friction the sign is only the direction watched for v = 0
                st[q.S] = -s_fly


@kernel
def run_range(P, x, v, t_end, t_end_lo, jac, max_events, out_x, out_v, out_zv, out_J,
              out_nev, out_status, out_paths, log_kind, log_t, log_x, log_v, log_vb, log_cnt,
              i0, i1):
    """``fast.batch``'s engine entry: states ``i0 <= i < i1`` (to ``t_end + t_end_lo``, the
    compensated clock's end: ``fast.compensated``)."""
    cap = log_kind.shape[1]
    st_own, wk_own, ev_own = np.zeros(q.SIZE), np.zeros(cs.SIZE), np.zeros(6 * cap + 1)
    st_own[q.CAP] = cap
    Pp, st, wk, ev = data_pointer(P), data_pointer(st_own), data_pointer(wk_own), data_pointer(ev_own)
    for i in range(i0, i1):
        cs.reset(wk, t_end_lo)
        status = run_state(Pp, x[i], v[i], t_end, jac, max_events, st, wk, ev)
        store(i, status, OK, NON_FINITE, st, ev, jac, out_x, out_v, out_zv, out_J, out_nev, out_status,
              out_paths, log_kind, log_t, log_x, log_v, log_vb, log_cnt)
    return st_own.size + wk_own.size + ev_own.size      # the owners live to the end


@kernel
def _flights(P, t0, x0, v0, s, t_end, jac, out_t, out_x, out_v, out_ev, out_J):
    st_own, wk_own = np.zeros(q.SIZE), np.zeros(cs.SIZE)
    Pp, st, wk = data_pointer(P), data_pointer(st_own), data_pointer(wk_own)
    n = 6 if jac else 2
    for i in range(t0.size):
        cs.reset(wk, 0.0)
        st[q.TT], st[q.S] = t0[i], s[i]
        wk[dp.Y0], wk[dp.Y0 + 1] = x0[i], v0[i]
        wk[dp.Y0 + 2], wk[dp.Y0 + 3], wk[dp.Y0 + 4], wk[dp.Y0 + 5] = 1.0, 0.0, 0.0, 1.0
        out_ev[i] = _fly(Pp, st, wk, t_end[i], n, 1 << 40)[0]
        out_t[i], out_x[i], out_v[i] = st[q.TT], wk[dp.Y0], wk[dp.Y0 + 1]
        if jac:
            for k in range(4):
                out_J[i, k] = wk[dp.Y0 + 2 + k]
    return st_own.size + wk_own.size


def flight(scene, t0, x0, v0, s, t_end, *, jac=False):
    """One flight per element from ``(t0, x0, v0)`` with sign ``s`` to its first event or
    ``t_end``: ``(t, x, v, event, J)`` (``event``: ``NO_EVENT``, ``WALL`` or ``VZERO``; ``J`` the
    flight matrices, shape ``(n, 2, 2)``, or ``None``).  Arrays of one length ``n``."""
    P = params(scene)
    arrays = {}
    n = np.size(x0)
    for name, a in (("t0", t0), ("x0", x0), ("v0", v0), ("s", s), ("t_end", t_end)):
        a = np.atleast_1d(np.asarray(a, dtype=np.float64))
        if a.shape != (n,):
            raise ValueError(f"fast.ode.flight: {name} must have shape ({n},), got {a.shape}")
        bad = np.flatnonzero(~np.isfinite(a))
        if bad.size:
            raise ValueError(f"fast.ode.flight: {name} must be finite; offending indices {bad[:10].tolist()}")
        arrays[name] = a
    bad = np.flatnonzero(np.abs(arrays["s"]) != 1)
    if bad.size:
        raise ValueError(f"fast.ode.flight: s must be +1 or -1; offending indices {bad[:10].tolist()}")
    out = (np.empty(n), np.empty(n), np.empty(n), np.zeros(n, np.int64), np.zeros((n, 4)))
    _flights(P, arrays["t0"], arrays["x0"], arrays["v0"], arrays["s"], arrays["t_end"], bool(jac),
             *out)
    return out[0], out[1], out[2], out[3], (out[4].reshape(n, 2, 2) if jac else None)
