"""A plant nonlinearity φ(t, x) as the numeric side sees it: a checked Python callable.

>>> import numpy as np
>>> f = check_phi(lambda t, x: np.sin(t) * x, 2)
>>> f(0.0, np.ones(2)).tolist()
[0.0, 0.0]
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from uio_ring.errors import DimensionError, SimulationError

__all__ = ["check_phi"]


def check_phi(phi: Any, n: int) -> Callable[[float, np.ndarray], np.ndarray]:
    """``phi`` wrapped so that it returns a finite ``(n,)`` float array (else ``SimulationError``)."""
    if not callable(phi):
        raise SimulationError(f"phi must be a callable phi(t, x) -> (n_x,) array, not {type(phi).__name__}")

    def f(t: float, x: np.ndarray) -> np.ndarray:
        v = np.asarray(phi(t, x), dtype=float).reshape(-1)
        if v.shape != (n,):
            raise DimensionError(f"phi(t, x) returned shape {v.shape}; expected ({n},)")
        if not np.all(np.isfinite(v)):
            raise SimulationError(f"phi(t, x) is not finite at t = {t:g}")
        return v

    return f
