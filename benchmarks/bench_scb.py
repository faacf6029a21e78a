#!/usr/bin/env python
"""Benchmark of the special coordinate basis and the observer of Tranninger et al. (2021).

Exact over Q: ``special_coordinate_basis`` (SCB), ``design_scb`` (the observer, which
computes its own SCB) and the certificate (every identity of the SCB and the observer,
including the Smith form of the Rosenbrock matrix), for the paper's example and for
systems with a planted structure of n = 8, 16, 32 states (random rational blocks mapped
by random rational Ts, Ti, To; seeded).  Targets of the issue: the example ≤ 50 ms,
n = 32 ≤ 2 s.  For scale, a floating-point computation of the invariant zeros alone
(generalised eigenvalues of the Rosenbrock pencil, scipy) — what the MATLAB toolkit's
floating-point SCB does not need to pay for exactness.  Timings are CPU time
(``time.process_time``) and never asserted.

Usage::

    python benchmarks/bench_scb.py            # example + n = 8, 16, 32
    python benchmarks/bench_scb.py --quick    # example + n = 8
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path

import numpy as np
import scipy.linalg

ROOT = Path(__file__).resolve().parents[1]
for p in (ROOT, ROOT / "tests"):
    if str(p) not in sys.path:
        sys.path.insert(0, str(p))

from analysis.paper003 import system as paper003  # noqa: E402
from analysis.planted_scb import planted  # noqa: E402

from uio_ring.analysis.scb import special_coordinate_basis  # noqa: E402
from uio_ring.design.scb import design_scb  # noqa: E402
from uio_ring.ring.qmatrix import QMatrix  # noqa: E402

SIZES = {8: (1, (2,), (3, 2), 0), 16: (2, (3, 2), (4, 3, 2), 1), 32: (4, (5, 4, 3), (6, 5, 3, 2), 1)}


def _cpu(fn):
    t0 = time.process_time()
    out = fn()
    return out, time.process_time() - t0


def _float_zeros(sys_) -> float:
    """CPU seconds of the invariant zeros in float64 (QZ of the Rosenbrock pencil, square-down by a random
    combination of the outputs when p > m)."""
    A, B, C, D = (np.array(QMatrix(M).tolist(), dtype=float) for M in (sys_.A, sys_.B, sys_.C, sys_.D))
    n, m, p = A.shape[0], B.shape[1], C.shape[0]
    R = np.random.default_rng(0).standard_normal((m, p))
    M = np.block([[A, B], [R @ C, R @ D]])
    N = np.block([[np.eye(n), np.zeros((n, m))], [np.zeros((m, n + m))]])
    t0 = time.process_time()
    scipy.linalg.eigvals(M, N)
    return time.process_time() - t0


def row(label: str, sys_, **design_options) -> None:
    scb, t_scb = _cpu(lambda: special_coordinate_basis(sys_))
    des, t_des = _cpu(lambda: design_scb(sys_, **design_options))
    cert, t_cert = _cpu(lambda: des.certificate())
    t_float = _float_zeros(sys_)
    dims = f"({scb.n_a},{scb.n_b},{scb.n_c},{scb.n_d}) q={scb.q} l={scb.l}"
    print(f"{label:<22} {sys_.n_x:>3} {dims:<40} {t_scb * 1e3:>9.1f} {t_des * 1e3:>9.1f} {t_cert * 1e3:>9.1f} "
          f"{'ok' if cert.ok else 'FAILED':>6} {t_float * 1e3:>9.2f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="the example and n = 8 only")
    args = ap.parse_args()
    print(f"{'system':<22} {'n':>3} {'(n_a,n_b,n_c,n_d), chains':<40} {'SCB ms':>9} {'design ms':>9} "
          f"{'cert ms':>9} {'cert':>6} {'float zeros ms':>9}")
    row("Tranninger2021 example", paper003(), poles_b=[-8, -6], input_ranges=[[-1, 2], [0, 1]])
    for n, (na, l, q, m0) in SIZES.items():
        if args.quick and n > 8:
            break
        for seed in (0, 1):
            A_a = QMatrix([[-(i + 1) if i == j else (1 if j == i + 1 else 0) for j in range(na)] for i in range(na)],
                          shape=(na, na))  # stable zeros −1, −2, …: a design exists
            sys_ = planted(na, l, q, m0, random.Random(1000 * n + seed), A_a=A_a).system
            row(f"planted seed {seed}", sys_, input_bounds=1)


if __name__ == "__main__":
    main()
