"""The per-core benchmark's baseline is a real kernel (issue 27): the plain float64 event
loop of ``tests/benchmarks/plain_kernel.py`` -- fast's physics and certified search without
double-double, log, Jacobian or state record, written apart from ``fast`` -- agrees with
``fast`` within ``plain_kernel_vs_fast`` on the well-conditioned states of both benchmark
scenes (the benchmark asserts it on 1e5 states; this keeps it checked in every run), and
the check is seen to fail on a kernel run with the wrong friction."""
import numpy as np
import pytest

from tests.benchmarks import plain_kernel as pk
from tests.benchmarks.test_bench_fast import SCENES, _batch
from tests.benchmarks.test_bench_per_core import disagreement, plain_constants

N = 2000


def _plain(K, x, v):
    out = np.empty(x.size), np.empty(x.size), np.empty(x.size, np.int64)
    pk.strobe(K, x, v, *out)
    return out


@pytest.mark.parametrize("name", list(SCENES))
def test_plain_kernel_agrees_with_fast(name):
    scene, x, v = _batch(name, N)
    compared, problem = disagreement(scene, x, v, *_plain(plain_constants(scene), x, v))
    assert problem is None, problem
    assert compared > 0.99


def test_agreement_check_fails_on_a_wrong_kernel():
    """1% more friction in the plain kernel: the check must say no."""
    scene, x, v = _batch("narrow", N)
    K = plain_constants(scene)
    K[1] *= 1.01
    compared, problem = disagreement(scene, x, v, *_plain(K, x, v))
    assert problem is not None and "disagree" in problem
