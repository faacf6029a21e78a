"""What an observer does to noise and how fast it forgets: the figures of a linear observer model.

For a linear :class:`~uio_ring.numeric.model.ObserverModel` (no injection term), output
noise ``v`` added to ``y`` moves the estimate by ``x̂_v = K * v`` with the kernel

    K(t) = Σ_{a,b} X_a e^{F (t − (a+b) h)} G_b · 1[t ≥ (a+b) h]  +  Σ_{a,b} X_a D_b δ(t − (a+b) h)

(``G = G_y``, ``D = D_y``: the delayed taps and the direct feed-through ``HΛ(δ)``
included exactly).  Hence, after the start-up transient,

* **peak-to-peak gain**: ``max_t |e_i(t) − e_i^0(t)| ≤ Σ_j P_ij · max|v_j|`` with
  ``P_ij = ‖K_ij‖₁`` (the integral of ``|K_ij|`` plus the weights of its Dirac terms);
  the bound is attained by the noise ``v_j(t) = sign K_ij(t₀ − t)`` — a guarantee, not
  an estimate;
* **H2 gain** (white noise of unit intensity): ``sqrt(∫ Σ_j K_ij²)``, finite only when
  no Dirac term remains (``X(δ)·D_y(δ) = 0``); otherwise ``None`` with the reason.

The smooth part is integrated on a grid aligned with the multiples of h (``K`` jumps
there) by the trapezoidal rule on each block, ``e^{FΔ}`` exact, extrapolated from two
grids (Richardson); the grid is refined until the figure moves by less than ``rtol``.

>>> import numpy as np
>>> from uio_ring.numeric.model import ObserverModel
>>> m = ObserverModel(F=[[-2.0]], G_y=[[[2.0]]], X=[[[1.0]]])     # x̂' = −2 x̂ + 2 y
>>> p = performance(m)
>>> round(float(p.peak_to_peak[0, 0]), 5), round(p.decay_rate, 6), round(float(p.h2[0]), 5)   # ∫2e^{−2t} = 1
(1.0, 2.0, 1.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.linalg import expm

from uio_ring.errors import NotSupportedError, SimulationError
from uio_ring.numeric.model import ObserverModel

__all__ = ["ObserverPerformance", "performance", "noise_kernel", "gain_estimate", "linear_part"]


@dataclass(frozen=True, eq=False)
class ObserverPerformance:
    """The figures of a linear observer (see the module docstring).

    Attributes
    ----------
    decay_rate : float
        ``−max Re λ(F)``: the error decays like ``e^{−decay_rate·t}``.
    convergence_time : float
        Time after which ``‖e^{F t}‖∞ ≤ tolerance`` (relative to the initial error),
        plus the lag ``lag·h`` of the output map.
    tolerance : float
    peak_to_peak : (n_x, n_y) array
        ``P_ij = ‖K_ij‖₁``: ``max|Δe_i| ≤ Σ_j P_ij max|v_j|``.
    h2 : (n_x,) array or None
        ``sqrt(∫ Σ_j K_ij²)``; None when a direct feed-through makes it infinite.
    h2_reason : str
        Why ``h2`` is None.
    lag, lag_seconds, order : int, float, int
        ``deg X``, ``lag·h`` and the observer order ``n_z``.
    scope : str
        What was measured when it is not the whole observer (e.g. the linear stage of an
        observer with nonlinear injection); empty for the whole observer.
    """

    decay_rate: float
    convergence_time: float
    tolerance: float
    peak_to_peak: np.ndarray
    h2: np.ndarray | None
    h2_reason: str
    lag: int
    lag_seconds: float
    order: int
    scope: str = ""

    @property
    def noise_gain(self) -> np.ndarray:
        """Per state, the bound of ``|Δe_i|`` for noise bounded by 1 on every output."""
        return self.peak_to_peak.sum(axis=1)

    def summary(self) -> str:
        g = ", ".join(f"{v:.4g}" for v in self.noise_gain)
        h2 = ("H2 gain per state: " + ", ".join(f"{v:.4g}" for v in self.h2)) if self.h2 is not None else \
            f"H2 gain: infinite ({self.h2_reason})"
        what = f"{self.scope}: " if self.scope else ""
        return (f"{what}decay rate {self.decay_rate:.4g}/s; converged to {self.tolerance:g} after ≈ "
                f"{self.convergence_time:.3g} s (lag {self.lag}·h = {self.lag_seconds:g} s included); "
                f"noise gain per state (|v| ≤ 1 on every output, peak to peak): {g}; {h2}")

    def to_dict(self) -> dict[str, Any]:
        return {
            "decay_rate": self.decay_rate, "convergence_time": self.convergence_time,
            "tolerance": self.tolerance, "peak_to_peak": self.peak_to_peak.tolist(),
            "noise_gain": self.noise_gain.tolist(),
            "h2": None if self.h2 is None else self.h2.tolist(), "h2_reason": self.h2_reason,
            "lag": self.lag, "lag_seconds": self.lag_seconds, "order": self.order, "scope": self.scope,
        }


def _pairs(model: ObserverModel) -> list[tuple[int, np.ndarray, np.ndarray]]:
    """``(c, X_a, G_b)`` for every tap pair, ``c = a + b`` (delay multiple)."""
    X, G = model.X, model.G_y
    return [(a + b, X[a], G[b]) for a in range(X.shape[0]) for b in range(G.shape[0])
            if np.any(X[a]) and np.any(G[b])]


def _dirac_weight(model: ObserverModel) -> np.ndarray:
    """``Σ_c |Σ_{a+b=c} X_a D_b|`` elementwise: the ℓ1 weight of the Dirac terms."""
    X, D = model.X, model.D_y
    if D.shape[0] == 0 or X.shape[0] == 0:
        return np.zeros((model.n_x, model.n_y))
    by_c: dict[int, np.ndarray] = {}
    for a in range(X.shape[0]):
        for b in range(D.shape[0]):
            by_c[a + b] = by_c.get(a + b, 0) + X[a] @ D[b]
    return sum((np.abs(M) for M in by_c.values()), np.zeros((model.n_x, model.n_y)))


#: Grid points stepped per block of :func:`_kernel_chain` (the block stays in cache).
_BLOCK = 256


def _kron_identity_factor(F: np.ndarray) -> tuple[np.ndarray, int]:
    """``(S, r)`` with ``F = S ⊗ I_r`` exactly (entry ``(i·r + a, j·r + b)`` of F is
    ``S[i, j]`` if ``a = b``, else 0) for the largest such r; ``(F, 1)`` when there is none.
    The Zheng–Bejarano ``L0 = A0 − G0 C0`` is ``(shift − g e₁ᵀ) ⊗ I_r`` (r output channels,
    no coupling): its exponential is ``e^{S t} ⊗ I_r``, and ``e^{F t} V`` is ``e^{S t}``
    times V read as an ``n_z/r × r·w`` matrix — r² times fewer flops per grid point.

    >>> S = np.array([[0.0, 1.0], [-2.0, -3.0]])
    >>> T, r = _kron_identity_factor(np.kron(S, np.eye(3)))
    >>> r, bool(np.array_equal(T, S)), _kron_identity_factor(S)[1]
    (3, True, 1)
    """
    n = F.shape[0]
    for r in range(n, 1, -1):
        if n % r:
            continue
        S = F[::r, ::r]
        if np.array_equal(F, np.kron(S, np.eye(r))):
            return np.ascontiguousarray(S), r
    return F, 1


def _kernel_chain(model: ObserverModel, step: float, T: int, offset: int = 0, stride: int = 1) -> np.ndarray:
    """``K`` at the grid points ``m = offset + stride·j < T`` (``t = m·step``), shape ``(J, n_x, n_y)``.

    With ``s = (a+b)·per`` (``per = h/step``, a multiple of ``stride``), ``K[m] = Σ X_a V[j − s/stride]
    G_b`` where ``V[i] = Φ^{stride·i} e^{F·offset·step} [G_b …]`` (the used ``G_b`` side by side),
    stepped by ``Φ^stride`` (``Φ = e^{F·step}``): an ``n_z × n_z`` times ``n_z × B·n_y`` product per
    point, in blocks of :data:`_BLOCK` points that are used and dropped (never all of ``V``, never
    an ``n_z × n_z`` power per point).
    """
    h = model.h if model.h is not None else step
    per = max(1, round(h / step))
    J = max(0, -(-(T - offset) // stride))
    ny = model.n_y
    K = np.zeros((J, model.n_x, ny))
    used = [b for b in range(model.G_y.shape[0]) if np.any(model.G_y[b])]
    taps = [a for a in range(model.X.shape[0]) if np.any(model.X[a])]
    if not used or not taps or J == 0:
        return K
    small, r = _kron_identity_factor(model.F)
    Phi = expm(small * (step * stride))  # e^{F t} = e^{S t} ⊗ I_r when F = S ⊗ I_r
    Xs = np.concatenate([model.X[a] for a in taps], axis=0)  # (A·n_x, n_z)
    nx = model.n_x
    w = len(used) * ny
    V = np.empty((_BLOCK, model.n_z, w))
    Vs = V.reshape(_BLOCK, model.n_z // r, r * w)  # the same memory: row i·r + a of V is (i, a·w …)
    first = np.concatenate([model.G_y[b] for b in used], axis=1)
    V[0] = first
    if offset:
        Vs[0] = expm(small * (step * offset)) @ Vs[0].copy()
    shifts = [(ia, ib, (a + b) * per // stride) for ia, a in enumerate(taps) for ib, b in enumerate(used)]
    for lo in range(0, J, _BLOCK):
        n = min(_BLOCK, J - lo)
        if lo:
            np.matmul(Phi, Vs[-1], out=Vs[0])  # the last point of the previous (full) block
        for i in range(1, n):
            np.matmul(Phi, Vs[i - 1], out=Vs[i])
        Y = np.matmul(Xs, V[:n])  # (n, A·n_x, B·n_y): every X_a V G_b at once
        for ia, ib, sh in shifts:
            if lo + sh < J:
                top = min(n, J - lo - sh)
                K[lo + sh : lo + sh + top] += Y[:top, ia * nx : (ia + 1) * nx, ib * ny : (ib + 1) * ny]
    return K


def _kernel(model: ObserverModel, step: float, T: int, coarse: np.ndarray | None = None) -> np.ndarray:
    """``K`` on ``t = 0, step, …`` (``T`` points, shape ``(T, n_x, n_y)``).  ``coarse``: ``K`` on the
    grid of twice the step (the previous grid of the refinement), which holds the even points;
    only the odd ones are stepped (:func:`_kernel_chain` with stride 2): half the products.
    (Delay-free models, ``h`` None: every shift is 0, any step may be halved.)
    """
    h = model.h if model.h is not None else step
    per = max(1, round(h / step))
    even = -(-T // 2)
    if coarse is None or coarse.shape[0] < even or (model.h is not None and per % 2):
        return _kernel_chain(model, step, T)
    K = np.empty((T, model.n_x, model.n_y))
    K[0::2] = coarse[:even]
    K[1::2] = _kernel_chain(model, step, T, offset=1, stride=2)
    return K


def noise_kernel(model: ObserverModel, step: float, horizon: float) -> tuple[np.ndarray, np.ndarray]:
    """The smooth part of ``K`` on ``t = 0, step, …`` (``step`` divides h): ``(t, K)`` with
    ``K`` of shape ``(T, n_x, n_y)``; at a multiple of h the value is the right limit.

    ``e^{F t} G_b`` is stepped once per ``b`` (:func:`_kernel_chain`) and shared by the pairs with
    that ``b``: ``n_z² · T · B·n_y`` flops.

    Precondition: linear model with ``h`` set when it has delays (not checked).
    """
    T = int(math.ceil(horizon / step)) + 1
    return np.arange(T) * step, _kernel_chain(model, step, T)


def _integrals(model: ObserverModel, step: float, horizon: float,
               coarse: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``∫|K|`` and ``∫K²`` by the trapezoidal rule on each block between multiples of h, and
    ``K`` itself (the even points of the next, halved, step)."""
    T = int(math.ceil(horizon / step)) + 1
    K = _kernel(model, step, T, coarse)
    h = model.h if model.h is not None else step
    per = max(1, round(h / step))
    pairs = _pairs(model)
    l1 = np.zeros((model.n_x, model.n_y))
    l2 = np.zeros((model.n_x, model.n_y))
    jumps = sorted({c * per for c, _, _ in pairs if c > 0})
    # at a jump the left limit lacks the terms that switch on there
    bounds = [0] + [j for j in jumps if j < T - 1] + [T - 1]
    for lo, hi in zip(bounds[:-1], bounds[1:], strict=True):
        seg = K[lo : hi + 1]
        last = seg[-1].copy()
        for c, Xa, Gb in pairs:
            if c * per == hi and hi > lo:
                last -= Xa @ Gb  # left limit at the block end
        w = np.full(hi - lo + 1, step)
        w[0] = w[-1] = step / 2
        l1 += np.einsum("m,mij->ij", w[:-1], np.abs(seg[:-1])) + w[-1] * np.abs(last)
        l2 += np.einsum("m,mij->ij", w[:-1], seg[:-1] ** 2) + w[-1] * last**2
    return l1, l2, K


#: Most grid points one integral of :func:`performance` may use (checked before allocating).
MAX_GRID_POINTS = 2_000_000


def performance(model: ObserverModel, *, tolerance: float = 1e-3, rtol: float = 1e-3,
                scope: str = "") -> ObserverPerformance:
    """The figures of a linear observer model (see :class:`ObserverPerformance`).

    Raises ``NotSupportedError`` for models with an injection term (their gain is not
    linear) and ``SimulationError`` when ``F`` is not Hurwitz (the gain is infinite).
    """
    from uio_ring.numeric.threads import blas_single_thread

    with blas_single_thread():  # small products: BLAS threads only hand over on busy cores
        return _performance(model, tolerance=tolerance, rtol=rtol, scope=scope)


def _performance(model: ObserverModel, *, tolerance: float, rtol: float, scope: str) -> ObserverPerformance:
    if model.injection is not None:
        raise NotSupportedError(f"performance: the {model.method or 'observer'} model has a nonlinear "
                                "injection term; its noise gain is not a linear figure")
    if model.max_delay > 0 and model.h is None:
        raise SimulationError("performance: the model has delayed taps; give h (design.numeric(h=…))")
    lam = np.linalg.eigvals(model.F) if model.n_z else np.array([-np.inf])
    rate = float(-np.max(lam.real))
    if not rate > 0:
        raise SimulationError(f"performance: F is not Hurwitz (decay rate {rate:g}); the gain is infinite")
    h = model.h
    delays = (model.X.shape[0] + model.G_y.shape[0]) * (h or 0.0)
    horizon = delays + 40.0 / rate
    fastest = float(np.max(np.abs(lam))) if model.n_z else 1.0
    step = min(0.1 / fastest, horizon / 200)
    if h is not None:
        step = h / max(1, math.ceil(h / step))
    if horizon / step > MAX_GRID_POINTS:  # bounded before any array is allocated
        raise SimulationError(
            f"performance: the observer's modes span decay rates {rate:.3g} … {fastest:.3g} per second; the figures "
            f"would need {horizon / step:.3g} grid points (limit {MAX_GRID_POINTS:.0e}), so they are not computed"
        )
    dirac = _dirac_weight(model)
    # trapezoid on grids of step Δ and Δ/2, Richardson-extrapolated (error O(Δ⁴) for a smooth
    # |K|; kinks where K changes sign leave O(Δ²)); halve until the figure settles
    l1c, l2c, K = _integrals(model, step, horizon)
    P = l1c + dirac
    for _ in range(6):
        if 2 * horizon / step > MAX_GRID_POINTS:
            break  # the finest grid the budget allows
        step /= 2
        l1f, l2f, K = _integrals(model, step, horizon, K)
        l1, l2 = l1f + (l1f - l1c) / 3, l2f + (l2f - l2c) / 3
        new_P = l1 + dirac
        settled = np.all(np.abs(new_P - P) <= rtol * np.maximum(np.abs(new_P), 1e-300))
        P, l1c, l2c = new_P, l1f, l2f
        if settled:
            break
    lag = model.lag
    lag_s = lag * (h or 0.0)
    # convergence: ‖e^{F t}‖∞ ≤ tolerance from then on
    coarse = 4 * step
    last_bad = _last_above(expm(model.F * coarse), int(math.ceil(horizon / coarse)), tolerance) * coarse
    has_dirac = bool(np.any(dirac))
    h2 = None if has_dirac else np.sqrt(l2.sum(axis=1))
    reason = ("the read-out passes the noise directly to x̂ (X(δ)·D_y(δ) ≠ 0: the terms H Λ(δ) y of the "
              "estimate), so white noise gives an unbounded variance") if has_dirac else ""
    return ObserverPerformance(
        decay_rate=rate, convergence_time=float(last_bad + lag_s), tolerance=tolerance, peak_to_peak=P,
        h2=h2, h2_reason=reason, lag=lag, lag_seconds=lag_s, order=model.n_z, scope=scope,
    )


def _last_above(Phi: np.ndarray, M: int, tolerance: float) -> int:
    """The last ``m ≤ M`` with ``‖Φ^m‖∞ > tolerance`` (0 if none).

    Two shortcuts, the answer unchanged (up to rounding) against stepping ``m = 1 … M``:

    * ``‖Φ^M‖∞ > tolerance``: the answer is ``M`` (``Φ^M`` by squaring: O(log M) products);
    * when ``‖Φ^m‖∞ ≤ tolerance ≤ 1`` for every ``m`` in ``[m₀, 2m₀)``, then for every
      ``n ≥ m₀``, ``n = j + k m₀`` with ``j ∈ [m₀, 2m₀)``, so ``‖Φ^n‖ ≤ ‖Φ^j‖ ‖Φ^{m₀}‖^k ≤
      tolerance`` (the norm is submultiplicative): the stepping stops there.

    >>> _last_above(np.array([[0.5]]), 10, 0.1)       # 0.5^3 = 0.125 > 0.1 ≥ 0.5^4
    3
    >>> _last_above(np.array([[0.99]]), 5, 0.1)       # still above at M
    5
    """
    def norm(E: np.ndarray) -> float:
        return float(np.abs(E).sum(axis=1).max())

    if M <= 0:
        return 0
    power, base, e = np.eye(Phi.shape[0]), Phi, M
    while e:
        if e & 1:
            power = power @ base
        e >>= 1
        if e:
            base = base @ base
    if norm(power) > tolerance:
        return M
    E = np.eye(Phi.shape[0])
    last_bad, run_start = 0, 0  # run_start: first m of the current run of m with ‖Φ^m‖ ≤ tolerance
    for m in range(1, M + 1):
        E = Phi @ E
        if norm(E) > tolerance:
            last_bad, run_start = m, 0
        elif run_start == 0:
            run_start = m
        elif tolerance <= 1 and m >= 2 * run_start - 1:
            break
    return last_bad


def linear_part(model: ObserverModel) -> ObserverModel:
    """The model without its injection term: what :func:`performance` measures for an observer
    with nonlinear injection when asked for the figures of its linear part.

    >>> m = ObserverModel(F=[[-1.0]], G_y=[[[1.0]]], X=[[[1.0]]])
    >>> linear_part(m) is m
    True
    """
    if model.injection is None:
        return model
    from dataclasses import replace

    return replace(model, injection=None)


def gain_estimate(model: ObserverModel, *, points_per_pole: float = 10.0,
                  decays: float = 25.0) -> tuple[np.ndarray, np.ndarray | None]:
    """``(noise gain per state, H2 gain per state or None)`` on one grid, for searches that
    compare many designs: the trapezoidal rule with about ``points_per_pole`` points per time
    constant of the fastest mode, over ``decays`` time constants of the slowest (no
    refinement; measured within 0.3 % of :func:`performance` on the examples).  Infinite
    gains when ``F`` is not Hurwitz.  Precondition: a linear model with ``h`` set when it
    has delays (not checked) — :func:`performance` gives the figure of the chosen design.

    >>> m = ObserverModel(F=[[-2.0]], G_y=[[[2.0]]], X=[[[1.0]]])
    >>> p2p, h2 = gain_estimate(m)
    >>> round(float(p2p[0]), 2), round(float(h2[0]), 2)
    (1.0, 1.0)
    """
    lam = np.linalg.eigvals(model.F) if model.n_z else np.array([-np.inf])
    rate = float(-np.max(lam.real))
    if not rate > 0:
        return np.full(model.n_x, np.inf), np.full(model.n_x, np.inf)
    fastest = float(np.max(np.abs(lam))) if model.n_z else 1.0
    h = model.h
    horizon = (model.X.shape[0] + model.G_y.shape[0]) * (h or 0.0) + decays / rate
    step = min(1.0 / (points_per_pole * fastest), horizon / 200)
    if h is not None:
        step = h / max(1, math.ceil(h / step))
    if horizon / step > MAX_GRID_POINTS:
        return np.full(model.n_x, np.inf), np.full(model.n_x, np.inf)
    with np.errstate(all="ignore"):  # a badly conditioned candidate overflows: its gain is infinite
        l1, l2, _ = _integrals(model, step, horizon)
        dirac = _dirac_weight(model)
        p2p = (l1 + dirac).sum(axis=1)
        h2 = None if np.any(dirac) else np.sqrt(l2.sum(axis=1))
    p2p = np.where(np.isfinite(p2p), p2p, np.inf)
    return p2p, None if h2 is None else np.where(np.isfinite(h2), h2, np.inf)
