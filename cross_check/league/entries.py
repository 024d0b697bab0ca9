"""What the league runs: every engine at its settings, and the scenes, as one registry.

An ``Entry`` is one row of the league: a ``peer`` (one curve of the work-precision plot), a
``setting`` (a tolerance, a time step, digits, threads), the ``group`` the command line selects
it by (``--peers``), the packages it ``needs`` (a group whose package is not installed is
skipped, and the league says so in one line), and ``make()``, which builds the adapter
(protocol: ``cross_check.score``; it is pickled into the scorer's worker process).  ``quick``
marks the entries of ``league --quick``.

Settings (three or more per engine in the full league):

* ``fast``: ``threads 1``, ``threads 2``, ``map + Jacobian`` (it has no accuracy knob:
  ``peers.shipped``); quick: ``threads 1``;
* the reference: ``dps 16, 20, 30``; quick: 16 and 30;
* scipy ``solve_ivp`` DOP853 and heyoka: ``rtol`` / ``tol`` 1e-6 .. 1e-15; quick: one each;
* SUNDIALS CVODE BDF and Adams, diffrax Tsit5 and Dopri8: ``rtol 1e-6, 1e-9, 1e-12``; quick:
  BDF and Adams at 1e-9, Tsit5 at 1e-9, Dopri8 at 1e-12;
* MuJoCo: ``dt 1e-3, 1e-4, 1e-5``; quick: 1e-3 and 1e-4 (a step of 1e-5 costs ~3 s per start
  and period at ``w = 1``).

Scenes (golden data shipped with the package):

* ``QUICK_SCENES`` (44 starts): ``fig:narrow-with-friction`` (eight impacts per period, the hard
  cases, a stick), ``fig:many:2pi/f=0.2`` (flights, chatter, sticking) and
  ``effect:restitution``;
* ``FULL_SCENES`` (183 starts): every scene with ``w = 2 pi`` (the six ``fig:many:2pi``, the
  three resonance scenes, position forcing, restitution, damping) and
  ``fig:narrow-with-friction``: every kind of the scorecard, at a cost MuJoCo's smallest step
  can pay (the scenes with ``w = 1`` have six times as many steps per period).
"""
from __future__ import annotations

import importlib.util
from dataclasses import dataclass
from typing import Callable

QUICK_SCENES = ("fig:narrow-with-friction", "fig:many:2pi/f=0.2", "effect:restitution")
FULL_SCENES = ("fig:narrow-with-friction", "fig:many:2pi/f=0.005", "fig:many:2pi/f=0.01", "fig:many:2pi/f=0.05",
               "fig:many:2pi/f=0.1", "fig:many:2pi/f=0.2", "fig:many:2pi/f=0.3", "fig:resonance/R=0.89",
               "fig:resonance/R=0.8932", "fig:resonance/R=0.895", "fig:xpotno", "effect:restitution",
               "effect:damping")
#: ``--peers`` names, in the league's order, with the packages each needs and how to get them
GROUPS = {"fast": (), "reference": (), "scipy": ("scipy",), "heyoka": ("heyoka",),
          "sundials": ("sksundae",), "diffrax": ("jax", "diffrax", "optimistix"), "mujoco": ("mujoco",)}
INSTALL = "pip install 'vibro-impact-vv[peers]'"


@dataclass(frozen=True)
class Entry:
    """One row of the league (module docstring)."""

    group: str
    peer: str
    setting: str
    make: Callable
    quick: bool = False


def _shipped():
    from cross_check.league.peers import shipped
    from cross_check.score import adapters
    return shipped, adapters


def _fast(threads=1, jacobian=False):
    return lambda: _shipped()[0].FastSetting(threads, jacobian)


def _reference(dps):
    return lambda: _shipped()[1].ReferenceAdapter(dps)


def _scipy(rtol):
    return lambda: _shipped()[1].BaselineAdapter(f"scipy DOP853 rtol {rtol:.0e}", "DOP853", rtol)


def _heyoka(tol):
    return lambda: _shipped()[0].heyoka_adapter(tol)


def _sundials(method, rtol):
    def make():
        from cross_check.league.peers.sundials import SundialsAdapter
        return SundialsAdapter(method, rtol)
    return make


def _diffrax(solver, rtol):
    def make():
        from cross_check.league.peers.jaxdiffrax import DiffraxAdapter
        return DiffraxAdapter(solver, rtol)
    return make


def _mujoco(dt):
    def make():
        from cross_check.league.peers.mujoco_slide import MujocoSlideAdapter
        return MujocoSlideAdapter(dt)
    return make


ENTRIES = (
    [Entry("fast", "fast", "threads 1", _fast(1), quick=True), Entry("fast", "fast", "threads 2", _fast(2)),
     Entry("fast", "fast", "map + Jacobian", _fast(1, jacobian=True))]
    + [Entry("reference", "reference", f"dps {d}", _reference(d), quick=d in (16, 30)) for d in (16, 20, 30)]
    + [Entry("scipy", "scipy DOP853", f"rtol {r:.0e}", _scipy(r), quick=r == 1e-9) for r in (1e-6, 1e-9, 1e-12)]
    + [Entry("heyoka", "heyoka", f"tol {t:.0e}", _heyoka(t), quick=t == 1e-15) for t in (1e-9, 1e-12, 1e-15)]
    + [Entry("sundials", f"sundials {m}", f"rtol {r:.0e}", _sundials(m, r), quick=r == 1e-9)
       for m in ("BDF", "Adams") for r in (1e-6, 1e-9, 1e-12)]
    + [Entry("diffrax", f"diffrax {s}", f"rtol {r:.0e}", _diffrax(s, r), quick=(s, r) in (("Tsit5", 1e-9), ("Dopri8", 1e-12)))
       for s in ("Tsit5", "Dopri8") for r in (1e-6, 1e-9, 1e-12)]
    + [Entry("mujoco", "mujoco", f"dt {dt:.0e}", _mujoco(dt), quick=dt > 1e-5) for dt in (1e-3, 1e-4, 1e-5)])


def missing(group: str) -> list[str]:
    """The packages of ``group`` that are not installed (found without importing them)."""
    return [pkg for pkg in GROUPS[group] if importlib.util.find_spec(pkg) is None]


def select(groups=None, quick: bool = False) -> tuple[list[Entry], dict]:
    """``(entries to run, {group: why skipped})`` for the ``--peers`` names ``groups`` (default:
    all), the quick ones when ``quick``."""
    groups = list(GROUPS) if groups is None else list(groups)
    unknown = [g for g in groups if g not in GROUPS]
    if unknown:
        raise ValueError(f"unknown peer(s) {unknown}; known: {', '.join(GROUPS)}")
    skipped = {g: f"{', '.join(m)} not installed ({INSTALL})" for g in groups if (m := missing(g))}
    chosen = [e for e in ENTRIES if e.group in groups and e.group not in skipped and (e.quick or not quick)]
    return chosen, skipped


__all__ = ["ENTRIES", "Entry", "FULL_SCENES", "GROUPS", "QUICK_SCENES", "missing", "select"]
