"""The suite's own engines and the shipped peers, at the league's settings.

The adapters of ``cross_check.score.adapters`` stay as they are; what the league adds is a
setting each can be run at, in a worker process (the adapter is pickled there):

* ``FastSetting`` -- ``fast`` has no accuracy knob: its events are certified and located to
  float64 resolution whatever the scene, and its one numerical flight (position forcing) runs
  at a fixed ``fast.ode.STEPS_PER_PERIOD``, compiled in.  What it exposes is the thread count
  (the same bits for every count; a batch below ``fast.batch.MIN_THREADED`` states runs on the
  calling thread, so on the golden scenes' batches of 8-15 starts every count does the same
  work) and whether the Jacobian is computed along (``fast.map_and_jacobian``: the price of
  ``Phi'``).  The league's settings: ``threads 1``, ``threads 2``, ``map + Jacobian``;
* the reference at ``dps`` digits (``adapters.ReferenceAdapter``), scipy's ``solve_ivp`` at
  ``rtol`` (``adapters.BaselineAdapter``), as shipped;
* ``heyoka_adapter(tol)`` -- heyoka.py's Taylor integrator in the baseline's event loop
  (``adapters.HeyokaFlight``), built in the worker on first use (``LazyHeyokaFlight``: a
  heyoka integrator holds its module and compiled code, which do not pickle).
"""
from __future__ import annotations

from cross_check.score import adapters


class FastSetting(adapters.FastAdapter):
    """``fast`` on ``threads`` threads, the Jacobian computed along when ``jacobian``."""

    jit = True        # numba: the first call loads (or compiles) the cached kernels

    def __init__(self, threads: int | None = 1, jacobian: bool = False):
        self.threads, self.with_jacobian = threads, jacobian
        self.name = "fast " + ("map + Jacobian" if jacobian else f"threads {threads}")

    def step(self, params, x, v, periods):
        import fast
        sc = adapters.scene_of(params)
        if self.with_jacobian:
            return fast.map_and_jacobian(sc, x, v, periods=periods, threads=self.threads)[:2]
        return fast.stroboscopic_map(sc, x, v, periods=periods, threads=self.threads)


class LazyHeyokaFlight:
    """``adapters.HeyokaFlight(tol)``, built on the first flight (pickles as ``tol``)."""

    def __init__(self, tol: float):
        self.tol, self._flight = tol, None

    def __getstate__(self):
        return {"tol": self.tol, "_flight": None}

    def __call__(self, *args):
        if self._flight is None:
            self._flight = adapters.HeyokaFlight(self.tol)
        return self._flight(*args)


def heyoka_adapter(tol: float):
    """heyoka.py at ``tol`` in the careful user's event loop (``adapters.heyoka``'s, at any tol);
    ``jit``: its Taylor integrator is compiled (LLVM) on the first flight."""
    adapter = adapters.BaselineAdapter(f"heyoka taylor {tol:.0e}", flight=LazyHeyokaFlight(tol))
    adapter.jit = True
    return adapter


__all__ = ["FastSetting", "LazyHeyokaFlight", "heyoka_adapter"]
