"""Double-double states at events and at the end of a run.

The search for events (``fast.roots``) runs in float64: it only has to locate and certify.
The *states* it hands on -- after each event and at ``t_end`` -- are recomputed here from
the segment start in double-double (``fast.flight.evaluate_dd``) and carried on as
double-doubles (``X0 + X0LO``, ``V0 + V0LO``, the start trig), so a chain of events within
a period is never rounded to float64 between its links; only the state handed back at the
end of the period is rounded, once.

Why: in float64 every term of ``x(t) - x0`` (``v0 h``, ``(F/w^2)(...)``, ``f h^2/2``) is
rounded to an ulp of *itself*; where they cancel (strong friction against strong forcing:
the 3:1 resonance scene has terms 3-4 times the result) a flight loses 2-5 ulp of ``x``,
an impact turns a position error into ``2 A dx / v`` of velocity, and on a sticking orbit
(neutral in ``x``) the loss repeats every period.

``at_event`` moves the float64 root onto the exact event with one or two steps of the
flight's local model.  With ``g = D0 - s dx`` the distance to the wall ahead, ``u = s v``
the speed towards it and ``a = s x''``, ``g(d) = g - u d - a d^2/2`` gives the impact at
``d = 2 g / (u + sqrt(u^2 + 2 a g))`` (when that root exists) and the velocity zero at
``d = -v / x''``.  Near a tangency (a turning point within float64 noise of a wall) the
float64 search cannot tell the two apart; ``u^2 + 2 a g`` in double-double can, and the
event changes kind when an impact's wall is not reached (it is the velocity zero before
it) or a velocity zero lies beyond the wall (it is that impact).  Steps are taken up to
``d_acc`` (where the cubic term of the flight is below float64 rounding) and repeated
once from the new time where they were not tiny (the model then errs by ``O(d^6)``).
"""
from __future__ import annotations

import math

from . import dd
from . import params as p
from . import state as q
from .flight import acceleration, evaluate_dd
from .jit import kernel
from .roots import bounds


@kernel
def flight_at(P, st, t_hi, t_lo):
    """``evaluate_dd`` of the current segment at the double-double time ``t_hi + t_lo``."""
    hh, hl = dd.add(t_hi, t_lo, -st[q.T0], -st[q.T0LO])
    if P[p.DAMP] > 0.0:
        st[q.PATHS] = float(int(st[q.PATHS]) | q.PATH_DAMPED)
    return evaluate_dd(P, st[q.V0], st[q.V0LO], st[q.S], st[q.SN0], st[q.SN0LO], st[q.CS0],
                       st[q.CS0LO], hh, hl, t_hi, t_lo)


@kernel
def end_state(P, st, dxh, dxl, vh, vl):
    """Float64 ``(x, v)`` at the end from the double-double flight values there (``x``
    clipped to the gap: rounding at a touch)."""
    xh, xl = dd.add(st[q.X0], st[q.X0LO], dxh, dxl)
    return min(max(xh + xl, P[p.L]), P[p.R]), vh + vl


@kernel
def at_end(P, st, t_end, t_end_lo):
    """Float64 ``(x, v)`` of the current flight at ``t_end + t_end_lo``."""
    dxh, dxl, vh, vl, _, _, _, _, _ = flight_at(P, st, t_end, t_end_lo)
    return end_state(P, st, dxh, dxl, vh, vl)


@kernel
def _step(P, st, code, dxh, dxl, vh, vl, ah, csh, csl, convert):
    """``(code, d)``: the event kind after the double-double tangency check (``convert``)
    and the step ``d`` onto it (0 where it would exceed ``d_acc``: a tangency the model
    cannot resolve keeps the float64 root)."""
    s = st[q.S]
    gh, gl = dd.add_d(-s * dxh, -s * dxl, st[q.D0])
    gh, gl = dd.norm(gh, gl)
    uh, ul = s * vh, s * vl
    # the velocity rounded whole: near a velocity zero or a grazing impact it is a
    # cancellation of O(1) terms, and the low part of the unnormalised pair can be as large
    # as the high part (a step from the high part alone misses by ~ulp(terms) / |a|)
    u = uh + ul
    a = s * ah
    d_acc = bounds(P, abs(st[q.V0]))[4]
    disc = u * u + 2.0 * a * gh
    if abs(disc) <= 1e-6 * u * u:            # near a tangency: the sign in double-double
        al = acceleration(P, s, csh, csl, vh, vl)[1]
        u2h, u2l = dd.mul(uh, ul, uh, ul)
        agh, agl = dd.mul(a, s * al, gh, gl)
        disc = dd.add(u2h, u2l, 2.0 * agh, 2.0 * agl)[0]
    den = u + math.sqrt(max(disc, 0.0))
    hits = disc >= 0.0 and den > 0.0
    d_imp = (gh + gh) / den if hits else math.inf
    d_v = -(s * u) / ah if ah != 0.0 else math.inf
    ok_imp = abs(d_imp) <= d_acc
    ok_v = abs(d_v) <= d_acc
    if convert:
        if code == q.IMPACT and not hits and gh > 0.0 and a < 0.0 and ok_v:
            code = q.VZERO
        elif code == q.VZERO and hits and a < 0.0 and ok_imp and d_imp <= d_v:
            code = q.IMPACT
    if code == q.IMPACT:
        return code, (d_imp if ok_imp else 0.0)
    return code, (d_v if ok_v else 0.0)


@kernel
def at_event(P, st, code, t_hi, t_lo):
    """Snap an accepted event (``IMPACT`` / ``VZERO``) at the float64 root ``t_hi + t_lo``
    onto the exact event (module docstring).  Returns ``(code, t_hi, t_lo, xh, xl, vh, vl,
    snh, snl, csh, csl)``: the refined double-double time, the state there (``x = W`` and
    ``v`` the velocity before an impact; ``v = 0`` at a velocity zero) and the trig of the
    phase there, all double-doubles."""
    dxh, dxl, vh, vl, ah, snh, snl, csh, csl = flight_at(P, st, t_hi, t_lo)
    code, delta = _step(P, st, code, dxh, dxl, vh, vl, ah, csh, csl, True)
    t_hi, t_lo = dd.add_d(t_hi, t_lo, delta)
    if abs(delta) > 1e-12 * (1.0 + abs(t_hi)):
        dxh, dxl, vh, vl, ah, snh, snl, csh, csl = flight_at(P, st, t_hi, t_lo)
        delta = _step(P, st, code, dxh, dxl, vh, vl, ah, csh, csl, False)[1]
        t_hi, t_lo = dd.add_d(t_hi, t_lo, delta)
    # the trig moved by z = w delta (|z| <= w d_acc ~ 1e-5: the omitted z^4/24 < 1e-21)
    z = P[p.W] * delta
    c1, s1 = -0.5 * z * z, z - z * z * z / 6.0
    snh, snl, csh, csl = (*dd.add_d(snh, snl, snh * c1 + csh * s1),
                          *dd.add_d(csh, csl, csh * c1 - snh * s1))
    s = st[q.S]
    if code == q.IMPACT:
        vh, vl = dd.add_d(vh, vl, ah * delta)
        xh, xl = (P[p.R] if s > 0.0 else P[p.L]), 0.0
    else:
        a, b = dd.mul_d(vh, vl, delta)
        dxh, dxl = dd.add(dxh, dxl, a, b + 0.5 * ah * delta * delta)
        xh, xl = dd.add(st[q.X0], st[q.X0LO], dxh, dxl)
        if not P[p.L] < xh < P[p.R]:
            xh, xl = min(max(xh, P[p.L]), P[p.R]), 0.0
        vh, vl = 0.0, 0.0
    return code, t_hi, t_lo, xh, xl, vh, vl, snh, snl, csh, csl
