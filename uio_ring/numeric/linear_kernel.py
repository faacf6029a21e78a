"""Compiled (numba) loops of the linear parts of a batch segment: delayed-tap sums and recursions.

``simulate_batch`` spends most of a linear observer's time in products with a handful of
columns over time-major arrays ``(rows, K, c)`` (the plant's and the observer's delayed
taps, the stencils of the quadratures) and in the recursions ``x_{j+1} = Φ x_j + g_j``
(one ``(K, n) @ (n, n)`` product per step).  In numpy each is one call per tap and per
step over memory; here each is one compiled pass:

* :func:`tap_sum`: ``out[l] = Σ_i S[starts[i] + l] @ M[i]`` (every output row written once);
* :func:`scan_rows`: ``x_{j+1} = x_j Φᵀ + g_j`` in place.

(One plant's segments and a linear observer's with the cubic forcing run scenario-innermost
instead: :mod:`uio_ring.numeric.scenario_kernel`; these loops serve the forcing of observers
with an injection term and the recursion of linear observers without the cubic forcing.)

The scenarios are the innermost loop (independent sums, which pipeline and vectorise);
zero coefficients are skipped (so a 0 · ∞ of a diverged run is not a NaN here).
With ``UIO_RING_THREADS=2`` (:func:`threads`) the scenarios are cut into contiguous blocks,
one per thread (``prange``); each scenario is computed by the same operations in any block,
so the numbers do not depend on the number of threads.

The numpy versions (:func:`uio_ring.sim._blocks.taps`, :func:`uio_ring.sim._blocks.scan_rows`)
are the reference; the two agree up to rounding (summation order).  Selected by the
``kernel`` switch (:mod:`uio_ring.numeric.backend`); numba is the optional extra ``fast``,
imported on the first call, the loops cached on disk (``cache=True``).

>>> import numpy as np
>>> S = np.arange(6.0).reshape(3, 1, 2)
>>> out = np.empty((2, 1, 2))
>>> tap_sum(S, np.array([0, 1]), np.stack([np.eye(2), 2 * np.eye(2)]), out)[:, 0].tolist()
[[4.0, 7.0], [10.0, 13.0]]
>>> G = np.zeros((3, 1, 1)); scan_rows(np.array([[0.5]]), np.array([[1.0]]), G)[:, 0, 0].tolist()
[0.5, 0.25, 0.125]
"""

from __future__ import annotations

import contextlib
import functools
import threading
from collections.abc import Iterator
from typing import Any

import numpy as np

__all__ = ["tap_sum", "scan_rows", "threads", "THREADS_ENV"]

#: Fewest scenarios per thread (below, the threads' hand-over costs more than the work).
MIN_CHUNK = 16
#: The environment variable with the threads of the compiled linear loops (default 1).
THREADS_ENV = "UIO_RING_THREADS"


def tap_sum(S: np.ndarray, starts: np.ndarray, M: np.ndarray, out: np.ndarray) -> np.ndarray:
    """``out[l, k] = Σ_i S[starts[i] + l, k] @ M[i]`` for ``l < len(out)``; returns ``out``.

    ``S`` ``(R, K, c)``, ``M`` ``(m, c, r)`` (row-vector form: the transposed coefficients),
    ``out`` ``(L, K, r)``; float64, C-contiguous ``S``, ``M``, ``out`` (``starts`` int64).
    Precondition: every row read is inside ``S`` (not checked).
    """
    _run(0, S, np.asarray(starts, dtype=np.int64), M, out)
    return out


def scan_rows(PhiT: np.ndarray, x0: np.ndarray, G: np.ndarray) -> np.ndarray:
    """:func:`uio_ring.sim._blocks.scan_rows` compiled: ``G`` ``(M, K, n)`` becomes ``x_1 … x_M``
    in place (``x_{j+1} = x_j Φᵀ + g_j``, ``x0`` ``(K, n)``); C-contiguous float64 ``G``."""
    if G.shape[0]:
        _run(1, np.ascontiguousarray(PhiT), np.ascontiguousarray(x0), G)
    return G


def threads() -> int:
    """Threads of the compiled linear loops: ``$UIO_RING_THREADS`` (default 1), never more than numba
    may use (``NUMBA_NUM_THREADS``, ``numba.set_num_threads``) nor than the machine's cores.

    One thread by default: measured on two cores that other jobs keep busy, a second thread
    waits for its core at every hand-over and the loops run 2–10× slower.

    >>> import os
    >>> os.environ.pop(THREADS_ENV, None) and None
    >>> threads()
    1
    """
    import os

    from uio_ring.errors import SimulationError

    raw = os.environ.get(THREADS_ENV, "").strip() or "1"
    if not raw.isdigit() or int(raw) < 1:
        raise SimulationError(f"{THREADS_ENV}={raw!r}: expected a positive integer")
    if int(raw) == 1:
        return 1
    from uio_ring.errors import require

    numba = require("numba", extra="fast")
    return max(1, min(int(raw), numba.get_num_threads(), os.cpu_count() or 1))


_LOCAL = threading.local()


@contextlib.contextmanager
def serial_loops() -> Iterator[None]:
    """In this thread, the compiled loops on one thread whatever ``UIO_RING_THREADS`` (a chunk of a
    batch already running on a thread of its own).

    >>> with serial_loops():
    ...     chunks(1000)
    1
    """
    _LOCAL.serial = True
    try:
        yield
    finally:
        _LOCAL.serial = False


def chunks(K: int) -> int:
    """Blocks of scenarios of K columns: one per thread (:func:`threads`), each of at least
    :data:`MIN_CHUNK` scenarios.

    >>> chunks(1), chunks(16)
    (1, 1)
    """
    if getattr(_LOCAL, "serial", False):
        return 1
    return max(1, min(threads(), K // MIN_CHUNK))


def _run(which: int, *args: np.ndarray) -> None:
    """Loop ``which`` (0: taps, 1: scan) over the K scenarios (axis 1 of the
    last array): one call, or one call per block of scenarios on numba's threads (:func:`chunks`)."""
    loops = _compiled()
    K = args[-1].shape[1]
    nc = chunks(K)
    if nc == 1:
        loops[which](*args)
    else:
        loops[2 + which](*args, nc)


@functools.cache
def _compiled() -> tuple[Any, ...]:
    """The two loops, then the two loops over blocks of scenarios in parallel."""
    from uio_ring.errors import require

    numba = require("numba", extra="fast")
    globals()["prange"] = numba.prange  # the blocks of scenarios in parallel (in Python: range)
    jit = numba.njit(cache=True, nogil=True)
    tap, scan = jit(_tap_loop), jit(_scan_loop)
    par = numba.njit(nogil=True, parallel=True)  # closures over the loops: compiled once per process
    return tap, scan, par(_tap_blocks(tap)), par(_scan_blocks(scan))


prange = range


# The loops below are compiled by numba (nopython mode): plain loops over plain arrays, the
# scenarios innermost (independent sums over K rows: they pipeline and vectorise, where sums
# over a handful of columns would wait on each other; measured 2× on paper 001's taps).  On
# several threads each gets a view of its block of scenarios (indexing with an offset instead
# measured 1.35× slower: the offset defeats the vectorisation).
def _tap_loop(S, starts, M, out):  # pragma: no cover
    L, K, r = out.shape
    m, c = M.shape[0], M.shape[1]
    col, acc = np.empty(K), np.empty((r, K))  # one input column, the output row: scenarios contiguous
    for l in range(L):  # noqa: E741
        acc[:, :] = 0.0
        for i in range(m):
            row = starts[i] + l
            for q in range(c):
                for k in range(K):
                    col[k] = S[row, k, q]
                for j in range(r):
                    w = M[i, q, j]
                    if w != 0.0:
                        for k in range(K):
                            acc[j, k] += w * col[k]
        for k in range(K):
            for j in range(r):
                out[l, k, j] = acc[j, k]


def _scan_loop(PhiT, x0, G):  # pragma: no cover
    Mn, K, n = G.shape
    x = np.empty((n, K))  # the state, scenarios contiguous
    for k in range(K):
        for q in range(n):
            x[q, k] = x0[k, q]
    acc = np.empty((n, K))
    for s in range(Mn):
        for j in range(n):
            for k in range(K):
                acc[j, k] = G[s, k, j]
        for q in range(n):
            for j in range(n):
                w = PhiT[q, j]
                if w != 0.0:
                    for k in range(K):
                        acc[j, k] += x[q, k] * w
        for j in range(n):
            for k in range(K):
                x[j, k] = acc[j, k]
                G[s, k, j] = acc[j, k]


def _tap_blocks(tap):  # pragma: no cover
    """:func:`_tap_loop` over ``nchunks`` contiguous blocks of the K scenarios, in parallel."""

    def run(S, starts, M, out, nchunks):
        K = out.shape[1]
        size = (K + nchunks - 1) // nchunks
        for ch in prange(nchunks):
            k0, k1 = ch * size, min(K, ch * size + size)
            tap(S[:, k0:k1], starts, M, out[:, k0:k1])

    return run


def _scan_blocks(scan):  # pragma: no cover
    """:func:`_scan_loop` over ``nchunks`` contiguous blocks of the K scenarios, in parallel."""

    def run(PhiT, x0, G, nchunks):
        K = G.shape[1]
        size = (K + nchunks - 1) // nchunks
        for ch in prange(nchunks):
            k0, k1 = ch * size, min(K, ch * size + size)
            scan(PhiT, x0[k0:k1], G[:, k0:k1])

    return run
