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
   ``(x_0, …, x_D) ↦ coefficients of x·M``; its reduced echelon basis comes
   from ``fmpz_mat.nullspace`` and one small ``rref`` (python-flint, in C).
2. The generators are the basis vectors led by δ^e·e_j with δ^(e−1)·e_j not a
   leading monomial.  There are m − rank M of them iff D ≥ max d_i; the rank is
   exact (:func:`~uio_ring.ring._predicates.rank_raw`), so the count proves
   that the basis is complete.  D starts at ⌈b_r / (m − r)⌉ (b_r: the degree
   bound of the r×r minors; Σ d_i ≤ b_r) and grows while generators are missing.
3. The result is checked once more: ``K·M == 0`` exactly (as ``T·g = 0`` over Z).

This is the linear-algebra view of minimal bases (Forney 1975, §4; the block
Toeplitz nullity sequence gives the minimal indices — Beelen & Van Dooren,
"A pencil approach for embedding a polynomial matrix into a unimodular
matrix", SIAM J. Matrix Anal. Appl. 9 (1988)).  Cost: one integer nullspace
of a (n·(D + deg M + 1)) × (m·(D + 1)) matrix, O(N³) word operations per
prime of flint's multimodular elimination with N = m·(D + 1); for a tall
(n+4)×n matrix of degree 2 the minimal indices are ≈ n/2, so N ≈ n²/2.  When
N would exceed :data:`MAX_UNKNOWNS` the callers use elimination instead.
"""

from __future__ import annotations

import flint

from uio_ring.ring import _dense as dn
from uio_ring.ring import _evaluation as ev
from uio_ring.ring._predicates import rank_raw

__all__ = ["popov_left_kernel", "MAX_UNKNOWNS"]

#: Largest Toeplitz system (number of unknowns m·(D + 1)) tried; beyond it the
#: elimination path is used (its cost does not grow with that size).
MAX_UNKNOWNS = 1500

IntCoeffs = list[list[list[int]]]  # [row j][column l] -> integer coefficients, low to high


def _integer_coefficients(a: dn.Rows, m: int, n: int) -> IntCoeffs:
    """Coefficients of M·diag(c) with c_l the lcm of the denominators in column l
    (same left kernel as M).  Precondition: shape m×n (not checked)."""
    scale = []
    for col in range(n):
        c = flint.fmpz(1)
        for j in range(m):
            q = a[j][col].denom()
            c = c * q // c.gcd(q)
        scale.append(c)
    return [[[int(x) for x in (a[j][col] * scale[col]).numer().coeffs()] for col in range(n)] for j in range(m)]


def _toeplitz_entries(mi: IntCoeffs, m: int, n: int, dm: int, D: int, mod: int | None) -> list[int]:
    """Row-major entries of the (n·(D+dm+1)) × (m·(D+1)) matrix T with
    ``T[(t, l), (e, j)] = coefficient t − e of M[j][l]``: ``T·vec(x) = vec(x·M)``."""
    cols = m * (D + 1)
    rows = n * (D + dm + 1)
    out = [0] * (rows * cols)
    for j in range(m):
        for col in range(n):
            cs = mi[j][col]
            if mod is not None:
                cs = [c % mod for c in cs]
            for s, c in enumerate(cs):
                if not c:
                    continue
                for e in range(D + 1):
                    out[((e + s) * n + col) * cols + e * m + j] = c
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


def popov_left_kernel(a: dn.Rows, m: int, n: int) -> dn.Rows | None:
    """The Popov basis of the left kernel of the m×n rows ``a`` (rows sorted by
    pivot degree, then pivot position), or None when the Toeplitz system would be
    larger than :data:`MAX_UNKNOWNS`.  Precondition: shape m×n (not checked)."""
    r = rank_raw(a, m, n)
    k = m - r
    if k == 0:
        return []
    if r == 0:
        return dn.identity(m)
    dm = max(dn.mat_degree(a), 0)
    mi = _integer_coefficients(a, m, n)
    d_cap = MAX_UNKNOWNS // m - 1
    # Σ d_i = deg of the maximal minors of K ≤ b_r (they are those of a column
    # basis of M, divided by their gcd), so max d_i ≤ b_r and the mean is ≤ b_r / k.
    bound = ev.minor_degree_bound(a, m, n, r)
    D = min(-(-bound // k), d_cap)
    while True:
        # Invariant: every d_i ≤ D has its generator in `gens`; the others exceed D.
        gens = _exact_generators(mi, m, n, dm, D)
        if len(gens) == k:
            break
        found = sum(i // m for i, _ in gens)
        nxt = min(2 * D + 1, bound - found, d_cap)
        if nxt <= D:
            return None
        D = nxt
    rows = [[flint.fmpq_poly([g[e * m + j] for e in range(D + 1)]) for j in range(m)] for _, g in gens]
    rows.sort(key=dn.leading_position)
    return rows
