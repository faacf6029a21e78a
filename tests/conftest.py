"""Test configuration shared by the whole suite.

Hypothesis profiles
-------------------
``ci`` (the default): no deadline (exact polynomial algebra has heavy tails),
modest ``max_examples`` so that ``pytest tests/ring`` stays well under two
minutes on two cores, and no example database written into the repository.
``dev``: fewer examples, for a quick edit-run loop.
``thorough``: many more examples, for a nightly or pre-release run.

Select one with ``HYPOTHESIS_PROFILE=thorough pytest tests/ring``.
"""

from __future__ import annotations

import os

from hypothesis import HealthCheck, Phase, settings

_COMMON = dict(
    deadline=None,
    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large],
    print_blob=True,
)

# no database and no "explain" phase: a CI run writes nothing into the repository
settings.register_profile(
    "ci",
    max_examples=25,
    database=None,
    phases=[p for p in Phase if p is not Phase.explain],
    **_COMMON,
)
settings.register_profile("dev", max_examples=10, **_COMMON)
settings.register_profile("thorough", max_examples=400, **_COMMON)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "ci"))
