"""History of a delayed signal on the grid ``t_j = j·dt``, ``dt = h/N``.

The delay ``i·h`` is exactly ``i·N`` grid steps, so ``x(t − i h)`` is a lookup,
never an interpolation.  :func:`sample_history` turns an initial function φ on
``[−k h, 0]`` (callable, constant vector or array of samples) into grid samples;
:class:`HistoryBuffer` keeps the last ``k·N + 1`` samples (plus any extra
``lookback``) in a ring buffer of constant size, for streaming use.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from uio_ring.errors import DimensionError, SimulationError
from uio_ring.numeric.grid import as_float, steps_per_delay

__all__ = ["HistoryBuffer", "sample_history", "sample_signal"]


def sample_signal(f: Any, t: np.ndarray, n: int, name: str) -> np.ndarray:
    """Samples of a signal at times ``t`` as an ``(n, len(t))`` array (time on the last axis).

    ``f`` is a callable of t (vectorised — ``f(t_array)`` of shape ``(n, len(t))``,
    or ``(len(t),)`` when n = 1 — or scalar, called once per sample) or a constant
    vector of length n.
    """
    m = len(t)
    if callable(f):
        out = None
        try:
            with np.errstate(all="ignore"):
                out = np.asarray(f(t), dtype=float)
        except Exception:  # noqa: BLE001 - a scalar-only callable; evaluate sample by sample
            out = None
        if out is not None and out.shape == (n, m):
            pass
        elif out is not None and n == 1 and out.shape == (m,):
            out = out[None, :]
        else:
            cols = []
            for tj in t:
                v = np.asarray(f(float(tj)), dtype=float).reshape(-1)
                if v.shape != (n,):
                    raise DimensionError(
                        f"{name}(t) returns shape {np.shape(f(float(tj)))}; expected ({n},) for a scalar t "
                        f"or ({n}, len(t)) for an array t"
                    )
                cols.append(v)
            out = np.stack(cols, axis=1) if cols else np.zeros((n, 0))
    else:
        v = np.asarray(f, dtype=float)
        if v.ndim == 0 and n == 1:
            v = v.reshape(1)
        if v.shape != (n,):
            raise DimensionError(f"{name} has shape {v.shape}; expected a constant vector of shape ({n},)")
        out = np.repeat(v[:, None], m, axis=1)
    bad = ~np.isfinite(out)
    if bad.any():
        i, j = np.argwhere(bad)[0]
        raise SimulationError(f"{name} is not finite (component {i}, t = {t[j]:g}): {out[i, j]}")
    return out


def sample_history(phi: Any, n: int, *, N: int, k: int, dt: float, name: str = "phi") -> np.ndarray:
    """Grid samples of φ on ``[−k h, 0]``: shape ``(n, k·N + 1)``, oldest first, last = x(0).

    ``phi`` is None (zero history), a callable of t, a constant vector, or an array of
    exactly ``k·N + 1`` samples with time on the last axis.

    >>> sample_history([1.0, 2.0], 2, N=2, k=1, dt=0.5)
    array([[1., 1., 1.],
           [2., 2., 2.]])
    """
    L = k * N + 1
    t = (np.arange(L) - (L - 1)) * dt
    if phi is None:
        return np.zeros((n, L))
    if callable(phi):
        return sample_signal(phi, t, n, name)
    arr = np.asarray(phi, dtype=float)
    if arr.ndim == 1 and arr.shape == (n,):
        return sample_signal(arr, t, n, name)
    if arr.ndim == 1 and n == 1:
        arr = arr[None, :]
    if arr.shape != (n, L):
        raise DimensionError(
            f"{name} has shape {np.shape(phi)}; expected a callable, a constant vector of shape ({n},) "
            f"or samples of shape ({n}, {L}) on the grid of [−{k}h, 0] (k = {k}, N = {N})"
        )
    bad = ~np.isfinite(arr)
    if bad.any():
        i, j = np.argwhere(bad)[0]
        raise SimulationError(f"{name} is not finite at component {i}, sample {j}")
    return arr.copy()


class HistoryBuffer:
    """Ring buffer of the last ``k·N + 1 + lookback`` samples of an n-vector signal.

    Parameters
    ----------
    n : int
        Signal dimension.
    h, dt : float
        Basic delay and step; ``dt = h/N`` with N a positive integer.
    max_delay : int
        Largest delay multiple k needed (``x(t − k h)``).
    phi : callable, array_like or None
        Initial history on ``[−k h, 0]`` (see :func:`sample_history`); None: zero.
    lookback : int
        Extra samples kept beyond ``k h`` (for interpolation stencils).

    After construction the newest sample is ``x(0) = φ(0)``; :meth:`push` appends the
    next grid sample.  :meth:`lookup` returns ``x(t_now − i h − j dt)`` exactly.

    >>> buf = HistoryBuffer(1, h=1.0, dt=0.5, max_delay=1, phi=lambda t: t)
    >>> buf.lookup(1), buf.lookup(0, 1)
    (array([-1.]), array([-0.5]))
    >>> buf.push([0.5]); buf.lookup(1)
    array([-0.5])
    """

    def __init__(self, n: int, *, h: Any, dt: Any, max_delay: int, phi: Any = None, lookback: int = 0):
        self.h, self.dt = as_float(h, "h"), as_float(dt, "dt")
        self.N = steps_per_delay(self.h, self.dt)
        if int(max_delay) != max_delay or max_delay < 0:
            raise SimulationError(f"max_delay={max_delay!r} must be a non-negative integer")
        self.n, self.max_delay = int(n), int(max_delay)
        self.capacity = self.max_delay * self.N + 1 + int(lookback)
        samples = sample_history(phi, self.n, N=self.N, k=self.max_delay, dt=self.dt)
        # extend further back with the oldest sample (constant extension) for the lookback
        self._buf = np.empty((self.capacity, self.n))
        self._buf[: self.capacity - samples.shape[1]] = samples[:, 0]
        self._buf[self.capacity - samples.shape[1] :] = samples.T
        self._head = self.capacity - 1  # index of the newest sample
        self.steps = 0

    @classmethod
    def from_samples(cls, samples: Any, *, h: Any, dt: Any) -> HistoryBuffer:
        """A buffer holding exactly ``samples`` (shape ``(n, L)``, oldest first; the last is "now").

        >>> buf = HistoryBuffer.from_samples([[0.0, 1.0, 2.0, 3.0]], h=0.2, dt=0.1)
        >>> buf.capacity, buf.lookup(1), buf.lookup(1, 1)
        (4, array([1.]), array([0.]))
        """
        arr = np.asarray(samples, dtype=float)
        if arr.ndim != 2 or arr.shape[1] < 1:
            raise DimensionError(f"samples have shape {arr.shape}; expected (n, L) with L ≥ 1")
        self = cls.__new__(cls)
        self.h, self.dt = as_float(h, "h"), as_float(dt, "dt")
        self.N = steps_per_delay(self.h, self.dt)
        self.n, self.capacity = arr.shape[0], arr.shape[1]
        self.max_delay = (self.capacity - 1) // self.N
        self._buf = np.ascontiguousarray(arr.T)
        self._head = self.capacity - 1
        self.steps = 0
        return self

    def push(self, sample: Any) -> None:
        """Append the sample at the next grid time ``t_now + dt``."""
        v = np.asarray(sample, dtype=float).reshape(-1)
        if v.shape != (self.n,):
            raise DimensionError(f"sample has shape {np.shape(sample)}; expected ({self.n},)")
        self._head = (self._head + 1) % self.capacity
        self._buf[self._head] = v
        self.steps += 1

    def lookup(self, i: int, j: int = 0) -> np.ndarray:
        """``x(t_now − i·h − j·dt)`` (a copy)."""
        back = i * self.N + j
        if back < 0 or back >= self.capacity:
            raise SimulationError(
                f"lookup({i}, {j}) reaches {back} samples back; the buffer holds {self.capacity}"
            )
        return self._buf[(self._head - back) % self.capacity].copy()

    def window(self, length: int) -> np.ndarray:
        """The last ``length`` samples, oldest first, shape ``(length, n)``."""
        if not 0 < length <= self.capacity:
            raise SimulationError(f"window({length}) exceeds the buffer of {self.capacity} samples")
        idx = (self._head - np.arange(length - 1, -1, -1)) % self.capacity
        return self._buf[idx]

    @property
    def t_now(self) -> float:
        """Time of the newest sample."""
        return self.steps * self.dt

    def __repr__(self) -> str:
        return (
            f"HistoryBuffer(n={self.n}, h={self.h:g}, dt={self.dt:g}, N={self.N}, "
            f"max_delay={self.max_delay}, capacity={self.capacity}, t_now={self.t_now:g})"
        )
