"""Row echelon form and its normalisation over Z[δ], fraction free.

:func:`~uio_ring.ring._echelon.row_echelon` and :func:`~uio_ring.ring._echelon.normalise`
work on ``fmpq_poly``; every operation there pays for a rational canonicalisation
(content and denominator gcds), which dominates on the small entries of an
elimination: python-flint's ``fmpq_poly`` ``a − b·c`` on degree-7 polynomials with
20-bit coefficients costs ≈ 3 µs with denominators and ≈ 0.45 µs on ``fmpz_poly``.
The functions here repeat the same elimination step for step on integer rows, each
row a nonzero rational multiple of the row of the rational elimination (a constant
is a unit of Q[δ], so scaling a row of ``[M | U]`` keeps U unimodular): the same pivot
choices (degrees and row degrees do not see the scaling), the same quotients and
extended-gcd steps with their denominators cleared —

* a quotient ``q = Q/D`` of ``x`` by ``y`` (Euclidean, over Q[δ]; D = 1 when the
  divisor's leading coefficient is ±1) becomes ``row_i ← D·row_i − Q·row_p``, the
  integral form of the pseudo-division of Collins (1967) and Brown (1971) with the
  least multiplier D rather than ``lc(y)^(deg x − deg y + 1)``;
* the xgcd step ``[[s, t], [−y/g, x/g]]`` becomes ``[[D₁s, D₁t], [−D₂y/g, D₂x/g]]``
  (determinant ``D₁D₂``, a unit);
* a row scaled by some D ≠ 1 is divided by its content (the gcd of all its
  coefficients, in M's and in U's part), so that it is the primitive integer form of
  the rational row: no larger than the rational row with a common denominator.

The pivots are not made monic on the way: :func:`to_rational_rows` divides each
pivot row by its pivot's leading coefficient at the end, which gives exactly the rows
of the rational elimination and normalisation (H normalised; the rows of U
that belong to H's nonzero rows).  The rows of U that belong to zero rows of H (a
basis of the left kernel) are rational multiples of the rational elimination's;
callers replace them by their Popov form, which is unique.  A matrix made of columns
of a unimodular integer matrix (the ``tall`` benchmark family) eliminates with unit
pivots and integer quotients throughout: no scaling at all.  The transform's rows are
packed (:class:`Packed`): one ``fmpz_poly`` product per row operation.

Degrees: ``deg 0 = -1``.
"""

from __future__ import annotations

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring._echelon import CoefficientGrowth

__all__ = ["Packed", "Scaled", "identity", "to_integer_rows", "to_rational_rows", "row_echelon_int", "normalise_int"]

IntRows = list[list[flint.fmpz_poly]]
_ZERO = flint.fmpz_poly()
_ONE = flint.fmpz(1)


def to_integer_rows(a: dn.Rows) -> tuple[IntRows, list[flint.fmpz] | None]:
    """The rows as ``fmpz_poly``, each multiplied by the least common denominator of its
    entries: ``(rows, scales)``, ``scales`` None when every row is integral already.

    >>> z, c = to_integer_rows([[bk.from_coeffs([flint.fmpq(1, 2), 1])], [bk.ONE]])
    >>> z, c
    ([[2*x + 1], [1]], [2, 1])
    """
    out: IntRows = []
    scales: list[flint.fmpz] = []
    for row in a:
        den = bk.denominator_lcm(row)
        scales.append(den)
        out.append([e.numer() if den == 1 else (e * den).numer() for e in row])
    return out, (scales if any(c != 1 for c in scales) else None)


def to_rational_rows(z: IntRows | Packed, divisors: list[flint.fmpz] | None = None) -> dn.Rows:
    """The rows as ``fmpq_poly`` (new objects), row k divided by ``divisors[k]`` for
    ``k < len(divisors)``."""
    if isinstance(z, Packed):
        return z.rational_rows(divisors)
    divisors = divisors or []
    out = []
    for k, row in enumerate(z):
        c = divisors[k] if k < len(divisors) else _ONE
        out.append([flint.fmpq_poly(e, c) if not e.is_zero() else bk.ZERO for e in row])
    return out


def pivot_divisors(a: IntRows, pivots: list[int]) -> list[flint.fmpz]:
    """The leading coefficients of the pivots: dividing pivot row k by the k-th makes its
    pivot monic (:func:`to_rational_rows`)."""
    return [a[k][j].leading_coefficient() for k, j in enumerate(pivots)]


class Packed:
    """The rows of an integer polynomial matrix (the transform U of an elimination), each
    packed into one ``fmpz_poly`` by Kronecker substitution: row i is
    ``Σ_c U[i][c]·x^(c·S)``.  A row operation ``U[t] ← D·U[t] − q·U[s]`` is then one product and
    one subtraction in C instead of one per entry (tall 18×16: the transform's share of
    the elimination and normalisation 2.0 → ≈ 1 ms).  ``deg[i]`` bounds the degree of every
    entry of row i; an operation that could reach ``S`` first repacks with a larger S, so
    entries never overlap and the packing is exact.
    """

    __slots__ = ("rows", "deg", "S", "m")

    def __init__(self, m: int, S: int = 32, diagonal: list[flint.fmpz] | None = None) -> None:
        self.m, self.S = m, S
        one = flint.fmpz_poly([1])
        self.rows = [(one if diagonal is None else flint.fmpz_poly([diagonal[i]])).left_shift(i * S)
                     for i in range(m)]
        self.deg = [0] * m

    def _repack(self, need: int) -> None:
        ents = self.entries()
        S = max(2 * self.S, need + 1)
        self.S = S
        self.rows = [_pack(row, S) for row in ents]

    def axpy(self, t: int, q: flint.fmpz_poly, s: int, scale: flint.fmpz = _ONE) -> None:
        """``U[t] ← scale·U[t] − q·U[s]``."""
        d = q.degree() + self.deg[s]
        if d >= self.S:
            self._repack(d)
        rt = self.rows[t] if scale == 1 else self.rows[t] * scale
        self.rows[t] = rt - q * self.rows[s]
        if d > self.deg[t]:
            self.deg[t] = d

    def swap(self, i: int, j: int) -> None:
        self.rows[i], self.rows[j] = self.rows[j], self.rows[i]
        self.deg[i], self.deg[j] = self.deg[j], self.deg[i]

    def content(self, i: int) -> flint.fmpz:
        return self.rows[i].content()

    def divide(self, i: int, g: flint.fmpz) -> None:
        """``U[i] ← U[i]/g`` (exact: g divides every coefficient)."""
        self.rows[i] = self.rows[i] // g

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

    def rational_rows(self, divisors: list[flint.fmpz] | None = None) -> dn.Rows:
        """The rows, unpacked as ``fmpq_poly``, row k divided by ``divisors[k]`` for
        ``k < len(divisors)``."""
        S, m = self.S, self.m
        divisors = divisors or []
        out = []
        for k, r in enumerate(self.rows):
            q = flint.fmpq_poly(r, divisors[k]) if k < len(divisors) else flint.fmpq_poly(r)
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


def _quotient(x: flint.fmpz_poly, y: flint.fmpz_poly) -> tuple[flint.fmpz_poly, flint.fmpz, flint.fmpz_poly]:
    """``(Q, D, R)`` with ``D·x = Q·y + R``: ``Q/D`` the Euclidean quotient of x by y over
    Q[δ] in lowest terms (D ≥ 1; D = 1 when y's leading coefficient is ±1) and ``R/D``
    the remainder.

    >>> x, y = flint.fmpz_poly([1, 0, 1]), flint.fmpz_poly([1, 2])  # δ² + 1 by 2δ + 1
    >>> _quotient(x, y)                                              # q = δ/2 − 1/4
    (2*x + (-1), 4, 5)
    """
    c = y.leading_coefficient()
    if c == 1 or c == -1:
        q, r = divmod(x, y)
        return q, _ONE, r
    qq, rr = divmod(flint.fmpq_poly(x), flint.fmpq_poly(y))
    D = qq.denom()
    return qq.numer(), D, (rr.numer() if D == 1 else (rr * D).numer())


def _scaled_axpy(a: IntRows, u: Packed | None, t: int, D: flint.fmpz, q: flint.fmpz_poly, s: int,
                 j: int) -> None:
    """``row_t ← D·row_t − q·row_s`` on ``[a | u]``, column j of ``a`` excepted (the caller
    sets it: the remainder).  Precondition: row s of ``a`` is zero left of column j."""
    rt, rs = a[t], a[s]
    if D != 1:
        for c in range(len(rt)):
            if c != j and not rt[c].is_zero():
                rt[c] = rt[c] * D
    for c in range(j + 1, len(rt)):
        e = rs[c]
        if not e.is_zero():
            rt[c] = rt[c] - q * e
    if u is not None:
        u.axpy(t, q, s, D)
    if D != 1:
        _make_primitive(a, u, t)


def _make_primitive(a: IntRows, u: Packed | None, i: int) -> None:
    """Divide row i of ``[a | u]`` by the gcd of all its coefficients."""
    g = flint.fmpz(0)
    for e in a[i]:
        if not e.is_zero():
            g = g.gcd(e.content())
            if g == 1:
                return
    if u is not None:
        g = g.gcd(u.content(i))
    if g > 1:
        a[i] = [e // g if not e.is_zero() else e for e in a[i]]
        if u is not None:
            u.divide(i, g)


def _row_degree(row: list[flint.fmpz_poly]) -> int:
    return max([e.degree() for e in row], default=-1)


def _cleared(s: flint.fmpq_poly, t: flint.fmpq_poly) -> tuple[flint.fmpz_poly, flint.fmpz_poly, flint.fmpz]:
    """``(D·s, D·t, D)`` with D the least common denominator of s and t."""
    ds, dt = s.denom(), t.denom()
    D = ds * dt // ds.gcd(dt)
    if D == 1:
        return s.numer(), t.numer(), D
    return (s * D).numer(), (t * D).numer(), D


def _xgcd_step(a: IntRows, u: Packed | None, p: int, i: int, j: int, scaling: bool = True) -> None:
    """:func:`uio_ring.ring._echelon._xgcd_step` (the same cofactors, from python-flint's
    ``xgcd`` over Q) with the denominators of each new row cleared (without ``scaling``:
    :class:`Scaled` instead, rows unchanged)."""
    x, y = flint.fmpq_poly(a[p][j]), flint.fmpq_poly(a[i][j])
    g, s0, t0 = bk.xgcd(x, y)
    s, t, D1 = _cleared(s0, t0)
    xg, yg, D2 = _cleared(x // g, y // g)
    if not scaling and (D1 != 1 or D2 != 1):
        raise Scaled
    rp, ri = a[p], a[i]
    # column j set, not computed: s·a_p + t·a_i = D1·g and xg·a_i − yg·a_p = 0
    gp, zero = (g * D1).numer(), flint.fmpz_poly()
    a[p] = [s * e + t * f if c != j else gp for c, (e, f) in enumerate(zip(rp, ri, strict=True))]
    a[i] = [xg * f - yg * e if c != j else zero for c, (e, f) in enumerate(zip(rp, ri, strict=True))]
    if u is not None:
        u.combine(p, i, s, t, xg, yg)
    if D1 != 1:
        _make_primitive(a, u, p)
    if D2 != 1:
        _make_primitive(a, u, i)


class Scaled(Exception):
    """A step of :func:`row_echelon_int` without ``scaling`` would scale a row."""


def row_echelon_int(
    a: IntRows, u: Packed | None, m: int, n: int, bit_cap: int | None = None, scaling: bool = True
) -> list[int]:
    """:func:`uio_ring.ring._echelon.row_echelon` over Z[δ], step for step (same pivots,
    same operations up to a constant factor per row; a lighter :class:`CoefficientGrowth`
    test, see below).  Without ``scaling``, raises :class:`Scaled` (``a`` and ``u`` half
    transformed) at the first step that would scale a row: an elimination that stays in
    Z[δ] by itself (unit pivots) — the primitive rows of a scaled one grow more slowly
    than the rational rows the cap was set for, so the cap would stop it later."""
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
                    q, D, rem = _quotient(a[i][j], pj)
                    if rem.is_zero():
                        if D != 1 and not scaling:
                            raise Scaled
                        a[i][j] = _ZERO  # the pivot divides: keep its row (as over Q)
                        _scaled_axpy(a, u, i, D, q, p, j)
                    else:
                        _xgcd_step(a, u, p, i, j, scaling)
                continue
            for i in nz:
                if i == p:
                    continue
                q, D, rem = _quotient(a[i][j], pj)
                if D != 1 and not scaling:
                    raise Scaled
                a[i][j] = rem  # the entry: D·a_ij − q·a_pj
                _scaled_axpy(a, u, i, D, q, p, j)
            if bit_cap is not None and max(a[i][j].height_bits() for i in nz) >= bit_cap:
                raise CoefficientGrowth(f"elimination coefficients exceed {bit_cap} bits in column {j}")
        if not nz:
            continue
        p = nz[0]
        if p != r:
            a[p], a[r] = a[r], a[p]
            if u is not None:
                u.swap(p, r)
        pivots.append(j)
        # the growth test: the transform's new pivot row (one packed polynomial) and the
        # next column from the pivot row down (whose entries carry the swell first: tall
        # (n+4)×n of degree 2 stop in 6 ms, 19 ms when only the pivot is watched) —
        # lighter than row_echelon's; the cap only chooses between two paths to the same
        # H and U
        if bit_cap is not None and (
            (u is not None and u.row_bits(r) > bit_cap)
            or max(a[i][j + 1].height_bits() if j + 1 < n else 0 for i in range(r, m)) >= bit_cap
        ):
            raise CoefficientGrowth(f"elimination coefficients exceed {bit_cap} bits at column {j}")
        r += 1
    return pivots


def normalise_int(a: IntRows, u: Packed | None, pivots: list[int]) -> None:
    """:func:`uio_ring.ring._echelon.normalise` over Z[δ], step for step, without making
    the pivots monic (:func:`to_rational_rows` with :func:`pivot_divisors` does that):
    bottom-up, the entries of row k above the pivots of rows k+1, … reduced by those
    rows (``row_k ← D·row_k − Q·row_i``, :func:`_quotient`)."""
    r = len(pivots)
    for k in range(r - 1, -1, -1):
        for i in range(k + 1, r):
            ji = pivots[i]
            piv = a[i][ji]
            if a[k][ji].degree() >= piv.degree():
                q, D, a[k][ji] = _quotient(a[k][ji], piv)  # the entry: D·a_kji − q·piv
                _scaled_axpy(a, u, k, D, q, i, ji)


def identity(m: int, diagonal: list[flint.fmpz] | None = None) -> Packed:
    """The m×m identity (or the diagonal matrix ``diagonal``), packed: the transform of an
    elimination of rows that were scaled by ``diagonal`` (:func:`to_integer_rows`)."""
    return Packed(m, diagonal=diagonal)
