"""Chinese remaindering of polynomial images modulo word primes, and rational
reconstruction with a common denominator, for multimodular paths that certify their
result exactly afterwards (:mod:`uio_ring.ring._monic_det`).

Images are kept as integer polynomials with coefficients in [0, modulus); one prime more
is one Garner step, a polynomial at a time in C (``a + modulus·((b − a)·modulus⁻¹ mod
p)``), instead of a Python step per coefficient.  Reconstruction (Wang's bound) reads the
coefficients in order and stops at the first that has no small fraction, so a candidate
that needs more primes usually costs a few coefficients, not all of them.

>>> p, q = 2305843009213693951, 2305843009213693921
>>> x = [flint.nmod_poly([pow(3, -1, r), -5 * pow(7, -1, r)], r) for r in (p, q)]   # 1/3 − 5δ/7
>>> acc = images_combined(images_combined(None, 1, [x[0]], p), p, [x[1]], q)
>>> proportional_integers(acc, p * q)                                  # 21 times it
[(-15)*x + 7]
"""

from __future__ import annotations

from typing import Any

import flint

__all__ = ["images_combined", "lift", "proportional_integers", "rational_reconstruction"]


def lift(e: flint.nmod_poly) -> flint.fmpz_poly:
    """The integer polynomial whose coefficients are the residues of e, in [0, p).

    >>> lift(flint.nmod_poly([-1, 3], 5))
    3*x + 4
    """
    return flint.fmpz_poly([int(x) for x in e.coeffs()])


def images_combined(
    acc: list[flint.fmpz_poly] | None, modulus: int, img: list[flint.nmod_poly], p: int
) -> list[flint.fmpz_poly]:
    """The polynomials ≡ acc modulo ``modulus`` and ≡ img modulo p (a prime not dividing
    modulus), coefficients in [0, modulus·p): one Garner step per polynomial.  ``acc``
    None: the first images (modulus 1).

    >>> images_combined([flint.fmpz_poly([2])], 3, [flint.nmod_poly([1], 5)], 5)   # 11 ≡ 2 mod 3, 1 mod 5
    [11]
    """
    if acc is None:
        return [lift(e) for e in img]
    u = pow(modulus, -1, p)
    return [a + lift((b - flint.nmod_poly(a, p)) * u) * modulus for a, b in zip(acc, img, strict=True)]


def rational_reconstruction(a: int, m: int) -> tuple[int, int] | None:
    """Wang's rational reconstruction of a mod m: (num, den) with |num|, den ≤ √(m/2),
    den > 0, gcd(num, den) = 1, or None.

    >>> rational_reconstruction(pow(3, -1, 1009), 1009)
    (1, 3)
    """
    bound = flint.fmpz(m // 2).isqrt()
    r0, r1, s0, s1 = m, a % m, 0, 1
    while r1 > bound:
        q = r0 // r1
        r0, r1 = r1, r0 - q * r1
        s0, s1 = s1, s0 - q * s1
    if s1 == 0 or abs(s1) > bound:
        return None
    if s1 < 0:
        r1, s1 = -r1, -s1
    if flint.fmpz(r1).gcd(s1) != 1:
        return None
    return int(r1), int(s1)


def proportional_integers(vals: list[flint.fmpz_poly], modulus: int) -> list[flint.fmpz_poly] | None:
    """Integer polynomials proportional to the rational reconstruction of every coefficient
    of ``vals`` (residues in [0, modulus)) with one common denominator, or None when some
    coefficient has no small fraction.  An entry's coefficients are read only when the
    entries before it passed.

    >>> proportional_integers([flint.fmpz_poly([pow(2, -1, 1009), 5])], 1009)   # 1/2 + 5δ
    [10*x + 1]
    """
    half = modulus // 2
    den = 1
    nums: list[list[Any]] = []
    for entry in vals:
        row: list[Any] = []
        for a in entry.coeffs():
            x: Any = a * den % modulus  # an fmpz, or an int once reconstructed
            if x > half:
                x -= modulus
            if abs(x) * abs(x) * 2 > modulus:  # not small with the current denominator
                rr = rational_reconstruction(int(x), modulus)
                if rr is None:
                    return None
                den *= rr[1]
                row = [c * rr[1] for c in row]
                nums = [[c * rr[1] for c in e] for e in nums]
                x = rr[0]
            row.append(x)
        nums.append(row)
    return [flint.fmpz_poly(e) for e in nums]
