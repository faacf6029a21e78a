"""The special coordinate basis (uio_ring.analysis.scb): paper 003's example, planted structure,
agreement with the independent routes (Smith form, Markov parameters, Hautus tests)."""

from __future__ import annotations

import random
from fractions import Fraction

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from uio_ring import DelaySystem
from uio_ring.analysis.infinite_structure import infinite_zero_structure
from uio_ring.analysis.observer_classes import observer_options
from uio_ring.analysis.scb import scb_dimensions, special_coordinate_basis
from uio_ring.analysis.scb_certificate import theorem1_violations
from uio_ring.analysis.scb_steps import theorem1_transformation
from uio_ring.analysis.strong_observability import (
    is_hurwitz_polynomial,
    is_strong_star_detectable,
    is_strongly_detectable,
    is_strongly_observable,
)
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.errors import DimensionError, DomainError
from uio_ring.ring.matrix import Poly, PolyMatrix
from uio_ring.ring.qmatrix import QMatrix as Q

from .paper003 import system as paper003_system
from .planted_scb import planted


def test_paper003_invariants():
    scb = special_coordinate_basis(paper003_system())
    assert (scb.n_a, scb.n_b, scb.n_c, scb.n_d) == (1, 2, 0, 5)
    assert (scb.m_0, scb.m_d, scb.p_b) == (0, 2, 1)
    assert scb.q == (3, 2) and scb.l == (2,)
    assert scb.invariant_zero_polynomial == Poly.gen("s") + 10  # the zero at −10
    assert scb.A_a == PolyMatrix("[[-10]]")
    # (A_b, C_b) in Brunovsky observer form with the paper's A_b; L_b = [13, 47] places {−8, −6}
    assert scb.C_b == PolyMatrix("[[1, 0]]")
    Lb = Q([[13], [47]])
    assert charpoly(Q(scb.A_b) - Lb @ Q(scb.C_b)) == (Poly.gen("s") + 8) * (Poly.gen("s") + 6)
    cert = scb.verify()
    assert cert.ok, str(cert)
    assert len(cert.checks) >= 19


def test_paper003_selectors_and_input_directions():
    scb = special_coordinate_basis(paper003_system())
    B = Q(scb.B_bar)
    assert [i for i in range(8) if not B.row(i).is_zero()] == [5, 7]  # the chain ends x_d,3 and x_d,5
    assert Q(scb.C_bar) == Q([[0, 0, 0, 1, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0, 1, 0], [0, 1, 0, 0, 0, 0, 0, 0]])


def _random_params(rng: random.Random) -> tuple[int, tuple[int, ...], tuple[int, ...], int]:
    while True:
        na = rng.randint(0, 3)
        l = tuple(rng.randint(1, 3) for _ in range(rng.randint(0, 2)))
        q = tuple(rng.randint(1, 4) for _ in range(rng.randint(0, 3)))
        m0 = rng.randint(0, 2)
        if na + sum(l) + sum(q):
            return na, l, q, m0


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32))
def test_planted_structure_is_recovered(seed):
    rng = random.Random(seed)
    na, l, q, m0 = _random_params(rng)
    P = planted(na, l, q, m0, rng)
    scb = special_coordinate_basis(P.system)
    assert (scb.n_a, scb.m_0) == (na, m0)
    assert scb.q == tuple(sorted(q, reverse=True))
    assert sorted(scb.l) == sorted(l)
    assert scb.invariant_zero_polynomial == P.zero_polynomial
    cert = scb.verify()
    assert cert.ok, str(cert)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32))
def test_invariants_agree_with_the_independent_routes(seed):
    """Markov-parameter infinite-zero orders, Smith-form zeros and Lemma 4 against the Hautus tests."""
    rng = random.Random(seed)
    na, l, q, m0 = _random_params(rng)
    sys = planted(na, l, q, m0, rng).system
    scb = special_coordinate_basis(sys)
    orders = infinite_zero_structure(sys).orders
    assert tuple(sorted((o for o in orders if o > 0), reverse=True)) == scb.q
    assert sum(1 for o in orders if o == 0) == scb.m_0
    hurwitz = is_hurwitz_polynomial(scb.invariant_zero_polynomial)
    assert is_strongly_observable(sys).holds == (scb.n_a == 0 and scb.n_c == 0)  # Lemma 4 i
    assert is_strongly_detectable(sys).holds == (scb.n_c == 0 and hurwitz)  # Lemma 4 ii
    assert is_strong_star_detectable(sys).holds == (scb.n_c == 0 and hurwitz and all(k == 1 for k in scb.q))  # iii


def test_not_left_invertible_has_an_x_c_part():
    sys = DelaySystem("[[0, 1], [0, 0]]", "[[1, 0], [0, 1]]", "[[1, 0]]", None)
    dims = scb_dimensions(sys)
    assert dims.n_c == 1 and not dims.left_invertible
    scb = special_coordinate_basis(sys)
    assert (scb.n_a, scb.n_b, scb.n_c, scb.n_d, scb.m_c) == (0, 0, 1, 1, 1)
    assert scb.verify().ok
    assert not is_strongly_detectable(sys).holds


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32))
def test_planted_structure_with_an_x_c_part(seed):
    """Not left invertible: planted (A_c, B_c) controllable, coupled as (17a) allows; the sizes, the
    chains and the zeros come back and the certificate (incl. (p.5)–(p.7) with R* ≠ 0) holds."""
    rng = random.Random(seed)
    na, l, q, m0 = _random_params(rng)
    nc = rng.randint(1, 3)
    P = planted(na, l, q, m0, rng, n_c=nc, m_c=rng.randint(1, nc))
    scb = special_coordinate_basis(P.system)
    assert (scb.n_a, scb.n_c, scb.m_0) == (na, nc, m0)
    assert scb.q == tuple(sorted(q, reverse=True)) and sorted(scb.l) == sorted(l)
    assert scb.invariant_zero_polynomial == P.zero_polynomial
    cert = scb.verify()
    assert cert.ok, str(cert)
    assert not observer_options(P.system).holds


def test_refusals():
    with pytest.raises(DimensionError, match="unknown-input columns are dependent"):
        special_coordinate_basis(DelaySystem("[[0, 1], [0, 0]]", "[[0, 0], [1, 1]]", "[[1, 0]]", None))
    with pytest.raises(DimensionError, match="outputs are dependent"):
        special_coordinate_basis(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [2, 0]]", None))
    with pytest.raises(DomainError, match="δ-degree"):
        special_coordinate_basis(DelaySystem("[[d]]", "[[1]]", "[[1]]", None))


def test_theorem1_retransformation_removes_couplings_outside_24():
    """A system already in SCB form with F_dd entries in its own chain's columns: the
    Lemma 2 transformation (paper 000's (54)) brings F_dd to the form (24)."""
    q = (2, 1)
    # x_d = [x11, x12, x21]; A_d = A_d* + B_d F_dd with F_dd row 0 hitting x12 (own chain) and row 1 hitting x21
    A = Q([[0, 1, 0], [0, 3, 2], [0, 5, 7]])
    Ts = theorem1_transformation(Q.identity(3), A, q, 0)
    sys = DelaySystem(A.to_polymatrix(), PolyMatrix("[[0, 0], [1, 0], [0, 1]]"), PolyMatrix("[[1, 0, 0], [0, 0, 1]]"), None)
    scb = special_coordinate_basis(sys)
    assert not theorem1_violations(scb)
    Ab = Ts.inverse() @ A @ Ts
    assert Ab[0, 1] == 1 and Ts.take_rows([0]).take_cols([0]) == Q([[1]])
    assert scb.verify().ok


def test_certificate_fails_on_a_tampered_basis():
    from dataclasses import replace

    scb = special_coordinate_basis(paper003_system())
    bad = replace(scb, A_bar=(Q(scb.A_bar) + Q([[Fraction(1) if (i, j) == (0, 2) else 0 for j in range(8)]
                                                for i in range(8)])).to_polymatrix())
    cert = bad.verify()
    assert not cert.ok
    assert not cert["Ā = Ts⁻¹ A Ts"].ok and not cert["(17a) Ā − B̄_0 C̄_0 has the SCB block pattern"].ok
