"""Two-impact orbits proved in impact coordinates, for every parameter of a box.

The stroboscopic map ``Phi`` of an orbit that hits a wall at a small speed ``V`` has
derivatives of order ``1/V`` and second derivatives of order ``1/V^3`` (the impact time moves
by ``dx/V``), so a Krawczyk box around its fixed point must shrink like a power of ``V``: near
x2's grazing boundary the stroboscopic proof (``shooting``) needs thousands of sub-boxes.  In
*impact coordinates* (Church & Fortin's formulation for impact billiards) the unknowns are
the impacts themselves, and the equations are smooth closed forms with no division by ``V``.

The orbit: ``m`` periods with exactly two impacts, one on each wall, and two flights without
any other event (no turn, no stop).  Unknowns ``u = (a, A, b, B)``: the phase ``a = w t`` of
the impact at ``l`` and the speed ``A > 0`` it arrives with, the phase ``b`` of the impact at
``r`` and its speed ``B > 0``.  With ``x(t)``, ``v(t)`` the closed-form flight of
``x'' = F cos(w t) - s f`` (``s = sgn x'`` fixed, no damping)::

    x(t) = x0 + u0 d - F/w^2 (cos w t - cos w t0) - F/w sin(w t0) d - s f d^2 / 2,
    v(t) = u0 + F/w (sin w t - sin w t0) - s f d,            d = t - t0,

the equations ``G(u, p) = 0`` are: the up-flight from ``(l, e A)`` at phase ``a`` reaches
``(r, B)`` at phase ``b``, and the down-flight from ``(r, -e B)`` at ``b`` reaches
``(l, -A)`` at ``a + 2 pi m``.  ``G`` and its derivatives are evaluated on balls by first-order
dual numbers (``dual``).  The parametric Krawczyk operator (``shooting.inflate``, with its
epsilon-inflation)

    K = u~ - C G(u~, p~) - (C G_p(u~, B)) (B - p~) + (I - C G_u(U, B)) (U - u~)

inside the interior of ``U`` proves, for every parameter ``p`` of the box ``B``, exactly one
zero of ``G(., p)`` in ``U``, lying in ``K``.  That the zero is an orbit of the Filippov system
with that itinerary is then proved on ``K x B``: ``A, B > 0`` (true impacts, not grazing),
``e > 0``, both flights of positive duration, and the velocity of each flight of one sign over
the whole flight (bisection with centred forms; at most ``SIGN_PIECES`` pieces).  A velocity of
one sign makes the closed form the motion (no turn, no stop: Filippov sticking needs
``x' = 0``) and ``x`` monotone, so neither wall is touched in between.

From ``K``: the state at the section ``t = ticks T`` (in the flight that provably contains it),
and the monodromy ``tr(S_l Fl(d_2) S_r Fl(d_1))`` (Table 1, ``reference.jacobian``: the flight
factor ``[[1, d], [0, 1]]``, the impact's saltation matrix with the velocity before it); its
determinant is ``e^4``.

Uniqueness: one orbit whose impacts lie in ``U``, and -- ``unique_in_point`` -- one fixed
point of ``Phi^m`` in the state ball ``S`` when every orbit from ``S`` provably hits the walls
next inside an impact box ``U'`` that passes the Krawczyk test and flies back to the section
with no other event (:func:`every_orbit_enters`).  For then a fixed point ``z`` in ``S`` has
impacts ``(a*, A*, b*, B*)`` in ``U'``, and the flight from the second impact through ``z`` on
to the first, one closed form, makes them a zero of ``G``: the one zero in ``U'``.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from fractions import Fraction
from types import SimpleNamespace

from flint import arb, arb_mat

from reference.enclosure.balls import BallModel, from_fraction, from_number, workprec
from reference.enclosure.boxes import BOX_PREC, NEWTON_STEPS, BoxOrbitProof
from reference.enclosure.dual import Dual
from reference.enclosure.kinds import classify
from reference.enclosure.shooting import inflate, krawczyk
from reference.jacobian import flight_matrix, impact_matrix, mat_mul

#: the parameters in the dual numbers' order (after the four unknowns)
NAMES = ("F", "f", "omega", "restitution", "l", "r")
#: pieces of one flight the velocity-sign proof may use
SIGN_PIECES = 2048
#: the impact boxes tried for uniqueness in the state ball, in multiples of the Krawczyk box's
#: radii (a wider box holds more of the orbits from the ball, if it still contracts)
UNIQUE_SCALES = (1, 4, 16)


@dataclass
class ImpactOrbitProof(BoxOrbitProof):
    """A :class:`~reference.enclosure.boxes.BoxOrbitProof` from impact coordinates:
    ``impacts`` the balls ``(a, A, b, B)`` (module docstring) for every parameter of the box,
    ``impact_radii`` the half-widths of ``U`` in which the zero is unique."""

    impacts: tuple = ()
    impact_radii: tuple = ()


def flight(t0, x0, u0, s, t, F, f, w):
    """``(x, v)`` at phase ``t`` of the flight from ``(x0, u0)`` at phase ``t0`` with
    ``sgn x' = s`` (module docstring); balls or dual numbers.

    The closed form of ``motion.Flight``, written in the absolute phases (``cos t - cos t0``)
    rather than in the elapsed time (``C0 (1 - cos theta) - S0 (theta - sin theta)``): here
    both phases are unknowns of the Krawczyk box, and this form keeps ``G_u`` over it tighter.
    With ``motion.Flight`` an x1 box took 215 sub-boxes instead of 71, and a period-3 box was
    not proved in 512 (142 here)."""
    d = (t - t0) / w
    x = x0 + u0 * d - F / (w * w) * (t.cos() - t0.cos()) - F / w * t0.sin() * d - s * f * d * d / 2
    v = u0 + F / w * (t.sin() - t0.sin()) - s * f * d
    return x, v


def equations(u, p, m):
    """``G(u, p)`` (module docstring), four balls or dual numbers."""
    a, A, b, B = u
    F, f, w, e, l, r = p
    x_up, v_up = flight(a, l, e * A, 1, b, F, f, w)
    x_dn, v_dn = flight(b, r, -(e * B), -1, a + 2 * m * arb.pi(), F, f, w)
    return [x_up - r, v_up - B, x_dn - l, v_dn + A]


def _duals(u, p, m):
    n = len(u) + len(p)
    return equations([Dual.variable(x, i, n) for i, x in enumerate(u)],
                     [Dual.variable(x, len(u) + i, n) for i, x in enumerate(p)], m)


def _params(scene):
    model = BallModel(scene)
    return [model.F, model.f, model.w, model.e, model.l, model.r]


def polish(u, p, m, prec):
    """Newton on midpoints for ``G(., p) = 0`` (``p`` the midpoint's balls)."""
    tol = arb(2) ** (20 - prec)
    for _ in range(NEWTON_STEPS):
        G = _duals(u, p, m)
        J = arb_mat([[g.grad[j] for j in range(4)] for g in G]).mid()
        step = J.solve(arb_mat([[g.val.mid()] for g in G]))
        u = [(u[i] - step[i, 0]).mid() for i in range(4)]
        if all(abs(step[i, 0]) < tol * (1 + abs(u[i])) for i in range(4)):
            break
    return u


def _one_sign(v_of, sign) -> bool:
    """Whether ``sign * v_of(s) > 0`` for every ``s`` of ``[0, 1]`` (bisection, centred forms:
    ``v(s) in v(c) + v'([s0, s1]) [-h, h]``; at most ``SIGN_PIECES`` pieces)."""
    work, used = [(Fraction(0), Fraction(1))], 0
    while work:
        lo, hi = work.pop()
        used += 1
        if used > SIGN_PIECES:
            return False
        c, h = (lo + hi) / 2, (hi - lo) / 2
        slope = v_of(Dual.variable(from_fraction(c) + arb(0, from_fraction(h)), 0, 1)).grad[0]
        value = sign * (v_of(from_fraction(c)) + slope * arb(0, from_fraction(h)))
        if not value > 0:
            work += [(lo, c), (c, hi)]
    return True


def _velocity(t0, u0, s, duration, F, f, w):
    """``s -> v`` over the flight from ``t0`` of the given phase ``duration``, at ``t0 + s
    duration`` (``sin(t) - sin(t0)`` as ``2 cos(t0 + x/2) sin(x/2)``: tight at ``s = 0``)."""
    def v(sigma):
        x = sigma * duration
        return u0 + F / w * 2 * (t0 + x / 2).cos() * (x / 2).sin() - s * f * x / w
    return v


def _itinerary(K, p, m):
    """None if the zero in ``K`` is an orbit with exactly the two impacts (module docstring),
    else the reason."""
    a, A, b, B = K
    F, f, w, e, _, _ = p
    d1, d2 = b - a, a + 2 * m * arb.pi() - b
    if not (A > 0 and B > 0):
        return f"an impact speed is not proved > 0 (grazing): A = {A}, B = {B}"
    if not e > 0:
        return f"restitution e = {e} is not proved > 0"
    if not (d1 > 0 and d2 > 0):
        return f"the flights' durations are not proved > 0: {d1}, {d2}"
    if not _one_sign(_velocity(a, e * A, 1, d1, F, f, w), 1):
        return ("the up-flight's velocity is not proved > 0 throughout (a turn or a stop in "
                "flight: the sticking boundary)")
    if not _one_sign(_velocity(b, -(e * B), -1, d2, F, f, w), -1):
        return ("the down-flight's velocity is not proved < 0 throughout (a turn or a stop in "
                "flight: the sticking boundary)")
    return None


def _section(K, m, ticks):
    """``(t, up)``: the section's phase ``2 pi ticks`` shifted by a multiple of ``2 pi m`` into
    the up-flight ``(a, b)`` (``up``) or the down-flight ``(b, a + 2 pi m)``, certainly; None if
    neither is certain."""
    a, _, b, _ = K
    period = 2 * m * arb.pi()
    for j in (-1, 0, 1, 2):
        t = 2 * arb.pi() * from_fraction(Fraction(ticks)) + j * period
        if a < t and t < b:
            return t, True
        if b < t and t < a + period:
            return t, False
    return None


def section_state(K, p, m, ticks):
    """``(x, v)`` at phase ``2 pi ticks`` (shifted by multiples of ``2 pi m``) from the flight
    that provably contains it, or a string saying why none does."""
    a, A, b, B = K
    F, f, w, e, l, r = p
    got = _section(K, m, ticks)
    if got is None:
        return f"the section at {ticks} T is not proved away from the impacts {a}, {b}"
    t, up = got
    return flight(a, l, e * A, 1, t, F, f, w) if up else flight(b, r, -(e * B), -1, t, F, f, w)


def _crossing(t0, x0, u0, s, wall, window, p, steps=3):
    """The phase where the flight from ``(x0, u0)`` at ``t0`` crosses ``wall``, known to cross
    once in ``window``: interval Newton ``N = c - g(c) / g'(window)`` (``g = x - wall``,
    ``g' = v / w``, of one sign there), intersected with the window ``steps`` times."""
    F, f, w = p[0], p[1], p[2]
    theta = window
    for _ in range(steps):
        c = theta.mid()
        x_c = flight(t0, x0, u0, s, c, F, f, w)[0]
        slope = flight(t0, x0, u0, s, theta, F, f, w)[1] / w
        theta = theta.intersection(c - (x_c - wall) / slope)
    return theta


def leg(t0, x0, u0, s, wall, window, speed, p):
    """The flight from ``(x0, u0)`` at phase ``t0`` (``sgn x' = s``) towards ``wall``: the
    ball of the phase where it crosses it and the ball of its speed there, if ``s x' > 0`` on
    ``[t0, hi]``, ``x`` is before the wall at ``lo`` and beyond it at ``hi`` (``[lo, hi]`` the
    ball ``window``: then it crosses once, ``x`` being monotone, and nowhere before ``lo``) and
    the speed lies in the ball ``speed``; else None."""
    F, f, w = p[0], p[1], p[2]
    lo, hi = window.lower(), window.upper()
    if not _one_sign(_velocity(t0, u0, s, hi - t0, F, f, w), s):
        return None
    before, after = flight(t0, x0, u0, s, lo, F, f, w)[0], flight(t0, x0, u0, s, hi, F, f, w)[0]
    if not (s * (before - wall) < 0 and s * (after - wall) > 0):
        return None
    theta = _crossing(t0, x0, u0, s, wall, window, p)
    hit = s * flight(t0, x0, u0, s, theta, F, f, w)[1]
    return (theta, hit) if hit > 0 and speed.contains(hit) else None


def flies_to(t0, x0, u0, s, end, p) -> bool:
    """Whether the flight from ``(x0, u0)`` at ``t0`` reaches phase ``end`` with no event:
    ``s x' > 0`` throughout and ``x(end)`` strictly between the walls (``x`` monotone)."""
    F, f, w, _, l, r = p
    x_end = flight(t0, x0, u0, s, end, F, f, w)[0]
    return _one_sign(_velocity(t0, u0, s, end - t0, F, f, w), s) and bool(l < x_end and x_end < r)


def every_orbit_enters(U, p, m, ticks, state) -> bool:
    """Whether every orbit from the state ball at the section hits the walls next inside the
    impact box ``U`` (two :func:`leg`, the second from the wall with ``-e`` times the first's
    speed) and flies back to the section with no other event (:func:`flies_to`): then a fixed
    point of ``Phi^m`` in the ball is a zero of ``G`` in ``U`` (module docstring)."""
    a, A, b, B = U
    e, l, r = p[3], p[4], p[5]
    period = 2 * m * arb.pi()
    got = _section(U, m, ticks)
    if got is None:
        return False
    ts, up = got
    legs = [(r, 1, b, B), (l, -1, a + period, A)] if up else [(l, -1, a + period, A), (r, 1, b + period, B)]
    t0, x0, u0 = ts, state[0], state[1]         # (points of the ball past a wall are no states)
    for wall, s, window, speed in legs:
        got = leg(t0, x0, u0, s, wall, window, speed, p)
        if got is None:
            return False
        t0, x0, u0 = got[0], wall, -s * e * got[1]
    return flies_to(t0, x0, u0, -legs[-1][1], ts + period, p)


def trace(u, p, m):
    """``tr (Phi^m)'`` along the orbit with impacts ``u`` (module docstring): Table 1's matrices
    (``reference.jacobian``: the impact's saltation matrix with the velocity before it, and the
    flight's), on balls or dual numbers; ``tr`` does not depend on the section (a cyclic
    product)."""
    a, A, b, B = u
    F, f, w, e, _, _ = p
    table = SimpleNamespace(e=e, f=f, one=1, zero=0, damping=False)    # what Table 1 reads

    def impact(phase, v_before):
        return impact_matrix(table, F * phase.cos(), v_before)

    down, up = (a + 2 * m * arb.pi() - b) / w, (b - a) / w
    M = mat_mul(mat_mul(impact(a, -A), flight_matrix(table, down)),
                mat_mul(impact(b, B), flight_matrix(table, up)))
    return M[0][0] + M[1][1]


def monodromy(K, p, pm, m):
    """``(trace, det)`` of ``(Phi^m)'`` for every zero in ``K`` and parameter in ``p``: the
    trace in centred form about ``(mid K, pm)`` (``pm`` the midpoint parameters), intersected
    with its direct enclosure; ``det = e^4`` (two impacts, flights of determinant 1)."""
    centre = [k.mid() for k in K]
    grad = _trace_duals(K, p, m).grad
    offsets = [k - c for k, c in zip(K, centre)] + [x - y for x, y in zip(p, pm)]
    centred = trace(centre, pm, m) + sum((g * o for g, o in zip(grad, offsets)), arb(0))
    return centred.intersection(trace(K, p, m)), p[3] ** 4


def _trace_duals(u, p, m):
    n = len(u) + len(p)
    return trace([Dual.variable(x, i, n) for i, x in enumerate(u)],
                 [Dual.variable(x, len(u) + i, n) for i, x in enumerate(p)], m)


def prove_two_impacts(box, guess, *, periods=1, ticks=Fraction(0), prec=BOX_PREC,
                      unique=True) -> ImpactOrbitProof:
    """Prove, for every parameter of ``box`` (a ``ParamBox`` without damping, or a scene without
    damping or position forcing), the orbit of ``Phi^periods`` with one impact on each wall near
    ``guess = (a, A, b, B)`` (module docstring); ``point`` holds its state at ``t = ticks T``.  ``unique``: also try
    uniqueness in the state ball (``unique_in_point``; it holds on small boxes: the ball of a
    wide one spans the orbit's motion over the box, and every orbit from it cannot enter one
    impact box; ~1 ms a try)."""
    if box.has("damping"):
        raise ValueError("prove_two_impacts: the closed-form flights need damping = 0 on the box")
    if box.has("position_forcing"):
        raise ValueError("prove_two_impacts: the closed-form flights need wavenumber = None (no "
                         "position forcing F cos(k x) cos(w t))")
    if isinstance(guess, str) or len(guess) != 4:
        raise TypeError(f"prove_two_impacts: guess must be four numbers (a, A, b, B), got {guess!r}")
    start = time.perf_counter()
    ticks = Fraction(ticks)
    phase = ticks - (ticks.numerator // ticks.denominator)
    with workprec(prec):
        proof = _prove(box, [from_number(g).mid() for g in guess], periods, ticks, prec, unique)
    proof.phase, proof.box, proof.seconds = phase, box, time.perf_counter() - start
    return proof


def _fail(box, periods, prec, reason, hint=None, radii=()):
    return ImpactOrbitProof(False, periods, reason=reason, prec=prec, box=box, split=hint,
                            impact_radii=tuple(radii))


def _jacobian(u, rho, P, m):
    """``G_u`` enclosed over ``U = u +- rho`` and the parameter balls ``P``."""
    return arb_mat([[g.grad[j] for j in range(4)] for g in _duals([arb(c, r) for c, r in zip(u, rho)], P, m)])


def _unique_in_state(u, head, C, P, m, rho, ticks, state) -> bool:
    """Whether the orbit is the only fixed point of ``Phi^m`` in the state ball, for every
    parameter: some impact box ``U = u +- s rho`` (``s`` in ``UNIQUE_SCALES``) passes the
    Krawczyk test (one zero of ``G`` in it) and every orbit from the ball enters it
    (:func:`every_orbit_enters`)."""
    for scale in UNIQUE_SCALES:
        wide = [r * scale for r in rho]
        if (krawczyk(u, head, C, _jacobian(u, wide, P, m), wide)[1]
                and every_orbit_enters([arb(c, r) for c, r in zip(u, wide)], P, m, ticks, state)):
            return True
    return False


def _prove(box, u, m, ticks, prec, unique):
    P, Pm = _params(box), _params(box.midpoint() if hasattr(box, "midpoint") else box)
    try:
        u = polish(u, Pm, m, prec)
        at_mid = _duals(u, Pm, m)
        C = arb_mat([[g.grad[j] for j in range(4)] for g in at_mid]).mid().inv().mid()
    except ZeroDivisionError:
        return _fail(box, m, prec, "G_u is singular at the midpoint: the orbit is not isolated "
                                   "(the fold itself)")
    over_box = _duals(u, P, m)
    dp = [P[j] - Pm[j] for j in range(len(NAMES))]
    CD = C * arb_mat([[g.grad[4 + j] for j in range(len(NAMES))] for g in over_box])
    head = C * arb_mat([[g.val] for g in at_mid]) + CD * arb_mat([[x] for x in dp])
    weight = [max(float((abs(CD[k, j]) * abs(dp[j])).upper()) for k in range(4)) for j in range(len(NAMES))]
    hint = NAMES[max(range(len(NAMES)), key=weight.__getitem__)]
    floor = [(abs(c) + 1) * arb(2) ** (-prec // 2) for c in u]
    K, rho, why = inflate(u, head, C, lambda rho: _jacobian(u, rho, P, m), floor)
    radii = [float(r) for r in rho]
    if K is None:
        return _fail(box, m, prec, why, hint, radii)
    why = _itinerary(K, P, m)
    if why is None:
        state = section_state(K, P, m, ticks)
        why = state if isinstance(state, str) else None
    if why is not None:
        return _fail(box, m, prec, why, hint, radii)
    unique = unique and _unique_in_state(u, head, C, P, m, rho, ticks, state)
    tr, det = monodromy(K, P, Pm, m)
    kinds = ["impact", "impact"]
    kind, stability, mults = classify(box, tr, det, kinds)
    return ImpactOrbitProof(True, m, point=tuple(state), radius=float(max(s.rad() for s in state)),
                            multipliers=mults, trace=tr, det=det, kind=kind, stability=stability,
                            itinerary=kinds, prec=prec, box=box,
                            radii=tuple(float(s.rad()) for s in state), impacts=tuple(K),
                            impact_radii=tuple(radii), split=hint, unique_in_point=unique)
