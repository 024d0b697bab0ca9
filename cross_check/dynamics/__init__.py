"""Dynamics of the stroboscopic map: periodic points, their continuation, phase portraits.

* ``periodic``     -- ONE Newton for ``Phi^k(z) = z`` over any engine (``fast`` in float64, or
  ``reference`` at any dps), the multipliers and ONE classifier, the search from a seed grid;
* ``continuation`` -- pseudo-arclength continuation in a parameter, folds, and thresholds
  (a fixed point plus a multiplier condition) on the reference;
* ``portraits``    -- orbits, Birkhoff regular/chaotic, islands, the area classes
  Omega_pres/Omega_dissip and the invariance of Omega_dissip.

May import: ``reference``, ``fast``, ``cross_check.tolerances``; never ``cross_check.paper``,
``cross_check.report``, ``cross_check.golden``, ``cross_check.agreement`` or ``cross_check.scenes``.
"""
