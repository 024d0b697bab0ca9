"""The suite's checks, run on any adapter (``cross_check.score``): each says whether it caught
something, where, and how long it took.

* ``golden map``        -- ``Phi`` of every golden case outside the band within
  ``fast_one_period_max`` (relative to ``max(1, |Phi|)``; 4 one-ulp floors where a graze makes
  the exact map itself that sensitive);
* ``golden itinerary``  -- the canonical event kinds of every golden case outside the band;
* ``golden event times``-- the times of the common canonical events within ``sensitivity_event_time``
  (not at a graze: a tangential event time moves like the square root of the start's rounding);
* ``Jacobian``          -- ``Phi'`` against the golden 40-digit Jacobian (``sensitivity_jacobian``),
  outside the band and away from grazing (where ``1/v-`` makes it ill-conditioned);
* ``constructed events``-- ``agreement.construct``'s starts with a known first event (issue 13's
  generator; crossing pairs, tangencies, roots at t = T, turns, sticks), on two scenes;
* ``threshold pairs``   -- ``agreement.thresholds`` (the pairs over one period: a protocol adapter
  maps whole periods only).
"""
from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass

import numpy as np

from cross_check import scenes
from cross_check.agreement import construct, thresholds
from cross_check.score.adapters import canonical_log
from cross_check.score.golden import all_cases
from cross_check.tolerances import tol

CONSTRUCT_SCENES = ("fig:narrow-with-friction", "fig:many:2pi/f=0.1")
CONSTRUCT_N = 400
#: not chatter: a chatter start logs ~3e3 bounces a period (the golden event times cover it)
CONSTRUCT_KINDS = tuple(k for k in construct.KINDS if k != "chatter")


@dataclass
class Result:
    check: str
    caught: bool
    detail: str
    seconds: float


def _cases(adapter):
    return [c for c in all_cases() if c.effects <= set(adapter.effects) and not c.band]


def _grazing(c) -> bool:
    """A grazing case: its kind, or (in an effect scene, whose kind is the effect) its construction."""
    return c.kind == "grazing" or c.name == "grazing"


def _batches(cases):
    by = {}
    for c in cases:
        by.setdefault(c.scene, []).append(c)
    return by.items()


def golden_map(adapter):
    limit = tol("fast_one_period_max").rtol
    bad = []
    for _, cs in _batches(_cases(adapter)):
        x, v = adapter.step(cs[0].params, np.array([c.x for c in cs]), np.array([c.v for c in cs]), 1)
        for c, a, b in zip(cs, x, v):
            err, floor = c.map_error(a, b)
            if not err <= max(limit, floor):
                bad.append(f"{c.id} ({err:.1e})")
    return bad


def _logs(adapter, cs):
    rows = adapter.events(cs[0].params, np.array([c.x for c in cs]), np.array([c.v for c in cs]))
    sc = scenes.scene(cs[0].scene)
    return [canonical_log(row, sc) for row in rows]


def golden_itinerary(adapter):
    bad = []
    for _, cs in _batches(_cases(adapter)):
        for c, evs in zip(cs, _logs(adapter, cs)):
            if [e.kind for e in evs] != [e[0] for e in c.events]:
                bad.append(c.id)
    return bad


def golden_event_times(adapter):
    limit = tol("sensitivity_event_time").rtol
    bad = []
    for _, cs in _batches([c for c in _cases(adapter) if not _grazing(c)]):
        T = 2 * math.pi / cs[0].params["omega"]
        for c, evs in zip(cs, _logs(adapter, cs)):
            for e, g in zip(evs, c.events):
                if e.kind != g[0]:
                    break
                if abs(e.t - float(g[1])) > limit * T:
                    bad.append(f"{c.id} {e.kind} ({abs(e.t - float(g[1])) / T:.1e} T)")
                    break
    return bad


def jacobian(adapter):
    limit = tol("sensitivity_jacobian").rtol
    bad = []
    cases = [c for c in _cases(adapter) if c.jacobian is not None and not _grazing(c)]
    for _, cs in _batches(cases):
        Js = adapter.jacobian(cs[0].params, np.array([c.x for c in cs]), np.array([c.v for c in cs]))
        for c, J in zip(cs, np.asarray(Js, float).reshape(-1, 2, 2)):
            G = np.array([[float(a) for a in r] for r in c.jacobian])
            if not np.max(np.abs(J - G)) <= limit * max(1.0, np.max(np.abs(G))):
                bad.append(c.id)
    return bad


def constructed_events(adapter):
    bad = []
    for name in CONSTRUCT_SCENES:
        sc = scenes.scene(name)
        if not sc.effects <= set(adapter.effects):
            continue
        cases = _constructed(name)
        rows = adapter.events(sc.floats(), cases.x, cases.v)
        first_kind = [row[0][0] if row else "" for row in rows]
        first_t = [row[0][1] if row else math.inf for row in rows]
        chatter_t = [next((e[1] for e in row if e[0] == "chatter"), math.inf) for row in rows]
        out = construct.verify(cases, first_kind, first_t, chatter_t)
        bad += [f"{name}: {k} {len(out[k])}" for k in ("missed", "invented", "wrong_time") if len(out[k])]
    return bad


@functools.lru_cache(maxsize=None)
def _constructed(name):
    return construct.construct(scenes.scene(name), CONSTRUCT_N, seed=18, kinds=CONSTRUCT_KINDS)


@functools.lru_cache(maxsize=None)
def _pairs():
    return thresholds.pairs()


def threshold_pairs(adapter):
    bad = []
    for pair in _pairs():
        if pair.t_end is not None or not pair.scene.effects <= set(adapter.effects):
            continue
        params, (x, v) = pair.scene.floats(), (np.array([float(pair.x)]), np.array([float(pair.v)]))
        if pair.expect[0] == "rest":
            X, V = adapter.step(params, x, v, 1)
            ok, _ = pair.verdict(at_rest=float(X[0]) == float(x[0]) and float(V[0]) == 0.0)
        else:
            ok, _ = pair.verdict(kinds=[e[0] for e in adapter.events(params, x, v)[0]])
        if not ok:
            bad.append(pair.id)
    return bad


CHECKS = {"golden map": golden_map, "golden itinerary": golden_itinerary, "golden event times": golden_event_times,
          "Jacobian": jacobian, "constructed events": constructed_events, "threshold pairs": threshold_pairs}


def run(adapter, checks=CHECKS) -> list[Result]:
    """Every check on ``adapter``; an exception of the adapter counts as caught (with its message)."""
    out = []
    for name, fn in checks.items():
        t0 = time.perf_counter()
        if name == "Jacobian" and not hasattr(adapter, "jacobian"):
            continue
        try:
            bad = fn(adapter)
            detail = f"{len(bad)}: {', '.join(bad[:3])}" if bad else "-"
            caught = bool(bad)
        except Exception as exc:  # noqa: BLE001 -- a raising integrator is caught, and says why
            caught, detail = True, f"raised {type(exc).__name__}: {str(exc)[:120]}"
        out.append(Result(name, caught, detail, time.perf_counter() - t0))
    return out
