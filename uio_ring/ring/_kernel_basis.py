"""The Popov basis of a left kernel from one exact nullspace over Z.

Let K be the Popov basis (row-wise, zero shift) of ``{x : x·M = 0}`` with
pivot positions π_i and pivot degrees d_i (the minimal indices), and let V_D be
the Q-vector space of kernel vectors of degree ≤ D.  By the predictable-degree
property V_D = ⊕_i {y·K_i : deg y ≤ D − d_i}.  Order the monomials δ^e·e_j by
(e, j) (degree first, then position: the term order of the zero-shift Popov
form).  Then the leading monomials of V_D are exactly the δ^(d_i + s)·e_(π_i),
and in the reduced echelon basis of V_D (leading monomial = greatest, zero
coefficient at every other leading monomial) the vector led by δ^(d_i)·e_(π_i)
is exactly K_i — the Popov basis is the reduced Gröbner basis of the kernel
for that order.  So:

1. V_D is the nullspace of the block-Toeplitz (Sylvester) matrix of the map
   ``(x_0, …, x_D) ↦ coefficients of x·M``.  The generators of its reduced echelon
   basis come from the column rank profile modulo a word prime and one exact square
   solve, certified exactly (:mod:`uio_ring.ring._kernel_lead`); when M has full
   column rank, low degree and fewer than m/2 kernel rows, that solve is a Schur
   complement on the kernel's pivot columns modulo word primes
   (:mod:`uio_ring.ring._reduced_crt`: Σ d_i unknowns instead of N).  When that prime
   is unlucky: from ``fmpz_mat.nullspace`` and one ``rref`` (python-flint, in C),
   whose fraction-free elimination swells with the size of the entries and with the
   dimension of the nullspace.
2. The generators are the basis vectors led by δ^e·e_j with δ^(e−1)·e_j not a
   leading monomial.  There are m − rank M of them iff D ≥ max d_i; the rank is
   exact (:func:`~uio_ring.ring._predicates.rank_raw`), so the count proves
   that the basis is complete.  D starts at ⌈b_r / (m − r)⌉ (b_r: the degree
   bound of the r×r minors; Σ d_i ≤ b_r) and grows while generators are missing;
   on the modular path the rank profiles modulo p at D = 0, 1, 3, … first locate the
   greatest minimal index, and the exact solve runs there
   (:func:`_generator_degree_mod_p`).
3. The result is checked once more: ``K·M == 0`` exactly (as ``T·g = 0`` over Z).

This is the linear-algebra view of minimal bases (Forney 1975, §4; the block
Toeplitz nullity sequence gives the minimal indices — Beelen & Van Dooren,
"A pencil approach for embedding a polynomial matrix into a unimodular
matrix", SIAM J. Matrix Anal. Appl. 9 (1988)).  Cost: one rank profile modulo p of
the (n·(D + deg M + 1)) × (m·(D + 1)) Toeplitz matrix, O(N³) word operations with
N = m·(D + 1), and one square solve over Z (multimodular, in C:
:func:`~uio_ring.ring._kernel_lead.solve_square`); for a tall
(n+4)×n matrix of degree 2 the minimal indices are ≈ n/2, so N ≈ n²/2.  When
N would exceed :data:`MAX_UNKNOWNS`, or M has fewer than :data:`TOEPLITZ_MIN_ROWS`
rows, the callers use elimination instead.

The same matrices give the transforms (:func:`solve_reduced`): the solution X of
``X·M = W`` reduced modulo the Popov kernel basis has unknowns exactly at the
non-leading monomials, which are the pivot columns of the Toeplitz matrix, so it
is the unique solution of one square system — Hermite's U = [X; K] for
rank M < rows, tall left inverses, ``solve_left`` for tall V.  For M of full column
rank that system is solved by block elimination modulo word primes and Chinese
remaindering (:mod:`uio_ring.ring._reduced_crt`; 28×24 of degree 2 with 24 right-hand
sides: 20 primes at about 1.4 ms each, against 0.35 s for the exact 360×360 solve).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring import _evaluation as ev
from uio_ring.ring._kernel_lead import (
    PRIME,
    column_profile,
    generators_by_crt,
    lead_solve,
    pivot_columns_mod_p,
    solve_square,
)
from uio_ring.ring._kronecker import scaled_numerator
from uio_ring.ring._minors_kernel import MINORS_MAX_COLUMNS, kernel_by_minors, solution_by_minors
from uio_ring.ring._predicates import rank_raw
from uio_ring.ring._reduced_crt import solve_reduced_crt, worthwhile

__all__ = [
    "KernelSolution", "generic_kernel_and_solution", "kernel_and_solution", "popov_left_kernel", "solve_reduced",
    "ToeplitzCoefficients", "MAX_UNKNOWNS", "SWELL_MAX_UNKNOWNS", "TOEPLITZ_MIN_ROWS",
]

#: Largest Toeplitz system (number of unknowns m·(D + 1)) tried; beyond it the
#: elimination path is used.
MAX_UNKNOWNS = 1000
#: The larger cap of a caller whose alternative is an elimination already seen to swell
#: (Hermite's U and the left inverse once the capped elimination gave way, the minors
#: proved coprime; the left kernel beyond :data:`MAX_UNKNOWNS`): a 10×8 of degree 32,
#: 1290 unknowns, 6.9 s for K and X, where that elimination ran for over 10 minutes;
#: 10×8 of degree 48, 1930 unknowns: 22 s; a dense 18×16 of degree 16, 2322 unknowns:
#: 39 s (K alone 21 s), where the elimination ran for over five minutes; 18×16 of degree
#: 20, 2898 unknowns: 213 s and 0.9 GB.
SWELL_MAX_UNKNOWNS = 3000
#: Fewer rows than this: elimination (a handful of rows of high degree — the matrices
#: of the observability algorithm, 3×2 of degree 127: elimination 1 ms, Toeplitz 4.7 s).
TOEPLITZ_MIN_ROWS = 6

#: At most this many unknowns m·(D + 1): the rank profile of ``T_D`` alone, without the
#: smaller probes of :func:`_generator_degree_mod_p` (4×2 of degree 16, 68 columns:
#: 0.63 → 0.33 ms, a 20×16 of degree 2, 180 columns: 4.0 → 2.5 ms; on matrices whose
#: generators have the degree of the bound the probes are built in vain).
PROBE_MIN_UNKNOWNS = 256

IntCoeffs = list[list[list[Any]]]  # [row j][column l] -> integer coefficients (int or fmpz), low to high


def _integer_coefficients(a: dn.Rows, m: int, n: int) -> IntCoeffs:
    """Coefficients of M·diag(c) with c_l the lcm of the denominators in column l
    (same left kernel as M).  Precondition: shape m×n (not checked)."""
    return ToeplitzCoefficients.of(a, m, n).mi


@dataclass
class ToeplitzCoefficients:
    """The integer coefficients (fmpz, no conversion to int) of M·diag(c), the column
    scales c and, on demand, the coefficients modulo the word prime: computed once for
    the kernel and the solve of the same M (:func:`uio_ring.ring.solve.solve_left`)."""

    mi: IntCoeffs
    scale: list[flint.fmpz]
    dm: int
    #: The greatest bit length of the integer coefficients (those of every ``T_D``; at
    #: least 1).
    bits: int = 1
    _residues: IntCoeffs | None = None

    @classmethod
    def of(cls, a: dn.Rows, m: int, n: int) -> ToeplitzCoefficients:
        """Precondition: shape m×n (not checked).

        >>> from uio_ring.ring.matrix import PolyMatrix
        >>> c = ToeplitzCoefficients.of(PolyMatrix("[[d/2 + 1], [-300*d]]")._r, 2, 1)
        >>> c.mi, c.scale, c.bits       # column scale 2: [2 + δ; −600·δ], 600 has 10 bits
        ([[[2, 1]], [[0, -600]]], [2], 10)
        """
        scale = _column_scale(a, m, n)
        polys = [[scaled_numerator(a[j][col], scale[col]) for col in range(n)] for j in range(m)]
        bits = max([p.height_bits() for row in polys for p in row], default=1)  # in C: no scan here
        return cls([[p.coeffs() for p in row] for row in polys], scale, max(dn.mat_degree(a), 0), max(bits, 1))

    @property
    def residues(self) -> IntCoeffs:
        """``mi`` modulo :data:`~uio_ring.ring._kernel_lead.PRIME`, entries in [0, p)."""
        if self._residues is None:
            self._residues = [[[c % PRIME for c in cs] for cs in row] for row in self.mi]
        return self._residues


def _column_scale(a: dn.Rows, m: int, n: int) -> list[flint.fmpz]:
    """c_l = lcm of the denominators of the coefficients in column l."""
    return [bk.denominator_lcm(a[j][col] for j in range(m)) for col in range(n)]


def _toeplitz_entries(mi: IntCoeffs, m: int, n: int, dm: int, D: int, mod: int | None) -> list[int]:
    """Row-major entries of the (n·(D+dm+1)) × (m·(D+1)) matrix T with
    ``T[(t, l), (e, j)] = coefficient t − e of M[j][l]``: ``T·vec(x) = vec(x·M)``."""
    cols = m * (D + 1)
    rows = n * (D + dm + 1)
    out = [0] * (rows * cols)
    # T[(e + s, col), (e, j)] = c for e = 0 … D: the flat index moves by n·cols + m
    # with e, so one strided slice writes a coefficient's D + 1 places
    step = n * cols + m
    for j in range(m):
        for col in range(n):
            cs = mi[j][col]
            if mod is not None:
                cs = [c % mod for c in cs]
            for s, c in enumerate(cs):
                if c:
                    start = (s * n + col) * cols + j
                    out[start : start + step * (D + 1) : step] = [c] * (D + 1)
    return out


def _toeplitz_mod_p(residues: IntCoeffs, m: int, n: int, dm: int, D: int) -> flint.nmod_mat:
    """``T_D`` of :func:`_toeplitz_entries` as an ``nmod_mat`` modulo
    :data:`~uio_ring.ring._kernel_lead.PRIME` (``residues``: the coefficients of M modulo
    p), written entry by entry into a zero matrix: it is mostly zeros (a fraction
    (dm + 1)/(D + dm + 1) of each column is not), and a matrix built from the list of
    all its entries costs more than its rank profile (28×24 of degree 2 at D = 12:
    20 ms against 3 ms).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix("[[1], [d]]")
    >>> _toeplitz_mod_p(_integer_coefficients(M._r, 2, 1), 2, 1, 1, 1)
    [1, 0, 0, 0]
    [0, 1, 1, 0]
    [0, 0, 0, 1]
    """
    rows, cols = n * (D + dm + 1), m * (D + 1)
    out = flint.nmod_mat(rows, cols, PRIME)
    for j in range(m):
        for col in range(n):
            for s, c in enumerate(residues[j][col]):
                if c:
                    for e in range(D + 1):
                        out[(e + s) * n + col, e * m + j] = c
    return out


def _exact_generators(
    mi: IntCoeffs, m: int, n: int, dm: int, D: int
) -> list[tuple[int, list[flint.fmpq]]]:
    """The reduced echelon vectors of V_D that are Popov rows (see the module text),
    as (leading index e·m + j, coefficient vector indexed e·m + j)."""
    rows, cols = n * (D + dm + 1), m * (D + 1)
    t = flint.fmpz_mat(rows, cols, _toeplitz_entries(mi, m, n, dm, D, None))
    basis, nul = t.nullspace()
    nul = int(nul)
    if nul == 0:
        return []
    # nullity × cols, columns reversed so that the greatest monomial comes first
    rev = flint.fmpz_mat(nul, cols, [basis[cols - 1 - c, v] for v in range(nul) for c in range(cols)])
    red, den, _ = rev.rref()
    qden = flint.fmpq(den)
    lead: dict[int, int] = {}  # leading index (original order) -> row of `red`
    for v in range(nul):
        first = next(c for c in range(cols) if red[v, c] != 0)
        lead[cols - 1 - first] = v
    chosen = [(idx, v) for idx, v in sorted(lead.items()) if not (idx >= m and (idx - m) in lead)]
    # the exact check T·g = 0 (that is, g·M = 0) on the integer vectors, in C
    g = flint.fmpz_mat(cols, len(chosen), [red[v, cols - 1 - c] for c in range(cols) for _, v in chosen])
    if not (t * g).is_zero():  # pragma: no cover - a nullspace vector; proven above
        raise ArithmeticError("Toeplitz kernel basis failed its check K·M = 0")
    return [(idx, [flint.fmpq(red[v, cols - 1 - c]) / qden for c in range(cols)]) for idx, v in chosen]


def _generator_degree_mod_p(
    residues: IntCoeffs, m: int, n: int, dm: int, D: int, k: int
) -> tuple[int, list[int]]:
    """``(D', pivots)``: the degree bound D' ≤ D at which the exact generators are sought,
    and the column rank profile modulo :data:`~uio_ring.ring._kernel_lead.PRIME` of
    ``T_D'`` (``residues``: the coefficients of M modulo p).

    The profiles of ``T_0, T_1, T_3, …`` (those with at most half the columns of
    ``T_D``: a larger probe would save less than it costs), then of ``T_D``, are computed until
    one has k generators (as many as Popov rows over Q): D' is then the greatest degree
    among them — the profile of ``T_D'`` is the part of that profile on its first
    m·(D' + 1) columns (those columns vanish outside the rows of ``T_D'``, and a column
    is a pivot iff it is not a combination of the columns before it).  Otherwise D' = D.
    D' is only a choice of where to look: the generators at D' are certified exactly
    (:func:`~uio_ring.ring._kernel_lead.generators_by_lead_solve`; an unlucky prime
    fails that certificate), so the basis does not depend on it.  (The 216×32
    observability matrix of degree 23 of a 32-state design has a constant kernel basis:
    D' = 0 and 32 unknowns instead of D = 3 and 128.)  Cost: rank profiles modulo p,
    O((m·(D + 1))³) word operations in all (the bounds at most double).  When ``T_D`` has
    at most :data:`PROBE_MIN_UNKNOWNS` columns only its profile is computed (the same
    D' and pivots: each probe's profile is a part of it).
    """
    probes = [0]
    while 2 * probes[-1] + 1 < D:
        probes.append(2 * probes[-1] + 1)
    if m * (D + 1) <= PROBE_MIN_UNKNOWNS:
        probes = []  # T_D's own profile costs less than building the smaller ones
    for d in [x for x in probes if 2 * (x + 1) <= D + 1] + [D]:
        cols = m * (d + 1)
        pivots = column_profile(_toeplitz_mod_p(residues, m, n, dm, d))
        is_pivot = [False] * cols
        for c in pivots:
            is_pivot[c] = True
        gens = [c for c in range(cols) if not is_pivot[c] and (c < m or is_pivot[c - m])]
        if len(gens) == k:
            d_use = max(c // m for c in gens)
            return d_use, [c for c in pivots if c < m * (d_use + 1)]
    return D, pivots


@dataclass(frozen=True)
class KernelSolution:
    """The Popov basis of M's left kernel and the solution of ``X·M = W`` reduced modulo
    it (:func:`kernel_and_solution`)."""

    #: Rows of the Popov basis (sorted by pivot degree, then pivot position).
    kernel: dn.Rows
    #: Rows of X, or None when none of degree within the bounds tried was found.
    solution: dn.Rows | None


def popov_left_kernel(
    a: dn.Rows, m: int, n: int, *, min_rows: int = TOEPLITZ_MIN_ROWS, coeffs: ToeplitzCoefficients | None = None,
    max_unknowns: int = MAX_UNKNOWNS,
) -> dn.Rows | None:
    """The Popov basis of the left kernel of the m×n rows ``a`` (rows sorted by
    pivot degree, then pivot position), or None when m < ``min_rows`` or the
    Toeplitz system would have more than ``max_unknowns`` unknowns m·(D + 1).  One kernel row ((n+1)×n
    of rank n, n ≤ :data:`~uio_ring.ring._minors_kernel.MINORS_MAX_COLUMNS`, or more
    columns when the degree bound of that row is beyond the Toeplitz systems): from the
    maximal minors instead (:mod:`uio_ring.ring._minors_kernel`).
    Precondition: shape m×n; ``coeffs``, when given, is ``ToeplitzCoefficients.of(a, m, n)``
    (not checked)."""
    got = _popov_left_kernel(a, m, n, min_rows, coeffs, None, max_unknowns)
    return None if got is None else got[0]


def kernel_and_solution(
    a: dn.Rows, m: int, n: int, rhs: dn.Rows, *, min_rows: int = TOEPLITZ_MIN_ROWS,
    coeffs: ToeplitzCoefficients | None = None, tries: int | None = None, max_unknowns: int = MAX_UNKNOWNS,
    guess: bool = True,
) -> KernelSolution | None:
    """The Popov basis K of the left kernel of the m×n rows ``a`` and the solution X of
    ``X·M = rhs`` reduced modulo K (:func:`popov_left_kernel` and :func:`solve_reduced`),
    or None when K is (m < ``min_rows``, or its Toeplitz system would have more than
    ``max_unknowns`` unknowns; X's own systems have the same cap).
    ``guess=False``: without the generic guess (:func:`_generic_generators`), for a caller
    whose :func:`generic_kernel_and_solution` has just refused it.

    Both are solutions on the same unknowns — the non-leading monomials, the pivot
    columns of ``T_D`` — so when X has degree ≤ D, the degree bound of K's generators,
    they come from one square solve (:func:`~uio_ring.ring._kernel_lead.lead_solve`;
    Hermite's U = [X; K] of a 4×2 of degree 16: 8.8 → 4 ms; 2.7 ms when the generic
    minimal indices are guessed, :func:`_generic_generators`).  Otherwise X is sought at
    the next bounds as :func:`solve_reduced` does (``tries`` of them when given).  With
    one kernel row (as in :func:`popov_left_kernel`) both come from the maximal minors
    and one inverse modulo a determinant (:mod:`uio_ring.ring._minors_kernel`).  X is
    checked exactly either way; ``solution`` is None when it was not found.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix("[[1], [d], [d**2]]")
    >>> got = kernel_and_solution(M._r, 3, 1, dn.identity(1), min_rows=0)
    >>> PolyMatrix._new(got.kernel, 2, 3, "d"), PolyMatrix._new(got.solution, 1, 3, "d")
    (PolyMatrix([[d, -1, 0], [0, d, -1]]), PolyMatrix([[1, 0, 0]]))
    """
    coeffs = coeffs or ToeplitzCoefficients.of(a, m, n)
    got = _popov_left_kernel(a, m, n, min_rows, coeffs, rhs, max_unknowns, guess)
    if got is None:
        return None
    K, X, refuted = got
    if X is None and rhs:
        X = solve_reduced(a, m, n, K, rhs, tries=tries, coeffs=coeffs, refuted=refuted, max_unknowns=max_unknowns)
    return KernelSolution(K, X if rhs else [])


def _popov_left_kernel(
    a: dn.Rows, m: int, n: int, min_rows: int, coeffs: ToeplitzCoefficients | None, rhs: dn.Rows | None,
    max_unknowns: int = MAX_UNKNOWNS, guess: bool = True,
) -> tuple[dn.Rows, dn.Rows | None, int] | None:
    """``(K, X, refuted)``: :func:`popov_left_kernel`, and when ``rhs`` is given the reduced
    solution X of degree ≤ D from the same square solve (D: the degree bound of K's
    generators), or None with ``refuted`` = D when there is none (−1: not tried)."""
    if m < min_rows:
        return None
    r = rank_raw(a, m, n)
    k = m - r
    if k == 0:
        return [], None, -1
    if r == 0:
        return dn.identity(m), None, -1
    # Σ d_i = deg of the maximal minors of K ≤ b_r (they are those of a column
    # basis of M, divided by their gcd), so max d_i ≤ b_r and the mean is ≤ b_r / k.
    bound = ev.minor_degree_bound(a, m, n, r)
    if m == n + 1 and r == n and (n <= MINORS_MAX_COLUMNS or bound > MAX_UNKNOWNS // m - 1):
        # one kernel row: the maximal minors, and X by one inverse modulo det M_R — also
        # for more columns when the row's degree bound is beyond the (default) Toeplitz cap
        # (a 9×8 of degree 32 in the W-step of a 32-state check: bound 256, 9·257 unknowns;
        # 6 s here, the elimination it fell back to ran for over 15 minutes)
        one = kernel_by_minors(a, n)
        if one is not None:
            return [one.row], solution_by_minors(a, n, one, rhs) if rhs and one.coprime else None, -1
    coeffs = coeffs or ToeplitzCoefficients.of(a, m, n)
    mi, dm = coeffs.mi, coeffs.dm
    d_cap = max_unknowns // m - 1
    D = min(-(-bound // k), d_cap)
    crt = 2 * k < m and r == n and worthwhile(n, dm)
    if guess and _generic_guess_degree(bound, m, n, r, dm, max_unknowns) == D:
        generic = _generic_generators(coeffs, m, n, D, k, rhs)
        if generic is not None:
            generators, solution, sought = generic
            return _kernel_rows(generators, m, D), solution, (D if sought and solution is None else -1)
    X: dn.Rows | None = None
    refuted = -1
    while True:
        # Invariant: every d_i ≤ D has its generator in `gens`; the others exceed D.
        # The modular rank profile and one certified square solve, whatever the nullity:
        # the fraction-free nullspace swells with the size of the entries (the 600×570
        # Toeplitz matrix of 223-bit entries of a 6×4 observability matrix of degree 55:
        # 56 s, against 1.5 s; rank-deficient 16×16: 146 → 31 ms) and with the
        # nullity (a 216×32 observability matrix: 184 rows); it stays the fallback
        # for an unlucky prime
        D_use, pivots = _generator_degree_mod_p(coeffs.residues, m, n, dm, D, k)
        lead: list[tuple[int, list[flint.fmpq]]] | None
        if crt:
            # rank n: the solve as a Schur complement modulo primes (_reduced_crt)
            lead = generators_by_crt(mi, dm, m, n, D_use, pivots)
        else:
            lead, X, sought = _solve_on_pivots(coeffs, m, n, D_use, pivots, rhs)
            refuted = D_use if sought and X is None else -1
        if lead is not None and D_use < D:
            if len(lead) == k:
                # certified at D' < D: lead_Q = lead_p there, and lead_p has all k generators
                D, gens = D_use, lead
                break
            lead = None  # pragma: no cover - as just said
        if lead is None:
            X, refuted = None, -1  # X's unknowns were the pivot columns of an uncertified profile
        gens = _exact_generators(mi, m, n, dm, D) if lead is None else lead
        if len(gens) == k:
            break
        X, refuted = None, -1  # the pivot columns were not yet the non-leading monomials
        found = sum(i // m for i, _ in gens)
        nxt = min(2 * D + 1, bound - found, d_cap)
        if nxt <= D:
            return None
        D = nxt
    return _kernel_rows(gens, m, D), X, refuted


def _generic_guess_degree(
    bound: int, m: int, n: int, r: int, dm: int, max_unknowns: int = MAX_UNKNOWNS
) -> int | None:
    """The degree D = ⌈b_r / k⌉ of :func:`_generic_generators` for an m×n M of rank r and
    degree dm whose r×r minors have the degree bound ``bound`` = b_r (k = m − r), or None
    when the guess does not apply: it needs rank n and b_r = n·dm (otherwise the minimal
    indices are not a generic M's), at most ``max_unknowns`` unknowns m·(D + 1), and not
    the case of the block elimination modulo primes
    (:func:`~uio_ring.ring._reduced_crt.worthwhile`, with 2k < m), which needs no square
    system.

    >>> _generic_guess_degree(32, 4, 2, 2, 16), _generic_guess_degree(16, 4, 1, 1, 16)
    (16, 6)
    >>> _generic_guess_degree(30, 4, 2, 2, 16) is None    # b_r < n·dm: not generic
    True
    """
    k = m - r
    if r != n or k == 0 or bound != n * dm:
        return None
    D = -(-bound // k)
    if m * (D + 1) > max_unknowns or (2 * k < m and worthwhile(n, dm)):
        return None
    return D


def generic_kernel_and_solution(
    a: dn.Rows, m: int, n: int, rhs: dn.Rows, *, coeffs: ToeplitzCoefficients | None = None,
    max_unknowns: int = MAX_UNKNOWNS,
) -> KernelSolution | None:
    """:func:`kernel_and_solution` by the generic guess alone (:func:`_generic_generators`),
    for callers that try it before anything else: None, at the cost of at most one
    Toeplitz system and one determinant modulo a prime, when it does not apply, when M
    is not generic, or when X is not found (``rhs`` of degree above D + deg M), or when
    ``T_D`` would have more than ``max_unknowns`` columns m·(D + 1).  A
    certified guess has ``T_D[:, P]`` square and nonsingular, so ``X·M = W`` has its
    reduced solution for every W within that degree: for W = I, M is left unimodular.
    Precondition: shape m×n (not checked).

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix("[[d**2 + 1], [d**2 - d], [2*d**2 + 3]]")   # minimal indices 1, 1
    >>> got = generic_kernel_and_solution(M._r, 3, 1, dn.identity(1))
    >>> [dn.row_degree(r) for r in got.kernel], dn.matmul(got.solution, M._r, 1, 3, 1)
    ([1, 1], [[1]])
    """
    coeffs = coeffs or ToeplitzCoefficients.of(a, m, n)
    r = rank_raw(a, m, n)
    D = _generic_guess_degree(ev.minor_degree_bound(a, m, n, r), m, n, r, coeffs.dm, max_unknowns)
    if D is None:
        return None
    got = _generic_generators(coeffs, m, n, D, m - r, rhs)
    if got is None or got[1] is None:
        return None
    return KernelSolution(_kernel_rows(got[0], m, D), got[1])


def _kernel_rows(gens: list[tuple[int, list[flint.fmpq]]], m: int, D: int) -> dn.Rows:
    """The Popov rows of the generators (coefficient vectors indexed e·m + j), sorted by
    pivot degree, then pivot position."""
    end = m * (D + 1)
    rows = [[flint.fmpq_poly(g[j:end:m]) for j in range(m)] for _, g in gens]  # g[e·m + j], e = 0 … D
    rows.sort(key=dn.leading_position)
    return rows


def _generic_generators(
    coeffs: ToeplitzCoefficients, m: int, n: int, D: int, k: int, rhs: dn.Rows | None
) -> tuple[list[tuple[int, list[flint.fmpq]]], dn.Rows | None, bool] | None:
    """The k Popov generators when the minimal indices are those of a generic M — D − 1
    and D with D = ⌈n·deg M / k⌉, Σ d_i = b_r = n·deg M — found without a rank profile,
    with the reduced solution of ``X·M = rhs`` of degree ≤ D when there is one, and
    whether it was sought (as :func:`_solve_on_pivots`); None when M is not generic so.

    The guess (:func:`_generic_leading`): the leading monomials Λ that a generic M gives
    by counting dimensions, so the unknowns P are all the other columns of ``T_D``, and
    ``T_D[:, P]`` is square.  Certificate: its exact solve succeeds only when it is
    nonsingular, so rank T_D = |P| and dim V_D = |Λ|.  The solution for each generator
    c ∈ Λ (c − m ∉ Λ) is a kernel vector on P ∪ {c}, checked to have no monomial above c
    (:func:`~uio_ring.ring._kernel_lead.lead_solve`), so it is led by c; with δ times those
    of degree D − 1 they are |Λ| kernel vectors with distinct leading monomials, so they
    span V_D and its leading monomials are exactly Λ.  The reduced echelon vector of V_D
    led by a generator c is zero on Λ \\ {c}, so it is the (unique) solution found: the
    Popov row of degree c // m (the rank, hence k = m − rank M, is exact).  Saves the
    modular rank profiles (4×2 of degree 16: 0.3 of 2.7 ms; 6×1 of degree 16, minimal
    indices 3, 3, 3, 3, 4: 0.62 → 0.5 ms); a wrong guess costs a determinant modulo a
    prime (:func:`~uio_ring.ring._kernel_lead.lead_solve` with ``guessed`` refuses a
    square system singular there).  The leading monomials are not always the generic
    ones: a 5×3 of degree 48 with zero leading coefficients has them at positions 2 and
    4, a 3×1 whose first entry has a lower degree at positions 0 and 2."""
    leading = _generic_leading(m, n, coeffs.dm, D, k)
    pivots = [c for c in range(m * (D + 1)) if c not in leading]
    generators, X, sought = _solve_on_pivots(coeffs, m, n, D, pivots, rhs, guessed=True)
    if generators is None or len(generators) != k:
        return None
    return generators, X, sought


def _generic_leading(m: int, n: int, dm: int, D: int, k: int) -> set[int]:
    """The leading monomials (columns e·m + j of ``T_D``) of the left kernel of a generic
    m×n M of degree dm and rank n, with D = ⌈n·dm / k⌉ (k = m − n): the kernel vectors of
    degree ≤ e have dimension max(0, k·(e + 1) − n·dm), and each degree's new leading
    monomials take its last positions, so s = k·D − n·dm generators have degree D − 1
    (positions m − s … m − 1) and the other k − s degree D (positions m − k … m − s − 1).

    >>> sorted(_generic_leading(4, 1, 16, 6, 3))    # minimal indices 5, 5, 6
    [22, 23, 25, 26, 27]
    >>> sorted(_generic_leading(4, 2, 16, 16, 2))   # 16 and 16: the last two columns
    [66, 67]
    """
    s = k * D - n * dm
    return {(D - 1) * m + j for j in range(m - s, m)} | {D * m + j for j in range(m - k, m)}


def _solve_on_pivots(
    coeffs: ToeplitzCoefficients, m: int, n: int, D: int, pivots: list[int], rhs: dn.Rows | None,
    *, guessed: bool = False,
) -> tuple[list[tuple[int, list[flint.fmpq]]] | None, dn.Rows | None, bool]:
    """``(generators, X, sought)``: :func:`~uio_ring.ring._kernel_lead.lead_solve` on
    ``T_D`` with these pivot columns (None: refused), with the right-hand sides of
    ``X·M = rhs`` in the same solve when their degree is ≤ D + deg M (``sought``) — X
    then, or None when that system has no solution.  ``guessed``: the pivot columns are
    a guess, not a rank profile (``lead_solve``'s)."""
    dm = coeffs.dm
    extra, bden = _toeplitz_rhs(coeffs, n, D, rhs) if rhs and dn.mat_degree(rhs) <= D + dm else (None, None)
    got = lead_solve(_toeplitz_entries(coeffs.mi, m, n, dm, D, None), n * (D + dm + 1), m * (D + 1), m,
                     pivots=pivots, extra=extra, bits=coeffs.bits, guessed=guessed)
    if got is None:
        return None, None, False
    X = None
    if got.solution is not None and extra is not None and bden is not None:
        ynum, yden = got.solution
        X = _solution_rows(ynum, bden * yden, pivots, m, D, extra.ncols())
    return got.generators, X, extra is not None


def _toeplitz_rhs(coeffs: ToeplitzCoefficients, n: int, D: int, rhs: dn.Rows) -> tuple[flint.fmpz_mat, flint.fmpz]:
    """``(B, den)``: the right-hand sides of ``X·M = rhs`` as columns of ``T_D``'s rows,
    over one denominator — coefficient t of ``rhs[v][l]·c_l`` at row (t, l), column v
    (c_l: the column scale of M).  Precondition: ``deg rhs ≤ D + dm`` (not checked)."""
    rows = n * (D + coeffs.dm + 1)
    k = len(rhs)
    scaled = [[(rhs[v][col] * coeffs.scale[col]).coeffs() for col in range(n)] for v in range(k)]
    b = flint.fmpq_mat(rows, k, [
        scaled[v][col][t] if t < len(scaled[v][col]) else 0
        for t in range(D + coeffs.dm + 1) for col in range(n) for v in range(k)
    ])
    return b.numer_denom()


def _solution_rows(num: flint.fmpz_mat, den: flint.fmpz, unknowns: list[int], m: int, D: int, k: int) -> dn.Rows:
    """The k rows of m polynomials of degree ≤ D whose coefficient e in column j is
    ``num[i, v] / den`` for ``unknowns[i] = e·m + j`` (zero at the other monomials)."""
    qden = flint.fmpq(den)
    pos = {c: i for i, c in enumerate(unknowns)}
    ents = num.entries()  # row-major: one call, not one per entry
    out: dn.Rows = []
    for v in range(k):
        row = []
        for j in range(m):
            cs = [ents[pos[e * m + j] * k + v] if (e * m + j) in pos else 0 for e in range(D + 1)]
            row.append(flint.fmpq_poly(cs) / qden if any(cs) else bk.ZERO)
        out.append(row)
    return out


def solve_reduced(
    a: dn.Rows, m: int, n: int, kernel: dn.Rows, rhs: dn.Rows, *, tries: int | None = None,
    coeffs: ToeplitzCoefficients | None = None, multimodular: bool = True, refuted: int = -1,
    max_unknowns: int = MAX_UNKNOWNS,
) -> dn.Rows | None:
    """The X with ``X·M = rhs`` reduced modulo the Popov kernel basis ``kernel`` (entries
    in a pivot column of lower degree than that pivot), from one square block-Toeplitz
    system; None when that system is too large (more than ``max_unknowns`` unknowns
    m·(D + 1)) or the degree bound must grow beyond it.

    The unknowns are the monomials that are not leading monomials of the kernel
    (δ^e·e_j with e < d_i when j = π_i): for every degree bound D these are the
    pivot columns of the Toeplitz matrix T_D (its free columns are the leading
    monomials, see the module text), so ``T_D`` restricted to them has full column
    rank and the reduced solution, when it has degree ≤ D, is its unique solution.
    Rows making a square nonsingular system are chosen by a rank computation modulo
    the prime 2⁶¹ − 1 (nonsingular modulo p implies nonsingular over Q); the square
    system is solved exactly (:func:`~uio_ring.ring._kernel_lead.solve_square`, in C), and the
    whole system ``T_D·x = rhs`` is then checked exactly — a solution of degree
    > D (or none) fails the check and D grows (a bound that the same system modulo p
    already refutes skips the exact solve: :func:`_consistent_mod_p`) (at most ``tries`` degree bounds
    when given: for a system that may have no solution).  Precondition: ``kernel`` is the
    Popov basis of the left kernel of the m×n rows ``a``; rhs rows have n entries;
    ``coeffs``, when given, is ``ToeplitzCoefficients.of(a, m, n)`` (not checked).

    For M of full column rank the square system is first solved by block elimination
    modulo word primes (:func:`~uio_ring.ring._reduced_crt.solve_reduced_crt`: a
    Σ d_i-unknown Schur complement instead of the whole system, Chinese remaindering with
    early termination, the result checked exactly); ``multimodular=False`` skips that
    (for testing the two against each other: the solution is unique).  ``refuted``: a
    degree bound at which the caller found no solution (:func:`kernel_and_solution`);
    the bounds start above it, and it counts as one of the ``tries``.
    """
    if not rhs:
        return []
    coeffs = coeffs or ToeplitzCoefficients.of(a, m, n)
    dm = coeffs.dm
    lead = {j: d for d, j in (dn.leading_position(row) for row in kernel)}
    hdeg = max(dn.mat_degree(rhs), 0)
    D = max([hdeg - dm, *lead.values(), 0])
    d_cap = max_unknowns // m - 1
    if refuted >= D:
        if tries is not None:
            tries -= 1
        if refuted >= d_cap or tries == 0:
            return None
        D = min(refuted + max(refuted // 2, 1), d_cap)
    while D <= d_cap:
        got = _solve_reduced_at(coeffs, m, n, D, lead, rhs, multimodular)
        if got is not None:
            return got
        if tries is not None:
            tries -= 1
        if D == d_cap or tries == 0:
            return None
        D = min(D + max(D // 2, 1), d_cap)
    return None


def _toeplitz_columns(mi: IntCoeffs, m: int, n: int, dm: int, D: int, columns: list[int]) -> list[list[int]]:
    """The given columns (indices e·m + j) of the Toeplitz matrix ``T_D`` of
    :func:`_toeplitz_entries`, each as a list of its n·(D + dm + 1) entries: column
    (e, j) holds coefficient s of ``M[j][l]`` at row ((e + s)·n + l)."""
    rows = n * (D + dm + 1)
    out = []
    for c in columns:
        e, j = divmod(c, m)
        col = [0] * rows
        for l_, cs in enumerate(mi[j]):
            for s, x in enumerate(cs):
                if x:
                    col[(e + s) * n + l_] = x
        out.append(col)
    return out


def _consistent_mod_p(
    residues: list[list[int]], chosen: list[int], bnum: flint.fmpz_mat, rows: int, u: int, k: int
) -> bool:
    """False only when the integer system ``T_P·X = B`` (T_P: the columns whose residues
    modulo :data:`~uio_ring.ring._kernel_lead.PRIME` are ``residues``; B = ``bnum``) has
    no rational solution.  Proof: the rows ``chosen`` of T_P form a square matrix S that is
    nonsingular modulo p, so a solution X is ``S⁻¹·B_chosen``, with denominators dividing
    det S, a unit modulo p; X mod p is then the unique solution Y of ``S·Y ≡ B_chosen``
    and satisfies ``T_P·Y ≡ B (mod p)``.  So a failure of that congruence proves that no
    X exists, before the exact solve (a degree bound too small: the solve of T of a
    32-state design at D = 0).  Cost: one u×u solve and one product modulo p."""
    p = PRIME
    b_p = flint.nmod_mat(bnum, p)
    sq_p = flint.nmod_mat(u, u, [residues[c][r] for r in chosen for c in range(u)], p)
    sb_p = flint.nmod_mat(u, k, [int(b_p[r, v]) for r in chosen for v in range(k)], p)
    t_p = flint.nmod_mat(rows, u, [residues[c][r] for r in range(rows) for c in range(u)], p)
    return bool(t_p * sq_p.solve(sb_p) == b_p)


def _solve_reduced_at(
    coeffs: ToeplitzCoefficients, m: int, n: int, D: int, lead: dict[int, int], rhs: dn.Rows,
    multimodular: bool = True,
) -> dn.Rows | None:
    """:func:`solve_reduced` at the degree bound D; None when the check fails."""
    mi, dm = coeffs.mi, coeffs.dm
    rows = n * (D + dm + 1)
    if dn.mat_degree(rhs) > D + dm:
        return None
    k = len(rhs)
    bnum, bden = _toeplitz_rhs(coeffs, n, D, rhs)
    crt = solve_reduced_crt(mi, dm, m, n, D, lead, bnum.tolist(), k) if multimodular else None
    if isinstance(crt, str):
        return None  # no solution of degree ≤ D (proved modulo a prime: see _reduced_crt)
    if crt is not None:  # checked exactly inside: X·M = rhs
        rows_, delta = crt
        qden = flint.fmpq(bden * delta)
        return [[flint.fmpq_poly(cs) / qden if any(cs) else bk.ZERO for cs in row] for row in rows_]
    unknowns = [e * m + j for e in range(D + 1) for j in range(m) if not (j in lead and e >= lead[j])]
    u = len(unknowns)
    exact = _toeplitz_columns(mi, m, n, dm, D, unknowns)
    residues = _toeplitz_columns(coeffs.residues, m, n, dm, D, unknowns)
    # independent rows of T restricted to the unknowns, modulo p
    chosen = pivot_columns_mod_p([x for col in residues for x in col], u, rows, reduced=True)
    if len(chosen) < u:
        return None  # a bad prime (T restricted to the unknowns has full column rank over Q)
    if not _consistent_mod_p(residues, chosen, bnum, rows, u, k):
        return None  # no solution of degree ≤ D (proved: see _consistent_mod_p)
    sq = flint.fmpz_mat(u, u, [exact[c][r] for r in chosen for c in range(u)])
    sb = flint.fmpz_mat(u, k, [bnum[r, v] for r in chosen for v in range(k)])
    snum, sden = solve_square(sq, sb, bits=coeffs.bits).numer_denom()
    # the exact check of the whole system: T_P · x = rhs, in integers
    tfull = flint.fmpz_mat(rows, u, [exact[c][r] for r in range(rows) for c in range(u)])
    if tfull * snum != bnum * sden:
        return None  # the reduced solution has degree > D
    return _solution_rows(snum, bden * sden, unknowns, m, D, k)
