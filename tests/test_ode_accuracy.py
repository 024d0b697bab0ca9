"""fast under position forcing against the reference at 30 digits (issue 33).

The measure is the golden tests' (``golden_fast_phi_per_cond``): a state's one-period error,
the max over ``x, v`` of ``|fast - ref| / max(1, |ref|)``, over its conditioning ``eps max(1,
max |Phi'_ij|)`` (``eps = 2^-52``, ``Phi'`` the reference's).  Over a batch of states of one
scene its mean is within ``fast_xpot_per_cond_mean`` and its max within
``fast_xpot_per_cond_max``:

* on random scenes (hypothesis over the wavenumber, damping, restitution, friction, walls,
  ``F`` and ``omega``: ``tests.strategies.position_forced_scenes``), two in the default run
  (a few seconds) and more under ``slow``;
* on every position-forced input of the shipped golden data (its values are the reference's).

Events as for the closed-form effects (``tests/test_golden.py``): the canonical itinerary is
the reference's outside the near-grazing band (``compare.reference_in_band``), and each event
time is within ``golden_fast_phi_per_cond`` times the conditioning.
"""
from __future__ import annotations

import json

import mpmath
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import fast
import reference
from cross_check import golden, scenes
from cross_check.agreement import compare
from cross_check.agreement.case import Case
from cross_check.tolerances import tol
from tests.strategies import fast_batches, position_forced_scenes

EPS = 2.0 ** -52
DPS = 30
#: the conditioning needs a digit, not thirty
JAC_DPS = 20


def _per_cond(fx, fv, ref, jmax):
    """The state's error over its conditioning (module docstring)."""
    with mpmath.workdps(DPS + 10):
        err = max(abs(mpmath.mpf(a) - mpmath.mpf(b)) / max(1, abs(mpmath.mpf(b)))
                  for a, b in ((fx, ref[0]), (fv, ref[1])))
    return float(err) / (EPS * jmax)


def _event_problems(where, fast_evs, ref_evs, jmax):
    """Event times of a common itinerary beyond ``golden_fast_phi_per_cond`` x conditioning."""
    rt = tol("golden_fast_phi_per_cond").rtol * jmax
    out = []
    with mpmath.workdps(DPS + 10):
        for e, g in zip(fast_evs, ref_evs):
            t, tr = mpmath.mpf(e.t), mpmath.mpf(g.t)
            if e.kind != "chatter" and not abs(t - tr) <= rt * max(1, abs(tr)):
                out.append(f"{where}: {e.kind} at t = {e.t!r}, reference {mpmath.nstr(tr, 20)}")
    return out


def _check_batch(scene, x, v):
    """``(errors, problems)`` of fast on the float64 states ``x, v`` against the reference."""
    X, V = fast.stroboscopic_map(scene, x, v)
    logs = compare.fast_events(scene, x, v)
    with mpmath.workdps(DPS):
        period = 2 * mpmath.pi / scene.mpf("omega")
    errs, problems = [], []
    for i in range(x.size):
        case = Case(f"state {i}", repr(float(x[i])), repr(float(v[i])), "float64", "")
        log = reference.trajectory(scene, float(x[i]), float(v[i]), period, dps=DPS)
        ref_evs = compare.canonical([compare.Event(e.kind, e.t, e.x, e.v, e.v_before, e.count)
                                     for e in log], scene)
        fast_evs = compare.canonical(logs[i], scene)
        if [e.kind for e in fast_evs] != [e.kind for e in ref_evs]:
            if not compare.reference_in_band(scene, case, dps=DPS):
                problems.append(f"{case.name} ({x[i]!r}, {v[i]!r}): itinerary "
                                f"{[e.kind for e in fast_evs]} != {[e.kind for e in ref_evs]}")
            continue                  # in the near-grazing band: no itinerary to hold it to
        J = reference.jacobian(scene, float(x[i]), float(v[i]), dps=JAC_DPS)
        jmax = max(1.0, max(abs(float(J[a][b])) for a in range(2) for b in range(2)))
        errs.append(_per_cond(X[i], V[i], (log.x_end, log.v_end), jmax))
        problems += _event_problems(f"{case.name} ({x[i]!r}, {v[i]!r})", fast_evs, ref_evs, jmax)
    return np.array(errs), problems


def _assert_within(scene, errs, problems):
    mean, worst = tol("fast_xpot_per_cond_mean").rtol, tol("fast_xpot_per_cond_max").rtol
    assert not problems, "\n".join(problems)
    assert errs.size, f"{scene}: every state in the near-grazing band"
    assert errs.mean() <= mean and errs.max() <= worst, (
        f"{scene}: error over conditioning mean {errs.mean():.2f} (bound {mean}), max "
        f"{errs.max():.2f} (bound {worst}); per state {np.round(errs, 2).tolist()}")


def _run(data, n):
    scene = data.draw(position_forced_scenes(), label="scene")
    x, v = data.draw(fast_batches(scene, n, 2 * scene.float("F") / scene.float("omega")), label="states")
    _assert_within(scene, *_check_batch(scene, x, v))


@settings(max_examples=2)
@given(st.data())
def test_error_over_conditioning_on_random_scenes(data):
    _run(data, 6)


@pytest.mark.slow
@settings(max_examples=25)
@given(st.data())
def test_error_over_conditioning_on_random_scenes_many(data):
    """25 scenes x 16 states (~2 min)."""
    _run(data, 16)


POSITION_FORCED = [name for name in scenes.SCENES if scenes.scene(name).has("position_forcing")]


@pytest.mark.parametrize("name", POSITION_FORCED)
def test_error_over_conditioning_on_golden_inputs(name):
    """Every float64 input of the shipped golden data outside the band, against its golden
    values (the reference's at 40 digits)."""
    sc = scenes.scene(name)
    data = json.loads((golden.DEFAULT_DIR / (scenes.slug(name) + ".json")).read_text())
    rows = [(case["name"], inp) for case in data["cases"] for label, inp in case["inputs"].items()
            if (label != "exact" or case["exact"] == "float64") and not inp["band"]]
    X = np.array([float(inp["x"]) for _, inp in rows])
    V = np.array([float(inp["v"]) for _, inp in rows])
    FX, FV = fast.stroboscopic_map(sc, X, V)
    errs = [_per_cond(FX[i], FV[i], inp["phi"],
                      max(1.0, max(abs(float(q)) for r in inp["jacobian"] for q in r)))
            for i, (_, inp) in enumerate(rows)]
    _assert_within(sc, np.array(errs), [])
