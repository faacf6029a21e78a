"""The order of the paths for tall matrices.  Dense ones of high degree try the generic
guess of their kernel and left inverse first (``hermite.guess_first``): the capped
elimination and the coprimality test of the minors are skipped when the guess is
certified, and every result is the one the usual order gives (compared with the
elimination, an independent path).  Once the capped elimination has given way, the
Toeplitz systems get the larger cap ``SWELL_MAX_UNKNOWNS`` (hermite, left_inverse, and
left_kernel beyond the usual cap ``MAX_UNKNOWNS``)."""

from __future__ import annotations

import importlib
import random
from unittest import mock

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring import PolyMatrix, _kernel_basis, hermite, left_inverse, left_kernel
from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring._kernel_basis import (
    SWELL_MAX_UNKNOWNS,
    generic_kernel_and_solution,
    kernel_and_solution,
)
from uio_ring.ring.errors import NotUnimodularError
from uio_ring.ring.hermite import hermite_by_elimination

from .strategies import assert_popov, matrices

# the module, not the function of the same name that the package exports
hermite_module = importlib.import_module("uio_ring.ring.hermite")
inverse_module = importlib.import_module("uio_ring.ring.inverse")
kernel_module = importlib.import_module("uio_ring.ring.kernel")


def _dense(rng: random.Random, m: int, n: int, degree: int) -> PolyMatrix:
    def entry() -> str:
        coeffs = [rng.randint(-3, 3) for _ in range(degree)] + [rng.choice([-3, -2, -1, 1, 2, 3])]
        return " + ".join(f"({c})*d**{e}" for e, c in enumerate(coeffs))

    return PolyMatrix([[entry() for _ in range(n)] for _ in range(m)])


def _forbid(monkeypatch, module, *names: str) -> list[str]:
    called: list[str] = []
    for name in names:
        monkeypatch.setattr(module, name, lambda *a, _name=name, **k: called.append(_name))
    return called


@pytest.mark.parametrize(("m", "n", "degree"), [(3, 1, 16), (4, 1, 8), (4, 2, 8), (6, 1, 16), (5, 3, 8)])
def test_a_dense_tall_matrix_skips_the_elimination(monkeypatch, m, n, degree):
    """Dense, δ-degree ≥ 8: neither the capped elimination nor the coprimality test runs,
    and H = [I; 0], U are the elimination's (U is unique once normalised)."""
    M = _dense(random.Random(m * 100 + n * 10 + degree), m, n, degree)
    want = hermite_by_elimination(M)
    called = _forbid(monkeypatch, hermite_module, "_hermite_by_small_elimination", "coprime_maximal_minors")
    got = hermite(M)
    assert called == []
    assert (got.H, got.U, got.rank, got.pivots) == (want.H, want.U, want.rank, want.pivots)
    called = _forbid(monkeypatch, inverse_module, "_hermite_by_small_elimination")
    X = left_inverse(M)
    assert called == [] and X == want.U[:n, :]


def test_a_dense_column_with_other_leading_positions_is_refused(monkeypatch):
    """Dense, but its first entry has degree 15: minimal indices 8 and 8 led at
    positions 0 and 2, not the generic 1 and 2.  The guess is refused — tried once, not
    again on the later path — and the result is still the elimination's."""
    rng = random.Random(7)
    M = PolyMatrix._new(_dense(rng, 1, 1, 15)._r + _dense(rng, 2, 1, 16)._r, 3, 1, "d")
    assert hermite_module.guess_first(M)
    assert generic_kernel_and_solution(M._r, 3, 1, dn.identity(1)) is None
    want = hermite_by_elimination(M)
    guesses: list = []
    real = _kernel_basis._generic_generators
    monkeypatch.setattr(_kernel_basis, "_generic_generators", lambda *a, **k: guesses.append(1) or real(*a, **k))
    got = hermite(M)
    assert (got.H, got.U) == (want.H, want.U) and len(guesses) == 1
    assert [dn.leading_position(r) for r in got.U._r[1:]] == [(8, 0), (8, 2)]
    assert left_inverse(M) == want.U[:1, :] and len(guesses) == 2


def test_sparse_entries_keep_the_usual_order(monkeypatch):
    """Few nonzero coefficients: the elimination first (it stays small there), no guess."""
    M = PolyMatrix("[[d**16 + 1], [d**16 + 2], [d**3]]")
    assert not hermite_module.guess_first(M)
    called = _forbid(monkeypatch, hermite_module, "generic_kernel_and_solution")
    got = hermite(M)
    assert called == [] and got.U @ M == got.H


def test_a_common_factor_is_refused():
    """M = M0·(δ + 1): the guessed system is singular, H has the pivot δ + 1, and
    left_inverse names the obstruction."""
    M0 = _dense(random.Random(2), 4, 1, 8)
    M = PolyMatrix._new([[row[0] * bk.from_coeffs([1, 1])] for row in M0._r], 4, 1, "d")
    got = hermite(M)
    assert got.H == hermite_by_elimination(M).H and got.H[0, 0].degree() == 1
    assert got.U @ M == got.H
    with pytest.raises(NotUnimodularError):
        left_inverse(M)


@settings(max_examples=25, deadline=None)
@given(st.sampled_from([(3, 1), (4, 1), (4, 2), (5, 2)]), st.integers(8, 12), st.integers(0, 10**6),
       st.booleans())
def test_the_guess_and_the_usual_order_agree(shape, degree, seed, sparse):
    """Dense or with zero coefficients (some guesses refused): the same H and U with and
    without the guess first."""
    m, n = shape
    rng = random.Random(seed)
    M = _dense(rng, m, n, degree)
    if sparse:
        M = PolyMatrix._new([[x if rng.random() < 0.6 else bk.ZERO for x in row] for row in M._r], m, n, "d")
    got = hermite(M)
    want = hermite_by_elimination(M)
    assert (got.H, got.U) == (want.H, want.U)


def test_the_toeplitz_cap_is_a_parameter():
    """A 4×2 of degree 16: 68 unknowns. Refused under a cap of 50, solved under 100."""
    M = _dense(random.Random(8), 4, 2, 16)
    I2 = dn.identity(2)
    assert kernel_and_solution(M._r, 4, 2, I2, min_rows=0, max_unknowns=50) is None
    got = kernel_and_solution(M._r, 4, 2, I2, min_rows=0, max_unknowns=100)
    assert got is not None and dn.matmul(got.solution, M._r, 2, 4, 2) == I2


def test_hermite_and_left_inverse_take_the_larger_cap_once_the_elimination_swelled(monkeypatch):
    """Past the capped elimination, with the minors coprime, the only alternative left is
    an elimination that swells: the Toeplitz systems get SWELL_MAX_UNKNOWNS."""
    M = _dense(random.Random(9), 4, 2, 16)
    caps: list = []
    real = kernel_and_solution

    def spy(*a, **k):
        caps.append(k.get("max_unknowns"))
        return real(*a, **k)

    for module in (hermite_module, inverse_module):
        monkeypatch.setattr(module, "guessed_kernel_and_inverse", lambda M: None)
        monkeypatch.setattr(module, "kernel_and_solution", spy)
    want = hermite_by_elimination(M)
    assert hermite(M).U == want.U and left_inverse(M) == want.U[:2, :]
    assert caps == [SWELL_MAX_UNKNOWNS, SWELL_MAX_UNKNOWNS]


def test_the_solution_keeps_the_cap_of_its_kernel(monkeypatch):
    """X sought after K (rank n, the block elimination modulo primes gives K alone: a 6×4
    of degree 2) is sought under the same cap as K: a caller's larger cap reaches it."""
    M = _dense(random.Random(10), 6, 4, 2)
    caps: list = []
    real = _kernel_basis.solve_reduced

    def spy(*a, **k):
        caps.append(k.get("max_unknowns"))
        return real(*a, **k)

    monkeypatch.setattr(_kernel_basis, "solve_reduced", spy)
    I4 = dn.identity(4)
    got = kernel_and_solution(M._r, 6, 4, I4, min_rows=0, max_unknowns=1234)
    assert caps == [1234]
    assert got is not None and dn.matmul(got.solution, M._r, 4, 6, 4) == I4
    assert got.kernel == hermite_by_elimination(M).U._r[4:]


@pytest.mark.parametrize("seed", [1, 2])
def test_left_kernel_beyond_the_usual_cap_after_the_elimination_swelled(monkeypatch, seed):
    """Beyond the usual Toeplitz cap (simulated: the default call refuses), a dense 6×4 of
    degree 4 swells past the elimination's cap, and the Toeplitz systems under
    SWELL_MAX_UNKNOWNS give the Popov kernel — the elimination's (unique)."""
    M = _dense(random.Random(seed), 6, 4, 4)
    want = kernel_module.left_kernel_by_elimination(M)
    calls: list = []
    real_kernel, real_elimination = _kernel_basis.popov_left_kernel, kernel_module._kernel_by_elimination

    def refusing(a, m, n, **k):
        calls.append(("toeplitz", k.get("max_unknowns")))
        return real_kernel(a, m, n, **k) if "max_unknowns" in k else None

    def eliminating(M, bit_cap):
        got = real_elimination(M, bit_cap)
        calls.append(("elimination", bit_cap is not None, got is not None))
        return got

    monkeypatch.setattr(kernel_module, "popov_left_kernel", refusing)
    monkeypatch.setattr(kernel_module, "_kernel_by_elimination", eliminating)
    K = left_kernel(M)
    assert calls == [("toeplitz", None), ("elimination", True, False), ("toeplitz", SWELL_MAX_UNKNOWNS)]
    assert K == want and (K @ M).is_zero()


def test_left_kernel_beyond_the_usual_cap_without_swelling(monkeypatch):
    """The first columns of a unimodular matrix: the capped elimination stays small and
    gives the Popov kernel itself; no Toeplitz system under the larger cap."""
    rng = random.Random(3)
    U = PolyMatrix.identity(7)
    for _ in range(12):  # elementary row operations: row i += (a + b·δ)·row j
        i, j = rng.sample(range(7), 2)
        entry = f"{rng.randint(-2, 2)} + {rng.randint(-2, 2)}*d"
        U = PolyMatrix([[entry if (r, c) == (i, j) else int(r == c) for c in range(7)] for r in range(7)]) @ U
    M = U[:, :4]
    calls: list = []
    real_kernel = _kernel_basis.popov_left_kernel

    def refusing(a, m, n, **k):
        calls.append(k.get("max_unknowns"))
        return real_kernel(a, m, n, **k) if "max_unknowns" in k else None

    monkeypatch.setattr(kernel_module, "popov_left_kernel", refusing)
    K = left_kernel(M)
    assert calls == [None]
    assert K == kernel_module.left_kernel_by_elimination(M) and K.rows == 3


@settings(max_examples=25, deadline=None)
@given(matrices(min_rows=6, max_rows=8, min_cols=1, max_cols=5))
def test_left_kernel_beyond_the_usual_cap_is_the_eliminations(M):
    """Beyond the usual cap (simulated), whichever of the capped elimination and the
    Toeplitz systems under the larger cap gives the kernel — dense, sparse, rank-deficient
    M — it is the Popov basis the elimination gives."""
    real = _kernel_basis.popov_left_kernel

    def refusing(a, m, n, **k):
        return real(a, m, n, **k) if "max_unknowns" in k else None

    with mock.patch.object(kernel_module, "popov_left_kernel", refusing):
        K = left_kernel(M)
    assert K == kernel_module.left_kernel_by_elimination(M)
    assert_popov(K)
