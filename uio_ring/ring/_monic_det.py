"""The monic determinant of a square matrix over Z[δ] from a certified primitive kernel vector.

Let W be n×n over Z[δ] with det W ≠ 0, i one of its rows and R = W without row i,
and suppose R is *left prime* (its (n−1)-minors have no common factor, e.g. proved
by :func:`~uio_ring.ring._left_prime.left_prime_mod_p`).  The signed cofactor vector
m of R (m_c = (−1)^c·det R without column c) spans the right kernel of R over Q(δ),
has coprime entries, and ``w_i·m = ±det W`` (Laplace along row i).  If v is any
nonzero vector over Z[δ] with ``R·v = 0`` whose entries have no common factor of
positive degree, then ``v = q·m`` with q ∈ Q[δ] (m generates the polynomial kernel)
and gcd(v) = q·gcd(m) forces q ∈ Q*, so::

    monic det W = monic(w_i · v).

v is found multimodularly and then *checked*: modulo word-size primes p the
cofactor vector of R is n determinants over GF(p)[δ], all from one Bareiss
elimination of R and a back substitution (:func:`_cofactors_mod_p`); scaled so that one fixed coefficient is 1 it
is ``v/v_c[e] mod p`` for every prime that divides neither that coefficient nor the
integer content of m (other primes are seen as a zero vector or a zero
coefficient and skipped).  The images are combined by the Chinese remainder theorem and every
coefficient is rationally reconstructed (Wang's bound, a common denominator tried
first); the candidate is accepted only when ``R·v = 0`` holds exactly over Z[δ] and
its entries are made coprime by their exact gcd.  A candidate that fails the check
costs more primes, so the result never rests on the reconstruction being right.

Why: a weak Popov basis W of the modules met by ``uio-ring check`` carries a huge
integer content in its minors (random 8-state spec of δ-degree 16: cofactors of
7.6 kbit = 7.5 kbit content × a 140-bit primitive v of degree 528), so the exact
Bareiss determinant of W computes megabits that the monic result divides away.

Cost: per prime, one Bareiss elimination of the (n−1)×n matrix R over GF(p)[δ]
(O(n³/3) products of degree ≤ Σ row degrees) and a back substitution (O(n²/2));
about ``2·bits(v)/62 + 1`` primes (from 2^62 up); one exact product R·v.  Random 16-state spec of δ-degree 16: f of degree
2720 from rows of up to 48 kbit in 34 s, where Bareiss over Z[δ] ran over 13 minutes;
from the 4.2 kbit rows that ``uio-ring check`` now meets there, 8 s for 23 primes
(v of 697 bits; 16 s with the n unit rows eliminated alongside R).

v also decides membership in the row module of W (:func:`in_row_module`).

>>> from uio_ring.ring import _backend as bk
>>> d = bk.from_coeffs([0, 1])
>>> W = [[bk.ONE, d], [bk.ZERO, d + 1]]
>>> monic_det_by_kernel([[p.numer() for p in row] for row in W], 2, 1)
x + 1
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import flint

from uio_ring import _progress
from uio_ring.ring._crt import images_combined, proportional_integers
from uio_ring.ring._left_prime import det_nmod

__all__ = ["KernelDet", "in_row_module", "kernel_det", "monic_det_by_kernel"]

_FIRST_PRIME = 1 << 62
_MAX_PRIMES = 400


def _primes(start: int) -> Iterator[int]:
    """The first ``_MAX_PRIMES`` primes ≥ start (deterministic; word-size for the default start)."""
    q, found = start, 0
    while found < _MAX_PRIMES:
        if flint.fmpz(q).is_prime():
            found += 1
            yield q
        q += 1


def _cofactors_mod_p(r: list[list[flint.fmpz_poly]], n: int, p: int) -> list[flint.nmod_poly]:
    """``m_c = det [R; e_c]`` (c = 0 … n−1) over GF(p)[δ] for the (n−1)×n rows r = R: a kernel
    vector of R (``R_i·m = det [R; R_i] = 0``), the signed cofactors.

    One Bareiss elimination of R (row swaps where a pivot is zero, ``sign`` their parity)
    to the upper trapezoidal T = L·R, L invertible over GF(p)(δ), whose diagonal entries
    are the leading minors of the permuted R (Sylvester's identity), so the last one is
    ``sign·det R[:, :n−1] = sign·m_{n−1}`` (Laplace along the unit row of ``[R; e_{n−1}]``).
    Once the leading (n−1)×(n−1) block is nonsingular the kernel of R is the line of m,
    so back substitution ``x_k = −(Σ_{j>k} T_kj·x_j) / T_kk`` from ``x_{n−1} = m_{n−1}``
    gives ``x = m``, every division exact (Cramer: the entries of m are polynomials;
    checked).  O(n³/3) products for the elimination and O(n²/2) for the substitution,
    against n·O(n²) more for the n unit rows eliminated alongside (the previous method,
    random 16-state spec: 0.65 s per prime).  When no row of R has a nonzero entry in a
    pivot column the n determinants are taken one by one
    (:func:`~uio_ring.ring._left_prime.det_nmod`)."""
    rp = [[flint.nmod_poly(e, p) for e in row] for row in r]
    zero, one = flint.nmod_poly([], p), flint.nmod_poly([1], p)

    def one_by_one() -> list[flint.nmod_poly]:
        return [det_nmod(rp + [[one if j == c else zero for j in range(n)]], n, p) for c in range(n)]

    a = [list(row) for row in rp]
    sign = 1
    prev = one
    for k in range(n - 1):
        if a[k][k].is_zero():
            piv = next((i for i in range(k + 1, n - 1) if not a[i][k].is_zero()), None)
            if piv is None:
                return one_by_one()
            a[k], a[piv] = a[piv], a[k]
            sign = -sign
        akk, row_k = a[k][k], a[k]
        for i in range(k + 1, n - 1):
            aik, row_i = a[i][k], a[i]
            for j in range(k + 1, n):
                row_i[j] = (row_i[j] * akk - aik * row_k[j]) // prev
        prev = akk
    x = [zero] * n
    x[n - 1] = a[n - 2][n - 2] if sign > 0 else -a[n - 2][n - 2]
    for k in range(n - 2, -1, -1):
        acc = zero
        for j in range(k + 1, n):
            if not a[k][j].is_zero() and not x[j].is_zero():
                acc += a[k][j] * x[j]
        q, rem = divmod(-acc, a[k][k])
        if not rem.is_zero():  # pragma: no cover - Cramer: cannot happen
            return one_by_one()
        x[k] = q
    return x


@dataclass(frozen=True)
class KernelDet:
    """``f``: monic det W; ``v``: the primitive kernel vector of W without row i (over Z[δ])."""

    f: flint.fmpq_poly
    v: list[flint.fmpz_poly]


def in_row_module(x: list[flint.fmpq_poly], kd: KernelDet) -> bool:
    """True iff the row x lies in the row module L(W) of the W behind ``kd`` (W without
    row i left prime, the precondition of :func:`kernel_det`).

    Proof: ``φ(y) = (y·v) mod f`` maps Q[δ]^n onto Q[δ]/(f) (gcd(v) = 1, so some y has
    y·v = 1) and vanishes on L(W) (``w_j·v = 0`` for j ≠ i, ``w_i·v`` = const·f).  Both
    ker φ and L(W) have Q-codimension deg f = deg det W, so ``L(W) = ker φ``.

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> kd = kernel_det([[p.numer() for p in row] for row in [[bk.ONE, d], [bk.ZERO, d + 1]]], 2, 1)
    >>> in_row_module([bk.ZERO, d * d + d], kd), in_row_module([bk.ZERO, d], kd)
    (True, False)
    """
    xv = sum((flint.fmpq_poly(xj) * vj for xj, vj in zip(x, kd.v, strict=True)), flint.fmpq_poly(0))
    return bool((xv % kd.f).is_zero())


def monic_det_by_kernel(w: list[list[flint.fmpz_poly]], n: int, i: int, *,
                        first_prime: int = _FIRST_PRIME) -> flint.fmpq_poly | None:
    """:func:`kernel_det` without the kernel vector."""
    kd = kernel_det(w, n, i, first_prime=first_prime)
    return None if kd is None else kd.f


def kernel_det(w: list[list[flint.fmpz_poly]], n: int, i: int, *,
               first_prime: int = _FIRST_PRIME) -> KernelDet | None:
    """monic det W for the n×n rows w over Z[δ] (n ≥ 2, det W ≠ 0), given that W without
    row i is left prime (module docstring; preconditions not checked).  Without that
    precondition the result is ``monic det W / monic gcd`` of the (n−1)-minors of W without
    row i (v is then the cofactor vector divided by that gcd).  None when no candidate
    passed the exact check within the prime budget (``_MAX_PRIMES`` primes from
    ``first_prime``; small values serve tests that meet unlucky primes)."""
    r = [w[j] for j in range(n) if j != i]
    modulus = 1
    acc: list[flint.fmpz_poly] | None = None  # the images so far, coefficients in [0, modulus)
    norm: tuple[int, int] | None = None
    with _progress.detail(f"the monic determinant of a {n}×{n} by its cofactors modulo primes") as tell:
        for count, p in enumerate(_primes(first_prime), 1):
            tell(f"prime {count} of at most {_MAX_PRIMES}")
            m = _cofactors_mod_p(r, n, p)
            if all(e.is_zero() for e in m):
                continue  # p divides the content of the cofactors
            if norm is None:
                c = max(range(n), key=lambda j: (m[j].degree(), j))
                norm = (c, m[c].degree())
            lc = int(m[norm[0]][norm[1]]) if m[norm[0]].degree() >= norm[1] else 0
            if lc == 0:
                continue  # unlucky: p divides the normalising coefficient
            inv = pow(lc, -1, p)
            acc = images_combined(acc, modulus, [e * inv for e in m], p)
            modulus *= p
            v = proportional_integers(acc, modulus)
            if v is None or all(e.is_zero() for e in v):
                continue
            zero = flint.fmpz_poly(0)
            if any(sum((row[j] * v[j] for j in range(n)), zero) != 0 for row in r):
                continue  # R·v = 0 fails: not yet enough primes
            g = zero
            for e in v:
                g = g.gcd(e)
            v = [e // g for e in v]  # exact: g divides every entry; now gcd(v) = 1
            det = sum((w[i][j] * v[j] for j in range(n)), zero)
            if det.is_zero():  # pragma: no cover - det W ≠ 0 by the precondition
                return None
            return KernelDet(flint.fmpq_poly(det) / det[det.degree()], v)
        return None
