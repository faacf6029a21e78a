"""The steps of the special coordinate basis (see :mod:`uio_ring.analysis.scb` for the algorithm).

Private to the SCB: exact linear algebra over Q on :class:`~uio_ring.ring.QMatrix`.
Step 1 the feed-through split, steps 2–3 the subspaces ``V*``, ``S*`` and the input chains,
steps 4–5 the rows of ``Ts⁻¹``, then Theorem 1's re-transformation of the d part.

>>> from uio_ring.ring.qmatrix import QMatrix
>>> [ch.closed_at for ch in input_chains(QMatrix([[0, 1], [0, 0]]), QMatrix([[0], [1]]), QMatrix([[1, 0]]))]
[2]
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from uio_ring.analysis.canonical_form import canonical_form
from uio_ring.analysis.chain_basis import chain_basis
from uio_ring.analysis.chain_couplings import chain_transformation, coupling_coefficients
from uio_ring.analysis.strong_observability import constant_matrices, weakly_unobservable_subspace
from uio_ring.errors import NotObservableError
from uio_ring.ring.errors import DimensionError, UioRingError
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.systems.delay_system import DelaySystem

Q = QMatrix


class NotLeftInvertibleError(NotObservableError):
    """The system is not left invertible (``n_c > 0``): some state is masked by the unknown input for every s."""


# -- small exact helpers -------------------------------------------------------------------------


def hstack(blocks: Sequence[QMatrix], rows: int) -> QMatrix:
    return Q.hstack(*blocks, rows=rows)


def vstack(blocks: Sequence[QMatrix], cols: int) -> QMatrix:
    return Q.vstack(*blocks, cols=cols)


def left_solve(M: QMatrix, Y: QMatrix, what: str) -> QMatrix:
    """``X`` with ``X M = Y`` (one solution, row by row); ``UioRingError`` naming ``what`` if none."""
    rows = []
    for i in range(Y.rows):
        x = M.min_norm_left_solve(Y.row(i))
        if x is None:  # pragma: no cover - excluded by the geometry; a guard for the certificate
            raise UioRingError(f"special coordinate basis: {what} has no solution (please report this system)")
        rows.append(x)
    return vstack(rows, M.rows)


def _column_space(M: QMatrix) -> QMatrix:
    """A basis of the column space of ``M`` (its independent columns, greedily)."""
    return M.take_cols(M.T.row_basis())


def _sum(U: QMatrix, V: QMatrix) -> QMatrix:
    return _column_space(hstack([U, V], U.rows))


def intersection(U: QMatrix, V: QMatrix) -> QMatrix:
    """A basis of ``span U ∩ span V`` (U, V with independent columns)."""
    n = U.rows
    if U.cols == 0 or V.cols == 0:
        return Q.zeros(n, 0)
    K = hstack([U, -V], n).nullspace()
    return _column_space(U @ K.take_rows(range(U.cols))) if K.cols else Q.zeros(n, 0)


def _compress(G: QMatrix) -> tuple[QMatrix, int]:
    """Invertible ``T`` with ``G T = [G_1, 0]``, ``G_1`` of full column rank ``r``; returns ``(T, r)``."""
    k = G.cols
    piv = G.rref().pivots
    N = G.nullspace()
    E = hstack([_unit_col(k, j) for j in piv], k)
    return hstack([E, N], k), len(piv)


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
    To0 = hstack([D1, *comp], p)
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
        cand = hstack([basis, _unit_col(p, i)], p)
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
        Sn = _sum(_column_space(B), A @ intersection(S, kerC)) if S.cols else _column_space(B)
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


def input_chains(A: QMatrix, B: QMatrix, C: QMatrix) -> list[_Chain]:
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
        S = hstack([C @ ch.cols[-1] for ch in closed], p)
        G = hstack([C @ ch.cols[-1] for ch in open_], p)
        M = hstack([S, G], p)
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


@dataclass(frozen=True)
class _ObservableChains:
    rows: QMatrix  # Φ_b (n_b×n)
    l: tuple[int, ...]
    y_rows: QMatrix  # hb (p_b×p1): hb C1 = the chain-start rows of Φ_b
    A_b: QMatrix  # Φ_b A = A_b Φ_b + H C1


def observable_chains(A: QMatrix, C: QMatrix, annihilated: QMatrix) -> _ObservableChains:
    """Rows of ``x_b`` (step 4): the functionals vanishing on ``V* + S*`` in Brunovsky observer form."""
    n, p = A.rows, C.rows
    P = annihilated.T.nullspace().T if annihilated.cols else Q.identity(n)
    nb = P.rows
    if nb == 0:
        return _ObservableChains(Q.zeros(0, n), (), Q.zeros(0, p), Q.zeros(0, 0))
    MH = left_solve(vstack([P, C], n), P @ A, "P A = M P + H C")
    M = MH.take_cols(range(nb))
    K = vstack([C, P], n).left_nullspace()  # [h, g]: h C + g P = 0
    h, g = K.take_cols(range(p)), K.take_cols(range(p, p + nb))
    cf = canonical_form(M.to_polymatrix(), (-g).to_polymatrix())
    Gx, Gy = Q(cf.Gamma_x), Q(cf.Gamma_y)
    rows = Gx.inverse(name="Γ_x") @ P
    return _ObservableChains(rows, cf.q, Gy.inverse(name="Γ_y") @ h, Q(cf.A_bar))


def chain_rows(A: QMatrix, C: QMatrix, T_d: QMatrix, q: Sequence[int], starts: Sequence[int]) -> tuple[QMatrix, QMatrix]:
    """Rows of ``x_d`` (step 5) and the ``y_d`` output rows ``kd``: ``φ_1 = kd_i C``,
    ``φ_{k+1} = φ_k A − Σ_j (φ_k A t_{j,1}) kd_j C``, so that ``Φ_d T_d = I``."""
    n = A.rows
    Ts_starts = T_d.take_cols(starts)
    kd = left_solve(C @ Ts_starts, Q.identity(len(starts)), "kd C T_d,starts = I")
    Y = kd @ C
    rows = []
    for i, qi in enumerate(q):
        phi = Y.row(i)
        rows.append(phi)
        for _ in range(qi - 1):
            nxt = phi @ A
            phi = nxt - (nxt @ Ts_starts) @ Y
            rows.append(phi)
    return (vstack(rows, n) if rows else Q.zeros(0, n)), kd


def zero_dynamics_rows(A: QMatrix, C: QMatrix, T_a: QMatrix, T_d: QMatrix, obs: _ObservableChains,
                        A_a: QMatrix) -> QMatrix:
    """Rows of ``x_a`` (step 5): a lift ``Φ⁰`` of the dual basis of ``V*`` inside ``(S*)^⊥``,
    corrected to ``Φ_a = Φ⁰ + Z Φ_b`` so that ``Φ_a A − A_a Φ_a`` lies in ``row C``:
    along each b chain, ``Z_{k−1} = A_a Z_k − R_k`` from ``Z_l = 0`` (``R``: the ``Φ_b`` part of ``Φ⁰ A``)."""
    n = A.rows
    na = T_a.cols
    Psi = T_d.T.nullspace().T if T_d.cols else Q.identity(n)
    phi0 = left_solve(Psi @ T_a, Q.identity(na), "lift of V*'s dual basis") @ Psi
    nb = obs.rows.rows
    if nb == 0:
        return phi0
    X = left_solve(vstack([phi0, obs.rows, C], n), phi0 @ A, "Φ⁰ A = A_a Φ⁰ + R Φ_b + H C")
    R = X.take_cols(range(na, na + nb))
    cols = [Q.zeros(na, 1) for _ in range(nb)]
    s = 0
    for li in obs.l:
        for k in range(li - 1, 0, -1):  # 0-based positions li−1 … 1
            cols[s + k - 1] = A_a @ cols[s + k] - R.col(s + k)
        s += li
    return phi0 + hstack(cols, na) @ obs.rows


def theorem1_transformation(Ts: QMatrix, A: QMatrix, q: Sequence[int], offset: int) -> QMatrix:
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
    starts = chain_starts(q)
    C_d = selector(q, at_end=False)
    H_dd = (A_d - shift_matrix(q)).take_cols(starts)
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


def chain_starts(lengths: Sequence[int], offset: int = 0) -> list[int]:
    out, s = [], offset
    for q in lengths:
        out.append(s)
        s += q
    return out


def chain_ends(lengths: Sequence[int], offset: int = 0) -> list[int]:
    return [s + q - 1 for s, q in zip(chain_starts(lengths, offset), lengths, strict=True)]


def shift_matrix(lengths: Sequence[int]) -> QMatrix:
    """``blkdiag(J_{q_1}, …)``: ones above the diagonal inside each chain."""
    n = sum(lengths)
    rows = [[0] * n for _ in range(n)]
    for s, q in zip(chain_starts(lengths), lengths, strict=True):
        for k in range(q - 1):
            rows[s + k][s + k + 1] = 1
    return Q(rows, shape=(n, n))


def selector(lengths: Sequence[int], at_end: bool) -> QMatrix:
    """``C_q = blkdiag([1, 0, …])`` (rows) or ``B_q = blkdiag([0; …; 1])`` (columns, ``at_end``)."""
    n = sum(lengths)
    idx = chain_ends(lengths) if at_end else chain_starts(lengths)
    rows = [[1 if j == i else 0 for j in range(n)] for i in idx]
    M = Q(rows, shape=(len(idx), n))
    return M.T if at_end else M


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


def reduce_system(sys: DelaySystem) -> _Reduced:
    """Checks, step 1 and the subspaces ``V*``, ``S*``, ``R* = V* ∩ S*``."""
    M = constant_matrices(sys)
    A, B, C, D = M["A"], M["B"], M["C"], M["D"]
    n, m, p = sys.n_x, sys.n_w, sys.n_y
    if m and vstack([B, D], m).rank() < m:
        raise DimensionError(f"the unknown-input columns are dependent (rank [B; D] = {vstack([B, D], m).rank()} < "
                             f"n_w = {m}): the SCB needs independent columns (combine the dependent inputs)")
    if p and hstack([C, D], p).rank() < p:
        raise DimensionError(f"the outputs are dependent (rank [C, D] = {hstack([C, D], p).rank()} < n_y = {p}): "
                             "the SCB needs independent outputs (remove the redundant ones)")
    ft = _feed_through(A, B, C, D)
    reduced = DelaySystem(ft.A_star.to_polymatrix(), ft.B1.to_polymatrix(), ft.C1.to_polymatrix(), None)
    V = weakly_unobservable_subspace(reduced) if n else Q.zeros(0, 0)
    S = _strongly_reachable(ft.A_star, ft.B1, ft.C1) if ft.B1.cols else Q.zeros(n, 0)
    R = intersection(V, S)
    VS = _sum(V, S) if V.cols + S.cols else Q.zeros(n, 0)
    dims = SCBDimensions(n_a=V.cols - R.cols, n_b=n - VS.cols, n_c=R.cols, n_d=S.cols - R.cols, m_0=ft.m0)
    return _Reduced(ft, A, B, C, D, V, S, dims)


# -- the whole basis of a strictly proper system ------------------------------------------------------


@dataclass(frozen=True)
class CoreSCB:
    """The basis of a strictly proper ``(A, B, C)``: ``Ts`` (order a, b, c, d), ``Ti`` (order d, c),
    ``To`` (order y_d, y_b) and the sizes."""

    Ts: QMatrix
    Ti: QMatrix
    To: QMatrix
    n_a: int
    n_c: int
    q: tuple[int, ...]
    l: tuple[int, ...]

    @property
    def n_b(self) -> int:
        return sum(self.l)


def left_invertible_scb(A: QMatrix, B: QMatrix, C: QMatrix, V: QMatrix) -> CoreSCB:
    """Steps 3–5 and Theorem 1 for a left-invertible strictly proper system (``V = V*``)."""
    n = A.rows
    chains = input_chains(A, B, C) if B.cols else []
    q = tuple(ch.closed_at for ch in chains)
    T_d = hstack([c for ch in chains for c in reversed(ch.cols)], n) if chains else Q.zeros(n, 0)
    Ti = hstack([ch.coef for ch in chains], B.cols) if chains else Q.zeros(0, 0)
    obs = observable_chains(A, C, hstack([V, T_d], n))
    Phi_d, kd = chain_rows(A, C, T_d, q, chain_starts(q))
    na = V.cols
    if na:
        A_a = left_solve(hstack([V, B], n).T, (A @ V).T, "A T_a = T_a A_a + B G").T.take_rows(range(na))
        Phi_a = zero_dynamics_rows(A, C, V, T_d, obs, A_a)
    else:
        Phi_a = Q.zeros(0, n)
    Ts = vstack([Phi_a, obs.rows, Phi_d], n).inverse(name="Ts⁻¹")
    Ts = Ts @ theorem1_transformation(Ts, A, q, na + obs.rows.rows)
    p = C.rows
    To = vstack([kd, obs.y_rows], p).inverse(name="To⁻¹") if p else Q.zeros(0, 0)
    return CoreSCB(Ts, Ti, To, na, 0, q, tuple(obs.l))


def _kron(X: QMatrix, Y: QMatrix) -> QMatrix:
    a, b = X.tolist(), Y.tolist()
    return Q([[a[i][j] * b[k][l] for j in range(X.cols) for l in range(Y.cols)]
              for i in range(X.rows) for k in range(Y.rows)], shape=(X.rows * Y.rows, X.cols * Y.cols))


def _vec(M: QMatrix) -> QMatrix:
    """Columns stacked (column-major)."""
    return vstack([M.col(j) for j in range(M.cols)], 1) if M.cols else Q.zeros(0, 1)


def controllable_part_scb(A: QMatrix, B: QMatrix, C: QMatrix, R: QMatrix) -> CoreSCB:
    """The basis of a system that is not left invertible (``R = R*`` ≠ 0, the columns of ``x_c``).

    ``R*`` is a controllability subspace in ``ker C``: with a friend ``K``
    (``(A + B K) R* ⊆ R*``) the quotient by ``R*``, driven by the inputs that do not point
    into ``R*``, is left invertible; its basis (:func:`left_invertible_scb`) is lifted by
    adding ``R*`` components ``R z`` to its columns, chosen so that ``x_c'`` sees the
    other parts only as (17a) allows: along every chain ``z_{k−1}`` solves
    ``A t_k − t_{k−1} ∈ span B_d`` (the d-chain ends are the input directions exactly), and
    the ``x_a`` columns solve ``A_r Z − Z A_a + B_c W = −ρ`` (``(A_r, B_c)`` is controllable).
    """
    n, m = B.shape
    nc = R.cols
    comp = [_unit_col(n, i) for i in _complement_rows(R)]
    Qm = hstack(comp, n)
    inv = hstack([Qm, R], n).inverse(name="[Q, R*]")
    Pq, Pr = inv.take_rows(range(n - nc)), inv.take_rows(range(n - nc, n))
    Uc = (Pq @ B).nullspace()  # inputs pointing into R*
    Tid0 = hstack([_unit_col(m, i) for i in _complement_rows(Uc)], m) if Uc.cols < m else Q.zeros(m, 0)
    if nc == n:  # the whole state is x_c (then C = 0 and every input points into R*)
        return CoreSCB(R, hstack([Tid0, Uc], m), Q.identity(C.rows), 0, nc, (), ())
    X = left_solve(hstack([R, B], n).T, (A @ R).T, "A R* = R* A_r + B G").T
    A_r, G = X.take_rows(range(nc)), X.take_rows(range(nc, nc + m))
    K = -(G @ (R.T @ R).inverse(name="Rᵀ R") @ R.T)
    AK = A + B @ K
    A_q, B_q, C_q = Pq @ AK @ Qm, Pq @ B @ Tid0, C @ Qm
    quotient = DelaySystem(A_q.to_polymatrix(), B_q.to_polymatrix(), C_q.to_polymatrix(), None)
    Vq = weakly_unobservable_subspace(quotient) if n - nc else Q.zeros(0, 0)
    core = left_invertible_scb(A_q, B_q, C_q, Vq)
    S = core.Ts
    Ti_d = Tid0 @ core.Ti
    BTd = B @ Ti_d
    basis = hstack([BTd, R], n)

    def r_part(v: QMatrix) -> QMatrix:
        """ρ with v = B Ti_d γ + R ρ."""
        sol = left_solve(basis.T, v.T, "a column of the lifted basis").T
        return sol.take_rows(range(BTd.cols, BTd.cols + nc))

    cols: dict[int, QMatrix] = {}
    na, nb = core.n_a, core.n_b
    for offset, lengths, is_d in ((na, core.l, False), (na + nb, core.q, True)):
        for i, (s0, L) in enumerate(zip(chain_starts(lengths, offset), lengths, strict=True)):
            end = s0 + L - 1
            cols[end] = BTd.col(i) if is_d else Qm @ S.col(end)
            for k in range(end, s0, -1):
                cols[k - 1] = Qm @ S.col(k - 1) + R @ r_part(A @ cols[k] - Qm @ S.col(k - 1))
    if na:
        S_a = S.take_cols(range(na))
        A_a = (S.inverse(name="Ts of the quotient") @ A_q @ S).take_rows(range(na)).take_cols(range(na))
        rho = hstack([r_part(A @ Qm @ S_a.col(j) - Qm @ (S_a @ A_a).col(j)) for j in range(na)], nc)
        bc = Pr @ B @ Uc
        M = hstack([_kron(Q.identity(na), A_r) - _kron(A_a.T, Q.identity(nc)), _kron(Q.identity(na), bc)],
                   nc * na)
        zw = left_solve(M.T, (-_vec(rho)).T, "A_r Z − Z A_a + B_c W = −ρ").T
        Z = hstack([zw.take_rows(range(j * nc, (j + 1) * nc)) for j in range(na)], nc)
        for j in range(na):
            cols[j] = Qm @ S_a.col(j) + R @ Z.col(j)
    order = [cols[j] for j in range(na + nb)] + [R.col(j) for j in range(nc)] + \
        [cols[j] for j in range(na + nb, n - nc)]
    Ts = hstack(order, n)
    # the friend K puts B_d-terms into every column of the d chain ends: Theorem 1 once more, on the whole
    # basis (it keeps C_d and B_d, so the patterns of the other parts stay)
    Ts = Ts @ theorem1_transformation(Ts, A, core.q, na + nb + nc)
    Ti = hstack([Ti_d, Uc], m)
    return CoreSCB(Ts, Ti, core.To, na, nc, core.q, core.l)
