"""Solving ``X·V = W`` over Q[δ].

With ``U V = H`` (row echelon, r nonzero rows, pivots p_k) every solution is
``X = Y U`` with ``Y_[:, :r] H_[:r] = W`` and ``Y_[:, r:]`` free.  The first part
is solved by back substitution along the pivots, which needs exact polynomial
divisions; a remainder anywhere means no polynomial solution.  A square
nonsingular V of size ≥ ``GENERIC_MIN_SIZE``, or smaller but of high degree
(:func:`~uio_ring.ring._generic.generic_first`: 4×4 from degree 6; 4×4 of degree 32,
27 against 81 ms), takes the evaluation path instead:
``W·adj V`` is interpolated and divided exactly by ``det V``
(:func:`uio_ring.ring._generic.generic_solve_left`).  The returned X
is reduced modulo a Popov basis of the left kernel of V (low δ-degree).  A tall
V first tries that reduced X directly, from one square block-Toeplitz system
checked exactly (:func:`uio_ring.ring._kernel_basis.solve_reduced`, at most three
degree bounds); elimination answers when it does not (and names the obstruction
when no polynomial solution exists).

>>> from uio_ring.ring.matrix import PolyMatrix
>>> V = PolyMatrix("[[1, d], [0, d + 1]]")
>>> W = PolyMatrix("[[1, 2*d + 1]]")
>>> X = solve_left(V, W)
>>> X, X @ V == W
(PolyMatrix([[1, 1]]), True)
"""

from __future__ import annotations

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring._division import reduce_modulo_popov
from uio_ring.ring._echelon import reduce_transform, row_echelon
from uio_ring.ring._generic import generic_first, generic_solve_left
from uio_ring.ring._kernel_basis import (
    ToeplitzCoefficients,
    kernel_and_solution,
    popov_left_kernel,
    solve_reduced,
)
from uio_ring.ring._predicates import left_unimodular_proved
from uio_ring.ring.errors import DimensionError, NoPolynomialSolutionError
from uio_ring.ring.hermite import _few_rows_of_high_degree, hermite
from uio_ring.ring.matrix import PolyMatrix, require_matrix

__all__ = ["solve_left", "solve_right"]


def solve_left(V: PolyMatrix, W: PolyMatrix) -> PolyMatrix:
    """A polynomial X with ``X @ V == W``.

    Parameters
    ----------
    V : PolyMatrix
        k×n.
    W : PolyMatrix
        m×n (same number of columns as V).

    Returns
    -------
    PolyMatrix
        X (m×k), reduced modulo a minimal (Popov) basis of the left kernel of V,
        so that among the solutions it has low degree.

    Raises
    ------
    DimensionError
        V and W have different numbers of columns.
    NoPolynomialSolutionError
        No polynomial X exists (the message names the row of W and whether the
        obstruction is rank or divisibility).
    """
    V = require_matrix(V, "solve_left")
    W = require_matrix(W, "solve_left")
    V._check("solve_left", W)
    k, n = V.shape
    m, n2 = W.shape
    if n != n2:
        raise DimensionError(
            f"solve_left: V is {k}×{n} and W is {m}×{n2}; X·V = W needs the same number of columns"
        )
    if k == n and generic_first(V._r, n):
        try:
            got = generic_solve_left(V._r, W._r, n, m)
        except ArithmeticError as exc:
            raise NoPolynomialSolutionError(
                f"solve_left: X·V = W has the unique rational solution W·V⁻¹, and its entry ({exc}) "
                "is not a polynomial"
            ) from None
        if got is not None:
            return PolyMatrix._new(got, m, k, V.var)
    if m and k > n:
        coeffs = ToeplitzCoefficients.of(V._r, k, n)
        both = kernel_and_solution(V._r, k, n, W._r, coeffs=coeffs, tries=3)
        kern = None if both is None else both.kernel
        got = both.solution if both is not None and kern else None
        if got is None and kern and left_unimodular_proved(V._r, k, n):
            # V is left unimodular: a solution exists, so the degree bounds grow until it
            # is found, instead of the elimination below, which swells (X·Ō = [I; C̄Ā^l] of
            # an 8-state observability matrix 14×8 of degree 20 needs D = 28, the fourth
            # bound: 0.6 s, against 100 s by elimination)
            got = solve_reduced(V._r, k, n, kern, W._r, coeffs=coeffs)
        if got is not None:  # X·V = W checked exactly inside; X reduced modulo the kernel
            return PolyMatrix._new(got, m, k, V.var)
    if _few_rows_of_high_degree(V):
        # few rows of high degree: hermite's elimination gives way to the Toeplitz systems
        # when its remainders swell (a 5×4 of degree 32: 28 → 2 s); its H and U serve the
        # same back substitution (H[:r] = U[:r]·V, U[r:] the Popov kernel)
        h = hermite(V)
        a, u, pivots, r = h.H._r, h.U._r, list(h.pivots), h.rank
    else:
        a = dn.copy(V._r)
        u = dn.identity(k)
        pivots = row_echelon(a, u, k, n)
        r = len(pivots)
        reduce_transform(u, r, popov_left_kernel(V._r, k, n) if r < k else None)
    # the kernel rows of u are untouched by the echelon rows: a[:r] still equals u[:r] @ V
    y = []
    for i in range(m):
        w = list(W._r[i])
        coeff = []
        for t, j in enumerate(pivots):
            q, rem = divmod(w[j], a[t][j])
            if not rem.is_zero():
                raise NoPolynomialSolutionError(
                    f"solve_left: row {i} of W is not a polynomial combination of the rows of V "
                    f"(division by the pivot {bk.to_str(a[t][j], V.var)} in column {j} leaves a remainder)"
                )
            coeff.append(q)
            if not q.is_zero():
                row = a[t]
                for c in range(j, n):
                    if not row[c].is_zero():
                        w[c] = w[c] - q * row[c]
        if any(not p.is_zero() for p in w):
            raise NoPolynomialSolutionError(
                f"solve_left: row {i} of W is not in the row space of V over Q(δ) "
                f"(rank of V is {r}; the residual is nonzero)"
            )
        y.append(coeff)
    x = dn.matmul(y, u[:r], m, r, k) if r else dn.zeros(m, k)
    if r < k:
        x = reduce_modulo_popov(x, u[r:])
    return PolyMatrix._new(x, m, k, V.var)


def solve_right(V: PolyMatrix, W: PolyMatrix) -> PolyMatrix:
    """A polynomial X with ``V @ X == W``: the transpose of ``solve_left(V.T, W.T)``."""
    V = require_matrix(V, "solve_right")
    W = require_matrix(W, "solve_right")
    return solve_left(V.T, W.T).T
