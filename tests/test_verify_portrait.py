"""verify's portrait under position forcing (issue 33): its shading classes the pixels on
``fast``'s coarse map first (``verify.portrait.PORTRAIT_STEPS`` steps a period) and again on the
default map wherever the coarse ``det Phi'`` is not clearly in a class
(``dynamics.portraits.area_classes``, ``claim_unit_det_clear``).  Wherever the default map
decides clearly, the portrait must give its class, on random scenes; at 16 steps a period the
coarse ``det`` alone is seen to change classes, and the second look puts them right."""
from __future__ import annotations

import numpy as np
from hypothesis import given, settings

from cross_check.dynamics import portraits as por
from cross_check.dynamics.periodic import AREA_TOL
from cross_check.tolerances import tol
from cross_check.verify import portrait, tasks
from reference.scene import Scene
from tests.strategies import position_forced_scenes


def _pixels(sc, n):
    """The centres of the portrait's ``n x n`` pixels over its window (``verify.portrait.png``)."""
    vmax = tasks.velocity_range(sc)
    X, V = portrait.pixel_centres((sc.float("l"), sc.float("r"), -vmax, vmax), n)
    return X.ravel(), V.ravel()


def _clear(det):
    """The states whose ``det`` the default map decides clearly (``claim_unit_det_clear``)."""
    c = tol("claim_unit_det_clear")
    return (np.abs(np.abs(det) - 1) <= c.atol) | (np.abs(det) < 1 - c.rtol)


@settings(max_examples=12, deadline=None)
@given(sc=position_forced_scenes(restitutions=("1", "0.8")))
def test_the_portrait_gives_every_pixel_the_default_maps_clear_class(sc):
    x, v = _pixels(sc, 12)
    want, det = por.area_classes(sc, x, v)
    got, _ = por.area_classes(sc, x, v, steps=portrait.PORTRAIT_STEPS)
    clear = _clear(det)
    assert list(got[clear]) == list(want[clear])


def test_a_map_too_coarse_changes_classes_and_the_second_look_puts_them_right():
    """At 16 steps a period the truncation reaches ``det`` on ``Omega_pres`` (measured on the
    120 x 120 pixels of this scene: ``|det - 1|`` up to 3.9e-9, 2,391 classes change)."""
    sc = Scene(F=1, f="0.2", omega=1, l=-1, r=1, wavenumber=1, name="test: portrait steps")
    x, v = _pixels(sc, 30)
    want, det = por.area_classes(sc, x, v)
    coarse = por._det(sc, x, v, 16)
    assert ((np.abs(np.abs(coarse) - 1) <= AREA_TOL) != (want == "pres")).sum() > 0
    clear = _clear(det)
    got, _ = por.area_classes(sc, x, v, steps=16)
    assert list(got[clear]) == list(want[clear])


def _orbit_starts(sc):
    """The starts of the portrait's orbits (``verify.portrait._orbits``)."""
    l, r, vmax = sc.float("l"), sc.float("r"), tasks.velocity_range(sc)
    gx, gv = por.grid_starts((l, r, -vmax, vmax), 9, 9, l, r)
    return np.clip(gx, l, r), gv


@settings(max_examples=12, deadline=None)
@given(sc=position_forced_scenes())
def test_the_portraits_orbits_move_by_far_less_than_a_pixel_a_period(sc):
    """One period of the drawn orbits on ``fast``'s map at ``PORTRAIT_ORBIT_STEPS`` lies within a
    hundredth of a pixel (the 120 x 120 grid of the full portrait) of the default map's."""
    import fast

    x0, v0 = _orbit_starts(sc)
    want = fast.stroboscopic_map(sc, x0, v0)
    got = fast.stroboscopic_map(sc, x0, v0, steps_per_period=portrait.PORTRAIT_ORBIT_STEPS)
    pixel = np.array([sc.float("r") - sc.float("l"), 2 * tasks.velocity_range(sc)]) / tasks.FULL.pixels
    for a, b, p in zip(got, want, pixel):
        assert np.abs(np.asarray(a) - np.asarray(b)).max() <= p / 100


def test_the_orbits_are_iterated_on_the_coarse_map_asked_for():
    """``run_orbits(steps=S)`` is ``fast``'s map at ``S`` steps a period, iterate for iterate
    (not the default map, which differs from it in the last digits)."""
    import fast

    sc = Scene(F=2, f=0, omega="0.5", l=-1, r=1, wavenumber=2, name="test: portrait orbit steps")
    x0, v0 = _orbit_starts(sc)
    xs, vs, _ = por.run_orbits(sc, x0, v0, 3, steps=portrait.PORTRAIT_ORBIT_STEPS)
    x, v = x0, v0
    for k in range(3):
        x, v = fast.stroboscopic_map(sc, x, v, steps_per_period=portrait.PORTRAIT_ORBIT_STEPS)
        assert np.array_equal(xs[k + 1], x) and np.array_equal(vs[k + 1], v)
    default, _, _ = por.run_orbits(sc, x0, v0, 1)
    assert not np.array_equal(default[1], xs[1])
