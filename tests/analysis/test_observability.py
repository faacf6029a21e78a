"""Algorithm (4)–(5) and Assumption 1 (uio_ring.analysis.observability)."""

from __future__ import annotations

import sympy
from design import paper001
from hypothesis import example, given
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


# -- the check's fast paths against the elimination paths -------------------------------------
@given(st.data())
def test_module_factors_from_the_weak_popov_basis_equal_elimination(data):
    from ring.strategies import dense_matrices

    from uio_ring.analysis._module_factors import module_invariant_factors
    from uio_ring.ring.row_basis import extend_row_basis
    from uio_ring.ring.smith import invariant_factors_by_elimination

    N = data.draw(dense_matrices(min_rows=1, max_rows=4, min_cols=1, max_cols=4, max_degree=3))
    W = extend_row_basis(PolyMatrix.zeros(0, N.cols), N).basis
    assert module_invariant_factors(N, W) == invariant_factors_by_elimination(N)


@given(st.data())
def test_module_factors_of_square_matrices_with_one_non_unit_factor(data):
    # U·diag(1, …, 1, f)·V: the d_{n−1} = 1 path with the kernel-vector determinant
    from ring.strategies import unimodular_matrices

    from uio_ring.analysis._module_factors import module_invariant_factors
    from uio_ring.ring.row_basis import extend_row_basis
    from uio_ring.ring.smith import invariant_factors_by_elimination

    n = data.draw(st.integers(2, 4))
    f = data.draw(st.sampled_from(["d + 1", "d**2 - 3", "(d - 1)**2"]))
    N = data.draw(unimodular_matrices(n)) @ PolyMatrix.diag(*(["1"] * (n - 1) + [f])) @ data.draw(unimodular_matrices(n))
    W = extend_row_basis(PolyMatrix.zeros(0, n), N).basis
    got = module_invariant_factors(N, W)
    assert got == invariant_factors_by_elimination(N)
    assert str(got[-1]) == str(PolyMatrix(f"[[{f}]]")[0, 0].monic())


@given(delay_systems())
def test_w_step_is_a_unimodular_elimination(sys):
    # [[G', F'], [free, 0]] = P·[[ΔA, ΔB], [G, F]] for some unimodular P: both sides span
    # the same row module, checked through the Hermite forms (the independent path)
    from uio_ring.analysis._w_step import eliminate_w
    from uio_ring.ring.hermite import hermite_by_elimination

    n, m = sys.n_x, sys.n_w
    Delta, F, G = sys.C, sys.D, sys.C  # a first step from (C, D) with Δ = C
    for _ in range(2):
        step = eliminate_w(Delta @ sys.B, Delta @ sys.A, F, G)
        before = PolyMatrix.vstack(PolyMatrix.hstack(Delta @ sys.A, Delta @ sys.B), PolyMatrix.hstack(G, F))
        after = PolyMatrix.vstack(PolyMatrix.hstack(step.G, step.F),
                                  PolyMatrix.hstack(step.free, PolyMatrix.zeros(step.free.rows, m)))
        hb, ha = hermite_by_elimination(before), hermite_by_elimination(after)
        assert hb.rank == ha.rank and hb.H[0 : hb.rank, :] == ha.H[0 : ha.rank, :]
        assert step.F.rows == hermite_by_elimination(PolyMatrix.vstack(Delta @ sys.B, F)).rank
        Delta, F, G = step.free if step.free.rows else PolyMatrix.zeros(0, n), step.F, step.G


@given(delay_systems())
@example(DelaySystem("[[0]]", "[[0]]", "[[0]]", "[[1]]"))  # D = I: no Hermite step, no factors
def test_w_step_with_the_small_solution_changes_delta_only_inside_n_k(sys):
    # after a Hermite step [X; K]·S = [I; 0] (F = I), the step with ``prev`` uses
    # u = Δ B·X − t·K: same F and G, and the w-free rows differ from Δ A − Δ B·G by
    # rows of L(K·R), which are the Hermite step's own w-free rows
    from uio_ring.analysis._w_step import eliminate_w
    from uio_ring.ring.hermite import hermite_by_elimination
    from uio_ring.ring.row_basis import is_weak_popov

    def module(M):
        h = hermite_by_elimination(M)
        return h.H[0 : h.rank, :]

    n = sys.n_x
    Delta, F, G = sys.C, sys.D, sys.C
    first = eliminate_w(Delta @ sys.B, Delta @ sys.A, F, G)
    S = PolyMatrix.vstack(Delta @ sys.B, F)
    if F.rows and F == PolyMatrix.identity(F.rows):  # D = I: the closed form, no Hermite step
        assert first.X is None and first.free == Delta @ sys.A - Delta @ sys.B @ G
        return
    assert first.X is not None and first.R is not None and first.K is not None
    assert first.X @ first.R == first.G and first.X @ S == first.F
    assert (first.K @ S).is_zero() and (first.K.rows == 0 or is_weak_popov(first.K))
    if first.K.rows:
        assert module(first.K @ first.R) == module(first.free)
    if not (first.F.rows and first.F == PolyMatrix.identity(first.F.rows)) or not first.free.rows:
        return
    D2 = first.free
    new = eliminate_w(D2 @ sys.B, D2 @ sys.A, first.F, first.G, first)
    old = eliminate_w(D2 @ sys.B, D2 @ sys.A, first.F, first.G)
    assert new.F == old.F and new.G == old.G
    assert (new.X, new.R, new.K) == (first.X, first.R, first.K)  # carried to the next step
    diff = new.free - old.free
    if first.free.rows:
        assert module(PolyMatrix.vstack(first.free, diff)) == module(first.free)
    else:
        assert diff.is_zero()
    assert new.free.cols == n


def test_planted_factor_d_minus_2_through_the_small_solution(monkeypatch):
    # x = T·z with T = diag(1, 1, δ − 2) applied to a system whose N_k* is unimodular of
    # rank 3 (A = [[-1, d+1, d+1], [3, 1, -1], [-(d-2), -d(d-2), d**2]], B = [d; -1; 0],
    # C = [[-d, 3, 0], [3, 0, 0]]): N_k(z) = N_k(x)·T, so the factors are 1, 1, δ − 2.
    # The F = I step with the small solution must be taken and must not lose δ − 2.
    import uio_ring.analysis._w_step as ws

    calls = []
    real = ws.remainder_rows
    monkeypatch.setattr(ws, "remainder_rows", lambda X, K: calls.append(K.rows) or real(X, K))
    sys = DelaySystem("[[-1, d + 1, (d + 1)*(d - 2)], [3, 1, -(d - 2)], [-1, -d, d**2]]",
                      "[[d], [-1], [0]]", "[[-d, 3, 0], [3, 0, 0]]", None)
    rep = unknown_input_observability(sys)
    assert calls and all(k > 0 for k in calls)
    assert [str(f) for f in rep.invariant_factors[rep.k_star]] == ["1", "1", "d - 2"]
    k_star, facs = _raw_algorithm(sys)
    assert (rep.k_star, [tuple(f) for f in rep.invariant_factors]) == (k_star, facs)


def test_new_rows_do_not_carry_the_left_inverse_size():
    # random 8-state system of δ-degree 16 (benchmarks/random_spec.py --n 8 --seed 1):
    # C B is 3×2 with a left inverse X of ≈ 1.3 kbit numerators; Δ_k B·X reduced modulo
    # the kernel row keeps every Δ_k below that size (Δ_k B·X itself: 1.3–5.2 kbit rows)
    from uio_ring.ring import _backend as bk
    from uio_ring.ring.hermite import _hermite_of_dependent_rows

    sys = _random_system(1, 8, 2, 3, 16)
    h = _hermite_of_dependent_rows(sys.C @ sys.B, min_rows=0)
    X = h.U[0 : h.rank, :]
    x_bits = max(int(p.numer().height_bits()) for row in X._r for p in row)
    rep = unknown_input_observability(sys)
    delta_bits = max(bk.bits(p) for D in rep.Delta for row in D._r for p in row)
    assert rep.k_star >= 5 and delta_bits < x_bits


def _random_system(seed, n, m, p, degree):
    import random as _random

    rng = _random.Random(seed)

    def poly():
        return " + ".join(f"{rng.randint(-3, 3)}*d**{e}" for e in range(degree + 1))

    def mat(r, c):
        return [[poly() for _ in range(c)] for _ in range(r)]

    return DelaySystem(mat(n, n), mat(n, m), mat(p, n), None)


def test_high_degree_small_systems_agree_with_the_raw_algorithm():
    # δ-degree 12 and 16 (the spec limit) at 2–3 states: the F = I closed form, the
    # Toeplitz first step and the modular certificates against the printed algorithm
    for seed, n, m, p, degree in [(1, 2, 1, 2, 16), (2, 3, 1, 2, 12), (5, 3, 2, 3, 8)]:
        sys = _random_system(seed, n, m, p, degree)
        rep = unknown_input_observability(sys)
        k_star, facs = _raw_algorithm(sys)
        assert (rep.k_star, [tuple(f) for f in rep.invariant_factors]) == (k_star, facs)


def test_each_step_leaves_a_progress_note_and_the_end_clears_it(monkeypatch):
    # the CLI's "still working" lines print this note: which step, how large N_k and Δ_k are
    from uio_ring import _progress

    notes = []
    monkeypatch.setattr(_progress, "_NOTE", _Recorder(notes))
    rep = unknown_input_observability(paper001.system())
    steps = [t for t in notes if t]
    assert len(steps) == rep.k_star + 1  # k = 0 … k*: one note per pass of the loop
    assert steps[0].startswith("algorithm (4)–(5) of Zheng et al. (2015), k = 0: rank N_0 = 0 of 4")
    assert f"k = {rep.k_star}: rank N_{rep.k_star} = 4 of 4" in steps[-1]
    assert notes[-1] == "" and _progress.current() == ""


class _Recorder(list):
    """A one-slot list that also records every note written into it."""

    def __init__(self, log):
        super().__init__([""])
        self.log = log

    def __setitem__(self, i, v):
        self.log.append(v)
        super().__setitem__(i, v)
