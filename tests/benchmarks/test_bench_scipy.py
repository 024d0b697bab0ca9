"""The general-purpose baseline against fast (pytest-benchmark, group "scipy-vs-fast").

Run: ``python -m pytest tests/benchmarks/test_bench_scipy.py --benchmark-only``.  Both rows
do one period of the same 32 states of the narrow scene with friction (fig:narrow-with-friction,
seeded sample): scipy's ``solve_ivp`` DOP853 at rtol 1e-10 restarted at every event
(``cross_check.agreement.baseline``), and ``fast.stroboscopic_map`` on the batch; a third row runs fast on
4096 states (the sample repeated), where its per-call overhead is amortised.  Speed ratio per
trajectory-period: (scipy mean / 32) / (fast mean / n).  Each benchmark also checks its result against the
reference (dps 30): fast within ``fast_one_period_max``; scipy converged (error well below
its rtol's square root on states whose itinerary it gets right).
"""
import numpy as np
import pytest

from cross_check.agreement import baseline, compare
from cross_check import scenes
from cross_check.tolerances import tol

NAME = "fig:narrow-with-friction"
N = 32
BIG = 4096


def _batch():
    cases = scenes.sample_states(NAME, N)
    return cases, np.array([c.float()[0] for c in cases]), np.array([c.float()[1] for c in cases])


def _scipy_batch(sc, X, V):
    return [baseline.stroboscopic(sc, x, v, 1, "DOP853", 1e-10) for x, v in zip(X, V)]


@pytest.mark.benchmark(group="scipy-vs-fast")
def test_bench_scipy_dop853_rtol1e10(benchmark):
    sc = scenes.scene(NAME)
    cases, X, V = _batch()
    runs = benchmark.pedantic(_scipy_batch, args=(sc, X, V), rounds=3, iterations=1)
    errs = []
    for c, run in zip(cases[:8], runs[:8]):
        ref = compare.ref_map(sc, c, 1, 30)
        errs.append(10.0 ** -min(compare.digits(run.x, ref[0]), compare.digits(run.v, ref[1])))
    assert np.median(errs) < 1e-5, errs   # sqrt(rtol): DOP853 at 1e-10 is far better than this


@pytest.mark.benchmark(group="scipy-vs-fast")
def test_bench_fast_same_states(benchmark):
    sc = scenes.scene(NAME)
    cases, X, V = _batch()
    fx, fv = benchmark.pedantic(compare.fast_map, args=(sc, X, V), rounds=5, iterations=1)
    t = tol("fast_one_period_max")
    for i in range(4):
        ref = compare.ref_map(sc, cases[i], 1, 30)
        assert abs(fx[i] - float(ref[0])) <= t.atol + t.rtol * abs(float(ref[0]))
        assert abs(fv[i] - float(ref[1])) <= t.atol + t.rtol * abs(float(ref[1]))


@pytest.mark.benchmark(group="scipy-vs-fast")
def test_bench_fast_4096_states(benchmark):
    sc = scenes.scene(NAME)
    cases, X, V = _batch()
    reps = BIG // N
    fx, fv = benchmark.pedantic(compare.fast_map, args=(sc, np.tile(X, reps), np.tile(V, reps)),
                                rounds=3, iterations=1)
    small_x, small_v = compare.fast_map(sc, X, V)
    assert np.array_equal(fx[:N], small_x) and np.array_equal(fv[-N:], small_v)   # batch-independent
