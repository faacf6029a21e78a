"""The delay unknown-input observer of Zheng, Bejarano, Perruquetti & Richard (2015).

For ``x' = A(δ)x + B(δ)w + E(δ)u``, ``y = C(δ)x + D(δ)w + F(δ)u`` satisfying
Assumptions 1 and 2, Steps 1–5 of the paper give the observer (21)::

    ξ' = L0 ξ + J(δ) Λ(δ) y + J_u(δ) u
    ẑ  = ξ + H(δ) Λ(δ) y + H_u(δ) u
    x̂  = T_L⁻¹(δ) ẑ

with the error ``e = T x − ẑ`` obeying ``e' = (A0 − G0 C0) e`` exactly.  ``H``
and ``J`` follow the corrected formulas (22′) of docs/errata.md, Z1 (the printed
(22) is wrong whenever ``[F, 0] Γ̄_i ≠ 0``).  ``J_u``, ``H_u`` carry the known
input, which the paper does not treat: ``H_u = −H Λ F_u``,
``J_u = T E − J Λ F_u − H Λ C E`` (zero when there is no known input).

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0, 1], [d, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", "[[0], [0]]")
>>> des = design_zheng_bejarano(sys, poles=[-1])
>>> des.r, des.l_star, des.n_z, des.lag, des.certificate().ok
(2, 1, 2, 0, True)
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any

from uio_ring import _progress
from uio_ring.analysis.assumptions import check_assumptions
from uio_ring.analysis.rank_condition import matching_matrix
from uio_ring.analysis.report import AssumptionsReport
from uio_ring.design.delay_uio_design import DelayUIODesign
from uio_ring.errors import DimensionError, DomainError, NotObservableError, UioRingError
from uio_ring.ring._predicates import det_not_constant_mod_p, left_unimodular_proved
from uio_ring.ring.errors import NoPolynomialSolutionError
from uio_ring.ring.hermite import hermite
from uio_ring.ring.inverse import is_unimodular, left_inverse
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import exact_fraction
from uio_ring.ring.solve import solve_left
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["DelayUIODesign", "design_zheng_bejarano", "zheng_bejarano_from_choices", "smallest_observer_orders"]

_I = PolyMatrix.identity
_Z = PolyMatrix.zeros


# ----------------------------------------------------------------------------------------
# Steps 1–5 for given choices
# ----------------------------------------------------------------------------------------
def _gain_from_poles(poles: Sequence[Fraction], r: int) -> PolyMatrix:
    """``G0 = [g_1 I_r; …; g_l I_r]`` with ``s^l + g_1 s^{l−1} + … + g_l = Π (s − p_i)``,
    so that every channel of ``A0 − G0 C0`` is a companion matrix with those roots.

    Precondition: ``poles`` are Fractions (not checked).
    """
    coeffs = [Fraction(1)]  # high -> low: s^k + c1 s^{k-1} + ...
    for p in poles:
        nxt = coeffs + [Fraction(0)]
        for i in range(1, len(nxt)):
            nxt[i] -= p * coeffs[i - 1]
        coeffs = nxt
    blocks = [PolyMatrix.diag(*([coeffs[i]] * r)) if r else _Z(0, 0) for i in range(1, len(coeffs))]
    return PolyMatrix.vstack(*blocks) if blocks else _Z(0, r)


def _shift_matrices(r: int, l: int) -> tuple[PolyMatrix, PolyMatrix]:
    """``A0`` (block shift with ``I_r`` above the diagonal, ``r l × r l``) and
    ``C0 = [I_r, 0, …, 0]`` of (14)."""
    from uio_ring.ring import _backend as bk

    n = r * l
    zero, one = bk.ZERO, bk.ONE  # built from the ring's constants: no parsing of n² entries
    A0 = PolyMatrix._new([[one if j == i + r else zero for j in range(n)] for i in range(n)], n, n, "d")
    C0 = PolyMatrix._new([[one if j == i else zero for j in range(n)] for i in range(r)], r, n, "d")
    return A0, C0


def _default_poles(sys: DelaySystem, l_star: int, rate: Any = None) -> tuple[Fraction, ...]:
    """``l*`` poles at ``−α``: α = ``rate``, or :func:`~uio_ring.design.noise.default_rate`."""
    from uio_ring.design.noise import default_rate

    alpha = default_rate(sys) if rate is None else exact_fraction(rate, "rate")
    if alpha <= 0:
        raise DomainError(f"rate = {alpha} must be > 0 (the decay rate of the observer error)")
    return tuple(-alpha for _ in range(l_star))


def _read_poles(poles: Sequence[Any] | None, l_star: int) -> tuple[Fraction, ...]:
    """Validate the requested spectrum: ``l*`` exact rationals (precondition: not None)."""
    if getattr(poles, "ndim", None) == 1 and hasattr(poles, "dtype"):
        poles = list(poles)  # type: ignore[arg-type]  # a 1-D NumPy array: its scalars follow the NumPy number rule
    if isinstance(poles, (str, bytes)) or not isinstance(poles, Sequence):
        count = f"{l_star} " if l_star else ""
        raise DomainError(f"poles must be a list of {count}rationals, not {poles!r}")
    values = tuple(exact_fraction(p, f"poles[{i}]") for i, p in enumerate(poles))
    if len(values) != l_star:
        raise DimensionError(
            f"poles has {len(values)} value(s); expected l* = {l_star} (the spectrum of "
            f"A0 − G0 C0 on each output channel; this design has l* = {l_star})"
        )
    return values


@dataclass(frozen=True)
class _ObservabilityIndex:
    """Step 3: the least ``l*`` with ``Ō_{l*}`` left unimodular, and ``O = Ō_{l*}``;
    ``solved`` (when known) is ``X`` with ``X·Ō = [I_n; C̄ Ā^{l*}]``, each row reduced modulo
    the Popov basis of Ō's left kernel (:func:`~uio_ring.ring.solve.solve_left`): its first
    n rows are the reduced left inverse, the witness that Ō is left unimodular."""

    l_star: int
    O: PolyMatrix
    solved: PolyMatrix | None = field(default=None, compare=False)
    next_block: PolyMatrix | None = field(default=None, compare=False)  # C̄ Ā^{l*} with ``solved``


class _RowSpaceAtZero:
    """The row space over Q of the blocks added so far, evaluated at δ = 0: a basis in
    reduced row echelon form (flint ``fmpq_mat.rref``, exact), extended block by block, so
    that the rank of ``Ō_l(0)`` costs one small echelon per block instead of the rank of
    the whole stack.

    >>> rs = _RowSpaceAtZero(2)
    >>> rs.add(PolyMatrix("[[1, d]]")); rs.rank
    1
    >>> rs.add(PolyMatrix("[[2, 3*d], [d, 1]]")); rs.rank
    2
    """

    def __init__(self, n: int) -> None:
        self.n = n
        self.rank = 0
        self._rows: list[Any] = []  # flattened constant coefficients of the basis rows

    def add(self, M: PolyMatrix) -> None:
        import flint

        if self.rank == self.n or M.rows == 0:
            return
        new = [p[0] for row in M._r for p in row]  # M(0): the constant coefficients
        rows = self.rank + M.rows
        echelon, rank = flint.fmpq_mat(rows, self.n, self._rows + new).rref()
        self.rank = rank
        self._rows = [echelon[i, j] for i in range(rank) for j in range(self.n)]


def _observability_index(A_bar: PolyMatrix, C_bar: PolyMatrix, n: int, *, solve: bool = True
                         ) -> _ObservabilityIndex | None:
    """Least ``l`` with ``Ō_l = [C̄; C̄Ā; …; C̄Ā^{l−1}]`` left unimodular, and ``Ō_l``.

    ``None`` when there is none: by Cayley–Hamilton over Q[δ] the row module of
    ``Ō_l`` is constant from ``l = n`` on, so ``l ≤ max(n, 1)`` suffices.  A left
    unimodular matrix has full column rank at every δ, so ``Ō_l(0)`` is tested
    first (exact, cheap) and the unimodularity test runs only when it passes.
    The test is the solve of ``X·Ō = [I; C̄ Ā^l]`` that the design needs anyway; with
    ``solve=False`` (only ``l*`` is wanted: ``uio-ring check``) two coprime compressed
    maximal minors prove it first when they are cheap
    (:func:`~uio_ring.ring._predicates.left_unimodular_proved`), and the solve runs only
    when they do not: X can be far larger than the proof (a 4-state system of δ-degree
    8 with 4 outputs: X of 31-kbit coefficients, 7 s, against 37 ms for the minors; a
    12-state one with 12 outputs: 77 s against 5 s).  A square ``Ō`` whose determinant
    has positive degree modulo a prime has no inverse: it is skipped without the solve,
    which would fail only after its work (an 8-state system with 8 outputs at δ-degree 8:
    Ō 8×8 of degree 64, 18 s).
    """
    r = C_bar.rows
    if r == 0:
        return None
    blocks = [C_bar]
    at_zero = _RowSpaceAtZero(n)
    at_zero.add(C_bar)
    last = C_bar
    for l in range(1, max(n, 1) + 1):
        if l > 1:
            last = last @ A_bar
            blocks.append(last)
            at_zero.add(last)
        if r * l < n:
            continue
        # necessary (and cheap): full column rank at δ = 0
        if at_zero.rank < n:
            continue
        O = PolyMatrix.vstack(*blocks)
        # Ō is left unimodular iff X·Ō = I has a polynomial solution (the definition): the
        # reduced solution the design needs anyway is the test (one elimination, not two);
        # C̄ Ā^l, the right side of (16), is solved for in the same pass
        nxt = last @ A_bar
        if O.rows == n and det_not_constant_mod_p(O._r, n):
            continue  # a square Ō whose det has positive degree (mod p): no inverse, no solve
        if not solve:
            with _progress.step(f"Zheng et al. (2015) step 3, l = {l}: proving Ō left unimodular by "
                                f"its maximal minors, Ō {_progress.size_text(O)}"):
                proved = left_unimodular_proved(O._r, *O.shape, cheap_only=True)
            if proved:
                return _ObservabilityIndex(l, O)  # proved without the solve, which may be large
        try:
            with _progress.step(f"Zheng et al. (2015) step 3, l = {l}: solving X·Ō = [I; C̄Ā^l], "
                                f"Ō {_progress.size_text(O)}"):
                solved = solve_left(O, PolyMatrix.vstack(_I(n), nxt))
        except NoPolynomialSolutionError:
            continue
        return _ObservabilityIndex(l, O, solved, nxt)
    return None


def _normal_form_T(A_bar: PolyMatrix, C_bar: PolyMatrix, F: PolyMatrix, l: int) -> PolyMatrix:
    """``T = [T_1; …; T_l]`` of (15): ``T_1 = C̄``, ``T_{i+1} = T_i Ā − F_i C̄``."""
    r = C_bar.rows
    Ts = [C_bar]
    for i in range(l - 1):
        F_i = F[i * r : (i + 1) * r, 0:r]
        Ts.append(Ts[-1] @ A_bar - F_i @ C_bar)
    return PolyMatrix.vstack(*Ts)


def _reduced_left_inverse(T: PolyMatrix) -> PolyMatrix:
    """The left inverse of ``T`` reduced modulo the Popov basis of its left kernel: unique
    (Popov division leaves one remainder), so :func:`~uio_ring.ring.solve.solve_left` of
    ``X·T = I`` and :func:`~uio_ring.ring.inverse.left_inverse` return the same matrix.
    For a tall T the solve goes straight to the square block-Toeplitz system of the
    reduced solution (checked exactly), where ``left_inverse`` first tries an elimination
    capped by coefficient growth (on T of a 32-state system: it fails, 0.4 s lost);
    ``left_inverse`` answers when the solve does not (and names why T has no inverse).

    >>> T = PolyMatrix("[[1, d], [0, 1], [d, 0]]")
    >>> _reduced_left_inverse(T) == left_inverse(T)
    True
    """
    if T.rows > T.cols > 0:
        try:
            return solve_left(T, _I(T.cols))
        except NoPolynomialSolutionError:
            pass
    return left_inverse(T)


def _F_from_row(X: PolyMatrix, r: int, l: int) -> PolyMatrix:
    """``[F_l, …, F_1]`` (r × r l) to ``F = [F_1; …; F_l]`` (r l × r)."""
    blocks = [X[0:r, (l - 1 - i) * r : (l - i) * r] for i in range(l)]
    return PolyMatrix.vstack(*blocks)


@dataclass(frozen=True)
class _Step12:
    """Steps 1–2 for one choice of U. Precondition: ``U M = [V; 0]`` (checked by caller)."""

    U: PolyMatrix
    V: PolyMatrix
    Vbar: PolyMatrix
    W: PolyMatrix
    A_bar: PolyMatrix
    C_tilde: PolyMatrix


def _steps_1_2(sys: DelaySystem, U: PolyMatrix, rho: int) -> _Step12:
    n, p, m = sys.n_x, sys.n_y, sys.n_w
    M = matching_matrix(sys)
    UM = U @ M
    V = UM[0:rho, 0 : 2 * m]
    if not UM[rho : 2 * p, 0 : 2 * m].is_zero():
        raise DimensionError(
            f"U M must be [V; 0] with V of {rho} rows (rank of M); rows {rho}… of U M are not zero"
        )
    target = PolyMatrix.vstack(
        PolyMatrix.hstack(sys.B, _Z(n, m)), PolyMatrix.hstack(sys.D, _Z(p, m))
    )
    Vbar = solve_left(V, target) if rho else _Z(n + p, 0)
    W = PolyMatrix.hstack(Vbar, _Z(n + p, 2 * p - rho)) @ U
    CA_C = PolyMatrix.vstack(sys.C @ sys.A, sys.C)
    A_bar = sys.A - W[0:n, 0 : 2 * p] @ CA_C
    C_tilde = sys.C - W[n : n + p, 0 : 2 * p] @ CA_C
    return _Step12(U=U, V=V, Vbar=Vbar, W=W, A_bar=A_bar, C_tilde=C_tilde)


def _assemble(
    sys: DelaySystem,
    s12: _Step12,
    Lam: PolyMatrix,
    *,
    index: _ObservabilityIndex | None = None,
    F_stack: PolyMatrix | None = None,
    O_left_inverse: PolyMatrix | None = None,
    T_left_inverse: PolyMatrix | None = None,
    poles: Sequence[Any] | None = None,
    G0_extra: PolyMatrix | None = None,
    choice: str = "",
    assumptions: AssumptionsReport | None = None,
    T: PolyMatrix | None = None,
) -> DelayUIODesign:
    """Steps 2 (end) to 5 for given choices; the remaining choices take the ring's
    reduced defaults.  ``T`` is (15) for the given ``F_stack`` when the caller has it
    (the search does), else computed.  ``G0_extra`` is added to the ``G0`` of the poles (a strictly
    block-triangular coupling, :func:`~uio_ring.design.noise.couple`: same spectrum).
    Precondition: ``Lam`` is unimodular with ``Lam C̃ = [C̄; 0]``."""
    n, p = sys.n_x, sys.n_y
    W = s12.W
    K, Gamma = W[0:n, 0 : 2 * p], W[n : n + p, 0 : 2 * p]
    K1, K2 = K[0:n, 0:p], K[0:n, p : 2 * p]
    G1, G2 = Gamma[0:p, 0:p], Gamma[0:p, p : 2 * p]
    A_bar, C_tilde = s12.A_bar, s12.C_tilde
    LC = Lam @ C_tilde
    r = C_tilde.rank()
    C_bar = LC[0:r, 0:n]
    if not LC[r:p, 0:n].is_zero():
        raise DimensionError(f"Λ C̃ must be [C̄; 0] with C̄ of {r} rows (= rank C̃); its last rows are not zero")
    if index is None:
        index = _observability_index(A_bar, C_bar, n)
        if index is None:  # pragma: no cover - excluded by Theorem 3 under Assumptions 1, 2
            raise UioRingError(
                "no l* with Ō_l left unimodular although Assumptions 1 and 2 hold "
                "(contradicts Theorem 3 of Zheng et al. (2015)); please report this system"
            )
    l_star, O = index.l_star, index.O
    if O_left_inverse is None:
        O_left_inverse = left_inverse(O)
    F = F_stack
    if F is None:
        F = _F_from_row(C_bar @ (A_bar**l_star) @ O_left_inverse, r, l_star)
    if T is None or F_stack is None:
        T = _normal_form_T(A_bar, C_bar, F, l_star)
    if T_left_inverse is None:
        T_left_inverse = left_inverse(T)
    vals = _default_poles(sys, l_star) if poles is None else _read_poles(poles, l_star)
    A0, C0 = _shift_matrices(r, l_star)
    G0 = _gain_from_poles(vals, r)
    if G0_extra is not None:
        G0 = G0 + G0_extra
    L0 = A0 - G0 @ C0
    Lam_inv = left_inverse(Lam)
    G1b, G2b = Lam @ G1 @ Lam_inv, Lam @ G2 @ Lam_inv
    K1b, K2b = T @ K1 @ Lam_inv, T @ K2 @ Lam_inv
    nz = T.rows
    FG0 = PolyMatrix.hstack(F + G0, _Z(nz, p - r))
    H = K1b - FG0 @ G1b
    J = FG0 @ (_I(p) - G2b) + K2b + L0 @ H
    H_u = -(H @ Lam @ sys.F)
    J_u = T @ sys.E - J @ Lam @ sys.F - H @ Lam @ sys.C @ sys.E
    return DelayUIODesign(
        system=sys, U=s12.U, V=s12.V, Vbar=s12.Vbar, W=W, K=K, Gamma=Gamma, K1=K1, K2=K2,
        Gamma1=G1, Gamma2=G2, A_bar=A_bar, C_tilde=C_tilde, Lam=Lam, Lam_inverse=Lam_inv,
        C_bar=C_bar, r=r, l_star=l_star, O=O, O_left_inverse=O_left_inverse, F_stack=F, T=T,
        T_left_inverse=T_left_inverse, A0=A0, C0=C0, K1_bar=K1b, K2_bar=K2b, Gamma1_bar=G1b,
        Gamma2_bar=G2b, poles=vals, G0=G0, L0=L0, H=H, J=J, H_u=H_u, J_u=J_u, choice=choice,
        assumptions=assumptions,
    )


def zheng_bejarano_from_choices(
    sys: DelaySystem,
    *,
    U: Any,
    Lam: Any,
    O_left_inverse: Any = None,
    T_left_inverse: Any = None,
    poles: Sequence[Any] | None = None,
) -> DelayUIODesign:
    """Steps 1–5 of Zheng et al. (2015) with the choices made by the caller (no search, no
    assumption check).

    Useful to reproduce a published design: pass the paper's ``U`` and ``Λ``
    (and optionally its left inverses); ``F`` then follows (16) with the given
    ``O_left_inverse``.  The result's :meth:`~DelayUIODesign.certificate` tells
    whether the choices were valid.

    Parameters
    ----------
    sys
        The delay system.
    U
        Unimodular ``2 n_y × 2 n_y`` with ``U M = [V; 0]``, ``M = [[CB, D], [D, 0]]``.
    Lam
        Unimodular ``n_y × n_y`` with ``Λ C̃ = [C̄; 0]``.
    O_left_inverse, T_left_inverse
        Left inverses of ``Ō_{l*}`` and ``T`` (default: the ring's reduced ones).
    poles
        ``l*`` rationals, the spectrum of ``A0 − G0 C0`` per channel (default ``−1, …, −l*``).

    Returns
    -------
    DelayUIODesign

    Raises
    ------
    DimensionError
        ``U M`` or ``Λ C̃`` without the required zero rows, or ``poles`` of the wrong length.
    NoPolynomialSolutionError
        ``Vbar V = [[B, 0], [D, 0]]`` has no polynomial solution (Assumption 2 fails).

    Examples
    --------
    Re-building a design from its own choices gives the same observer:

    >>> from uio_ring import DelaySystem
    >>> sys = DelaySystem("[[0, 1], [d, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)
    >>> des = design_zheng_bejarano(sys)
    >>> again = zheng_bejarano_from_choices(sys, U=des.U, Lam=des.Lam)
    >>> again.certificate().ok, again.n_z == des.n_z
    (True, True)
    """
    U_ = U if isinstance(U, PolyMatrix) else PolyMatrix(U)
    Lam_ = Lam if isinstance(Lam, PolyMatrix) else PolyMatrix(Lam)
    M = matching_matrix(sys)
    if U_.shape != (M.rows, M.rows):
        raise DimensionError(f"U is {U_.rows}×{U_.cols}; expected {M.rows}×{M.rows} (= rows of M)")
    if Lam_.shape != (sys.n_y, sys.n_y):
        raise DimensionError(f"Lam is {Lam_.rows}×{Lam_.cols}; expected {sys.n_y}×{sys.n_y}")
    s12 = _steps_1_2(sys, U_, M.rank())
    OL = None if O_left_inverse is None else PolyMatrix(O_left_inverse)
    TL = None if T_left_inverse is None else PolyMatrix(T_left_inverse)
    return _assemble(
        sys, s12, Lam_, O_left_inverse=OL, T_left_inverse=TL, poles=poles, choice="given by the caller"
    )


# ----------------------------------------------------------------------------------------
# the search over choices
# ----------------------------------------------------------------------------------------
def _candidate_Us(sys: DelaySystem) -> tuple[int, list[tuple[str, PolyMatrix]]]:
    """The Step-1 transforms tried: the ring's Hermite transform ``U0`` and its one-step
    neighbours ``U0 + [±e_i c_j; 0]`` (see :func:`design_zheng_bejarano`)."""
    n, p = sys.n_x, sys.n_y
    M = matching_matrix(sys)
    with _progress.step(f"Zheng et al. (2015) step 1: the Hermite form of M, {_progress.size_text(M)}"):
        herm = hermite(M)
    rho = herm.rank
    U0 = herm.U
    out = [("U = Hermite transform of M", U0)]
    s = 2 * p - rho
    if rho == 0 or s == 0:
        return rho, out
    U_top, U_bot = U0[0:rho, 0 : 2 * p], U0[rho : 2 * p, 0 : 2 * p]
    V = herm.H[0:rho, 0 : M.cols]
    target = PolyMatrix.vstack(
        PolyMatrix.hstack(sys.B, _Z(n, sys.n_w)), PolyMatrix.hstack(sys.D, _Z(p, sys.n_w))
    )
    Vbar = solve_left(V, target)
    # moves through a column of Vbar with a nonzero Γ-part change C̃ (and so r); moves
    # through the K-part only change Ā and are tried for small systems only
    moves_C = [i for i in range(rho) if not Vbar[n : n + p, i : i + 1].is_zero()]
    moves_A = [i for i in range(rho) if i not in moves_C and not Vbar[0:n, i : i + 1].is_zero()]
    useful = moves_C + (moves_A if sys.n_x * max(1, sys.max_delay_degree) <= 12 else [])
    if not useful:  # no move to make: the rows g_j below are not needed (their U can be large:
        return rho, out  # 12×8 of degree 64 with 3.6-kbit rows for an 8-state system, 47 s)
    N_tilde = U_bot @ PolyMatrix.vstack(sys.C @ sys.A, sys.C)
    with _progress.step("Zheng et al. (2015) step 1: the Hermite form of the w-free rows of U0 "
                        f"times [CA; C], {_progress.size_text(N_tilde)}"):
        hN = hermite(N_tilde)
    for j in range(hN.rank):
        c_j = hN.U[j : j + 1, 0:s] @ U_bot  # a row of the left kernel of M
        for i in useful:
            for sign in (1, -1):
                E = PolyMatrix([[1 if a == i else 0] for a in range(rho)], shape=(rho, 1))
                U = PolyMatrix.vstack(U_top + sign * (E @ c_j), U_bot)
                out.append((f"U = U0 {'+' if sign > 0 else '−'} e_{i + 1}·g_{j + 1} (Hermite transform moved by a w-free row)", U))
    return rho, out


def _lambda_choices(C_tilde: PolyMatrix) -> Iterator[tuple[str, PolyMatrix]]:
    """Output compressions ``Λ C̃ = [C̄; 0]``: the Hermite one, then row selections
    ``Λ = [rows S of I; left kernel of C̃]`` when unimodular (C̄ = rows S of C̃)."""
    herm = hermite(C_tilde)
    yield "Λ = Hermite transform of C̃", herm.U
    p, r = C_tilde.rows, herm.rank
    if r == 0:
        return
    Kc = herm.U[r:p, 0:p]
    from itertools import combinations

    for count, S in enumerate(combinations(range(p), r)):
        if count >= 24:
            break
        sel = PolyMatrix([[1 if j == i else 0 for j in range(p)] for i in S], shape=(r, p))
        Lam = PolyMatrix.vstack(sel, Kc)
        if is_unimodular(Lam):
            yield f"Λ = [rows {[i + 1 for i in S]} of I; left kernel of C̃]", Lam


def design_zheng_bejarano(
    sys: DelaySystem, poles: Sequence[Any] | str | None = None, *, rate: Any = None, criterion: str | None = None,
    search: bool = True, report: AssumptionsReport | None = None,
) -> DelayUIODesign:
    """Design the delay unknown-input observer of Zheng et al. (2015) (Steps 1–5, with (19′)/(22′)).

    Parameters
    ----------
    sys
        ``x' = A x + B w + E u``, ``y = C x + D w + F u`` over Q[δ].
    poles
        ``l*`` exact rationals (int, Fraction, decimal text), repeated values
        allowed: the spectrum of ``A0 − G0 C0`` on each of the ``r`` output
        channels.  ``G0`` is read off ``Π (s − p_i)`` (no pole placement
        routine).  Their number also selects ``l*`` when observers of the same
        smallest order ``n_z`` exist with different ``l*`` (e.g. ``(r, l*) = (2, 3)``
        and ``(3, 2)``).  Default: ``l*`` poles at ``−α`` with α = ``rate``, or
        ``⌈‖A(1)‖∞⌉`` (:func:`~uio_ring.design.noise.default_rate`: not slower than
        the plant; repeated poles amplify noise less than spread ones).
        ``"min-noise"``: the poles — and the design choices below, and a coupling of
        the channels in ``G0`` that keeps the poles — of least noise gain with every
        pole at least as fast as ``−rate`` (:func:`~uio_ring.design.noise.least_noise`:
        pole patterns ``−α(1, q, q², …)`` on the first assemblies of each ``l*``, then a
        Nelder–Mead search of the coupling from zero; needs the system's ``h``).
    rate
        The slowest decay rate α for the default poles and for ``"min-noise"``.
    criterion
        With ``"min-noise"``: ``"peak"`` (default) minimises the peak-to-peak gain of the
        worst state, ``"h2"`` its H2 gain (refused with the reason when the H2 gain is
        infinite for every candidate: a read-out ``H Λ(δ) y`` that feeds ``y`` through).
    search
        Try the variants of the choices below and keep the best (default); with
        ``False`` take the ring's Hermite transforms and reduced inverses only.
    report
        The :func:`~uio_ring.analysis.check_assumptions` report of ``sys`` when it was
        computed already (``design_auto`` analyses once); default: computed here.

    Returns
    -------
    DelayUIODesign
        All matrices of Steps 1–5; ``.certificate()`` checks them exactly.

    Raises
    ------
    NotObservableError
        Assumption 1 or 2 fails; ``.report`` is the
        :class:`~uio_ring.analysis.AssumptionsReport` and the message names the
        failed assumption(s).
    DimensionError
        ``poles`` has a length other than ``l*`` (the message gives ``l*``).
    DomainError
        A pole that is not an exact rational.

    Algorithm
    ---------
    Zheng, Bejarano, Perruquetti & Richard (2015), Steps 1–5 of §4.4, with
    (19′)/(22′) of docs/errata.md (Z1).  The choices (U, Λ, the left inverses)
    do not change the observer's error dynamics but do change its order
    ``n_z = r·l*`` and the lag ``deg T_L⁻¹``.  They are made as follows, to
    minimise ``n_z`` first and then the lag:

    1. *U (Step 1).*  Every valid ``W`` is ``Vbar (U_top + X U_bot)``, where
       ``U0 = [U_top; U_bot]`` is the ring's Hermite transform of ``M`` and
       ``U_bot`` spans the left kernel of ``M``; ``X`` changes ``Ā`` and ``C̃``
       only through ``X Ñ``, ``Ñ = U_bot [CA; C]`` (the w-free combinations of
       ``y`` and ``y'``).  We try ``X = 0`` and the one-step moves ``X Ñ = ±e_i g_j``
       for each Hermite generator ``g_j`` of ``Ñ`` and each column ``i`` of
       ``Vbar`` with a nonzero ``Γ``-part — the moves that switch an output row
       on or off in ``C̃`` (this is how ``r`` changes between 2 and 3 in the
       paper's example); columns with only a ``K``-part (they change ``Ā``
       alone) are tried when ``n_x·max(1, deg) ≤ 12``.
    2. *r and l*.*  For each ``U``, ``r = rank C̃`` and ``l*`` is the least
       ``l`` with ``Ō_l`` left unimodular (only ``l ≥ n_x / r`` are tested;
       candidates whose bound ``r·⌈n_x/r⌉`` cannot beat the best are skipped).
       The smallest ``n_z = r·l*`` wins.
    3. *Λ, F and T_L⁻¹.*  Among the ``U`` with the smallest ``n_z`` we try
       ``Λ`` from the Hermite form of ``C̃`` and the row-selection ``Λ``
       (``C̄`` = rows of ``C̃``, as in the paper), and ``F`` from (16) with the
       reduced left inverse of ``Ō_{l*}`` and from the reduced solution of
       ``[F_{l*}, …, F_1] Ō_{l*} = C̄ Ā^{l*}``; ``T_L⁻¹`` is the ring's reduced
       left inverse (reduced modulo the left kernel of ``T``).  The smallest
       lag wins, then the smallest degrees of ``T`` and ``F``; ties keep the
       first tried.  Finalists are tried in order of ``deg Ā + deg C̃``, and
       the number of (U, Λ, F) combinations is capped by a budget that depends
       on ``n_x·max(1, deg)`` only (48 up to 8, 8 up to 12, else 2), so the
       result depends on the system alone, never on timing.

    On the paper's example this gives ``(r, l*, n_z) = (3, 2, 6)`` with lag 1
    (the paper: ``(2, 3, 6)``, lag 4); with three poles it keeps ``l* = 3``
    and reaches lag 3.  An offline search over two moves, also with ``±δ``
    multiples, found no ``n_z = 6`` design with lag 0 (lag 0 needs
    ``n_z = 9``).  When ``D = 0``, ``Γ = 0`` and ``C̃ = C``: then ``r = n_y``
    whatever the choice, and only ``l*`` and the lag can vary.

    Examples
    --------
    A delay-free chain of three integrators driven by the unknown input,
    observed at both ends (``C B ≠ 0``, so the input is seen by ``y'``):

    >>> from uio_ring import DelaySystem
    >>> sys = DelaySystem("[[0, 1, 0], [0, 0, 1], [0, 0, 0]]", "[[0], [0], [1]]",
    ...                   "[[1, 0, 0], [0, 0, 1]]", None)
    >>> des = design_zheng_bejarano(sys, poles=["-1/2", "-1/2"])
    >>> des.r, des.l_star, des.n_z, des.lag, des.certificate().ok
    (2, 2, 4, 0, True)
    >>> design_zheng_bejarano(sys, poles=[-1])
    Traceback (most recent call last):
    ...
    uio_ring.ring.errors.DimensionError: poles has 1 value(s); expected l* = 2 (the spectrum of A0 − G0 C0 on each output channel; the smallest observer, n_z = 4, has l* = 2)
    """
    if not isinstance(sys, DelaySystem):
        raise DomainError(f"design_zheng_bejarano needs a DelaySystem, not {type(sys).__name__}")
    if report is None:
        report = check_assumptions(sys)
    if not report.holds:
        raise NotObservableError(
            "the Zheng–Bejarano observer does not exist for this system: " + report.reason,
            report=report,
        )
    from uio_ring.design.noise import check_criterion

    check_criterion(criterion, poles)
    rho, Us = _candidate_Us(sys)
    if not search:
        Us = Us[:1]
    candidates = _smallest_observers(sys, Us, rho)
    finalists = _with_requested_poles(candidates, poles)
    ranked = _ranked_assemblies(sys, finalists, _assembly_budget(sys) if search else 1)
    if isinstance(poles, str):
        from uio_ring.design.noise import least_noise

        return least_noise(sys, ranked, poles, rate=rate, criterion=criterion, assemble=_assemble, report=report)
    best = ranked[0]
    return _assemble(
        sys, best.steps12, best.Lam, index=best.index, F_stack=best.F_stack, O_left_inverse=best.O_left_inverse,
        T_left_inverse=best.T_left_inverse, poles=_default_poles(sys, best.index.l_star, rate) if poles is None
        else poles, choice=best.choice, assumptions=report, T=best.T,
    )


def smallest_observer_orders(sys: DelaySystem) -> tuple[int, tuple[int, ...]]:
    """``(n_z, l* options)``: the smallest observer order the design search finds and the
    numbers of poles (``l*``) that reach it — what ``poles`` must have.  Precondition:
    Assumptions 1 and 2 hold (not checked).

    >>> from uio_ring import DelaySystem
    >>> smallest_observer_orders(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None))
    (2, (1,))
    """
    rho, Us = _candidate_Us(sys)
    cands = _smallest_observers(sys, Us, rho, solve=False)
    return cands[0].n_z, tuple(sorted({c.index.l_star for c in cands}))


@dataclass(frozen=True)
class _Candidate:
    """Stage 1 of the search: one Step-1 transform U and the observer order it gives."""

    n_z: int
    order: int  # position of U in the list tried (ties are broken by it)
    label: str
    steps12: _Step12
    index: _ObservabilityIndex


@dataclass(frozen=True)
class _Assembly:
    """Stage 2 of the search: one (U, Λ, F) combination with its T_L⁻¹ and its lag."""

    key: tuple[int, int, int]  # (lag = deg T_L⁻¹, deg T, deg F): smaller is better
    steps12: _Step12
    Lam: PolyMatrix
    index: _ObservabilityIndex
    F_stack: PolyMatrix
    O_left_inverse: PolyMatrix
    T_left_inverse: PolyMatrix
    choice: str
    T: PolyMatrix  # (15) for F_stack


def _smallest_observers(
    sys: DelaySystem, Us: list[tuple[str, PolyMatrix]], rho: int, solve: bool = True
) -> list[_Candidate]:
    """Stage 1: Steps 1–3 for each U (pruning orders above the best so far); the
    candidates of the smallest ``n_z = r·l*``.  ``solve=False``: the orders only (see
    :func:`_observability_index`)."""
    n = sys.n_x
    best_nz: int | None = None
    scored: list[_Candidate] = []
    seen: list[tuple[PolyMatrix, PolyMatrix]] = []
    for idx, (label, U) in enumerate(Us):
        s12 = _steps_1_2(sys, U, rho)
        if any(s12.A_bar == a and s12.C_tilde == c for a, c in seen):
            continue
        seen.append((s12.A_bar, s12.C_tilde))
        r = s12.C_tilde.rank()
        if r == 0:
            continue
        if best_nz is not None and r * (-(-n // r)) > best_nz:
            continue  # even the least l* cannot beat the best order
        C_bar = hermite(s12.C_tilde).H[0:r, 0:n]
        index = _observability_index(s12.A_bar, C_bar, n, solve=solve)
        if index is None:  # pragma: no cover - Theorem 3
            continue
        nz = r * index.l_star
        best_nz = nz if best_nz is None else min(best_nz, nz)
        scored.append(_Candidate(nz, idx, label, s12, index))
    if best_nz is None:  # pragma: no cover - Theorem 3
        raise UioRingError(
            "no choice of U gave a left-unimodular Ō_l although Assumptions 1 and 2 hold "
            "(contradicts Theorem 3 of Zheng et al. (2015)); please report this system"
        )
    return [c for c in scored if c.n_z == best_nz]


def _with_requested_poles(candidates: list[_Candidate], poles: Sequence[Any] | str | None) -> list[_Candidate]:
    """The candidates whose ``l*`` equals the number of requested poles (all when none are given)."""
    if poles is None or isinstance(poles, str):
        return candidates
    count = len(_read_poles(poles, len(poles) if isinstance(poles, Sequence) or hasattr(poles, "ndim") else 0))
    matching = [c for c in candidates if c.index.l_star == count]
    if not matching:
        options = " or ".join(str(o) for o in sorted({c.index.l_star for c in candidates}))
        raise DimensionError(
            f"poles has {count} value(s); expected l* = {options} (the spectrum of A0 − G0 C0 on each "
            f"output channel; the smallest observer, n_z = {candidates[0].n_z}, has l* = {options})"
        )
    return matching


def _ranked_assemblies(sys: DelaySystem, finalists: list[_Candidate], budget: int) -> list[_Assembly]:
    """Stage 2: for the finalists, each output compression Λ and each way to read F off (16),
    T and its reduced left inverse; every combination evaluated (within ``budget``), least
    lag first (ties: lower degrees of T and F, then the order tried)."""
    n = sys.n_x
    finalists = sorted(finalists, key=lambda c: (c.steps12.A_bar.degree() + c.steps12.C_tilde.degree(), c.order))
    out: list[_Assembly] = []
    for cand in finalists:
        s12, l_star = cand.steps12, cand.index.l_star
        r = s12.C_tilde.rank()
        for lam_label, Lam in _lambda_choices(s12.C_tilde):
            if len(out) >= budget:
                break
            C_bar = (Lam @ s12.C_tilde)[0:r, 0:n]
            # one solve for both: X·Ō = [I; C̄ Ā^{l*}], each row reduced modulo the Popov basis
            # of Ō's left kernel (unique), so the first n rows are the reduced left inverse
            if C_bar == cand.index.O[0:r, 0:n] and cand.index.solved is not None and cand.index.next_block is not None:
                # Ō_{l*} of stage 1 (the Hermite Λ) and its solve: reused
                O, both, CAl = cand.index.O, cand.index.solved, cand.index.next_block
            else:
                rows = [C_bar]
                for _k in range(l_star):
                    rows.append(rows[-1] @ s12.A_bar)
                O, CAl = PolyMatrix.vstack(*rows[:l_star]), rows[l_star]
                with _progress.step(f"Zheng et al. (2015) step 3: solving X·Ō = [I; C̄Ā^l*], "
                                    f"Ō {_progress.size_text(O)}"):
                    both = solve_left(O, PolyMatrix.vstack(_I(n), CAl))
            OL, F_reduced = both[0:n, 0 : O.rows], both[n : n + r, 0 : O.rows]
            done: list[tuple[PolyMatrix, PolyMatrix, PolyMatrix]] = []  # (F, T, T_L⁻¹) for this Λ
            for f_label in ("F reduced modulo the left kernel of Ō", "F by (16) with the reduced left inverse of Ō"):
                if len(out) >= budget:
                    break
                X = F_reduced if f_label.startswith("F reduced") else CAl @ OL
                F = _F_from_row(X, r, l_star)
                # the two ways often give the same F (then the same T and T_L⁻¹: not recomputed)
                same = next((t for t in done if t[0] == F), None)
                if same is None:
                    T = _normal_form_T(s12.A_bar, C_bar, F, l_star)
                    with _progress.step(f"Zheng et al. (2015): the left inverse of T of (15), "
                                        f"{_progress.size_text(T)}"):
                        same = (F, T, _reduced_left_inverse(T))
                    done.append(same)
                _, T, TL = same
                key = (max(0, TL.degree()), T.degree(), F.degree())
                choice = f"{cand.label}; {lam_label}; {f_label}; T_L⁻¹ reduced modulo the left kernel of T"
                out.append(_Assembly(key, s12, Lam, _ObservabilityIndex(l_star, O), F, OL, TL, choice, T))
        if len(out) >= budget:
            break
    if not out:  # pragma: no cover - finalists is not empty and budget ≥ 1
        raise UioRingError("the design search evaluated no combination (budget 0?)")
    return sorted(out, key=lambda a: a.key)  # stable: the order tried breaks ties


def _assembly_budget(sys: DelaySystem) -> int:
    """How many (U, Λ, F) combinations stage 2 of the search evaluates.

    Each costs a left inverse of ``T`` (``r·l* × n_x``, degrees growing like
    ``l*·deg Ā``), the dominant cost of the design; the budget depends on the
    size only, so the result depends only on the system (never on timing).
    Measured with ``benchmarks/bench_design.py``.
    """
    size = sys.n_x * max(1, sys.max_delay_degree)
    if size <= 8:
        return 48
    if size <= 12:
        return 8
    return 2
