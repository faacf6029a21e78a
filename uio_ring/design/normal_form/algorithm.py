"""``design_normal_form``: the observer normal form and RED observer of Niederwieser et al. (2022), step by step.

The function reads like Section 4.1 of Niederwieser, Tranninger, Seeber &
Reichhartinger (2022)::

    model     = reduced_model(sys)                   Appendix A.1 / Section 5.4
    chains    = output_chains(A, B, C)               Step 1: Γ, Ξ, ν, μ
    basis     = chain_basis(Ǎ, Č, μ)                 Step 2: O_R, t_{e_j}
    couplings = coupling_coefficients(basis)         Step 3: β from H^(j) β = w^(j)
    form      = normal_form(model, chains, …)        Step 4: T, Ā, B̄, C̄, Ē, Π̄
    gains     = observer_gains(μ, b̄_{e_j}, L)         (14), (18)
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from uio_ring.analysis.chain_basis import chain_basis
from uio_ring.analysis.chain_couplings import coupling_coefficients
from uio_ring.analysis.normal_form_applicability import (
    NormalFormApplicability,
    normal_form_applicable,
)
from uio_ring.design.normal_form.design import NormalFormDesign
from uio_ring.design.normal_form.gains import input_bounds as read_bounds
from uio_ring.design.normal_form.gains import model_input_bounds, observer_gains
from uio_ring.design.normal_form.model import reduced_model
from uio_ring.design.normal_form.step1 import output_chains
from uio_ring.design.normal_form.step4 import normal_form
from uio_ring.errors import NotObservableError
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["design_normal_form"]


def design_normal_form(
    sys: DelaySystem,
    input_bounds: Sequence[Any] | Any,
    *,
    reconstruct_input: bool = False,
    gains: Sequence[Sequence[Any]] | None = None,
    lipschitz: Sequence[Any] | None = None,
    safety: Any = 8,
    lipschitz_floor: Any = 10,
    lambdas: Sequence[Any] | None = None,
    report: NormalFormApplicability | None = None,
) -> NormalFormDesign:
    """Observer normal form and RED observer of Niederwieser et al. (2022) for a delay-free system.

    Parameters
    ----------
    sys
        Delay-free, strongly observable, with independent unknown-input columns
        (``rank [B; D] = n_w``); see :func:`uio_ring.normal_form_applicable`.
    input_bounds
        ``L_i`` with ``|w_i(t)| ≤ L_i`` (one per unknown input, or one number for
        all); with ``reconstruct_input`` they bound ``|w_i'(t)|``.  Exact
        rationals (``"0.02"``; a float is read through its decimal text).
    reconstruct_input
        Estimate ``w`` too (Section 5.4): the normal form of ``χ = [x; w]``.
    gains
        Explicit RED gains per chain (normal-form order), top row to bottom row
        ``κ_{j,μ_j−1}, …, κ_{j,0}``.  Default: Levant's standard parameters.
    lipschitz
        Per-chain constants ``L_j`` for the default gains.  Default:
        ``max(safety · Σ_i L_i |b̄_{e_j,i}|, lipschitz_floor)``; ``safety = 8`` and
        ``lipschitz_floor = 10`` reproduce the paper's gains (89).
    safety, lipschitz_floor
        See ``lipschitz``.
    lambdas
        Levant's parameters (default :data:`uio_ring.design.red_gains.LEVANT_LAMBDAS`).
    report
        The :func:`~uio_ring.analysis.normal_form_applicable` report of ``sys`` when it was
        computed already (``design_auto`` analyses once); default: computed here.

    Returns
    -------
    NormalFormDesign
        ``T, Gamma, mu, A_bar, B_bar, C_bar, E_bar, Pi_bar, beta`` and the rest
        (``B_bar = T⁻¹ B`` is the paper's D̄, ``E_bar = T⁻¹ E`` its B̄).

    Raises
    ------
    NotObservableError
        The system is not strongly observable (the report says why), has delays,
        or has dependent unknown-input columns.
    DomainError
        Gains that violate the necessary condition (18).
    DimensionError
        Wrong number of bounds or gains.

    Algorithm
    ---------
    Niederwieser et al. (2022), Section 4.1, Steps 1–4, eqs. (28)–(54), with these
    choices where the paper leaves them open: round robin over active chains,
    minimum-norm ζ in (33), stable sort in (41), Step 3 by the element-wise form of
    (11b) instead of the garbled (49) (docs/errata.md, N2).  Appendix A.1 for ``D ≠ 0``;
    Section 5.4 for ``reconstruct_input``.  Exact over Q; the cost is dominated by
    O(n) exact ranks of n×n matrices and the growth of the entries of ``T``.

    Examples
    --------
    A double integrator with the unknown input at the acceleration:

    >>> from uio_ring import DelaySystem
    >>> des = design_normal_form(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None), ["0.5"])
    >>> des.mu, des.T, des.b_bar_rows(), [float(k) for k in des.kappa[0]]
    ((2,), PolyMatrix([[1, 0], [0, 1]]), ((Fraction(1, 1),),), [4.74341649025, 11.0])
    """
    rep = normal_form_applicable(sys) if report is None else report  # decisive: Smith form of P(s)
    if not rep.holds:
        raise NotObservableError(f"the observer normal form does not apply: {rep.reason}", report=rep)
    bounds = read_bounds(input_bounds, sys.n_w, "bounds of |w'|" if reconstruct_input else "bounds of |w|")
    model = reduced_model(sys, reconstruct_input=reconstruct_input)
    chains = output_chains(model.A, model.B, model.C)
    basis = chain_basis(chains.A_check, chains.C_check, chains.mu)
    couplings = coupling_coefficients(basis)
    form = normal_form(model, chains, basis, couplings)
    b_bar = form.B_bar.tolist()
    model_bounds = model_input_bounds(model.w_transform, bounds)
    red = observer_gains(
        chains.mu, tuple(tuple(b_bar[e]) for e in basis.ends), model_bounds,
        gains=gains, lipschitz=lipschitz, safety=safety, lipschitz_floor=lipschitz_floor, lambdas=lambdas,
    )

    def pm(M: QMatrix) -> PolyMatrix:
        return M.to_polymatrix()

    return NormalFormDesign(
        system=sys,
        model=DelaySystem(pm(model.A), pm(model.B), pm(model.C), None, E=pm(model.E) if model.E.cols else None),
        T=pm(form.T),
        T_inverse=pm(form.T_inverse),
        Gamma=pm(chains.Gamma),
        Xi=pm(chains.Xi),
        A_check=pm(chains.A_check),
        C_check=pm(chains.C_check),
        nu=chains.nu,
        mu=chains.mu,
        order=tuple(j + 1 for j in chains.order),
        O_R=pm(basis.O_R),
        beta=couplings.beta,
        A_bar=pm(form.A_bar),
        B_bar=pm(form.B_bar),
        C_bar=pm(form.C_bar),
        E_bar=pm(form.E_bar),
        Pi_bar=pm(form.Pi_bar),
        output_map=pm(chains.Gamma @ model.output_map),
        input_map=pm(model.input_map),
        state_map=pm(model.state_map @ form.T),
        w_map=None if model.w_map is None else pm(model.w_map @ form.T),
        U=pm(model.split.U),
        V=pm(model.split.V),
        rank_D=model.rank_D,
        reconstruct_input=reconstruct_input,
        input_bounds=model_bounds,
        lipschitz=red.lipschitz,
        kappa=red.kappa,
        trace=chains.trace,
        applicability=rep,
    )
