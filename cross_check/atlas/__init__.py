"""Where each claim holds: a claims atlas over parameter space, computed on Dask, kept in Zarr.

* ``claims`` -- what is computed at one point ``(f/F, w^2 R/F)`` for each parametric claim, and
  the closed forms it is held to;
* ``store``  -- the xarray Dataset in ``DIR/atlas.zarr``: one variable per quantity, written
  block by block with done markers (a stopped run resumes), and ``open_atlas``, its reader;
* ``run``    -- the grid, the blocks, the cluster (``dask.distributed``: a ``LocalCluster`` or a
  running scheduler), ``atlas.json`` and the CLI (``python -m cross_check atlas``);
* ``maps``   -- the fields, the closed-form boundaries against the computed switches (in grid
  cells), one PNG per claim, all read from the store.

Reading an atlas from other code: ``ds = cross_check.atlas.open_atlas("atlas")`` (an
``xarray.Dataset``: rows ``w2R_over_F``, columns ``f_over_F``).

May import ``cross_check.dynamics``, ``agreement``, ``tolerances``, ``reference`` and ``fast``; the
report and the CLI import it.  Needs ``dask[distributed]``, ``xarray`` and ``zarr`` (the ``atlas``
extra), imported when used.
"""
from cross_check.atlas.run import Grid, compute, main, summarize
from cross_check.atlas.store import open_atlas

__all__ = ["Grid", "compute", "main", "summarize", "open_atlas"]
