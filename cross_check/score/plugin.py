"""The pytest plugin of the golden data (entry point ``pytest11``: ``vibro_impact_golden``).

A third party's test file asks for the ``golden_case`` fixture and gets one test per golden
case (the float64 input of each; ``cross_check.score.golden.GoldenCase``)::

    def test_mine(golden_case):
        x, v = my_integrator(golden_case.params, golden_case.x, golden_case.v)
        golden_case.assert_close(x, v)

``assert_close`` holds ``Phi`` to the named tolerance ``golden_case_float64`` (or another name of
``cross_check.tolerances``), relative to ``max(1, |Phi|)``, widened by the exact map's own
one-ulp floor where a graze makes it larger; a case in the near-grazing band is skipped with that
reason (its itinerary is not fixed by a float64 start).  ``--golden-scenes NAME ...`` narrows the
scenes; ``--golden-kinds KIND ...`` the kinds (``score.golden.KINDS``); ``--golden-dir DIR`` takes
the golden data of DIR (a user's own scenes, as ``python -m cross_check verify`` writes it) instead
of the shipped data: ``pytest --golden-dir DIR`` in a user's CI.
"""
from __future__ import annotations

import pytest


class _Checked:
    """A ``GoldenCase`` with the assertion a test needs."""

    def __init__(self, case):
        self.case = case

    def __getattr__(self, name):
        return getattr(self.case, name)

    def assert_close(self, x, v, tolerance: str = "golden_case_float64"):
        """``(x, v)`` within the named tolerance of the golden ``Phi`` (module docstring)."""
        from cross_check.tolerances import tol

        if self.case.band:
            pytest.skip(f"{self.case.id}: in the near-grazing band (itinerary not fixed by a float64 start)")
        t = tol(tolerance)
        err, floor = self.case.map_error(x, v)
        assert err <= max(t.rtol, floor), (
            f"{self.case.id} [{self.case.kind}]: Phi = ({float(x)!r}, {float(v)!r}), golden "
            f"({self.case.phi[0][:20]}, {self.case.phi[1][:20]}): relative error {err:.2e} > "
            f"{tolerance} {t.rtol:g} (4 x one-ulp floor {floor:.1e})")

def pytest_addoption(parser):
    group = parser.getgroup("vibro-impact golden data")
    group.addoption("--golden-scenes", nargs="+", default=None, metavar="NAME",
                    help="golden_case: only these scenes (default: all)")
    group.addoption("--golden-kinds", nargs="+", default=None, metavar="KIND",
                    help="golden_case: only these kinds of case (cross_check.score.golden.KINDS)")
    group.addoption("--golden-dir", default=None, metavar="DIR",
                    help="golden_case: the golden data in DIR (written by `python -m cross_check verify` or "
                         "`golden`; default: the data shipped with the suite)")


def pytest_generate_tests(metafunc):
    if "golden_case" not in metafunc.fixturenames:
        return
    from cross_check.score.golden import all_cases

    try:
        cases = all_cases(metafunc.config.getoption("golden_scenes"), metafunc.config.getoption("golden_dir"))
    except ValueError as exc:             # no such directory, no golden file there, a scene it lacks
        raise pytest.UsageError(f"golden_case: {exc}") from None
    kinds = metafunc.config.getoption("golden_kinds")
    if kinds:
        cases = [c for c in cases if c.kind in kinds]
    metafunc.parametrize("golden_case", [_Checked(c) for c in cases], ids=[c.id for c in cases])
