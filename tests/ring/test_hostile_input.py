"""Hostile and extreme input to the exact layer: bounded work, the package's own errors.

Every case either finishes quickly or raises a :class:`UioRingError` subclass
(never a bare ValueError/TypeError/AttributeError, never a hang).
"""

from __future__ import annotations

import decimal
import time
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring import PolyMatrix, hermite, is_unimodular, left_kernel, smith, solve_left
from uio_ring.ring import det, rank
from uio_ring.ring.errors import DimensionError, DomainError, ParseError, UioRingError
from uio_ring.ring.parse import MAX_NUMBER_DIGITS, decimal_fraction, parse_poly
from uio_ring.ring.poly import exact_fraction

# (text, error class, regex) — each must be refused before the work it bounds
BOUNDED_TEXT = [
    ("1e99999999", DomainError, r"implies more than 1000 digits"),
    ("1e-5000", DomainError, r"implies more than 1000 digits"),
    ("9" * 5000, DomainError, r"more than 1000 digits"),
    ("0." + "0" * 2000 + "1", DomainError, r"more than 1000 digits"),
    ("(1+d)**4096*" * 15 + "(1+d)**4096", DomainError, r"the product has degree 8192, above the limit 4096"),
    ("d**4097", DomainError, r"exponent 4097 exceeds the limit 4096"),
    ("d**" + "9" * 50, DomainError, r"exponent 9+… exceeds"),
    ("(d**2)**3000", DomainError, r"the power has degree 6000"),
    ("(10**4096)**4096", DomainError, r"coefficients would need about \d+ bits"),
    ("+".join(f"1/{p}" for p in range(2, 100_000)), DomainError, r"coefficients need \d+ bits"),
    ("(" * 5000 + "d" + ")" * 5000, DomainError, r"parentheses nested deeper than 100"),
    ("1+*d", ParseError, r"at column 3"),
]


@pytest.mark.parametrize("text,cls,pattern", BOUNDED_TEXT, ids=lambda x: x[:20] if isinstance(x, str) else None)
def test_text_is_bounded_before_it_is_built(text, cls, pattern):
    start = time.perf_counter()
    with pytest.raises(cls, match=pattern) as info:
        parse_poly(text)
    assert time.perf_counter() - start < 10  # generous: each is refused in milliseconds
    assert len(str(info.value)) < 400  # one short line even for megabyte texts
    assert "\n" not in str(info.value)


def test_any_number_of_unary_signs_is_read_iteratively():
    assert PolyMatrix("-" * 100_001 + "d") == PolyMatrix("[[-d]]")
    assert parse_poly("--" * 50_000 + "2") == parse_poly("2")


@pytest.mark.parametrize(
    "text,value",
    [("0.1", Fraction(1, 10)), ("-2.5e-3", Fraction(-1, 400)), ("7", Fraction(7)), ("1/3", Fraction(1, 3)),
     ("1e999", Fraction(10) ** 999), (".5", Fraction(1, 2)), ("1_000", Fraction(1000))],
)
def test_decimal_fraction_reads_exactly(text, value):
    assert decimal_fraction(text) == value


@pytest.mark.parametrize("text", ["", ".", "1e", "nan", "inf", "0x10", "1:30", "1/0", "1.5/2"])
def test_decimal_fraction_refuses_non_decimals(text):
    with pytest.raises((ParseError, DomainError)):
        decimal_fraction(text)


def test_the_digit_limit_is_exact():
    assert decimal_fraction("1e" + str(MAX_NUMBER_DIGITS - 1)) == 10 ** (MAX_NUMBER_DIGITS - 1)
    with pytest.raises(DomainError):
        decimal_fraction("1e" + str(MAX_NUMBER_DIGITS))


# ---- one documented rule for NumPy and other number types --------------------------------
NUMBERS = [
    (np.float64(0.1), Fraction(1, 10)),
    (np.float32(0.1), Fraction(1, 10)),
    (np.float16(0.5), Fraction(1, 2)),
    (np.int64(-3), Fraction(-3)),
    (np.uint8(200), Fraction(200)),
    (decimal.Decimal("0.25"), Fraction(1, 4)),
    (0.1, Fraction(1, 10)),
]


@pytest.mark.parametrize("value,expected", NUMBERS, ids=repr)
def test_numbers_are_read_through_their_decimal_text(value, expected):
    assert exact_fraction(value) == expected
    assert PolyMatrix([[value]]) == PolyMatrix([[expected]])


BAD_NUMBERS = [np.float64("nan"), np.float32("inf"), np.bool_(True), True, np.complex128(1), 1 + 2j,
               decimal.Decimal("NaN"), decimal.Decimal("1e99999999"), object(), b"1"]


@pytest.mark.parametrize("value", BAD_NUMBERS, ids=repr)
def test_non_numbers_raise_domain_error(value):
    with pytest.raises(DomainError):
        exact_fraction(value)


def test_numpy_arrays_follow_the_same_rule():
    assert PolyMatrix(np.array([[0.1, 2.0]])) == PolyMatrix("[[1/10, 2]]")
    assert PolyMatrix(np.array([[1, 2], [3, 4]])) == PolyMatrix("[[1, 2], [3, 4]]")


# ---- the API raises the package's own errors --------------------------------------------
API = [
    (lambda: PolyMatrix(np.array([1.0, 2.0])), DimensionError, "1-dimensional array"),
    (lambda: PolyMatrix(np.zeros((2, 2, 2))), DimensionError, "3-dimensional array"),
    (lambda: PolyMatrix([{1, 2}]), DimensionError, "row 0 is a set"),
    (lambda: PolyMatrix([[1], frozenset({2})]), DimensionError, "row 1 is a frozenset"),
    (lambda: PolyMatrix({0: [1]}), DimensionError, "dict has no order"),
    (lambda: PolyMatrix([[1, 2]]) @ np.eye(2), DomainError, "convert the other operand"),
    (lambda: np.eye(2) @ PolyMatrix([[1, 2]]).T, DomainError, "convert the other operand"),
    (lambda: np.eye(1) + PolyMatrix([[1]]), DomainError, "convert the other operand"),
    (lambda: PolyMatrix([[1]]) - [[1]], DomainError, "convert the other operand"),
    (lambda: hermite([[1, 2]]), DomainError, r"hermite: expected a PolyMatrix, got list"),
    (lambda: is_unimodular([[1]]), DomainError, r"is_unimodular: expected a PolyMatrix"),
    (lambda: smith(np.eye(2)), DomainError, r"smith: expected a PolyMatrix, got ndarray"),
    (lambda: left_kernel("[[1]]"), DomainError, r"left_kernel: expected a PolyMatrix, got str"),
    (lambda: solve_left(PolyMatrix([[1]]), [[1]]), DomainError, r"solve_left: expected a PolyMatrix"),
    (lambda: rank([[1]]), DomainError, r"rank: expected"),
    (lambda: det(None), DomainError, r"det: expected a PolyMatrix, got NoneType"),
]


@pytest.mark.parametrize("call,cls,pattern", API)
def test_api_misuse_raises_package_errors(call, cls, pattern):
    with pytest.raises(cls, match=pattern) as info:
        call()
    assert isinstance(info.value, UioRingError)


# ---- fuzzing: any text parses or raises ParseError/DomainError, quickly ----------------------
PIECES = st.sampled_from(["d", "δ", "(", ")", "+", "-", "*", "/", "**", "^", "[", "]", ",", "1", "0", "9" * 50,
                          "1e999", "1e-999", "1e99999999", "4096", "(1+d)**4096", "0.5", " ", "x", "sqrt"])


@settings(max_examples=80, deadline=None)
@given(st.lists(PIECES, min_size=1, max_size=400))
def test_any_text_parses_or_raises_package_errors(pieces):
    text = "".join(pieces)
    start = time.perf_counter()
    try:
        PolyMatrix(text)
    except (ParseError, DomainError, DimensionError):
        pass
    assert time.perf_counter() - start < 10
