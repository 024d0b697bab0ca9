"""The suite proves its power (issue 18): every catalogued fault is caught by at least one of
the suite's checks, and the control -- ``fast`` itself, and ``fast`` with its Jacobian rebuilt by
Table 1 -- trips none.  ``python -m cross_check sensitivity`` prints the table."""
import numpy as np
import pytest

from cross_check.sensitivity import checks, faults, markdown, table, verdicts
from cross_check.score.adapters import FAST
from cross_check.score.golden import scene_cases

CATALOGUE = faults.catalogue()


@pytest.mark.parametrize("adapter", [FAST, faults.Faithful()], ids=["fast", "fast, Table 1 Jacobian"])
def test_the_control_trips_no_check(adapter):
    results = checks.run(adapter)
    assert [r.check for r in results if r.caught] == [], [(r.check, r.detail) for r in results if r.caught]
    assert {r.check for r in results} == set(checks.CHECKS)


@pytest.mark.parametrize("fault", CATALOGUE, ids=[f.name for f in CATALOGUE])
def test_every_fault_is_caught(fault):
    caught = [r.check for r in checks.run(fault) if r.caught]
    assert caught, f"{fault.name} ({fault.what}) escaped every check"


@pytest.mark.parametrize("fault", CATALOGUE, ids=[f.name for f in CATALOGUE])
def test_every_fault_changes_an_output(fault):
    """A fault that changed no output on any input would be no fault (issue 18): on the golden
    starts of three scenes, its map, event log or Jacobian differs from fast's."""
    changed = False
    for name in ("fig:narrow-with-friction", "fig:many:wide/f=0.1", "effect:zeno"):
        cs = scene_cases(name)
        p, X, V = cs[0].params, np.array([c.x for c in cs]), np.array([c.v for c in cs])
        changed |= not np.array_equal(np.array(fault.step(p, X, V, 1)), np.array(FAST.step(p, X, V, 1)))
        changed |= fault.events(p, X, V) != FAST.events(p, X, V)
        changed |= not np.array_equal(fault.jacobian(p, X, V), FAST.jacobian(p, X, V))
    assert changed, fault.name


def test_table_and_markdown():
    tab = table()
    escaped, tripped = verdicts(tab)
    assert escaped == [] and tripped == []
    text = markdown(tab)
    assert f"Caught: {len(CATALOGUE)} of {len(CATALOGUE)} faults; controls clean." in text
