#!/usr/bin/env python
"""Seeded random spec files at the documented limits, for ``uio-ring check``/``design`` timings.

A spec of ``n`` states, ``m`` unknown inputs and ``p`` outputs whose A, B, C entries
are dense polynomials of δ-degree ``degree`` with integer coefficients in [−3, 3]
(``D = 0``, ``h = 0.1``).  Such systems almost never satisfy Assumption 1 (their
``N_k`` has non-unit invariant factors), which is the point: the check must run
algorithm (4)–(5) to its end at full degree.

Usage::

    python benchmarks/random_spec.py --n 4 --degree 16 --seed 1 > spec.yaml
    PYTHONPATH=. python -m uio_ring.cli check spec.yaml
    PYTHONPATH=. python benchmarks/random_spec.py --time 4 8 16 --degree 16 --budget 600

``--time`` runs ``uio-ring check`` on each size in its own process (a case over the
budget is reported as a timeout) and prints the CPU time of that process (user +
system, so other jobs on the machine do not inflate it) and the verdict line.
Timings are never asserted.
"""

from __future__ import annotations

import argparse
import random
import resource
import subprocess
import sys
import tempfile
from pathlib import Path


def _poly(rng: random.Random, degree: int) -> str:
    terms = []
    for k in range(degree + 1):
        c = rng.randint(-3, 3)
        if c:
            terms.append(f"{c}*d**{k}" if k else str(c))
    return " + ".join(terms).replace("+ -", "- ") or "0"


def _mat(rng: random.Random, rows: int, cols: int, degree: int) -> str:
    return "[" + ", ".join("[" + ", ".join(f"'{_poly(rng, degree)}'" for _ in range(cols)) + "]"
                           for _ in range(rows)) + "]"


def random_spec_text(n: int, degree: int, seed: int, *, m: int | None = None, p: int | None = None) -> str:
    """The YAML text of one seeded random spec (defaults: ``m = max(1, n // 4)``, ``p = m + 1``).

    >>> text = random_spec_text(2, 1, 0)
    >>> text.splitlines()[0]
    'name: random_n2_deg1_seed0'
    """
    m = max(1, n // 4) if m is None else m
    p = m + 1 if p is None else p
    rng = random.Random(seed)
    return (
        f"name: random_n{n}_deg{degree}_seed{seed}\n"
        "system:\n"
        f"  A: {_mat(rng, n, n, degree)}\n"
        f"  B: {_mat(rng, n, m, degree)}\n"
        f"  C: {_mat(rng, p, n, degree)}\n"
        "  h: 0.1\n"
    )


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=4, help="states (default 4)")
    ap.add_argument("--m", type=int, default=None, help="unknown inputs (default max(1, n // 4))")
    ap.add_argument("--p", type=int, default=None, help="outputs (default m + 1)")
    ap.add_argument("--degree", type=int, default=16, help="δ-degree of every entry (default 16)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--time", type=int, nargs="*", metavar="N", help="time `uio-ring check` on these sizes")
    ap.add_argument("--budget", type=float, default=600.0, help="seconds per case with --time")
    args = ap.parse_args(argv)
    if args.time is None:
        print(random_spec_text(args.n, args.degree, args.seed, m=args.m, p=args.p), end="")
        return 0
    print(f"uio-ring check on random specs (δ-degree {args.degree}, seed {args.seed}, m = max(1, n/4), p = m + 1)")
    for n in args.time:
        with tempfile.TemporaryDirectory() as tmp:
            spec = Path(tmp) / "spec.yaml"
            spec.write_text(random_spec_text(n, args.degree, args.seed, m=args.m, p=args.p), encoding="utf-8")
            before = resource.getrusage(resource.RUSAGE_CHILDREN)
            try:
                proc = subprocess.run([sys.executable, "-m", "uio_ring.cli", "check", str(spec)],
                                      capture_output=True, text=True, timeout=args.budget)
            except subprocess.TimeoutExpired:
                print(f"  n = {n:>2}: timeout (> {args.budget:g} s wall)")
                continue
            after = resource.getrusage(resource.RUSAGE_CHILDREN)
            cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
            verdict = next((ln.strip()[:60] for ln in proc.stdout.splitlines() if "==" in ln), "")
            print(f"  n = {n:>2}: {cpu:8.2f} s CPU, exit {proc.returncode}  {verdict}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
