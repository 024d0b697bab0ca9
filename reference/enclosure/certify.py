"""Certificates on one motion: an event function has no zero on an interval (exclusion), or
exactly one zero in a ball, which is enclosed (Krawczyk).

Exclusion (:func:`exclude`) proves ``g > 0`` on ``(lo, hi]`` by bisection.  On a piece
``I = [c - r, c + r]`` the second-order Taylor form

    g(u) in g(c) + g'(c) [-r, r] + g''(I) [0, r^2/2]           (u in I)

is a certain lower bound (``g''(I)`` encloses ``g''`` over the piece and over every start
state of the box); a piece whose bound is not positive is split.  On the first piece, when the
start is a structural zero of order ``m`` (``g, ..., g^(m-1)`` vanish exactly at ``u = 0``:
see ``reference.enclosure.motion``), ``g^(m) > 0`` on ``[0, b]`` proves ``g > 0`` on
``(0, b]`` (Taylor's theorem with the Lagrange remainder).  Every loop is bounded:
``MAX_PIECES`` pieces and pieces no narrower than the working precision resolves.

Root (:func:`root`): the parametric Krawczyk operator (Krawczyk 1969; Moore, Kearfott and
Cloud, *Introduction to Interval Analysis*, 2009, sec. 8.2),

    K(H) = m - Y g(m) + (1 - Y g'(H)) (H - m),   m = mid H,  Y = 1 / mid g'(m),

with ``g(m)`` and ``g'(H)`` enclosed over the whole start box: if ``K(H)`` lies in the interior
of ``H``, then *for every start state of the box* ``g`` has exactly one zero in ``H``, and it
lies in ``K(H)``.  A wide ``H`` is tried first (uniqueness on a wide ball leaves less to
exclude), then ``H <- K(H) & H`` tightens the enclosure to what the box and the precision
allow.
"""
from __future__ import annotations

from flint import arb, ctx

from reference.enclosure.balls import span

#: Most pieces one exclusion may use before it gives up (a near-tangency needs ~2 log2(1/d)).
MAX_PIECES = 4000
#: Krawczyk: tries from the widest ball down (each 2^-RHO_STEP narrower), and tightenings.
RHO_STEP = 6
MAX_TIGHTEN = 200
#: Epsilon-inflations of a Krawczyk ball when the ladder finds none (wide boxes of starts).
INFLATE = 8
#: Over a wide box of starts the tightening goes on while a step shrinks the ball this much.
WIDE_RATIO = 0.98


class Unproved(Exception):
    """A certificate could not be established; the message says which and where."""


def _stack_value(motion, fn, u, k):
    return fn.derivative(motion.stack(u), k)


def _tiny(a, b) -> bool:
    width = b - a
    return not (width > (abs(a) + abs(b) + 1) * arb(2) ** (-ctx.prec + 12))


def _positive_on(motion, fn, a, b, at_start: bool) -> bool:
    piece = span(a, b)
    if at_start:
        return bool(_stack_value(motion, fn, piece, fn.order) > 0)
    c, r = piece.mid(), piece.rad()
    near = motion.stack(c)
    lower = (fn.derivative(near, 0) + fn.derivative(near, 1) * arb(0, r)
             + _stack_value(motion, fn, piece, 2) * arb(r * r / 4, r * r / 4))
    return bool(lower > 0)


def exclude(motion, fn, lo, hi, what: str) -> int:
    """Prove ``fn > 0`` on ``(lo, hi]`` (on ``[lo, hi]`` if ``fn.order == 0``); ``lo``, ``hi``
    exact balls.  Returns the number of pieces used; raises :class:`Unproved` otherwise."""
    if not hi > lo:
        return 0
    work, pieces = [(lo, hi)], 0
    while work:
        a, b = work.pop()
        pieces += 1
        if pieces > MAX_PIECES:
            raise Unproved(f"{what}: {fn.name} not excluded on [{a.mid().str(8)}, {b.mid().str(8)}] "
                           f"within {MAX_PIECES} pieces (a near-tangency)")
        if _positive_on(motion, fn, a, b, at_start=(fn.order > 0 and a is lo)):
            continue
        if _tiny(a, b):
            raise Unproved(f"{what}: {fn.name} may vanish near u = {a.mid().str(20)} "
                           f"(a tangency or grazing within the working precision)")
        mid = ((a + b) / 2).mid()
        work.append((mid, b))
        work.append((a, mid))
    return pieces


def _krawczyk(motion, fn, H, Y):
    m = H.mid()
    g_m = _stack_value(motion, fn, m, 0)
    g1_H = _stack_value(motion, fn, H, 1)
    return m - Y * g_m + (1 - Y * g1_H) * (H - m)


def root(motion, fn, guess, lo, what: str):
    """The unique zero of ``fn`` near ``guess`` (an exact ball), above ``lo``.

    Returns ``(wide, tight)``: ``wide`` a ball in which the zero is unique for every start
    of the box (the contracting ball ``H`` itself, so that the exclusion before it stops as far
    from the zeros as the contraction allows: over a wide box of starts the zeros spread and
    ``K(H)`` hugs them), ``tight`` the enclosure of the zero.  :class:`Unproved` if no ball
    works (a double zero: grazing or tangency).
    """
    guess = _refine(motion, fn, guess, lo)
    slope = _stack_value(motion, fn, guess, 1)
    if slope.contains(0):
        raise Unproved(f"{what}: {fn.name} has a vanishing slope at its zero u = "
                       f"{guess.str(20)} (a tangency)")
    Y = 1 / slope.mid()
    widest = ((guess - lo) / 4).mid()
    floor = ((abs(guess) + 1) * arb(2) ** (-ctx.prec + 16)).mid()
    found = _first_contracting(motion, fn, guess, Y, widest, arb(2) ** -RHO_STEP, floor, both=True)
    if found is None:       # a wide start box: the contracting balls lie between two rungs
        found = _inflated(motion, fn, guess, Y, lo, floor)
    if found is None:
        raise Unproved(f"{what}: no Krawczyk ball around u = {guess.str(20)} for {fn.name} "
                       f"(a double zero, or the box is too wide)")
    unique, image = found
    narrow = _first_contracting(motion, fn, guess, Y, floor, arb(2) ** RHO_STEP, image.rad())
    return unique, _tighten(motion, fn, narrow if narrow is not None else image, Y)


def _refine(motion, fn, guess, lo):
    """Polish the point integrator's event time (near a tangency it carries half the digits)
    by Newton steps on the quadratic model ``g0 + g1 d + g2 d^2/2``: the root where ``g``
    decreases, ``d = 2 g0 / (sqrt(g1^2 - 2 g0 g2) - g1)``; plain Newton if the model has no
    root.  Midpoints only: a better centre for the Krawczyk test, not a claim."""
    for _ in range(12):
        stack = motion.stack(guess)
        g0, g1, g2 = (fn.derivative(stack, k).mid() for k in range(3))
        disc = g1 * g1 - 2 * g0 * g2
        if disc > 0 and (disc.sqrt() - g1) > 0:
            step = 2 * g0 / (disc.sqrt() - g1)
        elif g1 != 0:
            step = -g0 / g1
        else:
            return guess
        new = (guess + step).mid()
        if not new > lo or new == guess:
            return guess
        guess = new
    return guess


def _first_contracting(motion, fn, guess, Y, rho, factor, stop, both=False):
    """The first ball ``H = guess +- rho`` (``rho`` scaled by ``factor`` from try to try, until
    it passes ``stop``) whose Krawczyk image ``K`` lies in its interior: ``K`` (``(H, K)`` with
    ``both``); else None."""
    for _ in range(4 * MAX_TIGHTEN):
        if (factor < 1 and not rho > stop) or (factor > 1 and not rho < stop):
            return None
        H = arb(guess, rho)
        K = _krawczyk(motion, fn, H, Y)
        if H.contains_interior(K):
            return (H, K) if both else K
        rho = (rho * factor).mid()
    return None


def _inflated(motion, fn, guess, Y, lo, floor):
    """Epsilon-inflation (Rump): ``rho = 2 |Y g(guess)|``, then ``rho <- 2 |K(H) - guess|``
    while ``K(H)`` is not inside ``H = guess +- rho`` (``INFLATE`` tries, ``H`` above ``lo``):
    the ball a wide box of starts needs, which the ladder of ``2^RHO_STEP`` may step over.
    ``(H, K)`` as :func:`_widest` gives them, or None."""
    rho = (2 * abs(Y * _stack_value(motion, fn, guess, 0)) + floor).upper()
    for _ in range(INFLATE):
        H = arb(guess, rho)
        if not H.lower() > lo:
            return None
        K = _krawczyk(motion, fn, H, Y)
        if H.contains_interior(K):
            return _widest(motion, fn, guess, Y, lo, rho, K)
        grown = (2 * abs(K - guess)).upper()
        if not grown.is_finite():
            return None
        rho = max(grown, (rho * 1.5).upper())
    return None


def _widest(motion, fn, guess, Y, lo, rho, K):
    """``(H, K)``: the widest ball ``H = guess +- 2^j rho`` (``j <= INFLATE``) that still
    contracts (the zero is unique on it, which leaves the exclusion less to prove next to the
    zero), and the image ``K`` of the first one (the tightening starts there)."""
    wide = arb(guess, rho)
    for _ in range(INFLATE):
        rho = (2 * rho).upper()
        H = arb(guess, rho)
        if not H.lower() > lo or not H.contains_interior(_krawczyk(motion, fn, H, Y)):
            break
        wide = H
    return wide, K


def _tighten(motion, fn, H, Y):
    """``H <- K(H) & H`` with a fresh ``Y`` each time, while the radius keeps shrinking (the
    Krawczyk operator is a contraction of ratio ``|1 - Y g'(H)|``, quadratic once narrow).
    A ball still wider than half the working precision (a wide box of starts: the zeros
    spread, the contraction is linear) goes on while it shrinks by ``WIDE_RATIO`` a step."""
    wide = (abs(H.mid()) + 1) * arb(2) ** (-ctx.prec // 2)
    for _ in range(MAX_TIGHTEN):
        slope = _stack_value(motion, fn, H.mid(), 1)
        if not slope.contains(0):
            Y = 1 / slope.mid()
        K = _krawczyk(motion, fn, H, Y).intersection(H)
        ratio = WIDE_RATIO if K.rad() > wide else 0.75
        if not K.rad() < H.rad() * ratio:
            return K
        H = K
    return H
