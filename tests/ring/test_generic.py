"""The certified generic fast path (evaluation/interpolation) against elimination.

Both paths must give the same unique objects (H, S, invariant factors) and
valid transforms; matrices whose invariant factors are not (1, …, 1, det) must
make the certificate refuse, and the public functions must still be right.
"""

from __future__ import annotations

import random

import flint
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from uio_ring.ring import (
    NoPolynomialSolutionError,
    PolyMatrix,
    hermite,
    invariant_factors,
    is_hermite,
    is_smith,
    is_unimodular,
    smith,
    solve_left,
)
from uio_ring.ring._generic import (
    _polynomial_parts,
    generic_hermite,
    generic_last_factor,
    generic_solve_left,
)
from uio_ring.ring.hermite import hermite_by_elimination
from uio_ring.ring.smith import invariant_factors_by_elimination, smith_by_elimination


def random_matrix(rng: random.Random, n: int, deg: int, lo: int = -3, hi: int = 3) -> PolyMatrix:
    return PolyMatrix(
        [["+".join(f"({rng.randint(lo, hi)})*d**{e}" for e in range(deg + 1)) for _ in range(n)] for _ in range(n)]
    )


def random_unimodular(rng: random.Random, n: int, steps: int = 6) -> PolyMatrix:
    """A product of elementary matrices with polynomial entries (det = ±1)."""
    U = PolyMatrix.identity(n)
    for _ in range(steps):
        i, j = rng.sample(range(n), 2)
        E = [[1 if a == b else 0 for b in range(n)] for a in range(n)]
        E[i][j] = f"{rng.randint(-2, 2)}*d + {rng.randint(-2, 2)}"
        U = PolyMatrix(E) @ U
    return U


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(1, 9), deg=st.integers(0, 2))
@example(seed=43, n=3, deg=1)  # the shape holds, but c_n = (adj M·r)_n shares a root with det M
def test_generic_hermite_agrees_with_elimination(seed, n, deg):
    M = random_matrix(random.Random(seed), n, deg)
    got = generic_hermite(M._r, n)
    ref = hermite_by_elimination(M)
    if got is None:
        # refused: the certificate gcd(c_n, det) = 1 is sufficient, not necessary (a fixed r
        # can be unlucky), so only the fallback is checked
        assert hermite(M).H == ref.H
        return
    H, U, _ = got
    Hm, Um = PolyMatrix._new(H, n, n, "d"), PolyMatrix._new(U, n, n, "d")
    assert Hm == ref.H
    assert Um @ M == Hm
    assert Um == ref.U  # U = H M^-1 is unique for nonsingular M


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(1, 9), deg=st.integers(0, 2))
def test_generic_smith_and_factors_agree_with_elimination(seed, n, deg):
    M = random_matrix(random.Random(seed), n, deg)
    s = smith(M)
    assert s.U @ M @ s.V == s.S and is_smith(s.S)
    assert s.invariant_factors == invariant_factors_by_elimination(M)
    assert invariant_factors(M) == s.invariant_factors
    assert smith_by_elimination(M).S == s.S


@pytest.mark.parametrize("n", [6, 7, 9])
def test_nontrivial_invariant_factors_refuse_the_certificate(n):
    rng = random.Random(n)
    P, Q = random_unimodular(rng, n), random_unimodular(rng, n)
    diag = [1] * (n - 2) + ["d + 1", "(d + 1)*(d - 2)"]
    M = P @ PolyMatrix.diag(*diag) @ Q
    assert generic_last_factor(M._r, n) is None
    assert generic_hermite(M._r, n) is None or is_hermite(hermite(M).H)
    s = smith(M)
    assert [str(f) for f in s.invariant_factors] == ["1"] * (n - 2) + ["d + 1", "d**2 - d - 2"]
    assert s.U @ M @ s.V == s.S and is_unimodular(s.U) and is_unimodular(s.V)
    h = hermite(M)
    assert h.U @ M == h.H and is_hermite(h.H) and is_unimodular(h.U)


def test_singular_square_matrix_takes_the_elimination_path():
    rng = random.Random(7)
    A = random_matrix(rng, 7, 1)
    M = A[:, :6] @ PolyMatrix.hstack(PolyMatrix.identity(6), PolyMatrix([[1]] * 6))  # rank 6
    assert generic_hermite(M._r, 7) is None
    h = hermite(M)
    assert h.rank == 6 and h.U @ M == h.H and is_unimodular(h.U)


@settings(max_examples=20, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(6, 9), m=st.integers(0, 3))
@example(seed=125, n=6, m=0)  # det V vanishes at a first point and W has no rows (was an IndexError)
def test_generic_solve_recovers_the_unique_solution(seed, n, m):
    rng = random.Random(seed)
    V = random_matrix(rng, n, 1)
    X0 = PolyMatrix([["+".join(f"({rng.randint(-2, 2)})*d**{e}" for e in range(2))] * n for _ in range(m)], shape=(m, n))
    W = X0 @ V
    got = generic_solve_left(V._r, W._r, n, m)
    if V.det() == 0:
        assert got is None
    else:
        assert PolyMatrix._new(got, m, n, "d") == X0


def test_generic_solve_when_V_is_singular_at_the_first_points():
    """det V vanishes at δ = 0, 1, −1: the sampling must skip those points."""
    rng = random.Random(11)
    n = 6
    V = random_unimodular(rng, n) @ PolyMatrix.diag(*([1] * (n - 1) + ["d*(d - 1)*(d + 1)"]))
    X0 = random_matrix(rng, n, 1)[:2, :]
    assert solve_left(V, X0 @ V) == X0
    with pytest.raises(NoPolynomialSolutionError):
        solve_left(V, PolyMatrix.identity(n))


@pytest.mark.parametrize("n", [6, 7, 9])
def test_two_nontrivial_factors_by_the_adjugate_tier(n):
    from uio_ring.ring._generic import generic_invariant_factors

    rng = random.Random(100 + n)
    P, Q = random_unimodular(rng, n, 2 * n), random_unimodular(rng, n, 2 * n)
    M = P @ PolyMatrix.diag(*([1] * (n - 2) + ["(d + 1)*(d - 3)", "(d + 1)**2*(d - 3)*(d - 2)"])) @ Q
    got = generic_invariant_factors(M._r, n)
    assert got is not None
    assert tuple(got) == tuple(f._p for f in invariant_factors_by_elimination(M))
    assert invariant_factors(M) == invariant_factors_by_elimination(M)


def test_three_nontrivial_factors_fall_back_to_elimination():
    from uio_ring.ring._generic import generic_invariant_factors

    rng = random.Random(5)
    n = 6
    P, Q = random_unimodular(rng, n, 12), random_unimodular(rng, n, 12)
    M = P @ PolyMatrix.diag(1, 1, 1, "d", "d", "d") @ Q
    assert generic_invariant_factors(M._r, n) is None
    assert [str(f) for f in invariant_factors(M)] == ["1", "1", "1", "d", "d", "d"]


@pytest.mark.parametrize("n", [6, 8])
def test_degree_reduction_path_keeps_the_forms(n):
    """P·D·Q with high-degree unimodular P, Q: row degrees far above deg det, so the
    weak Popov reduction runs first; H, S and the factors must equal elimination's."""
    from uio_ring.ring._reduce import degree_reduced

    rng = random.Random(40 + n)
    P, Q = random_unimodular(rng, n, 3 * n), random_unimodular(rng, n, 3 * n)
    M = P @ PolyMatrix.diag(*([1] * (n - 2) + ["d + 1", "(d + 1)*(d - 2)"])) @ Q
    assert degree_reduced(M._r, n, track=False) is not None
    h = hermite(M)
    assert h.H == hermite_by_elimination(M).H and h.U @ M == h.H and is_unimodular(h.U)
    s = smith(M)
    assert s.U @ M @ s.V == s.S and is_unimodular(s.U) and is_unimodular(s.V)
    assert s.invariant_factors == invariant_factors(M) == invariant_factors_by_elimination(M)


@pytest.mark.parametrize("n,deg", [(3, 16), (4, 8), (5, 4)])
def test_small_square_of_high_degree_solves_by_evaluation(monkeypatch, n, deg):
    """From ``generic_first`` on (3×3 from degree 14, 4×4 from 6, 5×5 from 3) solve_left takes
    the evaluation path: the unique solution, and a non-polynomial one is refused by name."""
    import importlib

    solve_module = importlib.import_module("uio_ring.ring.solve")
    calls = []
    monkeypatch.setattr(solve_module, "generic_solve_left", lambda *a: calls.append(1) or generic_solve_left(*a))
    rng = random.Random(n * deg)
    V = random_matrix(rng, n, deg)
    X0 = random_matrix(rng, n, 2)[:2, :]
    assert solve_left(V, X0 @ V) == X0
    with pytest.raises(NoPolynomialSolutionError):
        solve_left(V, PolyMatrix.identity(n))
    assert calls == [1, 1]


def test_degree_reduced_matrix_whose_elimination_swells_takes_the_generic_tier(monkeypatch):
    """W·A·diag(1, …, 1, δ−1, δ−1) with W unimodular of high degree: the weak Popov reduction
    applies, the elimination of the reduced matrix outgrows its cap, and the adjugate tier
    gives (1, …, 1, δ − 1, (δ − 1)·det A / lc) — where the elimination without cap took minutes
    on a 9×9 of degree 8."""
    import importlib

    smith_module = importlib.import_module("uio_ring.ring.smith")
    calls = []
    real = smith_module.generic_invariant_factors
    monkeypatch.setattr(smith_module, "generic_invariant_factors", lambda a, n: calls.append(n) or real(a, n))
    rng = random.Random(0)
    n = 6
    A = random_matrix(rng, n, 3)
    M = random_unimodular(rng, n, steps=12) @ A @ PolyMatrix.diag(*([1] * (n - 2) + ["d - 1", "d - 1"]))
    f = invariant_factors(M)
    assert calls == [n]
    d1 = PolyMatrix("[[d - 1]]")[0, 0]
    assert f[: n - 2] == (PolyMatrix.identity(1)[0, 0],) * (n - 2)
    assert f[n - 2] == d1 and f[n - 1] == (d1 * A.det()).monic()
    assert f == invariant_factors_by_elimination(M)


@settings(max_examples=60, deadline=None)
@given(data=st.data(), dd=st.integers(1, 12), dw=st.integers(0, 14), k=st.integers(1, 4))
def test_polynomial_parts_equal_the_exact_quotients(data, dd, dw, k):
    # U_ij = (adj_ij + h_i·w_j)/det with adj_ij = −(h_i·w_j mod det), so of degree < deg det:
    # the series path must give the quotients of the exact divisions
    def poly(deg, big=False):
        lim = 1 << 200 if big else 5
        cs = data.draw(st.lists(st.integers(-lim, lim), min_size=deg + 1, max_size=deg + 1))
        den = data.draw(st.integers(1, 1 << 60 if big else 3))
        return flint.fmpq_poly(cs, den)

    det = poly(dd)
    if det.degree() != dd:
        det += flint.fmpq_poly([0] * dd + [1])
    h = [poly(dd - 1, big=True) for _ in range(k)]
    w = [poly(dw) for _ in range(3)]
    adj = [[-((hi * wj) % det) for wj in w] for hi in h]
    want = [[(a + hi * wj) // det for a, wj in zip(row, w, strict=True)] for row, hi in zip(adj, h, strict=True)]
    assert _polynomial_parts(h, w, det) == want
