"""Rank and determinant over Q[δ] by evaluation — never by echelon over Q(δ).

Rank
    ``rank M(x) ≤ rank M`` for every rational x, and a nonzero k×k minor (degree
    ≤ b_k, see :func:`~uio_ring.ring._evaluation.minor_degree_bound`) vanishes at
    no more than b_k points.  So if ``b_{r+1} + 1`` distinct points all give rank
    ≤ r while some point gives r, the rank is exactly r.  Evaluation stops at
    once when the rank reaches min(m, n).
Determinant
    ``det M(x)`` at ``b_n + 1`` points, then interpolation.

Cost: O(points · n³) rational operations in C.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> M = PolyMatrix("[[d, d**2], [1, d]]")
>>> rank(M), det(M)
(1, 0)
>>> det(PolyMatrix("[[d, 1], [-1, d]]"))
d**2 + 1
"""

from __future__ import annotations

from uio_ring.ring._predicates import det_raw, rank_raw
from uio_ring.ring.errors import DimensionError
from uio_ring.ring.matrix import PolyMatrix, require_matrix
from uio_ring.ring.poly import Poly

__all__ = ["rank", "det", "det_raw"]


def rank(M: PolyMatrix) -> int:
    """Rank of M over Q[δ] (deterministic, exact; see :func:`~uio_ring.ring._predicates.rank_raw`)."""
    M = require_matrix(M, "rank")
    return rank_raw(M._r, *M.shape)


def det(M: PolyMatrix) -> Poly:
    """Determinant of a square matrix over Q[δ]."""
    M = require_matrix(M, "det")
    m, n = M.shape
    if m != n:
        raise DimensionError(f"det needs a square matrix; this one is {m}×{n}")
    return Poly._wrap(det_raw(M._r, n), M.var)
