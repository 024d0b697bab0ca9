"""A state of interest at ``t = 0``, with what its digits mean (float64 or decimal).

Both the agreement metrics (``compare``) and the scenes' states of interest (``cross_check.scenes``)
use it: a case is the unit of work the two engines are compared on.
"""
from __future__ import annotations

from dataclasses import dataclass

import mpmath


@dataclass(frozen=True)
class Case:
    """A state of interest at ``t = 0``.

    ``exact`` says what the strings mean: ``"float64"`` -- the float64 number ``float(x)``
    (shortest round-trip repr), exact in binary; ``"decimal"`` -- the decimal number itself
    (hard cases; float64 sees it rounded, which is part of what a hard case probes).
    """

    name: str
    x: str
    v: str
    exact: str
    how: str
    kind: str = ""
    t_event: str = ""

    def mpf(self):
        """``(x, v)`` as mpf at the current precision (exact for float64 cases)."""
        if self.exact == "float64":
            return mpmath.mpf(float(self.x)), mpmath.mpf(float(self.v))
        return mpmath.mpf(self.x), mpmath.mpf(self.v)

    def float(self):
        """``(x, v)`` as float64 (correctly rounded)."""
        return float(self.x), float(self.v)

    def rounded(self) -> "Case":
        """The float64 rounding of this state, as a ``float64`` case (what fast sees)."""
        x, v = self.float()
        return Case(self.name, repr(x), repr(v), "float64", self.how, self.kind, self.t_event)
