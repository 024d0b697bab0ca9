"""The impact-at-T scans read on fast's event arrays (``impact_at_t._crossing_pairs``): the same
brackets as reading each start's log event by event (``_crossing_times`` on ``EventLog[i]``, the
reading they replace), on every effect (issue 33)."""
from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from cross_check.agreement import impact_at_t
from reference.scene import Scene
from tests.strategies import position_forced_scenes

#: seed 33's R3 of the verify benchmark's distribution: its scan from rest brackets two impacts at T
R3 = Scene(F="1.39", f="0.197", omega="1.35", l="-1.38", r="1.51", wavenumber="1.681", damping="0.061",
           restitution="0.7")


def _by_events(scene, log):
    """``_crossings`` as it read the scan before: event by event, pair by pair."""
    return [i for i in range(len(log) - 1)
            for _ in impact_at_t._crossing_times(scene, log[i], log[i + 1])]


def _scan_log(scene, v0):
    x = impact_at_t.scan_grid(scene)
    return impact_at_t.logs(scene, x, v0, 1.25 * scene.period)


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scene=position_forced_scenes(), moving=st.booleans())
def test_scan_on_the_arrays_brackets_what_the_event_by_event_reading_does(scene, moving):
    """Hypothesis over every parameter and effect, from rest or at the first scan speed."""
    v0 = impact_at_t.speeds(scene)[0] if moving else "0"
    log = _scan_log(scene, v0)
    assert impact_at_t._crossing_pairs(scene, log) == _by_events(scene, log)


def test_scan_on_the_arrays_finds_the_brackets_of_a_scene_and_can_tell_a_wrong_one():
    """On R3 the scan from rest brackets impacts at T, those of the event-by-event reading; a log
    whose times are moved off T by the period (no event crosses it) gives none, as that reading
    does: the comparison is not between two empty lists."""
    log = _scan_log(R3, "0")
    hits = impact_at_t._crossing_pairs(R3, log)
    assert hits and hits == _by_events(R3, log)
    log.t = log.t + R3.period          # every event after T: no pair crosses it
    assert impact_at_t._crossing_pairs(R3, log) == _by_events(R3, log) == []
    assert np.all(np.diff(hits) >= 0)
