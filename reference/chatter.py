"""Chatter: the accumulation of infinitely many impacts at one wall, summed by acceleration.

After an impact at ``r`` with a force pushing into the wall (``A > f``), the particle
decelerates (``a = A + f``), turns, comes back (``a = A - f``) and hits again; for a frozen
force the impact speeds shrink by ``rho = e sqrt((A - f)/(A + f)) < 1`` (with restitution
``e < 1`` this happens without friction too).  The bounce map ``(t_n, u_n) -> (t_n+1, u_n+1)``
is analytic with a line ``u = 0`` of fixed points, normally attracting with multiplier
``lambda(t) = rho(t)``; hence the impact times converge as
``t_n = t_inf + sum_j b_j lambda^(j n)``, ``lambda = rho(t_inf)``, a sum of geometric
sequences.  Better still, every point ``(t_n, u_n)`` (impact time, impact speed) lies on
the same invariant fibre of the accumulation point, on which ``t`` is an analytic function
of ``u`` with ``t(0) = t_inf``: ``t_n = t_inf + R(u_n)``, ``R(0) = 0``.  The accumulation time
is therefore the value at ``u = 0`` of the interpolating polynomial through the last
``K + 1`` points ``(u_n, t_n)`` (Neville's algorithm), whose error is ``O(u_n^(K+1))``
times the Lebesgue factor of geometric nodes, ``prod_k 1/(1 - lambda^k)`` -- no knowledge of
``lambda`` needed, and far better conditioned than Wynn's epsilon algorithm
(``~(1 - lambda)^(-2K)``) when ``lambda`` is close to 1.  (``wynn_epsilon`` is kept as an
independent check in the tests.)

The regime is detected as a *run*: consecutive impacts at the same wall with only turning
points between them (with friction) or nothing between them (frictionless, ``e < 1``),
strictly decreasing impact speeds, and the force pushing into the wall at the latest impact.
From ``MIN_RUN`` impacts on, every new impact gives a new estimate; the accumulation
point is accepted when two successive estimates agree to ``tol`` (set by the integrator from
the caller's digits), the estimate lies after the last impact, and the force still
pushes into the wall there.  A run that does not converge within ``MAX_RUN`` impacts raises
``RuntimeError`` (no silent truncation of the bounce count); this happens only for
``lambda`` extremely close to 1 (friction a tiny fraction of the pushing force).
"""
from __future__ import annotations

import math

import mpmath

MIN_RUN = 5
#: Impacts without improvement of the estimates after which the best one is taken.
STALL = 10
MAX_RUN = 5000
#: Terms of the sequence fed to Wynn's algorithm (odd: the last column is an even one).
WYNN_TERMS = 21
#: Degree of the extrapolating polynomial in the impact speed (at most).
MAX_DEGREE = 14


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
        self.best = None                      # (difference, estimate, count) of the best pair
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

    def estimate(self, tol, loose_tol):
        """``t_inf`` if the run has converged, else ``None``.

        Converged: two successive estimates agree to ``tol``.  The impact times of tiny
        bounces are known only to ``noise / u`` (the wall is crossed at speed ``u``), so the
        agreement improves, then stalls at the noise level: if it has not improved for
        ``STALL`` impacts, the best estimate so far is taken when its agreement is within
        ``loose_tol`` (the chatter time is then known to that accuracy; the state after
        it, at rest on the wall, does not depend on it).
        """
        if self.count < MIN_RUN:
            return None
        if self.count > MAX_RUN:
            raise RuntimeError(
                f"chatter at wall {self.wall_side:+d} did not converge in {MAX_RUN} impacts: "
                f"(t, x, v, mode) = ({self.times[-1]}, wall, {self.speeds[-1]}, chatter)")
        k = self.degree() + 1
        est = extrapolate_to_zero(self.speeds[-k:], self.times[-k:])
        self.estimates.append(est)
        if len(self.estimates) < 2:
            return None
        diff = abs(self.estimates[-1] - self.estimates[-2])
        t_last = self.times[-1]
        if diff <= tol and est >= t_last - tol:
            return max(est, t_last)
        if self.best is None or diff < self.best[0]:
            self.best = (diff, est, self.count)
        best_diff, best_est, best_count = self.best
        if self.count - best_count >= STALL and best_diff <= loose_tol:
            return max(best_est, t_last)
        return None

    def degree(self):
        """Largest degree ``K <= MAX_DEGREE`` whose noise amplification is affordable.

        With nodes in ratio ``rho`` (the last speed ratio), extrapolation to 0 amplifies
        input noise by about ``prod_{k<=K} (1 + rho^k)/(1 - rho^k)``; ``K`` is capped so
        that this stays below ``2^(prec/3)`` (a third of the working digits).  For
        ``rho <= 0.9`` that is ``MAX_DEGREE``; for ``rho`` near 1 it is lower.
        """
        rho = min(float(self.speeds[-1] / self.speeds[-2]), 1 - 1e-9)
        budget, amp, K = mpmath.mp.prec / 3, 0.0, 0
        while K < min(MAX_DEGREE, self.count - 1):
            step = math.log2((1 + rho ** (K + 1)) / (1 - rho ** (K + 1)))
            if amp + step > budget:
                break
            amp += step
            K += 1
        return max(K, 1)

    def latest(self):
        """The latest estimate, converged or not (``None`` before ``MIN_RUN`` impacts)."""
        return self.estimates[-1] if self.estimates else None
