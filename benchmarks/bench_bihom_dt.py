#!/usr/bin/env python
"""Discretisation error of the bi-homogeneous observers (method ``scb``) against the step size.

A strongly observable system (a b chain of length 2 without input, a d chain of length 3
driven by ``w = cos 2t``, ``|w| ≤ 1``) observed by the CBHO + DBHO (defaults) and, for
reference, by the Luenberger + HOSMO design.  After the errors have settled (t ≥ 20 s) the
exact observer's error is 0; what is left is the discretisation's.  For each step size and
discretisation (``implicit``, the default; ``explicit``) the table gives the largest late
error of each row of the d chain (e_{d,1} the measured one) and of the b chain, the fitted
order (slope in log–log) and the CPU time per step.  Nothing is asserted.

Usage::

    python benchmarks/bench_bihom_dt.py            # dt = 4e-3 … 2.5e-4
    python benchmarks/bench_bihom_dt.py --quick    # dt = 4e-3, 2e-3
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from uio_ring import DelaySystem  # noqa: E402
from uio_ring.design.scb import design_scb  # noqa: E402
from uio_ring.errors import SimulationError  # noqa: E402
from uio_ring.ring.qmatrix import QMatrix as Q  # noqa: E402
from uio_ring.sim.engine import simulate_observer  # noqa: E402

SYSTEM = DelaySystem("[[0,1,0,0,0],[0,0,0,0,0],[0,0,0,1,0],[0,0,0,0,1],[0,0,0,0,0]]", "[[0],[0],[0],[0],[1]]",
                     "[[1,0,0,0,0],[0,0,1,0,0]]", None)
X0 = np.array([1.0, -1, 0.5, 0, 0.2])


def _late_errors(design, dt: float, disc: str, t_final: float) -> tuple[np.ndarray, float]:
    def w(t):
        return np.atleast_2d(np.cos(2 * np.asarray(t, float)))

    t0 = time.process_time()
    res = simulate_observer(design, t_final=t_final, dt=dt, w=w, x0=X0, x_hat0=X0 + 1.0, progress=False,
                            discretisation=disc)
    cpu = (time.process_time() - t0) / res.t.size
    e = np.linalg.inv(np.array(Q(design.scb.Ts).tolist(), float)) @ (res.x - res.x_hat)
    return np.max(np.abs(e[:, res.t >= 20.0]), axis=1), cpu


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true")
    args = ap.parse_args(argv)
    dts = (4e-3, 2e-3) if args.quick else (4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4)
    t_final = 22.0 if args.quick else 25.0
    designs = {
        "CBHO+DBHO": design_scb(SYSTEM, poles_b=[-2, -2], input_bounds=[1], b_observer="cbho", d_observer="dbho"),
        "Luenberger+HOSMO": design_scb(SYSTEM, poles_b=[-2, -2], input_bounds=[1]),
    }
    print("late errors (t >= 20 s): max |e| per row; rows e_b1 e_b2 | e_d1 e_d2 e_d3")
    for name, d in designs.items():
        for disc in ("implicit", "explicit"):
            rows = []
            for dt in dts:
                try:
                    err, cpu = _late_errors(d, dt, disc, t_final)
                except SimulationError as exc:
                    print(f"{name:17s} {disc:8s} dt={dt:.1e}  diverged ({exc})")
                    continue
                rows.append((dt, err))
                print(f"{name:17s} {disc:8s} dt={dt:.1e}  " + " ".join(f"{x:.2e}" for x in err)
                      + f"   {cpu * 1e6:.1f} us/step")
            if len(rows) >= 2:
                ldt = np.log([r[0] for r in rows])
                orders = [np.polyfit(ldt, np.log(np.maximum([r[1][i] for r in rows], 1e-300)), 1)[0]
                          for i in range(len(rows[0][1]))]
                print(f"{name:17s} {disc:8s} fitted order: " + " ".join(f"{o:.2f}" for o in orders))
    return 0


if __name__ == "__main__":
    sys.exit(main())
