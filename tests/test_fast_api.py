"""fast: the public API (shapes, validation, effects, determinism, batch independence,
work budgets)."""
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import fast
import reference
from fast import api, batch, loop, ode
from fast.params import E, params
from reference.scene import Scene
from tests.strategies import position_forced_scenes, scenes

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


@pytest.mark.parametrize("periods, error", [(-1, ValueError), (1.5, ValueError),
                                           (None, TypeError), ("2", TypeError), (True, TypeError)])
def test_bad_periods(periods, error):
    with pytest.raises(error, match="periods must be an integer >= 0"):
        fast.stroboscopic_map(NARROW, 0.4, 0.0, periods=periods)


def test_zero_periods_is_the_identity_in_both_engines():
    """``periods = 0`` is accepted by ``fast`` and ``reference`` alike: the start state."""
    X, V = fast.stroboscopic_map(NARROW, np.array([0.3, 0.7]), np.array([-0.5, 1e-25]), periods=0)
    assert np.array_equal(X, [0.3, 0.7]) and np.array_equal(V, [-0.5, 1e-25])
    xr, vr = reference.stroboscopic_map(NARROW, 0.3, -0.5, periods=0, dps=20)
    assert (float(xr), float(vr)) == (0.3, -0.5)


ENTRY_POINTS = {
    "stroboscopic_map": lambda s, x, v: fast.stroboscopic_map(s, x, v),
    "jacobian": lambda s, x, v: fast.jacobian(s, x, v),
    "map_and_jacobian": lambda s, x, v: fast.map_and_jacobian(s, x, v),
    "orbit": lambda s, x, v: fast.orbit(s, x, v, 2),
    "zero_velocity": lambda s, x, v: fast.zero_velocity(s, x, v),
    "flow": lambda s, x, v: fast.flow(s, x, v, 1.0),
    "events": lambda s, x, v: fast.events(s, x, v),
}


@pytest.mark.parametrize("entry", sorted(ENTRY_POINTS))
@pytest.mark.parametrize("scene", [{"F": 1}, "narrow", None, NARROW.floats()])
def test_scene_must_be_a_scene(entry, scene):
    with pytest.raises(TypeError, match=r"scene must be a reference.scene.Scene, got"):
        ENTRY_POINTS[entry](scene, 0.4, 0.1)


@pytest.mark.parametrize("entry", sorted(ENTRY_POINTS))
@pytest.mark.parametrize("which, bad", [
    ("x", np.array([0.4 + 0.1j])), ("v", 0.1 + 0j), ("x", np.array(["0.4"])),
    ("v", np.array([0.1], dtype=object)), ("v", np.array([True])), ("x", "0.4")])
def test_complex_object_string_and_bool_states_are_type_errors(entry, which, bad):
    """No silent cast (numpy would drop an imaginary part with only a warning)."""
    args = {"x": 0.4, "v": 0.1, which: bad}
    with pytest.raises(TypeError, match=rf"fast: {which} must be real numbers"):
        ENTRY_POINTS[entry](NARROW, args["x"], args["v"])


@pytest.mark.parametrize("bad, error", [(0, ValueError), (-1, ValueError), (2.5, ValueError),
                                        (None, TypeError), ("10", TypeError)])
def test_bad_event_budget(bad, error):
    with pytest.raises(error, match=r"max_events must be an integer >= 1"):
        fast.stroboscopic_map(NARROW, 0.4, 0.1, max_events=bad)


@pytest.mark.parametrize("bad, error", [(-1.0, ValueError), (math.inf, ValueError),
                                        (math.nan, ValueError), (None, TypeError)])
def test_bad_end_time(bad, error):
    with pytest.raises(error, match=r"t_end must be"):
        fast.flow(NARROW, 0.4, 0.1, bad)


def test_only_position_forcing_routes_to_ode():
    """Damping and restitution keep closed-form flights (``fast.loop``); only position
    dependent forcing goes to the numerical flights of ``fast.ode``."""
    assert api._engine(NARROW.replace(damping="0.1"))[0] is loop
    assert api._engine(NARROW.replace(restitution="0.9"))[0] is loop
    assert api._engine(NARROW.replace(wavenumber="pi/2"))[0] is ode


def test_restitution_is_closed_form():
    assert params(NARROW.replace(restitution="0.9"))[E] == 0.9


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
    J1 = fast.jacobian(scene, x, v)
    for threads, chunks, least in ((2, 37, 2), (3, 1, 1), (1, 8, 1)):
        monkeypatch.setattr(batch, "THREADS", threads)
        monkeypatch.setattr(batch, "CHUNKS_PER_THREAD", chunks)
        monkeypatch.setattr(batch, "MIN_THREADED", least)
        Xc, Vc = fast.stroboscopic_map(scene, x, v)
        assert np.array_equal(Xc, X) and np.array_equal(Vc, V), threads
        assert np.array_equal(fast.jacobian(scene, x, v), J1), threads


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


def test_event_budget_raises_naming_the_states_and_their_counts():
    """A gap of 1e-9 with v = 1 needs ~6e9 impacts per period: the per-state budget stops
    it, and the error names the states (index, start) and their event counts; the states
    within the budget are not blamed."""
    tiny = Scene(F=1, f="0.1", omega=1, l=0, r="1e-9")
    x, v = np.array([5e-10, 5e-10, 5e-10]), np.array([1.0, 0.0, -2.0])
    fast.stroboscopic_map(tiny, x[1:2], v[1:2], max_events=1000)   # at rest: chatter, contact
    with pytest.raises(RuntimeError, match=r"fast: 2 state\(s\): more than max_events = 1000 "
                                           r"events: state 0 \(x0=5e-10, v0=1.0, 1001 events\), "
                                           r"state 2 \(x0=5e-10, v0=-2.0, 1001 events\)$"):
        fast.stroboscopic_map(tiny, x, v, max_events=1000)


def test_many_impacts_are_just_work():
    """v = 1e6 between walls 0.8 apart: 7.85e6 impacts in a period, within the default
    budget.  Without forcing and friction the exact result is the triangle wave of the free
    flight: x(T) = reflect(x0 + v0 T) in [0, R], |v(T)| = v0 (``fast.flow`` of one period
    against that closed form; the impact times are exact to ~eps t each, so x(T) carries
    ~7.85e6 rounding errors of ~1e-16 |v| dt = 1e-16 R: about 1e-9 at the worst)."""
    free = Scene(F=0, f=0, omega=1, l=0, r="0.8")
    x0, v0 = 0.3, 1e6
    X, V = fast.stroboscopic_map(free, x0, v0)
    R, T = 0.8, 2 * math.pi
    u = math.fmod(x0 + math.fsum([v0 * T]), 2 * R)          # position on the unfolded circle
    x_exact = u if u <= R else 2 * R - u
    assert abs(V) == v0 and abs(X - x_exact) <= 1e-8, (X, x_exact)
    Xf, Vf = fast.stroboscopic_map(NARROW, x0, v0)          # with forcing and friction
    assert 0.0 <= Xf <= 0.8 and abs(abs(Vf) - v0) <= 2 * 1.0 + 0.005 * T


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


def test_warm_up_compiles_the_engines_asked_for_and_then_runs_from_them():
    """``fast.warm_up`` (issue 36: the report compiles the two engines in two processes at once):
    the engines asked for, each with its seconds; afterwards a call on either engine compiles
    nothing new (numba's dispatchers hold one signature each)."""
    import fast.loop as loop
    import fast.ode as ode

    assert set(fast.warm_up(position_forcing=False)) == {"closed_form"}
    got = fast.warm_up(closed_form=False)
    assert set(got) == {"position_forcing"} and got["position_forcing"] >= 0
    before = (len(loop.run_range.signatures), len(ode.run_range.signatures))
    sc = Scene(F=1, f="0.2", omega=2, l=-1, r=1, restitution="0.9", damping="0.1")
    fast.events(sc, np.array([0.3]), np.array([-0.4]))
    fast.map_and_jacobian(Scene(F=1, f="0.1", omega=1, l=0, r=2, wavenumber=2), np.array([1.0] * 300),
                          np.array([0.5] * 300), threads=2)
    assert (len(loop.run_range.signatures), len(ode.run_range.signatures)) == before == (1, 1)


XPOT_D = Scene(F=3, f="0.5", omega="0.8", l=-2, r="1.5", wavenumber="2.5")   # issue 33's scene D


@pytest.mark.parametrize("bad, error", [(15, ValueError), (129, ValueError), (32.5, ValueError),
                                        ("32", TypeError), (True, TypeError)])
def test_bad_steps_per_period_names_the_parameter_and_range(bad, error):
    with pytest.raises(error, match="steps_per_period"):
        fast.map_and_jacobian(XPOT_D, 0.1, 0.2, steps_per_period=bad)
    with pytest.raises(error, match="steps_per_period"):
        fast.stroboscopic_map(NARROW, 0.1, 0.2, steps_per_period=bad)


def test_steps_per_period_default_and_closed_form_are_bitwise_unchanged():
    """``None`` and ``STEPS_PER_PERIOD`` are the default map; closed-form flights have no steps."""
    x, v = _batch(XPOT_D, 20, 2.0, seed=5)
    ref = fast.map_and_jacobian(XPOT_D, x, v)
    same = fast.map_and_jacobian(XPOT_D, x, v, steps_per_period=ode.STEPS_PER_PERIOD)
    assert all(np.array_equal(a, b) for a, b in zip(ref, same))
    x, v = _batch(NARROW, 20, 2.0, seed=5)
    closed = fast.stroboscopic_map(NARROW, x, v)
    assert all(np.array_equal(a, b) for a, b in zip(closed, fast.stroboscopic_map(NARROW, x, v, steps_per_period=16)))


@settings(max_examples=12)
@given(sc=position_forced_scenes(), steps=st.sampled_from((24, 32, 48)), seed=st.integers(0, 2 ** 16))
def test_coarse_steps_err_like_their_truncation(sc, steps, seed):
    """``steps_per_period = S``: the map within ``4 (128 / S)^8 eps max(1, |Phi'|) max(1, |z|)`` of
    the default (``fast.api``'s docstring: DOP853's truncation grows like ``h^8`` from the
    default's error of at most 4 eps over its conditioning, ``golden_fast_phi_per_cond``), and
    not the default map itself (on D's 2,000 states the largest ratio was 0.39 of the bound)."""
    x, v = _batch(sc, 8, 2.0, seed=seed)
    X, V, J, _ = fast.map_and_jacobian(sc, x, v)
    Xs, Vs, _, _ = fast.map_and_jacobian(sc, x, v, steps_per_period=steps)
    ok = np.isfinite(J).all(axis=(1, 2))          # a grazing start has no Phi' to scale by
    cond = np.maximum(1, np.abs(J[ok]).max(axis=(1, 2))) * np.maximum(1, np.maximum(abs(X[ok]), abs(V[ok])))
    err = np.maximum(abs(Xs[ok] - X[ok]), abs(Vs[ok] - V[ok]))
    assert np.all(err <= 4 * (ode.STEPS_PER_PERIOD / steps) ** 8 * 2.0 ** -52 * cond), (err / cond).max()
    assert not (np.array_equal(Xs, X) and np.array_equal(Vs, V))


@settings(max_examples=10, deadline=None)
@given(st.one_of(scenes(), position_forced_scenes()), st.integers(0, 2**16), st.sampled_from([None, 24, 64]))
def test_map_and_zero_velocity_is_the_map_and_the_flags_of_the_jacobians_pass(scene, seed, steps):
    """``fast.map_and_zero_velocity`` (one pass without ``Phi'``, for orbits that track
    ``Omega_dissip``): the map and the zero-velocity flags of ``map_and_jacobian`` bit for bit, and
    those of ``stroboscopic_map`` and ``zero_velocity``, on both engines (``steps_per_period``
    where the scene has position forcing)."""
    rng = np.random.default_rng(seed)
    l, r = scene.float("l"), scene.float("r")
    x, v = rng.uniform(l, r, 24), rng.uniform(-3, 3, 24)
    opt = {"steps_per_period": steps} if steps is not None and scene.has("position_forcing") else {}
    x1, v1, zv = fast.map_and_zero_velocity(scene, x, v, **opt)
    X, V, _J, Z = fast.map_and_jacobian(scene, x, v, **opt)
    assert np.array_equal(x1, X) and np.array_equal(v1, V) and np.array_equal(zv, Z)
    Xs, Vs = fast.stroboscopic_map(scene, x, v, **opt)
    assert np.array_equal(x1, Xs) and np.array_equal(v1, Vs)
    if not opt:
        assert np.array_equal(zv, fast.zero_velocity(scene, x, v))
    with pytest.raises(ValueError, match="steps_per_period"):
        fast.map_and_zero_velocity(NARROW, 0.4, 0.5, steps_per_period=1)
