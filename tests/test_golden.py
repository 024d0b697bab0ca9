"""Golden-data regression: both integrators against the shipped golden data, cross_check/data/golden/ (cross_check.golden).

Each golden file holds the reference's answers at 40 digits (dps 90, checked at dps 110) for
the states of interest of one scene.  Tolerances come from cross_check/tolerances.py:

* reference at dps 50: ``golden_reference_state`` for Phi and event times/states,
  ``golden_reference_jacobian`` x kappa for the Jacobian (kappa: grazing conditioning),
  ``golden_reference_chatter_time`` for accumulation points of chatter;
* fast (float64): same canonical itinerary unless the golden file marks the float64 input as
  in the near-grazing band (``band``: the reference itinerary flips under a few-ulp move);
  Phi within ``golden_fast_phi_per_cond`` x max(1, |J|) (forward error = condition x
  backward error), event times likewise, Jacobian within ``golden_fast_jacobian_per_kappa``
  x kappa^2 x max(1, |J|); states in the band are held to nothing but are counted.

Enclosures (issue 17): every written digit of a proved input lies in its proved ball (up to the
rounding of its last written digit).  Every input is proved (issue 25: position forcing too),
or it is listed in ``UNPROVED`` with the reason no proof can exist -- the list is empty.

Comparisons follow ``assert_allclose`` (reference as ``desired``) with errors scaled by
``max(1, |desired|)``.
"""
from __future__ import annotations

import json
import math

import mpmath
import numpy as np
import pytest

from cross_check.agreement import compare
from cross_check import golden, scenes
from cross_check.tolerances import tol

FILES = {name: golden.DEFAULT_DIR / (scenes.slug(name) + ".json") for name in scenes.SCENES}


def _load(name):
    return json.loads(FILES[name].read_text())


def _within(actual, desired, rtol) -> bool:
    with mpmath.workdps(60):
        a, d = mpmath.mpf(actual), mpmath.mpf(desired)
        return bool(abs(a - d) <= rtol * max(1, abs(d)))


def _kappa(sc, events) -> float:
    unit = max(sc.float("F") / sc.float("omega"), sc.float("f") / sc.float("omega"), 1e-300)
    vb = [abs(float(e[4])) for e in events if e[0] == "impact" and e[4] is not None and float(e[4]) != 0]
    return max([1.0] + [unit / v for v in vb])


def _inputs(name):
    for case in _load(name)["cases"]:
        for label, inp in case["inputs"].items():
            exact = case["exact"] if label == "exact" else "float64"
            yield case, label, inp, scenes.Case(case["name"], inp["x"], inp["v"], exact, case["how"])


def test_every_scene_has_one_golden_file_of_modest_size():
    missing = [n for n, p in FILES.items() if not p.exists()]
    assert not missing, f"no golden file for {missing}; run `python -m cross_check golden`"
    total = sum(p.stat().st_size for p in FILES.values())
    assert total < 2 * 1024 * 1024, f"golden data is {total / 1e6:.1f} MB (budget 2 MB)"
    for name in FILES:
        data = _load(name)
        assert data["scene"]["name"] == name
        assert data["provenance"]["dps"] == golden.GOLDEN_DPS
        assert data["provenance"]["digits"] == golden.DIGITS


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_scene_parameters_recorded_exactly(name):
    sc, rec = scenes.scene(name), _load(name)["scene"]
    for k in ("F", "f", "omega", "l", "r"):
        assert rec[k] == str(getattr(sc, k)), k


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_reference_matches_golden(name):
    sc = scenes.scene(name)
    t_state = tol("golden_reference_state").rtol
    t_jac = tol("golden_reference_jacobian").rtol
    t_chat = tol("golden_reference_chatter_time").rtol
    for case, label, inp, c in _inputs(name):
        where = f"{name}/{case['name']}/{label}"
        phi = compare.ref_map(sc, c, 1, 50)
        assert _within(phi[0], inp["phi"][0], t_state) and _within(phi[1], inp["phi"][1], t_state), where
        evs = compare.canonical(compare.ref_events(sc, c, None, 50), sc)
        assert [e.kind for e in evs] == [e[0] for e in inp["events"]], where
        for e, g in zip(evs, inp["events"]):
            rt = t_chat if e.kind == "chatter" else t_state
            assert all(_within(a, d, rt) for a, d in ((e.t, g[1]), (e.x, g[2]), (e.v, g[3]))), (where, e.kind, g[1])
        if inp["jacobian"] is not None:
            J = compare.ref_jacobian(sc, c, 50)
            k = _kappa(sc, inp["events"])
            for i in range(2):
                for j in range(2):
                    assert _within(J[i][j], inp["jacobian"][i][j], t_jac * k), (where, i, j)


def _fast_batch(name):
    rows = [(case, label, inp, c) for case, label, inp, c in _inputs(name) if c.exact == "float64"]
    X = np.array([c.float()[0] for *_, c in rows])
    V = np.array([c.float()[1] for *_, c in rows])
    return rows, X, V


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_fast_matches_golden(name):
    sc = scenes.scene(name)
    rows, X, V = _fast_batch(name)
    fx, fv = compare.fast_map(sc, X, V)
    fJ = compare.fast_jacobian(sc, X, V)
    f_evs = compare.fast_events(sc, X, V)
    t_phi = tol("golden_fast_phi_per_cond").rtol
    t_jac = tol("golden_fast_jacobian_per_kappa").rtol
    problems = []
    for i, (case, label, inp, _) in enumerate(rows):
        where = f"{case['name']}/{label}"
        if inp["band"]:
            continue    # near-grazing band: the exact itinerary is ambiguous at float64 resolution
        kinds = [e.kind for e in compare.canonical(f_evs[i], sc)]
        if kinds != [e[0] for e in inp["events"]]:
            problems.append(f"{where}: itinerary {kinds} != golden {[e[0] for e in inp['events']]}")
            continue
        jmax = 1.0 if inp["jacobian"] is None else max(1.0, max(abs(float(v)) for r in inp["jacobian"] for v in r))
        if not (_within(fx[i], inp["phi"][0], t_phi * jmax) and _within(fv[i], inp["phi"][1], t_phi * jmax)):
            problems.append(f"{where}: Phi {fx[i]!r}, {fv[i]!r} vs {inp['phi']} (cond {jmax:.1e})")
        # an event time is conditioned by Phi' and, for an impact, by 1/|v-| (kappa): where the
        # force vanishes at the wall (eq. xpot) a grazing impact leaves Phi' ~ 1 (its saltation
        # 2A/v- is 0) while its time still moves by the position's error over the speed
        cond_t = max(jmax, _kappa(sc, inp["events"]))
        for e, g in zip(compare.canonical(f_evs[i], sc), inp["events"]):
            if e.kind != "chatter" and not _within(e.t, g[1], t_phi * cond_t):
                problems.append(f"{where}: {e.kind} at t={e.t!r} vs {g[1]} (cond {cond_t:.1e})")
        if inp["jacobian"] is not None:
            k = _kappa(sc, inp["events"]) ** 2 * jmax
            for a, b in zip(fJ[i].ravel(), [v for r in inp["jacobian"] for v in r]):
                if not _within(a, b, t_jac * k):
                    problems.append(f"{where}: Jacobian entry {a!r} vs {b} (kappa {k:.1e})")
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("name", ["fig:many:wide/f=0.3", "fig:resonance/R=0.8932", "fold/near"])
def test_fast_chatter_time_matches_golden(name):
    """Accumulation points of chatter (compared apart: fast's t_inf is the weakest number)."""
    sc = scenes.scene(name)
    rows, X, V = _fast_batch(name)
    f_evs = compare.fast_events(sc, X, V)
    rt = tol("golden_fast_chatter_time").rtol
    checked = 0
    for i, (case, label, inp, _) in enumerate(rows):
        ours = [e for e in compare.canonical(f_evs[i], sc) if e.kind == "chatter"]
        theirs = [g for g in inp["events"] if g[0] == "chatter"]
        for e, g in zip(ours, theirs):
            checked += 1
            assert _within(e.t, g[1], rt), f"{case['name']}/{label}: t_inf {e.t!r} vs {g[1]}"
    assert checked, f"no chatter event in {name}'s golden data"


def _assert_regenerates(name):
    committed = FILES[name].read_text()
    data = golden.scene_file(name, golden.N_SAMPLE)
    # The provenance records the mpmath that made the committed files; a newer mpmath
    # (or another integer backend) must reproduce every other byte, numbers included.
    recorded = json.loads(committed)["provenance"]
    for key in ("mpmath", "mpmath_backend"):
        data["provenance"][key] = recorded[key]
    assert golden.dumps(data) == committed, f"{name}: regenerated golden data differs"


def test_regeneration_is_byte_identical():
    """A scene regenerated from scratch gives exactly the committed file."""
    for name in ("stuck/F<f", "fig:many:2pi/f=0.3"):
        _assert_regenerates(name)


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(FILES))
def test_every_scene_regenerates_byte_identical(name):
    """All scenes (~40 s): the reorganisations of issue 14 left every golden byte in place."""
    _assert_regenerates(name)


def test_failed_self_agreement_writes_nothing(tmp_path, monkeypatch):
    real = golden.compute

    def shaky(sc, case, dps, **kw):
        out = real(sc, case, dps, **kw)
        if dps == golden.CHECK_DPS:
            out["phi"] = (out["phi"][0] * (1 + mpmath.mpf(10) ** -35), out["phi"][1])
        return out

    monkeypatch.setattr(golden, "compute", shaky)
    with pytest.raises(golden.GoldenError, match="dps 90 vs 110"):
        golden.generate(["stuck/F<f"], tmp_path / "out", n_sample=1)
    assert not (tmp_path / "out").exists() or not list((tmp_path / "out").iterdir())


def test_format_is_deterministic_and_compact():
    data = {"b": [1, "x"], "a": {"c": [[1, 2], [3, 4]], "d": None}}
    text = golden.dumps(data)
    assert text == golden.dumps(json.loads(text))
    assert '[1, "x"]' in text and "[1, 2]" in text and text.endswith("}\n")
    with mpmath.workdps(60):
        assert golden.fmt(mpmath.mpf(1) / 3) == "0." + "3" * 40
    assert math.isclose(float(golden.fmt(mpmath.mpf("2.5"), 5)), 2.5)


def test_fast_event_times_match_golden_to_a_fixed_fraction_of_the_period():
    """Every canonical event time of fast outside the band and away from grazing within
    ``sensitivity_event_time`` (1e-11 T) of the golden one, whatever the map's conditioning: a
    slip or release moved in time changes the state only at third order (the force equals the
    friction there), so the map alone would not show it (a mutation run found one that way)."""
    from cross_check.score.adapters import FAST
    from cross_check.sensitivity.checks import golden_event_times

    bad = golden_event_times(FAST)
    assert not bad, bad[:10]


# --- enclosures (issue 17) -------------------------------------------------------------------
def _half_unit(text: str) -> mpmath.mpf:
    """Half a unit in the last written digit of a decimal string."""
    digits = text.lstrip("-").split("e")[0].replace(".", "").lstrip("0")
    with mpmath.workdps(80):
        value = abs(mpmath.mpf(text))
        if value == 0:
            return mpmath.mpf(0)
        return mpmath.mpf(10) ** (mpmath.floor(mpmath.log10(value)) - len(digits) + 1) / 2


def _in_ball(text, ball) -> bool:
    with mpmath.workdps(80):
        mid, rad = mpmath.mpf(ball[0]), mpmath.mpf(ball[1])
        return bool(abs(mpmath.mpf(text) - mid) <= rad + _half_unit(text))


@pytest.mark.parametrize("name", list(scenes.SCENES))
def test_golden_digits_lie_in_their_proved_enclosures(name):
    """Each written digit of Phi and Phi' is consistent with the proof: the 40-digit value,
    as the interval its rounding denotes, meets the proved ball; the proved radius of Phi is
    within golden_enclosure_rel."""
    limit = tol("golden_enclosure_rel").rtol
    for case, label, inp, _ in _inputs(name):
        enc = inp["enclosure"]
        where = f"{name} / {case['name']} / {label}"
        if not enc["proved"]:
            assert len(enc["reason"]) > 20, where
            continue
        assert float(enc["radius"]) <= limit, where
        for text, ball in zip(inp["phi"], enc["phi"]):
            assert _in_ball(text, ball), (where, text, ball)
        if inp["jacobian"] is not None:
            for i in range(2):
                for j in range(2):
                    assert _in_ball(inp["jacobian"][i][j], enc["jacobian"][i][j]), (where, i, j)


#: golden inputs ("scene / case / label") that have no proof, each with the reason none can
#: exist (documented exceptions); since issue 25 there are none
UNPROVED: dict[str, str] = {}


def _unproved(files) -> dict:
    """``{"scene / case / label": reason}`` of the inputs without a proof in ``files``
    (``{scene: golden record}``)."""
    return {f"{name} / {case['name']} / {label}": inp["enclosure"]["reason"]
            for name, data in files.items() for case in data["cases"]
            for label, inp in case["inputs"].items() if not inp["enclosure"]["proved"]}


def test_every_golden_input_is_proved_or_a_documented_exception():
    got = _unproved({name: _load(name) for name in scenes.SCENES})
    assert set(got) == set(UNPROVED), {k: got.get(k, "proved, but listed") for k in set(got) ^ set(UNPROVED)}
    assert all(len(reason) > 20 for reason in got.values())


def test_an_unproved_input_outside_the_exceptions_is_seen():
    """The checker above, seen to fail: one input's proof removed by hand is reported."""
    data = _load("fig:xpotno")
    data["cases"][0]["inputs"]["exact"]["enclosure"] = {"proved": False, "reason": "removed by hand"}
    assert _unproved({"fig:xpotno": data}) == {"fig:xpotno / sample-0 / exact": "removed by hand"}


@pytest.mark.parametrize("name, case_name", [
    ("fig:many:wide/f=0.3", "chatter"), ("fig:many:wide/f=0.3", "sticking"),
    ("effect:damping", "sample-1"), ("effect:restitution", "sample-2"),
    ("fig:narrow", "grazing"), ("effect:zeno", "sample-3"),
])
def test_a_fresh_reference_run_lies_in_the_stored_enclosures(name, case_name):
    """The reference at dps 60 (not the 40-digit strings) inside the stored balls, for one case
    of each kind of itinerary: the stored balls are wide enough for an independent
    high-precision integrator, as a user's check would need."""
    slack = tol("enclosure_vs_reference_dps60")
    for case, label, inp, as_case in _inputs(name):
        if case["name"] != case_name:
            continue
        enc = inp["enclosure"]
        assert enc["proved"], enc["reason"]
        phi = compare.ref_map(scenes.scene(name), as_case, 1, 60)
        with mpmath.workdps(80):
            for value, ball in zip(phi, enc["phi"]):
                mid, rad = mpmath.mpf(ball[0]), mpmath.mpf(ball[1])
                assert abs(value - mid) <= rad + slack.atol + slack.rtol * abs(value), (label, value, ball)
