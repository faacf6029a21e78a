"""Compiled step loops (numba) of the observers with a Levant injection term.

The loops of :class:`~uio_ring.numeric.stepper.ObserverStepper` (one run) and of
``simulate_batch`` (K scenarios) are one loop here, over K scenarios and their steps
(K = 1 for one run), on plain arrays: the stepper's chain tables flattened into a
:class:`ChainTables` (built once per stepper).  With ``x`` the observer state ξ:

* implicit (backward Euler, set-valued sign): ``lin = Φ x + Fq[q]``, the chains' σ without
  injection ``base = meas[q + 1] + R lin``, then chain by chain (in order, each reading the
  earlier chains' terms through ``RK``) the inclusion of
  :func:`~uio_ring.numeric.stepper.solve_chain` (closed form for chains of length 2, the
  same Newton iteration for longer ones), and ``x ← lin + Kl l``;
* explicit: ``x ← Φ x + Fq[q] + Kl l(meas[q] + R x)``; explicit Euler is the same loop with
  ``Φ = I + dt F``, ``Kl = dt I`` and the forcing ``dt g``.

Bi-homogeneous chains are not covered (their models stay on the Python loop).  numba is
an optional dependency (``pip install 'uio-ring[fast]'``), imported on the first call;
the loops are compiled then, and cached on disk (``cache=True``: once per machine).
The Python loop (:mod:`uio_ring.numeric.stepper`) is the reference: the two agree up to
rounding (summation order).

>>> import numpy as np
>>> from uio_ring.numeric.model import LevantInjection, ObserverModel
>>> inj = LevantInjection(starts=(0,), lengths=(2,), gains=((6.0, 8.0),), sigma_y=np.array([[1.0]]),
...                       sigma_u=np.zeros((1, 0)))
>>> F = np.array([[0.0, 1.0], [0.0, 0.0]])
>>> m = ObserverModel(F=F, G_y=np.zeros((1, 2, 1)), X=np.eye(2)[None], injection=inj, interpolation="linear")
>>> st = m.stepper(1e-3, kernel="python")
>>> t = chain_tables(st.inj, st.Phi, st.Kl)
>>> t.starts.tolist(), t.mu.tolist(), t.R.tolist(), t.cols.tolist()
([0], [2], [[-1.0, 0.0]], [0, 1])
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["ChainTables", "chain_tables", "implicit_steps", "explicit_steps"]


@dataclass(frozen=True, eq=False)
class ChainTables:
    """The arrays of the compiled loops (p chains, n states, ``mμ`` the longest chain).

    ``starts``, ``mu`` (p,) int: where each chain sits and its length; ``coef`` (p, mμ): the
    weights ``w_k κ_k`` of its non-sign terms in its own σ; ``s0`` (p,): its sign term's weight;
    ``kap``, ``ex`` (p, mμ): gains and exponents ``(μ − k)/μ``; ``R`` (p, n): σ = meas + R ξ;
    ``RK`` = R Kl; ``PhiT`` = Φᵀ, ``KlT`` = Klᵀ (n, n); ``cols``: the chains' states.
    """

    starts: np.ndarray
    mu: np.ndarray
    coef: np.ndarray
    s0: np.ndarray
    kap: np.ndarray
    ex: np.ndarray
    R: np.ndarray
    RK: np.ndarray
    PhiT: np.ndarray
    KlT: np.ndarray
    cols: np.ndarray


def chain_tables(inj: Any, Phi: np.ndarray, Kl: np.ndarray) -> ChainTables:
    """The tables of a stepper's injection (``ObserverStepper.inj``, Levant chains) for the
    step matrix ``Phi`` and the injection weight ``Kl``."""
    p = len(inj.starts)
    mmax = max(inj.mu)
    coef, kap, ex = np.zeros((p, mmax)), np.zeros((p, mmax)), np.zeros((p, mmax))
    for j, m in enumerate(inj.mu):
        coef[j, : m - 1] = inj.coef[j]
        kap[j, :m] = inj.kap[j]
        ex[j, :m] = inj.exp[j]
    c = np.ascontiguousarray
    cols = np.concatenate([np.arange(s, s + m) for s, m in zip(inj.starts, inj.mu, strict=True)])
    return ChainTables(starts=np.array(inj.starts, dtype=np.int64), mu=np.array(inj.mu, dtype=np.int64),
                       coef=coef, s0=np.array(inj.s0, dtype=float), kap=kap, ex=ex, R=c(inj.R, dtype=float),
                       RK=c(inj.R @ Kl), PhiT=c(Phi.T), KlT=c(Kl.T), cols=np.sort(cols).astype(np.int64))


def implicit_steps(t: ChainTables, Fq: np.ndarray, Meas: np.ndarray, xi0: np.ndarray, out: np.ndarray) -> None:
    """``out[q, k]``: ξ after step q of scenario k (implicit), from ``xi0[k]``, the forcing
    ``Fq[q, k]`` and the measured part of σ ``Meas[q + 1, k]`` at the step's new time.

    Shapes ``Fq``, ``out`` (M, K, n), ``Meas`` (M + 1, K, p), ``xi0`` (K, n); float64, C-contiguous
    (precondition, not checked: ``out`` is written in place).
    """
    _compiled()[0](t.PhiT, t.KlT, t.R, t.RK, t.starts, t.mu, t.coef, t.s0, t.kap, t.cols, Fq, Meas, xi0, out)


def explicit_steps(t: ChainTables, Fq: np.ndarray, Meas: np.ndarray, xi0: np.ndarray, out: np.ndarray) -> None:
    """As :func:`implicit_steps` for the explicit step (σ at the old time, ``Meas[q, k]``)."""
    _compiled()[1](t.PhiT, t.KlT, t.R, t.starts, t.mu, t.kap, t.ex, t.cols, Fq, Meas, xi0, out)


@functools.cache
def _compiled() -> tuple[Any, Any]:
    from uio_ring.errors import require

    numba = require("numba", extra="fast")
    jit = numba.njit(cache=True, nogil=True)
    return jit(_implicit_loop), jit(_explicit_loop)


# The loops below are compiled by numba (nopython mode): plain loops over plain arrays.
def _implicit_loop(PhiT, KlT, R, RK, starts, mu, coef, s0, kap, cols, Fq, Meas, xi0, out):  # pragma: no cover
    M, K, n = Fq.shape
    p = starts.shape[0]
    x, lin, lvec, base = np.empty(n), np.empty(n), np.zeros(n), np.empty(p)
    for q in range(M):  # steps outer, scenarios inner: the arrays are read in memory order
        for k in range(K):
            prev = xi0[k] if q == 0 else out[q - 1, k]
            for i in range(n):
                x[i] = prev[i]
            for i in range(n):
                lin[i] = 0.0
            for c in range(n):  # lin = Φ x + Fq (columns of Φ: the inner loop vectorises)
                xc = x[c]
                for i in range(n):
                    lin[i] += PhiT[c, i] * xc
            for i in range(n):
                lin[i] += Fq[q, k, i]
            for j in range(p):  # σ with no injection at all
                acc = 0.0
                for i in range(n):
                    acc += R[j, i] * lin[i]
                base[j] = Meas[q + 1, k, j] + acc
            for i in range(n):
                lvec[i] = 0.0
            for j in range(p):  # chains in order: chain j reads the terms of the earlier ones
                acc = 0.0
                for jj in range(j):
                    for i in range(starts[jj], starts[jj] + mu[jj]):
                        acc += RK[j, i] * lvec[i]
                a = base[j] + acc
                s, m, sj = starts[j], mu[j], s0[j]
                mag = abs(a)
                if mag <= sj:  # sliding: σ = 0, the sign term takes the value a/s0 ∈ [−1, 1]
                    lvec[s + m - 1] = kap[j, m - 1] * (a / sj if sj > 0.0 else 0.0)
                    continue
                if m == 2:  # super-twisting, closed form: s = |σ|^½ solves s² + c1 s = |a| − s0
                    c1 = coef[j, 0]
                    lvec[s] = (0.5 * kap[j, 0]) * math.copysign(math.sqrt(c1 * c1 + 4.0 * (mag - sj)) - c1, a)
                    lvec[s + 1] = kap[j, 1] * (a / mag)
                    continue
                rhs = mag - sj
                sgn = math.copysign(1.0, a)
                if m > 1:  # solve_chain's Newton iteration on s = |σ|^{1/μ}
                    if m == 4:  # the start c^{1/μ} (by roots where there are cheaper ones than pow)
                        r = math.sqrt(math.sqrt(rhs))
                    elif m == 3:
                        r = np.cbrt(rhs)
                    else:
                        r = rhs ** (1.0 / m)
                    for _ in range(100):
                        f, df = 1.0, 0.0
                        for kk in range(m - 1):
                            df = df * r + f
                            f = f * r + coef[j, kk]
                        df = df * r + f
                        f = f * r - rhs
                        if f <= 0.0 or df <= 0.0:
                            break
                        r_new = r - f / df
                        if r_new >= r or r - r_new <= 1e-15 * r:
                            r = max(r_new, 0.0)
                            break
                        r = r_new
                    pw = r  # |σ|^{(μ−k)/μ} = r^{μ−k}: products, from the sign's neighbour up
                    for kk in range(m - 2, -1, -1):
                        lvec[s + kk] = kap[j, kk] * pw * sgn
                        pw *= r
                    if pw == 0.0:  # |σ| = r^μ underflows: σ = 0, as solve_chain returns it
                        for kk in range(m - 1):
                            lvec[s + kk] = 0.0
                lvec[s + m - 1] = kap[j, m - 1] * sgn
            for i in range(n):
                x[i] = 0.0
            for c in cols:  # x = lin + Kl l
                v = lvec[c]
                if v != 0.0:
                    for i in range(n):
                        x[i] += KlT[c, i] * v
            for i in range(n):
                x[i] += lin[i]
                out[q, k, i] = x[i]


def _explicit_loop(PhiT, KlT, R, starts, mu, kap, ex, cols, Fq, Meas, xi0, out):  # pragma: no cover
    M, K, n = Fq.shape
    p = starts.shape[0]
    new, lvec = np.empty(n), np.zeros(n)
    for q in range(M):
        for k in range(K):
            x = xi0[k] if q == 0 else out[q - 1, k]
            for j in range(p):  # l(σ) at the old time
                acc = 0.0
                for i in range(n):
                    acc += R[j, i] * x[i]
                sig = Meas[q, k, j] + acc
                mag, sgn = abs(sig), (1.0 if sig > 0.0 else (-1.0 if sig < 0.0 else 0.0))
                if sig != sig:
                    sgn = sig
                for kk in range(mu[j]):
                    lvec[starts[j] + kk] = kap[j, kk] * mag ** ex[j, kk] * sgn
            for i in range(n):
                new[i] = 0.0
            for c in range(n):
                xc = x[c]
                for i in range(n):
                    new[i] += PhiT[c, i] * xc
            for i in range(n):
                new[i] += Fq[q, k, i]
            for c in cols:
                v = lvec[c]
                for i in range(n):
                    new[i] += KlT[c, i] * v
            for i in range(n):
                out[q, k, i] = new[i]
