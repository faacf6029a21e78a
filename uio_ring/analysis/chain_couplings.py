"""Step 3 of Niederwieser et al. (2022) (Section 4.1, (48)–(53)): the coupling coefficients β.

For each chain ``j`` with later, shorter chains ``r`` (``μ_r < μ_j``) the unknowns
``β_{j,r,l}``, ``l = μ_r … μ_j − 1`` (ascending ``l``), solve ``H^{(j)} β^{(j)} = w^{(j)}`` with
(the element-wise form of (49)–(50), docs/errata.md, N2; ``a = 1 … μ_j − μ_r``,
``b = 1 … μ_j − μ_s``)::

    H^{(j)}_{r,s}(a, b) = č_r Ǎ^{μ_s + b − a − 1} t_{e_s}   (0 when the power is negative)
    w^{(j)}_r(a)       = č_r Ǎ^{μ_j − a} t_{e_j}

``det H^{(j)} = 1`` (Lemma 4.1(c)), so β is unique; the other couplings vanish (53).
``H^{(j)}`` is triangular up to row and column permutations, so it is solved by
substitution (:meth:`~uio_ring.ring.QMatrix.solve_by_peeling`), with elimination as
a fallback.

>>> from uio_ring.ring import QMatrix
>>> from uio_ring.analysis.chain_basis import chain_basis
>>> b = chain_basis(QMatrix([[0, 1, 0], [0, 0, 1], [1, 2, 3]]), QMatrix([[1, 0, 0], [0, 0, 1]]), (2, 1))
>>> c = coupling_coefficients(b)
>>> c.beta, [s.H.det() for s in c.systems]
({(1, 2, 1): Fraction(2, 1)}, [Fraction(1, 1)])
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from uio_ring.analysis.chain_basis import ChainBasis
from uio_ring.ring.qmatrix import QMatrix

__all__ = ["CouplingSystem", "Couplings", "coupling_coefficients"]


@dataclass(frozen=True)
class CouplingSystem:
    """``H^{(j)} β^{(j)} = w^{(j)}`` for chain ``j`` (1-based) and the later chains ``r`` (1-based)."""

    j: int
    later: tuple[int, ...]
    H: QMatrix
    w: QMatrix
    beta: QMatrix


@dataclass(frozen=True)
class Couplings:
    """The result of Step 3: ``beta[(j, r, l)] = β_{j,r,l}`` (1-based, sorted chains; only
    ``l ≥ μ_r``, the others vanish by (53)) and the systems that gave them."""

    beta: dict[tuple[int, int, int], Fraction]
    systems: tuple[CouplingSystem, ...]


def coupling_coefficients(basis: ChainBasis) -> Couplings:
    """Step 3: every ``β_{j,r,l}`` from the ``H^{(j)}`` systems (48)–(51)."""
    mu = basis.mu
    beta: dict[tuple[int, int, int], Fraction] = {}
    systems = []
    for j in range(len(mu) - 1):
        later = [r for r in range(j + 1, len(mu)) if mu[r] < mu[j]]
        if not later:
            continue
        H, w = _system(basis, j, later)
        sol = H.solve_by_peeling(w)  # det H^(j) = 1 and triangular up to permutations
        if sol is None:  # pragma: no cover - general elimination as a fallback
            sol = H.solve(w, name=f"H^({j + 1})")
        values = iter(sol.T.tolist()[0] if sol.rows else [])
        for r in later:
            for l in range(mu[r], mu[j]):  # ascending l (52)
                beta[(j + 1, r + 1, l)] = next(values)
        systems.append(CouplingSystem(j + 1, tuple(r + 1 for r in later), H, w, sol))
    return Couplings(beta, tuple(systems))


def _system(basis: ChainBasis, j: int, later: list[int]) -> tuple[QMatrix, QMatrix]:
    """``H^{(j)}`` and ``w^{(j)}`` (0-based j, later chains), cut from the rows ``b_r`` of the
    powers of Step 2 by slicing (no entry goes through a Fraction).  Precondition: ``later`` nonempty.

    Row ``a`` of block ``(r, s)`` holds ``č_r Ǎ^k t_{e_s}`` for ``k = μ_s − a … μ_j − a − 1``
    (zeros for ``k < 0``); ``w^{(j)}_r`` holds ``k = μ_j − 1`` down to ``μ_r``.
    """
    mu, P, starts = basis.mu, basis.powers, basis.starts
    H_rows, w_blocks = [], []
    for r in later:
        for a in range(1, mu[j] - mu[r] + 1):
            H_rows.append(
                QMatrix.hstack(
                    *[
                        QMatrix.hstack(
                            QMatrix.zeros(1, max(0, a - mu[s])), P[s][starts[r] : starts[r] + 1, max(0, mu[s] - a) : mu[j] - a]
                        )
                        for s in later
                    ]
                )
            )
        w_blocks.append(P[j][starts[r] : starts[r] + 1, :].take_cols(range(mu[j] - 1, mu[r] - 1, -1)))
    return QMatrix.vstack(*H_rows), QMatrix.hstack(*w_blocks).T


def chain_transformation(basis: ChainBasis, couplings: Couplings) -> QMatrix:
    """``T`` of (54): block ``j``, ``i = 0 … μ_j − 1``::

        t_{e_j − i} = Ǎ^i t_{e_j} − Σ_{r>j} Σ_{q=1}^{i} β_{j,r,μ_j−q} Ǎ^{i−q} t_{e_r}

    i.e. per block one matrix product ``X_j = P_j − Σ_r P_r Β_{j,r}`` with the powers
    ``P_s = [t_{e_s}, Ǎ t_{e_s}, …]`` of Step 2 and the upper triangular Toeplitz
    matrices ``Β_{j,r}[i−q, i] = β_{j,r,μ_j−q}``; column ``i`` of ``X_j`` is ``t_{e_j − i}``.
    Returned in the original coordinates (``T = O_R⁻¹ T̃``).

    >>> from uio_ring.analysis.chain_basis import chain_basis
    >>> b = chain_basis(QMatrix([[0, 1, 0], [0, 0, 1], [1, 2, 3]]), QMatrix([[1, 0, 0], [0, 0, 1]]), (2, 1))
    >>> chain_transformation(b, coupling_coefficients(b))
    QMatrix([[1, 0, 0], [0, 1, 0], [0, 0, 1]])
    """
    mu, P = basis.mu, basis.powers
    blocks = []
    for j in range(len(mu)):
        X = P[j][:, : mu[j]]
        later = [r for r in range(j + 1, len(mu)) if any(couplings.beta.get((j + 1, r + 1, l)) for l in range(mu[j]))]
        if later:
            X = X - QMatrix.hstack(*[P[r][:, : mu[j]] for r in later]) @ QMatrix.vstack(
                *[_toeplitz(couplings.beta, j, r, mu[j]) for r in later]
            )
        blocks.append(X.take_cols(range(mu[j] - 1, -1, -1)))  # column e_j − i holds t_{e_j − i}
    return basis.O_R.solve(QMatrix.hstack(*blocks, rows=basis.O_R.rows), name="O_R")  # back from z = O_R x


def _toeplitz(beta: dict[tuple[int, int, int], Fraction], j: int, r: int, size: int) -> QMatrix:
    """``Β_{j,r}[i − q, i] = β_{j,r,μ_j−q}`` for ``1 ≤ q ≤ i < μ_j`` (0-based j, r; ``size = μ_j``)."""
    zero = Fraction(0)
    return QMatrix(
        [[beta.get((j + 1, r + 1, size - (i - k)), zero) if i > k else zero for i in range(size)] for k in range(size)]
    )
