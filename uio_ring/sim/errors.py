"""Errors of the numeric layer (defined in :mod:`uio_ring.errors`, re-exported here).

``SimulationError`` is bad simulation input; ``NotSupportedError`` a request that
the implemented theory does not cover.
"""

from __future__ import annotations

from uio_ring.errors import DimensionError, NotSupportedError, SimulationError

__all__ = ["SimulationError", "NotSupportedError", "DimensionError"]
