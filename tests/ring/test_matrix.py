"""PolyMatrix and Poly: construction, arithmetic, structure, conversions.

Arithmetic is checked against sympy on the same matrices; structural
operations against their definitions.
"""

from __future__ import annotations

import re
from fractions import Fraction

import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from uio_ring import DimensionError, DomainError, Poly, PolyMatrix, UioRingError

from .strategies import (
    D_SYM,
    P,
    dense_matrices,
    heavy,
    matrices,
    poly_coeffs,
    poly_text,
    reference_det,
    reference_rank,
    same_poly,
    singular_at_sample_points,
    square_matrices,
    sympy_matrix,
    to_sympy_poly,
)

d = D_SYM


# ----------------------------------------------------------------------------
# construction
# ----------------------------------------------------------------------------
def test_text_construction_and_repr():
    M = PolyMatrix("[[d, 1 + 2*d], [0, d**2 - 1/3]]")
    assert M.shape == (2, 2) and M.rows == 2 and M.cols == 2
    assert repr(M) == "PolyMatrix([[d, 2*d + 1], [0, d**2 - 1/3]])"
    assert PolyMatrix(repr(M)[len("PolyMatrix("):-1]) == M  # the repr's text parses back
    assert M[0, 1] == P("2*d + 1")
    assert M[1, 1].coeffs() == [Fraction(-1, 3), 0, 1]


def test_nested_list_inputs_agree():
    a = PolyMatrix([[1, Fraction(1, 2)], ["d", P("d**2")]])
    b = PolyMatrix("[[1, 1/2], [d, d**2]]")
    assert a == b


def test_delta_and_d_are_the_same_indeterminate():
    assert PolyMatrix("[[δ**2 + 1, δ]]") == PolyMatrix("[[d**2 + 1, d]]")


def test_float_is_read_through_its_decimal_text():
    assert PolyMatrix([[0.1]]) == PolyMatrix([["1/10"]])
    assert PolyMatrix([[0.1]])[0, 0] != Fraction(0.1)  # not the binary float
    assert PolyMatrix([[2.5, -0.125]]) == PolyMatrix([["5/2", "-1/8"]])


def test_other_indeterminate():
    M = PolyMatrix("[[s, 1], [0, s**2]]", var="s")
    assert M.shape == (2, 2)
    assert M.det() == PolyMatrix("[[s**3]]", var="s")[0, 0]
    assert M @ M == PolyMatrix("[[s**2, s + s**2], [0, s**4]]", var="s")


@pytest.mark.parametrize(
    "op",
    [
        lambda a, b: a + b,
        lambda a, b: a - b,
        lambda a, b: a @ b,
        lambda a, b: PolyMatrix.hstack(a, b),
        lambda a, b: PolyMatrix.vstack(a, b),
    ],
    ids=["add", "sub", "matmul", "hstack", "vstack"],
)
def test_mixing_indeterminates_raises_domain_error(op):
    a = PolyMatrix("[[d, 1], [0, d]]")
    b = PolyMatrix("[[s, 1], [0, s]]", var="s")
    with pytest.raises(DomainError, match=r"(?s)(d.*s|s.*d)"):
        op(a, b)


def test_constructors():
    I3 = PolyMatrix.identity(3)
    assert I3.shape == (3, 3) and I3.det() == 1
    assert all(I3[i, j] == (1 if i == j else 0) for i in range(3) for j in range(3))
    Z = PolyMatrix.zeros(2, 3)
    assert Z.shape == (2, 3) and Z.is_zero() and Z.degree() == -1
    D = PolyMatrix.diag("d", 1, "d + 1")
    assert D == PolyMatrix("[[d, 0, 0], [0, 1, 0], [0, 0, d + 1]]")
    A = PolyMatrix("[[1, d]]")
    B = PolyMatrix("[[2]]")
    assert PolyMatrix.hstack(A, B) == PolyMatrix("[[1, d, 2]]")
    assert PolyMatrix.vstack(A, PolyMatrix("[[3, 4]]")) == PolyMatrix("[[1, d], [3, 4]]")
    blk = PolyMatrix.block([[PolyMatrix.identity(2), PolyMatrix.zeros(2, 1)],
                            [PolyMatrix("[[d, d]]"), PolyMatrix("[[1]]")]])
    assert blk == PolyMatrix("[[1, 0, 0], [0, 1, 0], [d, d, 1]]")


@pytest.mark.parametrize("shape", [(0, 0), (0, 3), (3, 0)])
def test_empty_shapes(shape):
    Z = PolyMatrix.zeros(*shape)
    assert Z.shape == shape
    assert Z.is_zero() and Z.degree() == -1 and Z.rank() == 0
    assert Z.T.shape == shape[::-1]
    assert Z + Z == Z and -Z == Z
    assert (Z @ PolyMatrix.zeros(shape[1], 2)).shape == (shape[0], 2)
    assert PolyMatrix.zeros(2, shape[0]) @ Z == PolyMatrix.zeros(2, shape[1])
    assert PolyMatrix.hstack(PolyMatrix.zeros(shape[0], 1), Z).shape == (shape[0], shape[1] + 1)
    assert PolyMatrix.vstack(PolyMatrix.zeros(1, shape[1]), Z).shape == (shape[0] + 1, shape[1])
    assert Z.tolist() == [[] for _ in range(shape[0])]


def test_det_of_empty_matrix_is_one():
    assert PolyMatrix.identity(0).det() == 1


def test_inner_dimension_zero_product_is_zero():
    A = PolyMatrix.zeros(2, 0)
    B = PolyMatrix.zeros(0, 3)
    assert A @ B == PolyMatrix.zeros(2, 3)


# ----------------------------------------------------------------------------
# dimension errors name both shapes
# ----------------------------------------------------------------------------
A23 = PolyMatrix("[[1, d, 0], [0, 1, d]]")
B32 = PolyMatrix("[[1, 0], [d, 1], [0, 0]]")
B22 = PolyMatrix("[[1, 0], [d, 1]]")


@pytest.mark.parametrize(
    "call, shapes",
    [
        (lambda: A23 + B32, [(2, 3), (3, 2)]),
        (lambda: A23 - B22, [(2, 3), (2, 2)]),
        (lambda: A23 @ A23, [(2, 3), (2, 3)]),
        (lambda: PolyMatrix.hstack(A23, B32), [(2, 3), (3, 2)]),
        (lambda: PolyMatrix.vstack(A23, B22), [(2, 3), (2, 2)]),
    ],
    ids=["add", "sub", "matmul", "hstack", "vstack"],
)
def test_dimension_mismatch_names_both_shapes(call, shapes):
    with pytest.raises(DimensionError) as info:
        call()
    msg = str(info.value)
    for r, c in shapes:
        assert re.search(rf"\b{r}\s*[×x]\s*{c}\b", msg) or f"({r}, {c})" in msg, msg
    assert isinstance(info.value, ValueError) and isinstance(info.value, UioRingError)


def test_ragged_rows():
    with pytest.raises(DimensionError, match="row"):
        PolyMatrix([[1, 2], [3]])
    with pytest.raises(DimensionError, match="row"):
        PolyMatrix("[[1, 2], [3]]")


def test_immutable():
    M = PolyMatrix("[[1, d]]")
    with pytest.raises((TypeError, AttributeError)):
        M[0, 0] = 5
    with pytest.raises((TypeError, AttributeError)):
        M.foo = 1
    assert M == PolyMatrix("[[1, d]]")


@pytest.mark.parametrize("bad", [0.5, float("nan"), "sqrt(2)"])
def test_no_floats_or_irrationals_in_scalar_multiplication(bad):
    M = PolyMatrix("[[1, d]]")
    with pytest.raises((DomainError, TypeError)):
        bad * M


# ----------------------------------------------------------------------------
# arithmetic against sympy
# ----------------------------------------------------------------------------
@given(st.data())
def test_arithmetic_matches_sympy(data):
    p = data.draw(st.integers(0, 4))
    q = data.draw(st.integers(0, 4))
    r = data.draw(st.integers(0, 4))
    A = data.draw(dense_matrices(rows=p, cols=q))
    B = data.draw(dense_matrices(rows=p, cols=q))
    C = data.draw(dense_matrices(rows=q, cols=r))
    c = data.draw(st.fractions(min_value=-5, max_value=5, max_denominator=7))
    sA, sB, sC = sympy_matrix(A), sympy_matrix(B), sympy_matrix(C)
    assert sympy_matrix(A + B).expand() == (sA + sB).expand()
    assert sympy_matrix(A - B).expand() == (sA - sB).expand()
    assert sympy_matrix(-A).expand() == (-sA).expand()
    assert sympy_matrix(A @ C).expand() == (sA * sC).expand()
    assert sympy_matrix(c * A).expand() == (sp.Rational(c.numerator, c.denominator) * sA).expand()
    assert sympy_matrix(3 * A) == sympy_matrix(A + A + A)
    pc = data.draw(poly_coeffs(2))
    pp = P(poly_text(pc))
    assert sympy_matrix(pp * A).expand() == (to_sympy_poly(pp).as_expr() * sA).expand()
    assert A.T.T == A
    assert (A @ C).T == C.T @ A.T
    assert (A + B) - B == A


@given(matrices())
def test_sympy_roundtrip(M):
    assert PolyMatrix.from_sympy(M.to_sympy(var="d"), var="d") == M
    S = M.to_sympy(var="d")
    assert S.shape == M.shape
    for i in range(M.rows):
        for j in range(M.cols):
            assert same_poly(M[i, j], sp.Poly(S[i, j], d, domain=sp.QQ))


@given(square_matrices(max_n=5))
def test_det_matches_sympy(M):
    assert same_poly(M.det(), reference_det(M))


@given(matrices(max_rows=5, max_cols=5))
def test_rank_matches_sympy(M):
    assert M.rank() == reference_rank(M)
    assert M.T.rank() == M.rank()


@heavy()
@given(singular_at_sample_points())
def test_rank_and_det_when_singular_at_sample_points(case):
    """rank/det by evaluation must not stop at the first (unlucky) sample points."""
    M, diag = case
    assert M.rank() == sum(e != "0" for e in diag) == reference_rank(M)
    assert same_poly(M.det(), reference_det(M))
    prod = P("1")
    for e in diag:
        prod = prod * P(e)
    assert M.det().monic() == prod.monic() if prod.degree() >= 0 else M.det() == 0


# ----------------------------------------------------------------------------
# structure
# ----------------------------------------------------------------------------
@given(matrices())
def test_degree_and_coefficients(M):
    degs = [e.degree() for row in M.tolist() for e in row]
    assert M.degree() == max(degs, default=-1)
    cs = M.coefficients()
    # the zero matrix may be given as [] or as [0]; otherwise exactly deg + 1 coefficients
    assert len(cs) == M.degree() + 1 or (M.is_zero() and len(cs) == 1 and cs[0].is_zero())
    assert all(c.shape == M.shape and c.degree() <= 0 for c in cs)
    total = PolyMatrix.zeros(*M.shape)
    for k, c in enumerate(cs):
        total = total + P(f"d**{k}") * c
    assert total == M
    assert PolyMatrix.from_coefficients(cs) == M if cs else True
    lists = M.coefficient_lists()
    assert len(lists) == len(cs)
    for ck, lk in zip(cs, lists, strict=True):
        assert all(isinstance(x, Fraction) for row in lk for x in row)
        assert PolyMatrix(lk) == ck if M.rows and M.cols else True
    if cs and M.rows and M.cols:
        assert PolyMatrix.from_coefficients(lists) == M


@given(matrices(), st.fractions(min_value=-3, max_value=3, max_denominator=5))
def test_eval_is_exact_and_matches_sympy(M, x):
    E = M.eval(x)
    assert E.shape == M.shape and E.degree() <= 0
    S = sympy_matrix(M).subs(d, sp.Rational(x.numerator, x.denominator))
    for i in range(M.rows):
        for j in range(M.cols):
            assert E[i, j] == Fraction(str(S[i, j]))
    assert M.eval(str(x)) == E
    if x.denominator == 1:
        assert M.eval(int(x)) == E


@given(matrices(min_rows=1, min_cols=1))
def test_indexing_and_slicing(M):
    rows = M.tolist()
    assert len(rows) == M.rows and all(len(r) == M.cols for r in rows)
    assert all(rows[i][j] == M[i, j] for i in range(M.rows) for j in range(M.cols))
    assert M[-1, -1] == M[M.rows - 1, M.cols - 1]
    sub = M[:, 1:3]
    assert isinstance(sub, PolyMatrix)
    assert sub.shape == (M.rows, len(range(M.cols)[1:3]))
    assert all(sub[i, j] == M[i, j + 1] for i in range(sub.rows) for j in range(sub.cols))
    assert PolyMatrix.hstack(M[:, :1], M[:, 1:]) == M
    assert PolyMatrix.vstack(M[:1, :], M[1:, :]) == M
    assert M.T[0, M.rows - 1] == M[M.rows - 1, 0]


def test_index_errors():
    M = PolyMatrix("[[1, d]]")
    with pytest.raises(IndexError):
        M[1, 0]
    with pytest.raises(IndexError):
        M[0, 2]


@given(matrices())
def test_is_zero(M):
    assert M.is_zero() == all(e.degree() == -1 for row in M.tolist() for e in row)
    assert (M - M).is_zero()


def test_equality():
    M = PolyMatrix("[[d, 1]]")
    assert M == PolyMatrix([["d", 1]])
    assert M != PolyMatrix("[[d, 2]]")
    assert M != PolyMatrix("[[d], [1]]")
    assert PolyMatrix.zeros(0, 2) != PolyMatrix.zeros(2, 0)
    assert PolyMatrix("[[s, 1]]", var="s") != PolyMatrix("[[d, 1]]")


def test_latex():
    M = PolyMatrix("[[d, 1 + 2*d], [0, d**2 - 1/3]]")
    tex = M.to_latex()
    assert "\\delta" in tex or "δ" in tex
    assert "\\frac" in tex or "\\tfrac" in tex or "/" in tex
    rl = M._repr_latex_()
    assert rl.startswith("$") and rl.endswith("$")
    assert tex in rl



@given(st.lists(st.fractions(max_denominator=10**6), min_size=1, max_size=5))
def test_text_reads_back_in_sympy_and_here(cs):
    """The text of a polynomial (highest power first, ``d**2/3 - d + 1``) is the same
    polynomial for sympy and for our own reader."""
    d = sp.Symbol("d")
    p = Poly.from_coeffs(cs)
    text = str(p)
    assert sp.expand(sp.sympify(text, locals={"d": d}) - sp.Poly(list(reversed(cs)), d, domain="QQ").as_expr()) == 0
    assert Poly(text) == p


def test_text_and_latex_of_coefficients_beyond_pythons_digit_limit():
    """A 9000-digit numerator and a 5000-digit denominator (Python's ``str(int)`` refuses
    more than 4300 digits; the transforms of a singular 16×16 of degree 16 have such
    coefficients): every digit is written, in text and in LaTeX, for polynomial and
    constant matrices."""
    from uio_ring.ring.qmatrix import QMatrix

    big, den = 7**10650, 3**10480  # 9000 and 5000 digits
    tail = str(big % 10**50)  # the last 50 digits, within the limit
    M = PolyMatrix([[Poly.from_coeffs([Fraction(big, den), 0, -big])]])
    text, tex = str(M), M.to_latex()
    assert text.startswith("[-") and f"{tail}*d**2 + " in text
    assert text.count(tail) == 2 and tex.count(tail) == 2
    assert len(text) > 2 * 9000 + 5000
    Q = QMatrix([[Fraction(big, den), 1]])
    assert Q.to_latex().count(tail) == 1 and str(Q).count(tail) == 1

# ----------------------------------------------------------------------------
# Poly
# ----------------------------------------------------------------------------
def test_poly_basics():
    p = P("d**2 + d")
    assert str(p) == "d**2 + d"
    assert p.degree() == 2
    assert p.coeffs() == [0, 1, 1]
    assert all(isinstance(c, Fraction) for c in p.coeffs())
    assert p.eval(2) == 6 and p.eval(Fraction(1, 2)) == Fraction(3, 4)
    zero = P("0")
    assert zero.degree() == -1 and zero.coeffs() == [] and zero == 0
    assert P("3") == 3 and P("3") != 4
    assert P("2*d + 4").monic() == P("d + 2")
    assert P("-1/2").is_unit() and not zero.is_unit() and not p.is_unit()
    assert isinstance(p, Poly)


@given(poly_coeffs(), poly_coeffs())
def test_poly_arithmetic_matches_sympy(a, b):
    pa, pb = P(poly_text(a)), P(poly_text(b))
    sa, sb = to_sympy_poly(pa), to_sympy_poly(pb)
    assert same_poly(pa + pb, sa + sb)
    assert same_poly(pa - pb, sa - sb)
    assert same_poly(pa * pb, sa * sb)
    assert same_poly(pa + 1, sa + 1) and same_poly(2 - pa, 2 - sa)
    if pb.degree() >= 0:
        q, r = pa // pb, pa % pb
        assert q * pb + r == pa
        assert r.degree() < pb.degree()
        sq, sr = sa.div(sb)
        assert same_poly(q, sq) and same_poly(r, sr)
    else:
        with pytest.raises(ZeroDivisionError):
            pa // pb


def test_poly_comparisons_with_int():
    assert P("1") == 1 and 1 == P("1")
    assert P("0") == 0
    assert P("d") != 0 and P("d") != 1


def test_indices_from_numpy_and_sympy():
    import numpy as np
    import sympy

    M = PolyMatrix("[[1, d], [d**2, 0]]")
    assert M[np.int64(1), np.int64(0)] == M[1, 0] == M[sympy.Integer(1), sympy.Integer(0)]


@given(st.integers(3, 4).flatmap(lambda n: dense_matrices(rows=n, cols=n, max_degree=4)))
def test_small_determinant_formulas_match_sympy_and_the_general_paths(M):
    """3×3 by cofactors and 4×4 by Laplace expansion along two rows (det_raw's formulas)
    against sympy and against the two general paths (Bareiss over Z[δ] and evaluation
    with interpolation), with rational coefficients and zero entries."""
    from uio_ring.ring import _evaluation as ev
    from uio_ring.ring import _fraction_free as ff
    from uio_ring.ring._predicates import det_raw

    n = M.rows
    d = det_raw(M._r, n)
    assert same_poly(M.det(), reference_det(M))
    assert d == ff.det_fraction_free(M._r, n)
    xs = ev.first_points(ev.minor_degree_bound(M._r, n, n, n) + 1)
    coeffs = ev.coefficient_mats(M._r, n, n)
    assert d == ev.interpolate(xs, [ev.det_at(coeffs, x) for x in xs])
