"""fast: the modes (reference.integrator's event kinds) and hard cases against closed forms derived here.

Every expected value is computed in the test from the model's closed forms (scipy's
brentq for a transcendental root), not copied from a run.
"""
import math

import numpy as np
import pytest
from scipy.optimize import brentq

import fast
from cross_check.tolerances import tol
from reference.scene import Scene

EPS = 2.0 ** -52


def test_free_flight_closed_form():
    """No event: x(T) = x0 + v0 T + (F/w^2)(1 - cos wT) - f T^2/2, v(T) = v0 - f T."""
    scene = Scene(F=1, f="0.1", omega=1, l=-50, r=50)
    T = 2 * math.pi
    X, V = fast.stroboscopic_map(scene, 0.0, 3.0)
    assert fast.events(scene, 0.0, 3.0).n == 0
    assert abs(X - (3 * T - 0.05 * T * T)) <= 32 * EPS * 3 * T
    assert abs(V - (3 - 0.1 * T)) <= 32 * EPS * 3
    J = fast.jacobian(scene, 0.0, 3.0)
    assert np.allclose(J, [[1, T], [0, 1]], rtol=0, atol=16 * EPS * T)


def test_weak_forcing_stops_and_stays():
    """F <= f: v(t) = v0 + sin t - f t reaches 0 and the particle sticks for good."""
    scene = Scene(F=1, f="1.5", omega=1, l=0, r=2)
    x0, v0 = 1.0, 0.5
    t_star = brentq(lambda t: v0 + math.sin(t) - 1.5 * t, 0.1, 2.0, xtol=1e-16)
    x_star = x0 + v0 * t_star + (1 - math.cos(t_star)) - 0.75 * t_star ** 2
    log = fast.events(scene, x0, v0)
    assert log.kinds(0) == ["stick"]
    assert abs(log[0][0].t - t_star) <= 1e-14
    X, V = fast.stroboscopic_map(scene, x0, v0)
    assert V == 0.0 and abs(X - x_star) <= 1e-14
    J = fast.jacobian(scene, x0, v0)
    assert np.allclose(J, [[1, t_star], [0, 0]], rtol=0, atol=1e-13)
    assert fast.zero_velocity(scene, x0, v0)


def test_interior_rest_slips_at_once_then_sticks():
    """v0 = 0 inside with F > f: stick and slip at t = 0 (s = +1), then v = sin t - f t
    vanishes at t* with |cos t*| <= f: stick until the phase pi - arccos(f)."""
    scene = Scene(F=1, f="0.6", omega=1, l=0, r=20)
    t_star = brentq(lambda t: math.sin(t) - 0.6 * t, 0.5, 2.0, xtol=1e-16)
    assert abs(math.cos(t_star)) <= 0.6
    log = fast.events(scene, 10.0, 0.0)
    kinds = log.kinds(0)
    assert kinds[:4] == ["stick", "slip", "stick", "slip"]
    ev = log[0]
    assert ev[0].t == ev[1].t == 0.0
    assert abs(ev[2].t - t_star) <= 1e-14
    assert abs(ev[3].t - (math.pi - math.acos(0.6))) <= 1e-14


def test_frictionless_never_sticks_or_turns():
    scene = Scene(F=1, f=0, omega=1, l=0, r="0.8")
    rng = np.random.default_rng(11)
    x, v = rng.uniform(0, 0.8, 200), rng.uniform(-2, 2, 200)
    log = fast.events(scene, x, v)
    assert set(np.unique(log.kind[log.kind >= 0])) <= {fast.KINDS.index("impact")}
    det = np.linalg.det(fast.jacobian(scene, x, v))
    assert np.allclose(det, 1.0, rtol=0, atol=1e-9)


def test_pre_impact_state_impacts_at_t0():
    scene = Scene(F=1, f="0.005", omega=1, l=0, r="0.8")
    ev = fast.events(scene, 0.8, 1.25)[0]
    assert ev[0].kind == "impact" and ev[0].t == 0.0
    assert ev[0].v_before == 1.25 and ev[0].v == -1.25


def test_contact_then_release_at_closed_form_phase():
    """At r with v = 0 and A(0) = F > -f: contact, released when cos t < -f/F."""
    scene = Scene(F=1, f="0.3", omega=1, l=0, r=2)
    ev = fast.events(scene, 2.0, 0.0)[0]
    assert [e.kind for e in ev[:2]] == ["contact", "release"]
    assert ev[0].t == 0.0
    assert abs(ev[1].t - (math.pi - math.acos(0.3))) <= 1e-14
    assert np.all(fast.jacobian(scene, 2.0, 0.0) == 0.0)


def test_chatter_accumulates_then_release():
    """Dropped near r while F cos t > f pushes it in: impacts with speeds shrinking by
    rho = sqrt((A - f)/(A + f)) accumulate; then contact until cos t < -f."""
    scene = Scene(F=1, f="0.3", omega=1, l=0, r=2)
    log = fast.events(scene, 2.0 - 1e-4, 0.0)
    ev = log[0]
    kinds = [e.kind for e in ev]
    assert "chatter" in kinds
    i = kinds.index("chatter")
    assert kinds[i + 1] == "release"
    assert set(kinds[2:i]) == {"impact", "turn"}
    assert ev[i].count == kinds[:i].count("impact")
    assert abs(ev[i + 1].t - (math.pi - math.acos(0.3))) <= 1e-14
    # frozen-force estimate from the first impact (A ~ 1 changes by ~1% over the tail)
    first = ev[2]
    u = first.v_before
    rho = math.sqrt(0.7 / 1.3)
    t_est = first.t + u * (1 + rho) ** 2 / (2 * 0.3 * rho)
    assert abs(ev[i].t - t_est) <= 0.05 * (t_est - first.t)
    assert np.all(fast.jacobian(scene, 2.0 - 1e-4, 0.0) == 0.0)
    X, V = fast.stroboscopic_map(scene, 2.0 - 1e-4, 0.0)
    assert 0.0 <= X < 2.0


@pytest.mark.parametrize("scene, vmax", [
    (Scene(F=1, f="0.005", omega=1, l=0, r="0.8"), 2.0),
    (Scene(F=1, f="0.3", omega="2*pi", l=-1, r=1), 3.0),
])
def test_determinant_is_product_of_turn_factors(scene, vmax):
    """det Phi' = prod over turns of (|A| - f)/(|A| + f) (impacts and flights have det 1);
    0 with sticking or wall contact (paper, Section 4).  Checked to claim_unit_det where the
    float64 determinant can resolve it: ``J11 J22 - J12 J21`` of entries up to ``|J|`` loses
    ``~2 eps |J|^2`` to cancellation, below ``claim_unit_det / 2`` only for ``|J| <= jmax``
    (~1e3; a 50x more accurate Jacobian of a state with |J| = 2.7e3 still misses 1e-9 by its
    rounding alone)."""
    rng = np.random.default_rng(12)
    x, v = rng.uniform(scene.float("l"), scene.float("r"), 150), rng.uniform(-vmax, vmax, 150)
    log = fast.events(scene, x, v)
    J = fast.jacobian(scene, x, v)
    det = np.linalg.det(J)
    atol = tol("claim_unit_det").atol
    jmax = math.sqrt(atol / (4 * 2.0 ** -52))
    F, f, w = scene.float("F"), scene.float("f"), scene.float("omega")
    checked = flying = 0
    for i in range(x.size):
        kinds = log.kinds(i)
        if set(kinds) & {"stick", "contact", "chatter"}:
            assert det[i] == 0.0
            continue
        flying += 1
        expect = 1.0
        for e in log[i]:
            if e.kind == "turn":
                a = abs(F * math.cos(w * e.t))
                expect *= (a - f) / (a + f)
        if np.abs(J[i]).max() <= jmax:
            checked += 1
            assert abs(det[i] - expect) <= atol * max(1.0, abs(expect))
    assert checked >= 0.9 * flying


def test_restitution_zero_rests_on_the_wall():
    """e = 0: the impact leaves the particle at rest on the wall; it stays while the force
    holds it (A >= -f at r) and is released at the phase pi - arccos(f/F)."""
    scene = Scene(F=1, f="0.1", omega=1, l=0, r=2, restitution=0)
    ev = fast.events(scene, 1.0, 1.5)[0]
    assert [e.kind for e in ev[:3]] == ["impact", "contact", "release"]
    assert ev[0].v == 0.0 and ev[0].v_before > 0 and ev[1].t == ev[0].t
    assert abs(ev[2].t - (math.pi - math.acos(0.1))) <= 1e-14
    assert fast.zero_velocity(scene, 1.0, 1.5)


def test_restitution_chatter_without_friction():
    """f = 0, e < 1: bounces shrink by rho = e under a force pushing into the wall, so
    they accumulate at t* + 2 u / (A (1 - e)) (frozen force, A ~ F near t = 0)."""
    scene = Scene(F=1, f=0, omega=1, l=0, r=2, restitution="0.5")
    ev = fast.events(scene, 2.0 - 1e-6, 0.0)[0]
    kinds = [e.kind for e in ev]
    i = kinds.index("chatter")
    assert kinds[i + 1] == "release"
    assert abs(ev[i + 1].t - math.pi / 2) <= 1e-14        # released when cos t < 0
    first = ev[0]
    assert first.kind == "impact"
    u = 0.5 * first.v_before
    t_est = first.t + 2 * u / (math.cos(first.t) * (1 - 0.5))
    assert abs(ev[i].t - t_est) <= 1e-3 * (t_est - first.t)
