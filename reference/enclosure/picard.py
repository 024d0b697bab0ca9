"""A priori enclosures of a validated flight (the first step of every Lohner step,
``reference.enclosure.lohner``, and of the hand-off's run back to ``base``,
``reference.enclosure.handoff``).

For an equation ``z' = f(t, z)`` and a set ``Y`` of states at the times ``t_span``, a box ``B``
with ``N = Y + hball f(t_span, B)`` in the interior of ``B`` (``hball`` the times ``[0, h]``,
or ``[-h, 0]`` backward) proves that every solution from ``Y`` exists over those times and
stays in ``N``: the Picard operator maps the continuous paths in ``B`` into those in ``N``, and
``f`` is Lipschitz on ``B``, so there is one solution (Lohner 1987; Nedialkov, Jackson and
Corliss 1999).  The comparisons are certain (ball arithmetic), the widening a heuristic.
"""
from __future__ import annotations

from flint import arb, ctx

#: Bound on the Picard iterations of one a priori box (each widens the box and tries again).
PICARD_TRIES = 12


def near_identity(e):
    """``I + [-e, e]`` entrywise (``e`` an exact nonnegative ball)."""
    return [[1 + arb(0, e), arb(0, e)], [arb(0, e), 1 + arb(0, e)]]


def interval(h):
    """The ball ``[0, h]`` (``h >= 0`` exact)."""
    return arb(h / 2, h / 2) if not h.is_zero() else arb(0)


def contracts(field, t_span, Y, hball, B):
    """The Picard test: ``N = Y + hball f(t_span, B)`` if it lies in the interior of ``B``
    (then every solution from ``Y`` at a time of ``t_span`` exists over the times ``hball``
    and stays in ``N``), else ``None``."""
    N = [Y[0] + hball * B[1], Y[1] + hball * field.accel(t_span, B[0], B[1])]
    return N if B[0].contains_interior(N[0]) and B[1].contains_interior(N[1]) else None


def picard_box(field, t_span, Y, hball):
    """An a priori enclosure over the times ``hball`` (``[0, h]`` or ``[-h, 0]``): iterate
    ``B <- Y + hball f(B)``, widened, until :func:`contracts` verifies it; ``None`` if no box
    verifies within ``PICARD_TRIES`` widenings."""
    x, v = Y
    N = [x + hball * v, v + hball * field.accel(t_span, x, v)]
    for _ in range(PICARD_TRIES):
        B = [n + arb(0, n.rad() + (abs(n.mid()) + 1) * arb(2) ** (-ctx.prec + 8)) for n in N]
        verified = contracts(field, t_span, Y, hball, B)
        if verified is not None:
            return verified
        N = [x + hball * B[1], v + hball * field.accel(t_span, B[0], B[1])]
    return None
