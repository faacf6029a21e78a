"""Fraction-free determinants and determinantal-divisor invariant factors (ring._fraction_free),
and the row-basis extension (ring.row_basis), against the independent paths."""

from __future__ import annotations

import flint
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring import _backend as bk
from uio_ring.ring import _evaluation as ev
from uio_ring.ring import _fraction_free as ff
from uio_ring.ring.hermite import hermite
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.row_basis import extend_row_basis, is_weak_popov, remainder_rows
from uio_ring.ring.smith import invariant_factors, invariant_factors_by_elimination

from .strategies import dense_matrices, matrices, square_matrices, unimodular_matrices


def _det_by_evaluation(M: PolyMatrix):
    """det M(x) at deg-bound + 1 points, then interpolation: the independent path."""
    n = M.rows
    coeffs = ev.coefficient_mats(M._r, n, n)
    xs = ev.first_points(ev.minor_degree_bound(M._r, n, n, n) + 1)
    return ev.interpolate(xs, [ev.evaluate(coeffs, x).det() for x in xs])


@given(dense_matrices(min_rows=1, max_rows=4, min_cols=1, max_cols=4), st.integers(-40, 40))
def test_evaluation_over_z_is_exact(M, x):
    # coefficient_mats scales to integers over one common denominator and evaluate
    # divides once: the value must be M(x) exactly, entry by entry
    coeffs = ev.coefficient_mats(M._r, *M.shape)
    value = ev.evaluate(coeffs, x)
    assert value.tolist() == [[bk.evaluate(p, flint.fmpq(x)) for p in row] for row in M._r]
    if M.rows == M.cols:
        assert ev.det_at(coeffs, x) == value.det()


@given(square_matrices(min_n=1, max_n=5))
def test_bareiss_equals_evaluation(M):
    assert ff.det_fraction_free(M._r, M.rows) == _det_by_evaluation(M)


def test_bareiss_needs_a_row_swap_and_a_sign():
    M = PolyMatrix("[[0, 1, d], [1, 0, 2], [d, 3, 0]]")
    assert ff.det_fraction_free(M._r, 3) == _det_by_evaluation(M)
    assert ff.det_fraction_free(PolyMatrix("[[0, 0], [0, d]]")._r, 2).is_zero()


@given(matrices(min_rows=1, max_rows=5, min_cols=1, max_cols=4))
def test_generic_factors_equal_elimination_or_give_up(M):
    A = M if M.rows >= M.cols else M.T
    got = ff.generic_factors_fraction_free(A._r, A.rows, A.cols)
    ref = invariant_factors_by_elimination(A)
    if got is not None:
        assert tuple(got) == tuple(p._p for p in ref)
    assert invariant_factors(M) == ref


@settings(max_examples=25, deadline=None)
@given(st.integers(2, 4), st.data())
def test_fallback_when_two_factors_are_nontrivial(n, data):
    # P·diag(1, …, δ+1, (δ+1)(δ−2))·Q: d_{n−1} = δ + 1 ≠ 1, so the fast path must refuse
    P = data.draw(unimodular_matrices(n))
    Q = data.draw(unimodular_matrices(n))
    M = P @ PolyMatrix.diag(*(["1"] * (n - 2) + ["d + 1", "(d + 1)*(d - 2)"])) @ Q
    assert ff.generic_factors_fraction_free(M._r, n, n) is None
    tall = PolyMatrix.vstack(M, PolyMatrix("[[" + ", ".join(["0"] * n) + "]]"))
    assert ff.generic_factors_fraction_free(tall._r, n + 1, n) is None
    assert invariant_factors(tall) == invariant_factors_by_elimination(tall)
    assert [str(f) for f in invariant_factors(M)] == ["1"] * (n - 2) + ["d + 1", "d**2 - d - 2"]


def test_high_degree_tall_matrix_agrees_with_elimination():
    # k = 24: the 2×2 high-degree family with a third row; d_2 = 1 or not, both paths agree
    k = 24
    M = PolyMatrix(f"[[(1 + d)**{k}, d**{k - 1} + 1], [d**{k} - 1, (d - 1)**{k}], [d**3, 1 - d]]")
    assert ff.prefer_fraction_free(M._r, 2)
    assert invariant_factors(M) == invariant_factors_by_elimination(M)
    S = PolyMatrix(f"[[(1 + d)**{k}, 0], [0, (1 + d)**{k}], [(1 + d)**{k - 1}, d*(1 + d)**{k - 1}]]")
    assert [f.degree() for f in invariant_factors(S)] == [k - 1, k]  # d_2 = (1 + δ)^(2k−1)
    assert invariant_factors(S) == invariant_factors_by_elimination(S)


def test_maximal_minors_gcd_gives_up_beyond_the_limit():
    z = [[bk.IntPoly([1 + i + j]) for j in range(2)] for i in range(13)]
    assert ff.maximal_minors_gcd(z, 13, 2) is None  # 78 > MAX_MINORS minors
    assert ff.maximal_minors_gcd(z[:3], 3, 2) == bk.ONE  # the minors are all −1


def test_integer_rows_scale_by_units():
    a = PolyMatrix("[[1/2, d/3], [2*d/5, 7]]")._r
    z, scale = ff.integer_rows(a)
    assert all(isinstance(p, flint.fmpz_poly) for r in z for p in r)
    assert bk.from_integer(ff.det_integer(z, 2)) == scale * ff.det_fraction_free(a, 2)


# -- extend_row_basis -------------------------------------------------------------------------
def _module(M: PolyMatrix) -> PolyMatrix:
    """The row module of M, canonically: the nonzero rows of its Hermite form."""
    h = hermite(M)
    return h.H[0 : h.rank, 0 : M.cols]


@given(dense_matrices(min_rows=0, max_rows=3, cols=3), dense_matrices(min_rows=1, max_rows=3, cols=3))
def test_extend_row_basis_keeps_the_module(B0, X):
    from uio_ring.ring import _dense as dn

    rows = dn.copy(B0._r)
    dn.weak_popov(rows)
    rows = [r for r in rows if any(not p.is_zero() for p in r)]
    B = PolyMatrix._new(rows, len(rows), 3, "d")
    ext = extend_row_basis(B, X)
    target = _module(PolyMatrix.vstack(B, X))
    assert _module(PolyMatrix.vstack(B, ext.rows)) == target
    assert ext.basis.rows == 0 or is_weak_popov(ext.basis)
    assert _module(ext.basis) == target if ext.basis.rows else target.rows == 0
    assert ext.rows.rows <= X.rows
    assert all(ext.rows[i, :].degree() <= X.degree() for i in range(ext.rows.rows))


def test_extend_row_basis_of_the_whole_module_is_the_identity(monkeypatch):
    # rows whose module is Q[δ]^n (coprime maximal minors) give the basis I directly: the
    # Mulders–Storjohann sequence there can swell by hundreds of bits a step (an 8-state spec
    # with 8 outputs at δ-degree 16: a 12×8 of 2.6-kbit rows, minutes; the proof takes 12 ms)
    from uio_ring.ring import _dense as dn

    def refuse(*args, **kwargs):
        raise AssertionError("weak_popov called on a module proved to be Q[δ]^n")

    B = PolyMatrix("[[d**2 + 1, d], [0, d**2 - 3]]")  # weak Popov, det of degree 4
    X = PolyMatrix("[[1, 2*d + 5]]")
    assert _module(PolyMatrix.vstack(B, X)) == PolyMatrix.identity(2)
    monkeypatch.setattr(dn, "weak_popov", refuse)
    ext = extend_row_basis(B, X)
    # a proper submodule still goes through the reduction
    with pytest.raises(AssertionError, match="weak_popov called"):
        extend_row_basis(B, PolyMatrix("[[d**3 + d, d**2]]"))  # δ·(row 1 of B)
    monkeypatch.undo()
    assert ext.basis == PolyMatrix.identity(2)
    assert _module(PolyMatrix.vstack(B, ext.rows)) == PolyMatrix.identity(2)


def test_extend_row_basis_completes_the_proof_exactly_when_cheap(monkeypatch):
    # [[δ, δ³ + 1], [1, δ²], [0, 1]] is not column reduced: the compressed minors miss their
    # degree bound modulo p, and the exact ones (cheap here) prove the module is Q[δ]²
    from uio_ring.ring import _dense as dn
    from uio_ring.ring import row_basis

    def refuse(*args, **kwargs):
        raise AssertionError("weak_popov called on a module proved to be Q[δ]^n")

    B, X = PolyMatrix("[[d, d**3 + 1]]"), PolyMatrix("[[1, d**2], [0, 1]]")
    monkeypatch.setattr(dn, "weak_popov", refuse)
    assert extend_row_basis(B, X).basis == PolyMatrix.identity(2)
    monkeypatch.setattr(row_basis, "EXACT_PROOF_BUDGET", 0)  # the modular proof alone fails
    with pytest.raises(AssertionError, match="weak_popov called"):
        extend_row_basis(B, X)


def _reduce_rationally(x: list[flint.fmpq_poly], lead: dict[int, list[flint.fmpq_poly]]) -> list[flint.fmpq_poly]:
    """Oracle: the plain one-term reduction over Q, then the primitive integer row
    ([] for zero) — what ``row_basis._reduce_row`` computes fraction-free."""
    from uio_ring.ring import _dense as dn

    while True:
        d, j = dn.leading_position(x)
        if j < 0:
            return []
        b = lead.get(j)
        if b is None or b[j].degree() > d:
            break
        q = bk.monomial(bk.lc(x[j]) / bk.lc(b[j]), d - b[j].degree())
        x = [xi - q * bi for xi, bi in zip(x, b, strict=True)]
    z, _ = bk.integer_row(x)
    content = flint.fmpz(0)
    for p in z:
        content = content.gcd(p.content()) if not p.is_zero() else content
    return [bk.from_integer(p) / content for p in z]


@settings(max_examples=60, deadline=None)
@given(
    dense_matrices(min_rows=1, max_rows=3, cols=3),
    dense_matrices(min_rows=1, max_rows=3, cols=3),
    dense_matrices(min_rows=1, max_rows=2, cols=3),
    st.sampled_from([1, 3, 1000]),
)
def test_fraction_free_reduction_equals_the_rational_one(B0, X, Y, every):
    from uio_ring.ring import _dense as dn
    from uio_ring.ring import row_basis as rb

    rows = dn.copy(B0._r)
    dn.weak_popov(rows)
    rows = [r for r in rows if any(not p.is_zero() for p in r)]
    lead_q = {dn.leading_position(r)[1]: r for r in rows}
    lead_z = {j: bk.integer_row(r)[0] for j, r in lead_q.items()}
    inside: list[list[flint.fmpq_poly]] = []
    shifted: list[list[flint.fmpq_poly]] = []
    if rows:
        B = PolyMatrix._new(rows, len(rows), 3, "d")
        C = PolyMatrix([[f"{i + j + 1}*d**{2 + i}" for j in range(len(rows))] for i in range(Y.rows)])
        inside = [list(r) for r in (C @ B)._r]  # in the module: must reduce to zero
        shifted = [list(r) for r in (Y + C @ B)._r]  # long reductions with large multipliers
    old, rb._CONTENT_EVERY = rb._CONTENT_EVERY, every
    try:
        for x in [list(r) for r in X._r] + inside + shifted:
            assert rb._reduce_row(list(x), lead_z) == _reduce_rationally(list(x), lead_q)
        assert all(rb._reduce_row(list(x), lead_z) == [] for x in inside)
    finally:
        rb._CONTENT_EVERY = old


@given(dense_matrices(min_rows=0, max_rows=3, cols=3), dense_matrices(min_rows=1, max_rows=3, cols=3),
       st.integers(0, 3))
def test_remainder_rows_subtracts_module_elements_and_is_reduced(B0, Y, shift):
    from uio_ring.ring import _dense as dn

    rows = dn.copy(B0._r)
    dn.weak_popov(rows)
    rows = [r for r in rows if any(not p.is_zero() for p in r)]
    B = PolyMatrix._new(rows, len(rows), 3, "d")
    # rows with a large part inside L(B): the reduction must remove it
    X = Y + PolyMatrix([[f"{i - j + 2}*d**{shift + i}" for j in range(B.rows)] for i in range(Y.rows)]) @ B \
        if B.rows else Y
    got = remainder_rows(X, B)
    assert got.shape == X.shape
    lead = {dn.leading_position(r)[1]: r for r in B._r}
    for i in range(X.rows):
        diff = X[i, :] - got[i, :]
        if B.rows:  # x − r ∈ L(B), with no unit factor: L(B) + L(x − r) = L(B)
            assert _module(PolyMatrix.vstack(B, diff)) == _module(B)
        else:
            assert diff.is_zero()
        # the Popov normal form: every entry of a pivot column below that pivot's degree
        assert all(got._r[i][j].degree() < b[j].degree() for j, b in lead.items())
        assert got[i, :].degree() <= X[i, :].degree()


def test_remainder_rows_keeps_the_scale():
    # x = 3·b + r exactly: the remainder is r, not a unit multiple of it
    B = PolyMatrix("[[d**2, 1]]")
    X = PolyMatrix("[[3*d**3 + 1/2, 3*d + 5]]")
    assert remainder_rows(X, B) == PolyMatrix("[[1/2, 5]]")


def test_extend_row_basis_refuses_bad_input():
    from uio_ring.ring.errors import DimensionError

    with pytest.raises(DimensionError, match="weak Popov"):
        extend_row_basis(PolyMatrix("[[1, d], [0, d]]"), PolyMatrix("[[1, 1]]"))
    with pytest.raises(DimensionError, match="columns"):
        extend_row_basis(PolyMatrix("[[1, d]]"), PolyMatrix("[[1, 1, 1]]"))


# -- coprimality proved modulo one prime (ring._modular) ---------------------------------------
@given(square_matrices(min_n=1, max_n=4), square_matrices(min_n=1, max_n=4))
def test_modular_coprimality_is_sound(A, B):
    from uio_ring.ring._modular import coprime_dets_mod_p, det_mod_p

    if coprime_dets_mod_p(A._r, B._r, A.rows, k2=B.rows):
        assert bk.gcd(_det_by_evaluation(A), _det_by_evaluation(B)).is_one()
    f, bound = det_mod_p(A._r, A.rows)
    assert bound >= _det_by_evaluation(A).degree() >= f.degree()


@given(square_matrices(min_n=1, max_n=4))
def test_det_mod_p_is_the_scaled_determinant_mod_p(A):
    """1×1 and 2×2 by products in GF(p)[δ], larger by evaluation: both are det Z mod p
    for the rows Z scaled to Z[δ] (det Z = c·det A)."""
    import flint

    from uio_ring.ring._fraction_free import integer_rows
    from uio_ring.ring._modular import PRIME, det_mod_p

    _, c = integer_rows(A._r)
    exact = _det_by_evaluation(A) * c
    assert all(x.q == 1 for x in exact.coeffs())
    f, _ = det_mod_p(A._r, A.rows)
    assert f == flint.nmod_poly([int(x.p) % PRIME for x in exact.coeffs()], PRIME)


def test_modular_coprimality_refuses_an_unattained_bound_and_a_common_factor():
    from uio_ring.ring._modular import PRIME, coprime_dets_mod_p

    # det = p·δ + 1 is ≡ 1 mod p: coprime modulo p to anything, but the degree bound 1 is
    # not attained, so nothing is claimed (here gcd(pδ + 1, pδ + 1) is not 1 over Q)
    A = PolyMatrix(f"[[{PRIME}*d + 1]]")
    assert not coprime_dets_mod_p(A._r, A._r, 1)
    B = PolyMatrix("[[d + 1, 0], [0, d - 1]]")
    assert not coprime_dets_mod_p(B._r, PolyMatrix("[[d**2 - 1]]")._r, 2, k2=1)
    assert coprime_dets_mod_p(B._r, PolyMatrix("[[d**2 + 1]]")._r, 2, k2=1)


def test_remainder_rows_reduces_every_pivot_column():
    # the leading position of x (column 0) is no pivot, yet its pivot-column entry δ² is
    # reduced: the Popov normal form, not only the leading term
    assert remainder_rows(PolyMatrix("[[d**3, d**2 + 1]]"), PolyMatrix("[[0, 2*d]]")) == PolyMatrix("[[d**3, 1]]")
