"""The whole V&V for the user's scenes: ``python -m cross_check verify SCENES.toml``.

Composes the rooms below it and owns no math:

* ``run``      -- the CLI and the Dask run: per scene a set of tasks, gathered by key;
* ``tasks``    -- the units of work (states and hard cases, golden data with proofs, agreement,
  orbits with proofs, portrait, scorecards), each a call into a room below, and the run's depth
  (``FULL``, ``QUICK``);
* ``ladder``   -- an orbit's proof: the precisions and Krawczyk boxes it climbs, and when it stops;
* ``document`` -- the checks each scene passes or fails, and ``report.md``;
* ``portrait`` -- the PNG of a scene's phase plane: Omega_pres / Omega_dissip, orbits, proved points.

The top room of ``cross_check`` (below ``__main__`` only): it may import every other room.

Where the time goes (issue 33, profiled with ``cProfile`` per task; the report gives each scene's
CPU seconds by task).  A full run on an unseen position-forced scene (``F=1 f=0.15 omega=1.7
l=-0.4 r=0.9 wavenumber=1.3``) took 292 CPU s: the orbit proofs 220 (at 320 bits ~90% of a proof
was the *point* integrator -- the Taylor flights of the Newton steps, the box and the section at
~100 digits), the golden data 36 (each input integrated three times per precision, the Jacobian's
flights a fourth, and six more runs for the band), scorecards and agreement 11 (the same
ten-period truths three times).  Now: the proofs climb a precision ladder from 64 bits with the
section from fast (``ladder.PROOF_LADDER``); ``golden.compute`` takes map, events and Jacobian from
one integration, ``golden_proof.band`` settles the band by one proof, ``golden_proof.enclosure`` proves at
192 bits first; the agreement reads the reference's answers from the golden data; both scorecards
run in one task; ``reference.taylor`` keeps each step's recurrence for the variational columns
and evaluates its polynomials on raw mpf values (every golden byte unchanged).  The hard cases
that position forcing now has (~14 more inputs) are in the same budget.
"""
from cross_check.verify.run import main

__all__ = ["main"]
