"""Periodic orbits proved for every parameter of a box (``prove_periodic`` on a ``ParamBox``).

``prove_periodic_box(box, x, v, periods=k, phase=...)`` proves that for *every* parameter
``p`` of the box ``Phi_p^k`` (from the section ``t = phase T``) has a periodic orbit near
``(x, v)``, unique among the orbits through its shooting boxes, with its state at the section
in the balls ``point`` and the trace and determinant of its monodromy in ``trace``, ``det``,
and the type those prove (``orbits.classify``: ``det = 1`` is used only where it is a theorem
for every parameter of the box: impacts and flights only, ``e = 1`` and ``c = 0`` on the
whole box).  The operator is the parametric Krawczyk operator in multiple-shooting form
(``reference.enclosure.shooting``).

Steps: Newton on midpoints for the fixed point ``z~`` at the box's midpoint parameters
(:func:`polish`; the point log of every enclosure is taken at the midpoint too), then the
Krawczyk test with ``C`` from the midpoint derivative and state boxes grown by
epsilon-inflation.  A box across an itinerary change (a grazing, a sticking threshold, an
event crossing the section) fails in ``enclose_map``, whose reason the proof returns; a box
too wide for the contraction fails with ``K(Z) not inside Z``.  Neither is ever a "proved";
``split`` names the parameter whose halving helps most (``continuation.cover`` uses it).
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from fractions import Fraction

from flint import arb

from reference.api import check_count
from reference.enclosure.balls import from_number, workprec
from reference.enclosure.maps import enclose_map
from reference.enclosure.kinds import OrbitProof, classify
from reference.enclosure.params import ParamBox
from reference.enclosure.shooting import MORE_PIECES, PIECES, Shooting, section

#: Newton steps on the midpoints before the proof (each one enclosure of ``P`` at a point).
NEWTON_STEPS = 30
#: Working precision of a box proof when the caller gives none (bits): the balls are as wide
#: as the box makes them; 128 bits leave ~25 digits below a box of width 1e-10.
BOX_PREC = 128


@dataclass
class BoxOrbitProof(OrbitProof):
    """An :class:`~reference.enclosure.orbits.OrbitProof` over a parameter box.

    ``point`` encloses the state at ``t = phase T`` of the orbit, ``trace``, ``det`` and
    ``multipliers`` its monodromy, for every parameter of ``box``; the orbit is the only one
    whose states at the ``sections`` (units of ``T``) lie in the boxes of half-widths
    ``shooting_radii`` around the midpoint orbit's (``radii``: the first section's), and, if
    ``unique_in_point``, the only fixed point of ``Phi^k`` in ``point``.  ``split``: the
    parameter to halve when the proof fails for width."""

    box: ParamBox = None
    radii: tuple = ()
    sections: tuple = ()
    shooting_radii: tuple = ()
    unique_in_point: bool = False
    split: object = None


def polish(scene, z, periods, phase, prec):
    """Newton on midpoints for the fixed point of ``Phi^periods`` (section ``phase``) at the
    point ``scene``: ``z <- z - (P' - I)^-1 (P(z) - z)`` until the step is below
    ``2^(20 - prec) (1 + |z|)`` (at most ``NEWTON_STEPS``).  Returns ``(z, enclosure at z)``."""
    kw = dict(periods=periods, phase=phase, prec=prec, max_prec=prec)
    tol = arb(2) ** (20 - prec)
    for _ in range(NEWTON_STEPS):
        enc = enclose_map(scene, z[0], z[1], **kw)
        if not enc.proved:
            return z, enc
        J = enc.jacobian
        a, b, c, d = (J[0][0] - 1).mid(), J[0][1].mid(), J[1][0].mid(), (J[1][1] - 1).mid()
        det = a * d - b * c
        if det.is_zero():
            return z, enc
        r0, r1 = (enc.phi[0] - z[0]).mid(), (enc.phi[1] - z[1]).mid()
        step = [((d * r0 - b * r1) / det).mid(), ((a * r1 - c * r0) / det).mid()]
        z = [(z[0] - step[0]).mid(), (z[1] - step[1]).mid()]
        if all(abs(step[i]) < tol * (1 + abs(z[i])) for i in range(2)):
            break
    return z, enclose_map(scene, z[0], z[1], **kw)


def prove_periodic_box(box, x, v, *, periods=1, phase=None, prec=BOX_PREC,
                       pieces=(PIECES, MORE_PIECES)) -> BoxOrbitProof:
    """Prove, for every parameter of ``box``, a periodic orbit of ``Phi^periods`` near ``(x, v)``
    (module docstring).  ``phase=None`` picks the section (:func:`section`; ``(x, v)`` is then
    the state at ``t = 0``), else ``(x, v)`` is the state at ``t = phase T``.  ``pieces``: the
    multiple-shooting pieces per period tried in turn (``shooting``)."""
    if not isinstance(box, ParamBox):
        raise TypeError(f"box must be a ParamBox, got {type(box).__name__}")
    check_count("periods", periods, 1)
    check_count("prec", prec, 64)
    start = time.perf_counter()
    mid = box.midpoint()
    with workprec(prec):
        if phase is None:
            phase, x, v = section(mid, x, v, periods, prec)
        phase = Fraction(phase)
        if not 0 <= phase < 1:
            raise ValueError(f"phase must be a rational number in [0, 1), got {phase}")
        z, enc_mid = polish(mid, [from_number(x).mid(), from_number(v).mid()], periods, phase, prec)
        if not enc_mid.proved:
            proof = _fail(box, periods, prec, f"Phi^{periods} at the midpoint parameters is not "
                                              f"proved: {enc_mid.reason}")
        else:
            for n_pieces in pieces:
                shooting = Shooting(box, mid, z, periods, phase, prec, enc_mid, n_pieces)
                proof = _shoot(box, shooting, periods, prec)
                if proof.proved:
                    break
    proof.phase, proof.box = phase, box
    proof.seconds = time.perf_counter() - start
    return proof


def _shoot(box, shooting, periods, prec):
    """One multiple-shooting proof, as a :class:`BoxOrbitProof` (``split`` set on failure)."""
    def fail(reason, radii):
        return _fail(box, periods, prec, reason, radii)

    def done(K, rho, J, kinds, sections, unique):
        tr = J[0][0] + J[1][1]
        det = J[0][0] * J[1][1] - J[0][1] * J[1][0]
        kind, stability, mults = classify(box, tr, det, kinds)
        return BoxOrbitProof(True, periods, point=(K[0], K[1]), radius=float(max(rho[:2])),
                             multipliers=mults, trace=tr, det=det, kind=kind, stability=stability,
                             itinerary=kinds, prec=prec, box=box, radii=(float(rho[0]), float(rho[1])),
                             sections=tuple(sections), shooting_radii=tuple(float(r) for r in rho),
                             unique_in_point=unique)

    proof = shooting.prove(fail, done)
    proof.split = shooting.hint
    return proof


def _fail(box, periods, prec, reason, radii=()):
    return BoxOrbitProof(False, periods, reason=reason, prec=prec, box=box, radii=tuple(radii),
                         radius=float(max(radii)) if radii else 0.0)
