"""Claims of issue 6 about the determinant of ``Phi'`` (reference, and fast where it runs
the effect).

Dissipation by restitution and damping (on orbits that never reach zero velocity)
----------------------------------------------------------------------------------
``Phi'`` is the time-ordered product of Table 1 matrices.  Their determinants:

* flight over ``h``: ``det [[1, (1 - e^{-ch})/c], [0, e^{-ch}]] = e^{-ch}`` (Liouville: the
  divergence of ``(v, A(t) - s f - c v)`` is ``-c``);
* impact: ``det [[-e, 0], [L, -e]] = e^2`` whatever the lower-left entry ``L``;
* turn: ``(|A| - f)/(|A| + f)``; stick and wall contact: 0 -- none of them occurs on an
  orbit that never reaches ``v = 0`` (frictionless scenes log no turn: there the flow is
  smooth through ``v = 0``, factor 1).

The flights cover ``[0, T]``, so on such an orbit with ``n`` impacts
``det Phi' = e^(2 n) exp(-c T)`` exactly: ``|det Phi'| < 1`` as soon as ``e < 1`` or ``c > 0``
(with ``e = 1``, ``c = 0`` it is 1: the base map preserves area away from zero velocity).

Position-dependent forcing (no dissipation)
--------------------------------------------
``x'' = F cos(k x) cos(w t) - s f``: the divergence of ``(v, A(x, t) - s f)`` is
``d/dv (A - s f) = 0``, so every flight matrix has determinant 1 (the Taylor flight's
variational matrix), impacts with ``e = 1`` have ``e^2 = 1``: ``det Phi' = 1`` on orbits
that never reach zero velocity, although ``Phi'`` itself is no longer a product of
``[[1, h], [0, 1]]`` factors.  Checked on central differences of the reference map.
"""
import mpmath
import numpy as np
import pytest
from mpmath import mpf

import fast
import reference
from cross_check.tolerances import tol
from reference import Scene
from reference.model import Model
from tests.test_reference_jacobian import finite_differences

# (scene, x, v): states whose orbit over [0, T] has impacts only (checked by each test)
DISSIPATIVE = {
    "e=0.5": (Scene(F=1, f=0, omega=1, l=0, r="0.8", restitution="0.5"), "0.3", "0.5"),
    "e=0.9,f=0.05": (Scene(F=1, f="0.05", omega=1, l=0, r=4, restitution="0.9"), "0.2", "4"),
    "c=0.1": (Scene(F=1, f=0, omega=1, l=0, r="0.8", damping="0.1"), "0.3", "0.5"),
    "c=0.3,f=0.1": (Scene(F=1, f="0.1", omega=1, l=0, r="0.8", damping="0.3"), "0.2", "4"),
    "c=0.2,e=0.85,f=0.05": (Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1, damping="0.2",
                                  restitution="0.85"), "0.5", "1.5"),
}
XPOT = Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2")


def det(J):
    return J[0][0] * J[1][1] - J[0][1] * J[1][0]


def impacts_only(scene, x, v):
    """The number of impacts over [0, T]; asserts that nothing else happens."""
    log = reference.trajectory(scene, x, v, 2 * mpmath.pi / scene.mpf("omega"), dps=30)
    kinds = [e.kind for e in log]
    assert set(kinds) == {"impact"}, kinds                # never at zero velocity
    return len(kinds)


def closed_form_det(scene, n):
    e, c = scene.mpf("restitution"), scene.mpf("damping")
    return e ** (2 * n) * mpmath.exp(-c * 2 * mpmath.pi / scene.mpf("omega"))


@pytest.mark.parametrize("name", sorted(DISSIPATIVE))
def test_det_is_e_to_the_2n_times_exp_minus_cT(name):
    scene, x, v = DISSIPATIVE[name]
    n = impacts_only(scene, x, v)
    with mpmath.workdps(70):
        expected = closed_form_det(scene, n)
        got = det(reference.jacobian(scene, x, v, dps=50))
        assert expected < 1
        assert abs(got / expected - 1) <= tol("effects_det_identity").rtol, (got, expected)


@pytest.mark.parametrize("name", ["e=0.9,f=0.05", "c=0.2,e=0.85,f=0.05"])
def test_det_closed_form_against_finite_differences(name):
    """Independent of Table 1: central differences of the reference map."""
    scene, x, v = DISSIPATIVE[name]
    n = impacts_only(scene, x, v)
    D = finite_differences(scene, x, v)
    with mpmath.workdps(90):
        t = tol("effects_det_fd")
        assert abs(det(D) - closed_form_det(scene, n)) <= t.atol + t.rtol


@pytest.mark.parametrize("name", sorted(DISSIPATIVE))
def test_fast_det_matches_the_closed_form(name):
    """fast's Phi' (float64; damping through fast.ode) has the same determinant."""
    scene, x, v = DISSIPATIVE[name]
    n = impacts_only(scene, x, v)
    J = fast.jacobian(scene, np.array([float(x)]), np.array([float(v)]))[0]
    expected = float(closed_form_det(scene, n))
    t = tol("fast_jacobian_vs_reference")
    scale = (1 + np.abs(J).max()) ** 2                    # det of entries each off by t |J|
    got = np.linalg.det(J)
    assert abs(got - expected) <= 2 * (t.atol + t.rtol) * scale, (got, expected)


def test_position_forcing_scene_runs_in_the_reference():
    log = reference.trajectory(XPOT, "0.3", "2.5", 1, dps=30)
    assert [e.kind for e in log] == ["impact"]


@pytest.mark.parametrize("x,v", [("0.3", "2.5"), ("-0.5", "-3")])
def test_position_forcing_preserves_area(x, v):
    """det Phi' = 1 on orbits without zero velocity: central differences of the map, and
    the Taylor flight's variational matrices (each of determinant 1)."""
    impacts_only(XPOT, x, v)
    D = finite_differences(XPOT, x, v)
    with mpmath.workdps(90):
        t = tol("effects_det_fd")
        assert abs(det(D) - 1) <= t.atol + t.rtol, det(D)
    from reference import taylor
    with mpmath.workdps(40):
        m = Model(XPOT)
        F = taylor.flight_matrix(m, mpf(0), mpf(x), mpf(v), mpf("0.2"))
        assert abs(det(F) - 1) < mpf(10) ** -30
        assert abs(F[0][1] - mpf("0.2")) > mpf("1e-6")    # not the base [[1, h], [0, 1]]


@pytest.mark.parametrize("x,v", [("0.3", "2.5"), ("-0.5", "-3")])
def test_fast_position_forcing_preserves_area(x, v):
    impacts_only(XPOT, x, v)
    J = fast.jacobian(XPOT, np.array([float(x)]), np.array([float(v)]))[0]
    t = tol("fast_jacobian_vs_reference")
    assert abs(np.linalg.det(J) - 1) <= 2 * (t.atol + t.rtol) * (1 + np.abs(J).max()) ** 2
