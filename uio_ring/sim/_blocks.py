"""Block integrator of ``x' = A_0 x + Σ_{i≥1} A_i x(t − i h) + f_in(t)`` on the grid ``dt = h/N``.

Over one block ``[k h, (k+1) h]`` every delayed value is already known, so the
block is the linear recursion ``x_{r+1} = Φ x_r + g_r`` with a known forcing
(see :mod:`uio_ring.numeric.expint`).  The forcing is interpolated with four-point
Lagrange stencils that stay inside the block (nodes ``r−1 … r+2``, shifted at the
block ends), so the derivative jumps at the multiples of ``h`` — all on the grid —
never sit inside a stencil and the global order is 4 (``min(4, N+1)`` points when
N < 3, with a correspondingly lower order).

Two evaluations of the same map:

* *sub* (default): the block is cut into sub-blocks of m | N steps (m ≤ 32); each is
  one matrix applied to the delayed samples it reads, plus ``Φ^{r+1}`` times its start
  value, plus the input part (precomputed for all blocks at once) — a few ``matvec``
  per sub-block, O(m n²) flops per step;
* *super* (N ≤ 16): groups of ``B = 32 // N`` blocks are one matrix applied to the
  window before the group (the group's own delayed values are composed in), plus the
  input part — one ``matvec`` per 32 steps;
* *dense*: the whole block is one matrix ``M`` applied to the window
  ``x[(k−K)N … kN]`` (K = deg A) — one ``matvec`` per block, O(N n²) per step;
* *chunked* (large N): per block, delayed forcing, quadrature, and a
  :class:`~uio_ring.numeric.expint.LinearScan`.

Batches of S trajectories of one plant also run time-major (:meth:`BlockIntegrator.run_rows`,
arrays ``(steps, S, n)``): per block the forcing on its points and its quadrature (one
product per delay and stencil node over all points and trajectories), then one
``(S, n) @ (n, n)`` product per step — O(n²) per step and trajectory instead of the
O(m n²) of the sub-block maps, with S rows to carry each product's overhead.
"""

from __future__ import annotations

import threading

import numpy as np

from uio_ring.numeric.expint import LinearScan, phi_functions, stencil_weights
from uio_ring.numeric.progress import Updater

__all__ = ["BlockIntegrator", "block_integrator", "block_stencils", "scan_rows", "tap_rows", "taps"]

DENSE_MAX_ENTRIES = 6_000_000
SUB_MAX = 32  # largest sub-block (steps)
SUB_MIN = 8  # below this divisor of N, sub-blocks cost more Python than they save
SUPER_MAX_N = 16  # up to this N, groups of blocks are advanced at once
SUPER_STEPS = 32  # steps per group


def sub_block_size(N: int) -> int:
    """Largest divisor of N that is ≤ SUB_MAX (N itself when N ≤ SUB_MAX).

    >>> sub_block_size(100), sub_block_size(1000), sub_block_size(10), sub_block_size(97)
    (25, 25, 10, 1)
    """
    return max(d for d in range(1, min(N, SUB_MAX) + 1) if N % d == 0)


def block_stencils(N: int) -> np.ndarray:
    """Stencil indices ``idx[r, m]`` (points of the block, 0…N) used for the step r → r+1.

    >>> block_stencils(5)
    array([[0, 1, 2, 3],
           [0, 1, 2, 3],
           [1, 2, 3, 4],
           [2, 3, 4, 5],
           [2, 3, 4, 5]])
    """
    npts = min(4, N + 1)
    s = np.clip(np.arange(N) - 1, 0, N + 1 - npts)
    return s[:, None] + np.arange(npts)[None, :]


def stencil_weight_table(A0: np.ndarray, dt: float, idx: np.ndarray) -> np.ndarray:
    """``W[r, m]``: weight of the stencil point ``idx[r, m]`` in step r (shape ``(R, npts, n, n)``)."""
    R, npts = idx.shape
    phis = phi_functions(A0 * dt, npts)
    nodes = idx - np.arange(R)[:, None]
    table: dict[tuple[int, ...], np.ndarray] = {}
    W = np.empty((R, npts) + A0.shape)
    for r in range(R):
        key = tuple(int(q) for q in nodes[r])
        if key not in table:
            table[key] = stencil_weights(A0 * dt, dt, key, phis)
        W[r] = table[key]
    return W


def toeplitz_powers(Phi: np.ndarray, N: int) -> tuple[np.ndarray, np.ndarray]:
    """``(P, T)``: ``P[r] = Φ^{r+1}`` and the ``(N n, N n)`` block matrix ``T[r, s] = Φ^{r−s}`` (s ≤ r)."""
    n = Phi.shape[0]
    pows = np.empty((N + 1, n, n))
    pows[0] = np.eye(n)
    for r in range(N):
        pows[r + 1] = Phi @ pows[r]
    rr, ss = np.meshgrid(np.arange(N), np.arange(N), indexing="ij")
    D = rr - ss
    T = np.where((D >= 0)[:, :, None, None], pows[np.clip(D, 0, N)], 0.0)  # (N, N, n, n)
    T = T.transpose(0, 2, 1, 3).reshape(N * n, N * n)
    return pows[1:], T


def taps(wins: list[np.ndarray], mats: list[np.ndarray]) -> np.ndarray:
    """``Σ_i wins[i] @ mats[i]`` over the rows of time-major windows ``(L, K, c)``: ``(L K, r)``.

    One product per window, accumulated in place: the windows are views (no copy), and
    products with a handful of columns cost less one by one than one product of the
    windows laid side by side (measured: 3× on paper 001, K = 100).

    >>> w = np.arange(6.0).reshape(3, 1, 2)
    >>> taps([w[:2], w[1:]], [np.eye(2), 2 * np.eye(2)]).tolist()
    [[4.0, 7.0], [10.0, 13.0]]
    """
    L, K = wins[0].shape[:2]
    out = wins[0].reshape(L * K, -1) @ mats[0]
    for w, m in zip(wins[1:], mats[1:], strict=True):
        out += w.reshape(L * K, -1) @ m
    return out


def tap_rows(S: np.ndarray, starts: list[int], mats: list[np.ndarray], L: int, kernel: str = "python") -> np.ndarray:
    """:func:`taps` of the windows ``S[s : s + L]`` (``s`` in ``starts``): ``(L, K, r)``; with
    ``kernel="numba"`` one compiled pass (:func:`uio_ring.numeric.linear_kernel.tap_sum`).

    >>> w = np.arange(6.0).reshape(3, 1, 2)
    >>> tap_rows(w, [0, 1], [np.eye(2), 2 * np.eye(2)], 2)[:, 0].tolist()
    [[4.0, 7.0], [10.0, 13.0]]
    """
    K = S.shape[1]
    if kernel != "numba":
        return taps([S[s : s + L] for s in starts], mats).reshape(L, K, mats[0].shape[1])
    from uio_ring.numeric.linear_kernel import tap_sum

    out = np.empty((L, K, mats[0].shape[1]))
    return tap_sum(np.ascontiguousarray(S), np.array(starts, dtype=np.int64), np.ascontiguousarray(np.stack(mats)), out)


def scan_rows(PhiT: np.ndarray, x0: np.ndarray, G: np.ndarray, kernel: str = "python") -> np.ndarray:
    """``x_{j+1} = Φ x_j + g_j`` in place: ``G`` ``(M, K, n)`` (time-major, K columns per step)
    becomes ``x_1 … x_M``; ``PhiT = Φᵀ``, ``x0`` ``(K, n)``.  One product per step carries the
    K columns (for K ≳ 8 cheaper than a chunked scan, whose products grow with the chunk).

    >>> G = np.zeros((3, 1, 1)); scan_rows(np.array([[0.5]]), np.array([[1.0]]), G)[:, 0, 0].tolist()
    [0.5, 0.25, 0.125]
    """
    if G.shape[0] == 0:
        return G
    if kernel == "numba":  # one compiled loop (uio_ring.numeric.linear_kernel)
        from uio_ring.numeric import linear_kernel

        return linear_kernel.scan_rows(PhiT, x0, G)
    rows = list(G)  # the row views once; np.dot with out: the least overhead per step (measured)
    dot, add, tmp = np.dot, np.add, np.empty(G.shape[1:])
    prev = rows[0]
    prev += x0 @ PhiT
    for r in rows[1:]:
        dot(prev, PhiT, out=tmp)
        add(r, tmp, out=r)
        prev = r
    return G


def _mm_shared(X: np.ndarray, M: np.ndarray) -> np.ndarray:
    """``X @ M`` for ``X`` ``(…, d)`` and one ``M`` ``(d, e)``: one 2-D product."""
    if X.ndim == 2:
        return X @ M
    return (X.reshape(-1, X.shape[-1]) @ M).reshape(X.shape[:-1] + (M.shape[-1],))


def _mm_stacked(X: np.ndarray, M: np.ndarray) -> np.ndarray:
    """``X[s] @ M[s]`` for every trajectory s: ``X`` ``(S, d)`` or ``(S, r, d)``, ``M`` ``(S, d, e)``."""
    if X.ndim == 2:
        return np.matmul(X[:, None, :], M)[:, 0]
    return np.matmul(X, M)


_CACHE: dict[tuple, BlockIntegrator] = {}
_CACHE_SIZE = 8
_CACHE_LOCK = threading.Lock()


def block_integrator(A: np.ndarray, N: int, dt: float) -> BlockIntegrator:
    """A :class:`BlockIntegrator`, reused when ``A``, N and dt repeat (parameter sweeps); for
    ``A`` of shape ``(S, K+1, n, n)`` (one plant per trajectory), a :class:`StackedBlockIntegrator`."""
    key = (A.shape, A.tobytes(), N, float(dt))
    integ = _CACHE.get(key)
    if integ is None:
        integ = StackedBlockIntegrator(A, N, dt) if A.ndim == 4 else BlockIntegrator(A, N, dt)
        with _CACHE_LOCK:  # chunks of a batch on threads
            if len(_CACHE) >= _CACHE_SIZE:
                _CACHE.pop(next(iter(_CACHE)))
            _CACHE[key] = integ
    return integ


class BlockIntegrator:
    """Precomputed block map for given ``A`` (coefficients ``(K+1, n, n)``), N and dt."""

    def __init__(self, A: np.ndarray, N: int, dt: float, *, method: str = "auto"):
        n = A.shape[1]
        self.n, self.N, self.dt = n, N, dt
        self.K = max(A.shape[0] - 1, 0)
        self.A = A
        A0 = A[0] if A.shape[0] else np.zeros((n, n))
        self.idx = block_stencils(N)
        npts = self.idx.shape[1]
        self.W = stencil_weight_table(A0, dt, self.idx)  # (N, npts, n, n)
        self.WT = self.W.transpose(0, 1, 3, 2).reshape(N, npts * n, n)  # row-vector form
        self.Phi = phi_functions(A0 * dt, 0)[0]
        K = self.K
        dense_size = (N * n) ** 2 + (N * n) * (K * N + 1) * n
        m = sub_block_size(N)
        if method == "auto":
            if N <= SUPER_MAX_N:
                method = "super"
            elif m >= SUB_MIN or N <= SUB_MAX:
                method = "sub"
            else:
                method = "dense" if dense_size <= DENSE_MAX_ENTRIES else "chunked"
        self.method = method
        if method == "sub":
            self._init_sub(A, m, npts)
        elif method in ("dense", "super"):
            P, T = toeplitz_powers(self.Phi, N)
            Qd = np.zeros((N, n, K * N + 1, n))
            rows = np.arange(N)
            for i in range(1, K + 1):
                for m in range(npts):
                    cols = (K - i) * N + self.idx[:, m]
                    Qd[rows, :, cols, :] += self.W[:, m] @ A[i]
            M = T @ Qd.reshape(N * n, (K * N + 1) * n)
            M[:, K * N * n :] += P.reshape(N * n, n)
            self.MT = M.T.copy()  # window_row @ MT
            # input forcing on the N+1 block points -> particular solution from zero
            Qin = np.zeros((N, n, N + 1, n))
            for m in range(npts):
                Qin[rows, :, self.idx[:, m], :] += self.W[:, m]
            self.QinT = (T @ Qin.reshape(N * n, (N + 1) * n)).T.copy()
            if method == "super":
                self._init_super()
        elif method == "chunked":
            self.scan = LinearScan(self.Phi, chunk=min(32, max(N, 1)))
        elif method != "weights":  # "weights": the stencil weights and Φ only (StackedBlockIntegrator)
            raise ValueError(f"method={method!r}: expected auto, sub, super, dense, chunked or weights")

    def _init_sub(self, A: np.ndarray, m: int, npts: int) -> None:
        """Sub-blocks of m steps (m | N): per sub-block one map from the delayed samples it
        reads and its start value; O(m) work per step instead of O(N)."""
        N, n, K = self.N, self.n, self.K
        self.m, self.S = m, N // m
        P, T = toeplitz_powers(self.Phi, m)
        self.TmT = T.T.copy()
        self.PT = P.reshape(m * n, n).T.copy()  # x_start @ PT
        self.sub: list[tuple[int, int, np.ndarray]] = []
        rows = np.arange(m)
        for c in range(self.S):
            idx_c = self.idx[c * m : (c + 1) * m]
            lo, hi = int(idx_c.min()), int(idx_c.max())
            width = hi - lo + 1
            Qd = np.zeros((m, n, max(K, 1), width, n))
            for i in range(1, K + 1):
                for q in range(npts):
                    Qd[rows, :, i - 1, idx_c[:, q] - lo, :] += self.W[c * m : (c + 1) * m, q] @ A[i]
            Md = T @ Qd.reshape(m * n, max(K, 1) * width * n)
            self.sub.append((lo, width, Md.T.copy()))

    def _init_super(self) -> None:
        """Groups of B blocks (small N): the map from the window before the group and the
        input forcing of its B blocks to its B·N new samples, by composing block maps."""
        N, n, K = self.N, self.n, self.K
        B = max(1, SUPER_STEPS // N)
        L = K * N + 1
        dw, df = L * n, (N + 1) * n
        D = dw + B * df
        samples = [np.eye(n, D, k=j * n) for j in range(L)]  # coefficient rows of each sample
        M1, Q1 = self.MT.T, self.QinT.T
        for b in range(B):
            win = np.concatenate(samples[len(samples) - L :], axis=0)  # (L n, D)
            sel = np.zeros((df, D))
            sel[:, dw + b * df : dw + (b + 1) * df] = np.eye(df)
            Xb = M1 @ win + Q1 @ sel  # (N n, D)
            samples.extend(Xb[r * n : (r + 1) * n] for r in range(N))
        out = np.concatenate(samples[L:], axis=0)  # (B N n, D)
        self.B = B
        self.SwT = out[:, :dw].T.copy()
        self.SfT = out[:, dw:].T.copy()

    @property
    def row_groups(self) -> list[tuple[int, int, list[int], list[np.ndarray]]]:
        """Consecutive steps ``r0 … r1 − 1`` of a block with the same stencil nodes (relative to r):
        ``(r0, r1, nodes, [W_qᵀ])`` — first step, last step + 1, the nodes and the weights."""
        if not hasattr(self, "_row_groups"):
            nodes = self.idx - np.arange(self.N)[:, None]
            groups: list[tuple[int, int, list[int], list[np.ndarray]]] = []
            r0 = 0
            for r in range(1, self.N + 1):
                if r == self.N or not np.array_equal(nodes[r], nodes[r0]):
                    groups.append((r0, r, [int(q) for q in nodes[r0]], [w.T.copy() for w in self.W[r0]]))
                    r0 = r
            self._row_groups = groups
        return self._row_groups

    def run_rows(self, X: np.ndarray, fin: np.ndarray, nblocks: int, end_fix: np.ndarray | None = None,
                 kernel: str = "python") -> None:
        """:meth:`run` for S trajectories of this plant, time-major: ``X`` ``(K N + nblocks N + 1, S, n)``,
        ``fin`` ``(nblocks N + 1, S, n)``, ``end_fix`` ``(S, nblocks, n)``; filled in place.

        Per block: the forcing on its N + 1 points (input plus delayed states, one product per
        delay), its quadrature (one product per stencil node and group of steps with the same
        nodes), then the N steps ``x_{r+1} = Φ x_r + g_r`` (:func:`scan_rows`): O(n²) per step
        and trajectory, against O(m n²) for the sub-block maps of :meth:`run`.  ``kernel="numba"``:
        the products and steps by the compiled loops (:mod:`uio_ring.numeric.linear_kernel`).
        """
        N, K = self.N, self.K
        S_, n = X.shape[1], self.n
        AT = [self.A[i].T.copy() for i in range(1, K + 1)]
        PhiT = self.Phi.T.copy()
        groups = self.row_groups
        KN = K * N
        for k in range(nblocks):
            a = k * N
            F = fin[a : a + N + 1].copy()  # f on the block's points
            if end_fix is not None:
                F[N] += end_fix[:, k]
            if kernel == "numba" and AT:
                F += tap_rows(X, [a + (K - i) * N for i in range(1, K + 1)], AT, N + 1, kernel)
            else:
                F2 = F.reshape((N + 1) * S_, n)
                for i, Ai in enumerate(AT, start=1):
                    F2 += X[a + (K - i) * N : a + (K - i) * N + N + 1].reshape((N + 1) * S_, n) @ Ai
            G = np.empty((N, S_, n))
            for r0, r1, nodes, WT in groups:
                G[r0:r1] = tap_rows(F, [r0 + q for q in nodes], WT, r1 - r0, kernel)
            X[a + KN + 1 : a + KN + N + 1] = scan_rows(PhiT, X[a + KN], G, kernel)

    def step_block(self, window: np.ndarray, forcing: np.ndarray) -> np.ndarray:
        """One block from its window ``x((k−K) h) … x(k h)`` (``(K N + 1, n)``) and the input
        forcing on its ``N + 1`` points (``(N + 1, n)``; a held input: the same value at both
        ends): the ``N`` new samples, shape ``(N, n)``.  Needs the ``"dense"`` method."""
        return (window.reshape(-1) @ self.MT + forcing.reshape(-1) @ self.QinT).reshape(self.N, self.n)

    def quadrature(self, F: np.ndarray) -> np.ndarray:
        """Forcing samples on blocks ``(B, N+1, n)`` → step forcings ``(B, N, n)``."""
        B = F.shape[0]
        Fg = F[:, self.idx, :].reshape(B, self.N, -1)  # (B, N, npts n)
        G = np.matmul(Fg.transpose(1, 0, 2), self.WT)  # (N, B, n)
        return G.transpose(1, 0, 2)

    #: ``X @ M`` for the block maps: one matrix for every trajectory (rows on the leading axes).
    _mm = staticmethod(_mm_shared)

    def _quadrature_batch(self, Fin: np.ndarray) -> np.ndarray:
        """:meth:`quadrature` of ``(S, B, N+1, n)`` forcing samples → ``(S, B, N, n)``."""
        S_, B = Fin.shape[:2]
        return self.quadrature(Fin.reshape(S_ * B, self.N + 1, self.n)).reshape(S_, B, self.N, self.n)

    def run(
        self, X: np.ndarray, fin: np.ndarray, nblocks: int, progress: Updater, end_fix: np.ndarray | None = None
    ) -> None:
        """Fill ``X[K N + 1 + k N …]`` block by block, in place.

        ``X`` has shape ``(K N + nblocks N + 1, n)`` with the history ``x(−K h) … x(0)``
        in its first ``K N + 1`` rows; ``fin`` (shape ``(nblocks N + 1, n)``) is the input
        forcing ``B(δ) w + E(δ) u`` on the grid of ``[0, nblocks h]``.  ``end_fix`` (shape
        ``(nblocks, n)``) is added to the forcing at the right end of each block: the left
        limit there, when an input jumps at a multiple of h.

        A batch of trajectories of the same plant: a leading axis on ``X``, ``fin`` and
        ``end_fix`` (``(S, …)``); every block product then has S rows.
        """
        N, n, K = self.N, self.n, self.K
        Xb = X if X.ndim == 3 else X[None]  # (S, rows, n): a view, filled in place
        fb = fin if fin.ndim == 3 else fin[None]
        S_ = Xb.shape[0]
        # input forcing of every block at once: f_in on the block points, quadrature
        jb = np.arange(nblocks)[:, None] * N + np.arange(N + 1)[None, :]
        Fin = fb[:, jb]  # (S, nblocks, N+1, n)
        if end_fix is not None:
            Fin[:, :, N, :] += end_fix
        step = max(1, nblocks // 100)
        mm = self._mm
        if self.method == "sub":
            m, S = self.m, self.S
            Gin = self._quadrature_batch(Fin)  # (S_, nblocks, N, n)
            XW = mm(Gin.reshape(S_, nblocks * S, m * n), self.TmT).reshape(S_, nblocks, S, m * n)
            PT, sub = self.PT, self.sub
            KN = K * N
            for k in range(nblocks):
                a = k * N
                for c, (lo, width, MdT) in enumerate(sub):
                    r0 = a + KN + c * m
                    acc = mm(Xb[:, r0], PT) + XW[:, k, c]
                    if K == 1:
                        acc += mm(Xb[:, a + lo : a + lo + width].reshape(S_, -1), MdT)
                    elif K > 1:
                        parts = [Xb[:, a + (K - i) * N + lo : a + (K - i) * N + lo + width] for i in range(1, K + 1)]
                        acc += mm(np.concatenate(parts, axis=1).reshape(S_, -1), MdT)
                    Xb[:, r0 + 1 : r0 + m + 1] = acc.reshape(S_, m, n)
                if k % step == 0:
                    progress.update(k)
        elif self.method == "super":
            B, L = self.B, K * N + 1
            ns = nblocks // B
            XS = mm(Fin[:, : ns * B].reshape(S_, ns, B * (N + 1) * n), self.SfT)
            SwT = self.SwT
            for g in range(ns):
                a = g * B * N
                Xb[:, a + L : a + L + B * N] = (mm(Xb[:, a : a + L].reshape(S_, -1), SwT) + XS[:, g]).reshape(S_, B * N, n)
                if g % max(1, ns // 100) == 0:
                    progress.update(g * B)
            MT = self.MT
            left = nblocks - ns * B
            XW = mm(Fin[:, ns * B :].reshape(S_, left, (N + 1) * n), self.QinT)
            for k in range(ns * B, nblocks):  # the blocks left over
                a = k * N
                Xb[:, a + L : a + L + N] = (mm(Xb[:, a : a + L].reshape(S_, -1), MT) + XW[:, k - ns * B]).reshape(S_, N, n)
        elif self.method == "dense":
            XW = mm(Fin.reshape(S_, nblocks, (N + 1) * n), self.QinT)  # from 0
            MT = self.MT
            L = K * N + 1
            for k in range(nblocks):
                a = k * N  # window X[a : a + K N + 1] = x((k−K) h) … x(k h)
                Xb[:, a + L : a + L + N] = (mm(Xb[:, a : a + L].reshape(S_, -1), MT) + XW[:, k]).reshape(S_, N, n)
                if k % step == 0:
                    progress.update(k)
        else:
            A = self.A
            for s_ in range(S_):  # per trajectory of a batch (this method is for large N only)
                Xs = Xb[s_]
                Gin = self.quadrature(Fin[s_])  # (nblocks, N, n)
                for k in range(nblocks):
                    a = k * N
                    win = Xs[a : a + K * N + 1]
                    fdT = np.zeros((n, N + 1))
                    for i in range(1, K + 1):
                        fdT += A[i] @ win[(K - i) * N : (K - i) * N + N + 1].T
                    G = self.quadrature(fdT.T[None])[0] + Gin[k]
                    Xs[a + K * N + 1 : a + K * N + 1 + N] = self.scan.run(Xs[a + K * N], G)
                    if k % step == 0:
                        progress.update(k)


def STACKED_METHOD(N: int) -> str:  # noqa: N802 - a policy, replaceable in tests
    """Method of a :class:`StackedBlockIntegrator` for N steps per block (measured, paper 001,
    K = 100: per-plant sub-block maps are K separate matrices that do not stay in cache)."""
    return "super" if N <= SUPER_MAX_N else "scan"


def SCAN_CHUNK(N: int) -> int:  # noqa: N802 - a policy, replaceable in tests
    """Steps per chunk of the stacked scan: the largest divisor of N that is ≤ 16."""
    return max(d for d in range(1, min(N, 16) + 1) if N % d == 0)


class StackedBlockIntegrator(BlockIntegrator):
    """S plants of the same size and delay degree, one per trajectory of a batch: the block
    maps of each (:class:`BlockIntegrator`, all with the same method) stacked on a leading
    axis, so that every block product of :meth:`run` is one batched product
    ``X[s] @ M[s]`` over the S trajectories (the loop over the blocks is shared).

    >>> from uio_ring.numeric.progress import Progress
    >>> A = np.array([[[[-1.0]], [[0.5]]], [[[-2.0]], [[0.25]]]])   # x' = a x + b x(t − 1), two plants
    >>> st = StackedBlockIntegrator(A, 4, 0.25)
    >>> X = np.zeros((2, 4 + 8 + 1, 1)); X[:, :5] = 1.0                # history x = 1 on [−1, 0]
    >>> st.run(X, np.zeros((2, 9, 1)), 2, Progress(1, False))
    >>> X1 = np.zeros((4 + 8 + 1, 1)); X1[:5] = 1.0
    >>> BlockIntegrator(A[1], 4, 0.25).run(X1, np.zeros((9, 1)), 2, Progress(1, False))
    >>> bool(np.allclose(X[1], X1, rtol=1e-14, atol=0))
    True
    """

    _mm = staticmethod(_mm_stacked)

    def __init__(self, A: np.ndarray, N: int, dt: float, *, method: str = "auto"):
        if method == "auto":
            method = STACKED_METHOD(N)
        first = BlockIntegrator(A[0], N, dt, method="weights" if method == "scan" else method)
        parts = [first] + [BlockIntegrator(A[s], N, dt, method=first.method) for s in range(1, A.shape[0])]
        self.__dict__.update(first.__dict__)
        self.parts, self.A = parts, A
        self.method = method
        for name in ("W", "WT", "Phi", "MT", "QinT", "SwT", "SfT", "PT", "TmT"):
            if hasattr(first, name):
                setattr(self, name, np.stack([getattr(p, name) for p in parts]))
        if first.method == "sub":
            self.sub = [(lo, width, np.stack([p.sub[c][2] for p in parts])) for c, (lo, width, _) in enumerate(first.sub)]
        nodes = self.idx - np.arange(N)[:, None]  # steps with the same stencil nodes share their weights
        keys = [tuple(int(q) for q in row) for row in nodes]
        self.groups = [np.array([r for r in range(N) if keys[r] == key]) for key in dict.fromkeys(keys)]
        if method == "scan":
            self._init_scan()

    def _init_scan(self) -> None:
        """The delayed forcing of a block's N steps from its window, per plant: ``g_r = Σ_{i,q}
        W[r, q] A_i x(idx[r, q] + (K − i) N)`` as one row-vector product ``x[gidx[r]] @ WA[r]``."""
        N, n, K = self.N, self.n, self.K
        npts = self.idx.shape[1]
        self.gidx: np.ndarray = np.concatenate([(K - i) * N + self.idx for i in range(1, K + 1)], axis=1) if K \
            else np.zeros((N, 0), dtype=int)
        m = SCAN_CHUNK(N)  # steps per chunk: x_{r+m} from x_r and the chunk's forcing at once
        pw = [toeplitz_powers(p.Phi, m) for p in self.parts]
        self.m_scan = m
        self.TmT = np.stack([T.T for _, T in pw])  # (S, m n, m n): the chunk's particular solution
        self.PT = np.stack([P.reshape(m * n, n).T for P, _ in pw])  # (S, n, m n): Φ^1 … Φ^m
        self.PmT = self.PT[:, :, (m - 1) * n :].copy()  # (S, n, n): Φ^m
        if K:
            W = self.W[:, [int(g[0]) for g in self.groups]]  # one weight table per group of steps
            WA = np.einsum("sgqab,sibc->sgqiac", W, self.A[:, 1:])  # W[r, q] A_i
            self.WA = WA.transpose(0, 1, 3, 2, 5, 4).reshape(len(self.parts), len(self.groups), K * npts * n, n)

    def _quadrature_batch(self, Fin: np.ndarray) -> np.ndarray:
        """Per trajectory, its own stencil weights: ``(S, B, N+1, n)`` → ``(S, B, N, n)`` (one
        batched product per group of steps with the same stencil)."""
        S_, B = Fin.shape[:2]
        out = np.empty((S_, B, self.N, self.n))
        for rows in self.groups:
            Fg = Fin[:, :, self.idx[rows], :].reshape(S_, B * rows.size, -1)
            out[:, :, rows] = np.matmul(Fg, self.WT[:, int(rows[0])]).reshape(S_, B, rows.size, self.n)
        return out

    def step_block(self, window: np.ndarray, forcing: np.ndarray) -> np.ndarray:
        raise NotImplementedError("step_block: one plant at a time (BlockIntegrator)")

    def quadrature(self, F: np.ndarray) -> np.ndarray:
        raise NotImplementedError("quadrature: per plant (self.parts[s].quadrature)")

    def run(
        self, X: np.ndarray, fin: np.ndarray, nblocks: int, progress: Updater, end_fix: np.ndarray | None = None
    ) -> None:
        """:meth:`BlockIntegrator.run` with one plant per trajectory: ``X``, ``fin`` and ``end_fix``
        have the leading axis S (one row per plant)."""
        if X.ndim != 3 or X.shape[0] != len(self.parts):
            raise ValueError(f"X: expected ({len(self.parts)}, rows, n), one trajectory per plant; got {X.shape}")
        if self.method == "scan":
            return self._run_scan(X, fin, nblocks, progress, end_fix)
        if self.method != "chunked":
            return super().run(X, fin, nblocks, progress, end_fix=end_fix)
        for s_, part in enumerate(self.parts):  # large N: per plant (as a batch of one plant does)
            part.run(X[s_], fin[s_], nblocks, progress, end_fix=None if end_fix is None else end_fix[s_])
        return None

    def _run_scan(self, Xb: np.ndarray, fb: np.ndarray, nblocks: int, progress: Updater,
                  end_fix: np.ndarray | None) -> None:
        """Per block: the forcing of its N steps for every plant at once (delayed part from the
        window, input part from the quadrature of all blocks), then the N steps
        ``x_{r+1} = Φ_s x_r + g_r`` in chunks of m: the chunks' solutions from zero in one
        product, the chunk starts ``x_{c m}`` in sequence (one batched product over the plants
        per chunk), the states from the starts in one product (as a LinearScan per plant)."""
        N, n, K = self.N, self.n, self.K
        S_ = Xb.shape[0]
        jb = np.arange(nblocks)[:, None] * N + np.arange(N + 1)[None, :]
        Fin = fb[:, jb]  # (S, nblocks, N+1, n)
        if end_fix is not None:
            Fin[:, :, N, :] += end_fix
        Gin = np.ascontiguousarray(self._quadrature_batch(Fin).transpose(1, 2, 0, 3))  # (nblocks, N, S, n)
        m, TmT, PT, PmT = self.m_scan, self.TmT, self.PT, self.PmT
        C = N // m
        KN, step = K * N, max(1, nblocks // 100)
        for k in range(nblocks):
            a = k * N
            G = Gin[k]
            if K:
                G = G.copy()
                for g, rows in enumerate(self.groups):
                    Xg = Xb[:, a + self.gidx[rows]].reshape(S_, rows.size, -1)
                    G[rows] += np.matmul(Xg, self.WA[:, g]).transpose(1, 0, 2)
            # chunks of m steps: the local solutions from zero at once, the chunk starts in sequence
            Yp = np.matmul(G.transpose(1, 0, 2).reshape(S_, C, m * n), TmT)  # (S, C, m n)
            starts = np.empty((S_, C, n))
            x = Xb[:, a + KN, None, :]  # (S, 1, n)
            for c in range(C):
                starts[:, c] = x[:, 0]
                x = np.matmul(x, PmT)
                x += Yp[:, c, None, (m - 1) * n :]
            Yp += np.matmul(starts, PT)
            Xb[:, a + KN + 1 : a + KN + 1 + N] = Yp.reshape(S_, N, n)
            if k % step == 0:
                progress.update(k)
