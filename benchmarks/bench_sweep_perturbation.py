#!/usr/bin/env python
"""Benchmark of a sweep over plant perturbations (``uio_ring.sweep``): wall and CPU time.

The sweep: paper 001's observer (examples/zheng2015.yaml), t_final = 3 s, dt = 5e-4,
perturbations ε ∈ {0, 0.0125, …, 0.05} × 20 directions (``perturbation_seed``) = 100 runs,
chunk_size 25.  Since plants are batched (one plant per scenario), the runs of one design
form 4 chunks of 25 scenarios each; before, every perturbed plant was a chunk of its own
(100 batched calls with K = 1, the ε = 0 runs aside).  Run it from both checkouts to compare::

    python benchmarks/bench_sweep_perturbation.py                    # this checkout
    python benchmarks/bench_sweep_perturbation.py --checkout ../main # another one (before)
    python benchmarks/bench_sweep_perturbation.py --workers 2

CPU time is user + system of this process and of its worker processes (``os.times``).
Timings are never asserted in tests.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

SWEEP = """
base: {base}
name: perturbation
seed: 1
chunk_size: 25
simulate: {{t_final: {t_final}, dt: 0.0005, settle: {settle}}}
metrics: {{tol: 0.001}}
axes:
  perturbation: {{linspace: [0, 0.05, 5]}}
  perturbation_seed: {seeds}
output: {{formats: [parquet]}}
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--checkout", default=str(ROOT), help="the uio_ring checkout to import (default: this one)")
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--quick", action="store_true", help="10 runs, t_final = 0.3 (a smoke test)")
    args = ap.parse_args()
    sys.path.insert(0, args.checkout)
    os.environ["PYTHONPATH"] = args.checkout + os.pathsep + os.environ.get("PYTHONPATH", "")  # spawned workers
    from uio_ring.sweeps import load_sweep, sweep

    n = 2 if args.quick else 20
    with tempfile.TemporaryDirectory() as tmp:
        f = Path(tmp) / "perturbation.yaml"
        f.write_text(SWEEP.format(base=ROOT / "examples" / "zheng2015.yaml", t_final=0.3 if args.quick else 3, settle=0.2 if args.quick else 2,
                                  seeds=list(range(n))))
        chunks = load_sweep(f).chunks()
        t0, c0 = time.perf_counter(), os.times()
        res = sweep(f, out=Path(tmp) / "out", workers=args.workers, progress=False)
        t1, c1 = time.perf_counter(), os.times()
    cpu = sum(getattr(c1, k) - getattr(c0, k) for k in ("user", "system", "children_user", "children_system"))
    bad = int((res.table["error"] != "").sum())
    print(f"checkout {args.checkout}: {len(res.table)} runs in {len(chunks)} chunks, workers {args.workers}: "
          f"wall {t1 - t0:.2f} s, CPU {cpu:.2f} s ({bad} failed runs)")


if __name__ == "__main__":
    main()
