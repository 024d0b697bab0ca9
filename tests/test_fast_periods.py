"""``fast.map_and_jacobian(periods=k)``: ``Phi^k`` and the chain rule in one call, the same bits
as ``k`` calls of one period (the atlas's Newton for period-3 and period-5 points uses it)."""
import numpy as np
import pytest

import fast
from reference.scene import Scene

SCENE = Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1)      # paper fig. many:2pi (c)


def _states():
    rng = np.random.default_rng(11)
    return rng.uniform(-1, 1, 40), rng.uniform(-6, 6, 40)


def test_k_periods_are_k_single_periods():
    x, v = _states()
    X, V, J, Z = fast.map_and_jacobian(SCENE, x, v, periods=3)
    xs, vs, Js, zs = x, v, [], np.zeros(x.shape, bool)
    for _ in range(3):
        xs, vs, Jj, zj = fast.map_and_jacobian(SCENE, xs, vs)
        Js.append(Jj)
        zs |= zj
    assert np.array_equal(X, xs) and np.array_equal(V, vs) and np.array_equal(Z, zs)
    X3, V3 = fast.stroboscopic_map(SCENE, x, v, periods=3)
    assert np.array_equal(X, X3) and np.array_equal(V, V3)
    chain = Js[2] @ (Js[1] @ Js[0])                         # later on the left
    assert np.array_equal(J, chain)
    wrong = Js[0] @ (Js[1] @ Js[2])                         # the check sees the order
    assert not np.allclose(J[np.isfinite(J).all(axis=(1, 2))], wrong[np.isfinite(J).all(axis=(1, 2))])


def test_one_period_is_the_default():
    x, v = _states()
    for a, b in zip(fast.map_and_jacobian(SCENE, x, v, periods=1), fast.map_and_jacobian(SCENE, x, v)):
        assert np.array_equal(a, b, equal_nan=True)


@pytest.mark.parametrize("periods, error", [(0, ValueError), (-1, ValueError), (1.5, ValueError),
                                           (None, TypeError)])
def test_bad_periods(periods, error):
    with pytest.raises(error, match="periods must be an integer >= 1"):
        fast.map_and_jacobian(SCENE, 0.1, 0.2, periods=periods)
