"""The block elimination modulo primes of :mod:`uio_ring.ring._reduced_crt`: its reduced
solution equals the one of the square Toeplitz system (unique), satisfies X·M = B
exactly, a wrong candidate fails the exact check, an inconsistent right-hand side is
refused modulo a prime, and the cases it does not handle are handed back (None)."""

from __future__ import annotations

import random

import flint
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring import PolyMatrix
from uio_ring.ring import _dense as dn
from uio_ring.ring._kernel_basis import ToeplitzCoefficients, popov_left_kernel, solve_reduced
from uio_ring.ring._reduced_crt import (
    NO_SOLUTION,
    SHIFTS,
    _Blocks,
    _finish,
    _taylor_shift,
    solve_reduced_crt,
    word_primes,
    worthwhile,
)


def _tall(rng: random.Random, n: int, extra: int, deg: int, rational: bool) -> PolyMatrix:
    def entry() -> str:
        cs = [rng.randint(-3, 3) for _ in range(rng.randint(0, deg) + 1)]
        den = rng.choice([1, 2, 3]) if rational else 1
        return " + ".join(f"({c}/{den})*d**{e}" for e, c in enumerate(cs))
    return PolyMatrix([[entry() for _ in range(n)] for _ in range(n + extra)])


def _lead(K: dn.Rows) -> dict[int, int]:
    return {j: d for d, j in (dn.leading_position(row) for row in K)}


def _integer_rhs(coeffs: ToeplitzCoefficients, W: PolyMatrix, n: int, D: int) -> list[list[flint.fmpz]]:
    """b[t·n + l][v] = coefficient t of W[v, l]·c_l (integers: W is integral here)."""
    nt = D + coeffs.dm + 1
    out = [[flint.fmpz(0)] * W.rows for _ in range(nt * n)]
    for v in range(W.rows):
        for col in range(n):
            cs = (W._r[v][col] * coeffs.scale[col]).coeffs()
            for t, c in enumerate(cs):
                assert c.denom() == 1
                out[t * n + col][v] = c.numer()
    return out


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 6), st.integers(1, 4), st.integers(1, 3), st.booleans(), st.integers(0, 10**6))
def test_the_multimodular_solution_is_the_square_systems(n, extra, deg, rational, seed):
    rng = random.Random(seed)
    M = _tall(rng, n, extra, deg, rational)
    m = n + extra
    K = popov_left_kernel(M._r, m, n, min_rows=0)
    if K is None or not K:
        return
    X0 = PolyMatrix([[f"{rng.randint(-2, 2)} + {rng.randint(-2, 2)}*d" for _ in range(m)] for _ in range(2)])
    off = X0 @ M + PolyMatrix([["d**3" if (v, col) == (0, 0) else "0" for col in range(n)] for v in range(2)])
    for W in (X0 @ M, PolyMatrix.identity(n) if M.rank() == n else X0 @ M, off):
        fast = solve_reduced(M._r, m, n, K, W._r, tries=2)
        slow = solve_reduced(M._r, m, n, K, W._r, tries=2, multimodular=False)
        assert fast == slow
        if fast is not None:
            assert PolyMatrix._new(fast, W.rows, m, "d") @ M == W


def _generic_case() -> tuple[PolyMatrix, ToeplitzCoefficients, dict[int, int], int]:
    rng = random.Random(11)
    while True:
        M = _tall(rng, 5, 3, 2, False)
        K = popov_left_kernel(M._r, 8, 5)
        assert K is not None
        coeffs = ToeplitzCoefficients.of(M._r, 8, 5)
        lead = _lead(K)
        D = max(lead.values())
        if M.rank() == 5 and all(lead.values()):
            return M, coeffs, lead, D


def test_the_result_is_delta_times_x_and_satisfies_x_m_equal_b():
    M, coeffs, lead, D = _generic_case()
    W = PolyMatrix.identity(5)
    got = solve_reduced_crt(coeffs.mi, coeffs.dm, 8, 5, D, lead, _integer_rhs(coeffs, W, 5, D), 5)
    assert isinstance(got, tuple)
    rows, delta = got
    X = PolyMatrix._new([[flint.fmpq_poly(cs) / delta for cs in row] for row in rows], 5, 8, "d")
    assert X @ M == W
    # reduced modulo the kernel: the entries of a pivot column have degree < its pivot's
    assert all(X._r[v][j].degree() < d for j, d in lead.items() for v in range(5))


def test_a_wrong_candidate_fails_the_exact_check():
    M, coeffs, lead, D = _generic_case()
    W = PolyMatrix.identity(5)
    b = _integer_rhs(coeffs, W, 5, D)
    got = solve_reduced_crt(coeffs.mi, coeffs.dm, 8, 5, D, lead, b, 5)
    assert isinstance(got, tuple)
    rows, delta = got
    blocks = _Blocks.of(coeffs.mi, coeffs.dm, 5, D, sorted(lead), lead, b, 5)
    y_p = flint.fmpz_mat(5, blocks.up, [rows[v][j][e] for v in range(5) for j, e in blocks.pu])
    assert _finish(delta, y_p, blocks) is not None
    wrong = flint.fmpz_mat(y_p.tolist())
    wrong[0, 0] += word_primes(1)[0]  # invisible modulo the first prime
    assert _finish(delta, wrong, blocks) is None
    assert _finish(delta + 1, y_p, blocks) is None
    # scaled by c = d^(D+1) (d: the denominator of A_0⁻¹) every division of the recurrence
    # is exact: the right candidate still passes, a wrong one fails at the coefficients > D
    c = den_a0(blocks) ** (D + 1)
    assert _finish(delta * c, y_p * c, blocks) is not None
    assert _finish(delta * c, wrong * c, blocks) is None


def den_a0(blocks: _Blocks) -> flint.fmpz:
    """The denominator of A_0⁻¹."""
    return flint.fmpq_mat(blocks.a[0]).inv().numer_denom()[1]


def test_an_inconsistent_right_hand_side_is_refused_modulo_a_prime():
    # column 0 of degree 1 < 2: coefficient D + 2 of column 0 of X·M is 0 for every X,
    # and the Schur system has more equations than unknowns (Σ d_i < n·dm)
    rng = random.Random(3)
    M = _tall(rng, 5, 3, 2, False)
    M = PolyMatrix([[f"{rng.randint(-3, 3)} + {rng.randint(1, 3)}*d" if col == 0 else str(M[r, col])
                     for col in range(5)] for r in range(8)])
    K = popov_left_kernel(M._r, 8, 5)
    assert K is not None and M.rank() == 5
    coeffs = ToeplitzCoefficients.of(M._r, 8, 5)
    lead = _lead(K)
    D = max(lead.values())
    assert sum(lead.values()) < 5 * coeffs.dm
    W = PolyMatrix.identity(5)
    b = _integer_rhs(coeffs, W, 5, D)
    assert isinstance(solve_reduced_crt(coeffs.mi, coeffs.dm, 8, 5, D, lead, b, 5), tuple)
    b[(D + coeffs.dm) * 5][0] += 1
    assert solve_reduced_crt(coeffs.mi, coeffs.dm, 8, 5, D, lead, b, 5) == NO_SOLUTION


def test_what_it_does_not_handle_is_handed_back():
    # rank 2 < 3 columns: the rows off the kernel's pivots are not square
    M = PolyMatrix("[[1, d, 1 + d], [d, 1, 1 + d], [2, 3, 5], [d**2, 1, d**2 + 1], [1, 1, 2], [d, d, 2*d]]")
    K = popov_left_kernel(M._r, 6, 3)
    assert K is not None
    c = ToeplitzCoefficients.of(M._r, 6, 3)
    lead = _lead(K)
    D = max(lead.values())
    W = PolyMatrix("[[1, d, 1 + d]]")
    assert solve_reduced_crt(c.mi, c.dm, 6, 3, D, lead, _integer_rhs(c, W, 3, D), 1) is None
    # A_0 = M_R(0) singular (every row a multiple of δ but the kernel's pivot rows):
    # solved for M(δ + 1) and shifted back, the same as the square system's
    M2 = PolyMatrix("[[d, 2*d], [d**2, d], [1, 0], [0, 1], [1, 1], [2, 1]]")
    K2 = popov_left_kernel(M2._r, 6, 2)
    assert K2 is not None
    c2 = ToeplitzCoefficients.of(M2._r, 6, 2)
    lead2 = _lead(K2)
    rest = [j for j in range(6) if j not in lead2]
    assert all(M2._r[j][col][0] == 0 for j in rest for col in range(2))
    D2 = max(lead2.values())
    W2 = PolyMatrix.identity(2)
    got = solve_reduced_crt(c2.mi, c2.dm, 6, 2, D2, lead2, _integer_rhs(c2, W2, 2, D2), 2)
    assert isinstance(got, tuple)
    rows, delta = got
    X2 = PolyMatrix._new([[flint.fmpq_poly(cs) / delta for cs in row] for row in rows], 2, 6, "d")
    assert X2 @ M2 == W2 and X2._r == solve_reduced(M2._r, 6, 2, K2, W2._r, multimodular=False)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 5), st.integers(1, 4), st.integers(1, 3), st.integers(0, 10**6))
def test_it_applies_whenever_its_conditions_hold(n, extra, deg, seed):
    """Rank n, M_R(α) nonsingular at 0 or a point of SHIFTS, 0 < deg M ≤ n and a kernel of
    positive degrees: the method answers (a solution or a proof that none exists), it does not
    hand back (it would fall back silently to the square system: same result, slower)."""
    rng = random.Random(seed)
    M = _tall(rng, n, extra, deg, False)
    m = n + extra
    K = popov_left_kernel(M._r, m, n, min_rows=0)
    assert K is not None
    c = ToeplitzCoefficients.of(M._r, m, n)
    lead = _lead(K)
    rest = [j for j in range(m) if j not in lead]
    X0 = PolyMatrix([[f"{rng.randint(-2, 2)} + {rng.randint(-2, 2)}*d" for _ in range(m)]])
    W = X0 @ M
    D = max([*lead.values(), dn.mat_degree(W._r) - c.dm, 0])
    got = solve_reduced_crt(c.mi, c.dm, m, n, D, lead, _integer_rhs(c, W, n, D), 1) if c.dm > 0 else None
    applies = (len(rest) == n and worthwhile(n, c.dm) and any(lead.values())
               and any(PolyMatrix([[str(M._r[j][col](alpha)) for col in range(n)] for j in rest]).det() != 0
                       for alpha in (0, *SHIFTS)))
    assert (got is not None) == applies
    if isinstance(got, tuple):
        rows, delta = got
        X = PolyMatrix._new([[flint.fmpq_poly(cs) / delta for cs in row] for row in rows], 1, m, "d")
        assert X @ M == W
        assert X._r == solve_reduced(M._r, m, n, K, W._r, multimodular=False)


def test_a_degree_bound_below_the_degree_of_m():
    # 12×3 of degree 3: nine kernel rows of degree 1, so D = 1 < dm − 1 = 2 and the tail
    # sums start at coefficient 0, not at D + i − dm < 0
    rng = random.Random(2)
    M = _tall(rng, 3, 9, 3, False)
    M = PolyMatrix([[str(M[r, c] + PolyMatrix([[f"{rng.randint(1, 3)}*d**3"]])[0, 0]) for c in range(3)]
                    for r in range(12)])
    K = popov_left_kernel(M._r, 12, 3)
    assert K is not None and M.rank() == 3
    lead = _lead(K)
    c = ToeplitzCoefficients.of(M._r, 12, 3)
    assert c.dm == 3 and max(lead.values()) == 1
    X0 = PolyMatrix([[str(rng.randint(-2, 2)) for _ in range(12)]])
    W = X0 @ M
    got = solve_reduced_crt(c.mi, c.dm, 12, 3, 1, lead, _integer_rhs(c, W, 3, 1), 1)
    assert isinstance(got, tuple)
    rows, delta = got
    X = PolyMatrix._new([[flint.fmpq_poly(cs) / delta for cs in row] for row in rows], 1, 12, "d")
    assert X @ M == W and X._r == solve_reduced(M._r, 12, 3, K, W._r, multimodular=False)


def test_few_columns_of_high_degree_are_left_to_the_square_system():
    M = PolyMatrix("[[1 + d**5, d], [d**4, 1], [d**5 - 2, d**3 + 1]]")
    K = popov_left_kernel(M._r, 3, 2, min_rows=0)
    assert K is not None
    c = ToeplitzCoefficients.of(M._r, 3, 2)
    lead = _lead(K)
    D = max(lead.values())
    W = PolyMatrix.identity(2)
    assert not worthwhile(2, c.dm)
    assert solve_reduced_crt(c.mi, c.dm, 3, 2, D, lead, _integer_rhs(c, W, 2, D), 2) is None


def test_taylor_shift_is_the_substitution():
    rng = random.Random(4)
    for _ in range(20):
        cs = [rng.randint(-9, 9) for _ in range(rng.randint(1, 6))] + [0] * rng.randint(0, 2)
        alpha = rng.choice(SHIFTS)
        got = _taylor_shift(cs, alpha)
        assert len(got) == len(cs)
        p = flint.fmpz_poly(cs)
        assert flint.fmpz_poly(got) == p(flint.fmpz_poly([alpha, 1]))
        assert _taylor_shift(got, -alpha) == cs


def test_the_primes_are_told_to_the_progress_note():
    """A long remaindering says which prime it is at (``uio-ring check``'s heartbeat prints
    the note), appended to the step's own note, which is restored afterwards."""
    from uio_ring import _progress

    M, coeffs, lead, D = _generic_case()
    W = PolyMatrix.identity(5)
    seen: list[str] = []
    _progress.set_sink(seen.append)
    try:
        with _progress.step("step 3"):
            got = solve_reduced_crt(coeffs.mi, coeffs.dm, 8, 5, D, lead, _integer_rhs(coeffs, W, 5, D), 5)
            assert _progress.current() == "step 3"
    finally:
        _progress.set_sink(None)
    assert isinstance(got, tuple)
    told = [s for s in seen if ": prime " in s]
    assert told and all(s.startswith("step 3; a ") and "Toeplitz system modulo primes: prime " in s for s in told)
    assert told[0].endswith("prime 1 of at most " + told[0].rsplit(" ", 1)[1])
    assert seen[-2:] == ["step 3", ""]
