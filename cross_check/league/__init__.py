"""The league: the field's integrators graded on the golden data, side by side
(``python -m cross_check league [--quick] [--out DIR] [--peers NAME ...]``).

A thin composer that owns no grading: every engine is an adapter like any user's (the
protocol of ``cross_check.score``), scored by ``cross_check.score.card.score`` in its worker
process; the league reads each scorecard into a row.

* ``peers``   -- the peer adapters, each documenting how its library was used: SUNDIALS CVODE
  (``peers.sundials``), diffrax (``peers.jaxdiffrax``), MuJoCo (``peers.mujoco_slide``), and the
  shipped engines at the league's settings (``peers.shipped``);
* ``entries`` -- the registry: every engine at its settings, the scenes, what ``--quick`` runs;
* ``run``     -- running it (``league``, ``main``);
* ``table``   -- rows from scorecards, the goal line, markdown and JSON;
* ``plot``    -- the work-precision diagram.

May import ``cross_check.score`` and everything below it; nothing imports it but ``__main__``
(the report reads ``league.md`` from disk).  ``main`` is imported on first use, so that
``python -m cross_check`` lists commands without loading the scorer.
"""
import importlib


def __getattr__(name):
    if name in ("main", "league"):
        return getattr(importlib.import_module("cross_check.league.run"), name)
    raise AttributeError(f"module 'cross_check.league' has no attribute {name!r}")


__all__ = ["league", "main"]
