"""Benchmarks of box proofs (group "proved box"): one parameter box of a claim, covered by
sub-boxes, in impact coordinates (``--method impacts``) against the stroboscopic map in
multiple shooting (``--method shooting``).

Run with ``python -m pytest tests/benchmarks/test_bench_proved_box.py --benchmark-only`` and
report the ratio of the two rows of a box (one run, same machine).  The boxes are ones both
methods prove (x2 where its impacts are fast, x1 at a middle friction); x2's slow-impact band,
where shooting needs more than 512 sub-boxes, is not among them.  Each benchmark checks that
the cover is proved and that both methods' hulls overlap.
"""
from fractions import Fraction

import pytest

from reference.enclosure import ParamBox
from reference.enclosure.branches import symmetric_cover

BOXES = {
    "x2 saddle, w2R/F 60.9-71.8": (ParamBox(F=1, f=("0.3125", "0.34375"), omega=1, l=0,
                                            r=(Fraction(62313, 1024), Fraction(73535, 1024))), 2, "saddle"),
    "x1 centre, w2R/F 19.1-22.5": (ParamBox(F=1, f=("0.3125", "0.34375"), omega=1, l=0,
                                            r=(Fraction(19555, 1024), Fraction(23075, 1024))), 1, "elliptic"),
}


@pytest.mark.benchmark(group="proved box")
@pytest.mark.parametrize("method", ["impacts", "shooting"])
@pytest.mark.parametrize("name", sorted(BOXES))
def test_bench_cover_one_box(benchmark, name, method):
    box, branch, kind = BOXES[name]
    got, _ = benchmark.pedantic(symmetric_cover, args=(box, branch),
                                kwargs=dict(kind=kind, max_leaves=512, method=method),
                                rounds=3, iterations=1)
    assert got.proved, got.reason
    other, _ = symmetric_cover(box, branch, kind=kind, max_leaves=512,
                               method="shooting" if method == "impacts" else "impacts")
    assert all(a.overlaps(b) for a, b in zip(got.hull(), other.hull()))
