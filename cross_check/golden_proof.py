"""The proofs of golden inputs (``cross_check.golden``): each input's enclosure record and the
band flag, settled by ``reference.enclosure.enclose_map``.

* ``enclosure``: ``proved`` and, if so, balls ``[mid, radius]`` that provably contain ``Phi`` and
  ``Phi'`` (``ENCLOSURE_DIGITS``-digit midpoints, radii rounded up and widened to
  ``golden_enclosure_floor``: a superset of a proved ball is proved), ``radius`` the relative
  radius actually proved for ``Phi`` and ``prec`` the bits it took; else ``reason``.  Under
  position forcing the first proof is ``position_proof`` (192 bits, or up to 256 where 192 is
  too wide: ``climb``; ``Phi'`` to the working precision), whose balls also certify the values of
  ``golden.proved_values``;
* ``band``: whether the reference's itinerary flips under a move of ``compare_band_ulps`` ulps,
  settled by one proof over the box of the moves where one holds;
* ``ball_within``: the test that a whole ball lies within a relative distance of a value.
"""
from __future__ import annotations

import math
from fractions import Fraction

import mpmath

from cross_check.agreement import compare
from cross_check.tolerances import tol
from reference.enclosure import enclose_map
from reference.enclosure.balls import decimal_ball, from_mpf, radius_text, to_mpf, workprec

#: Significant digits of an enclosure's midpoint (its rounding is added to the radius).
ENCLOSURE_DIGITS = 50


def ball_record(ball) -> list:
    """``[mid, radius]`` strings of a ball that contains ``ball`` and is at least
    ``golden_enclosure_floor`` wide (at the current arb precision)."""
    floor = tol("golden_enclosure_floor")
    mid, radius = decimal_ball(ball, ENCLOSURE_DIGITS)
    return [mid, radius_text(max(radius, floor.rtol * abs(float(mid)) + floor.atol))]


#: bits of the first, cheaper proof under position forcing, and the most that a proof which holds
#: but is wider than ``golden_enclosure_floor`` is made again with (issue 33: the validated Taylor
#: steps cost ~p^2, p = prec ln 2 / 2; at 192 bits a proof of ``Phi`` to ~1e-53 takes half the time
#: of 320 bits, ample for the floor unless the period loses more than ~15 digits -- ~20 fast
#: impacts, or near grazing -- where 256 bits, at ~1.8x the cost of 192, keep up to ~34); a proof
#: still wider than the floor is redone the usual way (from ``DEFAULT_PREC`` up), after the dps
#: 90 / 110 pair (``golden``).  Scene W of issue 33 (``F=3 f=0.3 omega=0.5 l=-2 r=2
#: wavenumber=2``, one run each): five of its 24 inputs were 1.0e-43 to 1.1e-42 wide at 192 bits
#: and took that road, 12 to 25 CPU s each
ENCLOSURE_PRECS_POSITION = (192, 256)
#: A proof's radius scales as ``2^-prec`` (every remainder is below ``2^-prec`` of the state, and
#: the period amplifies them all alike): a proof ``rho`` wide at ``prec`` bits is made again at
#: ``prec + log2(rho / floor) + CLIMB_MARGIN_BITS``, rounded up to ``CLIMB_STEP_BITS`` (at most
#: the last of ``ENCLOSURE_PRECS_POSITION``).  Measured on scenes W and Y of issue 33 (7 inputs, one
#: run each): 16 more bits took the radius down by 6.4e4 to 6.7e4 (2^16 = 6.6e4); W's inputs
#: 1e-43 to 7e-40 wide at 192 bits need 200 to 216 (1.7 to 1.9 CPU s, against 2.3 to 2.9 at 256),
#: the frictionless Y's 3e-37 wide 224 (1.6 against 2.0).
CLIMB_MARGIN_BITS = 4
CLIMB_STEP_BITS = 8


def climb(prec: int, radius: float, floor: float) -> int:
    """The bits to make again a proof ``radius`` wide at ``prec`` bits (``radius > floor``), so
    that it is within ``floor`` (``CLIMB_MARGIN_BITS``); more than ``prec``."""
    need = prec + math.log2(radius / floor) + CLIMB_MARGIN_BITS
    return min(ENCLOSURE_PRECS_POSITION[-1], CLIMB_STEP_BITS * math.ceil(need / CLIMB_STEP_BITS))


def position_proof(sc, case, points=None):
    """The first proof of a position-forced input, at ``ENCLOSURE_PRECS_POSITION[0]`` bits, made
    again with more bits (:func:`climb`, up to the last of ``ENCLOSURE_PRECS_POSITION``) while it
    holds but is wider than ``golden_enclosure_floor`` (the last one made is returned); the
    flights' ``Phi'`` to the working precision (``full_derivative``: what ``proved_values``
    needs); ``points``: a point log of the input to guide every proof (``enclose_map``), e.g.
    ``golden.compute``'s.  Each proof has more bits than the one before, so there are at most
    ``last - first`` of them."""
    x, v = _proof_start(case)
    floor = tol("golden_enclosure_floor").rtol
    first, last = ENCLOSURE_PRECS_POSITION[0], ENCLOSURE_PRECS_POSITION[-1]
    prec = first
    for _ in range(last - first + 1):
        enc = enclose_map(sc, x, v, prec=prec, max_prec=prec, full_derivative=True, points=points)
        if not enc.proved or enc.rel_radius() <= floor or prec >= last:
            break               # more bits help a proof that holds but is wide, not one that fails
        prec = climb(prec, enc.rel_radius(), floor)
    return enc


def _proof_start(case):
    return (float(case.x), float(case.v)) if case.exact == "float64" else (case.x, case.v)


def enclosure(sc, case, first=None) -> dict:
    """The proof record of one input (see the module docstring); ``first``: its
    ``position_proof`` if already made (under position forcing that proof comes first, and is
    kept if it is within ``golden_enclosure_floor``: ``prove --golden`` makes it again)."""
    x, v = _proof_start(case)
    floor = tol("golden_enclosure_floor").rtol
    enc = first
    if enc is None and sc.has("position_forcing"):
        enc = position_proof(sc, case)
    enc = enc if enc is not None and enc.proved and enc.rel_radius() <= floor else None
    enc = enc or enclose_map(sc, x, v, rel_radius=floor)
    if not enc.proved:
        return {"proved": False, "reason": enc.reason}
    with workprec(enc.prec):
        return {"proved": True, "radius": radius_text(enc.rel_radius()), "prec": enc.prec,
                "phi": [ball_record(b) for b in enc.phi],
                "jacobian": [[ball_record(b) for b in row] for row in enc.jacobian]}


#: bits of the proofs that settle ``band``, tried in turn (a box of a few ulps needs no more):
#: 64 bits settles most inputs at a quarter of 128's cost (Taylor order 22 instead of 44, as
#: many steps); 128 is tried where 64 does not prove (issue 33, scene D: 5.8 -> 3.9 CPU s for its
#: 16 inputs, the same flags; 2.0 of the 3.9 are the moves of the 5 inputs no proof settles)
BAND_PRECS = (64, 128)
#: digits of the reference's runs from the moved starts where no proof settles ``band`` (the
#: input's own itinerary comes from its ``PROVED_DPS`` run).  A move is ``compare_band_ulps`` ulps:
#: its itinerary differs from the input's only if an event is that close to grazing, which 30
#: digits resolve with ~15 to spare.  Issue 33, the frictionless far corner ``F=2 f=0 omega=0.5
#: l=-1 r=1 wavenumber=2`` (11 to 49 impacts a period): the box proofs fail on 6 of its 8 samples
#: (the walk's balls wrap by ~1e15 over 30 impacts, where ``|Phi'|`` is ~12), and the six moves
#: took 1.9 to 3.9 CPU s an input at 50 digits, 1.1 to 2.2 at 30, the same itineraries (one run)
BAND_MOVE_DPS = 30


def band(sc, case, points=None, events=None) -> bool:
    """``compare.reference_in_band`` (the reference's itinerary flips under a move of
    ``compare_band_ulps`` ulps), settled first by a proof: if ``enclose_map`` proves one itinerary
    for every start of the box that holds all the moves (cut to the gap), none flips (issue 33:
    the six moved runs of the reference were a quarter of a position-forced input's cost; the
    proof costs a fifth of them).  Where no proof holds (near grazing, or where the walk's balls
    wrap: ``BAND_MOVE_DPS``) the moves are run.

    ``points``: the input's own point log (``golden.compute``'s), to guide the proofs as it
    guides ``position_proof``: the box is a few ulps around the input, and a guide only guides
    (the walk proves every event from the balls).  Without it each proof runs the point
    integrator itself: on scene D (issue 33) 1.9 of the 2.7 CPU s of its 16 inputs' band
    proofs, with the same flags either way (one run each).  ``events``: that run's events (its
    dps-50 itinerary is the one the moves are compared with: one reference run fewer where the
    moves are run)."""
    X, V = case.float()
    k = int(tol("compare_band_ulps").rtol)
    ux, uv = (float(u) * k for u in compare.ulps(sc, X, V))       # the box that holds every move
    lo, hi = max(Fraction(X) - Fraction(ux), sc.exact("l")), min(Fraction(X) + Fraction(ux), sc.exact("r"))
    for prec in BAND_PRECS:
        if enclose_map(sc, (lo + hi) / 2, Fraction(V), x_radius=(hi - lo) / 2, v_radius=Fraction(uv),
                       prec=prec, max_prec=prec, points=points).proved:
            return False
    return compare.reference_in_band(sc, case, dps=BAND_MOVE_DPS, events=events)


def midpoints(balls) -> list:
    """The midpoints of a matrix of balls as exact ``mpf`` (``golden.proved_values``' Jacobian)."""
    return [[midpoint(b) for b in row] for row in balls]


def midpoint(ball):
    """The midpoint of a ball as an exact ``mpf`` (``golden.from_balls``)."""
    with mpmath.workprec(ball.mid().man_exp()[0].bit_length() + 8):
        return to_mpf(ball)


def ball_within(value, ball, rtol) -> bool:
    """Every point of ``ball`` within ``rtol max(1, |value|)`` of ``value`` (``value`` mpf)."""
    with workprec(256):                  # outward rounding: any precision is rigorous
        d = abs(ball - from_mpf(value))
        return bool(d.upper() <= rtol * max(1.0, abs(float(value))))
