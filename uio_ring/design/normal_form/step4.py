"""Step 4 of Niederwieser et al. (2022) (Section 4.1, (54), (21)): the transformation ``T`` and the normal form.

``T`` is (54), built by :func:`uio_ring.analysis.chain_couplings.chain_transformation`
(shared with the special coordinate basis, which uses it for Theorem 1 of
Tranninger et al. (2021)).  Then (21), in package notation (the paper's D̄ is our ``B̄``, its B̄ our ``Ē``)::

    Ā = T⁻¹ A T,   B̄ = T⁻¹ B,   C̄ = Γ C T = Č T,   Ē = T⁻¹ E,   Π̄ = Ā[:, b_j+1]  (13c)
"""

from __future__ import annotations

from dataclasses import dataclass

from uio_ring.analysis.chain_basis import ChainBasis
from uio_ring.analysis.chain_couplings import Couplings, chain_transformation
from uio_ring.design.normal_form.model import NormalFormModel
from uio_ring.design.normal_form.step1 import OutputChains
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
    T = chain_transformation(basis, couplings)
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

