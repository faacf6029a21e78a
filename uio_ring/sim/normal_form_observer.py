"""The higher-order sliding-mode observer (13)–(14) of paper 000 in float64.

In normal-form coordinates the observer is ::

    x̂' = M x̂ + Π̄ ȳ + B̄ ū + l̄(σ),   M = Ā − Π̄ C̄ (nilpotent),   σ = ȳ − C̄ x̂

with one Levant robust exact differentiator per chain: row ``k`` of chain ``j``
(``k = 1 … μ_j``) gets ``κ_{j,μ_j−k} [σ_j]^{(μ_j−k)/μ_j}`` (``[σ]^0 = sign σ``).

Discretisation (step ``h = dt``).  The linear part is integrated exactly
(``M`` is nilpotent, so ``e^{Mh}``, ``φ_1``, ``φ_2`` are finite sums), with the
measured signals ``ȳ`` (and ``ỹ_0`` of the feed-through reduction) interpolated
linearly between samples and ``u`` held over the step::

    x̂_{k+1} = e^{Mh} x̂_k + h(φ_1 − φ_2) S s_k + h φ_2 S (s_{k+1} − H_s Γ_u u_k) + Γ_u u_k + h φ_1 l̄(σ_*)

(``s = [ȳ; ỹ_0] = H_s x̄ + …``, ``S = [Π̄, B̄_ỹ0]``, ``Γ_u = ∫_0^h e^{Ā_p r} dr B̄_u``
the exact step response of the plant to the held ``u``).  Removing the known
input's response before interpolating makes the discrete error dynamics
independent of ``u`` even when ``u`` jumps every step (closed loop).  What is
left is the interpolation error of the outputs' free response, ``≈ h³ Π̄ ȳ''/12``
per step: it grows with the plant state and with ``‖Π̄‖``, so large states or
badly scaled normal forms need smaller steps.  A naive
Euler step of the linear part leaves a residual of order ``h·Ā B̄ u`` that no
differentiator rejects (the normal-form coordinates are badly scaled:
``|B̄|`` ≈ 8·10³ in the aircraft example).  The differentiator terms:

``"implicit"`` (default)
    ``σ_* = σ_{k+1}``, with the set-valued sign: the chains are solved in order
    (``M`` is block lower-triangular); in chain j the equation for ``σ_j`` is the
    monotone scalar inclusion ``σ + Σ_k w_k κ_{μ−k} [σ]^{(μ−k)/μ} ∋ a`` with
    ``w = (h, h²/2, h³/6, …) > 0``: ``σ = 0`` when ``|a| ≤ w_μ κ_0`` (the sign takes
    the value ``a / (w_μ κ_0)``), else a polynomial equation in ``|σ|^{1/μ}``
    solved by Newton from the right.  No chattering.
``"explicit"``
    ``σ_* = σ_k`` (explicit Euler of the differentiator terms; chatters, needs small steps).
``"euler"``
    Explicit Euler of the whole observer, ``x̂_{k+1} = x̂_k + h f(x̂_k, s_k, u_k)``
    (the textbook scheme; consistent only with an Euler-discretised plant).

The plant ``x' = A x + B w + E u`` is discretised exactly for ``A`` and the
held ``u``; ``w`` enters through its quadratic interpolation on ``t``,
``t + dt/2``, ``t + dt`` (local error O(dt⁴)).

>>> from uio_ring import DelaySystem, design_normal_form
>>> import numpy as np
>>> des = design_normal_form(DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None), [1])
>>> res = simulate_normal_form_observer(des, t_final=3.0, dt=1e-3, w=lambda t: np.sin(t), x0=[1, 0])
>>> bool(np.abs(res.error[:, -1]).max() < 1e-2)
True
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np
from scipy.linalg import expm

from uio_ring.sim._convert import coefficient_arrays
from uio_ring.sim.errors import DimensionError, NotSupportedError, SimulationError
from uio_ring.sim.result import SimulationResult
from uio_ring.sim.signals import as_noise

__all__ = ["NormalFormObserver", "simulate_normal_form_observer", "METHODS"]

METHODS = ("implicit", "explicit", "euler")


def _const(M: Any, rows: int, cols: int, name: str) -> np.ndarray:
    arr = coefficient_arrays(M, name=name)
    if arr.shape[0] > 1:
        raise SimulationError(f"{name} must be constant (degree 0 in δ)")
    return arr[0] if arr.shape[0] else np.zeros((rows, cols))


def _solve_chain(a: float, coef: list[float], s0: float, mu: int) -> tuple[float, float]:
    """Solve ``σ + Σ_{k=1}^{μ−1} coef_k [σ]^{(μ−k)/μ} + s0·sign(σ) ∋ a``; return ``(σ, sign value)``.

    ``coef_k = w_k κ_{μ−k}`` and ``s0 = w_μ κ_0`` (the sign term's weight).
    With ``s = |σ|^{1/μ}`` the equation for ``|σ|`` is the polynomial
    ``s^μ + Σ_k coef_k s^{μ−k} = |a| − s0`` (increasing and convex for s ≥ 0):
    Newton from ``(|a| − s0)^{1/μ}``, which lies right of the root, decreases monotonically.
    Precondition: ``coef ≥ 0``, ``s0 > 0`` (not checked).

    >>> _solve_chain(0.5, [], 1.0, 1), _solve_chain(3.0, [], 1.0, 1)
    ((0.0, 0.5), (2.0, 1.0))
    """
    if abs(a) <= s0:
        return 0.0, (a / s0 if s0 > 0 else 0.0)
    c = abs(a) - s0
    if mu == 1:
        return math.copysign(c, a), math.copysign(1.0, a)
    s = c ** (1.0 / mu)
    for _ in range(100):
        # Horner: f(s) = s^μ + Σ coef_k s^{μ−k} − c
        f, df = 1.0, 0.0
        for ck in coef:
            df = df * s + f
            f = f * s + ck
        df = df * s + f
        f = f * s - c
        if f <= 0.0 or df <= 0.0:
            break
        s_new = s - f / df
        if s_new >= s or s - s_new <= 1e-15 * s:
            s = max(s_new, 0.0)
            break
        s = s_new
    return math.copysign(s**mu, a), math.copysign(1.0, a)


class NormalFormObserver:
    """The observer of a :class:`~uio_ring.design.normal_form.NormalFormDesign`, step by step.

    Parameters
    ----------
    design
        The design (its float64 image is taken once).
    dt
        Step size.
    method
        ``"implicit"`` (default), ``"explicit"`` or ``"euler"``; see the module docstring.
    x_hat0
        Initial estimate of the model state (plant state, or ``[x; w]`` when the
        design reconstructs the input); default 0.

    Examples
    --------
    ``obs = design.simulator(dt)``; ``obs.start(y0, u0)``; then once per sample
    ``obs.step(y_next, u_next, u_held)`` and ``obs.estimate()``.
    """

    def __init__(self, design: Any, dt: Any, *, method: str = "implicit", x_hat0: Any = None):
        if method not in METHODS:
            raise SimulationError(f"method={method!r}; expected one of {METHODS}")
        self.method = method
        self.dt = float(dt)
        if not (self.dt > 0 and math.isfinite(self.dt)):
            raise SimulationError(f"dt = {dt!r} must be a positive number")
        n = design.n
        self.n = n
        self.mu = tuple(design.mu)
        self.starts = tuple(design.block_starts)
        self.kappa = [np.array([float(k) for k in ks]) for ks in design.kappa]
        A_bar = _const(design.A_bar, n, n, "A_bar")
        Pi = _const(design.Pi_bar, n, len(self.mu), "Pi_bar")
        C_bar = _const(design.C_bar, len(self.mu), n, "C_bar")
        self.M = A_bar - Pi @ C_bar
        sysm = design.system
        self.n_y, self.n_u = sysm.n_y, sysm.n_u
        B_bar = _const(design.B_bar, n, design.B_bar.cols, "B_bar")
        self.B_u, B_y0 = B_bar[:, : self.n_u], B_bar[:, self.n_u :]
        self.output_map = _const(design.output_map, len(self.mu), self.n_y + self.n_u, "output_map")
        input_map = _const(design.input_map, design.input_map.rows, self.n_y + self.n_u, "input_map")
        #: measured signals s = [ȳ; ỹ_0] = S_map [y; u] and their injection S = [Π̄, B̄_ỹ0]
        self.S_map = np.vstack([self.output_map, input_map[self.n_u :]])
        self.S = np.hstack([Pi, B_y0])
        self.state_map = _const(design.state_map, sysm.n_x, n, "state_map")
        self.w_map = None if design.w_map is None else _const(design.w_map, sysm.n_w, n, "w_map")
        T_inv = _const(design.T_inverse, n, n, "T_inverse")
        if x_hat0 is None:
            self.xbar = np.zeros(n)
        else:
            x0 = np.asarray(x_hat0, dtype=float).reshape(-1)
            if x0.shape != (n,):
                raise DimensionError(f"x_hat0 has shape {np.shape(x_hat0)}; expected ({n},) (the model state)")
            self.xbar = T_inv @ x0
        h = self.dt
        # M is nilpotent: e^{Mh}, φ1, φ2 are finite sums (exact up to rounding)
        Phi, phi1, phi2 = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
        P = np.eye(n)
        fact = 1.0
        for i in range(n + 1):
            Phi += P / fact
            phi1 += P / (fact * (i + 1))
            phi2 += P / (fact * (i + 1) * (i + 2))
            P = P @ (self.M * h)
            fact *= i + 1
        self.Phi = Phi
        self.S0 = h * (phi1 - phi2) @ self.S
        self.S1 = h * phi2 @ self.S
        # the known input's exact effect over a step: Γ_u = ∫_0^h e^{Ā_p r} dr B̄_u, with the plant
        # matrix Ā_p = Ā + B̄_ỹ0 C̃_0 T in normal-form coordinates; its effect on the measured
        # signals (H_s Γ_u u_k) is removed before interpolating, so ZOH steps of u leave no residual
        H_s = np.vstack([C_bar, input_map[self.n_u :, : self.n_y] @ _const(sysm.C, self.n_y, sysm.n_x, "C")
                         @ self.state_map])
        A_p = A_bar + B_y0 @ H_s[len(self.mu) :]
        blk = np.zeros((n + self.n_u, n + self.n_u))
        blk[:n, :n], blk[:n, n:] = A_p * h, self.B_u * h
        self.Gu = expm(blk)[:n, n:]
        self.S1u = self.S1 @ H_s @ self.Gu
        self._Gu_eff = self.Gu - self.S1u
        self.Kl = h * phi1
        # chain j's own weights in σ_j: Kl[b_j, block j] = (h, h²/2, h³/6, …) > 0
        self.weights = [self.Kl[s, s : s + m].copy() for s, m in zip(self.starts, self.mu, strict=True)]
        for j, wj in enumerate(self.weights):
            if np.any(wj <= 0):  # pragma: no cover - w = (h, h²/2, …) by construction
                raise SimulationError(f"chain {j + 1}: nonpositive implicit weights {wj}")
        self._coef = [[float(w[k - 1] * kap[k - 1]) for k in range(1, m)]
                      for w, kap, m in zip(self.weights, self.kappa, self.mu, strict=True)]
        self._s0 = [float(w[m - 1] * kap[m - 1]) for w, kap, m in zip(self.weights, self.kappa, self.mu, strict=True)]
        self._kap = [[float(k) for k in kap] for kap in self.kappa]
        self._exp = [[(m - k) / m for k in range(1, m + 1)] for m in self.mu]
        self._Kl_rows = [self.Kl[s].copy() for s in self.starts]
        self.exponents = [np.array([(m - k) / m for k in range(1, m + 1)]) for m in self.mu]
        self._sel = list(self.starts)
        self._s_prev: np.ndarray | None = None

    # ---------------------------------------------------------------- pieces
    def _signals(self, y: Any, u_y: Any) -> np.ndarray:
        y = np.asarray(y, dtype=float).reshape(-1)
        if y.shape != (self.n_y,):
            raise DimensionError(f"y has shape {y.shape}; expected ({self.n_y},)")
        u = np.zeros(self.n_u) if u_y is None else np.asarray(u_y, dtype=float).reshape(-1)
        return self.S_map @ np.concatenate([y, u])

    def _l(self, sigma: np.ndarray) -> np.ndarray:
        out = np.zeros(self.n)
        for j, (s, m) in enumerate(zip(self.starts, self.mu, strict=True)):
            sj = sigma[j]
            out[s : s + m] = self.kappa[j] * np.abs(sj) ** self.exponents[j] * np.sign(sj)
        return out

    def start(self, y0: Any, u0: Any = None) -> None:
        """Give the measurement at ``t = 0`` (and the known input that entered it)."""
        self._s_prev = self._signals(y0, u0)

    def step(self, y_next: Any, u_next: Any = None, u_held: Any = None) -> np.ndarray:
        """From ``t_k`` to ``t_{k+1}``: ``y_next`` is measured at ``t_{k+1}`` (with the known
        input ``u_next`` in it), ``u_held`` drives the plant on ``[t_k, t_{k+1})``
        (default ``u_next``).  Returns the new normal-form state ``x̂̄``."""
        if self._s_prev is None:
            raise SimulationError("call start(y0, u0) before the first step")
        s1 = self._signals(y_next, u_next)
        s0 = self._s_prev
        uh = np.zeros(self.n_u) if u_held is None and u_next is None else np.asarray(
            u_next if u_held is None else u_held, dtype=float).reshape(-1)
        self._s_prev = s1
        self.xbar = self._advance(s0, s1, uh)
        return self.xbar

    def _advance(self, s0: np.ndarray, s1: np.ndarray, uh: np.ndarray) -> np.ndarray:
        """One step on signals already mapped (precondition: shapes fit; not checked)."""
        p = len(self.mu)
        if self.method == "euler":
            sigma = s0[:p] - self.xbar[self._sel]
            f = self.M @ self.xbar + self.S @ s0 + self.B_u @ uh + self._l(sigma)
            return self.xbar + self.dt * f
        lin = self.Phi @ self.xbar + self.S0 @ s0 + self.S1 @ s1
        if self.n_u:
            lin += self._Gu_eff @ uh
        if self.method == "explicit":
            sigma = s0[:p] - self.xbar[self._sel]
            return lin + self.Kl @ self._l(sigma)
        lvec = np.zeros(self.n)
        for j, (s, m) in enumerate(zip(self.starts, self.mu, strict=True)):
            a = float(s1[j] - lin[s])
            if j:
                a -= float(self._Kl_rows[j] @ lvec)  # earlier chains only (block triangular)
            sig, sg = _solve_chain(a, self._coef[j], self._s0[j], m)
            kap, ex = self._kap[j], self._exp[j]
            if sig == 0.0:
                lvec[s + m - 1] = kap[m - 1] * sg
            else:
                mag, sgn = abs(sig), math.copysign(1.0, sig)
                for k in range(m - 1):
                    lvec[s + k] = kap[k] * mag ** ex[k] * sgn
                lvec[s + m - 1] = kap[m - 1] * sg
        return lin + self.Kl @ lvec

    def estimate(self) -> np.ndarray:
        """The plant-state estimate ``state_map · x̂̄``."""
        return self.state_map @ self.xbar

    def input_estimate(self) -> np.ndarray | None:
        """``ŵ = w_map · x̂̄`` (designs with ``reconstruct_input``), else ``None``."""
        return None if self.w_map is None else self.w_map @ self.xbar

    def __repr__(self) -> str:
        return f"NormalFormObserver(n={self.n}, mu={self.mu}, dt={self.dt:g}, method={self.method!r})"


def _sample(fn: Any, t: np.ndarray, n: int, name: str) -> np.ndarray:
    """Samples ``(n, len(t))`` of a callable of t (vectorised if it can be), a constant, or None."""
    if n == 0:
        return np.zeros((0, len(t)))
    if fn is None:
        return np.zeros((n, len(t)))
    if not callable(fn):
        v = np.asarray(fn, dtype=float).reshape(-1)
        if v.shape != (n,):
            raise DimensionError(f"{name} has shape {np.shape(fn)}; expected a callable of t or a constant ({n},)")
        return np.repeat(v[:, None], len(t), axis=1)
    try:
        out = np.asarray(fn(t), dtype=float)
        if out.shape == (len(t),) and n == 1:
            out = out[None, :]
        if out.shape != (n, len(t)):
            raise ValueError
    except (ValueError, TypeError):
        out = np.array([np.asarray(fn(float(tk)), dtype=float).reshape(n) for tk in t]).T.reshape(n, len(t))
    if not np.all(np.isfinite(out)):
        raise SimulationError(f"{name} is not finite on the grid")
    return out


def _plant_discretisation(A: np.ndarray, B: np.ndarray, E: np.ndarray, h: float) -> tuple[np.ndarray, ...]:
    """``e^{Ah}`` and the weights of ``w(t_k), w(t_k + h/2), w(t_{k+1})`` and of the held ``u``.

    ``∫_0^h e^{A(h−s)} B w(t_k + s) ds`` with ``w`` interpolated quadratically on the three
    nodes: ``h(φ1 − 3φ2 + 4φ3)``, ``h(4φ2 − 8φ3)``, ``h(−φ2 + 4φ3)`` times ``B`` (φ_j(hA)
    from one exponential of an augmented matrix).
    """
    n = A.shape[0]
    Z = np.zeros((4 * n, 4 * n))
    Z[:n, :n] = A * h
    Z[:n, n : 2 * n] = np.eye(n)
    Z[n : 2 * n, 2 * n : 3 * n] = np.eye(n)
    Z[2 * n : 3 * n, 3 * n :] = np.eye(n)
    F = expm(Z)
    Pd = F[:n, :n]
    phi1, phi2, phi3 = F[:n, n : 2 * n], F[:n, 2 * n : 3 * n], F[:n, 3 * n :]
    G0 = h * (phi1 - 3 * phi2 + 4 * phi3) @ B
    Gm = h * (4 * phi2 - 8 * phi3) @ B
    G1 = h * (-phi2 + 4 * phi3) @ B
    Ge = h * phi1 @ E
    return Pd, G0, Gm, G1, Ge


def simulate_normal_form_observer(
    design: Any,
    sys: Any = None,
    *,
    t_final: Any,
    dt: Any,
    w: Any = None,
    u: Any = None,
    feedback: Callable[[float, np.ndarray, np.ndarray | None], Any] | None = None,
    x0: Any = None,
    x_hat0: Any = None,
    method: str = "implicit",
    noise: Any = None,
) -> SimulationResult:
    """Simulate a delay-free plant and the normal-form observer on it.

    Parameters
    ----------
    design
        A :class:`~uio_ring.design.normal_form.NormalFormDesign`.
    sys
        The plant (default ``design.system``).
    t_final, dt
        Horizon and step.
    w, u
        Unknown and known inputs: callables of t (vectorised or scalar), constants, or None (zero).
    feedback
        ``feedback(t, x_hat, w_hat) -> u`` instead of ``u`` (closed loop, as in
        paper 000 Section 5.4); ``u`` is held over each step.
    x0, x_hat0
        Plant initial state (default 0) and initial estimate of the model state
        (default 0; ``[x̂; ŵ]`` when the design reconstructs the input).
    method
        ``"implicit"`` (default), ``"explicit"`` or ``"euler"``; see the module docstring.
    noise
        Bounded output noise: an amplitude (per output or one for all) or a
        :class:`~uio_ring.sim.UniformNoise`; added to the measured ``y`` (the
        plant is unaffected).

    Returns
    -------
    SimulationResult
        ``x``, ``y``, ``w``, ``u``, ``x_hat`` and ``error = x − x_hat`` (time on
        the last axis; ``h = dt``).  ``extra`` holds ``w_hat`` and ``w_error``
        (input reconstruction), ``method`` and the observer.
    """
    if sys is None:
        sys = design.system
    if not sys.is_delay_free:
        raise NotSupportedError("the plant has delays; the normal-form observer is for delay-free systems")
    if feedback is not None and u is not None:
        raise SimulationError("give u or feedback, not both")
    n, m, p, nu = sys.n_x, sys.n_w, sys.n_y, sys.n_u
    A, B, C = _const(sys.A, n, n, "A"), _const(sys.B, n, m, "B"), _const(sys.C, p, n, "C")
    D, E, F = _const(sys.D, p, m, "D"), _const(sys.E, n, nu, "E"), _const(sys.F, p, nu, "F")
    if feedback is not None and np.any(F):
        raise NotSupportedError("feedback with a known-input feed-through F ≠ 0 is an algebraic loop")
    dtv = float(dt)
    steps = int(round(float(t_final) / dtv))
    if steps < 1:
        raise SimulationError(f"t_final = {t_final!r} is shorter than one step dt = {dt!r}")
    t = np.arange(steps + 1) * dtv
    W = _sample(w, t, m, "w")
    Wh = _sample(w, t[:-1] + 0.5 * dtv, m, "w")
    Uo = None if feedback is not None else _sample(u, t, nu, "u")
    obs = NormalFormObserver(design, dtv, method=method, x_hat0=x_hat0)
    x = np.zeros(n) if x0 is None else np.asarray(x0, dtype=float).reshape(-1)
    if x.shape != (n,):
        raise DimensionError(f"x0 has shape {np.shape(x0)}; expected ({n},)")
    X = np.empty((n, steps + 1))
    Y = np.empty((p, steps + 1))
    nz = as_noise(noise)
    Nz = np.zeros((p, steps + 1)) if nz is None else nz.samples(p, steps + 1)
    Uall = np.zeros((nu, steps + 1))

    # plant: exact for A and the held u; w by quadratic interpolation on (t_k, t_k + h/2, t_{k+1})
    Pd, G0, Gm, G1, Ge = _plant_discretisation(A, B, E, dtv)
    Wf = G0 @ W[:, :-1] + Gm @ Wh + G1 @ W[:, 1:]  # (n, steps)
    if Uo is not None:
        Wf = Wf + Ge @ Uo[:, :-1]
    XB = np.empty((obs.n, steps + 1))
    S_y, S_u = obs.S_map[:, :p], obs.S_map[:, p:]

    def u_at(k: int) -> np.ndarray:
        if Uo is not None:
            return Uo[:, k]
        assert feedback is not None  # one of u / feedback (checked above)
        return np.asarray(feedback(t[k], obs.estimate(), obs.input_estimate()), dtype=np.float64).reshape(nu)

    uk = u_at(0)
    X[:, 0] = x
    Y[:, 0] = C @ x + D @ W[:, 0] + F @ uk + Nz[:, 0]
    obs.start(Y[:, 0], uk)
    XB[:, 0] = obs.xbar
    s_prev: np.ndarray = obs._signals(Y[:, 0], uk)
    for k in range(steps):
        Uall[:, k] = uk
        x = Pd @ x + Wf[:, k]
        if Uo is None:
            x += Ge @ uk
        y_new = C @ x + D @ W[:, k + 1] + F @ uk + Nz[:, k + 1]
        s_new = S_y @ y_new + S_u @ uk if nu else S_y @ y_new
        obs.xbar = obs._advance(s_prev, s_new, uk)
        s_prev = s_new
        X[:, k + 1] = x
        Y[:, k + 1] = y_new
        XB[:, k + 1] = obs.xbar
        if k % 1024 == 0 and not np.all(np.isfinite(obs.xbar)):
            raise SimulationError(f"the observer diverged near t = {t[k + 1]:g} (method={method!r}, dt={dtv:g})")
        if Uo is None:
            uk = u_at(k + 1)
        else:
            uk = Uo[:, k + 1]
    obs._s_prev = s_prev
    Uall[:, steps] = uk
    if not np.all(np.isfinite(XB)):
        raise SimulationError(f"the observer diverged (method={method!r}, dt={dtv:g})")
    XH = obs.state_map @ XB
    WH = None if obs.w_map is None else obs.w_map @ XB
    extra: dict[str, Any] = {"method": method, "observer": obs}
    if WH is not None:
        extra["w_hat"] = WH
        extra["w_error"] = W - WH
    return SimulationResult(
        t=t, x=X, y=Y, w=W, u=Uall, h=dtv, dt=dtv,
        state_names=sys.state_names, output_names=sys.output_names, noise=None if nz is None else Nz,
        x_hat=XH, error=X - XH, extra=extra,
    )
