"""Kernels of the exponential integrator (float64, no validation).

For ``x' = A0 x + f(t)`` with ``f`` known on the grid ``t_j = j·dt``, one step is

    x_{j+1} = Φ x_j + Σ_m W_m f(t_{j+q_m}),     Φ = exp(A0 dt),

where ``W_m = dt ∫_0^1 exp(A0 dt (1−τ)) ℓ_m(τ) dτ`` and ``ℓ_m`` is the Lagrange
basis through the stencil nodes ``q_m`` (in units of dt, relative to ``t_j``).
With four nodes the forcing is interpolated to O(dt⁴), the local error is
O(dt⁵) and the global error O(dt⁴), provided the stencil does not straddle a
jump of ``f`` or of its first derivatives (callers keep stencils inside one
delay block ``[kh, (k+1)h]``, where every break point lies on the grid).

The weights come from the φ-functions ``φ_k(Z) = ∫_0^1 e^{Z(1−τ)} τ^{k−1}/(k−1)! dτ``,
read off one matrix exponential of an augmented matrix (Higham, *Functions of
Matrices*, §10.7.4; Al-Mohy & Higham 2011).

The linear recursion ``x_{j+1} = Φ x_j + g_j`` over many steps is evaluated by
chunks (a lower block-triangular Toeplitz product per chunk) and a recursive
scan over the chunk ends, so that the Python work is O(steps / chunk).
"""

from __future__ import annotations

from functools import lru_cache
from math import factorial

import numpy as np
from scipy.linalg import expm

__all__ = ["phi_functions", "stencil_weights", "LinearScan"]


def phi_functions(Z: np.ndarray, p: int) -> list[np.ndarray]:
    """``[φ_0(Z), …, φ_p(Z)]`` with ``φ_0 = e^Z`` (cached on the bytes of Z; read-only arrays).

    Precondition: Z square (not checked).

    >>> [float(f[0, 0]) for f in phi_functions(np.zeros((1, 1)), 3)]
    [1.0, 1.0, 0.5, 0.16666666666666666]
    """
    return list(_phi_cached(Z.shape[0], np.ascontiguousarray(Z, dtype=float).tobytes(), int(p)))


@lru_cache(maxsize=32)
def _phi_cached(n: int, zbytes: bytes, p: int) -> tuple[np.ndarray, ...]:
    Z = np.frombuffer(zbytes, dtype=float).reshape(n, n)
    big = np.zeros(((p + 1) * n, (p + 1) * n))
    big[:n, :n] = Z
    for k in range(p):
        big[k * n : (k + 1) * n, (k + 1) * n : (k + 2) * n] = np.eye(n)
    E = expm(big)
    out = tuple(E[:n, k * n : (k + 1) * n].copy() for k in range(p + 1))
    for a in out:
        a.setflags(write=False)
    return out


def _lagrange_monomials(nodes: tuple[float, ...]) -> np.ndarray:
    """``c[m, k]``: ℓ_m(τ) = Σ_k c[m, k] τ^k for the Lagrange basis through ``nodes``."""
    q = len(nodes)
    V = np.vander(np.asarray(nodes, dtype=float), q, increasing=True)  # V[m, k] = node_m^k
    return np.linalg.inv(V).T  # ℓ_m(node_i) = δ_mi


def stencil_weights(Z: np.ndarray, dt: float, nodes: tuple[float, ...], phis=None) -> np.ndarray:
    """Weights ``W[m]`` (shape ``(len(nodes), n, n)``) of one step; see the module docstring.

    Precondition: ``Z = A0·dt``; nodes distinct (not checked).

    For ``A0 = 0`` the weights are the Newton–Cotes-like rule of the stencil:
    >>> np.round(stencil_weights(np.zeros((1, 1)), 1.0, (-1, 0, 1, 2))[:, 0, 0] * 24, 12)
    array([-1., 13., 13., -1.])
    """
    q = len(nodes)
    if phis is None:
        phis = phi_functions(Z, q)
    c = _lagrange_monomials(nodes)
    # ∫_0^1 e^{Z(1−τ)} τ^k dτ = k! φ_{k+1}(Z)
    mono = np.stack([factorial(k) * phis[k + 1] for k in range(q)])  # (q, n, n)
    return dt * np.einsum("mk,kij->mij", c, mono)


class LinearScan:
    """Solve ``x_{j+1} = Φ x_j + g_j`` for many steps with array operations.

    ``run(x0, g)`` with ``g`` of shape ``(M, n)`` returns ``x_1 … x_M`` (shape ``(M, n)``).
    Within a chunk of ``m`` steps, ``x_{c,r} = Φ^{r+1} x_c + Σ_{s≤r} Φ^{r−s} g_{c,s}``
    (one Toeplitz product for all chunks); the chunk starts ``x_c`` obey the same
    recursion with ``Φ^m``, solved by a nested scan.

    >>> s = LinearScan(np.array([[0.5]]), chunk=4)
    >>> s.run(np.array([1.0]), np.zeros((6, 1)))[:, 0]
    array([0.5     , 0.25    , 0.125   , 0.0625  , 0.03125 , 0.015625])
    """

    def __init__(self, Phi: np.ndarray, chunk: int = 16):
        n = Phi.shape[0]
        self.n, self.m = n, chunk
        pows = [np.eye(n)]
        for _ in range(chunk):
            pows.append(Phi @ pows[-1])
        self.Phi = Phi
        self.pows = np.stack(pows[1:])  # Φ^{r+1}, r = 0..m−1
        self.Pstack = self.pows.transpose(2, 0, 1).reshape(n, chunk * n).copy()  # starts @ Pstack
        T = np.zeros((chunk, n, chunk, n))
        for r in range(chunk):
            for s in range(r + 1):
                T[r, :, s, :] = pows[r - s]
        self.TT = T.reshape(chunk * n, chunk * n).T.copy()  # right-multiplication form
        self._next: LinearScan | None = None

    def _outer(self) -> LinearScan:
        if self._next is None:
            self._next = LinearScan(self.pows[-1], self.m)
        return self._next

    def run(self, x0: np.ndarray, g: np.ndarray) -> np.ndarray:
        M, n = g.shape
        m = self.m
        if M <= 2 * m:
            out = np.empty((M, n))
            x = x0
            Phi = self.Phi
            for j in range(M):
                x = Phi @ x + g[j]
                out[j] = x
            return out
        C = -(-M // m)
        gp = np.zeros((C * m, n))
        gp[:M] = g
        Yp = (gp.reshape(C, m * n) @ self.TT).reshape(C, m, n)
        # chunk starts: s_{c+1} = Φ^m s_c + Yp[c, m−1]
        starts = np.empty((C, n))
        starts[0] = x0
        if C > 1:
            starts[1:] = self._outer().run(x0, Yp[:-1, -1])
        X = (starts @ self.Pstack).reshape(C, m, n)
        X += Yp
        return X.reshape(C * m, n)[:M]


