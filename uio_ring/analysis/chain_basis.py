"""Step 2 of Niederwieser et al. (2022) (Section 4.1, (25), (46)–(47)): ``O_R`` and the last column of each
block of ``T``.

``O_R = [č_1; č_1 Ǎ; …; č_1 Ǎ^{μ_1−1}; …; č_p; …; č_p Ǎ^{μ_p−1}]`` (n×n, nonsingular by
Step 1) and ``t_{e_j} = O_R⁻¹ e_{e_j}`` (47), ``e_j = μ_1 + … + μ_j``.

Steps 2–4 run in the coordinates ``z = O_R x``.  There ``Ǎ`` is the block
companion matrix ``Ã = O_R Ǎ O_R⁻¹`` (row (k, i) of ``O_R`` times ``Ǎ`` is row
(k, i + 1); only the last row of each chain, ``č_k Ǎ^{μ_k} O_R⁻¹``, is dense),
``t_{e_k}`` is the unit vector ``e_{e_k}`` and ``č_r`` the row ``e_{b_r+1}ᵀ``.  The numbers
stay small; ``T = O_R⁻¹ T̃`` is formed once at the end (Step 4).

>>> from uio_ring.ring import QMatrix
>>> b = chain_basis(QMatrix([[-3, 1], [-2, 0]]), QMatrix([[1, 0]]), (2,))
>>> b.O_R, b.A_z, b.coupling(0, 1, 0)
(QMatrix([[1, 0], [-3, 1]]), QMatrix([[0, 1], [-2, -3]]), Fraction(1, 1))
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from uio_ring.ring.qmatrix import QMatrix

__all__ = ["ChainBasis", "chain_basis"]


@dataclass(frozen=True)
class ChainBasis:
    """The result of Step 2.

    Attributes
    ----------
    O_R
        (25), sorted chain order.
    mu
        The chain lengths ``μ`` (sorted).
    A_z
        ``Ã = O_R Ǎ O_R⁻¹`` (block companion form).
    powers
        ``powers[s]`` = ``[e_{e_s}, Ã e_{e_s}, …, Ã^{μ_1−1} e_{e_s}]`` (n×μ_1): the
        z-coordinates of ``Ǎ^i t_{e_s}``.
        Row ``b_r`` of ``powers[s]`` holds ``č_r Ǎ^k t_{e_s}``, the entries of ``H^{(j)}``
        and ``w^{(j)}`` (Step 3).
    """

    O_R: QMatrix
    mu: tuple[int, ...]
    A_z: QMatrix
    powers: tuple[QMatrix, ...]

    @property
    def starts(self) -> tuple[int, ...]:
        """``b_j`` (0-based index of the first state of chain j)."""
        return tuple(sum(self.mu[:j]) for j in range(len(self.mu)))

    @property
    def ends(self) -> tuple[int, ...]:
        """``e_j − 1`` (0-based index of the last state of chain j)."""
        return tuple(sum(self.mu[: j + 1]) - 1 for j in range(len(self.mu)))

    def coupling(self, r: int, k: int, s: int) -> Fraction:
        """``č_r Ǎ^k t_{e_s}`` (0-based chains, ``0 ≤ k < μ_1``)."""
        return self.powers[s][self.starts[r], k]


def chain_basis(A_check: QMatrix, C_check: QMatrix, mu: tuple[int, ...]) -> ChainBasis:
    """Step 2 for ``Ǎ``, ``Č`` (sorted order) and the chain lengths ``μ``.

    Precondition: ``O_R`` is nonsingular (Step 1 guarantees it; ``DimensionError`` otherwise).
    """
    n, p = A_check.rows, len(mu)
    O_rows: list[QMatrix] = []
    last_rows: list[QMatrix] = []
    for k in range(p):
        row = C_check.row(k)
        for _ in range(mu[k]):  # invariant: row = č_k Ǎ^i
            O_rows.append(row)
            row = row @ A_check
        last_rows.append(row)  # č_k Ǎ^{μ_k}
    O_R = QMatrix.vstack(*O_rows, cols=n)
    L = O_R.T.solve(QMatrix.vstack(*last_rows, cols=n).T, name="O_R").T  # (č_k Ǎ^{μ_k}) O_R⁻¹
    ends = [sum(mu[: k + 1]) - 1 for k in range(p)]
    chain_of_end = {e: k for k, e in enumerate(ends)}
    I = QMatrix.identity(n)
    A_z = QMatrix.vstack(*[L.row(chain_of_end[i]) if i in chain_of_end else I.row(i + 1) for i in range(n)], cols=n)
    powers = []
    for k in range(p):
        v = QMatrix.unit(n, ends[k])
        cols = [v]
        for _ in range(max(mu) - 1):  # invariant: v = Ã^i e_{e_k}
            v = A_z @ v
            cols.append(v)
        powers.append(QMatrix.hstack(*cols))
    return ChainBasis(O_R=O_R, mu=tuple(mu), A_z=A_z, powers=tuple(powers))
