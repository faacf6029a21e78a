"""The kernel and reduced solution of an (n+1)×n matrix from its maximal minors
(:mod:`uio_ring.ring._minors_kernel`): both are unique, so they must equal the
block-Toeplitz ones (the minors path switched off) and the elimination's kernel."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring import PolyMatrix, _kernel_basis, _minors_kernel, hermite
from uio_ring.ring import _dense as dn
from uio_ring.ring._kernel_basis import kernel_and_solution, popov_left_kernel, solve_reduced
from uio_ring.ring._minors_kernel import kernel_by_minors, solution_by_minors
from uio_ring.ring.hermite import hermite_by_elimination
from uio_ring.ring.kernel import left_kernel_by_elimination

from .strategies import assert_popov, dense_matrices, matrices


def _by_toeplitz(M: PolyMatrix, W: PolyMatrix | None):
    """K and X (or None) with the minors path off."""
    m, n = M.shape
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(_kernel_basis, "MINORS_MAX_COLUMNS", 0)
        K = popov_left_kernel(M._r, m, n, min_rows=0)
        X = None
        if W is not None and K is not None:
            X = solve_reduced(M._r, m, n, K, W._r, tries=3, multimodular=False)
    return K, X


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 4).flatmap(lambda n: matrices(min_rows=n + 1, max_rows=n + 1, min_cols=n, max_cols=n)),
       st.data())
def test_minors_kernel_and_solution_equal_the_toeplitz_ones(M, data):
    m, n = M.shape
    got = kernel_by_minors(M._r, n)
    if M.rank() < n:
        assert got is None
        return
    assert got is not None
    K, _ = _by_toeplitz(M, None)
    assert [got.row] == K
    assert PolyMatrix._new([got.row], 1, m, M.var) == left_kernel_by_elimination(M)
    assert_popov(PolyMatrix._new([got.row], 1, m, M.var))
    assert got.coprime == (hermite(M).H == PolyMatrix._new(dn.identity(n) + dn.zeros(1, n), m, n, M.var))
    if not got.coprime:
        return
    if data.draw(st.booleans()):
        W = data.draw(dense_matrices(rows=2, cols=m, max_degree=3)) @ M  # a solution exists
    else:
        W = data.draw(dense_matrices(rows=2, cols=n, max_degree=3))
    X = solution_by_minors(M._r, n, got, W._r)
    _, want = _by_toeplitz(M, W)
    if X is not None:
        assert PolyMatrix._new(X, 2, m, M.var) @ M == W
        assert want is None or X == want
    else:
        assert want is None


def test_a_combination_of_the_minors_when_no_single_one_is_coprime(monkeypatch):
    """f = det M_R = δ(δ + 1)(2δ + 1) shares a factor with each of v = (2δ² − 2, −2δ − 1):
    the unit combinations fail and a weighted one is used; with none left to try, the
    solution falls back to the Toeplitz solve — the same X either way."""
    M = PolyMatrix("[[-2, 1], [-2*d - 1, 0], [2*d + 2, -d**2 - d]]")
    I2 = PolyMatrix.identity(2)
    got = kernel_by_minors(M._r, 2)
    assert got is not None and got.coprime
    X = solution_by_minors(M._r, 2, got, I2._r)
    _, want = _by_toeplitz(M, I2)
    assert X is not None and X == want
    monkeypatch.setattr(_minors_kernel, "_POWERS", ())
    assert solution_by_minors(M._r, 2, got, I2._r) is None
    both = kernel_and_solution(M._r, 3, 2, I2._r, min_rows=0)
    assert both is not None and both.solution == want


@pytest.mark.parametrize("n,degree", [(1, 16), (2, 16), (3, 8), (4, 4)])
def test_hermite_of_one_kernel_row_solves_no_toeplitz_system(monkeypatch, n, degree):
    """(n+1)×n with coprime minors: hermite's U = [X; K] from the minors alone."""
    import random

    rng = random.Random(n * 100 + degree)

    def entry() -> str:
        return " + ".join(f"({rng.randint(-3, 3)})*d**{e}" for e in range(degree + 1))

    M = PolyMatrix([[entry() for _ in range(n)] for _ in range(n + 1)])
    calls: list = []
    monkeypatch.setattr(_kernel_basis, "lead_solve", lambda *a, **k: calls.append(1))
    monkeypatch.setattr(_kernel_basis, "_solve_reduced_at", lambda *a, **k: calls.append(2))
    h = hermite(M)
    assert calls == []
    assert h.H == PolyMatrix._new(dn.identity(n) + dn.zeros(1, n), n + 1, n, M.var)
    assert h.U @ M == h.H and h.U.det().degree() == 0
    monkeypatch.undo()
    K, X = _by_toeplitz(M, PolyMatrix.identity(n))
    assert h.U._r == X + K


def test_many_columns_take_the_minors_when_the_toeplitz_system_is_too_large(monkeypatch):
    """A 6×5 whose kernel row has degree 200: 6·201 Toeplitz unknowns exceed the cap, so
    the minors give K and X (before, K took 0.2 s of modular rank profiles and X was
    refused); they equal the elimination's."""
    rows = [[f"d**40 + {i + 1}" if j == i else "0" for j in range(5)] for i in range(5)] + [["1"] * 5]
    M = PolyMatrix(rows)
    I5 = PolyMatrix.identity(5)
    called: list = []
    monkeypatch.setattr(_kernel_basis, "_generator_degree_mod_p", lambda *a, **k: called.append(1))
    got = kernel_and_solution(M._r, 6, 5, I5._r, min_rows=0)
    assert called == [] and got is not None and got.solution is not None
    want = hermite_by_elimination(M)
    assert PolyMatrix._new(got.kernel, 1, 6, M.var) == left_kernel_by_elimination(M) == want.U[5:, :]
    assert PolyMatrix._new(got.solution, 5, 6, M.var) == want.U[:5, :]
    assert dn.row_degree(got.kernel[0]) == 200
