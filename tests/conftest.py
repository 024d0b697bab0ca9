"""Shared pytest configuration: hypothesis profiles and common fixtures.

Hypothesis profiles (pick with ``HYPOTHESIS_PROFILE=dev|ci|thorough``; the default is ``ci``
everywhere, so a plain ``pytest`` draws the same examples on every run and machine):

* ``dev``      -- quick local runs (20 examples, random);
* ``ci``       -- derandomized (the same examples on every run), ``print_blob=True``;
* ``thorough`` -- 1000 examples, for the ``slow`` marker runs.

``deadline=None`` everywhere: mpmath timings vary with the numbers.
"""
import os

from hypothesis import HealthCheck, settings

settings.register_profile("dev", max_examples=20, deadline=None)
settings.register_profile(
    "ci", max_examples=30, deadline=None, derandomize=True, print_blob=True,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "thorough", max_examples=1000, deadline=None,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
