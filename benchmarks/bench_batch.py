#!/usr/bin/env python
"""Benchmark of the batched simulator (uio_ring.simulate_batch) against one run at a time.

Problems
    paper 001 §5: the Zheng–Bejarano observer (poles −10, −25, −50) on its plant, h = 0.01,
        w = (−10 a sin 100t, 20 sin 20t) with a per-scenario factor a, random constant
        initial states; a linear observer (one linear recursion).
    paper 000 aircraft (n = 7): the observer normal form with two Levant differentiators
        (gains (89)), implicit discretisation, w = 0.008 + a sin 2t + 0.002 cos 13t; a
        per-step loop (vectorised over the K scenarios in the batch).

    paper 001 with K perturbed plants: the same observer on K plants whose matrices are
        ``M ∘ (1 + 0.05 R)`` (``perturbed_plant``, one seed each), one plant per scenario
        (``Scenario(plant=…)``): the K plants are integrated together (stacked block maps).

    aircraft closed loop: paper 000's Simulation 2 (the observer reconstructs w, gains (95))
        with the feedback u = −[K h] χ̂ of (96), ``simulate_batch(feedback=…)`` (the law
        called once per step with the K estimates as rows) against ``simulate_observer(feedback=…)``.

What is timed
    batch   simulate_batch(design, K scenarios, t_final, dt) — plant + observer + metrics,
            no trajectories kept (bounded memory); CPU time (time.process_time, the machine may be
            loaded), best of 2 (the first call builds the tables).
    single  simulate_observer once per scenario (plant + observer, trajectories; without its
            accuracy check, which repeats the start with dt/2), best of 2,
            on a few scenarios; steps/s extrapolates to K.
    plants  (K perturbed plants) one batch of K plants against one call per plant:
            simulate_batch with K = 1 (what a sweep did before plants were batched) and
            simulate_observer (check=False); CPU time (time.process_time), best of 2, each
            time with the integrator tables of every plant built (as in a sweep: new plants).
Both are checked to give the same numbers (max |x̂_batch − x̂_single| / max |x|).
The aircraft and paper 001 cases are timed with both backends (``kernel=``): ``"python"``
(numpy, vectorised over K) and ``"numba"`` (when numba is installed: ``pip install -e '.[fast]'``):
the compiled step loop of the aircraft's observer; for paper 001 the compiled linear loops
(plant steps and quadrature, delayed taps, the observer's recursion). The batch is timed in
CPU time and in wall-clock time (``wall st/s``), each the best of 3; paper 001 with numba also
with 2 threads (``UIO_RING_THREADS=2``, ``numba×2`` in the name: chunks of scenarios on a
thread pool, ``simulate_batch``'s ``chunk_bounds``) when the machine has 2 cores (the cores and the load average are printed first: a second
thread only gains on an idle core).

Usage::

    python benchmarks/bench_batch.py            # K = 100 (paper 001: dt = 1e-4, 1 s; aircraft: dt = 1e-4, 0.5 s)
    python benchmarks/bench_batch.py --K 400
    python benchmarks/bench_batch.py --quick    # K = 8, short horizons: a smoke test

Timings are never asserted in tests.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]  # this checkout, and the paper data of the tests

from design import paper000, paper001  # noqa: E402

from uio_ring import design_normal_form, design_zheng_bejarano, simulate_observer  # noqa: E402
from uio_ring.sim._blocks import _CACHE  # noqa: E402
from uio_ring.sim.batch import Scenario, simulate_batch  # noqa: E402
from uio_ring.sim.plant import perturbed_plant  # noqa: E402


def paper001_case(K: int, rng: np.random.Generator):  # noqa: D103
    des = design_zheng_bejarano(paper001.system(), poles=[-10, -25, -50])

    def w(a):
        return lambda t: np.array([-10 * a * np.sin(100 * np.asarray(t, float)), 20 * np.sin(20 * np.asarray(t, float))])

    scen = [Scenario(x0=rng.normal(size=4), w=w(rng.uniform(0.5, 2))) for _ in range(K)]
    return des, scen, {}


def aircraft_case(K: int, rng: np.random.Generator):
    des = design_normal_form(paper000.aircraft(), ["0.02"], gains=paper000.GAINS_89)

    def w(a):
        return lambda t: 0.008 + a * np.sin(2 * t) + 0.002 * np.cos(13 * t)

    scen = [Scenario(x0=np.array(paper000.X0) * rng.uniform(0.5, 1.5), w=w(rng.uniform(0, 0.01)))
            for _ in range(K)]
    return des, scen, {"discretisation": "implicit"}


def kernels() -> tuple[str, ...]:
    """The backends to time: python, and numba when it is installed."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return ("python",)
    return ("python", "numba")


def best(f, repeats=2, clock=time.perf_counter):
    out, el = None, float("inf")
    for _ in range(repeats):
        t0 = clock()
        out = f()
        el = min(el, clock() - t0)
    return el, out


def best_cpu_wall(f, repeats=3):
    """(CPU time, wall time, result): each the best of ``repeats`` runs (the machine may be loaded)."""
    out, cpu, wall = None, float("inf"), float("inf")
    for _ in range(repeats):
        c0, w0 = time.process_time(), time.perf_counter()
        out = f()
        cpu, wall = min(cpu, time.process_time() - c0), min(wall, time.perf_counter() - w0)
    return cpu, wall, out


def bench_plants(K, t_final, dt, n_single):
    """K perturbed plants of paper 001: one batch against one call per plant (CPU time)."""
    base = paper001.system()
    des, scen, _ = paper001_case(K, np.random.default_rng(0))
    scen = [Scenario(x0=s.x0, w=s.w, plant=perturbed_plant(base, 0.05, k)) for k, s in enumerate(scen)]
    steps = int(round(t_final / dt))
    def cpu():  # every plant is new in a sweep: its integrator tables are built in the timed call
        _CACHE.clear()
        return time.process_time()

    el_b, res = best(lambda: simulate_batch(des, scen, t_final=t_final, dt=dt), clock=cpu)
    traj = simulate_batch(des, scen[:n_single], t_final=t_final, dt=dt, trajectories=True)

    def k1():
        return [simulate_batch(des, [s], t_final=t_final, dt=dt) for s in scen[:n_single] if not _CACHE.clear()]

    el_1, _ = best(k1, clock=cpu)
    el_s, singles = best(lambda: [simulate_observer(des, s.plant, t_final=t_final, dt=dt, w=s.w, x0=s.x0, check=False)
                                  for s in scen[:n_single] if not _CACHE.clear()], clock=cpu)
    dev = max(float(np.max(np.abs(r.x_hat - traj.x_hat[k])) / np.max(np.abs(r.x))) for k, r in enumerate(singles))
    rate_b, rate_1, rate_s = K * steps / el_b, n_single * steps / el_1, n_single * steps / el_s
    conv = int(np.sum(np.isfinite(res.metrics["t_converge"])))
    print(f"{'K plants, dt=' + format(dt, 'g'):<32} {K:>5} {steps:>7} {el_b:>9.3f} {rate_b:>12.3g} {rate_s:>12.3g} "
          f"{rate_b / rate_s:>8.1f} {dev:>10.1e} {conv:>5}   (batch K=1 per plant: {rate_1:.3g} st/s, "
          f"speed-up {rate_b / rate_1:.1f})")


def closed_loop_case(K: int, rng: np.random.Generator):
    from fractions import Fraction

    des = design_normal_form(paper000.aircraft(), ["0.046"], reconstruct_input=True, gains=paper000.GAINS_95)
    gain = np.array([[float(Fraction(x)) for x in r] for r in paper000.K_97])

    def law(t, x_hat, w_hat):  # (96) for K rows at once
        return -x_hat @ gain.T - w_hat[:, :1] * np.array([1.0, 0.0])

    def w(a):
        return lambda t: 0.008 + a * np.sin(2 * t)

    scen = [Scenario(x0=np.array(paper000.X0) * rng.uniform(0.5, 1.5), w=w(rng.uniform(0, 0.01))) for _ in range(K)]
    return des, scen, {"feedback": law}


def _single_options(opts):
    """simulate_observer's options for one scenario (a batch law becomes a law of one row)."""
    law = opts.get("feedback")
    if law is None:
        return opts
    return {**opts, "feedback": lambda t, x, w: law(t, x[None], None if w is None else w[None])[0]}


def bench(name, case, K, t_final, dt, n_single, kernel=None, threads=1):
    os.environ["UIO_RING_THREADS"] = str(threads)  # chunks of scenarios on threads (simulate_batch)
    des, scen, opts = case(K, np.random.default_rng(0))
    if kernel is not None:
        opts = {**opts, "kernel": kernel}
    steps = int(round(t_final / dt))
    el_b, wall_b, res = best_cpu_wall(lambda: simulate_batch(des, scen, t_final=t_final, dt=dt, **opts))
    traj = simulate_batch(des, scen[:n_single], t_final=t_final, dt=dt, trajectories=True, **opts)
    singles = []

    def one_at_a_time():
        singles.clear()
        for s in scen[:n_single]:
            singles.append(simulate_observer(des, t_final=t_final, dt=dt, w=s.w, x0=s.x0, check=False,
                                             **_single_options(opts)))

    el_s, _ = best(one_at_a_time, clock=time.process_time)
    dev = max(float(np.max(np.abs(r.x_hat - traj.x_hat[k])) / np.max(np.abs(r.x))) for k, r in enumerate(singles))
    rate_b = K * steps / el_b
    rate_s = n_single * steps / el_s
    conv = int(np.sum(np.isfinite(res.metrics["t_converge"])))
    print(f"{name:<32} {K:>5} {steps:>7} {el_b:>9.3f} {rate_b:>12.3g} {rate_s:>12.3g} {rate_b / rate_s:>8.1f} "
          f"{dev:>10.1e} {conv:>5} {K * steps / wall_b:>12.3g}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="K = 8, short horizons (smoke test)")
    ap.add_argument("--K", type=int, default=100, help="scenarios per batch")
    args = ap.parse_args()
    K = 8 if args.quick else args.K
    print("scenario-steps/s: K · steps / CPU time (plant + observer + metrics); single = simulate_observer per "
          "scenario; wall st/s: K · steps / wall-clock time (one thread: wall ≥ CPU on a busy machine)")
    print(f"{'problem':<32} {'K':>5} {'steps':>7} {'batch [s]':>9} {'batch st/s':>12} {'single st/s':>12} "
          f"{'speed-up':>8} {'max dev':>10} {'conv':>5} {'wall st/s':>12}")
    cores = os.cpu_count() or 1
    print(f"cores: {cores}, load average: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    for kern in kernels():  # numba: the compiled linear loops (uio_ring.numeric.scenario_kernel, linear_kernel)
        for th in (1, 2) if kern == "numba" and cores >= 2 else (1,):
            tag = kern if th == 1 else f"{kern}×{th}"
            bench(f"paper 001 (ZB, dt=1e-4, {tag})", paper001_case, K, 0.1 if args.quick else 1.0, 1e-4,
                  2 if args.quick else 4, kernel=kern, threads=th)
            bench(f"paper 001 (ZB, dt=1e-3, {tag})", paper001_case, K, 0.5 if args.quick else 5.0, 1e-3,
                  2 if args.quick else 4, kernel=kern, threads=th)
    os.environ["UIO_RING_THREADS"] = "1"
    for kern in kernels():
        bench(f"aircraft (NF, implicit, {kern})", aircraft_case, K, 0.02 if args.quick else 0.5, 1e-4, 2, kernel=kern)
    bench("aircraft closed loop (NF)", closed_loop_case, K, 0.02 if args.quick else 0.2, 2e-4, 2)
    print("K perturbed plants of paper 001 (one plant per scenario), CPU time; single = one call per plant")
    bench_plants(K, 0.1 if args.quick else 1.0, 1e-4, 2 if args.quick else 4)
    bench_plants(K, 0.5 if args.quick else 5.0, 1e-3, 2 if args.quick else 4)


if __name__ == "__main__":
    main()
