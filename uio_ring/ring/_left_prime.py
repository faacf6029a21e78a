"""Left primeness (all invariant factors 1) of a full-row-rank matrix, proved modulo one prime.

An r×n matrix M over Q[δ] of rank r is *left prime* when its r×r minors have no
common factor, i.e. ``d_r = 1`` and all invariant factors are 1 (M(λ) has full
row rank for every λ ∈ C).  Scale the rows to Z[δ] (units of Q[δ]) and let
``d_i`` be the row degrees and L the leading row coefficient matrix (row i:
the coefficients of δ^(d_i)).  For an integer n×r matrix Q, ``f = det(M·Q)`` is a
Z-linear combination of the r×r minors (Cauchy–Binet), of degree ≤ Σ d_i, and its
coefficient of δ^(Σ d_i) is ``det(L·Q)``.

Test: pick integer Q₁, Q₂ (fixed pseudo-random entries in [0, p)) and a word-size
prime p.  If ``det(L·Q₁) ≢ 0 (mod p)`` and ``gcd(f₁ mod p, f₂ mod p) = 1`` in
GF(p)[δ], then M is left prime.  Proof: a common factor of positive degree of all
r×r minors can be taken primitive in Z[δ], h say; by Gauss' lemma h divides f₁
and f₂ in Z[δ].  ``lc(f₁) = det(L·Q₁) = lc(h)·lc(f₁/h)`` is not divisible by p, so
``h mod p`` keeps its positive degree and divides both reductions — their gcd is
not 1.  (The modular gcd argument of Brown 1971 / von zur Gathen & Gerhard,
*Modern Computer Algebra*, §6.4, with the lucky-prime condition read off L, as in
:mod:`uio_ring.ring._modular`.)  When the test fails nothing is concluded and the
caller computes exactly.  For a row-reduced M (a weak Popov basis) L has full
row rank, so ``det(L·Q₁) ≢ 0`` except with probability ≤ r/p (Schwartz–Zippel in the
entries of Q₁); a left-prime M then fails the test only when p divides one
resultant-sized integer or, with probability ≤ r·Σ d_i / p, a root of f₁ is one of f₂.

Cost: the rows reduced mod p (one conversion per entry), two r×r determinants by
Bareiss' fraction-free elimination over GF(p)[δ] (O(r³) products of nmod_poly of
degree ≤ Σ d_i, in C) and one gcd — no coefficient growth, against determinants
of Σ bits-sized integers over Z[δ].  Measured on the weak Popov bases that
``uio-ring check`` meets on a random 16-state spec of δ-degree 16
(``benchmarks/random_spec.py --n 16 --degree 16 --seed 1``; rows of degree 160–272
with up to 34 kbit coefficients): 0.25 s at rank 13, against 19.8 s for the exact
compressed minors of Bareiss over Z[δ] at rank 10.

>>> from uio_ring.ring import _backend as bk
>>> d = bk.from_coeffs([0, 1])
>>> left_prime_mod_p([[d, bk.ONE, bk.ZERO]], 1, 3)          # [δ, 1, 0]: the minors δ, 1, 0
True
>>> left_prime_mod_p([[d, d * d, bk.ZERO]], 1, 3)           # δ divides every minor
False
"""

from __future__ import annotations

import random

import flint

from uio_ring.ring import _dense as dn
from uio_ring.ring._fraction_free import integer_rows
from uio_ring.ring._modular import PRIME

__all__ = ["det_nmod", "left_prime_mod_p"]


def det_nmod(a: list[list[flint.nmod_poly]], n: int, p: int) -> flint.nmod_poly:
    """det of the n×n matrix a over GF(p)[δ] by Bareiss' fraction-free elimination
    (exact divisions by the previous pivot, Sylvester's identity; a zero pivot is
    replaced by a row below, which flips the sign).  Precondition: a is n×n over
    GF(p), n ≥ 1 (not checked; a is not modified).

    >>> x = flint.nmod_poly([0, 1], 7)
    >>> det_nmod([[x, flint.nmod_poly([1], 7)], [flint.nmod_poly([6], 7), x]], 2, 7)
    x^2 + 1
    """
    a = [list(r) for r in a]
    sign = 1
    prev = flint.nmod_poly([1], p)
    # Invariant after step k: a[i][j] (i, j > k) is the (k+2)×(k+2) leading minor with row i, column j.
    for k in range(n - 1):
        if a[k][k].is_zero():
            piv = next((i for i in range(k + 1, n) if not a[i][k].is_zero()), None)
            if piv is None:
                return flint.nmod_poly([], p)
            a[k], a[piv] = a[piv], a[k]
            sign = -sign
        akk, row_k = a[k][k], a[k]
        for i in range(k + 1, n):
            aik, row_i = a[i][k], a[i]
            for j in range(k + 1, n):
                row_i[j] = (row_i[j] * akk - aik * row_k[j]) // prev
        prev = akk
    return a[n - 1][n - 1] if sign > 0 else -a[n - 1][n - 1]


def _times_constants_mod_p(
    z: list[list[flint.fmpz_poly]], qs: list[list[list[int]]], r: int, n: int, d: int, p: int
) -> list[list[list[flint.nmod_poly]]]:
    """``z·Q mod p`` for each n×r integer matrix Q of ``qs``, as r×r matrices over GF(p)[δ],
    from one product in C: the coefficient stack (row (e, i): the δ^e-coefficients of
    row i of z, r·(d + 1) × n) times ``[Q₁, Q₂, …]`` (n × r·len(qs)) modulo p — instead of
    r²·n polynomial products in Python per Q.  Precondition: z is r×n of degree ≤ d."""
    cs = [[e.coeffs() for e in row] for row in z]
    stack = flint.nmod_mat(flint.fmpz_mat(r * (d + 1), n, [
        c[e] if e < len(c) else 0 for e in range(d + 1) for row in cs for c in row
    ]), p)
    qcat = flint.nmod_mat(n, r * len(qs), [q[l][j] for l in range(n) for q in qs for j in range(r)], p)
    prod = (stack * qcat).entries()
    width = r * len(qs)
    return [[[flint.nmod_poly([prod[(e * r + i) * width + t * r + j] for e in range(d + 1)], p) for j in range(r)]
             for i in range(r)] for t in range(len(qs))]


def left_prime_mod_p(a: dn.Rows, r: int, n: int, *, p: int = PRIME, seed: int = 1) -> bool:
    """True when the r×n rows ``a`` (over Q[δ]) are proved left prime by the test of the
    module docstring; False proves nothing.  Precondition: a is r×n with 1 ≤ r ≤ n
    (not checked)."""
    z, _ = integer_rows(a)
    degs = [max(e.degree() for e in row) for row in z]
    if min(degs) < 0:
        return False  # a zero row: rank < r
    rng = random.Random(seed)  # fixed: the answer depends only on a, p and seed
    qs = [[[rng.randrange(p) for _ in range(r)] for _ in range(n)] for _ in range(2)]
    lead = flint.nmod_mat(r, n, [int(z[i][j][degs[i]]) if z[i][j].degree() == degs[i] else 0
                                 for i in range(r) for j in range(n)], p)
    if (lead * flint.nmod_mat(n, r, [c for row in qs[0] for c in row], p)).det() == 0:
        return False  # the degree of f₁ mod p is not certified
    f1, f2 = (det_nmod(mq, r, p) for mq in _times_constants_mod_p(z, qs, r, n, max(degs), p))
    # f1 mod p has degree Σ d_i = deg f1 (its leading coefficient is det(L·Q₁) ≠ 0 mod p)
    return bool(f1.gcd(f2).is_one())
