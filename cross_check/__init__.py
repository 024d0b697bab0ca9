"""The front door of the suite: both engines on the same work, the report, the claims, the
figures and the golden data (``python -m cross_check --help``).

Rooms, each importing only those below it (the import contracts in ``pyproject.toml``):

* ``__main__``    -- the CLI, one line per command;
* ``report/``     -- the markdown V&V report and its plots;
* ``sensitivity/``-- the suite's checks on a catalogue of faulty integrators;
* ``atlas/``      -- where each claim holds: the claims over parameter space, on Dask;
* ``score/``      -- score any integrator against the golden data (adapter protocol, scorecard,
  pytest plugin);
* ``paper/``      -- the paper's claims and figures, each a registry;
* ``golden``      -- the golden data, written from the reference (its runs and self-check in
  ``golden_runs``, its files on disk in ``golden_files``, its proofs in ``golden_proof`` and
  ``golden_chatter``);
* ``scenes``      -- the paper's named scenes, sample states and hard states;
* ``dynamics/``   -- one Newton for periodic points, one classifier, continuation, portraits;
* ``agreement/``  -- comparing two integrators: itinerary first, then digits; hard cases; scipy;
* ``tolerances``  -- the one table of named tolerances, each with its source.
"""
