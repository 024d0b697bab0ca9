"""Threshold pairs (``cross_check.agreement.thresholds``): every regime switch, from both sides,
at relative distances 1e-3, 1e-6, 1e-9 (far outside the ~1e-15 band), in both engines.

The regime each side must take comes from the closed-form condition of the switch (the
module's docstring), never from an engine.  These pairs found that both engines crawled on a
slip toward a wall a hair away (F = f (1 + 1e-9): 20000 safe steps in the reference, 1e5
rounds in fast, then a budget error); the cubic certified step (``reference.events.
_crawl_step``, ``fast.roots._crawl``) settles them in under 0.1 s.
"""
import pytest

from cross_check.agreement import thresholds as T

PAIRS = T.pairs()


def test_every_switch_has_pairs_on_both_sides():
    assert {p.switch for p in PAIRS} == set(T.SWITCHES)
    for switch in T.SWITCHES:
        sides = {(p.variant, p.delta, p.side) for p in PAIRS if p.switch == switch}
        assert all((v, d, -s) in sides for v, d, s in sides), switch


@pytest.mark.parametrize("engine", ["fast", "reference"])
@pytest.mark.parametrize("pair", PAIRS, ids=[p.id for p in PAIRS])
def test_engine_takes_the_regime_of_its_side(pair, engine):
    ok, what = T.observe(pair, engine)
    assert ok, f"{engine} on {pair.id}: expected {pair.expect}, got {what}"


HELD = [p for p in PAIRS if p.switch == "e = 0 held or released"]


@pytest.mark.parametrize("pair", HELD, ids=[p.id for p in HELD])
def test_e0_logs_agree_event_by_event(pair):
    """With e = 0 the velocity before each logged event (zero for the contact that holds the
    particle) agrees between the engines, not only the kinds."""
    import numpy as np

    import fast
    from cross_check.agreement import compare
    from cross_check.agreement.case import Case

    case = Case(pair.id, pair.x, pair.v, "decimal", "threshold pair")
    ref = compare.canonical(compare.ref_events(pair.scene, case, None, 30), pair.scene)
    got = compare.canonical(compare.normalize_fast_events(
        fast.events(pair.scene, *(np.array([a]) for a in case.float())), 1)[0], pair.scene)
    assert [e.kind for e in got] == [e.kind for e in ref]
    for g, r in zip(got, ref):
        assert abs(g.v_before - float(r.v_before)) <= 1e-9 * max(1.0, abs(float(r.v_before))), (g, r)
