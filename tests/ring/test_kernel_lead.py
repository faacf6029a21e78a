"""Popov kernel rows from the leading monomials modulo a prime and one exact square
solve (:mod:`uio_ring.ring._kernel_lead`) against the fraction-free nullspace of the
whole Toeplitz matrix (:func:`uio_ring.ring._kernel_basis._exact_generators`): the
reduced echelon generators are unique, so the two must agree exactly — and with a
tiny prime, where rank drops modulo p are common, the modular path may give up
(None) but never returns other vectors."""

from __future__ import annotations

import flint
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring import PolyMatrix, _kernel_basis
from uio_ring.ring import _dense as dn
from uio_ring.ring._evaluation import minor_degree_bound
from uio_ring.ring._kernel_basis import (
    ToeplitzCoefficients,
    _exact_generators,
    _generator_degree_mod_p,
    _integer_coefficients,
    _toeplitz_entries,
    popov_left_kernel,
)
from uio_ring.ring._kernel_lead import (
    PRIME,
    generators_by_crt,
    generators_by_lead_solve,
    pivot_columns_mod_p,
    solve_square,
)
from uio_ring.ring._reduced_crt import worthwhile
from uio_ring.ring.kernel import left_kernel_by_elimination

from .strategies import dense_matrices, matrices


def _both(M: PolyMatrix, D: int, p: int | None = None):
    m, n = M.shape
    dm = max(dn.mat_degree(M._r), 0)
    mi = _integer_coefficients(M._r, m, n)
    full = _toeplitz_entries(mi, m, n, dm, D, None)
    rows, cols = n * (D + dm + 1), m * (D + 1)
    fast = generators_by_lead_solve(full, rows, cols, m) if p is None else generators_by_lead_solve(full, rows, cols, m, p)
    return fast, _exact_generators(mi, m, n, dm, D)


@given(matrices(min_rows=1, min_cols=1), st.integers(0, 3))
def test_lead_solve_equals_exact_nullspace(M, D):
    fast, exact = _both(M, D)
    assert fast == exact


@settings(max_examples=400)
@given(matrices(min_rows=1, min_cols=1, rational=False), st.integers(0, 2), st.sampled_from([2, 3, 5]))
def test_lead_solve_with_a_tiny_prime_is_right_or_gives_up(M, D, p):
    fast, exact = _both(M, D, p)
    assert fast is None or fast == exact


def test_lead_solve_gives_up_on_an_unlucky_prime():
    # M = [3; 1]: modulo 3 the first row vanishes, so e_0 looks like a kernel vector;
    # over Q the kernel is spanned by (1, −3), led by e_1
    M = PolyMatrix("[[3], [1]]")
    assert _both(M, 0, 3)[0] is None
    fast, exact = _both(M, 0)
    assert fast == exact and [i for i, _ in fast] == [1]
    # T_D ≡ 0 mod p without being 0 (found by the property test above): no kernel at all
    assert _both(PolyMatrix("[[2]]"), 0, 2) == (None, [])


def test_pivot_columns_mod_p():
    assert pivot_columns_mod_p([1, 2, 3, 2, 4, 7], 2, 3) == [0, 2]
    assert pivot_columns_mod_p([3, 1], 1, 2, 3) == [1]
    assert pivot_columns_mod_p([0, 0], 1, 2) == []



# ----------------------------------------------------------------------------
# the degree probe of popov_left_kernel, precomputed pivots, the square solve
# ----------------------------------------------------------------------------
def _generators_at(M: PolyMatrix, D: int, pivots: list[int]):
    m, n = M.shape
    dm = max(dn.mat_degree(M._r), 0)
    full = _toeplitz_entries(_integer_coefficients(M._r, m, n), m, n, dm, D, None)
    return generators_by_lead_solve(full, n * (D + dm + 1), m * (D + 1), m, pivots=pivots)


@settings(max_examples=200)
@given(matrices(min_rows=1, min_cols=1), st.integers(0, 2), st.data())
def test_lead_solve_with_wrong_pivots_is_right_or_gives_up(M, D, data):
    """A pivot list that is not the rank profile: with one pivot dropped the certificate
    fails or still gives the exact generators — never other vectors; with a dependent
    column added no square nonsingular system exists (None), or no generator is left and
    some are missed: a genuine profile is a precondition, and the caller's count of
    m − rank M generators notices missing ones."""
    m, n = M.shape
    dm = max(dn.mat_degree(M._r), 0)
    mi = _integer_coefficients(M._r, m, n)
    full = _toeplitz_entries(mi, m, n, dm, D, None)
    rows, cols = n * (D + dm + 1), m * (D + 1)
    pivots = pivot_columns_mod_p(full, rows, cols)
    assert _generators_at(M, D, pivots) == _exact_generators(mi, m, n, dm, D)
    if pivots and data.draw(st.booleans()):
        wrong = list(pivots)
        del wrong[data.draw(st.integers(0, len(wrong) - 1))]
        got = _generators_at(M, D, wrong)
        assert got is None or got == _exact_generators(mi, m, n, dm, D)
    extra = [c for c in range(cols) if c not in pivots]
    if extra:
        got = _generators_at(M, D, sorted([*pivots, data.draw(st.sampled_from(extra))]))
        exact = _exact_generators(mi, m, n, dm, D)
        assert got is None or all(g in exact for g in got)


def _krylov(C: PolyMatrix, A: PolyMatrix, blocks: int) -> PolyMatrix:
    rows = [C]
    for _ in range(blocks - 1):
        rows.append(rows[-1] @ A)
    return PolyMatrix.vstack(*rows)


@pytest.mark.parametrize("probe_min", [0, 10**6])
def test_probe_finds_a_constant_kernel_below_the_start_degree(monkeypatch, probe_min):
    """M = [N; R·N] with R constant has the constant Popov kernel [−R, I] (as the
    observability matrix of a 32-state design has): the probe looks at D' = 0 although
    the minor bound starts at D ≥ 1, and the basis equals the elimination one — with the
    small probes, and with the profile of T_D alone (``PROBE_MIN_UNKNOWNS``)."""
    monkeypatch.setattr(_kernel_basis, "PROBE_MIN_UNKNOWNS", probe_min)
    N = PolyMatrix("[[d**2, 1, 0], [0, d + 1, d**2], [1, 0, 2*d**2 - 1]]")
    R = PolyMatrix("[[1, 2, 0], [0, -1, 3], [5, 0, 1]]")
    M = PolyMatrix.vstack(N, R @ N)
    m, n = M.shape
    coeffs = ToeplitzCoefficients.of(M._r, m, n)
    k = m - M.rank()
    bound = minor_degree_bound(M._r, m, n, M.rank())
    D = -(-bound // k)
    d_use, pivots = _generator_degree_mod_p(coeffs.residues, m, n, coeffs.dm, D, k)
    assert D >= 1
    assert d_use == 0 and pivots == pivot_columns_mod_p(
        _toeplitz_entries(coeffs.mi, m, n, coeffs.dm, 0, None), n * (coeffs.dm + 1), m)
    K = popov_left_kernel(M._r, m, n, min_rows=0)
    assert K is not None
    assert PolyMatrix._new(K, len(K), m, M.var) == left_kernel_by_elimination(M)
    assert PolyMatrix._new(K, len(K), m, M.var) == PolyMatrix.hstack(-R, PolyMatrix.identity(3))


@settings(max_examples=30)
@given(st.integers(1, 3), st.integers(2, 4), st.integers(0, 10**6))
def test_probe_kernel_of_krylov_matrices_equals_elimination(r, n, seed):
    import random

    rng = random.Random(seed)
    A = PolyMatrix([[f"{rng.randint(-3, 3)}*d + {rng.randint(-3, 3)}" for _ in range(n)] for _ in range(n)])
    C = PolyMatrix([[str(rng.randint(-2, 2)) for _ in range(n)] for _ in range(r)])
    M = _krylov(C, A, n + 2)
    K = popov_left_kernel(M._r, *M.shape, min_rows=0)
    assert K is not None
    assert PolyMatrix._new(K, len(K), M.rows, M.var) == left_kernel_by_elimination(M)


@settings(max_examples=30)
@given(st.integers(1, 3), st.integers(2, 4), st.integers(0, 10**6))
def test_probes_and_the_whole_profile_agree(r, n, seed):
    """The generator degree D' and the pivots are the same whether the small probes run
    or only ``T_D``'s profile is computed (each probe's profile is a part of it)."""
    import random

    rng = random.Random(seed)
    A = PolyMatrix([[f"{rng.randint(-3, 3)}*d + {rng.randint(-3, 3)}" for _ in range(n)] for _ in range(n)])
    C = PolyMatrix([[str(rng.randint(-2, 2)) for _ in range(n)] for _ in range(r)])
    M = _krylov(C, A, n + 2)
    m, rank = M.rows, M.rank()
    if rank in (0, m):
        return
    coeffs = ToeplitzCoefficients.of(M._r, m, n)
    D = -(-minor_degree_bound(M._r, m, n, rank) // (m - rank))
    got = []
    for probe_min in (0, 10**6):
        with pytest.MonkeyPatch.context() as mp:
            mp.setattr(_kernel_basis, "PROBE_MIN_UNKNOWNS", probe_min)
            got.append(_generator_degree_mod_p(coeffs.residues, m, n, coeffs.dm, D, m - rank))
    assert got[0] == got[1]


def test_probe_falls_back_when_the_lead_solve_gives_up(monkeypatch):
    """An unlucky prime at D' (simulated: the lead solve returns None) falls back to the
    fraction-free nullspace at the start degree: same basis."""
    N = PolyMatrix("[[d**2, 1, 0], [0, d + 1, d**2], [1, 0, 2*d**2 - 1]]")
    M = PolyMatrix.vstack(N, PolyMatrix("[[1, 2, 0], [0, -1, 3], [5, 0, 1]]") @ N)
    want = popov_left_kernel(M._r, *M.shape, min_rows=0)
    monkeypatch.setattr(_kernel_basis, "lead_solve", lambda *a, **k: None)
    assert popov_left_kernel(M._r, *M.shape, min_rows=0) == want


@settings(max_examples=20, deadline=None)
@given(st.integers(3, 4), st.integers(0, 10**6))
def test_small_nullity_of_high_degree_takes_the_modular_solve(n, seed):
    """A tall (n + 2)×n of degree > n: 2 kernel rows (fewer than m/2) and no Schur
    complement (degree above the columns).  The kernel comes from the rank profile and
    one certified solve — the fraction-free nullspace is not called (it swelled for
    56 s on the 600×570 Toeplitz matrix of a 6×4 observability matrix of degree 55) —
    and equals the elimination's Popov basis."""
    import random

    rng = random.Random(seed)
    deg = n + 2
    M = PolyMatrix([[" + ".join(f"{rng.randint(-3, 3)}*d**{e}" for e in range(deg + 1)) for _ in range(n)]
                    for _ in range(n + 2)])
    m = M.rows
    assert 2 * (m - M.rank()) < m and not worthwhile(n, dn.mat_degree(M._r))
    original = _kernel_basis._exact_generators

    def refuse(*args, **kwargs):
        raise AssertionError("the fraction-free nullspace was called")

    _kernel_basis._exact_generators = refuse
    try:
        K = popov_left_kernel(M._r, m, n, min_rows=0)
    finally:
        _kernel_basis._exact_generators = original
    assert K is not None
    assert PolyMatrix._new(K, len(K), m, M.var) == left_kernel_by_elimination(M)


def test_toeplitz_coefficients_residues():
    M = PolyMatrix("[[-1/2, d/3], [d**2 - 7, 2*d/3]]")
    c = ToeplitzCoefficients.of(M._r, 2, 2)
    assert c.mi == _integer_coefficients(M._r, 2, 2) and c.dm == 2
    assert all(0 <= x < PRIME and (x - y) % PRIME == 0
               for ra, rb in zip(c.residues, c.mi, strict=True) for a, b in zip(ra, rb, strict=True)
               for x, y in zip(a, b, strict=True))


@given(st.integers(1, 20), st.integers(1, 4), st.integers(0, 10**6))
def test_solve_square_equals_the_rational_solve(n, k, seed):
    import random

    rng = random.Random(seed)
    a = flint.fmpz_mat(n, n, [rng.randint(-2**70, 2**70) for _ in range(n * n)])
    b = flint.fmpz_mat(n, k, [rng.randint(-9, 9) for _ in range(n * k)])
    if a.det() == 0:
        with pytest.raises(ZeroDivisionError):
            solve_square(a, b)
        return
    x = solve_square(a, b)
    assert x == flint.fmpq_mat(a).solve(flint.fmpq_mat(b))
    assert flint.fmpq_mat(a) * x == flint.fmpq_mat(b)


def test_solve_square_singular():
    with pytest.raises(ZeroDivisionError):
        solve_square(flint.fmpz_mat([[1, 2], [2, 4]]), flint.fmpz_mat([[1], [1]]))


def test_solve_square_both_solvers():
    """Few unknowns, big entries, many right-hand sides: the multimodular solve; many
    unknowns, small entries: lifting.  Both give the exact solution."""
    import random

    rng = random.Random(3)
    for n, bits, k in ((3, 900, 12), (30, 8, 2)):
        a = flint.fmpz_mat(n, n, [rng.randint(-2**bits, 2**bits) for _ in range(n * n)])
        b = flint.fmpz_mat(n, k, [rng.randint(-99, 99) for _ in range(n * k)])
        x = solve_square(a, b)
        assert flint.fmpq_mat(a) * x == flint.fmpq_mat(b)


# ----------------------------------------------------------------------------
# the generators of a rank-n matrix by the Schur complement modulo primes
# ----------------------------------------------------------------------------
def _crt_and_exact(M: PolyMatrix, D: int, pivots: list[int] | None = None):
    m, n = M.shape
    dm = max(dn.mat_degree(M._r), 0)
    mi = _integer_coefficients(M._r, m, n)
    if pivots is None:
        pivots = pivot_columns_mod_p(_toeplitz_entries(mi, m, n, dm, D, None), n * (D + dm + 1), m * (D + 1))
    return generators_by_crt(mi, dm, m, n, D, pivots), _exact_generators(mi, m, n, dm, D)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 4), st.integers(1, 4), st.integers(0, 4), st.data())
def test_crt_generators_equal_exact_nullspace(n, extra, D, data):
    M = data.draw(dense_matrices(rows=n + extra, cols=n, max_degree=2))
    fast, exact = _crt_and_exact(M, D)
    assert fast is None or fast == exact
    if M.rank() == n and len(exact) == extra and worthwhile(n, max(dn.mat_degree(M._r), 0)):
        # every generator found at D; the solver applies unless A_0 is singular
        rest = [j for j in range(n + extra) if j not in {i % (n + extra) for i, _ in exact}]
        a0 = PolyMatrix([[str(M._r[j][c][0]) for c in range(n)] for j in rest])
        if a0.det() != 0 and any(i >= n + extra for i, _ in exact):
            assert fast == exact


def test_crt_generators_of_a_tall_generic_matrix():
    M = PolyMatrix("[[1, d**2 - 1], [d, 2], [3, d + 1], [d**2, -1], [2*d - 1, d], [1, 1], [d, 0]]")
    m, n = M.shape
    D, pivots = _generator_degree_mod_p(ToeplitzCoefficients.of(M._r, m, n).residues, m, n, 2, 5, m - n)
    fast, exact = _crt_and_exact(M, D, pivots)
    assert fast is not None and fast == exact and len(fast) == m - n
    # a pivot column (not a leading monomial over Q) passed off as a generator: no kernel
    # vector has it as its greatest monomial, so the certificate refuses
    gen = max(i for i, _ in fast)
    fake = max(c for c in pivots if c % m != gen % m and c // m == gen // m)
    wrong = sorted([*[c for c in pivots if c != fake], gen])
    assert _crt_and_exact(M, D, wrong)[0] is None


def test_kernel_falls_back_when_the_crt_generators_give_up(monkeypatch):
    M = PolyMatrix("[[1, d**2 - 1], [d, 2], [3, d + 1], [d**2, -1], [2*d - 1, d], [1, 1], [d, 0]]")
    want = left_kernel_by_elimination(M)._r
    assert popov_left_kernel(M._r, *M.shape) == want
    monkeypatch.setattr(_kernel_basis, "generators_by_crt", lambda *a, **k: None)
    assert popov_left_kernel(M._r, *M.shape) == want


@settings(max_examples=40, deadline=None)
@given(m=st.integers(1, 4), n=st.integers(1, 3), dm=st.integers(0, 4), D=st.integers(0, 5),
       data=st.data(), mod=st.sampled_from([None, 7]))
def test_toeplitz_entries_match_their_definition(m, n, dm, D, data, mod):
    """``T[(t, l), (e, j)]`` = coefficient t − e of M[j][l] (reduced modulo ``mod``), zero
    elsewhere: T·vec(x) = vec(x·M).  The strided writes must put every coefficient in
    its D + 1 places and nothing anywhere else."""
    coeff = st.integers(-9, 9)
    mi = [[data.draw(st.lists(coeff, min_size=0, max_size=dm + 1)) for _ in range(n)] for _ in range(m)]
    got = _toeplitz_entries(mi, m, n, dm, D, mod)
    rows, cols = n * (D + dm + 1), m * (D + 1)
    assert len(got) == rows * cols
    for t in range(D + dm + 1):
        for l in range(n):
            for e in range(D + 1):
                for j in range(m):
                    cs = mi[j][l]
                    want = cs[t - e] if 0 <= t - e < len(cs) else 0
                    if mod is not None:
                        want %= mod
                    assert got[(t * n + l) * cols + e * m + j] == want
