"""Least-squares estimate of a constant uncertainty ``ΔA`` from reconstructed signals
(Bejarano, Fridman & Poznyak 2007, Section 3.4, (48)–(51)).

When the unknown input is ``w(t) = ΔA G x(t)`` with ``ΔA`` constant and ``G`` known, an
observer that reconstructs ``ŵ ≈ w`` and ``x̂ ≈ x`` (e.g. ``matched-sta``) gives, from a
start time ``t_0`` on,

    ΔA(t) = [∫_{t_0}^t ŵ (G x̂)ᵀ] Γ(t),     Γ(t) = [∫_{t_0}^t (G x̂)(G x̂)ᵀ]⁻¹          (49)

which is the solution of the paper's continuous form (51),
``ΔA' = (ŵ − ΔA G x̂)(G x̂)ᵀ Γ``, ``Γ' = −Γ (G x̂)(G x̂)ᵀ Γ``, started from the batch value.
The paper regresses on ``x`` (it estimates ``ΔA G``); regressing on ``G x̂`` estimates
``ΔA`` itself, the same for ``G = I``.  The integrals are trapezoidal on the record's grid.
How well ΔA is determined depends on the excitation: ``gram_condition`` is the
condition number of the Gram matrix ``∫ (G x̂)(G x̂)ᵀ`` at every time (a large value means
some direction of ``ΔA`` is barely excited and its estimate converges slowly).

>>> import numpy as np
>>> t = np.linspace(0.0, 5.0, 5001)
>>> x = np.vstack([np.sin(t), np.cos(2 * t)])
>>> est = estimate_uncertainty(t, x, np.array([[0.3, -0.2]]) @ x, t_start=1.0)
>>> np.round(est.final, 6).tolist(), bool(est.gram_condition[-1] < 10)
([[0.3, -0.2]], True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from uio_ring.sim.errors import DimensionError, SimulationError

__all__ = ["UncertaintyEstimate", "estimate_uncertainty"]


@dataclass(frozen=True, eq=False)
class UncertaintyEstimate:
    """The estimate at every time from ``t_start`` on.

    Attributes
    ----------
    t : (T,)
        Times (``t ≥ t_start``).
    delta_A : (T, q, r)
        ``ΔA(t)`` by (49); NaN while the Gram matrix is singular.
    gram_condition : (T,)
        Condition number (2-norm) of ``∫_{t_start}^t (G x̂)(G x̂)ᵀ``.
    gram_eigenvalues : (r,)
        Its eigenvalues at the last time (ascending).
    """

    t: np.ndarray
    delta_A: np.ndarray
    gram_condition: np.ndarray
    gram_eigenvalues: np.ndarray

    @property
    def final(self) -> np.ndarray:
        """``ΔA`` at the last time, ``(q, r)``."""
        return self.delta_A[-1]


def estimate_uncertainty(t: Any, x_hat: Any, w_hat: Any, *, G: Any = None, t_start: float = 0.0) -> UncertaintyEstimate:
    """The least-squares ``ΔA`` of ``w = ΔA G x`` from the records ``x̂`` ``(n, T)`` and ``ŵ``
    ``(q, T)`` on the times ``t`` ``(T,)`` (e.g. a :class:`~uio_ring.sim.result.SimulationResult`'s
    ``t``, ``x_hat``, ``w_hat``); ``G`` ``(r, n)`` defaults to the identity.

    Raises ``DimensionError`` for records that do not fit and ``SimulationError`` when fewer
    than two samples lie after ``t_start``.
    """
    tt = np.asarray(t, dtype=float).reshape(-1)
    X, Wh = np.asarray(x_hat, dtype=float), np.asarray(w_hat, dtype=float)
    if X.ndim != 2 or Wh.ndim != 2 or X.shape[1] != tt.size or Wh.shape[1] != tt.size:
        raise DimensionError(f"x_hat {X.shape} and w_hat {Wh.shape} must be (n, T) and (q, T) with T = {tt.size}")
    Gm = np.eye(X.shape[0]) if G is None else np.asarray(G, dtype=float)
    if Gm.ndim != 2 or Gm.shape[1] != X.shape[0]:
        raise DimensionError(f"G has shape {Gm.shape}; expected (r, {X.shape[0]})")
    keep = tt >= t_start
    if keep.sum() < 2:
        raise SimulationError(f"t_start = {t_start:g}: fewer than two samples after it")
    tt, V, Wk = tt[keep], (Gm @ X[:, keep]).T, Wh[:, keep].T  # (T, r), (T, q)
    h = np.diff(tt)[:, None, None] / 2.0

    def cumulative(P: np.ndarray) -> np.ndarray:
        out = np.zeros_like(P)
        out[1:] = np.cumsum(h * (P[1:] + P[:-1]), axis=0)
        return out

    S = cumulative(Wk[:, :, None] * V[:, None, :])  # ∫ ŵ (G x̂)ᵀ  (T, q, r)
    Gram = cumulative(V[:, :, None] * V[:, None, :])  # (T, r, r)
    cond = np.linalg.cond(Gram[1:]) if tt.size > 1 else np.array([])
    cond = np.concatenate([[np.inf], cond])
    est = np.full(S.shape, np.nan)
    ok = np.isfinite(cond) & (cond < 1e14)
    if ok.any():
        est[ok] = np.linalg.solve(Gram[ok], np.swapaxes(S[ok], 1, 2)).swapaxes(1, 2)  # S Γ (Gram symmetric)
    return UncertaintyEstimate(t=tt, delta_A=est, gram_condition=cond, gram_eigenvalues=np.linalg.eigvalsh(Gram[-1]))
