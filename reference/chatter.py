"""Chatter: the accumulation of infinitely many impacts at one wall, summed by acceleration.

After an impact at ``r`` with a force pushing into the wall (``A > f``), the particle
decelerates (``a = A + f``), turns, comes back (``a = A - f``) and hits again; for a frozen
force the impact speeds shrink by ``rho = e sqrt((A - f)/(A + f)) < 1`` (with restitution
``e < 1`` this happens without friction too).  The bounce map ``(t_n, u_n) -> (t_n+1, u_n+1)``
is analytic with a line ``u = 0`` of fixed points, normally attracting with multiplier
``lambda(t) = rho(t)``; every point ``(t_n, u_n)`` (impact time, impact speed) lies on the
invariant fibre of the accumulation point, on which ``t`` is an analytic function of ``u``
with ``t(0) = t_inf``: ``t_n = t_inf + R(u_n)``, ``R(0) = 0``.  The accumulation time is the
value at ``u = 0`` of the interpolating polynomial through points ``(u_n, t_n)`` of the run
(Neville's algorithm) -- no knowledge of ``lambda`` needed.

Working precision (issue 6)
---------------------------
1. *Wall-relative bounces* (:func:`wall_bounce`).  In absolute coordinates a bounce of
   speed ``u`` has height ``~u^2/a`` on top of ``|wall|``, so its impact time is known only
   to ``eps |wall| / u``: the late bounces carry half the digits.  Once a run has started,
   each bounce is solved in ``y = side (wall - x)`` and local times: every quantity is a
   difference-free closed form in the bounce's own duration, so times, heights and speeds
   keep full relative precision for any ``u``.  A bounce is taken only under a certificate
   (the push exceeds friction on the whole bounce): then it has exactly the events the
   generic event loop would find (a turn with friction, the impact); otherwise, and for
   damped or position-forced flights (no closed form here), the generic loop runs.
2. *Strided nodes* (:meth:`BounceRun.extrapolate`).  For ``rho`` near 1 (``e -> 1``, or
   ``f << A``) consecutive impacts are nearly equal nodes and extrapolating through them
   amplifies rounding like ``(2/(1-rho))^K / K!``.  The nodes are taken ``stride`` impacts
   apart so that their speeds differ by ``NODE_RATIO``: the Lebesgue constant is then
   bounded independently of ``rho``, and the degree is chosen from the tableau.

Cost.  ``R`` has a radius of convergence ``~(1 - rho) a / w`` in ``u`` (the tail lasts
``~u / ((1 - rho) a)`` and the force changes on the time scale ``1/w``), so the run must
reach speeds well inside it: ``~ln(u0/u)/(1 - rho)`` simulated bounces (measured at dps 50:
rho = 0.5: 18, 0.9: 80, 0.99: ~470, f/A = 0.01: ~410, f/A = 0.001: ~4000 bounces at
~0.6 ms each).  No data-driven extrapolation can do with fewer when ``rho -> 1``.

The regime is detected as a *run*: consecutive impacts at the same wall with only turning
points between them (with friction) or nothing between them (frictionless, ``e < 1``),
strictly decreasing impact speeds, and the force pushing into the wall at the latest impact.
From ``MIN_RUN`` impacts on, every ``stride`` impacts give a new estimate; the accumulation
point is accepted when it agrees with the previous one to ``tol`` (set by the integrator from
the caller's digits), the estimate lies after the last impact, and the force still
pushes into the wall there.  A run that does not converge within ``MAX_RUN`` impacts raises
``RuntimeError`` (no silent truncation of the bounce count).  ``wynn_epsilon`` is kept as an
independent check in the tests.
"""
from __future__ import annotations

import math

import mpmath

MIN_RUN = 5
#: Extrapolations without improvement after which the best one is taken (generic loop).
STALL = 10
MAX_RUN = 60000
#: Largest speed ratio between successive extrapolation nodes (see ``BounceRun.stride``).
NODE_RATIO = 0.9
#: Degree of the extrapolating polynomial in the impact speed (at most).
MAX_DEGREE = 40


def extrapolate_to_zero(us, ts):
    """Neville's algorithm: the interpolating polynomial through ``(u_i, t_i)`` at ``u = 0``."""
    P = list(ts)
    n = len(P)
    for k in range(1, n):
        for i in range(n - k):
            P[i] = (us[i + k] * P[i] - us[i] * P[i + 1]) / (us[i + k] - us[i])
    return P[0]


def wynn_epsilon(seq):
    """Wynn's epsilon algorithm: the last even-column entry of the table built on ``seq``.

    ``eps_{-1}^{(n)} = 0``, ``eps_0^{(n)} = S_n``,
    ``eps_{k+1}^{(n)} = eps_{k-1}^{(n+1)} + 1 / (eps_k^{(n+1)} - eps_k^{(n)})``;
    the even columns ``eps_{2k}`` are the Shanks transforms.  A zero difference means the
    column has converged exactly; the table stops there.
    """
    prev = [mpmath.mpf(0)] * (len(seq) + 1)
    cur = list(seq)
    best = cur[-1]
    for k in range(1, len(seq)):
        nxt = []
        for i in range(len(cur) - 1):
            diff = cur[i + 1] - cur[i]
            if diff == 0:
                return best
            nxt.append(prev[i + 1] + 1 / diff)
        prev, cur = cur, nxt
        if k % 2 == 0:
            best = cur[-1]
        if len(cur) < 2:
            break
    return best


class BounceRun:
    """The current run of impacts at one wall (see the module docstring)."""

    __slots__ = ("wall_side", "times", "speeds", "estimates", "between", "best")

    def __init__(self):
        self.reset()

    def reset(self):
        self.wall_side = 0
        self.times, self.speeds, self.estimates = [], [], []
        self.best = None                      # (difference, estimate, index) of the best
        self.between = 0

    def observe(self, kind, side=0):
        """Record an event; ``side`` is the wall (+1 r, -1 l) of an impact."""
        if kind == "turn":
            self.between += 1
            if self.between > 1:
                self.reset()
            return
        if kind != "impact":
            self.reset()
            return
        if side != self.wall_side:
            self.reset()
            self.wall_side = side
        self.between = 0

    def add_impact(self, t, speed):
        """Append an impact (after :meth:`observe`)."""
        if self.speeds and speed >= self.speeds[-1]:
            side = self.wall_side
            self.reset()
            self.wall_side = side
        self.times.append(t)
        self.speeds.append(speed)

    @property
    def count(self):
        return len(self.times)

    def stride(self):
        """Impacts between extrapolation nodes: the speeds of chosen nodes differ by a
        factor ``<= NODE_RATIO`` (``rho`` near 1 would give nearly equal nodes)."""
        rho = min(float(self.speeds[-1] / self.speeds[-2]), 1 - 1e-12)
        return max(1, math.ceil(math.log(NODE_RATIO) / math.log(rho)))

    def extrapolate(self):
        """``(t_inf estimate, error estimate)`` from nodes ``stride`` impacts apart.

        The nodes ``u_0 < u_1 < ...`` (latest first) are nearly geometric with ratio
        ``q <= NODE_RATIO``; Neville's tableau extrapolates to ``u = 0`` with degrees
        ``K = 1, 2, ...`` using nodes ``0..K``.  Its Lebesgue constant at ``u = 0`` stays
        below ``prod_k (1 + q^k)/(1 - q^k)`` (~8e3 for ``q = 0.8``; ~1e7 for 0.9), so rounding
        is not amplified, while the truncation error behaves like
        ``prod_{i<=K} (u_i / rho_R)`` (``rho_R`` the radius of convergence of ``R``): it falls
        while the nodes stay well inside the radius.  The degree taken is the one after
        which the tableau changes least; the change is the error estimate.  Nodes are added
        while the Lebesgue constant (computed from the nodes) stays below
        ``2^(prec/5)``.
        """
        m = self.stride()
        idx = list(range(self.count - 1, -1, -m))[:MAX_DEGREE + 1]
        us = [self.speeds[i] for i in idx]
        ts = [self.times[i] for i in idx]
        budget, uf = 2.0 ** (mpmath.mp.prec / 5), [float(u) for u in us]
        # Lebesgue constant at 0 of nodes 0..n: sum_i prod_{j != i} |u_j / (u_j - u_i)|,
        # the products updated as nodes are added
        prods, n = [1.0], 1
        while n < len(uf):
            new = uf[n]
            prods = [p * abs(new / (new - uf[i])) for i, p in enumerate(prods)]
            prods.append(math.prod(abs(uf[j] / (uf[j] - new)) for j in range(n)))
            if sum(prods) > budget:
                break
            n += 1
        P, best, best_err, prev = list(ts[:n]), ts[0], None, ts[0]
        for k in range(1, n):
            for i in range(n - k):
                P[i] = (us[i + k] * P[i] - us[i] * P[i + 1]) / (us[i + k] - us[i])
            err = abs(P[0] - prev)
            if best_err is None or err < best_err:
                best, best_err = P[0], err
            prev = P[0]
        if best_err is None:
            best_err = mpmath.inf
        return best, best_err

    def estimate(self, tol, loose_tol):
        """``t_inf`` if the run has converged, else ``None``.

        Every ``stride`` impacts a new extrapolation is made (:meth:`extrapolate`).
        Converged: its error estimate is below ``tol`` and it agrees to ``tol`` with the
        extrapolation made ``stride`` impacts earlier (whose nodes were all larger by the
        node ratio: its truncation error is ``~NODE_RATIO^-(K+1)`` times larger, so the
        agreement bounds the error of the older one and the new one is far better).
        Impact times found by the generic event loop (scenes with damping or position
        forcing) are known only to ``noise / u``: there the agreement stalls at the noise
        level; if it has not improved for ``STALL`` extrapolations, the best estimate so far
        is taken when within ``loose_tol``.  Wall-relative bounces (``wall_bounce``) have
        no such stall.
        """
        if self.count < MIN_RUN:
            return None
        if self.count > MAX_RUN:
            raise RuntimeError(
                f"chatter at wall {self.wall_side:+d} did not converge in {MAX_RUN} impacts: "
                f"(t, x, v, mode) = ({self.times[-1]}, wall, {self.speeds[-1]}, chatter)")
        m = self.stride()
        if self.estimates and self.count - self.estimates[-1][0] < m:
            return None
        est, err = self.extrapolate()
        previous = self.estimates[-1][1] if self.estimates else None
        self.estimates.append((self.count, est))
        if previous is None:
            return None
        diff = max(abs(est - previous), err)
        t_last = self.times[-1]
        if diff <= tol and est >= t_last - tol:
            return max(est, t_last)
        if self.best is None or diff < self.best[0]:
            self.best = (diff, est, len(self.estimates))
        best_diff, best_est, best_index = self.best
        if len(self.estimates) - best_index >= STALL and best_diff <= loose_tol:
            return max(best_est, t_last)
        return None

    def latest(self):
        """The latest estimate, converged or not (``None`` before ``MIN_RUN`` impacts)."""
        return self.estimates[-1][1] if self.estimates else None


# --- one bounce in wall-relative coordinates (base flights) ------------------------------
#: Bound on the Newton/bisection iterations of one root of a bounce.
MAX_ROOT_ITERATIONS = 200


class Bounce:
    """One certified bounce at a wall: the turn (friction only) and the next impact.

    ``t_turn``, ``t_impact`` are absolute times (absolute precision); ``duration`` (impact
    minus start), ``height`` (at the turn; a bound without friction) and ``speed`` (of the
    next impact) keep full relative precision however small.
    """

    __slots__ = ("t_turn", "height", "t_impact", "speed", "duration")

    def __init__(self, t_turn, height, t_impact, speed, duration):
        self.t_turn, self.height, self.t_impact, self.speed = t_turn, height, t_impact, speed
        self.duration = duration


def _integrals(w, C0, S0, h):
    """``(I1, I2, c)``: ``int_0^h cos w(t0+s) ds``, its integral, and ``cos w(t0+h)``.

    ``I1 = (C0 sin th - S0 (1 - cos th))/w``, ``I2 = (C0 (1 - cos th) - S0 (th - sin th))/w^2``
    with ``th = w h``; ``1 - cos th = 2 sin^2(th/2)`` and ``th - sin th`` at raised
    precision, so both keep full relative precision for tiny ``h``.
    """
    th = w * h
    extra = 10 if th >= 1 else 2 * (1 - int(mpmath.mag(th))) + 10
    with mpmath.extraprec(extra):
        c2, s2 = mpmath.cos_sin(th / 2)
        sn = 2 * s2 * c2
        tms = th - sn
    omc = 2 * s2 * s2
    return (C0 * sn - S0 * omc) / w, (C0 * omc - S0 * tms) / (w * w), C0 - C0 * omc - S0 * sn


def _decreasing_root(fn, guess, h_max, what):
    """The root ``h`` in ``(0, h_max]`` of a strictly decreasing ``fn`` (``fn(0+) > 0``),
    to working precision, or ``None`` if ``fn(h_max) > 0`` (no root in the window).

    Newton's method from ``guess``, inside the bracket ``[lo, hi]`` of the signs seen so
    far (``hi = h_max`` until a negative value is seen); a step leaving the bracket is
    replaced by ``h_max`` (first time) or by bisection.  Newton converges quadratically,
    so a step below ``2^-(prec/2 + 8) h`` leaves an error far below ``2^-prec h``; a
    bracket at rounding level ends a bisection.  Bounded by ``MAX_ROOT_ITERATIONS``.
    """
    tiny = mpmath.ldexp(1, -mpmath.mp.prec // 2 - 8)
    floor = mpmath.ldexp(1, -mpmath.mp.prec + 8)
    lo, hi, hi_seen = mpmath.mpf(0), h_max, False
    h = min(guess, h_max)
    for _ in range(MAX_ROOT_ITERATIONS):
        g, dg = fn(h)
        if g > 0:
            if h >= h_max:
                return None
            lo = h
        elif g < 0:
            hi, hi_seen = h, True
        else:
            return h
        if dg < 0 and abs(g / dg) <= tiny * h:           # converged (the bracket guards)
            return min(max(h - g / dg, lo), hi)
        h_new = h - g / dg if dg < 0 else hi
        if not lo < h_new < hi:
            h_new = h_max if not hi_seen else (lo + hi) / 2
        if hi_seen and hi - lo <= floor * hi:
            return h_new
        h = h_new
    raise RuntimeError(f"chatter bounce: the {what} did not converge in {MAX_ROOT_ITERATIONS} "
                       f"iterations: bracket [{lo}, {hi}]")


def wall_bounce(model, t, side, speed, t_end):
    """The next bounce at wall ``side`` after an impact at ``t`` (outgoing ``speed > 0``).

    Only for the base flight (no damping, no wavenumber); ``None`` when the bounce is not
    of the chatter kind (see below) and the generic event loop must take over.

    Wall-relative coordinates: ``y = side (wall - x) >= 0`` with the push into the wall
    ``P(t) = side F cos(w t)``; after the impact ``y(0) = 0``, ``y'(0) = speed``:

    * friction: away from the wall ``y'' = -(P + f)``: the turn is the root of
      ``y'(h) = speed - side F I1(h) - f h`` (strictly decreasing while ``P > -f``), the
      height ``H = speed h1 - side F I2(h1) - f h1^2/2``; back to the wall
      ``y'' = -(P - f)``: ``y(k) = H - side F I2'(k) + f k^2/2`` (``I'`` from the turn),
      strictly decreasing while ``P > f``; the impact speed is ``-y'(k2)``;
    * frictionless (``e < 1``): ``y(h) = speed h - side F I2(h)``; the root ``h > 0`` of
      ``y(h)/h`` (strictly decreasing while ``P > 0``).

    Every quantity is a difference-free expression in the local times ``h``, ``k``, so
    bounce heights and times keep full *relative* precision however small they are
    (absolute coordinates would know them only to ``eps |wall| / speed``).

    Certificate: with ``D`` the bounce duration, ``|P'| <= F w`` gives ``P > f`` on the
    whole bounce if ``P(t) - F w D > f``; then the turn and the impact are the only events
    (unique roots of monotone functions), none other happens in between (a stick needs
    ``P <= f``; the other wall is farther than ``H < r - l``).  Otherwise, or if the bounce
    reaches ``t_end``, ``None``.
    """
    if model.damping or model.position_forcing or speed <= 0:
        return None
    F, f, w = model.F, model.f, model.w
    C0, S0 = mpmath.cos_sin(w * t)
    P0 = side * F * C0
    if P0 <= f:
        return None

    def away(h):
        I1, I2, c_end = _integrals(w, C0, S0, h)
        if model.friction:                              # y'(h) and y''(h)
            return speed - side * F * I1 - f * h, -(side * F * c_end + f)
        q = speed - side * F * I2 / h                   # y(h)/h and its derivative
        return q, (speed - side * F * I1 - q) / h

    window = (P0 - f) / (F * w)          # P > f on [t, t + window]: the certified span
    if model.friction:
        h1 = _decreasing_root(away, speed / (P0 + f), window, "turn")
        if h1 is None:
            return None
        I1, I2, _ = _integrals(w, C0, S0, h1)
        height = speed * h1 - side * F * I2 - f * h1 * h1 / 2
        t_turn = t + h1
        C1, S1 = mpmath.cos_sin(w * t_turn)
        P1 = side * F * C1
        if P1 <= f or height <= 0 or h1 >= window:
            return None

        def back(k):
            J1, J2, _ = _integrals(w, C1, S1, k)
            return height - side * F * J2 + f * k * k / 2, -side * F * J1 + f * k

        k2 = _decreasing_root(back, mpmath.sqrt(2 * height / (P1 - f)), window - h1, "impact")
        if k2 is None:
            return None
        J1, _, _ = _integrals(w, C1, S1, k2)
        u_next, duration, t_imp = side * F * J1 - f * k2, h1 + k2, t_turn + k2
    else:
        h1 = _decreasing_root(away, 2 * speed / P0, window, "impact")
        if h1 is None:
            return None
        I1, _, _ = _integrals(w, C0, S0, h1)
        t_turn, duration, t_imp = None, h1, t + h1
        u_next = side * F * I1 - speed
        height = speed * speed / (2 * P0)               # only for the gap check (upper bound
        height = height * P0 / (P0 - F * w * h1)        # with P >= P0 - F w h on the bounce)
    margin = P0 - F * w * duration - f
    if margin <= model.noise_a or height >= model.r - model.l or u_next <= 0:
        return None
    if t_imp > t_end:
        return None
    return Bounce(t_turn, height, t_imp, u_next, duration)
