"""Row echelon forms and transform reduction on raw rows (no validation).

The elimination shared by :mod:`~uio_ring.ring.hermite`, :mod:`~uio_ring.ring.smith`,
:mod:`~uio_ring.ring.inverse`, :mod:`~uio_ring.ring.kernel` and
:mod:`~uio_ring.ring.solve`.  It imports only the dense kernels and the Popov
division, so those modules do not import one another.

Degrees: ``deg 0 = -1``.
"""

from __future__ import annotations

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring import _division as dv

__all__ = ["row_echelon", "normalise", "reduce_transform", "CoefficientGrowth", "max_bits"]


class CoefficientGrowth(Exception):
    """Raised by :func:`row_echelon` when a coefficient outgrows its ``bit_cap``."""


def max_bits(rows: dn.Rows) -> int:
    """Largest :func:`~uio_ring.ring._backend.bits` (numerator height plus denominator)
    of an entry of ``rows``.

    >>> import flint
    >>> max_bits([[flint.fmpq_poly([flint.fmpq(1, 1000), 5])]])  # (1 + 5000·δ)/1000
    23
    """
    return max((bk.bits(p) for row in rows for p in row if p), default=0)


def _xgcd_step(a: dn.Rows, u: dn.Rows | None, p: int, i: int, j: int) -> None:
    """Replace rows p, i by ``[[s, t], [−a_i/g, a_p/g]]·[row_p; row_i]``, where
    ``g = s·a_p + t·a_i = gcd(a_p, a_i)`` (column j): afterwards ``a[p][j] = g`` and
    ``a[i][j] = 0``.  The 2×2 factor has determinant 1.  Precondition: both entries
    nonzero, p ≠ i (not checked)."""
    x, y = a[p][j], a[i][j]
    g, s, t = bk.xgcd(x, y)
    xg, yg = x // g, y // g
    for rows, skip in ((a, j), (u, -1)):
        if rows is None:
            continue
        rp, ri = rows[p], rows[i]
        rows[p] = [s * e + t * f if c != skip else g for c, (e, f) in enumerate(zip(rp, ri, strict=True))]
        rows[i] = [xg * f - yg * e if c != skip else bk.ZERO for c, (e, f) in enumerate(zip(rp, ri, strict=True))]


def row_echelon(
    a: dn.Rows, u: dn.Rows | None, m: int, n: int, bit_cap: int | None = None, xgcd_rows: int = 2,
    small_lead_ties: bool = False,
) -> list[int]:
    """Row echelon form of ``a`` in place (unimodular row operations, mirrored on ``u``).

    Returns the pivot columns; rows ``0..len(pivots)-1`` are nonzero, the others
    zero.  Pivots are not yet monic and entries above them are not reduced.
    With ``bit_cap``: after each column, raise :class:`CoefficientGrowth` (``a``
    and ``u`` half transformed) when a coefficient of the new pivot row of ``a`` or
    ``u``, or of the next column below it, has more bits (:func:`max_bits`; these
    carry the swell of elimination over Q, at O(m + n) per column), and likewise
    after each pass of remainders on the column's entries — for callers that have
    a better method then.

    Algorithm: column by column.  While several candidate rows are nonzero in
    the column, the row with the least-degree entry (ties: least row degree) is
    the pivot.  If only two rows are left, the other one is eliminated by one 2×2
    extended-gcd step (:func:`_xgcd_step`; python-flint's ``xgcd``, half-gcd in C,
    as in the Euclidean Hermite form of SageMath's ``matrix2.pyx``) instead of a
    remainder sequence over Q, whose every step updates whole rows with swelling
    rational coefficients (the 2×2 ``[[(1+δ)^k, …], [δ^k − 1, …]]`` took 40 s at
    k = 128).  Both give the same second row up to a constant, and Bézout
    cofactors of least degree.  With three or more rows the others are reduced by
    their quotient (one Euclidean division each): pairwise xgcd steps there
    multiply whole rows by cofactors and the degrees grow without bound —
    unless the matrix is small: ``xgcd_rows`` (default 2) takes the extended-gcd
    steps as soon as at most that many rows are left, pairwise from the pivot (as
    SageMath's ``_hermite_form_euclidean`` always does); :func:`~uio_ring.ring.hermite.hermite`
    asks for it on square nonsingular matrices of at most 5 rows, where one xgcd step
    per row costs less than the passes of remainders (4×4 of degree 5: 0.30 → 0.20 ms)
    and the transform is unique, so the cofactors do not leave it larger.
    A pivot that divides an entry eliminates it by one division instead, and its
    row stays unchanged: then the alternating row/column passes of the Smith form
    keep the degree of the corner entry falling until it divides its row and
    column.  ``small_lead_ties``: ties of least degree go to the entry whose numerator has
    the smallest leading coefficient (fewer and smaller denominators in the quotients:
    rank-deficient 4×4, 0.13 → 0.12 ms) instead of the least row degree; for callers
    whose result does not depend on the steps (Hermite: H and the reduced U are unique).
    Precondition: ``u`` has m rows (not checked).
    """
    r = 0
    pivots: list[int] = []
    for j in range(n):
        if r == m:
            break
        # Loop invariant: rows r.. are zero in columns < j.
        while True:
            col = [(x.degree(), i) for i in range(r, m) if (x := a[i][j])]  # (degree, row), nonzero
            nz = [i for _, i in col]
            if len(nz) <= 1:
                break
            least = min(col)[0]
            ties = [i for d, i in col if d == least]
            # the row degree only breaks ties (it costs a pass over the row)
            if len(ties) == 1:
                p = ties[0]
            elif small_lead_ties:
                p = min(ties, key=lambda i: (abs(a[i][j].numer().leading_coefficient()), i))
            else:
                p = min(ties, key=lambda i: (dn.row_degree(a[i]), i))
            if len(nz) <= xgcd_rows:
                for i in nz:
                    if i == p:
                        continue
                    pj = a[p][j]  # changed by an xgcd step with an earlier row
                    q, rem = divmod(a[i][j], pj)
                    if rem.is_zero():  # the pivot divides: keep its row (Smith relies on it)
                        a[i][j] = rem  # = a_ij − q·a_pj
                        dn.row_axpy(a, i, q, p, j + 1)
                        if u is not None:
                            dn.row_axpy(u, i, q, p)
                    else:
                        _xgcd_step(a, u, p, i, j)
                continue
            pj = a[p][j]
            for i in nz:
                if i == p:
                    continue
                # a_ij − q·a_pj is the remainder: divmod gives it without a product
                q, a[i][j] = divmod(a[i][j], pj)
                dn.row_axpy(a, i, q, p, j + 1)
                if u is not None:
                    dn.row_axpy(u, i, q, p)
            # the remainders carry the swell of a column of high degree (a 5×4 of degree
            # 32: thousands of bits within the first column, long before its end)
            if bit_cap is not None and max(bk.bits(x) for i in nz if (x := a[i][j])) > bit_cap:
                raise CoefficientGrowth(f"elimination coefficients exceed {bit_cap} bits in column {j}")
        if not nz:
            continue
        p = nz[0]
        if p != r:
            a[p], a[r] = a[r], a[p]
            if u is not None:
                u[p], u[r] = u[r], u[p]
        pivots.append(j)
        watch = [a[r], [a[i][j + 1] for i in range(r + 1, m)] if j + 1 < n else []]
        if bit_cap is not None and max_bits(watch + ([u[r]] if u is not None else [])) > bit_cap:
            raise CoefficientGrowth(f"elimination coefficients exceed {bit_cap} bits at column {j}")
        r += 1
    return pivots


def normalise(a: dn.Rows, u: dn.Rows | None, pivots: list[int]) -> None:
    """Monic pivots and reduced entries above them, in place.

    Bottom-up: rows k = r−1, …, 0 in turn have their pivot made monic and their
    entries above the pivots of the finished rows i = k+1, …, r−1 reduced by those
    rows, in that order (row i is zero left of its pivot, so a later step keeps
    the entries reduced before).  The normalised form is unique, so this is the
    same result as the top-down order (each pivot row clearing the rows above
    it); but there the rows above are reduced by pivot rows whose own entries
    are not reduced yet, and the quotients and the transform grow (a random
    12×12 of degree 2: 27 ms top-down, 11 ms bottom-up; a 22×20 tall matrix:
    the same).  Precondition: ``a`` is in row echelon form with the given
    pivots (not checked).

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> a = [[2 * d, d**3, bk.ONE], [bk.ZERO, d, d**2], [bk.ZERO, bk.ZERO, d + 1]]
    >>> normalise(a, None, [0, 1, 2])
    >>> [[bk.to_str(e, "d") for e in row] for row in a]
    [['d', '0', '0'], ['0', 'd', '1'], ['0', '0', 'd + 1']]
    """
    r = len(pivots)
    for k in range(r - 1, -1, -1):
        j = pivots[k]
        c = bk.lc(a[k][j])
        if c != 1:
            dn.row_divide(a, k, c)
            if u is not None:
                dn.row_divide(u, k, c)
        for i in range(k + 1, r):
            ji = pivots[i]
            piv = a[i][ji]
            if a[k][ji].degree() >= piv.degree():
                # the reduced entry is the remainder: divmod gives it without a product
                q, a[k][ji] = divmod(a[k][ji], piv)
                dn.row_axpy(a, k, q, i, ji + 1)
                if u is not None:
                    dn.row_axpy(u, k, q, i)


#: Below this many entries in the rows to reduce, :func:`reduce_transform` divides by the
#: Popov basis itself (the 4×6 rows of a 6×4 tall matrix: the bookkeeping of the
#: division through the kernel generators costs more than it can save).
VIA_MIN_ENTRIES = 100


def _reduce_by_one_row(u: dn.Rows, r: int) -> None:
    """:func:`reduce_transform` when the kernel has one row (a rank-deficient square M of
    corank 1): its Popov form is the row made monic at its leading entry, and the
    division of a top row is one Euclidean quotient of its entry in that column — the
    remainder of :class:`~uio_ring.ring._division.PopovDivisor` with k = 1, without its
    set-up (a quarter of the Hermite form of a rank-deficient 4×4 went to that)."""
    d, j = dn.leading_position(u[r])
    c = bk.lc(u[r][j])
    if c != 1:
        dn.row_divide(u, r, c)
    pivot = u[r][j]
    for i in range(r):
        if u[i][j].degree() >= d:
            dn.row_axpy(u, i, u[i][j] // pivot, r)


def reduce_transform(u: dn.Rows, r: int, kernel: dn.Rows | None = None) -> None:
    """Lower the degree of a transform whose rows ``r:`` span a left kernel, in place.

    The kernel rows are replaced by their Popov form (a minimal, row-reduced
    basis of the same module) — or by ``kernel`` when the caller has that Popov
    basis already — and the rows ``:r`` are reduced modulo it by one matrix
    division (:func:`uio_ring.ring._division.reduce_modulo_popov`).  Neither
    changes ``u @ M``, and ``u`` stays unimodular (the kernel block changes by a
    unimodular factor, the top block by multiples of kernel rows).
    Precondition: rows ``r:`` of ``u`` are linearly independent and span the same
    module as ``kernel`` when it is given (not checked).
    """
    if r >= len(u):
        return
    if kernel is None and len(u) == r + 1:
        _reduce_by_one_row(u, r)
        return
    via = None
    if kernel is None and r * len(u) < VIA_MIN_ENTRIES:
        kern = u[r:]
        dn.weak_popov(kern)
        dn.popov(kern)
    elif kernel is None:
        gens = dn.copy(u[r:])
        kern = u[r:]
        p = dn.identity(len(kern))
        dn.weak_popov(kern, p)
        dn.popov(kern, p)
        # kern == p·gens (the same unimodular row operations on both).  Dividing
        # through gens pays when its coefficients are far smaller: tall 22×20 with
        # 24 against 154 bits, 3.9 instead of 5.0 ms; 10 against 20 bits (10×8),
        # 0.31 instead of 0.25 ms.
        if 4 * max_bits(gens) <= max_bits(kern):
            via = (p, gens)
    else:
        kern = dn.copy(kernel)
    u[r:] = kern
    u[:r] = dv.reduce_modulo_popov(u[:r], kern, via)



