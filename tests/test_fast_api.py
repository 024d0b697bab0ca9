"""fast: the public API (shapes, validation, effects, determinism, batch independence)."""
import numpy as np
import pytest

import fast
import fast.api as api
from fast.params import Params
from reference.scene import Scene

NARROW = Scene(F=1, f="0.005", omega=1, l=0, r="0.8")      # paper fig. narrow-with-friction
TWO_PI = Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1)      # paper fig. many:2pi (c)


def _batch(scene, n, vmax, seed=0):
    rng = np.random.default_rng(seed)
    return rng.uniform(scene.float("l"), scene.float("r"), n), rng.uniform(-vmax, vmax, n)


def test_shapes_broadcast():
    x = np.linspace(0.1, 0.7, 12).reshape(3, 4)
    X, V = fast.stroboscopic_map(NARROW, x, 0.5)
    assert X.shape == V.shape == (3, 4)
    J = fast.jacobian(NARROW, x, 0.5)
    assert J.shape == (3, 4, 2, 2)
    Xo, Vo = fast.orbit(NARROW, x, 0.5, 3)
    assert Xo.shape == Vo.shape == (4, 3, 4)
    zv = fast.zero_velocity(NARROW, x, 0.5)
    assert zv.shape == (3, 4) and zv.dtype == bool
    Xs, Vs = fast.stroboscopic_map(NARROW, 0.3, 0.5)
    assert np.ndim(Xs) == 0 and np.isfinite(Xs) and np.isfinite(Vs)


def test_orbit_matches_repeated_maps_and_periods():
    x, v = _batch(NARROW, 50, 2.0, seed=1)
    Xo, Vo = fast.orbit(NARROW, x, v, 3)
    assert np.array_equal(Xo[0], x) and np.array_equal(Vo[0], v)
    X3, V3 = fast.stroboscopic_map(NARROW, x, v, periods=3)
    assert np.array_equal(Xo[3], X3) and np.array_equal(Vo[3], V3)
    X0, V0 = fast.stroboscopic_map(NARROW, x, v, periods=0)
    assert np.array_equal(X0, x) and np.array_equal(V0, v)


def test_outside_walls_names_indices():
    x = np.full((2, 3), 0.4)
    x[1, 2] = 1.2
    with pytest.raises(ValueError, match=r"x\[1, 2\] = 1\.2 is outside the walls \[0\.0, 0\.8\]"):
        fast.stroboscopic_map(NARROW, x, 0.0)


@pytest.mark.parametrize("bad", [np.nan, np.inf])
def test_non_finite_raises(bad):
    v = np.zeros(4)
    v[3] = bad
    with pytest.raises(ValueError, match=r"v\[3\]"):
        fast.jacobian(NARROW, 0.4, v)
    with pytest.raises(ValueError, match=r"x\[0\]"):
        fast.zero_velocity(NARROW, np.array([bad]), 0.0)


def test_bad_periods():
    with pytest.raises(ValueError, match="periods"):
        fast.stroboscopic_map(NARROW, 0.4, 0.0, periods=-1)
    with pytest.raises(ValueError, match="periods"):
        fast.stroboscopic_map(NARROW, 0.4, 0.0, periods=1.5)


def test_only_position_forcing_routes_to_ode():
    """Damping has closed-form float64 flights (fast.flight); only position-dependent
    forcing goes to fast.ode's numerical flights (whose event logs are not available)."""
    from fast.ode import OdeParams

    assert type(Params.from_scene(NARROW.replace(damping="0.1"))) is Params
    xpot = NARROW.replace(wavenumber="pi/2")
    assert isinstance(Params.from_scene(xpot), OdeParams)
    with pytest.raises(NotImplementedError, match="event logs"):
        fast.events(xpot, 0.4, 0.1)


def test_restitution_is_closed_form():
    assert Params.from_scene(NARROW.replace(restitution="0.9")).e == 0.9


@pytest.mark.parametrize("scene, vmax", [(NARROW, 2.0), (TWO_PI, 15.0)])
def test_batch_independence_and_determinism(scene, vmax, monkeypatch):
    """A state's result never depends on its neighbours, the chunking or the threads."""
    x, v = _batch(scene, 300, vmax, seed=2)
    X, V = fast.stroboscopic_map(scene, x, v)
    X2, V2 = fast.stroboscopic_map(scene, x, v)
    assert np.array_equal(X, X2) and np.array_equal(V, V2)
    perm = np.random.default_rng(3).permutation(x.size)
    Xp, Vp = fast.stroboscopic_map(scene, x[perm], v[perm])
    assert np.array_equal(Xp, X[perm]) and np.array_equal(Vp, V[perm])
    for i in (0, 17, 299):
        Xi, Vi = fast.stroboscopic_map(scene, x[i:i + 1], v[i:i + 1])
        assert Xi[0] == X[i] and Vi[0] == V[i]
    monkeypatch.setattr(api, "CHUNK", 7)
    monkeypatch.setattr(api, "THREADS", 2)
    Xc, Vc = fast.stroboscopic_map(scene, x, v)
    assert np.array_equal(Xc, X) and np.array_equal(Vc, V)
    Jc = fast.jacobian(scene, x, v)
    monkeypatch.setattr(api, "CHUNK", 4096)
    assert np.array_equal(Jc, fast.jacobian(scene, x, v))


def test_events_log_consistent_with_map():
    x, v = _batch(NARROW, 40, 2.0, seed=4)
    log = fast.events(NARROW, x, v)
    X, V = fast.stroboscopic_map(NARROW, x, v)
    assert np.array_equal(log.x_end, X) and np.array_equal(log.v_end, V)
    T = NARROW.period
    for i in range(x.size):
        evs = log[i]
        assert len(evs) == log.n[i]
        times = [e.t for e in evs]
        assert times == sorted(times) and all(0 <= t <= T for t in times)
        for e in evs:
            assert e.kind in fast.KINDS
            if e.kind == "impact":
                assert e.x in (0.0, 0.8) and e.v == -e.v_before
            if e.kind in ("turn", "stick", "slip"):
                assert e.v == 0.0
    zv = fast.zero_velocity(NARROW, x, v)
    assert np.array_equal(zv, [any(k != "impact" for k in log.kinds(i)) for i in range(x.size)])


def test_loop_bound_raises_with_states(monkeypatch):
    """Exceeding the per-segment round bound raises RuntimeError naming the states."""
    from fast import kernel

    monkeypatch.setattr(kernel, "MAX_SEGMENT_ROUNDS", 1)
    with pytest.raises(RuntimeError, match=r"state 0: t=.* x0=.* v0="):
        fast.stroboscopic_map(NARROW, np.array([0.3]), np.array([0.5]))


def test_flow_matches_map_at_one_period():
    x, v = _batch(TWO_PI, 30, 15.0, seed=5)
    Xf, Vf = fast.flow(TWO_PI, x, v, TWO_PI.period)
    X, V = fast.stroboscopic_map(TWO_PI, x, v)
    assert np.array_equal(Xf, X) and np.array_equal(Vf, V)


def test_events_of_a_state_without_events():
    """A scalar state with no event in the period (free flight in a wide gap)."""
    wide = Scene(F=1, f="0.1", omega=1, l=-50, r=50)
    log = fast.events(wide, 0.0, 3.0)
    assert log.n == 0 and log[0] == [] and log.kinds(0) == []
    assert log.kind.shape == (0,)
