"""The paper's symmetric orbits over parameter boxes: where to cut, where to start, what to claim.

The symmetric solutions ``x_1`` (branch 1) and ``x_2`` (branch 2) of eq. ``nonstick`` and their
period-``m`` analogues (``reference.paper.symmetric_solution``) fly ``l -> r`` on
``psi <= w t <= psi + m pi`` and back.  Over a box:

* the section is the middle of the up-flight, ``w t = psi + m pi / 2``, rounded to a multiple
  of ``T / SECTION_GRID`` (:func:`section_ticks`) at the box's midpoint: away from both impacts
  for every parameter of a box whose impact phases ``arcsin(m pi f / 2F)`` move less than a
  quarter flight;
* the starting guess at a leaf is the closed form's state at that time (:func:`guess`), or the
  reason there is none (beyond the fold ``f/F > 2/(m pi)``, or the closed form sticks);
* the claim accepted of a proved leaf (:func:`claim_check`): exactly two impacts in the ``m``
  periods and nothing else (non-sticking), and the type (``"elliptic"``: ``|tr| < 2`` proved
  with ``det = 1``; ``"saddle"``: ``tr > 2`` proved; ``None``: any).

A leaf is proved as the stroboscopic map in multiple shooting (``method="shooting"``,
``boxes``) or in impact coordinates (``method="impacts"``, ``impacts``: the guess is then the
closed form's impact phases ``psi``, ``psi + m pi`` and its impact speed).

That the proved orbit is the symmetric one is by construction (it continues the closed form's
state); the symmetry itself is not part of the proof.
"""
from __future__ import annotations

from fractions import Fraction

import mpmath

from reference import paper as P
from reference.enclosure.continuation import cover
from reference.enclosure.impacts import prove_two_impacts
from reference.enclosure.shooting import SECTION_GRID

#: digits of the closed form's starting guess (Newton polishes it at the proof's precision)
GUESS_DPS = 60


def _times(scene, branch, m):
    """``(psi, T, w)`` of the closed form at ``GUESS_DPS`` (None beyond the fold)."""
    sol = P.symmetric_solution(scene, branch, m=m, dps=GUESS_DPS)
    if sol is None:
        return None
    w = scene.mpf("omega")
    return sol, 2 * mpmath.pi / w, w


def section_ticks(scene, branch, m=1):
    """The middle of the up-flight in units of ``T``, rounded to ``1 / SECTION_GRID`` (in
    ``[0, m)``); None beyond the fold."""
    got = _times(scene, branch, m)
    if got is None:
        return None
    with mpmath.workdps(GUESS_DPS):
        sol, T, w = got
        t = (sol.psi + m * mpmath.pi / 2) / w
        k = int(mpmath.nint(SECTION_GRID * t / T)) % (SECTION_GRID * m)
    return Fraction(k, SECTION_GRID)


def common_ticks(scene, branches, m=1):
    """The multiple of ``T / SECTION_GRID`` in ``[0, m)`` farthest from every impact of the
    given branches' closed forms (one section for several orbits: their balls compare there);
    None if a branch has no closed form."""
    impacts = []
    for b in branches:
        got = _times(scene, b, m)
        if got is None:
            return None
        with mpmath.workdps(GUESS_DPS):
            sol, T, w = got
            impacts += [float(((sol.psi + j * m * mpmath.pi) / w / T) % m) for j in (0, 1)]

    def gap(k):
        s = k / SECTION_GRID
        return min(min(abs(s - e), m - abs(s - e)) for e in impacts)

    return Fraction(max(range(SECTION_GRID * m), key=gap), SECTION_GRID)


def guess(branch, m, ticks, impacts=False):
    """``scene -> (x, v)``: the closed form's state at ``t = ticks T``, or why there is none;
    with ``impacts`` its impact coordinates ``(psi, V, psi + m pi, V)`` (``impacts``: the phases
    of the impacts on ``l`` and ``r``, ``V`` the impact speed)."""
    def at(scene):
        got = _times(scene, branch, m)
        if got is None:
            return f"no symmetric solution: f/F > 2/({m} pi) (eq. existence)"
        margin = P.nonstick_margin(scene, branch, m=m, dps=GUESS_DPS)
        if margin <= 0:
            return (f"the closed form x{branch} (m = {m}) sticks here (its velocity changes sign "
                    f"in flight: margin {mpmath.nstr(margin, 3)})")
        with mpmath.workdps(GUESS_DPS):
            sol, T, _ = got
            if impacts:
                return sol.psi, sol.v_impact, sol.tau, sol.v_impact
            t = T * ticks.numerator / ticks.denominator
            return sol.x(t), sol.v(t)
    return at


def claim_check(kind=None, impacts=2):
    """``proof -> None | reason``: ``impacts`` impacts and no other event, and the type."""
    def check(proof):
        if proof.itinerary != ["impact"] * impacts:
            return f"the itinerary is {proof.itinerary}, not {impacts} impacts (non-sticking)"
        if kind == "elliptic" and proof.kind != "elliptic":
            return f"elliptic not proved (|tr| < 2 with det = 1): {proof.kind}, trace {proof.trace}"
        if kind == "saddle" and not (proof.kind == "saddle" and proof.trace > 2):
            return f"a saddle with tr > 2 not proved: {proof.kind}, trace {proof.trace}"
        return None
    return check


#: how a leaf is proved: the stroboscopic map in multiple-shooting form (``shooting``), or the
#: impacts as unknowns (``impacts``: no ``1/V`` blow-up at slow impacts; no damping)
METHODS = ("shooting", "impacts")


def symmetric_cover(box, branch, m=1, *, kind=None, ticks=None, max_leaves=64, prec=None,
                    method="shooting"):
    """``continuation.cover`` of the symmetric orbit ``x_branch`` (period ``m``) over ``box``,
    at the section ``ticks`` (default :func:`section_ticks` at the box's midpoint), with
    :func:`claim_check` of ``kind``, each leaf proved by ``method`` (:data:`METHODS`).
    ``(cover, ticks)``; ``cover`` is None (with the reason as ``ticks``) when the box's
    midpoint has no closed form.  (``impacts`` leaves do not try uniqueness in their state
    ball: on leaves as wide as the atlas's it does not hold, and it would cost as much as the
    proof.)"""
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    mid = box.midpoint()
    ticks = section_ticks(mid, branch, m) if ticks is None else Fraction(ticks)
    if ticks is None:
        return None, f"no symmetric solution at the box's midpoint: f/F > 2/({m} pi)"
    at = {} if prec is None else {"prec": prec}
    prove = None if method == "shooting" else (
        lambda leaf, state: prove_two_impacts(leaf, state, periods=m, ticks=ticks, unique=False, **at))
    got = cover(box, guess(branch, m, ticks, impacts=method == "impacts"),
                phase=ticks - (ticks.numerator // ticks.denominator),
                periods=m, accept=claim_check(kind), max_leaves=max_leaves, prove=prove, **at)
    return got, ticks
