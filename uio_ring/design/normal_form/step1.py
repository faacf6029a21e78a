"""Step 1 of Niederwieser et al. (2022) (Section 4.1, (28)–(45)): the output transformation Γ, the output
injection Ξ and the chain lengths.

For the model ``x' = A x + B w``, ``y = C x`` (``B`` the unknown input; the
paper's D), find ``Γ`` (p×p) and ``Ξ`` (n×p) such that ``Ǎ = A + Ξ C`` and
``Č = Γ C = [č_1; …; č_p]`` give (26) an invertible
``O_R = [č_1; č_1 Ǎ; …; č_1 Ǎ^{μ_1−1}; …; č_p Ǎ^{μ_p−1}]`` and (27)
``č_j Ǎ^i B = 0`` for ``i ≤ μ_j − 2``.

The loop grows one row chain ``Z_j = [z_{j,1}; …; z_{j,ν_j}]`` per output
(starting from ``c_j``) and its output combination ``Ψ_j``, visiting the active
chains round robin:

* **Case 1** (31): the last row reaches a new direction of the unknown input
  (``rank [W; z B] > rank W``): the chain stops, ``w_j = z B``;
* **Case 2** (32)–(35): otherwise subtract ``ζ`` times the other chains
  (bottom-aligned) so that ``z B = 0`` (``ζ`` the minimum-norm solution of
  ``z B = ζ W``), then stop (Sub-case 2.1, (36)) if ``z A`` is in the row space of
  ``Z``, else append ``z A`` (Sub-case 2.2, (37)–(40)).

Then the stable sort (41) gives ``μ`` and the order ``j_1, …, j_p``, the first
rows of the ``Ψ``'s give ``Γ`` (44), and ``Ξ = Z⁻¹ R`` (45).

>>> from uio_ring.ring import QMatrix
>>> ch = output_chains(QMatrix([[0, 1], [0, 0]]), QMatrix([[0], [1]]), QMatrix([[1, 0]]))
>>> ch.nu, ch.mu, ch.Gamma, ch.Xi, [t.case for t in ch.trace]
((2,), (2,), QMatrix([[1]]), QMatrix([[0], [0]]), ['2/2.2', '1'])
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

from uio_ring.errors import NotObservableError, UioRingError
from uio_ring.ring.qmatrix import QMatrix

__all__ = ["Step1Trace", "OutputChains", "output_chains"]


@dataclass(frozen=True)
class Step1Trace:
    """One visit of chain ``j`` (1-based, original order) in Step 1: ``case`` is
    ``"1"``, ``"2/2.1"`` or ``"2/2.2"``; ``zeta`` the minimum-norm solution of (33)."""

    j: int
    case: str
    zeta: tuple[Fraction, ...] = ()


@dataclass(frozen=True)
class OutputChains:
    """The result of Step 1.

    Attributes
    ----------
    Z
        ``[Z_1; …; Z_p]`` (n×n, nonsingular), chains in the original output order.
    Psi
        ``Ψ_j`` (ν_j×p) per chain, original order: ``z_{j,1} = ψ_{j,1} C``.
    nu, mu
        Chain lengths in the original order (``ν``) and sorted (``μ``, (12)).
    order
        ``j_1, …, j_p`` (0-based): the original chain behind each sorted chain (41).
    Gamma, Xi
        (44), (45).
    A_check, C_check
        ``Ǎ = A + Ξ C`` (22), ``Č = Γ C`` (24), sorted order.
    trace
        The cases, visit by visit.
    """

    Z: QMatrix
    Psi: tuple[QMatrix, ...]
    nu: tuple[int, ...]
    mu: tuple[int, ...]
    order: tuple[int, ...]
    Gamma: QMatrix
    Xi: QMatrix
    A_check: QMatrix
    C_check: QMatrix
    trace: tuple[Step1Trace, ...]


def output_chains(A: QMatrix, B: QMatrix, C: QMatrix) -> OutputChains:
    """Step 1 of Niederwieser et al. (2022) for ``x' = A x + B w``, ``y = C x`` (``B``: the unknown input).

    Raises
    ------
    NotObservableError
        The loop stops with ``rank Z < n`` (the system is not strongly observable;
        excluded when the applicability check passed).
    """
    n, p = A.rows, C.rows
    Z, Psi, nu, trace = _chain_loop(A, B, C)
    Z_all = QMatrix.vstack(*[r for rows in Z for r in rows], cols=n)
    if sum(nu) != n or Z_all.rank() != n:  # pragma: no cover - excluded by the applicability test
        raise NotObservableError(f"Step 1 stopped with rank Z = {Z_all.rank()} < n = {n}")
    order = tuple(sorted(range(p), key=lambda j: -nu[j]))  # stable sort (41)
    Gamma = QMatrix.vstack(*[Psi[j][0] for j in order], cols=p)
    # R (45): chain j contributes ψ_{j,2}, …, ψ_{j,ν_j} and a zero row, original order
    R = QMatrix.vstack(*[r for j in range(p) for r in (*Psi[j][1:], QMatrix.zeros(1, p))], cols=p)
    Xi = Z_all.solve(R, name="Z")
    return OutputChains(
        Z=Z_all,
        Psi=tuple(QMatrix.vstack(*rows) for rows in Psi),
        nu=tuple(nu),
        mu=tuple(nu[j] for j in order),
        order=order,
        Gamma=Gamma,
        Xi=Xi,
        A_check=A + Xi @ C,
        C_check=Gamma @ C,
        trace=tuple(trace),
    )


def _chain_loop(
    A: QMatrix, B: QMatrix, C: QMatrix
) -> tuple[list[list[QMatrix]], list[list[QMatrix]], list[int], list[Step1Trace]]:
    """The loop (28)–(40), round robin over active chains (rows as 1×n matrices).

    Precondition: shapes agree (not checked).
    """
    n, p, m = A.rows, C.rows, B.cols
    Z = [[C.row(j)] for j in range(p)]
    Psi = [[QMatrix.unit(p, j).T] for j in range(p)]
    W = [QMatrix.zeros(1, m) for _ in range(p)]  # row j belongs to chain j (set in Case 1)
    rank_W = 0
    nu = [1] * p
    active = [True] * p
    trace: list[Step1Trace] = []
    rank_Z = C.rank()
    Z_all = C
    while any(active):
        for j in range(p):
            if not active[j]:
                continue
            # invariant: z_{j,i} B = 0 for i < ν_j; rows of finished chains never change;
            # rank_Z = rank Z_all, rank_W = rank [w_1; …; w_p]
            zB = Z[j][-1] @ B
            W_all = QMatrix.vstack(*W, cols=m)
            if m and QMatrix.vstack(W_all, zB).rank() > rank_W:  # Case 1 (31)
                W[j] = zB
                rank_W += 1
                active[j] = False
                trace.append(Step1Trace(j + 1, "1"))
                continue
            zeta = _zeta(W_all, zB, p)  # Case 2 (32)–(33)
            if any(zeta):
                Z[j], Psi[j] = _eliminate(j, zeta, Z, nu), _eliminate(j, zeta, Psi, nu)
                Z_all = QMatrix.vstack(*[r for rows in Z for r in rows], cols=n)
            new = Z[j][-1] @ A
            if QMatrix.vstack(Z_all, new).rank() == rank_Z:  # Sub-case 2.1 (36)
                active[j] = False
                trace.append(Step1Trace(j + 1, "2/2.1", zeta))
            else:  # Sub-case 2.2 (37)–(40)
                Z[j].append(new)
                Psi[j].append(QMatrix.zeros(1, p))
                nu[j] += 1
                rank_Z += 1
                Z_all = QMatrix.vstack(Z_all, new)
                trace.append(Step1Trace(j + 1, "2/2.2", zeta))
    return Z, Psi, nu, trace


def _zeta(W: QMatrix, zB: QMatrix, p: int) -> tuple[Fraction, ...]:
    """The minimum-norm ``ζ`` with ``z B = ζ W`` (33), as Fractions (zeros when ``z B = 0``)."""
    if W.cols == 0 or zB.is_zero():
        return (Fraction(0),) * p
    zeta = W.min_norm_left_solve(zB)
    if zeta is None:  # pragma: no cover - excluded by the rank test (31)
        raise UioRingError("Step 1: z B is in the row space of W but (33) has no solution")
    return tuple(zeta.tolist()[0])


def _eliminate(j: int, zeta: tuple[Fraction, ...], rows: list[list[QMatrix]], nu: list[int]) -> list[QMatrix]:
    """(34)/(35): ``x_{j,i} − Σ_k ζ_k x_{k, ν_k − ν_j + i}``, bottom-aligned (rows absent above
    the top count as zero), for the rows of chain j of ``rows`` (``Z`` or ``Ψ``).

    Precondition: ``len(rows[k]) = nu[k]`` and ``ζ_j = 0`` (not checked).
    """
    nj = nu[j]
    out = []
    for i in range(1, nj + 1):
        r = rows[j][i - 1]
        for k, z in enumerate(zeta):
            l = nu[k] - nj + i
            if z and l >= 1:
                r = r - z * rows[k][l - 1]
        out.append(r)
    return out
