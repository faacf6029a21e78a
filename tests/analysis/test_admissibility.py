"""Admissibility (uio_ring.analysis.admissibility): the paper's examples, invariance
(Remark 1, Lemma 5) and agreement with an independent sympy implementation."""

from __future__ import annotations

import random
from fractions import Fraction

import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from analysis import paper004 as ex
from uio_ring import AdmissibilityReport, admissibility
from uio_ring.errors import DimensionError, DomainError


def test_example1_fails_at_level_one_with_the_vector():
    r = admissibility(ex.A, ex.C, [ex.W1_EXAMPLE1])
    assert isinstance(r, AdmissibilityReport)
    assert not r.holds
    assert (r.index, r.matrix) == (1, 0)
    # v ∈ 𝒮_1 = ker C with W_1 v ∉ ker C
    assert r.vector == tuple(Fraction(x) for x in (0, 1, 0, 0, 0))
    assert r.image == tuple(Fraction(x) for x in (-1, 0, -1, 0, 1))
    assert "W[0]" in r.reason and "𝒮_1" in r.reason
    assert r.to_dict()["index"] == 1


def test_example2_fails_at_level_one():
    r = admissibility(ex.A, ex.C, [ex.W1_EXAMPLE2])
    assert not r.holds and r.index == 1 and r.matrix == 0
    assert r.vector == tuple(Fraction(x) for x in (0, 0, 0, 0, 1))


def test_example2_extension_16_is_admissible():
    r = admissibility(ex.A_E16, ex.C_E16, [ex.W_E16])
    assert r.holds and r.reason == "" and r.index is None
    assert r.dimensions[0] == 5


def test_which_matrix_is_named():
    zero = [[0] * 5 for _ in range(5)]
    r = admissibility(ex.A, ex.C, [zero, zero, ex.W1_EXAMPLE2])
    assert r.matrix == 2 and "W[2]" in r.reason


@pytest.mark.parametrize("W, holds", [([], True), ([[[0, 0], [0, 0]]], True), ([[[1, 0], [0, 1]]], True),
                                      ([[[0, 0], [1, 0]]], True), ([[[0, 1], [0, 0]]], False)])
def test_two_state_chain(W, holds):
    assert admissibility([[0, 1], [0, 0]], [[1, 0]], W).holds is holds


def test_failure_at_a_deeper_level():
    # chain of 3: W maps level 3 into level 2 (x2' gets x3): 𝒮_2 = span{e3}, W e3 = e2 ∉ 𝒮_2
    A = [[0, 1, 0], [0, 0, 1], [0, 0, 0]]
    r = admissibility(A, [[1, 0, 0]], [[[0, 0, 0], [0, 0, 1], [0, 0, 0]]])
    assert not r.holds and r.index == 2 and r.dimensions == (2, 1)


def test_unobservable_pair_is_handled():
    # 𝒮_i stops shrinking at the unobservable subspace; invariance is still tested there
    A = [[0, 0], [0, 0]]
    assert admissibility(A, [[1, 0]], [[[0, 0], [0, 1]]]).holds
    assert not admissibility(A, [[1, 0]], [[[0, 1], [0, 0]]]).holds


@pytest.mark.parametrize("A, C, W, err, match", [
    ([[0, 1]], [[1, 0]], [], DimensionError, "square"),
    ([[0]], [[1, 0]], [], DimensionError, "C has 2 columns"),
    ([[0]], [[1]], [[[1, 0], [0, 0]]], DimensionError, r"W\[0\] is 2×2"),
    ([[0]], [[1]], "[[1]]", DimensionError, "list"),
    ("[[d]]", [[1]], [], DomainError, "constant"),
])
def test_errors(A, C, W, err, match):
    with pytest.raises(err, match=match):
        admissibility(A, C, W)


def test_empty_state():
    assert admissibility(sympy.zeros(0, 0).tolist(), [], []).holds


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10**6), upward=st.booleans())
def test_invariance_under_coordinates_and_output_injection(seed, upward):
    rng = random.Random(seed)
    q = rng.choice([(2, 1), (3, 2), (2, 2, 1), (3, 1, 1)])
    A, C, W = ex.random_canonical(q, rng.randint(1, 2), rng, upward=upward)
    base = admissibility(A, C, W).holds
    assert base == ex.sympy_admissible(A, C, W)
    if not upward:
        assert base  # canonical sets are admissible (Theorem 2)
    n, p = sum(q), len(q)
    A2, C2, W2 = ex.transform(A, C, W, ex.unimodular(n, rng), ex.unimodular(p, rng))
    assert admissibility(A2, C2, W2).holds == base  # Remark 1
    L = sympy.Matrix(n, p, lambda i, j: rng.randint(-3, 3))
    A3 = (sympy.Matrix(A2) + L * sympy.Matrix(C2)).tolist()
    assert admissibility(A3, C2, W2).holds == base  # Lemma 5


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 10**6))
def test_agrees_with_sympy_on_random_sparse_sets(seed):
    rng = random.Random(seed)
    n = rng.randint(1, 5)
    p = rng.randint(1, n)
    A = [[rng.choice([0, 0, 0, 1, -1]) for _ in range(n)] for _ in range(n)]
    C = [[rng.choice([0, 0, 1]) for _ in range(n)] for _ in range(p)]
    W = [[[rng.choice([0, 0, 0, 0, 1]) for _ in range(n)] for _ in range(n)] for _ in range(rng.randint(0, 2))]
    assert admissibility(A, C, W).holds == ex.sympy_admissible(A, C, W)
