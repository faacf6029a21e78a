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
import os
from typing import Any

#: The environment variable with the threads of a batch (default 1): :func:`batch_threads`.
THREADS_ENV = "UIO_RING_THREADS"

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


def batch_threads() -> int:
    """Threads of :func:`~uio_ring.sim.batch.simulate_batch`: ``$UIO_RING_THREADS`` (default 1),
    never more than the machine's cores.  With n ≥ 2 the scenarios are cut into at least n
    chunks run on n threads, whole chunks each (the compiled loops and numpy's large
    operations release the GIL).

    >>> os.environ.pop(THREADS_ENV, None) and None
    >>> batch_threads()
    1
    """
    from uio_ring.errors import SimulationError

    raw = os.environ.get(THREADS_ENV, "").strip() or "1"
    if not raw.isdigit() or int(raw) < 1:
        raise SimulationError(f"{THREADS_ENV}={raw!r}: expected a positive integer")
    return max(1, min(int(raw), os.cpu_count() or 1))
