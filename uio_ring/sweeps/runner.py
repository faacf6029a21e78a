"""Running a sweep: chunks as tasks (local processes or dask.distributed), one file per chunk.

Each chunk (runs that share the design and the plant's true delay) is one task: it
designs the observer once, builds one :class:`~uio_ring.sim.batch.Scenario` per run
(with the run's perturbed plant, if any) and calls
:func:`~uio_ring.sim.batch.simulate_batch` once: runs on differently perturbed plants
are integrated together (one plant per scenario).  Its rows are written to
``<out>/chunks/<chunk file>`` as soon as it is done; a rerun of the same sweep
skips the chunks whose file exists (the file name carries a hash of everything that
changes the numbers).  A run that cannot be built, or a chunk whose design fails,
gives rows with the error message instead of metrics.
"""

from __future__ import annotations

import json
import os
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from uio_ring.errors import SpecError, require
from uio_ring.numeric.grid import steps_per_delay
from uio_ring.sim.plant import perturbed_plant
from uio_ring.sweeps.spec import Chunk, Run, SweepSpec, load_sweep

__all__ = ["sweep", "SweepResult", "run_chunk"]

_DESIGNS: dict[str, Any] = {}  # per process: design key -> (spec, design, noise gain)


# ---------------------------------------------------------------------------------- one chunk
def _spec_for(base: dict[str, Any], params: dict[str, Any], options: Sequence[str]) -> Any:
    from uio_ring.spec.loader import spec_from_dict

    data = dict(base)
    design = dict(data.get("design") or {})
    for k, v in params.items():
        if k == "method" or k in options:
            design[k] = v
    if design:
        data["design"] = design
    return spec_from_dict(data)


def _design(spec: Any) -> Any:
    from uio_ring.design.methods import design_auto, design_with

    if spec.design.method == "auto":
        return design_auto(spec.system, **spec.design.options).design
    return design_with(spec.design.method, spec.system, **spec.design.options)


def _noise_gain(design: Any, h: Any) -> float:
    """``max_i Σ_j P_ij`` of ``design.performance()`` (the continuous peak-to-peak gain, the
    figure that ``uio-ring design`` prints): the largest estimate deviation per unit bound
    of the output noise.  NaN when there is no such figure (an injection term, F not
    Hurwitz, modes too far apart to integrate; the design output says which)."""
    from uio_ring.errors import UioRingError

    try:
        return float(design.performance(h=h).noise_gain.max())
    except UioRingError:
        return float("nan")


def _w_signal(spec: Any, p: dict[str, Any], seed: int, n_w: int, t_final: float) -> Any:
    fam = p.get("w_family", "base")
    a = float(p.get("w_amplitude", 1.0))
    f = float(p.get("w_frequency", 1.0))
    if fam == "zero" or n_w == 0:
        return None
    if fam == "base":
        base = spec.simulate.signal("w")
        return None if base is None else (lambda t: a * base(t))
    if fam == "sine":
        phase = np.random.default_rng([seed, 17]).uniform(0, 2 * np.pi, size=(n_w, 1))
        return lambda t: a * np.sin(f * np.asarray(t, dtype=float)[None, :] + phase)
    if fam == "step":
        return lambda t: a * np.repeat((np.asarray(t, dtype=float) >= 1.0 / f)[None, :], n_w, axis=0).astype(float)
    levels = np.random.default_rng([seed, 23]).uniform(-a, a, size=(n_w, int(np.ceil(t_final * f)) + 2))

    def pwc(t: Any) -> Any:  # random piecewise constant, dwell 1/f, zero before 0
        t = np.asarray(t, dtype=float)
        k = np.clip(np.floor(t * f).astype(int), 0, levels.shape[1] - 1)
        return np.where(t[None, :] >= 0, levels[:, k], 0.0)

    return pwc


def _scenario(spec: Any, run: Run, n_x: int, n_w: int, plant: Any = None, plant_h: Any = None) -> Any:
    from uio_ring.sim.batch import Scenario
    from uio_ring.sim.signals import UniformNoise

    sim, p = spec.simulate, run.params
    scale = float(p.get("x0_scale", 1.0))
    r = float(p.get("x0_random", 0.0))
    phi = sim.signal("phi")
    shift = np.random.default_rng([run.seed, 29]).uniform(-r, r, size=(n_x, 1)) if r else np.zeros((n_x, 1))
    if phi is None:
        x0: Any = shift[:, 0]
    else:
        x0 = lambda t: scale * phi(t) + shift  # noqa: E731
    base_noise = sim.noise()
    amp = p.get("noise", None if base_noise is None else base_noise.amplitude)
    seed = int(p.get("noise_seed", run.seed))
    noise = None if amp is None else UniformNoise(amp, seed=seed)
    x_hat0 = None if sim.x_hat0 is None else [float(v) for v in sim.x_hat0]
    return Scenario(x0=x0, w=_w_signal(spec, p, run.seed, n_w, float(sim.t_final)), u=sim.signal("u"),
                    noise=noise, x_hat0=x_hat0, plant=plant, plant_h=plant_h)


def _row(run: Run, chunk: int, axes: Sequence[str], metrics: dict[str, float], gain: float, error: str) -> dict:
    from uio_ring.sim.batch import METRICS

    row: dict[str, Any] = {"run": run.run, "seed": run.seed, "chunk": chunk}
    for a in axes:
        v = run.params.get(a)
        row[a] = json.dumps(v) if isinstance(v, (list, dict)) else v
    for k in METRICS:
        row[k] = float(metrics.get(k, np.nan))
    row["noise_gain"] = gain
    row["error"] = error
    return row


def run_chunk(task: dict[str, Any]) -> list[dict[str, Any]]:
    """One chunk: design once, simulate every run of it in one batch; rows (errors included)."""
    from uio_ring.sim.batch import simulate_batch

    chunk: Chunk = task["chunk"]
    axes, base, options = task["axes"], task["base"], task["options"]
    runs = chunk.runs
    p0 = runs[0].params
    try:
        key = json.dumps({"base": task["fingerprint"], "d": {k: v for k, v in p0.items() if k == "method" or k in options}},
                         sort_keys=True, default=str)
        if key not in _DESIGNS:
            spec = _spec_for(base, p0, options)
            design = _design(spec)
            sim = spec.simulate
            h = None if spec.system.h is None else float(sim.h)
            _DESIGNS[key] = (spec, design, _noise_gain(design, h))
        spec, design, gain = _DESIGNS[key]
    except Exception as exc:  # noqa: BLE001 - a failing design is a row per run, not a lost chunk
        msg = f"{type(exc).__name__}: {exc}"
        return [_row(r, chunk.index, axes, {}, np.nan, msg) for r in runs]
    sim = spec.simulate
    rows: dict[int, dict[str, Any]] = {}
    good, scen = [], []
    for r in runs:
        try:
            plant = perturbed_plant(spec.system, float(r.params.get("perturbation", 0.0)),
                           int(r.params.get("perturbation_seed", 0)))
            h_true = r.params.get("h_true")
            if h_true is not None:
                steps_per_delay(float(h_true), float(sim.dt))  # a grid that does not fit: this run's error
            scen.append(_scenario(spec, r, spec.system.n_x, spec.system.n_w, plant, h_true))
            good.append(r)
        except Exception as exc:  # noqa: BLE001
            rows[r.run] = _row(r, chunk.index, axes, {}, gain, f"{type(exc).__name__}: {exc}")
    if good:
        try:
            res = simulate_batch(design, scen, plant=spec.system, t_final=float(sim.t_final),
                                 dt=float(sim.dt), tol=task["tol"], diverge=task["diverge"],
                                 settle=None if sim.settle is None else float(sim.settle),
                                 discretisation=p0.get("discretisation", sim.discretisation))
            for i, r in enumerate(good):
                rows[r.run] = _row(r, chunk.index, axes, {k: v[i] for k, v in res.metrics.items()}, gain, "")
        except Exception as exc:  # noqa: BLE001
            msg = f"{type(exc).__name__}: {exc}"
            for r in good:
                rows[r.run] = _row(r, chunk.index, axes, {}, gain, msg)
    return [rows[r.run] for r in runs]


# ---------------------------------------------------------------------------------- the sweep
@dataclass(frozen=True, eq=False)
class SweepResult:
    """What :func:`sweep` returns: the table (a pandas DataFrame, one row per run), where it
    was written, the chunks computed now and the chunks found done, and the summary PNGs."""

    table: Any
    path: Path
    computed: int
    skipped: int
    plots: tuple[Path, ...] = ()
    files: tuple[Path, ...] = field(default=())

    def __repr__(self) -> str:
        return (f"<SweepResult: {len(self.table)} runs, {self.computed} chunks computed, {self.skipped} found done; "
                f"{self.path}>")


def _replace(path: Path, write: Callable[[Path], Any]) -> None:
    """Write through a temporary file and rename: ``path`` is complete or unchanged."""
    tmp = path.with_name(f".{path.name}.tmp")
    try:
        write(tmp)
        os.replace(tmp, path)
    finally:
        tmp.unlink(missing_ok=True)


def _write_chunk(rows: list[dict[str, Any]], path: Path) -> None:
    pd = require("pandas", extra="sweep")
    _replace(path, lambda tmp: pd.DataFrame(rows).to_parquet(tmp, index=False))  # complete or absent


def _progress(total_runs: int, show: bool) -> Callable[[int], None]:
    t0 = time.perf_counter()
    done = [0]

    def update(n: int) -> None:
        done[0] += n
        if not show:
            return
        el = time.perf_counter() - t0
        left = el / done[0] * (total_runs - done[0]) if done[0] else float("nan")
        end = "\n" if done[0] >= total_runs else ""
        print(f"\rsweep: {done[0]}/{total_runs} runs, {el:.0f} s elapsed, ~{left:.0f} s left", end=end,
              file=sys.stderr, flush=True)

    return update


def sweep(
    sweep_file: Any,
    *,
    out: Any = None,
    workers: int | None = None,
    scheduler: str | None = None,
    formats: Sequence[str] | None = None,
    progress: bool | None = None,
    on_chunk: Callable[[Chunk], None] | None = None,
) -> SweepResult:
    """Run a sweep (a file name, or a :class:`SweepSpec`); write one Parquet file per chunk and the table.

    Parameters
    ----------
    sweep_file : str, Path or SweepSpec
    out : directory, optional
        Default: the sweep's ``output.directory`` (relative to the file), else ``./uio-ring-out/<name>``.
    workers : int, optional
        Local processes (default: ``os.cpu_count()``); 1 runs in this process.
    scheduler : str, optional
        Address of a ``dask.distributed`` scheduler: the chunks are its tasks.
    formats : sequence of str, optional
        ``parquet`` (always written), ``csv``, ``png`` (summary plots); default: the file's.
    progress : bool, optional
        Runs done / total and the time left on stderr (default: when stderr is a terminal).
    on_chunk : callable, optional
        Called with each chunk when its file is written.

    Returns
    -------
    SweepResult
        ``table`` (pandas DataFrame, one row per run, sorted by run), files, counts.

    Raises
    ------
    MissingDependencyError
        Without pandas and pyarrow (``pip install 'uio-ring[sweep]'``), or dask for ``scheduler``.
    """
    pd = require("pandas", extra="sweep")
    require("pyarrow", extra="sweep")
    sw = sweep_file if isinstance(sweep_file, SweepSpec) else load_sweep(sweep_file)
    if out is None:
        if sw.directory is not None:
            root = Path(sw.source).parent if sw.source else Path(".")
            out = root / sw.directory
        else:
            out = Path("uio-ring-out") / sw.name
    out = Path(out)
    cdir = out / "chunks"
    cdir.mkdir(parents=True, exist_ok=True)
    chunks = sw.chunks()
    todo = [c for c in chunks if not (cdir / c.filename).exists()]
    axes = [a.name for a in sw.axes]
    common = {"axes": axes, "base": sw.base, "options": list(sw.design_options), "tol": sw.tol,
              "diverge": sw.diverge, "fingerprint": sw.fingerprint()}
    tasks = [dict(common, chunk=c) for c in todo]
    show = sys.stderr.isatty() if progress is None else progress
    bar = _progress(sum(len(c.runs) for c in chunks), show)
    bar(sum(len(c.runs) for c in chunks) - sum(len(c.runs) for c in todo))

    def done(task: dict[str, Any], rows: list[dict[str, Any]]) -> None:
        c = task["chunk"]
        _write_chunk(rows, cdir / c.filename)
        bar(len(c.runs))
        if on_chunk is not None:
            on_chunk(c)

    if tasks:
        if scheduler is not None:
            _run_dask(tasks, scheduler, done)
        else:
            _run_local(tasks, workers, done)
    table = pd.concat([pd.read_parquet(cdir / c.filename) for c in chunks], ignore_index=True)
    table = table.sort_values("run", kind="stable").reset_index(drop=True)
    fmts = tuple(formats) if formats is not None else sw.formats
    path = out / f"{sw.name}.parquet"
    _replace(path, lambda tmp: table.to_parquet(tmp, index=False))
    files = [path]
    if "csv" in fmts:
        files.append(out / f"{sw.name}.csv")
        _replace(files[-1], lambda tmp: table.to_csv(tmp, index=False))
    plots: tuple[Path, ...] = ()
    if "png" in fmts:
        from uio_ring.sweeps.plots import summary_plots

        plots = tuple(summary_plots(table, sw, out))
    return SweepResult(table=table, path=path, computed=len(todo), skipped=len(chunks) - len(todo),
                       plots=plots, files=tuple(files))


#: Runs of a chunk, each in a process of its own, before a chunk whose worker process dies
#: every time (killed, out of memory, a crash in native code) is written as error rows.
LOCAL_ATTEMPTS = 2


def _run_local(tasks: list[dict[str, Any]], workers: int | None, done: Callable[..., None],
               run: Callable[[dict[str, Any]], list[dict[str, Any]]] = run_chunk) -> None:
    """Chunks in this process (1 worker) or in a pool of processes (``run`` runs one chunk).

    A worker that dies breaks the pool: the chunks already written stay and the others go
    to a new pool.  If that one breaks too, the remaining chunks run one at a time, each in
    a process of its own, so that a death is charged to its chunk only: a chunk whose
    process died ``LOCAL_ATTEMPTS`` times is written as rows with that error.
    """
    n = workers if workers is not None else (os.cpu_count() or 1)
    if n < 1:
        raise SpecError(f"workers={workers}: expected at least 1")
    if n == 1 or len(tasks) == 1:
        for t in tasks:
            done(t, run(t))
        return
    todo = _pool(tasks, n, done, run)
    if todo:
        todo = _pool(todo, n, done, run)  # a death once (a kill, memory): the rest in a new pool
    for t in sorted(todo, key=lambda t: t["chunk"].index):  # deaths again: find the chunk that dies
        for _ in range(LOCAL_ATTEMPTS):
            if not _pool([t], 1, done, run):
                break
        else:
            c = t["chunk"]
            msg = f"WorkerDied: the process running this chunk alone died {LOCAL_ATTEMPTS} times"
            done(t, [_row(r, c.index, t["axes"], {}, np.nan, msg) for r in c.runs])


def _pool(tasks: list[dict[str, Any]], n: int, done: Callable[..., None],
          run: Callable[[dict[str, Any]], list[dict[str, Any]]]) -> list[dict[str, Any]]:
    """Run ``tasks`` in a pool of ``n`` spawned processes; return those lost when it broke."""
    import multiprocessing as mp
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    lost = []
    with ProcessPoolExecutor(max_workers=min(n, len(tasks)), mp_context=mp.get_context("spawn")) as pool:
        futures = {pool.submit(run, t): t for t in tasks}
        for f in as_completed(futures):
            try:
                rows = f.result()
            except BrokenProcessPool:
                lost.append(futures[f])
                continue
            done(futures[f], rows)
    return lost


def _run_dask(tasks: list[dict[str, Any]], scheduler: str, done: Callable[..., None]) -> None:
    distributed = require("distributed", extra="sweep")
    with distributed.Client(scheduler) as client:
        futures = {client.submit(run_chunk, t, key=f"uio-ring-{t['chunk'].filename}", pure=False): t
                   for t in tasks}
        for f in distributed.as_completed(list(futures)):
            done(futures[f], f.result())
