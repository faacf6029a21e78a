#!/usr/bin/env python
"""Benchmark of the noise figures: the peak-to-peak gain of a design and the least-noise searches.

Cases
    * paper 001's example (h = 1/100): ``design.performance()`` with the paper's poles, and
      ``design_zheng_bejarano(sys, poles="min-noise", rate=10)`` (target ≤ 2 s), criterion
      peak (the pole patterns, then the coupling of G0) and the same search without the
      coupling stage (what the pole patterns alone give);
    * random delay systems with n_x = 8 from ``bench_design.py``'s family (h = 1/100, seeds
      0, 1, 2): the same operations, rate 5, baseline the default poles at −5;
    * the linear parts of the other methods: ``hierarchical-sta`` (its Luenberger stage) on
      the aircraft of paper 000 and ``high-gain`` on Example 3 of Grip & Saberi, rate 2;
    * ``criterion="h2"``: a delay-free system with finite H2 gains, and the refusal on paper
      001's example (its read-out feeds y through: H2 infinite for every candidate).

Printed (the "3 states" row compares H2 gains: min-noise with criterion peak as the baseline,
criterion h2 as the search): CPU time [s] (``time.process_time``: the machine may be shared) of each operation, the
worst-state gain (noise bounded by 1 on every output), the ratio baseline / chosen, the poles.
Timings are never asserted.

Usage::

    python benchmarks/bench_noise.py            # everything
    python benchmarks/bench_noise.py --quick    # paper example only
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path
from unittest import mock

ROOT = Path(__file__).resolve().parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from bench_design import PAPER, random_system  # noqa: E402

from uio_ring import DelaySystem, NotObservableError, design_zheng_bejarano  # noqa: E402
from uio_ring.errors import DomainError  # noqa: E402

HEAD = (f"{'case':<34} {'n_x':>3} {'gain [s]':>8} {'base gain':>10} {'search [s]':>10} {'best gain':>10} "
        f"{'ratio':>6}  poles")


def _timed(f):
    t0 = time.process_time()
    out = f()
    return out, time.process_time() - t0


def row(label: str, n_x: int, base, search, criterion: str = "peak") -> None:
    """``base()`` → baseline design, ``search()`` → chosen design; one printed line (the gains
    are the worst state's peak-to-peak gain, or its H2 gain with ``criterion="h2"``)."""

    def worst(perf) -> float:
        return float(perf.h2.max() if criterion == "h2" else perf.noise_gain.max())

    perf, t_perf = _timed(lambda: base().performance())
    best, t_opt = _timed(search)
    gain = worst(best.performance())
    poles = [str(p) for p in getattr(best, "poles", ())] or "-"
    print(f"{label:<34} {n_x:>3} {t_perf:>8.3f} {worst(perf):>10.4g} {t_opt:>10.2f} "
          f"{gain:>10.4g} {worst(perf) / gain:>6.2f}  {poles}")


def paper_rows() -> None:
    paper = DelaySystem(PAPER["A"], PAPER["B"], PAPER["C"], PAPER["D"], h="1/100")
    base = lambda: design_zheng_bejarano(paper, poles=[-10, -25, -50])  # noqa: E731
    row("paper 001 min-noise rate 10", paper.n_x, base,
        lambda: design_zheng_bejarano(paper, poles="min-noise", rate=10))
    with mock.patch("uio_ring.design.noise.couple", lambda *a, **k: None):
        row("paper 001 pole patterns only", paper.n_x, base,
            lambda: design_zheng_bejarano(paper, poles="min-noise", rate=10))
    _, t = _timed(lambda: _refused(paper))
    print(f"{'paper 001 criterion h2':<34} {paper.n_x:>3} refused in {t:.2f} s (H2 infinite for every candidate)")


def _refused(sys_) -> None:
    try:
        design_zheng_bejarano(sys_, poles="min-noise", rate=10, criterion="h2")
    except DomainError:
        return
    raise AssertionError("criterion='h2' was not refused on paper 001's example")  # noqa: TRY003


def other_rows() -> None:
    for seed in range(3):
        s = random_system(8, random.Random(seed))
        sys_ = DelaySystem(*s.matrices().values(), h="1/100")
        try:
            row(f"random n=8 seed {seed}, rate 5", 8, lambda sys_=sys_: design_zheng_bejarano(sys_, rate=5),
                lambda sys_=sys_: design_zheng_bejarano(sys_, poles="min-noise", rate=5))
        except NotObservableError as exc:
            print(f"random n=8 seed {seed}: refused ({str(exc)[:60]}…)")
    chain = DelaySystem("[[0,1,0],[0,0,1],[1,0,0]]", "[[0],[0],[0]]", "[[1,0,0],[0,0,1]]", None)
    row("3 states, H2 gain: peak vs h2", 3, lambda: design_zheng_bejarano(chain, poles="min-noise", rate=2),
        lambda: design_zheng_bejarano(chain, poles="min-noise", rate=2, criterion="h2"), criterion="h2")
    from uio_ring.design.hierarchical_sta import design_hierarchical_sta
    from uio_ring.design.high_gain import design_high_gain
    from uio_ring.spec import load_spec

    air = load_spec(ROOT.parent / "examples" / "aircraft_normal_form.yaml").system
    row("aircraft hierarchical-sta rate 2", air.n_x, lambda: design_hierarchical_sta(air),
        lambda: design_hierarchical_sta(air, poles="min-noise", rate=2))
    A = "[[0,1,0,0,0],[0,0,0,0,0],[0,0,0,1,0],[0,0,0,0,1],[0,0,0,0,0]]"
    W1 = [[0, -1, 0, 1, 0], [0, 0, 0, 0, 1], [0, -1, 0, 1, 0], [1, 0, 0, 0, 1], [0, 1, 0, 0, 0]]
    hg = DelaySystem(A, [[0]] * 5, "[[1,0,0,0,0],[0,0,1,0,0]]", None)
    row("grip-saberi ex. 3 high-gain rate 2", 5, lambda: design_high_gain(hg, W=[W1], poles=[-2, -4, -6]),
        lambda: design_high_gain(hg, W=[W1], poles="min-noise", rate=2))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args()
    print(HEAD)
    paper_rows()
    if not args.quick:
        other_rows()


if __name__ == "__main__":
    main()
