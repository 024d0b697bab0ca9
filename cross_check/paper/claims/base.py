"""The claim registry and the tools the claims share.

A ``Claim`` is one numerically checkable statement of the paper: its ``id``, the paper's words
(``statement``), the ``parameters`` it is checked at, and ``compute(quick) -> Outcome`` (the
``verdict``, the named ``numbers`` behind it and, for an erratum, the ``corrected`` statement).
``Claim.run`` turns an outcome into a row of the claims table (a dict, the JSON of
``python -m cross_check claims --json``).  Claims register themselves with ``@claim(...)``.

Shared tools: ``fl`` (JSON-friendly floats), ``itinerary`` (event counts of the reference over
whole periods), ``fast_points`` (``dynamics.periodic.find_periodic_points``), ``refined``
(that point polished by ``dynamics.periodic.newton`` on the reference at ``DPS`` digits) and
``prove`` (a computer-assisted proof of a periodic orbit, ``reference.enclosure``: a claim
whose verdict rests on an orbit lists its proofs in ``Outcome.proved``, the row's ``proved``;
a statement proved for every parameter of an interval is in ``Outcome.proved_on``, the row's
``proved_on``, read from the shipped ``intervals`` data).
"""
from __future__ import annotations

from collections import Counter
from dataclasses import dataclass
from typing import Callable

import mpmath
import numpy as np

import reference
from cross_check.dynamics import periodic
from reference.enclosure import prove_periodic, prove_segment
from reference.enclosure.balls import decimal_ball, workprec

DPS = 50
#: digits of the midpoints of the proofs' balls (their rounding is part of the radius)
BALL_DIGITS = 50
#: event counts of a periodic orbit are taken over [SHIFT T, (SHIFT + 1) T] (no event at the window ends)
SHIFT = mpmath.mpf("0.3183")
VERDICTS = ("reproduced", "not reproduced", "erratum")


@dataclass(frozen=True)
class Outcome:
    """What a claim's computation concludes; ``parameters`` overrides the claim's when the run sets them."""

    verdict: str
    numbers: dict
    corrected: str | None = None
    parameters: dict | None = None
    proved: list | None = None
    #: statements proved for every parameter of an interval (``intervals.lines``)
    proved_on: list | None = None


@dataclass(frozen=True)
class Claim:
    """One statement of the paper with the computation that checks it (module docstring)."""

    id: str
    statement: str
    parameters: dict
    compute: Callable[[bool], Outcome]
    corrected: str | None = None
    note: str = ""

    def run(self, quick: bool = False) -> dict:
        """The table row: ``id, statement, verdict, corrected, parameters, numbers, note``."""
        out = self.compute(quick)
        corrected = out.corrected if out.corrected is not None else (
            self.corrected if out.verdict == "erratum" else None)
        if out.verdict not in VERDICTS:
            raise ValueError(f"verdict must be one of {'|'.join(VERDICTS)}, got {out.verdict!r}")
        if (out.verdict == "erratum") != (corrected is not None):
            raise ValueError(f"claim {self.id}: 'corrected' is required exactly for an erratum")
        row = {"id": self.id, "statement": self.statement, "verdict": out.verdict, "corrected": corrected,
               "parameters": out.parameters or self.parameters, "numbers": out.numbers, "note": self.note}
        if out.proved is not None:
            row["proved"] = out.proved
        if out.proved_on is not None:
            row["proved_on"] = out.proved_on
        return row


#: every registered claim by id (registration order; ``cross_check.paper.claims`` orders the table)
REGISTRY: dict[str, Claim] = {}


def claim(cid, statement, parameters, *, corrected=None, note=""):
    """Register the decorated ``compute(quick) -> Outcome`` as the claim ``cid``."""
    def register(compute):
        if cid in REGISTRY:
            raise ValueError(f"claim {cid!r} registered twice")
        REGISTRY[cid] = Claim(cid, statement, parameters, compute, corrected, note)
        return compute
    return register


def fl(value):
    """An mpf as a float (JSON-friendly); complex as [re, im]."""
    if isinstance(value, (mpmath.mpc, complex)):
        return [float(mpmath.re(value)), float(mpmath.im(value))]
    return float(value)


def period(scene):
    return 2 * mpmath.pi / scene.mpf("omega")


def residual(scene, x0, v0, dps=DPS):
    """``|Phi(z) - z|_inf`` on the reference at ``dps`` digits (as a float)."""
    X, V = reference.stroboscopic_map(scene, x0, v0, dps=dps)
    return fl(max(abs(X - x0), abs(V - v0)))


def ref_newton(scene, x, v, *, k=1, dps=DPS):
    """``dynamics.periodic.newton`` on the reference map at ``dps`` digits, from one seed.

    Returns ``(x, v, J, residual)`` (``J`` an mpmath matrix); ``RuntimeError`` without convergence."""
    res = periodic.newton(scene, [x], [v], period=k, engine=periodic.Reference(dps))
    if not res.converged[0]:
        raise RuntimeError(f"ref_newton: no convergence from x={x}, v={v}, k={k}, residual={res.residual[0]}")
    with mpmath.workdps(dps):
        return res.x[0], res.v[0], mpmath.matrix(res.J[0].tolist()), max(abs(res.gx[0]), abs(res.gv[0]))


def itinerary(scene, x, v, periods=1, dps=30, shift=None):
    """Event counts over ``[0, periods T]``; frictionless velocity zeros counted as ``"turn"``.

    The reference logs no event when ``v`` passes 0 without friction; there the flight
    ``v(t) = v_a + F/w (sin wt - sin wt_a)`` between events is sampled (256 points) for sign changes.
    ``shift = s``: count over ``[s T, (s + periods) T]`` instead (for a periodic orbit with an event
    exactly at ``t = 0``, which a window starting at 0 would count ambiguously).
    """
    T = period(scene)
    if shift is not None:
        pre = reference.trajectory(scene, x, v, shift * T, dps=dps)
        log = reference.trajectory(scene, pre.x_end, pre.v_end, (shift + periods) * T, t0=pre.t_end, dps=dps)
    else:
        log = reference.trajectory(scene, x, v, periods * T, dps=dps)
    counts = Counter(e.kind for e in log)
    if not scene.has("friction"):
        F, w = scene.mpf("F"), scene.mpf("omega")
        marks = [(log.t0, log.v0)] + [(e.t, e.v) for e in log] + [(log.t_end, None)]
        zeros = 0
        for (ta, va), (tb, _) in zip(marks, marks[1:]):
            vs = [va + F / w * (mpmath.sin(w * (ta + (tb - ta) * j / 256)) - mpmath.sin(w * ta))
                  for j in range(1, 256)]
            zeros += sum(1 for a, b in zip(vs, vs[1:]) if a * b < 0)
        counts["turn"] += zeros
    return dict(counts)


def fast_points(scene, period=1, v_range=(-2.0, 2.0), grid=(24, 24), x_range=None):
    """Periodic points Newton finds on ``fast`` from a grid of seeds (``PeriodicPoint`` list)."""
    return periodic.find_periodic_points(scene, period=period, v_range=v_range, grid=grid, x_range=x_range)


def pick(points, kind):
    return [p for p in points if p.kind == kind]


def refined(scene, p, dps=DPS):
    """Refine a fast periodic point with ``ref_newton``; multipliers and itinerary."""
    x, v, J, res = ref_newton(scene, p.x, p.v, k=p.period, dps=dps)
    with mpmath.workdps(dps):
        lam = mpmath.eig(J)[0]
        out = {"x": x, "v": v, "residual": res, "trace": J[0, 0] + J[1, 1], "det": mpmath.det(J),
               "multipliers": sorted(lam, key=lambda z: (float(mpmath.re(z)), float(mpmath.im(z))))}
    out["itinerary"] = itinerary(scene, x, v, periods=p.period)
    out["kind"], out["stability"] = p.kind, p.stability
    return out


def _ball(b):
    """``[mid, radius]`` of a ball that contains ``b``, midpoint's rounding included."""
    return list(decimal_ball(b, BALL_DIGITS))


def prove(label, scene, x, v, k=1, segment=None, **how) -> dict:
    """A Krawczyk proof of the period-``k`` orbit through ``(x, v)`` at ``t = 0`` (a point the
    claim found; ``reference.enclosure.prove_periodic`` polishes it and picks a section away
    from the orbit's events).  JSON-ready: ``orbit``, ``periods``, ``proved`` and, if proved,
    the box ``radius``, the fixed point's balls ``point`` at ``t = phase T``, the multipliers
    (``[mid, radius]``, or ``{"re", "im"}`` for a complex pair), ``kind``, ``stability`` and
    the ``itinerary``; else ``reason`` (and ``OrbitProof``'s ``residual`` where the test failed
    on it, ``spread`` where ``P'`` was too wide for it, ``miss`` where ``K(Z)`` missed ``Z``
    after the box's walk, ``diverged`` where Newton did, and
    ``centre``, decimal strings, where Newton converged before the test failed: a seed for a
    proof with more bits).
    ``segment = (x_lo, x_hi)``: prove the segment of fixed points ``[x_lo, x_hi] x
    {v*}`` of a no-impact orbit instead (``prove_segment``).  ``how``:
    ``prove_periodic``'s ``prec``, ``radius``, ``phase`` (then ``(x, v)`` is the state at
    ``t = phase T``), ``points`` and ``tight``."""
    p = prove_periodic(scene, x, v, periods=k, **how) if segment is None else prove_segment(scene, *segment, v)
    rec = {"orbit": label, "periods": k, "proved": p.proved, "seconds": round(p.seconds, 2)}
    if not p.proved:
        rec["reason"] = p.reason
        if p.residual:
            rec["residual"] = p.residual
        if p.spread:
            rec["spread"] = p.spread
        if p.miss:
            rec["miss"] = p.miss
        if p.diverged:
            rec["diverged"] = True
        if p.centre:            # to the proof's bits: Newton at more bits starts converged there
            digits = mpmath.libmp.prec_to_dps(p.prec) + 3
            rec["centre"] = [c.str(digits, radius=False) for c in p.centre]
        return rec
    with workprec(p.prec):
        mults = [{"re": _ball(m[0]), "im": _ball(m[1])} if isinstance(m, tuple) else _ball(m)
                 for m in p.multipliers]
        rec.update(radius=p.radius, phase=str(p.phase), point=[_ball(b) for b in p.point],
                   multipliers=mults, kind=p.kind, stability=p.stability,
                   itinerary=dict(Counter(p.itinerary)))
    return rec


def cell_grid(scene, n, v_range):
    """An ``n x n`` grid of cell centres over the gap times ``v_range`` (flat arrays)."""
    l, r = scene.float("l"), scene.float("r")
    xs = l + (np.arange(n) + 0.5) / n * (r - l)
    vs = v_range[0] + (np.arange(n) + 0.5) / n * (v_range[1] - v_range[0])
    X, V = np.meshgrid(xs, vs, indexing="ij")
    return X.ravel(), V.ravel()
