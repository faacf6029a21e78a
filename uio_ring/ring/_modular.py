"""Coprimality of two determinants over Z[δ], proved modulo one word-size prime.

Let f, g ∈ Z[δ], let b ≥ deg f be a proven degree bound and p a prime.  If
``deg (f mod p) = b`` and ``gcd(f mod p, g mod p) = 1`` in GF(p)[δ], then f and g
are coprime in Q[δ].  Proof: a common factor of positive degree can be taken
primitive in Z[δ], h say; by Gauss' lemma h divides f and g in Z[δ].  From
``b ≥ deg f ≥ deg (f mod p) = b``, p does not divide lc(f) = lc(h)·lc(f/h), so
``h mod p`` keeps its degree ≥ 1 and divides both reductions — their gcd is not 1.
(The modular gcd argument of Brown 1971 / von zur Gathen & Gerhard, *Modern
Computer Algebra*, §6.4, with the lucky-prime condition read off the degree.)

``f mod p`` is ``det Z(x) mod p`` at ``b + 1`` points of GF(p) (flint ``nmod_mat``,
O(n³) word operations each), interpolated by a subproduct tree in GF(p)[δ]: no
coefficient growth at all, against the ~n·bits-sized integers of an exact
determinant.  When the test fails (the bound is not attained, or an unlucky prime),
nothing is concluded and the callers compute exactly.

>>> from uio_ring.ring import _backend as bk
>>> d = bk.from_coeffs([0, 1])
>>> f = [[d, bk.ONE], [bk.const(-1), d]]          # det = δ² + 1
>>> g = [[d, bk.ZERO], [bk.ZERO, d + 1]]          # det = δ² + δ
>>> coprime_dets_mod_p(f, g, 2)
True
>>> coprime_dets_mod_p(f, [[d * d + 1]], 2, k2=1)  # δ² + 1 twice: nothing proved
False
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import flint

from uio_ring.ring import _dense as dn
from uio_ring.ring import _evaluation as ev
from uio_ring.ring._fraction_free import integer_rows

__all__ = ["PRIME", "ModularGcd", "det_mod_p", "coprime_dets_mod_p", "gcd_mod_p"]

#: A word-size prime (2^61 − 1): far more points than any degree bound in the limits.
PRIME = (1 << 61) - 1


def _tree_sum(xs: Sequence[int], zs: Sequence[int], p: int) -> tuple[flint.nmod_poly, flint.nmod_poly]:
    """``(Σ_i z_i Π_{j≠i} (δ − x_j), Π_j (δ − x_j))`` over GF(p), by halving."""
    if len(xs) == 1:
        return flint.nmod_poly([zs[0]], p), flint.nmod_poly([(-xs[0]) % p, 1], p)
    h = len(xs) // 2
    sl, pl = _tree_sum(xs[:h], zs[:h], p)
    sr, pr = _tree_sum(xs[h:], zs[h:], p)
    return pr * sl + pl * sr, pl * pr


def _interpolate_mod_p(xs: Sequence[int], ys: Sequence[int], p: int) -> flint.nmod_poly:
    """The polynomial of degree < len(xs) through the points, over GF(p) (Lagrange:
    weights ``P'(x_i)`` with P = Π (δ − x_j)).  Precondition: distinct xs mod p."""
    _, prod = _tree_sum(xs, [0] * len(xs), p)
    dprod = prod.derivative()
    zs = [int(flint.nmod(y, p) / dprod(x)) for x, y in zip(xs, ys, strict=True)]
    return _tree_sum(xs, zs, p)[0]


def det_mod_p(a: dn.Rows, k: int, p: int = PRIME) -> tuple[flint.nmod_poly, int]:
    """``(det Z mod p, b)`` for Z = a with every row scaled to Z[δ] (a unit of Q[δ] per row)
    and b the degree bound of :func:`~uio_ring.ring._evaluation.minor_degree_bound`.
    Precondition: a is k×k, k ≥ 1 (not checked).

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> det_mod_p([[d, bk.const(2)], [bk.const(3), d]], 2)    # δ² − 6, within the bound 2
    (x^2 + 2305843009213693945, 2)
    >>> det_mod_p([[d, bk.ZERO, bk.ONE], [bk.ONE, d, bk.ZERO], [bk.ZERO, bk.ONE, d]], 3)[0]
    x^3 + 1
    """
    z, _ = integer_rows(a)
    bound = ev.minor_degree_bound(a, k, k, k)
    if k <= 2:  # the products themselves: one or two in GF(p)[δ], no evaluation points
        e = [[flint.nmod_poly([int(c) % p for c in q.coeffs()], p) for q in r] for r in z]
        return (e[0][0] if k == 1 else e[0][0] * e[1][1] - e[0][1] * e[1][0]), bound
    deg = max((q.degree() for r in z for q in r), default=0)
    coeffs = [
        flint.nmod_mat(k, k, [int(q[e]) % p if e <= q.degree() else 0 for r in z for q in r], p)
        for e in range(max(deg, 0) + 1)
    ]
    xs = list(range(bound + 1))
    ys = []
    for x in xs:
        acc = coeffs[-1]
        for c in reversed(coeffs[:-1]):
            acc = acc * x + c
        ys.append(int(acc.det()))
    return _interpolate_mod_p(xs, ys, p), bound


def coprime_dets_mod_p(a1: dn.Rows, a2: dn.Rows, k: int, *, k2: int | None = None, p: int = PRIME) -> bool:
    """True when det a1 and det a2 (k×k and k2×k2, k2 = k by default) are proved coprime in
    Q[δ] by the test of the module docstring; False proves nothing."""
    return gcd_mod_p(a1, a2, k, k2=k2, p=p).proves_coprime


@dataclass(frozen=True)
class ModularGcd:
    """``gcd(det a1 mod p, det a2 mod p)``: its ``degree`` (−1 when ``det a2 mod p`` is 0),
    and whether ``det a1 mod p`` ``attained`` its degree bound (then det a1 keeps its
    leading coefficient mod p).  Degree 0 with the bound attained proves det a1, det a2
    coprime (module docstring); a positive degree is evidence of a common factor over Q —
    unless p divides their resultant, which is unlikely for a 61-bit p — and proves
    nothing, attained or not."""

    degree: int
    attained: bool

    @property
    def proves_coprime(self) -> bool:
        return self.attained and self.degree == 0


def gcd_mod_p(a1: dn.Rows, a2: dn.Rows, k: int, *, k2: int | None = None, p: int = PRIME) -> ModularGcd:
    """The :class:`ModularGcd` of det a1 (k×k) and det a2 (k2×k2, k2 = k by default).

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> gcd_mod_p([[d * d + 1]], [[d * d * d + d]], 1)  # δ² + 1 divides δ³ + δ
    ModularGcd(degree=2, attained=True)
    """
    f, bound = det_mod_p(a1, k, p)
    g, _ = det_mod_p(a2, k if k2 is None else k2, p)
    return ModularGcd(-1 if g.is_zero() else int(f.gcd(g).degree()), f.degree() == bound >= 0)

