#!/usr/bin/env python
"""The sub-millisecond cells of ``bench_ring.py`` against SageMath, interleaved.

One pass of ``bench_ring.py`` times each library once per cell; on a shared machine
the sub-millisecond cells then move by up to 2× between runs, which hides a 5 %
difference.  Here each library times every cell in its own interpreter (best of 15
batches of ~20 ms), and the two alternate for ``--rounds`` rounds; the table shows
the best time of each library over all rounds, their ratio and the per-round ratios
(how much to trust it).  No sympy; SageMath as in ``bench_ring.py`` (passagemath,
``--sage-python`` or ``$UIO_SAGE_PYTHON``).

    PYTHONPATH=. python benchmarks/bench_small_cells.py --sage-python /path/to/sagevenv/bin/python
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))  # bench_ring, beside this script

#: the seed of bench_ring.py's default cases
SEED = 20261123

#: (family, n, operation[, shape]) of bench_ring.py whose times are below a millisecond or
#: so (the shape where a family has two at one n)
CELLS: list[tuple] = [
    ("random", 4, "hermite"), ("random", 4, "det"), ("rankdef", 4, "hermite"), ("smith", 4, "hermite"),
    ("tall", 4, "hermite"), ("tall", 4, "left_inverse"), ("tall", 8, "hermite"), ("tall", 8, "left_inverse"),
    ("paper001", 6, "hermite"), ("paper001", 6, "left_kernel"), ("highdeg", 16, "hermite"),
    ("highdeg", 32, "hermite"), ("highdeg", 32, "det"), ("highdeg", 64, "det"), ("highdeg", 128, "det"),
    ("highdeg", 256, "det"), ("highdeg4", 8, "hermite"), ("highdeg4", 8, "det"), ("sparse", 8, "hermite"),
    ("sparse", 8, "rank"), ("rowdeg", 24, "hermite"), ("rowdeg", 40, "hermite"),
    ("narrow", 16, "hermite", (2, 4)), ("narrow", 32, "hermite", (2, 4)),
]


def time_cells(library: str) -> dict[str, float]:
    """Best seconds per cell for ``library`` ("ours" or "sage") in this interpreter."""
    import bench_ring as br

    cases = br.build_cases([4, 8], SEED, max_n=8)
    setup = br._setup_ours if library == "ours" else br._setup_sage
    out = {}
    for family, n, op, *shape in CELLS:
        case = next(c for c in cases if c["family"] == family and c["n"] == n and shape in ([], [c["shape"]]))
        f = setup(case)[0][op]
        f()
        start = time.process_time()
        f()
        loops = max(1, int(0.02 / max(time.process_time() - start, 1e-6)))
        best = float("inf")
        for _ in range(15):
            start = time.process_time()
            for _ in range(loops):
                f()
            best = min(best, (time.process_time() - start) / loops)
        out[f"{family} {n} {op}" + "".join(f" {r}x{k}" for r, k in shape)] = best
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sage-python", default=os.environ.get("UIO_SAGE_PYTHON") or None,
                    help="a Python interpreter with passagemath (default: $UIO_SAGE_PYTHON)")
    ap.add_argument("--rounds", type=int, default=6)
    ap.add_argument("--worker", choices=["ours", "sage"], help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        print(json.dumps(time_cells(args.worker)))
        return 0
    if not args.sage_python:
        print("bench_small_cells: give --sage-python (or $UIO_SAGE_PYTHON): an interpreter with passagemath",
              file=sys.stderr)
        return 2
    import flint
    from bench_ring import flint_is_stable_abi, sage_available

    if not sage_available(args.sage_python):
        print(f"bench_small_cells: {args.sage_python} cannot import SageMath (install passagemath-flint and "
              "passagemath-modules there)", file=sys.stderr)
        return 2
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE.parent), os.environ.get("PYTHONPATH", "")]))
    runs: dict[str, list[dict[str, float]]] = {"ours": [], "sage": []}
    for _ in range(args.rounds):
        for lib, python in (("sage", args.sage_python), ("ours", sys.executable)):
            got = subprocess.run([python, __file__, "--worker", lib], env=env, capture_output=True, text=True)
            if got.returncode:
                print(f"bench_small_cells: the {lib} worker failed:\n{got.stderr.strip()}", file=sys.stderr)
                return 1
            runs[lib].append(json.loads(got.stdout.strip().splitlines()[-1]))
    build = " (a stable-ABI build: ~3x slower per small operation)" if flint_is_stable_abi() else ""
    print(f"# sub-millisecond cells, {args.rounds} interleaved rounds, best CPU time per library; "
          f"python-flint {flint.__version__}{build}")
    print(f"{'cell':26s} {'ours [µs]':>10s} {'sage [µs]':>10s} {'sage/ours':>9s}  per round")
    for key in runs["ours"][0]:
        ours = min(r[key] for r in runs["ours"])
        sage = min(r[key] for r in runs["sage"])
        rounds = " ".join(f"{s[key] / o[key]:.2f}" for s, o in zip(runs["sage"], runs["ours"], strict=True))
        print(f"{key:26s} {ours * 1e6:10.1f} {sage * 1e6:10.1f} {sage / ours:9.2f}  {rounds}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
