"""``impact_at_T``'s backward screen (``cross_check.agreement.impact_backward``, issue 33): the
motion that hits a wall at ``T``, run back to ``t = 0`` through inverted impacts.

* a start it finds, run forward by fast (another integrator, forward in time), meets that wall at
  ``T``; a start found with a wrong inversion of the impacts does not;
* ``impact_at_t.construct`` builds the case from a speed it proposes where no forward scan
  brackets one, and the reference, from the case's start at 30 digits, meets the wall at ``T``;
  without the screen it is not built;
* where every motion screened stops or passes ``MAX_SPEED V`` before ``t = 0``, the refusal says
  so.
"""
from __future__ import annotations

import dataclasses

import numpy as np

import fast
from cross_check.agreement import impact_at_t
from cross_check.agreement import impact_backward as B
from cross_check.agreement.hardcases_position import STATE_DIGITS
from reference.scene import Scene
from tests.hardcase_checks import assert_impact_at_T

#: unseen scenes (issue 33, drawn as the verify benchmark draws them, seeds 102 and 100)
BACKWARD = Scene(F="0.95", f="0.079", omega="1.56", l="-0.05", r="2.02", wavenumber="1.384", damping="0.185",
                 restitution="0.7", name="test: impact at T found backward")
DEAD = Scene(F="0.81", f="0.477", omega="1.43", l="-0.43", r="1.77", wavenumber="1.085", damping="0.199",
             restitution="0.7", name="test: the bounces die before T")


def _forward_impact_near_T(sc, start, side):
    """``|t - T|`` of fast's impact at wall ``side`` nearest ``T``, from ``start`` (inf: none)."""
    T, wall = sc.period, sc.float("r") if side > 0 else sc.float("l")
    log = fast.events(sc, np.array([start[0]]), np.array([start[1]]), 1.05 * T)[0]
    return min((abs(e.t - T) for e in log if e.kind == "impact" and abs(e.x - wall) < 1e-9), default=np.inf)


def test_a_start_found_backward_meets_the_wall_at_T_forward_and_a_wrong_inversion_does_not():
    found = [(side, u) for u in B.EVENT_SPEEDS for side in (1, -1) if B.start(BACKWARD, side, u * B.speed_scale(BACKWARD))[0]]
    assert found
    wrong = dataclasses.replace(BACKWARD, restitution="0.8")     # the impacts inverted with e = 0.8
    misled = 0
    for side, u in found:
        start, _ = B.start(BACKWARD, side, u * B.speed_scale(BACKWARD))
        assert _forward_impact_near_T(BACKWARD, start, side) < 1e-6
        bad, _ = B.start(wrong, side, u * B.speed_scale(BACKWARD))
        if bad is not None:
            misled += 1
            assert _forward_impact_near_T(BACKWARD, bad, side) > 1e-3
    assert misled > 0


def test_impact_at_T_from_a_speed_the_backward_screen_proposes(monkeypatch):
    """No forward scan (from rest, ``SPEEDS``) brackets an impact at ``T``
    here; a speed the screen proposes does, and the case is certified: the reference from its
    start meets a wall within 1e-20 of ``T``.  Without the screen it is not built."""
    sc = BACKWARD
    case, why = impact_at_t.construct(sc, STATE_DIGITS)
    assert why is None and case.v in B.proposals(sc)[0], why
    assert case.v not in impact_at_t.speeds(sc)
    assert all(impact_at_t._scan(sc, v0) == [] for v0 in ["0"] + impact_at_t.speeds(sc))
    assert_impact_at_T(sc, case)
    monkeypatch.setattr(B, "proposals", lambda scene: ([], []))
    case, why = impact_at_t.construct(sc, STATE_DIGITS)
    assert case is None and "brackets an impact at T" in why


def test_where_every_motion_screened_dies_the_refusal_says_so():
    sc = DEAD
    for u in B.EVENT_SPEEDS:
        for side in (1, -1):
            got, why = B.start(sc, side, u * B.speed_scale(sc))
            assert got is None and ("passes 64 V" in why or "stops" in why), why
    case, why = impact_at_t.construct(sc, STATE_DIGITS)
    assert case is None and "each of the 8 motions stops or passes 64 V before t = 0" in why
    assert B.start(dataclasses.replace(sc, restitution="0"), 1, 1.0) == (None, "restitution 0: an impact leaves no speed to run back from")


def test_at_restitution_0_the_refusal_claims_no_backward_evidence():
    """At restitution 0 no motion runs backward through an impact: the refusal of an unseen
    narrow, plastic scene (drawn at random; every flight forgets its start at each impact) says
    so, and does not claim that the bounces die (the screen ran nothing)."""
    sc = Scene(F="1.748", f="0.9527", omega="0.902", l="-0.92", r="-0.49", wavenumber="0.3739", damping="0.142",
               restitution=0)
    case, why = impact_at_t.construct(sc, STATE_DIGITS)
    assert case is None and "at restitution 0 no motion runs backward through an impact" in why, why
    assert "die" not in why and "brackets an impact at T" in why
