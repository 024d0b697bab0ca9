"""Return to rest in time: the certificate of one box of rest states.

A *rest state* is ``(x, v = 0)`` at a time ``tau`` in ``[0, T)``.  It *returns to rest within*
``B`` if its motion (``reference.integrator``'s: Filippov sticking, wall contact, the reset
``v+ = -e v-``) has ``v = 0`` at some time in ``(tau, tau + B]``; a state that sticks (or stays
in wall contact) has ``v = 0`` right after ``tau``.  If every rest state returns by ``2T``
(``tau + B <= 2T``; ``B <= T`` is the issue's sufficient "within one period"), then
``Phi(Omega_dissip)`` lies in ``Omega_dissip`` (``reference.enclosure.invariance``).

Coordinates: ``x = l + xi (r - l)``, ``tau = phi T``.  A box is ``[xi0, xi1] x [phi0, phi1]``
(exact rationals); over a parameter box (``ParamBox``) every statement below holds for every
parameter of the box (``xi`` in ``[0, 1]`` is every ``x`` in ``[l, r]`` of each parameter).

The certificate is a chain of *stages*, each a flight of one velocity sign ``sigma`` in closed
form (``motion.Flight`` on balls: the stage's start times, speeds and the parameters at once),
with ``x`` measured from the start and ``y0`` the distance to the wall ahead:

1. **stuck**: ``|F cos(w tau)| < f`` on the box: every state sticks (at a wall: stays).
2. **release**: ``sigma A > -f`` on the box (``A = F cos(w tau)``): no state leaves downwards.
   A state either sticks (``v = 0`` at once; should it be released at a later phase
   ``tau_b`` of the box, it then flies as the release from ``tau_b``, which the box holds:
   the bounds below hold for its flight too), or is released upwards: ``sigma v > 0`` just
   after ``tau``, ``sigma v = (F/w) sigma (sin w t - sin w tau) - f (t - tau)`` (undamped).  (The release
   boundary ``|A| = f`` needs no special case: the flight from it is in the box.)
3. **a stage** from a start set (times ``t0``, speeds ``u >= 0``, ``v0 = sigma u``; ``y0`` the
   distance to the wall ahead).  Until its first zero of ``v`` the motion is the closed form
   with sign ``sigma`` and ``x`` moves towards ``sigma`` only: the wall behind is out of reach.
   If ``sigma v(t0 + H) < 0`` is proved over the set, the closed form has a zero in ``(0, H)``
   (intermediate values: ``sigma v > 0`` just after the start; a start with ``u = 0`` after an
   impact is a grazing impact, itself a zero of ``v``).  If moreover
   ``y0 - sigma (x(h) - x0) > 0`` is proved on ``[0, H]`` (:func:`positive`: mean-value forms
   on pieces), no wall comes first: the return takes at most ``H``.  Else let ``h_b`` be a
   time where the closed form is proved beyond the wall for every start (none: ``h_b = H``;
   neither: the box is not proved): by ``h_b`` every state has met its zero or the wall.
   Every impact happens at a relative time in ``[h_a, h_b]`` (the wall excluded on
   ``[0, h_a]``) with a speed ``V`` in ``[V_min, V_max]``, the bounds of ``sigma v`` over
   ``[h_a, h_b]`` and the set (``V_min`` 0 unless positive); the reset leaves ``-sigma e V``.
   The next stage: ``-sigma``, from the wall (``y0 = r - l``), times ``t0 + [h_a, h_b]``,
   speeds ``e [V_min, V_max]``; this one took at most ``h_b``.
4. A state's return time is the sum of its stages' times, at most their bounds' sum; the box is
   proved when that bound is ``<= 2T - tau`` for every ``tau`` of the box (at most
   ``MAX_STAGES`` stages).

Frictionless (``f = 0``, no damping): no state sticks and the release needs ``A != 0`` proved
for its sign; besides, a rest state whose flight meets neither wall on ``[0, T]`` has
``v(tau + T) = v(tau) = 0`` (the forcing integrates to 0 over a period): it returns within
``T`` exactly, whatever the sign of ``A`` (``s v(tau + T) = -f T`` of the friction case is 0).
Position forcing has no closed-form flight: not supported.
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Optional

from flint import arb

from reference.enclosure import motion
from reference.enclosure.balls import from_fraction, span
from reference.enclosure.certify import Unproved

#: Stages (flights between impacts) one return may take before the box is given up.
MAX_STAGES = 8
#: The zero search steps through a period in SCAN steps, then bisects REFINE times.
SCAN, REFINE = 64, 10
#: Pieces of the impact window for the impact-free time and the speed bound; bisections of a
#: piece in the proof that no wall is met.
PIECES, DEPTH = 32, 10


@dataclass
class BoxReturn:
    """What :func:`box_return` proved for one box (module docstring).

    ``proved``: every rest state of the box returns to rest within ``within`` (an exact ball,
    the bound; ``tau + within <= 2T``), ``stuck`` if every state sticks (``within`` 0).  Else ``reason``
    says which step failed and ``split`` the axis to split (``"xi"`` or ``"phi"``; None: no
    split helps).  ``stages``: the flights of the longest chain proved."""

    proved: bool
    stuck: bool = False
    within: Optional[arb] = None
    stages: int = 0
    reason: Optional[str] = None
    split: Optional[str] = "phi"


def tau_ball(m, phi):
    """The phases ``[phi0 T, phi1 T]`` as a ball (``phi`` exact rationals)."""
    return span(from_fraction(Fraction(phi[0])) * m.T, from_fraction(Fraction(phi[1])) * m.T)


def frictionless(m) -> bool:
    """``f = 0`` exactly and no damping: the periodic argument of the module docstring."""
    return not m.friction and not m.damping


def box_return(m, xi, phi, max_stages=MAX_STAGES) -> BoxReturn:
    """The certificate of the box ``xi x phi`` (module docstring) on the ball model ``m``
    (``balls.BallModel`` of a scene or a ``ParamBox``), at the current precision."""
    if m.position_forcing:
        return BoxReturn(False, reason="not supported: position forcing has no closed-form flight",
                         split=None)
    tau = tau_ball(m, phi)
    A = m.F * (m.w * tau).cos()
    if m.friction and A < m.f and A > -m.f:
        return BoxReturn(True, stuck=True, within=arb(0))
    sigma = 1 if A > -m.f else (-1 if A < m.f else 0)
    gap = m.r - m.l
    xis = span(from_fraction(Fraction(xi[0])), from_fraction(Fraction(xi[1])))
    if sigma == 0:
        if frictionless(m):
            return _periodic(m, tau, xis, gap)
        return BoxReturn(False, reason="the phases span the sticking band and both releases "
                                       "(|F cos w tau| > f upwards and downwards)")
    ahead = gap * (1 - xis) if sigma > 0 else gap * xis
    got = _chain(m, sigma, tau, ahead, gap, (2 * m.T - tau).lower(), max_stages)
    if not got.proved and frictionless(m):
        periodic = _periodic(m, tau, xis, gap)
        if periodic.proved:
            return periodic
    return got


def _chain(m, sigma, t0, y0, gap, deadline, max_stages) -> BoxReturn:
    """Steps 3 and 4 of the module docstring from the release (``u = 0``) at ``t0``, within
    ``deadline`` (exact) in all."""
    total, u = arb(0), arb(0)
    for stage in range(1, max_stages + 1):
        flight = motion.Flight(m, t0, arb(0), sigma * u, sigma)
        where = f"stage {stage} ({'release' if stage == 1 else 'after an impact'}, sigma {sigma:+d})"
        limit = (deadline - total).lower()
        H = first_negative(flight, lambda st: sigma * st[1], m.T, limit)
        wall = motion.EventFunction("wall ahead", 0, -sigma, y0)
        if H is not None and positive(flight, wall, arb(0), H):
            return BoxReturn(True, within=(total + H).upper(), stages=stage)
        h_b = first_negative(flight, lambda st: wall.const + wall.coef * st[0], m.T,
                             limit if H is None else H) or H
        if h_b is None:
            return BoxReturn(False, stages=stage, split="phi" if stage == 1 else None,
                             reason=f"{where}: neither a zero of v nor the wall proved by t = 2T "
                                    f"({float(limit):.4g} after the stage's start)")
        h_a = wall_free(flight, wall, h_b)
        low, high = speed_range(flight, sigma, h_a, h_b)
        total = total + h_b
        t0 = t0 + span(h_a, h_b)
        u = m.e * span(low, high)
        sigma, y0 = -sigma, gap
        if not u.upper() > 0:                    # e = 0: the impact ends in contact
            return BoxReturn(True, within=total.upper(), stages=stage)
    return BoxReturn(False, stages=max_stages, split=None,
                     reason=f"more than {max_stages} flights (impacts) before a proved zero of v")


def _periodic(m, tau, xis, gap) -> BoxReturn:
    """Frictionless: no wall on ``[0, T]`` (both excluded) gives ``v(tau + T) = 0``."""
    flight = motion.Flight(m, tau, arb(0), arb(0), 1)
    T = m.T.upper()
    try:
        for fn in (motion.EventFunction("wall r", 0, -1, gap * (1 - xis)),
                   motion.EventFunction("wall l", 0, 1, gap * xis)):
            if not positive(flight, fn, arb(0), T):
                raise Unproved(fn.name)
    except Unproved:
        return BoxReturn(False, reason="frictionless: the sign of F cos(w tau) is not fixed on the "
                                       "box and its flight meets a wall within a period")
    return BoxReturn(True, within=T, stages=1)


def first_negative(flight, value, T, limit):
    """An exact ``H <= limit`` with ``value(stack(H)) < 0`` proved over the flight's start set
    (steps of ``T / SCAN``, then ``REFINE`` bisections down towards the zero), else None."""
    step = (T / SCAN).mid()
    lo, k = arb(0), 1
    while True:
        h = (k * step).mid()
        if not h < limit:
            h = limit.mid()
        if value(flight.stack(h)) < 0:
            break
        if not h < limit.mid():
            return None
        lo, k = h, k + 1
    hi = h
    for _ in range(REFINE):
        mid = ((lo + hi) / 2).mid()
        if value(flight.stack(mid)) < 0:
            hi = mid
        else:
            lo = mid
    return hi


def _pieces(lo, hi):
    width = (hi - lo) / PIECES
    for k in range(PIECES):
        a, b = (lo + k * width).mid(), (lo + (k + 1) * width).mid() if k < PIECES - 1 else hi
        yield a, b


def _mean_value(flight, offset, a, b):
    """The range of ``stack[offset]`` over ``[a, b]``: value at the centre plus the derivative
    over the piece times the half-width (the mean-value theorem)."""
    c, r = ((a + b) / 2).mid(), ((b - a) / 2).upper()
    return flight.stack(c)[offset] + flight.stack(span(a, b))[offset + 1] * arb(0, r)


def positive(flight, fn, lo, hi) -> bool:
    """Whether the wall function ``fn`` (``const + coef x``) is proved positive on
    ``[lo, hi]`` for every start: the mean-value form on ``PIECES`` pieces, each failing piece
    bisected down to ``DEPTH`` more levels (a near-grazing box gives up early: its impact is
    then bounded instead)."""
    work = [(a, b, 0) for a, b in _pieces(lo, hi)]
    while work:
        a, b, depth = work.pop()
        if fn.const + fn.coef * _mean_value(flight, 0, a, b) > 0:
            continue
        if depth >= DEPTH:
            return False
        mid = ((a + b) / 2).mid()
        work += [(a, mid, depth + 1), (mid, b, depth + 1)]
    return True


def wall_free(flight, wall, H):
    """The largest piece end ``h_a`` (of ``PIECES`` over ``[0, H]``) with the wall function
    proved positive on ``[0, h_a]``."""
    reached = arb(0)
    for a, b in _pieces(arb(0), H):
        if not wall.const + wall.coef * _mean_value(flight, 0, a, b) > 0:
            break
        reached = b
    return reached


def speed_range(flight, sigma, lo, hi):
    """Exact bounds ``0 <= low <= high`` of ``sigma v`` over ``[lo, hi]`` (``low`` 0 unless
    ``sigma v`` is proved positive there)."""
    low, high = None, arb(0)
    for a, b in _pieces(lo, hi):
        piece = sigma * _mean_value(flight, 1, a, b)
        high = max(high, piece.upper())
        low = piece.lower() if low is None else min(low, piece.lower())
    return max(arb(0), low), high
