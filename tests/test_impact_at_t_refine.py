"""The impact-at-T refinement's runs (``impact_at_t._impact_time``): a run that stops ``reach`` past
``T`` gives the impact time of the whole ``5T/4`` run, and one that stops before the impact runs
the whole span again (issue 33)."""
from __future__ import annotations

import mpmath

from cross_check.agreement import impact_at_t
from reference.scene import Scene

#: an unseen scene drawn over issue 33's ranges, whose impact at T is built through earlier events
#: (a narrow gap), and the two ends of its bracket from rest after fast's narrowing
SCENE = Scene(F="2.74", f="0.54", omega="1.06", l="-0.54", r="0.91", wavenumber="1.22")
ENDS = ("0.26702318455201857", "0.267023184911574")


def test_a_run_that_stops_past_the_impact_gives_its_time_and_one_that_stops_short_runs_on(monkeypatch):
    with mpmath.workdps(impact_at_t.REFINE_DPS + 10):
        T = 2 * mpmath.pi / SCENE.mpf("omega")
        logs = [impact_at_t._trajectory(SCENE, mpmath.mpf(x), 1.25 * T) for x in ENDS]
        j = impact_at_t._nearest_impact(logs[0], T)
        kinds = [e.kind for e in logs[0]][:j + 1]
        h = [log[j].t - T for log in logs]
        assert h[0] * h[1] < 0                                   # the ends bracket the impact at T
        late = ENDS[0] if h[0] > 0 else ENDS[1]                  # its impact after T
        whole = max(h)
        runs = []
        real = impact_at_t._trajectory
        monkeypatch.setattr(impact_at_t, "_trajectory", lambda *a, **k: runs.append(a[2]) or real(*a, **k))
        assert impact_at_t._impact_time(SCENE, mpmath.mpf(late), j, kinds, T, "0", 4 * whole) == whole
        assert runs == [T + 4 * whole]                           # one run, short of 5T/4
        runs.clear()
        assert impact_at_t._impact_time(SCENE, mpmath.mpf(late), j, kinds, T, "0", whole / 2) == whole
        assert runs == [T + whole / 2, 1.25 * T]                 # stopped before the impact: the whole span
