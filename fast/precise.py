"""Extended-precision states at events and at the end of a run (``np.longdouble``).

The search for events (``fast.roots``, ``fast.kernel``) runs in float64: it only has to
locate and certify.  The *states* it hands on -- after each event and at ``t_end`` --
are recomputed here from the segment start in ``np.longdouble`` (x86-64: 64-bit
significand, ``eps = 1.1e-19``) and rounded to float64 once:

* the segment's start phase ``w (T0 + T0LO)`` and the flight (``fast.flight.evaluate``
  with the scene's parameters read at 40 digits and rounded to long double; its series
  for ``theta - sin theta`` truncates at a relative 1e-18, its float64 coefficients
  add 1e-17 relative of a term of size ``theta^3 / 6``: both far below float64);
* one or two steps of the flight's local quadratic model from the float64 root onto the
  exact event (``at_event``), which also settles in long double whether a turning point
  within float64 noise of a wall reaches it (impact) or not (velocity zero);
* the segment's start state is carried on as float64 pairs ``X0 + X0LO``, ``V0 + V0LO``
  (the long-double value rounded, plus the rounding error rounded), so a chain of
  events within a period is not rounded to float64 at each link.

Why: in float64 every term of ``x(t) - x0`` (``v0 h``, ``(F/w^2)(...)``, ``f h^2/2``) is
rounded to an ulp of *itself*; where they cancel (strong friction against strong
forcing: the 3:1 resonance scene has terms 3-4 times the result) a flight loses 2-5 ulp
of ``x``, an impact turns a position error ``dx`` into ``2 A dx / v`` of velocity, and on
a sticking orbit (neutral in ``x``) the loss repeats every period.  With the state in
long double from event to event, what is left is the half-ulp rounding of the state
handed back at the end of the period: measured against the exact map rounded to
float64 after every period, fast's ten-period error is within 2x of it on the paper's
scenes (``cross_check.report``, ``tests/test_fast_vs_reference.py``).

Where ``np.longdouble`` is float64 (e.g. Windows, macOS on arm64) this module still runs
the same steps in float64: the results are then those of a float64 re-evaluation at
the double-double event time (``WIDE`` is ``False``).
"""
from __future__ import annotations

import numpy as np

from . import kernel as k
from .flight import evaluate, two_sum

from .params import WIDE, L

def _start_trig(P, st):
    """Long-double ``(sin, cos)`` of each segment's start phase ``w (T0 + T0LO)``."""
    ph0 = P.wide.w * (L(st[k.T0]) + L(st[k.T0LO]))
    return np.sin(ph0), np.cos(ph0)


def _flight(P, st, t_hi, t_lo, trig0=None):
    """Long-double ``(dx, v, x'')`` (``dx = x - X0``) of each segment of ``st`` at the
    double-double time ``t_hi + t_lo``: ``fast.flight.evaluate`` run on long-double
    arrays with the scene's parameters in long double (``P.wide``); ``trig0`` the
    segments' ``_start_trig`` when already known."""
    W = P.wide            # fast.params.Wide
    h = (L(t_hi) - L(st[k.T0])) + (L(t_lo) - L(st[k.T0LO]))
    sn0, cs0 = _start_trig(P, st) if trig0 is None else trig0
    s = st[k.S]
    v0 = L(st[k.V0]) + L(st[k.V0LO])
    dx, v, cs, _ = evaluate(W, h, None, v0, s, sn0, cs0)
    acc = W.F * cs - s * W.f
    if P.damp > 0:
        acc = acc - W.damp * v
    return dx, v, acc


def at_end(P, st, t_end, t_end_lo):
    """Float64 ``(x, v)`` of the flights of ``st`` at ``t_end + t_end_lo``."""
    dx, v, _ = _flight(P, st, np.full(st.shape[1], t_end), np.full(st.shape[1], t_end_lo))
    return np.clip((L(st[k.X0]) + (L(st[k.X0LO]) + dx)).astype(np.float64), P.l, P.r), v.astype(np.float64)


def at_event(P, sub, code, t_hi, t_lo):
    """Snap each accepted event of ``sub`` (codes ``kernel.IMPACT`` / ``kernel.VZERO``)
    onto the exact event in long double, from the float64 root ``t_hi + t_lo``.

    With ``g = D0 - s dx`` the distance to the wall ahead (the segment's ``D0 = s (W -
    X0)``: exact to relative rounding even where ``X0`` is a rounded position next to a
    wall, as in chatter), ``u = s v`` the speed towards it and ``a = s x''``, the local
    model ``g(d) = g - u d - a d^2/2`` gives the impact at ``d = 2 g / (u + sqrt(u^2 + 2
    a g))`` (when that root exists) and the velocity zero at ``d = -u / a``.  Near a
    tangency (a turning point within float64 noise of a wall) the float64 search cannot
    tell the two apart; the long-double model can, and the event changes kind when:
    an impact whose wall is not reached (``u^2 + 2 a g < 0``) is the velocity zero
    before it; a velocity zero beyond which the wall lies (the impact root comes first)
    is that impact.  Steps are taken up to ``P.d_acc`` (where the cubic term of the
    flight is below float64 rounding) and repeated once from the new time where they
    were not tiny (the model then errs by ``O(d^6)``).

    Returns float64 ``(code, x, dx, v, t_hi, t_lo, (x_lo, v_lo))`` at the refined time:
    ``x = W`` for an impact, ``v = 0`` for a velocity zero; ``dx = x - X0`` rounded on its
    own (a small displacement keeps its relative accuracy: the kernel's ``D0`` is formed
    from it); ``x_lo, v_lo`` the long-double state's residuals after rounding ``x, v``
    to float64 (the next segment starts at ``X0 + X0LO, V0 + V0LO``: a chain of impacts
    then carries no float64 rounding of ``v`` from one to the next)."""
    sn0, cs0 = _start_trig(P, sub)
    dx, v, acc = _flight(P, sub, t_hi, t_lo, (sn0, cs0))
    code, delta = _step(P, sub, code, dx, v, acc)
    again = np.abs(delta) > 1e-12 * (1.0 + np.abs(t_hi))
    t_hi, t_lo = _add(t_hi, t_lo, delta)
    if again.any():
        part = sub[:, again]
        dx2, v2, acc2 = _flight(P, part, t_hi[again], t_lo[again], (sn0[again], cs0[again]))
        _, d2 = _step(P, part, code[again], dx2, v2, acc2, convert=False)
        dx[again], v[again], acc[again], delta[again] = dx2, v2, acc2, d2
        t_hi[again], t_lo[again] = _add(t_hi[again], t_lo[again], d2)
    imp = code == k.IMPACT
    s = sub[k.S]
    dx_new = np.where(imp, s * L(sub[k.D0]), dx + v * delta + (acc * delta) * (delta / 2))
    v_new = np.where(imp, v + acc * delta, L(0))
    W = np.where(s > 0, P.r, P.l)
    x_wide = np.where(imp, L(W), L(sub[k.X0]) + (L(sub[k.X0LO]) + dx_new))
    x = np.clip(x_wide.astype(np.float64), P.l, P.r)
    v = v_new.astype(np.float64)
    x_lo = np.where((x > P.l) & (x < P.r), (x_wide - L(x)).astype(np.float64), 0.0)
    v_lo = (v_new - L(v)).astype(np.float64)
    return code, x, dx_new.astype(np.float64), v, t_hi, t_lo, (x_lo, v_lo)


def _step(P, sub, code, dx, v, acc, convert=True):
    """``(code, d)``: the event kind after the long-double check (``convert``) and the
    step ``d`` onto it (0 where it would exceed ``P.d_acc``: a tangency the model cannot
    resolve keeps the float64 root)."""
    s = sub[k.S]
    g = L(sub[k.D0]) - s * dx
    u, a = s * v, s * acc
    with np.errstate(divide="ignore", invalid="ignore"):
        disc = u * u + (a + a) * g
        den = u + np.sqrt(np.maximum(disc, L(0)))
        hits = (disc >= 0) & (den > 0)
        d_imp = np.where(hits, (g + g) / den, L(np.inf))
        d_v = -v / acc
    ok_imp = np.abs(d_imp) <= P.d_acc
    ok_v = np.isfinite(d_v) & (np.abs(d_v) <= P.d_acc)
    imp = code == k.IMPACT
    if convert:
        to_v = imp & ~hits & (g > 0) & (a < 0) & ok_v
        to_imp = (code == k.VZERO) & hits & (a < 0) & ok_imp & (d_imp <= d_v)
        code = np.where(to_v, k.VZERO, np.where(to_imp, k.IMPACT, code))
        imp = code == k.IMPACT
    delta = np.where(imp, np.where(ok_imp, d_imp, L(0)), np.where(ok_v, d_v, L(0)))
    return code, delta


def _add(t_hi, t_lo, delta):
    """The double-double time ``t_hi + t_lo + delta`` (``delta`` in long double)."""
    d64 = delta.astype(np.float64)
    hi, lo = two_sum(t_hi, d64)
    return hi, lo + (t_lo + (delta - L(d64)).astype(np.float64))
