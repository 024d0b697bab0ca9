"""Processing of located events (a sub-table of states whose trial time is an event).

Each handler updates the state table columns in place, multiplies the Jacobian by the
paper's Table 1 matrices (flight ``[[1, h], [0, 1]]`` first, then the event's), logs
the event when asked, and either starts a new flight segment or finishes the state
(written to ``out``: rows x, v, zero-velocity flag, J11, J12, J21, J22).

Flight matrix with damping ``c > 0``: ``[[1, (1 - exp(-c h))/c], [0, exp(-c h)]]``.
Event matrices (SEMANTICS.md): impact ``[[-e, 0], [((1 + e) A + (1 - e) s f) / v-, -e]]``
with the velocity ``v-`` before impact and ``s`` its sign (``e = 1``: ``2 A / v-``); turn ``diag(1, (|A| - f)/(|A| + f))``; a sticking interval
``[[1, 0], [0, 0]]``; wall contact (contact or chatter, until release) the zero matrix.
"""
from __future__ import annotations

import numpy as np

from . import kernel as k
from . import precise
from .modes import chatter_state, chatter_tail, stick_exit, wall_exit
from .flight import damped_factors, phase_trig, split, two_prod, two_sum
from .params import EPS, TWO_PI

_TWO_PI_SPLIT = split(TWO_PI[0])      # Dekker halves of 2 pi: n a1, n a2 exact

KINDS = ("impact", "turn", "stick", "slip", "contact", "chatter", "release")
IMPACT, TURN, STICK, SLIP, CONTACT, CHATTER, RELEASE = range(7)


def _log(log, sub, sel, code, t, x, v, vb, count=None):
    if log is None or not np.any(sel):
        return
    n = int(np.count_nonzero(sel))
    bc = lambda a: np.broadcast_to(np.asarray(a, float), sel.shape)[sel]  # noqa: E731
    log.append((sub[k.IDX][sel].astype(np.int64), np.full(n, code, np.int8), bc(t), bc(x),
                bc(v), bc(vb), bc(0.0 if count is None else count)))


def process(P, sub, dx, v, cs, sn, t_end, out, log, jac, t_lo=0.0, exact_trig=True, x=None,
            lo=None):
    """Process the pending events of ``sub`` at the double-double times ``TT + t_lo``
    (state ``X0 + dx``, ``v``; or ``x`` when given, with the residuals ``lo = (x_lo,
    v_lo)`` of the long-double state: ``fast.precise.at_event``); returns the mask of
    finished states."""
    t = sub[k.TT].copy()
    t_lo = np.broadcast_to(np.asarray(t_lo, float), t.shape).copy()
    kind = sub[k.PEND].copy()
    x0_old, x0lo_old = sub[k.X0].copy(), sub[k.X0LO].copy()
    s = sub[k.S].copy()
    A = P.F * cs
    if jac:
        _flight_matrix(P, sub, (t - sub[k.T0]) + (t_lo - sub[k.T0LO]))
    x = np.clip(sub[k.X0] + dx if x is None else x, P.l, P.r)
    sub[k.NEV] += 1
    sub[k.NIT] = 0
    fin = np.zeros(t.shape, bool)
    # new-segment proposals (applied at the end for the states that keep flying)
    x_lo, v_lo = (np.zeros_like(t), np.zeros_like(t)) if lo is None else lo
    new = dict(t=t.copy(), tlo=t_lo.copy(), x=x.copy(), v=np.zeros_like(t), s=s.copy(),
               cs=np.full_like(t, np.nan), sn=np.full_like(t, np.nan),
               xlo=x_lo.copy(), vlo=np.zeros_like(t))
    if exact_trig:          # cs, sn are cos, sin(w t) computed directly at the event time
        new["cs"][:] = cs
        new["sn"][:] = sn

    # ---- impacts ------------------------------------------------------------------
    im = kind == k.IMPACT
    W = np.where(s > 0, P.r, P.l)
    graze = im & (s * v <= 0)
    hit = im & ~graze
    e = P.e
    if hit.any():
        new["x"][hit] = W[hit]
        new["xlo"][hit] = 0.0
        new["v"][hit] = -e * v[hit]
        new["vlo"][hit] = -e * v_lo[hit]
        new["s"][hit] = -s[hit]
        _log(log, sub, hit, IMPACT, t, W, -e * v, v)
        if jac:
            # [[-e, 0], [((1 + e) A + (1 - e) s f) / v-, -e]] (e = 1: 2 A / v-)
            num = (1.0 + e) * A + (1.0 - e) * s * P.f
            kk = np.where(hit, num / np.where(hit, v, 1.0), 0.0)
            j11, j12 = sub[k.J11].copy(), sub[k.J12].copy()
            sub[k.J11] = np.where(hit, -e * j11, j11)
            sub[k.J12] = np.where(hit, -e * j12, j12)
            sub[k.J21] = np.where(hit, kk * j11 - e * sub[k.J21], sub[k.J21])
            sub[k.J22] = np.where(hit, kk * j12 - e * sub[k.J22], sub[k.J22])
        chn = sub[k.CHN]
        sub[k.CHN] = np.where(hit, np.where(np.sign(chn) == s, chn + s, s), chn)
        if e == 0:          # at rest on the wall: contact unless the force pulls it off
            sub[k.ZV][hit] = 1.0
            held = hit & (s * A >= -P.f)
            graze = graze | held
        elif P.chatter:
            _chatter(P, sub, hit, (t, t_lo), s, A, sn, e * np.abs(v), t_end, out, log, jac, fin, new)
    # ---- velocity zeros -----------------------------------------------------------
    vz = kind == k.VZERO
    if vz.any():
        sub[k.ZV][vz] = 1.0
        if P.friction:
            sA = s * A
            turn = vz & (sA < -P.f)
            new["s"][turn] = -s[turn]
            _log(log, sub, turn, TURN, t, x, 0.0, 0.0)
            if jac:
                aA = np.abs(A)
                q = np.where(turn, (aA - P.f) / (aA + P.f), 1.0)
                sub[k.J21] *= q
                sub[k.J22] *= q
            stick = vz & ~turn
            if stick.any():
                sub[k.CHN][stick] = 0.0
                _stick(P, sub, stick, (t, t_lo), x, cs, sn, t_end, out, log, jac, fin, new)
        else:
            # frictionless: v passes through 0 smoothly; only the sign bookkeeping flips
            rev = np.where(A != 0, np.sign(A), np.where(sn != 0, -np.sign(sn), 1.0))
            new["s"][vz] = rev[vz]
    # ---- states at rest on a wall (initial, or an impact at zero speed) -----------
    wall = (kind == k.ATWALL) | graze
    if wall.any():
        side = np.where(x >= 0.5 * (P.l + P.r), 1.0, -1.0)
        side = np.where(graze, s, side)
        vb_c = np.where(graze & (P.e != 0), v, 0.0)   # after an e = 0 impact: at rest
        _log(log, sub, wall, CONTACT, t, np.where(side > 0, P.r, P.l), 0.0, vb_c)
        _wall(P, sub, wall, (t, t_lo), side, cs, sn, t_end, out, log, jac, fin, new)
    # ---- start the new flight segments --------------------------------------------
    go = ~fin
    need = go & np.isnan(new["cs"])
    if need.any():
        new["cs"][need], new["sn"][need] = phase_trig(P, new["t"][need], new["tlo"][need])
    some_fin = fin.any()
    for row, key in ((k.T0, "t"), (k.T0LO, "tlo"), (k.X0, "x"), (k.X0LO, "xlo"), (k.V0, "v"),
                     (k.V0LO, "vlo"), (k.S, "s"), (k.SN0, "sn"), (k.CS0, "cs")):
        sub[row] = np.where(go, new[key], sub[row]) if some_fin else new[key]
    sub[k.TT] = sub[k.T0]
    # distance to the wall ahead; where x is continuous through the event (turn, stick,
    # slip) it is formed from the old start, (W - x0) - s dx, not from the rounded x:
    # near a wall (chatter) that keeps the bounce heights to relative accuracy
    d_new = np.where(sub[k.S] > 0, (P.r - sub[k.X0]) - sub[k.X0LO], (sub[k.X0] - P.l) + sub[k.X0LO])
    d_cont = np.where(sub[k.S] > 0, ((P.r - x0_old) - x0lo_old) - dx, ((x0_old - P.l) + x0lo_old) + dx)
    cont = go & (kind == k.VZERO) & (sub[k.X0] == x)
    sub[k.D0] = np.maximum(np.where(cont, d_cont, d_new), 0.0)
    sub[k.PEND] = 0.0
    sub[k.FRESH] = 1.0
    sub[k.C1] = sub[k.T0]
    sub[k.C2] = sub[k.T0]
    sub[k.SPEC] = 0.0
    sub[k.NFAIL] = 0.0
    return fin


def _flight_matrix(P, st, h):
    """``J <- [[1, a1], [0, E]] J`` (``a1 = h``, ``E = 1`` undamped; damped ``a1 = (1 -
    exp(-c h))/c``, ``E = exp(-c h)``)."""
    a1, E = damped_factors(P, h)
    st[k.J11] += a1 * st[k.J21]
    st[k.J12] += a1 * st[k.J22]
    if P.damp > 0:
        st[k.J21] *= E
        st[k.J22] *= E


def _finish(P, sub, sel, x, v, out, jac):
    idx = sub[k.IDX][sel].astype(np.int64)
    out[0, idx] = np.broadcast_to(x, sel.shape)[sel]
    out[1, idx] = np.broadcast_to(v, sel.shape)[sel]
    out[2, idx] = sub[k.ZV][sel]
    if jac:
        out[3:7, idx] = sub[k.J11:k.J22 + 1][:, sel]


def finish_flight(P, st, out, jac, t_end, t_end_lo=0.0):
    """States reaching ``t_end`` (+ ``t_end_lo``) in flight: final flight matrix, state
    (``fast.precise.at_end``) to ``out``."""
    if jac:
        _flight_matrix(P, st, ((t_end - st[k.T0]) - st[k.T0LO]) + t_end_lo)
    x, v = precise.at_end(P, st, t_end, t_end_lo)
    _finish(P, st, np.ones(x.shape, bool), x, v, out, jac)


def _chatter(P, sub, hit, tt, s, A, sn, u, t_end, out, log, jac, fin, new):
    """After an impact: sum the chatter tail (second order, fast.modes.chatter_tail) when
    its estimated error is below a few ulp of T or the bounces are at float resolution."""
    p = s * A
    cand = hit & (p > P.f)
    if not cand.any():
        return
    pc = np.where(cand, p, 2.0 * P.f + 1.0)
    p1 = -s * (P.F * P.w) * sn          # side * A'(t)
    delta, rho, err, tau, one_m = chatter_tail(P, pc, np.where(cand, u, 0.0), p1)
    # sum the tail when its neglected terms are below a few ulp of T, or when the bounces
    # are below float64 resolution anyway (height u^2 / (2 (p + f)) within 64 ulp of the wall)
    height = u * u / (2.0 * (pc + P.f))
    chat = cand & ((err <= 4 * EPS * P.T) | (height <= 64 * EPS * max(abs(P.l), abs(P.r))))
    if not chat.any():
        return
    W = np.where(s > 0, P.r, P.l)
    t, t_lo = tt
    t_inf, t_inf_lo = two_sum(t, delta)
    t_inf_lo += t_lo
    done_now = chat & (t_inf > t_end)
    if done_now.any():
        y, vy = chatter_state(P, pc, np.maximum(u, 1e-300), rho, tau, one_m, (t_end - t) - t_lo)
        sub[k.ZV][done_now] = 1.0        # the summed bounces turn (v = 0) every time
        if jac:  # the derivative is undefined in chatter; report the contact matrix
            sub[k.J11:k.J22 + 1][:, done_now] = 0.0
        _finish(P, sub, done_now, W - s * y, -s * vy, out, jac)
        fin |= done_now
    lim = chat & ~done_now
    if lim.any():
        sub[k.ZV][lim] = 1.0
        _log(log, sub, lim, CHATTER, t_inf, W, 0.0, 0.0, np.abs(sub[k.CHN]))
        cs, sn = phase_trig(P, t_inf, t_inf_lo)
        new["v"][lim] = 0.0
        new["vlo"][lim] = 0.0
        _wall(P, sub, lim, (t_inf, t_inf_lo), s, cs, sn, t_end, out, log, jac, fin, new)


def _stick(P, sub, sel, tt, x, cs, sn, t_end, out, log, jac, fin, new):
    """Sticking from ``tt = (t, t_lo)`` at ``x``: slip at the closed-form phase, or stay
    to the end."""
    t, t_lo = tt
    _log(log, sub, sel, STICK, t, x, 0.0, 0.0)
    if jac:
        sub[k.J21][sel] = 0.0
        sub[k.J22][sel] = 0.0
    dphi, s_new = stick_exit(P, cs, sn)
    t_exit, t_exit_lo = _exit_time(P, t, t_lo, dphi, s_new < 0)
    stay = sel & ~(t_exit <= t_end)
    _finish(P, sub, stay, x, 0.0, out, jac)
    fin |= stay
    slip = sel & ~stay
    if slip.any():
        _log(log, sub, slip, SLIP, t_exit, x, 0.0, 0.0)
        new["t"][slip] = t_exit[slip]
        new["tlo"][slip] = t_exit_lo[slip]
        new["s"][slip] = s_new[slip]
        at_once = dphi == 0
        new["cs"][slip] = np.where(at_once, cs, np.where(s_new < 0, -P.c, P.c))[slip]
        new["sn"][slip] = np.where(at_once, sn, np.where(s_new < 0, P.sin_alpha, -P.sin_alpha))[slip]


def _wall(P, sub, sel, tt, side, cs, sn, t_end, out, log, jac, fin, new):
    """Resting on wall ``side`` from ``tt = (t, t_lo)``: release at the closed-form phase
    or stay."""
    t, t_lo = tt
    sub[k.ZV][sel] = 1.0
    sub[k.CHN][sel] = 0.0
    if jac:
        sub[k.J11:k.J22 + 1][:, sel] = 0.0
    W = np.where(side > 0, P.r, P.l)
    dphi = wall_exit(P, cs, sn, side)
    t_exit, t_exit_lo = _exit_time(P, t, t_lo, dphi, side > 0)
    stay = sel & ~(t_exit <= t_end)
    _finish(P, sub, stay, W, 0.0, out, jac)
    fin |= stay
    rel = sel & ~stay
    if rel.any():
        _log(log, sub, rel, RELEASE, t_exit, W, 0.0, 0.0)
        new["t"][rel] = t_exit[rel]
        new["tlo"][rel] = t_exit_lo[rel]
        new["x"][rel] = W[rel]
        new["xlo"][rel] = 0.0
        new["s"][rel] = -side[rel]
        at_once = dphi == 0
        new["cs"][rel] = np.where(at_once, cs, -side * P.c)[rel]
        new["sn"][rel] = np.where(at_once, sn, side * P.sin_alpha)[rel]


def _exit_time(P, t, t_lo, dphi, upper):
    """The double-double time at which sticking or wall contact that began at ``t +
    t_lo`` ends, ``dphi / w`` later: exactly the phase ``B + 2 pi n`` with ``B = B1 = pi
    - alpha`` where ``upper`` (stick exit with ``s = -1``, release from ``r``), else
    ``B2 = 2 pi - alpha`` (stick exit with ``s = +1``, release from ``l``), ``n`` the
    nearest integer to ``(w t + dphi - B) / 2 pi``; ``t = (B + 2 pi n) / w`` is formed
    in double-double (Dekker's products, ``|n| < 2^26``).  ``dphi = 0`` (ends at once)
    keeps ``t``, ``inf`` (never ends) gives ``inf``."""
    with np.errstate(invalid="ignore"):
        b_hi = np.where(upper, P.B1[0], P.B2[0])
        b_lo = np.where(upper, P.B1[1], P.B2[1])
        n = np.rint((P.w * t + dphi - b_hi) * (1.0 / TWO_PI[0]))
        n = np.where(np.isfinite(n), n, 0.0)
        if np.any(np.abs(n) >= 2.0 ** 26):
            raise RuntimeError("fast: sticking or contact ends more than 2^26 periods in")
        a1, a2 = _TWO_PI_SPLIT
        p1, e1 = two_sum(b_hi, n * a1)        # n a1, n a2 are exact (26 + 26, 27 + 26 bits)
        p2, e2 = two_sum(p1, n * a2)
        ph_lo = (e1 + e2) + (b_lo + n * TWO_PI[1])
        q1 = p2 / P.w                        # (p2 + ph_lo) / (w + w_lo), double-double
        prod, err = two_prod(q1, P.w, P.w_split)
        rem = ((p2 - prod) - err) + (ph_lo - q1 * P.w_lo)
        hi, lo = two_sum(q1, rem / P.w)
        now = dphi == 0
        never = ~np.isfinite(dphi)
        hi = np.where(now, t, np.where(never, np.inf, hi))
        lo = np.where(now, t_lo, np.where(never, 0.0, lo))
    return hi, lo
