"""The progress line every long command prints: ``[  12.3s] message`` on stderr.

One ``Progress()`` per run: calling it prints a line stamped with the seconds since it was made;
``elapsed`` is that time, ``lap()`` the time since the last lap.  A closed stderr (the output
piped into ``head``) silences the lines and the run goes on.
"""
from __future__ import annotations

import sys
import time


class Progress:
    """Timestamped progress lines on stderr (module docstring)."""

    def __init__(self):
        self.t0 = self.t_lap = time.perf_counter()

    def __call__(self, msg: str):
        try:
            print(f"[{self.elapsed:6.1f}s] {msg}", file=sys.stderr, flush=True)
        except OSError:               # stderr closed: the run goes on, unheard
            pass

    @property
    def elapsed(self) -> float:
        return time.perf_counter() - self.t0

    def lap(self) -> float:
        now = time.perf_counter()
        out, self.t_lap = now - self.t_lap, now
        return out
