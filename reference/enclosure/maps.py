"""``enclose_map``: an enclosure of ``Phi^k`` and ``(Phi^k)'`` over a box of start states.

The point integrator runs once, from the box's midpoint, at the working precision; the walk
(``reference.enclosure.walk``) re-proves its itinerary for the whole box in ball arithmetic;
``Phi^k`` is the closed-form state at ``t = kT`` on the enclosures, and ``(Phi^k)'`` the
product of the paper's Table 1 matrices (``reference.jacobian.product_of_table1``, the same
code as the point Jacobian) over the enclosures of the event data.  When a certificate fails
at one precision because the precision cannot resolve it (a near-tangency), the walk is
tried again at twice the precision, up to ``max_prec`` bits.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from functools import lru_cache
from typing import Optional

import mpmath
from flint import arb

from reference.api import _model_here, check_count
from reference.enclosure.balls import (DEFAULT_PREC, BallModel, from_fraction, from_number,
                                       parameter, rel_radius, to_mpf, workprec)
from reference.enclosure.certify import Unproved
from reference.enclosure.centred import centred
from reference.enclosure.lohner import FlightFactors
from reference.enclosure.params import PARAMS, ParamBox
from reference.enclosure.sensitivity import PARAMETERS as SENSITIVE
from reference.enclosure.sensitivity import parameter_jacobian
from reference.enclosure.walk import Walk
from reference.integrator import MAX_EVENTS, integrate
from reference.jacobian import product_of_table1
from reference.model import GUARD_DIGITS
from reference.scene import Scene

#: The highest precision the retries reach (bits) unless the caller sets ``max_prec``.
MAX_PREC = 1280
#: Digits of the point integrator under position forcing: its Taylor flights cost ~dps^1.5,
#: and the walk needs from it only the itinerary and times that Newton steps then polish.
POINT_DPS_TAYLOR = 40
#: The fewest digits a point log may be asked for (``point_log``'s ``dps``): float64's 16 and a
#: guard of 4.  Its itinerary can then differ from the exact one only at an event within ~1e-20
#: of grazing, where a walk it guides fails (and never proves another itinerary).
MIN_POINT_DPS = 20


@dataclass
class MapEnclosure:
    """What ``enclose_map`` proved.

    ``proved``: every start state of the box has the itinerary ``events`` (kinds in order,
    each time in its ball) and ``Phi^k`` in ``phi = (x, v)``, ``(Phi^k)'`` in ``jacobian``
    (``None`` if it does not exist: a chatter run or contact makes it zero, which it is).
    ``reason`` says why not when ``proved`` is False (then the balls are not claims).
    ``prec`` is the precision (bits) of the proof, ``pieces`` the exclusion work.
    """

    proved: bool
    reason: Optional[str] = None
    phi: tuple = ()
    jacobian: Optional[list] = None
    events: list = field(default_factory=list)
    prec: int = 0
    pieces: int = 0
    #: ``d Phi^k / d p`` for the requested ``parameters`` (columns ``(dx/dp, dv/dp)``), enclosed
    #: over the box (``reference.enclosure.sensitivity``); None if not requested or not covered
    dparams: Optional[list] = None
    #: ``Phi^k`` at the box's centre alone, ``(x, v)`` balls as narrow as a walk from that point
    #: (position forcing: the walk's validated flights track it through their hand-offs,
    #: ``lohner.ValidatedFlight.point_state``); None for a point box, without position forcing,
    #: or where the walk lost it (a start at rest or at a wall, an event without a hand-off, a rest)
    phi_at_centre: Optional[tuple] = None

    def rel_radius(self) -> float:
        """The largest ``rad / |mid|`` of the two components of ``phi`` (``inf`` unproved)."""
        if not self.proved:
            return float("inf")
        return max(rel_radius(b) for b in self.phi)


@lru_cache(maxsize=32)
def _ball_model(scene, prec):
    return BallModel(scene)


def point_log(scene, x, v, periods, phase, prec, dps=None):
    """The point integrator's log of ``Phi^periods`` from ``(x, v)`` (numbers as in
    ``enclose_map``) at ``t = phase T`` with the walls its model held, at the digits
    ``enclose_map`` takes for ``prec`` (``dps``: at these digits instead, at least
    ``MIN_POINT_DPS``): ``enclose_map``'s ``points``, e.g. the guide of the walks of a whole
    orbit proof (``reference.enclosure.orbits.prove_periodic``), or of every rung of one.

    A guide only guides: the walk takes its itinerary and polishes each of its event times by
    Newton steps on the balls' midpoints (``certify.root``) before it proves the event, so a
    log good to a few digits past float64 guides a walk of any precision (a guide with another
    itinerary makes the walk fail, never prove something else)."""
    if dps is not None:
        check_count("dps", dps, MIN_POINT_DPS)
    with workprec(prec):
        return _point_log(scene, from_number(x).mid(), from_number(v).mid(), check_phase(phase),
                          Fraction(periods), prec, MAX_EVENTS, dps)


def _point_log(scene, x, v, phase, periods, prec, max_events, dps=None):
    """The point integrator's log from ``(x, v)`` (at a box's midpoint parameters); the same
    call again (a proof re-walks one centre on growing boxes) is served from a small cache."""
    point = scene.midpoint() if isinstance(scene, ParamBox) else scene
    return _cached_point_log(point, _key(x), _key(v), phase, periods, prec, max_events, dps)


def _key(value):
    man, exp = value.mid().man_exp()
    return int(man), int(exp)


@lru_cache(maxsize=64)
def _cached_point_log(scene, x, v, phase, periods, prec, max_events, dps=None):
    x, v = arb(x), arb(v)
    if dps is None:
        dps = int(prec / 3.33) + GUARD_DIGITS
        if scene.has("position_forcing"):     # Taylor flights: the walk polishes the event times
            dps = min(dps, POINT_DPS_TAYLOR)
    with mpmath.workdps(dps):
        model = _model_here(scene)
        t0 = model.T * phase.numerator / phase.denominator
        duration = model.T * periods.numerator / periods.denominator
        log = integrate(model, t0, to_mpf(x), to_mpf(v), t0 + duration, max_events)
        return log, (model.l, model.r)


def _check(scene, periods, prec, max_prec, max_events):
    if not isinstance(scene, (Scene, ParamBox)):
        raise TypeError(f"scene must be a reference.Scene or a ParamBox, got {type(scene).__name__}")
    if not (isinstance(periods, Fraction) and periods > 0):
        check_count("periods", periods, 1)
    check_count("prec", prec, 64)
    check_count("max_prec", max_prec, prec)
    check_count("max_events", max_events, 1)


def _box(value, radius, name):
    try:
        centre, radius = from_number(value), from_number(radius)
    except (TypeError, ValueError, OverflowError) as exc:
        kind = TypeError if isinstance(exc, TypeError) else ValueError
        raise kind(f"{name} and {name}_radius must be finite real numbers (int, float, "
                        f"decimal str, Fraction, mpf or arb), got {value!r} and {radius!r}") from None
    if not (radius >= 0):
        raise ValueError(f"{name}_radius must be >= 0, got {radius}")
    return centre if radius.is_zero() else centre + arb(0, radius.upper())


def enclose_map(scene, x, v, *, periods=1, x_radius=0, v_radius=0, phase=0, prec=DEFAULT_PREC,
                max_prec=MAX_PREC, rel_radius=None, max_events=MAX_EVENTS,
                parameters=(), centred=False, full_derivative=False, points=None) -> MapEnclosure:
    """Enclose ``Phi^periods`` and its derivative over the box ``x +- x_radius``,
    ``v +- v_radius`` (numbers as in ``reference.stroboscopic_map``: int, float, decimal str,
    Fraction, mpf, or an arb ball for ``x``, ``v``).  ``phase`` (a rational in ``[0, 1)``, as
    int, Fraction or decimal str) moves the section: the map runs from ``t0 = phase T`` to
    ``t0 + periods T`` (default 0: the paper's ``Phi``); ``periods`` may be a positive
    ``Fraction`` for a map over part of a period (the half-period map of a symmetry proof).

    Returns a :class:`MapEnclosure`; ``proved`` False with the reason where a certificate fails
    at every precision up to ``max_prec`` bits.  With ``rel_radius``, a proof whose ``Phi``
    balls are relatively wider than that is redone at twice the precision (up to
    ``max_prec``; the narrowest proof is returned).  ``max_events`` bounds the point
    integrator.

    ``scene`` may be a :class:`~reference.enclosure.params.ParamBox`: the statement then holds
    for every parameter of the box (the point log is taken at its midpoint; a point box runs
    the point code on its scene).  ``parameters`` (names among ``F, f, l, r, restitution``)
    asks for ``dparams``, the derivative of ``Phi^k`` with respect to them, enclosed over the
    box (``reference.enclosure.sensitivity``; flights, impacts and turns only).  ``centred``
    encloses ``Phi'`` (and ``dparams``) in mean-value form over the event data
    (``reference.enclosure.centred``): much tighter over a wide box, the same over a point.
    ``full_derivative`` (position forcing): the validated flights carry their flow derivative
    to the working precision, not to about half of it (``reference.enclosure.lohner``: ~1.4x
    the cost; what a proof of ``Phi'`` to 40 digits at 192 bits needs).  ``points``: the point
    integrator's log of this very map (``(log, (l, r))``: ``reference.integrator.integrate``'s
    ``EventLog`` and the walls its model held), made by the caller at any precision, in place of
    the one made here (a third of a position-forced proof's cost); as that one, it only guides
    the walk, which proves every event from the balls.
    """
    _check(scene, periods, prec, max_prec, max_events)
    if isinstance(scene, ParamBox) and scene.is_point:
        scene = scene.scene()
    phase, periods = check_phase(phase), Fraction(periods)
    last, best = None, None
    while prec <= max_prec:
        with workprec(prec):
            X, V = _box(x, x_radius, "x"), _box(v, v_radius, "v")
            try:
                best = _prove(scene, X, V, phase, periods, prec, max_events, tuple(parameters),
                              centred, full_derivative, points)
            except Unproved as exc:
                last = str(exc)
        if best is not None and (rel_radius is None or best.rel_radius() <= rel_radius):
            return best
        prec *= 2
    return best if best is not None else MapEnclosure(False, reason=last, prec=prec // 2)


def check_phase(phase):
    """``phase`` as a ``Fraction`` in ``[0, 1)`` (``TypeError``/``ValueError`` naming the range)."""
    try:
        value = Fraction(phase.strip() if isinstance(phase, str) else phase)
    except (TypeError, ValueError):
        raise TypeError(f"phase must be a rational number in [0, 1) (int, Fraction or decimal "
                        f"str), got {phase!r}") from None
    if isinstance(phase, (bool, float)) or not 0 <= value < 1:
        raise ValueError(f"phase must be a rational number in [0, 1) (int, Fraction or decimal "
                         f"str), got {phase!r}")
    return value


def _prove(scene, X, V, phase, periods, prec, max_events, parameters=(), centred=False,
           full_derivative=False, given=None):
    model = _ball_model(scene, prec)
    points, walls = given or _point_log(scene, X.mid(), V.mid(), phase, periods, prec, max_events)
    t0 = model.T * from_fraction(phase)
    t_end = t0 + from_fraction(periods) * model.T
    box = model.position_forcing and not (X.is_exact() and V.is_exact())
    walk = Walk(model, points, t_end, walls, full_derivative,
                track=(arb(X.mid()), arb(V.mid())) if box else None)
    log = walk.run(t0, X, V)
    J = product_of_table1(FlightFactors(model, walk.flights) if walk.flights else model, log)
    if not all(b.is_finite() for row in J for b in row):
        raise Unproved("Phi' is not enclosed: a flight factor the walk did not take survives")
    sens = parameter_jacobian(model, log, parameters) if parameters else None
    cols = None if sens is None else sens[1]
    if centred and (isinstance(scene, ParamBox) or not (X.is_exact() and V.is_exact())):
        J, cols = _centred(scene, X, V, phase, periods, prec, max_events, parameters, model, log,
                           (J, cols))
    at = None if walk.point_end is None else tuple(walk.point_end)
    return MapEnclosure(True, phi=(log.x_end, log.v_end), jacobian=J, events=list(log),
                        prec=prec, pieces=walk.pieces, dparams=cols, phi_at_centre=at)


def _centred(scene, X, V, phase, periods, prec, max_events, parameters, model, log, plain):
    """``Phi'`` and ``dPhi/dp`` in mean-value form over the box (``reference.enclosure.centred``)
    around ``u~``: the start box's centre and the midpoints of the varying parameters that have
    derivatives (``sensitivity.PARAMETERS``); any other varying parameter (``omega``, ``c``)
    stays a ball in the centre's walk too, so that the form holds for every parameter.  The
    plain enclosures if the centre is not proved."""
    names = [n for n in PARAMS if isinstance(scene, ParamBox) and scene.width(n) > 0
             and n in SENSITIVE]
    point = scene.replace(**{n: scene.mid(n) for n in names}) if names else scene
    try:
        at = _prove(point, X.mid(), V.mid(), phase, periods, prec, max_events, parameters)
    except Unproved:
        return plain
    deltas = [X - X.mid(), V - V.mid()] + [parameter(scene, n) - parameter(point, n) for n in names]
    return centred(model, log, names, parameters, deltas, (at.jacobian, at.dparams), plain)
