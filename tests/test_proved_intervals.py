"""The branches proved on parameter intervals (issue 26, part 3): the shipped statements file
``cross_check/data/proved_intervals.json`` (written by ``python -m cross_check prove
--intervals``) is consistent, its boxes re-prove to the same balls, random parameters of its
boxes land in its balls under the point reference, and the checks on it say no to a broken
file.  ``slow`` recomputes every chain and compares."""
import copy
import json
from fractions import Fraction

import mpmath
import pytest

from cross_check.paper.claims import intervals as I
from tests.test_enclosure_boxes import reference_fixed_point


@pytest.fixture(scope="module")
def data():
    got = I.load()
    assert got is not None, "cross_check/data/proved_intervals.json is missing: python -m cross_check prove --intervals"
    return got


def test_the_shipped_chains_are_consistent_and_cover_the_claims(data):
    st = data["statements"]
    assert I.problems(st) == []
    assert st["x1-x2"]["complete"] and st["period3"]["complete"]
    assert 0 < I._fold_gap(st) < 1e-29                       # f* within 1e-29 of 2/pi
    lo, hi = (Fraction(e) for e in st["period3"]["interval"])
    assert lo <= Fraction(5, 1000) and hi >= Fraction(2, 10)
    ell = st["period3-elliptic"]
    f_res = Fraction(ell["f_res"])
    assert all(Fraction(p["interval"][1]) < f_res or Fraction(p["interval"][0]) > f_res for p in ell["pieces"])


def test_the_checks_say_no_to_a_broken_file(data):
    st = data["statements"]
    holed = copy.deepcopy(st)
    del holed["x1-x2"]["boxes"][3]
    assert any("hole" in p for p in I.problems(holed))
    met = copy.deepcopy(st)
    met["x1-x2"]["boxes"][0]["x2"] = met["x1-x2"]["boxes"][0]["x1"]
    assert any("meet" in p for p in I.problems(met))
    short = copy.deepcopy(st)
    short["period3"]["interval"][1] = short["period3"]["boxes"][2]["f"][1]
    short["period3"]["boxes"] = short["period3"]["boxes"][:3]
    assert any("[0.005, 0.2]" in p for p in I.problems(short))


def _box_at(chain, f):
    return next(b for b in chain["boxes"] if Fraction(b["f"][0]) <= f <= Fraction(b["f"][1]))


@pytest.mark.parametrize("name, f", [("x1-x2", Fraction(3, 10)), ("period3", Fraction(1, 10))])
def test_a_shipped_box_re_proves_to_its_balls(data, name, f):
    box = _box_at(data["statements"][name], f)
    a, b = (Fraction(e) for e in box["f"])
    got, why = I.fold_box(a, b) if name == "x1-x2" else I.period3_box(None)(a, b)
    assert why is None
    assert json.loads(json.dumps(got)) == {k: v for k, v in box.items() if k != "f"}


@pytest.mark.parametrize("name, orbit, m, f, dps", [
    ("x1-x2", "x1", 1, Fraction(1, 5), 60), ("x1-x2", "x2", 1, Fraction(3, 5), 60),
    ("x1-x2", "x1", 1, None, 90), ("x1-x2", "x2", 1, None, 90),        # the last box: 6e-32 from the fold
    ("period3", "period3", 3, Fraction(3, 20), 60)])
def test_random_parameters_of_a_shipped_box_land_in_its_balls(data, name, orbit, m, f, dps):
    """The point reference at 60 digits (90 at the fold, where x1 and x2 are 1e-14 apart; its
    own Newton, on a finite-difference Jacobian, from the balls' midpoints) at three parameters
    of the box: the fixed point in the shipped balls, the trace in its interval."""
    chain = data["statements"][name]
    box = chain["boxes"][-1] if f is None else _box_at(chain, f)
    rec = box[orbit]
    a, b = (Fraction(e) for e in box["f"])
    make = I.wide_box if name == "x1-x2" else I.two_pi_box
    phase = Fraction(rec["phase_over_T"])
    for u in (Fraction(1, 7), Fraction(1, 2), Fraction(6, 7)):
        sc = make(a, b).point(f=a + u * (b - a))
        x, v, tr = reference_fixed_point(sc, rec["x"][0], rec["v"][0], phase, m, dps=dps)
        for value, ball in ((x, rec["x"]), (v, rec["v"]), (tr, rec["trace"])):
            with mpmath.workdps(dps):
                assert abs(value - mpmath.mpf(ball[0])) <= mpmath.mpf(ball[1]), (orbit, value, ball)


def test_the_claims_table_carries_the_intervals(data):
    lines = I.lines("existence-condition", data)
    assert "exist" in lines[0]["statement"] and lines[0]["interval"] == data["statements"]["x1-x2"]["interval"]
    assert "fold is enclosed" in I.lines("fold-fcrit", data)[0]["statement"]
    assert len(I.lines("subharmonic-islands", data)) == 2
    assert "not computed" in I.lines("fold-fcrit", path="/nonexistent/proved_intervals.json")[0]["statement"]


def without_timings(node):
    """``node`` with every ``seconds`` entry left out (wall times differ from run to run)."""
    if isinstance(node, dict):
        return {k: without_timings(v) for k, v in node.items() if k != "seconds"}
    if isinstance(node, list):
        return [without_timings(v) for v in node]
    return node


def test_without_timings_keeps_everything_else():
    node = {"seconds": 1.0, "a": [{"seconds": 2, "b": "1/3"}], "c": {"d": None}}
    assert without_timings(node) == {"a": [{"b": "1/3"}], "c": {"d": None}}
    assert without_timings({"a": "1/3"}) != without_timings({"a": "1/4"})


@pytest.mark.slow
def test_recomputing_every_chain_gives_the_shipped_file(data):
    got = json.loads(json.dumps(I.compute(progress=lambda m: None)))
    assert without_timings(got) == without_timings(data["statements"])
