"""The Zheng–Bejarano delay UIO (uio_ring.design.zheng_bejarano): paper 001, Section 5,
the delay-free special cases, and random systems."""

from __future__ import annotations

import dataclasses
import json
from fractions import Fraction

import pytest
import sympy
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring import (
    DelaySystem,
    DelayUIODesign,
    DimensionError,
    DomainError,
    NotObservableError,
    PolyMatrix,
    check_assumptions,
    design_zheng_bejarano,
    is_unimodular,
    zheng_bejarano_from_choices,
)
from uio_ring.design.zheng_bejarano import smallest_observer_orders

from . import paper001 as P

THM4 = "Theorem 4: e' − L0 e = 0"


@pytest.fixture(scope="module")
def paper_design() -> DelayUIODesign:
    return design_zheng_bejarano(P.system(), poles=P.POLES)


@pytest.fixture(scope="module")
def paper_choices() -> DelayUIODesign:
    """The paper's own choices: its U, Λ, Ō_L⁻¹ and T_L⁻¹."""
    return zheng_bejarano_from_choices(
        P.system(), U=P.U, Lam=P.LAM, O_left_inverse=P.O3_LEFT_INVERSE,
        T_left_inverse=P.T_LEFT_INVERSE, poles=P.POLES,
    )


# -- Section 5 ------------------------------------------------------------------------
def test_paper_example_certificate_ok(paper_design):
    cert = paper_design.certificate()
    assert cert.ok, str(cert)
    assert paper_design.n_z <= 6 and paper_design.lag <= 4
    assert paper_design.n_z == paper_design.r * paper_design.l_star


def test_paper_example_unique_quantities(paper_design):
    assert paper_design.V == P.V  # normalised Hermite form: unique
    assert paper_design.V.rows == 3  # rank M = 3
    assert paper_design.Vbar == P.VBAR  # V has full row rank: unique


def test_paper_example_spectrum_with_paper_gain(paper_design):
    assert (paper_design.r, paper_design.l_star) == (2, 3)  # three poles select l* = 3
    assert paper_design.G0 == P.G0 and paper_design.L0 == P.L0
    assert paper_design.poles == (Fraction(-10), Fraction(-25), Fraction(-50))
    assert paper_design.certificate()["spectrum of A0 − G0 C0"].ok


def test_paper_example_default_design_beats_the_paper():
    des = design_zheng_bejarano(P.system())
    assert des.certificate().ok
    assert des.n_z == 6
    assert des.lag < 4  # the paper's T_L⁻¹ has degree 4
    assert des.lag == des.T_left_inverse.degree() or des.lag == 0


def test_paper_example_without_search_is_the_papers_shape():
    des = design_zheng_bejarano(P.system(), search=False)
    assert des.certificate().ok
    assert (des.r, des.l_star, des.n_z) == (2, 3, 6)


def test_paper_choices_reproduce_the_printed_matrices(paper_choices):
    d = paper_choices
    assert d.certificate().ok, str(d.certificate())
    assert d.W == P.W and d.A_bar == P.A_BAR and d.C_tilde == P.C_TILDE
    assert d.C_bar == P.C_BAR and d.O == P.O3 and d.F_stack == P.F and d.T == P.T
    assert PolyMatrix.hstack(d.K1_bar, d.K2_bar) == P.K_BAR
    assert PolyMatrix.hstack(d.Gamma1_bar, d.Gamma2_bar) == P.GAMMA_BAR
    assert d.H == P.H and d.L0 == P.L0 and d.G0 == P.G0
    assert d.lag == 4


def test_paper_J_printed_is_wrong_and_corrected_J_is_right(paper_choices):
    assert paper_choices.J == P.J_CORRECTED
    assert paper_choices.J != P.J_PRINTED
    diff = paper_choices.J - P.J_PRINTED
    nonzero = [(i, j) for i in range(6) for j in range(3) if not diff[i, j].is_zero()]
    assert nonzero == [(4, 2), (5, 2)]  # J(5,3) and J(6,3), 1-based


def test_design_with_printed_J_fails_theorem_4(paper_choices):
    bad = dataclasses.replace(paper_choices, J=P.J_PRINTED)
    cert = bad.certificate()
    assert not cert.ok
    check = cert[THM4]
    assert not check.ok
    # the error is driven by the unknown input: the w-coefficient is nonzero
    assert "w" in check.residual and not check.residual["w"].is_zero()


# -- poles -------------------------------------------------------------------------------
def test_default_poles():
    """Default: l* poles at −⌈‖A(1)‖∞⌉ (= −4 on the paper's example: its A(1) has row sums
    2, 2, 2, 4), or at −rate when a rate is given."""
    des = design_zheng_bejarano(P.system())
    assert des.poles == (Fraction(-4),) * des.l_star
    des = design_zheng_bejarano(P.system(), rate="5/2")
    assert des.poles == (Fraction(-5, 2),) * des.l_star and des.certificate().ok


def test_repeated_and_decimal_poles():
    des = design_zheng_bejarano(P.system(), poles=["-0.5", "-0.5", -3])
    assert des.poles == (Fraction(-1, 2), Fraction(-1, 2), Fraction(-3))
    assert des.certificate().ok


@pytest.mark.parametrize("poles", [[-1], [-1, -2, -3, -4]])
def test_wrong_number_of_poles_names_l_star(poles):
    with pytest.raises(DimensionError, match=r"expected l\* = "):
        design_zheng_bejarano(P.system(), poles=poles)


def test_non_rational_pole():
    with pytest.raises(DomainError):
        design_zheng_bejarano(P.system(), poles=["sqrt(2)", -1, -2])


def test_unstable_poles_fail_the_hurwitz_check():
    des = design_zheng_bejarano(P.system(), poles=[1, -1, -2])
    cert = des.certificate()
    assert not cert.ok and [c.name for c in cert.failed] == ["A0 − G0 C0 Hurwitz"]


# -- the δ-degree-0 case ----------------------------------------------------------------------
def test_paper_example_at_delta_zero():
    sys0 = P.system().at_delta(0)
    rep = check_assumptions(sys0)
    assert rep.holds  # checked first: both assumptions hold for the δ = 0 system
    des = design_zheng_bejarano(sys0, poles=[-1, -2, -3])
    assert des.certificate().ok
    assert des.lag == 0 and des.T_left_inverse.degree() <= 0
    assert all(getattr(des, name).degree() <= 0 for name in ("L0", "H", "J", "Lam", "T"))


def test_delay_free_hautus_type_observer():
    # strongly observable, rank condition (3): x1' = x2, x2' = x1 + x3, x3' = −x3 + w;
    # y = (x1, x3).  y ≡ 0 forces x1 = x2 = 0, then x3 = 0 and w = 0.
    sys = DelaySystem("[[0, 1, 0], [1, 0, 1], [0, 0, -1]]", "[[0], [0], [1]]",
                      "[[1, 0, 0], [0, 0, 1]]", None)
    rep = check_assumptions(sys)
    assert rep.holds
    assert rep.rank_condition.hautus_rank_condition
    des = design_zheng_bejarano(sys)
    assert des.certificate().ok and des.lag == 0
    # Hautus form ξ' = P ξ + Q y, x̂ = T_L⁻¹ (ξ + K y): everything constant
    assert all(getattr(des, n).degree() <= 0 for n in ("L0", "J", "H", "T_left_inverse"))


def test_paper_003_refused_naming_assumption_2():
    from analysis.paper003 import system

    with pytest.raises(NotObservableError, match="Assumption 2") as info:
        design_zheng_bejarano(system())
    report = info.value.report
    assert "Assumption 2" in report.failed
    assert not report.rank_condition.holds


# -- known inputs ------------------------------------------------------------------------------
def test_known_input_terms_certified():
    s = P.system()
    sys = DelaySystem(s.A, s.B, s.C, s.D, E="[[1], [0], [d], [0]]", F="[[0], [1], [d]]")
    des = design_zheng_bejarano(sys)
    cert = des.certificate()
    assert cert.ok, str(cert)
    assert not des.J_u.is_zero() and des.H_u.shape == (des.n_z, 1)


# -- the object ----------------------------------------------------------------------------------
def test_attribute_names(paper_design):
    names = ("U V Vbar W K Gamma K1 K2 Gamma1 Gamma2 A_bar C_tilde Lam C_bar r l_star O "
             "O_left_inverse F_stack T T_left_inverse A0 C0 K1_bar K2_bar Gamma1_bar Gamma2_bar G0 L0 "
             "H J n_z lag").split()
    for name in names:
        assert hasattr(paper_design, name), name
    assert is_unimodular(paper_design.Lam) and is_unimodular(paper_design.U)


def test_display_and_dict(paper_design):
    assert "n_z = 6" in str(paper_design)
    assert repr(paper_design).startswith("DelayUIODesign(n_z=6")
    assert paper_design._repr_latex_().startswith("$$") and r"\delta" in paper_design._repr_latex_()
    data = paper_design.to_dict()
    json.dumps(data)
    assert data["n_z"] == 6 and data["matrices"]["L0"][0][0] == "-85"


def test_not_a_system():
    with pytest.raises(DomainError):
        design_zheng_bejarano("A")  # type: ignore[arg-type]


# -- random systems --------------------------------------------------------------------------------
@st.composite
def generic_systems(draw):
    """Small systems with δ anywhere: most are refused (non-unit invariant factors)."""
    n = draw(st.integers(1, 4))
    m = draw(st.integers(1, 2))
    p = draw(st.integers(m, m + 1))
    dense = st.sampled_from(["0", "1", "-1", "2", "d", "d + 1", "-d", "1 - d"])
    sparse = st.sampled_from(["0", "0", "0", "1", "d", "-1"])

    def mat(r, c, s):
        return [[draw(s) for _ in range(c)] for _ in range(r)]

    return DelaySystem(mat(n, n, dense), mat(n, m, dense), mat(p, n, dense), mat(p, m, sparse))


@st.composite
def state_delay_systems(draw):
    """Delays in A only, constant B, C, D: about a third satisfy both assumptions."""
    n = draw(st.integers(2, 4))
    m = draw(st.integers(1, 2))
    p = m + 1
    poly = st.sampled_from(["0", "0", "1", "-1", "d", "-d", "1 - d", "d**2"])
    const = st.sampled_from([0, 0, 1, -1, 2])

    def mat(r, c, s):
        return [[draw(s) for _ in range(c)] for _ in range(r)]

    D = mat(p, m, st.sampled_from([0, 0, 0, 1]))
    if draw(st.booleans()):  # a known input u with delays in E and F
        return DelaySystem(mat(n, n, poly), mat(n, m, const), mat(p, n, const), D,
                           E=mat(n, 1, poly), F=mat(p, 1, poly))
    return DelaySystem(mat(n, n, poly), mat(n, m, const), mat(p, n, const), D)


random_systems = st.one_of(generic_systems(), state_delay_systems())


def _independently_confirmed(sys, report) -> bool:
    """Confirm a refusal with sympy only (determinantal divisors, V* at generic points)."""
    from independent import determinantal_factors, system_at, weakly_unobservable_dim

    ok = False
    if "Assumption 2" in report.failed:
        rc = report.rank_condition
        ok |= determinantal_factors(rc.M) != determinantal_factors(rc.M_with_B)
    if "Assumption 1" in report.failed:
        obs = report.observability
        if obs.rank < sys.n_x:
            dims = [weakly_unobservable_dim(*system_at(sys, v)) for v in (sympy.Rational(7, 3), sympy.Rational(-11, 5), 13)]
            ok |= min(dims) > 0
        else:
            facs = determinantal_factors(obs.N[obs.k_star])
            ok |= len(facs) == sys.n_x and any(f.degree() > 0 for f in facs)
    return ok


@settings(max_examples=60)
@given(random_systems)
def test_random_systems_certified_or_refused_for_a_reason(sys):
    try:
        des = design_zheng_bejarano(sys)
    except NotObservableError as exc:
        assert exc.report.failed, "a refusal must name a failed assumption"
        assert _independently_confirmed(sys, exc.report), str(exc.report)
        return
    cert = des.certificate()
    assert cert.ok, str(cert)
    assert des.n_z == des.r * des.l_star >= sys.n_x
    # the search reads Ō's left inverse off one solve with F: it is the ring's (unique) reduced one
    from uio_ring.ring import left_inverse

    assert des.O_left_inverse == left_inverse(des.O)
    # the check's preview proves Ō left unimodular by its minors instead of solving: same orders
    n_z, l_options = smallest_observer_orders(sys)
    assert n_z == des.n_z and des.l_star in l_options


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_observability_index_proved_by_minors_equals_the_solve(seed):
    """Random 4-state systems of δ-degree 2 with 3 outputs (the shape where X·Ō = [I; C̄Ā^l]
    is far larger than the proof): the least l by the minors equals the least l by the solve,
    and the proof leaves the solve out."""
    import random

    from uio_ring.design.zheng_bejarano import _candidate_Us, _observability_index, _steps_1_2
    from uio_ring.ring import hermite

    rng = random.Random(seed)

    def mat(r, c):
        return [[" + ".join(f"{rng.randint(-3, 3)}*d**{e}" for e in range(3)) for _ in range(c)] for _ in range(r)]

    sys = DelaySystem(mat(4, 4), mat(4, 1), mat(3, 4), [[0]] * 3)
    if not check_assumptions(sys).holds:
        pytest.skip("this seed's system has no UIO")  # pragma: no cover - seeds 1–3 have one
    rho, Us = _candidate_Us(sys)
    for _, U in Us:
        s12 = _steps_1_2(sys, U, rho)
        r = s12.C_tilde.rank()
        C_bar = hermite(s12.C_tilde).H[0:r, 0:4]
        proved = _observability_index(s12.A_bar, C_bar, 4, solve=False)
        solved = _observability_index(s12.A_bar, C_bar, 4)
        assert proved.l_star == solved.l_star and proved.O == solved.O
        assert proved.solved is None and solved.solved is not None


@pytest.mark.parametrize("solve", [True, False])
def test_observability_index_skips_a_square_obar_whose_det_is_not_constant(monkeypatch, solve):
    """Ō_1 = C̄ = diag(1, δ + 1) is square with det of degree 1 (modulo a prime too): it has
    no inverse, so neither the solve nor the minors run on it (an 8-state system with 8
    outputs at δ-degree 8: an 8×8 Ō of degree 64, 18 s of solve to learn it); Ō_2 is left
    unimodular."""
    import uio_ring.design.zheng_bejarano as zb
    from uio_ring import _progress

    shapes = []
    solve_left, proved = zb.solve_left, zb.left_unimodular_proved

    def spy_solve(V, W):
        shapes.append(V.shape)
        return solve_left(V, W)

    def spy_proof(a, m, n, **kw):
        shapes.append((m, n))
        assert _progress.current().startswith("Zheng et al. (2015) step 3, l = 2: proving Ō left unimodular")
        return proved(a, m, n, **kw)

    monkeypatch.setattr(zb, "solve_left", spy_solve)
    monkeypatch.setattr(zb, "left_unimodular_proved", spy_proof)
    index = zb._observability_index(PolyMatrix("[[0, 1], [1, 0]]"), PolyMatrix("[[1, 0], [0, d + 1]]"), 2,
                                    solve=solve)
    assert index.l_star == 2 and index.O.shape == (4, 2)
    assert shapes and all(s == (4, 2) for s in shapes)


def test_observability_solve_grows_its_degree_bound_instead_of_eliminating(monkeypatch):
    """An 8-state system with 7 outputs (δ-degree 2): the reduced solution of
    X·Ō = [I; C̄Ā^l] (Ō 14×8 of δ-degree 20) has degree 28, beyond the three degree bounds
    solve_left tries for a system that may have no solution.  Ō is proved left unimodular,
    so the bounds keep growing (0.6 s); the elimination it used to fall into swelled for
    100 s.  The elimination is made to fail here: the solve must not reach it."""
    import random

    import uio_ring.ring.solve as solve_module
    from uio_ring.design.zheng_bejarano import _candidate_Us, _observability_index, _steps_1_2
    from uio_ring.ring import hermite

    rng = random.Random(1)

    def mat(r, c):
        return [[" + ".join(f"{rng.randint(-3, 3)}*d**{e}" for e in range(3)) for _ in range(c)] for _ in range(r)]

    sys = DelaySystem(mat(8, 8), mat(8, 1), mat(7, 8), [[0]] * 7)
    rho, Us = _candidate_Us(sys)
    s12 = _steps_1_2(sys, Us[0][1], rho)
    r = s12.C_tilde.rank()
    C_bar = hermite(s12.C_tilde).H[0:r, 0:8]

    def refuse(*args, **kwargs):
        raise AssertionError("solve_left fell back to the elimination")

    monkeypatch.setattr(solve_module, "row_echelon", refuse)
    index = _observability_index(s12.A_bar, C_bar, 8)
    assert index is not None and index.O.shape == (14, 8)
    assert index.solved @ index.O == PolyMatrix.vstack(PolyMatrix.identity(8), index.next_block)


def test_step_1_names_its_hermite_forms_while_they_run(monkeypatch):
    """The check's heartbeat says what is taking long: during step 1's Hermite forms the
    progress note names the matrix and its size."""
    import uio_ring.design.zheng_bejarano as zb
    from uio_ring import _progress

    notes = []
    hermite = zb.hermite

    def spy(M):
        notes.append(_progress.current())
        return hermite(M)

    monkeypatch.setattr(zb, "hermite", spy)
    sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)
    zb._candidate_Us(sys)
    assert notes[0].startswith("Zheng et al. (2015) step 1: the Hermite form of M, 4×2 of δ-degree")
    assert _progress.current() == ""


def test_step_1_skips_the_second_hermite_form_when_no_move_is_tried(monkeypatch):
    """With D = 0 the Γ-part of V̄ is zero, and moves through its K-part are tried only for
    small systems (n_x·δ-degree ≤ 12): then no move exists, and the Hermite form of the
    w-free rows of U0 times [CA; C], whose only use is the moves, is not computed (an
    8-state spec with 8 outputs at δ-degree 16: 47 s of a 2-minute check)."""
    import uio_ring.design.zheng_bejarano as zb

    shapes = []
    hermite = zb.hermite

    def spy(M):
        shapes.append(M.shape)
        return hermite(M)

    monkeypatch.setattr(zb, "hermite", spy)
    sys = DelaySystem("[[0, d**7], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)
    rho, Us = zb._candidate_Us(sys)
    assert shapes == [zb.matching_matrix(sys).shape]  # the Hermite form of M only
    assert rho == 1 and [label for label, _ in Us] == ["U = Hermite transform of M"]
