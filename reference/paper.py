"""The paper's closed forms, each checked against an independent derivation and corrected where
the printed text errs.  Every function cites the paper's equation label; the evidence for each
erratum (numbers at 50 digits) is in the docstring and is recomputed by
``tests/test_paper_formulas.py`` and ``cross_check/paper/claims/``.

Notation: ``F, f, w = omega, l, r, R = r - l``, ``S_m = sqrt(4 F^2 - m^2 pi^2 f^2)``,
``a_m = arcsin(m pi f / (2F))``.  Only mpmath and ``reference.scene`` are imported; every
function works at ``dps`` digits inside ``mpmath.workdps`` and returns ``mpf`` values.

Symmetric non-sticking solutions (eq. ``nonstick``), derived here independently.  Take a flight
``l -> r`` with ``x' > 0`` on ``[t_l, t_l + h]``, ``h = m pi / w`` (m odd; m = 1 is the paper's case,
m = 3 the period-3 islands), and its mirror image ``x(t + h) = r + l - x(t)`` (which needs
``cos w(t + h) = -cos wt``, i.e. m odd).  On the up-flight ``x'' = F cos wt - f``::

    x(t) = -F/w^2 cos wt - f/2 (t - t_l)^2 + C (t - t_l) + D,  v(t) = F/w sin wt - f (t - t_l) + C.

Elastic impact at ``r`` plus symmetry give ``v(t_l + h) = v(t_l)``, i.e. ``-2F sin psi = m pi f``
with ``psi = w t_l``: ``sin psi = -m pi f/(2F)`` (existence: ``f/F <= 2/(m pi)``).  The two roots are
``psi_2 = -a_m`` (cos psi > 0) and ``psi_1 = a_m - pi`` (cos psi < 0).  ``x(t_l + h) - x(t_l) = R``
gives ``C = (2 R w^2 - 4 F cos psi + f m^2 pi^2) / (2 m pi w)`` and ``x(t_l) = l`` gives
``D = l + F cos(psi)/w^2``; the impact speed is ``v_imp = (R w^2 - 2F cos psi)/(m pi w)``.

Monodromy (Table 1 matrices, period ``2h = m T``): both impacts carry the same matrix
``[[-1, 0], [k, -1]]``, ``k = 2F cos(w t_r)/v_imp = -2F cos(psi)/v_imp``, so
``Phi'^m = (I P(h))^2`` with ``tr(I P(h)) = k h - 2``, ``det = 1``, hence
``tr Phi'^m = (k h - 2)^2 - 2``; branch 1 has ``k h = m^2 pi^2 S_m / (R w^2 + S_m)`` (a centre iff
``0 < kh < 4``), branch 2 ``k h = -m^2 pi^2 S_m / (R w^2 - S_m) < 0`` (a saddle).

Errata (printed -> corrected; evidence in the functions' docstrings and the tests):

* eq. ``noimpacts``: ``R > F/w^2`` -> ``R >= 2F/w^2`` (``no_impact_offsets``);
* eq. ``nonstick``: second piece lacks ``r + l``; ``psi_1 = pi + a_1`` -> ``a_1 - pi`` (``printed_nonstick``);
* eq. ``nonstick:cond``: the condition for ``x_1`` only (``nonstick_condition_printed``);
* the no-impact attractor of Fig. many:wide turns (no sticking) for ``f/F < 0.53703`` (``no_impact_attractor``);
* eq. ``xpot``: ``eta = (2/pi) arccos(f/F)`` with ``[-1, -1 + eta] U [1 - eta, 1]`` -> ``[-1, -eta] U [eta, 1]``
  (``equilibrium_set``);
* eq. ``hamilsys``: forcing sign and friction sign (``lift_rhs_corrected``);
* Table 1: ``x'(t*)`` in the reflection matrix is the velocity before the impact (a reading, not an error).
Reproduced: ``f/F <= 2/pi``, eq. ``fold:bif``, the reduced fold condition (``fold_reduced_bound``),
Table 1's matrices, the 3:1 resonance gap ``R* = 0.89329974...`` (``resonance_gaps``).
"""
from __future__ import annotations

from dataclasses import dataclass

import mpmath

from reference.scene import Scene

DEFAULT_DPS = 50


def _ctx(dps: int):
    """Work at ``dps`` digits, or at the caller's precision if higher (so ``mpmath.diff`` works)."""
    if not (isinstance(dps, int) and dps >= 15):
        raise ValueError(f"dps must be an integer >= 15, got {dps!r}")
    return mpmath.workdps(max(dps, mpmath.mp.dps))


def _check_base(scene: Scene, where: str) -> None:
    for effect in ("restitution", "damping", "position_forcing"):
        if scene.has(effect):
            raise ValueError(f"{where}: the closed form is for the paper's eq. main; scene has {effect}")


def _p(scene: Scene):
    return tuple(scene.mpf(k) for k in ("F", "f", "omega", "l", "r"))


# --- eq. noimpacts ------------------------------------------------------------------------
def no_impact_condition_printed(scene: Scene) -> bool:
    """The paper's condition for eq. ``noimpacts``: ``R > F / w^2`` (printed; see erratum)."""
    F, _, w, l, r = (scene.float(k) for k in ("F", "f", "omega", "l", "r"))
    return r - l > F / w ** 2


def no_impact_offsets(scene: Scene, *, dps: int = DEFAULT_DPS):
    """Range ``(C_min, C_max)`` of ``C`` in eq. ``noimpacts`` for which no wall is touched, or None.

    Erratum: ``x(t) = -F/w^2 cos wt + C`` sweeps ``[C - F/w^2, C + F/w^2]`` (excursion ``2F/w^2``),
    so it stays in ``[l, r]`` iff ``l + F/w^2 <= C <= r - F/w^2``: the condition is
    ``R >= 2 F / w^2`` (``R > 2F/w^2`` for a segment rather than one grazing point), not
    ``R > F/w^2``.  E.g. F = w = 1, R = 1.5 satisfies the printed condition, but the orbit of
    width 2 cannot fit.  Only a solution of eq. ``main`` for ``f = 0`` (its velocity changes sign).
    """
    _check_base(scene, "no_impact_offsets")
    if scene.has("friction"):
        raise ValueError("no_impact_offsets: eq. noimpacts solves eq. main only for f = 0")
    with _ctx(dps):
        F, _, w, l, r = _p(scene)
        lo, hi = l + F / w ** 2, r - F / w ** 2
        return (lo, hi) if lo <= hi else None


def no_impact_solution(scene: Scene, C, t, *, dps: int = DEFAULT_DPS):
    """State ``(x(t), x'(t))`` of eq. ``noimpacts``: ``x = -F/w^2 cos wt + C`` (f = 0 only)."""
    if no_impact_offsets(scene, dps=dps) is None:
        raise ValueError("no_impact_solution: needs R >= 2F/w^2 (see no_impact_offsets)")
    with _ctx(dps):
        F, _, w, _, _ = _p(scene)
        t, C = mpmath.mpf(t), mpmath.mpf(C)
        return -F / w ** 2 * mpmath.cos(w * t) + C, F / w * mpmath.sin(w * t)


# --- eq. nonstick as printed ------------------------------------------------------------
def printed_nonstick_constants(scene: Scene, branch: int, *, dps: int = DEFAULT_DPS) -> dict:
    """``psi, tau, C, D`` exactly as printed under eq. ``nonstick`` (branch 1 or 2)."""
    _check_branch(branch)
    with _ctx(dps):
        F, f, w, l, r = _p(scene)
        a = mpmath.asin(mpmath.pi * f / (2 * F))
        S = mpmath.sqrt(4 * F ** 2 - f ** 2 * mpmath.pi ** 2)
        sg = 1 if branch == 1 else -1
        psi = mpmath.pi + a if branch == 1 else -a
        return {"psi": psi, "tau": psi - sg * mpmath.pi,
                "C": (f * mpmath.pi ** 2 + sg * 2 * S + 2 * (r - l) * w ** 2) / (2 * mpmath.pi * w),
                "D": l - sg * S / (2 * w ** 2)}


def printed_nonstick(scene: Scene, branch: int, t, *, deriv: int = 0, dps: int = DEFAULT_DPS):
    """``x_{1,2}(t)`` (``deriv=0``) or ``x'`` (``deriv=1``) of eq. ``nonstick`` as printed, ``0 <= wt < pi``.

    Errata (found by evaluating this printed form, see ``tests/test_paper_formulas.py``):

    1. the second piece lacks ``r + l``: it must be ``r + l - F/w^2 cos wt + f/2 (...)^2 - C(...) - D``
       (the mirror ``r + l - x(t - pi/w)`` of the first).  As printed it reaches ``-l`` instead of
       ``r`` at ``wt = tau``: correct only when ``l = -r`` (fig. many:2pi), wrong by ``r + l``
       (= 20 for fig. wide:b);
    2. ``psi_1 = pi + a_1`` anchors the parabola of ``x_1`` one period late: the up-flight of
       ``x_1`` that covers ``0 <= wt < tau_1`` starts at ``wt = a_1 - pi``, so ``psi_1 = a_1 - pi``
       (the printed ``tau_1 = psi_1 - pi = a_1`` is the right impact phase; with the corrected
       ``psi_1``, ``tau_{1,2} = psi_{1,2} + pi`` for both branches).  As printed, ``x_1`` is off by ``C_1 T`` plus friction terms
       (F = w = 1, l = 0, r = 20, f = 0.3: printed ``x_1(0) = -30.736``, true ``16.678``).
    ``C_{1,2}``, ``D_{1,2}``, ``psi_2``, ``tau_{1,2}`` and the domain ``0 <= wt < pi`` are right.
    """
    if deriv not in (0, 1):
        raise ValueError(f"printed_nonstick: deriv must be 0 or 1, got {deriv!r}")
    k = printed_nonstick_constants(scene, branch, dps=dps)
    with _ctx(dps):
        F, f, w, _, _ = _p(scene)
        t = mpmath.mpf(t)
        if not 0 <= w * t < mpmath.pi:
            raise ValueError(f"printed_nonstick: t must satisfy 0 <= w t < pi, got t={t}")
        first = w * t < k["tau"]
        u = t - (k["psi"] / w if first else (k["psi"] + mpmath.pi) / w)
        sg = 1 if first else -1
        if deriv == 0:
            return -F / w ** 2 * mpmath.cos(w * t) + sg * (-f / 2 * u ** 2 + k["C"] * u + k["D"])
        return F / w * mpmath.sin(w * t) + sg * (-f * u + k["C"])


def _check_branch(branch):
    if branch not in (1, 2):
        raise ValueError(f"branch must be 1 or 2, got {branch!r}")


# --- eq. nonstick, corrected ----------------------------------------------------------------
@dataclass(frozen=True)
class SymmetricSolution:
    """A symmetric non-sticking solution (eq. ``nonstick``, corrected; see the module docstring).

    ``m`` odd: one flight ``l -> r`` takes ``m pi / w``; the orbit has period ``m T`` (a fixed point
    of ``Phi^m``).  ``psi = w t_l`` (up-flight start), ``tau = psi + m pi = w t_r`` (impact at r),
    ``C, D`` as in the paper's form, ``v_impact > 0`` the speed at both impacts.
    """

    scene: Scene
    branch: int
    m: int
    dps: int
    psi: mpmath.mpf
    C: mpmath.mpf
    D: mpmath.mpf

    @property
    def tau(self):
        with _ctx(self.dps):
            return self.psi + self.m * mpmath.pi

    @property
    def half_period(self):
        """``h = m pi / w``: the duration of one flight."""
        with _ctx(self.dps):
            return self.m * mpmath.pi / self.scene.mpf("omega")

    @property
    def v_impact(self):
        """Speed just before each impact, ``(R w^2 - 2 F cos psi)/(m pi w)``."""
        with _ctx(self.dps):
            F, f, w, _, _ = _p(self.scene)
            return F / w * mpmath.sin(self.psi) + self.C

    def _phase(self, t):
        """Time since the start of the current flight, and whether it is the up-flight."""
        w = self.scene.mpf("omega")
        h = self.half_period
        u = mpmath.mpf(t) - self.psi / w
        u -= 2 * h * mpmath.floor(u / (2 * h))
        return (u, True) if u < h else (u - h, False)

    def x(self, t):
        """Position; on the down-flight ``r + l - (up-flight shifted by h)``."""
        with _ctx(self.dps):
            F, f, w, l, r = _p(self.scene)
            u, up = self._phase(t)
            cos_term = -F / w ** 2 * mpmath.cos(w * mpmath.mpf(t))
            poly = -f / 2 * u ** 2 + self.C * u + self.D
            return cos_term + poly if up else r + l + cos_term - poly

    def v(self, t):
        """Velocity (right limit at the impact instants)."""
        with _ctx(self.dps):
            F, f, w, _, _ = _p(self.scene)
            u, up = self._phase(t)
            lin = -f * u + self.C
            return F / w * mpmath.sin(w * mpmath.mpf(t)) + (lin if up else -lin)

    def state0(self):
        """``(x(0), x'(0))``: the fixed point of ``Phi^m``."""
        return self.x(0), self.v(0)

    def kh(self):
        """``k h`` of the monodromy ``(I P(h))^2`` (module docstring)."""
        with _ctx(self.dps):
            F, _, w, _, _ = _p(self.scene)
            return -2 * F * mpmath.cos(self.psi) / self.v_impact * self.half_period

    def trace(self):
        """``tr Phi'^m = (k h - 2)^2 - 2``; ``det Phi'^m = 1``."""
        with _ctx(self.dps):
            return (self.kh() - 2) ** 2 - 2

    def multipliers(self):
        """Eigenvalues of ``Phi'^m`` (complex on the unit circle for a centre)."""
        with _ctx(self.dps):
            tr = self.trace()
            disc = mpmath.sqrt(mpmath.mpc(tr ** 2 - 4))
            return (tr + disc) / 2, (tr - disc) / 2

    def min_flight_velocity(self):
        """``(v_min, wt_min)``: minimum of ``x'`` on the up-flight ``psi <= wt <= psi + m pi``.

        Candidates: the endpoints and the interior minima of ``w v = F(sin th - sin psi)
        - f(th - psi) + w v_imp``, where ``cos th = f/F`` and ``sin th < 0``
        (``th = -arccos(f/F) + 2 pi j``).  The orbit is non-sticking iff ``v_min > 0``.
        """
        with _ctx(self.dps):
            F, f, w, _, _ = _p(self.scene)
            lo, hi = self.psi, self.tau
            cands = [lo]
            base = -mpmath.acos(f / F)
            j = mpmath.ceil((lo - base) / (2 * mpmath.pi))
            while base + 2 * mpmath.pi * j <= hi:
                cands.append(base + 2 * mpmath.pi * j)
                j += 1
                if j > 10 * self.m + 10:
                    raise RuntimeError(f"min_flight_velocity: runaway candidate loop, psi={lo}, m={self.m}")

            def vel(th):
                return (F * (mpmath.sin(th) - mpmath.sin(lo)) - f * (th - lo)) / w + self.v_impact

            return min((vel(th), th) for th in cands)


def symmetric_solution(scene: Scene, branch: int, *, m: int = 1, dps: int = DEFAULT_DPS):
    """The corrected symmetric solution ``x_branch`` of eq. ``nonstick`` (m = 1), or its period-m analogue.

    Returns None when ``f/F > 2/(m pi)`` (no root of ``sin psi = -m pi f/(2F)``).  The returned
    orbit solves eq. ``main`` with the given walls and impact law; it is a genuine (non-sticking)
    solution iff ``min_flight_velocity()[0] > 0`` (see ``nonstick_margin``).
    """
    _check_base(scene, "symmetric_solution")
    _check_branch(branch)
    if not (isinstance(m, int) and m >= 1 and m % 2 == 1):
        raise ValueError(f"symmetric_solution: m must be an odd positive integer, got {m!r}")
    with _ctx(dps):
        F, f, w, l, r = _p(scene)
        if F == 0 or m * mpmath.pi * f > 2 * F:
            return None
        a = mpmath.asin(m * mpmath.pi * f / (2 * F))
        psi = a - mpmath.pi if branch == 1 else -a
        C = (2 * (r - l) * w ** 2 - 4 * F * mpmath.cos(psi) + f * m ** 2 * mpmath.pi ** 2) / (2 * m * mpmath.pi * w)
        D = l + F * mpmath.cos(psi) / w ** 2
        return SymmetricSolution(scene, branch, m, dps, psi, C, D)


def existence_bound(m: int = 1, *, dps: int = DEFAULT_DPS):
    """Largest ``f/F`` with symmetric solutions: ``2/(m pi)`` (m = 1: the paper's ``f/F <= 2/pi``)."""
    with _ctx(dps):
        return 2 / (m * mpmath.pi)


# --- eq. nonstick:cond, fold:bif ------------------------------------------------------------
def nonstick_condition_printed(scene: Scene, *, dps: int = DEFAULT_DPS):
    """Left side of eq. ``nonstick:cond`` (the paper: non-sticking iff it is > 0).

    It equals ``pi w v_min`` of branch 1 exactly (interior minimum at ``wt = -arccos(f/F)``), so it
    is the right condition for ``x_1``.  Erratum: it is not the condition for ``x_2``, whose
    minimum speed is at the impacts, ``v = (R w^2 - S_1)/(pi w)`` (or at an interior minimum when
    ``arccos(f/F) <= a_1``): for F = w = 1, f = 0, R = 1.5 the printed side is 0.358 > 0 while
    ``x_2`` would need ``R w^2 > 2`` (its flight would start with ``x' = -0.159 < 0``).
    """
    _check_base(scene, "nonstick_condition_printed")
    with _ctx(dps):
        F, f, w, l, r = _p(scene)
        pi = mpmath.pi
        return (mpmath.sqrt(4 * F ** 2 - pi ** 2 * f ** 2) - pi * mpmath.sqrt(F ** 2 - f ** 2)
                + pi * f * (mpmath.asin(pi * f / (2 * F)) - mpmath.asin(f / F)) + (r - l) * w ** 2)


def nonstick_margin(scene: Scene, branch: int, *, m: int = 1, dps: int = DEFAULT_DPS):
    """``m pi w v_min`` of the symmetric solution (> 0 iff non-sticking), or None if it does not exist.

    For branch 1, m = 1 this is eq. ``nonstick:cond``'s left side; for branch 2 the corrected
    condition (see ``nonstick_condition_printed``).
    """
    sol = symmetric_solution(scene, branch, m=m, dps=dps)
    if sol is None:
        return None
    with _ctx(dps):
        return m * mpmath.pi * scene.mpf("omega") * sol.min_flight_velocity()[0]


def fold_friction(scene: Scene, *, m: int = 1, dps: int = DEFAULT_DPS):
    """eq. ``fold:bif``: the two symmetric solutions coincide at ``f = 2F/(m pi)``."""
    with _ctx(dps):
        return 2 * scene.mpf("F") / (m * mpmath.pi)


def fold_reduced_bound(*, dps: int = DEFAULT_DPS):
    """Right side of the reduced condition at the fold: ``w^2 R / F > sqrt(pi^2 - 4) - 2 arccos(2/pi)``.

    Derived: at ``pi f = 2F`` eq. ``nonstick:cond`` reads ``-F sqrt(pi^2 - 4) + 2F(pi/2 - arcsin(2/pi))
    + R w^2 > 0``; ``pi/2 - arcsin = arccos``.  Reproduced: 0.66134817512852572571...
    """
    with _ctx(dps):
        return mpmath.sqrt(mpmath.pi ** 2 - 4) - 2 * mpmath.acos(2 / mpmath.pi)


def resonance_gaps(scene: Scene, *, trace=-1, m: int = 1, dps: int = DEFAULT_DPS):
    """Gaps ``R`` at which branch 1 has ``tr Phi'^m = trace`` (-1: the 3:1 resonance, multipliers ``e^{+-2 pi i/3}``).

    ``(kh - 2)^2 - 2 = trace`` gives ``kh = 2 +- sqrt(trace + 2)``; ``kh = m^2 pi^2 S/(R w^2 + S)``
    gives ``R = S (m^2 pi^2 / kh - 1) / w^2`` (only the roots with ``0 < kh`` and ``R > 0``).  For the
    paper's fig. resonance (w = 2 pi, F = w^2, f = 24.65) the roots are 0.8932997420... (kh = 3,
    the paper's ``R* ~ 0.8932``) and 3.4601186010... (kh = 1).
    """
    with _ctx(dps):
        F, f, w, _, _ = _p(scene)
        S = mpmath.sqrt(4 * F ** 2 - m ** 2 * mpmath.pi ** 2 * f ** 2)
        out = []
        for sg in (1, -1):
            kh = 2 + sg * mpmath.sqrt(mpmath.mpf(trace) + 2)
            if kh > 0:
                R = S * (m ** 2 * mpmath.pi ** 2 / kh - 1) / w ** 2
                if R > 0:
                    out.append(R)
        return sorted(out)


# --- the no-impact attractor of Fig. many:wide (stated after Table 1) -------------------------
def stick_threshold(*, dps: int = DEFAULT_DPS):
    """``f/F = 1/sqrt(1 + pi^2/4) = 0.53703...``: below it the no-impact periodic orbits turn, above they stick.

    Derived (``no_impact_attractor``): the symmetric turn-turn orbit has its turns at
    ``sin th0 = -pi f/(2F)``; a turn needs ``|F cos th0| > f``, i.e. ``1 - pi^2 f^2/(4F^2) > f^2/F^2``.
    """
    with _ctx(dps):
        return 1 / mpmath.sqrt(1 + mpmath.pi ** 2 / 4)


def no_impact_attractor(scene: Scene, *, dps: int = DEFAULT_DPS) -> dict:
    """The symmetric periodic orbits without impacts that attract (paper: "two intervals of sticking").

    Away from the walls, with ``f > 0``:

    * ``f/F < stick_threshold()``: two TURNING POINTS per period at ``wt = th0, th0 + pi``,
      ``sin th0 = -pi f/(2F)``, ``cos th0 > 0``; ``x'(0) = f arccos(pi f/(2F)) / w``; multipliers 1
      (translation) and ``((|A| - f)/(|A| + f))^2``, ``|A| = F cos th0``;
    * ``f/F >= stick_threshold()``: two STICKING intervals per period, slip at ``wt = -arccos(f/F)``
      (and ``+ pi``); ``x'(0) = (sqrt(F^2 - f^2) - f arccos(f/F)) / w``; multipliers 1 and 0.
    Returns ``{"kind": "turns"|"sticks", "v0", "multiplier"}`` (the non-unit multiplier).
    Erratum of the text after Table 1: for Fig. many:wide a-e (f = 0.1 ... 0.5 < 0.537) the
    attractor turns, it does not stick; only panel f (f = 0.6) has two sticking intervals.
    """
    _check_base(scene, "no_impact_attractor")
    with _ctx(dps):
        F, f, w, _, _ = _p(scene)
        if not 0 < f < F:
            raise ValueError("no_impact_attractor: needs 0 < f < F")
        if f / F < stick_threshold(dps=dps):
            c = mpmath.sqrt(1 - (mpmath.pi * f / (2 * F)) ** 2) * F
            return {"kind": "turns", "v0": f * mpmath.acos(mpmath.pi * f / (2 * F)) / w,
                    "multiplier": ((c - f) / (c + f)) ** 2}
        return {"kind": "sticks", "v0": (mpmath.sqrt(F ** 2 - f ** 2) - f * mpmath.acos(f / F)) / w,
                "multiplier": mpmath.mpf(0)}


# --- eq. xpot -----------------------------------------------------------------------------
def eta_printed(F, f, *, dps: int = DEFAULT_DPS):
    """``eta = (2/pi) arccos(f/F)`` as printed under eq. ``xpot``."""
    with _ctx(dps):
        return 2 / mpmath.pi * mpmath.acos(mpmath.mpf(f) / mpmath.mpf(F))


def equilibrium_set(scene: Scene, *, dps: int = DEFAULT_DPS):
    """The set E of eq. ``xpot`` (``k = pi/2``, walls at -1, 1) as intervals ``[(-1, -1 + e), (1 - e, 1)]``.

    At rest at ``x`` the particle stays for all t iff ``|F cos(pi x/2) cos wt| <= f`` for all t,
    i.e. ``cos(pi x/2) <= f/F`` (``cos >= 0`` on ``[-1, 1]``), i.e. ``|x| >= (2/pi) arccos(f/F)``.
    Erratum: with the printed ``eta = (2/pi) arccos(f/F)`` the sets must read ``[-1, -eta]`` and
    ``[eta, 1]`` (as in the paper's commented-out line); in the printed form ``-1 <= x <= -1 + eta``,
    ``1 - eta <= x <= 1`` the width is ``e = (2/pi) arcsin(f/F) = 1 - eta``.  For F = 1, f = 0.1:
    the true E is ``|x| >= 0.93623``, the printed one ``|x| >= 0.06377`` (almost the whole gap).
    """
    if scene.wavenumber is None:
        raise ValueError("equilibrium_set: needs the position-dependent forcing of eq. xpot (wavenumber)")
    with _ctx(dps):
        k, l, r = scene.mpf("wavenumber"), scene.mpf("l"), scene.mpf("r")
        if k != mpmath.pi / 2 or l != -1 or r != 1:
            raise ValueError("equilibrium_set: implemented for eq. xpot only: wavenumber=pi/2, l=-1, r=1")
        F, f = scene.mpf("F"), scene.mpf("f")
        e = 2 / mpmath.pi * mpmath.asin(min(f / F, 1)) if F > 0 else mpmath.mpf(1)
        return [(mpmath.mpf(-1), -1 + e), (1 - e, mpmath.mpf(1))]


# --- Table 1 (tab:matrices) -----------------------------------------------------------------
def flight_matrix(h):
    """Free flight over ``[t1, t2]``, ``h = t2 - t1``: ``[[1, h], [0, 1]]``."""
    return mpmath.matrix([[1, h], [0, 1]])


def sticking_matrix():
    """A sticking interval: ``[[1, 0], [0, 0]]``."""
    return mpmath.matrix([[1, 0], [0, 0]])


def reflection_matrix(F, omega, t_star, v_before):
    """Impact at ``t*``: ``[[-1, 0], [2 F cos(w t*) / v, -1]]`` with ``v = x'(t*-)``, the velocity BEFORE
    the impact (the printed ``x'(t*)`` is ambiguous; with the velocity after, the sign of the entry
    is wrong -- shown by finite differences in claim ``table1-matrices``)."""
    if v_before == 0:
        raise ValueError("reflection_matrix: v_before must be non-zero (grazing impact: Phi' undefined)")
    return mpmath.matrix([[-1, 0], [2 * F * mpmath.cos(omega * t_star) / v_before, -1]])


def turning_matrix(F, f, omega, t_turn):
    """Turning point at ``t~``: ``[[1, 0], [0, (|A| - f)/(|A| + f)]]``, ``A = F cos(w t~)``."""
    A = abs(F * mpmath.cos(omega * t_turn))
    return mpmath.matrix([[1, 0], [0, (A - f) / (A + f)]])


# --- eqs. hamilsys, map (the lift) --------------------------------------------------------------
def W(q):
    """The tent ``W(q) = q`` on [0,1), ``2 - q`` on [1,2), 2-periodic (eq. after ``hamilsys``)."""
    q = mpmath.mpf(q)
    u = q - 2 * mpmath.floor(q / 2)
    return u if u < 1 else 2 - u


def W_prime(q):
    """``W'(q)`` = +1 on [0,1), -1 on [1,2) (mod 2)."""
    q = mpmath.mpf(q)
    u = q - 2 * mpmath.floor(q / 2)
    return 1 if u < 1 else -1


def lift_map(scene: Scene, q):
    """eq. ``map``: ``x = R W(q) + l``."""
    return (scene.mpf("r") - scene.mpf("l")) * W(q) + scene.mpf("l")


def lift_rhs_printed(scene: Scene, t, q):
    """``q''`` from eq. ``hamilsys`` as printed: ``q'' = f/R - dV/dq``, ``V = (F/R) cos(wt) W(q)``."""
    F, f, w, l, r = _p(scene)
    R = r - l
    return f / R - F / R * mpmath.cos(w * t) * W_prime(q)


def lift_rhs_corrected(scene: Scene, t, q, qdot):
    """``q'' = (F/R) cos(wt) W'(q) - (f/R) sgn(q')`` (erratum of eq. ``hamilsys``).

    With ``x = R W(q) + l``: ``x'' = R W'(q) q''`` off the kinks and ``sgn x' = W'(q) sgn q'``, so
    eq. ``main`` holds iff ``q'' = W'(F cos wt - f W' sgn q')/R``.  The printed equation gives
    ``x'' = -F cos wt + f W'(q)``: the forcing has the wrong sign (the system shifted by half a
    period) and the friction sign fits only ``q' < 0``.  Corrected Hamiltonian form:
    ``V = -(F/R) cos(wt) W(q)`` and ``q'' + dV/dq = -(f/R) sgn q'`` (``= -f/R`` for ``q' > 0``).
    At the kinks ``q`` in Z the map reflects ``x'`` (elastic impact), as eq. ``impact`` requires.
    """
    if qdot == 0:
        raise ValueError("lift_rhs_corrected: qdot must be non-zero (the lift is for non-sticking motion)")
    F, f, w, l, r = _p(scene)
    R = r - l
    return F / R * mpmath.cos(w * t) * W_prime(q) - f / R * mpmath.sign(qdot)
