"""Row echelon form and its normalisation over Z[δ], for integer matrices whose
elimination over Q[δ] never leaves the integers.

:func:`~uio_ring.ring._echelon.row_echelon` and :func:`~uio_ring.ring._echelon.normalise`
work on ``fmpq_poly``; every operation there pays for a rational canonicalisation
(content and denominator gcds), which dominates on the small entries of an
elimination: python-flint's ``fmpq_poly`` subtraction of two degree-29 polynomials
costs ≈ 1.1 µs, the ``fmpz_poly`` one ≈ 0.16 µs.  The functions here repeat the same
elimination step for step — the same pivot choices (degrees and row degrees are
the same over Z), the same quotients (Euclidean quotients over Q[δ], computed over
Z when the divisor's leading coefficient is ±1, else over Q and accepted only when
integral), the same extended-gcd steps (computed over Q, accepted only when every
cofactor is integral) — on ``fmpz_poly`` entries, and raise :class:`NotIntegral` as
soon as a step would leave Z[δ].  Since both are exact, a run that finishes gives
exactly the rows of the rational elimination; a run that raises is redone over Q
by the caller.  The transform's rows are packed (:class:`Packed`): one ``fmpz_poly``
product per row operation.  A matrix made of columns of a unimodular integer matrix
(the ``tall`` benchmark family) eliminates with unit pivots and integer quotients
throughout: the elimination and the back substitution of a 22×20 take 2.7 + 1.1 ms
(and 0.6 ms to convert back) instead of 4.0 + 3.2 ms over Q.

Degrees: ``deg 0 = -1``.
"""

from __future__ import annotations

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring._echelon import CoefficientGrowth

__all__ = ["NotIntegral", "Packed", "identity", "to_integer_rows", "to_rational_rows", "row_echelon_int",
           "normalise_int"]

IntRows = list[list[flint.fmpz_poly]]
_ZERO = flint.fmpz_poly()



class NotIntegral(Exception):
    """A step of the elimination would leave Z[δ] (the caller redoes it over Q)."""


def to_integer_rows(a: dn.Rows) -> IntRows | None:
    """The rows as ``fmpz_poly``, or None when an entry has a denominator."""
    out: IntRows = []
    for row in a:
        zrow = []
        for e in row:
            if e.denom() != 1:
                return None
            zrow.append(e.numer())
        out.append(zrow)
    return out


def to_rational_rows(z: IntRows | Packed) -> dn.Rows:
    """The rows as ``fmpq_poly`` (new objects)."""
    if isinstance(z, Packed):
        return z.rational_rows()
    return [[flint.fmpq_poly(e) if not e.is_zero() else bk.ZERO for e in row] for row in z]


class Packed:
    """The rows of an integer polynomial matrix (the transform U of an elimination), each
    packed into one ``fmpz_poly`` by Kronecker substitution: row i is
    ``Σ_c U[i][c]·x^(c·S)``.  A row operation ``U[t] −= q·U[s]`` is then one product and
    one subtraction in C instead of one per entry (tall 18×16: the transform's share of
    the elimination and normalisation 2.0 → ≈ 1 ms).  ``deg[i]`` bounds the degree of every
    entry of row i; an operation that could reach ``S`` first repacks with a larger S, so
    entries never overlap and the packing is exact.
    """

    __slots__ = ("rows", "deg", "S", "m")

    def __init__(self, m: int, S: int = 32) -> None:
        self.m, self.S = m, S
        one = flint.fmpz_poly([1])
        self.rows = [one.left_shift(i * S) for i in range(m)]
        self.deg = [0] * m

    def _repack(self, need: int) -> None:
        ents = self.entries()
        S = max(2 * self.S, need + 1)
        self.S = S
        self.rows = [_pack(row, S) for row in ents]

    def axpy(self, t: int, q: flint.fmpz_poly, s: int) -> None:
        """``U[t] −= q·U[s]``."""
        d = q.degree() + self.deg[s]
        if d >= self.S:
            self._repack(d)
        self.rows[t] = self.rows[t] - q * self.rows[s]
        if d > self.deg[t]:
            self.deg[t] = d

    def swap(self, i: int, j: int) -> None:
        self.rows[i], self.rows[j] = self.rows[j], self.rows[i]
        self.deg[i], self.deg[j] = self.deg[j], self.deg[i]

    def negate(self, i: int) -> None:
        self.rows[i] = -self.rows[i]

    def combine(self, p: int, i: int, s: flint.fmpz_poly, t: flint.fmpz_poly,
                xg: flint.fmpz_poly, yg: flint.fmpz_poly) -> None:
        """``U[p], U[i] = s·U[p] + t·U[i], xg·U[i] − yg·U[p]``."""
        dp, di = self.deg[p], self.deg[i]
        dnew_p = max(s.degree() + dp, t.degree() + di)
        dnew_i = max(xg.degree() + di, yg.degree() + dp)
        if max(dnew_p, dnew_i) >= self.S:
            self._repack(max(dnew_p, dnew_i))
        rp, ri = self.rows[p], self.rows[i]
        self.rows[p] = s * rp + t * ri
        self.rows[i] = xg * ri - yg * rp
        self.deg[p], self.deg[i] = max(dnew_p, 0), max(dnew_i, 0)

    def row_bits(self, i: int) -> int:
        """:func:`_max_bits` of row i (0 for a zero row)."""
        r = self.rows[i]
        return 0 if r.is_zero() else _bits(r)

    def entries(self) -> IntRows:
        """The rows, unpacked."""
        S, m = self.S, self.m
        return [[r.truncate(S) if c == 0 else r.right_shift(c * S).truncate(S) for c in range(m)]
                for r in self.rows]

    def rational_rows(self) -> dn.Rows:
        """The rows, unpacked as ``fmpq_poly``."""
        S, m = self.S, self.m
        out = []
        for r in self.rows:
            q = flint.fmpq_poly(r)
            out.append([q.truncate(S) if c == 0 else q.right_shift(c * S).truncate(S) for c in range(m)])
        return out


def _pack(row: list[flint.fmpz_poly], S: int) -> flint.fmpz_poly:
    out = flint.fmpz_poly()
    for c, e in enumerate(row):
        if not e.is_zero():
            out = out + e.left_shift(c * S)
    return out


def _bits(p: flint.fmpz_poly) -> int:
    """:func:`~uio_ring.ring._backend.bits` of p as an ``fmpq_poly`` (denominator 1: one bit)."""
    return int(p.height_bits()) + 1


def max_bits(z: IntRows) -> int:
    """:func:`~uio_ring.ring._echelon.max_bits` of the integer rows (the same number as
    for them as ``fmpq_poly``)."""
    return max((int(e.height_bits()) for row in z for e in row if not e.is_zero()), default=-1) + 1


def _max_bits(rows: IntRows) -> int:
    return max((_bits(p) for row in rows for p in row if not p.is_zero()), default=0)


def _quotient_remainder(x: flint.fmpz_poly, y: flint.fmpz_poly) -> tuple[flint.fmpz_poly, flint.fmpz_poly]:
    """The Euclidean quotient q of x by y over Q[δ] and the remainder ``x − q·y``, when q
    is integral (then so is the remainder); raises :class:`NotIntegral` otherwise."""
    c = y.leading_coefficient()
    if c == 1 or c == -1:
        return divmod(x, y)
    qq, rr = divmod(flint.fmpq_poly(x), flint.fmpq_poly(y))
    if qq.denom() != 1:
        raise NotIntegral
    return qq.numer(), rr.numer()


def _divmod(x: flint.fmpz_poly, y: flint.fmpz_poly) -> tuple[flint.fmpz_poly, bool]:
    """(quotient over Q[δ], remainder is zero); raises when the quotient is not integral."""
    c = y.leading_coefficient()
    if c == 1 or c == -1:
        q, rem = divmod(x, y)
        return q, rem.is_zero()
    qq, rr = divmod(flint.fmpq_poly(x), flint.fmpq_poly(y))
    if qq.denom() != 1:
        raise NotIntegral
    return qq.numer(), rr.is_zero()


def _axpy(a: IntRows, target: int, q: flint.fmpz_poly, source: int, start: int = 0) -> None:
    """``a[target] -= q * a[source]`` on columns ``start:`` (:func:`~uio_ring.ring._dense.row_axpy`)."""
    rt, rs = a[target], a[source]
    for j in range(start, len(rt)):
        s = rs[j]
        if not s.is_zero():
            rt[j] = rt[j] - q * s


def _row_degree(row: list[flint.fmpz_poly]) -> int:
    return max([e.degree() for e in row], default=-1)


def _integral(p: flint.fmpq_poly) -> flint.fmpz_poly:
    if p.denom() != 1:
        raise NotIntegral
    return p.numer()


def _xgcd_step(a: IntRows, u: Packed | None, p: int, i: int, j: int) -> None:
    """:func:`uio_ring.ring._echelon._xgcd_step` (the same cofactors, from python-flint's
    ``xgcd`` over Q), when they are all integral."""
    x, y = flint.fmpq_poly(a[p][j]), flint.fmpq_poly(a[i][j])
    g, s, t = bk.xgcd(x, y)
    xg, yg = _integral(x // g), _integral(y // g)
    s, t = _integral(s), _integral(t)
    rp, ri = a[p], a[i]
    a[p] = [s * e + t * f for e, f in zip(rp, ri, strict=True)]
    a[i] = [xg * f - yg * e for e, f in zip(rp, ri, strict=True)]
    if u is not None:
        u.combine(p, i, s, t, xg, yg)


def row_echelon_int(a: IntRows, u: Packed | None, m: int, n: int, bit_cap: int | None = None) -> list[int]:
    """:func:`uio_ring.ring._echelon.row_echelon` over Z[δ], step for step (same pivots,
    same operations; a lighter :class:`CoefficientGrowth` test, see below); raises
    :class:`NotIntegral` (``a`` and ``u`` half transformed) when a step would leave Z[δ]."""
    r = 0
    pivots: list[int] = []
    for j in range(n):
        if r == m:
            break
        while True:
            nz = [i for i in range(r, m) if not a[i][j].is_zero()]
            if len(nz) <= 1:
                break
            degs = [a[i][j].degree() for i in nz]
            least = min(degs)
            ties = [i for i, d in zip(nz, degs, strict=True) if d == least]
            p = ties[0] if len(ties) == 1 else min(ties, key=lambda i: (_row_degree(a[i]), i))
            pj = a[p][j]
            if len(nz) == 2:
                for i in nz:
                    if i == p:
                        continue
                    q, exact = _divmod(a[i][j], pj)
                    if exact:
                        a[i][j] = _ZERO  # = a_ij − q·a_pj
                        _axpy(a, i, q, p, j + 1)
                        if u is not None:
                            u.axpy(i, q, p)
                    else:
                        _xgcd_step(a, u, p, i, j)
                continue
            for i in nz:
                if i == p:
                    continue
                q, a[i][j] = _quotient_remainder(a[i][j], pj)  # the entry: a_ij − q·a_pj
                _axpy(a, i, q, p, j + 1)
                if u is not None:
                    u.axpy(i, q, p)
        if not nz:
            continue
        p = nz[0]
        if p != r:
            a[p], a[r] = a[r], a[p]
            if u is not None:
                u.swap(p, r)
        pivots.append(j)
        # the growth test: the transform's new pivot row (one packed polynomial) and the
        # pivot — lighter than row_echelon's (which also watches the rest of the pivot
        # row and the next column); the cap only chooses between two paths to the same
        # H and U, and an elimination that stays in Z[δ] has no rational swell
        if bit_cap is not None and (
            (u is not None and u.row_bits(r) > bit_cap) or a[r][j].height_bits() >= bit_cap
        ):
            raise CoefficientGrowth(f"elimination coefficients exceed {bit_cap} bits at column {j}")
        r += 1
    return pivots


def normalise_int(a: IntRows, u: Packed | None, pivots: list[int]) -> None:
    """:func:`uio_ring.ring._echelon.normalise` over Z[δ], step for step; raises
    :class:`NotIntegral` (rows half normalised) when a pivot's leading coefficient is
    not ±1 or a quotient is not integral."""
    r = len(pivots)
    for k in range(r - 1, -1, -1):
        j = pivots[k]
        c = a[k][j].leading_coefficient()
        if c != 1:
            if c != -1:
                raise NotIntegral
            a[k] = [-x for x in a[k]]
            if u is not None:
                u.negate(k)
        for i in range(k + 1, r):
            ji = pivots[i]
            piv = a[i][ji]
            if a[k][ji].degree() >= piv.degree():
                q, a[k][ji] = _quotient_remainder(a[k][ji], piv)  # the entry: a_kji − q·piv
                _axpy(a, k, q, i, ji + 1)
                if u is not None:
                    u.axpy(k, q, i)


def identity(m: int) -> Packed:
    """The m×m identity, packed (the transform of an elimination)."""
    return Packed(m)
