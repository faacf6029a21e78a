"""Evaluation and interpolation: exact Q[δ] answers from computations over Q.

A polynomial matrix is evaluated at distinct integer points; linear algebra
over Q runs in C (flint ``fmpq_mat``); results of bounded degree are recovered
by interpolation.  Deterministic: the number of points always comes from a
proven degree bound, never from a random guess.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn

__all__ = [
    "coefficient_mats",
    "points",
    "first_points",
    "evaluate",
    "interpolate",
    "interpolate_columns",
    "minor_degree_bound",
]


def coefficient_mats(a: dn.Rows, m: int, n: int) -> list[flint.fmpq_mat]:
    """``[A0, A1, …]`` as flint rational matrices (``[0]`` for a zero matrix)."""
    deg = max(dn.mat_degree(a), 0)
    out = []
    for e in range(deg + 1):
        out.append(flint.fmpq_mat(m, n, [p[e] for r in a for p in r]))
    return out


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


_VANDERMONDE_INVERSES: dict[int, flint.fmpq_mat] = {}


def _vandermonde_inverse(xs: Sequence[int]) -> flint.fmpq_mat:
    count = len(xs)
    standard = list(xs) == first_points(count)
    inv = _VANDERMONDE_INVERSES.get(count) if standard else None
    if inv is None:
        v = flint.fmpq_mat(count, count, [flint.fmpq(x) ** e for x in xs for e in range(count)])
        inv = v.inv()
        if standard:
            _VANDERMONDE_INVERSES[count] = inv  # a cache of constants: results never depend on it
    return inv


def interpolate_columns(values: flint.fmpq_mat, xs: Sequence[int] | None = None) -> list[flint.fmpq_poly]:
    """Interpolate every column of ``values`` (row k = values at ``xs[k]``, by default the
    k-th point of :func:`points`) in one matrix product; one polynomial per column.
    Precondition: the xs are distinct."""
    count, k = values.nrows(), values.ncols()
    coeffs = _vandermonde_inverse(first_points(count) if xs is None else xs) * values
    entries = coeffs.entries()
    return [flint.fmpq_poly([entries[e * k + j] for e in range(count)]) for j in range(k)]


def evaluate(coeffs: Sequence[flint.fmpq_mat], x: int) -> flint.fmpq_mat:
    """``Σ coeffs[e]·x^e`` by Horner's rule (in C)."""
    acc = coeffs[-1]
    fx = flint.fmpq(x)
    for c in reversed(coeffs[:-1]):
        acc = acc * fx + c
    return acc


def interpolate(xs: Sequence[int], ys: Sequence[flint.fmpq]) -> flint.fmpq_poly:
    """The polynomial of degree < len(xs) through ``(xs[i], ys[i])`` (Newton's divided
    differences).  Precondition: the xs are distinct."""
    n = len(xs)
    coef = [flint.fmpq(y) for y in ys]
    for j in range(1, n):
        for i in range(n - 1, j - 1, -1):
            coef[i] = (coef[i] - coef[i - 1]) / (xs[i] - xs[i - j])
    p = flint.fmpq_poly([coef[-1]]) if n else bk.ZERO
    for i in range(n - 2, -1, -1):
        p = p * flint.fmpq_poly([-xs[i], 1]) + coef[i]
    return p


def minor_degree_bound(a: dn.Rows, m: int, n: int, k: int) -> int:
    """An upper bound on the degree of every k×k minor: the smaller of the sums of the
    k largest row degrees and of the k largest column degrees."""
    if k <= 0:
        return 0
    rd = sorted((max(dn.row_degree(r), 0) for r in a), reverse=True)
    cd = sorted((max(dn.row_degree([r[j] for r in a]), 0) for j in range(n)), reverse=True)
    return min(sum(rd[:k]), sum(cd[:k]))
