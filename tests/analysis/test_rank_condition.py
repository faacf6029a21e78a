"""Assumption 2 (uio_ring.analysis.rank_condition) and the combined report."""

from __future__ import annotations

from design import paper001
from hypothesis import given
from independent import determinantal_factors, factors_as_sympy, to_sympy

from uio_ring import DelaySystem, PolyMatrix, check_assumptions, check_rank_condition

from .paper003 import system as paper003_system
from .test_observability import constant_systems, delay_systems


def test_paper_example_factors_one_one_one_twice():
    rep = check_rank_condition(paper001.system())
    assert rep.holds
    assert [str(f) for f in rep.factors_with_B] == ["1", "1", "1"]
    assert [str(f) for f in rep.factors_without_B] == ["1", "1", "1"]
    assert rep.rank_M == 3 and rep.rank_BD == 2 and rep.rank_D == 1
    assert rep.hautus_rank_condition


def test_paper_003_fails_cb_is_zero():
    rep = check_rank_condition(paper003_system())
    assert not rep.holds
    assert rep.factors_without_B == () and len(rep.factors_with_B) == 2
    assert "relative degree above one" in rep.reason


def test_same_rank_different_factors_is_non_causal():
    # y = δ x, x' = w: w = ẏ(t + h) would need the future
    rep = check_rank_condition(DelaySystem("[[0]]", "[[1]]", "[[d]]", None))
    assert not rep.holds and rep.rank_M == 1
    assert "non-causal" in rep.reason


def test_report_display_and_dict():
    rep = check_rank_condition(paper001.system())
    assert "Assumption 2" in str(rep) and "{1, 1, 1}" in str(rep)
    assert rep._repr_latex_().startswith("$$") and "Inv" in rep._repr_html_()
    assert rep.to_dict()["factors_with_B"] == ["1", "1", "1"]


def test_combined_report_names_failures():
    rep = check_assumptions(paper003_system())
    assert not rep.holds and rep.failed == ("Assumption 1", "Assumption 2")
    assert "Assumption 2 fails" in rep.reason
    ok = check_assumptions(paper001.system())
    assert ok.holds and ok.failed == () and ok.to_dict()["holds"] is True


@given(constant_systems())
def test_delay_free_is_hautus_rank_condition(sys):
    """Remark 2: for constant matrices (6) ⇔ rank [M; [B,0]] = rank M = rank [B; D] + rank D."""
    rep = check_rank_condition(sys)
    B, C, D = (to_sympy(X) for X in (sys.B, sys.C, sys.D))
    import sympy

    M = sympy.Matrix(sympy.BlockMatrix([[C * B, D], [D, sympy.zeros(*D.shape)]]))
    MB = M.col_join(B.row_join(sympy.zeros(*B.shape)))
    expected = MB.rank() == M.rank() == B.col_join(D).rank() + D.rank()
    assert rep.holds == expected


@given(delay_systems())
def test_factors_agree_with_determinantal_divisors(sys):
    rep = check_rank_condition(sys)
    assert factors_as_sympy(rep.factors_without_B) == determinantal_factors(rep.M)
    assert factors_as_sympy(rep.factors_with_B) == determinantal_factors(rep.M_with_B)


def test_matching_matrix_shape():
    from uio_ring.analysis import matching_matrix

    assert matching_matrix(paper001.system()).shape == (6, 4)
    assert matching_matrix(paper001.system()) == PolyMatrix.block(
        [[paper001.system().C @ paper001.system().B, paper001.system().D],
         [paper001.system().D, PolyMatrix.zeros(3, 2)]]
    )


@given(delay_systems())
def test_factors_without_d_agree_with_determinantal_divisors(sys):
    # D = 0: the matrices of (6) have zero columns, which the check drops before the Smith form
    sys = DelaySystem(sys.A, sys.B, sys.C, None)
    rep = check_rank_condition(sys)
    assert factors_as_sympy(rep.factors_without_B) == determinantal_factors(rep.M)
    assert factors_as_sympy(rep.factors_with_B) == determinantal_factors(rep.M_with_B)
