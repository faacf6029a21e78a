"""Algorithm (4)–(5) and Assumption 1 (uio_ring.analysis.observability)."""

from __future__ import annotations

import sympy
from design import paper001
from hypothesis import given
from hypothesis import strategies as st
from independent import system_at, weakly_unobservable_dim

from uio_ring import DelaySystem, PolyMatrix, unknown_input_observability
from uio_ring.analysis import ObservabilityReport


def test_paper_example_k_star_and_M_sequence():
    rep = unknown_input_observability(paper001.system())
    assert isinstance(rep, ObservabilityReport)
    assert rep.holds and rep.reason == ""
    assert rep.k_star == 3
    assert [rep.M[k] for k in (1, 2, 3, 4)] == [PolyMatrix.identity(n) for n in (2, 3, 4, 4)]
    assert rep.rank == 4 and rep.non_unit_factors == ()
    assert rep.N[0].shape == (0, 4) and rep.Delta[0].shape == (0, 4)
    # N_k stacks the Δ's
    assert rep.N[2] == PolyMatrix.vstack(rep.N[1], rep.Delta[2])


def test_paper_example_at_delta_zero_is_strongly_observable():
    rep = unknown_input_observability(paper001.system().at_delta(0))
    assert rep.holds and rep.k_star == 3
    assert weakly_unobservable_dim(*system_at(paper001.system(), 0)) == 0


def test_rank_shortfall_is_reported():
    # y = x1 + w: the output says nothing w-free
    rep = unknown_input_observability(DelaySystem("[[d]]", "[[1]]", "[[1]]", "[[1]]"))
    assert not rep.holds and rep.k_star == 0 and rep.rank == 0
    assert "rank M_0 = 0 < n_x = 1" in rep.reason


def test_non_unit_factor_is_reported():
    # y = (1 + δ) x: x(t) + x(t − h) is known, x itself only through an unstable recursion
    rep = unknown_input_observability(DelaySystem("[[0]]", "[[0]]", "[[d + 1]]", None))
    assert not rep.holds and rep.rank == 1
    assert [str(f) for f in rep.non_unit_factors] == ["d + 1"]
    assert "not unimodular" in rep.reason and "d + 1" in rep.reason


def test_paper_003_example_has_an_invariant_zero():
    from .paper003 import system

    rep = unknown_input_observability(system())
    assert not rep.holds and rep.rank == 7  # V* = span{e1}, zero at -10
    assert weakly_unobservable_dim(*system_at(system(), 0)) == 1


def test_report_display_and_dict():
    rep = unknown_input_observability(paper001.system())
    text = str(rep)
    assert "k* = 3" in text and "holds" in text
    assert "<table>" in rep._repr_html_()
    assert rep._repr_latex_().startswith("$$")
    data = rep.to_dict()
    assert data["k_star"] == 3 and data["holds"] is True
    assert data["invariant_factors"][4] == ["1", "1", "1", "1"]


# -- delay-free: Assumption 1 is strong observability (paper 001, Remark 2) --------------
small = st.integers(-2, 2)


@st.composite
def constant_systems(draw):
    n = draw(st.integers(1, 3))
    m = draw(st.integers(1, 2))
    p = draw(st.integers(1, 3))

    def mat(r, c, sparse=False):
        vals = st.sampled_from([0, 0, 0, 1, -1, 2]) if sparse else small
        return [[draw(vals) for _ in range(c)] for _ in range(r)]

    return DelaySystem(mat(n, n), mat(n, m), mat(p, n), mat(p, m, sparse=True))


@given(constant_systems())
def test_delay_free_assumption_1_is_strong_observability(sys):
    rep = unknown_input_observability(sys)
    dim = weakly_unobservable_dim(*system_at(sys, 0))
    assert rep.rank == sys.n_x - dim
    assert rep.holds == (dim == 0)


# -- delay systems: the rank of M_k* is n_x − dim V* over Q(δ) ------------------------------
@st.composite
def delay_systems(draw):
    n = draw(st.integers(1, 3))
    m = draw(st.integers(1, 2))
    p = draw(st.integers(1, 3))
    entries = st.sampled_from(["0", "0", "1", "-1", "d", "d + 1", "2*d", "-d"])

    def mat(r, c):
        return [[draw(entries) for _ in range(c)] for _ in range(r)]

    return DelaySystem(mat(n, n), mat(n, m), mat(p, n), mat(p, m))


@given(delay_systems())
def test_rank_of_M_k_star_matches_generic_V_star(sys):
    rep = unknown_input_observability(sys)
    # dim V* at a point is at least the generic one; three points give the generic value
    dims = [weakly_unobservable_dim(*system_at(sys, v)) for v in (sympy.Rational(7, 3), sympy.Rational(-11, 5), 13)]
    assert rep.rank == sys.n_x - min(dims)


# -- the reduction of Δ_k modulo N_k changes no module: against the raw algorithm -------------
def _raw_algorithm(sys):
    """Algorithm (4)–(5) exactly as printed (no reduction of Δ_k), invariant factors by
    elimination: the independent path."""
    from uio_ring.ring.hermite import hermite_by_elimination
    from uio_ring.ring.smith import invariant_factors_by_elimination

    n = sys.n_x
    Delta, F, G = PolyMatrix.zeros(0, n), sys.D, sys.C
    N = Delta
    facs = [()]
    for k in range(40):
        S = PolyMatrix.vstack(Delta @ sys.B, F)
        h = hermite_by_elimination(S)
        PR = h.U @ PolyMatrix.vstack(Delta @ sys.A, G)
        F, G, Delta = h.H[0 : h.rank, 0 : S.cols], PR[0 : h.rank, 0:n], PR[h.rank : PR.rows, 0:n]
        N = PolyMatrix.vstack(N, Delta)
        facs.append(tuple(invariant_factors_by_elimination(N)))
        if facs[-1] == facs[-2]:
            return k, facs
    raise AssertionError("no stabilisation")  # pragma: no cover


@given(delay_systems())
def test_reduced_delta_gives_the_raw_algorithms_k_star_and_factors(sys):
    rep = unknown_input_observability(sys)
    k_star, facs = _raw_algorithm(sys)
    assert rep.k_star == k_star
    assert [tuple(f) for f in rep.invariant_factors] == facs


def test_reduction_keeps_degrees_low_on_a_random_degree_4_system():
    import random as _random

    rng = _random.Random(3)

    def poly():
        return " + ".join(f"{rng.randint(-3, 3)}*d**{e}" for e in range(5))

    def mat(r, c):
        return [[poly() for _ in range(c)] for _ in range(r)]

    sys = DelaySystem(mat(4, 4), mat(4, 1), mat(2, 4), None)
    rep = unknown_input_observability(sys)
    k_star, facs = _raw_algorithm(sys)
    assert (rep.k_star, [tuple(f) for f in rep.invariant_factors]) == (k_star, facs)
    # every Δ_k row lies in the row module of N_k and has degree at most that of the raw rows
    assert max(D.degree() for D in rep.Delta) <= 4 * (rep.k_star + 2)
