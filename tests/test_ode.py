"""fast/ode.py (with its parts fast/ode_flight.py and fast/ode_params.py): compiled DOP853 flights under position-dependent forcing.

Compared, flight by flight (the whole map is the cross-check's job), with the certified
Taylor flight of ``reference.taylor`` at 30 digits and its certified event search
(``reference.events.find_next_event``), and with the closed-form flight when ``k = 0``.
Event times are compared through the reference event function at the fast event time
(``ode_event_residual``): free of the ``1/|g'|`` conditioning of the time itself.
"""
import math

import mpmath
import numpy as np
import pytest
from hypothesis import assume, given, strategies as st

from cross_check.tolerances import tol
from fast import ode
from reference import events
from reference.scene import Scene
from reference.taylor import TaylorFlight
from tests.strategies import flight_starts, xpot_scenes

XPOT = Scene(F=1, f="0.1", omega="2*pi", l=-1, r=1, wavenumber="pi/2", name="xpot")


def _close(actual, desired, name):
    t = tol(name)
    desired = float(desired)
    return abs(actual - desired) <= t.atol + t.rtol * abs(desired)


def _reference_event(scene, t0, x0, v0, s, t_end):
    """Certified first event of the Taylor flight: ``(kind, t, flight)`` (kind None: t_end)."""
    fl = TaylorFlight(scene, t0, x0, v0, s)
    wall = scene.mpf("r") if s > 0 else scene.mpf("l")
    fns = [events.WallHit(s, wall), events.VelocityZero(s, from_rest=(v0 == 0))]
    fn, t, _ = events.find_next_event(fl, fns, mpmath.mpf(t_end))
    return (None if fn is None else fn.kind), t, fl


def test_k0_matches_closed_form():
    """No position forcing, no events: DOP853 against reference.flows' base flight (30 digits)."""
    scene = Scene(F=1, f="0.2", omega="2*pi", l=-50, r=50)
    t0 = np.array([0.0, 0.3, 0.77])
    x0, v0, s = np.array([0.3, -0.2, 0.0]), np.array([1.7, -2.4, 9.0]), np.array([1.0, -1.0, 1.0])
    t_end = t0 + 0.9
    t, x, v, ev, _ = ode.flight(scene, t0, x0, v0, s, t_end)
    assert np.all(ev == ode.NO_EVENT) and np.all(t == t_end)
    with mpmath.workdps(30):
        F, f, w = 1, scene.mpf("f"), scene.mpf("omega")
        for i in range(3):
            a, b, h = mpmath.mpf(t0[i]), mpmath.mpf(t_end[i]), mpmath.mpf(t_end[i]) - mpmath.mpf(t0[i])
            ve = v0[i] + F / w * (mpmath.sin(w * b) - mpmath.sin(w * a)) - s[i] * f * h
            xe = (x0[i] + v0[i] * h + F / w ** 2 * (mpmath.cos(w * a) - mpmath.cos(w * b) - w * h * mpmath.sin(w * a))
                  - s[i] * f * h * h / 2)
            assert _close(x[i], xe, "ode_vs_taylor_flight") and _close(v[i], ve, "ode_vs_taylor_flight")


@pytest.mark.parametrize("c", ["0", "0.4"])
def test_xpot_flight_and_matrix_match_taylor(c):
    scene = XPOT.replace(damping=c, l=-9, r=9)
    t0 = np.array([0.0, 0.25, 0.6])
    x0, v0, s = np.array([0.0, -0.3, 0.4]), np.array([0.8, 3.0, -0.6]), np.array([1.0, 1.0, -1.0])
    t_end = t0 + 1.0
    t, x, v, ev, J = ode.flight(scene, t0, x0, v0, s, t_end, jac=True)
    assert np.all(ev == ode.NO_EVENT)
    with mpmath.workdps(30):
        for i in range(3):
            fl = TaylorFlight(scene, t0[i], x0[i], v0[i], int(s[i]))
            xr, vr = fl.state(mpmath.mpf(t_end[i]))
            Jr = fl.jacobian(mpmath.mpf(t_end[i]))
            assert _close(x[i], xr, "ode_vs_taylor_flight") and _close(v[i], vr, "ode_vs_taylor_flight")
            for a in range(2):
                for b in range(2):
                    assert _close(J[i, a, b], Jr[a, b], "ode_vs_taylor_flight")
            detJ = J[i, 0, 0] * J[i, 1, 1] - J[i, 0, 1] * J[i, 1, 0]
            assert _close(detJ, math.exp(-float(c) * 1.0), "ode_vs_taylor_flight")   # Liouville


def _check_against_reference(scene, t0, x0, v0, s, horizon):
    t, x, v, ev, J = ode.flight(scene, [t0], [x0], [v0], [float(s)], [t0 + horizon], jac=True)
    with mpmath.workdps(30):
        kind, t_ref, fl = _reference_event(scene, t0, x0, v0, s, t0 + horizon)
        expected = {None: ode.NO_EVENT, "wall": ode.WALL, "velocity": ode.VZERO}[kind]
        xr, vr = fl.state(mpmath.mpf(t[0]))
        assert ev[0] == expected, (ev[0], kind, t[0], t_ref)
        if ev[0] == ode.WALL:
            assert _close(x[0], xr, "ode_event_residual")            # wall - x_ref(t_fast)
            assert _close(v[0], vr, "ode_vs_taylor_flight")
        elif ev[0] == ode.VZERO:
            assert _close(v[0], vr, "ode_event_residual")            # v_ref(t_fast)
            assert _close(x[0], xr, "ode_vs_taylor_flight")
        else:
            assert t[0] == t0 + horizon
            assert _close(x[0], xr, "ode_vs_taylor_flight") and _close(v[0], vr, "ode_vs_taylor_flight")
        Jr = fl.jacobian(mpmath.mpf(t[0]))
        scale = max(1.0, float(mpmath.mnorm(Jr, 1)))
        assert np.abs(J[0] - np.array(Jr.tolist(), dtype=float)).max() <= tol("ode_vs_taylor_flight").atol * scale


@pytest.mark.parametrize("x0, v0, s, kind", [
    (0.2, 2.0, 1, ode.WALL), (-0.9, -0.4, -1, ode.WALL), (0.5, -0.05, -1, ode.VZERO),
    (0.0, 0.0, 1, ode.VZERO), (0.3, 0.7, 1, ode.NO_EVENT)])
def test_first_event_matches_certified_reference(x0, v0, s, kind):
    _check_against_reference(XPOT, 0.0, x0, v0, s, 0.5 if kind == ode.NO_EVENT else 1.0)
    t, *_, ev, _ = ode.flight(XPOT, [0.0], [x0], [v0], [float(s)], [1.0])
    assert ev[0] == kind


def test_start_from_rest_at_the_friction_level():
    """Slip at x = 0 exactly where F cos(w t0) = f and rising: ``v`` and ``a`` both start at 0,
    ``v ~ tau^2``; the flight must not stop at its start but at the later ``v = 0``."""
    w, f = 2 * math.pi, 0.1
    t0 = (2 * math.pi - math.acos(f)) / w
    t, x, v, ev, _ = ode.flight(XPOT, [t0], [0.0], [0.0], [1.0], [t0 + 1.0])
    assert ev[0] == ode.VZERO and t[0] > t0 + 0.1
    _check_against_reference(XPOT, t0, 0.0, 0.0, 1, 1.0)


@given(data=st.data())
def test_first_event_property(data):
    """Random xpot-family scenes and starts: same first event as the certified reference,
    the reference event function vanishes at the fast event time, states and matrices agree."""
    scene = data.draw(xpot_scenes())
    t0, x0, v0, s = data.draw(flight_starts(scene))
    A = scene.float("F") * math.cos(scene.float("wavenumber") * x0) * math.cos(scene.float("omega") * t0)
    if v0 == 0:                       # a flight from rest needs |A| > f and s = sgn(A)
        assume(abs(A) > scene.float("f") + 1e-3)
        s = 1 if A > 0 else -1
    assume(abs(v0) > 1e-6 or v0 == 0)
    assume(scene.float("l") < x0 < scene.float("r") or (x0 - scene.float("l")) * s > 0)
    _check_against_reference(scene, t0, x0, v0, s, 1.0)


def test_bad_input_names_indices():
    with pytest.raises(ValueError, match=r"x0 must be finite; offending indices \[1\]"):
        ode.flight(XPOT, [0.0, 0.0], [0.0, np.nan], [1.0, 1.0], [1.0, 1.0], [1.0, 1.0])
    with pytest.raises(ValueError, match=r"s must be \+1 or -1; offending indices \[0\]"):
        ode.flight(XPOT, [0.0], [0.0], [1.0], [0.5], [1.0])
    with pytest.raises(ValueError, match="v0 must have shape"):
        ode.flight(XPOT, [0.0], [0.0], [1.0, 2.0], [1.0], [1.0])
    with pytest.raises(TypeError, match="scene must be a reference.scene.Scene"):
        ode.flight({"F": 1}, [0.0], [0.0], [1.0], [1.0], [1.0])


def test_batch_equals_singles():
    """A batch never changes any element (every step depends on its own state only)."""
    t0, x0 = np.array([0.0, 0.1, 0.2, 0.3]), np.array([0.2, -0.5, 0.9, 0.0])
    v0, s = np.array([2.0, -0.3, 0.05, 0.0]), np.array([1.0, -1.0, 1.0, 1.0])
    out = ode.flight(XPOT, t0, x0, v0, s, t0 + 1.0, jac=True)
    for i in range(4):
        one = ode.flight(XPOT, t0[i:i + 1], x0[i:i + 1], v0[i:i + 1], s[i:i + 1], t0[i:i + 1] + 1.0, jac=True)
        for a, b in zip(out, one):
            assert np.array_equal(a[i], b[0])


# --- the period map under position forcing (fast.ode's event loop, through fast's API) ----
#: (1, 0.6) and (-1, -0.8): at a wall moving into it, an impact at t = 0 (fast.ode's start path;
#: a mutation run found it untested)
MAP_STATES = [(0.2, 1.5), (0.0, 0.5), (0.95, 0.0), (-0.5, -3.0), (0.0, 0.0), (1.0, 0.0),
              (-1.0, 0.7), (0.6, -0.2), (-0.97, -0.01), (1.0, 0.6), (-1.0, -0.8)]


def test_period_map_matches_reference():
    """One period of eq. ``xpot`` from states with impacts, turns, sticking (inside E),
    wall contact and pre-impact starts: ``fast.stroboscopic_map`` (routed to ``fast.ode``)
    against ``reference.stroboscopic_map`` at 30 digits; the event logs against its
    trajectories (the canonical itineraries of ``cross_check.agreement.compare``)."""
    import fast
    import reference
    from cross_check.agreement import compare

    x0, v0 = np.array(MAP_STATES).T
    X, V = fast.stroboscopic_map(XPOT, x0, v0)
    log = fast.events(XPOT, x0, v0)
    assert np.array_equal(log.x_end, X) and np.array_equal(log.v_end, V)
    kinds = set()
    t = tol("fast_one_period_max")
    for i, (x, v) in enumerate(MAP_STATES):
        xr, vr = reference.stroboscopic_map(XPOT, x, v, dps=30)
        ref_log = reference.trajectory(XPOT, x, v, 1, dps=20)
        kinds |= {e.kind for e in ref_log}
        ref_kinds = [e.kind for e in compare.canonical(ref_log, XPOT)]
        fast_kinds = [e.kind for e in compare.canonical(log[i], XPOT)]
        if v == 0 and fast_kinds[:2] == ["stick", "slip"] and ref_kinds[:1] != ["stick"]:
            fast_kinds = fast_kinds[2:]      # fast logs a zero-length stick/slip at a start from rest
        assert fast_kinds == ref_kinds, (i, fast_kinds, ref_kinds)
        assert abs(X[i] - float(xr)) <= t.atol + t.rtol * max(1.0, abs(float(xr))), i
        assert abs(V[i] - float(vr)) <= t.atol + t.rtol * max(1.0, abs(float(vr))), i
    assert {"impact", "turn", "stick", "contact"} <= kinds


def test_period_map_long_period_scene():
    """A scene where the forcing is not the fastest scale (w = 1, F = 2, k = 0.7, gap 3.5:
    the step follows ``Lambda = max(w, k |v|, sqrt(F k))``), with impacts and a turn."""
    import fast
    import reference

    scene = Scene(F=2, f="0.1", omega=1, l="-0.5", r=3, wavenumber="0.7")
    x0, v0 = np.array([0.2, -0.45, 0.5]), np.array([1.5, 0.3, -2.0])
    X, V = fast.stroboscopic_map(scene, x0, v0)
    t = tol("fast_one_period_max")
    for i in range(3):
        xr, vr = reference.stroboscopic_map(scene, x0[i], v0[i], dps=30)
        assert abs(X[i] - float(xr)) <= t.atol + t.rtol * max(1.0, abs(float(xr))), i
        assert abs(V[i] - float(vr)) <= t.atol + t.rtol * max(1.0, abs(float(vr))), i


@pytest.mark.parametrize("scene", [XPOT, XPOT.replace(f="0.05", wavenumber="1.3", damping="0.2",
                                                      restitution="0.8")])
def test_period_jacobian_matches_reference_differences(scene):
    """fast.ode's Jacobian (variational flight matrices times Table 1's event matrices,
    impact term with ``A(wall, t*)``) against central differences of the reference map
    (step 1e-12 at 30 digits: error ~1e-24 + 1e-30/1e-12, far below float64)."""
    import fast
    import reference

    states = [(0.2, 1.5), (-0.5, -3.0), (0.7, 2.2)]
    x0, v0 = np.array(states).T
    J = fast.jacobian(scene, x0, v0)
    d = mpmath.mpf("1e-12")
    with mpmath.workdps(30):
        for i, (x, v) in enumerate(states):
            for col, (dx, dv) in enumerate(((d, 0), (0, d))):
                plus = reference.stroboscopic_map(scene, mpmath.mpf(x) + dx, mpmath.mpf(v) + dv, dps=30)
                minus = reference.stroboscopic_map(scene, mpmath.mpf(x) - dx, mpmath.mpf(v) - dv, dps=30)
                for row in range(2):
                    fd = float((plus[row] - minus[row]) / (2 * d))
                    assert _close(J[i, row, col], fd, "ode_vs_taylor_flight"), (i, row, col)


@pytest.mark.parametrize("miss", [1e-9, -1e-9])
def test_near_grazing_turn_versus_impact(miss):
    """A slow flight toward r (friction stops it, inside the rest set E) whose stopping point
    lies ``miss`` before (``> 0``) or after (``< 0``) the wall: the wall function then has two
    roots ~1e-4 apart in time, or a minimum 1e-9 above zero, inside one sub-interval of the
    dense output; fast must report the stop (v = 0 at x = r - miss) or the impact, like the
    certified reference."""
    x0, t0, horizon = 0.95, 0.0, 1.5
    with mpmath.workdps(30):
        def x_at_stop(v0):
            fl = TaylorFlight(XPOT, t0, x0, v0, 1)
            fn, _, (x, _, _) = events.find_next_event(fl, [events.VelocityZero(1)], mpmath.mpf(horizon))
            assert fn is not None
            return x

        v0 = mpmath.findroot(lambda u: x_at_stop(u) - (1 - mpmath.mpf(miss)),
                             (mpmath.mpf("0.09"), mpmath.mpf("0.1")), solver="secant", tol=1e-40)
    v0 = float(v0)
    t, x, v, ev, _ = ode.flight(XPOT, [t0], [x0], [v0], [1.0], [horizon])
    assert ev[0] == (ode.VZERO if miss > 0 else ode.WALL)
    if miss > 0:
        assert abs(x[0] - (1 - miss)) <= tol("ode_vs_taylor_flight").atol
    _check_against_reference(XPOT, t0, x0, v0, 1, horizon)


@pytest.mark.parametrize("scene, x0, v0", [
    (Scene(F="(2*pi)**2", f="24.65", omega="2*pi", l=0, r="0.89", name="resonance"), 0.88, 0.1),
    (Scene(F=1, f=0, omega=1, l=0, r="0.8", restitution="0.5", damping="0.01"), 0.79, 0.01)])
def test_chatter_run_is_summed(scene, x0, v0):
    """Impacts accumulating at a wall the force pushes into (friction, or restitution without
    friction): fast.ode sums the run (``chatter_tail``) and continues in wall contact, to
    the release and beyond, like the reference (which sums it by Wynn's epsilon)."""
    import fast
    import reference

    log = reference.trajectory(scene, x0, v0, 2 * mpmath.pi / scene.mpf("omega"), dps=30)
    assert "chatter" in [e.kind for e in log] and "release" in [e.kind for e in log]
    from cross_check.agreement import compare

    numerical = scene.replace(wavenumber="1e-9")      # the numerical flights of fast.ode
    X, V, J, _ = fast.map_and_jacobian(numerical, np.array([x0]), np.array([v0]))
    assert "chatter" in [e.kind for e in compare.canonical(fast.events(numerical, x0, v0)[0], scene)]
    t = tol("fast_one_period_max")
    assert abs(X[0] - float(log.x_end)) <= t.atol + t.rtol * max(1.0, abs(float(log.x_end)))
    assert abs(V[0] - float(log.v_end)) <= t.atol + t.rtol * max(1.0, abs(float(log.v_end)))
    assert np.all(J[0] == 0.0)                  # wall contact forgets the entry state (Table 1)
