"""Adapters for the scorer's tests, loaded by their ``MODULE:NAME`` spec (``tests/`` is on
``sys.path`` under pytest; a subprocess gets it through ``PYTHONPATH``).  The module imports only
numpy, so that a worker process loading one of the light adapters starts in a fraction of a second.

* ``Sticky`` -- the golden answer, except on a start that sticks (its golden log has a ``stick`` or
  a wall ``contact``): there ``step`` and ``events`` spin, as a smooth solver does on ``f sgn(v)``.  On a
  call with several starts (and always with ``in_c=True``) the spin is one C call that never
  returns to the interpreter, so no signal reaches it: only killing its process stops it; on a
  call with one start it is a pure-Python loop.  Both spins are bounded (2**62 turns: centuries);
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


FROZEN = Frozen()
RETURNS_NONE, WRONG_SHAPE, INT_ARRAYS, NO_STEP = ReturnsNone(), WrongShape(), IntArrays(), NoStep()
