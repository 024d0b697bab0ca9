"""Proofs over parameter ranges: a box covered by sub-boxes, an interval by a chain of boxes.

``cover(box, guess, ...)`` proves a periodic orbit for every parameter of ``box`` with
``boxes.prove_periodic_box``, bisecting where a box is too wide to prove at once: the box is
proved if every leaf is (the leaves tile it exactly: splits are at exact midpoints).  Each
leaf's statement is its own (a unique fixed point in its state box, for every parameter of the
leaf); the cover's ``hull`` is a ball that holds the fixed point for every parameter of the
whole box.  The section ``t = phase T`` is one for all leaves (taken at the box's midpoint), so
that the hull is a statement about one section.

``prove_interval(prove_box, lo, hi, ...)`` is rigorous continuation (Church & Fortin): the
interval ``[lo, hi]`` of one parameter is covered by consecutive boxes ``[a, b]``, each proved
by ``prove_box`` (typically one or more ``cover``); a box that fails is halved (down to
``min_width``), a proved box lets the next one grow (``GROW``), so the chain adapts to the
branch (fine near a fold, coarse elsewhere).  It stops at the first gap it cannot close and
reports how far it got: the statement holds for every parameter of ``[lo, reached]``.

Every loop is bounded (``max_leaves`` per box, ``max_boxes`` per interval); exceeding a bound
ends the proof with the reason, never with a "proved".
"""
from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Callable, Optional

from reference.enclosure.balls import workprec
from reference.enclosure.boxes import BOX_PREC, BoxOrbitProof, prove_periodic_box
from reference.enclosure.params import PARAMS, ParamBox

#: After a proved box, the next one is this much wider (and a failed one is halved).
GROW = Fraction(3, 2)


@dataclass
class Cover:
    """What :func:`cover` proved: ``proved`` iff every leaf is; ``leaves`` the proved leaves,
    ``failed`` the leaf that could not be proved (and ``reason``), ``attempts`` the proofs run."""

    box: ParamBox
    phase: Fraction
    proved: bool
    leaves: list = field(default_factory=list)
    reason: Optional[str] = None
    failed: Optional[BoxOrbitProof] = None
    attempts: int = 0

    def hull(self):
        """``(x, v, trace)``: balls holding, for every parameter of the box, the fixed point at
        ``t = phase T`` and its trace (the union of the leaves' balls; None if not proved)."""
        if not self.proved or not self.leaves:
            return None
        prec = max(p.prec for p in self.leaves)
        with workprec(prec):
            out = [self.leaves[0].point[0], self.leaves[0].point[1], self.leaves[0].trace]
            for p in self.leaves[1:]:
                out = [a.union(b) for a, b in zip(out, (p.point[0], p.point[1], p.trace))]
        return tuple(out)


def _split_name(box, root, hint, min_fraction):
    """The parameter to halve: the proof's ``hint`` (where the spread weighs most), else the
    relatively widest; one already narrower than ``min_fraction`` of the root box gives way to
    the next.  None when every one is."""
    wide = sorted((n for n in PARAMS if root.width(n) > 0), key=lambda n: -box.width(n) / root.width(n))
    for n in ([hint] if hint in wide else []) + wide:
        if box.width(n) >= root.width(n) * min_fraction * 2:
            return n
    return None


def cover(box: ParamBox, guess: Callable, *, phase, periods: int = 1,
          accept: Optional[Callable] = None, max_leaves: int = 64,
          min_fraction: Fraction = Fraction(1, 64), prec: int = BOX_PREC,
          prove: Optional[Callable] = None) -> Cover:
    """Prove the orbit for every parameter of ``box`` (module docstring).

    ``guess(scene)``: the orbit's state ``(x, v)`` at ``t = phase T`` for a scene (the
    midpoint of a leaf), or a string saying why there is none (then the box is not proved).
    ``accept(proof)``: ``None`` if a proved leaf says what is claimed (its type, its
    itinerary), else the reason it does not (a leaf that fails it is split like a failed
    one: the claim may hold on its halves).  A leaf narrower than ``min_fraction`` of the box
    in the direction it would be split, or more than ``max_leaves`` attempts, ends the cover
    unproved.  ``prove(leaf, state)``: the leaf's proof (a :class:`BoxOrbitProof`), by default
    ``boxes.prove_periodic_box`` from the state ``(x, v)`` at ``t = phase T``."""
    if not isinstance(box, ParamBox):
        raise TypeError(f"box must be a ParamBox, got {type(box).__name__}")
    phase = Fraction(phase)
    out = Cover(box, phase, False)
    work = [box]
    while work:
        leaf = work.pop()
        if out.attempts >= max_leaves:
            out.reason = f"more than {max_leaves} sub-boxes needed (last: {leaf})"
            return out
        out.attempts += 1
        state = guess(leaf.midpoint())
        if isinstance(state, str):
            out.reason = f"no candidate orbit at {leaf.midpoint()!r}: {state}"
            return out
        proof = (prove(leaf, state) if prove is not None else
                 prove_periodic_box(leaf, state[0], state[1], periods=periods, phase=phase, prec=prec))
        why = proof.reason if not proof.proved else (accept(proof) if accept else None)
        if why is None:
            out.leaves.append(proof)
            continue
        name = _split_name(leaf, box, proof.split, min_fraction)
        if name is None:
            out.reason, out.failed = f"on {leaf}: {why}", proof
            return out
        low, high = leaf.split(name)
        work += [high, low]
    out.proved = True
    return out


@dataclass
class Interval:
    """What :func:`prove_interval` proved: the statement for every parameter of
    ``[lo, reached]`` (``reached == lo``: nothing), one ``(a, b, proof)`` per box of the chain;
    ``reason`` why it stopped before ``hi`` (None if it reached ``hi``)."""

    lo: Fraction
    hi: Fraction
    reached: Fraction
    boxes: list = field(default_factory=list)
    reason: Optional[str] = None

    @property
    def complete(self) -> bool:
        return self.reached == self.hi


def prove_interval(prove_box: Callable, lo, hi, *, first, min_width, max_boxes: int = 400,
                   progress: Optional[Callable] = None) -> Interval:
    """Cover ``[lo, hi]`` by consecutive proved boxes (module docstring).  ``prove_box(a, b)``
    returns ``(proof, None)`` if its statement is proved for every parameter of ``[a, b]``,
    else ``(None, reason)``; ``first`` is the first box's width, no box is narrower than
    ``min_width``; ``progress(interval)`` after each proved box."""
    lo, hi, width, min_width = Fraction(lo), Fraction(hi), Fraction(first), Fraction(min_width)
    if not (lo < hi and width > 0 and min_width > 0):
        raise ValueError(f"prove_interval: needs lo < hi, first > 0 and min_width > 0, got "
                         f"lo={lo}, hi={hi}, first={width}, min_width={min_width}")
    out = Interval(lo, hi, lo)
    for _ in range(max_boxes):
        if out.reached >= hi:
            return out
        b = min(hi, out.reached + max(width, min_width))
        proof, why = prove_box(out.reached, b)
        if proof is not None:
            out.boxes.append((out.reached, b, proof))
            out.reached, width = b, (b - out.reached) * GROW
            if progress:
                progress(out)
            continue
        if b - out.reached <= min_width:
            out.reason = f"no proof on [{out.reached}, {b}]: {why}"
            return out
        width = (b - out.reached) / 2
    out.reason = f"more than {max_boxes} boxes (reached {out.reached})"
    return out
