"""reference.enclosure.series: the flow derivative's columns over a box from the centre's series
and a gradient bound (``Field.sin_gradient``, ``Field.variational_near``; issue 33).

Every check is against the box's own recurrence (``Field.series`` over balls, the code path the
Lohner step used before) or against point series at starts drawn inside the box -- exact
dyadic starts, so that a point's balls are pinned to the working precision -- and each is seen
to fail: a gradient off by a factor, or no gradient at all, leaves a point of the box outside.
"""
import random

import pytest
from flint import arb
from hypothesis import given, settings, strategies as st

from cross_check.tolerances import tol
from reference.enclosure.balls import BallModel, workprec
from reference.enclosure.series import Field
from tests.strategies import position_forced_scenes

PREC = 128
#: orders of the columns (the Lohner step's ``q``: half of 22 at 64 bits, all of 68 at 192)
ORDER = 14


def _field(scene, s):
    return Field(BallModel(scene), s if scene.has("friction") else 0)


def _box(centre, r):
    return [arb(c, r) for c in centre]


def _gradient_over(field, t, box, order):
    """``sin_gradient`` over ``box`` at the time ``t``, from the box's own series."""
    _, C, S, P = field.trig_series(t, box[0], box[1], order + 2)
    return field.sin_gradient(C, field.variational(S, P, order + 1), order)


def _points(centre, r, rng, n=3):
    """Dyadic starts inside the box of half-width ``r`` about ``centre`` (at most
    ``1023/1024 r`` away: the float sum's rounding, below ``2^-52 |c|``, cannot carry them out
    for ``r >= 2^-40``)."""
    return [[c + r * (rng.randrange(-1023, 1024) / 1024) for c in centre] for _ in range(n)]


@st.composite
def _cases(draw):
    scene = draw(position_forced_scenes())
    x = draw(st.floats(-1.0, 1.0)) * min(abs(float(scene.l)), abs(float(scene.r)), 1.0)
    v = draw(st.floats(-3.0, 3.0))
    t = draw(st.floats(0.0, 6.0))
    r = 2.0 ** -draw(st.integers(8, 40))
    return scene, draw(st.sampled_from((1, -1))), t, (x, v), r, draw(st.integers(0, 2**31))


def _overlaps_all(a, b):
    return all(x.overlaps(y) for x, y in zip(a, b))


@settings(max_examples=25, deadline=None)
@given(_cases())
def test_the_gradient_bound_holds_the_difference_of_two_starts(case):
    """Mean value theorem: for starts ``z0, z1`` of a box, ``S_n(z1) - S_n(z0)`` is
    ``grad S_n(xi) . (z1 - z0)`` for a ``xi`` of the box, so it lies in the gradient's balls over
    the box times ``z1 - z0``; at every order below ``ORDER``, on random scenes with every
    effect."""
    scene, s, t, centre, r, seed = case
    rng = random.Random(seed)
    with workprec(PREC):
        fl, tb = _field(scene, s), arb(t)
        dS = _gradient_over(fl, tb, _box(centre, r), ORDER)
        z0, z1 = _points(centre, r, rng, 2)
        S0 = fl.trig_series(tb, arb(z0[0]), arb(z0[1]), ORDER + 1)[2]
        S1 = fl.trig_series(tb, arb(z1[0]), arb(z1[1]), ORDER + 1)[2]
        d = [arb(z1[i]) - arb(z0[i]) for i in range(2)]
        for n in range(ORDER):
            assert (S1[n] - S0[n]).overlaps(dS[0][n] * d[0] + dS[1][n] * d[1]), (n, scene)


@settings(max_examples=25, deadline=None)
@given(_cases())
def test_the_columns_near_the_centre_hold_every_start_of_the_box(case):
    """``variational_near`` from the centre's ``S`` and the gradient over a larger box of starts
    and times (as the Lohner step has it: its a priori box) holds the columns of point starts
    drawn in the box, and overlaps the columns of the box's own recurrence, at most
    ``near_columns_width_factor`` times as wide, plus the working precision."""
    scene, s, t, centre, r, seed = case
    rng = random.Random(seed)
    with workprec(PREC):
        fl, tb = _field(scene, s), arb(t)
        big = _box(centre, 4 * r)
        dS = _gradient_over(fl, tb + arb(0, r), big, ORDER)          # times [t - r, t + r]
        m = [arb(c) for c in centre]
        _, _, S, P = fl.trig_series(tb, m[0], m[1], ORDER + 1)
        box = _box(centre, r)
        near = fl.variational_near(S, P, dS, [box[i] - m[i] for i in range(2)], ORDER)
        for z in _points(centre, r, rng):
            _, point = fl.series(tb, arb(z[0]), arb(z[1]), ORDER + 1, ORDER)
            for col_near, col_point in zip(near, point):
                assert _overlaps_all(col_near, col_point), (z, scene)
        _, own = fl.series(tb, box[0], box[1], ORDER + 1, ORDER)
        for col_near, col_own in zip(near, own):
            assert _overlaps_all(col_near, col_own)
            for a, b in zip(col_near, col_own):
                slack = abs(b.mid()) * arb(2) ** (8 - PREC) + arb(2) ** -PREC
                assert a.rad() <= tol("near_columns_width_factor").rtol * b.rad() + slack


@pytest.mark.parametrize("wrong", ["half the gradient", "no gradient", "the other column"])
def test_a_wrong_gradient_leaves_a_start_of_the_box_outside(wrong):
    """The same check refuses a gradient halved, a zero gradient (the centre's columns alone) and
    the gradient's two columns swapped: some corner of a box ``2^-10`` by ``2^-16`` falls
    outside, where the right gradient holds all four (exact corners: dyadic centre and radii)."""
    from reference.scene import Scene

    scene = Scene(F=2, f="0.3", omega="1.2", l=-1, r=1, damping="0.05", wavenumber="0.7")
    centre, radii, t = (0.25, 0.8), (2.0 ** -10, 2.0 ** -16), arb("0.4")
    with workprec(PREC):
        fl = _field(scene, 1)
        box = [arb(c, r) for c, r in zip(centre, radii)]
        right = _gradient_over(fl, t, box, ORDER)
        m = [arb(c) for c in centre]
        _, _, S, P = fl.trig_series(t, m[0], m[1], ORDER + 1)
        corners = [(arb(centre[0] + sx * radii[0]), arb(centre[1] + sv * radii[1]))
                   for sx in (-1, 1) for sv in (-1, 1)]
        points = [fl.series(t, z[0], z[1], ORDER + 1, ORDER)[1] for z in corners]

        def outside(dS):
            near = fl.variational_near(S, P, dS, [box[i] - m[i] for i in range(2)], ORDER)
            return sum(not all(_overlaps_all(a, b) for a, b in zip(near, pt)) for pt in points)

        assert outside(right) == 0
        dS = {"half the gradient": [[g / 2 for g in col] for col in right],
              "no gradient": [[arb(0)] * ORDER] * 2,
              "the other column": [right[1], right[0]]}[wrong]
        assert outside(dS), wrong


def test_sin_gradient_and_variational_near_check_their_orders():
    """The columns and ``C`` must reach the order asked for."""
    from reference.scene import Scene

    scene = Scene(F=1, f="0.1", omega=2, l=-1, r=1, wavenumber="1.5")
    with workprec(64):
        fl = _field(scene, 1)
        _, C, S, P = fl.trig_series(arb(0), arb("0.1"), arb(1), 6)
        cols = fl.variational(S, P, 5)
        with pytest.raises(ValueError, match="order"):
            fl.sin_gradient(C, cols, 7)
        with pytest.raises(ValueError, match="order"):
            fl.variational_near(S, P, fl.sin_gradient(C, cols, 5), [arb(0), arb(0)], 6)
