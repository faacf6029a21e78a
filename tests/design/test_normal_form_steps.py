"""The step functions of the observer normal form (uio_ring.design.normal_form), one by one:
the invariants of Step 1, (B4) for Step 2, det H^(j) = 1 (Lemma 4.1(c)) for Step 3,
T nonsingular for any β (Lemma 4.1(b)) for Step 4, and (A1) for the model."""

from __future__ import annotations

import dataclasses
import random
from fractions import Fraction as Fr

import pytest

from design import paper000
from uio_ring import DelaySystem, normal_form_applicable
from uio_ring.analysis.chain_basis import chain_basis
from uio_ring.analysis.chain_couplings import coupling_coefficients
from uio_ring.design.normal_form.model import feedthrough_split, reduced_model
from uio_ring.design.normal_form.step1 import output_chains
from uio_ring.design.normal_form.step4 import normal_form
from uio_ring.ring import QMatrix


def _steps(sys: DelaySystem, **kw):
    model = reduced_model(sys, **kw)
    chains = output_chains(model.A, model.B, model.C)
    basis = chain_basis(chains.A_check, chains.C_check, chains.mu)
    couplings = coupling_coefficients(basis)
    return model, chains, basis, couplings, normal_form(model, chains, basis, couplings)


def _random_system(rng: random.Random) -> DelaySystem:
    while True:
        n, m = rng.randint(2, 7), rng.randint(1, 2)
        p = rng.randint(m + 1, m + 3)
        A = [[rng.randint(-2, 2) for _ in range(n)] for _ in range(n)]
        B = [[rng.randint(-2, 2) for _ in range(m)] for _ in range(n)]
        C = [[rng.randint(-2, 2) if rng.random() < 0.6 else 0 for _ in range(n)] for _ in range(p)]
        sys = DelaySystem(A, B, C, None)
        if normal_form_applicable(sys).holds:
            return sys


def test_aircraft_step_records():
    model, chains, basis, couplings, form = _steps(paper000.aircraft())
    assert chains.nu == (3, 4) and chains.mu == (4, 3) and chains.order == (1, 0)
    assert chains.Gamma.tolist() == paper000.GAMMA
    # Step 3: one system, H^(1) = 1 (1×1), w^(1) = β_{1,2,3}
    (system,) = couplings.systems
    assert system.j == 1 and system.later == (2,) and system.H == QMatrix([[1]])
    assert system.w == QMatrix([[paper000.BETA_123]]) and couplings.beta == {(1, 2, 3): paper000.BETA_123}
    assert form.T.tolist() == [[Fr(x) for x in r] for r in paper000.T]
    assert form.E_bar.tolist() == [[Fr(x) for x in r] for r in paper000.E_BAR]  # (82), the paper's B̄
    assert form.B_bar.tolist() == [[0]] * 6 + [[Fr(-7017, 10)]]  # (81), the paper's D̄


@pytest.mark.parametrize("seed", range(10))
def test_step_invariants_on_random_systems(seed):
    rng = random.Random(100 + seed)
    sys = _random_system(rng)
    model, chains, basis, couplings, form = _steps(sys)
    A, B, C = model.A, model.B, model.C
    n, p = A.rows, C.rows
    # Step 1: z_{j,1} = ψ_{j,1} C, z_{j,i+1} = z_{j,i} A + ψ_{j,i+1} C, z_{j,i} B = 0 for i < ν_j, Z Ξ = R
    Z = chains.Z
    row = 0
    R_rows = []
    for j, Psi in enumerate(chains.Psi):
        nu = chains.nu[j]
        assert Psi.shape == (nu, p)
        assert Z[row, :] == Psi[0, :] @ C
        for i in range(nu - 1):
            assert Z[row + i + 1, :] == Z[row + i, :] @ A + Psi[i + 1, :] @ C
            assert (Z[row + i, :] @ B).is_zero()
        R_rows += [Psi[i, :] for i in range(1, nu)] + [QMatrix.zeros(1, p)]
        row += nu
    assert Z @ chains.Xi == QMatrix.vstack(*R_rows)
    assert chains.A_check == A + chains.Xi @ C and chains.C_check == chains.Gamma @ C
    # O_R is Z with its row blocks in sorted order
    starts = [sum(chains.nu[:j]) for j in range(p)]
    perm = [starts[j] + i for j in chains.order for i in range(chains.nu[j])]
    assert basis.O_R == Z.take_rows(perm)
    # Step 2, (B4): č_r Ǎ^k t_{e_s} = 1 if r = s and k = μ_s − 1, else 0, for k ≤ μ_r − 1
    O_inv = basis.O_R.inverse()
    for s in range(p):
        t = O_inv.take_cols([basis.ends[s]])
        for r in range(p):
            v = chains.C_check.row(r)
            for k in range(chains.mu[r]):
                assert (v @ t)[0, 0] == (1 if (r == s and k == chains.mu[s] - 1) else 0)
                assert (v @ t)[0, 0] == basis.coupling(r, k, s)
                v = v @ chains.A_check
    # Step 3: det H^(j) = 1 (Lemma 4.1(c)) and H β = w
    for system in couplings.systems:
        assert system.H.det() == 1 and system.H @ system.beta == system.w
    # Step 4: the transformation rules (21)
    assert form.T @ form.T_inverse == QMatrix.identity(n)
    assert form.T @ form.A_bar == A @ form.T and form.T @ form.B_bar == B
    assert form.C_bar == chains.Gamma @ C @ form.T


@pytest.mark.parametrize("seed", range(4))
def test_T_is_nonsingular_for_any_beta(seed):
    """Lemma 4.1(b): the columns (54) are independent whatever the β."""
    rng = random.Random(200 + seed)
    for _ in range(20):
        sys = _random_system(rng)
        model, chains, basis, couplings, _ = _steps(sys)
        if couplings.beta:
            break
    other = {k: Fr(rng.randint(-9, 9), rng.randint(1, 4)) for k in couplings.beta}
    form = normal_form(model, chains, basis, dataclasses.replace(couplings, beta=other))
    assert form.T.rank() == model.A.rows


@pytest.mark.parametrize(
    "D", [[[1, 2], [2, 4]], [[0, 0], [0, 0]], [[1, 0], [0, 1], [1, 1]], [[0, 1], [0, 2], [0, 0]]]
)
def test_feedthrough_split(D):
    Dq = QMatrix(D)
    s = feedthrough_split(Dq)
    p, m = Dq.shape
    target = QMatrix.block(
        [[QMatrix.identity(s.rank), QMatrix.zeros(s.rank, m - s.rank)],
         [QMatrix.zeros(p - s.rank, s.rank), QMatrix.zeros(p - s.rank, m - s.rank)]]
    )
    assert s.rank == Dq.rank() and s.U @ Dq @ s.V == target
    assert s.U.rank() == p and s.V.rank() == m


def test_augmented_model():
    """Section 5.4: χ = [x; w], A_χ = [[A, B], [0, 0]], B_χ = [0; I], C_χ = [C, D]."""
    sys = DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None)
    model = reduced_model(sys, reconstruct_input=True)
    assert model.A == QMatrix([[0, 1, 0], [-2, -3, 1], [0, 0, 0]])
    assert model.B == QMatrix([[0], [0], [1]]) and model.C == QMatrix([[1, 0, 0]])
    assert model.w_map == QMatrix([[0, 0, 1]]) and model.state_map == QMatrix([[1, 0, 0], [0, 1, 0]])
