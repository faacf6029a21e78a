"""Integer invariants of a delay-free system: relative degrees, observability indices,
infinite-zero orders and the normal-form chain lengths (exact, over Q).

For ``x' = A x + B w``, ``y = C x + D w`` (δ-degree 0, ``w`` unknown):

* the **relative degree** of ``y_j`` w.r.t. ``w`` is 0 if row j of D is nonzero,
  else the least ``k ≥ 1`` with ``c_jᵀ A^{k−1} B ≠ 0`` (``None``: w never reaches y_j);
* the **observability indices** of ``(A, C)`` come from the Luenberger row search
  ``c_1, …, c_p, c_1A, …, c_pA, …`` (keep a row iff it is independent of the rows kept);
* the **infinite-zero orders** come from the ranks of the block-Toeplitz matrices
  of Markov parameters ``T_k = [[D], [CB, D], …, [CA^{k−2}B, …, CB, D]]``:
  with ``ρ_k = rank T_k − rank T_{k−1}`` (nondecreasing), ``ρ_{i+1} − ρ_i`` orders
  equal ``i`` (order 0 is direct feed-through);
* the **chain lengths** ``μ`` of the observer normal form of Niederwieser et al. (2022): with
  ``d_k = rank [O_k, H_k] − rank H_k`` (``O_k = [C; …; CA^{k−1}]``, ``H_k`` the
  Toeplitz matrix of ``CA^iB`` without ``D``), ``d_k = Σ_j min(μ_j, k)``, so ``μ`` is
  the conjugate partition of the increments (an observation, checked on
  random systems in the test suite, not a statement of the paper).

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0, 1, 0], [0, 0, 1], [0, 0, 0]]", "[[0], [0], [1]]", "[[1, 0, 0]]", None)
>>> relative_degrees(sys).degrees, observability_indices(sys).indices, infinite_zero_structure(sys).orders
((3,), (3,), (3,))
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from uio_ring.analysis.report import Report
from uio_ring.analysis.strong_observability import constant_matrices
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = [
    "RelativeDegrees",
    "relative_degrees",
    "ObservabilityIndices",
    "observability_indices",
    "InfiniteZeroStructure",
    "infinite_zero_structure",
    "normal_form_chain_lengths",
]


@dataclass(frozen=True)
class RelativeDegrees(Report):
    """Relative degree of each output w.r.t. the unknown input (``None``: infinite).

    ``holds``: every output is reached by the unknown input; ``reason`` names the others.
    """

    degrees: tuple[int | None, ...]
    output_names: tuple[str, ...]
    reason: str = ""

    @property
    def holds(self) -> bool:
        """Every output is reached by the unknown input."""
        return all(d is not None for d in self.degrees)

    @property
    def name(self) -> str:
        return "every output reached by the unknown input (relative degrees w.r.t. w)"

    def _detail_lines(self) -> list[str]:
        return [", ".join(f"{n}: {'∞' if d is None else d}" for n, d in zip(self.output_names, self.degrees, strict=True))]

    def to_dict(self) -> dict[str, Any]:
        return {"degrees": list(self.degrees), "outputs": list(self.output_names), "reason": self.reason}


def relative_degrees(sys: DelaySystem) -> RelativeDegrees:
    """Relative degree of each output with respect to the unknown input ``w``.

    Examples
    --------
    >>> from uio_ring import DelaySystem
    >>> relative_degrees(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 0]]", "[[0], [1]]")).degrees
    (2, 0)
    """
    M = constant_matrices(sys)
    A, B, C, D = M["A"], M["B"], M["C"], M["D"]
    n = sys.n_x
    out: list[int | None] = []
    for j in range(sys.n_y):
        if sys.n_w and not D.row(j).is_zero():
            out.append(0)
            continue
        row = C.row(j)
        deg = None
        for k in range(1, n + 1):
            # invariant: row = c_jᵀ A^{k−1} and c_jᵀ A^i B = 0 for i < k − 1
            if sys.n_w and not (row @ B).is_zero():
                deg = k
                break
            row = row @ A
        out.append(deg)
    missing = [sys.output_names[j] for j, d in enumerate(out) if d is None]
    reason = f"the unknown input never reaches {', '.join(missing)}" if missing else ""
    return RelativeDegrees(tuple(out), sys.output_names, reason)


@dataclass(frozen=True)
class ObservabilityIndices(Report):
    """Luenberger observability indices of ``(A, C)`` (one per output).

    ``holds``: ``(A, C)`` is observable (the indices sum to ``n_x``).
    """

    indices: tuple[int, ...]
    n_x: int

    @property
    def holds(self) -> bool:
        """``(A, C)`` observable: the indices sum to ``n_x``."""
        return sum(self.indices) == self.n_x

    @property
    def reason(self) -> str:
        if self.holds:
            return ""
        return f"(A, C) is not observable: the observability indices sum to {sum(self.indices)} < n_x = {self.n_x}"

    @property
    def name(self) -> str:
        return "(A, C) observable (observability indices)"

    def _detail_lines(self) -> list[str]:
        return [f"observability indices {self.indices} (sum {sum(self.indices)}, n_x = {self.n_x})"]

    def to_dict(self) -> dict[str, Any]:
        return {"indices": list(self.indices), "n_x": self.n_x, "holds": self.holds}


def observability_indices(sys: DelaySystem) -> ObservabilityIndices:
    """Observability indices by the row search ``c_1, …, c_p, c_1 A, …`` (exact).

    Examples
    --------
    >>> from uio_ring import DelaySystem
    >>> observability_indices(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[0, 1]]", None))
    ObservabilityIndices(indices=(1,), n_x=2)
    """
    M = constant_matrices(sys)
    A, C = M["A"], M["C"]
    n, p = sys.n_x, sys.n_y
    basis = QMatrix.zeros(0, n)  # kept rows
    idx = [0] * p
    active = list(range(p))
    rows = [C.row(j) for j in range(p)]
    while active and basis.rows < n:
        still = []
        # invariant: basis has full row rank; rows[j] = c_jᵀ A^{idx[j]}
        for j in active:
            cand = QMatrix.vstack(basis, rows[j])
            if cand.rank() > basis.rows:
                basis = cand
                idx[j] += 1
                rows[j] = rows[j] @ A
                still.append(j)
        active = still
    return ObservabilityIndices(tuple(idx), n)


def _markov(M: dict[str, QMatrix], K: int) -> list[QMatrix]:
    """``[D, CB, CAB, …]`` (K terms)."""
    out = [M["D"]]
    X = M["B"]
    for _ in range(K - 1):
        out.append(M["C"] @ X)
        X = M["A"] @ X
    return out


def _toeplitz(blocks: list[QMatrix], k: int, p: int, m: int) -> QMatrix:
    """Lower block-Toeplitz ``[[G0], [G1, G0], …]`` with k block rows."""
    zero = QMatrix.zeros(p, m)
    return QMatrix.vstack(
        *[QMatrix.hstack(*[blocks[r - c] if c <= r else zero for c in range(k)], rows=p) for r in range(k)], cols=k * m
    )


@dataclass(frozen=True)
class InfiniteZeroStructure:
    """Orders of the infinite zeros (0 = direct feed-through), from Toeplitz ranks."""

    orders: tuple[int, ...]
    toeplitz_ranks: tuple[int, ...]
    normal_rank: int

    def __str__(self) -> str:
        return f"infinite-zero orders {self.orders} (normrank of the transfer matrix {self.normal_rank})"

    def to_dict(self) -> dict[str, Any]:
        return {"orders": list(self.orders), "toeplitz_ranks": list(self.toeplitz_ranks), "normal_rank": self.normal_rank}


def infinite_zero_structure(sys: DelaySystem) -> InfiniteZeroStructure:
    """Orders of the infinite zeros of ``G(s) = C (sI − A)⁻¹ B + D``.

    ``rank T_k`` for ``k = 1 … n_x + 1``; ``ρ_k = rank T_k − rank T_{k−1}``
    counts the columns of ``G`` (after unimodular column operations) whose
    order at infinity is below ``k``.

    Examples
    --------
    >>> from uio_ring import DelaySystem
    >>> sys = DelaySystem("[[0, 1, 0], [0, 0, 0], [0, 0, 0]]", "[[0, 0], [1, 0], [0, 1]]",
    ...                   "[[1, 0, 0], [0, 0, 1]]", None)
    >>> infinite_zero_structure(sys).orders
    (1, 2)
    """
    M = constant_matrices(sys)
    n, p, m = sys.n_x, sys.n_y, sys.n_w
    K = n + 1
    blocks = _markov(M, K)
    ranks = [0]
    for k in range(1, K + 1):
        ranks.append(_toeplitz(blocks, k, p, m).rank())
    rho = [0] + [ranks[k] - ranks[k - 1] for k in range(1, K + 1)]
    orders: list[int] = []
    for i in range(K):
        orders += [i] * (rho[i + 1] - rho[i])
    return InfiniteZeroStructure(tuple(orders), tuple(ranks[1:]), rho[K])


def normal_form_chain_lengths(sys: DelaySystem) -> tuple[int, ...]:
    """The block sizes ``μ`` of Niederwieser et al.'s observer normal form, as a system invariant.

    ``d_k = rank [O_k, H_k] − rank H_k`` (``H_k`` without feed-through) satisfies
    ``d_k = Σ_j min(μ_j, k)``; ``μ`` is the conjugate of the increments
    (checked on random systems in the test suite).  For a strongly observable system ``Σ μ = n_x``.
    Assumes ``D = 0`` (apply the feed-through reduction first).

    >>> from uio_ring import DelaySystem
    >>> normal_form_chain_lengths(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None))
    (2,)
    """
    M = constant_matrices(sys)
    n, p, m = sys.n_x, sys.n_y, sys.n_w
    A, C = M["A"], M["C"]
    blocks = [QMatrix.zeros(p, m)] + _markov(M, n + 1)[1:]
    d = [0]
    O_rows: list[QMatrix] = []
    X = C
    for k in range(1, n + 1):
        O_rows.append(X)
        X = X @ A
        H = _toeplitz(blocks, k, p, m)
        O = QMatrix.vstack(*O_rows, cols=n)
        d.append(QMatrix.hstack(O, H).rank() - H.rank())
        if k > 1 and d[-1] == d[-2]:
            break
    inc = [d[k] - d[k - 1] for k in range(1, len(d))]
    # μ_j = #{k : inc_k ≥ j}
    return tuple(sum(1 for x in inc if x >= j) for j in range(1, (max(inc) if inc else 0) + 1))
