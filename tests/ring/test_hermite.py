"""Normalised row Hermite form: identities, uniqueness, degree bounds, edge cases.

H is unique (normalised: zero rows last, pivots strictly right of the pivot
above, monic, entries above a pivot of lower degree), so H is compared by
value.  U is a choice except when M is square nonsingular (U = H M⁻¹); tests
check its identities, never its entries.
"""

from __future__ import annotations

import dataclasses

import pytest
from hypothesis import given
from hypothesis import strategies as st

from uio_ring import PolyMatrix, hermite, is_hermite, is_unimodular, left_kernel

from .strategies import (
    P,
    assert_hermite_normalised,
    assert_popov,
    assert_unimodular,
    dense_matrices,
    heavy,
    matrices,
    paper_001_M,
    rank_deficient_matrices,
    reference_rank,
    row_degrees,
    singular_at_sample_points,
    unimodular_matrices,
)


def check_hermite(M: PolyMatrix):
    h = hermite(M)
    assert h.H.shape == M.shape
    assert h.U.shape == (M.rows, M.rows)
    assert h.U @ M == h.H
    assert is_hermite(h.H)
    assert_hermite_normalised(h.H, h.pivots, h.rank)
    assert_unimodular(h.U, M.rows)
    assert is_unimodular(h.U)
    assert h.verify(M).ok
    return h


# ----------------------------------------------------------------------------
# properties on random matrices
# ----------------------------------------------------------------------------
@given(matrices())
def test_hermite_identities(M):
    h = check_hermite(M)
    assert h.rank == M.rank()
    assert all(isinstance(p, int) for p in h.pivots) and isinstance(h.pivots, tuple)


@given(matrices(max_rows=5, max_cols=5))
def test_hermite_rank_matches_sympy(M):
    assert hermite(M).rank == reference_rank(M)


@given(matrices())
def test_hermite_is_idempotent(M):
    H = hermite(M).H
    h2 = check_hermite(H)
    assert h2.H == H


@given(st.data())
def test_hermite_form_is_unique_under_unimodular_row_operations(data):
    M = data.draw(matrices())
    Q = data.draw(unimodular_matrices(M.rows))
    assert_unimodular(Q, M.rows)
    assert hermite(Q @ M).H == hermite(M).H


@given(matrices())
def test_kernel_part_of_transform(M):
    """Rows rank.. of U annihilate M and (as documented) form the Popov basis of the
    left kernel, which is unique — so they equal left_kernel(M)."""
    h = hermite(M)
    K = h.U[h.rank:, :]
    assert (K @ M).is_zero()
    assert K.rows == M.rows - h.rank
    assert_popov(K)
    assert K == left_kernel(M)


@given(st.integers(1, 5).flatmap(lambda n: dense_matrices(rows=n, cols=n, max_degree=2)))
def test_transform_degree_bound_for_nonsingular_square(M):
    """For square nonsingular M the transform is unique, U = H·adj(M)/det(M), so

        deg U[i, :] <= deg H[i, :] + (n − 1)·deg M − deg det M      (row by row)

    and, since deg H <= deg det M (each column's pivot divides det M and entries
    above a pivot have lower degree), deg U <= (n − 1)·deg M."""
    n = M.rows
    det = M.det()
    if det.degree() < 0:
        return  # singular: U is not unique, no bound from the mathematics
    h = check_hermite(M)
    dM = M.degree()
    assert h.H.degree() <= det.degree()
    assert h.U.degree() <= (n - 1) * dM
    for i, (du, dh) in enumerate(zip(row_degrees(h.U), row_degrees(h.H), strict=True)):
        assert du <= dh + (n - 1) * dM - det.degree(), f"row {i}: deg U = {du}"


@heavy()
@given(st.data())
def test_hermite_singular_at_sample_points(data):
    """Sizes 4..8 (the generic evaluation path starts at 6); M(x) singular at 0, ±1, ±2, ±3.
    H must be normalised, and equal for M and for R·M with R unimodular."""
    M, diag = data.draw(singular_at_sample_points())
    h = check_hermite(M)
    assert h.rank == sum(e != "0" for e in diag)
    R = data.draw(unimodular_matrices(M.rows))
    assert hermite(R @ M).H == h.H


@heavy()
@given(st.integers(6, 8).flatmap(lambda n: dense_matrices(rows=n, cols=n, max_degree=2,
                                                          rational=False)))
def test_hermite_at_fast_path_sizes(M):
    h = check_hermite(M)
    det = M.det()
    if det.degree() >= 0:
        assert h.U.degree() <= (M.rows - 1) * M.degree()
        prod = P("1")
        for i in range(M.rows):
            prod = prod * h.H[i, i]
        assert prod == det.monic()


# ----------------------------------------------------------------------------
# fixed examples
# ----------------------------------------------------------------------------
def test_style_guide_example():
    M = PolyMatrix([["d**2", "d"], ["d", 1]])
    h = check_hermite(M)
    assert h.H == PolyMatrix("[[d, 1], [0, 0]]")
    assert h.rank == 1 and h.pivots == (0,)


def test_convention_is_U_times_M():
    """An input where U·M and U⁻¹·M differ (an example must tell the conventions apart)."""
    M = PolyMatrix("[[d, 1], [d**2 + 1, d]]")  # det = -1: unimodular, H = I
    h = check_hermite(M)
    assert h.H == PolyMatrix.identity(2)
    assert h.U @ M == PolyMatrix.identity(2)
    assert M @ h.U == PolyMatrix.identity(2)  # U = M⁻¹ here
    N = PolyMatrix("[[d, 0], [1, d + 1]]")
    hN = check_hermite(N)
    assert hN.H == PolyMatrix("[[1, d + 1], [0, d**2 + d]]")


def test_known_forms():
    cases = [
        ("[[2*d, 4]]", "[[d, 2]]"),
        ("[[0, 0, 3]]", "[[0, 0, 1]]"),
        ("[[d], [d**2 - 1]]", "[[1], [0]]"),
        ("[[d, 0], [0, d]]", "[[d, 0], [0, d]]"),
        ("[[d + 1, d**3], [0, d]]", "[[d + 1, 0], [0, d]]"),
        ("[[0, d], [0, 0], [0, 2*d]]", "[[0, d], [0, 0], [0, 0]]"),
    ]
    for m, hform in cases:
        assert check_hermite(PolyMatrix(m)).H == PolyMatrix(hform), m


@pytest.mark.parametrize("shape", [(0, 0), (0, 3), (3, 0), (3, 3), (2, 4), (4, 2)])
def test_empty_and_zero_matrices(shape):
    Z = PolyMatrix.zeros(*shape)
    h = check_hermite(Z)
    assert h.H == Z and h.rank == 0 and h.pivots == ()


def test_rank_deficient():
    a = PolyMatrix("[[1, d], [d - 1, 2], [0, 1]]")
    b = PolyMatrix("[[d, 1, 0, d**2], [1, 0, d, 1]]")
    c = PolyMatrix("[[1], [d], [2]]")
    M = PolyMatrix.hstack(a @ b, c)  # 3×5, rank <= 3
    h = check_hermite(M)
    assert h.rank == M.rank() == reference_rank(M)
    N = a @ b  # 3×4 of rank 2
    hN = check_hermite(N)
    assert hN.rank == 2
    assert hN.H[2, :].is_zero()


def test_paper_001_step_1():
    """Zheng et al. §5, Step 1: M = [[CB, D], [D, 0]] has rank 3 and its normalised
    Hermite form is V = [[1,0,0,0],[0,1,0,0],[0,0,1,δ]] on top of three zero rows.
    (docs/errata.md Z6: V is unique; the printed U is a choice and is not compared.)"""
    M = paper_001_M()
    assert M.shape == (6, 4)
    h = check_hermite(M)
    V = PolyMatrix("[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, δ]]")
    assert h.rank == 3
    assert h.H == PolyMatrix.vstack(V, PolyMatrix.zeros(3, 4))
    assert h.pivots == (0, 1, 2)


# ----------------------------------------------------------------------------
# predicate, result object
# ----------------------------------------------------------------------------
@pytest.mark.parametrize(
    "text, expected",
    [
        ("[[1, d], [0, d**2]]", True),
        ("[[0, 1], [1, 0]]", False),  # pivot not right of the one above
        ("[[2, 0], [0, 1]]", False),  # pivot not monic
        ("[[1, d**2], [0, d**2]]", False),  # entry above pivot not of lower degree
        ("[[1, d**3], [0, d**2]]", False),
        ("[[0, 0], [1, 0]]", False),  # zero row not last
        ("[[1, 0], [0, 0]]", True),
        ("[[0, d, 1]]", True),
        ("[[d, 1], [0, 0], [0, 0]]", True),
        ("[[1, 1/2], [0, d]]", True),
    ],
)
def test_is_hermite(text, expected):
    assert is_hermite(PolyMatrix(text)) is expected


@pytest.mark.parametrize("shape", [(0, 0), (0, 2), (2, 0)])
def test_is_hermite_empty(shape):
    assert is_hermite(PolyMatrix.zeros(*shape))


def test_result_is_frozen_and_not_a_tuple():
    M = PolyMatrix("[[d, 1], [1, 0]]")
    h = hermite(M)
    with pytest.raises(AttributeError):  # dataclasses.FrozenInstanceError is one
        h.H = M  # type: ignore[misc]
    with pytest.raises(TypeError):
        iter(h)
    with pytest.raises(TypeError):
        H, U = h  # noqa: F841


def test_verify_detects_a_wrong_claim():
    M = PolyMatrix("[[d, 1], [d**2, d + 1]]")
    h = hermite(M)
    assert h.verify(M).ok
    wrong = dataclasses.replace(h, H=h.H + PolyMatrix("[[0, 1], [0, 0]]"))
    assert not wrong.verify(M).ok
    not_unimodular = dataclasses.replace(h, U=PolyMatrix.diag("d", 1) @ h.U)
    assert not not_unimodular.verify(M).ok
    assert not h.verify(M + PolyMatrix.identity(2)).ok


def test_scalar_entry_type():
    h = hermite(PolyMatrix("[[2*d + 2]]"))
    assert h.H[0, 0] == P("d + 1")


# ----------------------------------------------------------------------------
# tall / rank-deficient: elimination while coefficients stay small, else Toeplitz
# ----------------------------------------------------------------------------
@heavy()
@given(st.data())
def test_small_elimination_equals_the_toeplitz_path_on_columns_of_unimodular_matrices(data):
    """Tall M = first n columns of a unimodular matrix (6..9 rows: the Toeplitz path
    applies): the capped elimination finishes, and since H and the reduced U (Popov
    kernel rows, top rows reduced modulo them) are unique, it returns exactly what
    the elimination with the Toeplitz kernel returns."""
    from uio_ring.ring.hermite import _hermite_by_small_elimination, hermite_by_elimination

    m = data.draw(st.integers(6, 9))
    n = data.draw(st.integers(1, m - 1))
    Q = data.draw(unimodular_matrices(m, steps=2 * m))
    M = Q[:, :n]
    small = _hermite_by_small_elimination(M)
    assert small is not None
    ref = hermite_by_elimination(M)
    assert small.H == ref.H and small.U == ref.U and small.pivots == ref.pivots
    assert small.U @ M == small.H
    assert_unimodular(small.U, m)
    assert_popov(small.U[small.rank:, :])
    assert hermite(M).U == small.U



@heavy()
@given(st.data())
def test_small_elimination_without_zero_rows_gives_the_normalised_form(data):
    """Zero rows are left out of the elimination and come back as unit kernel rows:
    H, the Popov kernel rows (the units merged with the other rows' kernel in pivot
    order) and the reduced top rows are unique, so the result equals the elimination of
    the whole matrix, with or without the cap and the runaway guard."""
    from uio_ring.ring.hermite import _hermite_by_small_elimination, hermite_by_elimination

    N = data.draw(st.one_of(matrices(1, 4, 1, 4), rank_deficient_matrices(min_rows=2, max_rows=4, max_cols=4)))
    rows = [N[i, :] for i in range(N.rows)]
    for _ in range(data.draw(st.integers(1, 3))):
        rows.insert(data.draw(st.integers(0, len(rows))), PolyMatrix.zeros(1, N.cols))
    M = PolyMatrix.vstack(*rows)
    got = _hermite_by_small_elimination(M, full=data.draw(st.booleans()))
    assert got is not None  # below the cap's entries and degree: no cap
    ref = hermite_by_elimination(M)
    assert got.H == ref.H and got.U == ref.U and got.pivots == ref.pivots and got.rank == ref.rank
    assert got.U @ M == got.H
    assert_unimodular(got.U, M.rows)
    assert_popov(got.U[got.rank:, :])


def test_zero_rows_stay_out_of_the_elimination(monkeypatch):
    """The elimination runs on the nonzero rows only (a spy on ``row_echelon``): two zero
    rows of a 5×3 leave a 3×3, whose transform has no kernel rows to normalise."""
    import importlib

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    seen = []
    real = hermite_module.row_echelon
    monkeypatch.setattr(hermite_module, "row_echelon", lambda a, *args, **kw: seen.append(len(a)) or real(a, *args, **kw))
    M = PolyMatrix([["d", 1, 0], [0, 0, 0], ["d**2", "d", "d + 1"], [0, 0, 0], [1, "d", 2]])
    got = hermite_module._hermite_by_small_elimination(M)
    assert seen == [3]
    assert got.U @ M == got.H and got.rank == 3
    assert got.U[3:, :] == PolyMatrix([[0, 1, 0, 0, 0], [0, 0, 0, 1, 0]])

def test_small_elimination_gives_way_when_coefficients_swell():
    """A random 12×8 integer matrix of degree 2: Euclidean elimination over Q reaches
    thousands of bits, the capped attempt returns None and hermite takes the
    Toeplitz path — to the same unique H and reduced U as the full elimination."""
    import random

    from uio_ring.ring.hermite import _hermite_by_small_elimination, hermite_by_elimination

    rng = random.Random(20261130)
    coeffs = [[[rng.randint(-3, 3) for _ in range(8)] for _ in range(12)] for _ in range(3)]
    M = PolyMatrix.from_coefficients(coeffs)
    assert _hermite_by_small_elimination(M) is None
    h = check_hermite(M)
    ref = hermite_by_elimination(M)
    assert h.H == ref.H and h.U == ref.U


@heavy()
@given(st.data())
def test_rank_deficient_full_elimination_equals_the_toeplitz_path(data):
    """Rank-deficient M of 6..8 rows (H ≠ [I; 0]): hermite eliminates with transform (over
    Z[δ], fraction free, from 60 entries on) instead of H by elimination plus the
    Toeplitz kernel and solve; H and the reduced U are unique, so both give the same."""
    import importlib

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    m = data.draw(st.integers(6, 8))
    n = data.draw(st.integers(2, 10))
    M = data.draw(rank_deficient_matrices(rows=m, cols=n))
    h = check_hermite(M)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hermite_module, "FULL_ELIMINATION_BITS", -(10**6))  # the Toeplitz path
        mp.setattr(hermite_module, "CAP_MIN_ENTRIES", 0)
        ref = hermite(M)
    assert (h.H, h.U, h.pivots) == (ref.H, ref.U, ref.pivots)
    assert_popov(h.U[h.rank:, :])


@given(st.integers(1, 5).flatmap(lambda n: dense_matrices(rows=n, cols=n, max_degree=3)))
def test_pairwise_xgcd_elimination_gives_the_same_forms(M):
    """Square M of ≤ 5 rows: pairwise extended-gcd steps (what hermite uses when M(0) is
    nonsingular) and remainder passes give the same H, and for nonsingular M the same
    (unique) U; for singular M the same U once the kernel rows are reduced."""
    from uio_ring.ring import _dense as dn
    from uio_ring.ring._echelon import normalise, reduce_transform, row_echelon
    from uio_ring.ring.hermite import hermite_by_elimination

    n = M.rows
    a, u = dn.copy(M._r), dn.identity(n)
    pivots = row_echelon(a, u, n, n, xgcd_rows=n)
    normalise(a, u, pivots)
    reduce_transform(u, len(pivots))
    ref = hermite_by_elimination(M)
    assert PolyMatrix._new(a, n, n, M.var) == ref.H == hermite(M).H
    assert PolyMatrix._new(u, n, n, M.var) == ref.U == hermite(M).U
    assert PolyMatrix._new(u, n, n, M.var) @ M == ref.H


@heavy()
@given(st.data())
def test_high_degree_small_matrices_give_the_same_forms_on_every_path(data):
    """δ-degree ≥ CAP_MIN_DEGREE with fewer than 6 rows: the elimination is capped (its
    remainders can swell within one column) and the Toeplitz systems take over when it
    stops; H and the reduced U are unique, so every path gives the plain elimination's."""
    from uio_ring.ring.hermite import CAP_MIN_DEGREE, hermite_by_elimination

    m = data.draw(st.integers(2, 5))
    n = data.draw(st.integers(1, m))
    deg = CAP_MIN_DEGREE
    M = data.draw(st.one_of(
        dense_matrices(rows=m, cols=n, max_degree=deg, rational=False),
        rank_deficient_matrices(rows=m, cols=n),
    ))
    M = M + PolyMatrix([[f"d**{deg}" if (i, j) == (0, 0) else 0 for j in range(n)] for i in range(m)])
    h = check_hermite(M)
    ref = hermite_by_elimination(M)
    assert (h.H, h.U, h.pivots) == (ref.H, ref.U, ref.pivots)


def test_swelling_high_degree_elimination_stops_on_its_cap():
    """A seeded 5×4 of degree 16 with coefficients in [−9, 9]: the capped elimination stops
    (its first column's remainders pass the cap), hermite takes the Toeplitz systems, and
    the forms are the plain elimination's."""
    import random

    from uio_ring.ring.hermite import _hermite_by_small_elimination, hermite_by_elimination

    rng = random.Random(516)
    M = PolyMatrix.from_coefficients([[[rng.randint(-9, 9) for _ in range(4)] for _ in range(5)] for _ in range(17)])
    assert _hermite_by_small_elimination(M) is None
    h = check_hermite(M)
    ref = hermite_by_elimination(M)
    assert (h.H, h.U) == (ref.H, ref.U)


@given(matrices(max_rows=5, max_cols=5))
def test_pivot_ties_by_small_leading_coefficient_give_the_same_forms(M):
    """hermite's elimination breaks ties of least degree by the smallest leading
    coefficient (fewer denominators), the default by the least row degree: other steps,
    the same unique H and reduced U."""
    from uio_ring.ring import _dense as dn
    from uio_ring.ring._echelon import normalise, reduce_transform, row_echelon

    m, n = M.shape
    out = []
    for small in (False, True):
        a, u = dn.copy(M._r), dn.identity(m)
        pivots = row_echelon(a, u, m, n, small_lead_ties=small)
        normalise(a, u, pivots)
        reduce_transform(u, len(pivots))
        out.append((a, u, pivots))
    assert out[0] == out[1]
    assert PolyMatrix._new(out[1][1], m, m, M.var) @ M == PolyMatrix._new(out[1][0], m, n, M.var)


@given(st.data())
def test_wide_hermite_through_the_pivot_block_equals_the_elimination(data):
    """A wide M of full row rank: H = U·M with U from the Hermite form of the block of its
    pivot columns, read at a point.  The same H, U and pivots as the elimination, or None
    (rank-deficient rows, or a point where a column falls into the span of the earlier
    ones); hermite itself takes that path from 3 rows on, at rows·degree ≥ 16."""
    import importlib

    hm = importlib.import_module("uio_ring.ring.hermite")
    m = data.draw(st.integers(1, 4))
    n = data.draw(st.integers(m + 1, m + 3))
    M = data.draw(st.one_of(dense_matrices(rows=m, cols=n, max_degree=2),
                            rank_deficient_matrices(rows=m, cols=n)))
    ref = hm.hermite_by_elimination(M)
    got = hm._hermite_by_pivot_block(M)
    if got is not None:
        assert (got.H, got.U, got.rank, got.pivots) == (ref.H, ref.U, ref.rank, ref.pivots)
    else:  # only when no point has rank m, or the first that has gives other pivots
        full = [x for x in (0, 1, -1) if M.eval(x).rank() == m]
        assert ref.rank < m or not full or _column_profile(M.eval(full[0])) != ref.pivots


def _column_profile(E: PolyMatrix) -> tuple[int, ...]:
    """The columns of a constant matrix that raise the rank of the columns before them."""
    out: list[int] = []
    for j in range(E.cols):
        if E[:, 0 : j + 1].rank() > len(out):
            out.append(j)
    return tuple(out)


def test_wide_pivot_block_checks_the_pivots_it_read_at_a_point():
    import importlib

    hm = importlib.import_module("uio_ring.ring.hermite")
    # the first column vanishes at 0, 1 and −1: the points give J = [1], but M's pivot is 0
    M = PolyMatrix("[[d**3 - d, 1]]")
    assert hm._hermite_by_pivot_block(M) is None
    assert hermite(M).pivots == (0,)
    # rank 1 at every point for rows that are proportional
    assert hm._hermite_by_pivot_block(PolyMatrix("[[1, d, 0], [2, 2*d, 0]]")) is None


@heavy()
@given(st.integers(6, 7).flatmap(lambda m: dense_matrices(rows=m, cols=m + 1, max_degree=3, rational=False)))
def test_wide_hermite_at_the_pivot_block_sizes(M):
    import importlib

    hm = importlib.import_module("uio_ring.ring.hermite")
    r = hermite(M)
    ref = hm.hermite_by_elimination(M)
    assert (r.H, r.U, r.rank, r.pivots) == (ref.H, ref.U, ref.rank, ref.pivots)



@pytest.mark.parametrize("m, degree", [(3, 8), (5, 16)])
def test_wide_matrices_of_few_rows_and_high_degree_take_the_pivot_block(monkeypatch, m, degree):
    """m×(m+1) of degree 8 and 16 (rows·degree ≥ 16 from 3 rows: 5×6 of degree 16, 0.27 s
    for the elimination, 0.03 s here): the pivot-block path (spy), whose H and U (unique:
    full row rank) equal the elimination's."""
    import importlib
    import random

    hm = importlib.import_module("uio_ring.ring.hermite")
    rng = random.Random(m)
    M = PolyMatrix.from_coefficients(
        [[[rng.randint(-3, 3) for _ in range(m + 1)] for _ in range(m)] for _ in range(degree + 1)])
    calls = []
    real = hm._hermite_by_pivot_block
    monkeypatch.setattr(hm, "_hermite_by_pivot_block", lambda A: calls.append(A.shape) or real(A))
    r = hermite(M)
    assert calls == [(m, m + 1)]
    ref = hm.hermite_by_elimination(M)
    assert (r.H, r.U, r.rank, r.pivots) == (ref.H, ref.U, ref.rank, ref.pivots)

def test_a_lone_entry_column_goes_straight_to_the_elimination_with_transform(monkeypatch):
    """Tall 8×5, sparse, with a column whose only entry has degree 4: H ≠ [I; 0] is proved
    by that column, so hermite neither tries the capped elimination first nor the compressed
    minors; H and U equal the elimination's (both unique)."""
    import importlib

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    rows = [
        ["0", "0", "d**4 + 1", "0", "0"],
        ["0", "d**4 - d", "d**3", "d**2 + 3", "0"],
        ["0", "0", "0", "0", "d**4 - 2*d + 1"],
        ["0", "d**3 + 2", "d**2", "0", "0"],
        ["d**3 - 1", "d**4", "0", "0", "0"],
        ["2*d**4 + d", "0", "d**4 + d", "0", "0"],
        ["0", "d**4 + 1", "0", "3*d**2", "0"],
        ["d**4", "0", "d**2 - 1", "d", "0"],
    ]
    M = PolyMatrix(rows)
    calls = []
    real_small, real_minors = hermite_module._hermite_by_small_elimination, hermite_module.coprime_maximal_minors
    monkeypatch.setattr(hermite_module, "_hermite_by_small_elimination",
                        lambda *a, **k: calls.append(("small", k.get("full", False))) or real_small(*a, **k))
    monkeypatch.setattr(hermite_module, "coprime_maximal_minors",
                        lambda *a, **k: calls.append(("minors",)) or real_minors(*a, **k))
    h = check_hermite(M)
    assert calls == [("small", True)]
    ref = hermite_module.hermite_by_elimination(M)
    assert (h.H, h.U) == (ref.H, ref.U)
    assert h.rank == 5 and h.H[4, 4].degree() > 0


def test_tall_matrix_of_high_degree_takes_its_weak_popov_form_for_h(monkeypatch):
    """M = W·[R; 0] with R 3×3 of degree ≤ 2 (det of degree 4) and W unimodular of degree
    ~50, the first elimination stopped as if it swelled: H(M) = H(R) (the same row module)
    comes from M's weak Popov form, and U from its transform — the Euclidean elimination
    of a 4×3 of degree 72 from a Smith core took 260 s there, the weak Popov form 8 ms.
    U·M = H with U unimodular, and the Popov kernel row."""
    import importlib

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    import random

    rng = random.Random(3)

    def poly(degree: int) -> str:
        return " + ".join(f"({rng.randint(-3, 3)})*d**{k}" for k in range(degree + 1))

    R = PolyMatrix([["d**2 + 1", 0, 0], ["d", "d - 1", 0], [1, 2, "d**2 - 3"]])
    W = PolyMatrix.identity(4)
    for i, j in [(2, 0), (3, 1), (3, 2), (2, 3), (0, 2), (1, 3)]:
        E = PolyMatrix([[poly(12) if (a, b) == (i, j) else int(a == b) for b in range(4)] for a in range(4)])
        W = E @ W
    M = W @ PolyMatrix([[R[i, j] for j in range(3)] for i in range(3)] + [[0, 0, 0]])
    assert is_unimodular(W) and max(M[i, j].degree() for i in range(4) for j in range(3)) >= 45
    calls = []
    real = hermite_module._hermite_by_weak_popov
    monkeypatch.setattr(hermite_module, "_hermite_by_weak_popov", lambda A: calls.append(A.shape) or real(A))
    monkeypatch.setattr(hermite_module, "ELIMINATION_BITS", -(10**6))  # as if the elimination swelled
    h = check_hermite(M)
    assert calls == [(4, 3)]
    assert h.H[:3, :] == hermite(R).H and h.H[3, :].is_zero()
    assert_popov(h.U[3:, :])


@given(st.data())
def test_weak_popov_transform_gives_the_normalised_form_of_small_matrices(data):
    """2×1 … 5×5, dense or rank-deficient: H, U, rank and pivots through the weak Popov
    transform equal the elimination's (H and the normalised U are unique)."""
    import importlib

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    m = data.draw(st.integers(2, 5))
    n = data.draw(st.integers(1, m))
    M = data.draw(st.one_of(dense_matrices(rows=m, cols=n, max_degree=3), rank_deficient_matrices(rows=m, cols=n)
                            if min(m, n) >= 2 else dense_matrices(rows=m, cols=n, max_degree=3)))
    h = hermite_module._hermite_by_weak_popov(M)
    ref = hermite_module.hermite_by_elimination(M)
    assert (h.H, h.U, h.pivots, h.rank) == (ref.H, ref.U, ref.pivots, ref.rank)


@heavy()
@given(st.data())
def test_weak_popov_transform_gives_the_normalised_form(data):
    """Rank-deficient (or zero) 6×6 … 7×7: U from M's weak Popov transform and the
    Hermite form of its nonzero rows.  H and the normalised U are unique, so they equal
    the elimination's."""
    import importlib

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    m = data.draw(st.integers(6, 7))
    n = data.draw(st.integers(6, 7))
    M = data.draw(rank_deficient_matrices(rows=m, cols=n))
    h = hermite_module._hermite_by_weak_popov(M)
    ref = hermite_module.hermite_by_elimination(M)
    assert (h.H, h.U, h.pivots, h.rank) == (ref.H, ref.U, ref.pivots, ref.rank)
    assert h.U @ M == h.H
    assert_unimodular(h.U, m)
    assert_popov(h.U[h.rank:, :])


def test_singular_matrix_of_high_degree_takes_the_weak_popov_transform(monkeypatch):
    """A singular 6×6 of degree 40 (one row the sum of two others): H has pivots of
    positive degree and M a degree above the elimination's bound, so U comes from M's
    weak Popov transform (spy; 0.3 s, where the earlier route — the Euclidean elimination
    of the five independent rows, whose cofactors swell with the degree, then the Toeplitz
    kernel and solve — took 24 s).  H is that of those rows, and the kernel row is the
    Popov one."""
    import importlib
    import random

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    rng = random.Random(7)
    A = PolyMatrix.from_coefficients([[[rng.randint(-3, 3) for _ in range(6)] for _ in range(5)] for _ in range(41)])
    M = PolyMatrix.vstack(A, A[0, :] + A[1, :])
    calls = []
    real = hermite_module._hermite_by_weak_popov
    monkeypatch.setattr(hermite_module, "_hermite_by_weak_popov", lambda *a: calls.append(1) or real(*a))
    h = hermite(M)
    assert calls == [1]
    assert h.U @ M == h.H and is_unimodular(h.U) and is_hermite(h.H)  # U of degree 160: no sympy
    assert h.rank == 5 and h.U[5, :] == PolyMatrix([[-1, -1, 0, 0, 0, 1]])  # Popov: monic at its last entry
    assert h.H[:5, :] == hermite(A).H


@given(st.data())
def test_unimodularity_from_the_hermite_identity_agrees_with_det(data):
    """``unimodular_given_hermite`` (det U from det T, a minor of M and U's kernel block)
    against det U itself: on hermite's own U (unimodular), and on U with a kernel row
    multiplied by δ + c or replaced by another kernel row (U·M = H still holds; det U
    gains the factor or vanishes)."""
    from uio_ring.ring._predicates import is_unimodular_raw, unimodular_given_hermite

    M = data.draw(st.one_of(matrices(1, 5, 1, 5), rank_deficient_matrices(min_rows=2, max_rows=5, max_cols=5)))
    h = hermite(M)
    m, n = M.shape
    U = h.U
    assert unimodular_given_hermite(U._r, M._r, h.H._r, m, n)
    if h.rank < m:
        k = data.draw(st.integers(h.rank, m - 1))
        rows = [U[i, :] for i in range(m)]
        if data.draw(st.booleans()) or h.rank == m - 1:
            rows[k] = rows[k] * P(f"d + {data.draw(st.integers(-2, 2))}")
        else:
            rows[k] = rows[h.rank + (k == h.rank)]
        V = PolyMatrix.vstack(*rows)
        assert V @ M == h.H
        assert unimodular_given_hermite(V._r, M._r, h.H._r, m, n) is False
        assert is_unimodular_raw(V._r, m, m) is False
        assert not dataclasses.replace(h, U=V).verify(M).ok


def test_the_certificate_of_a_singular_hermite_form_needs_no_det_of_u(monkeypatch):
    """verify() proves U unimodular without det U: a spy on det_raw sees only M's r×r
    minor and U's 1×1 kernel block (a 6×6 of rank 5)."""
    import importlib

    pred = importlib.import_module("uio_ring.ring._predicates")
    A = PolyMatrix("[[d, 1, 0, 2, d**2, 1], [1, d, 1, 0, 0, 3], [0, 1, d, 1, 1, 0], "
                   "[2, 0, 1, d, 0, 1], [d, d, 0, 1, d + 1, 0]]")
    M = PolyMatrix.vstack(A, A[0, :] * P("d") + A[3, :])
    h = hermite(M)
    sizes = []
    real = pred.det_raw
    monkeypatch.setattr(pred, "det_raw", lambda a, n: sizes.append(n) or real(a, n))
    assert h.verify(M).ok
    assert sorted(sizes) == [1, 5]


@st.composite
def permuted_echelon_matrices(draw, max_rows: int = 6, max_cols: int = 6):
    """Row permutations of row echelon forms: nonzero rows starting in distinct columns
    (a pivot of any degree, anything right of it), zero rows among them."""
    N = draw(dense_matrices(min_rows=1, max_rows=max_rows, min_cols=1, max_cols=max_cols))
    m, n = N.shape
    starts = sorted(draw(st.sets(st.integers(0, n - 1), max_size=min(m, n))))
    rows = []
    for k, c in enumerate(starts):
        row = [0] * c + [N[k, j] for j in range(c, n)]
        if not row[c]:
            row[c] = P("d + 1") if k % 2 else 1
        rows.append(row)
    rows += [[0] * n for _ in range(m - len(starts))]
    rows = draw(st.permutations(rows))
    return PolyMatrix([[str(x) for x in row] for row in rows])


@given(permuted_echelon_matrices())
def test_permuted_echelon_input_is_normalised_without_elimination(M):
    """A matrix whose rows, permuted, are an echelon form (triangular, and a cascade's
    block rows) gets the H and U of the elimination — both are unique, the kernel rows
    the unit rows of its zero rows — from the permutation and the normalisation alone:
    no echelon pass and no other path runs (spies)."""
    import importlib

    from uio_ring.ring.hermite import hermite_by_elimination

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    calls = []
    real = hermite_module.row_echelon
    hermite_module.row_echelon = lambda *args, **kw: calls.append(1) or real(*args, **kw)
    try:
        got = hermite(M)
    finally:
        hermite_module.row_echelon = real
    ref = hermite_by_elimination(M)
    assert calls == []
    assert got.H == ref.H and got.U == ref.U and got.pivots == ref.pivots and got.rank == ref.rank
    check_hermite(M)


def test_triangular_pencil_with_dense_upper_part():
    """δI − A for an upper triangular A with repeated eigenvalues: H keeps the diagonal
    (monic) with entries above reduced to constants, and U is unique (M nonsingular)."""
    n = 6
    rows = [[("d - 1" if i % 2 else "d") if i == j else (f"{(i + 2 * j) % 5 - 2}" if j > i else "0")
             for j in range(n)] for i in range(n)]
    M = PolyMatrix(rows)
    h = check_hermite(M)
    assert [h.H[i, i] for i in range(n)] == [M[i, i] for i in range(n)]
    assert all(h.H[i, j].degree() <= 0 for i in range(n) for j in range(i + 1, n))
    from uio_ring.ring.hermite import hermite_by_elimination

    assert h.U == hermite_by_elimination(M).U


@pytest.mark.parametrize("n, degree", [(1, 40), (3, 48), (5, 24)])
def test_two_rows_of_high_degree_take_one_uncapped_extended_gcd(monkeypatch, n, degree):
    """Two rows: one extended gcd per column (cofactors of the size they have to be), no
    cap and no other path (a spy sees one elimination, uncapped), and the result is that
    of the plain elimination."""
    import importlib
    import random

    from uio_ring.ring.hermite import hermite_by_elimination

    hermite_module = importlib.import_module("uio_ring.ring.hermite")
    rng = random.Random(n)
    M = PolyMatrix([[" + ".join(f"({rng.randint(-3, 3)})*d**{k}" for k in range(degree + 1)) for _ in range(n)]
                    for _ in range(2)])
    calls = []
    real = hermite_module._hermite_by_small_elimination

    def spy(A, **kw):
        got = real(A, **kw)
        calls.append((kw.get("capped"), got is not None))
        return got

    monkeypatch.setattr(hermite_module, "_hermite_by_small_elimination", spy)
    got = check_hermite(M)
    assert calls == [(False, True)]
    ref = hermite_by_elimination(M)
    assert got.H == ref.H and got.U == ref.U
