"""Cost of an atlas point: the per-point path before issue 27 against today's, on the same points
(pytest-benchmark, group "atlas"; issue 27's goal: at least 2x the points per second per worker).

Run: ``python -m pytest tests/benchmarks/test_bench_atlas.py --benchmark-only`` (on a machine
shared with other work add ``--benchmark-timer time.process_time``: CPU seconds).  The points are
the first 4 rows of 4 blocks of a 64 x 64 atlas (the default ``--chunk 16``), on its diagonal, so
the f/F range and the w^2 R/F range are both covered and a row of a block shares its seeds as in
a real run; one worker (this process).  ``before``: ``atlas_before`` (the claims as they were,
each on its own) on ``fast_before`` (fast's wrappers as they were) -- the same compiled kernel.
``after_claims_only``: the old claims on today's fast (what the claims' changes alone give).
Points per second = points / time (``extra_info["points_per_s"]``); compare the rows of one run.
Every benchmark asserts that its values are those of the old path, value for value.
"""
import math

import pytest

import atlas_before
from cross_check.atlas import claims
from cross_check.atlas.run import CHUNK, Grid

GRID = Grid(64)
ALL = tuple(claims.CLAIMS)


def _points():
    fF, R = GRID.fF, GRID.R
    out = []
    for b in range(4):
        rows = range(b * CHUNK, b * CHUNK + 4)
        cols = range(b * CHUNK, (b + 1) * CHUNK)
        out += [(float(fF[j]), float(R[i])) for i in rows for j in cols]
    return out


POINTS = _points()


def _clear_caches():
    claims._closed_form.cache_clear()
    claims._attractor_speed.cache_clear()


def _same(a, b):
    if isinstance(a, float) and isinstance(b, float):
        return a == b or (math.isnan(a) and math.isnan(b))
    return a == b


@pytest.fixture(scope="module")
def expected():
    claims.evaluate(0.3, 2.0, ALL)                     # compile / load the kernels first
    atlas_before.evaluate(0.3, 2.0)
    return [atlas_before.evaluate(f, r) for f, r in POINTS]


def _check(got, expected):
    for (f, r), a, b in zip(POINTS, got, expected):
        assert set(a) == set(b) and all(_same(a[k], b[k]) for k in a), (f, r)


def _run(benchmark, fn, expected):
    got = benchmark.pedantic(fn, setup=_clear_caches, rounds=2, iterations=1)
    benchmark.extra_info["points"] = len(POINTS)
    benchmark.extra_info["points_per_s"] = len(POINTS) / benchmark.stats.stats.min
    _check(got, expected)


@pytest.mark.benchmark(group="atlas")
def test_bench_atlas_point_before(benchmark, expected):
    _run(benchmark, lambda: [atlas_before.evaluate(f, r) for f, r in POINTS], expected)


@pytest.mark.benchmark(group="atlas")
def test_bench_atlas_point_after(benchmark, expected):
    _run(benchmark, lambda: [claims.evaluate(f, r, ALL) for f, r in POINTS], expected)


@pytest.mark.benchmark(group="atlas")
def test_bench_atlas_point_after_claims_only(benchmark, expected, monkeypatch):
    """The old claims on today's fast: what the per-point changes of the claims alone give."""
    import types

    import fast
    from cross_check.dynamics import periodic
    today = types.SimpleNamespace(events=fast.events, stroboscopic_map=fast.stroboscopic_map,
                                  zero_velocity=fast.zero_velocity, jacobian=fast.jacobian,
                                  FAST_ENGINE=periodic.FAST)
    monkeypatch.setattr(atlas_before, "fast", today)
    _run(benchmark, lambda: [atlas_before.evaluate(f, r) for f, r in POINTS], expected)
