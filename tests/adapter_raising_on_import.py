"""An adapter module that raises on import: ``python -m cross_check score`` must name it and exit 2
(tests/test_score_budget.py)."""
raise RuntimeError("this module fails on import, on purpose")
