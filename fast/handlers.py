"""What happens at an event: impact, turn, stick and slip, wall contact and release, chatter.

Each handler updates the state record ``st`` (``fast.state``), multiplies the Jacobian by
the paper's Table 1 matrices (the flight's ``[[1, a1], [0, E]]`` first, then the event's),
logs the event, and either starts a new flight segment (returns ``False``) or writes the
state's final values (returns ``True``).  The event kinds are ``reference``'s (its
``integrator`` module docstring): ``impact`` (``v -> -e v``), ``turn`` (``v = 0`` with ``s A
< -f``), ``stick`` / ``slip``, ``contact`` / ``release`` (at rest on a wall while the force
holds it), ``chatter`` (the accumulation point of a run of impacts, summed).

Event matrices: impact ``[[-e, 0], [((1 + e) A + (1 - e) s f) / v-, -e]]`` with the
velocity ``v-`` before impact and ``s`` its sign (``e = 1``: ``2 A / v-``); turn
``diag(1, (|A| - f)/(|A| + f))``; a sticking interval ``[[1, 0], [0, 0]]``; wall contact
(contact or chatter, until release) the zero matrix.  Flight matrix with damping ``c > 0``:
``[[1, (1 - exp(-c h))/c], [0, exp(-c h)]]``.
"""
from __future__ import annotations

import math

from . import dd
from . import params as p
from . import state as q
from .flight import factors
from .jit import kernel
from .output import record
from .modes import chatter_state, chatter_tail, exit_time, slides, stick_exit, wall_exit

EPS = 2.0 ** -52


@kernel
def took(st, path):
    """Record that the state took the code path ``path`` (a ``PATH_*`` bit)."""
    st[q.PATHS] = float(int(st[q.PATHS]) | path)


@kernel
def finish(st, x, v):
    """The state is finished at ``(x, v)``; returns ``True``."""
    st[q.XF] = x
    st[q.VF] = v
    return True


@kernel
def flight_matrix(P, st, h):
    """``J <- [[1, a1], [0, E]] J`` for a flight of duration ``h``."""
    a1, E = factors(P, h)
    st[q.J11] += a1 * st[q.J21]
    st[q.J12] += a1 * st[q.J22]
    st[q.J21] *= E
    st[q.J22] *= E


@kernel
def zero_jacobian(st):
    for k in range(4):
        st[q.J11 + k] = 0.0


@kernel
def start_segment(P, st, t, tl, xh, xl, vh, vl, s, trig):
    """A new flight segment from the double-double ``(t, x, v)`` with sign ``s`` and the
    start trig ``trig = (sn, sn_lo, cs, cs_lo)``."""
    st[q.T0], st[q.T0LO], st[q.X0], st[q.X0LO], st[q.V0], st[q.V0LO] = t, tl, xh, xl, vh, vl
    st[q.S] = s
    st[q.SN0], st[q.SN0LO], st[q.CS0], st[q.CS0LO] = trig
    d = (P[p.R] - xh) - xl if s > 0.0 else (xh - P[p.L]) + xl
    st[q.D0] = max(d, 0.0)
    st[q.TT], st[q.C1], st[q.C2] = t, t, t
    st[q.P1], st[q.P2] = math.inf, math.inf
    st[q.SPEC], st[q.NFAIL], st[q.NIT] = 0.0, 0.0, 0.0


@kernel
def exit_trig(P, trig, side):
    """The trig at a stick exit or wall release that does not happen at once: the phase is
    ``pi - alpha`` (``side > 0``: cos = -c, sin = sin(alpha)) or ``2 pi - alpha``."""
    if side > 0.0:
        return P[p.SA], P[p.SA_LO], -P[p.C], -P[p.C_LO]
    return -P[p.SA], -P[p.SA_LO], P[p.C], P[p.C_LO]


@kernel
def on_wall(P, st, side, t, tl, trig, t_end, jac, ev):
    """At rest on wall ``side`` from ``t``: released at the closed-form phase, or stays."""
    st[q.ZV] = 1.0
    st[q.CHN] = 0.0
    took(st, q.PATH_WALL)
    if jac:
        zero_jacobian(st)
    W = P[p.R] if side > 0.0 else P[p.L]
    dphi = wall_exit(P, trig[2], trig[0], side)
    te, tel = exit_time(P, t, tl, dphi, side > 0.0)
    if not te <= t_end:
        return finish(st, W, 0.0)
    record(ev, st, q.K_RELEASE, te, W, 0.0, 0.0, 0)
    if dphi != 0.0:
        trig = exit_trig(P, trig, side)
    start_segment(P, st, te, tel, W, 0.0, 0.0, 0.0, -side, trig)
    return False


@kernel
def sticking(P, st, t, tl, xh, xl, trig, t_end, jac, ev):
    """Sticking at ``x`` from ``t``: slip at the closed-form phase, or stay to the end."""
    record(ev, st, q.K_STICK, t, xh, 0.0, 0.0, 0)
    st[q.CHN] = 0.0
    if jac:
        st[q.J21] = 0.0
        st[q.J22] = 0.0
    dphi, s_new = stick_exit(P, trig[2], trig[0])
    te, tel = exit_time(P, t, tl, dphi, s_new < 0.0)
    if not te <= t_end:
        return finish(st, xh, 0.0)
    record(ev, st, q.K_SLIP, te, xh, 0.0, 0.0, 0)
    if dphi != 0.0:
        trig = exit_trig(P, trig, -s_new)
    start_segment(P, st, te, tel, xh, xl, 0.0, 0.0, s_new, trig)
    return False


@kernel
def velocity_zero(P, st, t, tl, xh, xl, trig, t_end, jac, ev):
    """``v = 0`` in flight: a turn (``s A < -f``), sticking, or (``f = 0``) a smooth
    reversal, which logs nothing."""
    st[q.ZV] = 1.0
    s = st[q.S]
    A = P[p.F] * trig[2]
    if P[p.FRICTION] == 0.0:
        rev = 1.0
        if A != 0.0:
            rev = 1.0 if A > 0.0 else -1.0
        elif trig[0] != 0.0:
            rev = -1.0 if trig[0] > 0.0 else 1.0
        start_segment(P, st, t, tl, xh, xl, 0.0, 0.0, rev, trig)
        return False
    took(st, q.PATH_FRICTION)
    if slides(P, -s, trig[2], trig[0]):           # s A < -f, and the reversed slide lasts
        record(ev, st, q.K_TURN, t, xh, 0.0, 0.0, 0)
        if jac:
            fac = (abs(A) - P[p.FF]) / (abs(A) + P[p.FF])
            st[q.J21] *= fac
            st[q.J22] *= fac
        start_segment(P, st, t, tl, xh, xl, 0.0, 0.0, -s, trig)
        return False
    return sticking(P, st, t, tl, xh, xl, trig, t_end, jac, ev)


@kernel
def impact(P, st, t, tl, vh, vl, trig, t_end, jac, ev):
    """An impact with velocity ``v- = vh + vl`` (towards the wall ``s``)."""
    s, e, f = st[q.S], P[p.E], P[p.FF]
    A = P[p.F] * trig[2]
    W = P[p.R] if s > 0.0 else P[p.L]
    record(ev, st, q.K_IMPACT, t, W, -e * vh, vh, 0)
    if jac:
        kk = ((1.0 + e) * A + (1.0 - e) * s * f) / vh
        j11, j12 = st[q.J11], st[q.J12]
        st[q.J11], st[q.J12] = -e * j11, -e * j12
        st[q.J21] = kk * j11 - e * st[q.J21]
        st[q.J22] = kk * j12 - e * st[q.J22]
    chn = st[q.CHN]
    st[q.CHN] = chn + s if (chn > 0.0) == (s > 0.0) and chn != 0.0 else s
    if e != 1.0:
        took(st, q.PATH_RESTITUTION)
    if e == 0.0:
        st[q.ZV] = 1.0
        if s * A >= -f:                         # at rest on the wall, held there
            record(ev, st, q.K_CONTACT, t, W, 0.0, 0.0, 0)
            return on_wall(P, st, s, t, tl, trig, t_end, jac, ev)
    elif P[p.CHATTER] != 0.0 and not e * abs(vh) > P[p.U_CHATTER]:   # else chatter() says no
        done = chatter(P, st, t, tl, s, A, trig, e * abs(vh), t_end, jac, ev)
        if done >= 0:
            return done == 1
    start_segment(P, st, t, tl, W, 0.0, -e * vh, -e * vl, -s, trig)
    return False


@kernel
def chatter(P, st, t, tl, s, A, trig, u, t_end, jac, ev):
    """After an impact at wall ``s`` leaving with speed ``u``: sum the chatter tail
    (``fast.modes.chatter_tail``) when its estimated error is below a few ulp of ``T`` or
    the bounces are at float resolution.  Returns -1 (not summed), 1 (finished inside the
    tail) or 0 (wall contact from the accumulation point on)."""
    pu = s * A
    f = P[p.FF]
    if not pu > f:
        return -1
    height = u * u / (2.0 * (pu + f))
    at_resolution = height <= 64 * EPS * P[p.XSCALE]
    # a lower bound of chatter_tail's error estimate rejects most impacts without the
    # second-order tail: Delta >= (7/8) Delta_0 >= (7/8) u / (pu + f) where the expansion is
    # used (z <= 1/8), err >= 2 F w^2 Delta^3 / b there and >= 2 F w Delta_0^2 / b frozen
    d_lo = u / (pu + f)
    Fw, b = P[p.F] * P[p.W], pu - f
    lower = min(2.0 * Fw * d_lo * d_lo, 2.0 * Fw * P[p.W] * (0.875 * d_lo) ** 3) / b
    if not at_resolution and lower > 4 * EPS * P[p.T]:
        return -1
    p1 = -s * Fw * trig[0]                              # side * A'(t)
    took(st, q.PATH_CHATTER)
    delta, rho, err, tau, one_m = chatter_tail(P, pu, u, p1)
    if not (err <= 4 * EPS * P[p.T] or at_resolution):
        return -1
    W = P[p.R] if s > 0.0 else P[p.L]
    st[q.ZV] = 1.0
    ti, til = dd.two_sum(t, delta)
    til += tl
    if ti > t_end:
        y, vy = chatter_state(P, pu, max(u, 1e-300), rho, tau, one_m, (t_end - t) - tl)
        if jac:          # the derivative is undefined in chatter: the contact matrix
            zero_jacobian(st)
        finish(st, W - s * y, -s * vy)
        return 1
    record(ev, st, q.K_CHATTER, ti, W, 0.0, 0.0, int(abs(st[q.CHN])))
    ph, pl = dd.mul(P[p.W], P[p.W_LO], ti, til)
    trig = dd.sincos(ph, pl)
    return 0 if not on_wall(P, st, s, ti, til, trig, t_end, jac, ev) else 1


@kernel
def handle(P, st, code, t, tl, xh, xl, vh, vl, trig, t_end, jac, ev):
    """Process the event ``code`` at the double-double time ``t + tl`` with the state
    ``(x, v)`` there (``v`` before an impact); returns whether the state is finished."""
    if jac:
        flight_matrix(P, st, (t - st[q.T0]) + (tl - st[q.T0LO]))
    st[q.NIT] = 0.0
    if t == st[q.TLAST]:
        st[q.NSAME] += 1.0
    else:
        st[q.TLAST], st[q.NSAME] = t, 0.0
    s = st[q.S]
    if code == q.IMPACT:
        if s * vh > 0.0:
            return impact(P, st, t, tl, vh, vl, trig, t_end, jac, ev)
        # a grazing touch: at rest on the wall the flight reached
        vb = vh if P[p.E] != 0.0 else 0.0
        record(ev, st, q.K_CONTACT, t, P[p.R] if s > 0.0 else P[p.L], 0.0, vb, 0)
        return on_wall(P, st, s, t, tl, trig, t_end, jac, ev)
    if code == q.VZERO:
        return velocity_zero(P, st, t, tl, xh, xl, trig, t_end, jac, ev)
    side = 1.0 if xh >= 0.5 * (P[p.L] + P[p.R]) else -1.0     # at rest on a wall at t0
    record(ev, st, q.K_CONTACT, t, P[p.R] if side > 0.0 else P[p.L], 0.0, 0.0, 0)
    return on_wall(P, st, side, t, tl, trig, t_end, jac, ev)
