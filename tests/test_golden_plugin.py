"""The pytest plugin as a third party uses it: one test per golden case through ``golden_case``.

This file is the example of the README: ``fast`` wrapped by its shipped adapter, each case held
to ``golden_case_float64``.  (The plugin is the ``pytest11`` entry point of the installed suite;
nothing here imports it.)  Below it, a user's test file (run by pytester) whose integrator never
returns on sticking starts: that case fails with the timeout message, the session goes on.
"""
import time

import numpy as np

from cross_check.score.adapters import FAST

pytest_plugins = ["pytester"]


def test_fast_on_every_golden_case(golden_case):
    x, v = FAST.step(golden_case.params, np.array([golden_case.x]), np.array([golden_case.v]), 1)
    golden_case.assert_close(x[0], v[0])


# --- the time budget (issue 28): a golden case that never returns fails, the session goes on ----
MARGIN = 30.0       # seconds for the worker processes to start on a loaded 2-core machine

USER_TESTS = """
import numpy as np
from adapters_for_tests import sticky_in_c

STICKY = sticky_in_c()      # the golden answer, but one C call that never returns on sticking starts


def test_mine(golden_case):
    x, v = STICKY.step(golden_case.params, np.array([golden_case.x]), np.array([golden_case.v]), 1)
    print("ran", golden_case.id)
    golden_case.assert_close(x[0], v[0])


def test_with_request(golden_case, request):        # 'request' acts on pytest's process: runs there
    assert request.node.name.endswith("]") and golden_case.x == golden_case.x
"""
ARGS = ("--golden-scenes", "fig:narrow-with-friction", "fig:narrow", "--golden-kinds", "sticking", "impact",
        "-p", "no:cacheprovider")


def test_a_golden_case_over_its_budget_fails_with_the_timeout_message(pytester):
    pytester.makepyfile(test_user=USER_TESTS)
    t0 = time.perf_counter()
    result = pytester.runpytest(*ARGS, "--golden-timeout", "0.5", "-k", "test_mine or sticking")
    assert time.perf_counter() - t0 < 0.5 + MARGIN
    # 8 + 8 impacts pass before and after the sticking case; 'request' keeps that one test here
    result.assert_outcomes(passed=17, failed=1, warnings=1)
    result.stdout.fnmatch_lines([
        "*fig:narrow-with-friction/sticking [[]sticking[]]: timeout: no result within 0.5 s (the worker process was "
        "stopped); usual cause for sticking: a smooth solver sliding on sign(v): Filippov sticking*",
        "*test_with_request*runs in this process (its fixture(s) request act on this process)*"])


def test_in_process_the_budget_is_checked_after_the_test(pytester):
    pytester.makepyfile(test_user=USER_TESTS)
    result = pytester.runpytest("--golden-scenes", "fig:narrow-with-friction", "--golden-kinds", "impact",
                                "--golden-in-process", "--golden-timeout", "1e-9", "-k", "test_mine",
                                "-p", "no:cacheprovider")
    # the session's first test has the first-call budget (a JIT may compile); the rest are over 1 ns
    result.assert_outcomes(passed=1, failed=7)
    result.stdout.fnmatch_lines(["*timeout: no result within 1e-09 s (it took * s; in process the budget is "
                                 "checked after the test)*"])
