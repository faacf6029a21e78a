"""Subspaces of Q^n for the delay-free structural algorithms (Grip & Saberi 2010).

Private helpers on constant rational matrices (the ring's
:mod:`uio_ring.ring.constant` functions, python-flint ``fmpq_mat``): observability
stacks, kernels, column bases, membership and left solves.  Every subspace is a
matrix whose *columns* span it; bases are in reduced echelon form, so they are
unique for a given subspace.

>>> from uio_ring.ring import constant as qc
>>> A = qc.qmat([[0, 1], [0, 0]]); C = qc.qmat([[1, 0]])
>>> qc.to_polymatrix(kernel(observability_stack(A, C, 1)))
PolyMatrix([[0], [1]])
>>> qc.to_polymatrix(column_basis(qc.qmat([[1, 2], [2, 4]])))
PolyMatrix([[1], [2]])
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction
from typing import Any

from uio_ring.errors import DimensionError
from uio_ring.ring import constant as qc

__all__ = [
    "vstack",
    "hstack",
    "square_matrix",
    "observability_stack",
    "kernel",
    "column_basis",
    "left_solve",
    "in_span",
    "column",
    "as_tuple",
    "read_triple",
]

QMat = qc.QMat


def vstack(blocks: Sequence[QMat], ncols: int) -> QMat:
    """Blocks stacked vertically, through the flat entry lists (no per-entry Python loop).

    Precondition: every block has ``ncols`` columns (not checked).
    """
    entries: list[Any] = []
    for B in blocks:
        entries.extend(B.entries())
    return QMat(sum(B.nrows() for B in blocks), ncols, entries)


def hstack(blocks: Sequence[QMat], nrows: int) -> QMat:
    """Blocks side by side.  Precondition: every block has ``nrows`` rows (not checked)."""
    return vstack([B.transpose() for B in blocks], nrows).transpose()


def square_matrix(M: Any, name: str) -> QMat:
    """``M`` as a square ``fmpq_mat``; ``DimensionError`` naming ``name`` otherwise."""
    Q = qc.qmat(M, name)
    if Q.nrows() != Q.ncols():
        raise DimensionError(f"{name} is {Q.nrows()}×{Q.ncols()}; expected a square matrix")
    return Q


def read_triple(A: Any, C: Any, W: Sequence[Any]) -> tuple[QMat, QMat, tuple[QMat, ...]]:
    """``(A, C, (W_1, …))`` as constant rational matrices, shapes checked.

    ``A`` is n×n, ``C`` p×n and every ``W_k`` n×n; the errors name the matrix
    (``W[2]``) and the expected shape.
    """
    Aq = square_matrix(A, "A")
    n = Aq.nrows()
    Cq = qc.qmat(C, "C")
    if Cq.ncols() != n:
        raise DimensionError(f"C has {Cq.ncols()} columns; expected {n} (= columns of A)")
    if isinstance(W, (str, bytes)) or not isinstance(W, Sequence):
        raise DimensionError("W must be a list of n×n matrices (one per basis function of the Jacobian)")
    Ws = []
    for k, Wk in enumerate(W):
        Q = qc.qmat(Wk, f"W[{k}]")
        if (Q.nrows(), Q.ncols()) != (n, n):
            raise DimensionError(f"W[{k}] is {Q.nrows()}×{Q.ncols()}; expected {n}×{n} (= shape of A)")
        Ws.append(Q)
    return Aq, Cq, tuple(Ws)


def observability_stack(A: QMat, C: QMat, i: int) -> QMat:
    """``[C; C A; …; C A^{i−1}]`` (0×n for ``i = 0``).

    Precondition: ``A`` is n×n and ``C`` has n columns (not checked).
    """
    n = A.nrows()
    blocks = []
    row = C
    for _ in range(i):
        blocks.append(row)
        row = row * A
    return vstack(blocks, n)


def kernel(M: QMat) -> QMat:
    """A basis of ``{v : M v = 0}`` as columns (RREF basis, free variables set to 1)."""
    return qc.nullspace(M)


def column_basis(M: QMat) -> QMat:
    """A basis of the column space of ``M`` as columns, in reduced echelon form (unique)."""
    R, piv = qc.rref(M.transpose())
    k = len(piv)
    out = qc.qzeros(M.nrows(), k)
    for c in range(k):
        for i in range(M.nrows()):
            out[i, c] = R[c, i]
    return out


def left_solve(M: QMat, v: QMat) -> QMat | None:
    """A row ``x`` with ``x M = v`` (``v`` one row), or ``None`` when there is none.

    Precondition: ``v`` is 1×(columns of ``M``) (not checked).
    """
    m = M.nrows()
    aug = hstack([M.transpose(), v.transpose()], M.ncols())
    R, piv = qc.rref(aug)
    if m in piv:
        return None
    x = qc.qzeros(1, m)
    for i, p in enumerate(piv):
        x[0, p] = R[i, m]
    return x


def in_span(basis: QMat, v: QMat) -> bool:
    """``v`` (a column) lies in the span of the columns of ``basis``."""
    if basis.ncols() == 0:
        return qc.is_qzero(v)
    return qc.qrank(hstack([basis, v], basis.nrows())) == qc.qrank(basis)


def column(M: QMat, j: int) -> QMat:
    """Column ``j`` of ``M`` as an n×1 matrix."""
    out = qc.qzeros(M.nrows(), 1)
    for i in range(M.nrows()):
        out[i, 0] = M[i, j]
    return out


def as_tuple(v: QMat) -> tuple[Fraction, ...]:
    """The entries of a column or row vector as Fractions."""
    if v.ncols() == 1:
        return tuple(qc.frac(v[i, 0]) for i in range(v.nrows()))
    return tuple(qc.frac(v[0, j]) for j in range(v.ncols()))
