"""The special coordinate basis (SCB) of a delay-free system, exactly over Q.

For ``x' = A x + B w``, ``y = C x + D w`` (δ-degree 0, ``w`` unknown) the SCB
of Sannuti & Saberi (1987) (Chen, Lin & Shamash 2004, Thm. 5.4.1; the form
used by Tranninger et al. 2021, Prop. 2) is a triple of nonsingular
transformations, new → old::

    x = Ts x̄,   w = Ti w̄,   y = To ȳ
    x̄ = [x_a; x_b; x_c; x_d],   w̄ = [w_0; w_d; w_c],   ȳ = [y_0; y_d; y_b]

in which ``Ā − B̄_0 C̄_0`` has the block pattern (17a) and ``C̄``, ``D̄`` the
pattern (17b): ``x_a`` the zero dynamics (the eigenvalues of ``A_a`` are the
invariant zeros), ``x_b`` observable chains reached by no input, ``x_c`` the
part that makes the system not left invertible, ``x_d`` integrator chains of
lengths ``q_1 ≥ … ≥ q_{m_d}`` from ``w_d`` to ``y_d`` (the infinite zeros).

**Algorithm** (ours, exact; no step decides a rank in floating point).  The
literature's constructive algorithms (Sannuti & Saberi 1987; the numerically
stable one of Chu, Liu & Tan 2002 behind the Linear Systems Toolkit) use
orthogonal transformations, which leave Q (the paper's example needs √15 and
√10).  Any nonsingular rational ``Ts, Ti, To`` giving the pattern is an SCB and
the structural invariants do not depend on the choice, so we build one from
the geometric characterisation, every step a rational linear solve:

1. *Feed-through* (``m_0 = rank D``): ``To⁻¹ D Ti = [[I, 0], [0, 0]]``; with
   ``w_0 = y_0 − C_0 x`` the rest is the strictly proper ``(A − B_0 C_0, B_1, C_1)``.
2. *Zero dynamics*: ``V*`` (weakly unobservable subspace) is ``X_a`` when the
   system is left invertible; ``A T_a = T_a A_a + B G`` defines ``A_a``.
3. *Infinite-zero chains* (columns of ``X_d = S*``): chains grown from the input
   directions, ``t_{k−1} = A t_k − B f``, kept in ``ker C`` until their images
   ``C t`` become independent of the images of the chains already closed —
   the dual of Silverman's structure algorithm (:func:`_input_chains`).
4. *Observable chains* (rows of ``X_b``): the functionals annihilating
   ``V* + S*`` carry an observable pair; its Brunovsky observer form with
   output injection is :func:`~uio_ring.analysis.canonical_form.canonical_form`
   (the same construction as the high-gain method's).
5. *Rows of x_a and x_d*: ``x_d`` rows from the ``y_d`` functionals by
   ``φ_{k+1} = φ_k A − h y_d`` with ``h`` chosen so that ``Φ_d T_d = I``;
   ``x_a`` rows corrected by a triangular recursion along the b chains so that
   ``x_a'`` sees ``x_b`` only through ``y_b`` (:func:`_zero_dynamics_rows`).

``Ts⁻¹`` is then these rows; every identity of (17a)–(23) and Lemma 3 is
re-checked exactly by :meth:`SpecialCoordinateBasis.verify`.

Systems that are not left invertible (``n_c > 0``) get their dimensions
(:func:`scb_dimensions`) but no transformation: no unknown-input observer
exists for them, and this package does not build the ``x_c`` blocks.

>>> from uio_ring import DelaySystem
>>> scb = special_coordinate_basis(DelaySystem("[[0, 1, 0], [0, 0, 1], [-1, -2, -3]]",
...                                            "[[0], [0], [1]]", "[[1, 0, 0]]", None))
>>> (scb.n_a, scb.n_b, scb.n_c, scb.n_d), scb.q, scb.verify().ok
((0, 0, 0, 3), (3,), True)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

from uio_ring.analysis.canonical_form import canonical_form
from uio_ring.analysis.chain_basis import chain_basis
from uio_ring.analysis.chain_couplings import chain_transformation, coupling_coefficients
from uio_ring.analysis.report import _matrix_str
from uio_ring.analysis.strong_observability import (
    constant_matrices,
    invariant_zeros,
    is_strongly_observable,
    weakly_unobservable_subspace,
)
from uio_ring.errors import NotObservableError
from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.errors import DimensionError, UioRingError
from uio_ring.ring.matrix import Poly, PolyMatrix
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = [
    "SpecialCoordinateBasis",
    "special_coordinate_basis",
    "SCBDimensions",
    "scb_dimensions",
    "NotLeftInvertibleError",
]

Q = QMatrix


class NotLeftInvertibleError(NotObservableError):
    """The system is not left invertible (``n_c > 0``): some state is masked by the unknown input for every s."""


# -- small exact helpers -------------------------------------------------------------------------


def _hstack(blocks: Sequence[QMatrix], rows: int) -> QMatrix:
    return Q.hstack(*blocks, rows=rows)


def _vstack(blocks: Sequence[QMatrix], cols: int) -> QMatrix:
    return Q.vstack(*blocks, cols=cols)


def _left_solve(M: QMatrix, Y: QMatrix, what: str) -> QMatrix:
    """``X`` with ``X M = Y`` (one solution, row by row); ``UioRingError`` naming ``what`` if none."""
    rows = []
    for i in range(Y.rows):
        x = M.min_norm_left_solve(Y.row(i))
        if x is None:  # pragma: no cover - excluded by the geometry; a guard for the certificate
            raise UioRingError(f"special coordinate basis: {what} has no solution (please report this system)")
        rows.append(x)
    return _vstack(rows, M.rows)


def _column_space(M: QMatrix) -> QMatrix:
    """A basis of the column space of ``M`` (its independent columns, greedily)."""
    return M.take_cols(M.T.row_basis())


def _sum(U: QMatrix, V: QMatrix) -> QMatrix:
    return _column_space(_hstack([U, V], U.rows))


def _intersection(U: QMatrix, V: QMatrix) -> QMatrix:
    """A basis of ``span U ∩ span V`` (U, V with independent columns)."""
    n = U.rows
    if U.cols == 0 or V.cols == 0:
        return Q.zeros(n, 0)
    K = _hstack([U, -V], n).nullspace()
    return _column_space(U @ K.take_rows(range(U.cols))) if K.cols else Q.zeros(n, 0)


def _compress(G: QMatrix) -> tuple[QMatrix, int]:
    """Invertible ``T`` with ``G T = [G_1, 0]``, ``G_1`` of full column rank ``r``; returns ``(T, r)``."""
    k = G.cols
    piv = G.rref().pivots
    N = G.nullspace()
    E = _hstack([_unit_col(k, j) for j in piv], k)
    return _hstack([E, N], k), len(piv)


def _unit_col(k: int, j: int) -> QMatrix:
    return Q([[1 if i == j else 0] for i in range(k)], shape=(k, 1))


# -- step 1: feed-through -------------------------------------------------------------------------


@dataclass(frozen=True)
class _FeedThrough:
    m0: int
    To0: QMatrix  # p×p
    Ti0: QMatrix  # m×m
    A_star: QMatrix  # A − B_0 C_0
    B1: QMatrix
    C1: QMatrix


def _feed_through(A: QMatrix, B: QMatrix, C: QMatrix, D: QMatrix) -> _FeedThrough:
    """``To0⁻¹ D Ti0 = [[I, 0], [0, 0]]`` and the strictly proper rest (step 1)."""
    p, m = D.shape
    Ti0, m0 = _compress(D)
    D1 = (D @ Ti0).take_cols(range(m0))
    comp = [_unit_col(p, i) for i in _complement_rows(D1)]
    To0 = _hstack([D1, *comp], p)
    Cp = To0.inverse(name="To0") @ C
    Bp = B @ Ti0
    B0, B1 = Bp.take_cols(range(m0)), Bp.take_cols(range(m0, m))
    C0, C1 = Cp.take_rows(range(m0)), Cp.take_rows(range(m0, p))
    return _FeedThrough(m0, To0, Ti0, A - B0 @ C0, B1, C1)


def _complement_rows(D1: QMatrix) -> list[int]:
    """Indices of unit vectors completing the columns of ``D1`` to a basis."""
    p = D1.rows
    basis = D1
    out = []
    for i in range(p):
        cand = _hstack([basis, _unit_col(p, i)], p)
        if cand.rank() > basis.rank():
            basis = cand
            out.append(i)
    return out


# -- step 2/3: subspaces and input chains ----------------------------------------------------------


def _strongly_reachable(A: QMatrix, B: QMatrix, C: QMatrix) -> QMatrix:
    """``S*``: ``S_1 = im B``, ``S_{k+1} = im B + A (S_k ∩ ker C)`` (a basis as columns)."""
    n = A.rows
    kerC = C.nullspace() if C.rows else Q.identity(n)
    S = _column_space(B)
    while True:
        Sn = _sum(_column_space(B), A @ _intersection(S, kerC)) if S.cols else _column_space(B)
        if Sn.cols == S.cols:
            return Sn
        S = Sn


@dataclass
class _Chain:
    """A chain of columns grown from an input direction: ``cols[0] = B coef`` (its end),
    ``cols[k] = A cols[k−1] − B f`` (depth k); closed when its head's ``C``-image is new."""

    coef: QMatrix  # m×1: the end column is B coef
    cols: list[QMatrix]
    closed_at: int = 0  # level at which the chain closed (its length)


def _input_chains(A: QMatrix, B: QMatrix, C: QMatrix) -> list[_Chain]:
    """The infinite-zero chains of a left-invertible strictly proper system (step 3).

    Level k: the heads of the open chains (depth k − 1, all in ``ker C``) have images
    ``G = [C h_i]``; ``S`` holds the start images of the chains closed at levels k' < k.
    A vector ``[a; b]`` of ``ker [S, G]`` is a recombination ``Σ b_i chain_i`` whose image
    ``G b = −S a`` is cancelled by adding the closed chains shifted by k − k' (which keeps
    ``A t_d = t_{d+1} + B f`` and ``C t = 0`` below the head): it stays open and grows by
    ``A h``.  The chains of the pivot columns of ``[S, G]`` close at level k.  Every chain
    closes within n levels for a left-invertible system.
    """
    n, m = B.shape
    p = C.rows
    open_: list[_Chain] = [_Chain(_unit_col(m, j), [B.col(j)]) for j in range(m)]
    closed: list[_Chain] = []
    level = 1
    while open_:
        if level > n + 1:
            raise NotLeftInvertibleError("an input chain never reaches the output: the system is not left invertible")
        k = len(closed)
        S = _hstack([C @ ch.cols[-1] for ch in closed], p)
        G = _hstack([C @ ch.cols[-1] for ch in open_], p)
        M = _hstack([S, G], p)
        pivots = [j - k for j in M.rref().pivots if j >= k]
        N = M.nullspace()
        next_open = []
        for c in range(N.cols):
            ch = _combine(open_, [N[k + i, c] for i in range(len(open_))])
            for j, other in enumerate(closed):
                if N[j, c]:
                    _add_shifted(ch, other, N[j, c], level)
            ch.cols.append(A @ ch.cols[-1])
            next_open.append(ch)
        for i in pivots:
            ch = open_[i]
            ch.closed_at = level
            closed.append(ch)
        open_ = next_open
        level += 1
    return sorted(closed, key=lambda ch: -ch.closed_at)


def _add_shifted(ch: _Chain, other: _Chain, c: Any, level: int) -> None:
    """``ch.cols[d] += c · other.cols[d − δ]`` for ``δ = level − other.closed_at ≥ 1``."""
    shift = level - other.closed_at
    for d in range(shift, len(ch.cols)):
        ch.cols[d] = ch.cols[d] + other.cols[d - shift] * c


def _combine(chains: list[_Chain], b: list[Any]) -> _Chain:
    """``Σ b_i chain_i`` (chains of equal length)."""
    coef = chains[0].coef * 0
    cols = [c * 0 for c in chains[0].cols]
    for bi, ch in zip(b, chains, strict=True):
        if bi:
            coef = coef + ch.coef * bi
            cols = [a + c * bi for a, c in zip(cols, ch.cols, strict=True)]
    return _Chain(coef, cols)


# -- steps 4–5: the rows of Ts⁻¹ ----------------------------------------------------------------------


def _right_solve(M: QMatrix, Y: QMatrix, what: str) -> QMatrix:
    """``X`` with ``M X = Y``."""
    return _left_solve(M.T, Y.T, what).T


@dataclass(frozen=True)
class _ObservableChains:
    rows: QMatrix  # Φ_b (n_b×n)
    l: tuple[int, ...]
    y_rows: QMatrix  # hb (p_b×p1): hb C1 = the chain-start rows of Φ_b
    A_b: QMatrix  # Φ_b A = A_b Φ_b + H C1


def _observable_chains(A: QMatrix, C: QMatrix, annihilated: QMatrix) -> _ObservableChains:
    """Rows of ``x_b`` (step 4): the functionals vanishing on ``V* + S*`` in Brunovsky observer form."""
    n, p = A.rows, C.rows
    P = annihilated.T.nullspace().T if annihilated.cols else Q.identity(n)
    nb = P.rows
    if nb == 0:
        return _ObservableChains(Q.zeros(0, n), (), Q.zeros(0, p), Q.zeros(0, 0))
    MH = _left_solve(_vstack([P, C], n), P @ A, "P A = M P + H C")
    M = MH.take_cols(range(nb))
    K = _vstack([C, P], n).left_nullspace()  # [h, g]: h C + g P = 0
    h, g = K.take_cols(range(p)), K.take_cols(range(p, p + nb))
    cf = canonical_form(M.to_polymatrix(), (-g).to_polymatrix())
    Gx, Gy = Q(cf.Gamma_x), Q(cf.Gamma_y)
    rows = Gx.inverse(name="Γ_x") @ P
    return _ObservableChains(rows, cf.q, Gy.inverse(name="Γ_y") @ h, Q(cf.A_bar))


def _chain_rows(A: QMatrix, C: QMatrix, T_d: QMatrix, q: Sequence[int], starts: Sequence[int]) -> tuple[QMatrix, QMatrix]:
    """Rows of ``x_d`` (step 5) and the ``y_d`` output rows ``kd``: ``φ_1 = kd_i C``,
    ``φ_{k+1} = φ_k A − Σ_j (φ_k A t_{j,1}) kd_j C``, so that ``Φ_d T_d = I``."""
    n = A.rows
    Ts_starts = T_d.take_cols(starts)
    kd = _left_solve(C @ Ts_starts, Q.identity(len(starts)), "kd C T_d,starts = I")
    Y = kd @ C
    rows = []
    for i, qi in enumerate(q):
        phi = Y.row(i)
        rows.append(phi)
        for _ in range(qi - 1):
            nxt = phi @ A
            phi = nxt - (nxt @ Ts_starts) @ Y
            rows.append(phi)
    return (_vstack(rows, n) if rows else Q.zeros(0, n)), kd


def _zero_dynamics_rows(A: QMatrix, C: QMatrix, T_a: QMatrix, T_d: QMatrix, obs: _ObservableChains,
                        A_a: QMatrix) -> QMatrix:
    """Rows of ``x_a`` (step 5): a lift ``Φ⁰`` of the dual basis of ``V*`` inside ``(S*)^⊥``,
    corrected to ``Φ_a = Φ⁰ + Z Φ_b`` so that ``Φ_a A − A_a Φ_a`` lies in ``row C``:
    along each b chain, ``Z_{k−1} = A_a Z_k − R_k`` from ``Z_l = 0`` (``R``: the ``Φ_b`` part of ``Φ⁰ A``)."""
    n = A.rows
    na = T_a.cols
    Psi = T_d.T.nullspace().T if T_d.cols else Q.identity(n)
    phi0 = _left_solve(Psi @ T_a, Q.identity(na), "lift of V*'s dual basis") @ Psi
    nb = obs.rows.rows
    if nb == 0:
        return phi0
    X = _left_solve(_vstack([phi0, obs.rows, C], n), phi0 @ A, "Φ⁰ A = A_a Φ⁰ + R Φ_b + H C")
    R = X.take_cols(range(na, na + nb))
    cols = [Q.zeros(na, 1) for _ in range(nb)]
    s = 0
    for li in obs.l:
        for k in range(li - 1, 0, -1):  # 0-based positions li−1 … 1
            cols[s + k - 1] = A_a @ cols[s + k] - R.col(s + k)
        s += li
    return phi0 + _hstack(cols, na) @ obs.rows


def _theorem1(Ts: QMatrix, A: QMatrix, q: Sequence[int], offset: int) -> QMatrix:
    """``blkdiag(I, T_d)`` with ``T_d`` of Lemma 2 of Tranninger et al. (2021): the observer normal form
    transformation (54) of Niederwieser et al. (2022) for ``Ǎ_d = A_d − H_dd C_d``, ``Č = C_d``, ``μ = q``
    (its ``O_R`` is the identity, so ``C_d T_d = C_d`` and ``T_d⁻¹ B_d = B_d``): afterwards ``F_dd`` is
    lower triangular as (24)."""
    n = A.rows
    nd = n - offset
    if nd == 0:
        return Q.identity(n)
    d = list(range(offset, n))
    A_d = (Ts.inverse(name="Ts") @ A @ Ts).take_rows(d).take_cols(d)
    starts = _chain_starts(q)
    C_d = _selector(q, at_end=False)
    H_dd = (A_d - _shift(q)).take_cols(starts)
    basis = chain_basis(A_d - H_dd @ C_d, C_d, tuple(q))
    T_d = chain_transformation(basis, coupling_coefficients(basis))
    return Q.block([[Q.identity(offset), Q.zeros(offset, nd)], [Q.zeros(nd, offset), T_d]]) if offset else T_d


# -- the result ----------------------------------------------------------------------------------------


@dataclass(frozen=True)
class SCBDimensions:
    """The structural integers of the SCB, from subspaces alone (also when ``n_c > 0``).

    ``n_a = dim V* − dim R*``, ``n_c = dim R*``, ``n_d = dim S* − dim R*``,
    ``n_b = n − dim (V* + S*)``, ``m_0 = rank D``; ``R* = V* ∩ S*`` (Lemma 3 (p.6), (p.7)).
    """

    n_a: int
    n_b: int
    n_c: int
    n_d: int
    m_0: int

    @property
    def left_invertible(self) -> bool:
        """``n_c = 0`` (Lemma 3 (p.5))."""
        return self.n_c == 0


def _chain_starts(lengths: Sequence[int], offset: int = 0) -> list[int]:
    out, s = [], offset
    for q in lengths:
        out.append(s)
        s += q
    return out


def _chain_ends(lengths: Sequence[int], offset: int = 0) -> list[int]:
    return [s + q - 1 for s, q in zip(_chain_starts(lengths, offset), lengths, strict=True)]


def _shift(lengths: Sequence[int]) -> QMatrix:
    """``blkdiag(J_{q_1}, …)``: ones above the diagonal inside each chain."""
    n = sum(lengths)
    rows = [[0] * n for _ in range(n)]
    for s, q in zip(_chain_starts(lengths), lengths, strict=True):
        for k in range(q - 1):
            rows[s + k][s + k + 1] = 1
    return Q(rows, shape=(n, n))


def _selector(lengths: Sequence[int], at_end: bool) -> QMatrix:
    """``C_q = blkdiag([1, 0, …])`` (rows) or ``B_q = blkdiag([0; …; 1])`` (columns, ``at_end``)."""
    n = sum(lengths)
    idx = _chain_ends(lengths) if at_end else _chain_starts(lengths)
    rows = [[1 if j == i else 0 for j in range(n)] for i in idx]
    M = Q(rows, shape=(len(idx), n))
    return M.T if at_end else M


@dataclass(frozen=True)
class SpecialCoordinateBasis:
    """The special coordinate basis of a left-invertible delay-free system (exact).

    Orderings: ``x̄ = [x_a; x_b; x_d]`` (``x_c`` is empty: ``n_c = 0``),
    ``w̄ = [w_0; w_d]``, ``ȳ = [y_0; y_d; y_b]``; ``x = Ts x̄``, ``w = Ti w̄``, ``y = To ȳ``.

    Attributes
    ----------
    Ts, Ti, To
        Nonsingular rational transformations (new → old).
    A_bar, B_bar, C_bar, D_bar
        ``Ts⁻¹ A Ts``, ``Ts⁻¹ B Ti``, ``To⁻¹ C Ts``, ``To⁻¹ D Ti``.
    n_a, n_b, n_c, n_d, m_0, m_d, p_b
        Block sizes.
    q
        Lengths of the ``x_d`` chains (infinite-zero orders), non-increasing.
    l
        Lengths of the ``x_b`` chains (observability indices of ``(A_b, C_b)``), non-increasing.
    A_a, A_b, A_d, B_d, C_b, C_d
        Diagonal blocks; ``A_b = A_b* + H_bb C_b``, ``A_d = A_d* + B_d F_dd + H_dd C_d``.
    H_ab, H_ad, H_bb, H_bd, H_dd, F_da, F_db, F_dd
        Couplings of (17a), with the chain-start columns in the ``H`` blocks.
    B_0, C_0
        ``B̄_0`` (n×m_0) and ``C̄_0`` (m_0×n): the feed-through, ``Ā = Ā_s + B̄_0 C̄_0``.
    system
        The analysed system.
    """

    system: DelaySystem
    Ts: PolyMatrix
    Ti: PolyMatrix
    To: PolyMatrix
    A_bar: PolyMatrix
    B_bar: PolyMatrix
    C_bar: PolyMatrix
    D_bar: PolyMatrix
    n_a: int
    n_b: int
    n_d: int
    m_0: int
    q: tuple[int, ...]
    l: tuple[int, ...]
    n_c: int = 0

    # -- sizes ---------------------------------------------------------------------------------
    @property
    def m_d(self) -> int:
        return len(self.q)

    @property
    def p_b(self) -> int:
        return len(self.l)

    @property
    def dimensions(self) -> SCBDimensions:
        return SCBDimensions(self.n_a, self.n_b, self.n_c, self.n_d, self.m_0)

    def _idx(self, part: str) -> list[int]:
        start = {"a": 0, "b": self.n_a, "d": self.n_a + self.n_b}[part]
        size = {"a": self.n_a, "b": self.n_b, "d": self.n_d}[part]
        return list(range(start, start + size))

    def _q(self, M: PolyMatrix) -> QMatrix:
        return Q(M)

    @cached_property
    def A_s(self) -> PolyMatrix:
        """``Ā_s = Ā − B̄_0 C̄_0``: the state matrix with the feed-through eliminated (17a)."""
        return (self._q(self.A_bar) - Q(self.B_0) @ Q(self.C_0)).to_polymatrix()

    @property
    def B_0(self) -> PolyMatrix:
        return self._q(self.B_bar).take_cols(range(self.m_0)).to_polymatrix()

    @property
    def C_0(self) -> PolyMatrix:
        return self._q(self.C_bar).take_rows(range(self.m_0)).to_polymatrix()

    def _block(self, rows: Sequence[int], cols: Sequence[int]) -> PolyMatrix:
        return Q(self.A_s).take_rows(rows).take_cols(cols).to_polymatrix()

    @property
    def A_a(self) -> PolyMatrix:
        return self._block(self._idx("a"), self._idx("a"))

    @property
    def A_b(self) -> PolyMatrix:
        return self._block(self._idx("b"), self._idx("b"))

    @property
    def A_d(self) -> PolyMatrix:
        return self._block(self._idx("d"), self._idx("d"))

    @property
    def B_d(self) -> PolyMatrix:
        return _selector(self.q, at_end=True).to_polymatrix()

    @property
    def C_d(self) -> PolyMatrix:
        return _selector(self.q, at_end=False).to_polymatrix()

    @property
    def C_b(self) -> PolyMatrix:
        return _selector(self.l, at_end=False).to_polymatrix()

    def _starts(self, part: str) -> list[int]:
        return _chain_starts(self.q if part == "d" else self.l, self._idx(part)[0] if self._idx(part) else 0)

    def _ends(self, part: str) -> list[int]:
        return _chain_ends(self.q, self._idx("d")[0] if self.n_d else 0)

    @property
    def H_ab(self) -> PolyMatrix:
        return self._block(self._idx("a"), self._starts("b"))

    @property
    def H_ad(self) -> PolyMatrix:
        return self._block(self._idx("a"), self._starts("d"))

    @property
    def H_bd(self) -> PolyMatrix:
        return self._block(self._idx("b"), self._starts("d"))

    @property
    def H_bb(self) -> PolyMatrix:
        return self._block(self._idx("b"), self._starts("b"))

    @property
    def H_dd(self) -> PolyMatrix:
        return (Q(self._block(self._idx("d"), self._starts("d"))) - _shift(self.q).take_cols(
            [s - self.n_a - self.n_b for s in self._starts("d")])).to_polymatrix()

    @property
    def F_da(self) -> PolyMatrix:
        return self._block(self._ends("d"), self._idx("a"))

    @property
    def F_db(self) -> PolyMatrix:
        return self._block(self._ends("d"), self._idx("b"))

    @property
    def F_dd(self) -> PolyMatrix:
        """Rows of ``A_d − A_d* − H_dd C_d`` at the chain ends (zero in the chain-start columns)."""
        rest = Q(self.A_d) - _shift(self.q) - Q(self.H_dd) @ _selector(self.q, at_end=False)
        return rest.take_rows([e - self.n_a - self.n_b for e in self._ends("d")]).to_polymatrix()

    @property
    def invariant_zero_polynomial(self) -> Poly:
        """``det(s I − A_a)``: its roots are the invariant zeros (Lemma 3 (p.2))."""
        return charpoly(Q(self.A_a))

    # -- display -------------------------------------------------------------------------------
    def __str__(self) -> str:
        lines = [
            "special coordinate basis (Sannuti & Saberi 1987; exact over Q)",
            f"  (n_a, n_b, n_c, n_d) = ({self.n_a}, {self.n_b}, {self.n_c}, {self.n_d}); "
            f"m_0 = {self.m_0}, m_d = {self.m_d}, p_b = {self.p_b}",
            f"  infinite-zero chains q = {self.q}; observable chains l = {self.l}",
            f"  invariant-zero polynomial det(sI − A_a) = {self.invariant_zero_polynomial}",
        ]
        if self.n_a:
            lines.append("  A_a =\n" + _matrix_str(self.A_a))
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        import html

        return "<pre>" + html.escape(str(self)) + "</pre>"

    def to_dict(self) -> dict[str, Any]:
        return {
            "n_a": self.n_a, "n_b": self.n_b, "n_c": self.n_c, "n_d": self.n_d,
            "m_0": self.m_0, "m_d": self.m_d, "p_b": self.p_b, "q": list(self.q), "l": list(self.l),
            "invariant_zero_polynomial": str(self.invariant_zero_polynomial),
            "Ts": str(self.Ts), "Ti": str(self.Ti), "To": str(self.To),
        }

    def verify(self) -> Certificate:
        """Exact checks of (17a)–(23) and Lemma 3 (p.1)–(p.7); see :func:`scb_certificate`."""
        return scb_certificate(self)


# -- the algorithm ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class _Reduced:
    """The strictly proper system of step 1 and its subspaces."""

    ft: _FeedThrough
    A: QMatrix
    B: QMatrix
    C: QMatrix
    D: QMatrix
    V: QMatrix  # V* (columns)
    S: QMatrix  # S* (columns)
    dims: SCBDimensions


def _reduce(sys: DelaySystem) -> _Reduced:
    """Checks, step 1 and the subspaces ``V*``, ``S*``, ``R* = V* ∩ S*``."""
    M = constant_matrices(sys)
    A, B, C, D = M["A"], M["B"], M["C"], M["D"]
    n, m, p = sys.n_x, sys.n_w, sys.n_y
    if m and _vstack([B, D], m).rank() < m:
        raise DimensionError(f"the unknown-input columns are dependent (rank [B; D] = {_vstack([B, D], m).rank()} < "
                             f"n_w = {m}): the SCB needs independent columns (combine the dependent inputs)")
    if p and _hstack([C, D], p).rank() < p:
        raise DimensionError(f"the outputs are dependent (rank [C, D] = {_hstack([C, D], p).rank()} < n_y = {p}): "
                             "the SCB needs independent outputs (remove the redundant ones)")
    ft = _feed_through(A, B, C, D)
    reduced = DelaySystem(ft.A_star.to_polymatrix(), ft.B1.to_polymatrix(), ft.C1.to_polymatrix(), None)
    V = weakly_unobservable_subspace(reduced) if n else Q.zeros(0, 0)
    S = _strongly_reachable(ft.A_star, ft.B1, ft.C1) if ft.B1.cols else Q.zeros(n, 0)
    R = _intersection(V, S)
    VS = _sum(V, S) if V.cols + S.cols else Q.zeros(n, 0)
    dims = SCBDimensions(n_a=V.cols - R.cols, n_b=n - VS.cols, n_c=R.cols, n_d=S.cols - R.cols, m_0=ft.m0)
    return _Reduced(ft, A, B, C, D, V, S, dims)


def scb_dimensions(sys: DelaySystem) -> SCBDimensions:
    """``(n_a, n_b, n_c, n_d, m_0)`` of a delay-free system, also when it is not left invertible.

    >>> from uio_ring import DelaySystem
    >>> scb_dimensions(DelaySystem("[[0, 1], [0, 0]]", "[[1, 0], [0, 1]]", "[[1, 0]]", None))
    SCBDimensions(n_a=0, n_b=0, n_c=1, n_d=1, m_0=0)
    """
    return _reduce(sys).dims


def special_coordinate_basis(sys: DelaySystem) -> SpecialCoordinateBasis:
    """The special coordinate basis of a delay-free, left-invertible system, exactly over Q.

    Parameters
    ----------
    sys
        δ-degree 0, independent unknown-input columns (``rank [B; D] = n_w``) and
        outputs (``rank [C, D] = n_y``); known inputs play no part.

    Returns
    -------
    SpecialCoordinateBasis
        ``Ts, Ti, To``, the transformed matrices, the sizes, the chain lengths
        ``q`` and ``l`` and the blocks of (17a)–(23); ``.verify()`` checks them.

    Raises
    ------
    NotLeftInvertibleError
        ``n_c > 0`` (the message gives ``n_c``; :func:`scb_dimensions` gives all sizes).
    DomainError
        A matrix depends on δ.
    DimensionError
        Dependent unknown-input columns or outputs.

    Algorithm
    ---------
    Steps 1–5 of the module docstring: the feed-through split, ``V*`` and ``S*`` by
    their recursions, input chains grown in ``ker C`` (dual Silverman structure
    algorithm), the Brunovsky observer form of the functionals vanishing on
    ``V* + S*`` (:func:`~uio_ring.analysis.canonical_form.canonical_form`) and the
    rows of ``x_a``, ``x_d`` by triangular recursions.  All exact linear algebra over Q.

    Examples
    --------
    A double integrator ``y = x_2``, ``x_3' = w`` driving ``x_1' = −2 x_1 + x_2``, which
    ``y`` does not see: a zero at −2 (``x_a``) and one chain of length 2 (``x_d``):

    >>> from uio_ring import DelaySystem
    >>> sys = DelaySystem("[[-2, 1, 0], [0, 0, 1], [0, 0, 0]]", "[[0], [0], [1]]", "[[0, 1, 0]]", None)
    >>> scb = special_coordinate_basis(sys)
    >>> (scb.n_a, scb.n_b, scb.n_d), scb.q, scb.l, scb.invariant_zero_polynomial
    ((1, 0, 2), (2,), (), s + 2)
    """
    red = _reduce(sys)
    if red.dims.n_c:
        raise NotLeftInvertibleError(
            f"the system is not left invertible (n_c = dim R* = {red.dims.n_c} > 0): some state directions are "
            "masked by the unknown input for every s, and no unknown-input observer exists; this package does not "
            "build the SCB blocks of x_c (scb_dimensions gives the sizes)")
    ft = red.ft
    A, B1, C1 = ft.A_star, ft.B1, ft.C1
    n = A.rows
    chains = _input_chains(A, B1, C1) if B1.cols else []
    q = tuple(ch.closed_at for ch in chains)
    T_d = _hstack([c for ch in chains for c in reversed(ch.cols)], n) if chains else Q.zeros(n, 0)
    Ti1 = _hstack([ch.coef for ch in chains], B1.cols) if chains else Q.zeros(0, 0)
    T_a = red.V
    obs = _observable_chains(A, C1, _hstack([T_a, T_d], n))
    d_starts = _chain_starts(q)
    Phi_d, kd = _chain_rows(A, C1, T_d, q, d_starts)
    na = T_a.cols
    if na:
        A_a = _left_solve(_hstack([T_a, B1], n).T, (A @ T_a).T, "A T_a = T_a A_a + B G").T.take_rows(range(na))
        Phi_a = _zero_dynamics_rows(A, C1, T_a, T_d, obs, A_a)
    else:
        Phi_a = Q.zeros(0, n)
    Ts = _vstack([Phi_a, obs.rows, Phi_d], n).inverse(name="Ts⁻¹")
    Ts = Ts @ _theorem1(Ts, A, q, na + obs.rows.rows)
    m0 = ft.m0
    p, m = red.D.shape
    Ti = ft.Ti0 @ Q.block([[Q.identity(m0), Q.zeros(m0, m - m0)], [Q.zeros(m - m0, m0), Ti1]]) if m else Q.zeros(0, 0)
    To1 = _vstack([kd, obs.y_rows], p - m0).inverse(name="To⁻¹") if p - m0 else Q.zeros(0, 0)
    To = ft.To0 @ Q.block([[Q.identity(m0), Q.zeros(m0, p - m0)], [Q.zeros(p - m0, m0), To1]]) if p else Q.zeros(0, 0)
    Tsi = Ts.inverse(name="Ts")
    Toi = To.inverse(name="To") if p else To
    return SpecialCoordinateBasis(
        system=sys,
        Ts=Ts.to_polymatrix(), Ti=Ti.to_polymatrix(), To=To.to_polymatrix(),
        A_bar=(Tsi @ red.A @ Ts).to_polymatrix(),
        B_bar=(Tsi @ red.B @ Ti).to_polymatrix(),
        C_bar=(Toi @ red.C @ Ts).to_polymatrix(),
        D_bar=(Toi @ red.D @ Ti).to_polymatrix(),
        n_a=na, n_b=obs.rows.rows, n_d=T_d.cols, m_0=m0, q=q, l=tuple(obs.l),
    )


# -- the certificate -------------------------------------------------------------------------------


def _check(name: str, lhs: QMatrix, rhs: QMatrix, statement: str = "") -> Check:
    ok = lhs.shape == rhs.shape and lhs == rhs
    return Check(name, ok, None if ok else (lhs - rhs if lhs.shape == rhs.shape else f"{lhs.shape} vs {rhs.shape}"),
                 statement)


def _assembled(scb: SpecialCoordinateBasis) -> QMatrix:
    """``Ā_s`` rebuilt from the blocks of (17a) (``x_c`` empty)."""
    na, nb, nd = scb.n_a, scb.n_b, scb.n_d
    Cb, Cd, Bd = Q(scb.C_b), Q(scb.C_d), Q(scb.B_d)
    Z = Q.zeros
    return Q.block([
        [Q(scb.A_a), Q(scb.H_ab) @ Cb, Q(scb.H_ad) @ Cd],
        [Z(nb, na), Q(scb.A_b), Q(scb.H_bd) @ Cd],
        [Bd @ Q(scb.F_da), Bd @ Q(scb.F_db), Q(scb.A_d)],
    ]) if na + nb + nd else Z(0, 0)


def _theorem1_violations(scb: SpecialCoordinateBasis) -> list[tuple[int, int]]:
    """Entries ``(i, col)`` of ``F_dd`` outside the pattern (24) (0-based chain i, d column)."""
    F = Q(scb.F_dd)
    starts = _chain_starts(scb.q)
    owner = [j for j, qj in enumerate(scb.q) for _ in range(qj)]
    out = []
    for i in range(F.rows):
        for c in range(F.cols):
            if F[i, c] and (owner[c] >= i or c in starts):
                out.append((i, c))
    return out


def scb_certificate(scb: SpecialCoordinateBasis) -> Certificate:
    """Named exact checks of a :class:`SpecialCoordinateBasis`.

    The transformations (nonsingular; ``Ā = Ts⁻¹ A Ts`` etc.), the patterns (17a),
    (17b), (18)–(23), the dimension identities, and Lemma 3 of Tranninger et al. (2021):
    (p.1) normrank G = m_0 + m_d, (p.2) ``det(sI − A_a)`` is the invariant-zero
    polynomial of ``P(s)`` (Smith form), (p.3) (A_b, C_b) observable, (p.4)
    (A_d, B_d, C_d) strongly observable, (p.5) left invertible ⇔ n_c = 0, (p.6) the
    ``x_a`` columns of ``Ts`` span ``V*``, (p.7) ``R* = {0}`` (no ``x_c``).  The zeros are computed on
    the transformed system: its Rosenbrock matrix is ``diag(Ts⁻¹, To⁻¹) P(s) diag(Ts, Ti)`` (a constant
    unimodular equivalence once ``Ā = Ts⁻¹ A Ts`` etc. hold), so its invariant factors are those of ``P(s)``.
    """
    sys = scb.system
    M = constant_matrices(sys)
    A, B, C, D = M["A"], M["B"], M["C"], M["D"]
    Ts, Ti, To = Q(scb.Ts), Q(scb.Ti), Q(scb.To)
    n, m, p = sys.n_x, sys.n_w, sys.n_y
    checks: list[Check] = []
    nonsingular = all(T.is_square() and (T.rows == 0 or T.det() != 0) for T in (Ts, Ti, To))
    checks.append(Check("Ts, Ti, To nonsingular", nonsingular, None if nonsingular else "a singular transformation"))
    if not nonsingular:
        return Certificate("special coordinate basis", checks)
    Tsi = Ts.inverse() if n else Ts
    Toi = To.inverse() if p else To
    checks += [
        _check("Ā = Ts⁻¹ A Ts", Q(scb.A_bar), Tsi @ A @ Ts),
        _check("B̄ = Ts⁻¹ B Ti", Q(scb.B_bar), Tsi @ B @ Ti),
        _check("C̄ = To⁻¹ C Ts", Q(scb.C_bar), Toi @ C @ Ts),
        _check("D̄ = To⁻¹ D Ti", Q(scb.D_bar), Toi @ D @ Ti),
    ]
    na, nb, nd, m0, md, pb = scb.n_a, scb.n_b, scb.n_d, scb.m_0, scb.m_d, scb.p_b
    sizes = (na + nb + nd == n and sum(scb.q) == nd and sum(scb.l) == nb and m0 + md == m and m0 + md + pb == p
             and list(scb.q) == sorted(scb.q, reverse=True) and all(k >= 1 for k in scb.q + scb.l))
    checks.append(Check("sizes: n = n_a + n_b + n_d, Σq = n_d, Σl = n_b, m = m_0 + m_d, p = m_0 + m_d + p_b, "
                        "q non-increasing", sizes, None if sizes else (na, nb, nd, m0, md, pb, scb.q, scb.l)))
    if not sizes:
        return Certificate("special coordinate basis", checks)
    checks.append(_check("(17a) Ā − B̄_0 C̄_0 has the SCB block pattern", Q(scb.A_s), _assembled(scb)))
    Bd_full = _vstack([Q.zeros(na + nb, md), Q(scb.B_d)], md) if md else Q.zeros(n, 0)
    checks.append(_check("(17a) B̄ = [B̄_0, [0; 0; B_d]]", Q(scb.B_bar), _hstack([Q(scb.B_0), Bd_full], n)))
    Cbar = _vstack([Q(scb.C_0),
                    _hstack([Q.zeros(md, na + nb), Q(scb.C_d)], md) if md else Q.zeros(0, n),
                    _hstack([Q.zeros(pb, na), Q(scb.C_b), Q.zeros(pb, nd)], pb) if pb else Q.zeros(0, n)], n)
    checks.append(_check("(17b) C̄ = [C̄_0; [0, 0, C_d]; [0, C_b, 0]]", Q(scb.C_bar), Cbar))
    Dbar = Q([[1 if (i == j and i < m0) else 0 for j in range(m)] for i in range(p)], shape=(p, m))
    checks.append(_check("(17b) D̄ = [[I_m0, 0], [0, 0]]", Q(scb.D_bar), Dbar))
    checks.append(_check("(18)–(19) A_b = A_b* + H_bb C_b", Q(scb.A_b),
                         _shift(scb.l) + Q(scb.H_bb) @ Q(scb.C_b) if nb else Q.zeros(0, 0)))
    checks.append(_check("(20)–(23) A_d = A_d* + B_d F_dd + H_dd C_d", Q(scb.A_d),
                         _shift(scb.q) + Q(scb.B_d) @ Q(scb.F_dd) + Q(scb.H_dd) @ Q(scb.C_d) if nd else Q.zeros(0, 0)))
    bad = _theorem1_violations(scb)
    checks.append(Check("Theorem 1: F_dd lower triangular as (24) (row i only in columns 2…q_j of chains j < i)",
                        not bad, bad or None))
    # Lemma 3
    # P̄(s) = diag(Ts⁻¹, To⁻¹) P(s) diag(Ts, Ti) (identities checked above): the same invariant factors,
    # computed on the sparse SCB form (the original's entries can be large)
    zeros = invariant_zeros(DelaySystem(scb.A_bar, scb.B_bar, scb.C_bar, scb.D_bar))
    checks.append(Check("(p.1) normrank G(s) = m_0 + m_d", zeros.normal_rank - n == m0 + md,
                        None if zeros.normal_rank - n == m0 + md else f"normrank G = {zeros.normal_rank - n}"))
    zp, ap = zeros.polynomial, scb.invariant_zero_polynomial
    ok = ap == zp
    checks.append(Check("(p.2) det(sI − A_a) = invariant-zero polynomial of P(s)", ok,
                        None if ok else f"{ap} vs {zp}"))
    obs = Q(scb.C_b)
    Ab = Q(scb.A_b)
    stack, row = [], obs
    for _ in range(nb):
        stack.append(row)
        row = row @ Ab
    ok = nb == 0 or _vstack(stack, nb).rank() == nb
    checks.append(Check("(p.3) (A_b, C_b) observable", ok, None if ok else "rank of the observability matrix < n_b"))
    if nd:
        so = is_strongly_observable(DelaySystem(scb.A_d, scb.B_d, scb.C_d, None), cross_check=False).holds
    else:
        so = True
    checks.append(Check("(p.4) (A_d, B_d, C_d) strongly observable (no invariant zeros)", so,
                        None if so else "the d subsystem has invariant zeros"))
    ok = zeros.normal_rank == n + m and scb.n_c == 0
    checks.append(Check("(p.5) left invertible (normrank P = n + m) and n_c = 0", ok,
                        None if ok else f"normrank P = {zeros.normal_rank}, n + m = {n + m}"))
    V = weakly_unobservable_subspace(sys) if n else Q.zeros(0, 0)
    Ta = Ts.take_cols(range(na))
    ok = V.cols == na and (na == 0 or _hstack([V, Ta], n).rank() == na)
    checks.append(Check("(p.6) the x_a columns of Ts span V*", ok, None if ok else f"dim V* = {V.cols}, n_a = {na}"))
    red = _reduce(sys)
    ok = red.dims.n_c == 0 and _hstack([red.S, Ts.take_cols(range(na + nb, n))], n).rank() == red.S.cols == nd
    checks.append(Check("(p.7) R* = V* ∩ S* = {0} and the x_d columns of Ts span S*", ok,
                        None if ok else f"dim R* = {red.dims.n_c}, dim S* = {red.S.cols}, n_d = {nd}"))
    return Certificate("special coordinate basis", checks)
