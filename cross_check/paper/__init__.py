"""The paper: its claims and its figures, each a registry.

* ``claims``  -- ``CLAIMS``: every numerically checkable statement, a ``Claim`` object each
  (id, statement, parameters, compute -> verdict, numbers, corrected), one module per group;
* ``figures`` -- ``FIGURES``: every figure, one module each, drawn as a matplotlib Figure with
  its caption and notes.

May import: ``reference``, ``fast``, ``cross_check.dynamics``, ``cross_check.scenes``,
``cross_check.tolerances``; never ``cross_check.report``, ``cross_check.golden`` or
``cross_check.agreement``.
"""
