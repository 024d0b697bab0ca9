"""Public entry points of ``fast``: validation, the engine for the scene, and the results'
shapes (the public function validates and converts; the compiled core trusts its input).

Inputs ``x, v`` are numbers or arrays of real numbers (bool, complex, object and string
arrays are a ``TypeError``; a value that is not finite, a position outside the walls or a
speed above the engine's ``max_speed`` (``1e100``; under position forcing
``2^30 w/(S k)``, ``fast.ode.max_speed``), a ``ValueError`` naming the offending entries and
the bound); they broadcast together and the results
have the broadcast shape.  ``periods = 0`` is the identity (as in ``reference``).

``max_events`` bounds the events of each state in one call (a chatter tail counts as one):
at the compiled rate the default ``MAX_EVENTS`` takes at most a few seconds per state.
A state that needs more (a gap of 1e-9 with ``v = 1``: 6e9 impacts per period) raises a
``RuntimeError`` naming the states and their event counts instead of running on.

``threads`` (every function): None for ``default_threads()`` (every core available to the
process, or the environment variable ``VIBRO_THREADS``), or an int in ``[1, 1024]``.  The
results are the same bits for every thread count.
"""
from __future__ import annotations

import functools
import numbers
import time

import numpy as np

from . import batch, loop, ode
from .params import check_scene

#: default per-state event budget of one call (about a second of compiled work)
MAX_EVENTS = 10_000_000
_REAL_KINDS = "iuf"
#: batches up to this size are validated in Python (a Newton step's few states)
_SMALL = 8
#: the coarsest ``steps_per_period`` (module docstring): ``S = 16`` errs ~1e-8 (``(128/16)^8``
#: times the floor), about the most a Newton search can use
STEPS_MIN = 16


def _engine(scene):
    """``(engine, P)`` for the scene: position forcing takes the numerical flights of
    ``fast.ode`` (the only path to a numerical ODE solver), everything else the closed-form
    loop."""
    return _engine_of(check_scene(scene))


def validate_scene(scene) -> None:
    """Check that ``fast`` can run ``scene``, before any state is given: ``TypeError`` if it is
    not a ``reference.scene.Scene``, ``ValueError`` naming the parameter and the derived quantity
    (``F/w^2``, ``T``, ``f T``, the event finder's bounds, ...) that float64 cannot hold
    (``fast.params.check_ranges``).  Every public function makes the same check."""
    _engine(scene)


@functools.lru_cache(maxsize=256)
def _engine_of(scene):
    if scene.has("position_forcing"):
        return ode, ode.params(scene)
    return loop, loop.params(scene)


def _real_array(name, a):
    arr = np.asarray(a)
    if arr.dtype.kind not in _REAL_KINDS:
        raise TypeError(f"fast: {name} must be real numbers (int or float), got dtype "
                        f"{arr.dtype} ({type(a).__name__}); convert with np.asarray(..., float)")
    return arr.astype(np.float64, copy=False)


def _validate(engine, P, x, v):
    """Broadcast ``x, v`` to float64 arrays; finite, with ``l <= x <= r`` and ``|v| <= V_MAX``."""
    x, v = _real_array("x", x), _real_array("v", v)
    if x.shape != v.shape:
        x, v = np.broadcast_arrays(x, v)
    l, r = float(P[engine.p.L]), float(P[engine.p.R])
    if _fine(x, v, l, r, engine.max_speed(P)):
        return x, v
    for name, a in (("x", x), ("v", v)):
        bad = ~np.isfinite(a)
        if bad.any():
            raise ValueError(f"fast: non-finite state: {_items(name, a, bad)} "
                             f"({int(bad.sum())} in all)")
    bad = (x < l) | (x > r)
    if bad.any():
        raise ValueError(f"fast: {_items('x', x, bad)} is outside the walls [{l!r}, {r!r}] "
                         f"({int(bad.sum())} state(s) in all)")
    bad = abs(v) > engine.max_speed(P)
    if bad.any():
        raise ValueError(f"fast: {_items('v', v, bad)} is above |v| <= {engine.max_speed(P):.6g}, the largest "
                         f"speed fast holds in this scene ({int(bad.sum())} state(s) in all): "
                         f"{_SPEED_WHY[engine.__name__]}; the reference runs such states (at enough dps)")
    return x, v


#: why each engine has its speed bound (``max_speed`` of ``fast.loop`` and ``fast.ode``)
_SPEED_WHY = {"fast.loop": "FAST_MAX, the magnitudes the loop's products stay normal within (fast.loop.max_speed)",
              "fast.ode": "a numerical flight steps 2 pi/(S k |v|) and a period takes at most "
                          "MAX_STEPS_PER_PERIOD = 2^30 steps (fast.ode.max_speed: MAX_STEPS_PER_PERIOD w/(S k))"}


def _fine(x, v, l, r, vmax):
    """All ``l <= x <= r`` and ``|v| <= vmax`` (NaN fails the comparisons; the usual case in one
    pass, in Python for the few states of a Newton step, where numpy's reductions cost more)."""
    if x.size <= _SMALL:
        return bool(x.size) and all(l <= a <= r for a in x.flat) and all(abs(b) <= vmax for b in v.flat)
    return bool(np.all(x >= l)) and bool(np.all(x <= r)) and bool(np.all(abs(v) <= vmax))


def _items(name, a, bad):
    where = np.argwhere(bad)[:5]
    return ", ".join(f"{name}[{', '.join(map(str, i))}] = {float(a[tuple(i)])!r}" for i in where)


def _count(name, value, *, low=0):
    """A non-negative integer argument (``TypeError`` for None or a string, ``ValueError``
    for a fractional or too small number)."""
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"fast: {name} must be an integer >= {low}, got {value!r}")
    if int(value) != value or value < low:
        raise ValueError(f"fast: {name} must be an integer >= {low}, got {value!r}")
    return int(value)


def _setup(scene, x, v, max_events, threads=None, steps=None):
    """The engine, its constants (with ``steps``: ``steps_per_period``), the validated states,
    ``max_events`` and the thread count."""
    engine, P = _engine(scene)
    x, v = _validate(engine, P, x, v)
    if steps is not None:
        steps = _count("steps_per_period", steps, low=STEPS_MIN)
        if steps > ode.STEPS_PER_PERIOD:
            raise ValueError(f"fast: steps_per_period must be an integer in [{STEPS_MIN}, "
                             f"{ode.STEPS_PER_PERIOD}] (or None for {ode.STEPS_PER_PERIOD}), got {steps!r}")
        if engine is ode:
            P = ode.with_steps(P, steps)
    return engine, P, x, v, _count("max_events", max_events, low=1), batch.check_threads(threads, x.size)


def _period(engine, P):
    return P[engine.p.T], P[engine.p.T_LO]


def _run(engine, P, x, v, t_end, t_end_lo, max_events, threads, **kw):
    return batch.run(engine, P, x.ravel(), v.ravel(), t_end, t_end_lo, max_events=max_events,
                     threads=threads, **kw)


def stroboscopic_map(scene, x, v, *, periods=1, max_events=MAX_EVENTS, threads=None,
                     steps_per_period=None):
    """``Phi^periods(x, v)``: the state at ``t = periods T`` of the motion from ``(x, v)`` at
    ``t = 0``, each period from ``t0 = 0`` (the forcing is ``T``-periodic) with the state
    rounded to float64 in between; ``periods = 0`` returns the input."""
    periods = _count("periods", periods)
    engine, P, x, v, max_events, threads = _setup(scene, x, v, max_events, threads, steps_per_period)
    xs, vs = batch.run_periods(engine, P, x.ravel().copy(), v.ravel().copy(), *_period(engine, P),
                               periods, max_events=max_events, threads=threads)
    return xs.reshape(x.shape), vs.reshape(x.shape)


def orbit(scene, x, v, n, *, max_events=MAX_EVENTS, threads=None):
    """Iterates ``Phi^k(x, v)``, ``k = 0..n``: arrays of shape ``(n + 1,) + shape``."""
    n = _count("n", n)
    engine, P, x, v, max_events, threads = _setup(scene, x, v, max_events, threads)
    X, V = np.empty((n + 1, x.size)), np.empty((n + 1, x.size))
    batch.run_periods(engine, P, x.ravel(), v.ravel(), *_period(engine, P), n,
                      max_events=max_events, threads=threads, iterates=(X, V))
    return X.reshape((n + 1,) + x.shape), V.reshape((n + 1,) + x.shape)


def map_and_jacobian(scene, x, v, *, periods=1, max_events=MAX_EVENTS, threads=None,
                     steps_per_period=None):
    """``(x1, v1, J, zero_velocity)`` over one period in one pass; ``J`` of shape ``shape +
    (2, 2)`` is ``Phi'``: the time-ordered product of the paper's Table 1 matrices
    (reflection with the velocity before impact; sticking ``[[1, 0], [0, 0]]``; wall
    contact the zero matrix).

    ``periods = k >= 1``: ``Phi^k`` and the chain rule ``J_k = Phi'(z_{k-1}) ... Phi'(z_0)``
    (later on the left, one matrix product per period), each period from ``t = 0`` as in
    ``stroboscopic_map``; ``zero_velocity`` if any of the ``k`` periods reaches it."""
    periods = _count("periods", periods, low=1)
    engine, P, x, v, max_events, threads = _setup(scene, x, v, max_events, threads, steps_per_period)
    res = _run(engine, P, x, v, *_period(engine, P), max_events, threads, jac=True)
    xs, vs, zero = res.x, res.v, res.zero_velocity
    J = res.J.reshape(-1, 2, 2)
    for _ in range(periods - 1):
        res = batch.run(engine, P, xs, vs, *_period(engine, P), jac=True, max_events=max_events,
                        threads=threads)
        xs, vs, zero, J = res.x, res.v, zero | res.zero_velocity, res.J.reshape(-1, 2, 2) @ J
    sh = x.shape
    return xs.reshape(sh), vs.reshape(sh), J.reshape(sh + (2, 2)), zero.reshape(sh)


def map_and_zero_velocity(scene, x, v, *, max_events=MAX_EVENTS, threads=None, steps_per_period=None):
    """``(x1, v1, zero_velocity)`` over one period in one pass: ``stroboscopic_map`` and
    ``zero_velocity`` at once, without ``Phi'`` (what an orbit that tracks ``Omega_dissip``
    needs: ``map_and_jacobian`` costs ~1.33 times as much under position forcing, issue 33)."""
    engine, P, x, v, max_events, threads = _setup(scene, x, v, max_events, threads, steps_per_period)
    res = _run(engine, P, x, v, *_period(engine, P), max_events, threads)
    sh = x.shape
    return res.x.reshape(sh), res.v.reshape(sh), res.zero_velocity.reshape(sh)


def jacobian(scene, x, v, *, max_events=MAX_EVENTS, threads=None):
    """``Phi'`` over one period, shape ``shape + (2, 2)`` (``map_and_jacobian``)."""
    return map_and_jacobian(scene, x, v, max_events=max_events, threads=threads)[2]


def zero_velocity(scene, x, v, *, max_events=MAX_EVENTS, threads=None):
    """Whether the motion over ``[0, T]`` reaches zero velocity (turn, stick, contact,
    chatter; with ``f = 0`` a smooth velocity reversal counts too): the paper's
    ``Omega_dissip``; the rest is ``Omega_pres`` (``map_and_zero_velocity``'s pass)."""
    return map_and_zero_velocity(scene, x, v, max_events=max_events, threads=threads)[2]


def check_t_end(t_end):
    """A finite end time ``>= 0`` as a float."""
    if isinstance(t_end, bool) or not isinstance(t_end, numbers.Real):
        raise TypeError(f"fast: t_end must be a real number >= 0, got {t_end!r}")
    t_end = float(t_end)
    if not (t_end >= 0 and np.isfinite(t_end)):
        raise ValueError(f"fast: t_end must be finite and >= 0, got {t_end!r}")
    return t_end


def flow(scene, x, v, t_end, *, max_events=MAX_EVENTS, threads=None):
    """The state at ``t_end`` (any ``t_end >= 0``) of the motion from ``(x, v)`` at 0, in one
    pass (``stroboscopic_map`` restarts each period at ``t = 0`` instead)."""
    t_end = check_t_end(t_end)
    engine, P, x, v, max_events, threads = _setup(scene, x, v, max_events, threads)
    res = _run(engine, P, x, v, t_end, 0.0, max_events, threads)
    return res.x.reshape(x.shape), res.v.reshape(x.shape)


def warm_up(*, closed_form: bool = True, position_forcing: bool = True) -> dict:
    """Compile the kernels of ``fast``'s two engines, or load them from numba's cache, before a
    real call needs them; return the seconds each took, ``{"closed_form": s, "position_forcing":
    s}`` (the engines asked for).

    The first call of any function on an engine compiles that engine's whole event loop (one
    set of kernels serves every function, with or without the Jacobian, any thread count):
    cold, about 22 CPU s for the closed-form loop (``fast.loop``) and 14 s for the numerical
    flights of position forcing (``fast.ode``) on the 2-core machine of issue 33 (40 and 30
    before ``fast.jit._Dispatcher``, 33 and 22 before inlining was left to LLVM: ``fast.jit``;
    ~2.5x a quieter machine's figures); from the cache, well
    under a second.  A program that wants the compilation out of its timings, or on another
    core, calls this first (``python -m cross_check report`` compiles the two engines in two
    processes at once).  The call is one period of one state of a small scene of each engine."""
    from reference.scene import Scene

    scenes = {"closed_form": closed_form, "position_forcing": position_forcing}
    out = {}
    for name, wanted in scenes.items():
        if wanted:
            t0 = time.perf_counter()
            scene = Scene(F=1, f="0.1", omega=1, l=0, r=1,
                          wavenumber=1 if name == "position_forcing" else None)
            map_and_jacobian(scene, 0.5, 0.25, threads=1)
            out[name] = time.perf_counter() - t0
    return out
