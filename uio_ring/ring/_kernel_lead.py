"""Popov rows of a left kernel from the leading monomials modulo a prime and one exact
square solve, certified exactly.

Notation of :mod:`uio_ring.ring._kernel_basis`: ``T_D`` is the block-Toeplitz matrix of
``x ↦ x·M`` on vectors of degree ≤ D, its columns indexed by the monomials δ^e·e_j in
the order (e, j), and V_D its nullspace.  A column is a *pivot* (not a combination of
the columns before it) iff no vector of V_D has that monomial as its greatest one, so
the leading monomials of V_D are the non-pivot columns, and its reduced echelon vector
led by δ^(d_i)·e_(π_i) is ``δ^(d_i) e_(π_i) − x_i`` with x_i supported on the pivot
columns below it: ``T_D[:, P]·x_i = T_D[:, (d_i, π_i)]``.

The column rank profile of ``T_D`` is computed modulo the word prime 2⁶¹ − 1
(``nmod_mat.rref``, O(N³) word operations for N = m·(D + 1), no coefficient growth),
and all generators come from one square system over Z with the pivot columns as
unknowns and one right-hand side per generator (:func:`solve_square`), instead
of a fraction-free nullspace of the whole ``T_D`` followed by a rational echelon form.

Certificate (checked, or None is returned).  Modulo p the rank can only drop, so
``lead_Q ⊆ lead_p`` and ``dim V_D ≤ |lead_p|``; both sets are closed under the shift
δ·, so ``|lead_p| = Σ_i (D − d_i + 1)`` over its generators.  Each returned row is an
exact kernel vector (``T_D·g = 0`` checked over Z) whose greatest monomial is its
generator (the solution's entries above it are checked to be zero); their shifts
δ^s·g_i (s ≤ D − d_i) have distinct leading monomials, so ``dim V_D ≥ |lead_p|``.
Hence ``lead_Q = lead_p`` and the rows are exactly the reduced echelon vectors of V_D
that :func:`~uio_ring.ring._kernel_basis.popov_left_kernel` needs (its completeness
argument — m − rank M generators — is unchanged).  An unlucky prime shows up as a
failed solve or check, never as a wrong answer.

>>> from uio_ring.ring._kernel_basis import _integer_coefficients, _toeplitz_entries
>>> from uio_ring.ring.matrix import PolyMatrix
>>> M = PolyMatrix("[[1], [d], [d**2]]")        # 3×1 of degree 2; vectors of degree ≤ 1
>>> T = _toeplitz_entries(_integer_coefficients(M._r, 3, 1), 3, 1, 2, 1, None)
>>> gens = generators_by_lead_solve(T, 4, 6, 3)
>>> [(idx, [str(c) for c in g]) for idx, g in gens]   # δ·e_0 − e_1 and δ·e_1 − e_2
[(3, ['0', '-1', '0', '1', '0', '0']), (4, ['0', '0', '-1', '0', '1', '0'])]
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import flint

from uio_ring.ring._reduced_crt import solve_reduced_crt

__all__ = [
    "LeadSolution", "generators_by_crt", "generators_by_lead_solve", "lead_solve", "pivot_columns_mod_p", "solve_square",
]

#: The word prime of the rank profiles (2⁶¹ − 1).
PRIME = (1 << 61) - 1

#: The prime of the determinant that refuses a guessed square system before its exact
#: solve (2²⁶ − 5): flint's determinant modulo a prime below 2²⁶ takes 0.55–0.6 of the
#: time modulo PRIME (66×66: 84 against 152 µs; 363×363: 6.1 against 10.1 ms), and a
#: nonsingular system refused by bad luck (probability about 2⁻²⁶) only costs the
#: rank profile the guess was to save.
GUARD_PRIME = (1 << 26) - 5


def solve_square(a: flint.fmpz_mat, b: flint.fmpz_mat, *, bits: int | None = None) -> flint.fmpq_mat:
    """The X with ``a·X = b`` for a square nonsingular integer n×n matrix a and k
    right-hand sides, exactly, by the cheaper of two exact solvers in C.

    With w the word size of the largest entry of a and P the number of word primes (or
    lifting steps) that the solution needs — the same for both — p-adic lifting (Dixon
    1982; ``fmpq_mat.solve``, flint's ``fmpq_mat_solve_fmpz_mat`` from 25 unknowns on)
    multiplies a by the k residuals at every step, about P·n²·k·w word operations beyond
    one inverse modulo p, while the multimodular solve with a common denominator
    (``fmpz_mat.solve``: flint's ``fmpz_mat_solve_multi_mod_den``; Cramer up to 3×3,
    fraction-free LU up to 15×15) reduces a and solves modulo each prime, about
    P·(n³ + n²·(w + k)).  So the multimodular solve is taken when ``k·w > n + w + k``:
    on 64 unknowns with 1400-bit entries and 41 right-hand sides (the solve of a
    32-state observability matrix) 0.14 s against 0.80 s by lifting, while a random
    300×300 system with 60-bit entries and 50 right-hand sides takes 18 s by lifting and
    30 s multimodularly.  Either result is exact; the callers also check their whole
    systems exactly.  Raises ZeroDivisionError when a is singular.  ``bits``: a bound on
    the bit length of a's entries, when the caller knows it (the scan of a 66×66 matrix
    costs 0.8 ms, a solve of it 1 ms); it only chooses the solver.

    >>> solve_square(flint.fmpz_mat([[1, 4], [8, 3]]), flint.fmpz_mat([[0], [1]]))
    [ 4/29]
    [-1/29]
    """
    n, k = a.nrows(), b.ncols()
    if bits is None:
        bits = max((abs(x).bit_length() for x in a.entries()), default=1)
    w = -(-max(bits, 1) // 64)
    if k * w > n + w + k:
        x = a.solve(b)
        assert isinstance(x, flint.fmpq_mat)  # the stubs type the result as any flint matrix
        return x
    return flint.fmpq_mat(a).solve(flint.fmpq_mat(b))


def pivot_columns_mod_p(
    entries: list[int], rows: int, cols: int, p: int = PRIME, *, reduced: bool = False
) -> list[int]:
    """The pivot columns (column rank profile, left to right) of the rows × cols integer
    matrix with row-major ``entries``, modulo p (``reduced``: the entries are already
    residues in [0, p), as :func:`~uio_ring.ring._kernel_basis._toeplitz_entries` gives
    them with ``mod=p``).  The profile of the first c columns is the first part of it
    (a column is a pivot iff it is not a combination of the columns before it).

    >>> pivot_columns_mod_p([1, 2, 3, 2, 4, 7], 2, 3)
    [0, 2]
    """
    return column_profile(flint.nmod_mat(rows, cols, entries if reduced else [x % p for x in entries], p))


def column_profile(mat: flint.nmod_mat) -> list[int]:
    """The pivot columns (column rank profile, left to right) of ``mat`` over its prime field.

    >>> column_profile(flint.nmod_mat(2, 3, [1, 2, 3, 2, 4, 7], 5))
    [0, 2]
    """
    red, rank = mat.rref()
    cols = mat.ncols()
    pivots = []
    r = 0
    for c in range(cols):
        if r < rank and red[r, c] != 0:
            pivots.append(c)
            r += 1
    return pivots


@dataclass(frozen=True)
class LeadSolution:
    """What :func:`lead_solve` certified: the Popov generators, and the solution of the
    extra right-hand sides on the same pivot columns (None: not asked for, or that
    system has no solution)."""

    #: (leading index e·m + j, coefficient vector indexed e·m + j), as
    #: :func:`generators_by_lead_solve` returns them.
    generators: list[tuple[int, list[flint.fmpq]]]
    #: ``(Y, den)`` with ``T_D[:, P]·Y = den·B`` exactly (Y's rows follow ``pivots``).
    solution: tuple[flint.fmpz_mat, flint.fmpz] | None = None


def generators_by_lead_solve(
    full: list[int], rows: int, cols: int, m: int, p: int = PRIME, *, pivots: list[int] | None = None
) -> list[tuple[int, list[flint.fmpq]]] | None:
    """The reduced echelon vectors of V_D that are Popov rows, as (leading index e·m + j,
    coefficient vector indexed e·m + j), certified as in the module text; None when the
    prime p was unlucky (the caller then computes them another way).
    Precondition: ``full`` holds the row-major integer entries of ``T_D`` (rows × cols,
    columns in the order (e, j), m of them per degree), as built by
    :func:`~uio_ring.ring._kernel_basis._toeplitz_entries` (not checked); ``pivots``, when
    given, is its column rank profile modulo p (:func:`pivot_columns_mod_p`), or the part
    of the profile of a larger ``T_D`` on these columns (the same thing; not checked: the
    bound dim V_D ≤ |lead_p| of the certificate rests on it)."""
    got = lead_solve(full, rows, cols, m, p, pivots=pivots)
    return None if got is None else got.generators


def lead_solve(
    full: list[int], rows: int, cols: int, m: int, p: int = PRIME, *, pivots: list[int] | None = None,
    extra: flint.fmpz_mat | None = None, bits: int | None = None, guessed: bool = False,
) -> LeadSolution | None:
    """:func:`generators_by_lead_solve`, and in the same square solve the system
    ``T_D[:, P]·Y = B`` for the rows × k integer matrix ``extra`` = B (P: the pivot
    columns).  When the generators are certified, P is the set of non-leading monomials
    of degree ≤ D, so Y is the reduced solution of degree ≤ D of the system that B
    encodes (one solve for Hermite's U = [X; K]: a 4×2 of degree 16 took 8.8 ms for
    the two apart, 4 ms in one).  Y is checked exactly on every row of T_D (not needed
    when ``T_D[:, P]`` is square: its solve is exact); a failed check only sets
    ``solution`` to None.  ``bits``: a bound on the bit length of the entries
    (:func:`solve_square`).  ``guessed``: P is a guess, not a rank profile modulo p, so a
    square ``T_D[:, P]`` may be singular; one determinant modulo :data:`GUARD_PRIME`
    refuses it first (flint's exact solve would take far longer to find out: a 363×363,
    0.3 s).  A square ``T_D[:, P]`` on a rank profile is nonsingular modulo p, so over Q.
    Preconditions as for :func:`generators_by_lead_solve`; ``extra`` has ``rows`` rows
    (not checked).
    """
    if pivots is None:
        pivots = pivot_columns_mod_p(full, rows, cols, p)
    is_pivot = [False] * cols
    for c in pivots:
        is_pivot[c] = True
    gens = [c for c in range(cols) if not is_pivot[c] and (c < m or is_pivot[c - m])]
    if not gens:
        return LeadSolution([])
    if not pivots:  # T_D ≡ 0 mod p: every monomial is a kernel vector iff T_D = 0 over Z
        if any(full):
            return None
        return LeadSolution([(c, [flint.fmpq(int(i == c)) for i in range(cols)]) for c in gens])
    u = len(pivots)
    square = u == rows
    # rows of T_D[:, P] making a square system nonsingular modulo p (hence over Q): all
    # of them when it is square (its columns are independent modulo p)
    chosen = list(range(rows)) if square else pivot_columns_mod_p(
        [full[r * cols + c] for c in pivots for r in range(rows)], u, rows, p)
    if len(chosen) < u:  # pragma: no cover - T_D[:, P] has full column rank mod p
        return None
    k = len(gens)
    if pivots[-1] == u - 1:  # the first u columns (the generic guess): slices of the rows
        sq = flint.fmpz_mat(u, u, [x for r in chosen for x in full[r * cols : r * cols + u]])
    else:
        sq = flint.fmpz_mat(u, u, [full[r * cols + c] for r in chosen for c in pivots])
    if square and guessed and flint.nmod_mat(sq, GUARD_PRIME).det() == 0:
        return None  # singular modulo the guard prime: the guess was wrong (or the prime unlucky)
    rhs = [[full[r * cols + c] for c in gens] for r in chosen]
    if extra is not None:
        w, ex = extra.ncols(), extra.entries()  # one call, not one per entry
        rhs = [row + ex[r * w : r * w + w] for row, r in zip(rhs, chosen, strict=True)]
    width = k + (0 if extra is None else extra.ncols())
    try:
        snum, sden = solve_square(sq, flint.fmpz_mat(u, width, [x for row in rhs for x in row]), bits=bits).numer_denom()
    except ZeroDivisionError:  # square and singular: ``pivots`` was not a rank profile
        return None
    ents = snum.entries()  # row-major, u × width
    solution = None
    if square:  # the solve of the whole system is exact: nothing to check
        if extra is not None:
            solution = (_columns(snum, k, width), sden)
    else:
        # exact check of the whole system: T_D[:, P]·x = T_D[:, gens] (that is, g·M = 0)
        tp = flint.fmpz_mat(rows, u, [full[r * cols + c] for r in range(rows) for c in pivots])
        tg = flint.fmpz_mat(rows, k, [full[r * cols + c] for r in range(rows) for c in gens])
        xg = _columns(snum, 0, k)
        if tp * xg != tg * sden:
            return None
        if extra is not None:
            y = _columns(snum, k, width)
            if tp * y == extra * sden:
                solution = (y, sden)
    zero, one = flint.fmpq(0), flint.fmpq(1)
    out = []
    for v, c in enumerate(gens):
        vec = [zero] * cols
        for i, pc in enumerate(pivots):
            x = ents[i * width + v]
            if x != 0:
                if pc > c:
                    return None  # the greatest monomial would not be the generator
                vec[pc] = flint.fmpq(-x, sden)
        vec[c] = one
        out.append((c, vec))
    return LeadSolution(out, solution)


def _columns(a: flint.fmpz_mat, start: int, stop: int) -> flint.fmpz_mat:
    """The columns start … stop − 1 of a, as a matrix."""
    w, ents = a.ncols(), a.entries()
    return flint.fmpz_mat(a.nrows(), stop - start, [x for i in range(a.nrows()) for x in ents[i * w + start : i * w + stop]])


def generators_by_crt(
    mi: list[list[list[Any]]], dm: int, m: int, n: int, D: int, pivots: list[int]
) -> list[tuple[int, list[flint.fmpq]]] | None:
    """:func:`generators_by_lead_solve` for M of rank n (``m − n`` generators), the solve by
    :func:`~uio_ring.ring._reduced_crt.solve_reduced_crt` (a Schur complement modulo word
    primes, certified exactly) instead of one square system over Z; None when the profile
    does not have m − n generators or that solver does not apply.

    The reduced echelon vector led by δ^(d_i)·e_(π_i) is ``δ^(d_i)·e_(π_i) + y_i`` with
    ``y_i·M = −δ^(d_i)·M[π_i]`` and y_i supported on the pivot columns, that is, reduced
    modulo the leading monomials: y_i is the reduced solution of that system, unique.
    The certificate of the module text is unchanged: ``y_i·M = −δ^(d_i)·M[π_i]`` is
    checked exactly by the solver, and every monomial of y_i is checked to lie below the
    generator.  Precondition: ``mi`` are the integer coefficients of M (degree dm, rank n,
    not checked); ``pivots`` as for :func:`generators_by_lead_solve`.

    >>> from uio_ring.ring._kernel_basis import _integer_coefficients, _toeplitz_entries
    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> M = PolyMatrix("[[1, 0], [0, 1], [d, d]]")   # kernel [d, d, −1]
    >>> mi = _integer_coefficients(M._r, 3, 2)
    >>> piv = pivot_columns_mod_p(_toeplitz_entries(mi, 3, 2, 1, 1, None), 6, 6)
    >>> [(idx, [str(c) for c in g]) for idx, g in generators_by_crt(mi, 1, 3, 2, 1, piv)]
    [(4, ['0', '0', '-1', '1', '1', '0'])]
    """
    cols = m * (D + 1)
    is_pivot = [False] * cols
    for c in pivots:
        is_pivot[c] = True
    gens = [c for c in range(cols) if not is_pivot[c] and (c < m or is_pivot[c - m])]
    if len(gens) != m - n:
        return None
    lead = {c % m: c // m for c in gens}
    nt = D + dm + 1
    b: list[list[Any]] = [[0] * len(gens) for _ in range(nt * n)]
    for i, c in enumerate(gens):
        d, j = divmod(c, m)
        for col, cs in enumerate(mi[j]):
            for s, x in enumerate(cs):
                if x:
                    b[(d + s) * n + col][i] = -x
    got = solve_reduced_crt(mi, dm, m, n, D, lead, b, len(gens))
    if not isinstance(got, tuple):
        return None
    rows, delta = got
    qden = flint.fmpq(delta)
    out = []
    for c, row in zip(gens, rows, strict=True):
        vec = [flint.fmpq(0)] * cols
        for j, cs in enumerate(row):
            for e, x in enumerate(cs):
                if x != 0:
                    if e * m + j > c:
                        return None  # the greatest monomial would not be the generator
                    vec[e * m + j] = flint.fmpq(x) / qden
        vec[c] = flint.fmpq(1)
        out.append((c, vec))
    return out
