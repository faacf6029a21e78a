"""Step 4 of Niederwieser et al. (2022) (Section 4.1, (54), (21)): the transformation ``T`` and the normal form.

The columns of ``T`` (54), block ``j``, ``i = 0 … μ_j − 1``::

    t_{e_j − i} = Ǎ^i t_{e_j} − Σ_{r>j} Σ_{q=1}^{i} β_{j,r,μ_j−q} Ǎ^{i−q} t_{e_r}

i.e. per block one matrix product ``X_j = P_j − Σ_r P_r Β_{j,r}`` with the powers
``P_s = [t_{e_s}, Ǎ t_{e_s}, …]`` of Step 2 and the upper triangular Toeplitz
matrices ``Β_{j,r}[i−q, i] = β_{j,r,μ_j−q}``; column ``i`` of ``X_j`` is ``t_{e_j − i}``.
Then (21), in package notation (the paper's D̄ is our ``B̄``, its B̄ our ``Ē``)::

    Ā = T⁻¹ A T,   B̄ = T⁻¹ B,   C̄ = Γ C T = Č T,   Ē = T⁻¹ E,   Π̄ = Ā[:, b_j+1]  (13c)
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from uio_ring.design.normal_form.model import NormalFormModel
from uio_ring.design.normal_form.step1 import OutputChains
from uio_ring.design.normal_form.step2 import ChainBasis
from uio_ring.design.normal_form.step3 import Couplings
from uio_ring.ring.qmatrix import QMatrix

__all__ = ["NormalForm", "normal_form"]


@dataclass(frozen=True)
class NormalForm:
    """The result of Step 4: ``x̄ = T⁻¹ x_m`` and the normal form (11) of the model.

    Attributes
    ----------
    T, T_inverse
        ``T`` maps normal-form coordinates to model coordinates (``x_m = T x̄``).
    A_bar, B_bar, C_bar, E_bar
        ``T⁻¹ A T`` (11b), ``T⁻¹ B`` (11c, the unknown input), ``Γ C T`` (11d),
        ``T⁻¹ E`` (the known inputs).
    Pi_bar
        The first column of each block of ``Ā`` (13c).
    """

    T: QMatrix
    T_inverse: QMatrix
    A_bar: QMatrix
    B_bar: QMatrix
    C_bar: QMatrix
    E_bar: QMatrix
    Pi_bar: QMatrix


def normal_form(model: NormalFormModel, chains: OutputChains, basis: ChainBasis, couplings: Couplings) -> NormalForm:
    """Step 4: ``T`` from (54) and the normal form by (21)."""
    mu, P = basis.mu, basis.powers
    blocks = []
    for j in range(len(mu)):
        X = P[j][:, : mu[j]]
        later = [r for r in range(j + 1, len(mu)) if any(couplings.beta.get((j + 1, r + 1, l)) for l in range(mu[j]))]
        if later:
            X = X - QMatrix.hstack(*[P[r][:, : mu[j]] for r in later]) @ QMatrix.vstack(
                *[_toeplitz(couplings.beta, j, r, mu[j]) for r in later]
            )
        blocks.append(X.take_cols(range(mu[j] - 1, -1, -1)))  # column e_j − i holds t_{e_j − i}
    T = basis.O_R.solve(QMatrix.hstack(*blocks, rows=model.A.rows), name="O_R")  # back from z = O_R x
    T_inv = T.inverse(name="T")
    A_bar = T_inv @ (model.A @ T)
    return NormalForm(
        T=T,
        T_inverse=T_inv,
        A_bar=A_bar,
        B_bar=T_inv @ model.B,
        C_bar=chains.C_check @ T,
        E_bar=T_inv @ model.E,
        Pi_bar=A_bar.take_cols(basis.starts),
    )


def _toeplitz(beta: dict[tuple[int, int, int], Fraction], j: int, r: int, size: int) -> QMatrix:
    """``Β_{j,r}[i − q, i] = β_{j,r,μ_j−q}`` for ``1 ≤ q ≤ i < μ_j`` (0-based j, r; ``size = μ_j``)."""
    zero = Fraction(0)
    return QMatrix(
        [[beta.get((j + 1, r + 1, size - (i - k)), zero) if i > k else zero for i in range(size)] for k in range(size)]
    )
