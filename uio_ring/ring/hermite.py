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

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring import _evaluation as ev
from uio_ring.ring import _integral as zi
from uio_ring.ring._echelon import (
    CoefficientGrowth,
    max_bits,
    normalise,
    reduce_transform,
    row_echelon,
)
from uio_ring.ring._generic import (
    GENERIC_MIN_SIZE,
    GENERIC_MIN_WORK,
    generic_first,
    generic_hermite,
)
from uio_ring.ring._kernel_basis import (
    SWELL_MAX_UNKNOWNS,
    TOEPLITZ_MIN_ROWS,
    KernelSolution,
    generic_kernel_and_solution,
    kernel_and_solution,
    popov_left_kernel,
)
from uio_ring.ring._predicates import (
    coprime_maximal_minors,
    det_raw,
    full_rank_at_zero,
    is_hermite_raw,
    is_unimodular_raw,
    lone_entry_column,
    rank_raw,
    unimodular_given_hermite,
)
from uio_ring.ring._reduce import degree_reduced
from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.matrix import PolyMatrix, require_matrix

__all__ = ["HermiteResult", "hermite", "is_hermite", "row_echelon", "reduce_transform"]


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
        """Exact certificate: ``U @ M == H``, U unimodular, H normalised.  When the first
        and the last hold, U's unimodularity follows from two small determinants
        (:func:`~uio_ring.ring._predicates.unimodular_given_hermite`) instead of det U."""
        res = self.U @ M - self.H
        exact, normalised = res.is_zero(), is_hermite(self.H)
        m = self.U.rows
        if exact and normalised and self.H.shape == M.shape and self.U.shape == (m, m):
            unimodular = unimodular_given_hermite(self.U._r, M._r, self.H._r, m, M.cols)
        else:
            unimodular = is_unimodular_raw(self.U._r, *self.U.shape)
        return Certificate(
            "Hermite form",
            [
                Check("U @ M == H", exact, None if exact else res, "U M = H"),
                Check("U unimodular", unimodular, None, "det U is a nonzero constant"),
                Check("H normalised", normalised, None, "normalised row Hermite form"),
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
    When M's rows, permuted, are a row echelon form (triangular M, a cascade's block
    rows), the permutation and the normalisation alone (:func:`_hermite_of_echelon`).
    Square nonsingular matrices of size ≥ ``GENERIC_MIN_SIZE`` whose row degrees add
    up to more than ``deg det`` are first reduced to weak Popov form ``W·M``
    (:mod:`uio_ring.ring._reduce`).  They then try the certified
    evaluation/interpolation path of :mod:`uio_ring.ring._generic` (generic
    shape ``[[I, h], [0, det]]``, adj M interpolated, ``U = H·adj M / det``;
    O(n⁴·deg) rational operations in C).  Smaller square matrices of high degree
    (from 3×3, ``n³·deg ≥ GENERIC_MIN_WORK``: 4×4 from degree 6) take the same two paths
    when the elimination below outgrows its cap (``ELIMINATION_BITS``): a 5×5 of degree 32
    with entries in [−3, 3], 0.15 s against 11.5 s for the elimination.  Unless at most
    two rows are of high degree (:func:`few_high_rows`, row degrees such as 0, 1, 4, 16,
    32; from 3 rows on, below ``GENERIC_MIN_SIZE`` or not): then the elimination runs
    under a cap of U's own size (:func:`unbalanced_cap`; 7 ms against 22 ms by
    evaluation).  A very sparse M (δI − A with A sparse, :func:`_very_sparse`) tries the
    capped elimination first too.  Wide M of full
    row rank (at least ``WIDE_BLOCK_MIN_ROWS`` rows, rows·δ-degree ≥
    ``WIDE_BLOCK_MIN_DEGREES``): the Hermite form of the square block of its pivot
    columns, read at a point and checked, gives U and ``H = U·M``
    (:func:`_hermite_by_pivot_block`).  A tall, dense M of δ-degree ≥ ``CAP_MIN_DEGREE``
    (:func:`guess_first`) first guesses the generic minimal indices of its kernel: when
    one square Toeplitz system certifies them, ``H = [I; 0]`` and U comes from it
    (:func:`~uio_ring.ring._kernel_basis.generic_kernel_and_solution`).  When
    ``rank M < rows`` (tall or rank-deficient M)
    and M has at least ``TOEPLITZ_MIN_ROWS`` rows or a δ-degree above
    ``ELIMINATION_MAX_DEGREE``: the elimination below while its coefficients stay small
    (low degree only); else, when ``H = [I; 0]`` (two compressed maximal minors coprime),
    ``U = [X; K]`` with K the Popov kernel basis from one block-Toeplitz nullspace and X
    the solution of ``X·M = I`` reduced modulo K, from one square Toeplitz system
    (:mod:`uio_ring.ring._kernel_basis`; minimal bases as reduced Gröbner bases, Forney
    1975; O(N³) word operations per prime with N = rows·(max minimal index + 1)); when H
    has pivots of positive degree (singular or rank-deficient M): of δ-degree ≤
    ``ELIMINATION_MAX_DEGREE``, the elimination below with only a guard against runaway
    growth (``FULL_ELIMINATION_BITS``), else M's weak Popov form with its transform,
    ``W·M = [R; 0]``, and the Hermite form of R (:func:`_hermite_by_weak_popov`; a
    singular 16×16 of degree 16: 13 s, against over five minutes for the elimination).
    Square nonsingular M of at
    most ``PAIRWISE_MAX_ROWS`` rows whose constant term M(0) is nonsingular: pairwise
    extended-gcd steps (as SageMath does; U is unique there).
    Otherwise (and as the fallback): Euclidean elimination column by column with
    least-degree pivots and an extended-gcd step when two rows are left
    (:func:`~uio_ring.ring._echelon.row_echelon`; python-flint's ``xgcd``, by certified
    Chinese remaindering from degree 48 on, :mod:`uio_ring.ring._xgcd`), normalisation
    of the pivots, and a Popov reduction of the kernel part of U (Mulders & Storjohann
    2003; one-step Popov division, :mod:`uio_ring.ring._division`; with fewer than
    ``TOEPLITZ_MIN_ROWS`` rows, of U's own kernel rows).  For M of at least
    ``INTEGRAL_MIN_ENTRIES`` entries the elimination and the normalisation
    run fraction free over Z[δ], each row scaled by a constant where a quotient or
    a cofactor has a denominator, with the transform's rows packed
    (:mod:`uio_ring.ring._integral`): the same steps with the same exact result.

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
    m, n = M.shape
    zero_columns = _zero_columns(M)
    if zero_columns and len(zero_columns) < n:
        return _with_zero_columns(hermite(_without_columns(M, zero_columns)), zero_columns, n)
    order = _echelon_order(M._r)
    if order is not None:
        return _hermite_of_echelon(M, order)
    singular = False
    generic = m == n and generic_first(M._r, n)
    if generic and few_high_rows(M._r):
        small = _hermite_of_unbalanced_rows(M)
        if small is not None:
            return small
    if generic and n >= GENERIC_MIN_SIZE and _very_sparse(M._r, n):
        small = _hermite_by_small_elimination(M, capped=True)
        if small is not None:
            return small
    if generic and n >= GENERIC_MIN_SIZE:
        got, singular = _hermite_square_generic(M)
        if got is not None:
            return got
    if 0 < m < n and m >= WIDE_BLOCK_MIN_ROWS and m * dn.mat_degree(M._r) >= WIDE_BLOCK_MIN_DEGREES:
        wide = _hermite_by_pivot_block(M)
        if wide is not None:
            return wide
    guessed = guess_first(M)
    quick = guessed_kernel_and_inverse(M) if guessed else None
    if quick is not None:
        return _identity_on_top(M, quick)
    few_rows = 0 < m < TOEPLITZ_MIN_ROWS
    if few_rows:
        # pairwise xgcd steps when U is unique (square, nonsingular: proved by M(0)), and
        # no cap then (there is no other path) unless the generic path is worth a try
        # (small and of high degree); no cap on two rows either (one extended gcd, whose
        # cofactors are what they are: a 2×5 of degree 48, 1.35 → 0.70 ms, SageMath 0.59
        # ms); else the cap of high degrees
        pairwise = m == n <= PAIRWISE_MAX_ROWS and full_rank_at_zero(M._r, m, n)
        capped = True if generic else (False if pairwise or m <= 2 else None)
        small = _hermite_by_small_elimination(M, xgcd_rows=m if pairwise else 2, capped=capped)
        if small is not None:
            return small
        if generic:  # the elimination swelled: evaluation and interpolation, else no cap
            got, singular = _hermite_square_generic(M)
            if got is not None:
                return got
            if pairwise:
                small = _hermite_by_small_elimination(M, xgcd_rows=m, capped=False)
                if small is not None:
                    return small
    if m > 0:
        fast = _hermite_of_dependent_rows(M, singular=singular, min_rows=0 if few_rows else None,
                                          eliminate_first=not few_rows, guess=not guessed)
        if fast is not None:
            return fast
    return hermite_by_elimination(M)


@dataclass(frozen=True)
class EchelonOrder:
    """A row order that puts M in row echelon form (:func:`_echelon_order`)."""

    rows: list[int]  #: the nonzero rows by the column of their first nonzero entry, then the zero rows
    pivots: list[int]  #: that column, for each nonzero row in that order


def _echelon_order(a: dn.Rows) -> EchelonOrder | None:
    """The order of the rows of ``a`` that is a row echelon form, or None when two
    nonzero rows start in the same column.  Triangular matrices and their row
    permutations have one (a triangular pencil ``δI − A``, a cascade of subsystems).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> _echelon_order(PolyMatrix([[0, "d", 1], [0, 0, 0], ["d", 1, 0]])._r)
    EchelonOrder(rows=[2, 0, 1], pivots=[0, 1])
    >>> _echelon_order(PolyMatrix([["d", 1], [1, 0]])._r) is None
    True
    """
    first: dict[int, int] = {}  # column of the first nonzero entry → row
    zero = []
    for i, row in enumerate(a):
        for j, x in enumerate(row):
            if x:
                if j in first:
                    return None
                first[j] = i
                break
        else:
            zero.append(i)
    pivots = sorted(first)
    return EchelonOrder([first[j] for j in pivots] + zero, pivots)


def _triangular_order(M: PolyMatrix) -> EchelonOrder | None:
    """The :func:`_echelon_order` of a square M whose rows, permuted, are upper
    triangular with a nonzero diagonal (M nonsingular) and which is not its own Hermite
    form; else None."""
    n = M.rows
    if n == 0 or M.cols != n:
        return None
    order = _echelon_order(M._r)
    if order is None or len(order.pivots) < n or is_hermite_raw(M._r, n):
        return None
    return order


def hermite_of_triangular(M: PolyMatrix) -> HermiteResult | None:
    """:func:`hermite` of a square M whose rows, permuted, are upper triangular with a
    nonzero diagonal, when M is not its own Hermite form; else None.  For the Smith form
    and the invariant factors, which are those of H: H's entries above the diagonal are
    reduced below it, where the paths for general M first spend their work (upper
    triangular 24×24 of degree 2, diagonal δ, δ + 1: invariant factors 10.7 s from M,
    0.05 s from H).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> r = hermite_of_triangular(PolyMatrix([[0, "d + 1"], ["2*d", "d**2"]]))
    >>> r.H
    PolyMatrix([[d, 1/2], [0, d + 1]])
    >>> hermite_of_triangular(r.H) is None
    True
    """
    order = _triangular_order(M)
    return None if order is None else _hermite_of_echelon(M, order)


def triangular_hermite_form(M: PolyMatrix) -> PolyMatrix | None:
    """H of :func:`hermite_of_triangular`, without the transform."""
    order = _triangular_order(M)
    return None if order is None else PolyMatrix._new(_normalised(M, order, None), M.rows, M.cols, M.var)


def _normalised(M: PolyMatrix, order: EchelonOrder, u: dn.Rows | None) -> dn.Rows:
    """The rows of M in ``order``, normalised (monic pivots, entries above them reduced;
    :func:`~uio_ring.ring._echelon.normalise`, O(r²) row operations, mirrored on ``u``)."""
    a = [list(M._r[i]) for i in order.rows]
    normalise(a, u, order.pivots)
    return a


def _hermite_of_echelon(M: PolyMatrix, order: EchelonOrder) -> HermiteResult:
    """Hermite form with U of an M whose rows, in ``order``, are a row echelon form
    (:func:`_echelon_order`): the permutation, then the normalisation.  The nonzero rows
    are independent (distinct pivot columns), so the left kernel is spanned by the unit
    rows e_z of the zero rows z: its Popov basis, in that order, and the top rows of U,
    combinations of the nonzero rows only, are zero in those columns — reduced modulo it.
    So H and U are those of every other path.  An upper triangular 16×16 of degree 2
    (diagonal δ, δ + 1): 0.4 ms, against 77 ms by evaluation and interpolation (SageMath:
    0.9 ms).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([[0, "d + 1"], ["2*d", "d**2"]])
    >>> r = _hermite_of_echelon(M, _echelon_order(M._r))
    >>> r.H, r.U @ M == r.H
    (PolyMatrix([[d, 1/2], [0, d + 1]]), True)
    """
    m, n = M.shape
    z, one = bk.ZERO, bk.ONE
    u = [[one if c == i else z for c in range(m)] for i in order.rows]
    H = _normalised(M, order, u)
    return HermiteResult(
        H=PolyMatrix._new(H, m, n, M.var),
        U=PolyMatrix._new(u, m, m, M.var),
        rank=len(order.pivots),
        pivots=tuple(order.pivots),
    )


def _hermite_square_generic(M: PolyMatrix) -> tuple[HermiteResult | None, bool]:
    """The square paths by evaluation and interpolation: ``(result or None, M singular)``.

    A nonsingular M whose row degrees add up to more than ``deg det`` is first reduced
    to weak Popov form ``W·M`` (then ``U = U_R·W``); otherwise the certified generic
    Hermite form (:func:`~uio_ring.ring._generic.generic_hermite`), or None."""
    n, var = M.rows, M.var
    det = det_raw(M._r, n)
    if det.is_zero():
        return None, True
    reduced = degree_reduced(M._r, n, track=True, det=det)
    if reduced is not None:  # H(M) = H(W M) and U = U_R W
        R, W = reduced
        res = hermite(PolyMatrix._new(R, n, n, var))
        return HermiteResult(res.H, res.U @ PolyMatrix._new(W or [], n, n, var), res.rank, res.pivots), False
    got = generic_hermite(M._r, n)
    if got is None:
        return None, False
    H, U, _ = got
    return HermiteResult(
        H=PolyMatrix._new(H, n, n, var), U=PolyMatrix._new(U, n, n, var), rank=n, pivots=tuple(range(n))
    ), False


#: Wide M (rows < columns) of full row rank go through the square block of their pivot
#: columns (:func:`_hermite_by_pivot_block`) from ``WIDE_BLOCK_MIN_ROWS`` rows and
#: rows·δ-degree ``≥ WIDE_BLOCK_MIN_DEGREES`` on.  Measured against the elimination on
#: random m×n with coefficients in [−3, 3] (ms, elimination / block): 6×7 of degree 2,
#: 1.3 / 1.6, of degree 4, 6.3 / 4.4, of degree 8, 66 / 20; 8×9 of degree 1, 1.7 / 1.9, of
#: degree 2, 6.0 / 4.6, of degree 8, 869 / 98; 12×13 of degree 4, 1150 / 204.  With fewer
#: rows the block is a small square of high degree (its own capped elimination, then the
#: evaluation path): 5×6 of degree 8, 16 / 6; of degree 24, 1268 / 73; of degree 40,
#: 21 000 / 300; 4×5 of degree 4, 0.4 / 0.4; 3×10 of degree 8, 1.0 / 0.5; 3×4 of degree 40,
#: 158 / 25.  At 2 rows the pairwise extended gcd is as fast.
WIDE_BLOCK_MIN_DEGREES = 16
WIDE_BLOCK_MIN_ROWS = 3


def _hermite_by_pivot_block(M: PolyMatrix, tries: int = 3) -> HermiteResult | None:
    """Hermite form of a wide M (m < n) of full row rank through the square block of its
    pivot columns, or None.

    The pivot columns J are read from the rank profile of M(x) at the first of the points
    0, 1, −1, … (``tries`` of them, :func:`~uio_ring.ring._evaluation.points`; exact
    rational rows) where M(x) has rank m.  The block ``M_J`` is then nonsingular; its Hermite form
    ``U·M_J = H_J`` (a square path of :func:`hermite`, fast by evaluation and
    interpolation) gives ``H = U·M``, which is M's Hermite form exactly when every row i
    of H is zero before column ``J[i]`` — checked here (a point where a column drops into
    the span of the earlier ones would give a J that is not M's; then None).  U is unique
    (M has full row rank), so the result is the elimination's.  Measured on the wide 7×8
    of δ-degree 16 whose Hermite form is C̄ in Zheng et al.'s step 3 (a random 8-state
    spec with 7 outputs): 0.25 s against 7.0 s for the elimination, whose remainders swell
    to 4.3-kbit coefficients before the reduction.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([["d", 1, 0, 1], [1, "d", 1, 0], [0, 1, "d", 1]])
    >>> r = _hermite_by_pivot_block(M)
    >>> r.pivots, r.H == hermite_by_elimination(M).H, r.U @ M == r.H
    ((0, 1, 2), True, True)
    """
    m, n = M.shape
    coeffs = ev.coefficient_mats(M._r, m, n)
    for x in ev.first_points(tries):
        rref, rank = ev.evaluate(coeffs, x).rref()
        if rank == m:
            break
    else:
        return None
    J = [next(j for j in range(n) if rref[i, j] != 0) for i in range(m)]
    block = hermite(PolyMatrix._new([[row[j] for j in J] for row in M._r], m, m, M.var))
    # H's columns J are the block's Hermite form: only the others need the product U·M
    # (a 15×16 of degree 16 with U of degree ~240: 26 s for every column, 1.7 s for one)
    chosen = set(J)
    rest = [j for j in range(n) if j not in chosen]
    other = dn.matmul(block.U._r, [[row[j] for j in rest] for row in M._r], m, m, len(rest))
    H = [[bk.ZERO] * n for _ in range(m)]
    for i in range(m):
        for k, j in enumerate(J):
            H[i][j] = block.H._r[i][k]
        for k, j in enumerate(rest):
            H[i][j] = other[i][k]
    if any(H[i][j] for i in range(m) for j in range(J[i])):
        return None
    return HermiteResult(PolyMatrix._new(H, m, n, M.var), block.U, m, tuple(J))


def _zero_columns(M: PolyMatrix) -> list[int]:
    """The columns of M that are zero."""
    return [j for j, column in enumerate(zip(*M._r, strict=True)) if not any(column)]  # zip: 3× faster at 4×4


def _without_columns(M: PolyMatrix, drop: list[int]) -> PolyMatrix:
    """M without the columns ``drop``."""
    gone = set(drop)
    keep = [j for j in range(M.cols) if j not in gone]
    return PolyMatrix._new([[row[j] for j in keep] for row in M._r], M.rows, len(keep), M.var)


def _with_zero_columns(res: HermiteResult, zero_columns: list[int], n: int) -> HermiteResult:
    """The Hermite form of M from that of M without its zero columns: row operations leave
    a zero column zero, so H gets them back and U, the rank and the row relations (hence
    the Popov kernel rows of U and the rows reduced modulo them) are those of M.  The
    elimination of a tall rank-deficient M can swell on columns it cannot use: the
    matching matrix ``[[CB, D], [D, 0]]`` of an 8-state system with 8 outputs, D = 0 and
    δ-degree 16 (16×8, four zero columns, degree 32): 114 s, against 0.5 s without them."""
    keep, place = _places(zero_columns, n)
    H = PolyMatrix._new(_spread(res.H._r, place), res.H.rows, n, res.H.var)
    return HermiteResult(H, res.U, res.rank, tuple(keep[j] for j in res.pivots))


def _places(gaps: list[int], n: int) -> tuple[list[int], list[int]]:
    """``(keep, place)`` for n positions of which ``gaps`` are left out: the kept
    positions in order, and for each position its index among them (−1 for a gap)."""
    gone = set(gaps)
    keep = [j for j in range(n) if j not in gone]
    place = [-1] * n
    for k, j in enumerate(keep):
        place[j] = k
    return keep, place


def _spread(rows: dn.Rows, place: list[int]) -> dn.Rows:
    """Rows whose entry j is entry ``place[j]`` of the given row, zero where it is −1."""
    z = bk.ZERO
    return [[row[k] if k >= 0 else z for k in place] for row in rows]


#: Square matrices of at most this many rows, when M(0) is nonsingular, are eliminated
#: with pairwise extended-gcd steps (``row_echelon(xgcd_rows=n)``; random and Smith-family
#: 3×3 … 5×5: 0.7–0.95× the time of remainder passes; 8×8: 2–3× slower).
PAIRWISE_MAX_ROWS = 5


def _hermite_of_dependent_rows(
    M: PolyMatrix, *, min_rows: int | None = None, singular: bool = False, eliminate_first: bool = True,
    guess: bool = True,
) -> HermiteResult | None:
    """Hermite form with U for ``rank M < rows`` (tall or rank-deficient M), or None.

    When M has full column rank and two compressed maximal minors are coprime, ``H =
    [I; 0]`` and ``U = [X; K]``: K the Popov basis of the left kernel (one block-Toeplitz
    nullspace), X the solution of ``X·M = I`` reduced modulo K (one square Toeplitz
    system; :func:`~uio_ring.ring._kernel_basis.solve_reduced`).  U is unimodular: for
    any unimodular ``U0 = [X0; K0]`` with ``U0·M = H``, ``X − X0`` lies in the kernel
    (``= Y·K``) and ``K0 = Z·K`` with Z unimodular, so ``U = [[I, Y·Z⁻¹], [0, Z⁻¹]]·U0``.
    ``X·M = I`` and ``K·M = 0`` are checked exactly inside; None when a Toeplitz system
    would be too large.  (Tall M first try the elimination under the tight cap, unless
    ``eliminate_first=False``: the caller has seen it stop already; ``guess=False``: the
    caller has seen the generic guess refused, :func:`guessed_kernel_and_inverse`.)

    Otherwise H has pivots of positive degree: the Euclidean elimination with transform
    (δ-degree ≤ ``ELIMINATION_MAX_DEGREE``, under the guard ``FULL_ELIMINATION_BITS``),
    else U from M's weak Popov transform and the Hermite form of its nonzero rows
    (:func:`_hermite_by_weak_popov`), which is faster than the Toeplitz systems there
    (singular 8×8 … 16×16 of degree 4 … 16, one or two kernel rows: 1–150× against
    0.9× at worst; the Toeplitz X does not exist below its size bound when H has a pivot
    of high degree).

    None when M has fewer than ``min_rows`` rows (default ``TOEPLITZ_MIN_ROWS``).
    ``singular``: the caller has proved M square and singular (its rank is then not
    computed: it is < rows and < columns).
    """
    m, n = M.shape
    a = M._r
    if m < (TOEPLITZ_MIN_ROWS if min_rows is None else min_rows):
        return None
    # rank M < rows is certain when M is singular or tall (rank ≤ columns < rows)
    r = -1 if singular or m > n else rank_raw(a, m, n)
    if r == m:
        return None
    # H = [I; 0] needs rank n and no column whose lone entry divides every maximal minor:
    # a singular or rank-deficient M, or one with such a column (sparse: a 10×9 of degree 8,
    # 22 → 17 ms), goes straight to the elimination with transform (below); a tall one
    # tries it under the tight cap first
    top_identity_possible = not singular and (r == -1 or r == n) and not lone_entry_column(a, m, n)
    if top_identity_possible and eliminate_first:
        small = _hermite_by_small_elimination(M)
        if small is not None:
            return small
    if top_identity_possible and r == -1:
        r = rank_raw(a, m, n)
    if not (top_identity_possible and r == n and coprime_maximal_minors(a, m, n, routing=True)):
        # H has pivots of positive degree: eliminating for H costs most of what the
        # transform does; the elimination with transform while it stays small, else the
        # weak Popov transform
        if dn.mat_degree(a) <= ELIMINATION_MAX_DEGREE:
            got = _hermite_by_small_elimination(M, full=True)
            if got is not None:
                return got
        return _hermite_by_weak_popov(M)
    # the minors are coprime and the capped elimination gave way (or was not worth it):
    # the larger cap, as the elimination that is left swells
    both = kernel_and_solution(a, m, n, dn.identity(n), min_rows=0, max_unknowns=SWELL_MAX_UNKNOWNS,
                               guess=guess)
    if both is None or both.solution is None:
        return None
    return _identity_on_top(M, both)


def _identity_on_top(M: PolyMatrix, both: KernelSolution) -> HermiteResult:
    """``H = [I; 0]`` and ``U = [X; K]`` of a tall M from its Popov kernel K and the
    solution X of ``X·M = I`` reduced modulo K (``both``; unimodular, as
    :func:`_hermite_of_dependent_rows` shows)."""
    m, n = M.shape
    assert both.solution is not None
    return HermiteResult(
        H=PolyMatrix._new(dn.identity(n) + dn.zeros(m - n, n), m, n, M.var),
        U=PolyMatrix._new(both.solution + both.kernel, m, m, M.var),
        rank=n,
        pivots=tuple(range(n)),
    )


#: :func:`guess_first` only while the guessed square system has at most this many
#: unknowns m·(D + 1) (a 4×2 of degree 32: 132; 6×4 of degree 16: 198): beyond, the
#: capped elimination is tried first, as it is cheap whenever it does not swell.
GUESS_FIRST_MAX_UNKNOWNS = 256


def guessed_kernel_and_inverse(M: PolyMatrix) -> KernelSolution | None:
    """The Popov kernel of a tall M and its left inverse reduced modulo it, by the generic
    guess alone (:func:`~uio_ring.ring._kernel_basis.generic_kernel_and_solution`), or None
    when the guess is refused.  For an M where :func:`guess_first` holds (its callers ask
    it once, and pass on whether the guess was tried); the solution is never None.

    >>> M = PolyMatrix([["(d + 1)**8"], ["(d - 1)**8"], ["d**8 + 3*d - 1"]])
    >>> got = guessed_kernel_and_inverse(M)
    >>> [dn.row_degree(r) for r in got.kernel], PolyMatrix._new(got.solution, 1, 3, "d") @ M
    ([4, 4], PolyMatrix([[1]]))
    """
    m, n = M.shape
    return generic_kernel_and_solution(M._r, m, n, dn.identity(n), max_unknowns=GUESS_FIRST_MAX_UNKNOWNS)


def guess_first(M: PolyMatrix) -> bool:
    """Whether a tall M tries the generic guess of its kernel and left inverse
    (:func:`~uio_ring.ring._kernel_basis.generic_kernel_and_solution`, with
    ``max_unknowns=GUESS_FIRST_MAX_UNKNOWNS``) before the capped elimination: at least
    two rows more than columns, δ-degree ≥ ``CAP_MIN_DEGREE`` and dense entries, where
    the elimination swells to its cap and the coprimality test of the minors only routes
    to the same Toeplitz system (4×2 of degree 16: 0.19 of 2.4 ms; 6×1 of degree 16:
    0.17 of 0.54 ms).  Sparse entries keep the elimination cheap and the guess often
    wrong: ``[δ¹⁶ + 1; δ¹⁶ + 2; δ³]`` takes 48 µs by the usual order, 147 µs with a
    refused guess first.  Dense: at least half of the coefficients of degree 1, ⌊deg/2⌋
    and deg − 1 of the entries are nonzero (a sample: reading every coefficient costs
    5 µs on a 3×1 of degree 16).

    >>> guess_first(PolyMatrix([["(d + 1)**8"], ["(d - 1)**8"], ["d**8 + 3*d - 1"]]))
    True
    >>> guess_first(PolyMatrix([["d**8"], ["d + 1"], ["1"]]))      # sparse
    False
    """
    m, n = M.shape
    # D ≥ n·dm / (m − n) with dm ≥ CAP_MIN_DEGREE: beyond the cap whatever the entries
    # (a 10×8: no scan of its 80 entries, 1 % of its elimination)
    if m < n + 2 or m * (CAP_MIN_DEGREE * n // (m - n) + 1) > GUESS_FIRST_MAX_UNKNOWNS:
        return False
    dm = dn.mat_degree(M._r)
    if dm < CAP_MIN_DEGREE:
        return False
    nonzero = 0
    for row in M._r:
        for x in row:
            d = x.degree()
            if d >= 2:
                nonzero += (x[1] != 0) + (x[d // 2] != 0) + (x[d - 1] != 0)
    return 2 * nonzero >= 3 * m * n


def _hermite_by_weak_popov(M: PolyMatrix) -> HermiteResult:
    """Hermite form with U of M from its weak Popov form with the transform (Mulders &
    Storjohann 2003: leading terms cancelled, so degrees only fall; O(r·deg²) row
    operations): ``W·M = [R; 0]`` with W unimodular and R of full row rank r, which spans
    M's row module, so ``H = [H_R; 0]`` for the Hermite form ``U_R·R = H_R`` (R square
    nonsingular or wide: the paths by evaluation), and ``U = [U_R·W_top; W_bot]`` is
    unimodular with ``U·M = H``; its last rows span the left kernel (any v with ``v·M = 0``
    is ``c·W`` with ``c_top·R = 0``, so ``c_top = 0``).  The kernel rows are then put in
    Popov form and the top rows reduced modulo them (:func:`reduce_transform`).

    A Euclidean elimination of M itself builds Bézout cofactors whose coefficients swell
    with the degree: a 4×3 of degree 72 (rows of degree 8, 8, 72, 72, pivots of degree 0,
    0, 48; the transposed core of a Smith form) took 260 s, against 8 ms for H here; a
    singular 16×16 of degree 16 (entries in [−3, 3], one row the sum of two others) over
    five minutes, against 13 s here.  The Toeplitz kernel and solve of
    :func:`_hermite_of_dependent_rows` are slower there, or refuse: X has degree 224.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([["d", 1], ["d**2", "d"], [1, 0]])
    >>> r = _hermite_by_weak_popov(M)
    >>> r.H, r.U @ M == r.H, r.U[2, :]
    (PolyMatrix([[1, 0], [0, 1], [0, 0]]), True, PolyMatrix([[d, -1, 0]]))
    """
    m, n = M.shape
    a = dn.copy(M._r)
    w = dn.identity(m)
    r = len(dn.weak_popov(a, w))
    reduced = hermite(PolyMatrix._new(a[:r], r, n, M.var))
    u = dn.matmul(reduced.U._r, w[:r], r, r, m) + w[r:]
    reduce_transform(u, r)
    H = reduced.H._r + dn.zeros(m - r, n)
    return HermiteResult(
        H=PolyMatrix._new(H, m, n, M.var),
        U=PolyMatrix._new(u, m, m, M.var),
        rank=r,
        pivots=reduced.pivots,
    )


#: Elimination first for tall / rank-deficient M while its coefficients stay within
#: ``ELIMINATION_BITS + 4·(bits of M)`` bits (see :func:`_hermite_by_small_elimination`);
#: the same cap lets small square matrices of high degree leave the elimination (hermite,
#: smith, invariant_factors).
ELIMINATION_BITS = 64


def elimination_cap(rows: dn.Rows, base: int = ELIMINATION_BITS) -> int:
    """The bit cap of an elimination that gives way to a better path once it swells:
    ``base + 4·max_bits(rows)``, relative to the input's own coefficients."""
    return base + 4 * max_bits(rows)


#: The uncapped elimination with transform for H ≠ [I; 0] only up to this δ-degree of M
#: (remainder sequences of higher degree can swell over Q: a 5×4 of degree 32 in a
#: W-step of ``uio-ring check``, 28 s against 1.9 s for the Toeplitz systems).
ELIMINATION_MAX_DEGREE = 8
#: From this δ-degree of M on the cap applies whatever the number of entries (the same
#: 5×4 stops in its first column; a 3×2 of degree 127 of the observability algorithm
#: stays small and finishes in 1 ms, where the Toeplitz systems take seconds).
CAP_MIN_DEGREE = 8


#: :func:`unbalanced_cap`: bits per unit of ``Σ row degrees`` and of ``bits + log₂ n + 1``.
UNBALANCED_CAP_FACTOR = 16
#: :func:`few_high_rows` only for coefficients of at most this many bits (as measured).
UNBALANCED_MAX_BITS = 64


def few_high_rows(rows: dn.Rows) -> bool:
    """Whether at most two rows of M have a degree above a third of the greatest (row
    degrees such as 0, 1, 4, 16, 32 or 0, 8, 16, 24 or 3, 3, 3, 40).

    Then the Euclidean elimination with least-degree pivots clears the columns with the
    low rows, whose quotients do not swell, and only the last two rows meet in one
    extended gcd: its coefficients peaked at 1.0–2.5× the bits of U on such matrices,
    and at up to 7.7× with three rows or more of high degree.  For a square M of 3 to 5 rows
    (random entries in [−3, 3]; generic path / elimination, ms): row degrees 0, 1, 4,
    16, 32: 22 / 7.4; 3, 3, 3, 40: 20 / 5.2; 0, 0, 6, 32: 11 / 0.7; 2, 3, 4, 32, 32:
    55 / 59 (the worst seen); 0, 8, 16, 24: 11 / 3.1; but 1, 6, 12, 32, 32: 56 / 149
    and 8, 8, 8, 8, 8: 10 / 44.
    The other rows must be a block the elimination handles itself (``len³ · degree <
    GENERIC_MIN_WORK``, :func:`~uio_ring.ring._generic.generic_first`): three rows of
    degree 32 under two of degree 128 swell as a balanced 3×3 of degree 32 does (25 ms
    by the generic path, 51 ms by elimination).  That condition also bounds the size:
    the rule without it took 4.2 s by elimination against 0.19 s by the generic path on
    row degrees 1, 2, 3, 4, 4, 5, 5, 8, 15, 32; with it, 6×6 and 7×7 matrices pass when
    their other rows have degree ≤ 2 (2, 2, 2, 2, 2, 30: 7.2 against 20 ms; the worst
    seen, 1, 1, 2, 2, 2, 8, 8: 10 against 8.4 ms).  U is unique (M square and
    nonsingular), so the choice changes no result.  Only for coefficients of at most
    ``UNBALANCED_MAX_BITS`` bits, where it was measured: the weak Popov form of the
    bench's sparse 10×10 (row degrees 8, 8, 39, 16, 709-bit coefficients) met one
    extended gcd of 150 kbit cofactors, 4.4 s, against 0.34 s by the generic path.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([[1, 2, 0], ["d**16", 1, "d"], ["d**32", "d", 1]])
    >>> few_high_rows(M._r), few_high_rows((M + PolyMatrix([["d**12"] * 3] * 3))._r)
    (True, False)
    """
    degrees = sorted((dn.row_degree(row) for row in rows), reverse=True)
    high = sum(3 * d > degrees[0] for d in degrees)
    rest = degrees[high:]
    # and the low rows are themselves a block the elimination handles (generic_first);
    # the bits last: a pass over every coefficient, where most matrices fail on degrees
    return (high <= 2 and (not rest or len(rest) ** 3 * rest[0] < GENERIC_MIN_WORK)
            and max_bits(rows) <= UNBALANCED_MAX_BITS)


#: :func:`_very_sparse`: at most this many nonzero entries per row, on average.
SPARSE_ENTRIES_PER_ROW = 3


def _very_sparse(a: dn.Rows, n: int) -> bool:
    """Whether the square n×n M has at most ``SPARSE_ENTRIES_PER_ROW·n`` nonzero entries
    (δI − A with A sparse): its elimination under the usual cap
    (:func:`_hermite_by_small_elimination`) goes before the generic path, which
    interpolates a dense adj M whatever the zeros.  A diagonal of degree 1 to 4 and one
    or two other entries per row (ms, generic / elimination first): 8×8 0.82 / 0.12 and
    3.0 / 0.29, 12×12 of degree 2 3.5 / 1.1, 16×16 of degree 1 3.6 / 1.7; a 12×12 with
    32 entries of degree ≤ 1, 2.3 / 0.9 (SageMath 2.4).  When the cap stops the
    elimination (larger, or of higher degree) it costs 1–8 % more (12×12 of degree 4,
    28.9 / 30.6 ms).  With more entries it stopped on its cap more often than it won
    (3.3 a row, 16×16: 6.5 / 8.9 ms).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> _very_sparse(PolyMatrix.diag("d", "d + 1", "d - 2", "d")._r, 4), _very_sparse(PolyMatrix([["d"] * 4] * 4)._r, 4)
    (True, False)
    """
    return sum(1 for row in a for x in row if not x.is_zero()) <= SPARSE_ENTRIES_PER_ROW * n


def _hermite_of_unbalanced_rows(M: PolyMatrix) -> HermiteResult | None:
    """Hermite form with U of a square M with :func:`few_high_rows`, by the elimination
    under :func:`unbalanced_cap` (None when it swells past it): pairwise extended-gcd
    steps when M(0) is nonsingular, as SageMath's Euclidean Hermite form does (row
    degrees 2, 2, 2, 2, 2, 30: 7.2 ms, against 18 ms with remainder passes and 20 ms by
    the generic path), else remainder passes.  Ties of least degree go to the least row
    degree: on row degrees 0, 1, 4, 16, 32 a row of degree 32 that won a tie on its
    smaller leading coefficient made the elimination 31 ms instead of 7.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([[1, 2, 0], ["d**16", 1, "d"], ["d**32 + 1", "d", 1]])
    >>> r = _hermite_of_unbalanced_rows(M)
    >>> r.U @ M == r.H, r.H[2, 2] == M.det().monic()
    (True, True)
    """
    n = M.rows
    pairwise = full_rank_at_zero(M._r, n, n)
    return _hermite_by_small_elimination(M, xgcd_rows=n if pairwise else 2, capped=True, base_bits=unbalanced_cap(M._r),
                                         lead_ties=False)


def unbalanced_cap(rows: dn.Rows) -> int:
    """The bit cap, above M's own bits (:func:`elimination_cap`), of the elimination of a
    square M with :func:`few_high_rows`: ``UNBALANCED_CAP_FACTOR · Σ row degrees ·
    (bits + log₂ n + 1)``.  The U of such an M has about 2–4 bits per unit of
    ``Σ row degrees · (bits + log₂ n + 1)`` (``Σ row degrees ≥ deg det``; row degrees
    0, 1, 4, 16, 32 and entries in [−3, 3]: 949 bits against 53·5.3), its elimination
    peaked at 1–2.5 times that: the cap is a guard against a swell this rule did not
    foresee, not the test that chooses the path."""
    total = sum(dn.row_degree(row) for row in rows)
    return UNBALANCED_CAP_FACTOR * total * (max_bits(rows) + len(rows).bit_length() + 1)


def _few_rows_of_high_degree(M: PolyMatrix) -> bool:
    """Fewer than ``TOEPLITZ_MIN_ROWS`` rows and δ-degree ≥ ``CAP_MIN_DEGREE``: the shape
    where a plain elimination can swell for seconds and the callers (kernel, solve) go
    through :func:`hermite` instead, whose capped elimination gives way to the Toeplitz
    systems."""
    return M.rows < TOEPLITZ_MIN_ROWS and dn.mat_degree(M._r) >= CAP_MIN_DEGREE


def kernel_of_few_rows(M: PolyMatrix) -> PolyMatrix:
    """The Popov basis of the left kernel of M with few rows and high degree
    (:func:`_few_rows_of_high_degree`): the kernel rows of :func:`hermite`'s transform,
    and when M has full column rank (and more than two rows) by the same steps without
    the top rows — the capped elimination first (a 3×2 of degree 127 of the observability
    algorithm: 1 ms, where the Toeplitz systems take seconds), then
    :func:`~uio_ring.ring._kernel_basis.popov_left_kernel` alone, without the reduced
    solution X of :func:`_hermite_of_dependent_rows` (4×2 of degree 16: 8.8 → 4.0 ms,
    before X shared the kernel's solve; one kernel row comes from the maximal minors:
    5×4 of degree 48, 3.7 s → 1.1 ms).  The basis is unique, so it is the same.  A
    rank-deficient M keeps :func:`hermite`, whose weak Popov path is faster there than
    the Toeplitz kernel (4×3 of rank 2 and degree 48: 32 against 37 ms).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([["d**8 + 1", "d"], ["d", "d**8 - 1"], [1, "d**9"]])
    >>> K = kernel_of_few_rows(M)
    >>> K.shape, (K @ M).is_zero()
    ((1, 3), True)
    """
    m, n = M.shape
    r = rank_raw(M._r, m, n)
    if r == m:
        return PolyMatrix._new([], 0, m, M.var)
    if r == n and m > 2:
        small = _hermite_by_small_elimination(M)
        if small is not None:
            return small.U[small.rank :, :]
        K = popov_left_kernel(M._r, m, n, min_rows=0)
        if K is not None:
            return PolyMatrix._new(K, len(K), m, M.var)
    h = hermite(M)
    return h.U[h.rank :, :]


#: The cap of the same elimination when H ≠ [I; 0] (singular or rank-deficient M, where
#: the other path is the weak Popov transform, :func:`_hermite_by_weak_popov`).  Measured
#: (s, cap 2¹⁴ / 2¹¹ / 2⁸ bits above M's own): singular 12×12 of degree 8, 2.70 / 0.37 /
#: 0.35; 16×16 of degree 4, 1.48 / 0.41 / 0.40; a product of 16×15 and 15×16 of degree 2,
#: 4.40 / 1.04 / 1.03; but the sparse 12×12 of bench_ring 0.28 / 0.28 / 0.92 and the
#: rank-deficient 12×12 0.023 / 0.023 / 0.033, whose eliminations pass 2⁸ bits and finish.
FULL_ELIMINATION_BITS = 1 << 11
#: Below this many entries of M the elimination runs without that cap: the cap only
#: chooses between two paths to the same H and U, and on so few columns its test costs
#: more than any swell it can stop (the 6×4 of Zheng et al.: 17 of 84 µs).
CAP_MIN_ENTRIES = 40


def _hermite_by_small_elimination(
    M: PolyMatrix, *, xgcd_rows: int = 2, full: bool = False,
    capped: bool | None = None, base_bits: int | None = None, lead_ties: bool = True,
) -> HermiteResult | None:
    """:func:`hermite_by_elimination` with the Popov kernel taken from U itself, or
    None as soon as a coefficient of the elimination exceeds ``ELIMINATION_BITS +
    4·max_bits(M)`` bits (no cap below ``CAP_MIN_ENTRIES`` entries and ``CAP_MIN_DEGREE``).
    Zero rows of M stay out of the elimination (:func:`_with_zero_rows`).

    When the Euclidean elimination keeps its coefficients small (a tall M made of
    columns of a unimodular matrix: 22×20 of degree 2 ends with 22-bit
    coefficients), its transform is cheap, and the Popov basis of the left kernel
    follows from its last ``rows − rank`` rows by weak Popov reduction
    (Mulders & Storjohann 2003) and normalisation (:func:`reduce_transform`; the
    division of the top rows goes through the elimination's own kernel rows when
    their coefficients are far smaller than those of the Popov basis);
    the elimination runs over Z[δ] when it stays integral (:func:`_echelon_integral`);
    the result is the same H and U as from the Toeplitz nullspace, which costs
    O(N³) word operations per prime whatever the coefficients (40× slower there).
    Generic tall matrices swell to thousands of bits within a few columns: the
    cap stops those early and the caller takes the Toeplitz path.  ``xgcd_rows``: see
    :func:`row_echelon` (the rational elimination only).  ``full``: the elimination for H ≠ [I; 0], under the runaway
    guard ``FULL_ELIMINATION_BITS`` instead of ``ELIMINATION_BITS``, and fraction free over
    Z[δ] (otherwise the integral elimination gives way to the rational one at the first
    row it would scale, whose cap stops a swelling elimination sooner).  ``capped``:
    whether the cap applies (default: from ``CAP_MIN_ENTRIES`` entries or
    ``CAP_MIN_DEGREE`` on; with ``full``, from ``CAP_MIN_ENTRIES`` nonzero-row entries).
    ``base_bits``: the cap's allowance above M's own bits, instead of ``ELIMINATION_BITS``
    (``FULL_ELIMINATION_BITS`` with ``full``).  ``lead_ties``: ties of least degree go to
    the smallest leading coefficient (``small_lead_ties`` of :func:`row_echelon`), else
    to the least row degree.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix([[1, "d"], [0, 1], ["d", "d**2 + 1"]])
    >>> r = _hermite_by_small_elimination(M)
    >>> r.H, r.U @ M == r.H, r.U[2, :]
    (PolyMatrix([[1, 0], [0, 1], [0, 0]]), True, PolyMatrix([[d, 1, -1]]))
    """
    m, n = M.shape
    zero_rows = [i for i, row in enumerate(M._r) if not any(row)]
    if zero_rows and len(zero_rows) < m:
        gone = set(zero_rows)
        kept = PolyMatrix._new([row for i, row in enumerate(M._r) if i not in gone], m - len(gone), n, M.var)
        if capped is None and not full:  # the path-choosing cap: from M's own shape
            capped = _capped(M)
        res = _hermite_by_small_elimination(kept, xgcd_rows=xgcd_rows, full=full, capped=capped, base_bits=base_bits,
                                            lead_ties=lead_ties)
        return None if res is None else _with_zero_rows(res, zero_rows, m)
    bits = base_bits if base_bits is not None else FULL_ELIMINATION_BITS if full else ELIMINATION_BITS
    if capped is None:
        # the runaway guard of the full elimination (δ-degree ≤ ELIMINATION_MAX_DEGREE)
        # by the number of entries only: the sparse 8×8 of bench_ring, its five nonzero
        # rows 5×7, 54 → 41 µs without it
        capped = m * n >= CAP_MIN_ENTRIES if full else _capped(M)
    try:
        got = _echelon_integral(M._r, m, n, bits if capped else None, scaling=full)
    except CoefficientGrowth:
        return None
    if got is not None:
        a, u, pivots = got
    else:
        cap = elimination_cap(M._r, bits) if capped else None
        a = dn.copy(M._r)
        u = dn.identity(m)
        try:
            pivots = row_echelon(a, u, m, n, bit_cap=cap, xgcd_rows=xgcd_rows, small_lead_ties=lead_ties)
        except CoefficientGrowth:
            return None
        normalise(a, u, pivots)
    reduce_transform(u, len(pivots))
    return HermiteResult(
        H=PolyMatrix._new(a, m, n, M.var),
        U=PolyMatrix._new(u, m, m, M.var),
        rank=len(pivots),
        pivots=tuple(pivots),
    )


def _capped(M: PolyMatrix) -> bool:
    """Whether the path-choosing cap of :func:`_hermite_by_small_elimination` applies: from
    ``CAP_MIN_ENTRIES`` entries or δ-degree ``CAP_MIN_DEGREE`` on."""
    return M.rows * M.cols >= CAP_MIN_ENTRIES or dn.mat_degree(M._r) >= CAP_MIN_DEGREE


def _with_zero_rows(res: HermiteResult, zero_rows: list[int], m: int) -> HermiteResult:
    """The Hermite form of M from that of M without its zero rows (``res``, of the other
    rows in their order): H gets zero rows at the bottom; the unit rows e_z of the zero
    rows z join the kernel rows of U, and the rows of U are spread over M's rows.  The
    result is the normalised one: the e_z are Popov rows of degree 0 whose columns are
    zero in every other row, so with the other kernel rows (zero in column z) they form
    the Popov basis of M's left kernel (sorted by pivot degree, then position, as
    :func:`~uio_ring.ring._dense.popov` sorts), and the top rows, zero in column z, are
    reduced modulo it.  The sparse 8×8 of ``bench_ring`` (three zero rows, one zero
    column) eliminates 5 rows instead of 8 and has no kernel left to normalise."""
    # column i of the new U: column place[i] of res.U, or zero (-1) for a zero row i
    u = _spread(res.U._r, _places(zero_rows, m)[1])
    r = res.rank
    z = bk.ZERO
    kernel = [[bk.ONE if c == i else z for c in range(m)] for i in zero_rows]  # sorted
    if r < len(u):
        kernel = sorted(u[r:] + kernel, key=dn.leading_position)
    n = res.H.cols
    H = res.H._r + dn.zeros(len(zero_rows), n)
    return HermiteResult(
        H=PolyMatrix._new(H, m, n, res.H.var),
        U=PolyMatrix._new(u[:r] + kernel, m, m, res.U.var),
        rank=r,
        pivots=res.pivots,
    )

#: The integral elimination from this many entries of M on (the 6×4 of Zheng et al.:
#: 0.096 ms against 0.091 ms over Q; 10×8 columns of a unimodular matrix: 0.88 against
#: 0.96 ms; 22×20: 5.9 against 7.4 ms for the elimination and the normalisation).
INTEGRAL_MIN_ENTRIES = 60


def _echelon_integral(
    a: dn.Rows, m: int, n: int, cap_bits: int | None, scaling: bool = True
) -> tuple[dn.Rows, dn.Rows, list[int]] | None:
    """:func:`row_echelon` with transform and :func:`normalise` of the m×n rows ``a``
    fraction free over Z[δ] (:mod:`uio_ring.ring._integral`: the same steps with each row
    scaled by a constant, and the same exact result — up to a constant factor in the
    rows of U beyond the rank, a basis of the left kernel): ``(H rows, U rows, pivots)``;
    None below ``INTEGRAL_MIN_ENTRIES`` entries, or without ``scaling`` when a step
    would scale a row (:class:`~uio_ring.ring._integral.Scaled`).  A row of ``a`` with denominators
    is first multiplied by their least common multiple c (U then starts as diag(c)).
    Raises :class:`CoefficientGrowth` when the elimination stops on its cap
    ``cap_bits + 4·max_bits(a)`` (its own, lighter test; no cap when ``cap_bits`` is
    None)."""
    if m * n < INTEGRAL_MIN_ENTRIES:
        return None
    z, scales = zi.to_integer_rows(a)
    uz = zi.identity(m, scales)
    cap = None if cap_bits is None else cap_bits + 4 * zi.max_bits(z)
    try:
        pivots = zi.row_echelon_int(z, uz, m, n, bit_cap=cap, scaling=scaling)
    except zi.Scaled:
        return None
    zi.normalise_int(z, uz, pivots)
    divisors = zi.pivot_divisors(z, pivots)
    return zi.to_rational_rows(z, divisors), zi.to_rational_rows(uz, divisors), pivots


def hermite_by_elimination(M: PolyMatrix) -> HermiteResult:
    """:func:`hermite` without the generic fast path (for any shape; used for testing
    the two paths against each other)."""
    m, n = M.shape
    var = M.var
    a = dn.copy(M._r)
    u = dn.identity(m)
    pivots = row_echelon(a, u, m, n)
    normalise(a, u, pivots)
    r = len(pivots)
    reduce_transform(u, r, popov_left_kernel(M._r, m, n) if r < m else None)
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
    return is_hermite_raw(H._r, H.rows)
