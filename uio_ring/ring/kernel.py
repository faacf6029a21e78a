"""Left (and right) kernels over Q[δ] as minimal polynomial bases.

``left_kernel(M)`` returns K whose rows are a basis of the module
``{x ∈ Q[δ]^{1×m} : x M = 0}``.  The basis is in Popov form (row-wise, zero
shift): row reduced, so its row degrees are the minimal indices (the smallest
possible), pivots monic, rows sorted by degree.  It is saturated: K has a
polynomial right inverse.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> M = PolyMatrix("[[1], [d], [d**2]]")
>>> K = left_kernel(M)
>>> K, (K @ M).is_zero()
(PolyMatrix([[d, -1, 0], [0, d, -1]]), True)
"""

from __future__ import annotations

from uio_ring.ring import _dense as dn
from uio_ring.ring._echelon import CoefficientGrowth, reduce_transform, row_echelon
from uio_ring.ring._kernel_basis import SWELL_MAX_UNKNOWNS, TOEPLITZ_MIN_ROWS, popov_left_kernel
from uio_ring.ring.hermite import _few_rows_of_high_degree, elimination_cap, kernel_of_few_rows
from uio_ring.ring.matrix import PolyMatrix, require_matrix

__all__ = ["left_kernel", "right_kernel"]


def left_kernel(M: PolyMatrix) -> PolyMatrix:
    """Minimal (Popov) basis of the left kernel of M: rows x with ``x @ M == 0``.

    Shape ``(M.rows − rank M) × M.rows``; a ``0 × M.rows`` matrix when M has full
    row rank.

    Algorithm: the reduced echelon basis of one block-Toeplitz nullspace over Z
    (:mod:`uio_ring.ring._kernel_basis`: Forney's minimal bases as a Gröbner basis
    for the (degree, position) order; O(N³) word operations per prime, N = m·(D+1),
    D the largest minimal index).  Below ``TOEPLITZ_MIN_ROWS`` rows or beyond
    ``MAX_UNKNOWNS`` unknowns: Euclidean
    elimination with a unimodular transform, then the Mulders–Storjohann weak Popov
    form and Popov normalisation of its kernel rows — below ``TOEPLITZ_MIN_ROWS`` rows
    and from δ-degree ``CAP_MIN_DEGREE`` on, the kernel rows of
    :func:`~uio_ring.ring.hermite.hermite`'s transform, whose elimination gives way to
    the Toeplitz systems when its remainders swell (a 5×4 of degree 32: 27 → 1.9 s);
    from ``TOEPLITZ_MIN_ROWS`` rows on, the elimination stops as soon as its coefficients
    swell (:func:`~uio_ring.ring.hermite.elimination_cap`) and the Toeplitz systems take
    over up to ``SWELL_MAX_UNKNOWNS`` unknowns (a dense 18×16 of degree 16, minimal
    indices 128: 2322 unknowns, 21 s, where the elimination ran for over five minutes);
    beyond, the elimination without a cap.
    """
    M = require_matrix(M, "left_kernel")
    m, n = M.shape
    fast = popov_left_kernel(M._r, m, n)
    if fast is not None:
        return PolyMatrix._new(fast, len(fast), m, M.var)
    if _few_rows_of_high_degree(M):  # (no kernel, no Hermite form: 4×4 of degree 32, 0.8 s)
        return kernel_of_few_rows(M)
    if m >= TOEPLITZ_MIN_ROWS:  # the Toeplitz systems were beyond their usual cap
        small = _kernel_by_elimination(M, elimination_cap(M._r))
        if small is not None:
            return small
        swelled = popov_left_kernel(M._r, m, n, max_unknowns=SWELL_MAX_UNKNOWNS)
        if swelled is not None:
            return PolyMatrix._new(swelled, len(swelled), m, M.var)
    return left_kernel_by_elimination(M)


def left_kernel_by_elimination(M: PolyMatrix) -> PolyMatrix:
    """:func:`left_kernel` without the Toeplitz path (any size; for testing the two
    paths against each other — the Popov basis is unique, so they must agree)."""
    got = _kernel_by_elimination(M, None)
    assert got is not None  # no cap, no CoefficientGrowth
    return got


def _kernel_by_elimination(M: PolyMatrix, bit_cap: int | None) -> PolyMatrix | None:
    """The Popov basis of the left kernel of M from the transform of its Euclidean
    elimination (:func:`~uio_ring.ring._echelon.row_echelon`) and the Popov reduction of
    that transform's kernel rows; None when a coefficient of the elimination exceeds
    ``bit_cap`` bits (None: no cap).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> _kernel_by_elimination(PolyMatrix("[[1], [d], [d**2]]"), None)
    PolyMatrix([[d, -1, 0], [0, d, -1]])
    """
    m, n = M.shape
    a = dn.copy(M._r)
    u = dn.identity(m)
    try:
        r = len(row_echelon(a, u, m, n, bit_cap=bit_cap))
    except CoefficientGrowth:
        return None
    reduce_transform(u, r)
    return PolyMatrix._new(u[r:], m - r, m, M.var)


def right_kernel(M: PolyMatrix) -> PolyMatrix:
    """Columns x with ``M @ x == 0``: the transpose of ``left_kernel(M.T)``."""
    M = require_matrix(M, "right_kernel")
    return left_kernel(M.T).T
