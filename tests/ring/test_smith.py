"""Smith form: U M V = S, invariant factors against sympy and known constructions.

The invariant factors (monic, each dividing the next, as many as the rank)
are unique and compared by value; U and V are choices and only their
identities are checked.
"""

from __future__ import annotations

import dataclasses
import importlib

import pytest
from hypothesis import given
from hypothesis import strategies as st

from uio_ring import PolyMatrix, invariant_factors, is_smith, is_unimodular, smith
from uio_ring.ring._column_basis import full_rank_core
from uio_ring.ring.smith import invariant_factors_by_elimination

from .strategies import (
    P,
    assert_smith_form,
    assert_unimodular,
    dense_matrices,
    heavy,
    matrices,
    paper_001_M,
    paper_001_system,
    rank_deficient_matrices,
    reference_det,
    reference_invariant_factors,
    reference_rank,
    same_poly,
    singular_at_sample_points,
    square_matrices,
    to_sympy_poly,
    unimodular_matrices,
)

smith_module = importlib.import_module("uio_ring.ring.smith")


def check_smith(M: PolyMatrix, s=None):
    """smith(M), or the given result of another path, checked."""
    s = smith(M) if s is None else s
    assert s.S.shape == M.shape
    assert s.U.shape == (M.rows, M.rows) and s.V.shape == (M.cols, M.cols)
    assert s.U @ M @ s.V == s.S
    assert is_smith(s.S)
    assert isinstance(s.invariant_factors, tuple)
    assert_smith_form(s.S, s.invariant_factors)
    assert_unimodular(s.U, M.rows)
    assert_unimodular(s.V, M.cols)
    assert is_unimodular(s.U) and is_unimodular(s.V)
    assert len(s.invariant_factors) == M.rank()
    assert s.verify(M).ok
    return s


# ----------------------------------------------------------------------------
# properties
# ----------------------------------------------------------------------------
@given(matrices())
def test_smith_identities(M):
    s = check_smith(M)
    assert invariant_factors(M) == s.invariant_factors


@given(matrices(max_rows=5, max_cols=5))
def test_invariant_factors_match_sympy(M):
    """sympy.matrices.normalforms.invariant_factors over QQ[d] is an independent
    implementation; its nonzero factors, made monic, must equal ours."""
    ours = invariant_factors(M)
    ref = reference_invariant_factors(M)
    assert len(ours) == len(ref) == reference_rank(M)
    assert [to_sympy_poly(f) for f in ours] == ref


@given(square_matrices(max_n=5))
def test_product_of_invariant_factors_is_monic_det(M):
    fs = invariant_factors(M)
    det = reference_det(M)
    if det.is_zero:
        assert len(fs) < M.rows
    else:
        prod = P("1")
        for f in fs:
            prod = prod * f
        assert same_poly(prod, det.monic())
        assert same_poly(M.det().monic(), det.monic())


@given(st.data())
def test_invariant_factors_are_invariant_under_equivalence(data):
    M = data.draw(matrices(max_rows=5, max_cols=5))
    Pm = data.draw(unimodular_matrices(M.rows))
    Q = data.draw(unimodular_matrices(M.cols))
    assert invariant_factors(Pm @ M @ Q) == invariant_factors(M)
    assert invariant_factors(M.T) == invariant_factors(M)


@st.composite
def known_smith(draw):
    """P·diag(1, …, 1, [d+1], [(d+1)(d−2)], 0…)·Q with random unimodular P, Q (any shape)."""
    p = draw(st.integers(1, 6))
    q = draw(st.integers(1, 6))
    r = draw(st.integers(0, min(p, q)))
    k = draw(st.integers(0, min(r, 2)))  # how many non-trivial factors
    if k == 2:
        tail = ["d + 1", "(d + 1)*(d - 2)"]  # d+1 divides (d+1)(d-2)
    elif k == 1:
        tail = [draw(st.sampled_from(["d + 1", "(d + 1)*(d - 2)"]))]
    else:
        tail = []
    diag = ["1"] * (r - k) + tail
    rows = [["0"] * q for _ in range(p)]
    for i, e in enumerate(diag):
        rows[i][i] = e
    S0 = PolyMatrix(rows)
    Pm = draw(unimodular_matrices(p))
    Q = draw(unimodular_matrices(q))
    return Pm @ S0 @ Q, [P(e) for e in diag]


@given(known_smith())
def test_known_smith_forms(case):
    M, expected = case
    s = check_smith(M)
    assert list(s.invariant_factors) == expected
    assert list(invariant_factors(M)) == expected
    assert M.rank() == len(expected)


@heavy()
@given(singular_at_sample_points())
def test_known_smith_forms_singular_at_sample_points(case):
    """Sizes 4..8 reach the evaluation/interpolation fast paths; M(x) is singular at
    0, ±1, ±2, ±3, so any path that trusts a few sample points gets it wrong."""
    M, diag = case
    expected = [P(e) for e in diag if e != "0"]
    s = check_smith(M)
    assert list(s.invariant_factors) == expected
    assert list(invariant_factors(M)) == expected


@heavy()
@given(st.integers(6, 8).flatmap(lambda n: dense_matrices(rows=n, cols=n, max_degree=2,
                                                          rational=False)))
def test_invariant_factors_match_sympy_at_fast_path_sizes(M):
    ours = invariant_factors(M)
    assert [to_sympy_poly(f) for f in ours] == reference_invariant_factors(M)
    check_smith(M)


# ----------------------------------------------------------------------------
# fixed examples
# ----------------------------------------------------------------------------
def test_style_guide_example():
    s = check_smith(PolyMatrix.diag("d", "d + 1"))
    assert s.invariant_factors == (1, P("d**2 + d"))
    assert s.S == PolyMatrix.diag(1, "d**2 + d")


def test_known_small_cases():
    cases = [
        ("[[d, 0], [0, d]]", ["d", "d"]),
        ("[[2*d + 2]]", ["d + 1"]),
        ("[[d, 1], [0, d]]", ["1", "d**2"]),
        ("[[d**2, 0, 0], [0, d, 0]]", ["d", "d**2"]),
        ("[[d - 1, 0], [0, d + 1]]", ["1", "d**2 - 1"]),
        ("[[1, d, d**2]]", ["1"]),
        ("[[d], [d**2]]", ["d"]),
        ("[[0, 0], [0, 0]]", []),
    ]
    for text, fs in cases:
        s = check_smith(PolyMatrix(text))
        assert list(s.invariant_factors) == [P(f) for f in fs], text


@pytest.mark.parametrize("shape", [(0, 0), (0, 3), (3, 0), (3, 3), (2, 4), (4, 2)])
def test_empty_and_zero_matrices(shape):
    Z = PolyMatrix.zeros(*shape)
    s = check_smith(Z)
    assert s.S == Z and s.invariant_factors == ()
    assert invariant_factors(Z) == ()


def test_rank_deficient():
    a = PolyMatrix("[[1, d], [d - 1, 2], [0, 1], [d, d]]")
    b = PolyMatrix("[[d, 1, 0], [1, 0, d + 1]]")
    M = a @ b
    s = check_smith(M)
    assert len(s.invariant_factors) == 2
    assert [to_sympy_poly(f) for f in s.invariant_factors] == reference_invariant_factors(M)


def test_paper_001_invariant_factors():
    """Zheng et al. §5 (Assumption 2): Invs [[CB, D], [D, 0]] = {1, 1, 1}, and appending
    the block row [B, 0] does not change them (docs/errata.md Z6: unique, compare values)."""
    M = paper_001_M()
    s = check_smith(M)
    assert s.invariant_factors == (1, 1, 1)
    assert invariant_factors(M) == (1, 1, 1)
    assert M.rank() == 3
    sysm = paper_001_system()
    B = sysm["B"]
    M3 = PolyMatrix.vstack(M, PolyMatrix.hstack(B, PolyMatrix.zeros(B.rows, 2)))
    assert invariant_factors(M3) == (1, 1, 1)


# ----------------------------------------------------------------------------
# predicate and result object
# ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "text, expected",
    [
        ("[[1, 0], [0, d]]", True),
        ("[[d, 0], [0, 1]]", False),  # d does not divide 1
        ("[[2, 0], [0, d]]", False),  # not monic
        ("[[1, 1], [0, d]]", False),  # not diagonal
        ("[[0, 0], [0, d]]", False),  # zero before nonzero
        ("[[d, 0, 0], [0, d**2 - d, 0]]", True),
        ("[[d, 0], [0, d + 1]]", False),
        ("[[1, 0], [0, 0], [0, 0]]", True),
    ],
)
def test_is_smith(text, expected):
    assert is_smith(PolyMatrix(text)) is expected


def test_result_is_frozen_and_not_a_tuple():
    M = PolyMatrix("[[d, 1], [0, d]]")
    s = smith(M)
    with pytest.raises(AttributeError):
        s.S = M  # type: ignore[misc]
    with pytest.raises(TypeError):
        iter(s)


def test_verify_detects_a_wrong_claim():
    M = PolyMatrix("[[d, 1], [0, d]]")
    s = smith(M)
    assert s.verify(M).ok
    assert not dataclasses.replace(s, S=PolyMatrix.diag(1, "d")).verify(M).ok
    assert not dataclasses.replace(s, V=s.V @ PolyMatrix.diag("d", 1)).verify(M).ok


# ----------------------------------------------------------------------------
# rank-deficient: a square nonsingular core from kernel bases (ring._column_basis)
# ----------------------------------------------------------------------------
@given(rank_deficient_matrices(min_rows=2, max_rows=5, min_cols=2, max_cols=5))
def test_full_rank_core_has_the_invariant_factors(M):
    """T (r×r) built from kernel bases and one-sided inverses is nonsingular and has the
    invariant factors of M, by the elimination on M itself."""
    r = M.rank()
    if r == 0:
        return
    T = full_rank_core(M._r, *M.shape, r)
    assert T is not None
    T = PolyMatrix._new(T, r, r, M.var)
    assert not T.det().is_zero()
    assert invariant_factors_by_elimination(T) == invariant_factors_by_elimination(M)


def test_singular_square_beyond_the_guard_takes_the_core(monkeypatch):
    """With the runaway guard lowered, a singular square matrix whose elimination crosses it
    goes through the kernel-basis core, with the elimination's invariant factors."""
    calls = []
    real = smith_module.full_rank_core
    monkeypatch.setattr(smith_module, "full_rank_core", lambda *a: calls.append(a[3]) or real(*a))
    monkeypatch.setattr(smith_module, "FACTORS_GUARD_BITS", 8)
    A = PolyMatrix("[[d**3 + 2, 3*d - 1, d**2], [d - 5, d**4 + d, 7], [2*d**2, 1, d**3 - 4*d], [d, d + 1, 1]]")
    B = PolyMatrix("[[d + 1, 2, d**2 - 3, d, 1], [3, d**2 + 2*d, 1, d - 1, 2*d], [d**2, d, 5, 1, d + 3]]")
    M = A @ B @ PolyMatrix("[[1, 0, 0, 0, 0], [0, 1, 0, 0, 0], [0, 0, 1, 0, 0], [0, 0, 0, 1, 0], [1, 1, 1, 1, 1]]")
    M = PolyMatrix.vstack(M, M[0:1, :] + M[1:2, :])  # 5×5 of rank 3
    f = invariant_factors(M)
    assert calls == [3]
    assert f == smith_module.invariant_factors_by_elimination(M)


@st.composite
def singular_with_factors(draw):
    """A·D·B: A n×k, B k×n (or (n+2)×k for a tall M), k < n, D = diag of 1s and factors
    drawn from δ, δ+1, δ−2, so that M has rank k and often non-trivial factors; n ≥ 7, so
    the row-basis proof is tried (≥ ROW_BASIS_MIN_ENTRIES entries)."""
    n = draw(st.integers(7, 8))
    k = draw(st.integers(n - 2, n - 1))
    rows = n + draw(st.sampled_from([0, 0, 2]))
    A = draw(dense_matrices(rows=rows, cols=k, max_degree=1))
    B = draw(dense_matrices(rows=k, cols=n, max_degree=1))
    extra = draw(st.lists(st.sampled_from(["1", "d", "d + 1", "(d + 1)*(d - 2)"]), min_size=k, max_size=k))
    return A @ PolyMatrix.diag(*extra) @ B


@heavy()
@given(singular_with_factors())
def test_invariant_factors_of_singular_products_match_the_elimination(M):
    """Singular square and tall rank-deficient M, with and without non-trivial factors: the
    row-basis proof (all ones) and the routes after it give the elimination's factors."""
    assert invariant_factors(M) == invariant_factors_by_elimination(M)


def test_row_basis_proves_trivial_factors_without_elimination(monkeypatch):
    """A singular 8×8 product of 8×7 and 7×8 factors (degree 1, entries in [−3, 3]): its
    weak Popov rows have coprime maximal minors, so the factors are seven ones and the
    elimination never runs; with δ+1 in the middle the proof fails and the elimination
    finds it."""
    import random

    rng = random.Random(3)

    def rnd(m, n):
        return PolyMatrix.from_coefficients(
            [[[rng.randint(-3, 3) for _ in range(n)] for _ in range(m)] for _ in range(2)])

    A, B = rnd(8, 7), rnd(7, 8)
    calls = []
    real = smith_module._invariant_factors_by_elimination
    monkeypatch.setattr(smith_module, "_invariant_factors_by_elimination",
                        lambda *a, **k: calls.append(1) or real(*a, **k))
    assert smith_module._trivial_by_row_basis((A @ B)._r, 8, 8)
    assert invariant_factors(A @ B) == (P("1"),) * 7 and calls == []
    M = A @ PolyMatrix.diag(*(["1"] * 6 + ["d + 1"])) @ B
    assert not smith_module._trivial_by_row_basis(M._r, 8, 8)
    f = invariant_factors(M)
    assert f[-1] == P("d + 1") and f[:-1] == (P("1"),) * 6 and calls


def _through_hermite(monkeypatch, M: PolyMatrix, calls: list | None = None):
    """smith(M) with the elimination's first attempt made to fail at once, so that a
    rectangular or singular M (any size) goes through the Hermite forms."""
    from uio_ring.ring import _smith_by_hermite

    monkeypatch.setattr(smith_module, "SMITH_ELIMINATION_BITS", -(10**6))
    if calls is not None:
        real = _smith_by_hermite.diagonal_form_by_hermite
        monkeypatch.setattr(smith_module, "diagonal_form_by_hermite",
                            lambda *a, **k: calls.append(a[1:3]) or real(*a, **k))
    return check_smith(M)


@heavy()
@given(st.data())
def test_smith_through_hermite_forms_is_the_smith_form(data):
    """Rank-deficient square and tall/wide M of 1..7 rows and columns: the Smith form through
    Hermite forms and unit pivots has the invariant factors of the elimination (and of
    sympy), U·M·V = S with U, V unimodular, and the kernel rows of U and columns of V are
    the Popov bases."""
    from .strategies import assert_popov

    m, n = data.draw(st.integers(1, 7)), data.draw(st.integers(1, 7))
    kind = data.draw(st.sampled_from(["rank-deficient", "dense"]))
    if kind == "rank-deficient":
        M = data.draw(rank_deficient_matrices(rows=m, cols=n))
    else:
        M = data.draw(dense_matrices(rows=m, cols=n, max_degree=2))
    if M.rank() == 0 or (m == n and M.rank() == n):
        return  # nothing to eliminate, or square nonsingular: not this path
    calls: list = []
    with pytest.MonkeyPatch.context() as mp:
        s = _through_hermite(mp, M, calls)
    assert calls in ([], [(m, n)])
    if not calls:  # an elimination that never grew (a column [δ²; δ³]) met no cap: the path itself
        s = check_smith(M, smith_module._smith_by_hermite(M))
    ref = smith_module.smith_by_elimination(M)
    assert s.S == ref.S
    r = s.rank
    assert [str(f) for f in s.invariant_factors] == [str(f) for f in ref.invariant_factors]
    if r < m:
        assert_popov(s.U[r:, :])
        assert s.U[r:, :] == ref.U[r:, :]  # the Popov basis is unique
    if r < n:
        assert_popov(s.V[:, r:].T)
        assert s.V[:, r:] == ref.V[:, r:]


def test_smith_through_hermite_forms_clears_unit_pivots_without_arithmetic(monkeypatch):
    """diag(1, 1, 1, 1, δ, 0) times unimodular factors (6×6, rank 5): the row Hermite form
    has four unit pivots, and the core left is a single entry; the factors are
    1, 1, 1, 1, δ exactly (unique), with the kernel rows in Popov form."""
    U = PolyMatrix([[1, "d", 0, 0, 0, 0], [0, 1, 0, 0, 0, 0], [0, "d**2", 1, 0, 0, 0],
                    [0, 0, "2*d", 1, 0, 0], [0, 0, 0, "d", 1, 0], [1, 0, 0, 0, "d", 1]])
    V = PolyMatrix([[1, 0, 0, 0, 0, 0], ["d", 1, 0, 0, 0, 0], [0, 3, 1, 0, 0, 0],
                    [0, 0, "d", 1, 0, 0], [0, 0, 0, 0, 1, 0], ["d**2", 0, 0, 0, "d", 1]]).T
    M = U @ PolyMatrix.diag(1, 1, 1, 1, "d", 0) @ V
    s = _through_hermite(monkeypatch, M)
    assert [str(f) for f in s.invariant_factors] == ["1", "1", "1", "1", "d"]


def test_sparse_singular_smith_goes_through_hermite_forms_when_elimination_swells(monkeypatch):
    """A 10×10 of degree 6 with 30 % nonzero entries and a zero row (rank 9): the
    elimination outgrows its cap, and the Hermite path gives the Smith form (checked by
    the identities and against the invariant factors computed without transforms)."""
    import random

    rng = random.Random(5)
    n = 10
    rows = [[" + ".join(f"({rng.randint(-3, 3)})*d**{k}" for k in range(7)) if rng.random() < 0.3 else "0"
             for _ in range(n)] for _ in range(n)]
    rows[3] = ["0"] * n
    M = PolyMatrix(rows)
    calls: list = []
    real = smith_module.diagonal_form_by_hermite
    monkeypatch.setattr(smith_module, "diagonal_form_by_hermite",
                        lambda *a, **k: calls.append(a[1:3]) or real(*a, **k))
    s = smith(M)
    assert calls == [(n, n)]
    assert s.verify(M).ok  # U·M·V = S exactly, det U and det V nonzero constants, S normalised
    assert s.invariant_factors == invariant_factors(M) and s.rank == 9


@given(st.data())
def test_unimodularity_from_the_smith_identity_agrees_with_det(data):
    """``unimodular_given_smith`` (det U·det V from det D, a minor of M and the kernel
    blocks of U and V) against det U and det V: on smith's own U and V, and with a kernel
    row of U or a kernel column of V multiplied by δ + c (U·M·V = S still holds)."""
    from uio_ring.ring._predicates import is_unimodular_raw, unimodular_given_smith

    M = data.draw(st.one_of(matrices(1, 4, 1, 4), rank_deficient_matrices(min_rows=2, max_rows=4, max_cols=4)))
    s = smith(M)
    m, n = M.shape
    assert unimodular_given_smith(s.U._r, s.V._r, (s.U @ M)._r, M._r, s.S._r, m, n)
    r = len(s.invariant_factors)
    f = P(f"d + {data.draw(st.integers(-2, 2))}")
    U, V = s.U, s.V
    if r < m and data.draw(st.booleans()):
        k = data.draw(st.integers(r, m - 1))
        U = PolyMatrix.vstack(*[U[i, :] * f if i == k else U[i, :] for i in range(m)])
    elif r < n:
        k = data.draw(st.integers(r, n - 1))
        V = PolyMatrix.hstack(*[V[:, j] * f if j == k else V[:, j] for j in range(n)])
    else:
        return
    assert U @ M @ V == s.S
    assert unimodular_given_smith(U._r, V._r, (U @ M)._r, M._r, s.S._r, m, n) is False
    assert not (is_unimodular_raw(U._r, m, m) and is_unimodular_raw(V._r, n, n))
    cert = dataclasses.replace(s, U=U, V=V).verify(M)
    assert not cert.ok
    assert [c.ok for c in cert.checks][1:3] == [is_unimodular_raw(U._r, m, m), is_unimodular_raw(V._r, n, n)]


@st.composite
def permuted_triangular_matrices(draw, max_n: int = 6):
    """Row permutations of upper triangular matrices with a nonzero diagonal, whose
    diagonal entries share factors (δ, δ + 1, δ², δ(δ + 1), constants)."""
    n = draw(st.integers(1, max_n))
    N = draw(dense_matrices(rows=n, cols=n, max_degree=2))
    diagonal = ["d", "d + 1", "d**2", "d**2 + d", "2", "-1/3"]
    rows = [["0"] * i + [draw(st.sampled_from(diagonal))] + [str(N[i, j]) for j in range(i + 1, n)]
            for i in range(n)]
    return PolyMatrix(draw(st.permutations(rows)))


@given(permuted_triangular_matrices())
def test_permuted_triangular_matrices_go_through_their_hermite_form(M):
    """A row permutation of a triangular matrix has the Smith form of its Hermite form
    (U = U_S·U_H): the same invariant factors as the elimination of M itself, the
    identities exact, and the detour taken (a spy) unless M is its own Hermite form."""
    from uio_ring.ring.hermite import is_hermite

    seen = []
    real = smith_module.hermite_of_triangular

    def spy(A):
        got = real(A)
        seen.append(got is not None)
        return got

    smith_module.hermite_of_triangular = spy
    try:
        s = check_smith(M)
        factors = invariant_factors(M)
    finally:
        smith_module.hermite_of_triangular = real
    assert s.invariant_factors == factors == invariant_factors_by_elimination(M)
    assert seen[0] == (not is_hermite(M))


def test_small_rectangular_matrix_of_high_degree_leaves_the_swelling_elimination(monkeypatch):
    """A random 2×4 of degree 24: the alternating eliminations swell (their Bézout
    cofactors over Q) past the cap, and the Smith form comes from Hermite forms (a spy):
    exact identities, and the factors are those computed without transforms."""
    import random

    rng = random.Random(3)
    M = PolyMatrix([[" + ".join(f"({rng.randint(-3, 3)})*d**{k}" for k in range(25)) for _ in range(4)]
                    for _ in range(2)])
    calls: list = []
    real = smith_module.diagonal_form_by_hermite
    monkeypatch.setattr(smith_module, "diagonal_form_by_hermite",
                        lambda *a, **k: calls.append(a[1:3]) or real(*a, **k))
    s = smith(M)
    assert calls == [(2, 4)]
    assert s.verify(M).ok
    assert s.invariant_factors == invariant_factors(M)


@heavy()
@given(st.data())
def test_nonsingular_squares_off_the_generic_shape_go_through_hermite_forms(data):
    """P·D·Q of 6×6 or 7×7 with P, Q random unimodular and D = diag(1, …, 1, f, f·g) (two
    non-trivial invariant factors: the generic paths refuse): the Smith form comes from
    the Hermite forms and unit pivots (a spy), with the elimination's invariant factors
    and exact identities."""
    from .strategies import unimodular_matrices

    n = data.draw(st.integers(6, 7))
    f = data.draw(st.sampled_from(["d", "d + 1", "2*d - 1"]))
    g = data.draw(st.sampled_from(["d", "d - 2", "d**2 + 1"]))
    Pm = data.draw(unimodular_matrices(n, steps=data.draw(st.integers(n, 2 * n))))
    Q = data.draw(unimodular_matrices(n, steps=data.draw(st.integers(n, 2 * n))))
    M = Pm @ PolyMatrix.diag(*(["1"] * (n - 2) + [f, f"({f})*({g})"])) @ Q
    calls: list = []
    real = smith_module.diagonal_form_by_hermite
    smith_module.diagonal_form_by_hermite = lambda *a, **k: calls.append(a[1:3]) or real(*a, **k)
    try:
        s = check_smith(M)
    finally:
        smith_module.diagonal_form_by_hermite = real
    assert calls[:1] == [(n, n)]
    assert s.invariant_factors == invariant_factors_by_elimination(M)
