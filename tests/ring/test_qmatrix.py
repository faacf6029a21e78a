"""QMatrix: the immutable façade over exact constant matrices (uio_ring.ring.qmatrix)."""

from __future__ import annotations

import random
from fractions import Fraction as Fr

import pytest
import sympy

from uio_ring.ring import PolyMatrix, QMatrix
from uio_ring.ring.errors import DimensionError, DomainError


def _random(rng: random.Random, m: int, n: int, rank: int | None = None) -> QMatrix:
    if rank is None:
        return QMatrix([[Fr(rng.randint(-5, 5), rng.randint(1, 3)) for _ in range(n)] for _ in range(m)], shape=(m, n))
    L = _random(rng, m, rank)
    R = _random(rng, rank, n)
    return L @ R


def _sympy(M: QMatrix) -> sympy.Matrix:
    return sympy.Matrix(M.rows, M.cols, lambda i, j: sympy.Rational(M[i, j].numerator, M[i, j].denominator))


def test_construction_entries_and_conversion():
    M = QMatrix([[1, "1/2"], [0.1, Fr(-3, 4)]])
    assert M.shape == (2, 2) and M[1, 0] == Fr(1, 10) and isinstance(M[0, 0], Fr)
    assert M.tolist() == [[1, Fr(1, 2)], [Fr(1, 10), Fr(-3, 4)]]
    P = PolyMatrix("[[1, 1/2], [1/10, -3/4]]")
    assert M.to_polymatrix() == P and QMatrix(P) == M and QMatrix.from_polymatrix(P) == M
    assert QMatrix([], shape=(0, 3)).shape == (0, 3) and QMatrix([[], []], shape=(2, 0)).shape == (2, 0)
    assert repr(QMatrix.zeros(0, 2)) == "QMatrix.zeros(0, 2)" and repr(M) == "QMatrix([[1, 1/2], [1/10, -3/4]])"
    assert hash(M) == hash(QMatrix(M.tolist()))


@pytest.mark.parametrize(
    ("call", "exc", "match"),
    [
        (lambda: QMatrix([[1, 2], [3]]), DimensionError, "row 1 has 1 entries"),
        (lambda: QMatrix(PolyMatrix("[[d]]")), DomainError, "constant"),
        (lambda: QMatrix([[1]]) + QMatrix([[1, 2]]), DimensionError, r"1×1 and a 1×2"),
        (lambda: QMatrix([[1, 2]]) @ QMatrix([[1, 2]]), DimensionError, "2 columns vs 1 rows"),
        (lambda: QMatrix([[1]]) * 0.5, DomainError, "float"),
        (lambda: QMatrix([[1, 1], [1, 1]]).inverse(name="Z"), DimensionError, "Z is singular"),
        (lambda: QMatrix([[1, 2]])[0, 2], IndexError, "out of range"),
        (lambda: QMatrix.vstack(QMatrix([[1]]), QMatrix([[1, 2]])), DimensionError, "block 1"),
    ],
)
def test_errors(call, exc, match):
    with pytest.raises(exc, match=match):
        call()


def test_immutable():
    M = QMatrix.identity(2)
    with pytest.raises(AttributeError, match="immutable"):
        M._q = None  # type: ignore[misc]
    N = M + M
    assert M == QMatrix.identity(2) and N == 2 * M and -N == M * -2
    with pytest.raises(TypeError):
        bool(M)


def test_selection_and_stacking():
    M = QMatrix([[1, 2, 3], [4, 5, 6]])
    assert M[:, 1:] == QMatrix([[2, 3], [5, 6]]) and M[1, :] == QMatrix([[4, 5, 6]])
    assert M.take_cols([2, 0]) == QMatrix([[3, 1], [6, 4]]) and M.take_rows([1, 1]).rows == 2
    assert M.T.shape == (3, 2) and M.row(0) == M[0, :] and M.col(-1) == M[:, 2]
    assert QMatrix.hstack(M, QMatrix.zeros(2, 0)) == M and QMatrix.vstack(QMatrix.zeros(0, 3), M) == M
    assert QMatrix.block([[QMatrix.identity(1), QMatrix.zeros(1, 1)], [QMatrix.zeros(1, 1), QMatrix.identity(1)]]) == QMatrix.identity(2)
    assert QMatrix.vstack(cols=4).shape == (0, 4) and QMatrix.hstack(rows=2).shape == (2, 0)
    assert QMatrix.unit(3, 1) == QMatrix([[0], [1], [0]])


@pytest.mark.parametrize("seed", range(8))
def test_linear_algebra_identities(seed):
    rng = random.Random(seed)
    m, n = rng.randint(1, 5), rng.randint(1, 5)
    r = rng.randint(0, min(m, n))
    M = _random(rng, m, n, r)
    assert M.rank() == _sympy(M).rank() == r
    e = M.rref()
    assert e.rank == r and e.R == QMatrix(_sympy(M).rref()[0].tolist()) and e.pivots == _sympy(M).rref()[1]
    N, L = M.nullspace(), M.left_nullspace()
    assert N.shape == (n, n - r) and (M @ N).is_zero() and N.rank() == n - r
    assert L.shape == (m - r, m) and (L @ M).is_zero() and L.rank() == m - r
    basis = M.row_basis()
    assert len(basis) == r and M.take_rows(basis).rank() == r
    S = _random(rng, n, n)
    if S.rank() == n:
        assert S @ S.inverse() == QMatrix.identity(n) and S.det() == Fr(str(_sympy(S).det()))
        B = _random(rng, n, 2)
        assert S @ S.solve(B) == B


@pytest.mark.parametrize("seed", range(8))
def test_min_norm_left_solve(seed):
    rng = random.Random(seed)
    p, m = rng.randint(1, 4), rng.randint(1, 3)
    W = _random(rng, p, m, rng.randint(0, min(p, m)))
    zeta0 = _random(rng, 1, p)
    b = zeta0 @ W
    z = W.min_norm_left_solve(b)
    assert z is not None and z @ W == b
    # minimum norm: ζ is orthogonal to the left null space of W (so it equals b W⁺)
    assert (W.left_nullspace() @ z.T).is_zero()
    pinv = _sympy(W).pinv()
    assert _sympy(z) == _sympy(b) * pinv
    if W.rank() < m:
        # a right side outside the row space of W has no solution
        c = W.nullspace()
        assert W.min_norm_left_solve(b + c.T[0:1, :]) is None


def test_solve_by_peeling():
    H = QMatrix([[0, 2, 0], [1, 3, 0], [5, 0, 1]])
    w = QMatrix([[4], [5], [6]])
    x = H.solve_by_peeling(w)
    assert x is not None and H @ x == w
    assert QMatrix([[1, 1], [1, 2]]).solve_by_peeling(QMatrix([[1], [1]])) is None
