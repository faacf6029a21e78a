"""Popov kernel rows from the leading monomials modulo a prime and one exact square
solve (:mod:`uio_ring.ring._kernel_lead`) against the fraction-free nullspace of the
whole Toeplitz matrix (:func:`uio_ring.ring._kernel_basis._exact_generators`): the
reduced echelon generators are unique, so the two must agree exactly — and with a
tiny prime, where rank drops modulo p are common, the modular path may give up
(None) but never returns other vectors."""

from __future__ import annotations

from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring import PolyMatrix
from uio_ring.ring import _dense as dn
from uio_ring.ring._kernel_basis import _exact_generators, _integer_coefficients, _toeplitz_entries
from uio_ring.ring._kernel_lead import generators_by_lead_solve, pivot_columns_mod_p

from .strategies import matrices


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

