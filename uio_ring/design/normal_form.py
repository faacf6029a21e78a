"""The observer normal form of Niederwieser, Tranninger, Seeber & Reichhartinger (2022).

For a strongly observable delay-free system (package notation; the paper's
``D`` is our ``B``, its ``B`` our ``E``, its ``F`` our ``D``)::

    x' = A x + B w + E u,      y = C x + D w + F u

Section 4.1 constructs ``T`` (n×n) and ``Γ`` (p×p) such that ``x̄ = T⁻¹ x``,
``ȳ = Γ y`` are in the observer normal form (11)::

    x̄' = Ā x̄ + D̄ w + B̄ u,   ȳ = C̄ x̄,
    Ā = T⁻¹ A T (11b),  D̄ = T⁻¹ B (11c),  C̄ = Γ C T (11d),  B̄ = T⁻¹ E

p single-output chains of lengths ``μ_1 ≥ … ≥ μ_p`` (Σ μ = n), coupled only by
output injection (``Π̄``, the first column of each block) and by the
couplings ``β`` into the last rows of later chains.  The observer (13)–(14) is
one Levant robust exact differentiator per chain::

    x̂' = Ā x̂ + B̄ u + Π̄ σ + l̄(σ),   σ = ȳ − C̄ x̂

It converges in finite time if ``|w_i| ≤ L_i`` and the gains satisfy (18).

* ``D ≠ 0`` (direct feed-through of w): the reduction of Appendix A.1 is applied
  first (``U D V = [[I, 0], [0, 0]]``; ``ỹ_0`` becomes a known input).
* ``reconstruct_input=True``: Section 5.4, the system augmented with ``χ = [x; w]``
  (then ``input_bounds`` bound ``|w'|``), so that the observer also estimates ``w``.

Everything is exact (python-flint rationals): float64 rank decisions gave
structurally wrong normal forms on ill-conditioned systems in our tests
(docs/errata.md, N5).

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None)
>>> des = design_normal_form(sys, [1])
>>> des.mu, des.A_bar, des.certificate().ok
((2,), PolyMatrix([[-3, 1], [-2, 0]]), True)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, ClassVar

import flint

from uio_ring.analysis.normal_form_applicability import (
    NormalFormApplicability,
    normal_form_applicable,
)
from uio_ring.design.base import ObserverDesign, matrix_to_data
from uio_ring.design.red_gains import levant_gains
from uio_ring.errors import DimensionError, DomainError, NotObservableError, UioRingError
from uio_ring.ring import constant as qc
from uio_ring.ring.certificate import Certificate
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import exact_fraction
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["NormalFormDesign", "design_normal_form", "Step1Trace"]

Q = flint.fmpq_mat


# ----------------------------------------------------------------------------------------
# the design object
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Step1Trace:
    """One visit of chain ``j`` (1-based, original order) in Step 1: ``case`` is
    ``"1"``, ``"2/2.1"`` or ``"2/2.2"``; ``zeta`` the minimum-norm solution of (33)."""

    j: int
    case: str
    zeta: tuple[Fraction, ...] = ()


@dataclass(frozen=True, repr=False)
class NormalFormDesign(ObserverDesign):
    """An observer-normal-form design (Niederwieser et al. 2022), every matrix named as in the paper.

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
    A_bar, D_bar, C_bar, B_bar, Pi_bar
        The normal form (11) and the injection matrix (13c).
    output_map
        ``ȳ = output_map · [y; u]`` (Γ applied to the reduced outputs ``ỹ_1 = U_1 (y − F u)``).
    input_map
        ``ū = input_map · [y; u]`` (the model's known inputs: ``u`` and ``ỹ_0``).
    state_map
        ``x̂ = state_map · x̂̄``: the plant-state estimate from the observer state.
    w_map
        ``ŵ = w_map · x̂̄`` when ``reconstruct_input`` (else ``None``).
    U, V, m_F
        Appendix A: ``U D V = [[I_{m_F}, 0], [0, 0]]`` (identities when ``D = 0``).
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
    D_bar: PolyMatrix
    C_bar: PolyMatrix
    B_bar: PolyMatrix
    Pi_bar: PolyMatrix
    output_map: PolyMatrix
    input_map: PolyMatrix
    state_map: PolyMatrix
    w_map: PolyMatrix | None
    U: PolyMatrix
    V: PolyMatrix
    m_F: int
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

    def d_bar_rows(self) -> tuple[tuple[Fraction, ...], ...]:
        """``d̄_{e_j,·}``: the rows of ``D̄`` at the last state of each chain."""
        Dl = self.D_bar.coefficient_lists()[0] if self.D_bar.rows and self.D_bar.cols else []
        return tuple(tuple(Dl[e]) if Dl else () for e in self.block_ends)

    def condition_18(self) -> tuple[tuple[Fraction, Fraction], ...]:
        """``(κ_{j,0}, Σ_i L_i |d̄_{e_j,i}|)`` per chain; (18) asks for ``>`` where the bound is nonzero."""
        out = []
        for j, row in enumerate(self.d_bar_rows()):
            bound = sum((abs(d) * L for d, L in zip(row, self.input_bounds, strict=True)), Fraction(0))
            out.append((self.kappa[j][-1], bound))
        return tuple(out)

    def certificate(self) -> Certificate:
        """Every identity of the construction, exactly (see :func:`uio_ring.verify.normal_form_certificate`)."""
        from uio_ring.verify.normal_form import normal_form_certificate

        return normal_form_certificate(self)

    def numeric(self, *, h: Any = None) -> Any:
        """The float observer model: ``ξ = x̂̄``, ``F = Ā − Π̄ C̄``, the measured signals
        ``s = [ȳ; ỹ_0] = S_map [y; u]`` injected through ``S = [Π̄, B̄_ỹ0]`` (``G_y``, ``G_u``,
        the latter with ``B̄_u``), one Levant differentiator per chain on ``σ = ȳ − x̂̄[b_j]``,
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
        B_u, B_y0 = self.B_bar[:, :n_u], self.B_bar[:, n_u:]
        S_map = PolyMatrix.vstack(self.output_map, self.input_map[n_u:, :])
        S = PolyMatrix.hstack(self.Pi_bar, B_y0)
        H_s = PolyMatrix.vstack(self.C_bar, self.input_map[n_u:, :n_y] @ sysm.C @ self.state_map)
        injection = injection_from_exact(
            starts=self.block_starts, lengths=self.mu, gains=self.kappa,
            sigma_y=self.output_map[:, :n_y], sigma_u=self.output_map[:, n_y:],
        )
        held = held_input_from_exact(A=self.A_bar + B_y0 @ H_s[p:, :], B=B_u, M=S @ H_s) if n_u else None
        return model_from_exact(
            F=self.A_bar - self.Pi_bar @ self.C_bar, G_y=S @ S_map[:, :n_y], G_u=S @ S_map[:, n_y:] + B_u,
            X=self.state_map, W=self.w_map, initial=self.T_inverse, injection=injection,
            held_input=held, interpolation="linear", method=self.method,
        )

    # -- display and data ------------------------------------------------------------------
    def __repr__(self) -> str:
        return (
            f"NormalFormDesign(n={self.n}, mu={self.mu}, reconstruct_input={self.reconstruct_input}, "
            f"m_F={self.m_F}, kappa={[[str(k) for k in ks] for ks in self.kappa]})"
        )

    def __str__(self) -> str:
        lines = [repr(self), f"T =\n{self.T}", f"Gamma =\n{self.Gamma}", f"A_bar =\n{self.A_bar}",
                 f"D_bar =\n{self.D_bar}", f"C_bar =\n{self.C_bar}"]
        if self.B_bar.cols:
            lines.append(f"B_bar =\n{self.B_bar}")
        if self.beta:
            lines.append("beta = " + ", ".join(f"β{j}{r}{l} = {v}" for (j, r, l), v in self.beta.items()))
        return "\n".join(lines)

    def to_latex(self) -> str:
        B = r" + \bar B \bar u" if self.B_bar.cols else ""
        return (
            rf"\dot{{\hat{{\bar x}}}} = \bar A \hat{{\bar x}}{B} + \bar\Pi \sigma + \bar l(\sigma),\;"
            rf"\sigma = \bar y - \bar C \hat{{\bar x}},\; \mu = {self.mu},\;"
            rf"T = {self.T.to_latex()},\; \Gamma = {self.Gamma.to_latex()},\; \bar A = {self.A_bar.to_latex()},\;"
            rf"\bar D = {self.D_bar.to_latex()}"
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "method": self.method,
            "mu": list(self.mu),
            "nu": list(self.nu),
            "order": list(self.order),
            "m_F": self.m_F,
            "reconstruct_input": self.reconstruct_input,
            "T": matrix_to_data(self.T),
            "Gamma": matrix_to_data(self.Gamma),
            "Xi": matrix_to_data(self.Xi),
            "A_bar": matrix_to_data(self.A_bar),
            "D_bar": matrix_to_data(self.D_bar),
            "C_bar": matrix_to_data(self.C_bar),
            "B_bar": matrix_to_data(self.B_bar),
            "Pi_bar": matrix_to_data(self.Pi_bar),
            "beta": {f"{j},{r},{l}": str(v) for (j, r, l), v in self.beta.items()},
            "input_bounds": [str(x) for x in self.input_bounds],
            "lipschitz": [str(x) for x in self.lipschitz],
            "kappa": [[str(k) for k in ks] for ks in self.kappa],
        }


# ----------------------------------------------------------------------------------------
# helpers on fmpq_mat
# ----------------------------------------------------------------------------------------
def _row(M: Q, i: int) -> Q:
    n = M.ncols()
    r = Q(1, n)
    for j in range(n):
        r[0, j] = M[i, j]
    return r


def _col(M: Q, j: int) -> Q:
    n = M.nrows()
    c = Q(n, 1)
    for i in range(n):
        c[i, 0] = M[i, j]
    return c


def _cols(M: Q, idx: Sequence[int]) -> Q:
    out = Q(M.nrows(), len(idx))
    for c, j in enumerate(idx):
        for i in range(M.nrows()):
            out[i, c] = M[i, j]
    return out


def _rows(M: Q, idx: Sequence[int]) -> Q:
    return _cols(M.transpose(), idx).transpose()


def _pm(M: Q) -> PolyMatrix:
    return qc.to_polymatrix(M)


# ----------------------------------------------------------------------------------------
# Appendix A.1 and Section 5.4: the model system
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Model:
    A: Q
    B: Q  # unknown input of the model (paper's D)
    C: Q
    E: Q  # known inputs of the model: [u; ỹ_0]
    output_map: Q  # ỹ_1 = output_map [y; u]
    input_map: Q  # ū = input_map [y; u]
    state_map: Q  # x_plant = state_map x_model
    w_map: Q | None  # w = w_map x_model (augmented)
    U: Q
    V: Q
    m_F: int
    w_transform: Q  # the model's unknown input = w_transform · (plant w, or w' when augmented)


def _feedthrough_split(D: Q) -> tuple[Q, Q, int]:
    """Regular ``U`` (p×p), ``V`` (m×m) with ``U D V = [[I_r, 0], [0, 0]]`` (A1), and ``r = rank D``."""
    p, m = D.nrows(), D.ncols()
    r = qc.qrank(D)
    if r == 0:
        return qc.qidentity(p), qc.qidentity(m), 0
    J = list(qc.row_basis(D.transpose()))  # independent columns of D
    rest = [j for j in range(m) if j not in J]
    P = Q(m, m)  # permutation: D P = [D_J, D_rest]
    for c, j in enumerate(J + rest):
        P[j, c] = 1
    DJ = _cols(D, J)
    Dr = _cols(D, rest)
    # D_rest = D_J K
    R = list(qc.row_basis(DJ))  # r independent rows of D_J
    DJR = _rows(DJ, R)
    K = qc.qsolve(DJR, _rows(Dr, R), "D") if rest else Q(r, 0)
    Vc = qc.qidentity(m)
    for i in range(r):
        for c in range(len(rest)):
            Vc[i, r + c] = -K[i, c]
    V = P * Vc  # D V = [D_J, 0]
    # L: r×p with L D_J = I ; N: left null space of D_J
    S = Q(r, p)
    for i, ri in enumerate(R):
        S[i, ri] = 1
    L = qc.qinverse(DJR, "D") * S
    N = qc.left_nullspace(DJ)
    U = qc.qvstack([L, N], p)
    return U, V, r


def _model(M: dict[str, Q], n: int, m: int, p: int, nu_: int, reconstruct: bool) -> _Model:
    A, B, C, D, E, F = (M[k] for k in "ABCDEF")
    if reconstruct:
        # χ = [x; w]: A_χ = [[A, B], [0, 0]], B_χ = [0; I], C_χ = [C, D]; new unknown input w'
        A = qc.qvstack([qc.qhstack([A, B], n), Q(m, n + m)], n + m)
        C = qc.qhstack([C, D], p)
        E = qc.qvstack([E, Q(m, nu_)], nu_)
        B = qc.qvstack([Q(n, m), qc.qidentity(m)], m)
        D = Q(p, m)
        state_map = qc.qhstack([qc.qidentity(n), Q(n, m)], n)
        w_map: Q | None = qc.qhstack([Q(m, n), qc.qidentity(m)], m)
        nx = n + m
    else:
        state_map, w_map, nx = qc.qidentity(n), None, n
    U, V, r = _feedthrough_split(D)
    # ỹ = U (y − F u) = [ỹ_0; ỹ_1],  B V = [B̃_0, B̃_1],  U C = [C̃_0; C̃_1]
    BV = B * V
    B0, B1 = _cols(BV, range(r)), _cols(BV, range(r, m))
    UC = U * C
    C0, C1 = _rows(UC, range(r)), _rows(UC, range(r, p))
    A_t = A - B0 * C0
    Uyu = U * qc.qhstack([qc.qidentity(p), -F], p)  # ỹ = Uyu [y; u]
    Y0, Y1 = _rows(Uyu, range(r)), _rows(Uyu, range(r, p))
    # drop redundant outputs of C̃_1 (they carry no information: ỹ_1 = C̃_1 x exactly)
    keep = list(qc.row_basis(C1))
    C1, Y1 = _rows(C1, keep), _rows(Y1, keep)
    E_m = qc.qhstack([E, B0], nx)
    u_part = qc.qhstack([Q(nu_, p), qc.qidentity(nu_)], p + nu_)
    input_map = qc.qvstack([u_part, Y0], p + nu_)
    Vinv = qc.qinverse(V, "V")
    w_transform = _rows(Vinv, range(r, m))
    return _Model(A_t, B1, C1, E_m, Y1, input_map, state_map, w_map, U, V, r, w_transform)


# ----------------------------------------------------------------------------------------
# Step 1 (Section 4.1): Γ, Ξ and the chain lengths
# ----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class _Step1:
    Z: list[list[Q]]
    Psi: list[list[Q]]
    nu: list[int]
    trace: list[Step1Trace]


def _step1(A: Q, D: Q, C: Q) -> _Step1:
    """The loop (28)–(40) of Step 1, round robin over the active chains."""
    n, p, m = A.nrows(), C.nrows(), D.ncols()
    Z = [[_row(C, j)] for j in range(p)]
    Psi = [[_row(qc.qidentity(p), j)] for j in range(p)]
    W = Q(p, m)
    rank_W = 0
    nu = [1] * p
    f = [True] * p
    trace: list[Step1Trace] = []
    # basis of rowspace(Z) (updates (34) add other chains' rows, so only appends change it)
    rank_Z = qc.qrank(C)
    Zall = C
    while any(f):
        for j in range(p):
            if not f[j]:
                continue
            # invariant: z_{j,i} D = 0 for i < ν_j; rows of finished chains never change
            z = Z[j][-1]
            zD = z * D
            if m and qc.qrank(qc.qvstack([W, zD], m)) > rank_W:  # Case 1 (31)
                for i in range(m):
                    W[j, i] = zD[0, i]
                rank_W += 1
                f[j] = False
                trace.append(Step1Trace(j + 1, "1"))
                continue
            # Case 2 (32)–(33)
            if m and not qc.is_qzero(zD):
                zeta = qc.min_norm_left_solve(W, zD)
                if zeta is None:  # pragma: no cover - excluded by the rank test (31)
                    raise UioRingError("Step 1: z D is in the row space of W but (33) has no solution")
            else:
                zeta = Q(1, p)
            zl = tuple(qc.frac(zeta[0, k]) for k in range(p))
            if any(zl):
                nj = nu[j]
                for i in range(1, nj + 1):  # (34)/(35), bottom-aligned
                    for k in range(p):
                        if zl[k] == 0:
                            continue
                        l = nu[k] - nj + i
                        if l >= 1:
                            Z[j][i - 1] = Z[j][i - 1] - zeta[0, k] * Z[k][l - 1]
                            Psi[j][i - 1] = Psi[j][i - 1] - zeta[0, k] * Psi[k][l - 1]
                Zall = qc.qvstack([r for rows in Z for r in rows], n)
            new = Z[j][-1] * A
            if qc.qrank(qc.qvstack([Zall, new], n)) == rank_Z:  # Sub-case 2.1 (36)
                f[j] = False
                trace.append(Step1Trace(j + 1, "2/2.1", zl))
            else:  # Sub-case 2.2 (37)–(40)
                Z[j].append(new)
                Psi[j].append(Q(1, p))
                nu[j] += 1
                rank_Z += 1
                Zall = qc.qvstack([r for rows in Z for r in rows], n)
                trace.append(Step1Trace(j + 1, "2/2.2", zl))
    return _Step1(Z, Psi, nu, trace)


# ----------------------------------------------------------------------------------------
# the design
# ----------------------------------------------------------------------------------------
def _bounds(input_bounds: Any, m: int, what: str) -> tuple[Fraction, ...]:
    if input_bounds is None:
        if m:
            raise DimensionError(f"input_bounds: {m} bound(s) needed ({what}), got None")
        return ()
    if isinstance(input_bounds, (int, float, str, Fraction)):
        input_bounds = [input_bounds] * m
    out = tuple(exact_fraction(x, f"input_bounds[{i}]") for i, x in enumerate(input_bounds))
    if len(out) != m:
        raise DimensionError(f"input_bounds has {len(out)} entries; expected {m} ({what})")
    for i, x in enumerate(out):
        if x < 0:
            raise DomainError(f"input_bounds[{i}] = {x} must be ≥ 0")
    return out


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
        ``max(safety · Σ_i L_i |d̄_{e_j,i}|, lipschitz_floor)``; ``safety = 8`` and
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
        ``T, Gamma, mu, A_bar, D_bar, C_bar, Pi_bar, beta`` and the rest.

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
    Niederwieser et al. (2022), Section 4.1, Steps 1–4, eqs. (28)–(54), with the
    these choices where the paper leaves them open: round robin over active chains,
    minimum-norm ζ in (33), stable sort in (41), Step 3 by the element-wise form of
    (11b) instead of the garbled (49) (docs/errata.md, N2).
    Appendix A.1 for ``D ≠ 0``; Section 5.4 for ``reconstruct_input``.
    Exact over Q; cost dominated by O(n) exact ranks of n×n matrices.

    Examples
    --------
    A double integrator with the unknown input at the acceleration:

    >>> from uio_ring import DelaySystem
    >>> des = design_normal_form(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None), ["0.5"])
    >>> des.mu, des.T, des.d_bar_rows(), [float(k) for k in des.kappa[0]]
    ((2,), PolyMatrix([[1, 0], [0, 1]]), ((Fraction(1, 1),),), [4.74341649025, 11.0])
    """
    rep = normal_form_applicable(sys) if report is None else report  # decisive: Smith form of P(s)
    if not rep.ok:
        raise NotObservableError(f"the observer normal form does not apply: {rep.reason}", report=rep)
    M = {k: qc.qmat(v, k) for k, v in sys.matrices().items()}
    n, m, p, nu_ = sys.n_x, sys.n_w, sys.n_y, sys.n_u
    bounds = _bounds(input_bounds, m, "bounds of |w'|" if reconstruct_input else "bounds of |w|")
    mod = _model(M, n, m, p, nu_, reconstruct_input)
    A, D, C = mod.A, mod.B, mod.C
    nm, pm = A.nrows(), C.nrows()
    # bounds of the model's unknown input: w̃_1 = w_transform · w
    mb = tuple(
        sum((abs(qc.frac(mod.w_transform[i, j])) * bounds[j] for j in range(m)), Fraction(0))
        for i in range(mod.w_transform.nrows())
    )

    # ---- Step 1
    s1 = _step1(A, D, C)
    Zall = qc.qvstack([r for rows in s1.Z for r in rows], nm)
    if sum(s1.nu) != nm or qc.qrank(Zall) != nm:  # pragma: no cover - excluded by the applicability test
        raise NotObservableError(f"Step 1 stopped with rank Z = {qc.qrank(Zall)} < n = {nm}")
    order = sorted(range(pm), key=lambda j: -s1.nu[j])  # stable sort (41)
    mu = [s1.nu[j] for j in order]
    Gamma = qc.qvstack([s1.Psi[j][0] for j in order], pm)
    R_rows = []
    for j in range(pm):
        R_rows += s1.Psi[j][1:] + [Q(1, pm)]
    R = qc.qvstack(R_rows, pm)
    Xi = qc.qsolve(Zall, R, "Z")
    A_c = A + Xi * C
    C_c = Gamma * C

    # ---- Step 2: O_R (25) and t_{e_j} (47)
    O_rows = []
    for k in range(pm):
        row_k = _row(C_c, k)
        for _ in range(mu[k]):
            O_rows.append(row_k)
            row_k = row_k * A_c
    O_R = qc.qvstack(O_rows, nm)
    ends = []
    b = 0
    for mk in mu:
        b += mk
        ends.append(b - 1)
    # Steps 2–4 run in the coordinates z = O_R x, where Ǎ becomes the block companion matrix
    # Ã = O_R Ǎ O_R⁻¹ (row (k, i) of O_R times Ǎ is row (k, i + 1); only the last row of each
    # chain, č_k Ǎ^{μ_k} O_R⁻¹, is dense), t_{e_k} becomes the unit vector e_{e_k} (47) and č_r
    # the row e_{b_r}ᵀ.  The numbers stay small; T = O_R⁻¹ T̃ is formed once at the end.
    starts = [e - mk + 1 for e, mk in zip(ends, mu, strict=True)]
    last_rows = qc.qvstack([O_rows[e] * A_c for e in ends], nm)  # č_k Ǎ^{μ_k}
    L = qc.qsolve(O_R.transpose(), last_rows.transpose(), "O_R").transpose()  # (č_k Ǎ^{μ_k}) O_R⁻¹
    A_z = Q(nm, nm)
    for k in range(pm):
        for i in range(starts[k], ends[k]):
            A_z[i, i + 1] = 1
        for c in range(nm):
            A_z[ends[k], c] = L[k, c]
    # powers Ã^i e_{e_k}, i = 0 … μ_1 − 1
    pw: list[list[Q]] = []
    for k in range(pm):
        v = Q(nm, 1)
        v[ends[k], 0] = 1
        lst = [v]
        for _ in range(max(mu) - 1):
            v = A_z * v
            lst.append(v)
        pw.append(lst)

    def ct(r: int, k: int, s: int) -> Any:  # č_r Ǎ^k t_{e_s} = (Ã^k e_{e_s})[b_r]
        return pw[s][k][starts[r], 0]

    # ---- Step 3: β (48)–(53)
    beta: dict[tuple[int, int, int], Fraction] = {}
    for j in range(pm - 1):
        later = [r for r in range(j + 1, pm) if mu[r] < mu[j]]
        if not later:
            continue
        sizes = [mu[j] - mu[r] for r in later]
        N = sum(sizes)
        H = Q(N, N)
        w = Q(N, 1)
        ro = 0
        for ri, r in enumerate(later):
            for a in range(1, sizes[ri] + 1):
                w[ro + a - 1, 0] = ct(r, mu[j] - a, j)
                co = 0
                for si, s in enumerate(later):
                    for bb in range(1, sizes[si] + 1):
                        e = mu[s] + bb - a - 1
                        if e >= 0:
                            H[ro + a - 1, co + bb - 1] = ct(r, e, s)
                    co += sizes[si]
            ro += sizes[ri]
        # det H^(j) = 1 (Lemma 4.1(c)) and H^(j) is triangular up to permutations: substitution
        sol = qc.solve_by_peeling(H, w)
        if sol is None:  # pragma: no cover - general elimination as a fallback
            sol = qc.qsolve(H, w, f"H^({j + 1})")
        ro = 0
        for ri, r in enumerate(later):
            for bb in range(1, sizes[ri] + 1):
                beta[(j + 1, r + 1, mu[r] + bb - 1)] = qc.frac(sol[ro + bb - 1, 0])
            ro += sizes[ri]

    # ---- Step 4: the columns of T (54)
    T = Q(nm, nm)
    for j in range(pm):
        for i in range(mu[j]):
            col = pw[j][i]
            for r in range(j + 1, pm):
                for q in range(1, i + 1):
                    bv = beta.get((j + 1, r + 1, mu[j] - q), Fraction(0))
                    if bv:
                        col = col - flint.fmpq(bv.numerator, bv.denominator) * pw[r][i - q]
            c = ends[j] - i
            for row in range(nm):
                T[row, c] = col[row, 0]
    T = qc.qsolve(O_R, T, "O_R")  # back from z = O_R x
    T_inv = qc.qinverse(T, "T")
    A_bar = T_inv * (A * T)
    D_bar = T_inv * D
    C_bar = Gamma * C * T
    B_bar = T_inv * mod.E
    Pi_bar = _cols(A_bar, starts)

    # ---- gains
    d_rows = [[qc.frac(D_bar[e, i]) for i in range(D_bar.ncols())] for e in ends]
    need = [sum((abs(d) * L for d, L in zip(row, mb, strict=True)), Fraction(0)) for row in d_rows]
    if gains is not None:
        if len(gains) != pm:
            raise DimensionError(f"gains has {len(gains)} chains; the normal form has {pm} (mu = {tuple(mu)})")
        kappa = []
        for j, g in enumerate(gains):
            gj = tuple(exact_fraction(x, f"gains[{j}][{i}]") for i, x in enumerate(g))
            if len(gj) != mu[j]:
                raise DimensionError(f"gains[{j}] has {len(gj)} entries; chain {j + 1} has length {mu[j]}")
            kappa.append(gj)
        lips = tuple(Fraction(0) for _ in range(pm))
    else:
        if lipschitz is not None:
            if len(lipschitz) != pm:
                raise DimensionError(f"lipschitz has {len(lipschitz)} entries; expected {pm} (one per chain)")
            lips = tuple(exact_fraction(x, f"lipschitz[{j}]") for j, x in enumerate(lipschitz))
        else:
            sf, fl = exact_fraction(safety, "safety"), exact_fraction(lipschitz_floor, "lipschitz_floor")
            lips = tuple(max(sf * nd, fl) for nd in need)
        kappa = [levant_gains(mu[j], lips[j], lambdas=lambdas) for j in range(pm)]
    for j in range(pm):
        if need[j] and not kappa[j][-1] > need[j]:
            raise DomainError(
                f"gains of chain {j + 1} violate the necessary condition (18): κ_{{{j + 1},0}} = {kappa[j][-1]} "
                f"≤ Σ_i L_i |d̄_{{e_{j + 1},i}}| = {need[j]} (≈ {float(need[j]):.6g})"
            )

    sm = mod.state_map * T
    wm = None if mod.w_map is None else mod.w_map * T
    model = DelaySystem(_pm(A), _pm(D) if D.ncols() else PolyMatrix.zeros(nm, 0),
                        _pm(C) if C.nrows() else PolyMatrix.zeros(0, nm), None,
                        E=_pm(mod.E) if mod.E.ncols() else None)
    return NormalFormDesign(
        system=sys,
        model=model,
        T=_pm(T),
        T_inverse=_pm(T_inv),
        Gamma=_pm(Gamma),
        Xi=_pm(Xi),
        A_check=_pm(A_c),
        C_check=_pm(C_c),
        nu=tuple(s1.nu),
        mu=tuple(mu),
        order=tuple(j + 1 for j in order),
        O_R=_pm(O_R),
        beta=beta,
        A_bar=_pm(A_bar),
        D_bar=_pm(D_bar) if D_bar.ncols() else PolyMatrix.zeros(nm, 0),
        C_bar=_pm(C_bar),
        B_bar=_pm(B_bar) if B_bar.ncols() else PolyMatrix.zeros(nm, 0),
        Pi_bar=_pm(Pi_bar),
        output_map=_pm(Gamma * mod.output_map),
        input_map=_pm(mod.input_map) if mod.input_map.nrows() else PolyMatrix.zeros(0, p + nu_),
        state_map=_pm(sm),
        w_map=None if wm is None else _pm(wm),
        U=_pm(mod.U) if p else PolyMatrix.zeros(0, 0),
        V=_pm(mod.V) if m else PolyMatrix.zeros(0, 0),
        m_F=mod.m_F,
        reconstruct_input=reconstruct_input,
        input_bounds=mb,
        lipschitz=lips,
        kappa=tuple(kappa),
        trace=tuple(s1.trace),
        applicability=rep,
    )
