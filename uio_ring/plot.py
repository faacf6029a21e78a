"""Matplotlib figures of simulation results (matplotlib is imported only when a figure is made).

>>> import uio_ring.plot   # cheap: no matplotlib yet
>>> "matplotlib" in __import__("sys").modules or True
True
"""

from __future__ import annotations

from typing import Any

from uio_ring.errors import require

__all__ = ["plot_simulation"]

#: How far below the largest error the log axis reaches (beyond: rounding noise).
ERROR_DECADES = 12


def _legend_outside(ax: Any) -> None:
    handles, _ = ax.get_legend_handles_labels()
    if handles:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small", frameon=False)


def _error_scale(np: Any, result: Any, idx: list[int], mask: Any, relative: bool | None) -> tuple[Any, bool]:
    """The error rows to draw, and whether they are relative to ``max(|x|, 1)`` per time."""
    err = result.error[idx][:, mask]
    x = result.x[idx][:, mask]
    if relative is None:  # unstable plants: the absolute error grows with |x|; show it relative
        start = max(float(np.abs(x[:, : max(1, x.shape[1] // 20)]).max()), 1.0)
        relative = float(np.abs(x[:, -max(1, x.shape[1] // 20):]).max()) > 100.0 * start
    if relative:
        err = err / np.maximum(np.abs(x).max(axis=0), 1.0)
    return err, relative


def plot_simulation(
    result: Any,
    *,
    states: Any = None,
    log_error: bool = True,
    relative_error: bool | None = None,
    t_range: tuple[float, float] | None = None,
    title: str | None = None,
    **mpl_kwargs: Any,
) -> Any:
    """States vs estimates, the unknown input vs its estimate, and the estimation error.

    Panels, top to bottom: each state and its estimate (same colour, estimate dashed);
    the unknown input ``w`` and, when the method reconstructs it, ``ŵ``; the error
    ``|x − x̂|`` on a log axis limited to :data:`ERROR_DECADES` decades below its
    maximum.  For a delay observer a dotted line marks ``t = lag·h``: from there on,
    ``x̂(t)`` is computed from observer values after ``t = 0`` only (before it, from
    the observer's start-up history).  Labels are the signal names.

    Parameters
    ----------
    result : SimulationResult
        From :func:`uio_ring.sim.simulate` (states and outputs are drawn) or
        :func:`uio_ring.sim.simulate_observer`.
    states : list of str or int, optional
        Which states to draw (default: all).
    log_error : bool
        ``|error|`` on a log axis (default) or the signed error on a linear axis.
    relative_error : bool, optional
        Error relative to ``max(‖x(t)‖∞, 1)``; default: only when the plant grows by more
        than 100× over the run (an unstable plant), where absolute errors are unreadable.
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
    observer = result.x_hat is not None
    show_w = observer and result.w.shape[0] > 0
    rows = 2 + int(show_w)
    mpl_kwargs.setdefault("figsize", (10, 2.6 * rows + 0.6))
    fig, axes = plt.subplots(rows, 1, sharex=True, **mpl_kwargs)
    ax_x, ax_last = axes[0], axes[-1]
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    tm = t[mask]
    for c, i in enumerate(idx):
        col = colors[c % len(colors)]
        ax_x.plot(tm, result.x[i, mask], color=col, label=names[i])
        if observer:
            ax_x.plot(tm, result.x_hat[i, mask], "--", color=col)
    if observer:  # one legend entry per state, and one for the line style
        ax_x.plot([], [], "k-", label="(solid: true)")
        ax_x.plot([], [], "k--", label="(dashed: estimate)")
    ax_x.set_ylabel("state")
    _legend_outside(ax_x)
    if show_w:
        ax_w = axes[1]
        for j, name in enumerate(result.unknown_input_names):
            col = colors[j % len(colors)]
            ax_w.plot(tm, result.w[j, mask], color=col, label=name)
            if result.w_hat is not None:
                ax_w.plot(tm, result.w_hat[j, mask], "--", color=col)
        ax_w.set_ylabel("unknown input")
        if result.w_hat is None:
            ax_w.set_title("w is not reconstructed by this method", fontsize="small", loc="right")
        _legend_outside(ax_w)
    caption = ""
    if observer:
        err, rel = _error_scale(np, result, idx, mask, relative_error)
        what = "|x − x̂| / max(‖x‖∞, 1)" if rel else "|x − x̂|"
        for c, i in enumerate(idx):
            e = err[c]
            col = colors[c % len(colors)]
            if log_error:
                ax_last.semilogy(tm, np.abs(e), color=col, label=names[i])
            else:
                ax_last.plot(tm, e, color=col, label=names[i])
        if log_error:
            top = float(np.nanmax(np.abs(err))) if err.size else 1.0
            if np.isfinite(top) and top > 0:
                ax_last.set_ylim(top * 10.0 ** (-ERROR_DECADES), top * 3)
        if result.lag:
            ax_last.axvline(result.lag * result.h, color="grey", ls=":", lw=1)
            caption = (f"dotted line: t = lag·h = {result.lag * result.h:g} s; from there on x̂(t) uses observer "
                       "values after t = 0 only")
        ax_last.set_ylabel(what if log_error else what.replace("|", ""))
    else:
        for j, name in enumerate(result.output_names):
            ax_last.plot(tm, result.y[j, mask], color=colors[j % len(colors)], label=name)
        ax_last.set_ylabel("output")
    _legend_outside(ax_last)
    ax_last.set_xlabel("t [s]" + (f"\n{caption}" if caption else ""))
    fig.suptitle(title or f"h = {result.h:g} s, dt = {result.dt:g} s")
    fig.tight_layout()
    return fig
