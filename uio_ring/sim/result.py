"""Result objects of the simulations: arrays with time on the last axis, signals by label."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

__all__ = ["Signals", "SimulationResult"]


class Signals:
    """Read-only view of a ``(n, T)`` array whose rows have labels.

    ``sig['x[0]']`` or ``sig[0]`` is one row; ``np.asarray(sig)`` the whole array.

    >>> s = Signals(np.arange(6.0).reshape(2, 3), ["a", "b"])
    >>> s["b"], s.labels, s.shape
    (array([3., 4., 5.]), ('a', 'b'), (2, 3))
    """

    def __init__(self, array: np.ndarray, labels: Sequence[str]):
        self.array = array
        self.labels = tuple(labels)

    def __getitem__(self, key: Any) -> np.ndarray:
        if isinstance(key, str):
            try:
                return self.array[self.labels.index(key)]
            except ValueError:
                raise KeyError(f"{key!r}: no such signal; the labels are {list(self.labels)}") from None
        return self.array[key]

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        return self.array if dtype is None else self.array.astype(dtype)

    @property
    def shape(self) -> tuple[int, ...]:
        return self.array.shape

    def __len__(self) -> int:
        return len(self.labels)

    def __repr__(self) -> str:
        return f"Signals({list(self.labels)}, shape={self.array.shape})"


def _labels(names: Any, n: int, letter: str) -> tuple[str, ...]:
    if names is not None and len(names) == n:
        return tuple(str(s) for s in names)
    return tuple(f"{letter}[{i}]" for i in range(n))


@dataclass(frozen=True, eq=False)
class SimulationResult:
    """Plant (and observer) trajectories on the grid ``t = 0, dt, …``; time on the last axis.

    Attributes
    ----------
    t : (T,) array
    x : (n_x, T) array — plant state
    y : (n_y, T) array — measured output (noise included)
    w, u : (n_w, T), (n_u, T) arrays — unknown and known inputs on the grid
    noise : (n_y, T) array or None — the output noise that was added
    x_hat, error : (n_x, T) arrays or None — estimate and ``x − x_hat`` (observer runs)
    h, dt : float; N = h/dt
    lag : int or None — deg T_L⁻¹: the estimate uses ẑ over ``[t − lag h, t]``
    """

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    w: np.ndarray
    u: np.ndarray
    h: float
    dt: float
    state_names: tuple[str, ...] = ()
    output_names: tuple[str, ...] = ()
    noise: np.ndarray | None = None
    x_hat: np.ndarray | None = None
    error: np.ndarray | None = None
    lag: int | None = None
    success: bool = True
    message: str = ""
    extra: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        object.__setattr__(self, "state_names", _labels(self.state_names, self.x.shape[0], "x"))
        object.__setattr__(self, "output_names", _labels(self.output_names, self.y.shape[0], "y"))

    @property
    def N(self) -> int:
        return int(round(self.h / self.dt))

    @property
    def time(self) -> np.ndarray:
        return self.t

    @property
    def states(self) -> Signals:
        return Signals(self.x, self.state_names)

    @property
    def outputs(self) -> Signals:
        return Signals(self.y, self.output_names)

    @property
    def estimates(self) -> Signals | None:
        return None if self.x_hat is None else Signals(self.x_hat, self.state_names)

    @property
    def errors(self) -> Signals | None:
        return None if self.error is None else Signals(self.error, self.state_names)

    def error_norm(self, ord: float = np.inf) -> np.ndarray:
        """``‖x(t) − x̂(t)‖`` at every grid time (max norm by default)."""
        if self.error is None:
            raise AttributeError("this result has no estimate (use simulate_observer)")
        return np.linalg.norm(self.error, ord=ord, axis=0)

    def plot(self, **mpl_kwargs: Any) -> Any:
        """States vs estimates and the error on a log scale; see :func:`uio_ring.plot.plot_simulation`."""
        from uio_ring.plot import plot_simulation

        return plot_simulation(self, **mpl_kwargs)

    def to_pandas(self) -> Any:
        """A DataFrame indexed by t with one column per signal (pandas needed)."""
        from uio_ring.errors import require

        pd = require("pandas", extra="notebooks")
        cols: dict[str, np.ndarray] = {}
        for name, row in zip(self.state_names, self.x, strict=True):
            cols[name] = row
        for name, row in zip(self.output_names, self.y, strict=True):
            cols[name] = row
        if self.x_hat is not None and self.error is not None:
            for name, row, err in zip(self.state_names, self.x_hat, self.error, strict=True):
                cols[f"{name}_hat"] = row
                cols[f"e_{name}"] = err
        return pd.DataFrame(cols, index=pd.Index(self.t, name="t"))

    def __repr__(self) -> str:
        kind = "plant+observer" if self.x_hat is not None else "plant"
        return (
            f"<SimulationResult {kind}: {self.x.shape[0]} states, {self.y.shape[0]} outputs, "
            f"t = 0…{self.t[-1]:g} ({len(self.t)} samples), h = {self.h:g}, dt = {self.dt:g}>"
        )
