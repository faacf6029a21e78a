"""The modular consistency test of :func:`uio_ring.ring._kernel_basis._solve_reduced_at`
(:func:`~uio_ring.ring._kernel_basis._consistent_mod_p`): it never rejects a system
that has a solution (the theorem in its docstring), it rejects a right-hand side off by
one outside the square subsystem, and a right-hand side off by a multiple of the prime
passes it but is caught by the exact check of the whole system."""

from __future__ import annotations

import random

import flint
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring import PolyMatrix, solve_left
from uio_ring.ring import _dense as dn
from uio_ring.ring._kernel_basis import (
    ToeplitzCoefficients,
    _consistent_mod_p,
    _toeplitz_columns,
    _toeplitz_entries,
    popov_left_kernel,
    solve_reduced,
)
from uio_ring.ring._kernel_lead import PRIME, pivot_columns_mod_p
from uio_ring.ring.errors import NoPolynomialSolutionError


def _system(rng: random.Random, rows: int, u: int, k: int) -> tuple[list[list[int]], list[int], flint.fmpz_mat]:
    """Integer columns of a rows×u matrix of full column rank, its chosen rows, and
    B = T·X for a random rational X (scaled to integers)."""
    while True:
        cols = [[rng.randint(-9, 9) for _ in range(rows)] for _ in range(u)]
        chosen = pivot_columns_mod_p([x % PRIME for col in cols for x in col], u, rows, reduced=True)
        if len(chosen) == u:
            break
    t = flint.fmpz_mat(rows, u, [cols[c][r] for r in range(rows) for c in range(u)])
    x = flint.fmpq_mat(u, k, [flint.fmpq(rng.randint(-50, 50), rng.randint(1, 9)) for _ in range(u * k)])
    bnum, _ = (flint.fmpq_mat(t) * x).numer_denom()
    return cols, chosen, bnum


def _residues(cols: list[list[int]]) -> list[list[int]]:
    return [[x % PRIME for x in col] for col in cols]


@settings(max_examples=60)
@given(st.integers(1, 6), st.integers(0, 4), st.integers(1, 3), st.integers(0, 10**6))
def test_a_solvable_system_is_never_rejected(u, extra, k, seed):
    cols, chosen, bnum = _system(random.Random(seed), u + extra, u, k)
    assert _consistent_mod_p(_residues(cols), chosen, bnum, u + extra, u, k)


@settings(max_examples=60)
@given(st.integers(1, 5), st.integers(1, 4), st.integers(1, 3), st.integers(0, 10**6), st.data())
def test_off_by_one_outside_the_square_rows_is_rejected(u, extra, k, seed, data):
    rows = u + extra
    cols, chosen, bnum = _system(random.Random(seed), rows, u, k)
    r = data.draw(st.sampled_from([i for i in range(rows) if i not in chosen]))
    v = data.draw(st.integers(0, k - 1))
    entries = [[bnum[i, j] for j in range(k)] for i in range(rows)]
    entries[r][v] += 1  # the square rows still determine X; row r now disagrees with it
    wrong = flint.fmpz_mat(entries)
    assert not _consistent_mod_p(_residues(cols), chosen, wrong, rows, u, k)
    entries[r][v] += PRIME - 1  # off by the prime: invisible modulo p
    assert _consistent_mod_p(_residues(cols), chosen, flint.fmpz_mat(entries), rows, u, k)


def test_toeplitz_columns_are_columns_of_the_toeplitz_matrix():
    M = PolyMatrix("[[1, d**2 - 3, 0], [2*d, 5, d], [0, 1, -d**2]]")
    c = ToeplitzCoefficients.of(M._r, 3, 3)
    for D in range(3):
        rows, ncols = 3 * (D + c.dm + 1), 3 * (D + 1)
        full = _toeplitz_entries(c.mi, 3, 3, c.dm, D, None)
        assert _toeplitz_columns(c.mi, 3, 3, c.dm, D, list(range(ncols))) == [
            [full[r * ncols + col] for r in range(rows)] for col in range(ncols)]


def _tall_rank_deficient() -> PolyMatrix:
    # 7×3, third column = d·first + second: rank 2, every X·M satisfies that relation
    rng = random.Random(5)
    rows = []
    for _ in range(7):
        a, b = rng.randint(-4, 4), rng.randint(-4, 4)
        c0, c1 = rng.randint(-3, 3), rng.randint(-3, 3)
        rows.append([f"{a}*d + {c0}", f"{b} + {c1}*d", f"d*({a}*d + {c0}) + {b} + {c1}*d"])
    return PolyMatrix(rows)


def test_a_rhs_off_by_the_prime_passes_the_filter_and_fails_the_exact_check():
    M = _tall_rank_deficient()
    m, n = M.shape
    K = popov_left_kernel(M._r, m, n)
    assert K is not None
    X = PolyMatrix("[[1, 0, d, 0, 2, 0, -1], [0, 3, 0, 0, d + 1, 0, 0]]")
    good = X @ M
    got = solve_reduced(M._r, m, n, K, good._r, tries=3)
    assert got is not None and PolyMatrix._new(got, 2, m, "d") @ M == good
    # one coefficient of the last column off by PRIME (≡ 0 mod p) or by 1: no solution
    for off in (PRIME, 1):
        rhs = dn.copy(good._r)
        rhs[0][2] = rhs[0][2] + off
        assert solve_reduced(M._r, m, n, K, rhs, tries=3) is None
        try:
            solve_left(M, PolyMatrix._new(rhs, 2, n, "d"))
        except NoPolynomialSolutionError:
            pass
        else:  # pragma: no cover - the relation of the columns is broken
            raise AssertionError("a right-hand side outside the row space was solved")
