"""A state of interest at ``t = 0``, with what its digits mean (float64 or decimal).

Both the agreement metrics (``compare``) and the scenes' states of interest (``cross_check.scenes``)
use it: a case is the unit of work the two engines are compared on.  A hard case (``HardCase``)
is a decimal state built around a delicate event, by ``hardcases`` (closed-form flights) or
``hardcases_position`` (Taylor flights): the names, digits and record they share live here.
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


#: digits of the backward constructions, and of the decimal states they are rounded to
CONSTRUCT_DPS = 60
STATE_DIGITS = 40
#: every hard case ``hardcases.construct`` builds, in its order
NAMES = ("grazing", "crossing_pair", "turn_at_wall", "impact_at_T", "stick_slip_boundary", "sticking",
         "at_rest", "stopping", "chatter")


class ConstructionError(ValueError):
    """The chosen event cannot be reached backward unambiguously from ``t = 0``."""


@dataclass(frozen=True)
class HardCase:
    """A state at ``t = 0`` (decimal strings, exact) and the event it was built around."""

    name: str
    x: str
    v: str
    t_event: str
    kind: str
    how: str


def decimal_text(value, digits: int = STATE_DIGITS) -> str:
    """``value`` (mpf) as a decimal string of ``digits`` significant digits (``"0"`` for 0)."""
    return mpmath.nstr(value, digits, strip_zeros=False, min_fixed=-mpmath.inf, max_fixed=mpmath.inf) \
        if value != 0 else "0"


def first_built(candidates, limit: int, attempt):
    """``(case, why, tried)``: ``attempt(candidate)`` -- ``(HardCase or None, why)`` -- on at most
    ``limit`` candidates of the iterator ``candidates`` in turn, each drawn only once the one
    before is refused; ``why`` the last refusal (``None`` if no candidate came).  A scan that
    fast refuses (``ValueError``, ``RuntimeError`` while drawing) ends the search, and ``why``
    says so."""
    why, tried = None, 0
    for _ in range(limit):
        try:
            candidate = next(candidates, None)
        except (ValueError, RuntimeError) as exc:          # fast refused a scan: no candidates
            return None, f"fast's scan failed ({exc})", tried
        if candidate is None:
            break
        tried += 1
        case, why = attempt(candidate)
        if case is not None:
            return case, None, tried
    return None, why, tried
