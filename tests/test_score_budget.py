"""The scorer's time budget and its bad-adapter checks (issue 28): a conformance run never hangs.

The integrators here (``tests/adapters_for_tests.py``, loaded by spec in a worker process) spin
forever where they stick -- in a pure-Python loop and inside one C call that no signal
interrupts -- the way a smooth solver with ``f sgn(v)`` in its right-hand side does.  The run must
finish in about the budget times the number of such starts, flag only the sticking kind, with
timeouts, and grade the rest; an interrupted run must leave its scorecard, marked incomplete;
an adapter that breaks the protocol must be named, with status 2.
"""
import time

import pytest

from cross_check.score import isolate

#: seconds the worker processes of a run may take to start, together, on a loaded 2-core machine:
#: the margin over the budgets that a run may use
MARGIN = 30.0


def test_a_worker_stops_a_loop_inside_c_and_goes_on():
    with isolate.Worker() as worker:
        t0 = time.perf_counter()
        with pytest.raises(isolate.CallTimeout):
            worker.call("adapters_for_tests:spin_in_c", budget=0.5)
        assert time.perf_counter() - t0 < 0.5 + MARGIN
        assert worker.call("builtins:abs", -3, budget=MARGIN)[0] == 3         # a fresh process
        with pytest.raises(isolate.WorkerDied, match="exit code 3"):
            worker.call("os:_exit", 3, budget=MARGIN)
        with pytest.raises(isolate.RemoteError) as err:
            worker.call("builtins:int", "x", budget=MARGIN)
        assert isinstance(err.value.original, ValueError) and "invalid literal" in err.value.message
        assert worker.kills == 2
