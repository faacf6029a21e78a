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
    the samples ``j = jlo …`` of ``X`` and ``Xh`` (time-major ``(S, K, n)``, any strides; fastest as
    views of scenario-innermost arrays ``(S, n, K)``)."""
    if X.shape[0] and X.shape[1]:
        _compiled()(X.transpose(0, 2, 1), Xh.transpose(0, 2, 1), jlo, dt, tol, diverge, j_settle, last_bad, max_after, sumsq, count, peak, t_peak,
                    final, t_diverge, max_set, sq_set)


@functools.cache
def _compiled() -> Any:
    from uio_ring.errors import require

    numba = require("numba", extra="fast")
    return numba.njit(cache=True, nogil=True)(_loop)


def _loop(X, Xh, jlo, dt, tol, diverge, j_settle, last_bad, max_after, sumsq, count, peak, t_peak, final,
          t_diverge, max_set, sq_set):  # pragma: no cover - compiled
    S, n, K = X.shape  # scenario-innermost: the error of a sample in passes over the K scenarios
    inf = np.inf
    e = np.zeros(K)
    for s in range(S):
        j = jlo + s
        t = j * dt
        settled = j >= j_settle
        e[:] = 0.0
        for i in range(n):
            for k in range(K):
                d = abs(X[s, i, k] - Xh[s, i, k])
                ek = e[k]
                # the maximum, NaN propagating as in np.maximum
                e[k] = d if (i == 0 or d > ek or d != d) and (i == 0 or ek == ek) else ek
        for k in range(K):
            ek = e[k]
            finite = abs(ek) < inf
            if not finite or ek > tol:
                last_bad[k] = j
                max_after[k] = 0.0
                sumsq[k] = 0.0
                count[k] = 0
            else:
                if ek > max_after[k]:
                    max_after[k] = ek
                sumsq[k] += ek * ek
                count[k] += 1
            ep = ek if finite else inf
            if ep > peak[k]:
                peak[k] = ep
                t_peak[k] = t
            if (not finite or ek > diverge) and t_diverge[k] != t_diverge[k]:
                t_diverge[k] = t
            if settled:
                if ep > max_set[k]:
                    max_set[k] = ep
                sq_set[k] += ek * ek
            if s == S - 1:
                final[k] = ek
