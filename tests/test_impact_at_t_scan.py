"""The impact-at-T scans read on fast's event arrays (``impact_at_t._crossing_times``): the same
crossings, times and order as reading each start's log event by event (``EventLog[i]``), the
reading they replace, written again here as the oracle, on every effect (issue 33)."""
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


def _by_events(scene, log, a, b):
    """``[(p, (t_j - T, t'_j - T))]`` read event by event: along the common prefix of the logs of
    starts ``a[p]`` and ``b[p]`` (kinds equal and in ``PREFIX_KINDS``), each impact at the same
    wall with ``t - T`` of opposite signs."""
    l, r, T = scene.float("l"), scene.float("r"), scene.period
    out = []
    for p, (i, k) in enumerate(zip(a, b)):
        for ea, eb in zip(log[int(i)], log[int(k)]):
            if ea.kind != eb.kind or ea.kind not in impact_at_t.PREFIX_KINDS:
                break
            same_wall = (abs(ea.x - r) < abs(ea.x - l)) == (abs(eb.x - r) < abs(eb.x - l))
            if ea.kind == "impact" and same_wall and (ea.t - T) * (eb.t - T) < 0:
                out.append((p, (ea.t - T, eb.t - T)))
    return out


def _scan_log(scene, v0):
    x = impact_at_t.scan_grid(scene)
    return impact_at_t.logs(scene, x, v0, 1.25 * scene.period)


def _neighbours(log):
    starts = np.arange(len(log) - 1)
    return starts, starts + 1


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(scene=position_forced_scenes(), moving=st.booleans(), seed=st.integers(0, 2**16))
def test_scan_on_the_arrays_crosses_where_the_event_by_event_reading_does(scene, moving, seed):
    """Hypothesis over every parameter and effect, from rest or at the first scan speed: the
    neighbours of the scan (``_crossings``) and 64 random pairs of its starts (as ``_fast_jump``
    pairs the ends of two brackets)."""
    v0 = impact_at_t.speeds(scene)[0] if moving else "0"
    log = _scan_log(scene, v0)
    a, b = _neighbours(log)
    assert impact_at_t._crossing_times(scene, log, a, b) == _by_events(scene, log, a, b)
    a, b = np.random.default_rng(seed).integers(0, len(log), size=(2, 64))
    assert impact_at_t._crossing_times(scene, log, a, b) == _by_events(scene, log, a, b)


def test_scan_on_the_arrays_finds_the_crossings_of_a_scene_and_can_tell_a_wrong_one():
    """On R3 the scan from rest brackets impacts at T, those of the event-by-event reading and of
    ``_crossings``; a log whose times are moved past T by a period (no event crosses it) gives
    none: the comparison is not between two empty lists."""
    log = _scan_log(R3, "0")
    a, b = _neighbours(log)
    hits = impact_at_t._crossing_times(R3, log, a, b)
    assert hits and hits == _by_events(R3, log, a, b)
    assert impact_at_t._crossings(R3, impact_at_t.scan_grid(R3)) == [p for p, _ in hits]
    log.t = log.t + R3.period
    assert impact_at_t._crossing_times(R3, log, a, b) == _by_events(R3, log, a, b) == []
