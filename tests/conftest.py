"""Shared pytest configuration: hypothesis profiles and common fixtures.

Hypothesis profiles (pick with ``HYPOTHESIS_PROFILE=dev|ci|thorough``; the default is ``ci``
everywhere, so a plain ``pytest`` draws the same examples on every run and machine):

* ``dev``      -- quick local runs (20 examples, random);
* ``ci``       -- derandomized (the same examples on every run), ``print_blob=True``;
* ``thorough`` -- 1000 examples, for the ``slow`` marker runs.

``deadline=None`` everywhere: mpmath timings vary with the numbers.
"""
import os

import pytest
from hypothesis import HealthCheck, settings

settings.register_profile("dev", max_examples=20, deadline=None)
settings.register_profile(
    "ci", max_examples=30, deadline=None, derandomize=True, print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "thorough", max_examples=1000, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))


# --- order: the fastest, most fault-sensitive checks first ---------------------------------
#: modules run first, in this order, and marked ``sensitive`` (``python -m pytest -m sensitive``
#: runs only them): the negative tests of every proof certificate and of fast's noise floors
#: (issue 24), the golden data, the threshold pairs, the fault catalogue, the precision on
#: short flights, the scorecard, the constructed events -- the checks that caught every fault
#: injected so far (``python -m cross_check sensitivity``), in seconds
SENSITIVE = ("test_certify_negative.py", "test_walk_negative.py", "test_chatter_tail_negative.py",
             "test_orbits_negative.py", "test_impacts_negative.py", "test_fast_noise.py",
             "test_golden.py", "test_thresholds.py", "test_sensitivity.py", "test_short_flights.py",
             "test_score.py", "test_constructed_events.py")
#: modules run last: the claims and figures (the slowest), then the CLI end to end
LAST = ("test_claims.py", "test_figures.py", "test_cli.py")


def pytest_collection_modifyitems(config, items):
    import pytest

    def rank(item):
        name = item.path.name
        if name in SENSITIVE:
            return SENSITIVE.index(name)
        return len(SENSITIVE) + 1 + (LAST.index(name) if name in LAST else -1)

    for item in items:
        if item.path.name in SENSITIVE:
            item.add_marker(pytest.mark.sensitive)
    items.sort(key=rank)          # stable: the order inside a module is kept


@pytest.fixture(scope="module")
def client():
    """A local Dask cluster of 2 single-threaded worker processes for one test module, made the
    way the commands make it (``cross_check.cluster.client``); closed after the module."""
    pytest.importorskip("distributed", reason="the Dask tests need dask.distributed (the atlas extra)")
    from cross_check import cluster

    with cluster.client(workers=2) as c:
        yield c
