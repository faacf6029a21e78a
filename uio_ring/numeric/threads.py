"""Single-threaded BLAS for the small matrix products of the simulator.

The block products here are at most a few hundred wide: a multi-threaded BLAS
gains nothing on them and, on a machine whose cores are busy, loses up to 40×
to thread hand-over (measured: a 100×404 @ 404×400 product, 40 ms with
OpenBLAS threads on two loaded cores, 1 ms with one thread).  When
``threadpoolctl`` is installed, the simulator limits BLAS to one thread for the
duration of a run; without it, nothing changes (set ``OPENBLAS_NUM_THREADS=1``).
"""

from __future__ import annotations

import contextlib
from typing import Any

_CONTROLLER: Any = None


def blas_single_thread() -> Any:
    """Context manager: BLAS limited to one thread (a no-op without threadpoolctl)."""
    global _CONTROLLER
    try:
        from threadpoolctl import ThreadpoolController
    except ImportError:
        return contextlib.nullcontext()
    if _CONTROLLER is None:
        _CONTROLLER = ThreadpoolController()
    return _CONTROLLER.limit(limits=1, user_api="blas")
