"""Smith normal form over Q[δ], with both unimodular transforms, and invariant factors.

Normalisation
    ``S = diag(s_1, …, s_r, 0, …)`` (same shape as M) with monic invariant
    factors ``s_1 | s_2 | … | s_r``, r = rank M.  S is unique.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> smith(PolyMatrix.diag("d", "d + 1")).invariant_factors
(1, d**2 + d)
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring._column_basis import full_rank_core
from uio_ring.ring._echelon import (
    CoefficientGrowth,
    normalise,
    reduce_transform,
    row_echelon,
)
from uio_ring.ring._fraction_free import generic_factors_fraction_free, prefer_fraction_free
from uio_ring.ring._generic import (
    GENERIC_MIN_SIZE,
    GENERIC_MIN_SIZE_FACTORS,
    generic_first,
    generic_hermite,
    generic_invariant_factors,
    generic_last_factor,
)
from uio_ring.ring._kernel_basis import popov_left_kernel
from uio_ring.ring._predicates import (
    coprime_maximal_minors,
    full_rank_at_zero,
    is_smith_raw,
    is_unimodular_raw,
    rank_raw,
    unimodular_given_smith,
)
from uio_ring.ring._reduce import degree_reduced
from uio_ring.ring._smith_by_hermite import DiagonalForm, diagonal_form_by_hermite
from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.hermite import elimination_cap, hermite_of_triangular, triangular_hermite_form
from uio_ring.ring.matrix import PolyMatrix, require_matrix
from uio_ring.ring.poly import Poly

__all__ = ["SmithResult", "smith", "invariant_factors", "is_smith"]


def _offdiagonal_zero(a: dn.Rows, r: int) -> bool:
    for i in range(r):
        row = a[i]
        for j in range(len(row)):
            if j != i and not row[j].is_zero():
                return False
    return True


def _diagonalise(a: dn.Rows, u: dn.Rows | None, vt: dn.Rows | None, m: int, n: int,
                 bit_cap: int | None = None) -> tuple[dn.Rows, int]:
    """Alternate row and column echelon forms until the matrix is diagonal.

    Row operations are mirrored on ``u``; column operations on ``vt`` (= Vᵀ, so
    they are row operations there).  Returns the diagonalised matrix and the rank.
    After the first pass the nonzero part is an r×r triangular block; each pass
    replaces the corner entry by a gcd of its row or column, so its degree falls
    until the first row and column are clean, and likewise for the next corner.
    ``bit_cap``: that of :func:`~uio_ring.ring._echelon.row_echelon` (raises
    :class:`~uio_ring.ring._echelon.CoefficientGrowth`).
    """
    r = len(row_echelon(a, u, m, n, bit_cap=bit_cap))
    shape = (m, n)
    transposed = False  # True while `a` holds the transpose of the working matrix
    while not _offdiagonal_zero(a, r):
        a = dn.transpose(a, *shape)
        shape = (shape[1], shape[0])
        transposed = not transposed
        row_echelon(a, vt if transposed else u, *shape, bit_cap=bit_cap)
    if transposed:
        a = dn.transpose(a, *shape)
    return a, r


def _fix_divisibility(a: dn.Rows, u: dn.Rows | None, vt: dn.Rows | None, r: int) -> None:
    """Make the diagonal a divisibility chain with 2×2 gcd steps, in place.

    For a = d_i, b = d_j and g = s·a + t·b = gcd(a, b):
    ``[[s, t], [−b/g, a/g]] · diag(a, b) · [[1, −t·b/g], [1, s·a/g]] = diag(g, a·b/g)``,
    both factors of determinant 1.
    """
    for i in range(r):
        for j in range(i + 1, r):
            x, y = a[i][i], a[j][j]
            if (y % x).is_zero():
                continue
            g, s, t = bk.xgcd(x, y)
            xg, yg = x // g, y // g
            a[i][i], a[j][j] = g, x * yg
            if u is not None:
                ui, uj = u[i], u[j]
                u[i] = [s * p + t * q for p, q in zip(ui, uj, strict=True)]
                u[j] = [xg * q - yg * p for p, q in zip(ui, uj, strict=True)]
            if vt is not None:  # columns of V: v_i' = v_i + v_j, v_j' = −t·y/g·v_i + s·x/g·v_j
                vi, vj = vt[i], vt[j]
                vt[i] = [p + q for p, q in zip(vi, vj, strict=True)]
                vt[j] = [s * xg * q - t * yg * p for p, q in zip(vi, vj, strict=True)]


@dataclass(frozen=True, eq=False)
class SmithResult:
    """Result of :func:`smith`.

    Attributes
    ----------
    S : PolyMatrix
        Smith form, same shape as M: ``U @ M @ V == S``.
    U : PolyMatrix
        Unimodular, M.rows × M.rows.
    V : PolyMatrix
        Unimodular, M.cols × M.cols.
    invariant_factors : tuple of Poly
        The monic diagonal entries s_1 | … | s_r (r = rank M).
    """

    S: PolyMatrix
    U: PolyMatrix
    V: PolyMatrix
    invariant_factors: tuple[Poly, ...]

    @property
    def rank(self) -> int:
        return len(self.invariant_factors)

    def verify(self, M: PolyMatrix) -> Certificate:
        """Exact certificate: ``U @ M @ V == S``, U and V unimodular, S in Smith form.  When
        the first and the last hold, U's and V's unimodularity follows from determinants
        of a block of M and of U's and V's kernel blocks
        (:func:`~uio_ring.ring._predicates.unimodular_given_smith`) instead of det U, det V."""
        um = self.U @ M
        res = um @ self.V - self.S
        exact, normalised = res.is_zero(), is_smith(self.S)
        m, n = M.shape
        shapes = self.U.shape == (m, m) and self.V.shape == (n, n)
        if exact and normalised and shapes and unimodular_given_smith(self.U._r, self.V._r, um._r, M._r,
                                                                      self.S._r, m, n):
            unimodular = (True, True)
        else:  # which one fails (or neither, if the identities did not hold)
            unimodular = (is_unimodular_raw(self.U._r, *self.U.shape), is_unimodular_raw(self.V._r, *self.V.shape))
        return Certificate(
            "Smith form",
            [
                Check("U @ M @ V == S", exact, None if exact else res, "U M V = S"),
                Check("U unimodular", unimodular[0], None, "det U is a nonzero constant"),
                Check("V unimodular", unimodular[1], None, "det V is a nonzero constant"),
                Check("S normalised", normalised, None, "diagonal, monic, s_i | s_(i+1)"),
            ],
        )

    def _repr_latex_(self) -> str:
        return rf"$S = {self.S.to_latex()}$"


#: :func:`transposed_route` takes the transposed route when its degree bound is at most
#: this fraction of the direct one (a near tie keeps the direct route and its split;
#: exact, as everything in the ring).
TRANSPOSED_ROUTE_RATIO = Fraction(9, 10)


def transposed_route(a: dn.Rows, n: int) -> list[int] | None:
    """The row order P (the row of greatest degree last) under which the Smith transforms
    of a square M come out smaller through ``(P·M)ᵀ``, or None for M itself.

    The generic path gives ``U = H·adj M / det M`` and a small V (``[[I, −h], [0, 1]]``).
    With ``adj_ij`` the cofactor without row j and column i, of degree ≤ min(D_r − d_j,
    D_c − c_i) (d, c the row and column degrees, D_r, D_c their sums), every entry of
    U's column j has degree ≤ min(D_r − d_j, D_c − c_n).  Through the transpose the large
    transform is V, and its entries in row i have degree ≤ min(D_r − d_n, D_c − c_i),
    with d_n the degree of the last row — so that row is the row of greatest degree.
    The transposed route is taken when the sum of its bounds is at most
    ``TRANSPOSED_ROUTE_RATIO`` times the direct one: when the row degrees are far apart
    and the column degrees are not.  Measured (U + V, kbit, direct / transposed / SageMath):
    row degrees 0, 1, 4, 16, 32: 465 / 165 / 285; 3, 3, 3, 40: 179 / 20 / 112; 2, 2, 2,
    2, 2, 30: 543 / 70 / 322; 1, 6, 12, 32, 32: 1487 / 1151 / 1336, and 1.3–1.9× faster.
    Balanced matrices tie and keep the direct route, where the transposed one is larger
    (random 8×8 of degree 2: 238 against 280; 4×4 of degree 64: 8706 against 10823).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([["d**40 + 1", "d", 1], [1, "d + 2", 0], ["d**2", 1, "d**3 - 1"]])
    >>> B = PolyMatrix([["d**8 + 1", "d**8", "d**7 - 1"], ["d**8", "d**8 + 2", "d"], ["d**2", "d**8", "d**8 - 1"]])
    >>> transposed_route(M._r, 3), transposed_route(B._r, 3)       # rows of degree 40, 1, 3; balanced
    ([1, 2, 0], None)
    """
    d = [dn.row_degree(row) for row in a]
    c = [max(a[i][j].degree() for i in range(n)) for j in range(n)]
    last = max(range(n), key=lambda i: (d[i], i))
    dr, dc = sum(d), sum(c)
    direct = sum(max(0, min(dr - d[j], dc - c[n - 1])) for j in range(n))
    transposed = sum(max(0, min(dr - d[last], dc - c[i])) for i in range(n))
    if transposed > TRANSPOSED_ROUTE_RATIO * direct:
        return None
    return [i for i in range(n) if i != last] + [last]


def smith(M: PolyMatrix) -> SmithResult:
    """Smith normal form of M with unimodular U, V such that ``U @ M @ V == S``.

    Normalisation
    -------------
    S is diagonal (same shape as M), its nonzero entries monic and each dividing
    the next; zeros last.  S is unique; U and V are not.

    Parameters
    ----------
    M : PolyMatrix
        Any shape and rank.

    Returns
    -------
    SmithResult
        ``S``, ``U``, ``V``, ``invariant_factors``.  The last ``rows − r`` rows of
        U form a Popov (minimal) basis of the left kernel of M and the last
        ``cols − r`` columns of V a Popov basis of its right kernel; the other
        rows of U / columns of V are reduced modulo those bases.

    Algorithm
    ---------
    A row permutation of a triangular matrix with a nonzero diagonal that is not in
    Hermite form is replaced by its Hermite form H = U_H·M (one normalisation,
    :func:`~uio_ring.ring.hermite.hermite_of_triangular`; then U = U_S·U_H).
    Square matrices with M(0) nonsingular whose row degrees are far apart and column
    degrees are not (row degrees 0, 1, 4, 16, 32) are transposed first, their row of
    greatest degree last,
    which puts the large transform on the side of fewer bits
    (:func:`transposed_route`).  Square nonsingular matrices of size ≥
    ``GENERIC_MIN_SIZE`` whose row degrees
    add up to more than ``deg det`` are first reduced to weak Popov form ``W·M``
    (:mod:`uio_ring.ring._reduce`; then U = U_R·W).  They then try the certified
    generic path of :mod:`uio_ring.ring._generic` (``S = H·V`` with H the generic
    Hermite form and ``V = [[I, −h], [0, 1]]``).  Smaller square matrices of high
    degree (``generic_first``) take those paths when the elimination below outgrows its
    cap, as in :func:`~uio_ring.ring.hermite.hermite`.  Rectangular and singular M (any
    size) whose elimination (below) outgrows its cap (``SMITH_ELIMINATION_BITS``) go
    through Hermite forms, whose unit pivots are cleared by operations that touch
    nothing else, down to a small core
    (:mod:`uio_ring.ring._smith_by_hermite`); so do square nonsingular M of size ≥
    ``GENERIC_MIN_SIZE`` that the generic paths cannot take (a Hermite form other than
    ``[[I, h], [0, δ_n]]``), whose transforms the alternating echelon forms below leave
    unreduced and large.  Otherwise:
    alternating row and column echelon forms with least-degree pivots until
    the matrix is diagonal (python-flint ``xgcd`` when two rows are left), then 2×2
    gcd steps for divisibility, then monic normalisation; the kernel rows of U and
    the kernel columns of V become the Popov kernel bases (one block-Toeplitz
    nullspace each, :mod:`uio_ring.ring._kernel_basis`, from 6 rows) and the other
    rows/columns are reduced modulo them by one Popov division
    (:mod:`uio_ring.ring._division`).

    Examples
    --------
    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix.diag("d", "d + 1")
    >>> s = smith(M)
    >>> s.invariant_factors, s.U @ M @ s.V == s.S
    ((1, d**2 + d), True)

    See Also
    --------
    invariant_factors, is_smith
    """
    return _smith(require_matrix(M, "smith"))


def _smith(M: PolyMatrix, *, orient: bool = True) -> SmithResult:
    """:func:`smith`; ``orient=False``: M is not transposed (:func:`transposed_route`; only
    M itself is: its weak Popov form, whose rows are reduced, keeps the direct route —
    transposed, the P·diag(1, …, δ+1, (δ+1)(δ−2))·Q of 8×8 gave U + V of 67 against
    21 kbit)."""
    m, n = M.shape
    var = M.var
    triangular = hermite_of_triangular(M)
    if triangular is not None:  # S(M) = S(H) with H = U_H·M: U = U_S·U_H, V = V_S
        res = smith(triangular.H)
        return SmithResult(res.S, res.U @ triangular.U, res.V, res.invariant_factors)
    if m == n and generic_first(M._r, n):
        # (M(0) nonsingular proves M so, for which the generic path and the bounds hold)
        order = transposed_route(M._r, n) if orient and full_rank_at_zero(M._r, n, n) else None
        if order is not None:  # P·M = Mp and U'·Mpᵀ·V' = S: U = V'ᵀ·P, V = U'ᵀ
            mp = PolyMatrix._new([M._r[i] for i in order], n, n, var)
            res = _smith(mp.T, orient=False)
            ut = res.V.T._r
            u = [[bk.ZERO] * n for _ in range(n)]
            for r, i in enumerate(order):
                for k in range(n):
                    u[k][i] = ut[k][r]
            return SmithResult(res.S, PolyMatrix._new(u, n, n, var), res.U.T, res.invariant_factors)
        if n < GENERIC_MIN_SIZE:  # small, of high degree: the elimination while it stays small
            try:
                return _smith_by_elimination(M, bit_cap=elimination_cap(M._r))
            except CoefficientGrowth:
                pass
        reduced = degree_reduced(M._r, n, track=True)
        if reduced is not None:  # S(M) = S(W M): U = U_R W, V = V_R
            R, W = reduced
            res = _smith(PolyMatrix._new(R, n, n, var), orient=False)
            return SmithResult(res.S, res.U @ PolyMatrix._new(W or [], n, n, var), res.V, res.invariant_factors)
        got = generic_hermite(M._r, n)
        if got is not None:  # H = [[I, h], [0, δ_n]] and V = [[I, -h], [0, 1]]
            H, U, h = got
            V = dn.identity(n)
            for i in range(n - 1):
                V[i][n - 1] = -h[i]
            S = dn.identity(n)
            S[n - 1][n - 1] = H[n - 1][n - 1]
            return SmithResult(
                S=PolyMatrix._new(S, n, n, var),
                U=PolyMatrix._new(U, n, n, var),
                V=PolyMatrix._new(V, n, n, var),
                invariant_factors=tuple(Poly._wrap(S[i][i], var) for i in range(n)),
            )
    if min(m, n) >= 1 and (m != n or rank_raw(M._r, m, n) < n):
        # rectangular or singular: the elimination while it stays within a kilobit of M's
        # coefficients, else through Hermite forms (the kernel parts of the alternating
        # eliminations swell: a sparse 10×10 of rank 9, 20 s against 1.0 s; at every size:
        # a random 2×4 of degree 64, 26 s against 0.10 s, 6×4 of degree 16, 6.9 / 0.12 s)
        try:
            return _smith_by_elimination(M, bit_cap=elimination_cap(M._r, SMITH_ELIMINATION_BITS))
        except CoefficientGrowth:
            return _smith_by_hermite(M)
    if m == n >= GENERIC_MIN_SIZE:
        # nonsingular, and not of the generic shape: the Hermite forms and their unit
        # pivots keep the transforms reduced at every step, where the alternating echelon
        # forms do not (upper triangular 16×16 with factors δ and δ⁷(δ + 1)⁸: U of
        # 14/135/21k against 44/1806/2103k; P·diag(1, …, δ + 1, (δ + 1)(δ − 2))·Q of
        # 8×8: 22/28/18k and 1/9/0.1k against 22/51/28k and 1/73/1.7k; the same time)
        return _smith_by_hermite(M)
    return smith_by_elimination(M)


#: The bit cap (above 4·M's own) of the elimination a rectangular or singular M tries before
#: the Hermite forms of :mod:`uio_ring.ring._smith_by_hermite`: a sparse 8×8 of rank 5
#: finishes in 6 ms under it (the Hermite forms: 30 ms), a sparse 10×10 of rank 9 leaves it
#: within its first columns.
SMITH_ELIMINATION_BITS = 1024


def _smith_by_hermite(M: PolyMatrix) -> SmithResult:
    """:func:`smith` through Hermite forms and their unit pivots (see
    :mod:`uio_ring.ring._smith_by_hermite`; a core without unit pivots by the elimination),
    with the kernel rows of U and V normalised."""
    d = diagonal_form_by_hermite(M._r, M.rows, M.cols, M.var, _diagonal_form_by_elimination)
    return _normalised_result(M, d)


def smith_by_elimination(M: PolyMatrix) -> SmithResult:
    """:func:`smith` without the generic fast path (any shape; for testing both paths)."""
    return _smith_by_elimination(M)


def _smith_by_elimination(M: PolyMatrix, bit_cap: int | None = None) -> SmithResult:
    """:func:`smith_by_elimination`; with ``bit_cap``, :class:`CoefficientGrowth` as soon as
    an echelon pass outgrows it (the caller then has a better path)."""
    return _normalised_result(M, _diagonal_form_by_elimination(M._r, *M.shape, bit_cap))


def _diagonal_form_by_elimination(a: dn.Rows, m: int, n: int, bit_cap: int | None = None) -> DiagonalForm:
    """The Smith form of the m×n rows ``a`` by alternating echelon forms, divisibility
    steps and monic factors, before the kernel parts of U and V are normalised."""
    u = dn.identity(m)
    vt = dn.identity(n)
    d, r = _diagonalise(dn.copy(a), u, vt, m, n, bit_cap)
    _fix_divisibility(d, u, vt, r)
    for i in range(r):
        c = bk.lc(d[i][i])
        if c != 1:
            d[i][i] = d[i][i] / c
            dn.row_divide(u, i, c)
    return DiagonalForm([d[i][i] for i in range(r)], u, vt)


def _normalised_result(M: PolyMatrix, d: DiagonalForm) -> SmithResult:
    """The :class:`SmithResult` of ``U·M·V = diag(factors)`` (``d``), with the kernel rows
    of U and of Vᵀ replaced by the Popov bases of M's left and right kernels and the other
    rows reduced modulo them (:func:`~uio_ring.ring._echelon.reduce_transform`)."""
    m, n, var = M.rows, M.cols, M.var
    factors, u, vt = d.factors, d.u, d.vt
    r = len(factors)
    reduce_transform(u, r, popov_left_kernel(M._r, m, n) if r < m else None)
    reduce_transform(vt, r, popov_left_kernel(dn.transpose(M._r, m, n), n, m) if r < n else None)
    S = dn.zeros(m, n)
    for i in range(r):
        S[i][i] = factors[i]
    return SmithResult(
        S=PolyMatrix._new(S, m, n, var),
        U=PolyMatrix._new(u, m, m, var),
        V=PolyMatrix._new(dn.transpose(vt, n, n), n, n, var),
        invariant_factors=tuple(Poly._wrap(f, var) for f in factors),
    )


def invariant_factors(M: PolyMatrix) -> tuple[Poly, ...]:
    """The invariant factors of M: monic, ``s_1 | s_2 | … | s_r``, r = rank M.

    Computed without transforms.  A row permutation of a triangular matrix with a
    nonzero diagonal is first replaced by its Hermite form (same factors,
    :func:`~uio_ring.ring.hermite.triangular_hermite_form`).  Then, for a matrix of rank
    n = min(m, n) that is small, of high degree or with large coefficients
    (:func:`~uio_ring.ring._fraction_free.prefer_fraction_free`), the determinantal
    divisors over Z[δ]: two compressed (n−1)-minors with gcd 1 prove ``d_{n−1} = 1``,
    and the gcd of the maximal minors (Bareiss, when there are at most
    ``MAX_MINORS``) is ``d_n``: the factors are ``1, …, 1, d_n``
    (:func:`~uio_ring.ring._fraction_free.generic_factors_fraction_free`).  Otherwise:
    square matrices of size ≥ ``GENERIC_MIN_SIZE_FACTORS``
    first try the certified generic path (factors ``1, …, 1, det/lc`` proved by
    ``gcd(c_n, det) = 1``; from size ``GENERIC_MIN_SIZE`` also two non-trivial
    factors, from the interpolated adjugate; see :mod:`uio_ring.ring._generic`).
    A non-square M of full rank min(m, n) whose maximal minors are certified coprime
    (two compressed minors, :func:`~uio_ring.ring._predicates.coprime_maximal_minors`)
    has every invariant factor 1; otherwise a tall M is replaced by the nonzero rows
    of its Hermite form (same row module, so the same invariant factors; no
    transform is tracked) and a wide M by its transpose.  A singular square M or a tall M
    of rank r < n (from ``ROW_BASIS_MIN_ENTRIES`` nonzero entries) first tries the proof
    that its factors are r ones on a row basis, its weak Popov form
    (:func:`_trivial_by_row_basis`); a singular square M then takes the elimination under a
    guard against runaway growth, else the square core from kernel bases
    (:func:`~uio_ring.ring._column_basis.full_rank_core`).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> invariant_factors(PolyMatrix("[[d, 0], [0, d**2], [1, 1]]"))
    (1, d)
    """
    M = require_matrix(M, "invariant_factors")
    m, n = M.shape
    triangular = triangular_hermite_form(M)
    if triangular is not None:  # the invariant factors of its Hermite form
        return invariant_factors(triangular)
    if m < n:
        return invariant_factors(M.T)
    if m >= n > 0 and prefer_fraction_free(M._r, n):
        if m == n or rank_raw(M._r, m, n) == n:
            facs = generic_factors_fraction_free(M._r, m, n)
            if facs is not None:
                return tuple(Poly._wrap(f, M.var) for f in facs)
    if m > n > 0:
        r = rank_raw(M._r, m, n)
        if r == n and coprime_maximal_minors(M._r, m, n, routing=True):
            return (Poly._wrap(bk.ONE, M.var),) * n
        if 0 < r < n and _trivial_by_row_basis(M._r, m, n):
            return (Poly._wrap(bk.ONE, M.var),) * r
        a = dn.copy(M._r)
        pivots = row_echelon(a, None, m, n)
        # normalised (the Hermite form's nonzero rows): reduced entries instead of the raw
        # echelon's swollen ones (tall 28×24 of degree 3, not left unimodular: the square
        # factors took 42 s on the echelon rows, 0.04 s on H)
        normalise(a, None, pivots)
        return invariant_factors(PolyMatrix._new(a[: len(pivots)], len(pivots), n, M.var))
    if m == n >= GENERIC_MIN_SIZE_FACTORS:
        reduced = degree_reduced(M._r, n, track=False)
        if reduced is not None:  # low degree, large coefficients: elimination is faster here
            M = PolyMatrix._new(reduced[0], n, n, M.var)  # the same invariant factors
            try:  # while it stays small (a 9×9 of degree 8 with two non-trivial factors: 173 s, generic 28 ms)
                return _invariant_factors_by_elimination(M, bit_cap=elimination_cap(M._r))
            except CoefficientGrowth:
                pass
        last = generic_last_factor(M._r, n)
        if last is not None:
            one = Poly._wrap(bk.ONE, M.var)
            return (one,) * (n - 1) + (Poly._wrap(last, M.var),)
        if n >= GENERIC_MIN_SIZE:
            facs = generic_invariant_factors(M._r, n)
            if facs is not None:
                return tuple(Poly._wrap(f, M.var) for f in facs)
    if m == n > 0 and (r := rank_raw(M._r, m, n)) < n:
        # singular: r ones when a row basis proves it; else the elimination under a guard
        # against runaway growth, else a square nonsingular matrix with the same invariant
        # factors from kernel bases
        if _trivial_by_row_basis(M._r, m, n):
            return (Poly._wrap(bk.ONE, M.var),) * r
        try:
            return _invariant_factors_by_elimination(M, bit_cap=FACTORS_GUARD_BITS)
        except CoefficientGrowth:
            core = full_rank_core(M._r, m, n, r) if r else None
            if core is not None:
                return invariant_factors(PolyMatrix._new(core, r, r, M.var))
    return invariant_factors_by_elimination(M)


#: The proof by a row basis (:func:`_trivial_by_row_basis`) is tried on M of rank r < n
#: from this many nonzero entries.  Below, the guarded elimination is cheap and mostly
#: finishes (interleaved, ms, elimination / proof first): the sparse 8×8 of bench_ring
#: (14 entries), 0.53 / 1.86; a random singular 6×6 of degree 1, 0.28 / 0.60.  Above, the
#: proof wins by far when it holds (invariant_factors, random entries in [−3, 3], one row
#: the sum of two others: 12×12 of degree 4, 1.38 / 0.015 s; 16×16 of degree 4, 7.9 /
#: 0.04 s; rank-deficient 16×16 of bench_ring, 0.26 / 0.03 s) and adds 10–40 % to a short
#: elimination when the factors are not trivial (δ+1, (δ+1)(δ−2), …: 8×8 of degree 6,
#: 6.3 / 8.7 ms; on a 16×16 of degree 8 the failed proof costs 0.1 of 2.5 s).
ROW_BASIS_MIN_ENTRIES = 40


def _trivial_by_row_basis(a: dn.Rows, m: int, n: int) -> bool:
    """True when every invariant factor of the m×n ``a`` (rank r < n, at least
    ``ROW_BASIS_MIN_ENTRIES`` nonzero entries) is 1, proved on a row basis: the weak
    Popov form ``W·M = [R; 0]`` (W unimodular, Mulders & Storjohann 2003; degrees only
    fall) has the invariant factors of M, and R (r×n, full row rank) has r ones exactly
    when its r×r minors are coprime — two compressed minors coprime
    (:func:`~uio_ring.ring._predicates.coprime_maximal_minors` of Rᵀ).  False says
    nothing.  It holds for most singular M (random, entries in [−3, 3], 16×16 of degree
    8 and rank 15: 0.8 s, against 15 s for the elimination and the core from kernel
    bases); when M has a non-trivial factor the minors share it and the caller
    eliminates M itself.

    >>> import random
    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> rng = random.Random(1)
    >>> def rand(m, n):
    ...     return PolyMatrix([[f"{rng.randint(-3, 3)}*d + {rng.randint(-3, 3)}" for _ in range(n)]
    ...                        for _ in range(m)])
    >>> A, B = rand(7, 6), rand(6, 7)   # A·B: 7×7 of rank 6
    >>> _trivial_by_row_basis((A @ B)._r, 7, 7)
    True
    >>> M = A @ PolyMatrix.diag(1, 1, 1, 1, 1, "d + 1") @ B
    >>> _trivial_by_row_basis(M._r, 7, 7), invariant_factors(M)[-1]
    (False, d + 1)
    """
    if sum(1 for row in a for x in row if x) < ROW_BASIS_MIN_ENTRIES:
        return False
    rows = dn.copy(a)
    r = len(dn.weak_popov(rows))
    return 0 < r < n and coprime_maximal_minors(dn.transpose(rows[:r], r, n), n, r, routing=True)


#: The guard against runaway growth of the elimination for the invariant factors of a
#: singular square M (an absolute number of bits), before the square core from kernel
#: bases.  Its own constant: hermite's guard (``FULL_ELIMINATION_BITS``, 2 kbit) chooses
#: between other paths, and at 2 kbit here a singular 12×12 of degree 2 took 0.18 s
#: instead of 0.014 s, a rank-deficient 12×12 of bench_ring 0.056 s instead of 0.020 s.
FACTORS_GUARD_BITS = 1 << 14


def invariant_factors_by_elimination(M: PolyMatrix) -> tuple[Poly, ...]:
    """:func:`invariant_factors` without the generic fast path."""
    return _invariant_factors_by_elimination(M)


def _invariant_factors_by_elimination(M: PolyMatrix, bit_cap: int | None = None) -> tuple[Poly, ...]:
    """:func:`invariant_factors_by_elimination`; with ``bit_cap``, :class:`CoefficientGrowth`
    as soon as an echelon pass outgrows it."""
    m, n = M.shape
    a, r = _diagonalise(dn.copy(M._r), None, None, m, n, bit_cap)
    _fix_divisibility(a, None, None, r)
    return tuple(Poly._wrap(bk.monic(a[i][i]), M.var) for i in range(r))


def is_smith(S: PolyMatrix) -> bool:
    """True if S is diagonal with monic entries, each dividing the next, zeros last.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> is_smith(PolyMatrix.diag(1, "d")), is_smith(PolyMatrix.diag("d", 1))
    (True, False)
    """
    S = require_matrix(S, "is_smith")
    return is_smith_raw(S._r, *S.shape)
