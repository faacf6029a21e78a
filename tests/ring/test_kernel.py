"""Left kernel: K M = 0, K a basis (full row rank, right count), saturated, Popov.

A basis of the left kernel is not unique in general, but its documented
normalisation (row-wise Popov form, zero shift) is; the tests check the
normalisation entry by entry rather than pinning values.
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from uio_ring import (
    PolyMatrix,
    invariant_factors,
    is_right_unimodular,
    left_kernel,
    right_inverse,
    right_kernel,
    solve_left,
)

from .strategies import (
    assert_popov,
    dense_matrices,
    heavy,
    matrices,
    paper_001_M,
    rank_deficient_matrices,
    reference_rank,
    unimodular_matrices,
)


def check_left_kernel(M: PolyMatrix) -> PolyMatrix:
    K = left_kernel(M)
    r = M.rank()
    assert K.shape == (M.rows - r, M.rows)
    assert (K @ M).is_zero()
    assert K.rank() == K.rows  # rows independent
    # saturated (left prime / the row module is a direct summand): invariant factors all 1,
    # equivalently K has a polynomial right inverse
    assert invariant_factors(K) == (1,) * K.rows
    assert is_right_unimodular(K)
    assert K @ right_inverse(K) == PolyMatrix.identity(K.rows)
    assert_popov(K)
    return K


@given(matrices())
def test_left_kernel_properties(M):
    check_left_kernel(M)


@given(matrices(max_rows=5, max_cols=5))
def test_left_kernel_dimension_matches_sympy_rank(M):
    assert left_kernel(M).rows == M.rows - reference_rank(M)


@given(st.data())
def test_left_kernel_spans_known_relations(data):
    """M = [A; Y A]: every row of [−Y, I] is in the left kernel, so it must be a polynomial
    combination of the basis rows (completeness over Q[δ], not only over Q(δ))."""
    p = data.draw(st.integers(0, 4))
    q = data.draw(st.integers(0, 4))
    k = data.draw(st.integers(1, 3))
    A = data.draw(dense_matrices(rows=p, cols=q, max_degree=2))
    Y = data.draw(dense_matrices(rows=k, cols=p, max_degree=2))
    M = PolyMatrix.vstack(A, Y @ A)
    K = check_left_kernel(M)
    R = PolyMatrix.hstack(-Y, PolyMatrix.identity(k))
    assert (R @ M).is_zero()
    X = solve_left(K, R)
    assert X @ K == R


@pytest.mark.parametrize(
    "shape, krows",
    [((0, 0), 0), ((0, 3), 0), ((3, 0), 3), ((3, 3), 3), ((2, 4), 2), ((4, 2), 4)],
)
def test_empty_and_zero_matrices(shape, krows):
    K = check_left_kernel(PolyMatrix.zeros(*shape))
    assert K.shape == (krows, shape[0])
    assert K == PolyMatrix.identity(shape[0])  # the Popov basis of the whole space


def test_full_row_rank_has_empty_kernel():
    M = PolyMatrix("[[1, d, 0], [0, d, 1]]")
    K = check_left_kernel(M)
    assert K.shape == (0, 2)


def test_known_kernels():
    M = PolyMatrix("[[1], [d], [d**2]]")
    K = check_left_kernel(M)
    assert [max(e.degree() for e in row) for row in K.tolist()] == [1, 1]  # minimal indices
    N = PolyMatrix("[[d, 1], [2*d, 2], [d**2, d]]")  # rank 1
    KN = check_left_kernel(N)
    assert KN.rows == 2


def test_rank_deficient():
    a = PolyMatrix("[[1, d], [d - 1, 2], [0, 1], [d, d**2]]")
    b = PolyMatrix("[[d, 1, 0], [1, 0, d + 1]]")
    K = check_left_kernel(a @ b)
    assert K.rows == 2


def test_paper_001_kernel():
    """M = [[CB, D], [D, 0]] has rank 3, so its left kernel has 6 − 3 = 3 rows."""
    K = check_left_kernel(paper_001_M())
    assert K.shape == (3, 6)


@heavy()
@given(st.data())
def test_left_kernel_of_few_rows_of_high_degree_equals_the_elimination(data):
    """Below 6 rows and from δ-degree CAP_MIN_DEGREE on, left_kernel takes hermite's
    kernel rows (capped elimination, then the Toeplitz systems): the same unique Popov
    basis as the plain elimination."""
    from uio_ring.ring.hermite import CAP_MIN_DEGREE
    from uio_ring.ring.kernel import left_kernel_by_elimination

    m = data.draw(st.integers(2, 5))
    n = data.draw(st.integers(1, m))
    M = data.draw(rank_deficient_matrices(rows=m, cols=n))
    M = M + PolyMatrix([[f"d**{CAP_MIN_DEGREE}" if (i, j) == (m - 1, 0) else 0 for j in range(n)]
                        for i in range(m)])
    K = left_kernel(M)
    assert K == left_kernel_by_elimination(M)
    assert (K @ M).is_zero()


@heavy()
@given(st.data())
def test_solve_left_and_left_inverse_of_few_rows_of_high_degree_equal_the_elimination(data):
    """Below 6 rows from δ-degree CAP_MIN_DEGREE on, solve_left and left_inverse give way
    to the Toeplitz systems when the capped elimination stops; the reduced solution and
    the reduced left inverse are unique, so they equal the uncapped elimination's."""
    import importlib

    from uio_ring import left_inverse

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    n = data.draw(st.integers(1, 3))
    m = data.draw(st.integers(n + 1, 5))
    V = data.draw(unimodular_matrices(m, max_degree=2))[:, :n]  # left unimodular
    V = V + PolyMatrix([[f"d**{hermite_module.CAP_MIN_DEGREE}" if (i, j) == (m - 1, 0) else 0
                         for j in range(n)] for i in range(m)])
    W = data.draw(dense_matrices(rows=2, cols=m, max_degree=1)) @ V
    X = solve_left(V, W)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hermite_module, "CAP_MIN_DEGREE", 10**9)
        X0 = solve_left(V, W)
        L0 = left_inverse(V) if V.rank() == n and invariant_factors(V) == (1,) * n else None
    assert X @ V == W and X == X0
    if L0 is not None:
        assert left_inverse(V) == L0


def test_full_row_rank_few_rows_of_high_degree_has_an_empty_kernel_without_hermite(monkeypatch):
    """A 4×4 of degree 32 with full rank: the exact rank answers (the Hermite form cost 0.8 s);
    with a dependent row, the Popov kernel row still comes from the Hermite transform."""
    import importlib
    import random

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    calls = []
    real = hermite_module.hermite
    monkeypatch.setattr(hermite_module, "hermite", lambda M: calls.append(1) or real(M))
    rng = random.Random(1)
    rows = [["+".join(f"({rng.randint(-3, 3)})*d**{e}" for e in range(33)) for _ in range(4)] for _ in range(4)]
    M = PolyMatrix(rows)
    assert left_kernel(M).shape == (0, 4) and right_kernel(M).shape == (4, 0)
    assert calls == []
    S = PolyMatrix(rows[:3] + [rows[0]])  # row 4 = row 1
    K = left_kernel(S)
    assert calls
    assert K.shape == (1, 4) and K @ S == PolyMatrix.zeros(1, 4)
    assert K == PolyMatrix([[-1, 0, 0, 1]]) or K == PolyMatrix([[1, 0, 0, -1]])


@pytest.mark.parametrize("m, n, degree", [(4, 2, 16), (3, 1, 24), (5, 3, 9)])
def test_full_column_rank_few_rows_of_high_degree_skip_the_hermite_transform(monkeypatch, m, n, degree):
    """Tall M of full column rank, few rows and high degree: the Popov kernel is the
    block-Toeplitz one alone — no Hermite form and its reduced solution X (a spy) — and
    equals the kernel rows of hermite's transform (the basis is unique)."""
    import importlib
    import random

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    rng = random.Random(m * n)
    M = PolyMatrix([["+".join(f"({rng.randint(-3, 3)})*d**{e}" for e in range(degree + 1)) for _ in range(n)]
                    for _ in range(m)])
    calls = []
    real = hermite_module.hermite
    monkeypatch.setattr(hermite_module, "hermite", lambda A: calls.append(1) or real(A))
    K = left_kernel(M)
    assert calls == []
    h = real(M)
    assert K == h.U[h.rank :, :] and K.shape == (m - n, m)
    assert_popov(K)
