"""The high-gain canonical form of (A, C, W_1, …, W_v) (Grip & Saberi 2010, §3–4).

With ``x = Γ_x x̄`` and ``y = Γ_y ȳ``::

    Ā = Γ_x⁻¹ A Γ_x = blkdiag(A_{q_1}, …, A_{q_p}) + L C̄       (8)
    C̄ = Γ_y⁻¹ C Γ_x = blkdiag(C_{q_1}, …, C_{q_p})              (9)
    W̄_k = Γ_x⁻¹ W_k Γ_x

where ``A_q`` is the q×q shift (ones above the diagonal), ``C_q = [1, 0, …, 0]``
and ``q_1 ≥ … ≥ q_p`` are the observability indices of (A, C).  The set is in
canonical form when every block ``W̄_k[i, j]`` (q_i × q_j) is lower-triangular in
the generalised sense: entry (r, c) is zero whenever c > r (eq. (11)).  By the
paper's Theorem 2 this happens, for *any* Γ_x, Γ_y giving (8)–(9), exactly when
the set is admissible; :meth:`CanonicalForm.certificate` checks that equivalence
against :func:`~uio_ring.analysis.admissibility.admissibility`.

>>> cf = canonical_form([[0, 0], [1, 0]], [[0, 1]], [[[0, 1], [0, 0]]])
>>> cf.q, cf.lower_triangular, cf.certificate().ok
((2,), True, True)
>>> cf.C_bar, cf.A_bar
(PolyMatrix([[1, 0]]), PolyMatrix([[0, 1], [0, 0]]))
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from uio_ring.analysis import _subspaces as sp
from uio_ring.analysis.admissibility import admissibility
from uio_ring.errors import NotObservableError
from uio_ring.ring import constant as qc
from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.matrix import PolyMatrix

__all__ = ["CanonicalForm", "canonical_form", "observability_indices_of", "chain_blocks", "shift_blocks",
           "block_violations"]


def observability_indices_of(A: Any, C: Any) -> tuple[int, ...]:
    """Observability indices of a constant pair (A, C), largest first.

    The number of indices ≥ k is ``rank O_k − rank O_{k−1}``; the sum is the
    rank of the observability matrix (n exactly when observable).

    >>> observability_indices_of([[0,1,0],[0,0,0],[0,0,0]], [[1,0,0],[0,0,1]])
    (2, 1)
    """
    Aq = sp.square_matrix(A, "A")
    Cq = qc.qmat(C, "C")
    n = Aq.nrows()
    counts: list[int] = []
    prev = 0
    for k in range(1, n + 1):
        r = qc.qrank(sp.observability_stack(Aq, Cq, k))
        if r == prev:
            break
        counts.append(r - prev)
        prev = r
    # counts[k-1] = number of indices >= k
    p = counts[0] if counts else 0
    return tuple(sum(1 for c in counts if c > i) for i in range(p))


def chain_blocks(q: Sequence[int]) -> tuple[tuple[int, int], ...]:
    """``(start, length)`` of each chain in the stacked state, e.g. ``(3, 2) → ((0, 3), (3, 2))``."""
    out, s = [], 0
    for qi in q:
        out.append((s, qi))
        s += qi
    return tuple(out)


@dataclass(frozen=True)
class CanonicalForm:
    """Result of :func:`canonical_form`; matrices are constant ``PolyMatrix``.

    Attributes
    ----------
    Gamma_x, Gamma_y
        Nonsingular, with ``x = Γ_x x̄`` and ``y = Γ_y ȳ``.
    q
        Observability indices, largest first; chain i has length ``q[i]`` and output ``ȳ_i``.
    L
        n×p with ``Ā = blkdiag(A_{q_i}) + L C̄``.
    A_bar, C_bar, W_bar
        ``Γ_x⁻¹ A Γ_x``, ``Γ_y⁻¹ C Γ_x`` and the ``Γ_x⁻¹ W_k Γ_x``.
    violations
        Every ``(k, i, j, r, c)``: block (i, j) of ``W̄_k`` has a nonzero entry
        (r, c) above its generalised diagonal (c > r; all 0-based).
    A, C, W
        The input set.
    """

    A: PolyMatrix
    C: PolyMatrix
    W: tuple[PolyMatrix, ...]
    Gamma_x: PolyMatrix
    Gamma_y: PolyMatrix
    q: tuple[int, ...]
    L: PolyMatrix
    A_bar: PolyMatrix
    C_bar: PolyMatrix
    W_bar: tuple[PolyMatrix, ...]
    violations: tuple[tuple[int, int, int, int, int], ...]

    @property
    def lower_triangular(self) -> bool:
        """Every block of every ``W̄_k`` is generalised lower-triangular (eq. (11))."""
        return not self.violations

    def certificate(self) -> Certificate:
        """Exact checks of (8)–(9), the similarity identities, and Theorem 2.

        Theorem 2's check compares :attr:`lower_triangular` with an independent
        run of :func:`~uio_ring.analysis.admissibility.admissibility`: it holds
        when both say yes or both say no.
        """
        checks: list[Check] = []
        Gx, Gy = qc.qmat(self.Gamma_x), qc.qmat(self.Gamma_y)
        A, C = qc.qmat(self.A), qc.qmat(self.C)
        Ab, Cb = qc.qmat(self.A_bar), qc.qmat(self.C_bar)
        n, p = A.nrows(), C.nrows()

        def add(name: str, ok: bool, statement: str, residual: Any = None) -> None:
            checks.append(Check(name, bool(ok), None if ok else residual, statement))

        add("Γ_x, Γ_y nonsingular", qc.qrank(Gx) == n and qc.qrank(Gy) == p, "rank Γ_x = n, rank Γ_y = p",
            f"rank Γ_x = {qc.qrank(Gx)}, rank Γ_y = {qc.qrank(Gy)}")
        r = A * Gx - Gx * Ab
        add("A Γ_x = Γ_x Ā", qc.is_qzero(r), "Ā = Γ_x⁻¹ A Γ_x", qc.to_polymatrix(r))
        r = C * Gx - Gy * Cb
        add("C Γ_x = Γ_y C̄", qc.is_qzero(r), "C̄ = Γ_y⁻¹ C Γ_x", qc.to_polymatrix(r))
        bad = [k for k, (Wk, Wb) in enumerate(zip(self.W, self.W_bar, strict=True))
               if not qc.is_qzero(qc.qmat(Wk) * Gx - Gx * qc.qmat(Wb))]
        add("W_k Γ_x = Γ_x W̄_k", not bad, "W̄_k = Γ_x⁻¹ W_k Γ_x for every k", f"fails for W[{bad[0]}]" if bad else None)
        Aq, Cq = shift_blocks(self.q, n)
        r = Cb - Cq
        add("C̄ = blkdiag(C_{q_i})", qc.is_qzero(r), "eq. (9)", qc.to_polymatrix(r))
        r = Ab - Aq - qc.qmat(self.L) * Cb
        add("Ā = blkdiag(A_{q_i}) + L C̄", qc.is_qzero(r), "eq. (8)", qc.to_polymatrix(r))
        add("Σ q_i = n", sum(self.q) == n, "the chains cover the state", f"Σ q = {sum(self.q)}")
        adm = admissibility(self.A, self.C, self.W)
        add("Theorem 2", adm.holds == self.lower_triangular,
            "every block of every W̄_k is generalised lower-triangular exactly when (A, C, W) is admissible",
            f"lower-triangular: {self.lower_triangular}, admissible: {adm.holds}")
        return Certificate("canonical form (Grip & Saberi 2010, Theorem 2)", checks)

    def __str__(self) -> str:
        state = "canonical (admissible)" if self.lower_triangular else \
            f"not canonical: {len(self.violations)} entries above a block diagonal"
        return f"canonical form: q = {self.q}; {state}"

    def __repr__(self) -> str:
        return f"CanonicalForm(q={self.q}, lower_triangular={self.lower_triangular})"

    def _repr_html_(self) -> str:
        return html.escape(str(self))

    def to_dict(self) -> dict[str, Any]:
        def data(M: PolyMatrix) -> list[list[str]]:
            return [[str(x) for x in row] for row in M.tolist()]

        return {
            "q": list(self.q),
            "Gamma_x": data(self.Gamma_x), "Gamma_y": data(self.Gamma_y), "L": data(self.L),
            "A_bar": data(self.A_bar), "C_bar": data(self.C_bar), "W_bar": [data(W) for W in self.W_bar],
            "lower_triangular": self.lower_triangular,
            "violations": [list(v) for v in self.violations],
        }


def shift_blocks(q: Sequence[int], n: int) -> tuple[qc.QMat, qc.QMat]:
    """``blkdiag(A_{q_i})`` (n×n) and ``blkdiag(C_{q_i})`` (p×n) as ``fmpq_mat``.

    Precondition: ``sum(q) == n`` (not checked).
    """
    Aq = qc.qzeros(n, n)
    Cq = qc.qzeros(len(q), n)
    for i, (s, qi) in enumerate(chain_blocks(q)):
        Cq[i, s] = 1
        for r in range(qi - 1):
            Aq[s + r, s + r + 1] = 1
    return Aq, Cq


def block_violations(W_bar: Sequence[qc.QMat], q: Sequence[int]) -> tuple[tuple[int, int, int, int, int], ...]:
    """Every ``(k, i, j, r, c)`` with ``W̄_k[i, j][r, c] ≠ 0`` and ``c > r`` (eq. (11) fails there)."""
    out = []
    blocks = chain_blocks(q)
    for k, Wb in enumerate(W_bar):
        for i, (si, qi) in enumerate(blocks):
            for j, (sj, qj) in enumerate(blocks):
                for r in range(qi):
                    for c in range(r + 1, qj):
                        if Wb[si + r, sj + c] != 0:
                            out.append((k, i, j, r, c))
    return tuple(out)


def canonical_form(A: Any, C: Any, W: Sequence[Any] = ()) -> CanonicalForm:
    """Γ_x, Γ_y, q, L and (Ā, C̄, W̄_k) of the high-gain canonical form.

    Parameters
    ----------
    A, C
        n×n and p×n constant rational matrices; (A, C) observable and
        ``rank C = p``.
    W
        The ``W_k`` (n×n each); may be empty.

    Returns
    -------
    CanonicalForm
        With ``violations`` empty exactly when the set is admissible.

    Raises
    ------
    NotObservableError
        ``C`` is not of full row rank or (A, C) is not observable.
    DimensionError
        Shapes that do not fit.

    Algorithm
    ---------
    The dual Brunovsky construction (Grip & Saberi 2010, §4 reach (8)–(9) through
    the special coordinate basis; this is the same form without it).  For
    ``k = q_1, …, 1`` and each chain of length exactly k, pick ``v`` in
    𝒮_{k−1} = ker [C; …; C A^{k−2}] (𝒮_0 = Q^n) whose ``γ = C A^{k−1} v`` is
    independent of the γ's already chosen (greedily over an echelon basis of
    𝒮_{k−1}); the chain's columns of Γ_x are ``A^{k−1} v, …, A v, v`` (top first)
    and γ is its column of Γ_y.  Then ``L`` is the columns of Ā at the chain tops.
    O(n) kernels of ≤ n p × n matrices and O(n) n×n products.

    Examples
    --------
    Example 1 of the paper is already in form (8)–(9) up to the order of the
    chains, and is not admissible:

    >>> A = [[0,1,0,0,0],[0,0,0,0,0],[0,0,0,1,0],[0,0,0,0,1],[0,0,0,0,0]]
    >>> C = [[1,0,0,0,0],[0,0,1,0,0]]
    >>> W1 = [[0,-1,0,1,0],[0,0,0,0,1],[0,-1,0,1,0],[1,0,0,0,1],[0,1,0,0,0]]
    >>> cf = canonical_form(A, C, [W1])
    >>> cf.q, cf.lower_triangular, cf.violations[0], cf.certificate().ok
    ((3, 2), False, (0, 0, 0, 0, 1), True)
    """
    Aq, Cq, Ws = sp.read_triple(A, C, W)
    n, p = Aq.nrows(), Cq.nrows()
    if qc.qrank(Cq) < p:
        raise NotObservableError(f"C has rank {qc.qrank(Cq)} < {p} rows: the canonical form needs a full-row-rank C "
                                 "(remove the dependent outputs)")
    q = observability_indices_of(Aq, Cq)
    if sum(q) < n:
        raise NotObservableError(f"(A, C) is not observable (the observability matrix has rank {sum(q)} < n = {n}); "
                                 "the canonical form needs an observable pair")
    gammas: list[qc.QMat] = []  # chosen γ (p×1)
    tops: dict[int, qc.QMat] = {}  # chain index -> v
    chain_of_length: dict[int, list[int]] = {}
    for i, qi in enumerate(q):
        chain_of_length.setdefault(qi, []).append(i)
    for k in sorted(chain_of_length, reverse=True):
        S = sp.kernel(sp.observability_stack(Aq, Cq, k - 1)) if k > 1 else qc.qidentity(n)
        CAk = _last_block(sp.observability_stack(Aq, Cq, k), p)  # C A^{k−1}
        wanted = list(chain_of_length[k])
        # invariant: gammas are independent; each chain of length > k has its γ and v
        for j in range(S.ncols()):
            if not wanted:
                break
            v = sp.column(S, j)
            g = CAk * v
            if qc.qrank(sp.hstack([*gammas, g], p)) > len(gammas):
                gammas.append(g)
                tops[wanted.pop(0)] = v
        if wanted:  # pragma: no cover - impossible for an observable pair (dimension count)
            raise NotObservableError(f"no chain of length {k} found")
    cols: list[qc.QMat] = []
    for i, qi in enumerate(q):
        chain = [tops[i]]
        for _ in range(qi - 1):
            chain.append(Aq * chain[-1])
        cols.extend(reversed(chain))
    Gx = sp.hstack(cols, n)
    Gy = sp.hstack(gammas, p)
    Gxi = qc.qinverse(Gx, "Γ_x")
    Ab = Gxi * Aq * Gx
    Cb = qc.qinverse(Gy, "Γ_y") * Cq * Gx
    Wb = tuple(Gxi * Wk * Gx for Wk in Ws)
    L = qc.qzeros(n, p)
    for i, (s, _) in enumerate(chain_blocks(q)):
        for r in range(n):
            L[r, i] = Ab[r, s]
    P = qc.to_polymatrix
    return CanonicalForm(
        A=P(Aq), C=P(Cq), W=tuple(P(Wk) for Wk in Ws), Gamma_x=P(Gx), Gamma_y=P(Gy), q=q, L=P(L),
        A_bar=P(Ab), C_bar=P(Cb), W_bar=tuple(P(W) for W in Wb), violations=block_violations(Wb, q),
    )


def _last_block(M: qc.QMat, p: int) -> qc.QMat:
    """The last ``p`` rows of ``M``.

    Precondition: ``M`` has at least ``p`` rows (not checked).
    """
    out = qc.qzeros(p, M.ncols())
    off = M.nrows() - p
    for i in range(p):
        for j in range(M.ncols()):
            out[i, j] = M[off + i, j]
    return out
