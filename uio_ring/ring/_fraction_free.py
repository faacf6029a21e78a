"""Fraction-free determinants over Z[δ] and the determinantal divisors they give.

A row of a matrix over Q[δ] times the common denominator of its coefficients is a
row over Z[δ] that spans the same module (the factor is a unit of Q[δ]), so
determinants, minors and their gcds can be computed over Z[δ], where flint's
polynomial products (Kronecker substitution / Schönhage–Strassen, in C) are fast
at high degree and large coefficients.

Determinant
    Bareiss' fraction-free elimination (Bareiss 1968; the one-step form of
    Geddes, Czapor & Labahn, *Algorithms for Computer Algebra*, §9.3): after step
    k every entry is a (k+1)×(k+1) minor of the input, so each division by the
    previous pivot is exact (Sylvester's identity) and the entries never exceed
    the size of the determinant.  O(n³) products in Z[δ] of degree ≤ n·d.  A
    zero pivot is replaced by a row below with a nonzero entry (a row swap
    changes only the sign).  Measured on the 4×4 of degree 222 with 1549-bit
    coefficients that ``uio-ring check`` meets (benchmarks/random_spec.py,
    n = 4, degree 16): 0.03 s, against 5 s by evaluation and interpolation at
    889 points.
Determinantal divisors
    ``d_k`` = the gcd of the k×k minors.  ``det(Q·M·P)`` for integer Q (k×m) and
    P (n×k) is a Z-linear combination of the k×k minors (Cauchy–Binet), hence a
    multiple of ``d_k``: two such combinations with gcd 1 prove ``d_k = 1``.  The
    gcd of *all* maximal minors (when there are few) is ``d_n`` itself.  Then
    (Smith) ``s_1 = … = s_{n−1} = 1`` and ``s_n = d_n`` when ``d_{n−1} = 1``.

>>> from uio_ring.ring import _backend as bk
>>> a = [[bk.from_coeffs([0, 1]), bk.const(1)], [bk.const(-1), bk.from_coeffs([0, 1])]]
>>> det_fraction_free(a, 2)
x^2 + 1
"""

from __future__ import annotations

import itertools
import math
import random

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn

__all__ = [
    "integer_rows",
    "det_integer",
    "det_fraction_free",
    "compressed_minor",
    "smallest_first",
    "maximal_minors_gcd",
    "generic_factors_fraction_free",
    "MAX_MINORS",
    "prefer_fraction_free",
]

IntRows = list[list[flint.fmpz_poly]]

#: The gcd of all maximal minors is formed when there are at most this many.
MAX_MINORS = 64


def prefer_fraction_free(a: dn.Rows, n: int) -> bool:
    """True when Bareiss over Z[δ] is expected to beat evaluation for an n-column matrix of
    δ-degree d whose last row has coefficients of b bits: ``n⁴·b < 1024·d²`` (high degree,
    small coefficients), or b ≤ 12 and 2d ≥ n, or n ≤ 3 and b ≤ 256.

    Evaluation takes one integer determinant per point (n·d + 1 points,
    :func:`~uio_ring.ring._evaluation.det_at`), whose numbers grow with n·b; Bareiss
    multiplies polynomials of degree up to n·d, whose number of operations grows like n³ and
    whose coefficients swell with n·b.  The rule is a least-squares fit of the time ratio
    on a grid of random integer n×n (n = 4 … 16, d = 1 … 32, b = 3 … 1025; one core; time
    of Bareiss over evaluation): it picks the faster path on 259 of 280 cells and loses at
    most 2.1× elsewhere (n = 5, d = 32, b = 1025).  For example n = 8, d = 2: 1.9 at 3 bits,
    3.1 at 65 bits; n = 4, d = 16: 0.05 at 3 bits, 1.6 at 1025 bits; n = 16, d = 8: 0.80 at
    3 bits, 4.1 at 17 bits; n = 3, d = 2: 0.59 at 3 bits, 0.65 at 65 bits, 1.3 at 1025 bits.
    The fit misses structured matrices whose determinant has a far lower degree than its
    bound n·d (the Bareiss minors stay small): the second clause keeps Bareiss for the
    products of unimodular matrices and a Smith form of the ring benchmark (n = 8, d = 6,
    9 bits: 0.40 of the time; n = 12, d = 6, 11 bits: 0.56), and on the grid it picks
    Bareiss at 3 bits and 2d ≥ n (0.53 … 1.07).
    (Before: Bareiss whenever n ≤ 8 or 2d ≥ n with n·b < 2048, which lost up to 4× on 82
    cells.)  On the observability minors of a design: a compressed 8×8 minor of degree 103
    with 4.2-kbit coefficients, 4.6 s against 2.7 s; large rational coefficients at large n
    and low degree (the compressed minors of the design of a 32-state system of degree 1):
    Bareiss took 250 s."""
    # the size from the last row only (a heuristic, and both paths are exact; the rows of
    # the observability matrices grow downwards): scanning every entry cost a quarter of
    # a 4×4 determinant
    bits = max((bk.bits(p) for p in a[-1] if p), default=0)
    if n <= 3 and bits <= 256:
        return True
    deg = dn.mat_degree(a)
    return n**4 * bits < 1024 * deg * deg or (bits <= 12 and 2 * deg >= n)


def integer_rows(a: dn.Rows) -> tuple[IntRows, flint.fmpz]:
    """``(Z, c)``: every row scaled to Z[δ] (see :func:`~uio_ring.ring._backend.integer_row`)
    and the product c of the scales, so ``det Z = c·det a`` for a square a."""
    out = []
    scale = flint.fmpz(1)
    for row in a:
        z, c = bk.integer_row(row)
        out.append(z)
        scale *= c
    return out, scale


def det_integer(z: IntRows, n: int) -> flint.fmpz_poly:
    """det of the n×n matrix z over Z[δ] by Bareiss' elimination (see the module docstring).
    Precondition: z is n×n (not checked; it is not modified)."""
    if n == 0:
        return bk.IntPoly([1])
    a = [list(r) for r in z]
    sign = 1
    prev = bk.IntPoly([1])
    # Invariant after step k: a[i][j] (i, j > k) is the minor on rows 0…k, i and columns 0…k, j
    # of the row-permuted input, up to the sign of the permutation.
    for k in range(n - 1):
        if a[k][k].is_zero():
            piv = next((i for i in range(k + 1, n) if not a[i][k].is_zero()), None)
            if piv is None:
                return bk.IntPoly()
            a[k], a[piv] = a[piv], a[k]
            sign = -sign
        akk = a[k][k]
        for i in range(k + 1, n):
            aik = a[i][k]
            row_i, row_k = a[i], a[k]
            for j in range(k + 1, n):
                row_i[j] = (row_i[j] * akk - aik * row_k[j]) // prev  # exact (Sylvester)
        prev = akk
    return a[n - 1][n - 1] if sign > 0 else -a[n - 1][n - 1]


def det_fraction_free(a: dn.Rows, n: int) -> flint.fmpq_poly:
    """det of the n×n rows a over Q[δ], via Z[δ] (Bareiss).
    Precondition: a is n×n (not checked)."""
    z, scale = integer_rows(a)
    return bk.from_integer(det_integer(z, n)) / scale  # no column reordering: the sign stays


def _size(p: flint.fmpz_poly) -> int:
    return (p.degree() + 1) * int(p.height_bits()) if not p.is_zero() else 0


def smallest_first(z: IntRows, n: int) -> IntRows:
    """The rows and the columns of z sorted by increasing size (degree × bits).  Bareiss'
    step k works with minors of the first k+1 rows and columns, so small ones first keep
    the early steps cheap (the rows of ``N_k`` in the analysis differ by thousands of
    bits).  Minors change only in sign.  Precondition: every row has n entries (not checked)."""
    sizes = [max((_size(r[j]) for r in z), default=0) for j in range(n)]
    order = sorted(range(n), key=sizes.__getitem__)
    rows = sorted(z, key=lambda r: max((_size(p) for p in r), default=0))
    return [[r[j] for j in order] for r in rows]


def compressed_minor(z: IntRows, m: int, n: int, skip: int | None, seed: int) -> flint.fmpq_poly:
    """``det(Q·Z')`` for a pseudo-random integer Q fixed by ``seed``, where Z' is z without
    column ``skip`` (all columns when None) and Q has as many rows as Z' has columns: a
    Z-linear combination of the maximal minors of Z' (Cauchy–Binet), which are minors
    of z.  Q is the identity when Z' is square.  Only rows are mixed, so the columns
    keep their sizes.  Precondition: m ≥ number of columns of Z' ≥ 1 (not checked)."""
    cols = [j for j in range(n) if j != skip]
    k = len(cols)
    zp = [[row[j] for j in cols] for row in z]
    if k < m:
        rng = random.Random(seed)  # fixed: the answer depends only on z, skip and seed
        zero = bk.IntPoly()
        q = [[rng.randint(-9, 9) for _ in range(m)] for _ in range(k)]
        zp = [[sum((zp[l][j] * q[i][l] for l in range(m) if q[i][l]), zero) for j in range(k)]
              for i in range(k)]
    return bk.from_integer(det_integer(smallest_first(zp, k), k))


def maximal_minors_gcd(z: IntRows, m: int, n: int) -> flint.fmpq_poly | None:
    """The monic gcd of all n×n minors of the m×n matrix z (m ≥ n), or None when there
    are more than :data:`MAX_MINORS` of them.  Precondition: m ≥ n ≥ 1 (not checked)."""
    if math.comb(m, n) > MAX_MINORS:
        return None
    g = bk.ZERO
    for rows in itertools.combinations(range(m), n):
        g = bk.gcd(g, bk.from_integer(det_integer([z[i] for i in rows], n)))
        if g.is_one():
            break
    return g


def generic_factors_fraction_free(a: dn.Rows, m: int, n: int) -> list[flint.fmpq_poly] | None:
    """The invariant factors of an m×n matrix of rank n (m ≥ n ≥ 1) when they are
    ``(1, …, 1, d_n)``, certified; otherwise None (then the caller eliminates).

    1. Two compressions of the maximal minors with gcd 1 prove ``d_n = 1``: all ones.
    2. Two combinations of (n−1)-minors with gcd 1 prove ``d_{n−1} = 1`` (square: the
       minors without the largest row and the largest or the next column; tall:
       compressions of the matrix without those columns), and the gcd of
       all maximal minors (at most :data:`MAX_MINORS` of them) is ``d_n``.
    A zero ``d_n`` (rank < n) gives None.

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> generic_factors_fraction_free([[d, bk.ZERO], [bk.ZERO, d], [bk.ONE, bk.ONE]], 3, 2)
    [1, x]
    """
    z, _ = integer_rows(a)
    z = smallest_first(z, n)
    one = bk.ONE
    if m > n:
        g1 = compressed_minor(z, m, n, None, seed=1)
        if g1.is_zero():
            return None
        if bk.gcd(g1, compressed_minor(z, m, n, None, seed=2)).is_one():
            return [one] * n
    if n > 1:
        if m == n:  # two true minors without the largest row: no mixing, so no size blow-up
            g1 = bk.from_integer(det_integer([r[: n - 1] for r in z[: n - 1]], n - 1))
            g2 = bk.from_integer(det_integer([r[: n - 2] + r[n - 1 :] for r in z[: n - 1]], n - 1))
        else:
            g1 = compressed_minor(z, m, n, n - 1, seed=3)
            g2 = compressed_minor(z, m, n, n - 2, seed=4)
        if not bk.gcd(g1, g2).is_one():
            return None
    dn_ = maximal_minors_gcd(z, m, n)
    if dn_ is None or dn_.is_zero():
        return None
    return [one] * (n - 1) + [dn_]
