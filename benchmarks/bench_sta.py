#!/usr/bin/env python
"""Benchmark of the hierarchical super-twisting observer (Bejarano, Fridman & Poznyak 2007).

Design (exact over Q): Molinari's sequence + ``design_hierarchical_sta`` + certificate, for
the paper's Example 1 and random strongly observable systems (n = 5, 10, 20; seeded; D = 0,
one unknown input, two outputs, small integer entries).  Simulation: plant + observer
steps per second through ``simulate_observer`` on Example 1 (dt = 1e-3), implicit and
explicit discretisation, and on Example 2 (Section 3, ``matched-sta``, the uncertain plant).
Simulation times are CPU (process) times, the least of three runs.  Timings are never asserted.
``simulate_observer`` repeats the start of a run with dt/2 (its a-posteriori accuracy check,
about 40 % more observer steps on Example 1); the last column, ``no check``, is the rate of the
same run with ``check=False`` (plant + observer only).  Each simulation is timed with both
backends of the observer's step loop (``kernel="python"``, and ``"numba"`` when numba is
installed: ``pip install -e '.[fast]'``); ``first call`` is the wall time of the first numba
run in this process (loading the compiled loop from numba's disk cache, or compiling it).

Usage::

    python benchmarks/bench_sta.py            # Example 1 + n = 5, 10, 20
    python benchmarks/bench_sta.py --quick    # Example 1 only, short simulation
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
for p in (ROOT, ROOT / "tests"):
    if str(p) not in sys.path:
        sys.path.insert(0, str(p))

from design import paper002  # noqa: E402

from uio_ring import DelaySystem, simulate_observer  # noqa: E402
from uio_ring.analysis.molinari import molinari_sequence  # noqa: E402
from uio_ring.design.hierarchical_sta import design_hierarchical_sta  # noqa: E402
from uio_ring.design.matched_sta import design_matched_sta  # noqa: E402


def random_system(n: int, seed: int) -> DelaySystem:
    rng = random.Random(seed)
    while True:
        A = [[rng.choice([-2, -1, 0, 0, 1, 2]) for _ in range(n)] for _ in range(n)]
        B = [[rng.choice([0, 0, 1, -1])] for _ in range(n)]
        C = [[rng.choice([0, 0, 1, -1, 2]) for _ in range(n)] for _ in range(2)]
        sys_ = DelaySystem(A, B, C, None)
        if molinari_sequence(sys_).holds:
            return sys_


def time_design(label: str, sys_: DelaySystem, **kw) -> None:
    t0 = time.perf_counter()
    seq = molinari_sequence(sys_)
    t1 = time.perf_counter()
    des = design_hierarchical_sta(sys_, report=seq, **kw)
    t2 = time.perf_counter()
    ok = des.certificate().ok
    t3 = time.perf_counter()
    print(f"{label:<16} {sys_.n_x:>3} {seq.l:>3} {t1 - t0:>12.3f} {t2 - t1:>11.3f} {t3 - t2:>9.3f} {ok!s:>5} "
          f"{des.numeric().n_z:>5}")


def best_of(runs: int, fn) -> tuple:
    """The result of ``fn()`` and its least CPU time over ``runs`` calls (the machine may be loaded)."""
    best, out = float("inf"), None
    for _ in range(runs):
        t0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t0)
    return out, best


def kernels() -> tuple[str, ...]:
    """The backends to time: python, and numba when it is installed."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return ("python",)
    return ("python", "numba")


def first_call(fn) -> float:
    t0 = time.perf_counter()
    fn()
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    ex1 = paper002.example1()
    print("design (exact over Q)")
    print(f"{'case':<16} {'n':>3} {'l':>3} {'molinari [s]':>12} {'design [s]':>11} {'cert [s]':>9} {'ok':>5} {'n_z':>5}")
    time_design("Example 1", ex1, gains=paper002.GAINS)
    if not args.quick:
        for n in (5, 10, 20):
            time_design(f"random n={n}", random_system(n, n))
    t_final = 1.0 if args.quick else 10.0
    des = design_hierarchical_sta(ex1, gains=paper002.GAINS)
    print(f"\nsimulation (Example 1, plant + observer, dt = 1e-3, {t_final:g} s)")
    print(f"{'discretisation':<15} {'kernel':<7} {'steps':>7} {'time [s]':>9} {'steps/s':>9} {'max err t>=2':>13} "
          f"{'no check':>9}")
    for disc in ("implicit", "explicit"):
        for kern in kernels():
            def run1(check: bool = True, disc: str = disc, kern: str = kern):
                return simulate_observer(des, t_final=t_final, dt=1e-3, w=paper002.w, u=paper002.u, x0=paper002.X0,
                                         discretisation=disc, check=check, kernel=kern)
            if kern == "numba":
                print(f"  (numba, first call: {first_call(run1):.2f} s wall)")
            r, el = best_of(3, run1)
            _, el_nc = best_of(3, lambda run1=run1: run1(False))
            late = r.t >= min(2.0, t_final / 2)
            print(f"{disc:<15} {kern:<7} {r.t.size - 1:>7} {el:>9.3f} {(r.t.size - 1) / el:>9.0f} "
                  f"{float(np.max(r.error_norm()[late])):>13.2e} {(r.t.size - 1) / el_nc:>9.0f}")
    des2 = design_matched_sta(paper002.example2(), poles=[-3, -4], gains=paper002.GAINS_2)
    print(f"\nsimulation (Example 2, matched-sta, n_z = {des2.numeric().n_z}, the uncertain plant, dt = 1e-3, "
          f"{t_final:g} s)")
    print(f"{'discretisation':<15} {'kernel':<7} {'steps':>7} {'time [s]':>9} {'steps/s':>9} {'max err t>=1':>13} "
          f"{'no check':>9}")
    for kern in kernels():
        def run2(check: bool = True, kern: str = kern):
            return simulate_observer(des2, paper002.example2_true_plant(), t_final=t_final, dt=1e-3, u=paper002.u2,
                                     x0=paper002.X0_2, check=check, kernel=kern)
        r, el = best_of(3, run2)
        _, el_nc = best_of(3, lambda run2=run2: run2(False))
        print(f"{'implicit':<15} {kern:<7} {r.t.size - 1:>7} {el:>9.3f} {(r.t.size - 1) / el:>9.0f} "
              f"{float(np.max(r.error_norm()[r.t >= min(1.0, t_final / 2)])):>13.2e} {(r.t.size - 1) / el_nc:>9.0f}")


if __name__ == "__main__":
    main()
