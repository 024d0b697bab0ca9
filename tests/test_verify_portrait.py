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
