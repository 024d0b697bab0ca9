"""Where each claim holds: a claims atlas over parameter space, computed on Dask.

* ``claims`` -- what is computed at one point ``(f/F, w^2 R/F)`` for each parametric claim, and
  the closed forms it is held to;
* ``run``    -- the grid, the chunks, the cluster (``dask.distributed``: a ``LocalCluster`` or a
  running scheduler), the deterministic gather, ``atlas.json`` and the CLI
  (``python -m cross_check atlas``);
* ``maps``   -- the fields, the closed-form boundaries against the computed switches (in grid
  cells), one PNG per claim.

May import ``cross_check.dynamics``, ``agreement``, ``tolerances``, ``reference`` and ``fast``; the
report and the CLI import it.  Needs ``dask[distributed]`` (the ``atlas`` extra).
"""
from cross_check.atlas.run import Grid, compute, main, write

__all__ = ["Grid", "compute", "main", "write"]
