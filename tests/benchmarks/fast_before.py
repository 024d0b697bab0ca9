"""``fast``'s public wrappers before issue 27, kept as the atlas benchmark's baseline (not an engine).

The same compiled kernel (``engine.run_range``) behind the wrappers as they were: validation by
``np.broadcast_arrays`` and one reduction per check, a fresh (empty) event log per call, each
period of ``stroboscopic_map`` a full ``batch.run``, and the per-period Jacobian product of
``cross_check.dynamics`` (``FAST_ENGINE``, for ``periodic.newton(engine=...)``).  Only the
per-call overhead differs from today's ``fast``: the numbers are the same bits.
"""
import numpy as np

from cross_check.dynamics import newton
from fast import api, batch, loop, ode
from fast.eventlog import EventLog

MAX_EVENTS = api.MAX_EVENTS
THREADS = 2


def _log_arrays(n, cap):
    return (np.full((n, cap), -1, np.int8), np.full((n, cap), np.nan), np.full((n, cap), np.nan),
            np.full((n, cap), np.nan), np.full((n, cap), np.nan), np.zeros((n, cap), np.int64))


def _run_once(engine, P, x, v, jac, cap):
    n = x.size
    out = (np.empty(n), np.empty(n), np.zeros(n, np.uint8), np.zeros((n if jac else 0, 4)),
           np.zeros(n, np.int64), np.zeros(n, np.int64), np.zeros(n, np.int64))
    logs = _log_arrays(n, cap)

    def one(span):
        engine.run_range(P, x, v, P[engine.p.T], P[engine.p.T_LO], jac, MAX_EVENTS, *out, *logs,
                         span[0], span[1])

    spans = batch._chunks(n, THREADS)
    assert len(spans) == 1, "the baseline runs the atlas's small batches on one thread"
    one(spans[0])
    return out, logs


def _run(engine, P, x, v, jac=False, log=False):
    x = np.ascontiguousarray(x.ravel(), dtype=np.float64)
    v = np.ascontiguousarray(v.ravel(), dtype=np.float64)
    cap = batch.LOG_CAP if log else 0
    (xs, vs, zv, J, nev, status, paths), logs = _run_once(engine, P, x, v, jac, cap)
    if np.flatnonzero(status != batch.OK).size:
        batch._raise_on_failures(status, nev, x, v, MAX_EVENTS)
    if log and nev.size and nev.max() > cap:
        over = np.flatnonzero(nev > cap)
        big = int(nev[over].max())
        _, more = _run_once(engine, P, x[over], v[over], False, big)
        logs = tuple(np.concatenate([a, np.full((a.shape[0], big - cap), batch._pad(a), a.dtype)], 1)
                     for a in logs)
        for a, b in zip(logs, more):
            a[over] = b
    return batch.Result(xs, vs, zv.astype(bool), J if jac else None, nev, paths, logs if log else None)


def _validate(engine, P, x, v):
    x, v = np.broadcast_arrays(api._real_array("x", x), api._real_array("v", v))
    for a in (x, v):
        if (~np.isfinite(a)).any():
            raise ValueError("fast: non-finite state")
    l, r = float(P[engine.p.L]), float(P[engine.p.R])
    if ((x < l) | (x > r)).any():
        raise ValueError("fast: outside the walls")
    return x, v


def _setup(scene, x, v):
    api.check_scene(scene)
    engine = ode if scene.has("position_forcing") else loop
    P = engine.params(scene)
    x, v = _validate(engine, P, x, v)
    api._count("max_events", MAX_EVENTS, low=1)
    return engine, P, x, v


def stroboscopic_map(scene, x, v, *, periods=1):
    periods = api._count("periods", periods)
    engine, P, x, v = _setup(scene, x, v)
    xs, vs = x.ravel().copy(), v.ravel().copy()
    for _ in range(periods):
        res = _run(engine, P, xs, vs)
        xs, vs = res.x, res.v
    return xs.reshape(x.shape), vs.reshape(x.shape)


def map_and_jacobian(scene, x, v):
    engine, P, x, v = _setup(scene, x, v)
    res = _run(engine, P, x, v, jac=True)
    sh = x.shape
    return res.x.reshape(sh), res.v.reshape(sh), res.J.reshape(sh + (2, 2)), res.zero_velocity.reshape(sh)


def jacobian(scene, x, v):
    return map_and_jacobian(scene, x, v)[2]


def zero_velocity(scene, x, v):
    engine, P, x, v = _setup(scene, x, v)
    return _run(engine, P, x, v).zero_velocity.reshape(x.shape)


def events(scene, x, v):
    engine, P, x, v = _setup(scene, x, v)
    return EventLog(x.shape, _run(engine, P, x, v, log=True))


class _Engine(newton._Fast):
    """``cross_check.dynamics.newton``'s float64 engine as it was: one call per period."""

    def map_jac(self, scene, x, v, k):
        J = np.broadcast_to(np.eye(2), x.shape + (2, 2)).copy()
        for _ in range(k):
            x, v, Jj, _ = map_and_jacobian(scene, x, v)
            J = np.asarray(Jj, float) @ J
        return np.asarray(x, float), np.asarray(v, float), J


FAST_ENGINE = _Engine()
