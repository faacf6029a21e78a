"""Sweep files: a base spec, axes (grids or seeded random draws), runs and chunks.

A sweep file (YAML)::

    base: zheng2015.yaml          # a spec file, relative to the sweep file
    name: delay_mismatch          # default: the file name
    seed: 1                       # of every random draw (and of the noise)
    samples: 1                    # runs per grid point (random axes are drawn per run)
    chunk_size: 16                # runs per task (one batched simulation each)
    simulate: {t_final: 2, dt: 0.001}           # overrides of the base spec's simulate section
    metrics: {tol: 0.001, diverge: 1.0e+6}
    axes:
      h_true: [0.01, 0.011, 0.012]              # a list is a grid
      perturbation: {linspace: [0, 0.05, 3]}    # relative perturbation of the plant matrices
      noise: {uniform: [0, 0.01]}               # a random draw per run
      w_family: [base, sine, step, pwc]
      poles: [[-10, -25, -50], [-5, -12.5, -25]]  # any option of the design method (and method)
    output: {directory: sweep-out, formats: [parquet, csv, png]}

Axes (every one optional; see :data:`RUN_AXES`): the plant's true delay, relative matrix
perturbations (and the seed of their direction), the output-noise amplitude and seed, the
unknown-input family (the base spec's w, sines, steps, random piecewise-constant) with its
amplitude and frequency, the initial state (scale of the base one, a random one), and the
design options.  Grid axes combine as a Cartesian product (in file order); each grid point
gets ``samples`` runs; a random axis (``uniform``, ``loguniform``, ``choice``) is drawn per
run from the run's seed, ``SeedSequence([seed, run])`` — so the table depends on the file
only, not on how many workers run it.

>>> sw = sweep_from_dict({"base": {"system": {"A": [[-1]], "B": [[1]], "C": [[1]], "D": [[1]]},
...                                 "simulate": {"t_final": 1, "dt": "0.01"}},
...                        "axes": {"noise": [0, "0.1"], "x0_scale": {"uniform": [0, 1]}}, "samples": 2})
>>> [(r.run, r.params["noise"]) for r in sw.runs()]
[(0, 0.0), (1, 0.0), (2, 0.1), (3, 0.1)]
"""

from __future__ import annotations

import hashlib
import itertools
import json
from dataclasses import dataclass, field
from fractions import Fraction
from pathlib import Path
from typing import Any

import numpy as np

from uio_ring.errors import SpecError

__all__ = ["SweepSpec", "Run", "Chunk", "load_sweep", "sweep_from_dict", "RUN_AXES", "PLANT_AXES"]

#: Axes that change the plant or the design: runs that differ in the design are in different
#: chunks; the plant axes are per scenario (:data:`PER_SCENARIO_PLANT_AXES`).
PLANT_AXES = {
    "h_true": "the plant's true delay (the observer keeps the design's h): delay mismatch",
    "perturbation": "relative size ε of the plant-matrix perturbation M ∘ (1 + ε R), R uniform in [−1, 1]",
    "perturbation_seed": "seed of the perturbation direction R (default 0)",
    "method": "the design method (registry name)",
    "discretisation": "of injection terms: implicit, explicit, euler",
}
#: Plant axes: runs that differ only in them (and in :data:`RUN_AXES`) share a chunk, one plant
#: per scenario of the batch (its matrices; its true delay: the plants of each ``h_true`` are
#: integrated together, the one observer runs on all).
PER_SCENARIO_PLANT_AXES = ("perturbation", "perturbation_seed", "h_true")
#: Axes that change one scenario of a batch.

RUN_AXES = {
    "noise": "output-noise amplitude (uniform in [−a, a])",
    "noise_seed": "seed of the noise (default: the run's seed)",
    "w_family": "unknown input: base (the spec's w), sine, step, pwc (random piecewise constant), zero",
    "w_amplitude": "amplitude of the w family (base: a factor on the spec's w; default 1)",
    "w_frequency": "sine frequency [rad/s]; step time = 1/f; pwc dwell time = 1/f (default 1)",
    "x0_scale": "factor on the base spec's initial state (default 1)",
    "x0_random": "amplitude of a random constant initial state added to it (default 0)",
}
_RANDOM = ("uniform", "loguniform", "choice")
_TOP = {"base", "name", "seed", "samples", "chunk_size", "simulate", "metrics", "axes", "output", "description"}


def _num(v: Any, where: str) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float, Fraction, str)):
        raise SpecError(f"expected a number, got {v!r}", path=where)
    try:
        return float(Fraction(v) if isinstance(v, str) else v)
    except (ValueError, ZeroDivisionError):
        raise SpecError(f"expected a number, got {v!r}", path=where) from None


def _plain(v: Any) -> Any:
    """JSON-able form of a YAML value (Fractions as floats)."""
    if isinstance(v, Fraction):
        return float(v)
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, dict):
        return {str(k): _plain(x) for k, x in v.items()}
    return v


@dataclass(frozen=True)
class Axis:
    """One axis: a grid (``values``) or a random law (``law``, ``args``)."""

    name: str
    values: tuple[Any, ...] | None = None
    law: str | None = None
    args: tuple[Any, ...] = ()

    @property
    def is_grid(self) -> bool:
        return self.values is not None

    def draw(self, rng: np.random.Generator) -> Any:
        if self.law == "uniform":
            return float(rng.uniform(self.args[0], self.args[1]))
        if self.law == "loguniform":
            return float(np.exp(rng.uniform(np.log(self.args[0]), np.log(self.args[1]))))
        return self.args[int(rng.integers(len(self.args)))]


def _value(name: str, v: Any, where: str) -> Any:
    """An axis value, normalised (numbers as floats; design options kept as plain data)."""
    if name in ("w_family", "method", "discretisation"):
        if not isinstance(v, str):
            raise SpecError(f"expected a name, got {v!r}", path=where)
        if name == "w_family" and v not in ("base", "sine", "step", "pwc", "zero"):
            raise SpecError(f"unknown family {v!r}; expected base, sine, step, pwc or zero", path=where)
        return v
    if name in ("perturbation_seed", "noise_seed"):
        if isinstance(v, bool) or not isinstance(v, int) or v < 0:
            raise SpecError(f"expected a non-negative integer seed, got {v!r}", path=where)
        return int(v)
    if name in RUN_AXES or name in PLANT_AXES:
        x = _num(v, where)
        if name in ("h_true", "w_frequency") and not x > 0:
            raise SpecError(f"{name} must be positive, got {v!r}", path=where)
        if name in ("noise", "perturbation", "x0_random") and not x >= 0:
            raise SpecError(f"{name} must be ≥ 0, got {v!r}", path=where)
        return x
    return _plain(v)  # a design option: validated when the spec is built


def _axis(name: str, spec: Any, where: str) -> Axis:
    if isinstance(spec, list):
        spec = {"grid": spec}
    if not isinstance(spec, dict) or len(spec) != 1:
        raise SpecError("an axis is a list (grid) or one of {grid: […]}, {linspace: [a, b, n]}, "
                        "{uniform: [a, b]}, {loguniform: [a, b]}, {choice: […]}", path=where)
    (kind, arg), = spec.items()
    if kind == "grid":
        if not isinstance(arg, list) or not arg:
            raise SpecError("expected a non-empty list", path=f"{where}.grid")
        return Axis(name, values=tuple(_value(name, v, f"{where}.grid[{i}]") for i, v in enumerate(arg)))
    if kind == "linspace":
        if not isinstance(arg, list) or len(arg) != 3 or isinstance(arg[2], bool) or not isinstance(arg[2], int) \
                or arg[2] < 1:
            raise SpecError("expected [start, stop, count ≥ 1]", path=f"{where}.linspace")
        lo, hi = _num(arg[0], f"{where}.linspace[0]"), _num(arg[1], f"{where}.linspace[1]")
        vals = np.linspace(lo, hi, int(arg[2]))
        return Axis(name, values=tuple(_value(name, float(v), where) for v in vals))
    if kind in ("uniform", "loguniform"):
        if not isinstance(arg, list) or len(arg) != 2:
            raise SpecError("expected [low, high]", path=f"{where}.{kind}")
        lo, hi = (_num(v, f"{where}.{kind}[{i}]") for i, v in enumerate(arg))
        if not lo <= hi or (kind == "loguniform" and not lo > 0):
            raise SpecError(f"expected {'0 < ' if kind == 'loguniform' else ''}low ≤ high, got {arg}",
                            path=f"{where}.{kind}")
        _value(name, lo, where), _value(name, hi, where)
        return Axis(name, law=kind, args=(lo, hi))
    if kind == "choice":
        if not isinstance(arg, list) or not arg:
            raise SpecError("expected a non-empty list", path=f"{where}.choice")
        return Axis(name, law="choice", args=tuple(_value(name, v, f"{where}.choice[{i}]") for i, v in enumerate(arg)))
    raise SpecError(f"unknown axis kind {kind!r}; expected grid, linspace, uniform, loguniform or choice",
                    path=where)


@dataclass(frozen=True)
class Run:
    """One run: its number, seed and parameters (every axis, drawn or from the grid)."""

    run: int
    seed: int
    params: dict[str, Any]

    def design_key(self) -> str:
        """Runs with the same key share the design: one batch, whatever their plant perturbations
        and true delays (:data:`PER_SCENARIO_PLANT_AXES`, one plant per scenario)."""
        key = {k: v for k, v in self.params.items() if k not in RUN_AXES and k not in PER_SCENARIO_PLANT_AXES}
        return json.dumps(key, sort_keys=True)


@dataclass(frozen=True)
class Chunk:
    """Runs that share a design: one task, one batched simulation, one file."""

    index: int
    runs: tuple[Run, ...]
    fingerprint: str

    @property
    def filename(self) -> str:
        return f"chunk-{self.index:05d}-{self.fingerprint}.parquet"


@dataclass(frozen=True)
class SweepSpec:
    """A validated sweep: the base spec data, the axes, and the run settings."""

    base: dict[str, Any]
    axes: tuple[Axis, ...]
    name: str = "sweep"
    seed: int = 0
    samples: int = 1
    chunk_size: int = 16
    tol: float = 1e-3
    diverge: float = 1e6
    directory: str | None = None
    formats: tuple[str, ...] = ("parquet", "png")
    source: str | None = None
    design_options: tuple[str, ...] = field(default=())

    def runs(self) -> list[Run]:
        """Every run, in order: the grid's Cartesian product × ``samples``, random axes drawn."""
        grid = [a for a in self.axes if a.is_grid]
        rand = [a for a in self.axes if not a.is_grid]
        out: list[Run] = []
        n = 0
        for point in itertools.product(*(a.values or () for a in grid)):
            for _ in range(self.samples):
                ss = np.random.SeedSequence([self.seed, n])
                seed = int(ss.generate_state(1)[0])
                rng = np.random.default_rng(ss)
                params = {a.name: v for a, v in zip(grid, point, strict=True)}
                for a in rand:
                    params[a.name] = a.draw(rng)
                out.append(Run(n, seed, params))
                n += 1
        return out

    def chunks(self) -> list[Chunk]:
        """Runs grouped by design, cut into chunks of ``chunk_size`` (deterministic).

        Runs on differently perturbed plants, or plants of other true delays, share a chunk:
        the batch integrates one plant per scenario."""
        groups: dict[str, list[Run]] = {}
        for r in self.runs():
            groups.setdefault(r.design_key(), []).append(r)
        base = self.fingerprint()
        out: list[Chunk] = []
        for runs in groups.values():
            for i in range(0, len(runs), self.chunk_size):
                part = tuple(runs[i : i + self.chunk_size])
                h = hashlib.sha256((base + json.dumps([r.run for r in part])).encode()).hexdigest()[:10]
                out.append(Chunk(len(out), part, h))
        return out

    def fingerprint(self) -> str:
        """Hash of everything that changes the numbers (not the output settings)."""
        data = {"base": _plain(self.base), "axes": [(a.name, _plain(a.values), a.law, _plain(a.args))
                                                     for a in self.axes],
                "seed": self.seed, "samples": self.samples, "chunk_size": self.chunk_size,
                "tol": self.tol, "diverge": self.diverge}
        return hashlib.sha256(json.dumps(data, sort_keys=True, default=str).encode()).hexdigest()

    @property
    def grid_axes(self) -> list[str]:
        return [a.name for a in self.axes if a.is_grid]


def load_sweep(path: str | Path) -> SweepSpec:
    """Read and validate a sweep file (errors name the file and the place in it)."""
    from uio_ring.spec.files import read_text_limited, sanitise_name
    from uio_ring.spec.yaml_io import MAX_BYTES, load_yaml_text

    p = Path(path)
    text = read_text_limited(p, max_bytes=MAX_BYTES, what="sweep")  # regular files only, bounded
    try:
        data = load_yaml_text(text)
        return sweep_from_dict(data, root=p.parent, source=str(p), default_name=sanitise_name(p.stem))
    except SpecError as exc:
        raise SpecError(f"{p}: {exc}") from None


def sweep_from_dict(data: Any, *, root: str | Path = ".", source: str | None = None,
                    default_name: str = "sweep") -> SweepSpec:
    """Validate a sweep given as plain data; ``base`` is a spec file (relative to ``root``) or a dict."""
    from uio_ring.spec.files import read_text_limited, safe_name
    from uio_ring.spec.loader import spec_from_dict
    from uio_ring.spec.yaml_io import MAX_BYTES, load_yaml_text

    if not isinstance(data, dict):
        raise SpecError("a sweep file is a mapping with 'base' and 'axes'")
    unknown = sorted(set(map(str, data)) - _TOP)
    if unknown:
        hint = " (this is a spec file; a sweep file names it: 'base: spec.yaml')" if "system" in unknown else ""
        raise SpecError(f"unknown key(s) {', '.join(unknown)}; expected some of {', '.join(sorted(_TOP))}{hint}")
    base = data.get("base")
    if isinstance(base, str):
        bp = Path(root) / base
        try:
            base = load_yaml_text(read_text_limited(bp, max_bytes=MAX_BYTES, what="base spec"))
        except SpecError as exc:
            raise SpecError(f"the base spec {bp}: {exc}", path="base") from None
    if not isinstance(base, dict):
        raise SpecError("expected a spec file name or a spec mapping", path="base")
    base = dict(base)
    base.pop("output", None)
    sim_over = data.get("simulate") or {}
    if not isinstance(sim_over, dict):
        raise SpecError("expected a mapping of simulate settings", path="simulate")
    if sim_over:
        base["simulate"] = {**(base.get("simulate") or {}), **sim_over}
    if not base.get("simulate"):
        raise SpecError("the base spec has no simulate section (t_final, dt); add one here", path="simulate")
    spec = spec_from_dict(base)  # validates the base (errors name the place)
    from uio_ring.design.methods import METHODS

    axes_data = data.get("axes") or {}
    every = spec.design.method == "auto" or (isinstance(axes_data, dict) and "method" in axes_data)
    names = set(METHODS) if every else {spec.design.method}
    options = sorted({o for m in names for o in METHODS[m].option_names})
    if not isinstance(axes_data, dict):
        raise SpecError("expected a mapping axis name -> values", path="axes")
    axes = []
    for name, ax in axes_data.items():
        name = str(name)
        if name not in RUN_AXES and name not in PLANT_AXES and name not in options:
            raise SpecError(f"unknown axis {name!r}; expected one of {', '.join([*RUN_AXES, *PLANT_AXES, *options])}",
                            path=f"axes.{name}")
        axes.append(_axis(name, ax, f"axes.{name}"))

    def integer(key: str, default: int, low: int) -> int:
        v = data.get(key, default)
        if isinstance(v, bool) or not isinstance(v, int) or v < low:
            raise SpecError(f"expected an integer ≥ {low}, got {v!r}", path=key)
        return int(v)

    metrics = data.get("metrics") or {}
    if not isinstance(metrics, dict) or set(map(str, metrics)) - {"tol", "diverge"}:
        raise SpecError("expected {tol: …, diverge: …}", path="metrics")
    out = data.get("output") or {}
    if not isinstance(out, dict) or set(map(str, out)) - {"directory", "formats"}:
        raise SpecError("expected {directory: …, formats: […]}", path="output")
    directory = out.get("directory")
    if directory is not None:
        d = Path(str(directory))
        if not str(directory).strip() or d.is_absolute() or ".." in d.parts:
            raise SpecError(f"{directory!r}: expected a folder inside the sweep file's folder (no absolute path, "
                            "no '..'; use --out to write elsewhere)", path="output.directory")
    name = data.get("name")
    if name is not None:
        safe_name(str(name), "name")
    formats = tuple(out.get("formats") or ("parquet", "png"))
    bad = [f for f in formats if f not in ("parquet", "csv", "png")]
    if bad:
        raise SpecError(f"unknown format(s) {bad}; expected parquet, csv, png", path="output.formats")
    tol = _num(metrics.get("tol", "0.001"), "metrics.tol")
    div = _num(metrics.get("diverge", 1_000_000), "metrics.diverge")
    if not (tol > 0 and div > 0):
        raise SpecError("tol and diverge must be positive", path="metrics")
    return SweepSpec(
        base=base, axes=tuple(axes), name=str(name or default_name), seed=integer("seed", 0, 0),
        samples=integer("samples", 1, 1), chunk_size=integer("chunk_size", 16, 1), tol=tol, diverge=div,
        directory=None if out.get("directory") is None else str(out["directory"]), formats=formats,
        source=source, design_options=tuple(options),
    )
