"""The golden cases as plain objects for scoring: a start, its exact answer, its kind.

Each case of the golden data (``cross_check.golden``: the shipped data, or any directory ``golden``
or ``verify`` wrote, ``directory=``) gives one ``GoldenCase`` for the
input a float64 integrator sees: the ``float64`` rounding of a decimal hard case, or the state
itself when it is a float64 number.  Its ``kind`` says which regime the case tests:

* the scene's effect when the scene switches on one beyond walls, forcing and friction
  (``restitution``, ``damping``, ``position forcing``);
* else the hard case it was built as (``grazing``, ``crossing pair``, ``root at t = kT``,
  ``turning point at a wall``, ``stick-slip boundary``, ``sticking``, ``chatter``);
* else, for a sample state, by its exact itinerary: ``chatter`` if it chatters, ``sticking`` if it
  sticks or rests on a wall, ``impact`` if it hits a wall, ``smooth flight`` otherwise.

``band`` marks a start whose exact itinerary changes under a ``compare_band_ulps`` move: the
physics is ill-posed there in float64, and the scorecard lists it apart.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import mpmath

from cross_check import golden

#: the kinds in the scorecard's order
KINDS = ("smooth flight", "impact", "grazing", "crossing pair", "root at t = kT", "turning point at a wall",
         "stick-slip boundary", "sticking", "chatter", "restitution", "damping", "position forcing")
_BUILT = {"grazing": "grazing", "crossing_pair": "crossing pair", "impact_at_T": "root at t = kT",
          "turn_at_wall": "turning point at a wall", "stick_slip_boundary": "stick-slip boundary",
          "sticking": "sticking", "at_rest": "sticking", "stopping": "sticking", "chatter": "chatter"}
_EFFECT_KIND = (("position_forcing", "position forcing"), ("damping", "damping"), ("restitution", "restitution"))

#: what usually makes an integrator run out of time on a case of each kind (the scorecard's and
#: the pytest plugin's timeout message)
CAUSES = {
    "smooth flight": "no event to blame: a step size collapsing where f sgn(v) switches at a turning "
                     "point, or an integrator that is slow here (raise the budget if it is just slow)",
    "impact": "an event loop that restarts at the wall it has just left and finds the same impact "
              "again at zero time (no progress in t)",
    "grazing": "an impact with v -> 0: the wall event's root is tangent, so a root finder keeps "
               "halving its bracket or a restart finds the same graze again",
    "crossing pair": "two wall crossings closer than a step: a root finder that cannot separate the "
                     "pair, or a loop that re-finds one root of it",
    "root at t = kT": "an event exactly at the strobe time: a loop that re-triggers the event at the "
                      "end of the interval with no progress in t",
    "turning point at a wall": "v = 0 at the wall: an impact and a turn at the same instant, retried "
                               "with zero velocity, zero progress",
    "stick-slip boundary": "a turning point where |F cos wt| = f: a smooth solver sliding on sign(v) "
                           "along the boundary of Filippov sticking",
    "sticking": "a smooth solver sliding on sign(v): Filippov sticking (v stays 0 while |F cos wt| <= f); "
                "f sgn(v) in the right-hand side makes v chatter about 0 and the step size collapse",
    "chatter": "infinitely many impacts in finite time (Zeno): an event loop that restarts after "
               "every bounce never reaches the accumulation point, then sticks to the wall",
    "restitution": "bounces with e < 1 against a pushing force accumulate (Zeno chatter): an event loop "
                   "restarting per bounce never reaches the accumulation point",
    "damping": "with c x' the flights have no closed form: a numerical flight whose step collapses at "
               "a sign switch of v, or a stick on sign(v) as without damping",
    "position forcing": "F cos(k x) couples position and force: a numerical flight whose step collapses "
                        "at a sign switch of v, or sticking on sign(v)",
}


def timeout_message(case_id: str, kind: str, budget: float, how: str = "the worker process was stopped") -> str:
    """The one message for a start that gave no result within its budget (scorecard and plugin)."""
    return (f"{case_id} [{kind}]: timeout: no result within {budget:g} s ({how}); usual cause for "
            f"{kind}: {CAUSES.get(kind, 'an integrator looping or simply slow here')}")


@dataclass(frozen=True)
class GoldenCase:
    """One start and its exact answer (40 digits, strings kept for exact comparison)."""

    scene: str
    name: str
    kind: str
    params: dict
    effects: frozenset
    x: float
    v: float
    phi: tuple            # (x, v) strings, 40 significant digits
    jacobian: tuple | None
    events: tuple         # canonical (kind, t, x, v after, v before), strings
    band: bool
    input: str = "exact"  # the golden input's key: "exact" (the state itself) or "float64" (its rounding)

    @property
    def id(self) -> str:
        return f"{self.scene}/{self.name}"

    def phi_mpf(self):
        with mpmath.workdps(50):
            return mpmath.mpf(self.phi[0]), mpmath.mpf(self.phi[1])

    def ulp_floor(self) -> float | None:
        """The one-ulp floor of ``Phi`` at this start, relative to ``max(1, |Phi|)``: how far the
        exact map moves when ``x`` or ``v`` moves by one ulp (``|J| ulp``); ``None`` where the
        Jacobian is undefined (grazing)."""
        if self.jacobian is None:
            return None
        J = [[float(a) for a in row] for row in self.jacobian]
        ux, uv = math.ulp(self.x) or 5e-324, math.ulp(self.v) or 5e-324
        px, pv = (float(a) for a in self.phi)
        fx = (abs(J[0][0]) * ux + abs(J[0][1]) * uv) / max(1.0, abs(px))
        fv = (abs(J[1][0]) * ux + abs(J[1][1]) * uv) / max(1.0, abs(pv))
        return max(fx, fv, 2.0 ** -53)


    def map_error(self, x, v) -> tuple[float, float]:
        """``(error, allowed factor)``: the larger relative error of ``(x, v)`` against the golden
        ``Phi`` (relative to ``max(1, |Phi|)``), and the one-ulp floor times 4 (a start a
        float64 integrator sees only to one ulp cannot be asked for better; 0 where undefined)."""
        from cross_check.agreement import compare

        gx, gv = self.phi_mpf()
        err = max(10.0 ** -compare.digits(float(x), gx), 10.0 ** -compare.digits(float(v), gv))
        return err, 4 * (self.ulp_floor() or 0.0)


def _kind(case: dict, effects, events) -> str:
    for effect, kind in _EFFECT_KIND:
        if effect in effects:
            return kind
    if case["name"] in _BUILT:
        return _BUILT[case["name"]]
    kinds = {e[0] for e in events}
    if "chatter" in kinds:
        return "chatter"
    if kinds & {"stick", "slip", "contact", "release"}:
        return "sticking"
    return "impact" if "impact" in kinds else "smooth flight"


def golden_scene(name: str, directory=None):
    """The scene of a golden file, from its exact record (the default directory: the shipped data)."""
    return golden.scene_of(golden.load(name, directory), f"golden file of {name!r}")


def scene_cases(name: str, directory=None) -> list[GoldenCase]:
    """The golden cases of one scene, for the float64 input of each (from ``directory``, default the
    shipped golden data; the parameters are the file's own record)."""
    data = golden.load(name, directory)
    effects = frozenset(data["scene"]["effects"])
    params = golden.scene_of(data, f"golden file of {name!r}").floats()
    out = []
    for c in data["cases"]:
        key = "float64" if "float64" in c["inputs"] else "exact"
        inp = c["inputs"][key]
        events = tuple(tuple(e) for e in inp["events"])
        jac = tuple(tuple(r) for r in inp["jacobian"]) if inp["jacobian"] is not None else None
        out.append(GoldenCase(name, c["name"], _kind(c, effects, events), dict(params), effects,
                              float(inp["x"]), float(inp["v"]), tuple(inp["phi"]), jac, events,
                              bool(inp.get("band", False)), key))
    return out


#: sample states per scene scored over ten periods (``card``)
TEN_STATES = 2


def ten_period_cases(cases) -> list[int]:
    """The indices of the cases scored over ten periods: the first ``TEN_STATES`` sample states
    outside the band (chaotic orbits amplify every error alike: a reading, not a grade)."""
    return [i for i, c in enumerate(cases) if c.name.startswith("sample") and not c.band][:TEN_STATES]


_HARD = frozenset({"stick", "slip", "contact", "release", "chatter"})


def _difficulty(case) -> tuple:
    return any(e[0] in _HARD for e in case.events), len(case.events)


def easiest(cases) -> int:
    """The index of the case to warm an integrator up on: one whose exact itinerary neither sticks
    nor chatters (where general integrators loop), with the fewest events."""
    return min(range(len(cases)), key=lambda i: (*_difficulty(cases[i]), i))


@functools.lru_cache(maxsize=None)
def warmup_case(effects: frozenset, directory=None) -> GoldenCase | None:
    """The easiest case (``easiest``) of every scene whose effects are ``effects``, in ``directory``
    and in the shipped data: what the first call on a new set of effects runs on (a JIT compiles its
    code path there), so that even a scene where every start sticks gets no start on the long
    first-call budget.  ``None`` if no scene there has these effects (the caller then warms up on
    the scene's own easiest case)."""
    dirs = (None,) if directory is None else (directory, None)
    picks = [cs[easiest(cs)] for d in dirs for name in golden.names_in(d)
             for cs in [scene_cases(name, d)] if cs and cs[0].effects == effects]
    return min(picks, key=_difficulty) if picks else None


def all_cases(names=None, directory=None) -> list[GoldenCase]:
    """Every golden case of the scenes ``names`` (default: all scenes with golden data in
    ``directory``, by default the shipped data)."""
    return [c for name in (names or golden.names_in(directory)) for c in scene_cases(name, directory)]
