"""Issue 6 effects in the reference: viscous damping (closed-form flight) and restitution.

The damped flight is checked against mpmath's Taylor ODE solver (``mpmath.odefun``, an
independent method), the Jacobian against finite differences (damping cancels in the
reflection matrix, the flight matrix becomes ``[[1, (1 - e^{-ch})/c], [0, e^{-ch}]]``), and
the half-period symmetry (which damping and restitution preserve).
"""
import mpmath
import pytest
from mpmath import mpf

import reference
from reference import Scene
from reference.model import Model
from tests.test_reference_jacobian import assert_close, finite_differences

DAMPED = Scene(F=1, f="0.1", omega=1, l=0, r="0.8", damping="0.3")
DAMPED_E = Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1, damping="0.2", restitution="0.85")
DAMPED_F0 = Scene(F=1, f=0, omega=1, l=0, r="0.8", damping="0.1")


@pytest.mark.parametrize("s,h", [(1, "1e-15"), (1, "0.3"), (-1, "2.5"), (0, "1.7")])
def test_damped_flight_against_odefun(s, h):
    scene = DAMPED if s else DAMPED_F0
    with mpmath.workdps(40):
        F, f, c = 1, mpf("0.1") if s else 0, mpf("0.3") if s else mpf("0.1")
        t0, x0, v0 = mpf("0.7"), mpf("0.1"), mpf("0.8") * (s or 1)
        flight = Model(scene).flight(t0, x0, v0, s)
        x, v, a = flight.evaluate(t0 + mpf(h))
        ode = mpmath.odefun(lambda t, y: [y[1], F * mpmath.cos(t) - s * f - c * y[1]], t0, [x0, v0])
        xe, ve = ode(t0 + mpf(h))
        assert abs(x - xe) < mpf(10) ** -35 and abs(v - ve) < mpf(10) ** -35
        assert abs(a - (F * mpmath.cos(t0 + mpf(h)) - s * f - c * ve)) < mpf(10) ** -35
        if h == "1e-15":                       # short flights keep their relative digits
            assert abs((x - x0 - v0 * mpf(h)) / (a * mpf(h) ** 2 / 2) - 1) < mpf("1e-10")


@pytest.mark.parametrize("scene,x,v", [(DAMPED, "0.3", "0.5"), (DAMPED_E, "0.5", "1.5"),
                                       (DAMPED_F0, "0.3", "0.5")])
def test_damped_jacobian_against_finite_differences(scene, x, v):
    log = reference.trajectory(scene, x, v, 2 * mpmath.pi / scene.mpf("omega"), dps=30)
    assert "impact" in {e.kind for e in log} and "stick" not in {e.kind for e in log}
    J = reference.jacobian(scene, x, v, dps=60)
    assert_close(J, finite_differences(scene, x, v), "ref_fd_jacobian")


@pytest.mark.parametrize("scene,x,v", [(DAMPED, "0.3", "0.5"), (DAMPED_E, "0.5", "1.5")])
def test_damped_half_period_symmetry(scene, x, v):
    with mpmath.workdps(70):
        T, l, r = 2 * mpmath.pi / scene.mpf("omega"), scene.mpf("l"), scene.mpf("r")
        x1, v1 = reference.stroboscopic_map(scene, x, v, dps=40)
        log = reference.trajectory(scene, l + r - mpf(x), -mpf(v), 3 * T / 2, t0=T / 2, dps=40)
        assert abs(log.x_end - (l + r - x1)) < mpf(10) ** -32
        assert abs(log.v_end + v1) < mpf(10) ** -32


def test_damped_self_agreement():
    a = reference.stroboscopic_map(DAMPED_E, "0.5", "1.5", periods=3, dps=50)
    b = reference.stroboscopic_map(DAMPED_E, "0.5", "1.5", periods=3, dps=70)
    with mpmath.workdps(80):
        assert abs(a[0] - b[0]) < mpf(10) ** -30 and abs(a[1] - b[1]) < mpf(10) ** -30
