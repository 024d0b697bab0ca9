"""Speed of fast's compiled loop (pytest-benchmark, group "fast"; issue 13).

Run: ``python -m pytest tests/benchmarks/test_bench_fast.py --benchmark-only``.
Trajectory-periods per second = N / mean time (``extra_info["per_s"]``).  Issue 13's
targets on this 2-core machine at N = 1e5, one period: >= 4e5 /s per core on the narrow
scene (F=1, f=0.005, w=1, [0, 0.8], |v| <= 2) and >= 1.2e6 /s per core on the 2 pi scene
(F=1, f=0.05, w=2 pi, [-1, 1], |v| <= 15), and >= 1.8x that on 2 threads.  Speeds are
compared as ratios within one run (the machine is noisy), so the targets are read off
the table, not asserted; every benchmark asserts its result instead.
"""
import math
import os
import subprocess
import sys
import tempfile

import numpy as np
import pytest

import fast
from fast import batch
from reference.scene import Scene

SCENES = {
    "narrow": (Scene(F=1, f="0.005", omega=1, l=0, r="0.8"), 2.0),
    "twopi": (Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1), 15.0),
}


def _batch(name, n):
    scene, vmax = SCENES[name]
    rng = np.random.default_rng(12345)
    return scene, rng.uniform(scene.float("l"), scene.float("r"), n), rng.uniform(-vmax, vmax, n)


def _check(scene, X, V):
    assert np.all(np.isfinite(X)) and np.all(np.isfinite(V))
    assert np.all((X >= scene.float("l")) & (X <= scene.float("r")))


@pytest.mark.benchmark(group="fast")
@pytest.mark.parametrize("threads", [1, 2])
@pytest.mark.parametrize("n", [1_000, 10_000, 100_000])
@pytest.mark.parametrize("name", list(SCENES))
def test_bench_fast_map(benchmark, monkeypatch, name, n, threads):
    scene, x, v = _batch(name, n)
    monkeypatch.setattr(batch, "THREADS", threads)
    X, V = benchmark.pedantic(fast.stroboscopic_map, args=(scene, x, v),
                              rounds=3 if n == 100_000 else 5, iterations=1, warmup_rounds=1)
    benchmark.extra_info["per_s"] = n / benchmark.stats.stats.mean
    _check(scene, X, V)


@pytest.mark.benchmark(group="fast")
@pytest.mark.parametrize("threads", [1, 2])
def test_bench_fast_map_and_jacobian(benchmark, monkeypatch, threads):
    """Phi and Phi' (the Table 1 product) in one pass, narrow scene, N = 1e5."""
    scene, x, v = _batch("narrow", 100_000)
    monkeypatch.setattr(batch, "THREADS", threads)
    X, V, J, _ = benchmark.pedantic(fast.map_and_jacobian, args=(scene, x, v), rounds=3,
                                    iterations=1, warmup_rounds=1)
    benchmark.extra_info["per_s"] = x.size / benchmark.stats.stats.mean
    _check(scene, X, V)
    # det Phi' is the product of the turn factors (|A| - f)/(|A| + f) <= 1 (impacts and
    # flights have det 1, sticking and contact 0): in [0, 1] wherever Phi' is finite
    det = np.linalg.det(J[np.isfinite(J).all(axis=(1, 2))])
    assert det.size > 0.999 * x.size and np.all((det >= -1e-12) & (det <= 1 + 1e-9))


@pytest.mark.benchmark(group="fast-work")
def test_bench_many_impacts(benchmark):
    """One state that just needs many impacts: v = 1e6 between walls 0.8 apart, about
    7.85e6 impacts in one period of the narrow scene (issue 13: well under a second)."""
    scene = SCENES["narrow"][0]
    X, V = benchmark.pedantic(fast.stroboscopic_map, args=(scene, 0.3, 1e6), rounds=3,
                              iterations=1, warmup_rounds=1)
    benchmark.extra_info["impacts_per_s"] = 1e6 * 2 * math.pi / 0.8 / benchmark.stats.stats.mean
    assert 0.0 <= X <= 0.8 and abs(abs(V) - 1e6) <= 2.0 + 0.005 * 2 * math.pi


_START = ("import time; t = time.perf_counter(); import fast; from reference.scene import Scene; "
          "fast.stroboscopic_map(Scene(F=1, f='0.005', omega=1, l=0, r='0.8'), 0.3, 0.5); "
          "print(time.perf_counter() - t)")


def _fresh_process(cache_dir):
    env = dict(os.environ, NUMBA_CACHE_DIR=cache_dir)
    out = subprocess.run([sys.executable, "-c", _START], env=env, capture_output=True, text=True,
                         check=True)
    return float(out.stdout.split()[-1])


@pytest.mark.benchmark(group="fast-jit")
def test_bench_first_call_cold_cache(benchmark):
    """The first call of a fresh process with an empty cache: import and compilation."""
    def cold():
        with tempfile.TemporaryDirectory() as d:
            return _fresh_process(d)
    seconds = benchmark.pedantic(cold, rounds=2, iterations=1)
    benchmark.extra_info["first_call_s"] = seconds
    assert seconds > 0


@pytest.mark.benchmark(group="fast-jit")
def test_bench_first_call_warm_cache(benchmark):
    """The first call of a fresh process whose cache was written by an earlier one."""
    with tempfile.TemporaryDirectory() as d:
        _fresh_process(d)
        seconds = benchmark.pedantic(_fresh_process, args=(d,), rounds=3, iterations=1)
    benchmark.extra_info["first_call_s"] = seconds
    assert seconds > 0
