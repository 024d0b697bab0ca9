"""The paper's closed forms (reference/paper.py), checked independently of the printed text.

Every check evaluates a formula at 50 digits and tests what it must satisfy: the ODE (residual
by ``mpmath.diff`` at raised precision), the wall hits, the reflections, periodicity and the
half-period symmetry.  The printed forms are tested to FAIL where the paper errs, with the
numbers quoted in ``reference/paper.py``.  No integrator is used here (Table 1 is checked
against a self-contained one-event closed-form flow).
"""
import mpmath
import pytest
from hypothesis import given

from cross_check.tolerances import tol
from reference import paper as P
from reference.scene import Scene
from tests.strategies import symmetric_scenes

TOL = tol("paper_identity_dps50").atol
WIDE = Scene(F=1, f="0.3", omega=1, l=0, r=20)           # fig:many:wide/f=0.3 (r + l = 20)
TWO_PI = Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1)  # fig:many:2pi/f=0.05 (r + l = 0)


def _residuals(scene, x, v, t_l, h):
    """Max |residual| of: ODE on both flights, wall hits, reflections, period, symmetry."""
    F, f, w, l, r = (scene.mpf(k) for k in ("F", "f", "omega", "l", "r"))
    out = {}
    samples = [t_l + h * mpmath.mpf(k) / 7 for k in range(1, 14) if k != 7]
    out["ode"] = max(abs(mpmath.diff(x, t, 2) - (F * mpmath.cos(w * t) - f * mpmath.sign(v(t))))
                     for t in samples)
    out["dx=v"] = max(abs(mpmath.diff(x, t) - v(t)) for t in samples)
    out["wall_l"] = abs(x(t_l) - l)
    out["wall_r"] = abs(x(t_l + h) - r)
    eps = mpmath.mpf(10) ** -45
    out["reflect_r"] = abs(v(t_l + h - eps) + v(t_l + h + eps))
    T = 2 * mpmath.pi / w
    m = int(mpmath.nint(2 * h / T))
    out["period"] = max(abs(x(t + m * T) - x(t)) for t in samples)
    out["symmetry"] = max(abs(x(t + h) + x(t) - r - l) for t in samples)
    return out


@given(symmetric_scenes())
def test_corrected_symmetric_solutions_solve_the_problem(scene):
    with mpmath.workdps(50):
        for branch in (1, 2):
            sol = P.symmetric_solution(scene, branch)
            if sol.min_flight_velocity()[0] <= 0:
                continue    # not a genuine solution (covered by the nonstick tests)
            res = _residuals(scene, sol.x, sol.v, sol.psi / scene.mpf("omega"), sol.half_period)
            assert max(res.values()) < TOL, res


def test_period3_symmetric_solution_solves_the_problem():
    scene = Scene(F=1, f="0.2", omega="2*pi", l=-1, r=1)
    with mpmath.workdps(50):
        for branch in (1, 2):
            sol = P.symmetric_solution(scene, branch, m=3)
            res = _residuals(scene, sol.x, sol.v, sol.psi / scene.mpf("omega"), sol.half_period)
            assert max(res.values()) < TOL, res
    assert P.symmetric_solution(scene.replace(f="0.3"), 1, m=3) is None   # 0.3 > 2/(3 pi)


def _printed_pieces(scene, branch):
    """Printed x_{1,2} on [0, pi/w): x at 0, x(tau-) and x(tau+), v(tau-) + v(tau+), symmetry."""
    w = scene.mpf("omega")
    k = P.printed_nonstick_constants(scene, branch)
    eps = mpmath.mpf(10) ** -45
    tt = k["tau"] / w
    x = lambda t, d=0: P.printed_nonstick(scene, branch, t, deriv=d)
    return {"x_tau-": x(tt - eps), "x_tau+": x(tt + eps) if tt + eps < mpmath.pi / w else None,
            "reflect": (x(tt - eps, 1) + x(tt + eps, 1)) if tt + eps < mpmath.pi / w else None,
            "x0": x(0), "x_end": x(mpmath.pi / w - eps)}


def test_printed_x2_is_right_when_l_equals_minus_r():
    with mpmath.workdps(50):
        sol = P.symmetric_solution(TWO_PI, 2)
        w = TWO_PI.mpf("omega")
        for t in [mpmath.mpf(k) / 10 * mpmath.pi / w for k in range(10)]:
            assert abs(P.printed_nonstick(TWO_PI, 2, t) - sol.x(t)) < TOL
            assert abs(P.printed_nonstick(TWO_PI, 2, t, deriv=1) - sol.v(t)) < TOL


def test_printed_second_piece_misses_r_plus_l():
    """Erratum 1: after the impact at tau the printed x_2 is at -l = 0, not at r = 20."""
    with mpmath.workdps(50):
        p = _printed_pieces(WIDE, 2)
        assert abs(p["x_tau-"] - 20) < 1e-30           # the first piece does reach r
        assert abs(p["x_tau+"] - 0) < 1e-30            # printed: -l; should be r = 20
        sol = P.symmetric_solution(WIDE, 2)
        t = mpmath.mpf(3)                              # tau_2 = 2.6509 < 3 < pi
        assert abs(P.printed_nonstick(WIDE, 2, t) + WIDE.mpf("r") + WIDE.mpf("l") - sol.x(t)) < TOL


def test_printed_psi1_is_off_by_one_period():
    """Erratum 2: printed x_1(0) = -30.736 (outside the gap [0, 20]); true 16.678."""
    with mpmath.workdps(50):
        sol = P.symmetric_solution(WIDE, 1)
        printed = P.printed_nonstick(WIDE, 1, 0)
        assert mpmath.nstr(printed, 5) == "-30.736" and mpmath.nstr(sol.x(0), 5) == "16.678"
        # the shift psi_1 -> psi_1 - 2 pi repairs it (tau_1 unchanged)
        k = P.printed_nonstick_constants(WIDE, 1)
        assert abs(k["psi"] - 2 * mpmath.pi - sol.psi) < TOL and abs(k["tau"] - sol.tau) < TOL
        assert abs(k["C"] - sol.C) < TOL and abs(k["D"] - sol.D) < TOL
        # even with l = -r the printed x_1 is wrong (off by C_1 T plus friction terms)
        assert abs(P.printed_nonstick(TWO_PI, 1, 0) - P.symmetric_solution(TWO_PI, 1).x(0)) > 1


def _dense_min_velocity(sol, n=400):
    """Independent minimum of x' over the up-flight: dense sampling, then a local refinement."""
    w = sol.scene.mpf("omega")
    t0, h = sol.psi / w, sol.half_period
    ts = [t0 + h * k / n for k in range(n)]    # v(t0 + h-) = v(t0): the right end is the left one
    k = min(range(n), key=lambda i: sol.v(ts[i]))
    if 0 < k < n - 1:
        tm = mpmath.findroot(lambda t: mpmath.diff(sol.v, t), ts[k])
        return min(sol.v(tm), sol.v(ts[k]))
    return sol.v(ts[k])


@given(symmetric_scenes())
def test_nonstick_condition_is_the_branch1_minimum_velocity(scene):
    with mpmath.workdps(50):
        w = scene.mpf("omega")
        lhs = P.nonstick_condition_printed(scene)
        for branch in (1, 2):
            sol = P.symmetric_solution(scene, branch)
            vmin = sol.min_flight_velocity()[0]
            assert abs(vmin - _dense_min_velocity(sol)) < 1e-30
            if branch == 1 and scene.has("friction"):
                assert abs(mpmath.pi * w * vmin - lhs) < TOL


def test_nonstick_condition_is_not_sufficient_for_x2():
    scene = Scene(F=1, f=0, omega=1, l=0, r="1.5")
    with mpmath.workdps(50):
        assert P.nonstick_condition_printed(scene) > 0              # printed: non-sticking
        assert P.nonstick_margin(scene, 2) < 0                      # but x_2 is not
        sol = P.symmetric_solution(scene, 2)
        assert sol.v(sol.psi) < 0                                   # starts at l moving left


def test_fold_and_reduced_condition():
    with mpmath.workdps(50):
        f_fold = P.fold_friction(WIDE)
        at = WIDE.replace(f=f_fold)
        s1, s2 = P.symmetric_solution(at, 1), P.symmetric_solution(at, 2)
        fold_tol = tol("paper_fold_dps50").atol
        assert abs(s1.psi - s2.psi) < fold_tol and abs(s1.C - s2.C) < fold_tol and abs(s1.D - s2.D) < fold_tol
        R, F, w = 20, at.mpf("F"), at.mpf("omega")
        # eq. nonstick:cond at the fold == F (w^2 R/F - bound)
        assert abs(P.nonstick_condition_printed(at) - F * (w ** 2 * R / F - P.fold_reduced_bound())) < fold_tol
        assert mpmath.nstr(P.fold_reduced_bound(), 12) == "0.661348175129"
        assert P.symmetric_solution(WIDE.replace(f=f_fold * (1 + mpmath.mpf(10) ** -30)), 1) is None


def test_resonance_gap_gives_third_roots_of_unity():
    base = Scene(F="(2*pi)**2", f="24.65", omega="2*pi", l=0, r="0.8932")
    with mpmath.workdps(50):
        gaps = P.resonance_gaps(base)
        assert mpmath.nstr(gaps[0], 10) == "0.893299742"       # the paper's R* ~ 0.8932
        for R in gaps:
            sol = P.symmetric_solution(base.replace(r=R), 1)
            lam = sol.multipliers()
            target = mpmath.exp(2j * mpmath.pi / 3)
            assert min(abs(lam[0] - target), abs(lam[0] - target.conjugate())) < 1e-30
            assert sol.min_flight_velocity()[0] > 0


def test_monodromy_closed_form_matches_table1_product():
    with mpmath.workdps(50):
        for scene in (WIDE, TWO_PI):
            for branch in (1, 2):
                sol = P.symmetric_solution(scene, branch)
                F, w = scene.mpf("F"), scene.mpf("omega")
                h = sol.half_period
                t_r = sol.tau / w
                Ir = P.reflection_matrix(F, w, t_r, sol.v_impact)
                Il = P.reflection_matrix(F, w, t_r + h, -sol.v_impact)
                M = Il * P.flight_matrix(h) * Ir * P.flight_matrix(h)
                assert abs(M[0, 0] + M[1, 1] - sol.trace()) < TOL
                assert abs(mpmath.det(M) - 1) < TOL


def _flow(scene, t0, x0, v0, s, t):
    """Closed-form flight with velocity sign s (reference.flows), independent of the integrators."""
    F, f, w = scene.mpf("F"), scene.mpf("f"), scene.mpf("omega")
    h = t - t0
    v = v0 + F / w * (mpmath.sin(w * t) - mpmath.sin(w * t0)) - s * f * h
    x = x0 + v0 * h + F / w ** 2 * (mpmath.cos(w * t0) - mpmath.cos(w * t) - w * h * mpmath.sin(w * t0)) - s * f * h ** 2 / 2
    return x, v


def _one_event_map(scene, t0, t1, kind, guess):
    """(x0, v0) at t0 -> state at t1 across one impact at r (kind='impact') or one turn."""
    r = scene.mpf("r")

    def phi(x0, v0):
        s = 1 if v0 > 0 else -1
        if kind == "impact":
            ts = mpmath.findroot(lambda t: _flow(scene, t0, x0, v0, s, t)[0] - r, guess)
            xs, vs = _flow(scene, t0, x0, v0, s, ts)
            return _flow(scene, ts, xs, -vs, -s, t1)
        ts = mpmath.findroot(lambda t: _flow(scene, t0, x0, v0, s, t)[1], guess)
        xs, _ = _flow(scene, t0, x0, v0, s, ts)
        return _flow(scene, ts, xs, mpmath.mpf(0), -s, t1)
    return phi


def _fd_jacobian(phi, x0, v0, step):
    cols = []
    for dx, dv in ((step, 0), (0, step)):
        p, m = phi(x0 + dx, v0 + dv), phi(x0 - dx, v0 - dv)
        cols.append([(p[i] - m[i]) / (2 * step) for i in range(2)])
    return mpmath.matrix([[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]])


def test_table1_reflection_uses_velocity_before_impact():
    scene = WIDE
    with mpmath.workdps(80):
        sol = P.symmetric_solution(scene, 2)
        t_r = sol.tau / scene.mpf("omega")
        t0, t1 = t_r - mpmath.mpf("0.3"), t_r + mpmath.mpf("0.4")
        x0, v0 = sol.x(t0), sol.v(t0)
        J = _fd_jacobian(_one_event_map(scene, t0, t1, "impact", t_r), x0, v0, mpmath.mpf(10) ** -25)
        F, w = scene.mpf("F"), scene.mpf("omega")
        before = P.flight_matrix(t1 - t_r) * P.reflection_matrix(F, w, t_r, sol.v_impact) * P.flight_matrix(t_r - t0)
        after = P.flight_matrix(t1 - t_r) * P.reflection_matrix(F, w, t_r, -sol.v_impact) * P.flight_matrix(t_r - t0)
        assert mpmath.mnorm(J - before, 1) < tol("paper_fd_jacobian_dps80").atol
        assert mpmath.mnorm(J - after, 1) > 0.1


def test_table1_turning_point_matrix():
    scene = Scene(F=1, f="0.1", omega=1, l=-100, r=100)
    with mpmath.workdps(80):
        t0 = mpmath.pi
        x0, v0 = mpmath.mpf(0), mpmath.mpf("0.1")
        phi = _one_event_map(scene, t0, t0 + 1, "turn", t0 + mpmath.mpf("0.09"))
        tt = mpmath.findroot(lambda t: _flow(scene, t0, x0, v0, 1, t)[1], t0 + mpmath.mpf("0.09"))
        J = _fd_jacobian(phi, x0, v0, mpmath.mpf(10) ** -25)
        expect = P.flight_matrix(t0 + 1 - tt) * P.turning_matrix(1, scene.mpf("f"), 1, tt) * P.flight_matrix(tt - t0)
        assert mpmath.mnorm(J - expect, 1) < tol("paper_fd_jacobian_dps80").atol


def test_no_impact_condition_erratum():
    printed_ok = Scene(F=1, f=0, omega=1, l=0, r="1.5")     # R = 1.5 > F/w^2 = 1
    assert P.no_impact_condition_printed(printed_ok)
    assert P.no_impact_offsets(printed_ok) is None          # excursion 2F/w^2 = 2 > 1.5
    with mpmath.workdps(50):
        wide = Scene(F=1, f=0, omega=1, l=0, r=4)
        lo, hi = P.no_impact_offsets(wide)
        assert (lo, hi) == (1, 3)
        for C in (lo, (lo + hi) / 2, hi):
            xs = [P.no_impact_solution(wide, C, mpmath.mpf(k) / 50 * 2 * mpmath.pi)[0] for k in range(51)]
            assert min(xs) >= 0 and max(xs) <= 4 and (C != lo or min(xs) == 0)
    with pytest.raises(ValueError, match="f = 0"):
        P.no_impact_offsets(WIDE)


def test_xpot_equilibrium_set_by_direct_evaluation():
    """At rest at x: stays iff max_t |F cos(pi x/2) cos wt| <= f; compare with E and the printed eta."""
    scene = Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2")
    with mpmath.workdps(50):
        (a0, a1), (b0, b1) = P.equilibrium_set(scene)
        eta = P.eta_printed(1, "0.1")
        assert abs(-a1 - eta) < TOL and mpmath.nstr(eta, 6) == "0.936231"   # (2/pi) acos(0.1)
        wrong = 0
        for k in range(-200, 201):
            x = mpmath.mpf(k) / 200
            stays = abs(mpmath.cos(mpmath.pi * x / 2)) <= mpmath.mpf("0.1")   # max over t of |cos wt| = 1
            assert stays == (x <= a1 or x >= b0)
            printed = x <= -1 + eta or x >= 1 - eta
            wrong += stays != printed
        # the printed set wrongly holds the grid points with 0.0638 < |x| < 0.9362 (|k| = 13..187)
        assert wrong == 2 * 175


def test_lift_printed_has_wrong_forcing_sign():
    """eq. hamilsys: unfold the (validated) non-sticking x_1 to q and compare q'' with both forms."""
    scene = WIDE
    with mpmath.workdps(50):
        sol = P.symmetric_solution(scene, 1)
        R, l, w = 20, scene.mpf("l"), scene.mpf("omega")
        t_l, h = sol.psi / w, sol.half_period
        q = lambda t: (sol.x(t) - l) / R if t < t_l + h else 2 - (sol.x(t) - l) / R
        for t in (t_l + h / 3, t_l + 4 * h / 3):
            qdd, qd = mpmath.diff(q, t, 2), mpmath.diff(q, t)
            assert qd > 0 and abs(P.lift_map(scene, q(t)) - sol.x(t)) < TOL
            assert abs(qdd - P.lift_rhs_corrected(scene, t, q(t), qd)) < TOL
            assert abs(qdd - P.lift_rhs_printed(scene, t, q(t))) > 0.01


def test_bad_input_raises():
    with pytest.raises(ValueError, match="branch"):
        P.symmetric_solution(WIDE, 3)
    with pytest.raises(ValueError, match="m must"):
        P.symmetric_solution(WIDE, 1, m=2)
    with pytest.raises(ValueError, match="restitution"):
        P.symmetric_solution(WIDE.replace(restitution="0.9"), 1)
    with pytest.raises(ValueError, match="0 <= w t < pi"):
        P.printed_nonstick(WIDE, 1, 4)
    with pytest.raises(ValueError, match="grazing"):
        P.reflection_matrix(1, 1, 0, 0)
    with pytest.raises(ValueError, match="dps"):
        P.symmetric_solution(WIDE, 1, dps=3)
