"""The bottom-up Hermite normalisation and the Popov divisor (issue 15 speed-ups).

Each new routine is compared with an independent implementation: ``normalise``
(bottom-up) with the top-down pass it replaced, written out here; the closed-form
2×2 adjugate with ``P·adj P = det P·I``; ``PopovDivisor.remainder`` with the
one-leading-term-at-a-time reduction ``_dense.reduce_rows``; the square singular
and tall shortcuts of ``hermite``/``left_inverse`` with ``hermite_by_elimination``
(H and the reduced U are unique, so they must agree entry by entry).
"""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from uio_ring import PolyMatrix, hermite, left_inverse
from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring import _division as dv
from uio_ring.ring._echelon import normalise, row_echelon
from uio_ring.ring.errors import NotUnimodularError
from uio_ring.ring.hermite import hermite_by_elimination

from .strategies import (
    assert_popov,
    assert_unimodular,
    dense_matrices,
    heavy,
    matrices,
    rank_deficient_matrices,
    unimodular_matrices,
)


def _normalise_top_down(a: dn.Rows, u: dn.Rows, pivots: list[int]) -> None:
    """The former ``normalise``: monic pivots, then each pivot row clears the rows above."""
    for k, j in enumerate(pivots):
        c = bk.lc(a[k][j])
        inv = bk.const(1) / c
        a[k] = [x * inv for x in a[k]]
        u[k] = [x * inv for x in u[k]]
    for k, j in enumerate(pivots):
        piv = a[k][j]
        for i in range(k):
            if a[i][j].degree() >= piv.degree():
                q = a[i][j] // piv
                dn.row_axpy(a, i, q, k, j)
                dn.row_axpy(u, i, q, k)


@given(matrices(max_rows=6, max_cols=6))
def test_bottom_up_normalise_equals_top_down(M):
    m, n = M.shape
    a, u = dn.copy(M._r), dn.identity(m)
    pivots = row_echelon(a, u, m, n)
    a2, u2 = dn.copy(a), dn.copy(u)
    normalise(a, u, pivots)
    _normalise_top_down(a2, u2, pivots)
    assert a == a2 and u == u2
    H = PolyMatrix._new(a, m, n, M.var)
    assert PolyMatrix._new(u, m, m, M.var) @ M == H


@given(dense_matrices(rows=2, cols=2, max_degree=3))
def test_closed_form_2x2_adjugate(P):
    det, adj = dv.adjugate(P._r, 2)
    A = PolyMatrix._new(adj, 2, 2, P.var)
    d = PolyMatrix._new([[det, bk.ZERO], [bk.ZERO, det]], 2, 2, P.var)
    assert P @ A == d and A @ P == d
    assert PolyMatrix._new([[det]], 1, 1, P.var)[0, 0] == P.det()


@given(st.integers(3, 5).flatmap(lambda k: dense_matrices(rows=k, cols=k, max_degree=3)))
def test_adjugate_by_cofactors_equals_adjugate_by_evaluation(P):
    """3×3 and 4×4 by cofactors, 5×5 by evaluation: P·adj P = adj P·P = det P·I, and the
    two methods agree wherever both apply (P nonsingular)."""
    k = P.rows
    if P.det().is_zero():
        return
    det, adj = dv.adjugate(P._r, k)
    A = PolyMatrix._new(adj, k, k, P.var)
    D = PolyMatrix._new([[det if i == j else bk.ZERO for j in range(k)] for i in range(k)], k, k, P.var)
    assert P @ A == D and A @ P == D
    assert PolyMatrix._new([[det]], 1, 1, P.var)[0, 0] == P.det()
    if k <= dv.COFACTOR_MAX_SIZE:
        assert dv._adjugate_by_evaluation(P._r, k) == (det, adj)


@given(st.data())
def test_popov_divisor_remainder_equals_term_by_term_reduction(data):
    """A Popov basis (of 1 to 3 rows, so that the closed forms and the cofactors run) from a
    random left kernel; random rows reduced by it both ways."""
    k = data.draw(st.integers(1, 3))
    n = data.draw(st.integers(1, 3))
    M = data.draw(dense_matrices(rows=n + k, cols=n, max_degree=2))
    a, u = dn.copy(M._r), dn.identity(n + k)
    r = len(row_echelon(a, u, n + k, n))
    basis = u[r:]
    dn.weak_popov(basis)
    dn.popov(basis)
    X = data.draw(dense_matrices(rows=3, cols=n + k, max_degree=6))
    div = dv.PopovDivisor.of(basis)
    pivots = [(j, d) for d, j in (dn.leading_position(row) for row in basis)]
    for row in X._r:
        ref = [list(row)]
        dn.reduce_rows(ref, [0], pivots, basis=basis)
        got = div.remainder(row)
        assert got == ref[0]
        assert not div.pending(got)
    assert dv.reduce_modulo_popov(X._r, basis) == [div.remainder(row) for row in X._r]


@heavy()
@given(st.integers(6, 8).flatmap(lambda n: rank_deficient_matrices(rows=n, cols=n)))
def test_square_singular_hermite_equals_elimination(M):
    """n ≥ 6 singular: hermite skips the nonsingular paths and the rank; same H and U."""
    h = hermite(M)
    ref = hermite_by_elimination(M)
    assert h.H == ref.H and h.U == ref.U and h.rank == ref.rank
    assert h.U @ M == h.H
    assert_unimodular(h.U, M.rows)
    assert_popov(h.U[h.rank:, :])


@heavy()
@given(st.data())
def test_tall_hermite_and_left_inverse_equal_elimination(data):
    """Tall M (6 to 9 rows), left unimodular or not: hermite without a rank computation
    first gives the unique H and reduced U; left_inverse returns its top rows or raises."""
    m = data.draw(st.integers(6, 9))
    n = data.draw(st.integers(1, m - 1))
    if data.draw(st.booleans()):
        M = data.draw(unimodular_matrices(m, steps=2 * m))[:, :n]
    else:
        M = data.draw(dense_matrices(rows=m, cols=n, max_degree=1))
    h = hermite(M)
    ref = hermite_by_elimination(M)
    assert h.H == ref.H and h.U == ref.U
    if h.H[:n, :] == PolyMatrix.identity(n, M.var):
        assert left_inverse(M) == h.U[:n, :]
    else:
        with pytest.raises(NotUnimodularError):
            left_inverse(M)


@given(dense_matrices(min_rows=1, max_rows=6, min_cols=1, max_cols=5))
def test_row_echelon_and_weak_popov_invariants(M):
    # the eliminated entries are set from divmod's remainder and weak_popov recomputes
    # only the changed row's leading position: the row operations still give u·M = a,
    # a in echelon form, and the weak Popov rows have distinct leading positions
    m, n = M.shape
    a, u = dn.copy(M._r), dn.identity(m)
    pivots = row_echelon(a, u, m, n)
    assert dn.matmul(u, M._r, m, m, n) == a
    for k, j in enumerate(pivots):
        assert not a[k][j].is_zero() and all(a[i][j].is_zero() for i in range(k + 1, m))
        assert all(e.is_zero() for e in a[k][:j])
    assert all(e.is_zero() for row in a[len(pivots):] for e in row)
    normalise(a, u, pivots)
    assert dn.matmul(u, M._r, m, m, n) == a
    b, p = dn.copy(M._r), dn.identity(m)
    nz = dn.weak_popov(b, p)
    assert dn.matmul(p, M._r, m, m, n) == b
    leads = [dn.leading_position(b[i])[1] for i in nz]
    assert len(set(leads)) == len(leads) and all(j >= 0 for j in leads)
    assert all(e.is_zero() for row in b[len(nz):] for e in row)
