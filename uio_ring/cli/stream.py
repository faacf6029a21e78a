"""Long simulations streamed to CSV: memory bounded whatever the number of steps.

``uio-ring simulate`` keeps a run in memory when its record (steps × columns) has at
most :data:`STREAM_VALUES` values.  A longer run written as CSV is computed by segments
of whole delay blocks (:func:`uio_ring.sim.batch.simulate_batch` with one scenario and
``on_segment``: the plant and the observer carry only the tails they read) and every
segment's rows are written as soon as they are computed.  Memory is then one segment
plus a preview of at most :data:`PREVIEW_POINTS` samples (every k-th one) for the plot;
the summary figures are accumulated on the fly.  Runs with a ``nonlinearity`` and NPZ
output are kept in memory (bounded by ``MAX_RECORDED_VALUES`` at load).

Before the long run, its start is simulated in memory with the accuracy check of
:mod:`uio_ring.sim.accuracy` (the same window as an in-memory run).

>>> streamed(steps=10**6, columns=11, nonlinear=False, npz=False)
True
>>> streamed(steps=3000, columns=11, nonlinear=False, npz=False)
False
"""

from __future__ import annotations

import csv
from collections.abc import Callable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["PREVIEW_POINTS", "STREAM_VALUES", "StreamSummary", "stream_csv", "streamed", "write_rows"]

STREAM_VALUES = 5_000_000  # records larger than this (steps × columns) are streamed
PREVIEW_POINTS = 20_000  # samples kept for the plot of a streamed run
_KINDS = ("t", "x", "y", "w", "u", "x_hat", "error", "w_hat")


def streamed(*, steps: int, columns: int, nonlinear: bool, npz: bool) -> bool:
    """Whether ``simulate`` streams this run (a large CSV record without a nonlinearity)."""
    return steps * columns > STREAM_VALUES and not nonlinear and not npz


def write_rows(writer: Any, data: np.ndarray) -> None:
    """Rows of ``data`` ``(T, columns)`` with 10 significant digits (the CSV format of ``simulate``)."""
    writer.writerows([f"{v:.10g}" for v in row] for row in data)


@dataclass
class StreamSummary:
    """What the summary line needs, accumulated over the segments."""

    steps: int = 0
    t_last: float = 0.0
    final: float = 0.0
    max_after: float = 0.0
    w_max_after: float | None = None
    preview: Any = None  # SimulationResult of every k-th sample, for the plot


def _result(seg: Any, system: Any, h: float, dt: float) -> Any:
    """One segment (scenario 0) as a :class:`~uio_ring.sim.result.SimulationResult`."""
    from uio_ring.sim.result import SimulationResult

    def rows(a: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(a[:, 0, :].T)

    x, xh = rows(seg.x), rows(seg.x_hat)
    return SimulationResult(
        t=seg.t, x=x, y=rows(seg.y), w=rows(seg.w), u=rows(seg.u), h=h, dt=dt,
        state_names=system.state_names, output_names=system.output_names,
        unknown_input_names=system.unknown_input_names, known_input_names=system.known_input_names,
        x_hat=xh, error=x - xh, w_hat=None if seg.w_hat is None else rows(seg.w_hat),
    )


def stream_csv(design: Any, spec: Any, path: Path, *, settle: float, check: Callable[[Any], None],
               progress: bool | None = None, preview: bool = True, segment_steps: int | None = None) -> StreamSummary:
    """Simulate ``spec`` with ``design`` by segments and write the CSV to ``path``.

    ``check(segment_result)`` raises on a segment that must stop the run (non-finite values);
    ``segment_steps`` as in :func:`~uio_ring.sim.batch.simulate_batch` (default: about 2²⁰
    values per segment array).
    """
    from uio_ring.numeric.grid import step_count
    from uio_ring.sim.batch import Scenario, simulate_batch

    sim, system = spec.simulate, spec.system
    dt = float(sim.dt)
    h = float(sim.h) if system.h is not None else dt
    steps = step_count(float(sim.t_final), dt)
    stride = max(1, -(-(steps + 1) // PREVIEW_POINTS))
    noise = sim.noise()
    scenario = Scenario(x0=sim.signal("phi"), w=sim.signal("w"), u=sim.signal("u"),
                        noise=None if noise is None else noise.amplitude,
                        seed=None if noise is None else noise.seed,
                        x_hat0=None if sim.x_hat0 is None else [float(v) for v in sim.x_hat0])
    out = StreamSummary()
    kept: dict[str, np.ndarray] = {}  # every stride-th sample, preallocated: (n, ≤ PREVIEW_POINTS)
    first: list[Any] = []
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)

        def on_segment(seg: Any) -> None:
            res = _result(seg, system, h, dt)
            check(res)
            cols = res.columns()
            if out.steps == 0 and res.t[0] == 0.0:
                writer.writerow(list(cols))
            write_rows(writer, np.column_stack(list(cols.values())))
            err = np.max(np.abs(res.error), axis=0) if res.error.shape[0] else np.zeros(res.t.size)
            late = res.t >= settle
            if late.any():
                out.max_after = max(out.max_after, float(err[late].max()))
                if res.w_hat is not None:
                    w_err = np.max(np.abs(res.w - res.w_hat), axis=0)[late]
                    out.w_max_after = max(out.w_max_after or 0.0, float(w_err.max()))
            out.final, out.t_last = float(err[-1]), float(res.t[-1])
            out.steps = int(round(out.t_last / dt))
            if preview:
                j = np.rint(res.t / dt).astype(np.int64)
                pick = np.nonzero(j % stride == 0)[0]
                if not first:  # names, h, dt of the preview (its arrays come from kept)
                    first.append(replace(res, **{k: getattr(res, k)[..., :1] for k in _KINDS
                                                 if getattr(res, k) is not None}))
                for k in _KINDS:
                    a = getattr(res, k)
                    if a is None:
                        continue
                    if k not in kept:
                        kept[k] = np.zeros(a.shape[:-1] + (steps // stride + 1,))
                    kept[k][..., j[pick] // stride] = a[..., pick]

        simulate_batch(design, [scenario], t_final=float(sim.t_final), dt=dt, plant=system,
                       discretisation=sim.discretisation, progress=progress, on_segment=on_segment,
                       segment_steps=segment_steps)
    if first:
        n = out.steps // stride + 1
        out.preview = replace(first[0], **{k: v[..., :n] for k, v in kept.items()})
    return out

