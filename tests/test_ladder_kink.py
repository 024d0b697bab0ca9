"""The proof ladder's rules for points where ``P`` is not smooth, on random scenes (issue 33):
the kink rule (``verify.ladder.KINK_SHARE``) and the first rung alone for a rest state at the edge
of a family of them (``verify.ladder.REST_EDGE_TOL``).

A rung whose Krawczyk image ``K(Z)`` misses its box by more than ``2^(KINK_SHARE prec)`` radii
ends the climb: ``P`` is not smooth over the box, and more bits do not change that.  The rule
only saves time if it never stops a climb that a higher rung would have finished with a proof:
checked here on random position-forced scenes (every effect drawn: ``tests.strategies``), on
the period-1 orbits fast's search finds, against the ladder without the rule.  The same holds
of the first rung alone for a point of rank-one ``P'`` near ``tr = 1``: such points sit where a
family of rest states ends, and a higher rung never proved one.  The rules' own decisions, with
``prove`` faked, are in ``tests/test_verify.py``.
"""
from __future__ import annotations

import pytest
from hypothesis import example, given, settings

from reference import Scene
from tests.ladder_pairs import assert_same_proofs
from tests.strategies import position_forced_scenes


#: two unseen scenes of issue 33 where the rule ends climbs: a sticking one (its first period-1
#: points are at rest, and missed their boxes by 2^50 radii) and one where every period chatters
#: (a node at rest, 2^49 radii); random scenes seldom have such points
STICKING = Scene(F="1.072", f="0.0075", omega="1.332", l="0.21", r="3.56", wavenumber="0.8216",
                 restitution="0.6")
CHATTERING = Scene(F="2.97", f="0.513", omega="1.16", l="0.04", r="0.5", wavenumber="3.553",
                   damping="0.144", restitution="0.7")


def _on_random_scenes_and_the_two(test):
    """``slow``; ten random position-forced scenes (hypothesis) and, as explicit examples, the
    sticking and the chattering scene."""
    for wrap in (example(CHATTERING), example(STICKING),
                 given(position_forced_scenes(restitutions=("1", "0.9", "0.6"))),
                 settings(max_examples=10, deadline=None), pytest.mark.slow):
        test = wrap(test)
    return test


@_on_random_scenes_and_the_two
def test_the_kink_rule_stops_no_climb_that_would_prove(sc):
    """The first three period-1 orbits of 8 x 8 seeds: the ladder with the rule proves the same
    orbits as without it (``KINK_SHARE = inf``), on the same rung (~2 min: without the rule the
    two scenes' points at rest climb to 192 bits).  Both climb every rung for a rest state at the
    edge of a family (``REST_EDGE_TOL < 0``): the two scenes' points at rest are such states, where
    the kink rule fires."""
    assert_same_proofs(sc, "KINK_SHARE", float("inf"), REST_EDGE_TOL=-1.0)


@_on_random_scenes_and_the_two
def test_a_rest_edge_point_tried_on_the_first_rung_only_is_one_the_whole_ladder_does_not_prove(sc):
    """The first three period-1 orbits of 8 x 8 seeds: the ladder that tries a point of rank-one
    ``P'`` near ``tr = 1`` on its first rung only proves the same orbits as the ladder without
    that rule (``REST_EDGE_TOL < 0``), on the same rung (~10 s: without the rule the sticking
    scene's two points climb to 96 bits, where the kink rule ends the climb)."""
    assert_same_proofs(sc, "REST_EDGE_TOL", -1.0)
