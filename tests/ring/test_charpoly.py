"""charpoly (flint's fmpq_mat.charpoly) against det(sI − M) computed as a polynomial
determinant by the ring, and Cayley–Hamilton: p(M) = 0."""

from __future__ import annotations

from hypothesis import given

from uio_ring.ring import PolyMatrix
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.matrix import Poly

from .strategies import dense_matrices


@given(dense_matrices(min_rows=1, max_rows=5, max_degree=0).filter(lambda M: M.rows == M.cols)
       | dense_matrices(rows=3, cols=3, max_degree=0))
def test_charpoly_is_det_of_s_minus_m_and_annihilates(M):
    n = M.rows
    s = Poly.gen("s")
    coeffs = M.coefficient_lists()[0]
    sI_M = PolyMatrix([[(s if i == j else Poly(0, "s")) - Poly(coeffs[i][j], "s") for j in range(n)]
                       for i in range(n)], var="s")
    p = charpoly(M)
    assert p == sI_M.det() and p.degree() == n and p.lc() == 1
    acc = PolyMatrix.zeros(n, n)
    for c in reversed(p.coeffs()):  # Horner: p(M) = 0
        acc = acc @ M + c * PolyMatrix.identity(n)
    assert acc.is_zero()
