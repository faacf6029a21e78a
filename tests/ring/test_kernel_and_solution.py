"""One square solve for the Popov kernel K and the reduced solution X of ``X·M = W``
(:func:`uio_ring.ring._kernel_basis.kernel_and_solution`): both are unique, so they
must equal the separate :func:`popov_left_kernel` and :func:`solve_reduced` (the latter
by its exact Toeplitz solve, not the modular one) on every input — when X has degree
within the kernel's bound (the shared solve), above it (the bounds grow after it), and
when there is no X at all."""

from __future__ import annotations

import random

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring import PolyMatrix, _kernel_basis, _kernel_lead, hermite
from uio_ring.ring import _dense as dn
from uio_ring.ring._kernel_basis import kernel_and_solution, popov_left_kernel, solve_reduced
from uio_ring.ring.kernel import left_kernel_by_elimination

from .strategies import dense_matrices, matrices


def _separately(M: PolyMatrix, W: PolyMatrix, tries: int | None):
    m, n = M.shape
    K = popov_left_kernel(M._r, m, n, min_rows=0)
    if K is None:
        return None, None
    return K, solve_reduced(M._r, m, n, K, W._r, tries=tries, multimodular=False)


def _random_tall(rng: random.Random, m: int, n: int, k: int) -> PolyMatrix:
    def entry() -> str:
        return " + ".join(f"({rng.randint(-3, 3)})*d**{e}" for e in range(k + 1))

    return PolyMatrix([[entry() for _ in range(n)] for _ in range(m)])


@settings(max_examples=60, deadline=None)
@given(matrices(min_rows=1, max_rows=5, min_cols=1, max_cols=3), st.integers(1, 2), st.data())
def test_equals_the_kernel_and_the_solve_apart(M, k, data):
    """W = Y·M for a random Y (a solution exists, of any degree) or a random W (often
    none): the same K, and the same X or the same absence within the same tries."""
    m, n = M.shape
    if data.draw(st.booleans()):
        Y = data.draw(dense_matrices(rows=k, cols=m, max_degree=3))
        W = Y @ M
    else:
        W = data.draw(dense_matrices(rows=k, cols=n, max_degree=2))
    tries = data.draw(st.sampled_from([None, 1, 2]))
    if tries is None and W.is_zero() is False and M.rank() < n:
        tries = 2  # no X may exist: the bounds would grow to their cap
    got = kernel_and_solution(M._r, m, n, W._r, min_rows=0, tries=tries)
    K, X = _separately(M, W, tries)
    if K is None:
        assert got is None
        return
    assert got is not None and got.kernel == K
    if X is not None and got.solution is not None:
        assert got.solution == X
        assert PolyMatrix._new(X, k, m, M.var) @ M == W
    # the shared first bound counts as a try: the same bounds are tried in both
    assert (got.solution is None) == (X is None)


@pytest.mark.parametrize("shape,degree", [((4, 2), 8), ((3, 1), 12), ((5, 3), 4), ((4, 2), 16)])
def test_hermite_of_a_tall_matrix_takes_one_square_solve(monkeypatch, shape, degree):
    """A tall M of full column rank with coprime minors: U = [X; K] from the shared solve;
    the separate reduced solve is not called, and U equals the two computed apart."""
    M = _random_tall(random.Random(degree), *shape, degree)
    m, n = shape
    calls: list = []
    real = _kernel_basis._solve_reduced_at
    monkeypatch.setattr(_kernel_basis, "_solve_reduced_at", lambda *a, **k: calls.append(a[3]) or real(*a, **k))
    h = hermite(M)
    assert h.H == PolyMatrix._new(dn.identity(n) + dn.zeros(m - n, n), m, n, M.var)
    assert calls == []
    K, X = _separately(M, PolyMatrix._new(dn.identity(n), n, n, M.var), None)
    assert h.U._r == X + K


def test_an_x_above_the_kernel_bound_is_found_after_it(monkeypatch):
    """A 4×2 whose kernel generators have degree ≤ 2, and a W of degree 4 ≤ D + deg M
    whose reduced solution has degree 3: the shared solve at D = 2 finds none (its
    exact system refutes it), and the bounds start above 2 (2 is not tried again)."""
    M = PolyMatrix("[[2*d**2 - 2*d + 1, -2*d**2 + 1], [1, 2*d - 2], [-d, 2], [0, 2*d + 2]]")
    W = PolyMatrix("[[d**4 + d**3 - 5*d - 1, -2*d**3 - 6*d**2 + 4*d + 11]]")
    calls: list = []
    real = _kernel_basis._solve_reduced_at
    monkeypatch.setattr(_kernel_basis, "_solve_reduced_at", lambda *a, **k: calls.append(a[3]) or real(*a, **k))
    got = kernel_and_solution(M._r, 4, 2, W._r, min_rows=0)
    assert got is not None and got.solution is not None
    assert max(dn.mat_degree(got.kernel), 0) <= 2 < dn.mat_degree(got.solution)
    assert calls and min(calls) > 2
    K, X = _separately(M, W, None)
    assert got.kernel == K and got.solution == X
    assert PolyMatrix._new(X, 1, 4, "d") @ M == W


def test_the_generic_guess_needs_no_rank_profile(monkeypatch):
    """A random 4×2 of degree 8: minimal indices 8 and 8 = 2·8/2, leading monomials the
    last two columns; the kernel and X come without any modular rank profile, equal to
    those of the profile route and to the elimination's kernel."""
    M = _random_tall(random.Random(5), 4, 2, 8)
    I2 = PolyMatrix.identity(2)
    want = kernel_and_solution(M._r, 4, 2, I2._r, min_rows=0)
    with monkeypatch.context() as mp:
        mp.setattr(_kernel_basis, "_generic_generators", lambda *a, **k: None)
        profiled = kernel_and_solution(M._r, 4, 2, I2._r, min_rows=0)
    calls: list = []
    monkeypatch.setattr(_kernel_basis, "_generator_degree_mod_p", lambda *a, **k: calls.append(1))
    got = kernel_and_solution(M._r, 4, 2, I2._r, min_rows=0)
    assert calls == [] and got == want == profiled
    assert [dn.leading_position(r) for r in got.kernel] == [(8, 2), (8, 3)]
    assert PolyMatrix._new(got.kernel, 2, 4, M.var) == left_kernel_by_elimination(M)


@pytest.mark.parametrize(("shape", "degree", "indices"), [
    ((4, 1), 8, [2, 3, 3]),          # k = 3 does not divide n·deg M = 8: degrees D − 1 and D
    ((6, 1), 16, [3, 3, 3, 3, 4]),
    ((5, 2), 7, [4, 5, 5]),
])
def test_the_generic_guess_with_two_minimal_indices(monkeypatch, shape, degree, indices):
    """When k does not divide n·deg M the generic minimal indices are ⌈n·deg M / k⌉ and
    one less: still no modular rank profile, and the same kernel and X as the profile
    route and the elimination."""
    m, n = shape
    M = _random_tall(random.Random(3), m, n, degree)
    rhs = PolyMatrix.identity(n)._r
    with monkeypatch.context() as mp:
        mp.setattr(_kernel_basis, "_generic_generators", lambda *a, **k: None)
        profiled = kernel_and_solution(M._r, m, n, rhs, min_rows=0)
    calls: list = []
    monkeypatch.setattr(_kernel_basis, "_generator_degree_mod_p", lambda *a, **k: calls.append(1))
    got = kernel_and_solution(M._r, m, n, rhs, min_rows=0)
    assert calls == [] and got == profiled
    assert sorted(dn.row_degree(r) for r in got.kernel) == indices
    assert PolyMatrix._new(got.kernel, m - n, m, M.var) == left_kernel_by_elimination(M)
    assert dn.matmul(got.solution, M._r, n, m, n) == rhs


def test_a_wrong_guess_is_refused_and_the_profile_decides(monkeypatch):
    """Minimal indices 0 and 2 (not 1 and 1 = 2·1/2): the guessed square system is
    singular, the guess is refused by its determinant modulo the guard prime before any
    exact solve, and the profile route gives the kernel."""
    M = PolyMatrix("[[-d, d - 2], [d + 2, -2], [-1, 2*d + 2], [d + 2, d - 2]]")
    coeffs = _kernel_basis.ToeplitzCoefficients.of(M._r, 4, 2)
    with monkeypatch.context() as mp:
        solves: list = []
        mp.setattr(_kernel_lead, "solve_square", lambda *a, **k: solves.append(1))
        assert _kernel_basis._generic_generators(coeffs, 4, 2, 1, 2, None) is None
        assert solves == []
    K = popov_left_kernel(M._r, 4, 2, min_rows=0)
    assert K is not None and [dn.row_degree(r) for r in K] == [0, 2]
    assert PolyMatrix._new(K, 2, 4, M.var) == left_kernel_by_elimination(M)


@settings(max_examples=40, deadline=None)
@given(st.sampled_from([(3, 1), (4, 2), (5, 3), (5, 1), (4, 1), (5, 2), (6, 1)]), st.integers(1, 3),
       st.integers(0, 10**6))
def test_kernels_of_few_columns_equal_the_elimination(shape, degree, seed):
    """Whatever route (minors, generic guess, profile), the kernel is the elimination's."""
    M = _random_tall(random.Random(seed), *shape, degree)
    K = popov_left_kernel(M._r, *shape, min_rows=0)
    assert K is not None
    assert PolyMatrix._new(K, len(K), shape[0], M.var) == left_kernel_by_elimination(M)
