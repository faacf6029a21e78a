"""The monic determinant from a certified primitive kernel vector (ring._monic_det), against Bareiss."""

from __future__ import annotations

import flint
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring._fraction_free import det_integer, integer_rows
from uio_ring.ring._left_prime import det_nmod
from uio_ring.ring._monic_det import monic_det_by_kernel

from .strategies import dense_matrices, square_matrices, unimodular_matrices


def _cofactor_gcd(z: list[list[flint.fmpz_poly]], n: int, i: int) -> flint.fmpz_poly:
    """gcd over Z[δ] of the (n−1)-minors of z without row i, exactly (Bareiss)."""
    r = [z[j] for j in range(n) if j != i]
    g = flint.fmpz_poly(0)
    for c in range(n):
        g = g.gcd(det_integer([[row[j] for j in range(n) if j != c] for row in r], n - 1))
    return g


def _monic(p: flint.fmpz_poly) -> flint.fmpq_poly:
    return flint.fmpq_poly(p) / p[p.degree()]


def _expected(z: list[list[flint.fmpz_poly]], n: int, i: int) -> flint.fmpq_poly:
    # monic det W / monic gcd of the minors of W without row i: monic det W when that
    # submatrix is left prime (the independent path: exact Bareiss determinants)
    return _monic(det_integer(z, n)) / _monic(_cofactor_gcd(z, n, i))


@settings(max_examples=60, deadline=None)
@given(square_matrices(min_n=2, max_n=4), st.integers(0, 3), st.sampled_from([2, 1 << 62]))
def test_monic_det_over_the_cofactor_gcd(M, i, first_prime):
    # first_prime = 2 meets primes that divide the content of the cofactors or the
    # normalising coefficient; the exact check R·v = 0 must still hold the answer
    n = M.rows
    i %= n
    z, _ = integer_rows(M._r)
    if det_integer(z, n).is_zero():
        return
    assert monic_det_by_kernel(z, n, i, first_prime=first_prime) == _expected(z, n, i)


@settings(max_examples=25, deadline=None)
@given(st.integers(2, 4), st.integers(40, 300), st.data())
def test_huge_integer_content_and_large_kernel_vectors(n, bits, data):
    # T·V·diag(1, …, 1, f) with T a constant integer matrix of `bits`-bit entries: its
    # minors carry a content of about n·bits bits and the kernel vector needs several
    # primes; the monic det is monic(f)·monic(det V)·1 = monic(f) (V unimodular)
    V = data.draw(unimodular_matrices(n, max_degree=2))
    f = flint.fmpz_poly(data.draw(st.lists(st.integers(-3, 3), min_size=2, max_size=4)))
    if f.degree() < 1:
        return
    rows = [list(r) for r in integer_rows(V._r)[0]]
    rows = [[e * f for e in r] if k == n - 1 else r for k, r in enumerate(rows)]
    T = [[flint.fmpz(data.draw(st.integers(-(1 << bits), 1 << bits))) for _ in range(n)] for _ in range(n)]
    i = data.draw(st.integers(0, n - 1))
    rest = [T[a][:n - 1] for a in range(n) if a != i]
    if flint.fmpz_mat(T).det() == 0 or flint.fmpz_mat(rest).det() == 0:
        return  # (T without row i)·diag(1, …, f) has the constant minor det(rest): left prime
    z = [[sum((T[a][k] * rows[k][j] for k in range(n)), flint.fmpz_poly(0)) for j in range(n)] for a in range(n)]
    got = monic_det_by_kernel(z, n, i)
    assert got == _expected(z, n, i)
    assert got == _monic(det_integer(z, n))  # W without row i is left prime (see above)


@settings(max_examples=60, deadline=None)
@given(dense_matrices(min_rows=1, max_rows=4, min_cols=2, max_cols=5, max_degree=3), st.integers(0, 4))
def test_cofactors_mod_p_are_the_determinants_with_a_unit_row(M, zero_col):
    # det [R; e_c] one by one (det_nmod) against the single elimination; a zeroed column
    # forces the case where no row of R can pivot
    from uio_ring.ring._monic_det import _cofactors_mod_p

    n = M.rows + 1
    if M.cols != n:
        return
    z, _ = integer_rows(M._r)
    if zero_col < n:
        z = [[flint.fmpz_poly(0) if j == zero_col else e for j, e in enumerate(row)] for row in z]
    p = 101
    zero, one = flint.nmod_poly([], p), flint.nmod_poly([1], p)
    rp = [[flint.nmod_poly(e, p) for e in row] for row in z]
    want = [det_nmod(rp + [[one if j == c else zero for j in range(n)]], n, p) for c in range(n)]
    assert _cofactors_mod_p(z, n, p) == want


def test_cofactors_mod_p_after_row_swaps():
    # zero pivots in columns 0 and 1 force swaps (sign flips) before the back substitution
    from uio_ring.ring._monic_det import _cofactors_mod_p

    d = flint.fmpz_poly([0, 1])
    rows = [[flint.fmpz_poly(0), flint.fmpz_poly(0), d, 1 + d],
            [flint.fmpz_poly(0), d, flint.fmpz_poly(2), flint.fmpz_poly(3)],
            [d * d, flint.fmpz_poly(1), flint.fmpz_poly(0), d]]
    p, n = 101, 4
    zero, one = flint.nmod_poly([], p), flint.nmod_poly([1], p)
    rp = [[flint.nmod_poly(e, p) for e in row] for row in rows]
    want = [det_nmod(rp + [[one if j == c else zero for j in range(n)]], n, p) for c in range(n)]
    assert _cofactors_mod_p(rows, n, p) == want and not all(w.is_zero() for w in want)


@settings(max_examples=40, deadline=None)
@given(st.integers(2, 4), st.sampled_from(["d + 1", "d**2 - 3", "(d - 1)**2", "2*d**3 + d"]), st.data())
def test_row_module_membership_equals_reduction_to_zero(n, f, data):
    # W: a weak Popov basis of U·diag(1, …, 1, f)·V; x ∈ L(W) iff reducing x modulo W
    # leaves nothing (extend_row_basis, the independent path); members y·W are drawn too
    from uio_ring.analysis._module_factors import module_factors_and_kernel
    from uio_ring.ring._monic_det import in_row_module
    from uio_ring.ring.matrix import PolyMatrix
    from uio_ring.ring.row_basis import extend_row_basis

    N = (data.draw(unimodular_matrices(n)) @ PolyMatrix.diag(*(["1"] * (n - 1) + [f]))
         @ data.draw(unimodular_matrices(n)))
    W = extend_row_basis(PolyMatrix.zeros(0, n), N).basis
    facs, kd = module_factors_and_kernel(N, W)
    if kd is None:
        return
    assert str(facs[-1]) == str(PolyMatrix(f"[[{f}]]")[0, 0].monic())
    x = data.draw(dense_matrices(rows=1, cols=n, max_degree=4))
    if data.draw(st.booleans()):
        x = x @ PolyMatrix.diag(*([f] * n)) if data.draw(st.booleans()) else x @ W
    assert in_row_module(list(x._r[0]), kd) == (extend_row_basis(W, x).rows.rows == 0)


def test_the_primes_are_told_to_the_progress_note():
    """kernel_det says which prime it is at, after the step's note, and restores that note."""
    from uio_ring import _progress
    from uio_ring.ring._monic_det import _MAX_PRIMES

    z = [[flint.fmpz_poly([1, 2, 3]), flint.fmpz_poly([0, 1])], [flint.fmpz_poly([5]), flint.fmpz_poly([1, 0, 1])]]
    seen: list[str] = []
    _progress.set_sink(seen.append)
    try:
        with _progress.step("step 5"):
            f = monic_det_by_kernel(z, 2, 1)
            assert _progress.current() == "step 5"
    finally:
        _progress.set_sink(None)
    assert f == _expected(z, 2, 1)
    assert f"step 5; the monic determinant of a 2×2 by its cofactors modulo primes: prime 1 of at most {_MAX_PRIMES}" in seen
    assert seen[-2:] == ["step 5", ""]
