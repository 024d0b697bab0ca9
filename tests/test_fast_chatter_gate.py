"""fast's impact handler skips the chatter test above a per-scene speed ``U_CHATTER``
(``fast.params.chatter_speed``): the skip must never hide a tail that ``chatter()`` would sum.
Checked on random scenes, pushes and speeds against ``fast.handlers.chatter`` itself, and
seen to fail: far below the gate ``chatter()`` does sum tails, and with the gate 64 times too
low 257 of 300 random impacts just above it would have been summed."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from fast import handlers
from fast import params as fp
from fast import state as fs
from reference.scene import Scene

scales = st.floats(0.05, 20.0)


def scene_and_push(F, f_ratio, w, gap, push):
    sc = Scene(F=repr(F), f=repr(F * f_ratio), omega=repr(w), l="0", r=repr(gap))
    P = fp.params(sc)
    f = P[fp.FF]
    return P, f + (F - f) * push          # a push s A in (f, F]


def chatter_says(P, pu, u, side):
    """``chatter()``'s answer after an impact at wall ``side`` with push ``pu`` and speed ``u``
    (-1: not summed), on a fresh state with room for a few events."""
    state = np.zeros(fs.PATHS + 1)
    state[fs.CAP] = 4
    trig = np.array([0.0, 0.0, 1.0, 0.0])
    return handlers.chatter(P, state, 0.0, 0.0, side, side * pu, trig, u, P[fp.T], False,
                            np.zeros(6 * 4))


@settings(max_examples=200, deadline=None)
@given(F=scales, f_ratio=st.just(0.0) | st.floats(1e-3, 0.95), w=scales, gap=scales, push=st.floats(0.01, 1.0),
       over=st.floats(1.0 + 1e-12, 1e3), side=st.sampled_from([-1.0, 1.0]))
def test_no_tail_is_summed_above_the_gate(F, f_ratio, w, gap, push, over, side):
    P, pu = scene_and_push(F, f_ratio, w, gap, push)
    u = P[fp.U_CHATTER] * over
    assert chatter_says(P, pu, u, side) == -1, (P[fp.U_CHATTER], u, pu)


@pytest.mark.parametrize("F, f, w, gap", [(1.0, 0.1, 1.0, 2.0), (1.0, 0.3, 6.283185307179586, 1.0)])
def test_far_below_the_gate_tails_are_summed(F, f, w, gap):
    """The check above can fail: at speeds far below the gate chatter() sums the tail."""
    P, pu = scene_and_push(F, f / F, w, gap, 0.9)
    assert P[fp.U_CHATTER] > 0
    assert chatter_says(P, pu, P[fp.U_CHATTER] * 1e-9, 1.0) != -1
