"""The chatter tail bound holds, and is refused where it does not (issue 24).

``reference.enclosure.tails.chatter_tail(m, t, side, u)`` bounds the accumulation time of the
infinitely many bounces that follow an impact at wall ``side`` at time ``t`` with outgoing speed
``u``, without simulating them: on a window where the push exceeds friction, each bounce shrinks
by at most ``rho = e sqrt(R_max / D) < 1``, and the geometric sum is bounded on both sides.

* Refused: ``rho = 1`` (elastic, frictionless), ``rho`` so near 1 that the sum outlasts the
  push (restitution ``1 - 10^-6``; friction ``10^-3`` against a unit push), a force pulling
  away from the wall or at the friction level, bounces higher than the gap.
* Held: where it is given, the bound contains the accumulation time of the reference
  (``reference.trajectory`` from the same state, 60 digits: an independent computation, each
  bounce located and the tail extrapolated), for restitution, friction, both, damping, and at
  either wall -- at phases where the force changes fast, so that the bound's width comes from
  that change and a bound with a wrong ratio, constant or drag misses the truth.
"""
from __future__ import annotations

import mpmath
import pytest

import reference
from cross_check.tolerances import tol
from reference.enclosure.balls import BallModel, from_mpf, from_number, workprec
from reference.enclosure.certify import Unproved
from reference.enclosure.tails import chatter_tail
from reference.scene import Scene

PREC = 320


def _tail(scene, t, side, u):
    with workprec(PREC):
        return chatter_tail(BallModel(scene), from_number(t), side, from_number(u))


@pytest.mark.parametrize("scene, t, side, u, why", [
    (Scene(F=1, f=0, omega=1, l=0, r=1), "0", 1, "1e-3", "elastic and frictionless: rho = 1"),
    (Scene(F=1, f=0, omega=1, l=0, r=1, restitution="0.999999"), "0", 1, "1e-2",
     "e = 1 - 1e-6: the bounces sum to ~2u/(A(1-e)) = 2e4, far beyond the push"),
    (Scene(F=1, f="0.001", omega=1, l=0, r=1), "0", 1, "1e-2",
     "f = 1e-3: rho = 0.998, the sum ~2u/(1-rho) = 20 outlasts the push"),
    (Scene(F=1, f="0.3", omega=1, l=0, r=1), "3.14159", 1, "1e-6", "the force pulls away from r"),
    (Scene(F=1, f="0.3", omega=1, l=0, r=1), "1.2661036727794991113", 1, "1e-6",
     "the push falls through the friction level (cos t = 0.3)"),
    (Scene(F=1, f="0.1", omega=1, l=0, r="1e-6"), "0", 1, "1e-2",
     "bounces of height u^2/(2(A+f)) ~ 5e-5 in a gap of 1e-6: the other wall is hit"),
    (Scene(F=1, f="0.3", omega=1, l=-1, r=1), "0", -1, "1e-3", "the force pushes into r, not l"),
])
def test_a_tail_whose_geometric_bound_fails_is_refused(scene, t, side, u, why):
    with pytest.raises(Unproved, match="not bounded"):
        _tail(scene, t, side, u)


#: (scene, t, side, u): impacts at phases where the push changes fast (|A'| ~ 0.5-0.8)
HELD = [
    (Scene(F=1, f=0, omega=1, l=0, r=1, restitution="0.8"), "0.5", 1, "1e-3"),
    (Scene(F=1, f=0, omega=1, l=0, r=1, restitution="0.95"), "0.5", 1, "1e-4"),
    (Scene(F=1, f="0.3", omega=1, l=0, r=1), "0.5", 1, "1e-3"),
    (Scene(F=1, f="0.05", omega=1, l=0, r=1), "-0.7", 1, "1e-4"),
    (Scene(F=1, f="0.2", omega=1, l=0, r=1, restitution="0.9"), "-0.7", 1, "1e-3"),
    (Scene(F=1, f="0.3", omega=1, l=0, r=1, damping="0.2"), "0.5", 1, "1e-3"),
    (Scene(F=1, f=0, omega=1, l=0, r=1, restitution="0.9", damping="0.1"), "0.5", 1, "1e-3"),
    # slow forcing, strong damping: the drag c |v| dominates the width of the bound
    (Scene(F=1, f="0.3", omega="0.01", l=0, r=1, damping="1"), "0.5", 1, "1e-2"),
    (Scene(F=1, f="0.3", omega=1, l=-1, r=1), "3.6", -1, "1e-3"),
    # the push just above friction (R = A - f ~ 0.06) and moving fast: R varies by 15 % over
    # the tail, where the down-time 1/sqrt(D R) makes the bound most sensitive to it
    (Scene(F=1, f="0.3", omega=1, l=0, r=1), "1.2025", 1, "1e-3"),
    (Scene(F=1, f="0.3", omega=1, l=0, r=1), "1.15", 1, "3e-3"),
    (Scene(F=1, f="0.3", omega=1, l=0, r=1), "-1.2025", 1, "1e-3"),
    (Scene(F=1, f="0.3", omega=1, l=0, r=1), "-1.25", 1, "1e-4"),
]


@pytest.mark.parametrize("scene, t, side, u", HELD,
                         ids=[f"f={s.f},e={s.restitution},c={s.damping},side={d:+d},t={t}"
                              for s, t, d, _ in HELD])
def test_the_tail_bound_holds_the_reference_accumulation_time(scene, t, side, u):
    low, high = _tail(scene, t, side, u)
    wall = scene.exact("r" if side > 0 else "l")
    v = f"{'-' if side > 0 else ''}{u}"                        # leaving the wall
    log = reference.trajectory(scene, str(wall), v, mpmath.mpf(t) + 2, t0=mpmath.mpf(t), dps=60)
    chatter = [e for e in log if e.kind == "chatter"]
    assert len(chatter) == 1, [e.kind for e in log][-4:]
    slack = tol("ref_chatter_time_dps50").atol
    with workprec(PREC):
        elapsed = from_mpf(chatter[0].t) - from_number(t)
        assert low - slack <= elapsed <= high + slack, (low, elapsed, high)
        assert 0 < low < high
