"""Agreement: how two integrators, or an integrator and the truth, compare.

* ``compare`` -- event-aware metrics: the itinerary first, then event times, then states, in
  significant digits; the near-grazing band; the floors of float64;
* ``hardcases`` -- a handful of delicate events constructed exactly (mpmath, 60 digits);
  ``hardcases_position`` under position forcing (Taylor flights backward, certified by validated
  flights);
* ``construct`` -- constructed events in bulk (float64 numpy): 1e4 in the default test run,
  1e6 behind ``slow``; ``construct_position`` under position forcing, on ``backflight`` (a float64
  double-double Taylor flight backward, its error carried to the event);
* ``baseline`` -- scipy's ``solve_ivp`` restarted at every event, the general-purpose peer.

May import: ``reference``, ``fast``, ``cross_check.scenes``, ``cross_check.tolerances``;
never ``cross_check.dynamics``, ``cross_check.paper`` or ``cross_check.report``.
"""
