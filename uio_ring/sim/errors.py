"""Errors of the numeric layer; both belong to the :class:`~uio_ring.errors.UioRingError` tree.

``SimulationError`` is bad simulation input (a step that is not ``h/N``, a
history of the wrong shape, NaN in a signal, mismatched delays); the message
names the argument.  ``NotSupportedError`` is a request that the theory used
here does not cover (known inputs in the Zheng–Bejarano observer).
"""

from __future__ import annotations

from uio_ring.errors import DimensionError, UioRingError

__all__ = ["SimulationError", "NotSupportedError", "DimensionError"]


class SimulationError(UioRingError, ValueError):
    """Simulation arguments that cannot be used; the message names the argument."""


class NotSupportedError(UioRingError, NotImplementedError):
    """A case the implemented theory does not cover; the message says which and why."""
