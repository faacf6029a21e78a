"""Molinari's sequence ``M_k`` (Bejarano, Fridman & Poznyak 2007, Algorithm 1), exactly over Q.

For a delay-free system ``x' = A x + D w``, ``y = C x + F w`` in the papers' letters
(here: ``B`` is the unknown-input matrix and ``D`` the feed-through, as everywhere in the
package), the sequence

    M_1 = F^⊥ C,        M_{k+1} = T_{k,b} [M_k A; C],        T_{k,b} = [M_k B; D]^⊥

(``X^⊥``: a basis of the left kernel of ``X``) has non-decreasing rank; its kernel
tends to the weakly unobservable subspace ``V*`` (``V* = ker M_n``).  The system is
strongly observable exactly when some ``M_l`` has rank ``n`` (then ``l ≤ n``): that
``l`` is the number of levels of the hierarchical super-twisting observer.  Each
``T_{k,b}`` annihilates the unknown input, so ``d/dt`` of ``T_{k,b}[M_k x; ∫y]`` is
``M_{k+1} x`` whatever ``w`` is: the identity each level of the observer relies on.

The annihilators are the ring's left-kernel bases (Popov form: rational, minimal),
not orthonormal SVD bases: the row spaces of the ``M_k`` are the paper's, their
entries are another (equivalent) choice.

>>> from uio_ring import DelaySystem
>>> seq = molinari_sequence(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None))
>>> seq.ranks, seq.l, seq.holds
((1, 2), 2, True)
"""

from __future__ import annotations

from dataclasses import dataclass

from uio_ring.analysis.report import Report
from uio_ring.errors import DomainError
from uio_ring.ring.kernel import left_kernel
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["MolinariSequence", "molinari_sequence"]


@dataclass(frozen=True)
class MolinariSequence(Report):
    """The sequence and its verdict (a :class:`~uio_ring.analysis.report.Report`).

    Attributes
    ----------
    M : tuple of PolyMatrix
        ``M_1, M_2, …`` (constant), up to ``M_l`` (or until the rank stalls).
    T_b : tuple of PolyMatrix
        ``T_{0,b} = D^⊥, T_{1,b}, …``: ``M_{k+1} = T_{k,b} [M_k A; C]`` (``M_1 = T_{0,b} C``).
    ranks : tuple of int
        ``rank M_k``.
    l : int or None
        The least ``k`` with ``rank M_k = n`` (None when the sequence stalls below n).
    holds : bool
        Strongly observable (``l`` exists).
    reason : str
        Why not, when it does not hold (the dimension of ``V* = ker M`` left).
    """

    M: tuple[PolyMatrix, ...]
    T_b: tuple[PolyMatrix, ...]
    ranks: tuple[int, ...]
    l: int | None
    holds: bool
    reason: str = ""

    @property
    def n(self) -> int:
        return self.M[0].cols if self.M else 0

    @property
    def name(self) -> str:
        return "strongly observable (Molinari sequence; Bejarano, Fridman & Poznyak 2007, Algorithm 1)"

    def _detail_lines(self) -> list[str]:
        return [f"ranks {list(self.ranks)}" + (f", l = {self.l}" if self.holds else "")]


def _annihilator(X: PolyMatrix) -> PolyMatrix:
    """A basis of the left kernel of a constant matrix (rows ``N`` with ``N X = 0``); the
    identity when ``X`` has no columns."""
    if X.cols == 0:
        return PolyMatrix.identity(X.rows)
    return left_kernel(X)


def molinari_sequence(sys: DelaySystem) -> MolinariSequence:
    """The sequence ``M_k`` of a delay-free system, up to the first of full column rank.

    Raises ``DomainError`` for a system with delays (the algorithm is stated over R).
    """
    if not sys.is_delay_free:
        raise DomainError("molinari_sequence needs a delay-free system (δ-degree 0)")
    A, B, C, D = sys.A, sys.B, sys.C, sys.D
    n = sys.n_x
    T0 = _annihilator(D)  # F^⊥ in the paper's letters
    M = [T0 @ C]
    T_b = [T0]
    ranks = [M[0].rank()]
    for _ in range(n):
        if ranks[-1] == n:
            return MolinariSequence(tuple(M), tuple(T_b), tuple(ranks), len(M), True)
        Mk = M[-1]
        T = _annihilator(PolyMatrix.vstack(Mk @ B, D))
        nxt = T @ PolyMatrix.vstack(Mk @ A, C)
        T_b.append(T)
        M.append(nxt)
        ranks.append(nxt.rank())
        if ranks[-1] == ranks[-2] and ranks[-1] < n:
            break  # stalled: the kernel is V* ≠ 0
    if ranks[-1] == n:
        return MolinariSequence(tuple(M), tuple(T_b), tuple(ranks), len(M), True)
    return MolinariSequence(
        tuple(M), tuple(T_b), tuple(ranks), None, False,
        reason=f"the rank stalls at {ranks[-1]} < n = {n}: V* = ker M has dimension {n - ranks[-1]} "
        "(the system has invariant zeros; not strongly observable)",
    )
