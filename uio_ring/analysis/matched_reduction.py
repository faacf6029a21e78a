"""The reduction of a matched system to its unknown-input-free part (Bejarano, Fridman &
Poznyak 2007, Section 3), exactly over Q.

For a delay-free system ``x' = A x + B w + E u``, ``y = C x + F u`` (no feed-through of
``w``) under the matching condition ``rank C B = rank B = q < p`` (the paper's A3–A4;
its letters ``D, B`` are ``B, E`` here), the change of coordinates

    r = P x,   P = [B^⊥; (C B)^+ C],   P⁻¹ = [(I − B (C B)^+ C) B^{⊥+},  B]        (31)

splits the state into ``r_1 = B^⊥ x`` (``n − q``), which ``w`` does not reach, and
``r_2 = (C B)^+ C x`` (``q``), which is measured:

    r_1' = A11 r_1 + A12 r_2 + B1 u,         ȳ_1 = (C B)^⊥ (y − F u) = C̄ r_1          (34)
    r_2' = A21 r_1 + A22 r_2 + B2 u + w,     r_2 = (C B)^+ (y − F u)

with ``P A P⁻¹ = [A11 A12; A21 A22]``, ``P E = [B1; B2]``, ``P B = [0; I]`` and
``C̄ = (C B)^⊥ C B^{⊥+}``.  The system is strongly observable exactly when
``(A11, C̄)`` is observable (the paper's Lemma 2); ``M_k = [C̄; C̄ A11; …; C̄ A11^{k−1}]``
and ``l`` is the least ``k`` with ``rank M_k = n − q``.

``X^⊥`` is the ring's rational left-kernel basis and ``X^+`` the exact left or right
inverse ``(XᵀX)⁻¹Xᵀ`` / ``Xᵀ(XXᵀ)⁻¹`` — the paper's orthonormal (irrational) choices
differ by invertible factors: ``A11`` is then similar to the paper's and ``C̄`` differs by
a left and a right factor; spectra, ranks and ``l`` are the same.

>>> from uio_ring import DelaySystem
>>> r = matched_reduction(DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None))
>>> r.holds, r.l, r.A11.tolist()
(True, 1, [[0]])
"""

from __future__ import annotations

from dataclasses import dataclass

from uio_ring.analysis.report import Report
from uio_ring.errors import DomainError
from uio_ring.ring.inverse import left_inverse
from uio_ring.ring.kernel import left_kernel
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["MatchedReduction", "matched_reduction", "left_pinv", "right_pinv"]


def left_pinv(X: PolyMatrix) -> PolyMatrix:
    """``(XᵀX)⁻¹Xᵀ`` of a constant matrix of full column rank (``X^+ X = I``)."""
    return left_inverse(X.T @ X) @ X.T


def right_pinv(X: PolyMatrix) -> PolyMatrix:
    """``Xᵀ(XXᵀ)⁻¹`` of a constant matrix of full row rank (``X X^+ = I``)."""
    return X.T @ left_inverse(X @ X.T)


@dataclass(frozen=True)
class MatchedReduction(Report):
    """The reduced system and its verdict (a :class:`~uio_ring.analysis.report.Report`).

    Attributes
    ----------
    holds, reason
        The matching condition holds (``D = 0``, ``rank B = rank C B = q``, ``q < p``) and
        ``(A11, C̄)`` is observable; why not otherwise.
    B_perp, CB_pinv, CB_perp
        ``B^⊥`` ((n − q) × n), ``(C B)^+`` (q × p), ``(C B)^⊥`` ((p − q) × p).
    P, P_inv
        The transformation (31) and its inverse (by the formula, not by inversion).
    A11, A12, A21, A22, B1, B2, C_bar
        The blocks of (32)–(34).
    M
        ``M_1 … M_l`` (the observability sequence of ``(A11, C̄)``), when the matching holds.
    l
        The least ``k`` with ``rank M_k = n − q`` (None when it does not exist).
    """

    holds: bool
    reason: str = ""
    B_perp: PolyMatrix | None = None
    CB_pinv: PolyMatrix | None = None
    CB_perp: PolyMatrix | None = None
    P: PolyMatrix | None = None
    P_inv: PolyMatrix | None = None
    A11: PolyMatrix | None = None
    A12: PolyMatrix | None = None
    A21: PolyMatrix | None = None
    A22: PolyMatrix | None = None
    B1: PolyMatrix | None = None
    B2: PolyMatrix | None = None
    C_bar: PolyMatrix | None = None
    M: tuple[PolyMatrix, ...] = ()
    l: int | None = None

    @property
    def name(self) -> str:
        return ("matching condition and observable w-free part (A11, C̄) "
                "(Bejarano, Fridman & Poznyak 2007, Section 3)")

    def _detail_lines(self) -> list[str]:
        if self.A11 is None:
            return []
        return [f"n − q = {self.A11.rows}, p − q = {self.C_bar.rows if self.C_bar is not None else 0}, "
                f"ranks of M_k {[M.rank() for M in self.M]}" + (f", l = {self.l}" if self.l else "")]


def _refuse(reason: str) -> MatchedReduction:
    return MatchedReduction(False, reason)


def matched_reduction(sys: DelaySystem) -> MatchedReduction:
    """The transformation (31), the blocks (32)–(34) and the sequence ``M_k`` of ``(A11, C̄)``.

    Raises ``DomainError`` for a system with delays; a failed condition is a report with
    ``holds = False`` and the reason.
    """
    if not sys.is_delay_free:
        raise DomainError("matched_reduction needs a delay-free system (δ-degree 0)")
    A, B, C, D, E = sys.A, sys.B, sys.C, sys.D, sys.E
    n, p, q = sys.n_x, sys.n_y, sys.n_w
    if q == 0:
        return _refuse("the system has no unknown input (B has no columns)")
    if not D.is_zero():
        return _refuse("the unknown input reaches the output (D ≠ 0); Section 3 needs D = 0")
    if B.rank() != q:
        return _refuse(f"rank B = {B.rank()} < q = {q}: B needs full column rank")
    CB = C @ B
    if CB.rank() != q:
        return _refuse(f"rank C B = {CB.rank()} ≠ rank B = {q}: the matching condition fails")
    if q >= p:
        return _refuse(f"q = {q} unknown inputs need at least q + 1 = {q + 1} outputs (p = {p})")
    B_perp = left_kernel(B)
    CB_pinv = left_pinv(CB)
    CB_perp = left_kernel(CB)
    B_perp_pinv = right_pinv(B_perp)
    P = PolyMatrix.vstack(B_perp, CB_pinv @ C)
    P_inv = PolyMatrix.hstack((PolyMatrix.identity(n) - B @ CB_pinv @ C) @ B_perp_pinv, B)
    m = n - q
    PAPi = P @ A @ P_inv
    PE = P @ E
    A11, A12, A21, A22 = PAPi[0:m, 0:m], PAPi[0:m, m:n], PAPi[m:n, 0:m], PAPi[m:n, m:n]
    B1, B2 = PE[0:m, :], PE[m:n, :]
    C_bar = CB_perp @ C @ B_perp_pinv
    M = [C_bar]
    while M[-1].rank() < m and len(M) < m:
        M.append(PolyMatrix.vstack(M[-1], C_bar @ _power(A11, len(M))))
    blocks = dict(B_perp=B_perp, CB_pinv=CB_pinv, CB_perp=CB_perp, P=P, P_inv=P_inv, A11=A11, A12=A12,
                  A21=A21, A22=A22, B1=B1, B2=B2, C_bar=C_bar, M=tuple(M))
    if M[-1].rank() < m:
        return MatchedReduction(False, f"(A11, C̄) is not observable (rank {M[-1].rank()} < n − q = {m}): "
                                "the system has invariant zeros (not strongly observable)", **blocks)
    return MatchedReduction(True, "", l=len(M), **blocks)


def _power(A: PolyMatrix, k: int) -> PolyMatrix:
    out = PolyMatrix.identity(A.rows)
    for _ in range(k):
        out = out @ A
    return out
