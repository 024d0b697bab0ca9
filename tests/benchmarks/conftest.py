"""Benchmark helpers: ``summary_line`` adds a line to a "benchmark notes" section at the end
of the run (pytest-benchmark's table has no room for derived figures such as a ratio);
``timed_command`` runs a command as a user would and keeps its CPU seconds."""
import resource
import subprocess

import pytest

_LINES = pytest.StashKey[list]()


@pytest.fixture
def summary_line(request):
    """``summary_line(text)``: print ``text`` in the end-of-run "benchmark notes"."""
    return request.config.stash.setdefault(_LINES, []).append


def pytest_terminal_summary(terminalreporter, config):
    lines = config.stash.get(_LINES, [])
    if lines:
        terminalreporter.section("benchmark notes")
        for line in lines:
            terminalreporter.write_line(line)


@pytest.fixture
def timed_command():
    """``timed_command(argv, cpu)``: run ``argv`` in a fresh process, append the CPU seconds of it
    and its children (user + system: what other load on a shared machine does not inflate) to the
    list ``cpu``, return its exit status."""
    def run(argv, cpu):
        use = resource.getrusage(resource.RUSAGE_CHILDREN)
        before = use.ru_utime + use.ru_stime
        status = subprocess.run(argv, capture_output=True).returncode
        use = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu.append(use.ru_utime + use.ru_stime - before)
        return status
    return run
