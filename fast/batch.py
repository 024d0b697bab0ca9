"""The batch driver: one compiled per-state event loop, run over a batch on threads.

An *engine* is a module with two functions (``fast.loop`` for the closed-form flights,
``fast.ode`` for position-dependent forcing):

* ``params(scene) -> P``: the scene's float64 constants as a 1-d array (named slots);
* ``run_range(P, x, v, t_end, t_end_lo, jac, max_events, out_x, out_v, out_zv, out_J,
  out_nev, out_status, out_paths, log_kind, log_t, log_x, log_v, log_vb, log_cnt, i0, i1)``,
  compiled
  with ``fast.jit.kernel`` (``nogil``): integrates states ``i0 <= i < i1`` of the float64
  arrays ``x, v`` from ``t = 0`` to the double-double end ``t_end + t_end_lo`` and writes

  - ``out_x[i], out_v[i]``: the state at the end (right limit);
  - ``out_zv[i]`` (uint8): 1 if the velocity is zero somewhere on ``[0, t_end]`` (turn,
    stick, wall contact, chatter; a smooth reversal when ``f = 0``; ``v0 = 0``);
  - ``out_J[i]`` (4 floats, row-major ``Phi'``) when ``jac``, else ``out_J`` has 0 rows;
  - ``out_nev[i]``: the number of events of the state (a chatter tail counts as one);
  - ``out_status[i]``: ``OK``, or why the state stopped (``EVENT_BUDGET``: more than
    ``max_events`` events; ``BOUNCE_BUDGET``: the same, in a run of bounces at one wall
    (``fast.output.out_of_events``); ``LOOP_BOUND``: an inner loop exceeded its bound;
    ``NON_FINITE``; ``TOO_FAST``: a numerical flight's step below float64's time resolution);
  - ``out_paths[i]``: the code paths the state took, as bits (``fast.state.PATH_*``): the
    evidence that a scene runs only the effects it switches on;
  - events ``j < cap`` of the log (``log_*`` of shape ``(n, cap)``, ``cap = 0`` without a
    log): kind code into ``fast.KINDS``, time, position, velocity after and before, and the
    impacts simulated one by one before a summed chatter tail (0 for other kinds).

Every state's numbers depend on that state only, so the split into chunks and threads
never changes a result: the same bits for every batch size, order and thread count.

Threads: every core available to the process by default (``default_threads``: the CPU
affinity mask where the platform has one, else ``os.cpu_count()``), overridden by the
environment variable ``VIBRO_THREADS`` (an integer in ``[1, MAX_THREADS]``) and by the
``threads=`` keyword of each public function.
"""
from __future__ import annotations

import functools
import os
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

OK, EVENT_BUDGET, LOOP_BOUND, NON_FINITE, BOUNCE_BUDGET, TOO_FAST = 0, 1, 2, 3, 4, 5
_WHY = {EVENT_BUDGET: "more than max_events = {max_events} events",
        LOOP_BOUND: "an inner loop bound was exceeded",
        NON_FINITE: "a non-finite value appeared",
        BOUNCE_BUDGET: "more than max_events = {max_events} events, the last of them a run of bounces at one "
                       "wall that does not sum to rest (a bounce shrinks by e sqrt((A - f)/(A + f)): with "
                       "restitution 1 and no friction it does not, and every bounce is an event); raise "
                       "max_events to follow them",
        TOO_FAST: "a numerical flight's step 2 pi/(S k |v|) fell below the resolution of its clock: the "
                  "speed grew beyond what fast's position-forcing flights hold (fast.ode.max_speed); the "
                  "reference runs such states"}

#: a process-wide override of the thread count (None: ``default_threads()``, read at each call)
THREADS = None
#: the largest thread count accepted (``threads=`` and ``VIBRO_THREADS``)
MAX_THREADS = 1024
#: the environment variable that overrides the default thread count
ENV = "VIBRO_THREADS"
#: chunks per thread (the states of a batch differ in cost: several chunks balance the load)
CHUNKS_PER_THREAD = 8
#: a batch smaller than this runs on the calling thread (thread start-up costs ~50 us)
MIN_THREADED = 256
#: initial capacity of an event log row (rows that need more are run again with more)
LOG_CAP = 32


def cores() -> int:
    """The cores this process may run on: ``len(os.sched_getaffinity(0))`` where the platform
    has it (Linux: the affinity mask, so a container or ``taskset`` limit is seen), else
    ``os.cpu_count()``."""
    affinity = getattr(os, "sched_getaffinity", None)
    n = len(affinity(0)) if affinity is not None else os.cpu_count()
    return max(1, int(n or 1))


def default_threads() -> int:
    """The thread count of a call without ``threads=``: ``VIBRO_THREADS`` if set, else every
    core available to the process (``cores()``), evaluated now."""
    env = os.environ.get(ENV, "").strip()
    return _env_threads(env) if env else cores()


@functools.lru_cache(maxsize=16)
def _env_threads(env):
    try:
        n = int(env)
    except ValueError:
        n = None
    if n is None or not 1 <= n <= MAX_THREADS:
        raise ValueError(f"fast: the environment variable {ENV} must be an integer in "
                         f"[1, {MAX_THREADS}], got {env!r}")
    return n


def check_threads(threads, n=None) -> int:
    """``threads=``: None (the default, ``default_threads()``) or an int in ``[1, MAX_THREADS]``.

    ``n``, the batch size when known: a batch smaller than ``MIN_THREADED`` runs on the calling
    thread whatever the count, so its default is 1 without counting the cores (a system call
    per call costs a Newton step more than its states); ``VIBRO_THREADS`` is checked all the same.
    """
    if threads is None:
        if THREADS is not None:
            return THREADS
        env = os.environ.get(ENV, "").strip()
        if env:
            return _env_threads(env)
        return 1 if n is not None and n < MIN_THREADED else cores()
    if isinstance(threads, bool) or not isinstance(threads, (int, np.integer)):
        raise TypeError(f"fast: threads must be None or an integer in [1, {MAX_THREADS}], got {threads!r}")
    if not 1 <= threads <= MAX_THREADS:
        raise ValueError(f"fast: threads must be an integer in [1, {MAX_THREADS}], got {threads!r}")
    return int(threads)


@dataclass
class Result:
    """What ``run`` gives back: flat arrays over the batch."""

    x: np.ndarray
    v: np.ndarray
    zero_velocity: np.ndarray
    J: np.ndarray | None
    n_events: np.ndarray
    paths: np.ndarray
    log: tuple | None


def _chunks(n, threads):
    if threads <= 1 or n < MIN_THREADED:
        return [(0, n)]
    k = min(threads * CHUNKS_PER_THREAD, n)
    edges = np.linspace(0, n, k + 1).astype(np.int64)
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:]) if b > a]


def _log_arrays(n, cap):
    if cap == 0:
        return _NO_LOG
    return (np.full((n, cap), -1, np.int8), np.full((n, cap), np.nan), np.full((n, cap), np.nan),
            np.full((n, cap), np.nan), np.full((n, cap), np.nan), np.zeros((n, cap), np.int64))


#: the log of a run without one: empty arrays (``cap = 0``: the kernel never writes them), shared
_NO_LOG = (np.full((0, 0), -1, np.int8), np.full((0, 0), np.nan), np.full((0, 0), np.nan),
           np.full((0, 0), np.nan), np.full((0, 0), np.nan), np.zeros((0, 0), np.int64))


def _run_once(engine, P, x, v, t_end, t_end_lo, jac, max_events, cap, threads):
    n = x.size
    out = (np.empty(n), np.empty(n), np.zeros(n, np.uint8), np.zeros((n if jac else 0, 4)),
           np.zeros(n, np.int64), np.zeros(n, np.int64), np.zeros(n, np.int64))
    log = _log_arrays(n, cap)
    spans = _chunks(n, threads)
    if len(spans) == 1:
        engine.run_range(P, x, v, t_end, t_end_lo, jac, max_events, *out, *log, 0, n)
    else:
        def one(span):
            engine.run_range(P, x, v, t_end, t_end_lo, jac, max_events, *out, *log, span[0], span[1])

        with ThreadPoolExecutor(min(threads, len(spans))) as pool:
            list(pool.map(one, spans))
    return out, log


def run(engine, P, x, v, t_end, t_end_lo=0.0, *, jac=False, log=False, max_events,
        threads=None):
    """Run ``engine`` over the flat float64 arrays ``x, v`` (module docstring).

    ``threads``: None (``default_threads()``, or the module's ``THREADS`` override) or an int
    in ``[1, MAX_THREADS]``; the results do not depend on it.  ``log``: gather the event log
    (rows that overflow ``LOG_CAP`` are run again with room for all their events).  Raises
    ``RuntimeError`` naming the states that did not finish.
    """
    threads = check_threads(threads)
    x = np.ascontiguousarray(x, dtype=np.float64)
    v = np.ascontiguousarray(v, dtype=np.float64)
    cap = LOG_CAP if log else 0
    (xs, vs, zv, J, nev, status, paths), logs = _run_once(engine, P, x, v, t_end, t_end_lo, jac,
                                                   max_events, cap, threads)
    if np.count_nonzero(status):
        _raise_on_failures(status, nev, x, v, max_events)
    if log and nev.size and nev.max() > cap:
        over = np.flatnonzero(nev > cap)
        big = int(nev[over].max())
        _, more = _run_once(engine, P, x[over], v[over], t_end, t_end_lo, False, max_events,
                            big, threads)
        logs = tuple(np.concatenate([a, np.full((a.shape[0], big - cap), _pad(a), a.dtype)], 1)
                     for a in logs)
        for a, b in zip(logs, more):
            a[over] = b
    return Result(xs, vs, zv.astype(bool), J if jac else None, nev, paths, logs if log else None)


def run_periods(engine, P, x, v, t_end, t_end_lo, periods, *, max_events, threads=None,
                iterates=None):
    """``Phi^periods`` on the flat float64 arrays ``x, v``: ``periods`` runs over
    ``[0, t_end + t_end_lo]``, each from ``t = 0`` with the previous run's end state (the
    forcing is periodic): the same bits as ``periods`` calls of ``run``, without its per-call
    set-up.  ``iterates``: a pair of arrays ``(periods + 1, n)`` to fill with every iterate's
    ``x`` and ``v`` (the start first).  Returns the final ``(x, v)``; raises like ``run`` in the
    period that fails."""
    threads = check_threads(threads, x.size)
    x = np.ascontiguousarray(x, dtype=np.float64)
    v = np.ascontiguousarray(v, dtype=np.float64)
    if iterates is not None:
        iterates[0][0], iterates[1][0] = x, v
    for k in range(1, periods + 1):
        (xs, vs, _, _, nev, status, _), _ = _run_once(engine, P, x, v, t_end, t_end_lo, False,
                                                     max_events, 0, threads)
        if np.count_nonzero(status):
            _raise_on_failures(status, nev, x, v, max_events)
        x, v = xs, vs
        if iterates is not None:
            iterates[0][k], iterates[1][k] = x, v
    return x, v


def _pad(a):
    return -1 if a.dtype == np.int8 else (0 if a.dtype == np.int64 else np.nan)


def _raise_on_failures(status, nev, x, v, max_events):
    bad = np.flatnonzero(status != OK)
    if not bad.size:
        return
    parts = []
    for code in np.unique(status[bad]):
        idx = bad[status[bad] == code][:5]
        states = ", ".join(f"state {i} (x0={float(x[i])!r}, v0={float(v[i])!r}, {int(nev[i])} events)"
                           for i in idx)
        why = _WHY.get(int(code), f"status {int(code)}").format(max_events=max_events)
        parts.append(f"{int(np.count_nonzero(status[bad] == code))} state(s): {why}: {states}")
    raise RuntimeError("fast: " + "; ".join(parts))
