"""``uio-ring check | design | simulate | schema`` — the main job, driven by spec files.

    $ uio-ring design examples/zheng2015.yaml
    $ uio-ring simulate examples/zheng2015.yaml --out results/

Files: everything is written under the output folder (``--out``, else the
spec's ``output.directory`` inside the spec's folder, else
``uio-ring-out/<name>``), under names made from the spec's safe ``name``.
Existing files are not replaced unless ``--force`` (checked before any work).
The design's own files (JSON, YAML, LaTeX), which ``design`` and ``simulate``
both write, may exist when they hold exactly the bytes the run would write: they
are left as they are, so ``simulate`` after ``design`` in one folder works; with
other bytes the run is refused as soon as the design is known, before the
simulation and before anything is written.
All files of a run are written under temporary names and renamed at the end,
so a failed or interrupted run leaves none.  A design whose certificate fails
is reported (exit 1) and **not written**; a simulation that produces
non-finite values, or that its step dt does not resolve (the accuracy check), is an
error (exit 2) and writes nothing.  Long CSV runs are streamed to disk
(:mod:`uio_ring.cli.stream`).
"""

from __future__ import annotations

import argparse
import json
import os
import sys
import warnings
from fractions import Fraction
from pathlib import Path
from typing import Any

from uio_ring.cli.heartbeat import Heartbeat


def add_parser(sub: Any) -> None:
    p = sub.add_parser(
        "check",
        help="structural report only (assumptions, invariants)",
        description="Read a spec file and report, for each design method, whether its assumptions hold "
        "and why not. Designs nothing and writes nothing. Exit code 0 if a method applies, 1 if none "
        "does, 2 for a bad spec.",
    )
    p.add_argument("spec", help="spec file (YAML)")
    p.set_defaults(run=_run_check)

    p = sub.add_parser(
        "design",
        help="check, design, certify; write the design as JSON and YAML",
        description="Check the assumptions, design the observer exactly, verify its certificate and write "
        "the design (JSON and YAML; reload with uio_ring.load_design). Exit code 0 if the certificate "
        "holds, 1 if an assumption or the certificate fails, 2 for a bad spec.",
    )
    p.add_argument("spec", help="spec file (YAML)")
    _output_options(p)
    p.add_argument("--latex", metavar="FILE", help="also write the design as a LaTeX file")
    p.set_defaults(run=_run_design)

    p = sub.add_parser(
        "simulate",
        help="design and simulate; write CSV/NPZ of t, x, y, x̂, error and PNG plots",
        description="Design the observer as 'design' does, then simulate plant and observer numerically "
        "(float64, with history buffers) over the spec's 'simulate' section: signals as CSV (or NPZ), "
        "a PNG plot (needs matplotlib) and the design as JSON. Exit codes as for 'design'.",
    )
    p.add_argument("spec", help="spec file (YAML) with a 'simulate' section")
    _output_options(p)
    p.add_argument("--npz", action="store_true", help="write NPZ instead of CSV")
    p.add_argument("--no-plot", action="store_true", help="do not write PNG plots")
    p.add_argument("--progress", dest="progress", action="store_true", default=None, help="force a progress bar")
    p.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")
    p.set_defaults(run=_run_simulate)

    p = sub.add_parser(
        "schema",
        help="print the JSON Schema of spec files",
        description="Print the JSON Schema that spec files are validated against (for editors and tools).",
    )
    p.set_defaults(run=_run_schema)


def _output_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--out", metavar="DIR", help="output directory (default: the spec's output.directory, else ./uio-ring-out/<spec name>)")
    p.add_argument("--quiet", action="store_true", help="print only the summary")
    p.add_argument("--force", action="store_true",
                   help="overwrite existing output files (refused otherwise; design files with the same bytes are kept)")


def _out_dir(args: argparse.Namespace, spec: Any) -> Path:
    if args.out is not None:
        return Path(args.out)
    if spec.output.directory:
        base = Path(spec.source).parent if spec.source else Path(".")
        return base / spec.output.directory
    return Path("uio-ring-out") / (spec.name or "design")


#: Suffixes of the design's own files, written alike by ``design`` and ``simulate``.
DESIGN_SUFFIXES = (".json", ".yaml", ".tex")


def _outputs(args: argparse.Namespace, spec: Any, suffixes: list[str], latex: Path | None = None) -> tuple[Any, Path]:
    """The output folder checked before any work: (Outputs, stem).

    The design's files (and the ``--latex`` file) are *shared*: they may exist with the
    bytes this run would write (see :meth:`uio_ring.spec.files.Outputs.refuse_changed`)."""
    from uio_ring.errors import SpecError
    from uio_ring.spec.files import Outputs

    if args.out is not None and not str(args.out).strip():
        raise SpecError("an empty folder name", path="--out")
    where = "--out" if args.out is not None else ("output.directory" if spec.output.directory else None)
    out = Outputs(_out_dir(args, spec), force=args.force, where=where)
    stem = out.folder / (spec.name or "design")
    targets = [stem.with_suffix(s) for s in suffixes]
    _never_the_spec(spec, targets, where)
    shared = [t for t in targets if t.suffix in DESIGN_SUFFIXES] + ([latex] if latex is not None else [])
    out.prepare(targets, shared=shared)
    return out, stem


def _never_the_spec(spec: Any, targets: list[Path], where: str | None) -> None:
    """No output may replace the spec file itself, not even with --force."""

    from uio_ring.errors import SpecError

    if not spec.source:
        return
    source = Path(spec.source)
    for target in targets:
        try:
            same = target.exists() and os.path.samefile(target, source)
        except OSError:
            same = False
        if same:
            raise SpecError(f"{target} is the spec file itself; choose another --out or name", path=where)


def _latex_target(args: argparse.Namespace) -> tuple[Path, Any] | None:
    """The ``--latex`` file checked before any work: (path, its Outputs, for :meth:`refuse_changed`)."""
    from uio_ring.errors import SpecError
    from uio_ring.spec.files import Outputs

    if not args.latex:
        return None
    path = Path(args.latex)
    if "\x00" in args.latex:
        raise SpecError("the file name contains a NUL character", path="--latex")
    if path.is_dir():
        raise SpecError(f"{args.latex} is a folder; give a file name such as design.tex", path="--latex")
    check = Outputs(path.parent, force=args.force, where="--latex")
    check.prepare([path], shared=[path])
    check.cleanup()  # checked now; the folder is made again when the file is written
    return path, check


def _rule(title: str) -> str:
    return f"\n== {title} " + "=" * max(0, 60 - len(title))


def _size_text(system: Any) -> str:
    return f"{system.n_x} states, δ-degree {system.max_delay_degree}"


def _checks(spec: Any) -> list[tuple[str, bool, Any, str]]:
    """``(method, holds, report, reason)`` for the spec's method, or for every method under auto."""
    from uio_ring.design.methods import METHODS, get_method

    names = list(METHODS) if spec.design.method == "auto" else [spec.design.method]
    out = []
    for name in names:
        with Heartbeat(f"checking method {name} ({_size_text(spec.system)}: exact algebra over Q[δ])"):
            out.append((name, *get_method(name).applies(spec.system)))
    return out


def _run_check(args: argparse.Namespace) -> int:
    from uio_ring.spec import load_spec

    spec = load_spec(args.spec)
    system = spec.system
    print(f"{spec.name}: n_x = {system.n_x}, n_w = {system.n_w}, n_u = {system.n_u}, n_y = {system.n_y}, "
          f"δ-degree {system.max_delay_degree}, {_delay_text(system)}")
    from uio_ring.design.methods import METHODS

    any_ok = False
    checked = _checks(spec)
    for name, holds, report, reason in checked:
        print(_rule(f"method {name}: {'applicable' if holds else 'NOT applicable'}"))
        print(report if report is not None else reason)
        show = METHODS[name].preview
        if holds and show is not None:
            with Heartbeat(f"previewing method {name} ({_size_text(system)}: exact algebra over Q[δ])"):
                preview = show(system)
            print(preview)
        any_ok = any_ok or holds
    if system.is_delay_free and "scb" in METHODS and "scb" not in [c[0] for c in checked]:
        from uio_ring.analysis.observer_classes import observer_options

        print(_rule("which unknown-input observers exist (special coordinate basis)"))
        with Heartbeat(f"special coordinate basis ({_size_text(system)})"):
            print(observer_options(system))
    if not any_ok and spec.design.method != "auto":
        others = [m for m in METHODS.values() if m.name != spec.design.method and m.applies(system)[0]]
        for m in others:
            needs = f" (needs the option(s) {', '.join(m.required)})" if m.required else ""
            print(f"\nmethod {m.name} applies to this system{needs}: set design.method: {m.name}")
    return 0 if any_ok else 1


def _delay_text(system: Any) -> str:
    """``h = 0.01``, or why there is none (never Python's ``None``)."""
    if system.h is not None:
        text = f"{float(system.h):g}"
        return f"h = {text}" if Fraction(text) == system.h else f"h = {system.h}"
    return "delay-free (no h)" if system.is_delay_free else "h not given"


def _design(spec: Any) -> tuple[Any, str, tuple[tuple[str, str], ...]]:
    from uio_ring.design.methods import design_auto, design_with
    from uio_ring.errors import DimensionError, DomainError, SimulationError, SpecError

    try:
        with Heartbeat(f"designing ({spec.design.method}; {_size_text(spec.system)}: exact algebra over Q[δ])"):
            if spec.design.method == "auto":
                res = design_auto(spec.system, **spec.design.options)
                return res.design, res.method, res.skipped
            return design_with(spec.design.method, spec.system, **spec.design.options), spec.design.method, ()
    except (DimensionError, DomainError, SimulationError) as exc:  # an option of the design section does not fit
        option = getattr(exc, "option", None)
        raise SpecError(str(exc), path=f"design.{option}" if option else "design") from exc


def _print_design(spec: Any, design: Any, method: str, skipped: Any, cert: Any, quiet: bool) -> None:
    if not quiet:
        report = getattr(design, "assumptions", None)
        if report is not None:
            print(_rule("assumptions"))
            print(report)
        print(_rule(f"design ({method})"))
        for name, why in skipped:
            print(f"auto skipped {name}: {why}")
        print(design)
        print(_performance_line(design, spec))
        print(_rule("certificate"))
        print(cert)
        print()
    line = f"{spec.name}: method {method}, certificate {'ok' if cert.ok else 'FAILED'}"
    if hasattr(design, "n_z"):
        line += f", n_z = {design.n_z}"
    if hasattr(design, "lag"):
        h = spec.system.h
        line += f", lag = {design.lag}" + (
            f" (x̂(t) estimates x(t) and needs {float(design.lag * h):g} s = {design.lag}·h of history)" if h else ""
        )
    print(line)


def _performance_line(design: Any, spec: Any) -> str:
    """The design's noise and speed figures, or why there are none."""
    from uio_ring.errors import NotSupportedError, SimulationError

    try:
        perf = design.performance(h=spec.system.h)
    except NotSupportedError:
        return "performance: observer with a nonlinear (sliding-mode) injection term: no linear noise gain"
    except SimulationError as exc:
        return f"performance: not computed ({exc})"
    return "performance: " + perf.summary()


def _run_design(args: argparse.Namespace) -> int:
    from uio_ring.spec import load_spec

    spec = load_spec(args.spec)
    formats = [f for f in (spec.output.formats or ("json", "yaml")) if f in ("json", "yaml", "latex")]
    suffixes = {"json": ".json", "yaml": ".yaml", "latex": ".tex"}
    latex = _latex_target(args)
    if latex is not None:
        _never_the_spec(spec, [latex[0]], "--latex")
    out, stem = _outputs(args, spec, [suffixes[f] for f in formats], latex[0] if latex else None)  # before any work
    try:
        return _design_and_write(args, spec, out, stem, formats, latex)
    finally:
        out.cleanup()  # folders made for this run go again when nothing was written


def _design_and_write(args: argparse.Namespace, spec: Any, out: Any, stem: Path, formats: list[str], latex: Any) -> int:
    design, method, skipped = _design(spec)
    cert = design.certificate()
    _print_design(spec, design, method, skipped, cert, args.quiet)
    if not cert.ok:
        print("certificate FAILED: no design files written", file=sys.stderr)
        return 1
    texts = _design_files(design, out, stem, formats)
    if latex is not None:
        path, check = latex
        texts[path] = design.to_latex() + "\n"
        check.refuse_changed({path: texts[path]})
    with out:
        paths = [out.write_text(path, text) for path, text in texts.items()]
    _print_written(out, paths)
    return 0


def _design_files(design: Any, out: Any, stem: Path, formats: list[str]) -> dict[Path, str]:
    """The design's files by path, refused now if one exists with other bytes (see the module docstring)."""
    from uio_ring.spec.designs import design_texts

    texts = {stem.with_suffix(suffix): text for suffix, text in design_texts(design, formats).items()}
    out.refuse_changed(texts)
    return texts


def _print_written(out: Any, paths: list[Path]) -> None:
    written = [str(p) for p in paths if p not in out.unchanged]
    kept = [str(p) for p in paths if p in out.unchanged]
    if written:
        print("wrote " + ", ".join(written))
    if kept:
        print("unchanged (already there with the same content): " + ", ".join(kept))


def _run_simulate(args: argparse.Namespace) -> int:
    from uio_ring.errors import SpecError
    from uio_ring.spec import load_spec

    spec = load_spec(args.spec)
    if spec.simulate is None:
        raise SpecError("the spec has no 'simulate' section (t_final, dt, inputs)", path="simulate")
    formats = _simulation_formats(spec.output.formats, npz=args.npz, plot=not args.no_plot)
    suffixes = {"json": ".json", "yaml": ".yaml", "latex": ".tex", "csv": ".csv", "npz": ".npz", "png": ".png"}
    out, stem = _outputs(args, spec, [suffixes[f] for f in sorted(formats)])  # before any work
    try:
        return _simulate_and_write(args, spec, out, stem, formats)
    finally:
        out.cleanup()  # folders made for this run go again when nothing was written


def _simulate_and_write(args: argparse.Namespace, spec: Any, out: Any, stem: Path, formats: set[str]) -> int:
    import numpy as np

    from uio_ring.cli.stream import streamed
    from uio_ring.errors import NotObservableError, SpecError, UioRingError
    from uio_ring.spec.loader import check_memory_budget, recorded_values

    sim = spec.simulate
    steps, columns = recorded_values(spec.system, sim.t_final, sim.dt)
    stream = streamed(steps=steps, columns=columns, nonlinear=bool(sim.nonlinearity), npz="npz" in formats)
    if "npz" in formats:
        check_memory_budget(spec.system, sim.t_final, sim.dt, why="NPZ output is kept in memory")
    design, method, skipped = _design(spec)
    cert = design.certificate()
    _print_design(spec, design, method, skipped, cert, args.quiet)
    if not cert.ok:
        print("certificate FAILED: not simulated, no files written", file=sys.stderr)
        return 1
    settle = float(sim.settle) if sim.settle is not None else float(sim.t_final) / 2
    texts = _design_files(design, out, stem, [f for f in ("json", "yaml", "latex") if f in formats])
    try:
        with np.errstate(all="ignore"):  # overflow is reported once, by _accept below
            if stream:
                window = _probe_window(spec, steps)
                probe = _simulate(design, spec, False, t_final=window, noisy=False)  # the accuracy check
            else:
                probe = _simulate(design, spec, args.progress)
    except (SpecError, NotObservableError):
        raise
    except UioRingError as exc:  # the simulation refused its input: name the spec section
        raise SpecError(str(exc), path="simulate") from None
    _accept(probe)
    with out:
        paths = [out.write_text(path, text) for path, text in texts.items()]
        if stream:
            figures, result = _stream(args, design, spec, out, stem, formats, settle, paths)
        else:
            figures, result = _figures(probe, settle), probe
            for kind in ("csv", "npz"):
                if kind in formats:
                    paths.append(out.write_with(stem.with_suffix("." + kind),
                                                lambda p, kind=kind: _write_signals(result, p, npz=kind == "npz")))
        if "png" in formats and result is not None:
            paths.append(out.write_with(stem.with_suffix(".png"), lambda p: _write_plot(result, p, spec.name)))
    steps_done, t_last, final, after, w_after = figures
    line = (f"{spec.name}: simulated {t_last:g} s with dt = {float(sim.dt):g} ({steps_done} steps); "
            f"final error {final:.3g}, max error after t = {settle:g} s: {after:.3g}")
    if w_after is not None:
        line += f"; max |w − ŵ| after t = {settle:g} s: {w_after:.3g}"
    if stream:
        line += " (streamed to disk)"
    print(line)
    _print_written(out, paths)
    return 0


def _accept(result: Any) -> None:
    """A non-finite or unresolved simulation is an error (exit 2, nothing written)."""
    from uio_ring.errors import SpecError

    _check_finite(result)
    if not result.success:  # the a-posteriori accuracy check failed: never a success with a wrong number
        raise SpecError(f"the simulation is {result.message} (nothing written)", path="simulate.dt")


def _figures(result: Any, settle: float) -> tuple[int, float, float, float, float | None]:
    """(steps, t_final, final error, max error after settle, max |w − ŵ| after settle or None)."""
    import numpy as np

    t = result.t
    err = np.max(np.abs(result.error), axis=0)
    after = err[t >= settle]
    w_after = None
    if result.w_hat is not None:
        w_err = np.max(np.abs(result.w - result.w_hat), axis=0)[t >= settle]
        w_after = float(w_err.max()) if w_err.size else 0.0
    return len(t) - 1, float(t[-1]), float(err[-1]), float(after.max()) if after.size else 0.0, w_after


def _probe_window(spec: Any, steps: int) -> float:
    """Seconds of the accuracy check of a streamed run (the window of an in-memory run)."""
    from uio_ring.sim.accuracy import window_steps

    sim = spec.simulate
    dt = float(sim.dt)
    N = round(float(sim.h) / dt) if spec.system.h is not None else 1
    return window_steps(steps, N) * dt


def _stream(args: argparse.Namespace, design: Any, spec: Any, out: Any, stem: Path, formats: set[str], settle: float,
            paths: list[Path]) -> tuple[tuple[int, float, float, float, float | None], Any]:
    """The long run by segments, its CSV written as it goes; (figures, preview for the plot)."""
    import numpy as np

    from uio_ring.cli.stream import stream_csv
    from uio_ring.errors import NotObservableError, SpecError, UioRingError

    box: list[Any] = []

    def write(p: Path) -> None:
        box.append(stream_csv(design, spec, p, settle=settle, check=_check_finite, progress=args.progress,
                              preview="png" in formats))

    try:
        with np.errstate(all="ignore"):  # overflow is reported once, by _check_finite on its segment
            paths.append(out.write_with(stem.with_suffix(".csv"), write))
    except (SpecError, NotObservableError):
        raise
    except UioRingError as exc:
        raise SpecError(str(exc), path="simulate") from None
    s = box[0]
    return (s.steps, s.t_last, s.final, s.max_after, s.w_max_after), s.preview


def _check_finite(result: Any) -> None:
    """A simulation with NaN or ±inf anywhere is an error, never a success (exit 2, nothing written)."""
    import numpy as np

    from uio_ring.errors import SpecError

    signals = (("state", result.x), ("output", result.y), ("estimate", result.x_hat), ("error", result.error),
               ("input estimate", getattr(result, "w_hat", None)))
    for label, values in signals:
        if values is None:
            continue
        finite = np.isfinite(values)
        if not finite.all():
            k = int(np.argmax(~finite.all(axis=0)))
            raise SpecError(
                f"the simulation overflowed: the {label} is not finite from t = {float(result.t[k]):g} s on; "
                "reduce the inputs, noise or initial values, or the step dt (nothing written)",
                path="simulate",
            )


def _simulation_formats(requested: Any, *, npz: bool, plot: bool) -> set[str]:
    """What ``simulate`` writes: the spec's ``output.formats`` when given (design: json, yaml,
    latex; signals: csv, npz; plot: png), else json + csv + png; ``--npz`` swaps csv for npz,
    ``--no-plot`` drops png."""
    formats = set(requested) if requested else {"json", "csv", "png"}
    if npz:
        formats = (formats - {"csv"}) | {"npz"}
    if not plot:
        formats.discard("png")
    return formats


def _simulate(design: Any, spec: Any, progress: bool | None, *, t_final: float | None = None,
              noisy: bool = True) -> Any:
    """Run the spec's simulation (up to ``t_final`` when given; without its noise when not
    ``noisy``); an untrustworthy result comes back with ``success=False`` (the caller reports
    it; the API's warning is not printed)."""

    from uio_ring.sim import AccuracyWarning, simulate_observer

    sim = spec.simulate
    x_hat0 = None if sim.x_hat0 is None else [float(v) for v in sim.x_hat0]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AccuracyWarning)
        return simulate_observer(
            design,
            spec.system,
            h=None if spec.system.h is None else float(sim.h),
            t_final=float(sim.t_final) if t_final is None else t_final,
            dt=float(sim.dt),
            w=sim.signal("w"),
            u=sim.signal("u"),
            x0=sim.signal("phi"),
            noise=sim.noise() if noisy else None,
            x_hat0=x_hat0,
            discretisation=sim.discretisation,
            progress=progress,
            phi=sim.nonlinearity_function(),
        )


def _write_signals(result: Any, path: Path, *, npz: bool) -> None:
    """Every signal of the result (t, x, y, w, u, x̂, error, ŵ) as CSV columns ``kind.name``
    (unique by construction), or as NPZ arrays with the names alongside."""
    import csv

    import numpy as np

    from uio_ring.cli.stream import write_rows

    columns = result.columns()
    if npz:
        arrays = {k: getattr(result, k) for k in ("t", "x", "y", "w", "u", "x_hat", "error", "w_hat")
                  if getattr(result, k) is not None}
        with open(path, "wb") as fh:  # a file object: savez would append '.npz' to the temporary name
            np.savez_compressed(fh, **arrays, columns=np.array(list(columns)))
        return
    data = np.column_stack(list(columns.values()))
    with open(path, "w", newline="", encoding="utf-8") as fh:
        writer = csv.writer(fh)
        writer.writerow(list(columns))
        write_rows(writer, data)


def _write_plot(result: Any, path: Path, title: str) -> None:
    from uio_ring.errors import require

    matplotlib = require("matplotlib", extra="plot")
    matplotlib.use("Agg")
    fig = result.plot(title=title)
    fig = getattr(fig, "figure", fig)
    import matplotlib.pyplot as plt

    try:
        fig.savefig(path, dpi=110, bbox_inches="tight", format="png")
    finally:
        plt.close(fig)


def _run_schema(args: argparse.Namespace) -> int:
    from uio_ring.spec import schema

    json.dump(schema(), sys.stdout, indent=2)
    print()
    return 0
