"""Unimodularity predicates and one-sided inverses.

Left inverses of a tall matrix are not unique (X + Y K for any Y, K the left
kernel); tests check X M = I and degree bounds that the mathematics guarantees
for a left inverse reduced modulo a Popov basis of the kernel (see
``test_left_inverse_degree_bound``), never the entries.
"""

from __future__ import annotations

import random

import pytest
from hypothesis import event, example, given
from hypothesis import strategies as st

from uio_ring import (
    NotUnimodularError,
    PolyMatrix,
    UioRingError,
    invariant_factors,
    is_left_unimodular,
    is_right_unimodular,
    is_unimodular,
    left_inverse,
    left_kernel,
    right_inverse,
)

from .strategies import (
    assert_unimodular,
    column_leading_matrix_rank,
    dense_matrices,
    heavy,
    matrices,
    reference_det,
    square_matrices,
    unimodular_matrices,
)


@given(st.integers(0, 6).flatmap(lambda n: unimodular_matrices(n, max_degree=2)))
def test_inverse_of_unimodular(U):
    n = U.rows
    assert_unimodular(U)
    assert is_unimodular(U) and is_left_unimodular(U) and is_right_unimodular(U)
    X = left_inverse(U)
    assert X @ U == PolyMatrix.identity(n) == U @ X
    assert right_inverse(U) == X  # the two-sided inverse is unique
    # U⁻¹ = adj(U)/det U with det U constant: deg U⁻¹ <= (n − 1) deg U
    assert X.degree() <= max(0, (n - 1) * U.degree())


@given(square_matrices(max_n=5))
def test_is_unimodular_is_constant_nonzero_det(M):
    det = reference_det(M)
    assert is_unimodular(M) == (det.degree() == 0 and not det.is_zero)


@given(matrices())
def test_one_sided_unimodularity_definition(M):
    """left unimodular ⇔ rank = columns and all invariant factors are 1."""
    fs = invariant_factors(M)
    left = len(fs) == M.cols and all(f == 1 for f in fs)
    right = len(fs) == M.rows and all(f == 1 for f in fs)
    assert is_left_unimodular(M) == left
    assert is_right_unimodular(M) == right
    if left:
        X = left_inverse(M)
        assert X.shape == (M.cols, M.rows)
        assert X @ M == PolyMatrix.identity(M.cols)
    else:
        with pytest.raises(NotUnimodularError):
            left_inverse(M)
    if right:
        Y = right_inverse(M)
        assert Y.shape == (M.cols, M.rows)
        assert M @ Y == PolyMatrix.identity(M.rows)
    else:
        with pytest.raises(NotUnimodularError):
            right_inverse(M)


@st.composite
def tall_left_unimodular(draw):
    """First m columns of a random n×n unimodular matrix (n > m): left unimodular."""
    n = draw(st.integers(2, 6))
    m = draw(st.integers(1, n - 1))
    U = draw(unimodular_matrices(n, max_degree=2))
    return U[:, :m]


@given(tall_left_unimodular())
def test_left_inverse_of_tall(M):
    assert is_left_unimodular(M) and not is_right_unimodular(M)
    X = left_inverse(M)
    assert X @ M == PolyMatrix.identity(M.cols)
    Y = right_inverse(M.T)
    assert M.T @ Y == PolyMatrix.identity(M.cols)


@given(st.data())
def test_left_inverse_degree_bound(data):
    """Degree bound for a left inverse reduced modulo the Popov kernel basis.

    Let M be n×m left unimodular and *column reduced* (column degrees c_j, column
    leading coefficient matrix M_hc of rank m), and K the Popov basis of its left kernel
    (row degrees ν_k).  If a row x of X has degree t >= 1, comparing the coefficients of
    δ^(t + c_j) in x M = e_i gives x_t M_hc = 0; comparing those of δ^(ν_k + c_j) in
    K M = 0 gives K_hc M_hc = 0, so rowspan K_hc = left kernel of M_hc ∋ x_t.  A row
    reduced modulo a Popov K has deg x_p < ν_k at every pivot column p of K; when
    t >= max ν this makes x_t vanish at all pivot columns, and no nonzero combination of
    K_hc's rows does.  Hence

        deg X <= max(0, max ν − 1) <= max(0, Σ c_j − 1) <= max(0, m·deg M − 1)

    (Σ ν = degree of the maximal minors = Σ c_j for column-reduced, left-prime M).
    """
    n = data.draw(st.integers(2, 6))
    m = data.draw(st.integers(1, n - 1))
    M = data.draw(dense_matrices(rows=n, cols=m, max_degree=2, rational=False))
    cdeg = [max(e.degree() for e in col) for col in M.T.tolist()]
    colreduced = min(cdeg) >= 0 and column_leading_matrix_rank(M) == m
    if not (colreduced and is_left_unimodular(M)):
        event("bound not applicable (not column reduced or not left unimodular)")
        return
    event("bound applies")
    X = left_inverse(M)
    assert X @ M == PolyMatrix.identity(m)
    K = left_kernel(M)
    nu = [max(e.degree() for e in row) for row in K.tolist()]
    assert sum(nu) == sum(cdeg)
    assert X.degree() <= max(0, max(nu, default=0) - 1)
    assert X.degree() <= max(0, sum(cdeg) - 1)
    assert X.degree() <= max(0, m * M.degree() - 1)


@pytest.mark.parametrize(
    "text, pattern",
    [
        ("[[d], [d**2]]", r"\bd\b"),  # invariant factor d: loses rank at d = 0
        ("[[d + 1], [d**2 - 1]]", r"d \+ 1"),
        ("[[1, 1], [1, 1]]", r"rank 1"),
        ("[[1, d, 0]]", r"rank|column"),  # wide: rank 1 < 3 columns
        ("[[d, 0], [0, 1]]", r"\bd\b"),
    ],
)
def test_not_left_unimodular_names_the_obstruction(text, pattern):
    M = PolyMatrix(text)
    assert not is_left_unimodular(M)
    with pytest.raises(NotUnimodularError, match=pattern) as info:
        left_inverse(M)
    assert isinstance(info.value, ArithmeticError) and isinstance(info.value, UioRingError)


def test_right_inverse_errors():
    with pytest.raises(NotUnimodularError, match=r"\bd\b"):
        right_inverse(PolyMatrix("[[d, d**2]]"))
    with pytest.raises(NotUnimodularError):
        right_inverse(PolyMatrix("[[1], [d]]"))


def test_documented_examples():
    M = PolyMatrix("[[1, d], [0, 1], [d, 0]]")
    X = left_inverse(M)
    assert X @ M == PolyMatrix.identity(2)
    W = PolyMatrix("[[1, d, 0], [0, 1, d]]")
    assert W @ right_inverse(W) == PolyMatrix.identity(2)


@pytest.mark.parametrize("shape", [(0, 0), (3, 0)])
def test_empty_left_inverse(shape):
    M = PolyMatrix.zeros(*shape)
    assert is_left_unimodular(M)
    X = left_inverse(M)
    assert X.shape == (0, shape[0])
    assert X @ M == PolyMatrix.identity(0)


def test_empty_right_inverse():
    M = PolyMatrix.zeros(0, 3)
    assert is_right_unimodular(M) and not is_left_unimodular(M)
    assert right_inverse(M).shape == (3, 0)
    with pytest.raises(NotUnimodularError):
        left_inverse(M)


@pytest.mark.parametrize("shape", [(2, 2), (3, 2), (2, 3)])
def test_zero_matrix_is_not_one_sided_unimodular(shape):
    Z = PolyMatrix.zeros(*shape)
    assert not is_left_unimodular(Z) and not is_right_unimodular(Z) and not is_unimodular(Z)
    with pytest.raises(NotUnimodularError):
        left_inverse(Z)
    with pytest.raises(NotUnimodularError):
        right_inverse(Z)


def test_rank_deficient_square():
    M = PolyMatrix("[[1, d], [d, d**2]]")
    assert not is_unimodular(M)
    with pytest.raises(NotUnimodularError, match="rank"):
        left_inverse(M)


def test_paper_001_observability_matrix_left_inverse():
    """§5 Step 3: Ō_3 (6×4) is left unimodular; the printed left inverse is one choice
    (docs/errata.md Z6: choice-dependent), so only X Ō_3 = I is checked."""
    O3 = PolyMatrix("[[0, 1, 0, 0], [-δ, 0, 1, 1], [-1, δ, 0, 0], [-δ, 0, 1, 1], "
                    "[-δ, 1 + δ**2, -1, 0], [-δ, 0, 1, 1]]")
    assert is_left_unimodular(O3)
    X = left_inverse(O3)
    assert X @ O3 == PolyMatrix.identity(4)
    printed = PolyMatrix("[[δ, 0, -1, 0, 0, 0], [1, 0, 0, 0, 0, 0], [1, 0, δ, 0, -1, 0], "
                         "[δ**2 - 1, 1, -2*δ, 0, 1, 0]]")
    assert printed @ O3 == PolyMatrix.identity(4)  # the paper's choice is valid too


@heavy()
@given(st.data())
def test_left_inverse_of_columns_of_a_unimodular_matrix_is_the_reduced_hermite_transform(data):
    """M = first n columns of a unimodular matrix: the left inverse (from the capped
    elimination here) is the top of the Hermite transform reduced modulo the Popov
    kernel, which is unique — the same as from elimination with the Toeplitz kernel."""
    from uio_ring.ring.hermite import hermite_by_elimination

    m = data.draw(st.integers(3, 9))
    n = data.draw(st.integers(1, m - 1))
    M = data.draw(unimodular_matrices(m, steps=2 * m))[:, :n]
    X = left_inverse(M)
    assert X @ M == PolyMatrix.identity(n)
    assert X == hermite_by_elimination(M).U[:n, :]


def test_left_inverse_of_a_tall_matrix_that_loses_rank_names_its_invariant_factors():
    """A tall 10×6 of full column rank with every other row times δ (its maximal minors
    share the factor δ): left_inverse refuses, naming the non-constant invariant
    factors, before any elimination with transform."""
    import random

    from uio_ring import invariant_factors
    from uio_ring.ring.errors import NotUnimodularError

    rng = random.Random(7)
    rows = [[f"{rng.randint(-3, 3)}*d**2 + {rng.randint(-3, 3)}*d + {rng.randint(-3, 3)}" for _ in range(6)]
            for _ in range(10)]
    M = PolyMatrix([[f"d*({e})" if i % 2 == 0 else e for e in row] for i, row in enumerate(rows)])
    bad = [f for f in invariant_factors(M) if f.degree() > 0]
    assert bad and M.rank() == 6
    with pytest.raises(NotUnimodularError, match="not left unimodular: its invariant factor"):
        left_inverse(M)


@given(st.one_of(
    st.integers(1, 5).flatmap(lambda n: unimodular_matrices(n + 2, max_degree=2).map(lambda U: U[:, 0:n])),
    matrices(min_rows=1, max_rows=6, min_cols=1, max_cols=4),
))
def test_left_unimodular_proof_is_sound(M):
    """A proof by two coprime compressed minors (modulo a prime, or exactly when they are
    cheap) never contradicts the elimination's decision."""
    from uio_ring.ring._predicates import left_unimodular_proved

    m, n = M.shape
    if m < n:
        return
    proved = left_unimodular_proved(M._r, m, n)
    event(f"proved={proved}")
    if proved:
        assert is_left_unimodular(M)


@given(st.integers(1, 4).flatmap(lambda n: st.one_of(unimodular_matrices(n, max_degree=2),
                                                     matrices(min_rows=n, max_rows=n, min_cols=n, max_cols=n))))
def test_square_minors_decide_by_the_determinant(M):
    """Square M: the compressed minors are det M times constants, so the proof is exactly
    'det M is a nonzero constant'; det modulo a prime of positive degree proves the opposite."""
    from uio_ring.ring._predicates import coprime_maximal_minors, det_not_constant_mod_p

    n = M.rows
    unimodular = is_unimodular(M)
    assert coprime_maximal_minors(M._r, n, n) == unimodular
    assert not coprime_maximal_minors(M._r, n, n, exact=False)
    if det_not_constant_mod_p(M._r, n):
        assert M.det().degree() > 0 and not unimodular


@given(st.integers(1, 4).flatmap(lambda n: dense_matrices(rows=n + 2, cols=n, max_degree=2)))
def test_top_minor_proof_is_sound(M):
    """First n rows made upper triangular (as C̄ on top of Ō): their exact minor and one
    compressed minor, coprime modulo a prime, prove M left unimodular — never wrongly."""
    from uio_ring.ring import _dense as dn
    from uio_ring.ring._predicates import _coprime_with_the_top_minor

    n = M.cols
    a = dn.copy(M._r)
    for i in range(n):
        for j in range(i):
            a[i][j] = a[i][j] * 0
    T = PolyMatrix._new(a, n + 2, n, "d")
    Q = PolyMatrix([[(3 * i + 5 * k) % 7 - 3 for k in range(n + 2)] for i in range(n)])
    compressed = (Q @ T)._r
    proved = _coprime_with_the_top_minor(a, compressed, n)
    event(f"proved={proved}")
    if proved:
        assert is_left_unimodular(T)


def test_top_minor_proves_an_observability_matrix_that_is_not_column_reduced():
    """Ō = [C̄; C̄Ā] with C̄ = [[d, 1], [0, d]] (Hermite, det δ²) and C̄Ā = [[1, 0], [δ, δ + 1]]:
    left unimodular (rows 1 and 3 give −1)."""
    from uio_ring.ring._predicates import _coprime_with_the_top_minor, coprime_maximal_minors

    O = PolyMatrix("[[d, 1], [0, d], [1, 0], [d, d + 1]]")
    assert is_left_unimodular(O)
    compressed = (PolyMatrix("[[1, 2, -1, 3], [2, -3, 1, 1]]") @ O)._r
    assert _coprime_with_the_top_minor(O._r, compressed, 2)
    assert coprime_maximal_minors(O._r, 4, 2)
    N = PolyMatrix("[[d, 1], [0, d], [d, 0], [d, d]]")  # every 2×2 minor is a multiple of δ
    assert not _coprime_with_the_top_minor(N._r, (PolyMatrix("[[1, 2, -1, 3], [2, -3, 1, 1]]") @ N)._r, 2)


@pytest.mark.parametrize("text", ["[[1, d**2], [0, 1], [d, d**3 + 1]]", "[[d + 1, d], [d, d - 1], [1, 1]]"])
def test_left_unimodular_proof_completed_exactly_when_not_column_reduced(text):
    """Left unimodular but not column reduced: the compressed minor misses its degree bound,
    so the modular proof says nothing; the exact minors, cheap on so small a matrix, prove it."""
    from uio_ring.ring import _predicates
    from uio_ring.ring._predicates import coprime_maximal_minors, left_unimodular_proved

    M = PolyMatrix(text)
    assert is_left_unimodular(M)
    assert not coprime_maximal_minors(M._r, 3, 2, exact=False)
    assert left_unimodular_proved(M._r, 3, 2)
    budget = _predicates.EXACT_MINORS_BUDGET
    try:  # over the budget of the exact minors: the modular proof alone, which says nothing
        _predicates.EXACT_MINORS_BUDGET = 0
        assert not left_unimodular_proved(M._r, 3, 2)
        # a column-reduced one is still proved modulo p, unless only the cheap proof is asked
        R = PolyMatrix("[[1, 0], [d, 1], [0, d]]")
        assert left_unimodular_proved(R._r, 3, 2)
        assert not left_unimodular_proved(R._r, 3, 2, cheap_only=True)
    finally:
        _predicates.EXACT_MINORS_BUDGET = budget


def test_one_exact_compressed_minor_is_enough_when_its_degree_survives_mod_p(monkeypatch):
    """Not column reduced (the modular proof says nothing) and a top minor of zero: one exact
    compressed minor, whose degree survives modulo p, and the other one reduced mod p prove
    it; the second exact determinant is never computed."""
    from uio_ring.ring import _predicates
    from uio_ring.ring._predicates import coprime_maximal_minors

    M = PolyMatrix("[[d + 1, d], [2*d + 2, 2*d], [1, 1]]")  # rows 1 and 3: minor 1
    assert is_left_unimodular(M)
    assert not coprime_maximal_minors(M._r, 3, 2, exact=False)
    calls = []
    real = _predicates.det_raw
    monkeypatch.setattr(_predicates, "det_raw", lambda a, n: calls.append(n) or real(a, n))
    assert coprime_maximal_minors(M._r, 3, 2)
    assert calls == [2]


@given(st.integers(1, 3).flatmap(lambda n: st.one_of(
    dense_matrices(rows=n + 1, cols=n, max_degree=2),
    unimodular_matrices(n + 1, max_degree=2).map(lambda U: U[:, 0:n]))))
@example(PolyMatrix("[[-1], [1/3]]"))  # the first fixed compression (−3, −9) maps it to 0
def test_compressed_minor_proofs_are_sound_without_the_top_minor(M):
    from uio_ring.ring import _predicates
    from uio_ring.ring._predicates import coprime_maximal_minors

    top = _predicates._coprime_with_the_top_minor
    try:
        _predicates._coprime_with_the_top_minor = lambda *args: False
        proved = coprime_maximal_minors(M._r, M.rows, M.cols)
    finally:
        _predicates._coprime_with_the_top_minor = top
    event(f"proved={proved}")
    assert proved == is_left_unimodular(M)


@given(st.integers(1, 5).flatmap(lambda n: dense_matrices(rows=n, cols=n, max_degree=2)), st.data())
def test_det_below_echelon_equals_the_determinant(M, data):
    """First n − 1 rows put in echelon form (entries left of a chosen pivot zeroed): the
    Schur-complement determinant equals det M; rows that are not in echelon form give None."""
    from uio_ring.ring import _dense as dn
    from uio_ring.ring._predicates import det_below_echelon

    n = M.rows
    a = dn.copy(M._r)
    pivots = sorted(data.draw(st.lists(st.integers(0, n - 1), min_size=n - 1, max_size=n - 1, unique=True)))
    for i, j in enumerate(pivots):
        for c in range(j):
            a[i][c] = a[i][c] * 0
    E = PolyMatrix._new(a, n, n, "d")
    got = det_below_echelon(a, n)
    if all(not a[i][pivots[i]].is_zero() for i in range(n - 1)):
        assert got is not None and PolyMatrix._new([[got]], 1, 1, "d")[0, 0] == E.det()
    elif got is not None:  # a zero pivot: the rows may still be in echelon form elsewhere
        assert PolyMatrix._new([[got]], 1, 1, "d")[0, 0] == E.det()


def test_det_below_echelon_refuses_rows_out_of_echelon_form():
    from uio_ring.ring._predicates import det_below_echelon

    M = PolyMatrix("[[0, 1, d], [1, 0, 0], [d, 1, 1]]")
    assert det_below_echelon(M._r, 3) is None
    assert det_below_echelon(PolyMatrix("[[0, 0, 0], [1, 0, 0], [d, 1, 1]]")._r, 3) is None


@given(st.integers(1, 4).flatmap(lambda n: dense_matrices(rows=n + 2, cols=n, max_degree=2)), st.data())
def test_a_lone_entry_column_proves_m_is_not_left_unimodular(M, data):
    """A column made zero but for one entry of positive degree: that entry divides every
    maximal minor, so M is never left unimodular, and the predicate says so; with a
    constant lone entry it says nothing (it must not claim anything then)."""
    from uio_ring.ring import _backend as bk
    from uio_ring.ring import _dense as dn
    from uio_ring.ring._predicates import coprime_maximal_minors, lone_entry_column

    m, n = M.shape
    a = dn.copy(M._r)
    j, i = data.draw(st.integers(0, n - 1)), data.draw(st.integers(0, m - 1))
    lone = data.draw(st.sampled_from(["d", "d**2 - 1", "3", ""]))
    for k in range(m):
        a[k][j] = bk.ZERO
    if lone:
        a[i][j] = PolyMatrix([[lone]])._r[0][0]
    T = PolyMatrix._new(a, m, n, "d")
    claimed = lone_entry_column(a, m, n)
    event(f"lone={lone!r} claimed={claimed}")
    if lone in ("d", "d**2 - 1", ""):
        assert claimed
    if claimed:
        assert not is_left_unimodular(T)
        assert not coprime_maximal_minors(a, m, n)


@pytest.mark.parametrize("M, R", [
    # every maximal minor a multiple of δ − 2; the first compressed minor at its degree bound
    ("[[d, 1], [d, 1 + d], [d**2, d]] @ [[1, 0], [0, d - 2]]", "[[1, 0], [d, 1], [0, d]]"),
    # every maximal minor a multiple of δ + 1; a compressed minor of degree 4 below its
    # bound 6, so the modular test proves nothing: the gcd mod p is taken as evidence
    ("[[d + 1, 0], [0, d + 1], [d**3, d**3 + d + 1]]", "[[1, 0], [0, 1], [d**3, d**3 + 1]]"),
])
def test_routing_answer_skips_the_exact_minors_on_modular_evidence(monkeypatch, M, R):
    """M (3×2, no lone column) is not left unimodular.  The routing answer stops at the
    modular gcd; the full answer computes exact minors to be sure; both say False, and a
    left unimodular R of the same shape is still proved with routing."""
    from uio_ring.ring import _predicates
    from uio_ring.ring._predicates import coprime_maximal_minors, lone_entry_column

    left, _, right = M.partition(" @ ")
    M = PolyMatrix(left) @ PolyMatrix(right) if right else PolyMatrix(left)
    assert not lone_entry_column(M._r, 3, 2)
    exact_calls = []
    real = _predicates.det_raw
    monkeypatch.setattr(_predicates, "det_raw", lambda *a: exact_calls.append(1) or real(*a))
    assert not coprime_maximal_minors(M._r, 3, 2, routing=True)
    assert exact_calls == []
    assert not coprime_maximal_minors(M._r, 3, 2)
    assert exact_calls
    R = PolyMatrix(R)
    assert coprime_maximal_minors(R._r, 3, 2, routing=True) and is_left_unimodular(R)


@given(st.integers(8, 48), st.integers(8, 48), st.integers(0, 10**6))
def test_left_inverse_of_two_rows_is_the_reduced_bezout_row(da, db, seed):
    """M = [a; b] with coprime a, b of high degree (the elimination runs without cap on two
    rows): X·M = 1 and deg X₀ < deg b, deg X₁ < deg a — the unique Bézout row of least
    degree (any other is X + q·(−b, a))."""
    rng = random.Random(seed)

    def entry(d: int) -> str:
        return " + ".join(f"({rng.randint(-3, 3) if e < d else rng.choice([-2, -1, 1, 2])})*d**{e}" for e in range(d + 1))

    M = PolyMatrix([[entry(da)], [entry(db)]])
    a, b = M[0, 0], M[1, 0]
    if a.gcd(b).degree() > 0:
        with pytest.raises(NotUnimodularError):
            left_inverse(M)
        return
    X = left_inverse(M)
    assert X @ M == PolyMatrix.identity(1)
    assert X[0, 0].degree() < b.degree() and X[0, 1].degree() < a.degree()
