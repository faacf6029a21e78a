"""The characteristic polynomial of a constant matrix, exactly.

flint's ``fmpq_mat.charpoly`` (in C: the Hessenberg or Berkowitz method over Z after
clearing one denominator, O(n³)–O(n⁴) operations on integers) — a 216×216 observer
matrix takes milliseconds, where ``det(sI − M)`` as a polynomial determinant took minutes.

>>> charpoly(PolyMatrix("[[0, 1], [-2, -3]]"))
s**2 + 3*s + 2
"""

from __future__ import annotations

from typing import Any

import flint

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
    mat = flint.fmpq_mat(n, n, [row[j][0] for row in M._r for j in range(n)])
    return Poly._wrap(mat.charpoly(), var)
