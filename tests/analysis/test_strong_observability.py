"""Strong observability / detectability, invariant zeros, V*, and the integer invariants
(uio_ring.analysis.strong_observability, .infinite_structure, .normal_form_applicability)."""

from __future__ import annotations

import random
from fractions import Fraction

import numpy as np
import pytest
import sympy
from design import paper000
from independent import weakly_unobservable_dim

from analysis import paper003
from uio_ring import (
    DelaySystem,
    Poly,
    infinite_zero_structure,
    invariant_zeros,
    is_strong_star_detectable,
    is_strongly_detectable,
    is_strongly_observable,
    normal_form_applicable,
    normal_form_chain_lengths,
    observability_indices,
    relative_degrees,
    rosenbrock_matrix,
    unknown_input_observability,
    weakly_unobservable_subspace,
)
from uio_ring.analysis.strong_observability import is_hurwitz_polynomial
from uio_ring.errors import DomainError


# ---------------------------------------------------------------------------- aircraft (paper 000)
def test_aircraft_strongly_observable_and_zero_free():
    sys = paper000.aircraft()
    rep = is_strongly_observable(sys)
    assert rep.holds and rep.reason == ""
    z = rep.invariant_zeros
    assert z.normal_rank == 8 and z.factors == () and z.polynomial == Poly(1, "s") and z.roots == ()
    assert rep.dim_V_star == 0 and rep.left_invertible
    # the gcd of the 9 maximal 8×8 minors of P(s) is 1
    P = sympy.Matrix(rosenbrock_matrix(sys).to_sympy())
    s = sympy.Symbol("s")
    minors = [P[[i for i in range(9) if i != k], :].det() for k in range(9)]
    g = 0
    for mnr in minors:
        g = sympy.gcd(g, sympy.expand(mnr))
    assert sympy.Poly(g, s).degree() == 0


def test_aircraft_structure_and_matching_condition():
    sys = paper000.aircraft()
    assert relative_degrees(sys).degrees == (3, 3)  # c_1ᵀA²D = −701.7, c_2ᵀA²D = −190
    assert observability_indices(sys).indices == (4, 3)
    assert infinite_zero_structure(sys).orders == (3,)
    assert normal_form_chain_lengths(sys) == (4, 3)  # claim 19: d = (2, 4, 6, 7, 7)
    rep = normal_form_applicable(sys)
    assert rep.holds and rep.matching_condition is False
    assert "matching condition fails" in rep.summary
    # strong* detectability needs the rank condition, which CD = 0 violates
    star = is_strong_star_detectable(sys)
    assert not star.holds and "rank (observer-matching) condition fails" in star.reason
    assert is_strongly_detectable(sys).holds


def test_augmented_aircraft_chain_lengths():
    sys = paper000.aircraft(known_input=False)
    A = [list(r) + [w[0]] for r, w in zip(paper000.A, paper000.W, strict=True)] + [[0] * 8]
    aug = DelaySystem(A, [[0]] * 7 + [[1]], [list(r) + [0] for r in paper000.C], None)
    assert is_strongly_observable(aug).holds  # (93)
    assert normal_form_chain_lengths(aug) == (4, 4)
    assert normal_form_chain_lengths(sys) == (4, 3)


# ---------------------------------------------------------------------------- paper 003's example
def test_paper003_zero_at_minus_10_detectable_not_observable():
    sys = paper003.system()
    z = invariant_zeros(sys)
    assert z.polynomial == Poly("s + 10", "s") and z.normal_rank == 10
    assert z.roots == (-10 + 0j,)
    so, sd, ss = is_strongly_observable(sys), is_strongly_detectable(sys), is_strong_star_detectable(sys)
    assert not so.holds and "roots of s + 10" in so.reason and so.dim_V_star == 1
    assert sd.holds
    assert not ss.holds and ss.rank_condition is not None and not ss.rank_condition.hautus_rank_condition
    assert infinite_zero_structure(sys).orders == (2, 3)
    assert not normal_form_applicable(sys).holds


# ---------------------------------------------------------------------------- small cases
@pytest.mark.parametrize(
    "A, B, C, D, so, sd",
    [
        ("[[-2]]", "[[1]]", "[[1]]", "[[1]]", False, True),  # zero at −3
        ("[[2]]", "[[1]]", "[[1]]", "[[1]]", False, False),  # det P = s − 1: zero at +1
        ("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None, True, True),
        ("[[0, 1], [0, 0]]", "[[0], [1]]", "[[0, 1]]", None, False, False),  # zero at 0
        ("[[0, 1], [0, 0]]", "[[1, 0], [0, 1]]", "[[1, 0]]", None, False, False),  # not left invertible
        ("[[0, 1], [-1, 0]]", "[[0], [0]]", "[[1, 0]]", None, True, True),  # w never acts; (A, C) observable
    ],
)
def test_small_systems(A, B, C, D, so, sd):
    sys = DelaySystem(A, B, C, D)
    r_so, r_sd = is_strongly_observable(sys), is_strongly_detectable(sys)
    assert (r_so.holds, r_sd.holds) == (so, sd)
    assert (r_so.reason == "") == so and (r_sd.reason == "") == sd
    assert r_so.to_dict()["holds"] == so and str(r_so).startswith("strongly observable")
    assert (r_so.dim_V_star == 0) == so


def test_redundant_unknown_inputs_do_not_spoil_strong_observability():
    """``rank [B; D]`` (not n_w) is the target rank: w = [w1, w2] entering as w1 + w2."""
    sys = DelaySystem("[[0, 1], [0, 0]]", "[[0, 0], [1, 1]]", "[[1, 0]]", None)
    assert is_strongly_observable(sys).holds
    rep = normal_form_applicable(sys)
    assert not rep.holds and "dependent" in rep.reason


def test_delay_system_refused():
    sys = DelaySystem("[[d]]", "[[1]]", "[[1]]", None)
    with pytest.raises(DomainError, match="δ-degree 1"):
        rosenbrock_matrix(sys)
    rep = normal_form_applicable(sys)
    assert not rep.holds and "delays" in rep.reason and rep.strong_observability is None


def test_relative_degree_infinite_and_zero():
    sys = DelaySystem("[[0, 0], [0, 0]]", "[[1], [0]]", "[[0, 1], [1, 0]]", "[[0], [1]]")
    assert relative_degrees(sys).degrees == (None, 0)
    assert not relative_degrees(sys).holds and "y[0]" in relative_degrees(sys).reason


# ---------------------------------------------------------------------------- Routh test
def test_hurwitz_polynomial_against_numeric_roots():
    rng = random.Random(7)
    for _ in range(300):
        deg = rng.randint(1, 6)
        cs = [Fraction(rng.randint(-4, 6), rng.randint(1, 3)) for _ in range(deg)] + [Fraction(rng.randint(1, 3))]
        p = Poly.from_coeffs(cs, "s")
        roots = np.roots([float(c) for c in reversed(cs)])
        margin = np.abs(roots.real).min()
        if margin < 1e-6:
            continue  # numerically undecidable; the exact test still decides
        assert is_hurwitz_polynomial(p) == bool(np.all(roots.real < 0)), cs
    s = Poly.gen("s")
    assert is_hurwitz_polynomial(Poly(3, "s")) and not is_hurwitz_polynomial(s**2 + 1)
    assert not is_hurwitz_polynomial(s**3 + s**2 + s + 1)  # roots −1, ±j
    assert is_hurwitz_polynomial(-(s**2) - 3 * s - 2)


# ---------------------------------------------------------------------------- random systems
def _random_system(rng: random.Random) -> DelaySystem:
    n = rng.randint(1, 5)
    m = rng.randint(1, 2)
    p = rng.randint(1, 3)

    def mat(r, c, density):
        return [[rng.randint(-2, 2) if rng.random() < density else 0 for _ in range(c)] for _ in range(r)]

    D = mat(p, m, 0.3) if rng.random() < 0.3 else None
    return DelaySystem(mat(n, n, 0.5), mat(n, m, 0.5), mat(p, n, 0.5), D)


def test_paper001_assumption_1_agrees_with_strong_observability():
    """On delay-free systems Assumption 1 of paper 001 is strong observability (Remark 2, (7))."""
    rng = random.Random(2024)
    seen = set()
    for _ in range(60):
        sys = _random_system(rng)
        so = is_strongly_observable(sys)
        a1 = unknown_input_observability(sys)
        assert so.holds == a1.holds, (sys, so.reason, a1.reason)
        seen.add(so.holds)
    assert seen == {True, False}


def test_V_star_matches_independent_implementation_and_smith():
    rng = random.Random(11)
    for _ in range(40):
        sys = _random_system(rng)
        V = weakly_unobservable_subspace(sys)
        mats = [sympy.Matrix(M.to_sympy()) if M.rows and M.cols else sympy.zeros(M.rows, M.cols) for M in
                (sys.A, sys.B, sys.C, sys.D)]
        assert V.cols == weakly_unobservable_dim(*mats)
        so = is_strongly_observable(sys)
        assert so.holds == (V.cols == 0)
        # dim V* = (number of invariant zeros) when left invertible
        if so.left_invertible:
            assert V.cols == so.invariant_zeros.count


def test_chain_lengths_are_a_partition_of_n_when_strongly_observable():
    rng = random.Random(5)
    count = 0
    for _ in range(60):
        sys = _random_system(rng)
        if sys.D.is_zero() and normal_form_applicable(sys).holds:
            mu = normal_form_chain_lengths(sys)
            assert sum(mu) == sys.n_x and list(mu) == sorted(mu, reverse=True)
            count += 1
    assert count >= 5
