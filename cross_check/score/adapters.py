"""The shipped adapters (the protocol: ``cross_check.score``): examples, and the peers the
report measures.

* ``FAST``       -- ``fast``, float64, every effect, map + Jacobian + events;
* ``REFERENCE``  -- ``reference`` at 30 digits, rounded to float64: every effect;
* ``SCIPY``      -- ``solve_ivp`` DOP853 at rtol 1e-10 with a careful user's event handling
  (``cross_check.agreement.baseline``), map + events;
* ``heyoka()``   -- heyoka.py's Taylor integrator (tolerance 1e-15, its own event detection)
  in the same careful event handling; ``None`` when heyoka is not installed.

Each wraps its engine in a few lines: a ``Scene`` from the plain-float ``params``, the engine's
call, plain arrays back.
"""
from __future__ import annotations

import numpy as np

from reference.scene import EFFECTS, Scene


def scene_of(params: dict) -> Scene:
    """The ``Scene`` of a protocol ``params`` dict (its floats taken exactly)."""
    return Scene(**params)


class FastAdapter:
    """``fast``: the compiled float64 engine."""

    name = "fast"
    effects = frozenset(EFFECTS)

    def step(self, params, x, v, periods):
        import fast
        return fast.stroboscopic_map(scene_of(params), x, v, periods=periods)

    def jacobian(self, params, x, v):
        import fast
        return np.asarray(fast.jacobian(scene_of(params), x, v), float)

    def events(self, params, x, v):
        from cross_check.agreement import compare
        return [[tuple(e[:5]) for e in evs] for evs in compare.fast_events(scene_of(params), x, v)]


class ReferenceAdapter:
    """``reference`` at ``dps`` digits, its results rounded to float64."""

    effects = frozenset(EFFECTS)

    def __init__(self, dps: int = 30):
        self.dps = dps
        self.name = f"reference dps {dps}"

    def step(self, params, x, v, periods):
        import reference
        sc = scene_of(params)
        out = [reference.stroboscopic_map(sc, float(a), float(b), periods=periods, dps=self.dps)
               for a, b in zip(x, v)]
        return np.array([float(o[0]) for o in out]), np.array([float(o[1]) for o in out])

    def events(self, params, x, v):
        import mpmath
        import reference
        sc = scene_of(params)
        with mpmath.workdps(self.dps):
            T = 2 * mpmath.pi / sc.mpf("omega")
        return [[(e.kind, float(e.t), float(e.x), float(e.v), float(getattr(e, "v_before", 0.0) or 0.0))
                 for e in reference.trajectory(sc, float(a), float(b), T, dps=self.dps)] for a, b in zip(x, v)]


class BaselineAdapter:
    """The careful user's event handling (``agreement.baseline``) around a smooth integrator:
    solve_ivp's ``method`` at ``rtol``, or another ``flight`` (heyoka's) and ``rest`` (the
    league's SUNDIALS peer)."""

    effects = frozenset(EFFECTS)

    def __init__(self, name, method="DOP853", rtol=1e-10, flight=None, rest=None):
        self.name, self.method, self.rtol, self.flight, self.rest = name, method, rtol, flight, rest

    def _runs(self, params, x, v, periods):
        from cross_check.agreement import baseline      # scipy: imported when used (a worker loading fast starts light)
        sc = scene_of(params)
        return [baseline.stroboscopic(sc, float(a), float(b), periods, self.method, self.rtol, flight=self.flight,
                                      rest=self.rest)
                for a, b in zip(x, v)]

    def step(self, params, x, v, periods):
        runs = self._runs(params, x, v, periods)
        return np.array([r.x for r in runs]), np.array([r.v for r in runs])

    def events(self, params, x, v):
        return [[(e.kind, e.t, e.x, e.v, e.v_before) for e in r.events] for r in self._runs(params, x, v, 1)]


class HeyokaFlight:
    """A flight of the baseline by heyoka.py's Taylor integrator, with its event detection:
    terminal events on the walls (``x - r`` rising, ``x - l`` falling) and on ``s v + delta``
    falling through zero (the end of a flight in direction ``s``).  A flight after a turn or
    a slip starts at ``v = 0`` exactly, and heyoka's root isolation then misses the flight's
    end (tried: a whole turn lost); ``delta = 1e-13 (F + f) / omega`` keeps the event function
    off zero at the start and moves the detected turn by ``delta / |v'|`` in time, which
    changes the state only by ``O(delta^2)`` (``v = 0`` there).  One integrator per process,
    its parameters ``[F, f, omega, s, c, k, l, r, delta]`` set per flight."""

    def __init__(self, tol=1e-15):
        import heyoka as hy
        self.hy, self.tol = hy, tol
        x, v = hy.make_vars("x", "v")
        F, f, w, s, c, k, l, r, delta = (hy.par[i] for i in range(9))
        acc = F * hy.cos(k * x) * hy.cos(w * hy.time) - s * f - c * v
        events = [hy.t_event(x - r, direction=hy.event_direction.positive),
                  hy.t_event(x - l, direction=hy.event_direction.negative),
                  hy.t_event(s * v + delta, direction=hy.event_direction.negative)]
        self.ta = hy.taylor_adaptive([(x, v), (v, acc)], [0.0, 0.0], tol=tol, t_events=events,
                                     pars=[0.0] * 9, compact_mode=True)

    def __call__(self, p, t0, x0, v0, s, t_end, rtol, atol):
        ta = self.ta
        ta.pars[:] = [p.F, p.f, p.w, float(s), p.c, 0.0 if p.k is None else p.k, p.l, p.r,
                      1e-13 * (p.F + p.f) / p.w]
        ta.time = t0
        ta.state[:] = [x0, v0]
        ta.reset_cooldowns()      # a cooldown left by the previous flight would hide an event of this one
        out = ta.propagate_until(t_end)
        code, steps = int(out[0]), int(out[3])
        if code == int(self.hy.taylor_outcome.time_limit):
            return t_end, ta.state.copy(), "end", steps
        index = -code - 1
        if not 0 <= index < 3:
            raise RuntimeError(f"heyoka: outcome {out[0]} at t={ta.time}, state {ta.state}")
        name = ("r", "l", "v0")[index]
        return ta.time, ta.state.copy(), name, steps


def heyoka():
    """The heyoka.py adapter, or ``None`` when heyoka is not installed (``pip install heyoka``)."""
    try:
        flight = HeyokaFlight()
    except ImportError:
        return None
    return BaselineAdapter("heyoka taylor 1e-15", flight=flight)


FAST = FastAdapter()
REFERENCE = ReferenceAdapter()
SCIPY = BaselineAdapter("scipy DOP853 rtol 1e-10")

#: short names for the CLI
SHIPPED = {"fast": lambda: FAST, "reference": lambda: REFERENCE, "scipy": lambda: SCIPY, "heyoka": heyoka}


def canonical_log(row, scene) -> list:
    """An adapter's event tuples ``(kind, t, x, v after, v before)`` of one start as
    ``compare.Event`` objects in ``compare.canonical`` form (what itineraries are compared in)."""
    from cross_check.agreement import compare
    return compare.canonical([compare.Event(str(e[0]), *(float(a) for a in e[1:5])) for e in row], scene)


__all__ = ["FAST", "REFERENCE", "SCIPY", "SHIPPED", "canonical_log", "heyoka", "scene_of"]
