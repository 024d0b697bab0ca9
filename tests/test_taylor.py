"""reference/taylor.py (its steps in reference/taylor_series.py): the certified Taylor flight for position-dependent forcing.

Checks, each against something independent of the Taylor recurrences:
closed-form flight when ``k = 0`` (reference.flows' base flight), ``mpmath.odefun`` (mpmath's own
Taylor integrator) on eq. ``xpot``, the proved truncation bound against the true tail
(higher order), Liouville ``det J = exp(-c t)``, central differences for the flight
matrix, the energy balance, the jerk and the event bounds of the flight interface, the
rest set ``E``.
"""
import math

import mpmath
import pytest
from hypothesis import given, settings, strategies as st

import reference
from cross_check.tolerances import tol
from reference import taylor
from reference.scene import Scene
from reference.taylor import TaylorFlight
from tests.strategies import flight_starts, position_forced_scenes, xpot_scenes

XPOT = Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2", name="xpot")


def closed_form(scene, t0, x0, v0, s, t):
    """reference.flows' base flight (c = 0, k = None), evaluated at 30 extra digits."""
    with mpmath.extradps(30):
        F, f, w = scene.mpf("F"), scene.mpf("f"), scene.mpf("omega")
        t0, x0, v0, t = (mpmath.mpf(a) for a in (t0, x0, v0, t))
        h = t - t0
        v = v0 + F / w * (mpmath.sin(w * t) - mpmath.sin(w * t0)) - s * f * h
        x = (x0 + v0 * h + F / w ** 2 * (mpmath.cos(w * t0) - mpmath.cos(w * t) - w * h * mpmath.sin(w * t0))
             - s * f * h * h / 2)
    return +x, +v


@pytest.mark.parametrize("t0, x0, v0, s", [(0, "0.3", "1.7", 1), ("0.37", "-0.2", "-0.4", -1),
                                           ("0.9", "0.0", "3.5", 1)])
def test_k0_matches_closed_form(t0, x0, v0, s):
    scene = Scene(F=1, f="0.2", omega="2*pi", l=-5, r=5)          # k = None: cos(kx) = 1
    with mpmath.workdps(50):
        fl = TaylorFlight(scene, mpmath.mpf(t0), mpmath.mpf(x0), mpmath.mpf(v0), s)
        t_end = mpmath.mpf(t0) + mpmath.mpf("1.3")
        assert fl.steps_taken() == 0
        for t in (mpmath.mpf(t0) + mpmath.mpf("0.013"), mpmath.mpf(t0) + mpmath.mpf("0.61"), t_end):
            x, v = fl.state(t)
            xe, ve = closed_form(scene, t0, x0, v0, s, t)
            assert abs(x - xe) <= tol("taylor_closed_form_dps50").atol
            assert abs(v - ve) <= tol("taylor_closed_form_dps50").atol
        assert fl.steps_taken() > 5                                    # several steps were chained


def test_xpot_matches_odefun():
    x0, v0, s, t1 = mpmath.mpf("0.2"), mpmath.mpf("1.5"), 1, mpmath.mpf("0.5")
    with mpmath.workdps(40):
        F, f, w, k = 1, mpmath.mpf("0.1"), 2 * mpmath.pi, mpmath.pi / 2
        sol = mpmath.odefun(lambda t, y: [y[1], F * mpmath.cos(k * y[0]) * mpmath.cos(w * t) - s * f],
                            0, [x0, v0])
        want = sol(t1)
    with mpmath.workdps(30):
        fl = TaylorFlight(XPOT, 0, x0, v0, s)
        x, v = fl.state(t1)
    assert abs(x - want[0]) <= tol("taylor_odefun_dps30").atol
    assert abs(v - want[1]) <= tol("taylor_odefun_dps30").atol
    assert abs(x - (x0 + v0 * t1)) > 1e-3                           # the forcing did act


@pytest.mark.parametrize("v0", ["0", "1.5", "-6"])
def test_truncation_bound_bounds_the_tail(v0):
    """One step of order N at the certified h: the terms N+1 .. N+12 (computed) stay below
    the proved bound ``X q^(N+2)/(1-q)`` (x) and ``V q^(N+1)/(1-q)`` (v)."""
    with mpmath.workdps(30):
        prec = mpmath.mp.prec
        N = taylor.taylor_order(prec)
        prm = taylor._params(XPOT)
        fl = tuple(float(p) for p in prm)
        cert = taylor.step_certificate(fl, abs(float(v0)), N, prec + taylor.EXTRA_BITS)
        h, q = mpmath.mpf(cert["h"]), cert["q"]
        with mpmath.workprec(prec + 60):
            xs, _ = taylor.series(prm, mpmath.mpf("0.3"), mpmath.mpf("0.1"), mpmath.mpf(v0), 1, N + 12)
            tail_x = abs(sum(xs[n] * h ** n for n in range(N + 2, N + 14)))
            tail_v = abs(sum(n * xs[n] * h ** (n - 1) for n in range(N + 2, N + 14)))
        assert tail_x <= cert["X"] * q ** (N + 2) / (1 - q)
        assert tail_v <= cert["V"] * q ** (N + 1) / (1 - q)
        assert cert["V"] * q ** (N + 1) / (1 - q) <= 2.0 ** -(prec + taylor.EXTRA_BITS)
        assert tail_v > 0                                             # a real tail was measured


def test_order_n_and_n_plus_10_agree():
    with mpmath.workdps(30):
        a = TaylorFlight(XPOT, 0, mpmath.mpf("-0.4"), mpmath.mpf("2.5"), 1)
        b = TaylorFlight(XPOT, 0, mpmath.mpf("-0.4"), mpmath.mpf("2.5"), 1, order=a.order + 10)
        xa, va = a.state(1)
        xb, vb = b.state(1)
        assert b.steps_taken() < a.steps_taken()
        budget = a.steps_taken() * 2.0 ** -(a.prec + taylor.EXTRA_BITS) * math.e ** 3
        assert abs(xa - xb) <= budget and abs(va - vb) <= budget


@pytest.mark.parametrize("c", ["0", "0.3"])
def test_liouville(c):
    scene = XPOT.replace(damping=c)
    with mpmath.workdps(30):
        fl = TaylorFlight(scene, mpmath.mpf("0.1"), mpmath.mpf("0.5"), mpmath.mpf("-1.2"), -1)
        for t in ("0.1", "0.35", "1.1"):
            t = mpmath.mpf(t)
            det = mpmath.det(fl.jacobian(t))
            assert abs(det - mpmath.exp(-scene.mpf("damping") * (t - mpmath.mpf("0.1")))) \
                <= tol("taylor_identity_dps30").atol


def test_jacobian_against_central_differences():
    t0, x0, v0, s, t1 = mpmath.mpf("0.2"), mpmath.mpf("0.1"), mpmath.mpf("1.1"), 1, mpmath.mpf("0.9")
    scene = XPOT.replace(damping="0.2")
    with mpmath.workdps(50):
        J = TaylorFlight(scene, t0, x0, v0, s).jacobian(t1)
        d = mpmath.mpf("1e-15")
        for col, (dx, dv) in enumerate(((d, 0), (0, d))):
            plus = TaylorFlight(scene, t0, x0 + dx, v0 + dv, s).state(t1)
            minus = TaylorFlight(scene, t0, x0 - dx, v0 - dv, s).state(t1)
            for row in range(2):
                fd = (plus[row] - minus[row]) / (2 * d)
                assert abs(J[row, col] - fd) <= tol("taylor_fd_jacobian_dps50").atol
        assert abs(J[0, 1] - (t1 - t0)) > 1e-3                   # not the free-flight matrix


def test_energy_balance():
    """``v^2/2 |_t0^t1 = int v A dt - s f (x1 - x0) - c int v^2 dt`` on the dense output."""
    scene = XPOT.replace(damping="0.2")
    t0, t1, s = mpmath.mpf(0), mpmath.mpf("0.6"), 1
    with mpmath.workdps(30):
        fl = TaylorFlight(scene, t0, mpmath.mpf("-0.3"), mpmath.mpf("1.8"), s)
        F, f, c, k, w = taylor._params(scene)
        x1, v1 = fl.state(t1)

        def force_power(t):
            x, v = fl.state(t)
            return v * F * mpmath.cos(k * x) * mpmath.cos(w * t)

        work = mpmath.quad(force_power, mpmath.linspace(t0, t1, 7))
        dissip = mpmath.quad(lambda t: fl.state(t)[1] ** 2, mpmath.linspace(t0, t1, 7))
        lhs = (v1 ** 2 - mpmath.mpf("1.8") ** 2) / 2
        rhs = work - s * f * (x1 - mpmath.mpf("-0.3")) - c * dissip
        assert abs(lhs - rhs) <= tol("taylor_identity_dps30").atol
        assert abs(work) > 1e-3                                       # the forcing did work


def _deriv(fn, t, h=mpmath.mpf("1e-12")):
    """Fourth-order central difference (error ~h^4 |fn^(5)|/30 + eps |fn| / h)."""
    return (8 * (fn(t + h) - fn(t - h)) - (fn(t + 2 * h) - fn(t - 2 * h))) / (12 * h)


def test_flight_interface_bounds_and_jerk():
    """At 60 digits the difference quotient is good to ~1e-40: the jerk is a' and the event
    bounds bound |a|, |a'|, |a''| over the window."""
    scene = XPOT.replace(damping="0.1")
    with mpmath.workdps(60):
        fl = TaylorFlight(scene, 0, mpmath.mpf("0.7"), mpmath.mpf("-2"), -1)
        ta, tb = mpmath.mpf("0.1"), mpmath.mpf("0.6")
        mx, mv, ma = fl.bound_x2(ta, tb), fl.bound_v2(ta, tb), fl.bound_a2(ta, tb)
        for t in mpmath.linspace(ta, tb, 11):
            x, v, a = fl.evaluate(t)
            jerk = fl.jerk(t, x, v, a)
            num = _deriv(lambda u: fl.evaluate(u)[2], t)
            assert abs(jerk - num) <= tol("taylor_identity_dps30").atol
            a2 = _deriv(lambda u: fl.jerk(u, *fl.evaluate(u)), t)
            assert abs(a) <= mx and abs(jerk) <= mv and abs(a2) <= ma
        assert 0 < fl.max_window < 2 * mpmath.pi / scene.mpf("omega") and fl.noise_v > 0


def test_rest_set_of_xpot():
    """``|F cos(pi x/2)| <= f`` exactly on ``[-1, -eta'] U [eta', 1]``, ``eta' = (2/pi) arccos(f/F)``
    (wall layers of width ``(2/pi) arcsin(f/F)``); checked against ``|A(x, t)| <= f`` on a grid."""
    with mpmath.workdps(30):
        E = taylor.equilibrium_intervals(XPOT)
        eta = 2 / mpmath.pi * mpmath.acos(mpmath.mpf("0.1"))
        assert len(E) == 2
        assert E[0][0] == -1 and abs(E[0][1] + eta) < 1e-28
        assert abs(E[1][0] - eta) < 1e-28 and E[1][1] == 1
        for x in mpmath.linspace(-1, 1, 41):
            inside = any(lo <= x <= hi for lo, hi in E)
            worst = max(abs(mpmath.cos(mpmath.pi * x / 2) * mpmath.cos(2 * mpmath.pi * t))
                        for t in mpmath.linspace(0, 1, 101))
            assert inside == (worst <= mpmath.mpf("0.1"))
    assert taylor.equilibrium_intervals(XPOT.replace(f=2)) == [(-1, 1)]
    assert taylor.equilibrium_intervals(XPOT.replace(wavenumber=None)) == []


@pytest.mark.parametrize("wall", [-1, 1])
def test_a_frictionless_rest_where_the_force_vanishes_stays(wall):
    """f = 0 and cos(pi x/2) = 0 at both walls: a particle at rest on a wall feels no force at
    any time, so it stays (an equilibrium of x'' = F cos(k x) cos(w t)).  The force's rounding
    noise (~1e-40 at 30 digits, of either sign) once made the reference leave the wall and land
    again at the same instant until its loop bound raised ("no progress in time")."""
    sc = XPOT.replace(f=0)
    log = reference.trajectory(sc, wall, 0, 3, dps=30)
    assert (log.x_end, log.v_end) == (wall, 0)
    assert [e.kind for e in log] == ["contact"]
    x, v = reference.stroboscopic_map(sc, wall, 0, periods=3, dps=30)
    assert (x, v) == (wall, 0)
    # an interior start where the force does not vanish still moves
    assert reference.stroboscopic_map(sc, wall * mpmath.mpf("0.5"), 0, dps=30)[1] != 0


def test_bad_input():
    with pytest.raises(ValueError, match="s must be"):
        TaylorFlight(XPOT, 0, 0, 1, 2)
    with pytest.raises(ValueError, match="s = 0"):
        TaylorFlight(XPOT, 0, 0, 1, 0)
    with pytest.raises(ValueError, match="x0 must be finite"):
        TaylorFlight(XPOT, 0, mpmath.inf, 1, 1)
    fl = TaylorFlight(XPOT, 1, 0, 1, 1)
    with pytest.raises(ValueError, match="t must be"):
        fl.state(0)
    with pytest.raises(ValueError, match="tb >= ta"):
        fl.bound_x2(2, 1)


def test_model_selects_the_taylor_flight():
    from reference import model as model_mod
    with mpmath.workdps(20):
        model = model_mod.Model(XPOT)
        fl = model.flight(mpmath.mpf(0), mpmath.mpf("0.5"), mpmath.mpf(1), 1)
        assert isinstance(fl, TaylorFlight)
        x, v, a = fl.evaluate(mpmath.mpf("0.25"))
        assert fl.noise_x > 0 and abs(a - fl.acceleration(mpmath.mpf("0.25"))) == 0


@given(data=st.data())
def test_semigroup_and_liouville_property(data):
    """Restarting a flight at ``t1`` from its own state gives the same state at ``t2``;
    ``det J = exp(-c (t - t0))``."""
    scene = data.draw(xpot_scenes())
    t0, x0, v0, s = data.draw(flight_starts(scene))
    with mpmath.workdps(20):
        t1, t2 = mpmath.mpf(t0) + mpmath.mpf("0.3"), mpmath.mpf(t0) + mpmath.mpf("0.7")
        fl = TaylorFlight(scene, t0, x0, v0, s)
        x1, v1 = fl.state(t1)
        again = TaylorFlight(scene, t1, x1, v1, s).state(t2)
        direct = fl.state(t2)
        scale = 1 + abs(direct[0]) + abs(direct[1])
        assert abs(again[0] - direct[0]) <= 1e-15 * scale
        assert abs(again[1] - direct[1]) <= 1e-15 * scale
        det = mpmath.det(fl.jacobian(t2))
        assert abs(det - mpmath.exp(-scene.mpf("damping") * (t2 - t0))) <= 1e-15 * abs(det)


def test_table1_with_variational_flight_matrices_is_the_map_derivative():
    """Position forcing: Table 1's impact matrix ``[[-1, 0], [2 A(x*, t*)/v-, -1]]`` between
    variational flight matrices (``taylor.flight_matrix``) is the derivative of the reference
    map (central differences of ``reference.stroboscopic_map``, step 1e-15 at 50 digits).
    This is the product ``reference.jacobian.product_of_table1`` needs for such scenes."""
    import importlib

    from reference.model import Model
    table1 = importlib.import_module("reference.jacobian")   # the package re-exports a function

    scene = XPOT.replace(f="0.05", wavenumber="1.3")     # A(r, t) != 0: the impact term matters
    x0, v0 = mpmath.mpf("0.2"), mpmath.mpf("1.5")
    with mpmath.workdps(50):
        model = Model(scene)
        T = 2 * mpmath.pi / model.w
        log = reference.trajectory(scene, x0, v0, T, dps=50)
        assert [e.kind for e in log] == ["impact"]
        (ev,) = log
        J = mpmath.matrix(taylor.flight_matrix(model, mpmath.mpf(0), x0, v0, ev.t))
        J = mpmath.matrix(table1.impact_matrix(model, model.force(ev.x, ev.t), ev.v_before)) * J
        J = mpmath.matrix(taylor.flight_matrix(model, ev.t, ev.x, ev.v, T)) * J
        d = mpmath.mpf("1e-15")
        for col, (dx, dv) in enumerate(((d, 0), (0, d))):
            plus = reference.stroboscopic_map(scene, x0 + dx, v0 + dv, dps=50)
            minus = reference.stroboscopic_map(scene, x0 - dx, v0 - dv, dps=50)
            for row in range(2):
                fd = (plus[row] - minus[row]) / (2 * d)
                assert abs(J[row, col] - fd) <= tol("taylor_fd_jacobian_dps50").atol
        assert abs(model.force(ev.x, ev.t)) > 1e-2


@settings(max_examples=8, deadline=None)
@given(data=st.data())
def test_the_event_bounds_hold_over_long_windows_of_damped_flights(data):
    """``bound_x2`` and ``bound_v2`` bound ``|a|`` and ``|a'|`` over a window of two periods from
    a random point of a random damped position-forced flight (issue 33: their ``vmax`` now uses
    that damping only slows, ``|v| <= max(|v(ta)|, (F+f)/c)``; a bound without the growth of
    ``|v|`` -- ``vmax = |v(ta)|`` -- was seen to fail here)."""
    scene = data.draw(position_forced_scenes()).replace(damping=data.draw(st.sampled_from(("0.05", "0.3", "1.5"))))
    t0, x0, v0, s = data.draw(flight_starts(scene))
    with mpmath.workdps(20):
        fl = TaylorFlight(scene, t0, x0, v0, s)
        ta = fl.t_start + data.draw(st.floats(0, 0.5)) * scene.period
        tb = ta + 2 * scene.period
        mx, mv = fl.bound_x2(ta, tb), fl.bound_v2(ta, tb)
        vmax = fl._bounds(ta, tb)[0]               # the speed bound they rest on (docstring)
        for t in mpmath.linspace(ta, tb, 25):
            x, v, a = fl.evaluate(t)
            assert abs(v) <= vmax, (t, v, vmax)
            assert abs(a) <= mx and abs(fl.jerk(t, x, v, a)) <= mv, (t, a, mx)


def test_a_ten_period_map_of_a_damped_scene_settles():
    """An unseen damped scene (the verify benchmark's R1): the ten-period map at 40 digits used
    to stop with 'event search did not settle in 20000 safe steps' (the bound's ``e^{c 10 T}``)."""
    from cross_check.agreement import compare
    from cross_check.scenes import Case

    scene = Scene(F="1.69", f="0.271", omega="0.91", l="-1.72", r="-0.26", wavenumber="0.199",
                  damping="0.163", name="R1")
    case = Case("R1 sample", "-0.2952775489546542", "1.2794028578969763", "float64", "verify benchmark R1")
    x, v = compare.ref_map(scene, case, 10, 40)
    assert -1.72 <= float(x) <= -0.26 and mpmath.isfinite(v)


@given(st.lists(st.integers(-(1 << 90), 1 << 90), min_size=1, max_size=120),
       st.integers(0, 1 << 80))
def test_the_fixed_point_horner_is_within_n_units_of_the_exact_sum(coeffs, sig):
    """``taylor._fixed_horner``: ``sum Z_n sigma^n`` in ``P``-bit fixed point (``sigma = sig 2^-P``
    in ``[0, 1]``) is within ``N`` units of ``2^-P`` of the exact rational sum (each of the ``N``
    Horner steps rounds down by less than one unit), and exact at ``sigma = 1``."""
    from fractions import Fraction

    P = 80
    exact = sum(Fraction(z) * Fraction(sig, 1 << P) ** n for n, z in enumerate(coeffs))
    got = taylor._fixed_horner(coeffs, sig, P)
    assert abs(got - exact) <= len(coeffs)
    assert taylor._fixed_horner(coeffs, 1 << P, P) == sum(coeffs)
