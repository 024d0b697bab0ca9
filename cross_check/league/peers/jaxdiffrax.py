"""diffrax (JAX) as a peer: Tsit5 / Dopri8 with ``diffrax.Event`` root finding, batched with
``jax.vmap``, written as a careful JAX user would write it (protocol: ``cross_check.score``).

How the library is used
-----------------------
One smooth flight ``x' = v, v' = F cos(k x) cos(w t) - s f - c v`` (the friction sign ``s``
frozen per flight, never ``sgn(v)``) is one ``diffrax.diffeqsolve`` with a ``PIDController``
(``rtol``, ``atol = rtol * min(R, max(F, f)/w)``: diffrax takes one scalar ``atol``) and a
terminating ``diffrax.Event`` located by ``optimistix.Bisection`` (1e-14 in ``t``).
Its one real-valued condition is the first of the flight's two events, positive until then::

    g = min( s (W_s - x),  s v + SPEED_SHIFT (F + f) / w ),   falling through zero,

the distance to the wall ahead (``W_+ = r``, ``W_- = l``; the wall behind cannot be reached
before the flight ends) and the end of the flight; which of the two fired is read off the
state at the root.  Where the library had to be worked around:

* ``optimistix.Newton`` (the documented choice) does not keep to the event's bracket: on
  Dopri8's long steps it diverged at a turning point where ``v' = A - s f`` is small (measured:
  ``fig:narrow-with-friction/sticking``, every tolerance), and the solve failed.
  ``Bisection`` keeps the bracket but finds roots of one scalar function only: hence the one
  condition ``g``.  Its ``flip`` is fixed (``True``: ``g`` falls), because diffrax root-finds
  on *every* start of a vmapped batch as soon as one has an event, and on a start without one
  the ``"detect"`` check of the bracket raises.  And it stops on the bracket's width alone
  (``jaxdiffrax_loop.BracketBisection``): optimistix's also asks ``|g| < atol``, which the
  rounding noise of a steep ``g`` does not meet within its 256 steps (measured: failed solves on
  the resonance scenes at Dopri8 rtol 1e-6 and 1e-9);
* diffrax fires a downward crossing only from a strictly positive value: a flight that starts
  at ``v = 0`` (after a turn or a release) would start ``g`` at 0, and a wall one step away
  would be flown through (measured: the chatter run of ``fig:many:2pi/f=0.2``).  The shift
  ``SPEED_SHIFT (F + f)/w`` (1e-13, as heyoka's adapter does) keeps ``g`` positive at the
  start; the detected end of a flight moves by ``shift / |v'|`` in time, ``O(shift^2)`` in state;
* on a start without an event that root-find ends at the bisection's approximation of
  ``t_end``, not at ``t_end``, so its answer would depend on the other starts of the batch:
  the last flight of each start is solved again after the loop, without an event (a flight
  known to have none), and every start gives the same bits alone or in any batch;
* a start that has finished still runs the vmapped loop body (its result thrown away): its
  flight is given the interval ``[t_end, t_end + 1]``, since an empty one makes an empty
  bracket.

The event state is diffrax's dense output at the root (``sol.ys``).  Each event is handled in
``jax.numpy`` (``jaxdiffrax_loop``) and the next flight restarts from it, all inside one
``jax.lax.while_loop`` per start (bounded: ``MAX_EVENTS_PER_PERIOD`` times the periods; a start that needs more comes
back as NaN and ``step`` raises naming it).  ``jax.vmap`` runs the starts of a call in lockstep
(the loop ends when the last start ends); calls are padded to a multiple of ``LANES`` starts
so that one compiled program serves every scene, and the tolerances are traced arguments, so
one compilation serves every tolerance of a solver.

Event handling per kind (the careful user's policy of ``cross_check.agreement.baseline``,
written in ``jax.numpy``):

* **impact**: the wall event; ``v -> -e v``, ``x`` set exactly to the wall, ``s -> -s``;
* **chatter**: at a wall the force pushes into (``A >= -f`` at ``r``, ``A <= f`` at ``l``),
  a bounce slower than ``100 atol_v`` or lower than ``100 atol_x``
  (``v^2 / 2(|A| + f)``) is declared the end of a chatter run: wall contact from there;
* **turn**: the ``v = 0`` event with ``s A < -f``: ``s -> -s``;
* **stick / slip**: the ``v = 0`` event otherwise: ``v = 0`` and the release time is solved
  in closed form, the first ``t`` after the stick with ``|a cos(w t)| = f`` crossing outward
  (``a = F cos(k x)`` at the resting position), then a flight with ``s = sgn A``;
* **wall contact / release**: a ``v = 0`` event within ``1e-12 R`` of a wall the force pushes
  into, or the end of a chatter run: ``x`` at the wall, released (``s`` away from the wall)
  when ``A`` crosses ``-f`` downward at ``r`` (``+f`` upward at ``l``), also in closed form;
* **grazing**: nothing special: an impact at ``v -> 0`` is found only if ``g`` changes sign
  between two steps (a tangency inside one step is missed: diffrax issue 507).

Settings: ``solver`` ``"Tsit5"`` or ``"Dopri8"``, ``rtol`` in ``[1e-14, 1e-3]``.  float64 is
switched on (``jax_enable_x64``) when the adapter first runs, not when this module is
imported.  The compiled program is built on the first call (``jit = True``: the league reports
that warm-up apart from the run time).
"""
from __future__ import annotations

import math

import numpy as np

SOLVERS = ("Tsit5", "Dopri8")
EFFECTS = frozenset({"walls", "forcing", "friction", "restitution", "damping", "position_forcing"})
#: starts per vmapped call (a call is padded to a multiple of it: one compiled program)
LANES = 16
#: loop bound per period of a start (flights + rests; a chatter run to the cut-off is ~200)
MAX_EVENTS_PER_PERIOD = 1000


class DiffraxAdapter:
    """diffrax ``solver`` at ``rtol`` (module docstring: how the library is used, and the event
    handling per kind).  Pickles as its settings; the compiled program is built in the process
    that calls it."""

    effects = EFFECTS
    jit = True

    def __init__(self, solver: str = "Tsit5", rtol: float = 1e-10):
        if solver not in SOLVERS:
            raise ValueError(f"solver must be one of {SOLVERS}, got {solver!r}")
        if not (isinstance(rtol, (int, float)) and 1e-14 <= rtol <= 1e-3):
            raise ValueError(f"rtol must be a number in [1e-14, 1e-3], got {rtol!r}")
        self.solver, self.rtol = solver, float(rtol)
        self.name = f"diffrax {solver} rtol {rtol:.0e}"
        self._run = None

    def __getstate__(self):
        return {"solver": self.solver, "rtol": self.rtol, "name": self.name, "_run": None}

    def _call(self, params, x, v, periods):
        if self._run is None:
            from cross_check.league.peers import jaxdiffrax_loop
            self._run = jaxdiffrax_loop.program(self.solver)
        p = params
        k = 0.0 if p["wavenumber"] is None else p["wavenumber"]
        P = np.array([p["F"], p["f"], p["omega"], p["l"], p["r"], p["restitution"], p["damping"], k])
        scale = min(p["r"] - p["l"], max(p["F"], p["f"]) / p["omega"]) or 1.0
        tol = np.array([self.rtol, self.rtol * scale])
        x, v = np.asarray(x, float), np.asarray(v, float)
        n = len(x)
        if n == 0:
            return None
        pad = -n % LANES
        X, V = np.concatenate([x, np.full(pad, x[0])]), np.concatenate([v, np.full(pad, v[0])])
        out = self._run(P, tol, X, V, periods * 2 * math.pi / p["omega"], MAX_EVENTS_PER_PERIOD * periods)
        return {k: np.asarray(a)[:n] for k, a in out.items()}

    def _failed(self, out, periods):
        """``RuntimeError`` naming the starts without a result and why, if any."""
        from cross_check.league.peers.jaxdiffrax_loop import LOOP_BOUND, OK

        bad = np.flatnonzero(out["status"] != OK)
        if len(bad):
            why = ["diffrax reported a failed solve (its RESULTS: max_steps, or the event's root find)"
                   if out["status"][i] != LOOP_BOUND else
                   f"more than {MAX_EVENTS_PER_PERIOD * periods} events and rests" for i in bad[:10]]
            raise RuntimeError(f"diffrax {self.solver} rtol {self.rtol:g}: no result for start(s) "
                               + "; ".join(f"{i}: {w}" for i, w in zip(bad[:10].tolist(), why)))

    def step(self, params, x, v, periods):
        out = self._call(params, x, v, periods)
        if out is None:
            return np.zeros(0), np.zeros(0)
        self._failed(out, periods)
        return out["x"], out["v"]

    def events(self, params, x, v):
        from cross_check.league.peers.jaxdiffrax_loop import KINDS, LOG

        out = self._call(params, x, v, 1)
        if out is None:
            return []
        self._failed(out, 1)
        n = out["n"]
        if (n > LOG).any():
            raise RuntimeError(f"diffrax {self.solver}: more than {LOG} events in a period for start(s) "
                               f"{np.flatnonzero(n > LOG)[:10].tolist()}")
        cols = [out[k] for k in ("t", "x_event", "v_after", "v_before")]
        return [[(KINDS[out["kinds"][i, j]],) + tuple(float(c[i, j]) for c in cols) for j in range(n[i])]
                for i in range(len(n))]

__all__ = ["DiffraxAdapter", "LANES", "SOLVERS"]
