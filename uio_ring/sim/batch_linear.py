"""A linear observer's segments of a batch, scenario-innermost (compiled loops).

:class:`~uio_ring.sim.batch._BatchObserver` with ``kernel="numba"``, a linear observer
(no injection term) and the cubic forcing runs its segments here: the same recursion
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
>>> runs = [Scenario(x0=[1.0, 0.0]), Scenario(x0=[0.0, 2.0])]
>>> a, b = (simulate_batch(des, runs, t_final=0.5, dt=1e-3, kernel=k, trajectories=True) for k in ("python", "numba"))
>>> bool(np.allclose(a.x_hat, b.x_hat, rtol=0, atol=1e-12))  # doctest: +SKIP
True
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from uio_ring.numeric.scenario_kernel import (
    TapPairs,
    delayed_sum_k,
    stencil_scan_k,
    tap_pairs,
    tap_sum_k,
)

__all__ = ["LinearObserverK", "row_form", "rows_k"]


class LinearObserverK:
    """The segments of a linear observer with cubic forcing for K scenarios, scenario-innermost.

    ``xi0(D0)`` gives the initial ``ξ(0)`` ``(K, n_z)`` from ``D(δ) y`` at t = 0 (the batch
    observer's rule: ``x_hat0``, ``exact_start``'s ẑ(0), else 0).
    """

    def __init__(self, stepper: Any, u_history: np.ndarray, pad: int, xi0: Callable[[np.ndarray], np.ndarray]):
        st = self.st = stepper
        self.N, self.Lt, self.pad, self.xi0 = st.N, st.history_length + 1, pad, xi0
        self.u_history = u_history  # (L, K, n_u), time-major
        self.PhiT = np.ascontiguousarray(st.Phi.T)
        self.Gy, self.Dy, self.X = tap_pairs(row_form(st.Gy)), tap_pairs(row_form(st.Dy)), tap_pairs(row_form(st.X))
        self.Gu = self.Du = None
        if st.n_u:
            self.Gu, self.Du = tap_pairs(row_form(st.Gu)), tap_pairs(row_form(st.Du))
        self.Wm = None if st.Wm is None else tap_pairs(row_form(st.Wm))
        self.W = tap_pairs(row_form(np.asarray(st.W)))  # the cubic stencil at nodes −2 … 1
        self.eye = tap_pairs(np.eye(st.n_z)[None])  # steps of a given forcing
        self.YtailT: np.ndarray | None = None
        self.UtailT = self.ZtailT = np.zeros(0)
        self.xiT = np.zeros((st.n_z, 0))  # ξ at the last sample, (n_z, K)
        self.started = False

    def start_exact(self, Yp: np.ndarray, Up: np.ndarray) -> None:
        """The true past of y and u (time-major ``(Lt, K, ·)``) instead of y held at y(0)."""
        self.YtailT, self.UtailT = _t(Yp), _t(Up)

    def _taps(self, pairs: TapPairs | None, rows: np.ndarray, j0: int, L: int, off: int, into: np.ndarray | None = None,
              ) -> np.ndarray:
        """``Σ_i M_i s(t_j − i h)`` for ``j = j0 … j0 + L − 1``: ``(L, r, K)`` (``rows[off + j] = s(t_j)``);
        added to ``into`` when given."""
        assert pairs is not None
        out = delayed_sum_k(pairs, rows, j0, L, off, self.N)
        if into is None:
            return out
        into += out
        return into

    def segment(self, jlo: int, Y: np.ndarray, U: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """``x̂`` (and ``ŵ``) at the samples ``jlo …`` from y, u there (time-major ``(S, K, ·)``):
        time-major views ``(S, K, n_x)``."""
        st, N, Lt, pad = self.st, self.N, self.Lt, self.pad
        Sn, K = Y.shape[0], Y.shape[1]
        first, self.started = not self.started, True
        if self.YtailT is None:  # y held at y(0) before 0; u from its history (and one more row, never read)
            self.YtailT = np.repeat(_t(Y[:1]), Lt, axis=0)
            self.UtailT = _t(np.concatenate([self.u_history[:1], self.u_history], axis=0))
        Yr = rows_k(self.YtailT, Y)  # Yr[Lt + j − jlo] = y(t_j), (rows, n_y, K)
        Ur = rows_k(self.UtailT, U) if st.n_u else None
        off = Lt - jlo
        G = self._taps(self.Gy, Yr, jlo - 3, Sn + 3, off)  # G[j − jlo + 3] = g(t_j)
        D = self._taps(self.Dy, Yr, jlo, Sn, off)
        if Ur is not None:
            self._taps(self.Gu, Ur, jlo - 3, Sn + 3, off, into=G)
            self._taps(self.Du, Ur, jlo, Sn, off, into=D)
        s0 = 0 if first else jlo - 1  # the steps s0 … j1 − 1 (j → j + 1) of this segment
        M = jlo + Sn - 1 - s0
        xi_prev = np.ascontiguousarray(self.xi0(D[0].T).T) if first else self.xiT
        g0 = s0 - (jlo - 3)  # G row of g(t_{s0})
        nodes = np.array([g0 - 2, g0 - 1, g0, g0 + 1])
        Xi = np.empty((M, st.n_z, K))
        if M and s0 >= st.guard_blocks * N:  # past the start's stencils: forcing and steps in one pass
            stencil_scan_k(G, nodes, self.W, self.PhiT, xi_prev, Xi)
        elif M:
            F = tap_sum_k(G, nodes, self.W, np.empty((M, st.n_z, K)))
            self._guarded(F, G, s0, g0)
            stencil_scan_k(F, np.zeros(1, dtype=np.int64), self.eye, self.PhiT, xi_prev, Xi)
        if first:
            Xi = np.concatenate([xi_prev[None], Xi], axis=0)
        self.xiT = Xi[-1].copy()
        Z = np.empty((pad + Xi.shape[0], st.n_z, K))  # ẑ = ξ + D(δ) y after its tail
        np.add(Xi, D, out=Z[pad:])
        Z[:pad] = Z[pad] if first else self.ZtailT  # held at ẑ(0) before 0
        xh = self._taps(self.X, Z, jlo, Sn, pad - jlo)
        wh = None if self.Wm is None else self._taps(self.Wm, Z, jlo, Sn, pad - jlo).transpose(0, 2, 1)
        self.YtailT = Yr[Yr.shape[0] - Lt :].copy()
        if Ur is not None:
            self.UtailT = Ur[Ur.shape[0] - Lt :].copy()
        self.ZtailT = Z[Z.shape[0] - pad :].copy()
        return xh.transpose(0, 2, 1), wh

    def _guarded(self, F: np.ndarray, G: np.ndarray, s0: int, g0: int) -> None:
        """The first two steps of each guarded block (``ObserverStepper._forcing_table``): the
        one-sided stencils ``W_first`` (nodes 0, 1) and ``W_second`` (nodes −1, 0, 1), in place."""
        st, N = self.st, self.N
        steps = np.arange(s0, s0 + F.shape[0])
        end = st.guard_blocks * N
        gi = steps - s0 + g0
        r = steps % N
        sel = np.nonzero((steps < end) & (r == 0))[0]
        F[sel] = _apply(st.W_first[0], G[gi[sel]]) + _apply(st.W_first[1], G[gi[sel] + 1])
        if N > 1:
            Ws = st.W_second
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
