"""The characteristic polynomial of a constant matrix, exactly.

>>> charpoly(PolyMatrix("[[0, 1], [-2, -3]]"))
s**2 + 3*s + 2
"""

from __future__ import annotations

from typing import Any

from uio_ring.ring.errors import DomainError
from uio_ring.ring.matrix import Poly, PolyMatrix

__all__ = ["charpoly"]


def charpoly(M: Any, var: str = "s") -> Poly:
    """``det(s I − M)`` of a constant matrix (PolyMatrix of δ-degree ≤ 0 or QMatrix) as a polynomial in ``var``.

    >>> charpoly(PolyMatrix.zeros(0, 0))
    1
    """
    if not isinstance(M, PolyMatrix):
        M = M.to_polymatrix()
    if M.degree() > 0:
        raise DomainError("charpoly needs a constant matrix")
    n = M.rows
    if n == 0:
        return Poly(1, var)
    coeffs = M.coefficient_lists()[0]
    s = Poly.gen(var)
    rows = [[(s if i == j else Poly(0, var)) - Poly(coeffs[i][j], var) for j in range(n)] for i in range(n)]
    return PolyMatrix(rows, var=var).det()
