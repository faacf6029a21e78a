"""Output shaping (uio_ring.analysis.output_shaping): the paper's Examples 1–4 through
their unique quantities (traces, iteration counts, filter orders, extended indices),
random-coordinate invariance, the cap, and the polynomial inverse P(s)."""

from __future__ import annotations

import random

import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from analysis import paper004 as ex
from uio_ring import PolyMatrix, ShapingResult, admissibility, shape
from uio_ring.analysis import extend, extended_set, observability_indices_of
from uio_ring.errors import DimensionError, NotObservableError

s = sympy.Symbol("s")


def test_example1_trace_and_filter():
    r = shape(ex.A, ex.C, [ex.W1_EXAMPLE1])
    assert isinstance(r, ShapingResult) and r.found
    assert r.ell_sequence == (1, 0, 0, 0, 0, 0, 0)
    assert r.m_sequence == (1, 1, 2, 3, 4, 5, 6)
    assert r.iterations == 8 and r.order == 1
    assert observability_indices_of(r.A_e, r.C_e) == (3, 3)
    assert admissibility(r.A_e, r.C_e, r.W_e).holds
    cert = r.certificate()
    assert cert.ok, str(cert)
    # the tie-break of (23): G(s) = [[0, 1/s], [-1, 1]], P(s) = G⁻¹ = [[s, -1], [s, 0]]
    assert r.G_sympy() == sympy.Matrix([[0, 1 / s], [-1, 1]])
    assert r.P == PolyMatrix([["s", -1], ["s", 0]], var="s")
    assert "order 1" in r.message and "iteration 8" in r.message


def test_example1_first_extend_is_23():
    st_ = extend(ex.A, ex.C, [ex.W1_EXAMPLE1], 1)
    assert st_.ell == 1 and (st_.r, st_.r_tilde) == (0, 2)
    f = st_.filter
    assert f.A_z == PolyMatrix([[0]]) and f.B_z == PolyMatrix([[0, 1]])
    assert f.C_z == PolyMatrix([[1], [0]]) and f.D_z == PolyMatrix([[0, 0], [-1, 1]])
    assert st_.E_sigma.cols == 4  # ρ = 4


def test_example2_trace_filter_and_16():
    r = shape(ex.A, ex.C, [ex.W1_EXAMPLE2])
    assert r.found and r.order == 2 and r.iterations == 11
    assert r.ell_sequence == (1, 0, 1, 0, 0, 0, 0, 0, 0, 0)
    assert r.trace[-1].m == 7 and r.trace[-1].n_e == 7  # terminates with m = 8 = n_e + 1
    assert r.A_e == PolyMatrix(ex.A_E16) and r.C_e == PolyMatrix(ex.C_E16) and r.W_e == (PolyMatrix(ex.W_E16),)
    assert observability_indices_of(r.A_e, r.C_e) == (4, 3)
    assert r.G_sympy() == sympy.diag(1 / s**2, 1)
    assert r.P == PolyMatrix.diag("s**2", 1, var="s")
    assert r.certificate().ok
    # both extend steps return the paper's (24)
    for step in r.steps:
        assert step.filter.B_z == PolyMatrix([[1, 0]]) and step.filter.D_z == PolyMatrix([[0, 0], [0, 1]])


def test_admissible_input_gives_identity_filter_at_iteration_n_plus_1():
    r = shape(ex.A_E16, ex.C_E16, [ex.W_E16])
    assert r.found and r.order == 0 and r.iterations == 8 and set(r.ell_sequence) == {0}
    assert r.P == PolyMatrix.identity(2, var="s") and r.certificate().ok


def test_split_example1_hits_the_cap():
    r = shape(ex.A, ex.C, ex.split_example1())
    assert not r.found
    assert r.message.startswith("no filter found within order 5")
    assert "unsolvable" not in r.message
    assert r.order <= 5
    assert r.certificate().ok  # the filter built so far still has P G = I, det P = c s^n_f
    r2 = shape(ex.A, ex.C, ex.split_example1(), max_order=20, max_iterations=30)
    assert not r2.found and "within 30 iterations" in r2.message and r2.iterations == 30


@pytest.mark.parametrize("A, C, match", [([[0, 0], [0, 0]], [[1, 0]], "not observable"),
                                         ([[0, 1], [0, 0]], [[1, 0], [1, 0]], "rank")])
def test_refuses_unobservable(A, C, match):
    with pytest.raises(NotObservableError, match=match):
        shape(A, C, [])


def test_extended_set_matches_18_19():
    r = shape(ex.A, ex.C, [ex.W1_EXAMPLE1])
    Ae, Ce, We = extended_set(ex.A, ex.C, [ex.W1_EXAMPLE1], r.filter)
    assert (Ae, Ce, We) == (r.A_e, r.C_e, r.W_e)


def test_extend_argument_errors():
    with pytest.raises(DimensionError, match="m = 0"):
        extend(ex.A, ex.C, [], 0)


@settings(max_examples=8, deadline=None)
@given(seed=st.integers(0, 10**6), which=st.sampled_from([1, 2]))
def test_random_coordinates_same_order_and_iterations(seed, which):
    """The paper's robustness claim: Γ-transformed Examples 1 and 2 shape the same way."""
    rng = random.Random(seed)
    W = ex.W1_EXAMPLE1 if which == 1 else ex.W1_EXAMPLE2
    A2, C2, W2 = ex.transform(ex.A, ex.C, [W], ex.unimodular(5, rng), ex.unimodular(2, rng))
    r = shape(A2, C2, W2)
    assert r.found
    assert (r.order, r.iterations) == ((1, 8) if which == 1 else (2, 11))
    assert admissibility(r.A_e, r.C_e, r.W_e).holds
    assert r.certificate().ok


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10**6))
def test_random_admissible_sets_need_no_filter(seed):
    rng = random.Random(seed)
    q = rng.choice([(2, 1), (3, 2), (2, 2, 1)])
    A, C, W = ex.random_canonical(q, 1, rng)
    A2, C2, W2 = ex.transform(A, C, W, ex.unimodular(sum(q), rng), ex.unimodular(len(q), rng))
    r = shape(A2, C2, W2)
    assert r.found and r.order == 0 and r.iterations == sum(q) + 1


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10**6))
def test_random_upward_sets_certificate(seed):
    """Inadmissible canonical sets: whatever shape returns is certified (found or capped)."""
    rng = random.Random(seed)
    q = rng.choice([(2, 1), (3, 2), (2, 2)])
    A, C, W = ex.random_canonical(q, 1, rng, upward=True)
    r = shape(A, C, W, max_order=4)
    assert r.order <= 4
    cert = r.certificate()
    assert cert.ok, str(cert)
    if r.found:
        assert ex.sympy_admissible(r.A_e.to_sympy().tolist(), r.C_e.to_sympy().tolist(),
                                   [Wk.to_sympy().tolist() for Wk in r.W_e])


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10**6), m=st.integers(1, 4))
def test_extend_identities_on_random_sets(seed, m):
    """extend's defining identities, with sympy: S22 C̃Ã^{m−1} = R̃* of full row rank r̃ − r,
    S32 C̃Ã^{m−1} + S31 R = 0, [S22; S32] nonsingular; im E_σ ⊇ ker R̃ and W̃-invariant;
    ℓ = rank R̃* E_σ; T1 R̃* E_σ = 0 with [T1; T2] nonsingular; M = [𝓑; 𝓓] invertible."""
    rng = random.Random(seed)
    n, p = rng.randint(2, 5), rng.randint(1, 2)
    A = sympy.Matrix(n, n, lambda i, j: rng.choice([0, 0, 1, -1, 2]))
    C = sympy.Matrix(p, n, lambda i, j: rng.choice([0, 1, -1]))
    W = [sympy.Matrix(n, n, lambda i, j: rng.choice([0, 0, 0, 1])) for _ in range(rng.randint(1, 2))]
    st_ = extend(A.tolist(), C.tolist(), [w.tolist() for w in W], m)
    R = sympy.zeros(0, n)
    for k in range(m - 1):
        R = R.col_join(C * A**k)
    last = C * A ** (m - 1)
    Rt = R.col_join(last)
    S22, S31, S32 = (M.to_sympy() for M in (st_.S22, st_.S31, st_.S32))
    assert (st_.r, st_.r_tilde) == (R.rank(), Rt.rank())
    Rstar = S22 * last
    assert Rstar.rank() == Rstar.shape[0] == st_.r_tilde - st_.r
    if S32.shape[0]:
        assert (S32 * last + S31 * R).is_zero_matrix
    assert S22.col_join(S32).rank() == p
    E = st_.E_sigma.to_sympy()
    for v in Rt.nullspace():
        assert E.row_join(v).rank() == E.rank()
    for w in W:
        assert E.row_join(w * E).rank() == E.rank()
    X = Rstar * E
    assert st_.ell == X.rank()
    if st_.ell:
        T1, T2 = st_.T1.to_sympy(), st_.T2.to_sympy()
        assert (T1 * X).is_zero_matrix and T1.col_join(T2).rank() == T1.shape[1]
    assert st_.M.to_sympy().rank() == p
