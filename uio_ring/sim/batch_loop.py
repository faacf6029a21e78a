"""Closed-loop batches: K plants and their observers in lockstep, ``u = feedback(t, X̂, Ŵ)``.

The batched counterpart of the closed loop of :func:`~uio_ring.sim.engine.simulate_observer`
(delay-free plants; u held over each step, in the plant and in the observer, through the
model's :class:`~uio_ring.numeric.model.HeldInput`): each step advances the K plants (their
one-step map), their outputs and the K observer states (the stepper's step, its injection
term on K rows) with a few products of K rows, and calls ``feedback`` once, with the K
estimates as rows.  Observers with delayed taps are not batched here (the single-run loop
keeps ring buffers of their past; use :func:`simulate_observer`).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from typing import Any

import numpy as np

from uio_ring.errors import NotSupportedError, SimulationError

__all__ = ["ClosedLoop", "check_closed_loop"]


def check_closed_loop(S: Any, stepper: Any, scenarios: Sequence[Any]) -> None:
    """The closed loops :func:`simulate_observer` runs, and observers without delayed taps.

    ``S``: the plants' :class:`~uio_ring.sim.plant.SystemArrays` (one stack, or one per scenario).
    """
    if any(S.deg(M) > 0 for M in (S.A, S.B, S.C, S.D, S.E, S.F)):
        raise NotSupportedError("feedback: closed-loop runs are implemented for delay-free plants")
    if S.n_u == 0:
        raise SimulationError("feedback: the plant has no known input u")
    if S.F.shape[-3] and np.any(S.F):
        raise NotSupportedError("feedback with a known-input feed-through F ≠ 0 is an algebraic loop")
    if any(sc.u is not None for sc in scenarios):
        raise SimulationError("give u or feedback, not both")
    if stepper.cubic:
        raise SimulationError("held inputs need a model with linear interpolation")
    taps = (stepper.Gy, stepper.Gu, stepper.Dy, stepper.Du, stepper.X) + (() if stepper.Wm is None else (stepper.Wm,))
    if any(M.shape[0] > 1 for M in taps):
        raise NotSupportedError("feedback in a batch: observers with delayed taps are not batched "
                                "(simulate_observer runs them one at a time)")


def _rows(v: np.ndarray, M: np.ndarray) -> np.ndarray:
    """``M v`` for each row of ``v`` ``(K, c)``: ``M`` is ``(1, r, c)`` (shared) or ``(K, 1, r, c)``
    (one plant per row); ``(K, r)``."""
    if M.shape[-3] == 0:
        return np.zeros((v.shape[0], M.shape[-2]))
    if M.ndim == 3:
        return v @ M[0].T
    return np.einsum("kc,krc->kr", v, M[:, 0])


class ClosedLoop:
    """The closed loop of K scenarios, one segment of samples at a time (:meth:`segment`).

    ``plant`` is the batch's :class:`~uio_ring.sim.batch._BatchPlant` (its step map, inputs,
    noise and initial states); ``observer`` its :class:`~uio_ring.sim.batch._BatchObserver`
    (the initial observer state); ``binj`` the injection term on K rows (None without one).
    """

    def __init__(self, plant: Any, observer: Any, binj: Any, feedback: Callable[..., Any]):
        self.bp, self.st, self.binj, self.feedback = plant, observer.st, binj, feedback
        S, st = plant.S, observer.st
        self.S = S
        K = len(plant.scen)
        integ = plant.integ  # one step a block: x_{k+1} = x_k MT + [f_k, f_{k+1}] QinT
        self.MT, self.QinT = integ.MT, integ.QinT
        n = S.n_x
        self.x = plant.Xtail[0].copy()  # (K, n): x(0)
        w0 = plant._inputs("w", S.n_w, 0, 0)[0]
        nz0 = plant._noise(S.n_y, 0, 0)
        self.y = _rows(self.x, S.C) + _rows(w0, S.D) + (0.0 if nz0 is None else nz0[0])
        self.u = np.zeros((K, S.n_u))  # the input stored at the last sample (0 at the start)
        self.xi = observer._xi0(self.y[None], np.zeros((1, K, st.n_u)), 0)
        g0 = self.y @ st.Gy[0].T  # u(0) = 0; the history is held at the first sample
        self.g = [g0, g0, g0]
        self.z = self.xi + self.y @ st.Dy[0].T
        self.n = n
        self.PhiT, self.W0T, self.W1T = st.Phi.T, st.W_first[0].T, st.W_first[1].T

    def _matmul(self, x: np.ndarray, M: np.ndarray) -> np.ndarray:
        return x @ M if M.ndim == 2 else np.matmul(x[:, None, :], M)[:, 0]

    def _estimate(self) -> tuple[np.ndarray, np.ndarray | None]:
        st = self.st
        return self.z @ st.X[0].T, None if st.Wm is None else self.z @ st.Wm[0].T

    def _feedback(self, t: float, xh: np.ndarray, wh: np.ndarray | None) -> np.ndarray:
        K, n_u = self.u.shape
        v = np.asarray(self.feedback(t, xh, wh), dtype=float)
        if v.shape != (K, n_u) or not np.all(np.isfinite(v)):
            raise SimulationError(f"feedback returned an array of shape {v.shape} at t = {t:g}; expected "
                                  f"({K}, {n_u}) finite values (one row per scenario)")
        return v

    def _step(self, uk: np.ndarray, w0: np.ndarray, w1: np.ndarray, nz1: np.ndarray | None) -> None:
        """Advance plant and observer from t_k to t_{k+1} with u_k held (ObserverStepper.step, held=True)."""
        S, st, binj = self.S, self.st, self.binj
        Eu = _rows(uk, S.E)
        f = np.concatenate([_rows(w0, S.B) + Eu, _rows(w1, S.B) + Eu], axis=1)
        x_new = self._matmul(self.x, self.MT) + self._matmul(f, self.QinT)
        y_new = _rows(x_new, S.C) + _rows(w1, S.D)
        if nz1 is not None:
            y_new += nz1
        g_new = y_new @ st.Gy[0].T + (uk @ st.Gu[0].T if st.n_u else 0.0)
        xi, g, u_prev = self.xi, self.g, self.u
        method = None if binj is None else binj.inj.method
        meas_prev = None if method in (None, "implicit") else binj.measured(self.y, u_prev)
        if method == "euler":
            xi = xi + st.dt * (xi @ st.model.F.T + g[2] + binj.l_of(meas_prev + xi @ binj.RT))
        else:
            g0, gc, extra = g[2], g_new, 0.0
            if st._held is not None:  # the held input's exact effect (as the single-run step)
                Gam, MGam, Bd = st._held
                g0 = g0 - u_prev @ Bd.T
                gc = g_new - uk @ Bd.T - uk @ MGam.T
                extra = uk @ Gam.T
            lin = xi @ self.PhiT + (g0 @ self.W0T + gc @ self.W1T) + extra
            if method is None:
                xi = lin
            elif method == "explicit":
                xi = lin + binj.l_of(meas_prev + xi @ binj.RT) @ binj.KlT
            else:
                xi = binj.implicit(lin, binj.measured(y_new, uk))
        self.g = [g[1], g[2], g_new]
        self.xi, self.x, self.y, self.u = xi, x_new, y_new, uk
        self.z = xi + y_new @ st.Dy[0].T + (uk @ st.Du[0].T if st.n_u else 0.0)

    def segment(self, j0: int, j1: int, n_steps: int) -> tuple[Any, ...]:
        """Samples ``j0 … j1`` (time-major ``(S, K, ·)``): x, y, w, u, x̂, ŵ (None without ŵ); the
        state is at sample ``j0`` on entry and at ``j1 + 1`` on return (``j1 < n_steps``)."""
        S, K, dt = self.S, self.u.shape[0], self.bp.dt
        L = j1 - j0 + 1
        W = self.bp._inputs("w", S.n_w, j0, min(j1 + 1, n_steps))
        nz = self.bp._noise(S.n_y, j0, min(j1 + 1, n_steps))
        X, Y, U = np.empty((L, K, S.n_x)), np.empty((L, K, S.n_y)), np.empty((L, K, S.n_u))
        XH = np.empty((L, K, self.st.n_x))
        WH = None if self.st.Wm is None else np.empty((L, K, self.st.n_w))
        with np.errstate(all="ignore"):
            for q, j in enumerate(range(j0, j1 + 1)):
                xh, wh = self._estimate()
                X[q], Y[q], XH[q] = self.x, self.y, xh
                if WH is not None:
                    WH[q] = wh
                if j == n_steps:  # the last sample: u held from the last step
                    U[q] = self.u
                    break
                uk = self._feedback(j * dt, xh, wh)
                U[q] = uk
                self._step(uk, W[q], W[q + 1], None if nz is None else nz[q + 1])
        return X, Y, W[:L], U, XH, WH

    def segments(self, n_steps: int, seg: int) -> Iterator[tuple[int, tuple[np.ndarray, ...]]]:
        """``(j0, segment)`` for consecutive segments of ``seg`` samples covering ``0 … n_steps``."""
        for j0 in range(0, n_steps + 1, seg):
            yield j0, self.segment(j0, min(j0 + seg - 1, n_steps), n_steps)
