"""fast finds every constructed event (issue 13): starts built backwards from a known first
event (``cross_check.agreement.construct``, independent of both integrators), 1e4 in the default run
and 1e6 in a ``slow`` test.  Outside the band (where the rounding of the start to float64
cannot decide the event) the constructed event must come first, of its kind, at its time;
everywhere, nothing may be invented before it.
"""
import numpy as np
import pytest

import reference
from cross_check.agreement import construct as C
from reference.scene import Scene

SCENES = {
    "narrow_f0005": Scene(F=1, f="0.005", omega=1, l=0, r="0.8"),
    "twopi_f005": Scene(F=1, f="0.05", omega="2*pi", l=-1, r=1),
    "wide_f03": Scene(F=1, f="0.3", omega=1, l=0, r=20),
    "resonance": Scene(F="(2*pi)**2", f="24.65", omega="2*pi", l=0, r="0.8932"),
    "weak_F_lt_f": Scene(F=1, f="1.5", omega=1, l=0, r=2),
    "narrow_f0": Scene(F=1, f=0, omega=1, l=0, r="0.8"),
}
first_events = C.first_events


def _check(scene, n, seed):
    cases = C.construct(scene, n, seed=seed)
    result = C.verify(cases, *first_events(scene, cases))
    for name in ("missed", "invented", "wrong_time"):
        idx = result[name][:5]
        assert not idx.size, (name, [(C.KINDS[cases.kind[i]], cases.x[i], cases.v[i],
                                      cases.t_star[i]) for i in idx])
    return cases, result


@pytest.mark.parametrize("name", list(SCENES))
def test_every_constructed_event_is_found(name):
    """About 1e4 cases in all (up to 300 of each kind a scene admits)."""
    cases, result = _check(SCENES[name], 300, seed=11)
    assert len(cases) >= 600 and result["band"] < len(cases)


@pytest.mark.slow
@pytest.mark.parametrize("name", list(SCENES))
def test_a_million_constructed_events_are_found(name):
    """1e6 cases in all (28000 of each kind a scene admits, six scenes)."""
    _check(SCENES[name], 28_000, seed=12)


def test_the_construction_agrees_with_the_reference():
    """A sample of the non-band cases, integrated by the reference at 30 digits: the same
    first event at the constructed time (chatter: an accumulation before the push ends)."""
    scene = SCENES["twopi_f005"]
    cases = C.construct(scene, 40, seed=13)
    kinds = np.array(C.KINDS)[cases.kind]
    for k in C.KINDS:
        idx = np.flatnonzero((kinds == k) & ~cases.in_band)[:3]
        for i in idx:
            log = reference.trajectory(scene, float(cases.x[i]), float(cases.v[i]),
                                       float(cases.t_star[i] + cases.margin[i]) if k == "chatter"
                                       else scene.period, dps=30)
            got = [e.kind for e in log]
            if k == "chatter":
                assert "chatter" in got or got[-1:] == ["contact"], (i, got)
            else:
                assert got[0] == C.FIRST_EVENT[k], (i, got)
                assert abs(float(log[0].t) - cases.t_star[i]) <= cases.time_tol[i], (i, log[0])


def test_the_check_catches_a_missed_and_a_mistimed_event():
    """The verifier is not vacuous: a first event dropped or moved is reported."""
    scene = SCENES["wide_f03"]
    cases = C.construct(scene, 50, seed=14, kinds=("crossing_pair", "turn"))
    kinds, times, chatter = first_events(scene, cases)
    out = np.flatnonzero(~cases.in_band)
    i, j = out[0], out[-1]
    kinds[i], times[i] = "", np.inf                     # missed
    times[j] += 50 * cases.time_tol[j]                   # mistimed
    result = C.verify(cases, kinds, times, chatter)
    assert list(result["missed"]) == [i] and list(result["wrong_time"]) == [j]


def test_bad_arguments():
    with pytest.raises(ValueError, match="n must be an integer >= 1"):
        C.construct(SCENES["wide_f03"], 0)
    with pytest.raises(ValueError, match="unknown kind"):
        C.construct(SCENES["wide_f03"], 5, kinds=("bounce",))
    with pytest.raises(ValueError, match="the base model with forcing"):
        C.construct(SCENES["wide_f03"].replace(damping="0.1"), 5)
