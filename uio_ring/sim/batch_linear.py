"""A linear observer's segments of a batch, scenario-innermost (compiled loops).

:class:`~uio_ring.sim.batch._BatchObserver` with ``kernel="numba"``, a linear observer
(no injection term), the cubic forcing and K ≥ 8 scenarios runs its segments here: the same recursion
(``ObserverStepper.trajectories``: ``g = G(δ) y``, the cubic stencil of g, the steps
``ξ_{j+1} = Φ ξ_j + f_j``, ``ẑ = ξ + D(δ) y``, ``x̂ = X(δ) ẑ``, ``ŵ = W(δ) ẑ``) with every
array laid out ``(rows, columns, K)``: y is transposed once per segment, every tap sum and
the fused stencil and steps are one pass of :mod:`uio_ring.numeric.scenario_kernel`, and
x̂ is handed back as a time-major view ``(rows, K, n_x)``.  The start's guarded steps (the
first two steps of each of the first ``guard_blocks`` blocks use the one-sided stencils
``W_first``, ``W_second``) are patched into the forcing, which the same fused pass then
steps (identity taps).

Complexity: ``O(S K (P_G + P_D + P_X) n_z + S K (4 n_z + n_z) n_z)`` per segment of S
samples (P_·: nonzero coefficient rows of the tap stacks); memory: a few
``(S, n_z, K)`` arrays and the tails the delays read.

>>> import numpy as np
>>> from uio_ring import DelaySystem, design_zheng_bejarano
>>> from uio_ring.sim.batch import Scenario, simulate_batch
>>> sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)
>>> des = design_zheng_bejarano(sys, poles=[-10])
>>> runs = [Scenario(x0=[1.0, k / 8]) for k in range(8)]         # (K ≥ 8: fewer run as simulate_observer)
>>> a, b = (simulate_batch(des, runs, t_final=0.5, dt=1e-3, kernel=k, trajectories=True) for k in ("python", "auto"))
>>> bool(np.allclose(a.x_hat, b.x_hat, rtol=0, atol=1e-12))   # "auto": this path when numba is installed
True
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

from uio_ring.numeric.scenario_kernel import (
    TapPairs,
    delayed_sum_k,
    stencil_scan_k,
    tap_pairs,
    tap_sum_k,
)

__all__ = ["LinearObserverK", "decoupled_parts", "row_form", "rows_k"]


@dataclass(frozen=True, eq=False)
class _Part:
    """The observer restricted to a set of states ``idx`` of ξ that no other state drives (Φ and the
    stencil weights couple none of them with the rest): its tap stacks (coefficient rows) and Φᵀ."""

    idx: np.ndarray
    Gy: TapPairs
    Dy: TapPairs
    Gu: TapPairs | None
    Du: TapPairs | None
    W: TapPairs
    eye: TapPairs
    PhiT: np.ndarray
    X: TapPairs
    Wm: TapPairs | None
    W_first: np.ndarray
    W_second: np.ndarray


def decoupled_parts(mats: list[np.ndarray]) -> list[np.ndarray]:
    """The connected components of the states coupled by the square matrices ``mats`` (i ~ j when
    some ``M[i, j] ≠ 0``), each sorted, in order of their smallest state (union–find, O(n² len(mats))).

    >>> [c.tolist() for c in decoupled_parts([np.array([[1.0, 0, 2], [0, 1, 0], [0, 0, 1]])])]
    [[0, 2], [1]]
    """
    n = mats[0].shape[0]
    root = list(range(n))

    def find(i: int) -> int:
        while root[i] != i:
            root[i] = root[root[i]]
            i = root[i]
        return i

    for M in mats:
        for i, j in np.argwhere(M != 0.0):
            a, b = find(int(i)), find(int(j))
            if a != b:
                root[max(a, b)] = min(a, b)
    comps: dict[int, list[int]] = {}
    for i in range(n):
        comps.setdefault(find(i), []).append(i)
    return [np.array(c) for c in comps.values()]


class LinearObserverK:
    """The segments of a linear observer with cubic forcing for K scenarios, scenario-innermost.

    ``xi0(D0)`` gives the initial ``ξ(0)`` ``(K, n_z)`` from ``D(δ) y`` at t = 0 (the batch
    observer's rule: ``x_hat0``, ``exact_start``'s ẑ(0), else 0).  States of ξ that Φ and the
    stencil weights do not couple (:func:`decoupled_parts`; paper 001: two chains of three) run
    as separate recursions: the zero blocks cost no products.
    """

    def __init__(self, stepper: Any, u_history: np.ndarray, pad: int, xi0: Callable[[np.ndarray], np.ndarray]):
        st = self.st = stepper
        self.N, self.Lt, self.pad, self.xi0 = st.N, st.history_length + 1, pad, xi0
        self.u_history = u_history  # (L, K, n_u), time-major
        W = np.asarray(st.W)
        self.parts = [self._part(st, W, idx) for idx in decoupled_parts([st.Phi, *W, *st.W_first, *st.W_second])]
        self.YtailT: np.ndarray | None = None
        self.UtailT = np.zeros(0)
        self.ZtailT: list[np.ndarray] = []  # per part: ẑ before the segment (pad rows)
        self.xiT: list[np.ndarray] = []  # per part: ξ at the last sample, (r, K)
        self.started = False

    @staticmethod
    def _part(st: Any, W: np.ndarray, idx: np.ndarray) -> _Part:
        def rows(M: np.ndarray) -> TapPairs:  # the part's rows of a stack (m, n_z, c)
            return tap_pairs(row_form(M[:, idx, :]))

        def cols(M: np.ndarray) -> TapPairs:  # the part's columns of a stack (m, r, n_z)
            return tap_pairs(row_form(M[:, :, idx]))

        sq = np.ix_(idx, idx)
        return _Part(idx, rows(st.Gy), rows(st.Dy), rows(st.Gu) if st.n_u else None, rows(st.Du) if st.n_u else None,
                     tap_pairs(row_form(W[:, idx][:, :, idx])), tap_pairs(np.eye(idx.size)[None]),
                     np.ascontiguousarray(st.Phi[sq].T), cols(st.X), None if st.Wm is None else cols(st.Wm),
                     np.stack([Wm[sq] for Wm in st.W_first]), np.stack([Wm[sq] for Wm in st.W_second]))

    def start_exact(self, Yp: np.ndarray, Up: np.ndarray) -> None:
        """The true past of y and u (time-major ``(Lt, K, ·)``) instead of y held at y(0)."""
        self.YtailT, self.UtailT = _t(Yp), _t(Up)

    def _taps(self, pairs: TapPairs | None, rows: np.ndarray, j0: int, L: int, off: int, into: np.ndarray | None = None,
              ) -> np.ndarray:
        """``Σ_i M_i s(t_j − i h)`` for ``j = j0 … j0 + L − 1``: ``(L, r, K)`` (``rows[off + j] = s(t_j)``);
        added to ``into`` when given."""
        assert pairs is not None
        return delayed_sum_k(pairs, rows, j0, L, off, self.N, into=into)

    def segment(self, jlo: int, Y: np.ndarray, U: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """``x̂`` (and ``ŵ``) at the samples ``jlo …`` from y, u there (time-major ``(S, K, ·)``):
        time-major views ``(S, K, n_x)``."""
        st, Lt = self.st, self.Lt
        Sn = Y.shape[0]
        first, self.started = not self.started, True
        if self.YtailT is None:  # y held at y(0) before 0; u from its history (and one more row, never read)
            self.YtailT = np.repeat(_t(Y[:1]), Lt, axis=0)
            self.UtailT = _t(np.concatenate([self.u_history[:1], self.u_history], axis=0))
        Yr = rows_k(self.YtailT, Y)  # Yr[Lt + j − jlo] = y(t_j), (rows, n_y, K)
        Ur = rows_k(self.UtailT, U) if st.n_u else None
        xi_all = None
        xh: np.ndarray | None = None
        wh: np.ndarray | None = None
        for c, part in enumerate(self.parts):
            if first:
                if xi_all is None:  # ξ(0) of all states from D(δ) y at t = 0 of all states
                    D0 = np.empty((Y.shape[1], st.n_z))
                    for q in self.parts:
                        D0[:, q.idx] = (self._taps(q.Dy, Yr, 0, 1, Lt)[0] if Ur is None else
                                        self._taps(q.Dy, Yr, 0, 1, Lt)[0] + self._taps(q.Du, Ur, 0, 1, Lt)[0]).T
                    xi_all = self.xi0(D0)
                xi_prev = np.ascontiguousarray(xi_all[:, part.idx].T)
            else:
                xi_prev = self.xiT[c]
            Z = self._part_segment(c, part, jlo, Sn, Yr, Ur, xi_prev, first)
            xh = self._taps(part.X, Z, jlo, Sn, self.pad - jlo, into=xh)
            if part.Wm is not None:
                wh = self._taps(part.Wm, Z, jlo, Sn, self.pad - jlo, into=wh)
        assert xh is not None
        self.YtailT = Yr[Yr.shape[0] - Lt :].copy()
        if Ur is not None:
            self.UtailT = Ur[Ur.shape[0] - Lt :].copy()
        return xh.transpose(0, 2, 1), None if wh is None else wh.transpose(0, 2, 1)

    def _part_segment(self, c: int, part: _Part, jlo: int, Sn: int, Yr: np.ndarray, Ur: np.ndarray | None,
                      xi_prev: np.ndarray, first: bool) -> np.ndarray:
        """ẑ of one part on the S = ``Sn`` samples of the segment after its tail ``(pad + S, r, K)``;
        keeps its ξ and tail."""
        st, N, pad, off = self.st, self.N, self.pad, self.Lt - jlo
        K, r = Yr.shape[2], part.idx.size
        G = self._taps(part.Gy, Yr, jlo - 3, Sn + 3, off)  # G[j − jlo + 3] = g(t_j)
        if Ur is not None:
            self._taps(part.Gu, Ur, jlo - 3, Sn + 3, off, into=G)
        s0 = 0 if first else jlo - 1  # the steps s0 … j1 − 1 (j → j + 1) of this segment
        M = jlo + Sn - 1 - s0
        g0 = s0 - (jlo - 3)  # G row of g(t_{s0})
        nodes = np.array([g0 - 2, g0 - 1, g0, g0 + 1])
        Z = np.empty((pad + Sn, r, K))  # ξ, then ẑ = ξ + D(δ) y, after the tail of ẑ
        Xi = Z[pad + Sn - M :]  # the steps' states (the first segment: ξ(0) before them)
        if first:
            Z[pad] = xi_prev
        if M and s0 >= st.guard_blocks * N:  # past the start's stencils: forcing and steps in one pass
            stencil_scan_k(G, nodes, part.W, part.PhiT, xi_prev, Xi)
        elif M:
            F = tap_sum_k(G, nodes, part.W, np.empty((M, r, K)))
            self._guarded(part, F, G, s0, g0)
            stencil_scan_k(F, np.zeros(1, dtype=np.int64), part.eye, part.PhiT, xi_prev, Xi)
        xi_last = Z[-1].copy()
        self._taps(part.Dy, Yr, jlo, Sn, off, into=Z[pad:])
        if Ur is not None:
            self._taps(part.Du, Ur, jlo, Sn, off, into=Z[pad:])
        Z[:pad] = Z[pad] if first else self.ZtailT[c]  # held at ẑ(0) before 0
        if first:
            self.xiT.append(xi_last)
            self.ZtailT.append(Z[Z.shape[0] - pad :].copy())
        else:
            self.xiT[c] = xi_last
            self.ZtailT[c] = Z[Z.shape[0] - pad :].copy()
        return Z

    def _guarded(self, part: _Part, F: np.ndarray, G: np.ndarray, s0: int, g0: int) -> None:
        """The first two steps of each guarded block (``ObserverStepper._forcing_table``): the
        one-sided stencils ``W_first`` (nodes 0, 1) and ``W_second`` (nodes −1, 0, 1), in place."""
        st, N = self.st, self.N
        steps = np.arange(s0, s0 + F.shape[0])
        end = st.guard_blocks * N
        gi = steps - s0 + g0
        r = steps % N
        sel = np.nonzero((steps < end) & (r == 0))[0]
        Wf, Ws = part.W_first, part.W_second
        F[sel] = _apply(Wf[0], G[gi[sel]]) + _apply(Wf[1], G[gi[sel] + 1])
        if N > 1:
            sel = np.nonzero((steps < end) & (r == 1))[0]
            F[sel] = _apply(Ws[0], G[gi[sel] - 1]) + _apply(Ws[1], G[gi[sel]]) + _apply(Ws[2], G[gi[sel] + 1])


def row_form(M: np.ndarray) -> np.ndarray:
    """``(m, r, c)`` coefficient matrices → ``(m, c, r)`` (the transposed ones, row-vector form)."""
    return np.ascontiguousarray(np.asarray(M, dtype=float).transpose(0, 2, 1))


def _t(A: np.ndarray) -> np.ndarray:
    """Time-major ``(rows, K, c)`` → scenario-innermost ``(rows, c, K)``, contiguous."""
    return np.ascontiguousarray(A.transpose(0, 2, 1))


def rows_k(tail: np.ndarray, new: np.ndarray) -> np.ndarray:
    """The tail ``(T, c, K)`` followed by the time-major rows ``new`` ``(S, K, c)``: ``(T + S, c, K)``."""
    out = np.empty((tail.shape[0] + new.shape[0], new.shape[2], new.shape[1]))
    out[: tail.shape[0]] = tail
    out[tail.shape[0] :] = new.transpose(0, 2, 1)
    return out


def _apply(Wm: np.ndarray, rows: np.ndarray) -> np.ndarray:
    """``Wm @ rows[s]`` for every row ``s`` of ``rows`` ``(S, c, K)``: ``(S, r, K)``."""
    return np.matmul(Wm, rows)
