"""The design object of the observer normal form (Niederwieser et al. 2022): ``NormalFormDesign``.

Package notation (one notation for every method; the paper's letters in the
right column)::

    plant   x' = A x + B w + E u,   y = C x + D w + F u
    model   x_m' = A x_m + B w_m + E ū,   ỹ_1 = C x_m        (after Appendix A.1 / Section 5.4)
    normal form (11)   x̄' = Ā x̄ + B̄ w_m + Ē ū,   ȳ = C̄ x̄,   x_m = T x̄,   ȳ = Γ ỹ_1

==========================  ============================  ==========================
package                     Niederwieser et al.           meaning
==========================  ============================  ==========================
``w``                       Δ                             unknown input
``u``                       u                             known input
``B`` (``model.B``)         D                             unknown-input matrix
``D``                       F                             feed-through of ``w``
``E`` (``model.E``)         B                             known-input matrix
``B_bar`` = T⁻¹ B           D̄ (11c)                       unknown input, normal form
``E_bar`` = T⁻¹ E           B̄ (82)                        known inputs, normal form
``A_bar``, ``C_bar``        Ā (11b), C̄ (11d)
``Pi_bar``                  Π̄ (13c)
``A_check``, ``C_check``    Ǎ (22), Č (24)
``Xi``, ``Gamma``           Ξ (45), Γ (44)
``O_R``, ``beta``           O_R (25), β_{j,r,l} (48)–(53)
``nu``, ``mu``, ``order``   ν_j, μ_j (12), j_1 … j_p (41)
``rank_D``, ``U``, ``V``    m_F, U, V (A1)
``kappa``                   κ_{j,k} (14)
``b_bar_rows()``            d̄_{e_j,·}
==========================  ============================  ==========================
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, ClassVar

from uio_ring.analysis.normal_form_applicability import NormalFormApplicability
from uio_ring.design.base import ObserverDesign, matrix_to_data
from uio_ring.design.normal_form.step1 import Step1Trace
from uio_ring.ring.certificate import Certificate
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["NormalFormDesign", "Step1Trace"]


@dataclass(frozen=True, repr=False)
class NormalFormDesign(ObserverDesign):
    """An observer-normal-form design (Niederwieser et al. 2022), in package notation (table in the module
    docstring: ``B_bar`` is the paper's D̄, ``E_bar`` its B̄).

    The *model* is the system the normal form is computed for: the plant after
    the feed-through reduction (Appendix A) and, with ``reconstruct_input``, the
    augmentation ``χ = [x; w]`` (Section 5.4).  Its matrices are ``model.A``,
    ``model.B`` (unknown input, the paper's D), ``model.C`` and ``model.E``
    (known inputs ``ū``, the paper's B).

    Attributes
    ----------
    system
        The plant as given.
    model
        The model system (``D = F = 0``).
    T, T_inverse
        ``x̄ = T⁻¹ x_model`` (``T`` maps normal-form coordinates to model coordinates).
    Gamma
        ``ȳ = Γ ỹ`` (p_m × p_m, sorted chain order).
    Xi, A_check, C_check
        Step 1: ``Ǎ = A + Ξ C``, ``Č = Γ C``.
    nu, mu
        Chain lengths in the original output order (``ν``) and sorted (``μ``, (12)).
    order
        ``j_1, …, j_p`` (1-based): the model output behind each normal-form chain.
    O_R
        (25), nonsingular.
    beta
        ``{(j, r, l): β_{j,r,l}}`` (1-based, sorted blocks), the nonzero-able couplings.
    A_bar, B_bar, C_bar, E_bar, Pi_bar
        The normal form (11): ``T⁻¹ A T``, ``T⁻¹ B`` (unknown input), ``Γ C T``,
        ``T⁻¹ E`` (known inputs ``ū``), and the injection matrix (13c).
    output_map
        ``ȳ = output_map · [y; u]`` (Γ applied to the reduced outputs ``ỹ_1 = U_1 (y − F u)``).
    input_map
        ``ū = input_map · [y; u]`` (the model's known inputs: ``u`` and ``ỹ_0``).
    state_map
        ``x̂ = state_map · x̂̄``: the plant-state estimate from the observer state.
    w_map
        ``ŵ = w_map · x̂̄`` when ``reconstruct_input`` (else ``None``).
    U, V, rank_D
        Appendix A: ``U D V = [[I_r, 0], [0, 0]]``, ``r = rank D`` (identities when ``D = 0``).
    input_bounds
        Bounds ``L_i`` of the model's unknown input (``|w|``, or ``|w'|`` when reconstructing).
    lipschitz
        The RED constant ``L_j`` of each chain.
    kappa
        ``kappa[j] = (κ_{j,μ_j−1}, …, κ_{j,0})``, top row to bottom row.
    trace
        Step 1 trace.
    """

    method: ClassVar[str] = "normal-form"

    system: DelaySystem
    model: DelaySystem
    T: PolyMatrix
    T_inverse: PolyMatrix
    Gamma: PolyMatrix
    Xi: PolyMatrix
    A_check: PolyMatrix
    C_check: PolyMatrix
    nu: tuple[int, ...]
    mu: tuple[int, ...]
    order: tuple[int, ...]
    O_R: PolyMatrix
    beta: dict[tuple[int, int, int], Fraction]
    A_bar: PolyMatrix
    B_bar: PolyMatrix
    C_bar: PolyMatrix
    E_bar: PolyMatrix
    Pi_bar: PolyMatrix
    output_map: PolyMatrix
    input_map: PolyMatrix
    state_map: PolyMatrix
    w_map: PolyMatrix | None
    U: PolyMatrix
    V: PolyMatrix
    rank_D: int
    reconstruct_input: bool
    input_bounds: tuple[Fraction, ...]
    lipschitz: tuple[Fraction, ...]
    kappa: tuple[tuple[Fraction, ...], ...]
    trace: tuple[Step1Trace, ...] = ()
    applicability: NormalFormApplicability | None = field(default=None, compare=False)

    # -- derived -----------------------------------------------------------------------
    @property
    def n(self) -> int:
        """Observer order (= model states)."""
        return self.T.rows

    @property
    def p(self) -> int:
        """Number of chains."""
        return len(self.mu)

    @property
    def block_starts(self) -> tuple[int, ...]:
        """``b_j`` (0-based index of the first state of chain j)."""
        out, b = [], 0
        for m in self.mu:
            out.append(b)
            b += m
        return tuple(out)

    @property
    def block_ends(self) -> tuple[int, ...]:
        """``e_j − 1`` (0-based index of the last state of chain j)."""
        return tuple(b + m - 1 for b, m in zip(self.block_starts, self.mu, strict=True))

    def b_bar_rows(self) -> tuple[tuple[Fraction, ...], ...]:
        """``b̄_{e_j,·}`` (the paper's ``d̄_{e_j,·}``): the rows of ``B̄`` at the last state of each chain."""
        Bl = self.B_bar.coefficient_lists()[0] if self.B_bar.rows and self.B_bar.cols else []
        return tuple(tuple(Bl[e]) if Bl else () for e in self.block_ends)

    def condition_18(self) -> tuple[tuple[Fraction, Fraction], ...]:
        """``(κ_{j,0}, Σ_i L_i |b̄_{e_j,i}|)`` per chain; (18) asks for ``>`` where the bound is nonzero."""
        out = []
        for j, row in enumerate(self.b_bar_rows()):
            bound = sum((abs(d) * L for d, L in zip(row, self.input_bounds, strict=True)), Fraction(0))
            out.append((self.kappa[j][-1], bound))
        return tuple(out)

    def certificate(self) -> Certificate:
        """Every identity of the construction, exactly (see :func:`uio_ring.verify.normal_form_certificate`)."""
        from uio_ring.verify.normal_form import normal_form_certificate

        return normal_form_certificate(self)

    def numeric(self, *, h: Any = None) -> Any:
        """The float observer model: ``ξ = x̂̄``, ``F = Ā − Π̄ C̄``, the measured signals
        ``s = [ȳ; ỹ_0] = S_map [y; u]`` injected through ``S = [Π̄, Ē_ỹ0]`` (``G_y``, ``G_u``,
        the latter with ``Ē_u``), one Levant differentiator per chain on ``σ = ȳ − x̂̄[b_j]``,
        ``X`` = state map, ``W`` = input map; every product is formed exactly first.  The
        model is delay-free (``h`` is accepted for the common signature and not used); the
        differentiators are discretised ``"implicit"`` unless the stepper says otherwise.

        >>> from uio_ring import DelaySystem, design_normal_form
        >>> design_normal_form(DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None), [1]).numeric()
        ObserverModel(normal-form: n_z=2, n_y=1, n_u=0, n_x=2, n_w=0, lag=0, injection=implicit)
        """
        from uio_ring.numeric.build import (
            held_input_from_exact,
            injection_from_exact,
            model_from_exact,
        )

        sysm, n_u, n_y, p = self.system, self.system.n_u, self.system.n_y, len(self.mu)
        E_u, E_y0 = self.E_bar[:, :n_u], self.E_bar[:, n_u:]
        S_map = PolyMatrix.vstack(self.output_map, self.input_map[n_u:, :])
        S = PolyMatrix.hstack(self.Pi_bar, E_y0)
        H_s = PolyMatrix.vstack(self.C_bar, self.input_map[n_u:, :n_y] @ sysm.C @ self.state_map)
        injection = injection_from_exact(
            starts=self.block_starts, lengths=self.mu, gains=self.kappa,
            sigma_y=self.output_map[:, :n_y], sigma_u=self.output_map[:, n_y:],
        )
        held = held_input_from_exact(A=self.A_bar + E_y0 @ H_s[p:, :], B=E_u, M=S @ H_s) if n_u else None
        return model_from_exact(
            F=self.A_bar - self.Pi_bar @ self.C_bar, G_y=S @ S_map[:, :n_y], G_u=S @ S_map[:, n_y:] + E_u,
            X=self.state_map, W=self.w_map, initial=self.T_inverse, injection=injection,
            held_input=held, interpolation="linear", method=self.method,
        )

    # -- display and data ------------------------------------------------------------------
    def __repr__(self) -> str:
        return (
            f"NormalFormDesign(n={self.n}, mu={self.mu}, reconstruct_input={self.reconstruct_input}, "
            f"rank_D={self.rank_D}, kappa={[[str(k) for k in ks] for ks in self.kappa]})"
        )

    def __str__(self) -> str:
        lines = [repr(self), f"T =\n{self.T}", f"Gamma =\n{self.Gamma}", f"A_bar =\n{self.A_bar}",
                 f"B_bar =\n{self.B_bar}", f"C_bar =\n{self.C_bar}"]
        if self.E_bar.cols:
            lines.append(f"E_bar =\n{self.E_bar}")
        if self.beta:
            lines.append("beta = " + ", ".join(f"β{j}{r}{l} = {v}" for (j, r, l), v in self.beta.items()))
        return "\n".join(lines)

    def to_latex(self) -> str:
        E = r" + \bar E \bar u" if self.E_bar.cols else ""
        return (
            rf"\dot{{\hat{{\bar x}}}} = \bar A \hat{{\bar x}}{E} + \bar\Pi \sigma + \bar l(\sigma),\;"
            rf"\sigma = \bar y - \bar C \hat{{\bar x}},\; \mu = {self.mu},\;"
            rf"T = {self.T.to_latex()},\; \Gamma = {self.Gamma.to_latex()},\; \bar A = {self.A_bar.to_latex()},\;"
            rf"\bar B = {self.B_bar.to_latex()}"
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "method": self.method,
            "mu": list(self.mu),
            "nu": list(self.nu),
            "order": list(self.order),
            "rank_D": self.rank_D,
            "reconstruct_input": self.reconstruct_input,
            "T": matrix_to_data(self.T),
            "Gamma": matrix_to_data(self.Gamma),
            "Xi": matrix_to_data(self.Xi),
            "A_bar": matrix_to_data(self.A_bar),
            "B_bar": matrix_to_data(self.B_bar),
            "C_bar": matrix_to_data(self.C_bar),
            "E_bar": matrix_to_data(self.E_bar),
            "Pi_bar": matrix_to_data(self.Pi_bar),
            "beta": {f"{j},{r},{l}": str(v) for (j, r, l), v in self.beta.items()},
            "input_bounds": [str(x) for x in self.input_bounds],
            "lipschitz": [str(x) for x in self.lipschitz],
            "kappa": [[str(k) for k in ks] for ks in self.kappa],
        }
