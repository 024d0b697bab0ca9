"""fast with viscous damping c > 0: the closed-form damped flight (never a numerical ODE
solver), its Jacobian, chatter with damping, against reference (mpmath, dps 30) and
against closed forms written out here.

Expected values: ``reference.stroboscopic_map`` / ``reference.jacobian`` /
``reference.trajectory`` at dps 30 (accurate far beyond float64), or the damped flight
``v = v_p(t) + (v0 - v_p(t0)) exp(-c h)`` integrated by ``mpmath.quad`` at 30 digits.
"""
import math

import mpmath
import numpy as np
import pytest

import fast
import reference
from cross_check.tolerances import tol
from fast import api, loop
from fast import params as fp
from reference.scene import Scene

DAMPED = [
    ("narrow_c03_f01", Scene(F=1, f="0.1", omega=1, l=0, r="0.8", damping="0.3"), 2.0),
    ("narrow_c01_f0", Scene(F=1, f=0, omega=1, l=0, r="0.8", damping="0.1"), 2.0),
    ("twopi_c02_e085", Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1, damping="0.2",
                             restitution="0.85"), 15.0),
    ("narrow_c1e-4", Scene(F=1, f="0.005", omega=1, l=0, r="0.8", damping="0.0001"), 2.0),
    ("wide_c15", Scene(F=1, f="0.3", omega=1, l=0, r=20, damping="1.5"), 2.0),
]
N = 7


def _ref_map(scene, x, v):
    xr, vr = reference.stroboscopic_map(scene, float(x), float(v), dps=30)
    return float(xr), float(vr)


def _ref_jac(scene, x, v):
    return np.array([[float(a) for a in row]
                     for row in reference.jacobian(scene, float(x), float(v), dps=30)])


def test_damped_scenes_are_closed_form():
    """Damping alone never reaches fast.ode: the closed-form loop carries c, Pd, Qd."""
    engine, P = api._engine(DAMPED[0][1])
    assert engine is loop and P[fp.DAMP] == 0.3
    assert math.isclose(P[fp.PD], 0.3 / 1.09, rel_tol=1e-15)
    assert math.isclose(P[fp.QD], 1 / 1.09, rel_tol=1e-15)


@pytest.mark.parametrize("name, scene, vmax", DAMPED, ids=[d[0] for d in DAMPED])
def test_damped_map_and_jacobian_against_reference(name, scene, vmax):
    """One period, N states per scene: map error <= fast_one_period_max scaled by
    max(1, |value|); Phi' within fast_jacobian_vs_reference scaled by max(1, |Phi'|)."""
    rng = np.random.default_rng(606)
    x = rng.uniform(scene.float("l"), scene.float("r"), N)
    v = rng.uniform(-vmax, vmax, N)
    X, V, J, _ = fast.map_and_jacobian(scene, x, v)
    tm, tj = tol("fast_one_period_max"), tol("fast_jacobian_vs_reference")
    for i in range(N):
        xr, vr = _ref_map(scene, x[i], v[i])
        assert abs(X[i] - xr) <= tm.atol * max(1.0, abs(xr)), (i, X[i], xr)
        assert abs(V[i] - vr) <= tm.atol * max(1.0, abs(vr)), (i, V[i], vr)
        Jr = _ref_jac(scene, x[i], v[i])
        assert np.abs(J[i] - Jr).max() <= tj.atol * max(1.0, np.abs(Jr).max()), (i, J[i], Jr)


def _damped_flight_mp(F, f, c, w, x0, v0, t):
    """x(t), v(t) of a flight with s = sgn(v0) from t = 0, at 30 digits: v closed form,
    x by quadrature of v (independent of fast's cancellation-free rewrite)."""
    with mpmath.workdps(30):
        F, f, c, w, x0, v0, t = (mpmath.mpf(a) for a in (F, f, c, w, x0, v0, t))
        s = 1 if v0 > 0 else -1
        den = c * c + w * w

        def vp(tt):
            return F * c / den * mpmath.cos(w * tt) + F * w / den * mpmath.sin(w * tt) - s * f / c

        def vel(tt):
            return vp(tt) + (v0 - vp(0)) * mpmath.exp(-c * tt)

        return float(mpmath.quad(vel, [0, t]) + x0), float(vel(t))


@pytest.mark.parametrize("c, t_end", [(c, t) for c in ("1e-7", "0.01", "0.7", "3")
                                       for t in (1e-5, 0.3, 2.5) if (c, t) != ("3", 2.5)])
def test_free_damped_flight_closed_form(c, t_end):
    """No event (wide gap, fast start): x, v at t_end to a few ulp of their size, even for
    tiny c h and tiny h (no cancellation); the flight matrix over a period for small c."""
    scene = Scene(F=1, f="0.1", omega="1.3", l=-100, r=100, damping=c)
    x0, v0 = 0.0, 10.0
    xe, ve = _damped_flight_mp(1, 0.1, float(c), 1.3, x0, v0, t_end)
    assert fast.events(scene, x0, v0, t_end).n == 0
    X, V = fast.flow(scene, x0, v0, t_end)
    assert abs(X - xe) <= 16 * 2.0 ** -52 * abs(xe), (X, xe)
    assert abs(V - ve) <= 16 * 2.0 ** -52 * max(abs(ve), 1.0), (V, ve)
    cf, T = float(c), 2 * math.pi / 1.3
    if cf <= 0.01:          # v stays near v0 - f t > 0 over the period: one flight
        assert fast.events(scene, x0, v0).n == 0
        J = fast.jacobian(scene, x0, v0)
        assert np.allclose(J, [[1, -math.expm1(-cf * T) / cf], [0, math.exp(-cf * T)]],
                           rtol=1e-14, atol=0)


def test_determinant_is_damping_times_turn_factors():
    """det Phi' = exp(-c T) prod over turns (|A| - f)/(|A| + f) (impacts with e = 1 have det
    1; Table 1), 0 with sticking or wall contact."""
    scene = Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1, damping="0.2")
    rng = np.random.default_rng(7)
    x, v = rng.uniform(-1, 1, 120), rng.uniform(-15, 15, 120)
    log = fast.events(scene, x, v)
    det = np.linalg.det(fast.jacobian(scene, x, v))
    w, f, T = 2 * math.pi, 0.05, 1.0
    for i in range(x.size):
        if set(log.kinds(i)) & {"stick", "contact", "chatter"}:
            assert det[i] == 0.0
            continue
        expect = math.exp(-0.2 * T)
        for e in log[i]:
            if e.kind == "turn":
                a = abs(math.cos(w * e.t))
                expect *= (a - f) / (a + f)
        assert abs(det[i] - expect) <= 1e-12 * expect, (i, det[i], expect)


@pytest.mark.parametrize("scene, x0", [
    (Scene(F=1, f="0.3", omega=1, l=0, r=2, damping="0.2"), 2 - 1e-4),
    (Scene(F=1, f=0, omega=1, l=0, r="0.8", restitution="0.5", damping="0.01"), 0.8 - 1e-5),
])
def test_damped_chatter_against_reference(scene, x0):
    """A chatter run with damping: the summed tail's accumulation time and the end state
    agree with the reference (dps 30); the release follows at the closed-form phase."""
    log = fast.events(scene, x0, 0.0)[0]
    ref = reference.trajectory(scene, x0, 0.0, scene.period, dps=30)
    tc = [e.t for e in log if e.kind == "chatter"]
    tr = [float(e.t) for e in ref if e.kind == "chatter"]
    assert len(tc) == len(tr) == 1
    assert abs(tc[0] - tr[0]) <= tol("fast_chatter_time").atol * scene.period
    X, V = fast.stroboscopic_map(scene, x0, 0.0)
    t = tol("fast_one_period_max")
    assert abs(X - float(ref.x_end)) <= t.atol * max(1.0, abs(float(ref.x_end)))
    assert abs(V - float(ref.v_end)) <= t.atol * max(1.0, abs(float(ref.v_end)))
