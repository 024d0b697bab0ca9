"""``sticking`` under position forcing through earlier events (``cross_check.agreement.
forward_position.sticking``, issue 33): where no single flight from ``t = 0`` reaches a stop
(a narrow gap, a long period), a scan of starts finds one whose stop comes later.

* the reference from the case's start, at 30 digits, stops at the case's time, mid-gap, where
  ``|A| <= STICK_SHARE f``, and slips later;
* without the forward construction the kind is not built, and the note says why;
* refused: a candidate whose reference stop does not stick as the screen's does, and one whose
  forward proof fails;
* a candidate from rest is nudged along the force, out of the band.
"""
from __future__ import annotations

import mpmath

import reference
from cross_check.agreement import compare, hardcases, impact_at_t
from cross_check.agreement import forward_position as FP
from cross_check.agreement.impact_backward import speed_scale
from reference.enclosure.maps import MapEnclosure
from reference.scene import Scene

#: an unseen scene (issue 33, drawn as the verify benchmark draws them, seed 106): a gap of 0.53
#: and a period of 4.8, where every flight run back from a stop at T/4 or 3T/4 meets a wall
NARROW = Scene(F="0.75", f="0.37", omega="1.3", l="-1.45", r="-0.92", wavenumber="0.407", damping="0.196",
               restitution="0.7", name="test: sticking through earlier events")
DPS = 30


def test_sticking_later_in_the_period_where_no_single_flight_reaches_a_stop(monkeypatch):
    sc = NARROW
    cases, why = hardcases.construct(sc)
    case = next(c for c in cases if c.name == "sticking")
    assert "certified" in case.how and "it slips later" in case.how
    with mpmath.workdps(DPS + 10):
        t_star = mpmath.mpf(case.t_event)
        log = reference.trajectory(sc, case.x, case.v, sc.period, dps=DPS)
        at = min(range(len(log)), key=lambda i: abs(log[i].t - t_star))
        stop = log[at]
        assert stop.kind == "stick" and abs(stop.t - t_star) < mpmath.mpf(10) ** -15
        assert FP._sticks(sc, stop) and "slip" in [e.kind for e in log][at:]
    monkeypatch.setattr(FP, "sticking", lambda scene: (None, "none found"))
    cases, why = hardcases.construct(sc)
    assert "sticking" not in {c.name for c in cases}
    assert "no single flight from t = 0 reaches it" in why["sticking"] and "nor through earlier events: none found" in why["sticking"]


def test_a_stop_that_does_not_stick_as_screened_or_an_unproved_itinerary_is_refused(monkeypatch):
    sc = NARROW
    good, _ = FP.sticking(sc)
    assert good is not None
    monkeypatch.setattr(FP, "_sticks", lambda scene, ev: False)       # the reference's stop judged
    monkeypatch.setattr(FP, "candidates", lambda scene, hits_of: iter([(float(good.x), good.v, float(good.t_event), 0)]))
    refused, why = FP.sticking(sc)
    assert refused is None and "has no sticking event" in why
    monkeypatch.undo()
    monkeypatch.setattr(impact_at_t, "enclose_map", lambda *a, **k: MapEnclosure(False, "a failure, injected"))
    refused, why = FP.sticking(sc)
    assert refused is None and "a failure, injected" in why


def test_a_candidate_from_rest_is_nudged_along_the_force_out_of_the_band():
    """``NUDGE``: the sticking case here comes from the scan from rest, and starts instead at
    ``v0 = s NUDGE V`` along the force ``F cos(k x0)``.  Its float64 state is out of the band
    (``compare.reference_in_band``: the reference's itinerary holds under the moves of a few ulps);
    the same ``x0`` at rest is in it (a move of ``v`` against the force adds a turn at ``t ~ 0``),
    which is why the start is nudged."""
    from cross_check.scenes import Case

    sc = NARROW
    case, why = FP.sticking(sc)
    assert case is not None, why
    x0 = float(case.x)
    assert case.v == FP._nudged(sc, x0) and "from rest nudged along the force" in case.how
    sign = 1 if float(sc.mpf("F") * mpmath.cos(sc.mpf("wavenumber") * x0)) >= 0 else -1
    assert float(case.v) * sign > 0 and abs(float(case.v)) < 2 * FP.NUDGE * speed_scale(sc)
    moving, rest = (Case("sticking", repr(x0), repr(float(v)), "float64", "") for v in (case.v, "0"))
    assert not compare.reference_in_band(sc, moving) and compare.reference_in_band(sc, rest)


def test_first_built_draws_each_candidate_only_after_the_one_before_is_refused():
    """``case.first_built``: at most ``limit`` candidates, each drawn lazily; the first accepted
    is the case; a scan that fast refuses while drawing ends the search and says so."""
    from cross_check.agreement.case import first_built

    drawn = []

    def scans(fail_at=None):
        for i in range(10):
            if i == fail_at:
                raise ValueError("fast: too fast")
            drawn.append(i)
            yield i

    attempt = lambda c: ("case", None) if c == 2 else (None, f"refused {c}")     # noqa: E731
    assert first_built(scans(), 5, attempt) == ("case", None, 3) and drawn == [0, 1, 2]
    drawn.clear()
    assert first_built(scans(), 2, attempt) == (None, "refused 1", 2) and drawn == [0, 1]
    assert first_built(iter([]), 2, attempt) == (None, None, 0)
    case, why, tried = first_built(scans(fail_at=1), 5, attempt)
    assert case is None and why == "fast's scan failed (fast: too fast)" and tried == 1
