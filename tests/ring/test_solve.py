"""solve_left: X V = W over Q[δ], or NoPolynomialSolutionError."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from uio_ring import (
    DimensionError,
    NoPolynomialSolutionError,
    PolyMatrix,
    UioRingError,
    solve_left,
)

from .strategies import (
    dense_matrices,
    matrices,
    paper_001_M,
    paper_001_system,
    unimodular_matrices,
)


@given(st.data())
def test_solvable_systems(data):
    V = data.draw(matrices())
    k = data.draw(st.integers(0, 4))
    X0 = data.draw(dense_matrices(rows=k, cols=V.rows, max_degree=2))
    W = X0 @ V
    X = solve_left(V, W)
    assert X.shape == (k, V.rows)
    assert X @ V == W


@given(st.data())
def test_unsolvable_by_divisibility(data):
    """V = P·diag(1, d+1)·Q, W = e2·Q: X P diag(1, d+1) = e2 needs 1/(d+1)."""
    Pm = data.draw(unimodular_matrices(2))
    Q = data.draw(unimodular_matrices(2))
    V = Pm @ PolyMatrix.diag(1, "d + 1") @ Q
    W = PolyMatrix("[[0, 1]]") @ Q
    with pytest.raises(NoPolynomialSolutionError):
        solve_left(V, W)
    # but (d+1)·W is solvable
    X = solve_left(V, PolyMatrix("[[d + 1]]")[0, 0] * W)
    assert X @ V == PolyMatrix("[[d + 1]]")[0, 0] * W


@pytest.mark.parametrize(
    "V, W",
    [
        ("[[d, 0], [0, d]]", "[[1, 0], [0, 1]]"),  # V = d·I, W = I
        ("[[d]]", "[[1]]"),
        ("[[1, 0]]", "[[0, 1]]"),  # not even over Q(δ): W outside the row space
        ("[[1, d], [2, 2*d]]", "[[1, 0]]"),  # rank-deficient V
        ("[[d, d**2]]", "[[1, d]]"),
        ("[[d + 1, 0], [0, d - 1]]", "[[1, 1]]"),
    ],
)
def test_unsolvable_table(V, W):
    with pytest.raises(NoPolynomialSolutionError, match="row") as info:
        solve_left(PolyMatrix(V), PolyMatrix(W))
    assert isinstance(info.value, ArithmeticError) and isinstance(info.value, UioRingError)


def test_dimension_mismatch_names_both_shapes():
    V = PolyMatrix("[[1, 0, 0], [0, 1, 0]]")
    W = PolyMatrix("[[1, 0]]")
    with pytest.raises(DimensionError, match=r"2\s*[×x]\s*3.*1\s*[×x]\s*2"):
        solve_left(V, W)


def test_empty_cases():
    V = PolyMatrix.zeros(0, 3)
    assert solve_left(V, PolyMatrix.zeros(2, 3)) == PolyMatrix.zeros(2, 0)
    with pytest.raises(NoPolynomialSolutionError):
        solve_left(V, PolyMatrix("[[0, 1, 0]]"))
    V2 = PolyMatrix("[[1, d], [0, 1]]")
    assert solve_left(V2, PolyMatrix.zeros(0, 2)).shape == (0, 2)
    assert solve_left(PolyMatrix.zeros(2, 0), PolyMatrix.zeros(3, 0)).shape == (3, 2)


def test_zero_V():
    V = PolyMatrix.zeros(3, 2)
    X = solve_left(V, PolyMatrix.zeros(1, 2))
    assert X.shape == (1, 3) and (X @ V).is_zero()
    with pytest.raises(NoPolynomialSolutionError):
        solve_left(V, PolyMatrix("[[1, 0]]"))


def test_paper_001_step_1_vbar():
    """§5, Step 1: some V̄ with V̄ V = [[B, 0], [D, 0]] exists (V the nonzero Hermite rows
    of M); V̄ is a choice, so only the identity is checked."""
    s = paper_001_system()
    V = PolyMatrix("[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, δ]]")
    rhs = PolyMatrix.vstack(PolyMatrix.hstack(s["B"], PolyMatrix.zeros(4, 2)),
                            PolyMatrix.hstack(s["D"], PolyMatrix.zeros(3, 2)))
    Vbar = solve_left(V, rhs)
    assert Vbar @ V == rhs
    assert Vbar.shape == (7, 3)
    M = paper_001_M()
    assert (solve_left(M, M[0:2, :]) @ M) == M[0:2, :]
