"""Compiled (numba) error metrics of a batch segment: ``e = ‖x − x̂‖_∞`` and its running statistics.

:class:`uio_ring.sim.batch._Metrics` keeps, per scenario, the last sample with ``e > tol`` (or
not finite), the maximum, sum of squares and count of ``e`` after it, the peak and its time,
the first divergence (``e > diverge`` or not finite), the final ``e``, and the maximum and sum
of squares from ``j_settle`` on.  Its numpy update takes a segment at a time (an error array
and a dozen reductions over it); :func:`update_metrics` is one pass over the samples of the
segment in time order, each scenario's statistics updated sample by sample, the error never
stored.  The same numbers: every statistic is a maximum, a first or last index, or a count,
except the sums of squares (summed in time order here, pairwise by numpy: equal up to rounding).

Complexity: ``O(S K n)`` for S samples, K scenarios and n states; no allocation.

>>> import numpy as np
>>> st = [np.full(1, -1), np.zeros(1), np.zeros(1), np.zeros(1, dtype=np.int64), np.zeros(1), np.zeros(1),
...       np.full(1, np.nan), np.full(1, np.nan), np.zeros(1), np.zeros(1)]
>>> X = np.array([[[2.0]], [[0.5]], [[0.1]]])             # one scenario, one state, x̂ = 0
>>> update_metrics(X, np.zeros_like(X), 0, 0.1, 1.0, 1e6, 1, *st)
>>> int(st[0][0]), float(st[1][0]), float(st[4][0]), float(st[8][0])   # last bad, max after, peak, max settled
(0, 0.5, 2.0, 0.5)
"""

from __future__ import annotations

import functools
from typing import Any

import numpy as np

__all__ = ["update_metrics"]


def update_metrics(X: np.ndarray, Xh: np.ndarray, jlo: int, dt: float, tol: float, diverge: float, j_settle: int,
                   last_bad: np.ndarray, max_after: np.ndarray, sumsq: np.ndarray, count: np.ndarray,
                   peak: np.ndarray, t_peak: np.ndarray, final: np.ndarray, t_diverge: np.ndarray,
                   max_set: np.ndarray, sq_set: np.ndarray) -> None:
    """Update the statistics (arrays of K, in place; see :class:`uio_ring.sim.batch._Metrics`) with
    the samples ``j = jlo …`` of ``X`` and ``Xh`` (time-major ``(S, K, n)``, any strides)."""
    if X.shape[0] and X.shape[1]:
        _compiled()(X, Xh, jlo, dt, tol, diverge, j_settle, last_bad, max_after, sumsq, count, peak, t_peak,
                    final, t_diverge, max_set, sq_set)


@functools.cache
def _compiled() -> Any:
    from uio_ring.errors import require

    numba = require("numba", extra="fast")
    return numba.njit(cache=True, nogil=True)(_loop)


def _loop(X, Xh, jlo, dt, tol, diverge, j_settle, last_bad, max_after, sumsq, count, peak, t_peak, final,
          t_diverge, max_set, sq_set):  # pragma: no cover - compiled
    S, K, n = X.shape
    inf = np.inf
    for s in range(S):
        j = jlo + s
        t = j * dt
        settled = j >= j_settle
        for k in range(K):
            e = 0.0
            for i in range(n):
                d = abs(X[s, k, i] - Xh[s, k, i])
                if i == 0 or d > e or d != d:  # NaN propagates, as in np.maximum
                    if e == e or i == 0:
                        e = d
            finite = abs(e) < inf
            if not finite or e > tol:
                last_bad[k] = j
                max_after[k] = 0.0
                sumsq[k] = 0.0
                count[k] = 0
            else:
                if e > max_after[k]:
                    max_after[k] = e
                sumsq[k] += e * e
                count[k] += 1
            ep = e if finite else inf
            if ep > peak[k]:
                peak[k] = ep
                t_peak[k] = t
            if (not finite or e > diverge) and t_diverge[k] != t_diverge[k]:
                t_diverge[k] = t
            if settled:
                if ep > max_set[k]:
                    max_set[k] = ep
                sq_set[k] += e * e
            if s == S - 1:
                final[k] = e
