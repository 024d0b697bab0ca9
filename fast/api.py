"""Public entry points of ``fast``: validation, batching over chunks and threads.

States are processed in chunks of ``CHUNK`` (16384: measured best of 4096..65536 on one
thread, the larger chunks amortise the per-ufunc Python overhead, the smaller ones stay
in cache).  Batches of at least ``2 THREADS CHUNK`` states run on ``THREADS`` threads
(numpy releases the GIL inside its ufuncs) in equal chunks of at most ``4 CHUNK``, a
multiple of ``THREADS`` of them: the kernel's ufuncs on a few thousand elements last
microseconds, so two threads on small chunks mostly wait for the GIL (measured at
N = 1e4: 2 threads x 5000 ran at 0.65-0.85x one thread), while one large chunk per
thread keeps both cores busy to the end (N = 1e5: 1.2-1.35x the wall throughput of
7 chunks of 16384 on 2 threads).  Every state's result depends on that state only, so
the chunking never changes a number.
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from . import kernel, ode
from .params import Params

CHUNK = 16384
THREADS = min(2, os.cpu_count() or 1)


def _validate(P, x, v):
    x, v = np.broadcast_arrays(np.asarray(x, dtype=float), np.asarray(v, dtype=float))
    for name, a in (("x", x), ("v", v)):
        bad = ~np.isfinite(a)
        if bad.any():
            where = np.argwhere(bad)[:5]
            items = ", ".join(f"{name}[{', '.join(map(str, i))}] = {float(a[tuple(i)])!r}" for i in where)
            raise ValueError(f"fast: non-finite state: {items} ({int(bad.sum())} in all)")
    bad = (x < P.l) | (x > P.r)
    if bad.any():
        where = np.argwhere(bad)[:5]
        items = ", ".join(f"x[{', '.join(map(str, i))}] = {float(x[tuple(i)])!r}" for i in where)
        raise ValueError(f"fast: {items} is outside the walls [{P.l!r}, {P.r!r}] "
                         f"({int(bad.sum())} state(s) in all)")
    return x, v


def _params(scene):
    """The float64 parameters: closed-form flights (base model, restitution e < 1,
    damping c > 0); scenes with position forcing get ``fast.ode``'s (``Params.from_scene``
    routes them: the only path to a numerical ODE solver)."""
    return Params.from_scene(scene)


def _run_all(P, x, v, t_end, jac=False, log=None, t_end_lo=0.0):
    """Run the kernel over flat arrays in chunks to ``t_end + t_end_lo`` (a period:
    ``P.T + P.T_lo``, the exact period as a double-double); returns (x, v, zv, J)."""
    if not isinstance(P, Params):           # position forcing: fast.ode's event loop
        return ode.run_all(P, x, v, t_end, jac=jac, log=log)
    n = x.size
    threaded = log is None and THREADS > 1 and n >= 2 * THREADS * CHUNK
    if threaded:        # equal chunks of at most 4 CHUNK, a multiple of THREADS of them
        k = THREADS * -(-n // (THREADS * 4 * CHUNK))
        size = -(-n // k)
    else:
        size = CHUNK
    starts = list(range(0, n, size)) or [0]

    def one(i0):
        sl = slice(i0, min(i0 + size, n))
        return kernel.run(P, x[sl], v[sl], t_end, jac=jac, log=log, offset=i0, t_end_lo=t_end_lo)

    if threaded and len(starts) > 1:
        with ThreadPoolExecutor(THREADS) as pool:
            parts = list(pool.map(one, starts))
    else:
        parts = [one(i0) for i0 in starts]
    if log is not None and len(starts) > 1:
        raise AssertionError("event logs are gathered for a single chunk only")
    xs = np.concatenate([p[0] for p in parts])
    vs = np.concatenate([p[1] for p in parts])
    zv = np.concatenate([p[2] for p in parts])
    J = np.concatenate([p[3] for p in parts]) if jac else None
    return xs, vs, zv, J


def stroboscopic_map(scene, x, v, *, periods=1):
    """``Phi^periods(x, v)``: the state at ``t = periods T`` of the motion from ``(x, v)``
    at ``t = 0`` (each period from ``t0 = 0``: the forcing is ``T``-periodic).

    ``x, v`` broadcast together; returns arrays of the broadcast shape.
    """
    if int(periods) != periods or periods < 0:
        raise ValueError(f"fast: periods must be an integer >= 0, got {periods!r}")
    P = _params(scene)
    x, v = _validate(P, x, v)
    shape = x.shape
    xs, vs = x.ravel().copy(), v.ravel().copy()
    for _ in range(int(periods)):
        xs, vs, _, _ = _run_all(P, xs, vs, P.T, t_end_lo=P.T_lo)
    return xs.reshape(shape), vs.reshape(shape)


def orbit(scene, x, v, n):
    """Iterates ``Phi^k(x, v)``, ``k = 0..n``: arrays of shape ``(n + 1,) + shape``."""
    if int(n) != n or n < 0:
        raise ValueError(f"fast: n must be an integer >= 0, got {n!r}")
    P = _params(scene)
    x, v = _validate(P, x, v)
    X = np.empty((int(n) + 1,) + x.shape)
    V = np.empty_like(X)
    X[0], V[0] = x, v
    xs, vs = x.ravel().copy(), v.ravel().copy()
    for i in range(1, int(n) + 1):
        xs, vs, _, _ = _run_all(P, xs, vs, P.T, t_end_lo=P.T_lo)
        X[i], V[i] = xs.reshape(x.shape), vs.reshape(x.shape)
    return X, V


def jacobian(scene, x, v):
    """``Phi'`` over one period, shape ``shape + (2, 2)``: the time-ordered product of the
    paper's Table 1 matrices (reflection with the velocity before impact; sticking
    ``[[1, 0], [0, 0]]``; wall contact the zero matrix)."""
    P = _params(scene)
    x, v = _validate(P, x, v)
    _, _, _, J = _run_all(P, x.ravel(), v.ravel(), P.T, jac=True, t_end_lo=P.T_lo)
    return J.reshape(x.shape + (2, 2))


def zero_velocity(scene, x, v):
    """Whether the motion over ``[0, T]`` reaches zero velocity (turn, stick, contact,
    chatter; with ``f = 0`` a smooth velocity reversal counts too): the paper's
    ``Omega_dissip``; the rest is ``Omega_pres``."""
    P = _params(scene)
    x, v = _validate(P, x, v)
    _, _, zv, _ = _run_all(P, x.ravel(), v.ravel(), P.T, t_end_lo=P.T_lo)
    return zv.reshape(x.shape)


def map_and_jacobian(scene, x, v):
    """``(x1, v1, J, zero_velocity)`` over one period in one pass."""
    P = _params(scene)
    x, v = _validate(P, x, v)
    xs, vs, zv, J = _run_all(P, x.ravel(), v.ravel(), P.T, jac=True, t_end_lo=P.T_lo)
    sh = x.shape
    return xs.reshape(sh), vs.reshape(sh), J.reshape(sh + (2, 2)), zv.reshape(sh)


def flow(scene, x, v, t_end):
    """The state at ``t_end`` (any ``t_end >= 0``) of the motion from ``(x, v)`` at 0,
    in one pass (``stroboscopic_map`` restarts each period at ``t = 0`` instead)."""
    P = _params(scene)
    x, v = _validate(P, x, v)
    t_end = float(t_end)
    if not (t_end >= 0 and np.isfinite(t_end)):
        raise ValueError(f"fast: t_end must be finite and >= 0, got {t_end!r}")
    xs, vs, _, _ = _run_all(P, x.ravel(), v.ravel(), t_end)
    return xs.reshape(x.shape), vs.reshape(x.shape)
