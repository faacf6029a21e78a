"""Exact linear algebra over Q on python-flint ``fmpq_mat``: the kernel behind ``QMatrix``.

The delay-free methods (Niederwieser et al. 2022 and related papers) work with constant matrices
only; there the ring's polynomial algorithms are overkill.  This module is the
one place that does rank, row echelon form, null spaces, inverses and
minimum-norm solutions over Q — exact, no tolerances.

It is ring-internal: its functions take and return mutable ``fmpq_mat`` and
do little validation.  The layers above the ring use the immutable façade
:class:`~uio_ring.ring.qmatrix.QMatrix`, whose methods delegate here.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> Q = qmat(PolyMatrix("[[1, 2], [2, 4]]"))
>>> qrank(Q), to_polymatrix(nullspace(Q))
(1, PolyMatrix([[-2], [1]]))
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any, TypeAlias

import flint

from uio_ring.ring.errors import DimensionError, DomainError
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.parse import canonical_var

__all__ = [
    "QMat",
    "qmat",
    "to_polymatrix",
    "to_fractions",
    "qzeros",
    "qidentity",
    "qvstack",
    "qhstack",
    "qrank",
    "rref",
    "nullspace",
    "left_nullspace",
    "qinverse",
    "qsolve",
    "min_norm_left_solve",
    "row_basis",
    "is_qzero",
    "frac",
    "solve_by_peeling",
]

QMat: TypeAlias = flint.fmpq_mat


def frac(q: Any) -> Fraction:
    """A flint rational (or int/Fraction) as :class:`fractions.Fraction`.

    >>> frac(flint.fmpq(-3, 4))
    Fraction(-3, 4)
    """
    if isinstance(q, Fraction):
        return q
    if isinstance(q, int):
        return Fraction(q)
    return Fraction(int(q.p), int(q.q))


def qzeros(m: int, n: int) -> QMat:
    """The m×n zero matrix."""
    return flint.fmpq_mat(m, n)


def qidentity(n: int) -> QMat:
    """The n×n identity."""
    Q = flint.fmpq_mat(n, n)
    for i in range(n):
        Q[i, i] = 1
    return Q


def qmat(M: Any, name: str = "matrix", *, shape: tuple[int, int] | None = None) -> QMat:
    """A constant matrix as ``fmpq_mat``.

    ``M`` is a PolyMatrix of δ-degree ≤ 0, an ``fmpq_mat`` (returned as is), or
    nested lists of int/Fraction/decimal strings (no floats).

    Raises
    ------
    DomainError
        ``M`` depends on the indeterminate (the error names ``name``).
    """
    if isinstance(M, flint.fmpq_mat):
        return M
    if not isinstance(M, PolyMatrix):
        M = PolyMatrix(M, shape=shape)
    if M.degree() > 0:
        raise DomainError(f"{name} must be a constant matrix (degree 0 in {M.var}); it has degree {M.degree()}")
    m, n = M.shape
    Q = flint.fmpq_mat(m, n)
    if m and n and M.degree() == 0:
        for i, row in enumerate(M.coefficient_lists()[0]):
            for j, c in enumerate(row):
                if c:
                    Q[i, j] = flint.fmpq(c.numerator, c.denominator)
    return Q


def to_fractions(Q: QMat) -> list[list[Fraction]]:
    """Entries as nested lists of Fractions."""
    return [[frac(Q[i, j]) for j in range(Q.ncols())] for i in range(Q.nrows())]


def to_polymatrix(Q: QMat, var: str = "d") -> PolyMatrix:
    """An ``fmpq_mat`` as a constant PolyMatrix in ``var`` (entry by entry, no parsing)."""
    m, n = Q.nrows(), Q.ncols()
    if m == 0 or n == 0:
        return PolyMatrix.zeros(m, n, var)
    rows = [[flint.fmpq_poly([x]) if x != 0 else flint.fmpq_poly() for x in r] for r in Q.tolist()]
    return PolyMatrix._new(rows, m, n, canonical_var(var))


def is_qzero(Q: QMat) -> bool:
    """True iff every entry is zero."""
    return all(Q[i, j] == 0 for i in range(Q.nrows()) for j in range(Q.ncols()))


def qvstack(blocks: Sequence[QMat], ncols: int | None = None) -> QMat:
    """Stack blocks vertically (``ncols`` fixes the width when ``blocks`` is empty)."""
    blocks = list(blocks)
    n = blocks[0].ncols() if blocks else (ncols or 0)
    m = sum(B.nrows() for B in blocks)
    out = flint.fmpq_mat(m, n)
    r = 0
    for B in blocks:
        if B.ncols() != n:
            raise DimensionError(f"qvstack: a block has {B.ncols()} columns; expected {n}")
        for i in range(B.nrows()):
            for j in range(n):
                out[r + i, j] = B[i, j]
        r += B.nrows()
    return out


def qhstack(blocks: Sequence[QMat], nrows: int | None = None) -> QMat:
    """Stack blocks horizontally."""
    return qvstack([B.transpose() for B in blocks], nrows).transpose()


def qrank(Q: QMat) -> int:
    """Rank over Q."""
    if Q.nrows() == 0 or Q.ncols() == 0:
        return 0
    return Q.rank()


def rref(Q: QMat) -> tuple[QMat, tuple[int, ...]]:
    """Reduced row echelon form and its pivot columns.

    >>> R, piv = rref(flint.fmpq_mat([[0, 2, 4], [0, 1, 3]]))
    >>> piv
    (1, 2)
    """
    m, n = Q.nrows(), Q.ncols()
    if m == 0 or n == 0:
        return flint.fmpq_mat(m, n), ()
    R, r = Q.rref()
    piv = []
    for i in range(r):
        j = next(j for j in range(n) if R[i, j] != 0)
        piv.append(j)
    return R, tuple(piv)


def nullspace(Q: QMat) -> QMat:
    """A basis of the right null space ``{v : Q v = 0}`` as the columns of an n×k matrix."""
    n = Q.ncols()
    R, piv = rref(Q)
    free = [j for j in range(n) if j not in piv]
    N = flint.fmpq_mat(n, len(free))
    for c, f in enumerate(free):
        N[f, c] = 1
        for i, p in enumerate(piv):
            N[p, c] = -R[i, f]
    return N


def left_nullspace(Q: QMat) -> QMat:
    """A basis of ``{v : v Q = 0}`` as the rows of a k×m matrix."""
    return nullspace(Q.transpose()).transpose()


def row_basis(Q: QMat) -> tuple[int, ...]:
    """Indices of the first rows of ``Q`` that form a basis of its row space (greedy)."""
    return rref(Q.transpose())[1]


def qinverse(Q: QMat, name: str = "matrix") -> QMat:
    """The inverse of a square nonsingular matrix.

    Raises
    ------
    DimensionError
        ``Q`` is not square or is singular (the message names ``name``).
    """
    n = Q.nrows()
    if Q.ncols() != n:
        raise DimensionError(f"{name} is {n}×{Q.ncols()}; an inverse needs a square matrix")
    if n == 0:
        return flint.fmpq_mat(0, 0)
    try:
        return Q.inv()
    except ZeroDivisionError:
        raise DimensionError(f"{name} is singular (rank {Q.rank()} < {n})") from None


def qsolve(Q: QMat, B: QMat, name: str = "matrix") -> QMat:
    """``X`` with ``Q X = B`` for a square nonsingular ``Q``."""
    n = Q.nrows()
    if Q.ncols() != n or B.nrows() != n:
        raise DimensionError(f"{name}: cannot solve a {n}×{Q.ncols()} system for a {B.nrows()}-row right side")
    if n == 0:
        return flint.fmpq_mat(0, B.ncols())
    try:
        return Q.solve(B)
    except ZeroDivisionError:
        raise DimensionError(f"{name} is singular (rank {Q.rank()} < {n})") from None


def min_norm_left_solve(W: QMat, b: QMat) -> QMat | None:
    """The minimum-norm ``ζ`` (1×p) with ``ζ W = b``, or ``None`` if there is none.

    The minimum-norm solution is orthogonal to the left null space of ``W``,
    i.e. ``ζᵀ`` lies in the column space of ``W``: ``ζ = (W c)ᵀ`` where ``c``
    solves ``cᵀ (Wᵀ W) = b`` (any solution; ``ζ`` is then unique).  Exact, and
    equal to ``b W⁺`` (Moore–Penrose) whenever a solution exists.

    >>> W = flint.fmpq_mat([[2], [0]])
    >>> min_norm_left_solve(W, flint.fmpq_mat([[3]]))
    [3/2, 0]
    """
    G = W.transpose() * W  # m×m
    # solve c G = b  <=>  G^T c^T = b^T ; G symmetric
    m = G.nrows()
    aug = qhstack([G, b.transpose()])
    R, piv = rref(aug)
    if m in piv:
        return None
    c = flint.fmpq_mat(m, 1)
    for i, p in enumerate(piv):
        c[p, 0] = R[i, m]
    zeta = (W * c).transpose()
    if zeta * W != b:
        return None
    return zeta


def solve_by_peeling(H: QMat, w: QMat) -> QMat | None:
    """Solve ``H β = w`` (square, one right-hand side) by substitution when ``H`` is
    triangular up to row and column permutations; ``None`` if it is not.

    Repeatedly takes an equation with exactly one unknown left (nonzero
    coefficient), solves it and substitutes: O(N²) operations instead of the
    O(N³) of elimination — what makes Step 3 of Niederwieser et al. (2022) cheap, whose matrices
    ``H^{(j)}`` have this structure (``det H^{(j)} = 1``).

    >>> H = flint.fmpq_mat([[0, 2], [1, 3]])
    >>> solve_by_peeling(H, flint.fmpq_mat([[4], [5]]))
    [-1]
    [ 2]
    >>> solve_by_peeling(flint.fmpq_mat([[1, 1], [1, 2]]), flint.fmpq_mat([[1], [1]])) is None
    True
    """
    N = H.nrows()
    if H.ncols() != N or w.nrows() != N or w.ncols() != 1:
        raise DimensionError(f"solve_by_peeling: H is {N}×{H.ncols()}, w is {w.nrows()}×{w.ncols()}")
    rows = [{c: H[i, c] for c in range(N) if H[i, c] != 0} for i in range(N)]
    rhs = [w[i, 0] for i in range(N)]
    cols: list[set[int]] = [set() for _ in range(N)]
    for i, r in enumerate(rows):
        for c in r:
            cols[c].add(i)
    ready = [i for i in range(N) if len(rows[i]) == 1]
    x: list[Any] = [None] * N
    done_rows = [False] * N
    solved = 0
    while ready:
        i = ready.pop()
        if done_rows[i] or len(rows[i]) != 1:
            continue
        ((c, a),) = rows[i].items()
        done_rows[i] = True
        v = rhs[i] / a
        x[c] = v
        solved += 1
        for k in cols[c]:
            if k == i or done_rows[k]:
                continue
            rhs[k] -= rows[k].pop(c) * v
            if len(rows[k]) == 1:
                ready.append(k)
            elif not rows[k]:
                if rhs[k] != 0:
                    return None  # inconsistent (H singular)
                done_rows[k] = True
    if solved != N:
        return None
    out = flint.fmpq_mat(N, 1)
    for c in range(N):
        out[c, 0] = x[c]
    return out
