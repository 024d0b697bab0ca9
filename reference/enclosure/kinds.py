"""What an orbit proof returns and what its multiplier enclosures prove (``orbits``, ``boxes``).

The multipliers are the eigenvalues of ``P'`` at the fixed point, enclosed through ``tr`` and
``det``: ``lambda = (tr +- sqrt(tr^2 - 4 det)) / 2``.  The type follows when the enclosures
decide it: a saddle (real, ``|l1| > 1 > |l2|``), an attracting focus or node (``|l| < 1``:
hyperbolic, so attracting for the map too, by Hartman-Grobman), or -- without friction's
turns and stops, restitution and damping, where every Table 1 factor has determinant 1, so
``det P' = 1`` exactly -- an elliptic point (non-real multipliers on the unit circle).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Optional

from flint import arb


@dataclass
class OrbitProof:
    """The outcome of :func:`prove_periodic`.

    ``proved``: a unique fixed point of ``Phi^k`` lies in ``box`` (centre +- ``radius``), in
    the balls ``point = (x, v)``; ``multipliers`` their enclosures (real balls, or
    ``(re, im)`` pairs for a complex pair); ``kind`` the type the enclosures prove and
    ``stability`` what that says (and what it does not); ``itinerary`` the event kinds of one
    orbit period.  Else ``reason``, and ``residual`` where the Krawczyk test failed on the
    residual alone (the radius of ``C (P(z) - z)``, wider than the box: at ``prec`` bits the
    walk lost ``~log2(residual) + prec`` bits, which a caller may use to pick its next precision),
    ``spread`` where ``P'`` at the Newton centre was too wide for any Krawczyk box
    (``orbits._spread``: it shrinks ~``2^-(bits / 2)`` with more bits, the flights' derivative
    being carried to half the precision), ``miss`` where the box was walked and ``K(Z)`` still
    not inside ``Z`` (the largest ``|K - z~|``, to compare with ``radius``), and ``diverged``
    where Newton diverged from the seed (no precision helps).
    """

    proved: bool
    periods: int
    reason: Optional[str] = None
    point: tuple = ()
    radius: float = 0.0
    multipliers: list = field(default_factory=list)
    trace: object = None
    det: object = None
    kind: str = ""
    stability: str = ""
    itinerary: list = field(default_factory=list)
    prec: int = 0
    seconds: float = 0.0
    phase: object = 0
    residual: float = 0.0
    spread: float = 0.0
    miss: float = 0.0
    #: Newton diverged from the seed (``orbits.DIVERGE_GROWTH``): more bits take the same path
    diverged: bool = False
    #: a Krawczyk test that failed after Newton converged: the polished centre ``z~`` (exact
    #: balls), a seed for a proof with more bits (whose Newton then starts converged)
    centre: tuple = ()


#: the kinds ``classify`` gives where the enclosures do not decide the type
UNDECIDED = frozenset({"real multipliers", "complex multipliers", "undecided"})


def classify(scene, tr, det, kinds):
    """``(kind, stability, multipliers)`` from enclosures of ``tr`` and ``det`` of ``P'``.

    ``det P' = 1`` exactly when the orbit has only flights and elastic impacts (no turn,
    stop or contact) and no damping: every such Table 1 factor has determinant 1 (flight
    ``[[1, h], [0, 1]]``, reflection ``[[-1, 0], [*, -1]]``; under position forcing the
    flight factor solves ``V' = [[0, 1], [A_x, 0]] V``, trace 0, so ``det V = 1`` by
    Liouville) -- a theorem, used as such.
    """
    conservative = (all(k == "impact" for k in kinds) and not scene.has("restitution")
                    and not scene.has("damping"))
    if conservative:
        det = arb(1)
    disc = tr * tr - 4 * det
    if disc > 0:
        root = disc.sqrt()
        l1, l2 = (tr + root) / 2, (tr - root) / 2
        if not (abs(l2) < 1 or abs(l2) > 1) and (tr > 0 or tr < 0):
            # a wide trace: the small root as det / (the large one), no cancellation
            big_root = l1 if tr > 0 else l2
            l1, l2 = big_root, det / big_root
        big = [abs(l) > 1 for l in (l1, l2)]
        small = [abs(l) < 1 for l in (l1, l2)]
        if (big[0] and small[1]) or (big[1] and small[0]):
            return "saddle", "unstable (hyperbolic saddle: proved)", [l1, l2]
        if all(small):
            return "attracting node", "asymptotically stable (hyperbolic: proved)", [l1, l2]
        if all(big):
            return "repelling node", "unstable (hyperbolic: proved)", [l1, l2]
        return "real multipliers", "type not decided by the enclosures", [l1, l2]
    if disc < 0:
        re, im = tr / 2, (-disc).sqrt() / 2
        if conservative:
            return ("elliptic", "linearly stable: non-real multipliers on the unit circle "
                    "(proved, det = 1 exactly); nonlinear stability not proved (KAM)", [(re, im)])
        if det < 1:
            return "attracting focus", "asymptotically stable (|lambda|^2 = det < 1: proved)", [(re, im)]
        if det > 1:
            return "repelling focus", "unstable (|lambda|^2 = det > 1: proved)", [(re, im)]
        return "complex multipliers", "modulus not decided by the enclosures", [(re, im)]
    return "undecided", "tr^2 - 4 det encloses 0: real or complex not decided", []
