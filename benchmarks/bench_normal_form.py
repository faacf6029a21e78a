#!/usr/bin/env python
"""Benchmark of the observer-normal-form design (Niederwieser et al. 2022) and its simulation.

Design: for seeded random strongly observable systems with n = 5, 10, 20, 40
in two families — short chains (``p = max(m + 1, n // 5)`` outputs) and one long
chain (``p = m + 1``) — with ``m = max(1, n // 10)`` unknown inputs (chains longer than 8 get Levant's
parameters continued linearly, for timing only), integer entries
in [−2, 2], ``D = 0`` (generically strongly observable since p > m), the time of

* ``normal_form_applicable`` (Smith form of the Rosenbrock matrix over Q[s]),
* ``design_normal_form`` (which includes that check, Steps 1–4, exact over Q),
* its certificate,

plus the chain lengths μ and the size (decimal digits) of the largest
denominator of ``T``.  The simulation of the observer (steps per second through
the one engine) is in ``bench_sim.py``.  Timings are never asserted.

Usage::

    python benchmarks/bench_normal_form.py            # n = 5, 10, 20, 40
    python benchmarks/bench_normal_form.py --sizes 5 10
    python benchmarks/bench_normal_form.py --quick    # n = 5
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
for p in (ROOT, ROOT / "tests"):
    if str(p) not in sys.path:
        sys.path.insert(0, str(p))


from uio_ring import DelaySystem, design_normal_form, normal_form_applicable  # noqa: E402

#: Levant's standard parameters continued linearly (only to time long random chains; no tuning claim)
LAMBDAS = [1.1, 1.5, 2, 3, 5, 7, 10, 12] + [12 + 3 * k for k in range(1, 40)]


def random_system(n: int, seed: int, *, balanced: bool = False) -> tuple[DelaySystem, int]:
    """A random strongly observable system (drawn until one is); returns it and the draw count.

    ``p = m + 1`` outputs give one long chain (μ_1 ≈ n − p + 1); ``balanced`` uses
    ``p = max(m + 1, n // 5)`` outputs, i.e. chains of length about 5.
    """
    rng = random.Random(seed)
    m = max(1, n // 10)
    p = max(m + 1, n // 5) if balanced else m + 1
    draws = 0
    while True:
        draws += 1
        A = [[rng.randint(-2, 2) for _ in range(n)] for _ in range(n)]
        B = [[rng.randint(-2, 2) for _ in range(m)] for _ in range(n)]
        C = [[rng.randint(-2, 2) for _ in range(n)] for _ in range(p)]
        sys_ = DelaySystem(A, B, C, None)
        if normal_form_applicable(sys_).holds:
            return sys_, draws


def _digits(M) -> int:
    return max((len(str(c.denominator)) for row in M.coefficient_lists()[0] for c in row), default=1)


def bench_design(sizes: list[int], *, balanced: bool = False) -> None:
    kind = "p = max(m + 1, n // 5): short chains" if balanced else "p = m + 1: one long chain"
    print(f"design (exact over Q), {kind}")
    print(f"{'n':>4} {'m':>3} {'p':>3} {'draws':>5} {'check [s]':>10} {'design [s]':>11} {'cert [s]':>9}  "
          f"{'mu':<14} {'digits(T)':>9}")
    for n in sizes:
        sys_, draws = random_system(n, seed=n, balanced=balanced)
        t0 = time.perf_counter()
        normal_form_applicable(sys_)
        t1 = time.perf_counter()
        d = design_normal_form(sys_, [1] * sys_.n_w, lambdas=LAMBDAS)
        t2 = time.perf_counter()
        ok = d.certificate().ok
        t3 = time.perf_counter()
        assert ok, "certificate failed"
        print(f"{n:>4} {sys_.n_w:>3} {sys_.n_y:>3} {draws:>5} {t1 - t0:>10.3f} {t2 - t1:>11.3f} {t3 - t2:>9.3f}  "
              f"{str(d.mu):<14} {_digits(d.T):>9}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="*", default=[5, 10, 20, 40])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    if args.quick:
        bench_design([5])
    else:
        bench_design(args.sizes, balanced=True)
        print()
        bench_design(args.sizes)


if __name__ == "__main__":
    main()
