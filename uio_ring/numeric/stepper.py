"""The discrete observer: one stepper for every :class:`~uio_ring.numeric.model.ObserverModel`.

Protocol (the same for every method)::

    stepper = design.numeric().stepper(dt)
    x_hat_0 = stepper.start(y_0, u_0)           # t = 0
    x_hat_k = stepper.step(y_k, u_k)            # once per sample, t_k = k·dt
    X_hat   = stepper.run(Y, U)                 # a whole record (same numbers as start/step)

Discretisation of ``ξ' = F ξ + g(t) + l(σ)`` with ``g = G_y(δ) y + G_u(δ) u`` on the
grid ``dt = h/N`` (a delay-free model takes ``h = dt``):

* the linear part exactly: ``ξ_{k+1} = e^{F dt} ξ_k + Σ_m W_m g_{k+q_m} (+ injection)``,
  the forcing interpolated through the nodes ``q_m`` — ``"cubic"``: the causal
  four-point stencil ``k−2 … k+1`` (local error O(dt⁵); in the first
  ``guard_blocks`` blocks, where y may have derivative jumps at the multiples of h,
  the stencil stays inside the block); ``"linear"``: the nodes ``k, k+1``;
* a known input held over the step (closed loop) with the model's
  :class:`~uio_ring.numeric.model.HeldInput`: its exact effect is added and removed
  from the forcing before interpolating, so that jumps of u leave no residual;
* the injection term (:class:`~uio_ring.numeric.model.LevantInjection`) ``"implicit"``
  (backward Euler: σ at ``t_{k+1}`` with the set-valued sign, the term entering with the
  right-endpoint weight ``dt·e^{F dt}`` — in sliding, a chain's derivative estimate is the
  backward difference of its input, so no step-to-step oscillation is left and a cascade
  of differentiators stays first order in dt; chains solved in order),
  ``"explicit"`` (σ at ``t_k``) or ``"euler"`` (explicit Euler of the whole observer).
  Bi-homogeneous chains (a ``profiles`` entry, Moreno's injection) take the same implicit
  step: σ at ``t_{k+1}`` solves the scalar, odd, strictly increasing inclusion
  ``σ + Σ_k w_k κ_k Φ_k(σ) ∋ a`` (σ = 0 inside the jump of the sign part when d0 = −1,
  else bracketed Newton, :func:`~uio_ring.numeric.bihom.solve_bihom_chain`).

Before the first sample, y and u are held at their first value unless histories
are given; ẑ is held at ẑ(0).

>>> import numpy as np
>>> from uio_ring.numeric.model import ObserverModel
>>> m = ObserverModel(F=np.array([[-2.0]]), G_y=np.array([[[2.0]]]), X=np.array([[[1.0]]]))
>>> s = m.stepper(0.01)
>>> x = s.run(np.ones((1, 501)))            # ξ' = −2ξ + 2y with y = 1: ξ → 1
>>> round(float(x[0, -1]), 6)
0.999955
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.linalg import expm

from uio_ring.errors import DimensionError, SimulationError
from uio_ring.numeric.bihom import chain_exponents, phi_values, solve_bihom_chain
from uio_ring.numeric.expint import LinearScan, phi_functions, stencil_weights
from uio_ring.numeric.grid import as_float, steps_per_delay
from uio_ring.numeric.model import DISCRETISATIONS, ObserverModel
from uio_ring.numeric.nonlinearity import check_phi
from uio_ring.numeric.taps import delayed_sum
from uio_ring.numeric.threads import blas_single_thread

__all__ = ["ObserverStepper", "ObserverTrajectories", "solve_chain"]

_NODES = (-2, -1, 0, 1)  # cubic stencil of the step k → k+1, relative to t_k
_NODES_FIRST = (0, 1)  # first step of a guarded block (and the linear stencil)
_NODES_SECOND = (-1, 0, 1)  # second step of a guarded block


@dataclass(frozen=True, eq=False)
class ObserverTrajectories:
    """What a whole run gives: ``x_hat`` ``(n_x, T)``, ``w_hat`` ``(n_w, T)`` or None, and the
    observer's ``z`` (ẑ) and state ``xi`` (ξ), both ``(n_z, T)``."""

    x_hat: np.ndarray
    w_hat: np.ndarray | None
    z: np.ndarray
    xi: np.ndarray


def solve_chain(a: float, coef: list[float], s0: float, mu: int) -> tuple[float, float]:
    """Solve ``σ + Σ_{k=1}^{μ−1} coef_k ⌈σ⌋^{(μ−k)/μ} + s0·sign(σ) ∋ a``; return ``(σ, sign value)``.

    ``coef_k = w_k κ_{μ−k}`` and ``s0 = w_μ κ_0`` (the sign term's weight).  With
    ``s = |σ|^{1/μ}`` the equation for ``|σ|`` is the polynomial
    ``s^μ + Σ_k coef_k s^{μ−k} = |a| − s0`` (increasing and convex for s ≥ 0):
    Newton from ``(|a| − s0)^{1/μ}``, right of the root, decreases monotonically.
    Precondition: ``coef ≥ 0``, ``s0 > 0`` (not checked).

    >>> solve_chain(0.5, [], 1.0, 1), solve_chain(3.0, [], 1.0, 1)
    ((0.0, 0.5), (2.0, 1.0))
    """
    if abs(a) <= s0:
        return 0.0, (a / s0 if s0 > 0 else 0.0)
    c = abs(a) - s0
    if mu == 1:
        return math.copysign(c, a), math.copysign(1.0, a)
    s = c ** (1.0 / mu)
    for _ in range(100):
        f, df = 1.0, 0.0  # Horner: f(s) = s^μ + Σ coef_k s^{μ−k} − c
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


def _as_index(idx: np.ndarray) -> Any:
    """A slice for evenly spaced increasing indices (a view, no gather), else the array."""
    if len(idx) == 1 or (len(idx) > 1 and np.all(np.diff(idx) == idx[1] - idx[0]) and idx[1] > idx[0]):
        step = int(idx[1] - idx[0]) if len(idx) > 1 else 1
        return slice(int(idx[0]), int(idx[-1]) + 1, step)
    return idx


def _finite(a: np.ndarray, name: str) -> None:
    bad = ~np.isfinite(a)
    if bad.any():
        idx = tuple(int(i) for i in np.argwhere(bad)[0])
        raise SimulationError(f"{name} is not finite at index {idx}: {a[idx]}")


def _vector(v: Any, n: int, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=float).reshape(-1)
    if a.shape != (n,):
        raise DimensionError(f"{name} has shape {np.shape(v)}; expected ({n},)")
    _finite(a, name)
    return a


def _tap(M: np.ndarray, rows: np.ndarray, pos: int, N: int) -> np.ndarray:
    """``Σ_i M_i s(t − i h)`` where ``rows[pos]`` is ``s(t)`` (precondition: in range)."""
    out = M[0] @ rows[pos]
    for i in range(1, M.shape[0]):
        out = out + M[i] @ rows[pos - i * N]
    return out


class _Injection:
    """Float tables of a :class:`LevantInjection` for step ``dt`` and ``Kl = dt φ1(F dt)``.

    With ``R_j = sigma_xi[j] − e_{s_j}ᵀ`` (``s_j`` the chain's first state), ``σ_j`` at the
    new time is ``meas_j + R_j (lin + Kl l)``; the weights of chain j's own terms in it,
    ``w = −R_j Kl[:, chain j]``, must be positive (the step is then a monotone scalar
    inclusion per chain) and ``R_j`` must not see later chains' terms (the chains are
    solved in order).
    """

    def __init__(self, inj: Any, Kl: np.ndarray, n: int):
        self.inj = inj
        self.method = inj.discretisation
        self.starts, self.mu = tuple(inj.starts), tuple(inj.lengths)
        self.kap = [[float(k) for k in g] for g in inj.gains]
        self.kappa = [np.array(g) for g in self.kap]
        self.exp = [[(m - k) / m for k in range(1, m + 1)] for m in self.mu]
        self.exponents = [np.array(e) for e in self.exp]
        # bi-homogeneous chains (None: Levant's): (p_0, p_∞, μ) and the last step's |σ| (Newton's start)
        self.bihom: list[tuple[list[float], list[float], float] | None] = []
        for j, m in enumerate(self.mu):
            prof = inj.profile(j)
            self.bihom.append(None if prof is None else (*chain_exponents(m, prof[0], prof[1]), prof[2]))
        self._guess = [0.0] * len(self.mu)
        self.Kl, self.n = Kl, n
        p = len(self.starts)
        Sxi = np.zeros((p, n)) if inj.sigma_xi is None else np.asarray(inj.sigma_xi, float)
        self.Sxi = Sxi if np.any(Sxi) else None
        R = Sxi.copy()
        R[np.arange(p), list(self.starts)] -= 1.0
        self.R = R
        RK = R @ Kl  # (p, n): how σ_j moves with each injected term
        scale = max(float(np.abs(RK).max()), 1e-300)
        weights = []
        for j, (s, m) in enumerate(zip(self.starts, self.mu, strict=True)):
            wj = -RK[j, s : s + m]
            if np.any(wj <= 0):
                raise SimulationError(f"chain {j + 1}: the implicit weights {wj} are not positive "
                                      "(the model's F is not in normal form)")
            later = [c for c in range(j + 1, p)]
            for c in later:
                sc, mc = self.starts[c], self.mu[c]
                if np.any(np.abs(RK[j, sc : sc + mc]) > 1e-12 * scale):
                    raise SimulationError(f"chain {j + 1}: its σ sees the terms of the later chain {c + 1}; "
                                          "order the chains so that each reads only earlier ones")
            weights.append(wj)
        self.coef = [[float(w[k - 1] * kap[k - 1]) for k in range(1, m)]
                     for w, kap, m in zip(weights, self.kap, self.mu, strict=True)]
        self.s0 = [float(w[m - 1] * kap[m - 1]) for w, kap, m in zip(weights, self.kap, self.mu, strict=True)]
        self.RK = RK
        self.Sy, self.Su = np.asarray(inj.sigma_y, float), np.asarray(inj.sigma_u, float)
        self.layers = self._layers(scale)

    def _layers(self, scale: float) -> list[tuple[np.ndarray, list[int]]]:
        """Consecutive chains that do not see each other, solved together: ``(index array of
        the chains of length 2 (closed form, one pass), other chains (one at a time))``."""
        out: list[list[int]] = []
        for j in range(len(self.starts)):
            cur = out[-1] if out else None
            sees = cur is not None and any(
                np.any(np.abs(self.RK[j, self.starts[c] : self.starts[c] + self.mu[c]]) > 1e-12 * scale)
                for c in cur)
            if cur is None or sees:
                out.append([j])
            else:
                cur.append(j)
        layers = []
        for group in out:
            closed = [j for j in group if self.mu[j] == 2 and self.bihom[j] is None]
            pairs = np.array(closed, dtype=int)
            layers.append((pairs, [j for j in group if j not in closed]))
        self._pair_tables = [self._pair_table(pairs, first=i == 0) for i, (pairs, _) in enumerate(layers)]
        self._plan = [(table, others) for table, (_, others) in zip(self._pair_tables, layers, strict=True)]
        return layers

    def _pair_table(self, idx: np.ndarray, first: bool) -> tuple[Any, ...] | None:
        """Per-step constants of one layer's super-twisting chains: where their σ sits in the
        list of σ values (a slice), the rows ``RK`` that add the earlier layers' terms (None
        for the first layer), where their two injected terms sit (slices when evenly spaced:
        no gather), and per chain the tuple ``(c1, c1², s0, κ_1/2, κ_2)``."""
        if not len(idx):
            return None
        st = np.array([self.starts[j] for j in idx])
        at = _as_index(idx)
        both = np.stack([st, st + 1], axis=1).reshape(-1)  # [top, sign] of each chain, in order
        rows = tuple((float(self.coef[j][0]), float(self.coef[j][0]) * float(self.coef[j][0]), float(self.s0[j]),
                      float(0.5 * self.kap[j][0]), float(self.kap[j][1])) for j in idx.tolist())
        return (at if isinstance(at, slice) else slice(None), None if isinstance(at, slice) else at.tolist(),
                None if first else self.RK[idx], _as_index(both), rows)

    def measured(self, y: np.ndarray, u: np.ndarray) -> np.ndarray:
        out = self.Sy @ y
        return out + self.Su @ u if self.Su.shape[1] else out

    def sigma(self, meas: np.ndarray, xi: np.ndarray) -> np.ndarray:
        """``σ = meas + sigma_xi ξ − ξ[starts]`` at one time."""
        return meas + self.R @ xi

    def l_of(self, sigma: np.ndarray) -> np.ndarray:
        out = np.zeros(self.n)
        for j, (s, m) in enumerate(zip(self.starts, self.mu, strict=True)):
            sj = sigma[j]
            bh = self.bihom[j]
            if bh is None:
                out[s : s + m] = self.kappa[j] * np.abs(sj) ** self.exponents[j] * np.sign(sj)
            else:
                out[s : s + m] = self.kappa[j] * np.array(phi_values(float(sj), *bh))
        return out

    def implicit(self, lin: np.ndarray, meas_next: np.ndarray) -> np.ndarray:
        """``lin + Kl l(σ_{k+1})`` with σ_{k+1} solved layer by layer (block triangular); in a
        layer, the chains of length 2 (super-twisting) by their closed form at once."""
        lvec = np.zeros(self.n)
        self._solve_layers(meas_next + self.R @ lin, lvec)  # σ with no injection at all, then the terms
        return lin + self.Kl @ lvec

    def implicit_run(self, Phi: np.ndarray, Fq: np.ndarray, Meas: np.ndarray, Xi: np.ndarray, k0: int,
                     k1: int) -> None:
        """Rows ``k0 … k1−1`` of ``Xi`` from row ``k0 − 1``: the steps of :meth:`implicit` with
        ``lin = Phi ξ + Fq[k−1]`` and ``meas_next = Meas[k]`` — the same floating-point
        operations in the same order (so the same numbers), without per-step allocations of
        ``lin`` and ``ξ``."""
        R, Kl, n, solve = self.R, self.Kl, self.n, self._solve_layers
        lin = np.empty(n)
        xi = Xi[k0 - 1]
        for k in range(k0, k1):
            np.matmul(Phi, xi, out=lin)
            np.add(lin, Fq[k - 1], out=lin)
            lvec = np.zeros(n)
            solve(Meas[k] + R @ lin, lvec)
            xi = Xi[k]
            np.add(lin, Kl @ lvec, out=xi)

    def _solve_layers(self, base: np.ndarray, lvec: np.ndarray) -> None:
        """The injected terms ``lvec`` (zero on entry) from σ without injection, ``base``."""
        blist = base.tolist()
        for table, others in self._plan:
            if table is not None:
                # chains of length 2 (super-twisting), closed form: s = |σ|^½ solves s² + c1 s = |a| − s0
                # (σ = 0 while |a| ≤ s0: sliding, the sign term's value is a/s0).  Scalar floats: for the
                # few chains of a layer, cheaper per step than array calls (the same IEEE operations)
                at, gather, RKl, both, rows = table
                a = blist[at] if gather is None else [blist[i] for i in gather]
                if RKl is not None:
                    a = [x + y for x, y in zip(a, (RKl @ lvec).tolist(), strict=True)]
                vals: list[float] = []
                for aj, (c1j, c1sqj, s0j, khj, ksj) in zip(a, rows, strict=True):
                    mag = abs(aj)
                    if mag > s0j:
                        vals += (khj * math.copysign(math.sqrt(c1sqj + 4.0 * (mag - s0j)) - c1j, aj),
                                 ksj * (aj / mag))
                    else:  # sliding: σ = 0, the sign term takes the value a/s0 ∈ [−1, 1]
                        vals += (0.0, ksj * (aj / s0j))
                lvec[both] = vals
            for j in others:
                self._solve_one(j, float(base[j] + self.RK[j] @ lvec), lvec)

    def _solve_one(self, j: int, a: float, lvec: np.ndarray) -> None:
        s, m = self.starts[j], self.mu[j]
        kap, bh = self.kap[j], self.bihom[j]
        if bh is not None:  # bi-homogeneous chain: a monotone scalar equation in σ (set-valued at 0 if d0 = −1)
            sig, v = solve_bihom_chain(a, [*self.coef[j], self.s0[j]], *bh, guess=self._guess[j])
            self._guess[j] = abs(sig)
            if sig == 0.0:
                lvec[s : s + m - 1] = 0.0
                lvec[s + m - 1] = kap[m - 1] * (v / self.s0[j])
            else:
                lvec[s : s + m] = np.multiply(kap, phi_values(sig, *bh))
            return
        sig, sg = solve_chain(a, self.coef[j], self.s0[j], m)
        ex = self.exp[j]
        if sig == 0.0:
            lvec[s + m - 1] = kap[m - 1] * sg
        else:
            mag, sgn = abs(sig), math.copysign(1.0, sig)
            for k in range(m - 1):
                lvec[s + k] = kap[k] * mag ** ex[k] * sgn
            lvec[s + m - 1] = kap[m - 1] * sg


class ObserverStepper:
    """An :class:`ObserverModel` on the grid ``dt`` (``dt = h/N`` for a delay model).

    Parameters
    ----------
    model : ObserverModel
    dt : float
    discretisation : str, optional
        Overrides the injection term's discretisation (``"implicit"``, ``"explicit"``, ``"euler"``).
    guard_blocks : int, optional
        Overrides ``model.guard_blocks`` (0 when y is smooth across the multiples of h).
    kernel : str, optional
        Backend of the step loop of :meth:`trajectories` for models with an injection term:
        ``"auto"``, ``"python"`` or ``"numba"`` (default: ``$UIO_RING_KERNEL``, else ``"auto"``;
        see :mod:`uio_ring.numeric.backend`).  The attribute ``kernel`` says which one runs
        (``"python"`` for linear models, bi-homogeneous chains and the streaming :meth:`step`).
    """

    def __init__(self, model: ObserverModel, dt: Any, *, discretisation: str | None = None,
                 guard_blocks: int | None = None, kernel: str | None = None):
        if discretisation is not None:
            if discretisation not in DISCRETISATIONS:
                raise SimulationError(f"discretisation={discretisation!r}; expected one of {DISCRETISATIONS}")
            model = model.with_discretisation(discretisation)
        self.model = model
        dtv = as_float(dt, "dt")
        if model.h is None and model.max_delay > 0:
            raise SimulationError("the model has delayed taps but no h (the basic delay): "
                                  "design.numeric(h=…)")
        if model.h is None:
            self.h, self.N = dtv, 1
        else:
            self.h = float(model.h)
            self.N = steps_per_delay(self.h, dtv)
        self.dt = self.h / self.N
        self.n_z, self.n_y, self.n_u, self.n_x, self.n_w = model.n_z, model.n_y, model.n_u, model.n_x, model.n_w
        self.lag = model.lag
        self.guard_blocks = model.guard_blocks if guard_blocks is None else int(guard_blocks)
        if self.guard_blocks < 0:
            raise SimulationError(f"guard_blocks={guard_blocks} must be ≥ 0")
        nz = self.n_z
        F = model.F
        self.cubic = model.interpolation == "cubic"
        phis = phi_functions(F * self.dt, 4)
        self.Phi = phis[0]
        self.W_first = stencil_weights(F * self.dt, self.dt, _NODES_FIRST, phis)
        self.W = stencil_weights(F * self.dt, self.dt, _NODES, phis) if self.cubic else self.W_first
        self.W_second = stencil_weights(F * self.dt, self.dt, _NODES_SECOND, phis)
        # injection weight: right endpoint (backward Euler) for the implicit step, exact for a
        # term held over the step (dt φ1) for the explicit ones
        implicit = model.injection is not None and model.injection.discretisation == "implicit"
        self.Kl = self.dt * (phis[0] if implicit else phis[1])
        z = np.zeros
        self.Gy = model.G_y if model.G_y.shape[0] else z((1, nz, self.n_y))
        self.Gu = model.G_u if model.G_u.shape[0] else z((1, nz, self.n_u))
        self.Dy = model.D_y if model.D_y.shape[0] else z((1, nz, self.n_y))
        self.Du = model.D_u if model.D_u.shape[0] else z((1, nz, self.n_u))
        self.X = model.X if model.X.shape[0] else z((1, self.n_x, nz))
        self.Wm = None if model.W is None else (model.W if model.W.shape[0] else z((1, self.n_w, nz)))
        N = self.N
        kg = max(self.Gy.shape[0], self.Gu.shape[0]) - 1
        kd = max(self.Dy.shape[0], self.Du.shape[0]) - 1
        #: samples of y and u before t = 0 that the observer reads
        self.history_length = max(kg * N + 2, kd * N, 2)
        self.inj = None if model.injection is None else _Injection(model.injection, self.Kl, nz)
        self._held = None
        if model.held_input is not None and self.n_u:
            hi = model.held_input
            n = hi.A.shape[0]
            blk = np.zeros((n + self.n_u, n + self.n_u))
            blk[:n, :n], blk[:n, n:] = hi.A * self.dt, hi.B * self.dt
            Gam = expm(blk)[:n, n:]
            self._held = (Gam, hi.M @ Gam, hi.B)  # exact effect on ξ and on g_{k+1}; direct term
        self.kernel_option = kernel
        self.kernel, self._tables = self._kernel_tables(kernel)
        self.k = -1

    def _kernel_tables(self, kernel: str | None) -> tuple[str, Any]:
        """The backend of the step loop and, for numba, the compiled loop's tables (an Euler
        step is the explicit loop with ``Φ = I + dt F``, ``Kl = dt I``)."""
        inj = self.inj
        if inj is None or any(b is not None for b in inj.bihom):
            return "python", None
        from uio_ring.numeric.backend import resolve_kernel

        if resolve_kernel(kernel) == "python":
            return "python", None
        from uio_ring.numeric.kernel import chain_tables

        if inj.method == "euler":
            eye = np.eye(self.n_z)
            return "numba", chain_tables(inj, eye + self.dt * self.model.F, self.dt * eye)
        return "numba", chain_tables(inj, self.Phi, self.Kl)

    @property
    def discretisation(self) -> str | None:
        """How the injection term is discretised (None: the model has none)."""
        return None if self.inj is None else self.inj.method

    # ------------------------------------------------------------------ start
    def _initial_xi(self, x_hat0: Any, Y: np.ndarray, U: np.ndarray, pos: int, z0: Any = None) -> np.ndarray:
        if x_hat0 is not None and z0 is not None:
            raise SimulationError("give x_hat0 or z0, not both")
        if z0 is not None:
            return _vector(z0, self.n_z, "z0") - self._dsum(Y, U, pos)
        if x_hat0 is None:
            return np.zeros(self.n_z)
        n_init = self.model.initial.shape[1]
        v = _vector(x_hat0, n_init, "x_hat0")
        return self.model.initial @ v - self._dsum(Y, U, pos)

    def _dsum(self, Y: np.ndarray, U: np.ndarray, pos: int) -> np.ndarray:
        out = _tap(self.Dy, Y, pos, self.N)
        return out + _tap(self.Du, U, pos, self.N) if self.n_u else out

    def _gsum(self, Y: np.ndarray, U: np.ndarray, pos: int) -> np.ndarray:
        out = _tap(self.Gy, Y, pos, self.N)
        return out + _tap(self.Gu, U, pos, self.N) if self.n_u else out

    def _histories(self, y0: np.ndarray, u0: np.ndarray, y_history: Any, u_history: Any) -> tuple[np.ndarray, ...]:
        L = self.history_length
        out = []
        for v, hist, n, name in ((y0, y_history, self.n_y, "y_history"), (u0, u_history, self.n_u, "u_history")):
            if hist is None:
                out.append(np.repeat(v[None, :], L, axis=0))
                continue
            a = np.asarray(hist, dtype=float)
            if a.shape != (n, L):
                raise DimensionError(f"{name} has shape {a.shape}; expected ({n}, {L}) "
                                     f"(samples at t = −{L}·dt … −dt, oldest first)")
            _finite(a, name)
            out.append(a.T)
        return out[0], out[1]

    def start(self, y0: Any, u0: Any = None, *, x_hat0: Any = None, z0: Any = None, y_history: Any = None,
              u_history: Any = None) -> np.ndarray:
        """Take the samples at t = 0 and return ``x̂(0)``.

        ``x_hat0`` sets the initial estimate (``ẑ(0) = model.initial · x_hat0``), ``z0`` the
        observer's ẑ(0) directly (default ξ(0) = 0);
        ``y_history``, ``u_history`` (shape ``(n, history_length)``, oldest first) are the
        samples before 0 (default: held at the first sample).
        """
        y = _vector(y0, self.n_y, "y0")
        u = np.zeros(self.n_u) if u0 is None else _vector(u0, self.n_u, "u0")
        Yh, Uh = self._histories(y, u, y_history, u_history)
        L = self.history_length
        cap = L + 1
        self._Y = np.concatenate([Yh, y[None, :]])  # ring buffers, newest at index _head
        self._U = np.concatenate([Uh, u[None, :]])
        self._cap, self._head = cap, L
        self._xi = self._initial_xi(x_hat0, self._Y, self._U, L, z0)
        self._g = [self._gsum(self._Y, self._U, L - 2 + q) for q in range(3)]  # g at k = −2, −1, 0
        zcap = self.lag * self.N + 1
        self._Z = np.repeat((self._xi + self._dsum(self._Y, self._U, L))[None, :], zcap, axis=0)
        self._zhead = zcap - 1
        self.k = 0
        return self._x_hat()

    # ------------------------------------------------------------------ one step
    def _ring(self, R: np.ndarray, head: int, N: int) -> np.ndarray:
        """Rows of the ring buffer R in time order (oldest first)."""
        cap = R.shape[0]
        return R[(head + 1 + np.arange(cap)) % cap]

    def step(self, y_k: Any, u_k: Any = None, *, held: bool = False) -> np.ndarray:
        """Take the sample at ``t_k = k·dt`` and return ``x̂(t_k)``.

        ``held=True``: ``u_k`` was held constant over ``[t_{k−1}, t_k)`` (closed loop); the
        model's :class:`~uio_ring.numeric.model.HeldInput` then makes the step exact in u.
        """
        if self.k < 0:
            raise SimulationError("call start(y0, u0) before the first step")
        y = _vector(y_k, self.n_y, "y_k")
        u = np.zeros(self.n_u) if u_k is None else _vector(u_k, self.n_u, "u_k")
        self._head = (self._head + 1) % self._cap
        self._Y[self._head] = y
        self._U[self._head] = u
        Yr, Ur = self._time_ordered()
        pos = self._cap - 1
        g_new = self._gsum(Yr, Ur, pos)
        meas_prev = None
        if self.inj is not None and self.inj.method != "implicit":
            meas_prev = self.inj.measured(Yr[pos - 1], Ur[pos - 1])
        if held and self.cubic:
            raise SimulationError("held inputs need a model with linear interpolation")
        self._xi = self._advance(self._xi, g_new, y, u, held, meas_prev, Ur[pos - 1])
        self.k += 1
        self._zhead = (self._zhead + 1) % self._Z.shape[0]
        self._Z[self._zhead] = self._xi + self._dsum(Yr, Ur, pos)
        return self._x_hat()

    def _time_ordered(self) -> tuple[np.ndarray, np.ndarray]:
        if self._head == self._cap - 1:
            return self._Y, self._U
        idx = (self._head + 1 + np.arange(self._cap)) % self._cap
        return self._Y[idx], self._U[idx]

    def _advance(self, xi: np.ndarray, g_new: np.ndarray, y_new: np.ndarray, u_new: np.ndarray,
                 held: bool, meas_prev: Any, u_prev: Any = None) -> np.ndarray:
        """ξ at the next sample (precondition: shapes fit; not checked)."""
        g = self._g
        inj = self.inj
        if inj is not None and inj.method == "euler":
            sigma = inj.sigma(meas_prev, xi)
            new = xi + self.dt * (self.model.F @ xi + g[2] + inj.l_of(sigma))
            self._g = [g[1], g[2], g_new]
            return new
        gc, g0 = g_new, g[2]
        extra: Any = 0.0
        if held and self._held is not None:
            # NF-style exact treatment: the direct input term integrated exactly (Γ u), and
            # the held input's response removed from the measured forcing before interpolating
            Gam, MGam, Bd = self._held
            g0 = g0 - Bd @ u_prev
            gc = g_new - Bd @ u_new - MGam @ u_new
            extra = Gam @ u_new
        r = self.k % self.N
        if not self.cubic or (self.k < self.guard_blocks * self.N and r == 0):
            W = self.W_first
            forcing = W[0] @ g0 + W[1] @ gc
        elif self.k < self.guard_blocks * self.N and r == 1:
            W = self.W_second
            forcing = W[0] @ g[1] + W[1] @ g[2] + W[2] @ gc
        else:
            W = self.W
            forcing = W[0] @ g[0] + W[1] @ g[1] + W[2] @ g[2] + W[3] @ gc
        lin = self.Phi @ xi + forcing + extra
        self._g = [g[1], g[2], g_new]
        if inj is None:
            return lin
        if inj.method == "explicit":
            return lin + self.Kl @ inj.l_of(inj.sigma(meas_prev, xi))
        return inj.implicit(lin, inj.measured(y_new, u_new))

    def _x_hat(self) -> np.ndarray:
        Z = self._Z
        cap = Z.shape[0]
        out = self.X[0] @ Z[self._zhead]
        for i in range(1, self.X.shape[0]):
            out = out + self.X[i] @ Z[(self._zhead - i * self.N) % cap]
        return out

    def w_hat(self) -> np.ndarray | None:
        """``ŵ`` at the last sample (None when the model does not reconstruct w)."""
        if self.Wm is None:
            return None
        Z, cap = self._Z, self._Z.shape[0]
        out = self.Wm[0] @ Z[self._zhead]
        for i in range(1, self.Wm.shape[0]):
            out = out + self.Wm[i] @ Z[(self._zhead - i * self.N) % cap]
        return out

    # ------------------------------------------------------------------ whole record
    def run(self, Y: Any, U: Any = None, **start: Any) -> np.ndarray:
        """Estimates ``x̂`` (shape ``(n_x, T)``) for records ``Y`` ``(n_y, T)`` and ``U`` ``(n_u, T)``.

        Same numbers as :meth:`start` + :meth:`step` on each sample; the streaming state is
        not touched.  Keyword arguments are those of :meth:`start`.
        """
        return self.trajectories(Y, U, **start).x_hat

    def trajectories(self, Y: Any, U: Any = None, *, x_hat0: Any = None, z0: Any = None, y_history: Any = None,
                     u_history: Any = None, progress: Any = None, phi: Any = None) -> ObserverTrajectories:
        """``x̂``, ``ŵ``, ``ẑ`` and ``ξ`` for a whole record (see :meth:`run`); ``progress``:
        an updater ``progress.update(steps done)`` (models with an injection term step in a loop).

        ``phi(t, x̂)``: a plant nonlinearity the observer copies, entering ``ξ'`` through
        the model's ``phi_map`` (delay-free models without injection terms); the step is
        the exponential Runge–Kutta method of order 2 (ETD2RK) in the φ term.
        """
        Yv = self._record(Y, self.n_y, "y")
        T = Yv.shape[1]
        Uv = np.zeros((self.n_u, T)) if U is None else self._record(U, self.n_u, "u")
        if Uv.shape[1] != T:
            raise DimensionError(f"u has {Uv.shape[1]} samples and y {T}")
        with blas_single_thread():
            Yh, Uh = self._histories(Yv[:, 0], Uv[:, 0], y_history, u_history)
            Yrows = np.concatenate([Yh, Yv.T])  # y(t_j) = Yrows[L + j]
            Urows = np.concatenate([Uh, Uv.T])
            xi0 = self._initial_xi(x_hat0, Yrows, Urows, self.history_length, z0)
            if phi is not None:
                return self._run_phi(Yrows, Urows, T, xi0, phi, progress)
            if self.inj is None:
                return self._run_linear(Yrows, Urows, T, xi0)
            return self._run_loop(Yrows, Urows, T, xi0, progress)

    @staticmethod
    def _record(A: Any, n: int, name: str) -> np.ndarray:
        a = np.asarray(A, dtype=float)
        if a.ndim == 1 and n == 1:
            a = a[None, :]
        if a.ndim != 2 or a.shape[0] != n or a.shape[1] < 1:
            raise DimensionError(f"{name} has shape {np.shape(A)}; expected ({n}, T) with time on the last axis")
        _finite(a, name)
        return a

    def _outputs(self, Zr: np.ndarray, xi: np.ndarray, T: int) -> ObserverTrajectories:
        """x̂ and ŵ from ẑ (rows, held at ẑ(0) before 0)."""
        Kz = self.lag * self.N
        kw = 0 if self.Wm is None else (self.Wm.shape[0] - 1) * self.N
        pad = max(Kz, kw)
        Zrows = np.concatenate([np.repeat(Zr[:1], pad, axis=0), Zr])
        xh = delayed_sum(self.X, Zrows, 0, T - 1, self.N, pad).T
        wh = None if self.Wm is None else delayed_sum(self.Wm, Zrows, 0, T - 1, self.N, pad).T
        return ObserverTrajectories(x_hat=xh, w_hat=wh, z=Zr.T, xi=xi.T)

    def _forcing_table(self, G: np.ndarray, T: int) -> np.ndarray:
        """Forcing of the steps ``j → j+1`` (rows ``j = 0 … T−2``) from ``G[j + 2] = g(t_j)``."""
        N = self.N
        GT = G.T
        if self.cubic:
            Gq = (self.W[0] @ GT[:, 0 : T - 1] + self.W[1] @ GT[:, 1:T] + self.W[2] @ GT[:, 2 : T + 1]
                  + self.W[3] @ GT[:, 3 : T + 2]).T
            end = min(self.guard_blocks * N, T - 1)
        else:
            Gq = (self.W_first[0] @ GT[:, 2 : T + 1] + self.W_first[1] @ GT[:, 3 : T + 2]).T
            end = 0
        # steps at the start of a guarded block stay inside it
        first = np.arange(0, end, N)
        second = first[first + 1 < end] + 1
        Wf, Ws = self.W_first, self.W_second
        Gq[first] = (Wf[0] @ GT[:, first + 2] + Wf[1] @ GT[:, first + 3]).T
        if N > 1:
            Gq[second] = (Ws[0] @ GT[:, second + 1] + Ws[1] @ GT[:, second + 2] + Ws[2] @ GT[:, second + 3]).T
        return Gq

    def _taps(self, Yrows: np.ndarray, Urows: np.ndarray, T: int) -> tuple[np.ndarray, np.ndarray]:
        """``G[j + 2] = g(t_j)`` for ``j = −2 … T−1`` and ``D[j] = ẑ(t_j) − ξ(t_j)``."""
        L, N = self.history_length, self.N
        G = delayed_sum(self.Gy, Yrows, -2, T - 1, N, L)
        D = delayed_sum(self.Dy, Yrows, 0, T - 1, N, L)
        if self.n_u:
            G = G + delayed_sum(self.Gu, Urows, -2, T - 1, N, L)
            D = D + delayed_sum(self.Du, Urows, 0, T - 1, N, L)
        return G, D

    def _run_linear(self, Yrows: np.ndarray, Urows: np.ndarray, T: int, xi0: np.ndarray) -> ObserverTrajectories:
        G, D = self._taps(Yrows, Urows, T)
        xi = np.empty((T, self.n_z))
        xi[0] = xi0
        if T > 1:
            xi[1:] = LinearScan(self.Phi, chunk=16).run(xi0, self._forcing_table(G, T))
        return self._outputs(xi + D, xi, T)

    def _run_loop(self, Yrows: np.ndarray, Urows: np.ndarray, T: int, xi: np.ndarray,
                  progress: Any = None) -> ObserverTrajectories:
        """Models with an injection term: one step at a time (the term is nonlinear)."""
        L = self.history_length
        Y, U = Yrows[L:], Urows[L:]
        G, D = self._taps(Yrows, Urows, T)
        inj = self.inj
        assert inj is not None  # _run_loop is only for models with injection
        Meas = Y @ inj.Sy.T + (U @ inj.Su.T if self.n_u else 0.0)
        Xi = np.empty((T, self.n_z))
        Xi[0] = xi
        Phi, Kl, F, dt, method = self.Phi, self.Kl, self.model.F, self.dt, inj.method
        Fq = self._forcing_table(G, T) if T > 1 else np.zeros((0, self.n_z))
        if self._tables is not None:
            return self._run_kernel(Fq, G, Meas, Xi, T, D, progress)
        if method == "implicit":
            for k0 in range(1, T, 1024):  # chunks: the checkpoint every 1024 steps
                k1 = min(k0 + 1024, T)
                inj.implicit_run(Phi, Fq, Meas, Xi, k0, k1)
                if (k1 - 1) % 1024 == 0:
                    self._checkpoint(k1 - 1, Xi[k1 - 1], progress)
            return self._outputs(Xi + D, Xi, T)
        for k in range(1, T):
            if method == "explicit":
                xi = Phi @ xi + Fq[k - 1] + Kl @ inj.l_of(inj.sigma(Meas[k - 1], xi))
            else:  # euler
                xi = xi + dt * (F @ xi + G[k + 1] + inj.l_of(inj.sigma(Meas[k - 1], xi)))
            Xi[k] = xi
            if k % 1024 == 0:
                self._checkpoint(k, xi, progress)
        return self._outputs(Xi + D, Xi, T)

    def _run_kernel(self, Fq: np.ndarray, G: np.ndarray, Meas: np.ndarray, Xi: np.ndarray, T: int, D: np.ndarray,
                    progress: Any) -> ObserverTrajectories:
        """:meth:`_run_loop` by the compiled loop (:mod:`uio_ring.numeric.kernel`, K = 1), in the
        same chunks between checkpoints."""
        from uio_ring.numeric.kernel import explicit_steps, implicit_steps

        assert self.inj is not None and self._tables is not None
        method = self.inj.method
        if method == "euler":  # g(t_{k−1}) over the step k − 1 → k, weighted by dt
            Fq = self.dt * G[2 : T + 1]
        run = implicit_steps if method == "implicit" else explicit_steps
        Fq3, Meas3, Xi3 = np.ascontiguousarray(Fq)[:, None, :], np.ascontiguousarray(Meas)[:, None, :], Xi[:, None, :]
        for k0 in range(1, T, 1024):
            k1 = min(k0 + 1024, T)
            run(self._tables, Fq3[k0 - 1 : k1 - 1], Meas3[k0 - 1 : k1], Xi3[k0 - 1], Xi3[k0:k1])
            if (k1 - 1) % 1024 == 0:
                self._checkpoint(k1 - 1, Xi[k1 - 1], progress)
        return self._outputs(Xi + D, Xi, T)

    def _run_phi(self, Yrows: np.ndarray, Urows: np.ndarray, T: int, xi: np.ndarray, phi: Any,
                 progress: Any = None) -> ObserverTrajectories:
        """Linear models with a copied plant nonlinearity: one ETD2RK step at a time,
        ``N(t, ξ) = phi_map · φ(t, X₀ (ξ + D))``."""
        m = self.model
        if m.phi_map is None:
            raise SimulationError(f"phi: the {m.method or 'observer'} model does not say how φ enters it (phi_map)")
        if self.inj is not None or not m.is_delay_free:
            raise SimulationError("phi: supported for delay-free observers without injection terms")
        f = check_phi(phi, self.n_x)
        G, D = self._taps(Yrows, Urows, T)
        Fq = self._forcing_table(G, T) if T > 1 else np.zeros((0, self.n_z))
        Pm, X0, dt = m.phi_map, self.X[0], self.dt
        K1, K2 = self.Kl, dt * phi_functions(m.F * dt, 3)[2]
        Xi = np.empty((T, self.n_z))
        Xi[0] = xi
        n0 = Pm @ f(0.0, X0 @ (xi + D[0]))
        for k in range(1, T):
            pred = self.Phi @ xi + Fq[k - 1] + K1 @ n0
            n1 = Pm @ f(k * dt, X0 @ (pred + D[k]))
            xi = pred + K2 @ (n1 - n0)
            n0 = Pm @ f(k * dt, X0 @ (xi + D[k]))
            Xi[k] = xi
            if k % 1024 == 0:
                self._checkpoint(k, xi, progress)
        return self._outputs(Xi + D, Xi, T)

    def _checkpoint(self, k: int, xi: np.ndarray, progress: Any) -> None:
        """Every 1024 steps of a loop: refuse a diverged state, report progress."""
        if not np.all(np.isfinite(xi)):
            raise SimulationError(f"the observer diverged near t = {k * self.dt:g} (dt = {self.dt:g})")
        if progress is not None:
            progress.update(k)

    def noise_gain(self, horizon: float | None = None) -> np.ndarray:
        """ℓ¹ norms of the discrete impulse responses, output j → estimate i: shape ``(n_x, n_y)``.

        For output noise with ``|ν_j| ≤ a_j`` (any sequence), the estimate moves by at most
        ``Σ_j gain[i, j] a_j`` in component i — the exact ∞-norm gain of the discretised
        observer once its start-up blocks have been forgotten (up to a term decaying like
        the slowest observer pole).  ``horizon`` (seconds) defaults to the delays plus 40
        time constants of the slowest pole.  Linear observers only (no injection term).
        """
        if self.inj is not None:
            raise SimulationError("noise_gain: the observer has a nonlinear injection term; its gain is not linear")
        rate = -np.max(np.linalg.eigvals(self.model.F).real)
        if rate <= 0:
            raise SimulationError("noise_gain: F is not Hurwitz, the gain is infinite")
        if horizon is None:
            horizon = 40.0 / rate + (self.model.max_delay + self.lag + 2) * self.h
        # the impulse comes after the start-up: before 0 the observer holds ẑ at ẑ(0), which
        # would turn an impulse at t = 0 into a step of length lag·h
        k0 = (self.model.max_delay + self.lag + 1) * self.N + 3
        T = k0 + int(np.ceil(horizon / self.dt)) + 1
        quiet = ObserverStepper(self.model, self.dt, guard_blocks=0)
        gain = np.empty((self.n_x, self.n_y))
        zeros = np.zeros((self.n_y, self.history_length))
        for j in range(self.n_y):
            y = np.zeros((self.n_y, T))
            y[j, k0] = 1.0
            gain[:, j] = np.abs(quiet.run(y, y_history=zeros)[:, k0:]).sum(axis=1)
        return gain

    def __repr__(self) -> str:
        return (f"ObserverStepper({self.model.method or 'observer'}: n_z={self.n_z}, n_y={self.n_y}, "
                f"n_u={self.n_u}, n_x={self.n_x}, dt={self.dt:g}, N={self.N}, lag={self.lag}, k={self.k})")
