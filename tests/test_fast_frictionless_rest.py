"""fast at frictionless rest on a zero of the position forcing, against the reference.

Without friction a mass at rest where ``cos(k x) = 0`` feels no force but its rounding
(``F cos(k x*) ~ 1e-16`` at the float64 nearest ``x*``), and the periodic search of ``verify``
converges onto such a state (an equilibrium is a fixed point of ``Phi``).  There the float64
force picked the flight's direction, the flight's own (compensated) acceleration turned it back at
once, and the state stopped at ``v = 0`` at the same instant until the loop bound: ``verify`` of
two random frictionless scenes (issue 33's sweeps) failed with "an inner loop bound was
exceeded".  Without friction that direction only says which sign of ``v`` is watched for a zero,
so fast now flies the other way (``fast.ode.run_state``).  Expected values: the reference at
dps 30 from the same float64 states.
"""
import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

import fast
import reference
from cross_check.tolerances import tol
from reference.scene import Scene
from tests.strategies import position_forced_scenes
from tests.test_ode_accuracy import _assert_within, _check_batch

#: the two scenes of the failed verify runs, with ``x*`` (``k x* + pi/2 == 0.0`` in float64)
CASES = [
    (Scene(F="2.05", f=0, omega="3.845", l="-0.76", r="0.09", wavenumber="4.3461"), -0.3614266415395174),
    (Scene(F="0.733", f=0, omega="1.765", l="-1.52", r="1.70", wavenumber="1.8353", damping="0.226",
           restitution="0.9"), -0.8558798707540438),
]


@pytest.mark.parametrize("scene, x", CASES, ids=["undamped", "damped"])
@pytest.mark.parametrize("v", [0.0, 1e-17, -1e-17])
def test_frictionless_rest_on_a_zero_of_the_forcing_matches_the_reference(scene, x, v):
    assert scene.float("wavenumber") * x + np.pi / 2 == 0.0
    X, V = fast.stroboscopic_map(scene, np.array([x]), np.array([v]))
    J = fast.jacobian(scene, np.array([x]), np.array([v]))
    xr, vr = (float(a) for a in reference.stroboscopic_map(scene, x, v, dps=30))
    assert max(abs(X[0] - xr) / max(1, abs(xr)), abs(V[0] - vr) / max(1, abs(vr))) <= tol("fast_one_period_max").atol
    Jr = np.array([[float(a) for a in row] for row in reference.jacobian(scene, x, v, dps=30)])
    t = tol("fast_jacobian_vs_reference")
    assert np.abs(J[0] - Jr).max() <= (t.atol + t.rtol) * max(1.0, np.abs(Jr).max())
    ref_kinds = [e.kind for e in reference.trajectory(scene, x, v, scene.period, dps=30)]
    assert fast.events(scene, np.array([x]), np.array([v])).kinds(0) == ref_kinds


@pytest.mark.parametrize("scene, x", CASES, ids=["undamped", "damped"])
def test_the_coarse_search_map_runs_there_too(scene, x):
    """The periodic search's screen (``steps_per_period = 32``) met the state first: it runs, and
    lands within the coarse map's documented error of the default map
    (``cross_check.dynamics.periodic.SEARCH_STEPS``: 1.2e-9)."""
    X, V, J, _ = fast.map_and_jacobian(scene, np.array([x] * 3), np.array([0.0, 1e-17, -1e-17]), steps_per_period=32)
    Xd, Vd = fast.stroboscopic_map(scene, np.array([x] * 3), np.array([0.0, 1e-17, -1e-17]))
    assert np.isfinite(J).all() and np.abs(X - Xd).max() <= 1.2e-9 and np.abs(V - Vd).max() <= 1.2e-9


def _rest_on_a_zero(data):
    """A random position-forced scene without friction, and rest (``v = 0, +-1e-17``) at the
    float64 nearest one of the zeros ``(n + 1/2) pi / k`` of ``cos(k x)`` in its gap."""
    scene = replace(data.draw(position_forced_scenes(), label="scene"), f=0)
    k, l, r = scene.float("wavenumber"), scene.float("l"), scene.float("r")
    zeros = [z for n in range(-64, 64) for z in [(n + 0.5) * math.pi / k] if l < z < r]
    assume(zeros)
    x = data.draw(st.sampled_from(zeros), label="x*")
    return scene, np.full(3, x), np.array([0.0, 1e-17, -1e-17])


@settings(max_examples=4)
@given(st.data())
def test_frictionless_rest_on_random_scenes_within_the_conditioning(data):
    """On random scenes (``tests.strategies.position_forced_scenes`` with ``f = 0``), fast's one
    period from rest on a zero of the forcing meets the accuracy bound of every position-forced
    state (``tests/test_ode_accuracy.py``: error over conditioning, events, itinerary)."""
    scene, x, v = _rest_on_a_zero(data)
    _assert_within(scene, *_check_batch(scene, x, v))
