"""Summary figures of a sweep table: error vs each axis, a heatmap for two axes, convergence times."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from uio_ring.errors import require

__all__ = ["summary_plots"]


def _numeric_axes(table: Any, names: list[str]) -> list[str]:
    out = []
    for a in names:
        if a in table and np.issubdtype(table[a].dtype, np.number) and table[a].nunique() > 1:
            out.append(a)
    return out


def summary_plots(table: Any, sw: Any, out: Path) -> list[Path]:
    """Write the summary PNGs of ``table`` into ``out``; return their paths.

    ``<name>_errors.png``: the largest error ``‖x − x̂‖_∞`` after the settle time against each
    numeric axis (one point per run; for grid axes the median per value as a line);
    ``<name>_heatmap.png``: the median of its log10 over the first two numeric grid axes; ``<name>_convergence.png``:
    the histogram of the convergence times (runs that did not converge counted in the title).
    """
    matplotlib = require("matplotlib", extra="plot")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths: list[Path] = []
    ok = table[table["error"] == ""]
    axes = _numeric_axes(ok, [a.name for a in sw.axes])
    final = np.asarray(ok["max_settled"], dtype=float)
    label = "max error after settle"
    if axes:
        fig, axs = plt.subplots(1, len(axes), figsize=(4.2 * len(axes), 3.4), squeeze=False)
        for ax, a in zip(axs[0], axes, strict=True):
            x = np.asarray(ok[a], dtype=float)
            ax.scatter(x, final, s=10, alpha=0.6)
            if a in sw.grid_axes:
                xs = np.unique(x)
                ax.plot(xs, [np.median(final[x == v]) for v in xs], color="k", lw=1, label="median")
                ax.legend()
            ax.set_yscale("log")
            ax.set_xlabel(a)
        axs[0][0].set_ylabel(f"{label} ‖x − x̂‖∞")
        fig.suptitle(f"{sw.name}: {label} against each axis")
        paths.append(_save(fig, out / f"{sw.name}_errors.png", plt))
    grid = [a for a in axes if a in sw.grid_axes]
    if len(grid) >= 2:
        a, b = grid[:2]
        with np.errstate(divide="ignore"):
            logf = np.log10(final)
        df = ok.assign(_logf=logf)
        piv = df.pivot_table(index=b, columns=a, values="_logf", aggfunc="median")
        fig, ax = plt.subplots(figsize=(5.5, 4.2))
        im = ax.imshow(piv.to_numpy(), origin="lower", aspect="auto", cmap="viridis")
        ax.set_xticks(range(piv.shape[1]), [f"{v:.3g}" for v in piv.columns], rotation=45)
        ax.set_yticks(range(piv.shape[0]), [f"{v:.3g}" for v in piv.index])
        ax.set_xlabel(a)
        ax.set_ylabel(b)
        fig.colorbar(im, ax=ax, label=f"median log10 {label}")
        ax.set_title(f"{sw.name}: {a} × {b}")
        paths.append(_save(fig, out / f"{sw.name}_heatmap.png", plt))
    tc = np.asarray(ok["t_converge"], dtype=float)
    fig, ax = plt.subplots(figsize=(5.5, 3.4))
    conv = tc[np.isfinite(tc)]
    if conv.size:
        ax.hist(conv, bins=min(30, max(5, conv.size // 3)))
    ax.set_xlabel(f"convergence time to {sw.tol:g} [s]")
    ax.set_ylabel("runs")
    ax.set_title(f"{sw.name}: {conv.size} of {len(table)} runs converged "
                 f"({len(table) - len(ok)} failed)")
    paths.append(_save(fig, out / f"{sw.name}_convergence.png", plt))
    return paths


def _save(fig: Any, path: Path, plt: Any) -> Path:
    fig.savefig(path, dpi=100, bbox_inches="tight")
    plt.close(fig)
    return path
