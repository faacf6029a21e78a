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
