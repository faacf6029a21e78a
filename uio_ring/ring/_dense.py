"""In-place kernels on dense matrices stored as ``list[list[fmpq_poly]]``.

No validation happens here: every function states its precondition, and the
façade (:mod:`uio_ring.ring.matrix`) or the algorithm modules check inputs.
A matrix with ``m`` rows and ``n`` columns is a list of ``m`` lists of length
``n``; a 0×n matrix cannot carry ``n`` in this form, so callers pass shapes.

The degree of the zero polynomial is ``-1``.
"""

from __future__ import annotations

from collections.abc import Sequence

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring._kronecker import STACK_MIN_BIG_BITS, matmul_kronecker, matmul_stacked

Rows = list[list[flint.fmpq_poly]]

__all__ = [
    "Rows",
    "copy",
    "identity",
    "zeros",
    "matmul",
    "transpose",
    "row_axpy",
    "row_divide",
    "mat_degree",
    "row_degree",
    "leading_position",
    "weak_popov",
    "popov",
    "reduce_rows",
]


def copy(a: Rows) -> Rows:
    return [list(r) for r in a]


def identity(n: int) -> Rows:
    z, o = bk.ZERO, bk.ONE
    return [[o if i == j else z for j in range(n)] for i in range(n)]


def zeros(m: int, n: int) -> Rows:
    z = bk.ZERO
    return [[z] * n for _ in range(m)]


#: From this many entry products (m·k·n) on, :func:`matmul` uses Kronecker substitution.
KRONECKER_MIN_PRODUCTS = 512


def matmul(a: Rows, b: Rows, m: int, k: int, n: int) -> Rows:
    """``a @ b`` for a (m×k) and b (k×n): entry by entry, or from
    ``KRONECKER_MIN_PRODUCTS`` entry products on by one integer matrix product
    (:func:`~uio_ring.ring._kronecker.matmul_kronecker`) — unless a is so sparse that
    its nonzero entries times n do not exceed the ``m·k + k·n`` values that product
    would pack: then row by row from those entries (:func:`_matmul_sparse_rows`).
    First, whatever their number, products whose first entries show coefficients of
    ``STACK_MIN_BIG_BITS`` bits or more go through the coefficient-stacked product when
    its rule takes it (big coefficients times small ones,
    :func:`~uio_ring.ring._kronecker.matmul_stacked`): one by one, or row by row from a
    sparse a, flint pads the small coefficients to the big size (Δ_k·A of a random
    32-state check, a dense 1×32 row of 17-kbit coefficients by the 32×32 A of degree 16,
    took the row-by-row path: 43 % of the samples of a profile of that check's first
    280 s).
    Precondition: shapes fit (not checked)."""
    if m * k * n > 1 and max(_first_bits(a), _first_bits(b)) >= STACK_MIN_BIG_BITS:
        stacked = matmul_stacked(a, b, m, k, n)  # big coefficients times small ones: not one by one
        if stacked is not None:
            return stacked
    if m * k * n >= KRONECKER_MIN_PRODUCTS:
        rows = [[t for t in range(k) if not ai[t].is_zero()] for ai in a]
        if sum(len(r) for r in rows) * n <= m * k + k * n:
            return _matmul_sparse_rows(a, b, rows, n)
        return matmul_kronecker(a, b, m, k, n)
    z = bk.ZERO
    out = []
    bt = [[b[t][j] for t in range(k)] for j in range(n)] if k else [[] for _ in range(n)]
    for i in range(m):
        ai = a[i]
        nz = [t for t in range(k) if not ai[t].is_zero()]
        row = []
        for j in range(n):
            col = bt[j]
            s = z
            for t in nz:
                c = col[t]
                if not c.is_zero():
                    s = s + ai[t] * c
            row.append(s)
        out.append(row)
    return out


def _first_bits(a: Rows) -> int:
    """:func:`~uio_ring.ring._backend.bits` of the first nonzero entry of a (0 when there is
    none): a sample, two calls, that lets :func:`matmul` skip the full size scan of
    :func:`~uio_ring.ring._kronecker.matmul_stacked` for the small products it mostly forms."""
    for row in a:
        for p in row:
            if p:
                return bk.bits(p)
    return 0


def _matmul_sparse_rows(a: Rows, b: Rows, rows: list[list[int]], n: int) -> Rows:
    """``a @ b`` row by row from the nonzero entries of a (``rows[i]``: their columns):
    ``nnz(a)·n`` polynomial products, fewer than the ``m·k + k·n`` values the Kronecker
    product packs when a is sparse (a block shift ``A0``, ``L0 = A0 − G0 C0``: one or two
    entries a row)."""
    z = bk.ZERO
    out = []
    for ai, nz in zip(a, rows, strict=True):
        row = [z] * n
        for t in nz:
            c, bt = ai[t], b[t]
            row = [x + c * y if not y.is_zero() else x for x, y in zip(row, bt, strict=True)]
        out.append(row)
    return out


def transpose(a: Rows, m: int, n: int) -> Rows:
    return [[a[i][j] for i in range(m)] for j in range(n)]


def row_axpy(a: Rows, target: int, q: flint.fmpq_poly, source: int, start: int = 0) -> None:
    """``a[target] -= q * a[source]`` on columns ``start:``. Precondition: target ≠ source."""
    rt, rs = a[target], a[source]
    for j in range(start, len(rt)):
        s = rs[j]
        if s:  # truth value, not ``is_zero()``: no method call (10 % of a small elimination)
            rt[j] = rt[j] - q * s


def row_divide(a: Rows, i: int, c: flint.fmpq) -> None:
    """``a[i] /= c`` for a nonzero rational c (by ``fmpq_poly / fmpq``: half the time of a
    product by the constant polynomial ``1/c``, and no inverse to build)."""
    a[i] = [x / c if x else x for x in a[i]]  # zero entries stay (the same zero)


def row_degree(row: Sequence[flint.fmpq_poly]) -> int:
    return max([p.degree() for p in row], default=-1)  # a list: faster than a generator


def mat_degree(a: Rows) -> int:
    return max([p.degree() for r in a for p in r], default=-1)  # one list: no call per row


def leading_position(row: Sequence[flint.fmpq_poly | flint.fmpz_poly]) -> tuple[int, int]:
    """``(degree, position)``: the row degree and the rightmost column attaining it
    (``(-1, -1)`` for a zero row). Row-wise convention, zero shift."""
    best_d, best_j = -1, -1
    for j, p in enumerate(row):
        dj = p.degree()
        if dj >= best_d and dj >= 0:
            best_d, best_j = dj, j
    return best_d, best_j


#: Up to this size :func:`det_closed_form` applies.
CLOSED_FORM_MAX_SIZE = 4


def det_closed_form(a: Rows, n: int) -> flint.fmpq_poly:
    """The determinant of the n×n rows ``a`` (n ≤ :data:`CLOSED_FORM_MAX_SIZE`) by its
    closed form: products only, no evaluation points.

    >>> d = bk.from_coeffs([0, 1])
    >>> det_closed_form([[d, bk.ONE], [bk.const(2), d]], 2)
    x^2 + (-2)
    """
    if n == 0:
        return bk.ONE
    if n == 1:
        return a[0][0] * bk.ONE  # a new object: entries are never shared with a result
    if n == 2:
        return a[0][0] * a[1][1] - a[0][1] * a[1][0]
    if n == 3:
        return _det3(a)
    return _det4(a)


def _det3(a: Rows) -> flint.fmpq_poly:
    """The 3×3 determinant by cofactors along the first row: nine products, where the
    fraction-free elimination or the interpolation of
    :func:`~uio_ring.ring._predicates.det_raw` cost 3–8× more
    (degree 16, coefficients in [−3, 3]: 19 against 3.2 µs; degree 48 with 64-bit
    coefficients: 317 against 120 µs)."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    return a00 * (a11 * a22 - a12 * a21) - a01 * (a10 * a22 - a12 * a20) + a02 * (a10 * a21 - a11 * a20)


def _det4(a: Rows) -> flint.fmpq_poly:
    """The 4×4 determinant by Laplace expansion along the first two rows: six 2×2 minors
    of rows 0, 1 times the complementary minors of rows 2, 3, with sign
    (−1)^(1 + j + k) for columns j < k (1.6–3× faster than the general paths of
    :func:`~uio_ring.ring._predicates.det_raw`:
    degree 16, 50 against 22 µs; degree 48 with 64-bit coefficients, 1.66 against 0.52 ms).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([["d", 1, 0, 2], [0, "d", 1, 0], [3, 0, "d", 1], [1, 1, 0, "d"]])
    >>> from uio_ring.ring._fraction_free import det_fraction_free
    >>> _det4(M._r) == det_fraction_free(M._r, 4)   # Bareiss over Z[δ]
    True
    """
    r0, r1, r2, r3 = a

    def minor(x: Sequence[flint.fmpq_poly], y: Sequence[flint.fmpq_poly], j: int, k: int) -> flint.fmpq_poly:
        return x[j] * y[k] - x[k] * y[j]

    return (minor(r0, r1, 0, 1) * minor(r2, r3, 2, 3) - minor(r0, r1, 0, 2) * minor(r2, r3, 1, 3)
            + minor(r0, r1, 0, 3) * minor(r2, r3, 1, 2) + minor(r0, r1, 1, 2) * minor(r2, r3, 0, 3)
            - minor(r0, r1, 1, 3) * minor(r2, r3, 0, 2) + minor(r0, r1, 2, 3) * minor(r2, r3, 0, 1))


def weak_popov(a: Rows, u: Rows | None = None) -> list[int]:
    """Bring the rows of ``a`` into weak Popov form in place (Mulders–Storjohann).

    The same row operations are applied to ``u`` when given.  Rows that become
    zero are moved to the end.  Returns the indices of the nonzero rows (they are
    ``0..k-1`` after the call).  Precondition: ``u`` (if any) has as many rows as
    ``a``.

    Invariant: every operation is ``a[i] -= c·δ^e·a[k]`` with ``deg a[i] ≥ deg a[k]``
    and the same leading position, which lowers the (degree, position) of row i.
    """
    # each step changes one row: only its leading position is computed again
    lead = [leading_position(row)[1] for row in a]
    while True:
        seen: dict[int, int] = {}
        conflict = None
        for i, j in enumerate(lead):
            if j < 0:
                continue
            if j in seen:
                conflict = (seen[j], i, j)
                break
            seen[j] = i
        if conflict is None:
            break
        k, i, j = conflict
        dk, di = a[k][j].degree(), a[i][j].degree()
        if di < dk:
            i, k, di, dk = k, i, dk, di
        c = bk.lc(a[i][j]) / bk.lc(a[k][j])
        q = bk.monomial(c, di - dk)
        row_axpy(a, i, q, k)
        if u is not None:
            row_axpy(u, i, q, k)
        lead[i] = leading_position(a[i])[1]
    nonzero = sorted(seen.values())  # the rows with a leading position
    rest = set(nonzero)
    order = nonzero + [i for i in range(len(a)) if i not in rest]
    a[:] = [a[i] for i in order]
    if u is not None:
        u[:] = [u[i] for i in order]
    return list(range(len(nonzero)))


def popov(a: Rows, u: Rows | None = None) -> None:
    """Popov form (row-wise, zero shift) of a weak Popov matrix with nonzero rows, in place.

    Afterwards: rows sorted by (pivot degree, pivot position), pivots monic, and
    every entry in a pivot column has lower degree than that pivot (outside its
    own row).  Precondition: ``a`` is in weak Popov form without zero rows.
    """
    lead = sorted((leading_position(row), i) for i, row in enumerate(a))
    a[:] = [a[i] for _, i in lead]
    if u is not None:
        u[:] = [u[i] for _, i in lead]
    pivots: list[tuple[int, int]] = []  # (position, degree) of processed rows
    for i, ((dg, j), _) in enumerate(lead):
        # the reduction keeps row i's leading position: a step subtracts δ^e·row k with
        # e < dg − d_k when j_k > j (j is the rightmost entry of degree dg), and row k's
        # entry in column j has degree < d_k when j > j_k
        if pivots:
            reduce_rows(a, [i], pivots, u)
        c = bk.lc(a[i][j])
        if c != 1:
            row_divide(a, i, c)
            if u is not None:
                row_divide(u, i, c)
        pivots.append((j, dg))
    # Earlier rows need no further reduction: their entries in a later pivot column
    # have degree ≤ their own pivot degree, which is ≤ the later pivot degree, with
    # equality excluded by the (degree, position) order.


def reduce_rows(
    a: Rows,
    targets: Sequence[int],
    pivots: Sequence[tuple[int, int] | None],
    u: Rows | None = None,
    basis: Rows | None = None,
    basis_u: Rows | None = None,
) -> None:
    """Reduce rows ``targets`` of ``a`` modulo a Popov basis, in place.

    ``pivots[r] = (position, degree)`` describes row ``r`` of the basis (rows of
    ``a`` itself unless ``basis`` is given; ``None`` skips that row).  After the
    call every target entry in a pivot column has lower degree than the pivot.
    ``u``/``basis_u`` receive the same operations.  Precondition: the basis rows
    are in Popov form (pivot columns of other basis rows have lower degree).

    Terminates because each step removes the leading term of the entry with the
    largest excess ``deg(x_j) − d_k``, and entries in other pivot columns of the
    subtracted row have excess below it (Popov property).
    """
    src = a if basis is None else basis
    src_u = u if basis_u is None else basis_u
    for t in targets:
        row = a[t]
        while True:
            best = None
            for r, pv in enumerate(pivots):
                if pv is None:
                    continue
                j, dk = pv
                ex = row[j].degree() - dk
                if ex >= 0 and (best is None or ex > best[0]):
                    best = (ex, r, j)
            if best is None:
                break
            ex, r, j = best
            q = bk.monomial(bk.lc(row[j]) / bk.lc(src[r][j]), ex)
            srow = src[r]
            for c, e in enumerate(srow):
                if e:
                    row[c] = row[c] - q * e
            if u is not None and src_u is not None:
                urow = u[t]
                for c, e in enumerate(src_u[r]):
                    if e:
                        urow[c] = urow[c] - q * e
