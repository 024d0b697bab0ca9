"""Chatter in the reference: accumulation times to working precision (issue 6).

Chattering orbits start on the wall ``x = r = 1`` with a small speed into it at ``t = 0``,
where ``A = F cos 0 = 1`` pushes into the wall (``F = w = 1``, ``l = 0``); the initial
speed ``u0`` is chosen so that the tail, ``~ u0 (1/(A+f) + 1/sqrt(A^2-f^2)) e / (1 - rho)``
long, ends well before the push falls below ``f`` (at ``t = arccos f ~ 1.5``).  The
accumulation time at dps 50 must agree with dps 80 to ``ref_chatter_time_dps50``.
"""
import time

import mpmath
import pytest
from hypothesis import given, settings
from mpmath import mpf

import reference
from cross_check.tolerances import tol
from reference import Scene, chatter
from reference.model import Model
from tests.strategies import chattering_orbits

# (name, scene parameters, u0): bounce ratio rho = e sqrt((A - f)/(A + f)) at A = 1
CHATTER_CASES = [
    ("e=0.5", dict(restitution="0.5", f=0), "0.1"),          # rho = 0.5
    ("e=0.9", dict(restitution="0.9", f=0), "0.02"),         # rho = 0.9
    ("e=0.99", dict(restitution="0.99", f=0), "0.002"),      # rho = 0.99
    ("f=0.3", dict(f="0.3"), "0.05"),                        # rho = 0.734
    ("f=0.01", dict(f="0.01"), "0.002"),                     # rho = 0.990
    ("f=0.001", dict(f="0.001"), "0.0002"),                  # rho = 0.999
    # damping: the generic event loop (no wall-relative bounces), strided extrapolation
    ("e=0.9,c=0.1", dict(restitution="0.9", f=0, damping="0.1"), "0.02"),
    ("f=0.3,c=0.2", dict(f="0.3", damping="0.2"), "0.05"),
]
SLOW_CASES = {"f=0.001"}


def chatter_event(scene, u0, dps):
    log = reference.trajectory(scene, "1", u0, "1.5", dps=dps)
    found = [e for e in log if e.kind == "chatter"]
    assert len(found) == 1, [e.kind for e in log[-5:]]
    nxt = log[log.index(found[0]) + 1:]
    assert all(e.kind == "release" for e in nxt)          # contact until the push ends
    return found[0]


@pytest.mark.parametrize("name,params,u0", [
    pytest.param(*case, marks=pytest.mark.slow) if case[0] in SLOW_CASES else case
    for case in CHATTER_CASES])
def test_chatter_time_to_working_precision(name, params, u0):
    scene = Scene(F=1, omega=1, l=0, r=1, **params)
    start = time.perf_counter()
    a = chatter_event(scene, u0, 50)
    b = chatter_event(scene, u0, 80)
    elapsed = time.perf_counter() - start
    with mpmath.workdps(100):
        assert abs(a.t - b.t) <= tol("ref_chatter_time_dps50").atol, (name, a.t - b.t)
    assert a.count < chatter.MAX_RUN and elapsed < 60, (a.count, elapsed)


def test_tiny_bounce_keeps_relative_precision():
    """A bounce of speed 1e-40 (height ~1e-80, far below the absolute noise of x at the
    wall): its duration, height and speed agree between dps 50 and 80 relatively."""
    scene = Scene(F=1, f="0.2", omega=1, l=0, r=1)
    out = {}
    for dps in (62, 92):
        with mpmath.workdps(dps):
            m = Model(scene)
            b = chatter.wall_bounce(m, mpf("0.3"), 1, mpf("1e-40"), mpf(10))
            out[dps] = (b.duration, b.height, b.speed)
    with mpmath.workdps(120):
        for p, q in zip(out[62], out[92]):
            assert abs(p / q - 1) <= tol("ref_chatter_bounce_rel_dps50").rtol
        # frozen force A = cos 0.3 to leading order (A varies by ~1e-40 over the bounce):
        # height u^2/(2(A+f)), speed ratio sqrt((A-f)/(A+f)), duration u (1/a1 + 1/sqrt(a1 a2))
        A, f, u = mpmath.cos(mpf("0.3")), mpf("0.2"), mpf("1e-40")
        a1, a2 = A + f, A - f
        assert abs(out[92][1] / (u * u / (2 * a1)) - 1) < mpf("1e-35")
        assert abs(out[92][2] / u - mpmath.sqrt(a2 / a1)) < mpf("1e-35")
        assert abs(out[92][0] / (u / a1 + u / mpmath.sqrt(a1 * a2)) - 1) < mpf("1e-35")


@pytest.mark.parametrize("params,t", [(dict(f="0.2"), "1.4"),        # P = cos 1.4 < f
                                      (dict(f="0.2", damping="0.1"), "0.3"),
                                      (dict(f=0, restitution="0.5"), "2")])  # P < 0
def test_wall_bounce_declines_outside_its_certificate(params, t):
    """``None`` (generic event loop) when the push does not exceed friction at the impact,
    for damped flights, or when the force pulls away from the wall."""
    with mpmath.workdps(40):
        m = Model(Scene(F=1, omega=1, l=0, r=1, **params))
        assert chatter.wall_bounce(m, mpf(t), 1, mpf("0.01"), mpf(10)) is None


def test_bounce_that_leaves_the_certified_window_is_declined():
    """A big bounce whose duration would outlast the push above f: not a chatter bounce."""
    with mpmath.workdps(40):
        m = Model(Scene(F=1, f="0.1", omega=1, l=0, r=100))
        assert chatter.wall_bounce(m, mpf(0), 1, mpf(3), mpf(100)) is None
        assert chatter.wall_bounce(m, mpf(0), 1, mpf("0.01"), mpf(100)) is not None


def test_run_cap_raises_with_the_state(monkeypatch):
    monkeypatch.setattr(chatter, "MAX_RUN", 30)
    scene = Scene(F=1, f="0.01", omega=1, l=0, r=1)
    with pytest.raises(RuntimeError, match=r"did not converge in 30 impacts: \(t, x, v, mode\)"):
        reference.trajectory(scene, "1", "0.002", "1.5", dps=30)


def test_elastic_micro_bouncing_hits_the_event_budget_clearly():
    """f = 0, e = 1 at a wall with speed 1e-3 into it: ~500 genuine impacts (no
    accumulation); a budget below that raises naming the budget and the state."""
    scene = Scene(F=1, f=0, omega=1, l=0, r=20)
    with pytest.raises(RuntimeError, match=r"max_events = 50 .*\(t, x, v, mode\) = \("):
        reference.trajectory(scene, "20", "0.001", "1.5", dps=20, max_events=50)


def test_root_iteration_bound_raises(monkeypatch):
    monkeypatch.setattr(chatter, "MAX_ROOT_ITERATIONS", 2)
    with mpmath.workdps(40):
        m = Model(Scene(F=1, f="0.2", omega=1, l=0, r=1))
        with pytest.raises(RuntimeError, match="chatter bounce: the turn did not converge"):
            chatter.wall_bounce(m, mpf("0.3"), 1, mpf("1e-3"), mpf(10))


def test_neville_tail_on_nearly_unit_ratio_nodes():
    """rho = 0.995 (nodes nearly equal): strided nodes keep the extrapolation exact."""
    run = chatter.BounceRun()
    with mpmath.workdps(62):
        t_inf, lam = mpf("0.123"), mpf("0.995")
        for n in range(2000):
            u = lam ** n / 1000
            run.observe("impact", 1)
            run.add_impact(t_inf - 3 * u - 40 * u ** 2 + 500 * u ** 3, u)   # R(u) analytic
        est, err = run.extrapolate()
        assert abs(est - t_inf) < mpf(10) ** -50 and err < mpf(10) ** -45


@settings(max_examples=12, deadline=None)
@given(chattering_orbits())
def test_chatter_time_self_agreement_property(case):
    """Drawn chattering orbits: one chatter event, then contact; its time at dps 30 agrees
    with dps 50 to 30 digits minus the 5 of ``ref_chatter_time_dps50``'s derivation
    (62 - 45 = 17 digits of margin at dps 50 -> 1e-25 at dps 30)."""
    scene, x, u0 = case
    a = chatter_event(scene, u0, 30)
    b = chatter_event(scene, u0, 50)
    with mpmath.workdps(60):
        assert abs(a.t - b.t) <= tol("ref_chatter_time_dps30").atol, (a.t - b.t)


@pytest.mark.slow
@settings(max_examples=150, deadline=None)
@given(chattering_orbits())
def test_chatter_time_self_agreement_property_exhaustive(case):
    test_chatter_time_self_agreement_property.hypothesis.inner_test(case)


@pytest.mark.parametrize("params,u0", [(dict(f="0.3"), "0.05"), (dict(restitution="0.9", f=0), "0.02")])
def test_chatter_at_the_left_wall_is_the_mirror_image(params, u0):
    """Half-period symmetry ``(x, v, t) -> (l + r - x, -v, t + T/2)``: the run at ``l = 0``
    from ``t0 = pi`` is the run at ``r = 1`` from 0, shifted by ``pi``."""
    scene = Scene(F=1, omega=1, l=0, r=1, **params)
    right = chatter_event(scene, u0, 50)
    with mpmath.workdps(80):
        pi = +mpmath.pi
        log = reference.trajectory(scene, "0", "-" + u0, pi + mpf("1.5"), t0=pi, dps=50)
        left = next(e for e in log if e.kind == "chatter")
        assert left.x == 0 and left.count == right.count
        assert abs(left.t - mpmath.pi - right.t) <= tol("ref_chatter_time_dps50").atol
