"""Helpers of the tests that run ``verify.ladder.proof`` two ways on random scenes and compare
(``tests/test_orbit_guide.py``, ``tests/test_ladder_kink.py``, ``tests/test_ladder_rungs.py``)."""
from __future__ import annotations

from cross_check.dynamics import periodic
from cross_check.verify import ladder, tasks


def first_orbits(sc, n: int = 3, period: int = 1) -> list:
    """The first ``n`` period-``period`` points that fast's search finds from 8 x 8 seeds."""
    vmax = tasks.velocity_range(sc)
    return periodic.find_periodic_points(sc, period=period, v_range=(-vmax, vmax), grid=(8, 8),
                                         search_steps=periodic.SEARCH_STEPS)[:n]


def proofs_under(sc, p, name: str, values, period: int = 1) -> list:
    """``ladder.proof`` of the period-``period`` point ``p`` once with ``ladder``'s attribute
    ``name`` set to each of ``values`` in turn (restored after each)."""
    kept, out = getattr(ladder, name), []
    for value in values:
        setattr(ladder, name, value)
        try:
            out.append(ladder.proof("o", sc, p, period, None))
        finally:
            setattr(ladder, name, kept)
    return out


def assert_same_proofs(sc, name: str, off, **held) -> None:
    """The first three period-1 orbits of ``sc``: ``ladder.proof`` with ``ladder``'s rule ``name``
    as it is and at ``off`` (the rule off) proves the same orbits, on the same rung (the same
    box radius); ``held``: other attributes of ``ladder`` held at these values in both (restored
    after)."""
    kept = {key: getattr(ladder, key) for key in held}
    try:
        for key, value in held.items():
            setattr(ladder, key, value)
        for p in first_orbits(sc):
            ruled, unruled = proofs_under(sc, p, name, (getattr(ladder, name), off))
            assert ruled["proved"] == unruled["proved"], (sc, p.x, p.v, ruled, unruled)
            if ruled["proved"]:
                assert ruled["radius"] == unruled["radius"], (sc, ruled, unruled)
    finally:
        for key, value in kept.items():
            setattr(ladder, key, value)
