"""Dynamics of the stroboscopic map: periodic points, their continuation, phase portraits.

* ``newton``       -- ONE Newton for ``Phi^k(z) = z`` over any engine (``fast`` in float64, or
  ``reference`` at any dps; under position forcing a coarse screen first), and the multipliers;
* ``periodic``     -- ONE classifier and the search from a seed grid (``newton``'s names are also
  its own: the suite asks ``periodic`` for them);
* ``continuation`` -- pseudo-arclength continuation in a parameter, folds, and thresholds
  (a fixed point plus a multiplier condition) on the reference;
* ``portraits``    -- orbits, Birkhoff regular/chaotic, islands, the area classes
  Omega_pres/Omega_dissip and the invariance of Omega_dissip.

May import: ``reference``, ``fast``, ``cross_check.tolerances``; never ``cross_check.paper``,
``cross_check.report``, ``cross_check.golden``, ``cross_check.agreement`` or ``cross_check.scenes``.
"""
