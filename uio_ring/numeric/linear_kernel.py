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
zero coefficients are skipped (so a 0 · ∞ of a diverged run is not a NaN here).  The loops
run on the calling thread (threads: whole chunks of scenarios,
:func:`uio_ring.sim.batch.simulate_batch` with ``UIO_RING_THREADS``).

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

import functools
import threading
from typing import Any

import numpy as np

__all__ = ["tap_sum", "scan_rows"]


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


_COMPILE_LOCK = threading.Lock()


def _run(which: int, *args: np.ndarray) -> None:
    """Loop ``which`` (0: taps, 1: scan) over the K scenarios."""
    with _COMPILE_LOCK:  # chunks of a batch on threads: one compilation
        loops = _compiled()
    loops[which](*args)


@functools.cache
def _compiled() -> tuple[Any, ...]:
    """The two loops."""
    from uio_ring.errors import require

    numba = require("numba", extra="fast")
    jit = numba.njit(cache=True, nogil=True)
    return jit(_tap_loop), jit(_scan_loop)


# The loops below are compiled by numba (nopython mode): plain loops over plain arrays, the
# scenarios innermost (independent sums over K rows: they pipeline and vectorise, where sums
# over a handful of columns would wait on each other; measured 2× on paper 001's taps).
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
