"""The whole V&V for the user's scenes: ``python -m cross_check verify SCENES.toml``.

Composes the rooms below it and owns no math:

* ``run``      -- the CLI and the Dask run: per scene a set of tasks, gathered by key;
* ``tasks``    -- the units of work (states and hard cases, golden data with proofs, agreement,
  orbits with proofs, portrait, scorecards), each a call into a room below, and the run's depth
  (``FULL``, ``QUICK``);
* ``document`` -- the checks each scene passes or fails, and ``report.md``;
* ``portrait`` -- the PNG of a scene's phase plane: Omega_pres / Omega_dissip, orbits, proved points.

The top room of ``cross_check`` (below ``__main__`` only): it may import every other room.
"""
from cross_check.verify.run import main

__all__ = ["main"]
