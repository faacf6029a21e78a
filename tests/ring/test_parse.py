"""Reading polynomial matrices from text: accepted syntax and error messages.

Error messages must say what is wrong, where (the column, counted from 1 in
the message; ``ParseError.position`` is the 0-based index) and what was
expected.
"""

from __future__ import annotations

from fractions import Fraction

import pytest
from hypothesis import given

from uio_ring import DimensionError, DomainError, ParseError, PolyMatrix, UioRingError

from .strategies import P, matrices, poly_coeffs, poly_text


# ----------------------------------------------------------------------------
# accepted syntax: each text equals the canonical one
# ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "text, canonical",
    [
        ("d^2", "d**2"),  # caret is a power
        ("δ", "d"),
        ("δ**2 - 1", "d**2 - 1"),
        ("δ^3 + 2*δ", "d**3 + 2*d"),
        ("2d", "2*d"),  # implicit multiplication of a coefficient and the indeterminate
        ("2δ", "2*d"),
        ("(d + 1)*(d - 2)", "d**2 - d - 2"),
        ("(d+1)^2", "d**2 + 2*d + 1"),
        ("-d", "-1*d"),
        ("d/2", "1/2*d"),
        ("(d**2 - 1)/3", "1/3*d**2 - 1/3"),
        ("0.25*d", "1/4*d"),
        ("1.5", "3/2"),
        ("  d  +  1 ", "d + 1"),
        ("2/6", "1/3"),
        ("d**0", "1"),
        ("0*d**5", "0"),
    ],
)
def test_accepted_syntax(text, canonical):
    assert P(text) == P(canonical)


def test_matrix_text_forms():
    M = PolyMatrix("[[d, 1 + 2*d], [0, d**2 - 1/3]]")
    assert M == PolyMatrix([["d", "1 + 2*d"], [0, "d**2 - 1/3"]])
    assert M == PolyMatrix([["δ", "1 + 2δ"], [0, "δ^2 - 1/3"]])
    assert PolyMatrix("[[1]]").shape == (1, 1)
    assert PolyMatrix("[[1, 2, 3]]").shape == (1, 3)
    assert PolyMatrix("[[1], [2], [3]]").shape == (3, 1)


@given(matrices(min_rows=1, min_cols=1))
def test_repr_text_parses_back(M):
    text = repr(M)
    assert text.startswith("PolyMatrix(") and text.endswith(")")
    assert PolyMatrix(text[len("PolyMatrix("):-1]) == M


@given(poly_coeffs())
def test_str_of_poly_parses_back(cs):
    p = P(poly_text(cs))
    assert P(str(p)) == p
    assert [Fraction(c) for c in p.coeffs()] == _trim([Fraction(c) for c in cs])


def _trim(cs):
    while cs and cs[-1] == 0:
        cs = cs[:-1]
    return cs


def test_other_indeterminate_text():
    M = PolyMatrix("[[s^2 + 1, 2s]]", var="s")
    assert M == PolyMatrix([["s**2 + 1", "2*s"]], var="s")
    with pytest.raises(DomainError, match="'d'"):
        PolyMatrix("[[s, d]]", var="s")


# ----------------------------------------------------------------------------
# syntax errors: position and expectation
# ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "text, column, expected",
    [
        ("1+*d", 3, r"expected"),
        ("(d+1", 5, r"expected '\)'"),
        ("d**", 4, r"expected .*exponent"),
        ("d**-1", 4, r"expected .*non-negative integer exponent"),
        ("d**d", 4, r"expected .*exponent"),
        ("d - * 2", 5, r"expected"),
    ],
)
def test_syntax_error_gives_column_and_expectation(text, column, expected):
    with pytest.raises(ParseError, match=rf"column {column}\b.*{expected}") as info:
        P(text)
    err = info.value
    assert err.position == column - 1  # 0-based attribute, 1-based in the message
    assert err.text == text
    assert text in str(err)
    assert isinstance(err, ValueError) and isinstance(err, UioRingError)


def test_repeated_signs_follow_python():
    """Unary signs nest as in Python and sympy: ``--d`` is d, ``1 + -2`` is −1."""
    assert P("--d") == P("d")
    assert P("1 + -2") == P("-1")
    assert P("-d**2") == -P("d**2")


def test_syntax_error_in_matrix_text_gives_column():
    with pytest.raises(ParseError, match=r"column 8\b.*expected ',' or '\]'") as info:
        PolyMatrix("[[1, 2]")
    assert info.value.position == 7


@pytest.mark.parametrize("text", ["", "   "])
def test_empty_text(text):
    with pytest.raises(ParseError, match="empty"):
        P(text)


def test_division_by_zero_is_a_parse_error():
    with pytest.raises(ParseError, match="division by zero"):
        P("1/0")


@pytest.mark.parametrize("text", ["[[1 2]]", "[[d 1]]", "[[1 d**2 3]]"])
def test_space_separated_row_is_not_silently_a_product(text):
    """``[[1 2]]`` (MATLAB-style row) must not be read as the 1×1 matrix [[2]].

    Implicit multiplication ``2d`` / ``2 d`` (coefficient then indeterminate) is
    accepted; a number *following* another factor is never a product in ordinary
    notation, so it has to be an error rather than a silently different matrix.
    """
    with pytest.raises(ParseError, match="column"):
        PolyMatrix(text)


# ----------------------------------------------------------------------------
# domain errors: non-rational numbers, unknown symbols, non-polynomials
# ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "text, pattern",
    [
        ("x", r"unknown symbol 'x'.*'d'"),
        ("d + x**2", r"column 5.*unknown symbol 'x'"),
        ("d2", r"unknown symbol 'd2'"),
        ("sqrt(2)", r"'sqrt'.*(not rational|exact rational)"),
        ("pi*d", r"'pi'.*(not rational|exact rational)"),
        ("2/d", r"column 2.*(not .*polynomial|polynomial)"),
    ],
)
def test_domain_errors_name_the_culprit(text, pattern):
    with pytest.raises((DomainError, ParseError), match=pattern) as info:
        P(text)
    assert isinstance(info.value, UioRingError)


def test_non_polynomial_division_message_names_the_indeterminate():
    with pytest.raises(DomainError) as info:
        P("2/d")
    msg = str(info.value)
    assert "None" not in msg, msg
    assert "'d'" in msg or "δ" in msg, msg


def test_unknown_symbol_in_matrix_text_names_it_and_its_column():
    with pytest.raises(DomainError, match=r"column 6.*unknown symbol 'x'"):
        PolyMatrix("[[1, x]]")


@pytest.mark.parametrize("value", [float("nan"), float("inf"), complex(1, 1), object(), True])
def test_non_rational_python_values(value):
    with pytest.raises((DomainError, TypeError)):
        PolyMatrix([[value]])


# ----------------------------------------------------------------------------
# shapes in text and nested lists
# ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "data",
    [
        "[[1, 2], [3]]",
        "[[1], [2, 3]]",
        [[1, 2], [3]],
        [[1], [2, 3]],
        [["d", "1"], ["d"]],
    ],
)
def test_ragged_rows_are_dimension_errors(data):
    with pytest.raises(DimensionError, match=r"row 1 .*1 .*2|row 1 .*2 .*1"):
        PolyMatrix(data)
