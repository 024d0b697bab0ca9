"""The tail of a chatter run, bounded without simulating a bounce (``reference.enclosure.walk``
closes a run with it: the accumulation time for every start of a box, and wall contact after).
"""
from __future__ import annotations

from flint import arb

from reference.enclosure.balls import span
from reference.enclosure.certify import Unproved

#: Tries of the chatter window (each doubles it) before the tail is declared unbounded.
CHATTER_TRIES = 12


def chatter_tail(m, t, side, u):
    """Bound the accumulation of a chatter run: returns ``(low, high)`` with ``t_inf`` in
    ``[t + low, t + high]`` for every start in the balls (``t``: the last impact, ``u``: the
    speed after it).  No bounce is simulated.

    On a window where the push ``P = side A`` lies in ``[P_min, P_max]`` with
    ``R_min = P_min - f - c V > 0`` (``V = u max(1, sqrt(R_max / D))`` bounds ``|v|`` on a
    bounce): a bounce of speed ``u`` decelerates at a rate in ``[D, D_max] = [P_min + f,
    P_max + f + c V]``, so it lasts ``u/D_max .. u/D`` up and its height is in
    ``[u^2 / 2 D_max, u^2 / 2 D]``; it falls back at a rate in ``[R_min, R_max] = [.., P_max - f]``,
    so it lasts ``u / sqrt(D_max R_max) .. u / sqrt(D R_min)`` down and the next speed is in
    ``[rho_lo u, rho u]``, ``rho = e sqrt(R_max / D)``, ``rho_lo = e sqrt(R_min / D_max)``.  If
    ``rho < 1`` the infinitely many later bounces sum to

        K_lo u / (1 - rho_lo)  <=  t_inf - t  <=  K u / (1 - rho),

    ``K = 1/D + 1/sqrt(D R_min)``, ``K_lo = 1/D_max + 1/sqrt(D_max R_max)``.  The bounds are
    valid if the upper one fits in the window (the push bounds then held on every bounce) and
    the heights stay below the gap (no other wall).  The width is second order in ``u``.
    Under position forcing the push is bounded over the strip ``H`` wide at the wall as well,
    with ``H`` at least the highest bounce ``u^2 / 2 D`` (later bounces are slower).
    """
    f, e, wall = m.f, m.e, m.wall(side)
    W, strip, H = m.T * arb(2) ** -20, wall, arb(0)
    for _ in range(CHATTER_TRIES):
        push = side * m.force(strip, span(t, t + W))
        D, R_max = push.lower() + f, push.upper() - f
        if not (D > 0 and R_max > 0):
            break
        if m.position_forcing and not u * u / (2 * D) <= H:
            H = (u * u / D).upper()          # twice the highest bounce: the strip, tried next
            strip = wall - side * arb(H / 2, H / 2)
            continue
        speed = u * max(arb(1), (R_max / D).sqrt()).upper()     # |v| on a bounce
        drag = m.c * speed if m.damping else arb(0)
        R_min, D_max = push.lower() - f - drag, push.upper() + f + drag
        rho = e * (R_max / D).sqrt() if R_min > 0 else arb(1)
        if not rho < 1:
            break
        high = (1 / D + 1 / (D * R_min).sqrt()) * u / (1 - rho)
        if high < W and u * u / (2 * D) < m.r - m.l:
            low = (1 / D_max + 1 / (D_max * R_max).sqrt()) * u / (1 - e * (R_min / D_max).sqrt())
            return low.lower(), high.upper()
        W = 2 * high.upper()
    raise Unproved(f"chatter at t = {t.mid().str(15)}: no window on which the push exceeds "
                   f"friction and the bounces shrink (the accumulation is not bounded)")
