"""Left primeness proved modulo one prime (ring._left_prime), against exact invariant factors."""

from __future__ import annotations

import flint
from hypothesis import given
from hypothesis import strategies as st

from uio_ring.ring import _dense as dn
from uio_ring.ring._fraction_free import det_integer, integer_rows
from uio_ring.ring._left_prime import _times_constants_mod_p, det_nmod, left_prime_mod_p
from uio_ring.ring._modular import PRIME
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.smith import invariant_factors_by_elimination

from .strategies import dense_matrices, square_matrices, unimodular_matrices


def _weak_popov_rows(M: PolyMatrix) -> list:
    rows = dn.copy(M._r)
    dn.weak_popov(rows)
    return [r for r in rows if any(not p.is_zero() for p in r)]


@given(square_matrices(min_n=1, max_n=5))
def test_det_over_gf_p_is_the_integer_determinant_mod_p(M):
    z, _ = integer_rows(M._r)
    n = M.rows
    got = det_nmod([[flint.nmod_poly(e, PRIME) for e in row] for row in z], n, PRIME)
    assert got == flint.nmod_poly(det_integer(z, n), PRIME)


@given(dense_matrices(min_rows=1, max_rows=4, min_cols=1, max_cols=5, max_degree=3))
def test_a_proof_of_left_primeness_is_never_wrong(M):
    # Soundness: whenever the test says "left prime", every invariant factor is 1 and the
    # rank is the number of rows (exact elimination, the independent path).
    rows = _weak_popov_rows(M)
    if not rows or len(rows) > M.cols:
        return
    W = PolyMatrix._new(rows, len(rows), M.cols, "d")
    if left_prime_mod_p(rows, len(rows), M.cols):
        facs = invariant_factors_by_elimination(W)
        assert len(facs) == len(rows) and all(f.is_unit() for f in facs)


@given(st.integers(1, 4), st.integers(0, 2), st.data())
def test_row_reduced_left_prime_matrices_are_recognised(r, extra, data):
    # [I 0]·V for unimodular V is left prime; its weak Popov form is row-reduced, so the
    # lucky-prime condition holds and the test must say so (failure probability ≤ r·Σd / p).
    n = r + extra
    V = data.draw(unimodular_matrices(n, max_degree=2))
    M = V[0:r, :]
    rows = _weak_popov_rows(M)
    assert len(rows) == r
    assert left_prime_mod_p(rows, r, n)


@given(st.integers(1, 3), st.integers(0, 2), st.data())
def test_a_common_factor_of_the_minors_is_never_missed(r, extra, data):
    # diag(1, …, 1, δ − 2)·[I 0]·V: every r×r minor is divisible by δ − 2
    n = r + extra
    V = data.draw(unimodular_matrices(n, max_degree=2))
    M = PolyMatrix.diag(*(["1"] * (r - 1) + ["d - 2"])) @ V[0:r, :]
    rows = _weak_popov_rows(M)
    assert not left_prime_mod_p(rows, r, n)
    assert not invariant_factors_by_elimination(PolyMatrix._new(rows, r, n, "d"))[-1].is_unit()


def test_an_unreduced_leading_matrix_proves_nothing():
    # rows of equal degree with dependent leading coefficients: det(L·Q) = 0, so no proof,
    # although [[d, 1], [d + 1, 1]] is unimodular
    M = PolyMatrix("[[d, 1], [d + 1, 1]]")
    assert not left_prime_mod_p(M._r, 2, 2)
    assert invariant_factors_by_elimination(M) == (PolyMatrix("[[1]]")[0, 0],) * 2


def test_high_degree_left_prime_row():
    # [(1+δ)^32, δ^31 − 1]: coprime entries of degree 32 with 30-bit coefficients
    M = PolyMatrix("[[(1 + d)**32, d**31 - 1, 0]]")
    assert left_prime_mod_p(M._r, 1, 3)
    N = PolyMatrix("[[(1 + d)**32, (1 + d)**31*(d - 1), 0]]")
    assert not left_prime_mod_p(N._r, 1, 3)


@given(dense_matrices(min_rows=1, max_rows=4, min_cols=1, max_cols=5, max_degree=3), st.integers(0, 10**6),
       st.sampled_from([PRIME, 7]))
def test_products_with_constants_mod_p_are_the_polynomial_products(M, seed, p):
    """The stacked product of :func:`_times_constants_mod_p` against the r²·n polynomial
    products over GF(p)[δ] it replaces."""
    import random

    z, _ = integer_rows(M._r)
    r, n = M.shape
    d = max(max(e.degree() for e in row) for row in z)
    if d < 0:
        return
    rng = random.Random(seed)
    qs = [[[rng.randrange(p) for _ in range(r)] for _ in range(n)] for _ in range(2)]
    got = _times_constants_mod_p(z, qs, r, n, d, p)
    zp = [[flint.nmod_poly(e, p) for e in row] for row in z]
    zero = flint.nmod_poly([], p)
    for q, mq in zip(qs, got, strict=True):
        assert mq == [[sum((row[l] * q[l][j] for l in range(n)), zero) for j in range(r)] for row in zp]
