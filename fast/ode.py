"""Numerical flights under position-dependent forcing, compiled: ``fast.batch``'s second engine.

The forcing ``F cos(k x) cos(w t)`` (the paper's last section, eq. ``xpot``: ``k = pi/2``)
has no closed-form flight; ``fast.api`` routes such scenes here (the only path to a
numerical ODE solver).  A flight is integrated by fixed compensated DOP853 steps to its
first event (``fast.ode_flight``: the steps, their accuracy, the certified first event on the
dense output); ``P`` is ``fast.ode_params``' parameter vector.  The names of both that the
engine's callers read are this module's too (``__all__``): ``fast.api`` and ``fast.batch``
take the engine as this module.

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
from .jit import data_pointer, kernel
from .ode_flight import EPS, NO_EVENT, TOO_FAST, VZERO, WALL, _fly, _force, flight
from .ode_params import (DAMP, STEPS_PER_PERIOD, E, F, FF, K, L, R, T, W, XS, max_speed, p,
                         params, with_steps)
from .output import out_of_events, record, store

#: the engine's names that live in its two parts (``fast.api``, ``fast.batch`` and the tests
#: read them here)
__all__ = ["NO_EVENT", "STEPS_PER_PERIOD", "VZERO", "WALL", "flight", "max_speed", "p", "params",
           "run_range", "run_state", "with_steps"]

#: steps that count as one event against the budget
STEPS_PER_EVENT = 16
OK, LOOP_BOUND, NON_FINITE = batch.OK, batch.LOOP_BOUND, batch.NON_FINITE
#: modes of the loop
FLIGHT, STICK, CONTACT = 0, 1, 2

#: phases (radians) of a closing window of ``first_above`` too short to leave rest in
SLIVER = 16 * EPS * 2 * math.pi


@kernel
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


@kernel
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


@kernel
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
