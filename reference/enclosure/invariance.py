"""``Phi(Omega_dissip)`` in ``Omega_dissip``: proved by a cover of rest states, refuted by a
proved counterexample ball.

``Omega_dissip`` is the set of starts ``(x, v)`` at ``t = 0`` whose motion has ``v = 0`` at least
once in ``[0, T]``; ``Omega_pres`` the rest.  The paper observes (Fig. fig:regs) that
``Phi(Omega_dissip)`` lies in ``Omega_dissip``.

**The reduction.**  Take a start in ``Omega_dissip`` and ``t*`` the last zero of ``v`` in
``[0, T]``.  The forcing is ``T``-periodic, so the image's motion over ``[0, T]`` is the
start's over ``[T, 2T]``: the image is in ``Omega_dissip`` iff ``v`` vanishes in ``[T, 2T]``.
If ``t* = T`` it does.  Else ``v != 0`` on ``(t*, T]``, and the motion after ``t*`` is the one
of the rest state ``(x(t*), 0)`` at the time ``t*`` (the state decides the future): a zero of
``v`` in ``(t*, 2T]`` lies in ``(T, 2T]``.  So it suffices that *every rest state returns to
rest by 2T*: for every ``x`` in ``[l, r]`` and time ``tau`` in ``[0, T)``, ``v = 0`` again in
``(tau, 2T]`` -- a statement on a compact set of two dimensions, which :func:`cover` proves by
boxes (``reference.enclosure.rest``: each box with its proved bound ``B`` on the return time,
``tau + B <= 2T``).  Returning within one period (``B <= T``) is the stronger sufficient
condition; the deadline ``2T`` is the exact one (a rest state at ``tau`` that is some start's
last zero must return by ``2T``), and a cover for it needs far fewer boxes.  Stuck rest
states (``v = 0`` right after ``tau``) are never a last zero before ``T``: they hold trivially.

**The refutation.**  A ball of starts ``(x, v)``, each proved in ``Omega_dissip`` and each
image proved in ``Omega_pres``: :func:`prove_counterexample` proves the whole itinerary over
``[0, 2T]`` for every start of the ball (``enclose_map`` with ``periods=2``: each event's kind
proved, no other event) and reads the certificate off it: an event with ``v = 0`` (a turn, a
stop, a slip, a chatter run's end, contact) proved before ``T``, and from the last of them to
``2T`` only impacts proved non-grazing and flights on which ``v`` has a proved sign.  With
``f = 0`` the walk has no velocity events: the zero is proved as a sign change of ``v``
within one flight before ``T`` and the flights after it are proved free of zeros here.
"""
from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Optional

from flint import arb

from reference.enclosure import certify, motion
from reference.enclosure.balls import BallModel, from_number, parameter, workprec
from reference.enclosure.maps import enclose_map
from reference.enclosure.params import ParamBox
from reference.enclosure.rest import BoxReturn, box_return

#: Working precision (bits) of the cover: the stages are a few closed forms deep.
PREC = 128
#: Boxes the cover may try unless the caller says otherwise, and the first split of the phases.
MAX_BOXES, PHASE_BOXES = 20000, 16
#: A box narrower than this (in xi or phi) is not split further.
MIN_WIDTH = Fraction(1, 2 ** 30)
#: The parameters of a parameter box the cover may halve.
PARAM_AXES = ("f", "r", "F", "omega", "l", "restitution", "damping")
#: Interior times at which a frictionless flight's velocity is tried for a sign change.
SAMPLES = 32
#: Kinds of events at which ``v = 0`` (``reference.integrator``).
ZERO_KINDS = ("turn", "stick", "slip", "contact", "release", "chatter")


@dataclass
class Leaf:
    """One box of the cover: ``xi``, ``phi`` exact pairs, its :class:`BoxReturn`, and the
    parameter box it holds for (``params``: the cover's scene or box, or a part of it)."""

    xi: tuple
    phi: tuple
    result: BoxReturn
    params: object = None


@dataclass
class Cover:
    """The boxes of :func:`cover` (proved and not), in the order they were settled."""

    leaves: list = field(default_factory=list)
    tried: int = 0
    seconds: float = 0.0

    @property
    def proved(self) -> bool:
        return all(leaf.result.proved for leaf in self.leaves)

    def undecided(self) -> list:
        return [leaf for leaf in self.leaves if not leaf.result.proved]


def _axis(m, xi, phi, hint):
    """The axis to split: the hint, else the wider in length (``phi`` scaled by ``T F / w``,
    the distance a flight covers in the box's phases)."""
    if hint in ("xi", "phi"):
        return hint
    gap = float((m.r - m.l).mid())
    scale = float((m.T * m.F / m.w).mid())
    return "xi" if float(xi[1] - xi[0]) * gap >= float(phi[1] - phi[0]) * scale else "phi"


def _children(item, m, hint, models):
    """The two halves of a failed item ``(params, xi, phi, depth)``.  Over a parameter box the
    item is tried twice more: at the midpoint parameters, and over the parameters at the
    state box's centre.  If only the latter fails (or both, at an odd depth), the parameters'
    spread is what fails, and the relatively widest varying parameter is halved; else (and
    over a scene) the state axis :func:`_axis` picks.  ``[]`` at the smallest width."""
    params, xi, phi, depth = item
    varying = [n for n in PARAM_AXES if isinstance(params, ParamBox) and params.width(n) > 0]
    if varying and _blame_parameters(params, xi, phi, depth, m, models):
        name = max(varying, key=lambda n: _relative_width(params, n))
        return [(half, xi, phi, depth + 1) for half in params.split(name)]
    axis = _axis(m, xi, phi, hint)
    lo, hi = xi if axis == "xi" else phi
    if hi - lo <= MIN_WIDTH:
        return []
    mid = (lo + hi) / 2
    if axis == "xi":
        return [(params, (lo, mid), phi, depth + 1), (params, (mid, hi), phi, depth + 1)]
    return [(params, xi, (lo, mid), depth + 1), (params, xi, (mid, hi), depth + 1)]


def _blame_parameters(params, xi, phi, depth, m, models) -> bool:
    at_mid = box_return(_model(models, params.midpoint()), xi, phi).proved
    centre = ((xi[0] + xi[1]) / 2,) * 2, ((phi[0] + phi[1]) / 2,) * 2
    at_centre = box_return(m, *centre).proved
    return not at_centre and (at_mid or depth % 2 == 1)


def _relative_width(params, name) -> float:
    ball = parameter(params, name)
    return float(ball.rad()) / max(abs(float(ball.mid())), 1.0)


def _model(models, params):
    """The ball model of ``params`` (cached per cover: a parameter box's halves recur)."""
    if params not in models:
        models[params] = BallModel(params)
    return models[params]


def cover(scene, *, max_boxes=MAX_BOXES, phase_boxes=PHASE_BOXES, prec=PREC, progress=None,
          progress_every=2000) -> Cover:
    """Cover ``[0, 1] x [0, 1)`` of ``(xi, phi)`` (``x = l + xi (r - l)``, ``tau = phi T``) by
    boxes, each proved by :func:`~reference.enclosure.rest.box_return` or split (at most
    ``max_boxes`` tries; a box that cannot be split or is past the budget stays undecided
    with its reason).  ``scene``: a ``Scene`` or a ``ParamBox``: every leaf holds for every
    parameter of its ``params`` (a parameter box is split too, :func:`_children`, and the
    leaves' parameter boxes cover it).  ``progress(message)`` every ``progress_every`` tries."""
    if not (isinstance(max_boxes, int) and not isinstance(max_boxes, bool) and max_boxes >= 1):
        raise ValueError(f"max_boxes must be an int >= 1, got {max_boxes!r}")
    if not (isinstance(phase_boxes, int) and not isinstance(phase_boxes, bool) and 1 <= phase_boxes <= 4096):
        raise ValueError(f"phase_boxes must be an int in [1, 4096], got {phase_boxes!r}")
    start = time.perf_counter()
    out, models = Cover(), {}
    with workprec(prec):
        work = deque((scene, (Fraction(0), Fraction(1)), (Fraction(k, phase_boxes), Fraction(k + 1, phase_boxes)), 0)
                     for k in range(phase_boxes))
        while work:
            item = work.popleft()
            params, xi, phi, _ = item
            if out.tried >= max_boxes:
                out.leaves.append(Leaf(xi, phi, BoxReturn(False, reason=f"not tried: the budget of "
                                                                        f"{max_boxes} boxes is spent"), params))
                continue
            out.tried += 1
            m = _model(models, params)
            got = box_return(m, xi, phi)
            if progress and out.tried % progress_every == 0:
                progress(f"dissip-invariance cover: {out.tried} boxes tried, {len(out.leaves)} settled, "
                         f"{len(work)} waiting")
            children = [] if got.proved or got.split is None and got.reason.startswith("not supported") \
                else _children(item, m, got.split, models)
            if not children and not got.proved and not got.reason.startswith("not supported"):
                got.reason = f"{got.reason} (box at the smallest width, 2^-30)"
            if children:
                work.extend(children)
            else:
                out.leaves.append(Leaf(xi, phi, got, params))
    out.seconds = time.perf_counter() - start
    return out


# -- the counterexample ---------------------------------------------------------------------
@dataclass
class Counterexample:
    """What :func:`prove_counterexample` proved for the ball ``x +- x_radius``,
    ``v +- v_radius``: ``proved`` (every start in ``Omega_dissip``, every image in
    ``Omega_pres``), else ``reason``; ``zero``: the ball of the last time ``v = 0`` before
    ``T``, ``events``: the proved itinerary over ``[0, 2T]`` (kinds)."""

    proved: bool
    x: tuple
    v: tuple
    reason: Optional[str] = None
    zero: Optional[arb] = None
    events: list = field(default_factory=list)


def prove_counterexample(scene, x, v, x_radius, v_radius, *, prec=None, max_prec=None) -> Counterexample:
    """Prove that every start of the ball is in ``Omega_dissip`` and its image in
    ``Omega_pres`` (module docstring); numbers, ``prec`` and ``max_prec`` as ``enclose_map``
    takes them (a search passes ``max_prec = prec``: a ball too wide fails at every
    precision, the next, smaller one is the cheaper try)."""
    kwargs = {k: val for k, val in (("prec", prec), ("max_prec", max_prec)) if val is not None}
    enc = enclose_map(scene, x, v, periods=2, x_radius=x_radius, v_radius=v_radius, **kwargs)
    out = Counterexample(False, (x, x_radius), (v, v_radius))
    if not enc.proved:
        out.reason = f"the itinerary over [0, 2T] is not proved for the whole ball: {enc.reason}"
        return out
    out.events = [ev.kind for ev in enc.events]
    with workprec(enc.prec):
        m = BallModel(scene if not hasattr(scene, "is_point") or not scene.is_point else scene.scene())
        X = from_number(x) + arb(0, from_number(x_radius).upper())
        V = from_number(v) + arb(0, from_number(v_radius).upper())
        zero, reason = _certificate(m, enc, X, V)
    out.proved, out.zero, out.reason = reason is None, zero, reason
    return out


def _certificate(m, enc, X, V):
    """``(zero, reason)``: the last proved zero of ``v`` before ``T`` and None, or the reason."""
    T, events = m.T, enc.events
    zeros = [i for i, ev in enumerate(events) if ev.kind in ZERO_KINDS]
    if not all(ev.kind in ZERO_KINDS + ("impact",) for ev in events):
        return None, f"an event of kind {sorted({ev.kind for ev in events})} the certificate does not read"
    if zeros:
        last = events[zeros[-1]]
        if not last.t < T:
            return None, (f"the last zero of v (a {last.kind} at t = {last.t.mid().str(10)}) is not "
                          f"proved before T: the image may not be in Omega_pres")
        if not (enc.phi[1] > 0 or enc.phi[1] < 0):
            return None, "v(2T) encloses 0"
        if m.friction:
            return last.t, None
    if m.friction:
        return None, "no zero of v in [0, T] (no turn, stop or contact): the starts are in Omega_pres"
    return _frictionless(m, enc, zeros, X, V)


def _flights(enc, X, V, end):
    """The flights of the proved itinerary: ``(t0, x0, v0, t1)`` balls (``t1`` the next
    event's time, ``end`` after the last)."""
    log = enc.events
    starts = [(arb(0), X, V)] + [(ev.t, ev.x, ev.v) for ev in log]
    return [s + (t1,) for s, t1 in zip(starts, [ev.t for ev in log] + [end])]


def _sign(ball):
    return 1 if ball > 0 else (-1 if ball < 0 else 0)


def _turns(m, t0, x0, v0, t1):
    """A time before ``min(t1, T)`` by which ``v`` has changed sign on the flight from
    ``(t0, x0, v0)`` (proved of the opposite sign there, at one of ``SAMPLES`` interior times:
    intermediate values), else None."""
    s = _sign(v0)
    width = (t1 - t0).lower()
    if not s or not width > 0:
        return None
    flight = motion.Flight(m, t0, x0, v0, s)
    for k in range(1, SAMPLES + 1):
        h = (width * k / SAMPLES).mid()
        if not t0 + h < m.T:
            return None
        if s * flight.stack(h)[1] < 0:
            return t0 + h
    return None


def _frictionless(m, enc, zeros, X, V):
    """``f = 0``: the walk logs no velocity events.  The zero before ``T``: a zero-kind event
    (contact, chatter) or a flight on which ``v`` changes sign before ``T`` (:func:`_turns`);
    after ``T``: every flight that may reach into ``[T, 2T]`` has
    ``v`` of one sign there (``certify.exclude`` of ``s v`` on the flight's closed form)."""
    T = m.T
    flights = _flights(enc, X, V, 2 * T)
    changes = [t for t in (_turns(m, t0, x0, v0, t1) for t0, x0, v0, t1 in flights) if t is not None]
    if not zeros and not changes:
        return None, "no zero of v proved in [0, T] (no sign change within a flight before T)"
    ends = ([enc.events[zeros[-1]].t] if zeros else []) + changes[-1:]
    zero = ends[-1] if len(ends) == 1 or ends[-1] > ends[0] else ends[0]
    for t0, x0, v0, t1 in flights:
        if t1 < T:
            continue
        s = _sign(v0)
        if not s:
            return None, f"a flight from t = {t0.mid().str(10)} reaching past T starts with v enclosing 0"
        lo = max(arb(0), (T - t0).lower()) if not t0 > T else arb(0)
        try:
            certify.exclude(motion.Flight(m, t0, x0, v0, s), motion.velocity(s), lo,
                            (t1 - t0).upper(), f"flight from t = {t0.mid().str(10)}")
        except certify.Unproved as exc:
            return None, f"v may vanish in [T, 2T]: {exc}"
    return zero, None
