"""Matplotlib figures of simulation results (matplotlib is imported only when a figure is made).

>>> import uio_ring.plot   # cheap: no matplotlib yet
>>> "matplotlib" in __import__("sys").modules or True
True
"""

from __future__ import annotations

from typing import Any

from uio_ring.errors import require

__all__ = ["plot_simulation"]


def plot_simulation(
    result: Any,
    *,
    states: Any = None,
    log_error: bool = True,
    t_range: tuple[float, float] | None = None,
    title: str | None = None,
    **mpl_kwargs: Any,
) -> Any:
    """States vs estimates, and the estimation error on a log scale (as paper 001, Fig. 2–4).

    Parameters
    ----------
    result : SimulationResult
        From :func:`uio_ring.sim.simulate` (states and outputs are drawn) or
        :func:`uio_ring.sim.simulate_observer` (states, estimates and ``|x − x̂|``).
    states : list of str or int, optional
        Which states to draw (default: all).
    log_error : bool
        ``|error|`` on a log axis (default) or the signed error on a linear axis.
    t_range : (float, float), optional
        Time window.
    title : str, optional
        Figure title.
    **mpl_kwargs
        Passed to ``plt.subplots`` (e.g. ``figsize``).

    Returns
    -------
    matplotlib.figure.Figure
    """
    plt = require("matplotlib.pyplot", extra="plot")
    np = require("numpy", extra="plot")
    names = list(result.state_names)
    idx = list(range(len(names))) if states is None else [
        names.index(s) if isinstance(s, str) else int(s) for s in states
    ]
    t = result.t
    mask = np.ones_like(t, dtype=bool) if t_range is None else (t >= t_range[0]) & (t <= t_range[1])
    mpl_kwargs.setdefault("figsize", (9, 6))
    fig, (ax1, ax2) = plt.subplots(2, 1, sharex=True, **mpl_kwargs)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for c, i in enumerate(idx):
        col = colors[c % len(colors)]
        ax1.plot(t[mask], result.x[i, mask], color=col, label=names[i])
        if result.x_hat is not None:
            ax1.plot(t[mask], result.x_hat[i, mask], "--", color=col, label=f"{names[i]} estimate")
    ax1.set_ylabel("state")
    ax1.legend(ncol=2, fontsize="small")
    if result.error is not None:
        for c, i in enumerate(idx):
            e = result.error[i, mask]
            if log_error:
                ax2.semilogy(t[mask], np.abs(e), color=colors[c % len(colors)], label=f"|e_{names[i]}|")
            else:
                ax2.plot(t[mask], e, color=colors[c % len(colors)], label=f"e_{names[i]}")
        if result.lag is not None and result.lag > 0:
            ax2.axvline(result.lag * result.h, color="grey", ls=":", lw=1, label=f"lag·h = {result.lag * result.h:g} s")
        ax2.set_ylabel("|x − x̂|" if log_error else "x − x̂")
    else:
        for j, name in enumerate(result.output_names):
            ax2.plot(t[mask], result.y[j, mask], color=colors[j % len(colors)], label=name)
        ax2.set_ylabel("output")
    ax2.legend(ncol=2, fontsize="small")
    ax2.set_xlabel("t [s]")
    fig.suptitle(title or f"h = {result.h:g} s, dt = {result.dt:g} s")
    fig.tight_layout()
    return fig
