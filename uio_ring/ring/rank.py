"""Rank and determinant over Q[δ] by evaluation — never by echelon over Q(δ): the public
façade of :mod:`uio_ring.ring._predicates`, whose docstring states the algorithm and why
the evaluation points prove the result.

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
