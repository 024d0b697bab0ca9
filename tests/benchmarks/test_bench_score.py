"""What the scorer's process isolation costs (group "score-isolation", issue 28).

``python -m cross_check score fast`` as a user runs it (a fresh process; every scene, one and
ten periods): ``fast`` loaded by its spec in one worker process that a call over its budget
would kill, and the same with ``--in-process``.  The difference is the price of a time budget
that cannot be ignored: a process start, the imports both processes need, and a pipe round trip
per call (both runs import ``fast`` and load its JIT cache once, in the worker or here).  Run
with ``python -m pytest tests/benchmarks/test_bench_score.py --benchmark-only`` and compare the
two rows; on a shared machine compare also ``extra_info["cpu_s"]``, the CPU seconds of the command
and its worker (user + system), which other load does not inflate.  Each run checks its card:
no kind flagged, complete, no timeout, the same digits both ways.
"""
import json
import sys

import pytest

DIGITS = {}


@pytest.mark.benchmark(group="score-isolation")
@pytest.mark.parametrize("flags", [[], ["--in-process"]], ids=["worker process", "in process"])
def test_bench_score_fast_command(benchmark, flags, tmp_path, timed_command):
    argv = [sys.executable, "-m", "cross_check", "score", "fast", "--out", str(tmp_path), *flags]
    cpu = []

    status = benchmark.pedantic(timed_command, args=(argv, cpu), rounds=3, iterations=1)
    benchmark.extra_info["cpu_s"] = min(cpu)
    card = json.loads((tmp_path / "scorecard.json").read_text())
    assert status == 0 and card["complete"] and not any(c["failure"] for c in card["cases"])
    DIGITS[bool(flags)] = {c["id"]: c["digits"] for c in card["cases"]}
    assert len(DIGITS) < 2 or DIGITS[True] == DIGITS[False]
