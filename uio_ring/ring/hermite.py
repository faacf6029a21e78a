"""Row Hermite normal form over Q[δ], with its unimodular transform.

Degrees: ``deg 0 = -1``.

Normalisation (row-wise)
    Zero rows last; the pivot (first nonzero entry) of each nonzero row lies
    strictly to the right of the pivot of the row above; pivots are monic;
    every entry above a pivot has lower degree than that pivot.  With this
    normalisation the Hermite form H of M is unique.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> M = PolyMatrix([["d**2", "d"], ["d", 1]])
>>> r = hermite(M)
>>> r.H, r.rank, r.U @ M == r.H, is_hermite(r.H)
(PolyMatrix([[d, 1], [0, 0]]), 1, True, True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring._generic import GENERIC_MIN_SIZE, generic_hermite
from uio_ring.ring._reduce import degree_reduced
from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.matrix import require_matrix

if TYPE_CHECKING:
    from uio_ring.ring.matrix import PolyMatrix

__all__ = ["HermiteResult", "hermite", "is_hermite", "row_echelon", "reduce_transform"]


def row_echelon(a: dn.Rows, u: dn.Rows | None, m: int, n: int) -> list[int]:
    """Row echelon form of ``a`` in place (unimodular row operations, mirrored on ``u``).

    Returns the pivot columns; rows ``0..len(pivots)-1`` are nonzero, the others
    zero.  Pivots are not yet monic and entries above them are not reduced.

    Algorithm: column by column, a Euclidean reduction over all candidate rows:
    the row whose entry has the least degree (ties: least row degree) is the
    pivot and the others are reduced by their quotient, until one nonzero entry
    is left.  Precondition: ``u`` has m rows (not checked).
    """
    r = 0
    pivots: list[int] = []
    for j in range(n):
        if r == m:
            break
        # Loop invariant: rows r.. are zero in columns < j.
        while True:
            nz = [i for i in range(r, m) if not a[i][j].is_zero()]
            if len(nz) <= 1:
                break
            p = min(nz, key=lambda i: (a[i][j].degree(), dn.row_degree(a[i]), i))
            pj = a[p][j]
            for i in nz:
                if i == p:
                    continue
                q = a[i][j] // pj
                dn.row_axpy(a, i, q, p, j)
                if u is not None:
                    dn.row_axpy(u, i, q, p)
        if not nz:
            continue
        p = nz[0]
        if p != r:
            a[p], a[r] = a[r], a[p]
            if u is not None:
                u[p], u[r] = u[r], u[p]
        pivots.append(j)
        r += 1
    return pivots


def _normalise(a: dn.Rows, u: dn.Rows | None, pivots: list[int]) -> None:
    """Monic pivots and reduced entries above them, in place.
    Precondition: ``a`` is in row echelon form with the given pivots."""
    for k, j in enumerate(pivots):
        c = bk.lc(a[k][j])
        if c != 1:
            inv = bk.const(1) / c
            a[k] = [x * inv for x in a[k]]
            if u is not None:
                u[k] = [x * inv for x in u[k]]
    for k, j in enumerate(pivots):
        piv = a[k][j]
        dp = piv.degree()
        for i in range(k):
            if a[i][j].degree() >= dp:
                q = a[i][j] // piv
                dn.row_axpy(a, i, q, k, j)
                if u is not None:
                    dn.row_axpy(u, i, q, k)


def reduce_transform(u: dn.Rows, r: int) -> None:
    """Lower the degree of a transform whose rows ``r:`` span a left kernel, in place.

    The kernel rows are brought to Popov form (a minimal, row-reduced basis) and the
    rows ``:r`` are reduced modulo them; neither changes ``u @ M``.
    Precondition: rows ``r:`` of ``u`` are linearly independent.
    """
    if r >= len(u):
        return
    kern = u[r:]
    dn.weak_popov(kern)
    dn.popov(kern)
    u[r:] = kern
    pivots = [dn.leading_position(row)[::-1] for row in kern]
    top = u[:r]
    dn.reduce_rows(top, range(r), pivots, basis=kern)
    u[:r] = top


@dataclass(frozen=True, eq=False)
class HermiteResult:
    """Result of :func:`hermite`.

    Attributes
    ----------
    H : PolyMatrix
        The normalised row Hermite form of M (same shape as M).
    U : PolyMatrix
        Square unimodular transform with ``U @ M == H``.
    rank : int
        Number of nonzero rows of H (the rank of M over Q[δ]).
    pivots : tuple of int
        Column of the pivot of each nonzero row of H.
    """

    H: PolyMatrix
    U: PolyMatrix
    rank: int
    pivots: tuple[int, ...]

    def verify(self, M: PolyMatrix) -> Certificate:
        """Exact certificate: ``U @ M == H``, U unimodular, H normalised."""
        from uio_ring.ring.inverse import is_unimodular

        res = self.U @ M - self.H
        return Certificate(
            "Hermite form",
            [
                Check("U @ M == H", res.is_zero(), None if res.is_zero() else res, "U M = H"),
                Check("U unimodular", is_unimodular(self.U), None, "det U is a nonzero constant"),
                Check("H normalised", is_hermite(self.H), None, "normalised row Hermite form"),
            ],
        )

    def _repr_latex_(self) -> str:
        return rf"$H = {self.H.to_latex()},\quad U = {self.U.to_latex()}$"


def hermite(M: PolyMatrix) -> HermiteResult:
    """Normalised row Hermite form of M with a unimodular transform.

    Normalisation
    -------------
    Row-wise; zero rows last; the pivot of each row strictly to the right of the
    pivot above; pivots monic; entries above a pivot of lower degree than the
    pivot.  H is unique.

    Parameters
    ----------
    M : PolyMatrix
        Any shape and rank (0×n, n×0 and zero matrices included).

    Returns
    -------
    HermiteResult
        ``H`` with ``U @ M == H``; ``U`` square (M.rows × M.rows), unimodular;
        ``rank``; ``pivots``.  When M has full row rank and is square, U is
        unique (``U = H M⁻¹``).  Otherwise the last ``rows − rank`` rows of U are
        a basis of the left kernel of M in Popov form (minimal degrees), and the
        first ``rank`` rows are reduced modulo that basis, which keeps U of low
        degree.

    Algorithm
    ---------
    Square nonsingular matrices of size ≥ ``GENERIC_MIN_SIZE`` whose row degrees add
    up to more than ``deg det`` are first reduced to weak Popov form ``W·M``
    (:mod:`uio_ring.ring._reduce`).  They then try the certified
    evaluation/interpolation path of :mod:`uio_ring.ring._generic` (generic
    shape ``[[I, h], [0, det]]``, U = H·M⁻¹ interpolated; O(n⁴·deg) rational
    operations in C).  Otherwise: Euclidean elimination column by column with
    least-degree pivots (:func:`row_echelon`), normalisation of the pivots, and
    a Popov reduction of the kernel part of U (Mulders & Storjohann 2003).

    Examples
    --------
    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([["d**2", "d"], ["d", 1]])
    >>> r = hermite(M)
    >>> r.H, r.U @ M == r.H
    (PolyMatrix([[d, 1], [0, 0]]), True)

    See Also
    --------
    is_hermite, uio_ring.ring.smith.smith
    """
    M = require_matrix(M, "hermite")
    from uio_ring.ring.matrix import PolyMatrix

    m, n = M.shape
    var = M.var
    if m == n >= GENERIC_MIN_SIZE:
        reduced = degree_reduced(M._r, n, track=True)
        if reduced is not None:  # H(M) = H(W M) and U = U_R W
            R, W = reduced
            res = hermite(PolyMatrix._new(R, n, n, var))
            return HermiteResult(res.H, res.U @ PolyMatrix._new(W or [], n, n, var), res.rank, res.pivots)
        got = generic_hermite(M._r, n)
        if got is not None:
            H, U, _ = got
            return HermiteResult(
                H=PolyMatrix._new(H, n, n, var),
                U=PolyMatrix._new(U, n, n, var),
                rank=n,
                pivots=tuple(range(n)),
            )
    return hermite_by_elimination(M)


def hermite_by_elimination(M: PolyMatrix) -> HermiteResult:
    """:func:`hermite` without the generic fast path (for any shape; used for testing
    the two paths against each other)."""
    from uio_ring.ring.matrix import PolyMatrix

    m, n = M.shape
    var = M.var
    a = dn.copy(M._r)
    u = dn.identity(m)
    pivots = row_echelon(a, u, m, n)
    _normalise(a, u, pivots)
    reduce_transform(u, len(pivots))
    return HermiteResult(
        H=PolyMatrix._new(a, m, n, var),
        U=PolyMatrix._new(u, m, m, var),
        rank=len(pivots),
        pivots=tuple(pivots),
    )


def is_hermite(H: PolyMatrix) -> bool:
    """True if H is in normalised row Hermite form (see :func:`hermite`).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> is_hermite(PolyMatrix("[[1, d], [0, d**2]]")), is_hermite(PolyMatrix("[[0, 1], [1, 0]]"))
    (True, False)
    """
    H = require_matrix(H, "is_hermite")
    last = -1
    seen_zero = False
    pivots: list[tuple[int, int]] = []
    for k, row in enumerate(H._r):
        j = next((c for c, p in enumerate(row) if not p.is_zero()), None)
        if j is None:
            seen_zero = True
            continue
        if seen_zero or j <= last:
            return False
        if bk.lc(row[j]) != 1:
            return False
        pivots.append((k, j))
        last = j
    for k, j in pivots:
        dp = H._r[k][j].degree()
        for i in range(H.rows):
            if i != k and H._r[i][j].degree() >= (dp if i < k else 0):
                return False
    return True
