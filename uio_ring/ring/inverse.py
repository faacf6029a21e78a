"""Unimodularity predicates and one-sided inverses over Q[δ].

A matrix M (m×n) is *left unimodular* when some polynomial X has ``X M = I_n``:
equivalently rank n and every invariant factor 1 (M(δ) keeps full column rank
for every complex δ).  *Right unimodular*: the same for the transpose.
*Unimodular*: square with a nonzero constant determinant.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> M = PolyMatrix("[[1, d], [0, 1], [d, 0]]")
>>> X = left_inverse(M)
>>> X @ M == PolyMatrix.identity(2), is_left_unimodular(M), is_unimodular(M)
(True, True, False)
"""

from __future__ import annotations

from uio_ring.ring import _dense as dn
from uio_ring.ring._echelon import reduce_transform, row_echelon
from uio_ring.ring._kernel_basis import (
    SWELL_MAX_UNKNOWNS,
    ToeplitzCoefficients,
    kernel_and_solution,
    popov_left_kernel,
    solve_reduced,
)
from uio_ring.ring._predicates import is_unimodular_raw, left_unimodular_proved, rank_raw
from uio_ring.ring.errors import NotUnimodularError
from uio_ring.ring.hermite import (
    _hermite_by_small_elimination,
    guess_first,
    guessed_kernel_and_inverse,
)
from uio_ring.ring.matrix import PolyMatrix, require_matrix
from uio_ring.ring.smith import invariant_factors

__all__ = ["is_unimodular", "is_left_unimodular", "is_right_unimodular", "left_inverse", "right_inverse"]


def is_unimodular(M: PolyMatrix) -> bool:
    """Square with determinant a nonzero constant (0×0 counts)."""
    M = require_matrix(M, "is_unimodular")
    return is_unimodular_raw(M._r, *M.shape)


def _echelon_unit_pivots(M: PolyMatrix, u: dn.Rows | None) -> tuple[dn.Rows, list[int], bool]:
    m, n = M.shape
    a = dn.copy(M._r)
    pivots = row_echelon(a, u, m, n)
    units = len(pivots) == n and all(a[k][j].degree() == 0 for k, j in enumerate(pivots))
    return a, pivots, units


def is_left_unimodular(M: PolyMatrix) -> bool:
    """True if ``X @ M == I`` has a polynomial solution X (rank n, invariant factors 1)."""
    M = require_matrix(M, "is_left_unimodular")
    m, n = M.shape
    if n > m:
        return False
    if n == 0:
        return True
    # the product of the echelon pivots is the gcd of the n×n minors, up to a unit
    return _echelon_unit_pivots(M, None)[2]


def is_right_unimodular(M: PolyMatrix) -> bool:
    """True if ``M @ X == I`` has a polynomial solution X."""
    M = require_matrix(M, "is_right_unimodular")
    return is_left_unimodular(M.T)


def left_inverse(M: PolyMatrix) -> PolyMatrix:
    """A polynomial X with ``X @ M == I`` (M m×n, left unimodular).

    Returns the first n rows of a unimodular U with ``U M = [I; 0]``, reduced
    modulo a Popov (minimal) basis of the left kernel of M: no leading term of
    that basis divides the corresponding entry of X.  This keeps the δ-degree
    low (in an observer, degree is delay).  For square M it is the inverse.

    Algorithm: a tall, dense M of high degree is first tried by the generic guess of its
    Toeplitz systems (:func:`~uio_ring.ring.hermite.guessed_kernel_and_inverse`).  A tall
    M of full column rank is then tried by Euclidean elimination
    stopped as soon as its coefficients swell (:mod:`~uio_ring.ring.hermite`: cheap
    on columns of a unimodular matrix; X is then the top of the Hermite transform,
    reduced modulo the Popov kernel taken from its own kernel rows).  Otherwise, or
    when it stops: X from
    one square block-Toeplitz system (:func:`~uio_ring.ring._kernel_basis.solve_reduced`,
    checked exactly; two degree bounds, or as many as needed when the maximal minors
    are proved coprime: two compressed minors,
    :func:`~uio_ring.ring._predicates.left_unimodular_proved`)
    and the Popov kernel from one Toeplitz nullspace; otherwise
    Euclidean elimination with a unimodular transform, then Popov division of its
    first n rows by the kernel basis.

    Raises
    ------
    NotUnimodularError
        If M has rank < n, or loses rank at some δ (a non-unit invariant factor,
        named in the message).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> left_inverse(PolyMatrix("[[1, d], [0, 1]]"))
    PolyMatrix([[1, -d], [0, 1]])
    """
    M = require_matrix(M, "left_inverse")
    m, n = M.shape
    small = None
    guessed = guess_first(M)  # dense and of high degree: the guess before the elimination, which swells
    quick = guessed_kernel_and_inverse(M) if guessed else None
    if quick is not None and quick.solution is not None:  # never None there; narrows the type
        return PolyMatrix._new(quick.solution, n, m, M.var)
    if m > n > 0:
        # Elimination while its coefficients stay small: U·M = [I; 0] proves it, and
        # any other H proves that no left inverse exists (the errors are raised below).
        # (no cap on two rows: one extended gcd, whose cofactors are what they are, as in
        # :func:`~uio_ring.ring.hermite.hermite`; a 2×1 of degree 128: 15.6 → 7 ms)
        small = _hermite_by_small_elimination(M, capped=False if m <= 2 else None)
        # H[:n] = I exactly when the rank is n and every pivot (k, k) is a constant: H is
        # normalised (pivots monic, so 1; entries above a pivot of lower degree, so 0)
        if small is not None and small.rank == n and all(small.H._r[k][k].degree() == 0 for k in range(n)):
            return PolyMatrix._new(small.U._r[:n], n, m, M.var)
    if m > n > 0 and small is None and rank_raw(M._r, m, n) == n:
        # A returned X is checked exactly (X·M = I), which itself proves that M is left
        # unimodular: two degree bounds first, and all of them only when the minors are
        # proved coprime (the proof costs more than the usual first solve).
        coeffs = ToeplitzCoefficients.of(M._r, m, n)  # one conversion for both
        # any number of rows: the elimination has stopped on its cap (few rows: of high degree)
        got = kernel_and_solution(M._r, m, n, dn.identity(n), coeffs=coeffs, min_rows=0, tries=2,
                                  max_unknowns=SWELL_MAX_UNKNOWNS, guess=not guessed)
        if got is not None:
            X = got.solution
            if X is None and left_unimodular_proved(M._r, m, n):
                X = solve_reduced(M._r, m, n, got.kernel, dn.identity(n), coeffs=coeffs,
                                  max_unknowns=SWELL_MAX_UNKNOWNS)
            if X is not None:
                return PolyMatrix._new(X, n, m, M.var)
            # not proved left unimodular: the invariant factors decide before the
            # elimination below, which swells on such M (28×24 of degree 3: 34 s, 3.5 s)
            _raise_if_not_left_unimodular(M)
    u = dn.identity(m)
    a, pivots, units = _echelon_unit_pivots(M, u)
    if len(pivots) < n:
        raise NotUnimodularError(
            f"the {m}×{n} matrix has rank {len(pivots)} < {n} columns: no left inverse exists"
        )
    if not units:
        _raise_if_not_left_unimodular(M)
        raise AssertionError("a pivot of positive degree, yet every invariant factor constant")  # pragma: no cover
    # a[:n] is upper triangular with constant diagonal: finish to the identity
    for k in range(n - 1, -1, -1):
        c = a[k][k][0]
        dn.row_divide(a, k, c)
        dn.row_divide(u, k, c)
        for i in range(k):
            q = a[i][k]
            if not q.is_zero():
                dn.row_axpy(a, i, q, k)
                dn.row_axpy(u, i, q, k)
    reduce_transform(u, n, popov_left_kernel(M._r, m, n) if n < m else None)
    return PolyMatrix._new(u[:n], n, m, M.var)


def _raise_if_not_left_unimodular(M: PolyMatrix) -> None:
    """Raise :class:`NotUnimodularError` naming the non-constant invariant factors of the
    m×n M of rank n, if there are any."""
    m, n = M.shape
    bad = [f for f in invariant_factors(M) if f.degree() > 0]
    if bad:
        raise NotUnimodularError(
            f"the {m}×{n} matrix is not left unimodular: its invariant factor(s) "
            f"{', '.join(str(f) for f in bad)} are not constants, so it loses rank where "
            f"{' and '.join(f'{f} = 0' for f in bad)}"
        )


def right_inverse(M: PolyMatrix) -> PolyMatrix:
    """A polynomial X with ``M @ X == I`` (M right unimodular); see :func:`left_inverse`.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix("[[1, d, 0], [0, 1, d]]")
    >>> M @ right_inverse(M) == PolyMatrix.identity(2)
    True
    """
    M = require_matrix(M, "right_inverse")
    return left_inverse(M.T).T
