"""The markdown V&V report and its plots (``python -m cross_check report``).

* ``build``     -- the plan (``FULL``, ``QUICK``), progress, assembly of ``report.md``, the CLI;
* ``sections``  -- agreement per scene, hard cases, solve_ivp's itineraries, the claims table,
  the machine: each a function returning markdown lines;
* ``precision`` -- the work-precision measurements (error and seconds per trajectory-period);
* ``plots``     -- the work-precision diagram (digits against seconds, labels without overlap);
* ``league_link`` -- the league's table, read from ``league.md`` when a league was run.

May import the rooms below it (agreement, scenes, dynamics, paper, score, tolerances),
``reference`` and ``fast``, not the league beside it (it reads the league's page from disk);
nothing imports it but ``cross_check.__main__``.
"""
from cross_check.report.build import FULL, QUICK, Plan, build, main

__all__ = ["FULL", "QUICK", "Plan", "build", "main"]
