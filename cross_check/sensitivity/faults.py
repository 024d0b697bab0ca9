"""The catalogue of faulty integrators: ``fast`` with one physics fault each, as adapters of the
scoring protocol (``cross_check.score``).

A fault lives where a real integrator would carry it: in the parameters it integrates with
(friction, restitution), in the horizon (the period), in its output (a bias of the map), in its
event log (grazing impacts skipped, chatter cut short), or in its Jacobian (rebuilt from the log
by Table 1 with one factor wrong, ``table1``).  Each changes an output on some input: a fault
that changed nothing would be no fault.
"""
from __future__ import annotations

import math

import numpy as np

from cross_check.score.adapters import FastAdapter, scene_of
from cross_check.sensitivity import table1


class Fault(FastAdapter):
    """``fast`` with one fault (module docstring).  ``what`` says it in words."""

    jacobian_fault = None

    def __init__(self, name: str, what: str):
        self.name, self.what = name, what

    def params(self, params):
        return params

    def horizon(self, params, periods):
        return None                               # one period of the scene per period

    def out(self, x, v):
        return x, v

    def log(self, params, evs):
        return evs

    def step(self, params, x, v, periods):
        import fast
        p = self.params(params)
        end = self.horizon(p, periods)
        if end is None:
            return self.out(*super().step(p, x, v, periods))
        return self.out(*fast.flow(scene_of(p), x, v, end))

    def events(self, params, x, v):
        return [self.log(params, row) for row in super().events(self.params(params), x, v)]

    def jacobian(self, params, x, v):
        if self.jacobian_fault is None or not scene_of(params).effects <= table1.SUPPORTED:
            return super().jacobian(self.params(params), x, v)
        return np.array([table1.jacobian(params, row, _start_mode(row), self.jacobian_fault)
                         for row in super().events(params, x, v)])


def _start_mode(row):
    if row and row[0][1] == 0.0 and row[0][0] in ("stick", "contact"):
        return "stick" if row[0][0] == "stick" else "contact"
    return "flight"


class Friction(Fault):
    def __init__(self, rel):
        super().__init__(f"friction {rel:+.0e}", f"f multiplied by 1 {'+' if rel > 0 else '-'} {abs(rel):g}")
        self.rel = rel

    def params(self, params):
        return {**params, "f": params["f"] * (1 + self.rel)}


class RestitutionTwice(Fault):
    def __init__(self):
        super().__init__("restitution twice", "each impact applies e twice: v -> e^2 v")

    def params(self, params):
        return {**params, "restitution": params["restitution"] ** 2}


class PeriodOff(Fault):
    def __init__(self, rel=1e-9):
        super().__init__("period 1e-9 long", f"integrates to k T (1 + {rel:g})")
        self.rel = rel

    def horizon(self, params, periods):
        return periods * 2 * math.pi / params["omega"] * (1 + self.rel)


class MapBias(Fault):
    def __init__(self, rel=1e-12):
        super().__init__("map bias 1e-12", f"Phi multiplied by 1 + {rel:g}")
        self.rel = rel

    def out(self, x, v):
        return x * (1 + self.rel), v * (1 + self.rel)


class SkipGrazing(Fault):
    def __init__(self, speed=1e-3):
        super().__init__("grazing impacts skipped", f"impacts slower than {speed:g} F/w are not logged")
        self.speed = speed

    def log(self, params, evs):
        cut = self.speed * params["F"] / params["omega"]
        return [e for e in evs if not (e[0] == "impact" and abs(e[4]) < cut)]


class ChatterCut(Fault):
    def __init__(self, n=1):
        super().__init__(f"chatter cut after {n} bounce{'s' if n > 1 else ''}",
                         f"a chatter run is declared at rest at its impact number {n + 1}")
        self.n = n

    def log(self, params, evs):
        out = []
        for e in evs:
            if e[0] == "chatter":
                j = len(out)
                while j > 0 and out[j - 1][0] in ("impact", "turn"):
                    j -= 1
                impacts = [i for i in range(j, len(out)) if out[i][0] == "impact"]
                if len(impacts) > self.n:
                    cut = out[impacts[self.n]]
                    out = out[:impacts[self.n]] + [("contact", cut[1], cut[2], 0.0, 0.0)]
                    continue
            out.append(e)
        return out


class ReflectionVAfter(Fault):
    jacobian_fault = "reflection with v+"

    def __init__(self):
        super().__init__("reflection with v+", "the reflection matrix of Phi' uses the velocity after the impact")


class NoTurnFactor(Fault):
    jacobian_fault = "no turn factor"

    def __init__(self):
        super().__init__("turn factor missing", "Phi' omits the turning point's factor (|A| - f)/(|A| + f)")


class Faithful(Fault):
    """The control: ``fast`` with its Jacobian rebuilt by ``table1`` and no fault at all."""

    jacobian_fault = "none"

    def __init__(self):
        super().__init__("fast (control, Table 1 Jacobian)", "no fault")


def catalogue() -> list[Fault]:
    """Every catalogued fault (issue 18's list)."""
    return [Friction(1e-2), Friction(-1e-2), Friction(1e-6), Friction(-1e-6), RestitutionTwice(), PeriodOff(),
            SkipGrazing(), ChatterCut(), ReflectionVAfter(), NoTurnFactor(), MapBias()]
