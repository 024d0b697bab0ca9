"""Benchmark helpers: ``summary_line`` adds a line to a "benchmark notes" section at the end
of the run (pytest-benchmark's table has no room for derived figures such as a ratio)."""
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
