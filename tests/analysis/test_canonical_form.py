"""Canonical form (uio_ring.analysis.canonical_form): identities (8)–(9), Theorem 2 in
both directions on random sets, and the paper's Examples 1–3."""

from __future__ import annotations

import random

import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from analysis import paper004 as ex
from uio_ring import CanonicalForm, PolyMatrix, canonical_form, shape
from uio_ring.analysis import observability_indices_of
from uio_ring.errors import NotObservableError


def test_example1_is_not_canonical():
    cf = canonical_form(ex.A, ex.C, [ex.W1_EXAMPLE1])
    assert isinstance(cf, CanonicalForm)
    assert sorted(cf.q) == [2, 3]
    assert not cf.lower_triangular and cf.violations
    cert = cf.certificate()
    assert cert.ok, str(cert)
    assert cert["Theorem 2"].ok


def test_example2_extension_is_canonical_with_q_4_3():
    cf = canonical_form(ex.A_E16, ex.C_E16, [ex.W_E16])
    assert cf.q == (4, 3) and cf.lower_triangular and cf.certificate().ok
    assert cf.L.is_zero()


def test_example3_canonical_form_of_the_shaped_set():
    """Example 3: the shaped Example 1 has q = (3, 3); both off-diagonal W̄ blocks are
    diagonal with zero top-left entry, the diagonal blocks zero (for the paper's Γ's;
    ours may differ, the structure may not)."""
    r = shape(ex.A, ex.C, [ex.W1_EXAMPLE1])
    cf = canonical_form(r.A_e, r.C_e, r.W_e)
    assert cf.q == (3, 3) and cf.lower_triangular and cf.certificate().ok


def test_paper_gammas_for_example3_give_the_form():
    """The paper's Γ_y and the reconstructed Γ_x of Example 3 put the shaped set in form (8)–(9)."""
    r = shape(ex.A, ex.C, [ex.W1_EXAMPLE1])
    Gx = sympy.Matrix([[-1, 0, 0, 0, 0, 0], [0, -1, 0, 0, 0, 0], [0, 0, -1, 0, 0, 0], [0, -1, 0, 1, 0, 0],
                       [0, 0, -1, 0, 1, 0], [0, 0, 0, 0, 0, 1]])
    Gy = sympy.diag(-1, 1)
    Ae, Ce, We = (r.A_e.to_sympy(), r.C_e.to_sympy(), r.W_e[0].to_sympy())
    Ab, Cb = Gx.inv() * Ae * Gx, Gy.inv() * Ce * Gx
    assert Cb == sympy.Matrix([[1, 0, 0, 0, 0, 0], [0, 0, 0, 1, 0, 0]])
    assert Ab == sympy.Matrix([[0, 1, 0, -1, 0, 0], [0, 0, 1, 0, 0, 0], [0] * 6, [0, 0, 0, 0, 1, 0],
                               [0, 0, 0, 0, 0, 1], [0] * 6])
    assert Gx.inv() * We * Gx == sympy.Matrix([[0] * 6, [0, 0, 0, 0, -1, 0], [0, 0, 0, 0, 0, -1], [0] * 6,
                                               [0, -1, 0, 0, 0, 0], [0, 0, -1, 0, 0, 0]])


def test_observability_indices():
    assert observability_indices_of(ex.A, ex.C) == (3, 2)
    assert observability_indices_of([[0]], [[0]]) == ()


@pytest.mark.parametrize("A, C, match", [
    ([[0, 0], [0, 0]], [[1, 0]], "not observable"),
    ([[0, 1], [0, 0]], [[1, 0], [2, 0]], "rank"),
])
def test_refuses(A, C, match):
    with pytest.raises(NotObservableError, match=match):
        canonical_form(A, C)


def test_no_W_and_single_state():
    cf = canonical_form([[3]], [[2]])
    assert cf.q == (1,) and cf.W_bar == () and cf.certificate().ok
    assert cf.L == PolyMatrix([[3]])


@settings(max_examples=30, deadline=None)
@given(seed=st.integers(0, 10**6), upward=st.booleans())
def test_theorem2_both_directions_in_random_coordinates(seed, upward):
    rng = random.Random(seed)
    q = rng.choice([(1,), (2, 1), (3, 2), (2, 2, 1), (3, 1, 1), (4, 2)])
    A, C, W = ex.random_canonical(q, rng.randint(1, 2), rng, upward=upward)
    n, p = sum(q), len(q)
    A2, C2, W2 = ex.transform(A, C, W, ex.unimodular(n, rng), ex.unimodular(p, rng))
    cf = canonical_form(A2, C2, W2)
    cert = cf.certificate()
    assert cert.ok, str(cert)
    assert sorted(cf.q, reverse=True) == sorted(q, reverse=True)
    assert cf.lower_triangular == ex.sympy_admissible(A2, C2, W2)
    if not upward or sum(q) == len(q):
        assert cf.lower_triangular
    d = cf.to_dict()
    assert d["q"] == list(cf.q) and len(d["W_bar"]) == len(W)
