"""Observer normal form of paper 000 (uio_ring.design.normal_form): exact values of the
aircraft example (exact reproduction of the printed values), the augmented design (§3.9), the paper-001 cross case
(§5.4), general properties on random systems (§4 item 18), refusals."""

from __future__ import annotations

import random
from fractions import Fraction as Fr

import pytest
import sympy

from design import paper000, paper001
from uio_ring import (
    DelaySystem,
    NormalFormDesign,
    check_assumptions,
    design_normal_form,
    design_zheng_bejarano,
    levant_gains,
    normal_form_applicable,
    normal_form_chain_lengths,
)
from uio_ring.errors import DimensionError, DomainError, NotObservableError
from uio_ring.verify.delay_uio import charpoly


def _q(M):
    return M.coefficient_lists()[0] if M.rows and M.cols else []


@pytest.fixture(scope="module")
def aircraft_design() -> NormalFormDesign:
    return design_normal_form(paper000.aircraft(), ["0.02"])


@pytest.fixture(scope="module")
def augmented_design() -> NormalFormDesign:
    return design_normal_form(paper000.aircraft(), ["0.046"], reconstruct_input=True, lipschitz=["122.65716", 10])


# ---------------------------------------------------------------------------- aircraft, exact
def test_aircraft_step1(aircraft_design):
    d = aircraft_design
    trace = [(t.j, t.case) for t in d.trace]
    assert trace == [(1, "2/2.2"), (2, "2/2.2"), (1, "2/2.2"), (2, "2/2.2"), (1, "1"), (2, "2/2.2"), (2, "2/2.1")]
    assert d.trace[5].zeta == (Fr(1900, 7017), 0)  # ζ_{2,3,1} (62)
    assert d.trace[6].zeta == (Fr(164619502, 82063815), 0)  # ζ_{2,4,1} (66)
    assert d.nu == (3, 4) and d.mu == (4, 3) and d.order == (2, 1)
    assert _q(d.Gamma) == paper000.GAMMA
    Xi = _q(d.Xi)
    assert Xi[4][0] == paper000.XI_51
    assert all(Xi[i][j] == 0 for i in range(7) for j in range(2) if (i, j) != (4, 0))


def test_aircraft_T_A_bar_E_bar(aircraft_design):
    d = aircraft_design
    assert _q(d.T) == [[Fr(x) for x in r] for r in paper000.T]
    A = _q(d.A_bar)
    assert [A[i][0] for i in range(7)] == paper000.ALPHA_1
    assert [A[i][4] for i in range(7)] == paper000.ALPHA_5
    assert d.beta == {(1, 2, 3): paper000.BETA_123}  # β_{1,2,1} = β_{1,2,2} = 0 by (53)
    assert A[6][3] == paper000.BETA_123
    assert _q(d.E_bar) == [[Fr(x) for x in r] for r in paper000.E_BAR]
    assert _q(d.B_bar) == [[0]] * 6 + [[Fr(-7017, 10)]]
    assert _q(d.C_bar) == [[1, 0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 1, 0, 0]]
    # T⁻¹ rows 1 and 5 are č_1, č_2
    Ti = _q(d.T_inverse)
    assert Ti[0] == [0, Fr(-1900, 7017), 0, 0, 1, 0, 0] and Ti[4] == [0, 1, 0, 0, 0, 0, 0]
    # Ā and A have the same characteristic polynomial; Ā − Π̄C̄ nilpotent
    assert charpoly(d.A_bar) == charpoly(d.model.A)
    assert ((d.A_bar - d.Pi_bar @ d.C_bar) ** 7).is_zero()


def test_aircraft_certificate_and_gains(aircraft_design):
    d = aircraft_design
    cert = d.certificate()
    assert cert.ok, str(cert)
    assert len(cert) >= 19
    # default gains = (89) to the printed 4 decimals (L = 10 and 8·14.034)
    assert d.lipschitz == (10, Fr("112.272"))
    for ks, printed in zip(d.kappa, paper000.GAINS_89, strict=True):
        assert all(abs(k - Fr(p)) <= Fr(6, 100000) for k, p in zip(ks, printed, strict=True))
    # (18): κ_{2,0} = 123.4992 > L|d̄_7| = 14.034 (exact); chain 1 has no input
    assert d.condition_18() == ((11, 0), (Fr("123.4992"), Fr("14.034")))
    assert d.b_bar_rows() == ((0,), (Fr(-7017, 10),))


def test_aircraft_data_and_display(aircraft_design):
    d = aircraft_design
    data = d.to_dict()
    assert data["mu"] == [4, 3] and data["beta"] == {"1,2,3": str(paper000.BETA_123)}
    assert "mu=(4, 3)" in repr(d) and "A_bar" in str(d) and d.to_latex().startswith(r"\dot")


def test_augmented_design(augmented_design):
    d = augmented_design
    assert d.mu == (4, 4) and d.nu == (4, 4) and d.order == (1, 2)  # stable sort (94)
    assert _q(d.Gamma) == [[1, 0], [Fr(-1900, 7017), 1]]
    assert d.Xi.is_zero() and d.beta == {}
    A = _q(d.A_bar)
    assert A[3][0] == Fr(-338379273, 17060800) and A[7][0] == Fr(6213, 4678)
    assert A[0][0] == Fr(-208617, 11695)  # −17.8381 in (94)
    assert _q(d.B_bar) == [[0]] * 3 + [[Fr(-7017, 10)]] + [[0]] * 4
    # (95) to the printed decimals with L = 3.8·32.2782 and 10
    for ks, printed in zip(d.kappa, paper000.GAINS_95, strict=True):
        assert all(abs(k - Fr(p)) <= Fr(6, 100000) for k, p in zip(ks, printed, strict=True))
    assert d.condition_18()[0][1] == Fr("32.2782")
    assert d.w_map is not None and d.certificate().ok


def test_printed_gains_accepted_and_violations_refused():
    sys = paper000.aircraft()
    d = design_normal_form(sys, ["0.02"], gains=paper000.GAINS_89)
    assert d.kappa[1][-1] == Fr("123.4992")
    bad = [paper000.GAINS_89[0], ["9.6484", "49.369", "14"]]  # κ_{2,0} = 14 ≤ 14.034
    with pytest.raises(DomainError, match=r"\(18\).*14\.034"):
        design_normal_form(sys, ["0.02"], gains=bad)
    with pytest.raises(DimensionError, match="chain 2 has length 3"):
        design_normal_form(sys, ["0.02"], gains=[paper000.GAINS_89[0], ["1", "2"]])
    with pytest.raises(DimensionError, match="input_bounds has 2 entries; expected 1"):
        design_normal_form(sys, [1, 2])


def test_levant_gains_reproduce_89_and_95():
    for mu, L, printed in [(4, 10, paper000.GAINS_89[0]), (3, "112.272", paper000.GAINS_89[1]),
                           (4, "122.65716", paper000.GAINS_95[0])]:
        ks = levant_gains(mu, L)
        assert all(abs(k - Fr(p)) <= Fr(6, 100000) for k, p in zip(ks, printed, strict=True))
    assert levant_gains(1, 3) == (Fr("3.3"),)
    with pytest.raises(DomainError):
        levant_gains(9, 1)


# ---------------------------------------------------------------------------- paper 001 refuses, this method applies
def test_zheng_bejarano_refuses_aircraft_normal_form_applies():
    sys = paper000.aircraft(known_input=False)
    a = check_assumptions(sys)
    assert a.observability.holds and not a.rank_condition.holds  # strongly observable, CD = 0
    with pytest.raises(NotObservableError):
        design_zheng_bejarano(sys)
    rep = normal_form_applicable(sys)
    assert rep.holds and "applies" in rep.summary and "matching condition fails" in rep.summary
    assert rep.to_dict()["matching_condition"] is False


# ---------------------------------------------------------------------------- paper 001's example at δ = 0 (cross-check case)
def test_paper001_at_delta_zero_with_feedthrough():
    sys = paper001.system().at_delta(0)
    d = design_normal_form(sys, [1, 1])
    assert d.rank_D == 1 and d.mu == (3, 1) and d.nu == (3, 1)
    assert _q(d.Gamma) == [[1, 0], [0, 1]]
    assert _q(d.Xi) == [[0, -1], [0, 0], [0, 0], [0, 0]]
    assert d.beta == {(1, 2, 1): 5, (1, 2, 2): -3}
    assert _q(d.T) == [[2, -1, 0, 0], [1, 0, 0, 0], [-4, 2, -1, 1], [4, -2, 1, 0]]
    assert _q(d.A_bar) == [[-2, 1, 0, 0], [1, 0, 1, -1], [3, 0, 0, -1], [-9, 5, -3, 2]]
    assert _q(d.B_bar) == [[0], [0], [0], [1]]
    assert _q(d.C_bar) == [[1, 0, 0, 0], [0, 0, 0, 1]]
    cert = d.certificate()
    assert cert.ok and cert["(A1) U D V"].ok and cert["plant ↔ normal form"].ok


# ---------------------------------------------------------------------------- refusals
def test_refusals_carry_the_report():
    with pytest.raises(NotObservableError, match="invariant zero") as exc:
        design_normal_form(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[0, 1]]", None), [1])
    assert not exc.value.report.holds
    with pytest.raises(NotObservableError, match="delays"):
        design_normal_form(DelaySystem("[[d]]", "[[1]]", "[[1]]", None), [1])
    with pytest.raises(NotObservableError, match="dependent"):
        design_normal_form(DelaySystem("[[0, 1], [0, 0]]", "[[0, 0], [1, 1]]", "[[1, 0]]", None), [1, 1])


# ---------------------------------------------------------------------------- general properties
def _random_so_system(rng: random.Random, n: int, m: int, p: int, feedthrough: bool = False) -> DelaySystem:
    while True:
        A = [[rng.randint(-3, 3) for _ in range(n)] for _ in range(n)]
        B = [[rng.randint(-2, 2) for _ in range(m)] for _ in range(n)]
        C = [[rng.randint(-2, 2) if rng.random() < 0.7 else 0 for _ in range(n)] for _ in range(p)]
        D = [[rng.randint(-1, 1) if rng.random() < 0.4 else 0 for _ in range(m)] for _ in range(p)] if feedthrough else None
        E = [[rng.randint(-1, 1)] for _ in range(n)]
        sys = DelaySystem(A, B, C, D, E=E)
        if normal_form_applicable(sys).holds:
            return sys


@pytest.mark.parametrize("seed", range(12))
def test_random_systems_certificate(seed):
    rng = random.Random(seed)
    n, m = rng.randint(2, 6), rng.randint(1, 2)
    p = rng.randint(m + (1 if rng.random() < 0.5 else 0), m + 2)
    sys = _random_so_system(rng, n, m, p, feedthrough=seed % 3 == 0)
    d = design_normal_form(sys, [1] * m)
    cert = d.certificate()
    assert cert.ok, str(cert)
    assert sum(d.mu) == d.n
    if sys.D.is_zero():
        assert d.mu == normal_form_chain_lengths(sys)  # claim 19: μ is a system invariant
    # (B23): d̄_{e_j} = č_j Ǎ^{μ_j−1} B
    for j, mu in enumerate(d.mu if d.model.B.cols else ()):
        r = d.C_check[j : j + 1, 0 : d.n] @ (d.A_check ** (mu - 1)) @ d.model.B
        assert tuple(_q(r)[0]) == d.b_bar_rows()[j]
    # (B31): č_{j̄} t_{e_j − i} = 1 iff j̄ = j and i = μ_j − 1
    CT = _q(d.C_check @ d.T)
    for jb in range(d.p):
        for j, (start, mu) in enumerate(zip(d.block_starts, d.mu, strict=True)):
            for c in range(start, start + mu):
                assert CT[jb][c] == (1 if (jb == j and c == start) else 0)


def test_single_output_gives_companion_form():
    """Remark 3.1: p = 1 gives the transposed observable canonical form."""
    rng = random.Random(3)
    n = 5
    # relative degree n (no zeros): upper Hessenberg A with unit superdiagonal, B = e_n, C = e_1,
    # hidden by a random unimodular change of coordinates x = S z
    H = sympy.Matrix(n, n, lambda i, j: 1 if j == i + 1 else (rng.randint(-3, 3) if j <= i else 0))
    S = sympy.Matrix(n, n, lambda i, j: 1 if i == j else (rng.randint(-2, 2) if j < i else 0))
    A, B, C = S * H * S.inv(), S * sympy.Matrix([0] * (n - 1) + [1]), sympy.Matrix([[1] + [0] * (n - 1)]) * S.inv()
    sys = DelaySystem(A.tolist(), B.tolist(), C.tolist(), None)
    d = design_normal_form(sys, [1])
    assert d.mu == (n,) and d.certificate().ok
    cp = charpoly(sys.A).coeffs()  # a_0 … a_{n−1}, 1
    assert [row[0] for row in _q(d.A_bar)] == [-c for c in reversed(cp[:-1])]


def test_design_is_exact_on_an_ill_conditioned_chain():
    """A long chain with large ζ: float64 rank decisions break here (docs/errata.md, N5); exact does not."""
    n = 8
    A = [[1 if j == i + 1 else 0 for j in range(n)] for i in range(n)]
    A[n - 1] = [(-1) ** k * (k + 3) ** 3 for k in range(n)]
    B = [[0]] * (n - 1) + [[1]]
    C = [[1] + [0] * (n - 1), [0, 0, 0, 1000, 0, 0, 0, 0]]
    d = design_normal_form(DelaySystem(A, B, C, None), ["1/1000"])
    assert d.certificate().ok and sum(d.mu) == n
