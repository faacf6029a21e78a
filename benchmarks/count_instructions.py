#!/usr/bin/env python
"""Instructions per call of ``bench_ring.py`` cells, ours and SageMath's, counted by valgrind.

On a shared machine a time moves with the load and with the process: the same 4×2
Hermite form of degree 16 reads 2.7 ms in one interpreter and 4.2 ms in the next, every
repetition alike.  The number of instructions executed hardly moves, so a change of a
few per cent, or a ratio near 1 against SageMath, is readable here when timings cannot
show it.
Instructions are not time — a cache miss or a division costs more than an addition —
so this complements ``bench_ring.py`` and ``bench_small_cells.py``, it does not
replace them.

Each library runs each cell in its own interpreter under ``valgrind --tool=callgrind``:
the worker builds the case, calls the operation three times (first-call caches), then
``--calls`` times inside one ``functools.reduce``, and callgrind collects only while
that C function runs (``--collect-atstart=no --toggle-collect=functools_reduce``): the
count covers those calls and nothing else (the interpreter's start and the imports are
not counted; their counts vary by up to 25 M instructions between runs of SageMath's).
Repeated runs agree to 0.05 % (ours) and 1 % (SageMath's).  Needs valgrind (exit 2
when it is missing); SageMath as in ``bench_ring.py``.  A cell takes 10–60 s of
valgrind per library.

    PYTHONPATH=. python benchmarks/count_instructions.py narrow:16:4x2:hermite rankdef:4:4x4:hermite \\
        --sage-python /path/to/sagevenv/bin/python
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))  # bench_ring, beside this script

#: the seed of bench_ring.py's default cases
SEED = 20261123


def parse_cell(text: str) -> tuple[str, int, tuple[int, int], str]:
    """``family:n:RxC:operation`` → (family, n, (R, C), operation).

    >>> parse_cell("narrow:16:4x2:hermite")
    ('narrow', 16, (4, 2), 'hermite')
    """
    family, n, shape, op = text.split(":")
    rows, cols = shape.split("x")
    return family, int(n), (int(rows), int(cols)), op


def collected(stderr: str) -> int:
    """The instruction count in callgrind's summary line (``==pid== Collected : N``).

    >>> collected("==7== Events    : Ir\\n==7== Collected : 1216990343\\n")
    1216990343
    """
    found = re.search(r"Collected\s*:\s*(\d+)", stderr)
    if found is None:
        raise RuntimeError("callgrind printed no 'Collected' line:\n" + stderr[-2000:])
    return int(found.group(1))


def run_cell(library: str, cell: str, calls: int) -> None:
    """Build the case of ``cell`` for ``library`` ("ours" or "sage"), call its operation
    three times, then ``calls`` times inside one ``functools.reduce`` (the worker whose
    reduce callgrind watches)."""
    import functools

    import bench_ring as br

    family, n, shape, op = parse_cell(cell)
    cases = [c for c in br.build_cases([n], SEED) if c["family"] == family and c["n"] == n and c["shape"] == shape]
    if not cases:
        raise SystemExit(f"count_instructions: no bench_ring case {family} n={n} {shape[0]}x{shape[1]}")
    setup = br._setup_ours if library == "ours" else br._setup_sage
    f = setup(cases[0])[0][op]
    for _ in range(3):
        f()
    functools.reduce(lambda _acc, _i: f(), range(calls), None)


def count(python: str, library: str, cell: str, calls: int, env: dict[str, str]) -> float:
    """Instructions per call of ``cell`` for ``library`` in the interpreter ``python``."""
    got = subprocess.run(
        ["valgrind", "--tool=callgrind", "--callgrind-out-file=/dev/null", "--collect-atstart=no",
         "--toggle-collect=functools_reduce", python, __file__, "--worker", library, cell, str(calls)],
        env=env, capture_output=True, text=True)
    if got.returncode:
        raise RuntimeError(f"the {library} worker failed on {cell}:\n{got.stderr[-2000:]}")
    return collected(got.stderr) / calls


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cells", nargs="*", help="family:n:RxC:operation of bench_ring.py (e.g. narrow:16:4x2:hermite)")
    ap.add_argument("--sage-python", default=os.environ.get("UIO_SAGE_PYTHON") or None,
                    help="a Python interpreter with passagemath (default: $UIO_SAGE_PYTHON; without it, ours only)")
    ap.add_argument("--calls", type=int, default=10, help="calls counted per cell (default 10)")
    ap.add_argument("--worker", nargs=3, metavar=("LIB", "CELL", "CALLS"), help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.worker:
        library, cell, calls = args.worker
        run_cell(library, cell, int(calls))
        return 0
    if not args.cells:
        ap.error("give at least one cell, e.g. narrow:16:4x2:hermite")
    for cell in args.cells:
        try:
            parse_cell(cell)
        except ValueError:
            print(f"count_instructions: {cell!r} is not family:n:RxC:operation", file=sys.stderr)
            return 2
    if shutil.which("valgrind") is None:
        print("count_instructions: valgrind is not installed (it counts the instructions)", file=sys.stderr)
        return 2
    if args.sage_python:
        from bench_ring import sage_available

        if not sage_available(args.sage_python):
            print(f"count_instructions: {args.sage_python} cannot import SageMath", file=sys.stderr)
            return 2
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(HERE.parent), os.environ.get("PYTHONPATH", "")]))
    libraries = [("ours", sys.executable)] + ([("sage", args.sage_python)] if args.sage_python else [])
    print(f"# instructions per call (valgrind callgrind, {args.calls} calls counted)")
    print(f"{'cell':32s} " + " ".join(f"{lib + ' [M]':>10s}" for lib, _ in libraries)
          + ("  sage/ours" if args.sage_python else ""))
    for cell in args.cells:
        got = [count(python, lib, cell, args.calls, env) for lib, python in libraries]
        ratio = f"  {got[1] / got[0]:9.2f}" if len(got) == 2 else ""
        print(f"{cell:32s} " + " ".join(f"{x / 1e6:10.2f}" for x in got) + ratio, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
