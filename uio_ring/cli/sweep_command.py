"""``uio-ring sweep sweep.yaml`` — robustness sweeps (see :mod:`uio_ring.sweeps`).

    $ uio-ring sweep examples/sweeps/zheng2015_delay_sweep.yaml --out results/
    $ uio-ring sweep sweep.yaml --scheduler tcp://10.0.0.5:8786     # an existing dask cluster
"""

from __future__ import annotations

import argparse
from typing import Any


def add_parser(sub: Any) -> None:
    p = sub.add_parser("sweep", help="robustness sweep: many batched runs of one design; a table and summary plots")
    p.add_argument("sweep", help="sweep file (YAML): base spec and axes")
    p.add_argument("--out", metavar="DIR", help="output directory (default: the file's output.directory, "
                                                 "else ./uio-ring-out/<name>)")
    p.add_argument("--workers", type=int, metavar="N", help="local processes (default: the number of cores)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="address of a dask.distributed scheduler")
    p.add_argument("--csv", action="store_true", help="also write the table as CSV")
    p.add_argument("--no-plot", action="store_true", help="do not write the summary PNGs")
    p.add_argument("--progress", dest="progress", action="store_true", default=None, help="force a progress bar")
    p.add_argument("--no-progress", dest="progress", action="store_false", help="no progress bar")
    p.add_argument("--quiet", action="store_true", help="print only the summary line")
    p.set_defaults(run=_run_sweep)


def _run_sweep(args: argparse.Namespace) -> int:
    import numpy as np

    from uio_ring.errors import SpecError
    from uio_ring.sweeps import load_sweep, sweep

    sw = load_sweep(args.sweep)
    if args.workers is not None and args.workers < 1:
        raise SpecError(f"--workers {args.workers}: expected at least 1")
    formats = set(sw.formats) | {"parquet"}
    if args.csv:
        formats.add("csv")
    if args.no_plot:
        formats.discard("png")
    res = sweep(sw, out=args.out, workers=args.workers, scheduler=args.scheduler, formats=sorted(formats),
                progress=args.progress)
    t = res.table
    failed = int((t["error"] != "").sum())
    conv = int(np.isfinite(t["t_converge"].to_numpy(dtype=float)).sum())
    if not args.quiet and failed:
        for msg, n in t.loc[t["error"] != "", "error"].value_counts().items():
            print(f"{n} run(s) failed: {msg}")
    print(f"{sw.name}: {len(t)} runs ({res.computed} chunks computed, {res.skipped} found done); "
          f"{conv} converged to {sw.tol:g}, {failed} failed")
    print("wrote " + ", ".join(str(p) for p in (*res.files, *res.plots)))
    return 0
