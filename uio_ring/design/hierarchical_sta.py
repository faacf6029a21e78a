"""The hierarchical super-twisting observer (Bejarano, Fridman & Poznyak 2007, Section 2).

For a delay-free, strongly observable system ``x' = A x + B w + E u``, ``y = C x + D w + F u``
— no matching condition needed, ``D ≠ 0`` allowed — the observer estimates ``x`` exactly
after a finite time.  With Molinari's sequence ``M_1 … M_l``
(:func:`~uio_ring.analysis.molinari.molinari_sequence`) and the paper's letters mapped
onto the package's (paper ``D, F, B`` = package ``B, D, E``):

* a Luenberger part ``x̃' = A x̃ + E u + K (y − F u − C x̃)`` with ``A − K C`` Hurwitz;
* ``q = x̃ − x_a`` (``q' = K (y − F u − C x̃)``) and ``ι = ∫ (y − F u − C x̃)``: the
  drift-free form of the paper's auxiliary vector ``x_a`` and ``∫y`` (they grow without
  bound; their differences do not);
* ``l − 1`` levels, each a first-order robust exact differentiator (super-twisting,
  gains ``λ_k``, ``α_k``) of ``σ_k = S_k [z^{(k−1)} + M_k q; ι]`` with
  ``z^{(0)} = D^⊥ (y − F u − C x̃)``, ``S_k = T_{k,b}`` and ``S_{l−1} = M_l^+ T_{l−1,b}``:
  once level ``k − 1`` slides, ``σ_k' = M_{k+1}(x − x̃)`` (the unknown input is
  annihilated by ``T_{k,b}``), so its derivative estimate ``z^{(k)}`` is ``M_{k+1}(x − x̃)``;
* the estimate ``x̂ = x̃ + z^{(l−1)}`` (28).

The paper's (22) is garbled; this is (14)/(24), and ``D − K F`` (not ``D + K F``) in the
Luenberger error.  ``l = 1`` needs no sliding mode: ``x = M_1^+ D^⊥ (y − F u)``.

>>> from uio_ring import DelaySystem
>>> des = design_hierarchical_sta(DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None))
>>> des.l, des.certificate().ok, des.numeric().n_z
(2, True, 9)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from fractions import Fraction
from typing import Any, ClassVar

from uio_ring.analysis.molinari import MolinariSequence, molinari_sequence
from uio_ring.analysis.strong_observability import is_hurwitz_polynomial
from uio_ring.design.base import ObserverDesign, matrix_to_data
from uio_ring.errors import DimensionError, DomainError, NotObservableError, for_option
from uio_ring.ring.certificate import Certificate
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.inverse import left_inverse
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import exact_fraction
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["HierarchicalSTADesign", "design_hierarchical_sta", "DEFAULT_GAINS", "exact_gain_matrix"]

#: (λ, α) of every level when none are given: the values of the paper's Example 1.
DEFAULT_GAINS = (Fraction(15), Fraction(10))


@dataclass(frozen=True, repr=False)
class HierarchicalSTADesign(ObserverDesign):
    """A hierarchical super-twisting observer; see the module docstring for the equations.

    Attributes
    ----------
    system
    M, T_b
        Molinari's sequence (``M_1 … M_l``) and its annihilators (``T_{0,b} = D^⊥ … T_{l−1,b}``).
    M_l_pinv
        ``M_l^+ = (M_lᵀ M_l)⁻¹ M_lᵀ``: ``M_l^+ M_l = I``.
    K
        Luenberger gain, ``A − K C`` Hurwitz.
    S
        ``S_1 … S_{l−1}`` (``S_k = T_{k,b}``, the last ``M_l^+ T_{l−1,b}``).
    gains
        ``(λ_k, α_k)`` per level.
    """

    method: ClassVar[str] = "hierarchical-sta"
    noise_scope: ClassVar[str] = ("Luenberger stage x̃' = (A − K C) x̃ + K y (noise → x̃; the super-twisting "
                                  "levels that correct it are nonlinear and not counted)")

    system: DelaySystem
    M: tuple[PolyMatrix, ...]
    T_b: tuple[PolyMatrix, ...]
    M_l_pinv: PolyMatrix
    K: PolyMatrix
    S: tuple[PolyMatrix, ...]
    gains: tuple[tuple[Fraction, Fraction], ...]
    molinari: MolinariSequence | None = field(default=None, compare=False)
    gain_report: Any = field(default=None, compare=False)

    def gain_condition(self, *, w_bound: Any, e_bound: Any, theta: Any = None) -> Any:
        """The sufficient condition (16)/(21) on the gains for ``‖w‖ ≤ w_bound`` and
        ``‖x − x̃‖ ≤ e_bound``, level by level with its margins
        (:func:`~uio_ring.design.sta_gains.sta_gain_condition`)."""
        from uio_ring.design.sta_gains import sta_gain_condition

        return sta_gain_condition(self, w_bound=w_bound, e_bound=e_bound, theta=theta)

    @property
    def l(self) -> int:  # noqa: E743 - the paper's name
        return len(self.M)

    @property
    def levels(self) -> int:
        return len(self.S)

    def certificate(self) -> Certificate:
        from uio_ring.verify.hierarchical_sta import hierarchical_sta_certificate

        return hierarchical_sta_certificate(self)

    def linear_model(self, *, h: Any = None) -> Any:
        """The Luenberger stage ``x̃' = (A − K C) x̃ + K y``, ``x̂ = x̃`` (known inputs omitted):
        the linear part whose poles ``K`` places; the levels above it are nonlinear.

        >>> from uio_ring import DelaySystem
        >>> sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None)
        >>> design_hierarchical_sta(sys, poles=[-1, -2]).linear_model().F.tolist()
        [[-3.0, 1.0], [-2.0, 0.0]]
        """
        from uio_ring.numeric.build import model_from_exact

        sys = self.system
        return model_from_exact(F=sys.A - self.K @ sys.C, G_y=self.K, X=PolyMatrix.identity(sys.n_x),
                                method=self.method)

    def numeric(self, *, h: Any = None) -> Any:
        """The float model: ``ξ = [x̃; q; ι; (ζ, z) per component of every level]`` with one
        super-twisting chain per component (``σ`` reads ``x̃, q, ι`` and the previous level's
        ``z``: ``sigma_xi``).  Delay-free (``h`` is not used)."""
        from uio_ring.numeric.build import injection_from_exact, model_from_exact

        sys = self.system
        n, p, nu = sys.n_x, sys.n_y, sys.n_u
        Z, I_n = PolyMatrix.zeros, PolyMatrix.identity
        rows = [S.rows for S in self.S]
        n_chain = 2 * sum(rows)
        nz = 2 * n + p + n_chain
        C, K, A, E, F = sys.C, self.K, sys.A, sys.E, sys.F
        # linear part
        blocks = [[A - K @ C, Z(n, n), Z(n, p), Z(n, n_chain)],
                  [-(K @ C), Z(n, n), Z(n, p), Z(n, n_chain)],
                  [-C, Z(p, n), Z(p, p), Z(p, n_chain)]]
        chain = [[1 if (r % 2 == 0 and c == r + 1) else 0 for c in range(n_chain)] for r in range(n_chain)]
        blocks.append([Z(n_chain, n), Z(n_chain, n), Z(n_chain, p), PolyMatrix(chain, shape=(n_chain, n_chain))])
        Fm = PolyMatrix.block(blocks)
        G_y = PolyMatrix.vstack(K, K, I_n(p), Z(n_chain, p))
        G_u = PolyMatrix.vstack(E - K @ F, -(K @ F), -F, Z(n_chain, nu))
        # the chains: σ of level k, component i
        off = 2 * n + p
        starts, sig_y, sig_u, sig_xi = [], [], [], []
        prev_z: list[int] = []
        T0 = self.T_b[0]
        for k, S in enumerate(self.S):
            rho = self.M[k].rows
            S_top, S_bot = S[:, 0:rho], S[:, rho : rho + p]
            xi_rows = PolyMatrix.zeros(S.rows, nz)
            # [z^{(k−1)} + M_k q; ι]
            xi_map = PolyMatrix.hstack(Z(rho, n), self.M[k], Z(rho, p), Z(rho, n_chain))
            if k == 0:  # z^{(0)} = D^⊥ (y − F u − C x̃)
                xi_map = xi_map + PolyMatrix.hstack(-(T0 @ C), Z(rho, n + p + n_chain))
                y_map, u_map = S_top @ T0, -(S_top @ T0 @ F)
            else:
                sel = [[1 if c == prev_z[r] else 0 for c in range(nz)] for r in range(rho)]
                xi_map = xi_map + PolyMatrix(sel, shape=(rho, nz))
                y_map, u_map = Z(S.rows, p), Z(S.rows, nu)
            iota = PolyMatrix.hstack(Z(p, 2 * n), I_n(p), Z(p, n_chain))
            xi_rows = S_top @ xi_map + S_bot @ iota
            comp_starts = [off + 2 * i for i in range(S.rows)]
            starts += comp_starts
            sig_y.append(y_map)
            sig_u.append(u_map)
            sig_xi.append(xi_rows)
            prev_z = [s + 1 for s in comp_starts]
            off += 2 * S.rows
        lam_alpha = [g for g, r in zip(self.gains, rows, strict=True) for _ in range(r)]
        injection = None
        if self.S:
            injection = injection_from_exact(
                starts=tuple(starts), lengths=tuple(2 for _ in starts), gains=lam_alpha,
                sigma_y=PolyMatrix.vstack(*sig_y), sigma_u=PolyMatrix.vstack(*sig_u),
                sigma_xi=PolyMatrix.vstack(*sig_xi),
            )
            last = [[1 if c == prev_z[r] else 0 for c in range(nz)] for r in range(n)]
            X = PolyMatrix.hstack(I_n(n), Z(n, nz - n)) + PolyMatrix(last, shape=(n, nz))
            D_y, D_u = None, None
        else:  # l = 1: x = M_1^+ D^⊥ (y − F u), read out directly
            X = PolyMatrix.hstack(I_n(n), Z(n, nz - n))
            Fm = PolyMatrix.block([[-I_n(n), Z(n, nz - n)], [Z(nz - n, n), -I_n(nz - n)]])
            G_y, G_u = Z(nz, p), Z(nz, nu)
            D_y = PolyMatrix.vstack(self.M_l_pinv @ T0, Z(nz - n, p))
            D_u = PolyMatrix.vstack(-(self.M_l_pinv @ T0 @ F), Z(nz - n, nu))
        initial = PolyMatrix.vstack(I_n(n), Z(nz - n, n))
        return model_from_exact(F=Fm, G_y=G_y, G_u=G_u if nu else None, D_y=D_y, D_u=D_u if nu else None, X=X,
                                initial=initial, injection=injection, interpolation="linear", method=self.method)

    # -- display and data --------------------------------------------------------------
    def __repr__(self) -> str:
        return (f"HierarchicalSTADesign(l={self.l}, levels={self.levels}, "
                f"gains={[[str(g) for g in ga] for ga in self.gains]})")

    def __str__(self) -> str:
        lines = [f"hierarchical super-twisting observer (Bejarano, Fridman & Poznyak 2007): l = {self.l}, "
                 f"{self.levels} level(s), ranks of M_k {[M.rank() for M in self.M]}",
                 f"  x̂ = x̃ + z^({self.levels})" if self.levels else "  x̂ = M_1^+ D^⊥ (y − F u)",
                 "  K =\n    " + str(self.K).replace("\n", "\n    ")]
        for k, (lam, alpha) in enumerate(self.gains, start=1):
            lines.append(f"  level {k}: λ = {lam}, α = {alpha}, {self.S[k - 1].rows} component(s)")
        if self.gain_report is not None:
            lines.append("  " + str(self.gain_report).replace("\n", "\n  "))
        return "\n".join(lines)

    def to_latex(self) -> str:
        return (r"\hat x = \tilde x + z^{(" + str(self.levels) + r")},\; \dot{\tilde x} = A\tilde x + E u + "
                r"K(y - F u - C\tilde x),\; K = " + self.K.to_latex())

    def to_dict(self) -> dict[str, Any]:
        return {
            "method": self.method, "l": self.l, "ranks": [M.rank() for M in self.M],
            "K": matrix_to_data(self.K), "M": [matrix_to_data(M) for M in self.M],
            "S": [matrix_to_data(S) for S in self.S],
            "gains": [[str(g) for g in ga] for ga in self.gains],
        } | ({} if self.gain_report is None else {"gain_condition": self.gain_report.to_dict()})


def _ackermann(A: PolyMatrix, C: PolyMatrix, poles: Sequence[Fraction]) -> PolyMatrix:
    """An exact ``K`` with ``spec(A − K C) = poles``: Ackermann's formula on one combined
    output ``c = vᵀ C`` with ``(c, A)`` observable, ``K = p(A) O_c⁻¹ e_n vᵀ``, for ``v`` among
    the unit vectors, ``(1, …, 1)`` and ``(1, 2, …, p)``; the one of smallest largest entry
    (a single output channel needs large gains when it observes some states weakly)."""
    n, p = A.rows, C.rows
    coeffs = [Fraction(1)]
    for r in poles:  # Π (s − r), highest power first
        nxt = coeffs + [Fraction(0)]
        for i in range(1, len(nxt)):
            nxt[i] -= r * coeffs[i - 1]
        coeffs = nxt
    pA = PolyMatrix.zeros(n, n)
    power = PolyMatrix.identity(n)
    for a in reversed(coeffs):  # Σ_i coeffs[n − i] A^i
        pA = pA + power * a
        power = power @ A
    e_n = PolyMatrix([[1 if i == n - 1 else 0] for i in range(n)], shape=(n, 1))
    choices = [[1 if j == i else 0 for j in range(p)] for i in range(p)] + [[1] * p, [i + 1 for i in range(p)]]
    best: tuple[Fraction, PolyMatrix] | None = None
    for v in choices:
        vrow = PolyMatrix([v], shape=(1, p))
        rows = [vrow @ C]
        for _ in range(n - 1):
            rows.append(rows[-1] @ A)
        O = PolyMatrix.vstack(*rows)
        if O.rank() < n:
            continue
        K = pA @ left_inverse(O) @ e_n @ vrow
        size = max(abs(x) for row in K.coefficient_lists()[0] for x in row) if not K.is_zero() else Fraction(0)
        if best is None or size < best[0]:
            best = (size, K)
    if best is None:
        raise NotObservableError("no single combination of the outputs makes (c, A) observable; give K")
    return best[1]


def _gain_pairs(gains: Any, levels: int, *, default: tuple[Fraction, Fraction] = DEFAULT_GAINS,
                name: str = "gains") -> tuple[tuple[Fraction, Fraction], ...]:
    """``[[λ, α], …]`` read exactly, one pair per level (``default`` for every level when None)."""
    if gains is None:
        return tuple(default for _ in range(levels))
    rows = list(gains)
    if len(rows) != levels:
        raise for_option(DimensionError(f"{name} has {len(rows)} level(s); the observer has {levels} (l − 1)"), name)
    out = []
    for k, g in enumerate(rows):
        pair = tuple(exact_fraction(x, f"{name}[{k}][{i}]") for i, x in enumerate(g))
        if len(pair) != 2 or not all(x > 0 for x in pair):
            raise for_option(DomainError(f"{name}[{k}] = [{', '.join(str(x) for x in g)}]: expected two positive values "
                                         "[λ, α]"), name)
        out.append((pair[0], pair[1]))
    return tuple(out)


def exact_gain_matrix(K: Any, shape: tuple[int, int], name: str = "K") -> PolyMatrix:
    """A gain given as a PolyMatrix or as rows of exact numbers, checked against ``shape``."""
    Km = K if isinstance(K, PolyMatrix) else PolyMatrix([[str(x) if not isinstance(x, str) else x for x in r]
                                                          for r in K])
    if Km.shape != shape:
        raise for_option(DimensionError(f"{name} is {Km.rows}×{Km.cols}; expected {shape[0]}×{shape[1]}"), name)
    return Km


def design_hierarchical_sta(
    sys: DelaySystem,
    *,
    K: Any = None,
    poles: Sequence[Any] | str | None = None,
    gains: Any = None,
    rate: Any = None,
    criterion: str | None = None,
    w_bound: Any = None,
    e_bound: Any = None,
    theta: Any = None,
    report: MolinariSequence | None = None,
) -> HierarchicalSTADesign:
    """Design the hierarchical super-twisting observer (Algorithm 2 of the paper).

    Parameters
    ----------
    sys
        Delay-free and strongly observable (no invariant zeros); no matching condition.
    K
        The Luenberger gain (``A − K C`` must be Hurwitz).  Default: 0 when ``A`` is
        Hurwitz, else the exact gain placing ``poles``.
    poles
        ``n`` exact rationals for ``spec(A − K C)`` (Ackermann's formula on one combined
        output, exact — its gains can be large, which the super-twisting levels must then
        dominate: prefer a K of your own when they are); default ``−1, …, −n`` when ``A`` is
        not Hurwitz.  ``"min-noise"``: the pole set of least noise gain of the Luenberger
        stage (:attr:`HierarchicalSTADesign.noise_scope`) among ``−rate·(1, q, q², …)``
        (:func:`~uio_ring.design.noise.search_poles`).
    rate, criterion
        With ``poles="min-noise"`` only: the slowest decay rate allowed (default
        ``⌈‖A‖∞⌉``) and ``"peak"`` (default) or ``"h2"`` (the figure minimised).
    gains
        ``[[λ_1, α_1], …]`` per level (``l − 1`` levels); default :data:`DEFAULT_GAINS` for
        every level (the values of the paper's Example 1).  The paper's sufficient
        condition on them is conservative (its own example violates it and converges):
        check convergence in simulation.
    w_bound, e_bound, theta
        Bounds ``‖w‖ ≤ w_bound`` and ``‖x − x̃‖ ≤ e_bound`` (after the Luenberger transient)
        and ``θ ∈ (0, 1)`` (default 1/10): without ``gains``, the gains are computed from the
        sufficient condition (16)/(21) (:func:`~uio_ring.design.sta_gains.gains_from_bounds`);
        with ``gains``, they are checked against it.  Either way ``design.gain_report`` says
        whether the condition holds and with which margins.
    report
        :func:`~uio_ring.analysis.molinari.molinari_sequence` of ``sys`` when computed already.

    Raises
    ------
    NotObservableError
        The system has delays or is not strongly observable (the sequence stalls).
    """
    if not sys.is_delay_free:
        raise NotObservableError("the hierarchical super-twisting observer is for delay-free systems")
    seq = molinari_sequence(sys) if report is None else report
    if not seq.holds:
        raise NotObservableError(f"the hierarchical super-twisting observer needs strong observability: "
                                 f"{seq.reason}", report=seq)
    n, p = sys.n_x, sys.n_y
    A, C = sys.A, sys.C
    if isinstance(poles, str):
        from uio_ring.design.noise import read_noise_options, search_poles

        if K is not None:
            raise DomainError("give K or poles, not both")
        alpha, crit = read_noise_options(sys, poles, rate, criterion)
        return search_poles(lambda pat: design_hierarchical_sta(sys, poles=pat, gains=gains, w_bound=w_bound,
                                                                 e_bound=e_bound, theta=theta, report=seq), n,
                            rate=alpha, criterion=crit, model=lambda d: d.linear_model())[1]
    if rate is not None or criterion is not None:
        raise DomainError("rate and criterion apply to poles='min-noise' only")
    if K is not None:
        if poles is not None:
            raise DomainError("give K or poles, not both")
        Km = exact_gain_matrix(K, (n, p))
    elif poles is None and is_hurwitz_polynomial(charpoly(A)):
        Km = PolyMatrix.zeros(n, p)
    else:
        vals = [exact_fraction(x, f"poles[{i}]") for i, x in enumerate(poles)] if poles is not None else \
            [Fraction(-(i + 1)) for i in range(n)]
        if len(vals) != n:
            raise for_option(DimensionError(f"poles has {len(vals)} value(s); expected n_x = {n}"), "poles")
        Km = _ackermann(A, C, vals)
    l = seq.l or 0
    M_l = seq.M[-1]
    M_l_pinv = left_inverse(M_l.T @ M_l) @ M_l.T
    S = [seq.T_b[k] for k in range(1, l)]
    if S:
        S[-1] = M_l_pinv @ S[-1]
    des = HierarchicalSTADesign(
        system=sys, M=seq.M, T_b=seq.T_b, M_l_pinv=M_l_pinv, K=Km, S=tuple(S),
        gains=_gain_pairs(gains, len(S)), molinari=seq,
    )
    if w_bound is None:
        if e_bound is not None or theta is not None:
            raise for_option(DomainError("e_bound and theta go with w_bound (the gain condition (16)/(21))"), "w_bound")
        return des
    from uio_ring.design.sta_gains import gains_from_bounds, sta_gain_condition

    if gains is None:
        des = replace(des, gains=gains_from_bounds(des, w_bound=w_bound, e_bound=e_bound, theta=theta))
    return replace(des, gain_report=sta_gain_condition(des, w_bound=w_bound, e_bound=e_bound, theta=theta))
