"""Hard cases constructed exactly, independently of both integrators.

Each hard case is a state ``(x0, v0)`` at ``t = 0`` whose trajectory hits a delicate event
at a chosen time ``t*`` (a grazing impact, a crossing pair, an impact at exactly ``t = T``,
a turning point exactly on the stick-slip boundary ``|F cos w t| = f``, a turning point at a
wall, a stick).  It is made by choosing the *left* state at ``t*`` (position, velocity just
before, flight sign ``s``) and running this module's own closed-form flight **backward** in
time to ``t = 0``.  With damping ``c`` (``x'' + c x' + s f = F cos wt``), ``h = t - t0``,
``E = exp(-c h)``, ``phi1 = (1 - E)/c``, ``phi2 = (h - phi1)/c``::

    v(t) = v0 E - s f phi1 + G(t) - G(t0) E,              G(t) = F (c cos wt + w sin wt)/(c^2 + w^2)
    x(t) = x0 + v0 phi1 - s f phi2 + Q(t) - Q(t0) - G(t0) phi1,   Q(t) = F ((c/w) sin wt - cos wt)/(c^2 + w^2)

(``phi1 -> h``, ``phi2 -> h^2/2`` as ``c -> 0``: the undamped flight
``v = v0 + (F/w)(sin wt - sin wt0) - s f h``; with ``c = 0`` that form is used as it stands).

Going backward, the segment with sign ``s`` ends (at its forward start) where ``x`` reaches
the wall behind (``l`` for ``s = +1``: forward, an impact there, ``v -> -e v``, so backward the
speed before it is the speed after divided by ``e``; ``e = 0`` cannot be crossed backward) or
where ``v = 0`` (forward, a turning point; accepted only if ``s A > f`` there, so that the forward
motion is unambiguous; otherwise the candidate ``t*`` is rejected).  Roots are located by
the certified step of ``reference.events`` ("Safe steps"): with ``G(u) = g(t - u) >= 0`` and ``|G''| <= M``,
``G(u + h) >= G + G' h - M h^2 / 2``, so the step ``h = (G' + sqrt(G'^2 + 2 M G)) / M`` never
jumps over a root.  ``M = F + f + c V`` for ``x`` and ``F w + c (F + f + c V)`` for ``v``, with
``V = (|v1| + (F + f) U) exp(c U)`` bounding ``|v|`` on a backward stretch of length ``U``
(``|dv/du| <= c |v| + F + f``; Gronwall).  The construction runs at ``CONSTRUCT_DPS`` digits;
the state is then rounded to ``STATE_DIGITS`` significant digits (a decimal string: the exact
definition of the hard case from then on).

The chattering case is explicit (no backward run): ``x0 = r - h``, ``v0 = u > 0`` at ``t = 0``,
where ``A = F > f`` pushes into ``r``, with ``(h, u) = (10^-3 100^-k, 10^-2 10^-k)`` for the first
``k = 0, 1, ...`` with ``h < R/100`` whose accumulation time, estimated with the force frozen at
``F`` (first impact at speed ``v1 = sqrt(u^2 + 2 (F - f) h)``, then bounces shrinking by
``rho = e sqrt((F - f)/(F + f))``, each lasting ``e v (1/(F + f) + 1/sqrt(F^2 - f^2))``), falls
within 0.7 of the push ``[0, acos(f/F)/w)``; and only while ``rho <= RHO_MAX`` (slower shrinking
costs the reference thousands of bounces at the golden data's digits).  With ``F <= f`` two explicit cases: at rest mid-gap, and
moving mid-gap (it stops for good).

``construct(scene)`` returns the cases and, for every kind the scene does not admit, the reason
(frictionless: no sticking; ``F <= f``: no turn and no chatter; a construction that found no
unambiguous backward run: its last obstacle).  Under position forcing (``F cos(k x) cos(w t)``,
``F > 0``) the flight has no closed form: every kind but chatter comes from
``hardcases_position`` (the reference's Taylor flight run backward, each case a single flight
certified by a validated one), chatter from ``_chatter_case`` at the wall the force pushes into at
``t = 0`` (``_push``), or where it pushes into neither beyond friction, from a chatter run later in
the period that a scan of starts finds and a forward proof certifies (``forward_position``).
"""
from __future__ import annotations

import mpmath

from cross_check.agreement.case import (CONSTRUCT_DPS, NAMES, STATE_DIGITS, ConstructionError,  # noqa: F401
                                        HardCase, decimal_text as _dec)
from reference.scene import Scene

_MAX_STEPS = 20000
_MAX_EVENTS = 400


def _params(scene: Scene):
    return tuple(scene.mpf(k) for k in ("F", "f", "omega", "l", "r"))


def _phi12(c, h):
    """``phi1 = (1 - exp(-c h))/c`` and ``phi2 = (h - phi1)/c`` without cancellation
    (the series ``h^2 sum_k (-c h)^k/(k + 2)!`` while ``|c h| < 1/4``; at most 400 terms)."""
    z = c * h
    phi1 = -mpmath.expm1(-z) / c
    if abs(z) >= mpmath.mpf(1) / 4:
        return phi1, (h - phi1) / c
    term, total, eps = h * h / 2, mpmath.mpf(0), mpmath.eps
    for k in range(400):
        total += term
        if abs(term) <= eps * abs(total):
            return phi1, total
        term = term * (-z) / (k + 3)
    raise RuntimeError(f"phi2 series did not converge for c h = {z}")


def flight(scene: Scene, t0, x0, v0, s, t):
    """Closed-form flight with sign ``s`` from ``(t0, x0, v0)``: ``(x, v, a)`` at ``t`` (module
    docstring; damping ``c`` taken from the scene)."""
    F, f, w, _, _ = _params(scene)
    h = t - t0
    c = scene.mpf("damping")
    if c == 0:
        v = v0 + (F / w) * (mpmath.sin(w * t) - mpmath.sin(w * t0)) - s * f * h
        x = (x0 + v0 * h + (F / w ** 2) * (mpmath.cos(w * t0) - mpmath.cos(w * t) - w * h * mpmath.sin(w * t0))
             - s * f * h * h / 2)
        return x, v, F * mpmath.cos(w * t) - s * f
    k = F / (c * c + w * w)
    G = lambda u: k * (c * mpmath.cos(w * u) + w * mpmath.sin(w * u))       # noqa: E731
    Q = lambda u: k * ((c / w) * mpmath.sin(w * u) - mpmath.cos(w * u))     # noqa: E731
    E = mpmath.exp(-c * h)
    phi1, phi2 = _phi12(c, h)
    v = v0 * E - s * f * phi1 + G(t) - G(t0) * E
    x = x0 + v0 * phi1 - s * f * phi2 + Q(t) - Q(t0) - G(t0) * phi1
    return x, v, F * mpmath.cos(w * t) - c * v - s * f


def force(scene: Scene, t):
    """``A(t) = F cos(w t)``."""
    F, _, w, _, _ = _params(scene)
    return F * mpmath.cos(w * t)


class Budget:
    """Safe steps a construction may take in all (``KIND_BUDGET`` per kind of hard case): a
    scene whose backward runs crawl (strong damping, a huge gap) gives up with a reason."""

    def __init__(self, steps: int):
        self.left = steps

    def take(self):
        if self.left <= 0:
            raise ConstructionError("the construction's budget of safe steps is spent (KIND_BUDGET)")
        self.left -= 1


#: safe backward steps per kind of hard case, over all its candidate times (the paper's scenes
#: take at most a few thousand)
KIND_BUDGET = 30000


def _bounds(scene, v, H):
    """``(M_wall, M_velocity)``: bounds of ``|x''|`` and ``|v''|`` over a backward stretch of
    length ``H`` from a point with velocity ``v`` (``|v| <= (|v| + (F + f) H) exp(c H)`` there)."""
    F, f, w, _, _ = _params(scene)
    c = scene.mpf("damping")
    vmax = (abs(v) + (F + f) * H) * mpmath.exp(c * H)
    tiny = mpmath.mpf(10) ** (-mpmath.mp.dps)               # F = 0: a linear function, any M > 0 holds
    return max(F + f + c * vmax, tiny), max(F * w + c * (F + f + c * vmax), tiny)


def _backward_segment(scene, t1, x1, v1, s, t_stop, budget=None):
    """Run the flight of sign ``s`` backward from ``t1`` to its forward start or ``t_stop``.

    Returns ``(tau, kind)`` with kind ``"wall"``, ``"zero_velocity"`` or ``"stop"``.  With damping
    each step stays within ``1/c`` of where its bounds were taken (``_bounds``).
    """
    _, _, _, l, r = _params(scene)
    c = scene.mpf("damping")
    wall = l if s > 0 else r
    eps = mpmath.mpf(10) ** (-(mpmath.mp.dps - 8))
    budget = budget or Budget(KIND_BUDGET)
    u = mpmath.mpf(0)
    for _ in range(_MAX_STEPS):
        budget.take()
        t = t1 - u
        x, v, a = flight(scene, t1, x1, v1, s, t)
        H = t - t_stop if c == 0 else min(t - t_stop, 1 / c)
        M = _bounds(scene, v, H)
        bounds = {"wall": M[0], "zero_velocity": M[1]}
        # G >= 0 on the safe side, dG/du = -dg/dt.
        G = {"wall": s * (x - wall), "zero_velocity": s * v}
        dG = {"wall": -s * v, "zero_velocity": -s * a}
        if u > 0:
            noise = eps * (1 + abs(x) + abs(v))              # the evaluation noise floor
            for name in ("wall", "zero_velocity"):
                if G[name] < -noise:
                    raise RuntimeError(f"backward flight crossed {name} unseen at t={t}, x={x}, v={v}, s={s}")
                if G[name] <= noise:
                    return t, name
        step = t - t_stop
        for name in ("wall", "zero_velocity"):
            g, dg, M = max(G[name], 0), dG[name], bounds[name]
            if u == 0 and g == 0 and dg <= 0:
                raise ConstructionError(f"{name} is not left going backward from t={t1}")
            root = mpmath.sqrt(dg * dg + 2 * M * g)
            # the same root, written without cancellation on the approaching side (dg < 0)
            h = (dg + root) / M if dg >= 0 else 2 * g / (root - dg)
            step = min(step, max(h, eps / 1000))
        if t - t_stop <= eps:
            return t_stop, "stop"
        u += min(step, H)
    raise RuntimeError(f"backward flight: more than {_MAX_STEPS} steps from t={t1}, x={x1}, v={v1}, s={s}")


def construct_backward(scene: Scene, t_star, x_star, v_before, s, budget=None):
    """The state at ``t = 0`` whose forward flight arrives at ``(t*, x*, v_before)`` with sign ``s``.

    Returns ``(x0, v0, log)``; ``log`` lists the forward events passed on the way
    (``(kind, t)``, latest first).  Raises ``ConstructionError`` if the backward run meets an
    ambiguous point (``v = 0`` with ``|A| <= f``) or leaves the gap.
    """
    _, f, _, l, r = _params(scene)
    e = scene.mpf("restitution")
    t, x, v = mpmath.mpf(t_star), mpmath.mpf(x_star), mpmath.mpf(v_before)
    log = []
    for _ in range(_MAX_EVENTS):
        tau, kind = _backward_segment(scene, t, x, v, s, mpmath.mpf(0), budget)
        xt, vt, _ = flight(scene, t, x, v, s, tau)
        noise = mpmath.mpf(10) ** (-(mpmath.mp.dps - 8)) * (2 + abs(xt) + abs(vt))   # the segment's stop test
        if not (l - noise <= xt <= r + noise):
            raise ConstructionError(f"backward flight leaves the gap at t={tau}")
        if kind == "stop":
            return min(max(xt, l), r), vt, log       # a wall reached within the noise floor is the wall
        if kind == "wall":
            if e == 0:
                raise ConstructionError(f"restitution 0: the impact at t={tau} leaves v = 0, the speed "
                                        "before it is not determined (no backward run across it)")
            log.append(("impact", tau))
            t, x, v, s = tau, (l if s > 0 else r), -vt / e, -s     # forward v+ = -e v-
            continue
        A = force(scene, tau)
        if not s * A > f * (1 + mpmath.mpf(10) ** -6):
            raise ConstructionError(f"backward run reaches v = 0 at t={tau} with |A| near or below f")
        log.append(("turn", tau))
        t, x, v, s = tau, xt, mpmath.mpf(0), -s
    raise RuntimeError(f"backward construction: more than {_MAX_EVENTS} events from t*={t_star}")


def _first_valid(scene, candidates, left_state, name, kind, how):
    """Try candidate event times until the backward construction succeeds: ``(case, None)``, or
    ``(None, why)`` with the last obstacle met."""
    why, tried = "no candidate time", 0
    budget = Budget(KIND_BUDGET)
    for t_star in candidates:
        if budget.left <= 0:
            break
        tried += 1
        try:
            x0, v0, log = construct_backward(scene, t_star, *left_state(t_star), budget=budget)
        except (ConstructionError, RuntimeError) as exc:
            why = f"{type(exc).__name__}: {exc}"
            continue
        path = ", ".join(f"{k}@{mpmath.nstr(t, 6)}" for k, t in reversed(log)) or "no earlier event"
        return HardCase(name, _dec(x0), _dec(v0), _dec(t_star), kind,
                        f"{how}; backward from t*={mpmath.nstr(t_star, 12)} ({path})"), None
    return None, (f"no backward run from t* reached t = 0 unambiguously ({tried} of {len(candidates)} "
                  f"candidate times tried; last: {why})")


def construct(scene: Scene) -> tuple[list[HardCase], dict[str, str]]:
    """The hard cases of ``scene`` and ``{name: reason}`` for each of ``NAMES`` it does not admit
    (under position forcing every kind but chatter comes from ``hardcases_position``)."""
    if scene.has("position_forcing") and scene.has("forcing"):
        from cross_check.agreement import hardcases_position

        built, notes = hardcases_position.construct(scene)
        with mpmath.workdps(CONSTRUCT_DPS):
            _chatter_case(scene, built, notes)
        return [built[n] for n in NAMES if built.get(n) is not None], notes
    with mpmath.workdps(CONSTRUCT_DPS):
        F, f, w, l, r = _params(scene)
        T = 2 * mpmath.pi / w
        grid = [T * k / 64 for k in range(3, 62)]
        decel = [t for t in grid if F * mpmath.cos(w * t) < -f - F / 20]   # a < 0 coming to r
        built, notes = {}, {}

        def at_r(speed):
            return lambda t: (r, speed(t), 1)

        def attempt(name, candidates, left_state, kind, how):
            if not candidates:
                notes[name] = ("the force never decelerates a flight into r beyond friction "
                               "(F cos wt < -f - F/20 nowhere" + ("; F <= f" if F <= f else "") + ")")
                return
            built[name], why = _first_valid(scene, candidates, left_state, name, kind, how)
            if why:
                notes[name] = why

        attempt("grazing", decel, at_r(lambda t: mpmath.mpf("1e-6")), "impact",
                "near-grazing impact at r with v- = 1e-6 while decelerating (A < -f)")
        attempt("crossing_pair", decel, at_r(lambda t: (f - force(scene, t)) * mpmath.mpf("5e-14")), "impact",
                "x - r has two roots 1e-13 apart: impact at r with v- = |a| * 5e-14 (a = A - f < 0)")
        attempt("turn_at_wall", decel, lambda t: (r, mpmath.mpf(0), 1), "contact",
                "v reaches 0 exactly at x = r with A < -f (contact and release at once, or a turn)")
        if F > 0:
            attempt("impact_at_T", [T], at_r(lambda t: F / w / 2), "impact",
                    "impact at r at exactly t = T with v- = F/(2w)")
        else:
            notes["impact_at_T"] = "no forcing (F = 0): the case's impact speed F/(2w) would be 0 (a tangency)"
        _friction_cases(scene, built, notes)
        _chatter_case(scene, built, notes)
        return [built[n] for n in NAMES if built.get(n) is not None], notes


def _friction_cases(scene, built, notes):
    """Stick-slip boundary and sticking (``F > f > 0``), or at rest and stopping (``F <= f``)."""
    F, f, w, l, r = _params(scene)
    mids = [l + (r - l) * k / 8 for k in (4, 3, 5, 2, 6, 1, 7)]
    if f > 0 and F > f:
        t_b = mpmath.acos(-f / F) / w                       # A(t_b) = -f, |A| grows after
        for name, case in (("stick_slip_boundary", _boundary_case(scene, t_b, mids)),
                           ("sticking", _stick_case(scene, 2 * mpmath.pi / w / 4, mids))):
            built[name] = case
            if case is None:
                notes[name] = "no mid-gap stop reached back to t = 0 unambiguously (7 positions tried)"
    else:
        why = ("frictionless (f = 0): no sticking and no stick-slip boundary" if f == 0 else
               "F <= f: a stop is final, no slip follows a stick (the at_rest and stopping cases stand for it)")
        notes["stick_slip_boundary"] = notes["sticking"] = why
    if F <= f:
        built["at_rest"] = HardCase("at_rest", _dec((l + r) / 2), "0", "0", "stick",
                                    "explicit: v0 = 0 mid-gap with F <= f: the particle never moves")
        if f == 0:
            notes["stopping"] = "F = f = 0: nothing slows a moving particle down, it never stops"
        else:
            speed, text = (F / w, "F/w") if F > 0 else (f / w, "f/w")
            built["stopping"] = HardCase("stopping", _dec((l + r) / 2), _dec(speed), "0", "stick",
                                         f"explicit: v0 = {text} mid-gap with F <= f: it stops, then stays stopped")
    else:
        notes["at_rest"] = notes["stopping"] = "F > f: the force moves a particle at rest (no permanent rest)"


#: chatter starts tried: ``(h, u) = (10^-3 100^-k, 10^-2 10^-k)``, ``k < _CHATTER_TRIES``
_CHATTER_TRIES = 5
#: under position forcing from ``k = 3``: every bounce the reference simulates at the golden
#: data's 90 and 110 digits is a Taylor flight with its own event search, and a start nearer the
#: accumulation has fewer of them (issue 33, scene A: 42 events instead of 62 from k = 0)
_FIRST_TRY_POSITION = 3
#: bounces shrinking slower than this cost the reference thousands of bounces at the golden
#: data's 90 and 110 digits (rho = 0.99: about a minute per input): no chatter case then
RHO_MAX = mpmath.mpf("0.92")


def _push(scene):
    """``(P, side, wall, name)``: the wall the force pushes into hardest at ``t = 0`` and the push
    ``P = side A(wall, 0)`` (``F`` into ``r`` for the base model; ``side F cos(k wall)`` under
    position forcing, the larger of the two walls)."""
    F, _, _, l, r = _params(scene)
    k = scene.mpf("wavenumber")
    if k is None:
        return F, 1, r, "r"
    return max((F * mpmath.cos(k * r), 1, r, "r"), (-F * mpmath.cos(k * l), -1, l, "l"))


def _chatter_case(scene, built, notes):
    """The explicit chatter start (module docstring) where the scene chatters: at the wall the
    force pushes into at ``t = 0`` (``_push``; ``F`` in place of the push ``P`` in the docstring)."""
    _, f, w, l, r = _params(scene)
    F, side, wall, name = _push(scene)
    e = scene.mpf("restitution")
    if f == 0 and e == 1:
        notes["chatter"] = "f = 0 and e = 1: the bounces do not shrink (rho = 1), no chatter"
        return
    if e == 0:
        notes["chatter"] = "restitution 0: an impact ends in contact at once, no run of bounces"
        return
    if F <= f and scene.mpf("wavenumber") is None:
        notes["chatter"] = "F <= f: the force never pushes into a wall beyond friction, no chatter"
        return
    if F <= f:              # position forcing: a chatter run later in the period, found forward
        from cross_check.agreement import forward_position

        peaks = [abs(scene.mpf("F") * mpmath.cos(scene.mpf("wavenumber") * wall)) for wall in (l, r)]
        if max(peaks) <= f:         # the push into a wall is at most |F cos(k wall)|, at any t
            notes["chatter"] = (f"the force never pushes into a wall beyond friction (|F cos(k l)| = "
                                f"{mpmath.nstr(peaks[0], 6)}, |F cos(k r)| = {mpmath.nstr(peaks[1], 6)} <= f), no chatter")
            return

        built["chatter"], why = forward_position.chatter(scene, RHO_MAX)
        if why:
            notes["chatter"] = (f"the force at t = 0 pushes into neither wall beyond friction (push "
                                f"{mpmath.nstr(F, 6)} <= f at wall {name}), and no chatter run later: {why}")
        return
    a, b = F + f, F - f
    rho = e * mpmath.sqrt(b / a)
    if rho > RHO_MAX:
        notes["chatter"] = (f"the bounces shrink too slowly (rho = e sqrt((F - f)/(F + f)) = {mpmath.nstr(rho, 4)} > "
                            f"{mpmath.nstr(RHO_MAX, 2)}): the reference would simulate thousands of bounces at "
                            "the golden data's 90 and 110 digits")
        return
    push = mpmath.acos(f / F) / w                       # A = F cos wt > f on [0, push)
    for k in range(_FIRST_TRY_POSITION if scene.mpf("wavenumber") is not None else 0, _CHATTER_TRIES):
        h_den, u_den = 10 ** (3 + 2 * k), 10 ** (2 + k)
        h, u = mpmath.mpf(1) / h_den, mpmath.mpf(1) / u_den
        if not h < (r - l) / 100:
            continue
        v1 = mpmath.sqrt(u * u + 2 * b * h)                # speed at the first impact (frozen force)
        t_inf = (v1 - u) / b + e * v1 * (1 / a + 1 / mpmath.sqrt(a * b)) / (1 - rho)
        if t_inf < push * 7 / 10:
            sign, pushed = ("", "F") if scene.mpf("wavenumber") is None else ("-" if side < 0 else "", "P")
            built["chatter"] = HardCase(
                "chatter", _dec(wall - side * h), sign + "0." + "0" * (1 + k) + "1", "0", "chatter",
                f"explicit: x0 = {name} {'-' if side > 0 else '+'} 1/{h_den}, v0 = {sign}1/{u_den} at t = 0 "
                f"where A = {pushed} > f pushes into {name}")
            return
    notes["chatter"] = (f"no start tried (x0 = r - 1e-3 .. 1e-11, v0 = 1e-2 .. 1e-6) accumulates within 0.7 of "
                        f"the push acos(f/F)/w (rho = {mpmath.nstr(rho, 4)})")


def _stop_case(scene, t_star, mids, name, where):
    """``v`` reaches 0 at ``t_star`` at the first mid-gap position that a backward flight
    (``s = +1``, ``v = 0``) reaches from ``t = 0``; ``where`` says what the force is there."""
    budget = Budget(KIND_BUDGET)
    for xm in mids:
        try:
            x0, v0, log = construct_backward(scene, t_star, xm, 0, 1, budget=budget)
        except (ConstructionError, RuntimeError):
            continue
        return HardCase(name, _dec(x0), _dec(v0), _dec(t_star), "stick",
                        f"v reaches 0 at x = {mpmath.nstr(xm, 8)} at {where}; "
                        f"backward with {len(log)} earlier events")
    return None


def _boundary_case(scene, t_b, mids):
    """Turning point exactly at ``A = -f`` (stick of zero length, then slip)."""
    return _stop_case(scene, t_b, mids, "stick_slip_boundary", "t* = acos(-f/F)/w where A = -f exactly")


def _stick_case(scene, t_s, mids):
    """A stick: ``v`` reaches 0 at ``t* = T/4`` where ``A = 0``, inside ``|A| <= f``."""
    return _stop_case(scene, t_s, mids, "sticking", "t* = T/4 where A = 0 < f")
