"""The reduced-order super-twisting observer under the matching condition, with the
reconstruction of the unknown input (Bejarano, Fridman & Poznyak 2007, Section 3).

For ``x' = A x + B w + E u``, ``y = C x + F u`` with ``rank C B = rank B = q < p`` (the
paper's letters ``D, B`` are ``B, E`` here) and the reduction ``r = P x``
(:func:`~uio_ring.analysis.matched_reduction.matched_reduction`), Algorithm 3 is

* a Luenberger part for the w-free block, ``r̃' = A11 r̃ + A12 r_2 + B1 u + K (ȳ_1 − C̄ r̃)``
  with ``A11 − K C̄`` Hurwitz; its error ``r_1 − r̃`` obeys ``e' = (A11 − K C̄) e`` exactly,
  whatever ``w`` is;
* ``q = r̃ − r_a`` (``q' = K (ȳ_1 − C̄ r̃)``), the drift-free form of the paper's ``r_a``;
* ``l − 1`` super-twisting levels (gains ``λ_k, α_k``), level ``k`` a robust exact
  differentiator of ``σ_k = z^{(k−1)} + C̄ A11^{k−1} q`` with ``z^{(0)} = ȳ_1 − C̄ r̃``
  (37): once sliding, ``z^{(k)} = C̄ A11^k (r_1 − r̃)``;
* ``r̂_1 = r̃ + M_l^+ [z^{(0)}; …; z^{(l−1)}]`` (41) and ``x̂ = P⁻¹ [r̂_1; (C B)^+ (y − F u)]`` (44);
* the reconstruction of ``w`` (Section 3.4): one more super-twisting loop (gains
  ``λ_w, α_w``) on ``σ̄ = r_2 − r̂_2``, ``r̂_2' = A21 r̂_1 + A22 r_2 + B2 u + ū``: its
  ``z̄`` equals ``w`` once ``r̂_1 = r_1`` and the loop slides, ``ŵ = z̄`` (47).

For ``w = ΔA G x`` with constant ``ΔA``, :func:`uio_ring.sim.identification.estimate_uncertainty`
gives the least-squares estimate (49)/(51) from ``x̂`` and ``ŵ``.

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0, 1, 0], [0, 0, 1], [-1, -2, -3]]", "[[0], [0], [1]]", "[[1, 0, 0], [0, 0, 1]]", None)
>>> des = design_matched_sta(sys)
>>> des.l, des.certificate().ok, des.numeric().n_w
(2, True, 1)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any, ClassVar

from uio_ring.analysis.matched_reduction import MatchedReduction, left_pinv, matched_reduction
from uio_ring.analysis.strong_observability import is_hurwitz_polynomial
from uio_ring.design.base import ObserverDesign, matrix_to_data
from uio_ring.design.hierarchical_sta import _ackermann, _gain_pairs, exact_gain_matrix
from uio_ring.errors import DimensionError, DomainError, NotObservableError, for_option
from uio_ring.ring.certificate import Certificate
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import exact_fraction
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["MatchedSTADesign", "design_matched_sta", "DEFAULT_LEVEL_GAINS", "DEFAULT_W_GAINS"]

#: (λ, α) of every level when none are given: the paper's Example 2.
DEFAULT_LEVEL_GAINS = (Fraction(30), Fraction(20))
#: (λ, α) of the loop that reconstructs w when none are given (the paper gives none).
DEFAULT_W_GAINS = (Fraction(60), Fraction(60))


@dataclass(frozen=True, repr=False)
class MatchedSTADesign(ObserverDesign):
    """A reduced-order super-twisting observer with w reconstruction; see the module docstring.

    Attributes
    ----------
    system
    reduction
        The exact reduction (``P``, ``P⁻¹``, the blocks ``A11 … B2``, ``C̄``, ``M_1 … M_l``).
    K
        ``(n − q) × (p − q)``, ``A11 − K C̄`` Hurwitz.
    M_l_pinv
        ``M_l^+``: ``M_l^+ M_l = I``.
    gains
        ``(λ_k, α_k)`` per level (``l − 1`` levels).
    w_gains
        ``(λ_w, α_w)`` of the loop that reconstructs ``w``.
    """

    method: ClassVar[str] = "matched-sta"

    system: DelaySystem
    reduction: MatchedReduction
    K: PolyMatrix
    M_l_pinv: PolyMatrix
    gains: tuple[tuple[Fraction, Fraction], ...]
    w_gains: tuple[Fraction, Fraction]

    @property
    def l(self) -> int:  # noqa: E743 - the paper's name
        return len(self.reduction.M)

    @property
    def levels(self) -> int:
        return self.l - 1

    def certificate(self) -> Certificate:
        from uio_ring.verify.matched_sta import matched_sta_certificate

        return matched_sta_certificate(self)

    def numeric(self, *, h: Any = None) -> Any:
        """The float model, ``ξ = [r̃; q; (ζ, z) per component of every level; J; (ζ̄, z̄) per
        component of w; s]``: ``J' = A21 r̂_1 + A22 r_2 + B2 u`` (so ``r̂_2 = J + ζ̄``), and
        ``s`` a read-out block (``ẑ_s = s + y − F u``, ``s' = −s``, 0 unless an initial
        estimate is given).  Delay-free (``h`` is not used)."""
        from uio_ring.numeric.build import injection_from_exact, model_from_exact

        red, sys = self.reduction, self.system
        assert red.A11 is not None and red.C_bar is not None and red.CB_perp is not None  # noqa: S101
        assert red.CB_pinv is not None and red.P_inv is not None and red.B_perp is not None  # noqa: S101
        assert red.A12 is not None and red.A21 is not None and red.A22 is not None  # noqa: S101
        assert red.B1 is not None and red.B2 is not None  # noqa: S101
        n, p, q, nu = sys.n_x, sys.n_y, sys.n_w, sys.n_u
        m, pc, lv = n - q, p - q, self.levels
        Z = PolyMatrix.zeros
        Fu = sys.F
        # index layout
        i_r, i_q, i_lv = 0, m, 2 * m
        i_J = i_lv + 2 * pc * lv
        i_w = i_J + q
        i_s = i_w + 2 * q
        nz = i_s + p

        def rows_at(M: PolyMatrix, col: int) -> PolyMatrix:
            """M placed at columns col … col + M.cols − 1 of an n_z-wide block."""
            return PolyMatrix.hstack(*([Z(M.rows, col)] if col else []), M,
                                     *([Z(M.rows, nz - col - M.cols)] if nz - col - M.cols else []))

        def pick(cols: Sequence[int]) -> PolyMatrix:
            return PolyMatrix([[1 if c == j else 0 for c in range(nz)] for j in cols], shape=(len(cols), nz))

        A11, A12, A21, A22, B1, B2, Cb = red.A11, red.A12, red.A21, red.A22, red.B1, red.B2, red.C_bar
        K, CBp, CBperp = self.K, red.CB_pinv, red.CB_perp
        z_cols = [[i_lv + 2 * (k * pc + i) + 1 for i in range(pc)] for k in range(lv)]
        # r̂_1 = R_xi ξ + R_y (y − F u)
        stack_xi = PolyMatrix.vstack(rows_at(-Cb, i_r), *(pick(c) for c in z_cols))
        stack_y = PolyMatrix.vstack(CBperp, *(Z(pc, p) for _ in z_cols))
        R_xi = rows_at(PolyMatrix.identity(m), i_r) + self.M_l_pinv @ stack_xi
        R_y = self.M_l_pinv @ stack_y
        # linear part
        F_rows = [rows_at(A11 - K @ Cb, i_r), rows_at(-(K @ Cb), i_r)]
        Gy_rows = [A12 @ CBp + K @ CBperp, K @ CBperp]
        chain = [[1 if (r % 2 == 0 and c == r + 1) else 0 for c in range(2 * pc * lv)] for r in range(2 * pc * lv)]
        if lv:
            F_rows.append(rows_at(PolyMatrix(chain, shape=(2 * pc * lv, 2 * pc * lv)), i_lv))
            Gy_rows.append(Z(2 * pc * lv, p))
        F_rows.append(A21 @ R_xi)
        Gy_rows.append(A21 @ R_y + A22 @ CBp)
        F_rows.append(rows_at(PolyMatrix([[1 if (r % 2 == 0 and c == r + 1) else 0 for c in range(2 * q)]
                                          for r in range(2 * q)], shape=(2 * q, 2 * q)), i_w))
        Gy_rows.append(Z(2 * q, p))
        F_rows.append(rows_at(-PolyMatrix.identity(p), i_s))
        Gy_rows.append(Z(p, p))
        Fm, G_y = PolyMatrix.vstack(*F_rows), PolyMatrix.vstack(*Gy_rows)
        known = [B1, Z(m, nu)] + ([Z(2 * pc * lv, nu)] if lv else []) + [B2, Z(2 * q, nu), Z(p, nu)]
        G_u = PolyMatrix.vstack(*known) - G_y @ Fu
        # the chains: levels in order, then the w loop
        starts, sig_y, sig_xi = [], [], []
        for k in range(lv):
            comp = [i_lv + 2 * (k * pc + i) for i in range(pc)]
            Mq = Cb @ _power(A11, k)
            if k == 0:  # σ_1 = ȳ_1 − C̄ r̃ + C̄ q
                sig_y.append(CBperp)
                sig_xi.append(rows_at(-Cb, i_r) + rows_at(Cb, i_q))
            else:  # σ_k = z^{(k−1)} + C̄ A11^{k−1} q
                sig_y.append(Z(pc, p))
                sig_xi.append(pick(z_cols[k - 1]) + rows_at(Mq, i_q))
            starts += comp
        starts += [i_w + 2 * i for i in range(q)]
        sig_y.append(CBp)  # σ̄ = r_2 − J − ζ̄
        sig_xi.append(rows_at(-PolyMatrix.identity(q), i_J))
        S_y = PolyMatrix.vstack(*sig_y)
        gains = [g for g in self.gains for _ in range(pc)] + [self.w_gains] * q
        injection = injection_from_exact(
            starts=tuple(starts), lengths=tuple(2 for _ in starts), gains=gains,
            sigma_y=S_y, sigma_u=-(S_y @ Fu), sigma_xi=PolyMatrix.vstack(*sig_xi),
        )
        # outputs: x̂ = P⁻¹ [r̂_1; r_2] with y − F u read from ẑ_s
        Pi1, Pi2 = red.P_inv[:, 0:m], red.P_inv[:, m:n]
        X = Pi1 @ R_xi + rows_at(Pi1 @ R_y + Pi2 @ CBp, i_s)
        W = pick([i_w + 2 * i + 1 for i in range(q)])
        D_y = PolyMatrix.vstack(Z(i_s, p), PolyMatrix.identity(p))
        init_x = PolyMatrix.vstack(red.B_perp, Z(i_s - m, n), sys.C)  # r̃(0) = B^⊥ x̂0, ẑ_s(0) = C x̂0
        initial = PolyMatrix.hstack(init_x, Z(nz, q))  # [x̂0; ŵ0]: ŵ0 is not used
        return model_from_exact(F=Fm, G_y=G_y, G_u=G_u if nu else None, D_y=D_y, D_u=-(D_y @ Fu) if nu else None,
                                X=X, W=W, initial=initial, injection=injection, interpolation="linear",
                                method=self.method)

    # -- display and data --------------------------------------------------------------
    def __repr__(self) -> str:
        return (f"MatchedSTADesign(l={self.l}, levels={self.levels}, gains={[[str(g) for g in ga] for ga in self.gains]}, "
                f"w_gains={[str(g) for g in self.w_gains]})")

    def __str__(self) -> str:
        red = self.reduction
        lines = [f"reduced-order super-twisting observer with w reconstruction (Bejarano, Fridman & Poznyak 2007, "
                 f"Section 3): n − q = {self.system.n_x - self.system.n_w}, l = {self.l}, {self.levels} level(s)",
                 "  P =\n    " + str(red.P).replace("\n", "\n    "),
                 "  A11 =\n    " + str(red.A11).replace("\n", "\n    "),
                 "  C̄ =\n    " + str(red.C_bar).replace("\n", "\n    "),
                 "  K =\n    " + str(self.K).replace("\n", "\n    ")]
        for k, (lam, alpha) in enumerate(self.gains, start=1):
            lines.append(f"  level {k}: λ = {lam}, α = {alpha}")
        lines.append(f"  w loop: λ = {self.w_gains[0]}, α = {self.w_gains[1]}")
        return "\n".join(lines)

    def to_latex(self) -> str:
        return (r"\hat x = P^{-1}\begin{bmatrix}\tilde r + M_l^+ z\\ (CB)^+ (y - F u)\end{bmatrix},\; "
                r"\hat w = \bar z,\; P = " + (self.reduction.P or PolyMatrix.zeros(0, 0)).to_latex())

    def to_dict(self) -> dict[str, Any]:
        red = self.reduction
        out: dict[str, Any] = {"method": self.method, "l": self.l, "K": matrix_to_data(self.K),
                               "gains": [[str(g) for g in ga] for ga in self.gains],
                               "w_gains": [str(g) for g in self.w_gains]}
        for name in ("P", "P_inv", "A11", "A12", "A21", "A22", "B1", "B2", "C_bar"):
            out[name] = matrix_to_data(getattr(red, name))
        out["M"] = [matrix_to_data(M) for M in red.M]
        return out


def _power(A: PolyMatrix, k: int) -> PolyMatrix:
    out = PolyMatrix.identity(A.rows)
    for _ in range(k):
        out = out @ A
    return out


def design_matched_sta(
    sys: DelaySystem,
    *,
    K: Any = None,
    poles: Sequence[Any] | None = None,
    gains: Any = None,
    w_gains: Any = None,
    report: MatchedReduction | None = None,
) -> MatchedSTADesign:
    """Design the observer of Algorithm 3 with the reconstruction of w (Section 3.4).

    Parameters
    ----------
    sys
        Delay-free, ``D = 0``, ``rank C B = rank B = q < p``, strongly observable.
    K
        ``(n − q) × (p − q)`` with ``A11 − K C̄`` Hurwitz, in the coordinates of
        :func:`~uio_ring.analysis.matched_reduction.matched_reduction`.  Default: 0 when
        ``A11`` is Hurwitz, else the exact gain placing ``poles``.
    poles
        ``n − q`` exact rationals, the spectrum of ``A11 − K C̄`` (default ``−1, …`` when
        ``A11`` is not Hurwitz).
    gains
        ``[[λ_1, α_1], …]`` per level (``l − 1``); default :data:`DEFAULT_LEVEL_GAINS`.
    w_gains
        ``[λ_w, α_w]`` of the w loop; default :data:`DEFAULT_W_GAINS`.  ``α_w`` must exceed
        a bound of ``|w'|`` (for ``w = ΔA G x``: of ``‖ΔA G ẋ‖``).
    report
        :func:`matched_reduction` of ``sys`` when computed already.
    """
    if not sys.is_delay_free:
        raise NotObservableError("the matched super-twisting observer is for delay-free systems")
    red = matched_reduction(sys) if report is None else report
    if not red.holds:
        raise NotObservableError(f"the matched super-twisting observer needs the matching condition and "
                                 f"strong observability: {red.reason}", report=red)
    assert red.A11 is not None and red.C_bar is not None  # noqa: S101
    m, pc = red.A11.rows, red.C_bar.rows
    if K is not None:
        if poles is not None:
            raise DomainError("give K or poles, not both")
        Km = exact_gain_matrix(K, (m, pc), "K")
    elif poles is None and is_hurwitz_polynomial(charpoly(red.A11)):
        Km = PolyMatrix.zeros(m, pc)
    else:
        vals = [exact_fraction(x, f"poles[{i}]") for i, x in enumerate(poles)] if poles is not None else \
            [Fraction(-(i + 1)) for i in range(m)]
        if len(vals) != m:
            raise for_option(DimensionError(f"poles has {len(vals)} value(s); expected n − q = {m}"), "poles")
        Km = _ackermann(red.A11, red.C_bar, vals)
    levels = len(red.M) - 1
    lg = _gain_pairs(gains, levels, default=DEFAULT_LEVEL_GAINS)
    wg = _gain_pairs([w_gains] if w_gains is not None else None, 1, default=DEFAULT_W_GAINS)[0]
    return MatchedSTADesign(system=sys, reduction=red, K=Km, M_l_pinv=left_pinv(red.M[-1]), gains=lg, w_gains=wg)
