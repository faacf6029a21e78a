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


#: The signal kinds of a result, in column order: (attribute, label source, prefix).
_KINDS = (
    ("x", "state_names", "x"),
    ("y", "output_names", "y"),
    ("w", "unknown_input_names", "w"),
    ("u", "known_input_names", "u"),
    ("x_hat", "state_names", "x_hat"),
    ("error", "state_names", "error"),
    ("w_hat", "unknown_input_names", "w_hat"),
)


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
    w_hat : (n_w, T) array or None — the unknown-input estimate, for methods that reconstruct it
    h, dt : float; N = h/dt
    lag : int or None — the estimate at t reads the observer's state over ``[t − lag·h, t]``
    success, message : bool, str — False and the reason when the a-posteriori accuracy check
        failed (:attr:`accuracy`; the numbers are then not to be trusted)
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
    unknown_input_names: tuple[str, ...] = ()
    known_input_names: tuple[str, ...] = ()
    noise: np.ndarray | None = None
    x_hat: np.ndarray | None = None
    error: np.ndarray | None = None
    w_hat: np.ndarray | None = None
    lag: int | None = None
    success: bool = True
    message: str = ""
    extra: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        put = object.__setattr__
        put(self, "state_names", _labels(self.state_names, self.x.shape[0], "x"))
        put(self, "output_names", _labels(self.output_names, self.y.shape[0], "y"))
        put(self, "unknown_input_names", _labels(self.unknown_input_names, self.w.shape[0], "w"))
        put(self, "known_input_names", _labels(self.known_input_names, self.u.shape[0], "u"))

    @property
    def accuracy(self) -> Any:
        """The a-posteriori :class:`~uio_ring.sim.accuracy.AccuracyCheck` of an observer run
        (None when it was not checked); ``success`` is False when it fails."""
        return self.extra.get("accuracy")

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

    @property
    def input_estimates(self) -> Signals | None:
        return None if self.w_hat is None else Signals(self.w_hat, self.unknown_input_names)

    def error_norm(self, ord: float = np.inf) -> np.ndarray:
        """``‖x(t) − x̂(t)‖`` at every grid time (max norm by default)."""
        if self.error is None:
            raise AttributeError("this result has no estimate (use simulate_observer)")
        return np.linalg.norm(self.error, ord=ord, axis=0)

    def columns(self) -> dict[str, np.ndarray]:
        """Every signal as one named column: ``t``, then ``kind.name`` (``x.p``, ``y.p``,
        ``w.w[0]``, ``u.u[0]``, ``x_hat.p``, ``error.p``, ``w_hat.w[0]``).

        Signal names never contain ``.``, so ``kind.name`` never collides — a state and
        an output may share a name, and a state may be called ``t``.

        >>> r = SimulationResult(t=np.zeros(2), x=np.ones((1, 2)), y=np.ones((1, 2)), w=np.zeros((0, 2)),
        ...                      u=np.zeros((0, 2)), h=1.0, dt=1.0, state_names=("p",), output_names=("p",))
        >>> list(r.columns())
        ['t', 'x.p', 'y.p']
        """
        cols: dict[str, np.ndarray] = {"t": self.t}
        for attr, names, prefix in _KINDS:
            arr = getattr(self, attr)
            if arr is None:
                continue
            for name, row in zip(getattr(self, names), arr, strict=True):
                cols[f"{prefix}.{name}"] = row
        return cols

    def plot(self, **mpl_kwargs: Any) -> Any:
        """States vs estimates and the error on a log scale; see :func:`uio_ring.plot.plot_simulation`."""
        from uio_ring.plot import plot_simulation

        return plot_simulation(self, **mpl_kwargs)

    def to_pandas(self) -> Any:
        """A DataFrame indexed by t with the columns of :meth:`columns` (pandas needed)."""
        from uio_ring.errors import require

        pd = require("pandas", extra="notebooks")
        cols = self.columns()
        t = cols.pop("t")
        return pd.DataFrame(cols, index=pd.Index(t, name="t"))

    def __repr__(self) -> str:
        kind = "plant+observer" if self.x_hat is not None else "plant"
        return (
            f"<SimulationResult {kind}: {self.x.shape[0]} states, {self.y.shape[0]} outputs, "
            f"t = 0…{self.t[-1]:g} ({len(self.t)} samples), h = {self.h:g}, dt = {self.dt:g}>"
        )
