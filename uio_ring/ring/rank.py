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

from typing import TYPE_CHECKING

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring import _evaluation as ev
from uio_ring.ring.errors import DimensionError
from uio_ring.ring.matrix import require_matrix
from uio_ring.ring.poly import Poly

if TYPE_CHECKING:
    from uio_ring.ring.matrix import PolyMatrix

__all__ = ["rank", "det", "det_raw"]


def rank(M: PolyMatrix) -> int:
    """Rank of M over Q[δ] (deterministic, exact)."""
    M = require_matrix(M, "rank")
    m, n = M.shape
    if m == 0 or n == 0 or M.is_zero():
        return 0
    a = M._r
    coeffs = ev.coefficient_mats(a, m, n)
    top = min(m, n)
    best = 0
    needed = ev.minor_degree_bound(a, m, n, 1) + 1
    used = 0
    for x in ev.points():
        r = bk.mat_rank(ev.evaluate(coeffs, x))
        used += 1
        if r > best:
            best = r
            if best == top:
                return best
            needed = ev.minor_degree_bound(a, m, n, best + 1) + 1
        if used >= needed:
            return best
    raise AssertionError("unreachable")  # pragma: no cover


def det(M: PolyMatrix) -> Poly:
    """Determinant of a square matrix over Q[δ]."""
    M = require_matrix(M, "det")
    m, n = M.shape
    if m != n:
        raise DimensionError(f"det needs a square matrix; this one is {m}×{n}")
    return Poly._wrap(det_raw(M._r, n), M.var)


def det_raw(a: dn.Rows, n: int) -> flint.fmpq_poly:
    """Determinant of the n×n rows ``a`` (precondition: square, not checked)."""
    if n == 0:
        return bk.ONE
    m = n
    coeffs = ev.coefficient_mats(a, m, n)
    bound = ev.minor_degree_bound(a, m, n, n)
    xs, ys = [], []
    for x in ev.points():
        xs.append(x)
        ys.append(bk.mat_det(ev.evaluate(coeffs, x)))
        if len(xs) > bound:
            break
    return ev.interpolate_columns(flint.fmpq_mat(len(ys), 1, ys))[0]
