"""The league's peer adapters (``cross_check.league.peers``): one smoke case per installed peer on
golden cases, skipped with the reason when the library is absent (every peer is optional).

Each smoke case checks what the adapter's docstring promises on cases whose answer the golden
data gives: digits within the scorecard's flag line (``score_flag``) at a tight tolerance and the
golden itinerary for the event-finding peers; MuJoCo within its first-order bound on flights
without an impact (``peer_mujoco_flight``).  diffrax is run once per module (its compilation is
the cost: ~5 CPU seconds).
"""
import math
import pickle
import subprocess
import sys

import numpy as np
import pytest

from cross_check.agreement import compare
from cross_check.score import score
from cross_check.score.adapters import canonical_log
from cross_check.score.golden import golden_scene, scene_cases
from cross_check.tolerances import tol

SCENE = "fig:many:2pi/f=0.2"
#: golden cases of SCENE: two smooth flights with turns, an impact, a stick and its slip, a chatter run
#: into wall contact and its release
NAMES = ("sample-0", "sample-2", "sample-1", "sample-5", "chatter")


def _cases(names=NAMES, scene=SCENE):
    by_name = {c.name: c for c in scene_cases(scene)}
    return [by_name[n] for n in names]


def _arrays(cases):
    return np.array([c.x for c in cases]), np.array([c.v for c in cases])


def _assert_map_and_itinerary(adapter, cases):
    X, V = _arrays(cases)
    xs, vs = adapter.step(cases[0].params, X, V, 1)
    for c, a, b in zip(cases, xs, vs):
        err, _ = c.map_error(a, b)
        assert err <= tol("score_flag").rtol, (adapter.name, c.id, err)
    logs = adapter.events(cases[0].params, X, V)
    sc = golden_scene(SCENE)
    for c, log in zip(cases, logs):
        assert [e.kind for e in canonical_log(log, sc)] == [e[0] for e in c.events], (adapter.name, c.id, log)
    return xs, vs


# --- SUNDIALS CVODE --------------------------------------------------------------------------
def test_sundials_bdf_and_adams_on_golden_cases():
    pytest.importorskip("sksundae", reason="scikit-sundae is optional (pip install 'vibro-impact-vv[peers]'): "
                                           "the SUNDIALS peer is skipped")
    from cross_check.league.peers.sundials import SundialsAdapter
    for method in ("Adams", "BDF"):
        _assert_map_and_itinerary(SundialsAdapter(method, 1e-12), _cases())


def test_sundials_settings_are_checked_and_pickle():
    from cross_check.league.peers.sundials import SundialsAdapter
    with pytest.raises(ValueError, match="method"):
        SundialsAdapter("RK45", 1e-9)
    with pytest.raises(ValueError, match="rtol"):
        SundialsAdapter("BDF", 1e-16)
    a = pickle.loads(pickle.dumps(SundialsAdapter("BDF", 1e-9)))
    assert (a.method, a.rtol, a.name) == ("BDF", 1e-9, "sundials BDF rtol 1e-09")


# --- diffrax -----------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def dopri8():
    pytest.importorskip("diffrax", reason="diffrax is optional (pip install 'vibro-impact-vv[peers]'): "
                                          "the diffrax peer is skipped")
    from cross_check.league.peers.jaxdiffrax import DiffraxAdapter
    return DiffraxAdapter("Dopri8", 1e-12)


def test_diffrax_on_golden_cases_and_batch_independent(dopri8):
    cases = _cases()
    xs, vs = _assert_map_and_itinerary(dopri8, cases)
    # every start gives the same bits alone as in the batch (the last flight is solved without an
    # event: with one, a start's end depends on the batch's other starts)
    X, V = _arrays(cases)
    for i, c in enumerate(cases):
        x1, v1 = dopri8.step(c.params, X[i:i + 1], V[i:i + 1], 1)
        assert (x1[0], v1[0]) == (xs[i], vs[i]), c.id
    assert dopri8.events(cases[0].params, X[:0], V[:0]) == []


def test_diffrax_module_leaves_jax_alone_until_it_runs():
    """Importing the adapter does not import jax (so float64 is switched on only where it runs)."""
    code = ("import sys, cross_check.league.peers.jaxdiffrax as d; d.DiffraxAdapter('Tsit5', 1e-9); "
            "assert 'jax' not in sys.modules, 'jax imported'")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr[-2000:]


def test_diffrax_settings_are_checked():
    from cross_check.league.peers.jaxdiffrax import DiffraxAdapter
    with pytest.raises(ValueError, match="solver"):
        DiffraxAdapter("Euler", 1e-9)
    with pytest.raises(ValueError, match="rtol"):
        DiffraxAdapter("Tsit5", 1.0)


# --- MuJoCo ------------------------------------------------------------------------------------
def test_mujoco_slide_within_its_first_order_bound():
    pytest.importorskip("mujoco", reason="mujoco is optional (pip install 'vibro-impact-vv[peers]'): "
                                         "the MuJoCo peer is skipped")
    from cross_check.league.peers.mujoco_slide import MujocoSlideAdapter
    dt = 1e-3
    for scene in (SCENE, "effect:damping"):
        cases = [c for c in scene_cases(scene) if c.kind in ("smooth flight", "damping") and not c.band
                 and not any(e[0] == "impact" for e in c.events)]
        p = cases[0].params
        xs, vs = MujocoSlideAdapter(dt).step(p, *_arrays(cases), 1)
        bound = tol("peer_mujoco_flight").rtol * (2 * math.pi / p["omega"]) * (p["F"] + p["f"]) * dt
        for c, a, b in zip(cases, xs, vs):
            assert c.map_error(a, b)[0] <= bound, (c.id, c.map_error(a, b)[0], bound)
    # an impact is a ten-step spring: a few digits, not float64 (what the league shows)
    (c,) = _cases(("sample-1",))
    x, v = MujocoSlideAdapter(dt).step(c.params, *_arrays([c]), 1)
    assert 1e-6 < c.map_error(x[0], v[0])[0] < 0.1


def test_mujoco_unstable_spring_raises_instead_of_a_reset_state(monkeypatch, tmp_path):
    """A wall spring too stiff for the step blows up; MuJoCo then resets the state (time 0, x 0)
    with a warning: ``step`` sees the time and raises, never returns the reset state."""
    pytest.importorskip("mujoco", reason="mujoco is optional (pip install 'vibro-impact-vv[peers]'): "
                                         "the MuJoCo peer is skipped")
    from cross_check.league.peers import mujoco_slide
    monkeypatch.setattr(mujoco_slide, "CONTACT_STEPS", 0.3)      # dt sqrt(K) = 10: past Euler's bound 2
    monkeypatch.chdir(tmp_path)          # MuJoCo appends its warning to MUJOCO_LOG.TXT in the working directory
    (c,) = _cases(("sample-1",))
    with pytest.raises(RuntimeError, match="stopped early"):
        mujoco_slide.MujocoSlideAdapter(1e-3).step(c.params, *_arrays([c]), 1)


def test_mujoco_declares_what_it_models():
    from cross_check.league.peers.mujoco_slide import EFFECTS, MujocoSlideAdapter
    assert {"restitution", "position_forcing"}.isdisjoint(EFFECTS)
    assert not hasattr(MujocoSlideAdapter, "events") and not hasattr(MujocoSlideAdapter, "jacobian")
    with pytest.raises(ValueError, match="dt"):
        MujocoSlideAdapter(0.5)
    # the scorer skips and lists the scenes it does not model (no call made)
    card = score(MujocoSlideAdapter(1e-3), scenes=["effect:restitution", "fig:xpotno"], periods=(1,))
    assert set(card.skipped) == {"effect:restitution", "fig:xpotno"} and card.cases == []


# --- the shipped engines at the league's settings --------------------------------------------
def test_heyoka_setting_pickles_and_builds_in_the_worker():
    pytest.importorskip("heyoka", reason="heyoka.py is optional (pip install heyoka): its adapter is skipped")
    from cross_check.league.peers.shipped import heyoka_adapter
    a = pickle.loads(pickle.dumps(heyoka_adapter(1e-12)))
    assert a.flight._flight is None
    (c,) = _cases(("sample-1",))
    x, v = a.step(c.params, *_arrays([c]), 1)
    assert c.map_error(x[0], v[0])[0] <= tol("score_grade_b").rtol


def test_fast_settings_give_the_same_bits():
    from cross_check.league.peers.shipped import FastSetting
    cases = scene_cases(SCENE)
    X, V = _arrays(cases)
    p = cases[0].params
    one, two, jac = (FastSetting(1).step(p, X, V, 1), FastSetting(2).step(p, X, V, 1),
                     FastSetting(1, jacobian=True).step(p, X, V, 1))
    for a, b in ((one, two), (one, jac)):
        np.testing.assert_array_equal(a[0], b[0])
        np.testing.assert_array_equal(a[1], b[1])
    assert compare.digits(float(one[0][0]), cases[0].phi_mpf()[0]) >= 15
