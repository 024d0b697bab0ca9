"""The pytest plugin as a third party uses it: one test per golden case through ``golden_case``.

This file is the example of the README: ``fast`` wrapped by its shipped adapter, each case held
to ``golden_case_float64``.  (The plugin is the ``pytest11`` entry point of the installed suite;
nothing here imports it.)
"""
import numpy as np

from cross_check.score.adapters import FAST


def test_fast_on_every_golden_case(golden_case):
    x, v = FAST.step(golden_case.params, np.array([golden_case.x]), np.array([golden_case.v]), 1)
    golden_case.assert_close(x[0], v[0])
