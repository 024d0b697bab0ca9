"""Benchmarks of the proofs (group "enclosure"): what a theorem costs against a number.

Run with ``python -m pytest tests/benchmarks/test_bench_enclosure.py --benchmark-only``; compare
each ``enclose`` row with the ``point`` row of the same orbit (one run, same machine: report the
ratio).  The point reference runs at dps 96, the digits of the enclosure's 320 bits.  Each
benchmark checks its result: the proof holds and contains the point answer.

The "xpot" orbits (issue 25) are position-forced (fig:xpotno), where both sides integrate
flights by Taylor series: the proof on validated flights (balls, Picard boxes, Lohner frames,
the flow derivative) against the point reference's Taylor flights at the same digits.
"""
import mpmath
import pytest

import reference
from cross_check import scenes
from reference.enclosure import enclose_map, prove_periodic
from reference.enclosure.balls import from_mpf, workprec
from tests.strategies import REFERENCE_SCENES

ORBITS = {
    "narrow_f0 impacts": ("narrow_f0", "0.3", "0.5"),
    "narrow_f0005 impacts+turns": ("narrow_f0005", "0.3", "0.5"),
    "wide_f03 impact+turns": ("wide_f03", "0.1", "-0.7"),
    "resonance stick/slip/impact": ("resonance", "0.1", "-0.7"),
    # position forcing: the non-sticking centre (two impacts), golden sample-6 (two turns)
    "xpot centre impacts": ("fig:xpotno", "0.8711736193141787", "4.039221265591076"),
    "xpot turns": ("fig:xpotno", "-0.6990588081638365", "-0.04105985922703809"),
}


def _scene(name):
    return REFERENCE_SCENES[name] if name in REFERENCE_SCENES else scenes.scene(name)


@pytest.mark.benchmark(group="enclosure")
@pytest.mark.parametrize("orbit", sorted(ORBITS))
def test_bench_enclose_one_period(benchmark, orbit):
    name, x, v = ORBITS[orbit]
    scene = _scene(name)
    enc = benchmark(enclose_map, scene, x, v)
    assert enc.proved, enc.reason
    point = reference.stroboscopic_map(scene, x, v, dps=96)
    with workprec(enc.prec):
        assert all(abs(from_mpf(p) - b.mid()) <= b.rad() + mpmath.mpf(10) ** -90
                   for p, b in zip(point, enc.phi))


@pytest.mark.benchmark(group="enclosure")
@pytest.mark.parametrize("orbit", sorted(ORBITS))
def test_bench_point_one_period_dps96(benchmark, orbit):
    name, x, v = ORBITS[orbit]
    result = benchmark(reference.stroboscopic_map, _scene(name), x, v, dps=96)
    assert len(result) == 2


@pytest.mark.benchmark(group="enclosure")
def test_bench_prove_the_caption_saddle(benchmark):
    from cross_check import scenes
    from reference import paper
    sc = scenes.scene("fig:many:wide/f=0.6")
    x, v = paper.symmetric_solution(sc, 2, dps=60).state0()
    proof = benchmark(prove_periodic, sc, x, v)
    assert proof.proved and proof.kind == "saddle"


@pytest.mark.benchmark(group="enclosure")
def test_bench_prove_the_xpot_centre(benchmark):
    _, x, v = ORBITS["xpot centre impacts"]
    proof = benchmark(prove_periodic, scenes.scene("fig:xpotno"), x, v)
    assert proof.proved and proof.kind == "elliptic"
