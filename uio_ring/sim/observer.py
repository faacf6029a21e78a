"""The delay unknown-input observer of Zheng, Bejarano, Perruquetti & Richard (Theorem 4).

    ξ'(t) = L0 ξ(t) + J(δ) Λ(δ) y(t)
    ẑ(t)  = ξ(t) + H(δ) Λ(δ) y(t)
    x̂(t)  = T_L⁻¹(δ) ẑ(t)

(eq. (21) as corrected in shared/ERRATA.md: ẑ, not ẑ').  The observer reads only
past and present outputs, so it runs online: :class:`DelayObserverSimulator`
takes one output sample per :meth:`~DelayObserverSimulator.step` and keeps a
constant amount of memory; :meth:`~DelayObserverSimulator.run` processes a
whole record with array operations and gives the same numbers.

Discretisation: exponential integrator ``ξ_k = e^{L0 dt} ξ_{k−1} + Σ_m W_m g_{k−3+m}``
with ``g = (JΛ)(δ) y`` on the grid and a causal four-point stencil (nodes
``k−3 … k``), so only samples up to ``t_k`` are used; local error O(dt⁵).  In the
first ``guard_blocks`` blocks, where y and its first derivatives jump at the
multiples of h, the stencil stays inside the block (linear, then quadratic for
the first two steps of a block): local O(dt³) at finitely many steps, so the
start-up transient is O(dt³) and the steady state O(dt⁴).
Before the first sample, signals are held at their first value unless a
history is given (``y_history``); ẑ is held at ẑ(0).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from uio_ring.sim._convert import coefficient_arrays, eval_at_one, poly_matmul
from uio_ring.sim._expint import LinearScan, phi_functions, stencil_weights
from uio_ring.sim._grid import as_float, steps_per_delay
from uio_ring.sim._threads import blas_single_thread
from uio_ring.sim.errors import DimensionError, NotSupportedError, SimulationError
from uio_ring.sim.history import HistoryBuffer
from uio_ring.sim.plant import delayed_sum, plant_run, resolve_h
from uio_ring.sim.result import SimulationResult

__all__ = ["DelayObserverSimulator", "simulate_observer"]

_NODES = (-2, -1, 0, 1)  # stencil of the step k−1 → k, relative to t_{k−1}
_NODES_FIRST = (0, 1)  # first step of a block, stencil kept inside the block
_NODES_SECOND = (-1, 0, 1)  # second step of a block


def guard_blocks_for(system: Any) -> int:
    """Blocks ``[0, M h]`` in which y, y' or y'' may jump at the multiples of h.

    x' jumps at 0 (history vs. dynamics), x^{(q)} at ``i h`` for ``i ≤ (q − 1) deg A``
    (plus ``deg B`` when w starts at 0), and y = C(δ)x + D(δ)w shifts them by up to
    ``max(deg C, deg D)``.  Beyond, y is C³ across block ends, where a centred cubic
    stencil keeps the local error O(dt⁵).
    """
    if system is None:
        return 8
    deg = {k: coefficient_arrays(getattr(system, k), name=k).shape[0] - 1
           for k in "ABCD" if getattr(system, k, None) is not None}
    return max(2 * max(deg.get("A", 0), 0) + max(deg.get("B", 0), 0)
               + max(deg.get("C", 0), deg.get("D", 0), 0) + 2, 1)


def _design_h(design: Any) -> Any:
    h = getattr(design, "h", None)
    if h is None:
        h = getattr(getattr(design, "system", None), "h", None)
    return h


def _finite(a: np.ndarray, name: str) -> None:
    bad = ~np.isfinite(a)
    if bad.any():
        idx = tuple(int(i) for i in np.argwhere(bad)[0])
        raise SimulationError(f"{name} is not finite at index {idx}: {a[idx]}")


class DelayObserverSimulator:
    """Numeric observer of a Zheng–Bejarano design on the grid ``dt = h/N``.

    Parameters
    ----------
    design : DelayUIODesign
        Needs ``L0, J, H, Lam, T, T_left_inverse`` (and ``system``).
    h, dt : float
        Basic delay (must agree with the design's h, if it has one) and step.
    x_hat0 : array, optional
        Initial estimate: ``ξ(0) = T(1) x̂0 − (HΛ)(δ) y(0)``, so that ``x̂(0) = x̂0``.
    xi0 : array, optional
        Initial observer state ξ(0) directly (default 0).
    y_history : array, optional
        Output samples before 0, ``(n_y, L)`` with ``L = history_length``, oldest
        first (default: y held at y(0)).
    guard_blocks : int, optional
        Number of blocks ``[k h, (k+1) h]`` from t = 0 whose stencils stay inside the
        block (y may have derivative jumps at their ends); default from the degrees of
        ``design.system`` (:func:`guard_blocks_for`); 0 when y is smooth across them
        (e.g. a record that starts long after the plant did).

    Examples
    --------
    ``obs = design.simulator(h=0.01, dt=0.001)``, then ``x_hat = obs.step(y_k)`` once
    per sample, or ``x_hat = obs.run(y)`` for a record ``y`` of shape ``(n_y, T)``.
    """

    def __init__(
        self,
        design: Any,
        h: Any,
        dt: Any,
        *,
        x_hat0: Any = None,
        xi0: Any = None,
        y_history: Any = None,
        guard_blocks: int | None = None,
    ):
        system = getattr(design, "system", None)
        self.h = resolve_h(h, _design_h(design), what="the design")
        self.dt = as_float(dt, "dt")
        self.N = steps_per_delay(self.h, self.dt)
        self.dt = self.h / self.N
        for name in ("E", "F"):
            M = getattr(system, name, None)
            if M is not None and coefficient_arrays(M, name=name).shape[0] > 0:
                raise NotSupportedError(
                    f"the design's system has a known input (nonzero {name}); the observer of paper 001 "
                    "(Theorem 4) is stated for u-free systems, and its known-input terms are not derived here"
                )
        L0 = coefficient_arrays(design.L0, name="design.L0")
        n_z = design.L0.shape[0]
        self.L0 = L0[0] if L0.shape[0] else np.zeros((n_z, n_z))
        if L0.shape[0] > 1:
            raise SimulationError("design.L0 must be a constant matrix (degree 0 in δ)")
        Lam = coefficient_arrays(design.Lam, name="design.Lam")
        self.JL = poly_matmul(coefficient_arrays(design.J, name="design.J"), Lam)
        self.HL = poly_matmul(coefficient_arrays(design.H, name="design.H"), Lam)
        self.TL = coefficient_arrays(design.T_left_inverse, name="design.T_left_inverse")
        self.Tc = coefficient_arrays(design.T, name="design.T")
        self.n_z, self.n_y = n_z, design.Lam.shape[0]
        self.n_x = design.T_left_inverse.shape[0]
        self.lag = max(self.TL.shape[0] - 1, 0)
        if self.JL.shape[0] == 0:
            self.JL = np.zeros((1, n_z, self.n_y))
        if self.HL.shape[0] == 0:
            self.HL = np.zeros((1, n_z, self.n_y))
        if self.TL.shape[0] == 0:
            self.TL = np.zeros((1, self.n_x, n_z))
        N = self.N
        kJ, kH = self.JL.shape[0] - 1, self.HL.shape[0] - 1
        #: samples of y before t = 0 that the observer reads
        self.history_length = max(kJ * N + 2, kH * N)
        phis = phi_functions(self.L0 * self.dt, 4)
        self.Phi = phis[0]
        self.W = stencil_weights(self.L0 * self.dt, self.dt, _NODES, phis)  # (4, n_z, n_z)
        self.W_first = stencil_weights(self.L0 * self.dt, self.dt, _NODES_FIRST, phis)
        self.W_second = stencil_weights(self.L0 * self.dt, self.dt, _NODES_SECOND, phis)
        #: blocks from t = 0 in which the stencils do not cross a multiple of h
        self.guard_blocks = guard_blocks_for(system) if guard_blocks is None else int(guard_blocks)
        if self.guard_blocks < 0:
            raise SimulationError(f"guard_blocks={guard_blocks} must be ≥ 0")
        self._x_hat0 = None if x_hat0 is None else self._vector(x_hat0, self.n_x, "x_hat0")
        self._xi0 = None if xi0 is None else self._vector(xi0, n_z, "xi0")
        if x_hat0 is not None and xi0 is not None:
            raise SimulationError("give x_hat0 or xi0, not both")
        self._y_history = None
        if y_history is not None:
            yh = np.asarray(y_history, dtype=float)
            if yh.shape != (self.n_y, self.history_length):
                raise DimensionError(
                    f"y_history has shape {yh.shape}; expected ({self.n_y}, {self.history_length}) "
                    f"(samples at t = −{self.history_length}·dt … −dt)"
                )
            _finite(yh, "y_history")
            self._y_history = yh
        self.reset()

    @staticmethod
    def _vector(v: Any, n: int, name: str) -> np.ndarray:
        a = np.asarray(v, dtype=float).reshape(-1)
        if a.shape != (n,):
            raise DimensionError(f"{name} has shape {np.shape(v)}; expected ({n},)")
        _finite(a, name)
        return a

    # ------------------------------------------------------------------ shared pieces
    def _pre(self, y0: np.ndarray) -> np.ndarray:
        """y before 0 as rows (history_length, n_y)."""
        if self._y_history is not None:
            return self._y_history.T
        return np.repeat(y0[None, :], self.history_length, axis=0)

    def _xi_start(self, Yrows: np.ndarray, off: int) -> np.ndarray:
        if self._xi0 is not None:
            return self._xi0.copy()
        if self._x_hat0 is not None:
            T1 = eval_at_one(self.Tc, self.n_z, self.n_x)
            hy0 = delayed_sum(self.HL, Yrows, 0, 0, self.N, off)[0]
            return T1 @ self._x_hat0 - hy0
        return np.zeros(self.n_z)

    # ------------------------------------------------------------------ streaming
    def reset(self) -> None:
        """Back to t = 0 (nothing received yet)."""
        self.k = -1

    def step(self, y_k: Any, u_k: Any = None) -> np.ndarray:
        """Take the output sample at ``t_k = k·dt`` and return the estimate ``x̂(t_k)``."""
        if u_k is not None:
            raise DimensionError("u_k was given, but the observer has no known input (n_u = 0)")
        y = np.asarray(y_k, dtype=float).reshape(-1)
        if y.shape != (self.n_y,):
            raise DimensionError(f"y_k has shape {np.shape(y_k)}; expected ({self.n_y},)")
        _finite(y, "y_k")
        N, L = self.N, self.history_length
        if self.k < 0:
            # y: the last L + 1 samples (t_k − L dt … t_k); ẑ: the last lag·N + 1
            Y = np.concatenate([self._pre(y), y[None, :]])
            self._yb = HistoryBuffer.from_samples(Y.T, h=self.h, dt=self.dt)
            self._g = [self._gsum(Y, L - 2 + q) for q in range(3)]  # g at k = −2, −1, 0
            self._xi = self._xi_start(Y, L)
            z = self._xi + self._hsum(Y, L)
            self._zb = HistoryBuffer(self.n_z, h=self.h, dt=self.dt, max_delay=self.lag, phi=z)
            self.k = 0
            return self._xhat()
        self._yb.push(y)
        g_new = self._delayed(self.JL, self._yb)
        g = self._g
        r = self.k % N  # position in its block of the step's left end t_k (k = old count)
        if self.k < self.guard_blocks * N and r == 0:
            W = self.W_first
            forcing = W[0] @ g[2] + W[1] @ g_new
        elif self.k < self.guard_blocks * N and r == 1:
            W = self.W_second
            forcing = W[0] @ g[1] + W[1] @ g[2] + W[2] @ g_new
        else:
            W = self.W
            forcing = W[0] @ g[0] + W[1] @ g[1] + W[2] @ g[2] + W[3] @ g_new
        self._xi = self.Phi @ self._xi + forcing
        self._g = [g[1], g[2], g_new]
        self._zb.push(self._xi + self._delayed(self.HL, self._yb))
        self.k += 1
        return self._xhat()

    @staticmethod
    def _delayed(M: np.ndarray, buf: HistoryBuffer) -> np.ndarray:
        """``Σ_i M_i s(t_now − i h)`` from a history buffer."""
        out = M[0] @ buf.lookup(0)
        for i in range(1, M.shape[0]):
            out = out + M[i] @ buf.lookup(i)
        return out

    def _gsum(self, Y: np.ndarray, pos: int) -> np.ndarray:
        return sum((self.JL[i] @ Y[pos - i * self.N] for i in range(1, self.JL.shape[0])), self.JL[0] @ Y[pos])

    def _hsum(self, Y: np.ndarray, pos: int) -> np.ndarray:
        return sum((self.HL[i] @ Y[pos - i * self.N] for i in range(1, self.HL.shape[0])), self.HL[0] @ Y[pos])

    def _xhat(self) -> np.ndarray:
        return self._delayed(self.TL, self._zb)

    # ------------------------------------------------------------------ whole record
    def run(self, y: Any, u: Any = None, *, output: str = "x_hat") -> np.ndarray:
        """Estimates ``x̂`` (shape ``(n_x, T)``) for a record ``y`` of shape ``(n_y, T)`` from t = 0.

        Same numbers as calling :meth:`step` on each sample (the streaming state is not
        touched).  ``output="z"`` returns ẑ and ``output="xi"`` the observer state ξ
        (both ``(n_z, T)``) instead of x̂.
        """
        if u is not None:
            raise DimensionError("u was given, but the observer has no known input (n_u = 0)")
        with blas_single_thread():
            return self._run(y, output)

    def _run(self, y: Any, output: str) -> np.ndarray:
        if output not in ("x_hat", "z", "xi"):
            raise SimulationError(f"output={output!r}: expected 'x_hat', 'z' or 'xi'")
        Y = np.asarray(y, dtype=float)
        if Y.ndim == 1 and self.n_y == 1:
            Y = Y[None, :]
        if Y.ndim != 2 or Y.shape[0] != self.n_y or Y.shape[1] < 1:
            raise DimensionError(f"y has shape {np.shape(y)}; expected ({self.n_y}, T) with time on the last axis")
        _finite(Y, "y")
        T = Y.shape[1]
        L, N = self.history_length, self.N
        Yrows = np.concatenate([self._pre(Y[:, 0]), Y.T])  # y(t_j) = Yrows[L + j]
        G = delayed_sum(self.JL, Yrows, -2, T - 1, N, L)  # g at j = −2 … T−1 → G[j + 2]
        xi0 = self._xi_start(Yrows, L)
        if T > 1:
            GT = G.T  # BLAS-friendly orientation (see delayed_sum)
            Gq = (self.W[0] @ GT[:, 0 : T - 1] + self.W[1] @ GT[:, 1:T] + self.W[2] @ GT[:, 2 : T + 1]
                  + self.W[3] @ GT[:, 3 : T + 2]).T
            # steps j → j+1 (row j of Gq) at the start of a guarded block: stay inside it
            end = min(self.guard_blocks * N, T - 1)
            first = np.arange(0, end, N)
            second = first[first + 1 < end] + 1
            Wf, Ws = self.W_first, self.W_second
            Gq[first] = (Wf[0] @ GT[:, first + 2] + Wf[1] @ GT[:, first + 3]).T
            if N > 1:
                Gq[second] = (Ws[0] @ GT[:, second + 1] + Ws[1] @ GT[:, second + 2] + Ws[2] @ GT[:, second + 3]).T
            xi = np.empty((T, self.n_z))
            xi[0] = xi0
            xi[1:] = LinearScan(self.Phi, chunk=16).run(xi0, Gq)
        else:
            xi = xi0[None, :]
        if output == "xi":
            return xi.T
        Z = xi + delayed_sum(self.HL, Yrows, 0, T - 1, N, L)
        if output == "z":
            return Z.T
        Kz = self.lag * N
        Zrows = np.concatenate([np.repeat(Z[:1], Kz, axis=0), Z])
        return delayed_sum(self.TL, Zrows, 0, T - 1, N, Kz).T

    def noise_gain(self, horizon: float | None = None) -> np.ndarray:
        """ℓ¹ norms of the discrete impulse responses, output j → estimate i: shape ``(n_x, n_y)``.

        For output noise with ``|ν_j| ≤ a_j`` (any sequence, ξ(0) independent of y), the
        estimate moves by at most ``Σ_j gain[i, j] a_j`` in component i — the exact
        ∞-norm gain of the discretised observer once its start-up blocks (the guarded
        stencils, see ``guard_blocks``) have been forgotten, i.e. up to a term decaying
        like the slowest observer pole.  ``horizon`` (seconds) defaults to the delays
        plus 40 time constants of the slowest pole.
        """
        rate = -np.max(np.linalg.eigvals(self.L0).real)
        if rate <= 0:
            raise SimulationError("noise_gain: L0 is not Hurwitz, the gain is infinite")
        if horizon is None:
            horizon = 40.0 / rate + (self.JL.shape[0] + self.HL.shape[0] + self.lag + 2) * self.h
        T = int(np.ceil(horizon / self.dt)) + 1
        sub = DelayObserverSimulator.__new__(DelayObserverSimulator)
        sub.__dict__.update(self.__dict__)
        sub._x_hat0, sub._xi0 = None, None
        sub._y_history = np.zeros((self.n_y, self.history_length))
        sub.guard_blocks = 0
        gain = np.empty((self.n_x, self.n_y))
        for j in range(self.n_y):
            y = np.zeros((self.n_y, T))
            y[j, 0] = 1.0
            gain[:, j] = np.abs(sub.run(y)).sum(axis=1)
        return gain

    def __repr__(self) -> str:
        return (
            f"DelayObserverSimulator(n_z={self.n_z}, n_y={self.n_y}, n_x={self.n_x}, h={self.h:g}, "
            f"dt={self.dt:g}, N={self.N}, lag={self.lag}, k={self.k})"
        )


def simulate_observer(
    design: Any,
    sys: Any = None,
    *,
    h: Any = None,
    t_final: Any,
    dt: Any,
    w: Any = None,
    u: Any = None,
    phi: Any = None,
    noise: Any = None,
    x_hat0: Any = None,
    exact_start: bool = False,
    progress: bool | None = None,
) -> SimulationResult:
    """Simulate the plant and the observer of ``design`` on it.

    Parameters are those of :func:`~uio_ring.sim.simulate` (``sys`` defaults to
    ``design.system``), plus

    x_hat0 : array, optional
        Initial estimate (see :class:`DelayObserverSimulator`); default ξ(0) = 0.
    exact_start : bool
        Start the plant earlier, at ``−t_warm`` (φ is its history before that; w must be a
        callable or None), so that x on ``[−t_warm, 0]`` is a trajectory of the system; give
        the observer the true past outputs and ``ξ(0) = T(δ) x(0) − (HΛ)(δ) y(0)``.  Then
        ẑ = z for t ≥ 0 up to integration error, and the only error left comes from ẑ
        before 0 (held at ẑ(0)), which leaves ``x̂ = T_L⁻¹(δ) ẑ`` at ``t = lag·h``: the
        estimate's delay.  ``t_warm = (deg T + deg JΛ + deg HΛ + deg C + 2)·h``.

    Returns
    -------
    SimulationResult
        with ``x_hat`` and ``error = x − x_hat`` (time on the last axis) and ``lag``.
    """
    if sys is None:
        sys = getattr(design, "system", None)
        if sys is None:
            raise SimulationError("sys is required: the design has no system")
    dh = _design_h(design)
    if h is None:
        h = getattr(sys, "h", None) if getattr(sys, "h", None) is not None else dh
    hv = resolve_h(h, getattr(sys, "h", None), what="sys")
    if dh is not None:
        resolve_h(hv, dh, what="the design (design.h): a design is simulated with the plant's h")
    for name in ("E", "F"):
        M = getattr(sys, name, None)
        if M is not None and coefficient_arrays(M, name=name).shape[0] > 0:
            raise NotSupportedError(
                f"sys has a known input (nonzero {name}); the observer of paper 001 is stated for u-free systems"
            )
    if x_hat0 is not None and exact_start:
        raise SimulationError("give x_hat0 or exact_start=True, not both")
    dtv = as_float(dt, "dt")
    obs = DelayObserverSimulator(design, hv, dtv, x_hat0=x_hat0)
    n_x_sys = sys.A.shape[0]
    if (obs.n_x, obs.n_y) != (n_x_sys, sys.C.shape[0]):
        raise DimensionError(
            f"the design is for {obs.n_x} states and {obs.n_y} outputs; sys has {n_x_sys} and {sys.C.shape[0]}"
        )
    if not exact_start:
        res = plant_run(sys, h=hv, t_final=t_final, dt=dtv, w=w, u=u, phi=phi, noise=noise, progress=progress)
    else:
        res = _warm_plant(obs, sys, hv, t_final, w, u, phi, noise, progress)
    x_hat = obs.run(res.y)
    return SimulationResult(
        t=res.t, x=res.x, y=res.y, w=res.w, u=res.u, h=res.h, dt=res.dt,
        state_names=res.state_names, output_names=res.output_names, noise=res.noise,
        x_hat=x_hat, error=res.x - x_hat, lag=obs.lag,
        extra={"observer": obs},
    )


def _warm_plant(obs: DelayObserverSimulator, sys: Any, h: float, t_final: Any, w: Any, u: Any,
                phi: Any, noise: Any, progress: bool | None) -> SimulationResult:
    """Plant run from ``−t_warm``; sets the observer's y history and ξ(0) to the true ones."""
    if w is not None and not callable(w):
        raise SimulationError("w: exact_start=True needs w as a callable of t (or None)")
    if u is not None:
        raise SimulationError("u: exact_start=True is for u-free systems")
    C = coefficient_arrays(sys.C, name="sys.C")
    blocks = (obs.Tc.shape[0] - 1) + (obs.JL.shape[0] - 1) + (obs.HL.shape[0] - 1) + max(C.shape[0] - 1, 0) + 2
    blocks = max(blocks, -(-obs.history_length // obs.N) + 1, obs.guard_blocks + 1)
    s0 = blocks * obs.N
    t_warm = s0 * obs.dt
    w_s = None if w is None else (lambda t: w(np.asarray(t) - t_warm))
    full = plant_run(sys, h=h, t_final=as_float(t_final, "t_final") + t_warm, dt=obs.dt, w=w_s,
                     phi=phi, noise=noise, progress=progress)
    L = obs.history_length
    obs._y_history = full.y[:, s0 - L : s0]
    Xrows, Yrows = full.x.T, full.y.T
    z0 = delayed_sum(obs.Tc, Xrows, 0, 0, obs.N, s0)[0]
    obs._xi0 = z0 - delayed_sum(obs.HL, Yrows, 0, 0, obs.N, s0)[0]
    obs.guard_blocks = 0  # the break points of the plant lie before 0
    sl = slice(s0, None)
    return SimulationResult(
        t=full.t[sl] - t_warm, x=full.x[:, sl], y=full.y[:, sl], w=full.w[:, sl], u=full.u[:, sl],
        h=full.h, dt=full.dt, state_names=full.state_names, output_names=full.output_names,
        noise=None if full.noise is None else full.noise[:, sl],
    )
