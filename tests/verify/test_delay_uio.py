"""The certificate of a delay UIO (uio_ring.verify.delay_uio): it passes on good
designs and each check catches its own kind of damage."""

from __future__ import annotations

import dataclasses

import pytest
from design import paper001 as P

from uio_ring import Certificate, PolyMatrix, design_zheng_bejarano
from uio_ring.verify import Check, delay_uio_certificate
from uio_ring.verify.delay_uio import charpoly

NAMES = [
    "Step 1: U M = [V; 0]",
    "Lemma 2(1): W M = [[B, 0], [D, 0]]",
    "Lemma 2(2): annihilators of [B; D] annihilate W",
    "Step 2: Ā and C̃",
    "(9): Λ C̃ = [C̄; 0]",
    "(12): Ō_{l*} left unimodular",
    "Theorem 2: T Ā = A0 T + F C̄",
    "Theorem 2: C0 T = C̄",
    "(15): T_L⁻¹ T = I",
    "(11), (20): Γ̄i and K̄i",
    "(19′) state equation",
    "(19′) output equation",
    "(22′): L0, H, J",
    "Theorem 4: e' − L0 e = 0",
    "spectrum of A0 − G0 C0",
    "A0 − G0 C0 Hurwitz",
]


@pytest.fixture(scope="module")
def design():
    return design_zheng_bejarano(P.system())


def test_all_named_checks_hold(design):
    cert = delay_uio_certificate(design)
    assert isinstance(cert, Certificate) and all(isinstance(c, Check) for c in cert)
    assert cert.names() == NAMES
    assert cert.ok and cert.failed == ()
    assert all(c.statement for c in cert)
    assert cert.to_dict()["ok"] is True


def _unit(rows, cols, i, j):
    return PolyMatrix([[1 if (a, b) == (i, j) else 0 for b in range(cols)] for a in range(rows)])


def _failed(design, **changes):
    return [c.name for c in delay_uio_certificate(dataclasses.replace(design, **changes)).failed]


def test_wrong_left_inverse_of_T(design):
    bad = design.T_left_inverse + _unit(4, design.n_z, 0, 0)
    assert _failed(design, T_left_inverse=bad) == ["(15): T_L⁻¹ T = I"]


def test_non_unimodular_U_and_Lambda(design):
    U2 = PolyMatrix.diag("d", 1, 1, 1, 1, 1) @ design.U
    assert "Step 1: U M = [V; 0]" in _failed(design, U=U2)
    Lam = design.Lam @ PolyMatrix.diag("d + 1", 1, 1)
    assert "(9): Λ C̃ = [C̄; 0]" in _failed(design, Lam=Lam)


def test_wrong_H_breaks_22_and_theorem_4(design):
    H = design.H + _unit(design.n_z, 3, 0, 1)
    failed = _failed(design, H=H)
    assert "(22′): L0, H, J" in failed and "Theorem 4: e' − L0 e = 0" in failed


def test_wrong_F_breaks_theorem_2(design):
    F = design.F_stack + _unit(design.n_z, design.r, 0, 0)
    assert "Theorem 2: T Ā = A0 T + F C̄" in _failed(design, F_stack=F)


def test_shape_errors_become_failed_checks(design):
    cert = delay_uio_certificate(dataclasses.replace(design, O_left_inverse=PolyMatrix("[[1]]")))
    check = cert["(12): Ō_{l*} left unimodular"]
    assert not check.ok and "DimensionError" in str(check.residual)


def test_spectrum_check_compares_polynomials(design):
    cert = delay_uio_certificate(dataclasses.replace(design, poles=tuple(p - 1 for p in design.poles)))
    assert [c.name for c in cert.failed] == ["spectrum of A0 − G0 C0"]


def test_charpoly():
    assert str(charpoly(PolyMatrix("[[0, 1], [-2, -3]]"))) == "s**2 + 3*s + 2"
    assert str(charpoly(PolyMatrix.zeros(0, 0))) == "1"


@pytest.mark.parametrize("block", ["first", "middle", "last"])
def test_a_changed_block_of_O_fails_12(design, block):
    """Ō is checked block by block (first block C̄, each next one the one before times Ā):
    a change in any block is caught."""
    r, rows = design.C_bar.rows, design.O.rows
    i = {"first": 0, "middle": r * (design.l_star // 2), "last": rows - 1}[block]
    O = design.O + _unit(rows, design.O.cols, i, 1)
    assert "(12): Ō_{l*} left unimodular" in _failed(design, O=O)


def test_O_with_a_missing_block_fails_12(design):
    r = design.C_bar.rows
    O = design.O[: design.O.rows - r, :]
    cert = delay_uio_certificate(dataclasses.replace(design, O=O))
    assert not cert["(12): Ō_{l*} left unimodular"].ok


def test_a_left_inverse_that_is_not_one_fails_12(design):
    """Ō_L⁻¹ Ō = I is the proof that Ō is left unimodular: a changed Ō_L⁻¹ is caught."""
    X = design.O_left_inverse + _unit(design.O_left_inverse.rows, design.O_left_inverse.cols, 0, 0)
    assert "(12): Ō_{l*} left unimodular" in _failed(design, O_left_inverse=X)
