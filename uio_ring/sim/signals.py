"""Input signals on the grid and bounded output noise.

Inputs ``w`` (unknown) and ``u`` (known) are callables of t — evaluated at every
grid time they are needed at, negative times included, since ``B(δ) w`` reads
``w(t − i h)`` — or arrays of samples on the grid of ``[0, t_final]`` (time on the
last axis), taken as zero before ``t = 0``.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from uio_ring.numeric.history import sample_signal
from uio_ring.sim.errors import DimensionError, SimulationError

__all__ = ["UniformNoise", "as_noise", "input_samples"]


@dataclass(frozen=True)
class UniformNoise:
    """Output noise, independent and uniform in ``[−amplitude, amplitude]`` at each grid sample.

    ``amplitude`` is a number or one number per output; ``seed`` makes it reproducible.

    >>> UniformNoise(2.0, seed=1).samples(3, 4).shape
    (3, 4)
    >>> bool(np.all(np.abs(UniformNoise(2.0).samples(3, 1000)) <= 2.0))
    True
    """

    amplitude: Any = 1.0
    seed: int | None = 0

    def samples(self, n_y: int, m: int) -> np.ndarray:
        amp = np.broadcast_to(np.asarray(self.amplitude, dtype=float), (n_y,)) if n_y else np.zeros(0)
        if np.any(~np.isfinite(amp)) or np.any(amp < 0):
            raise SimulationError(f"noise amplitude {self.amplitude!r} must be finite and ≥ 0")
        rng = np.random.default_rng(self.seed)
        return rng.uniform(-1.0, 1.0, size=(n_y, m)) * amp[:, None]

    def bound(self, n_y: int) -> np.ndarray:
        """Per-output bound of ``|noise|``."""
        return np.broadcast_to(np.asarray(self.amplitude, dtype=float), (n_y,)).copy()


def as_noise(noise: Any) -> UniformNoise | None:
    """``None``, a :class:`UniformNoise`, or a number / per-output vector (amplitude, seed 0)."""
    if noise is None or isinstance(noise, UniformNoise):
        return noise
    try:
        amp = np.asarray(noise, dtype=float)
    except (TypeError, ValueError) as exc:
        raise SimulationError(f"noise={noise!r}: expected None, an amplitude or UniformNoise(...)") from exc
    if np.any(~np.isfinite(amp)) or np.any(amp < 0):
        raise SimulationError(f"noise={noise!r}: the amplitude must be finite and ≥ 0")
    return UniformNoise(amp if amp.ndim else float(amp), seed=0)


def input_samples(sig: Any, n: int, *, j_min: int, j_max: int, n_steps: int, dt: float, name: str) -> np.ndarray:
    """Samples of an input at grid indices ``j_min … j_max`` (shape ``(n, j_max − j_min + 1)``).

    Arrays cover ``0 … n_steps`` (``n_steps + 1`` samples); zero before 0, held after
    ``n_steps`` (only reached by internal padding, never returned to the user).
    """
    m = j_max - j_min + 1
    if n == 0:
        if sig is not None:
            raise DimensionError(f"{name} was given, but the system has no {name} inputs (n_{name} = 0)")
        return np.zeros((0, m))
    if sig is None:
        return np.zeros((n, m))
    t = np.arange(j_min, j_max + 1) * dt
    if callable(sig):
        return sample_signal(sig, t, n, name)
    arr = np.asarray(sig, dtype=float)
    if arr.ndim == 0 and n == 1:
        arr = arr.reshape(1)
    if arr.ndim == 1 and arr.shape == (n,) and n_steps + 1 != n:
        return sample_signal(arr, t, n, name)  # a constant vector
    if arr.ndim == 1 and n == 1:
        arr = arr[None, :]
    if arr.shape != (n, n_steps + 1):
        raise DimensionError(
            f"{name} has shape {np.shape(sig)}; expected a callable of t or samples of shape "
            f"({n}, {n_steps + 1}) on the grid t = 0, dt, …, {n_steps}·dt"
        )
    bad = ~np.isfinite(arr)
    if bad.any():
        i, j = np.argwhere(bad)[0]
        raise SimulationError(f"{name} is not finite at component {i}, sample {j} (t = {j * dt:g})")
    out = np.zeros((n, m))
    lo, hi = max(j_min, 0), min(j_max, n_steps)
    if hi >= lo:
        out[:, lo - j_min : hi - j_min + 1] = arr[:, lo : hi + 1]
    if j_max > n_steps:
        out[:, max(n_steps + 1, j_min) - j_min :] = arr[:, -1:]
    return out
