"""Benchmarks of the cost of each effect (groups "effects-reference", "effects-fast").

One period from the same start (an impacts-only orbit: two impacts, one with e = 0.9) on the same scene with one effect switched on at a
time: no friction (walls and forcing only), Coulomb friction (the base scene), restitution
``e = 0.9``, viscous damping ``c = 0.05`` (closed-form exponential flights), and position
forcing (eq. ``xpot``: ``F cos(pi x / 2) cos(2 pi t)``, numerical flights: certified Taylor
steps in ``reference``, DOP853 in ``fast``).  Run with
``python -m pytest tests/benchmarks/test_bench_effects.py --benchmark-only``; compare the
two rows of a group (the ratio is the price of the numerical flight).  Each benchmark
checks its result: the reference against a dps + 20 run, fast against the reference.
"""
import mpmath
import numpy as np
import pytest

import fast
import reference
from cross_check.tolerances import tol
from reference.scene import Scene

BASE = Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, name="xpot without position forcing")
XPOT = BASE.replace(wavenumber="pi/2", name="xpot")
SCENES = {
    "friction (base, closed-form flights)": BASE,
    "no friction": BASE.replace(f=0, name="frictionless"),
    "restitution e = 0.9": BASE.replace(restitution="0.9", name="restitution"),
    "damping c = 0.05": BASE.replace(damping="0.05", name="damping"),
    "position forcing (k = pi/2)": XPOT,
}
#: an impacts-only orbit in every scene (2 impacts; 1 with e = 0.9, whose second comes after T)
X0, V0 = "-0.5", "-3"


@pytest.mark.benchmark(group="effects-reference")
@pytest.mark.parametrize("which", sorted(SCENES))
def test_bench_reference_period_dps50(benchmark, which):
    scene = SCENES[which]
    result = benchmark.pedantic(reference.stroboscopic_map, args=(scene, X0, V0),
                                kwargs=dict(dps=50), rounds=3, iterations=1)
    log = reference.trajectory(scene, X0, V0, 1, dps=30)
    kinds = [e.kind for e in log]
    assert kinds and set(kinds) == {"impact"}, kinds   # comparable work: flights and impacts only
    exact = reference.stroboscopic_map(scene, X0, V0, dps=70)
    with mpmath.workdps(80):
        assert all(abs(a - b) <= tol("ref_map_dps50").atol for a, b in zip(result, exact))


@pytest.mark.benchmark(group="effects-fast")
@pytest.mark.parametrize("which", sorted(SCENES))
def test_bench_fast_period_1000_states(benchmark, which):
    scene = SCENES[which]
    rng = np.random.default_rng(20261122)
    x = rng.uniform(-1.0, 1.0, 1000)
    v = rng.uniform(-3.0, 3.0, 1000)
    X, V = benchmark.pedantic(fast.stroboscopic_map, args=(scene, x, v), rounds=3, iterations=1,
                              warmup_rounds=1)
    t = tol("fast_one_period_max")
    for i in (0, 1, 2):
        xr, vr = reference.stroboscopic_map(scene, x[i], v[i], dps=30)
        assert abs(X[i] - float(xr)) <= t.atol + t.rtol * max(1.0, abs(float(xr)))
        assert abs(V[i] - float(vr)) <= t.atol + t.rtol * max(1.0, abs(float(vr)))
