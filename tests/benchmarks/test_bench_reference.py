"""Benchmarks of the reference (group "reference"): one period at dps = 50.

Run with ``python -m pytest tests/benchmarks/test_bench_reference.py --benchmark-only``.
Each benchmark also checks its result (the orbit's event count and self-agreement with a
dps-70 run), so a fast wrong answer cannot pass.  ms per event = ms per period / events.
"""
import mpmath
import pytest

import reference
from cross_check.tolerances import tol
from tests.strategies import REFERENCE_SCENES

#: typical orbits with 2-6 events per period (counts from the reference's own log)
ORBITS = {
    "narrow_f0 4 impacts": ("narrow_f0", "0.3", "0.5", 4),
    "narrow_f0005 impacts+turns": ("narrow_f0005", "0.3", "0.5", 6),
    "wide_f03 impact+turns": ("wide_f03", "0.1", "-0.7", 3),
    "2pi_f01 2 turns": ("2pi_f01", "0.5", "0.01", 2),
    "resonance stick/slip/impact": ("resonance", "0.1", "-0.7", 6),
}


@pytest.mark.benchmark(group="reference")
@pytest.mark.parametrize("orbit", sorted(ORBITS))
def test_bench_one_period_dps50(benchmark, orbit):
    name, x, v, n_events = ORBITS[orbit]
    scene = REFERENCE_SCENES[name]
    result = benchmark(reference.stroboscopic_map, scene, x, v, dps=50)
    log = reference.trajectory(scene, x, v, 2 * mpmath.pi / scene.mpf("omega"), dps=50)
    assert len(log) == n_events
    benchmark.extra_info["events"] = n_events
    exact = reference.stroboscopic_map(scene, x, v, dps=70)
    with mpmath.workdps(80):
        t = tol("ref_map_dps50")
        assert all(abs(a - b) <= t.atol for a, b in zip(result, exact))
