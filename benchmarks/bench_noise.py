#!/usr/bin/env python
"""Benchmark of the noise figures: the peak-to-peak gain of a design and the least-noise search.

Cases
    * paper 001's example (h = 1/100): ``design.performance()`` with the paper's poles, and
      ``design_zheng_bejarano(sys, poles="min-noise", rate=10)`` (target ≤ 2 s);
    * random delay systems with n_x = 8 from ``bench_design.py``'s family (h = 1/100, seeds
      0, 1, 2): the same two operations, rate 5.

Printed: time [s] of each operation, the worst-state gain (noise bounded by 1 on every
output) and the ratio to the gain with the default poles.  Timings are never asserted.

Usage::

    python benchmarks/bench_noise.py            # paper example + n_x = 8
    python benchmarks/bench_noise.py --quick    # paper example only
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from bench_design import PAPER, random_system  # noqa: E402

from uio_ring import DelaySystem, NotObservableError, design_zheng_bejarano  # noqa: E402


def _timed(f):
    t0 = time.perf_counter()
    out = f()
    return out, time.perf_counter() - t0


def row(label: str, sys, rate, baseline_poles=None) -> None:
    base = design_zheng_bejarano(sys, poles=baseline_poles, rate=rate)
    perf, t_perf = _timed(base.performance)
    best, t_opt = _timed(lambda: design_zheng_bejarano(sys, poles="min-noise", rate=rate))
    gain = best.performance().noise_gain.max()
    print(f"{label:<22} {sys.n_x:>3} {t_perf:>12.3f} {perf.noise_gain.max():>12.4g} {t_opt:>13.2f} "
          f"{gain:>12.4g} {perf.noise_gain.max() / gain:>7.2f}  {[str(p) for p in best.poles]}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    print(f"{'case':<22} {'n_x':>3} {'gain time [s]':>12} {'base gain':>12} {'min-noise [s]':>13} "
          f"{'best gain':>12} {'ratio':>7}  poles")
    paper = DelaySystem(PAPER["A"], PAPER["B"], PAPER["C"], PAPER["D"], h="1/100")
    row("paper 001 (poles -10,-25,-50)", paper, 10, baseline_poles=[-10, -25, -50])
    if args.quick:
        return
    for seed in range(3):
        s = random_system(8, random.Random(seed))
        sys_ = DelaySystem(*s.matrices().values(), h="1/100")
        try:
            row(f"random n=8 seed {seed}", sys_, 5)
        except NotObservableError as exc:
            print(f"random n=8 seed {seed}: refused ({str(exc)[:60]}…)")


if __name__ == "__main__":
    main()
