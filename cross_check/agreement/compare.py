"""Agreement metrics, event-aware: itinerary first, then event times, then states.

A tiny shift of an impact time gives an O(1) velocity difference just after it, so states
are never compared with one norm across an impact.  The comparison of an integrator with the
reference on one start ``(x0, v0)`` over ``[0, T]`` goes:

1. **itinerary** -- the sequence of event kinds (``impact``, ``turn``, ``stick``, ...); if it
   differs, the states after the first difference are not comparable and are not scored;
2. **event times** -- for the common prefix of identical kinds, in significant correct digits;
3. **states** -- ``x`` and ``v`` after each common event and ``Phi(x0, v0)`` at ``t = T``
   (only when the itineraries agree), each component separately.

Significant correct digits of ``a`` against the reference ``d``::

    digits(a, d) = -log10( |a - d| / max(1, |d|) ),   capped at ``cap`` (17 for float64),

the scaling of the tolerance table (``atol + rtol |d|`` with ``atol = rtol``).

The **near-grazing band** is the set of starts whose itinerary changes when ``x0`` or ``v0``
moves by ``compare_band_ulps`` ulps (``band_mask``): there a float64 integrator cannot be
expected to agree with the reference, and the report lists these states instead of hiding them.

Engine adapters (``ref_*``, ``fast_*``) wrap ``reference`` and ``fast`` (imported lazily:
both are written by other helpers) into one shape: events as ``Event(kind, t, x, v, v_before)``
tuples of floats or mpf.
"""
from __future__ import annotations

import functools
import importlib
import math
from dataclasses import dataclass, field
from typing import NamedTuple, Sequence

import mpmath
import numpy as np

from cross_check.agreement.case import Case
from cross_check.tolerances import tol

DIGITS_CAP = 17.0   # float64 carries 15.95 digits; exact agreement scores 17


class Event(NamedTuple):
    """One event in a neutral shape: kind, time, state just after, velocity just before."""

    kind: str
    t: object
    x: object
    v: object
    v_before: object
    count: object = None


def canonical_of(events, scene) -> list:
    """``canonical`` of the events of any log (the reference's, an enclosure's: objects with
    ``kind, t, x, v, v_before, count``), as ``Event`` tuples."""
    return canonical([Event(e.kind, e.t, e.x, e.v, e.v_before, e.count) for e in events], scene)


def canonical(events, scene) -> list:
    """The events that define the itinerary in ``scene`` (what two integrators must share).

    * Without friction the flow ``x'' = A`` does not depend on the sign of ``v``: passing
      ``v = 0`` is no event (the reference logs none; Table 1's turn factor is 1), so ``turn``
      entries an integrator may log there are dropped.
    * A chatter run -- impacts at one wall, with turns between them, ending at rest against
      that wall -- is kept as its first impact and one ``chatter`` event: how many bounces are
      simulated one by one before the tail is summed depends on the working precision
      (``.count``), not on the physics.  A run that ends in ``contact`` at the wall (the
      bounces fell under the noise floor before an accumulation test converged) is the same
      physical event and is relabelled ``chatter``.
    """
    evs = list(events) if scene.has("friction") else [e for e in events if e.kind != "turn"]
    out = []
    for e in evs:
        if e.kind == "contact" and out and out[-1].kind in ("impact", "turn") and any(
                o.kind == "impact" and _same_wall(o.x, e.x) for o in out[-2:]):
            e = e._replace(kind="chatter")
        if e.kind == "chatter":
            j = len(out)
            while j > 0 and (out[j - 1].kind == "turn"
                             or out[j - 1].kind == "impact" and _same_wall(out[j - 1].x, e.x)):
                j -= 1
            while j < len(out) and out[j].kind != "impact":
                j += 1            # keep turns that came before the run's first impact
            del out[j + 1:]
        out.append(e)
    return out


def _same_wall(a, b) -> bool:
    return a is not None and b is not None and abs(float(a) - float(b)) <= 1e-9 * max(1.0, abs(float(b)))


# --- engine adapters ------------------------------------------------------------------
def _module(name: str):
    return importlib.import_module(name)


def available(name: str) -> bool:
    """Whether the integrator package ``name`` is importable and has its map."""
    try:
        return hasattr(_module(name), "stroboscopic_map")
    except Exception:  # noqa: BLE001 -- a half-written package counts as unavailable
        return False


def _start(case, dps):
    with mpmath.workdps(dps + 10):
        return case.mpf()


@functools.lru_cache(maxsize=64)
def ref_map(scene, case, periods: int = 1, dps: int = 50):
    """``Phi^periods`` of the reference at ``dps`` digits, as an ``(x, v)`` mpf pair (the recent
    results are kept: ``verify`` asks the same ten-period truths for every adapter it scores)."""
    x, v = _start(case, dps)
    return tuple(_module("reference").stroboscopic_map(scene, x, v, periods=periods, dps=dps))


def ref_jacobian(scene, case, dps: int = 50):
    """The reference Jacobian ``Phi'`` as a 2x2 nested list of mpf."""
    x, v = _start(case, dps)
    J = _module("reference").jacobian(scene, x, v, dps=dps)
    return [[J[i][j] for j in range(2)] for i in range(2)]


def ref_events(scene, case, t_end=None, dps: int = 50) -> list[Event]:
    """The reference event log on ``[0, t_end]`` (default one period) as ``Event`` tuples."""
    x, v = _start(case, dps)
    with mpmath.workdps(dps):
        t_end = 2 * mpmath.pi / scene.mpf("omega") if t_end is None else t_end
        evs = _module("reference").trajectory(scene, x, v, t_end, dps=dps)
    return [Event(e.kind, e.t, e.x, e.v, getattr(e, "v_before", None), getattr(e, "count", None)) for e in evs]


def fast_map(scene, X, V, periods: int = 1):
    """``Phi^periods`` of ``fast`` on float64 arrays ``X, V``: two arrays."""
    out = _module("fast").stroboscopic_map(scene, np.asarray(X, float), np.asarray(V, float), periods=periods)
    if isinstance(out, tuple):
        return np.asarray(out[0], float), np.asarray(out[1], float)
    out = np.asarray(out, float)
    return out[..., 0], out[..., 1]


def fast_jacobian(scene, X, V):
    """``fast``'s Jacobian, shape ``(n, 2, 2)``."""
    return np.asarray(_module("fast").jacobian(scene, np.asarray(X, float), np.asarray(V, float)), float)


_ITINERARY_NAMES = ("itinerary", "events", "event_log", "trajectory", "event_itinerary")


def fast_itinerary_function():
    """The event-itinerary function of ``fast`` (its name is fast's choice), or ``None``."""
    fast = _module("fast")
    for name in _ITINERARY_NAMES:
        fn = getattr(fast, name, None)
        if callable(fn):
            return fn
    return None


def fast_events(scene, X, V) -> list[list[Event]]:
    """``fast``'s event log over one period for each start, as lists of ``Event``."""
    fn = fast_itinerary_function()
    if fn is None:
        raise RuntimeError("fast has no event-itinerary function (looked for: "
                           + ", ".join(_ITINERARY_NAMES) + ")")
    X, V = np.atleast_1d(np.asarray(X, float)), np.atleast_1d(np.asarray(V, float))
    return normalize_fast_events(fn(scene, X, V), len(X))


def fast_safe(fn, scene, X, V, **kw):
    """Run a batched ``fast`` call; if the batch raises, run state by state.

    Returns ``(results, failures)``: ``results[i]`` is the per-state result (``None`` where
    ``fast`` raised) and ``failures`` maps the index to the error message.  One failing state
    must not hide the other results (and the failure itself is reported, not dropped).
    """
    X, V = np.atleast_1d(np.asarray(X, float)), np.atleast_1d(np.asarray(V, float))
    try:
        return _split(fn(scene, X, V, **kw), len(X)), {}
    except (RuntimeError, ValueError, FloatingPointError):
        pass
    results, failures = [], {}
    for i in range(len(X)):
        try:
            results.append(_split(fn(scene, X[i:i + 1], V[i:i + 1], **kw), 1)[0])
        except (RuntimeError, ValueError, FloatingPointError) as exc:
            results.append(None)
            failures[i] = f"{type(exc).__name__}: {str(exc)[:200]}"
    return results, failures


def _split(out, n):
    if isinstance(out, tuple) and len(out) == 2 and not isinstance(out[0], list):
        return [(float(out[0][i]), float(out[1][i])) for i in range(n)]
    return list(out)


def normalize_fast_events(raw, n: int) -> list[list[Event]]:
    """Bring ``fast``'s itinerary output (indexable per state: ``raw[i]`` a list of records
    with ``kind, t, x, v, v_before[, count]``) into ``n`` lists of ``Event``."""
    counts = getattr(raw, "n", None)
    if counts is not None and int(np.max(counts, initial=0)) == 0:
        return [[] for _ in range(n)]   # (fast's EventLog cannot index an all-empty log)
    rows = [raw[i] for i in range(n)]
    out = []
    for row in rows:
        evs = []
        for e in row:
            count = getattr(e, "count", None)
            evs.append(Event(str(e.kind), float(e.t), float(e.x), float(e.v),
                             float(getattr(e, "v_before", math.nan)),
                             int(count) if count is not None and e.kind == "chatter" else None))
        out.append(evs)
    return out


# --- digits ---------------------------------------------------------------------------
def digits(actual, desired, cap: float = DIGITS_CAP) -> float:
    """Significant correct digits ``-log10(|a - d| / max(1, |d|))`` (``cap`` if exact).

    The difference is taken in mpmath at 160 digits (exact for float-vs-mpf comparisons).
    """
    if actual is None or desired is None:
        return math.nan
    with mpmath.workdps(160):    # enough for the reference at dps 100 against dps 120
        a, d = mpmath.mpf(actual), mpmath.mpf(desired)
        if not (mpmath.isfinite(a) and mpmath.isfinite(d)):
            return 0.0
        err = abs(a - d) / max(1, abs(d))
        if err == 0:
            return cap
        return float(min(cap, max(0.0, -mpmath.log10(err))))


@dataclass
class CaseAgreement:
    """Agreement of one start (over one period) of an integrator with the reference."""

    name: str
    same_itinerary: bool
    ref_kinds: tuple
    other_kinds: tuple
    time_digits: list = field(default_factory=list)
    state_digits: list = field(default_factory=list)
    map_digits: tuple = (math.nan, math.nan)
    in_band: bool = False

    @property
    def worst_time(self) -> float:
        return min(self.time_digits, default=math.nan)

    @property
    def worst_state(self) -> float:
        return min(list(self.map_digits) + self.state_digits, default=math.nan)


def compare_case(name, ref_evs: Sequence[Event], other_evs: Sequence[Event], ref_phi, other_phi,
                 cap: float = DIGITS_CAP, scene=None) -> CaseAgreement:
    """Itinerary, then event times and states on the common prefix, then ``Phi``.

    With ``scene`` given, both logs are first reduced by ``canonical``.
    """
    if other_evs is None:    # the other integrator failed on this state
        return CaseAgreement(name, False, tuple(e.kind for e in ref_evs), ("FAILED",))
    if scene is not None:
        ref_evs, other_evs = canonical(ref_evs, scene), canonical(other_evs, scene)
    rk = tuple(e.kind for e in ref_evs)
    ok = tuple(e.kind for e in other_evs)
    same = rk == ok
    out = CaseAgreement(name, same, rk, ok)
    for re_, oe in zip(ref_evs, other_evs):
        if re_.kind != oe.kind:
            break
        out.time_digits.append(digits(oe.t, re_.t, cap))
        out.state_digits.append(min(digits(oe.x, re_.x, cap), digits(oe.v, re_.v, cap)))
    if same and other_phi is not None:
        out.map_digits = (digits(other_phi[0], ref_phi[0], cap), digits(other_phi[1], ref_phi[1], cap))
    return out


def map_digits(other_x, other_v, ref_pairs, cap: float = DIGITS_CAP) -> np.ndarray:
    """Digits of ``(x, v)`` per start, shape ``(n, 2)`` (no itinerary check: a plain state)."""
    return np.array([[digits(ox, r[0], cap), digits(ov, r[1], cap)]
                     for ox, ov, r in zip(other_x, other_v, ref_pairs)])


def map_error(pair, truth) -> float:
    """Worst error of ``pair = (x, v)`` against ``truth`` over x and v, scaled by
    ``max(1, |truth|)`` (``digits`` with ``cap=300``: floored at 1e-300)."""
    return max(10.0 ** -digits(pair[0], truth[0], cap=300),
               10.0 ** -digits(pair[1], truth[1], cap=300))


def map_floors(scene, x0: float, v0: float, truth, periods: int, dps: int) -> tuple:
    """``(one_ulp_floor, rounding_floor)`` of issue 3's ten-period target for the float64
    start ``(x0, v0)``, against ``truth = Phi^periods(x0, v0)``; both from the reference
    alone (at ``dps``), both at least 1e-17:

    * the one-ulp floor: the spread of the exact map under one-ulp moves of ``x0`` or
      ``v0`` (chaotic orbits amplify it by up to ~1e7 over ten periods);
    * the rounding floor: the larger of that and the error of the exact map rounded to
      float64 after every period -- what any engine that hands float64 states from
      period to period carries.  On a neutral or contracting direction (sticking, wall
      contact) the one-ulp floor is below that rounding, so no float64 engine meets it.
    """
    ref = _module("reference").stroboscopic_map
    x0, v0 = float(x0), float(v0)
    spread = 1e-17
    for xm, vm in ((np.nextafter(x0, np.inf), v0), (np.nextafter(x0, -np.inf), v0),
                   (x0, np.nextafter(v0, np.inf)), (x0, np.nextafter(v0, -np.inf))):
        spread = max(spread, map_error(ref(scene, float(xm), float(vm), periods=periods, dps=dps), truth))
    x, v = x0, v0
    for _ in range(periods):
        x, v = (float(a) for a in ref(scene, x, v, periods=1, dps=dps))
    return spread, max(spread, map_error((x, v), truth))


# --- near-grazing band ----------------------------------------------------------------
def ulps(scene, X, V):
    """``(ux, uv)``: one ulp of ``max(|x|, R)`` and of ``max(|v|, F/w)``, the unit of the band's
    moves (an ulp of the value, or of its natural scale near zero: a subnormal move of ``v = 0``
    means nothing); arrays of ``X``'s shape."""
    X, V = np.asarray(X, float), np.asarray(V, float)
    R = scene.float("r") - scene.float("l")
    return (np.spacing(np.maximum(np.abs(X), R)),
            np.spacing(np.maximum(np.abs(V), max(scene.float("F"), scene.float("f")) / scene.float("omega"))))


def _ulp_moves(scene, X, V, k: int):
    """The moved starts: ``k`` ulps (``ulps``) in ``x``, in ``v`` and in both."""
    X, V = np.asarray(X, float), np.asarray(V, float)
    ux, uv = ulps(scene, X, V)
    moves = []
    for dx, dv in ((k, 0), (-k, 0), (0, k), (0, -k), (k, k), (-k, -k)):
        moves.append((X + dx * ux, V + dv * uv))
    return moves


def band_mask(scene, X, V, ulps: int | None = None) -> np.ndarray:
    """True where ``fast``'s one-period itinerary changes under a move of ``ulps`` ulps.

    The moves are ``(+-k, 0)``, ``(0, +-k)``, ``+-(k, k)`` ulps in ``(x, v)`` (``_ulp_moves``),
    clipped to the gap, with ``k = compare_band_ulps``.
    """
    k = int(tol("compare_band_ulps").rtol) if ulps is None else int(ulps)
    l, r = scene.float("l"), scene.float("r")
    def kinds(Xs, Vs):
        evs, _ = fast_safe(fast_events, scene, Xs, Vs)
        return [None if e is None else tuple(x.kind for x in canonical(e, scene)) for e in evs]

    base = kinds(X, V)
    flip = np.zeros(len(base), bool)
    for Xm, Vm in _ulp_moves(scene, X, V, k):
        flip |= np.array([a != b for a, b in zip(base, kinds(np.clip(Xm, l, r), Vm))])
    return flip


def reference_in_band(scene, case, ulps: int | None = None, dps: int = 50, events=None) -> bool:
    """True if the reference's one-period itinerary (canonical) from the float64 state
    ``case`` changes under the ``band_mask`` moves: the exact dynamics is ambiguous at
    float64 resolution there, so no float64 integrator can be held to its itinerary.
    ``events``: the case's own reference events at ``dps`` digits, if the caller has run them
    (``golden.compute``), else they are run here."""
    k = int(tol("compare_band_ulps").rtol) if ulps is None else int(ulps)
    l, r = scene.float("l"), scene.float("r")
    X, V = case.float()
    events = ref_events(scene, case, None, dps) if events is None else events
    base = tuple(e.kind for e in canonical(events, scene))
    for Xm, Vm in _ulp_moves(scene, np.array([X]), np.array([V]), k):
        moved = Case(case.name, repr(float(np.clip(Xm[0], l, r))), repr(float(Vm[0])), "float64", "")
        if tuple(e.kind for e in canonical(ref_events(scene, moved, None, dps), scene)) != base:
            return True
    return False


def itinerary_text(evs, sc) -> str:
    """Canonical itinerary, with repeated pairs written once (``(impact turn)x12``)."""
    if evs is None:
        return "FAILED"
    toks, out, i = [e.kind for e in canonical(evs, sc)], [], 0
    while i < len(toks):
        same = 1
        while i + same < len(toks) and toks[i + same] == toks[i]:
            same += 1
        pairs = 1
        while toks[i:i + 2] == toks[i + 2 * pairs:i + 2 * pairs + 2] and i + 2 * pairs + 1 < len(toks):
            pairs += 1
        if same > 2:
            out.append(f"{toks[i]}x{same}")
            i += same
        elif pairs > 2 and toks[i] != toks[i + 1]:
            out.append(f"({toks[i]} {toks[i + 1]})x{pairs}")
            i += 2 * pairs
        else:
            out.append(toks[i])
            i += 1
    return " ".join(out) or "(none)"


# --- summaries ------------------------------------------------------------------------
@dataclass
class Summary:
    """Median and worst of digits over a set (NaNs -- not comparable -- excluded)."""

    n: int
    median: float
    worst: float

    @staticmethod
    def of(values) -> "Summary":
        vals = np.asarray([v for v in values if not math.isnan(v)], float)
        if vals.size == 0:
            return Summary(0, math.nan, math.nan)
        return Summary(int(vals.size), float(np.median(vals)), float(vals.min()))

    def __str__(self):
        return "n/a" if self.n == 0 else f"{self.median:.1f} / {self.worst:.1f}"


def summarize(cases: Sequence[CaseAgreement]) -> dict:
    """Itinerary share, event-time and state digits (median / worst) over a set of starts."""
    n = len(cases)
    same = [c for c in cases if c.same_itinerary]
    return {
        "n": n,
        "itinerary_share": (len(same) / n) if n else math.nan,
        "band": [c.name for c in cases if c.in_band],
        "mismatch_outside_band": [c.name for c in cases if not c.same_itinerary and not c.in_band],
        "event_time": Summary.of([d for c in cases for d in c.time_digits]),
        "event_state": Summary.of([d for c in cases for d in c.state_digits]),
        "map": Summary.of([min(c.map_digits) for c in same]),
    }
