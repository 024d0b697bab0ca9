"""Adapters for the scorer's tests, loaded by their ``MODULE:NAME`` spec (``tests/`` is on
``sys.path`` under pytest; a subprocess gets it through ``PYTHONPATH``).  The module imports only
numpy, so that a worker process loading one of the light adapters starts in a fraction of a second.

* ``Sticky`` -- the golden answer, except on a start that sticks (its golden log has a ``stick`` or
  a wall ``contact``): there ``step`` and ``events`` spin, as a smooth solver does on ``f sgn(v)``.  On a
  call with several starts (and always with ``in_c=True``) the spin is one C call that never
  returns to the interpreter, so no signal reaches it: only killing its process stops it; on a
  call with one start it is a pure-Python loop.  Both spins are bounded (2**62 turns: centuries);
* ``SlowKind`` (``SLOW_CHATTER``) -- ``Sticky``, slow (0.8 s a start) on one kind, chatter;
* ``NAIVE`` -- the naive ``solve_ivp`` integrator (``NaiveSolveIvp``): ``f sign(v)`` in its
  right-hand side, so it hangs where the motion sticks;
* ``FROZEN`` -- returns its start unchanged (fast and wrong) without friction, spins in Python with
  friction: a cheap adapter to interrupt;
* ``RETURNS_NONE``, ``WRONG_SHAPE``, ``INT_ARRAYS``, ``NO_STEP`` -- each breaks the protocol one way
  (``tests/adapter_raising_on_import.py`` is the module that raises on import).
"""
import itertools

import numpy as np

TURNS = 2 ** 62
EFFECTS = frozenset({"walls", "forcing", "friction", "restitution", "damping", "position_forcing"})


def spin_python(turns=TURNS):
    n = 0
    while n < turns:
        n += 1
    raise RuntimeError(f"spun {turns} turns in Python")


def spin_in_c(turns=TURNS):
    """One C call that never returns to the interpreter: the builtin ``sum`` over
    ``itertools.repeat`` checks no signals, so a signal handler (a ``SIGALRM`` timeout, Ctrl-C)
    runs only once it is done.  Only killing its process stops it."""
    return sum(itertools.repeat(1, turns))


class Sticky:
    """The golden answer itself (rounded to float64) as the integrator -- every kind grades A --
    except on a start that sticks (module docstring): there it spins."""

    name = "sticky: loops on sticking starts"
    effects = EFFECTS

    def __init__(self, in_c=None):
        self.in_c = in_c

    @staticmethod
    def _cases(params, x, v):
        from cross_check import scenes
        from cross_check.score.golden import scene_cases

        name = next(n for n in scenes.SCENES if scenes.scene(n).floats() == params)
        by_start = {(c.x, c.v): c for c in scene_cases(name)}
        return [by_start[(float(a), float(b))] for a, b in zip(x, v)]

    def _spin_on_sticking(self, cases):
        for c in cases:
            if any(e[0] in ("stick", "contact") for e in c.events):
                if self.in_c or (self.in_c is None and len(cases) > 1):
                    raise RuntimeError(f"spun {spin_in_c()} turns in C")
                spin_python()

    def step(self, params, x, v, periods):
        if periods != 1:
            raise ValueError("the golden data holds one period")
        cases = self._cases(params, x, v)
        self._spin_on_sticking(cases)
        return np.array([float(c.phi[0]) for c in cases]), np.array([float(c.phi[1]) for c in cases])

    def events(self, params, x, v):
        cases = self._cases(params, x, v)
        self._spin_on_sticking(cases)
        return [[(e[0], *(float(a) for a in e[1:5])) for e in c.events] for c in cases]


def sticky_in_c():
    return Sticky(in_c=True)


class SlowKind(Sticky):
    """``Sticky`` (the golden answer, a spin on sticking starts) that takes ``slow`` seconds on each
    start of ``kind`` and ``typical`` seconds on each other start: a correct but slow regime, far
    above the adapter's median start, in an integrator that also hangs elsewhere (issue 37: the
    short budget must never cut it)."""

    def __init__(self, kind="chatter", slow=0.8, typical=0.01):
        super().__init__()
        self.kind, self.slow, self.typical = kind, slow, typical
        self.name = f"slow on {kind}: {slow} s a start, {typical} s elsewhere; loops on sticking starts"

    def step(self, params, x, v, periods):
        import time

        out = super().step(params, x, v, periods)
        time.sleep(sum(self.slow if c.kind == self.kind else self.typical for c in self._cases(params, x, v)))
        return out


class Frozen:
    name = "frozen: returns its start, spins on friction"
    effects = EFFECTS

    def step(self, params, x, v, periods):
        if params["f"] > 0:
            spin_python()
        return np.array(x, float), np.array(v, float)


class ReturnsNone(Frozen):
    name = "returns None"

    def step(self, params, x, v, periods):
        return None


class WrongShape(Frozen):
    name = "wrong shape"

    def step(self, params, x, v, periods):
        return np.zeros(len(x) + 1), np.zeros(len(x) + 1)


class IntArrays(Frozen):
    name = "integer arrays"

    def step(self, params, x, v, periods):
        return np.zeros(len(x), dtype=np.int64), np.zeros(len(x), dtype=np.int64)


class NoStep:
    name = "no step"
    effects = frozenset({"walls", "forcing"})


SLOW_CHATTER = SlowKind()
FROZEN = Frozen()
RETURNS_NONE, WRONG_SHAPE, INT_ARRAYS, NO_STEP = ReturnsNone(), WrongShape(), IntArrays(), NoStep()


class NaiveSolveIvp:
    """The integrator a careful user of a general solver writes first (issue 37): scipy's
    ``solve_ivp`` (DOP853, ``rtol`` 1e-10, ``atol`` 1e-12) on ``x' = v, v' = F cos(k x) cos(w t)
    - f sign(v) - c v`` -- friction as ``f * sign(v)`` in the right-hand side -- with terminal wall
    events (``x - r`` rising, ``x - l`` falling), restarted after each with ``v -> -e v`` and ``x``
    set on the wall.  Correct in flight and at impacts; where the motion sticks, ``sign(v)``
    makes ``v`` chatter about 0, the step size collapses (the jump ``2 f h`` of ``v'`` per step
    must stay below ``atol``) and a period takes hours: only a budget stops it.  Where bounces
    accumulate (chatter, ``e < 1`` against a pushing force) the restarts never reach the limit;
    ``MAX_SEGMENTS`` bounds them (then ``RuntimeError``).  scipy is imported on the first call (the
    module stays light)."""

    name = "naive solve_ivp: f sign(v) in the right-hand side"
    effects = EFFECTS
    MAX_SEGMENTS = 10_000

    def __init__(self, rtol=1e-10, atol=1e-12, method="DOP853"):
        self.rtol, self.atol, self.method = rtol, atol, method

    def _one(self, p, x, v, t_end):
        from scipy.integrate import solve_ivp

        F, f, w, c, l, r = p["F"], p["f"], p["omega"], p["damping"], p["l"], p["r"]
        k, e = p["wavenumber"], p["restitution"]

        def rhs(t, y):
            force = F * (1.0 if k is None else np.cos(k * y[0])) * np.cos(w * t)
            return [y[1], force - f * np.sign(y[1]) - c * y[1]]

        def right(t, y):
            return y[0] - r

        def left(t, y):
            return y[0] - l

        right.terminal = left.terminal = True
        right.direction, left.direction = 1.0, -1.0
        t = 0.0
        for _ in range(self.MAX_SEGMENTS):
            sol = solve_ivp(rhs, (t, t_end), [x, v], method=self.method, rtol=self.rtol, atol=self.atol,
                            events=[right, left])
            if sol.status == -1:
                raise RuntimeError(f"solve_ivp: {sol.message} at t={t}, x={x}, v={v}")
            if sol.status == 0:
                return float(sol.y[0, -1]), float(sol.y[1, -1])
            hit = 0 if sol.t_events[0].size else 1
            t, v = float(sol.t_events[hit][0]), -e * float(sol.y_events[hit][0][1])
            x = r if hit == 0 else l
        raise RuntimeError(f"more than {self.MAX_SEGMENTS} restarts before t={t_end} (t={t}, x={x}, v={v})")

    def step(self, params, x, v, periods):
        t_end = periods * 2 * np.pi / params["omega"]
        out = [self._one(params, float(a), float(b), t_end) for a, b in zip(x, v)]
        return np.array([o[0] for o in out]), np.array([o[1] for o in out])


NAIVE = NaiveSolveIvp()
