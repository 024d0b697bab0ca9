"""``fast`` on every core: the default thread count (the process's CPU affinity, ``VIBRO_THREADS``),
the ``threads=`` keyword of every public function, and the same bits for every thread count."""
import os

import numpy as np
import pytest

import fast
from fast import batch
from reference.scene import Scene

TWO_PI = Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1)      # paper fig. many:2pi (c): many events
FORCED = TWO_PI.replace(wavenumber="pi/2")                   # position forcing: fast.ode's engine
N = batch.MIN_THREADED + 45                                  # big enough to be split into chunks


def _states(n, seed):
    rng = np.random.default_rng(seed)
    return rng.uniform(-1, 1, n), rng.uniform(-15, 15, n)


@pytest.fixture
def no_env(monkeypatch):
    monkeypatch.delenv(batch.ENV, raising=False)
    monkeypatch.setattr(batch, "THREADS", None)


@pytest.fixture
def pools(monkeypatch):
    """The sizes of the thread pools the batch driver starts."""
    sizes = []
    real = batch.ThreadPoolExecutor

    def spy(n):
        sizes.append(n)
        return real(n)

    monkeypatch.setattr(batch, "ThreadPoolExecutor", spy)
    return sizes


def test_the_same_bits_on_1_2_3_and_7_threads(pools):
    x, v = _states(N, seed=5)
    first = None
    for threads in (1, 2, 3, 7):
        X, V, J, Z = fast.map_and_jacobian(TWO_PI, x, v, threads=threads)
        log = fast.events(TWO_PI, x, v, threads=threads)
        got = (X, V, J, Z, log.kind, log.t, log.x, log.v, log.n)
        if first is None:
            first = got
        assert all(np.array_equal(a, b, equal_nan=True) for a, b in zip(got, first)), threads
    assert pools == [2, 2, 3, 3, 7, 7]        # the thread counts were used (1 runs inline)


def test_the_same_bits_on_any_thread_count_with_numerical_flights():
    x, v = _states(N, seed=6)
    X1, V1 = fast.stroboscopic_map(FORCED, x, v, threads=1)
    X3, V3 = fast.stroboscopic_map(FORCED, x, v, threads=3)
    assert np.array_equal(X1, X3) and np.array_equal(V1, V3)


def test_the_coarse_map_is_the_same_bits_on_any_thread_count_and_batch():
    """``steps_per_period`` (a slot of the engine's constants) keeps the batch driver's promise:
    the same bits for every thread count and for a state alone."""
    x, v = _states(N, seed=7)
    runs = [fast.map_and_jacobian(FORCED, x, v, threads=t, steps_per_period=32) for t in (1, 3)]
    assert all(np.array_equal(a, b, equal_nan=True) for a, b in zip(*runs))
    alone = fast.map_and_jacobian(FORCED, x[5:6], v[5:6], steps_per_period=32)
    assert all(np.array_equal(a[5:6], b, equal_nan=True) for a, b in zip(runs[0], alone))


def test_the_map_with_its_flags_is_the_same_bits_on_any_thread_count_and_batch():
    """``fast.map_and_zero_velocity`` keeps the batch driver's promise on both engines: the same
    bits for every thread count and for a state alone."""
    x, v = _states(N, seed=9)
    for scene, opt in ((TWO_PI, {}), (FORCED, {"steps_per_period": 32}), (FORCED, {})):
        runs = [fast.map_and_zero_velocity(scene, x, v, threads=t, **opt) for t in (1, 3)]
        assert all(np.array_equal(a, b, equal_nan=True) for a, b in zip(*runs))
        alone = fast.map_and_zero_velocity(scene, x[5:6], v[5:6], **opt)
        assert all(np.array_equal(a[5:6], b, equal_nan=True) for a, b in zip(runs[0], alone))


def test_default_is_the_affinity_mask(no_env, monkeypatch, pools):
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(16)), raising=False)
    assert fast.default_threads() == 16
    fast.zero_velocity(TWO_PI, *_states(N, seed=7))
    assert pools == [16]


def test_default_without_an_affinity_mask_is_cpu_count(no_env, monkeypatch):
    monkeypatch.delattr(os, "sched_getaffinity", raising=False)
    monkeypatch.setattr(os, "cpu_count", lambda: 5)
    assert fast.default_threads() == 5


def test_environment_overrides_the_default(no_env, monkeypatch, pools):
    monkeypatch.setattr(os, "sched_getaffinity", lambda pid: set(range(16)), raising=False)
    monkeypatch.setenv("VIBRO_THREADS", "3")
    assert fast.default_threads() == 3
    fast.flow(TWO_PI, *_states(N, seed=8), 0.5)
    fast.flow(TWO_PI, *_states(N, seed=8), 0.5, threads=2)      # the keyword wins
    assert pools == [3, 2]


@pytest.mark.parametrize("value", ["0", "-2", "1.5", "many", "1025"])
def test_bad_environment_value_names_the_variable(no_env, monkeypatch, value):
    monkeypatch.setenv("VIBRO_THREADS", value)
    with pytest.raises(ValueError, match=r"VIBRO_THREADS must be an integer in \[1, 1024\]"):
        fast.stroboscopic_map(TWO_PI, 0.1, 0.2)


ENTRY_POINTS = {
    "stroboscopic_map": lambda x, v, t: fast.stroboscopic_map(TWO_PI, x, v, threads=t),
    "jacobian": lambda x, v, t: fast.jacobian(TWO_PI, x, v, threads=t),
    "map_and_jacobian": lambda x, v, t: fast.map_and_jacobian(TWO_PI, x, v, threads=t),
    "orbit": lambda x, v, t: fast.orbit(TWO_PI, x, v, 2, threads=t),
    "zero_velocity": lambda x, v, t: fast.zero_velocity(TWO_PI, x, v, threads=t),
    "map_and_zero_velocity": lambda x, v, t: fast.map_and_zero_velocity(TWO_PI, x, v, threads=t),
    "flow": lambda x, v, t: fast.flow(TWO_PI, x, v, 1.0, threads=t),
    "events": lambda x, v, t: fast.events(TWO_PI, x, v, threads=t),
}


@pytest.mark.parametrize("entry", sorted(ENTRY_POINTS))
@pytest.mark.parametrize("threads, error", [(0, ValueError), (1025, ValueError), (2.0, TypeError),
                                            (True, TypeError), ("2", TypeError)])
def test_bad_threads_keyword(entry, threads, error):
    with pytest.raises(error, match=r"threads must be None or an integer|threads must be an integer"):
        ENTRY_POINTS[entry](0.1, 0.2, threads)


# The exported functions that integrate no batch: they check a scene, report the default, or
# compile the engines on one state (warm_up, on the calling thread).
NO_EVENT_LOOP = {"default_threads", "validate_scene", "warm_up"}


def test_every_exported_function_takes_threads():
    import inspect
    for name in fast.__all__:
        obj = getattr(fast, name)
        if inspect.isfunction(obj) and name not in NO_EVENT_LOOP:
            assert "threads" in inspect.signature(obj).parameters, name
