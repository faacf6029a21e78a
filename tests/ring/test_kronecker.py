"""The product by Kronecker substitution (:mod:`uio_ring.ring._kronecker`) against the
entry-by-entry product: equal exactly, rational coefficients, signs and zeros included."""

from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from uio_ring.ring import PolyMatrix
from uio_ring.ring import _dense as dn
from uio_ring.ring._kronecker import matmul_kronecker

from .strategies import dense_matrices


def _entrywise(a: PolyMatrix, b: PolyMatrix) -> list:
    m, k, n = a.rows, a.cols, b.cols
    return [[sum((a._r[i][t] * b._r[t][j] for t in range(k)), dn.bk.ZERO) for j in range(n)] for i in range(m)]


@given(st.tuples(st.integers(1, 5), st.integers(1, 5), st.integers(1, 5)).flatmap(
    lambda s: st.tuples(dense_matrices(rows=s[0], cols=s[1]), dense_matrices(rows=s[1], cols=s[2]))))
def test_kronecker_product_equals_entrywise_product(ab):
    a, b = ab
    assert matmul_kronecker(a._r, b._r, a.rows, a.cols, b.cols) == _entrywise(a, b)


def test_kronecker_product_large_coefficients_and_high_degree():
    a = PolyMatrix([["(2**200 + 1)*d**40 - 3/7", "-(2**100)*d"], ["0", "d**3 - 2**150/11"]])
    b = PolyMatrix([["-(2**90 - 1)*d**7 + 1", "0"], ["d**50/(2**70 + 1)", "-1"]])
    assert matmul_kronecker(a._r, b._r, 2, 2, 2) == _entrywise(a, b)
    assert (a @ b)._r == _entrywise(a, b)
    big = PolyMatrix([[f"{(-1) ** (i + j)}*d**{i} + {j}/3" for j in range(12)] for i in range(12)])
    assert (big @ big)._r == _entrywise(big, big)  # 12³ products: the Kronecker path


@given(st.lists(st.integers(-(2**80), 2**80), max_size=12), st.integers(1, 12))
def test_packing_is_the_value_at_the_power_of_two(coeffs, nbytes):
    import flint

    from uio_ring.ring._kronecker import _value_at_power_of_two

    p = flint.fmpz_poly(coeffs)
    s = 8 * nbytes
    assert _value_at_power_of_two(p, s) == int(p(flint.fmpz(2) ** s))


@given(dense_matrices(rows=9, cols=3), st.integers(0, 8), st.integers(1, 3))
def test_sparse_left_factor_product_equals_entrywise_product(b, shift, r):
    """A block shift plus a few entries (the pattern of L0 = A0 − G0 C0): ``_dense.matmul``
    takes the row-by-row path for it; the product is the entry-by-entry one."""
    rows = [[0] * 9 for _ in range(9)]
    for i in range(9 - shift):
        rows[i][i + shift] = 1
    for i in range(9):
        rows[i][i % r] -= i + 1
    a = PolyMatrix(rows, shape=(9, 9))
    nnz = sum(not p.is_zero() for row in a._r for p in row)
    assert nnz * 3 <= 9 * 9 + 9 * 3  # the sparse path is taken
    assert dn.matmul(a._r, b._r, 9, 9, 3) == _entrywise(a, b)


@given(st.tuples(st.integers(1, 5), st.integers(1, 5), st.integers(1, 5)).flatmap(
    lambda s: st.tuples(dense_matrices(rows=s[0], cols=s[1]), dense_matrices(rows=s[1], cols=s[2]))))
def test_both_paths_equal_the_entrywise_product(ab):
    """The coefficient-stacked path and the digit-packing path, each forced, against the
    entry-by-entry product (small random matrices take the stacked path by default)."""
    import uio_ring.ring._kronecker as kr

    a, b = ab
    saved = kr.STACK_MAX_DEGREE, kr.STACK_MAX_BITS
    try:
        for bound in (-1, 10**6):  # never stacked / always stacked
            kr.STACK_MAX_DEGREE, kr.STACK_MAX_BITS = bound, 10**9 if bound > 0 else 128
            assert matmul_kronecker(a._r, b._r, a.rows, a.cols, b.cols) == _entrywise(a, b)
    finally:
        kr.STACK_MAX_DEGREE, kr.STACK_MAX_BITS = saved


def test_stacked_product_big_coefficients_times_low_degree():
    """A Krylov-like block (high degree, big rational coefficients) times a degree-1 factor
    with small ones: the stacked path, exactly the entry-by-entry product."""
    a = PolyMatrix([[f"({3**60 + i}*d**{9 + j} - {2**70 + j}*d)/{7 + i}" for j in range(5)] for i in range(3)])
    b = PolyMatrix([[f"{i - j}*d + {(i * j) % 3}/2" for j in range(4)] for i in range(5)])
    assert matmul_kronecker(a._r, b._r, 3, 5, 4) == _entrywise(a, b)
    assert matmul_kronecker(b.T._r, a.T._r, 4, 5, 3) == _entrywise(b.T, a.T)


@given(st.lists(st.fractions(max_denominator=50), max_size=6), st.integers(1, 40))
def test_scaled_numerator_is_the_scaled_polynomial(coeffs, mult):
    """``scaled_numerator(p, c)`` (no gcd) is ``(p·c).numer()`` for every multiple c of the
    denominator of p — zero polynomial and c = denominator included."""
    import flint

    from uio_ring.ring._kronecker import scaled_numerator

    p = flint.fmpq_poly([flint.fmpq(c.numerator, c.denominator) for c in coeffs])
    for c in (p.denom(), p.denom() * mult):
        assert scaled_numerator(p, c) == (p * c).numer()
        assert flint.fmpq_poly(scaled_numerator(p, c)) == p * c


@given(st.integers(0, 2), st.integers(0, 6), st.integers(1, 4), st.integers(1, 4), st.integers(1, 4))
def test_stacked_product_both_orientations(d_small, d_big, m, k, n):
    """The Toeplitz block goes on the factor of lower degree: both orientations (and equal
    degrees) against the entry-by-entry product."""
    a = PolyMatrix([[f"({i - t + 2})*d**{d_big} + {t}/3*d**{min(d_big, 1)} - {i}" for t in range(k)]
                    for i in range(m)])
    b = PolyMatrix([[f"{(t + 2 * j) % 5 - 2}*d**{d_small} + {j}/7" for j in range(n)] for t in range(k)])
    assert matmul_kronecker(a._r, b._r, m, k, n) == _entrywise(a, b)
    assert matmul_kronecker(b.T._r, a.T._r, n, k, m) == _entrywise(b.T, a.T)


@given(st.tuples(st.integers(1, 5), st.integers(1, 5), st.integers(1, 5)).flatmap(
    lambda s: st.tuples(dense_matrices(rows=s[0], cols=s[1]), dense_matrices(rows=s[1], cols=s[2]),
                        st.lists(st.booleans(), min_size=s[0] + 2 * s[1] + s[2], max_size=s[0] + 2 * s[1] + s[2]))))
def test_product_on_the_support_equals_entrywise_product(abz):
    """Zero rows and columns of a, zero rows and columns of b (the support that
    ``matmul_kronecker`` restricts the product to), against the entry-by-entry product —
    all-zero factors and products included."""
    a, b, zero = abz
    m, k, n = a.rows, a.cols, b.cols
    ar = [[dn.bk.ZERO if zero[i] or zero[m + t] else a._r[i][t] for t in range(k)] for i in range(m)]
    br = [[dn.bk.ZERO if zero[m + k + t] or zero[m + 2 * k + j] else b._r[t][j] for j in range(n)] for t in range(k)]
    za, zb = PolyMatrix._new(ar, m, k, "d"), PolyMatrix._new(br, k, n, "d")
    assert matmul_kronecker(ar, br, m, k, n) == _entrywise(za, zb)


def test_stack_rule_takes_the_stack_for_unbalanced_factors(monkeypatch):
    """A factor of high degree and large coefficients times one of low degree and small
    coefficients (the check U·M = H of a large Hermite form) goes through the coefficient
    stack beyond STACK_MAX_DEGREE; balanced factors through the Kronecker product; both
    equal the entry-by-entry product."""
    import importlib

    kr = importlib.import_module("uio_ring.ring._kronecker")
    assert kr._stack_wins(240, 16, 6000, 3, 6016) and kr._stack_wins(8, 32, 4, 3000, 3016)
    assert not kr._stack_wins(16, 16, 1000, 1000, 2008) and not kr._stack_wins(64, 16, 500, 3, 512)
    calls = []
    real = kr._matmul_stacked
    monkeypatch.setattr(kr, "_matmul_stacked", lambda *a: calls.append(a[5:7]) or real(*a))
    big = PolyMatrix([[f"({(-1) ** (i + j)}*2**300 + {i * j})*d**{30 + i} + {j}/7*d**3 - 1" for j in range(4)]
                      for i in range(3)])
    small = PolyMatrix([[f"d**{4 + i} - {j}*d**2 + {i + j}" for j in range(5)] for i in range(4)])
    assert matmul_kronecker(big._r, small._r, 3, 4, 5) == _entrywise(big, small)
    assert calls == [(32, 7)]
    balanced = PolyMatrix([[f"(2**300 + {i})*d**{20 + j} - {j}" for j in range(4)] for i in range(4)])
    assert matmul_kronecker(balanced._r, balanced._r, 4, 4, 4) == _entrywise(balanced, balanced)
    assert calls == [(32, 7)]


def test_big_coefficients_times_small_ones_take_the_stack_in_few_products(monkeypatch):
    """Past ``STACK_MIN_BIG_BITS`` the stack rule also takes factors of degree 32 and 64
    against big coefficients (measured 1.3–5× faster), but not at 500 bits; and
    ``matmul`` sends a product of few entries (below ``KRONECKER_MIN_PRODUCTS``) with big
    coefficients times small ones to the stacked product — not a big product by a big
    one, nor a small one — with the result of the entry-by-entry product."""
    import importlib

    kr = importlib.import_module("uio_ring.ring._kronecker")
    assert kr._stack_wins(300, 32, 16000, 3, 16016) and kr._stack_wins(300, 64, 2500, 20, 2536)
    assert kr._stack_wins(32, 200, 3, 8000, 8016)  # either orientation
    assert not kr._stack_wins(300, 64, 500, 3, 520) and not kr._stack_wins(300, 64, 2500, 2500, 5016)
    calls = []
    real = kr._matmul_stacked
    monkeypatch.setattr(kr, "_matmul_stacked", lambda *a: calls.append(a[5:7]) or real(*a))
    row = PolyMatrix([[f"({(-1) ** t}*3**1400 + {t})*d**{40 + t} - {t}/5*d - 7" for t in range(4)]])
    small = PolyMatrix([[f"{(t + j) % 3 - 1}*d**{16 - j} + {j}/2" for j in range(3)] for t in range(4)])
    assert (row @ small)._r == _entrywise(row, small)  # 12 products, 2219-bit by 2-bit
    assert (small.T @ row.T)._r == _entrywise(small.T, row.T)
    assert calls == [(43, 16), (16, 43)]
    assert (row @ row.T)._r == _entrywise(row, row.T)  # big by big: one by one
    assert (small @ small.T)._r == _entrywise(small, small.T)
    assert calls == [(43, 16), (16, 43)]
    # 1×32 by 32×32, 1024 products from a dense row, which took the row-by-row path
    wide = PolyMatrix([[f"({(-1) ** t}*3**1400 + {t})*d**{8 + t % 5} - 7" for t in range(32)]])
    square = PolyMatrix([[f"{(t * j) % 5 - 2}*d**{(t + j) % 4} + 1" for j in range(32)] for t in range(32)])
    assert (wide @ square)._r == _entrywise(wide, square)
    assert calls[2:] == [(12, 3)]
