"""Interpolation (ring._evaluation): the cached integer inverse at few standard points and
the subproduct tree elsewhere both recover the polynomial through its values."""

from __future__ import annotations

from fractions import Fraction

import flint
from hypothesis import given
from hypothesis import strategies as st

from uio_ring.ring import _backend as bk
from uio_ring.ring import _evaluation as ev

_coefficients = st.lists(st.fractions(max_denominator=50).filter(lambda q: abs(q) < 10**6), max_size=45)


def _values(p: flint.fmpq_poly, xs: list[int]) -> list[flint.fmpq]:
    return [bk.evaluate(p, flint.fmpq(x)) for x in xs]


@given(_coefficients, st.integers(0, 6))
def test_interpolate_recovers_the_polynomial(cs, extra):
    # degree < count: at the standard points (≤ SMALL_INVERSE_POINTS of them: one integer
    # product; more: Lagrange) and at shifted points (always Lagrange)
    p = bk.from_coeffs([Fraction(c) for c in cs])
    count = len(cs) + extra or 1
    for xs in (ev.first_points(count), [x + 3 for x in ev.first_points(count)]):
        assert ev.interpolate(xs, _values(p, xs)) == p


@given(st.lists(_coefficients, min_size=1, max_size=12), st.integers(0, 3))
def test_interpolate_columns_recovers_every_column(columns, extra):
    polys = [bk.from_coeffs([Fraction(c) for c in cs]) for cs in columns]
    count = max(len(cs) for cs in columns) + extra or 1
    xs = ev.first_points(count)
    values = flint.fmpq_mat(count, len(polys), [v for x in xs for v in (bk.evaluate(p, flint.fmpq(x)) for p in polys)])
    assert ev.interpolate_columns(values) == polys


def test_the_small_inverse_is_for_standard_points_only():
    assert ev._small_standard_inverse(ev.first_points(5)) is not None
    assert ev._small_standard_inverse([0, 1, -1, 2, 3]) is None
    assert ev._small_standard_inverse(ev.first_points(ev.SMALL_INVERSE_POINTS + 1)) is None


@given(st.lists(st.integers(-60, 60), min_size=1, max_size=24, unique=True))
def test_vandermonde_inverse_by_lagrange_is_the_inverse(xs):
    """The closed form (columns: coefficients of P/(δ − x_i) / P'(x_i)) is V⁻¹, whatever the
    distinct points, standard or not."""
    n = len(xs)
    V = flint.fmpq_mat(n, n, [flint.fmpq(x) ** e for x in xs for e in range(n)])
    inv = ev._vandermonde_inverse(xs)
    assert inv * V == flint.fmpq_mat(n, n, [int(i == j) for i in range(n) for j in range(n)])
    assert inv == V.inv()


@given(st.lists(_coefficients, min_size=9, max_size=10), st.sampled_from([40, 129, 140]))
def test_interpolate_columns_beyond_the_inverse(columns, count):
    """Many columns: by the cached inverse up to ``_INVERSE_MAX_POINTS`` points (40), by the
    subproduct tree beyond (129, 140); both recover every column of degree < count (the
    precondition: a column of up to 45 coefficients at 40 points has no interpolant of
    its own degree, so its coefficients beyond the 40th are dropped)."""
    polys = [bk.from_coeffs([Fraction(c) for c in cs[:count]]) for cs in columns]
    xs = ev.first_points(count)
    values = flint.fmpq_mat(count, len(polys), [v for x in xs for v in (bk.evaluate(p, flint.fmpq(x)) for p in polys)])
    assert ev.interpolate_columns(values) == polys
