"""Evaluation and interpolation: exact Q[δ] answers from computations over Q.

A polynomial matrix is evaluated at distinct integer points; linear algebra
over Q runs in C (flint ``fmpq_mat``); results of bounded degree are recovered
by interpolation.  Deterministic: the number of points always comes from a
proven degree bound, never from a random guess.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn

__all__ = [
    "Coefficients",
    "coefficient_mats",
    "points",
    "first_points",
    "evaluate",
    "det_at",
    "interpolate",
    "interpolate_columns",
    "minor_degree_bound",
]


@dataclass(frozen=True)
class Coefficients:
    """An m×n polynomial matrix M as integer coefficient matrices, row i scaled by the
    least common denominator ``dens[i]`` of its coefficients:
    ``M = diag(dens)⁻¹·(Z_0 + Z_1 δ + …)`` (:func:`coefficient_mats`).

    Horner's rule then runs over Z (flint ``fmpz_mat``) and divides once at the end:
    over Q every step normalised a fraction per entry — 50× slower on a 16×8 of
    δ-degree 103 with 4.2-kbit coefficients (13 s against 0.25 s at 168 points).  A
    scale per row, not one for the whole matrix: rows with different denominators
    would otherwise carry each other's (the determinants of a degree-reduced 16×16 were
    4× slower)."""

    mats: list[flint.fmpz_mat]
    dens: list[flint.fmpz]
    inverse_scale: flint.fmpq_mat | None  # diag(dens)⁻¹, None when every dens[i] is 1


def coefficient_mats(a: dn.Rows, m: int, n: int) -> Coefficients:
    """The integer coefficient matrices of the m×n rows ``a`` (:class:`Coefficients`;
    one zero matrix for a zero matrix).

    >>> from fractions import Fraction
    >>> c = coefficient_mats([[bk.from_coeffs([Fraction(1, 2), 1])], [bk.from_coeffs([0, 3])]], 2, 1)
    >>> [int(d) for d in c.dens], evaluate(c, 2).tolist(), det_at(coefficient_mats([[bk.from_coeffs([0, 3])]], 1, 1), 2)
    ([2, 1], [[5/2], [6]], 6)
    """
    deg = max(dn.mat_degree(a), 0)
    mats = [flint.fmpq_mat(m, n, [p[e] for r in a for p in r]) for e in range(deg + 1)]
    pairs = [c.numer_denom() for c in mats]
    if all(d == 1 for _, d in pairs):
        return Coefficients([z for z, _ in pairs], [flint.fmpz(1)] * m, None)
    dens = [bk.denominator_lcm(row) for row in a]
    scale = flint.fmpq_mat(m, m, [dens[i] if i == j else 0 for i in range(m) for j in range(m)])
    inverse = flint.fmpq_mat(m, m, [flint.fmpq(1, dens[i]) if i == j else 0
                                    for i in range(m) for j in range(m)])
    return Coefficients([(scale * c).numer_denom()[0] for c in mats], dens, inverse)


def points() -> Iterator[int]:
    """0, 1, −1, 2, −2, … (small integers keep the evaluated entries small)."""
    yield 0
    k = 1
    while True:
        yield k
        yield -k
        k += 1


def first_points(count: int) -> list[int]:
    """The first ``count`` points of :func:`points`."""
    out: list[int] = []
    for x in points():
        if len(out) == count:
            break
        out.append(x)
    return out


def _weights(xs: Sequence[int]) -> list[int]:
    """``W_i = Π_{j≠i} (x_i − x_j)`` (nonzero integers for distinct xs)."""
    out = []
    for i, xi in enumerate(xs):
        w = 1
        for j, xj in enumerate(xs):
            if j != i:
                w *= xi - xj
        out.append(w)
    return out


def _lagrange_sum(xs: Sequence[int], zs: Sequence[flint.fmpq]) -> tuple[flint.fmpq_poly, flint.fmpq_poly]:
    """``(Σ_i z_i Π_{j≠i} (δ − x_j), Π_j (δ − x_j))`` by halving (a subproduct tree):
    ``S = P_right·S_left + P_left·S_right``.  O(M(N) log N) operations in C."""
    if len(xs) == 1:
        return flint.fmpq_poly([zs[0]]), flint.fmpq_poly([-xs[0], 1])
    h = len(xs) // 2
    sl, pl = _lagrange_sum(xs[:h], zs[:h])
    sr, pr = _lagrange_sum(xs[h:], zs[h:])
    return pr * sl + pl * sr, pl * pr


def interpolate_columns(values: flint.fmpq_mat, xs: Sequence[int] | None = None) -> list[flint.fmpq_poly]:
    """Interpolate every column of ``values`` (row k = values at ``xs[k]``, by default the
    k-th point of :func:`points`); one polynomial of degree < len(xs) per column.

    At most ``SMALL_INVERSE_POINTS`` of the standard points: one integer product with the
    cached ``D·V⁻¹`` (:func:`_small_standard_inverse`).  Otherwise
    Lagrange's formula ``p = Σ_i y_i/W_i · Π_{j≠i}(δ − x_j)``, ``W_i = Π_{j≠i}(x_i − x_j)``.
    Few columns (≤ 8), or more than ``_INVERSE_MAX_POINTS`` points: a subproduct tree per
    column (:func:`_lagrange_sum`, O(M(N) log N)); no Vandermonde inverse, whose size grows
    like N⁴ bits.  Many columns at fewer points: one product with the (cached) inverse of
    the Vandermonde matrix (:func:`_vandermonde_inverse`), O(N²·k) rational operations in C,
    which is faster there (measured: N = 65, k = 1024 — 0.14 s against 0.76 s for an
    integer Lagrange product).
    Precondition: the xs are distinct (not checked)."""
    count, k = values.nrows(), values.ncols()
    if xs is None:
        xs = first_points(count)
    if count == 0:
        return [bk.ZERO] * k
    small = _small_standard_inverse(xs)
    if small is not None:
        numer, denom = values.numer_denom()
        return _from_coefficient_columns(small[0] * numer, small[1] * denom, count, k)
    w = _weights(xs)
    if k <= _FEW_COLUMNS or count > _INVERSE_MAX_POINTS:
        return [
            _lagrange_sum(xs, [values[i, j] / w[i] for i in range(count)])[0] for j in range(k)
        ]
    coeffs = _vandermonde_inverse(xs) * values
    entries = coeffs.entries()
    return [flint.fmpq_poly([entries[e * k + j] for e in range(count)]) for j in range(k)]


_VANDERMONDE_INVERSES: dict[int, flint.fmpq_mat] = {}

#: Interpolation at up to this many standard points (:func:`first_points`) is one product
#: with the integer matrix ``D·V⁻¹`` (cached: 2.3 ms to build at 33 points, 25 ms at 65).
#: Measured against the subproduct tree of :func:`_lagrange_sum` for one column of 20-bit
#: values: 6 against 58 µs at 17 points (the determinant of an 8×8 of degree 2), 18 against
#: 187 µs at 33; of 2000-bit values, 25 against 103 µs and 79 against 348 µs.
SMALL_INVERSE_POINTS = 33

_SMALL_INVERSES: dict[int, tuple[flint.fmpz_mat, flint.fmpz]] = {}


def _small_standard_inverse(xs: Sequence[int]) -> tuple[flint.fmpz_mat, flint.fmpz] | None:
    """``(D·V⁻¹, D)`` with V the Vandermonde matrix of ``xs`` and D the least common
    denominator of V⁻¹, when ``xs`` are the first ``SMALL_INVERSE_POINTS`` or fewer of the
    standard points (:func:`first_points`); else None.  A cache of constants: results never
    depend on it."""
    count = len(xs)
    if count > SMALL_INVERSE_POINTS or list(xs) != first_points(count):
        return None
    got = _SMALL_INVERSES.get(count)
    if got is None:
        got = _SMALL_INVERSES[count] = _vandermonde_inverse(xs).numer_denom()
    return got


def _from_coefficient_columns(c: flint.fmpz_mat, denom: flint.fmpz, count: int, k: int) -> list[flint.fmpq_poly]:
    """The k polynomials whose coefficient vectors (constant term first) are the columns
    of ``c / denom`` (count rows)."""
    entries = c.entries()
    return [flint.fmpq_poly([entries[e * k + j] for e in range(count)], denom) for j in range(k)]


def _vandermonde_inverse(xs: Sequence[int]) -> flint.fmpq_mat:
    """``V⁻¹`` for ``V[i][e] = xs[i]^e`` (distinct xs), by Lagrange's formula: column i holds
    the coefficients of ``L_i = P/(δ − x_i) / W_i``, ``P = Π_j (δ − x_j)``, ``W_i = P'(x_i)``
    (:func:`_weights`).  O(N²) integer operations, one exact division by a monic linear
    factor per column; the same matrix as ``V.inv()`` (O(N³) rational operations), 3× faster at
    65 points (6.6 against 19 ms) and 5× at 193 (0.19 against 1.0 s).

    >>> _vandermonde_inverse([0, 1, -1]) * flint.fmpq_mat(3, 3, [1, 0, 0, 1, 1, 1, 1, -1, 1]) == flint.fmpq_mat(3, 3, [1, 0, 0, 0, 1, 0, 0, 0, 1])
    True
    """
    count = len(xs)
    standard = list(xs) == first_points(count)
    inv = _VANDERMONDE_INVERSES.get(count) if standard else None
    if inv is None:
        P = flint.fmpz_poly([1])
        for x in xs:
            P *= flint.fmpz_poly([-x, 1])
        entries: list[flint.fmpq | int] = [0] * (count * count)
        for i, (x, w) in enumerate(zip(xs, _weights(xs), strict=True)):
            for e, c in enumerate((P // flint.fmpz_poly([-x, 1])).coeffs()):  # exact: P(x) = 0
                entries[e * count + i] = flint.fmpq(c, w)
        inv = flint.fmpq_mat(count, count, entries)
        if standard:
            _VANDERMONDE_INVERSES[count] = inv  # a cache of constants: results never depend on it
    return inv


_FEW_COLUMNS = 8
#: Beyond this many points every column goes through the subproduct tree, whatever their
#: number: the product with the cached inverse loses there, and building that inverse costs
#: more than it saves.  Integer values of 10·N bits, ms, tree / product with the cached
#: inverse: N = 97, k = 16: 17 / 12; N = 129, k = 16: 32 / 33; N = 193, k = 16: 81 / 147,
#: k = 256: 1240 / 855 plus 190 to build the inverse (once; 4 kbit entries, 37 000 of them).
_INVERSE_MAX_POINTS = 128


def _integer_value(coeffs: Coefficients, x: int) -> flint.fmpz_mat:
    """``Σ Z_e·x^e`` by Horner's rule over Z (in C): ``diag(dens)·M(x)``."""
    mats = coeffs.mats
    acc = mats[-1]
    for c in reversed(mats[:-1]):
        acc = acc * x + c
    return acc


def evaluate(coeffs: Coefficients, x: int) -> flint.fmpq_mat:
    """``M(x)`` exactly: ``Σ Z_e·x^e`` by Horner's rule over Z (in C), row i divided by
    ``dens[i]`` (:class:`Coefficients`)."""
    out = flint.fmpq_mat(_integer_value(coeffs, x))
    return out if coeffs.inverse_scale is None else coeffs.inverse_scale * out


def det_at(coeffs: Coefficients, x: int) -> flint.fmpq:
    """``det M(x)`` for a square M: the integer determinant of ``Σ Z_e·x^e`` (flint
    ``fmpz_mat``) over the product of the row scales — no rational matrix is built."""
    det = flint.fmpq(_integer_value(coeffs, x).det())
    if coeffs.inverse_scale is None:
        return det
    for d in coeffs.dens:
        det /= d
    return det


def interpolate(xs: Sequence[int], ys: Sequence[flint.fmpq]) -> flint.fmpq_poly:
    """The polynomial of degree < len(xs) through ``(xs[i], ys[i])``: one column of
    :func:`interpolate_columns`.  Precondition: the xs are distinct.

    >>> interpolate([0, 1, -1], [1, 3, 3])
    2*x^2 + 1
    >>> interpolate([5, 7], [1, 2])
    1/2*x + (-3/2)
    """
    if not xs:
        return bk.ZERO
    return interpolate_columns(flint.fmpq_mat(len(xs), 1, list(ys)), xs)[0]


def minor_degree_bound(a: dn.Rows, m: int, n: int, k: int) -> int:
    """An upper bound on the degree of every k×k minor: the smaller of the sums of the
    k largest row degrees and of the k largest column degrees."""
    if k <= 0:
        return 0
    degrees = [[p.degree() for p in r] for r in a]
    rd = sorted((max(max(r, default=0), 0) for r in degrees), reverse=True)
    cd = sorted((max(max(c), 0) for c in zip(*degrees, strict=True)), reverse=True) if m else []
    return min(sum(rd[:k]), sum(cd[:k]))
