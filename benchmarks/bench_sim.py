#!/usr/bin/env python
"""Benchmark of the numeric backend (uio_ring.sim) against jitcdde, at equal accuracy.

Problem: the example of Zheng et al. (2015) §5 — plant (4 states, A(δ), B(δ), C(δ), D(δ)) and the
Zheng–Bejarano observer of ``design_zheng_bejarano(sys, poles=[-10, -25, -50])``
(n_z states), unknown inputs w1 = −10 sin 100t, w2 = 20 sin 20t, constant history
x = (1, 0, −1, 1/2) and ξ = 0 before 0, h = 0.01, 10 s.  As one DDE::

    x' = A(δ) x + B(δ) w(t),   ξ' = L0 ξ + (JΛ)(δ) [C(δ) x + D(δ) w(t)]

What is timed
    ours      simulate() + observer run() at dt = 1e-4 (10⁵ steps), samples on the grid.
              "warm" = best of 5 (the per-(A, N, dt) precomputation is cached); "cold"
              = first call in the process (includes expm and the block matrices).
    jitcdde   (pip install jitcdde; benchmark-only) the same 4 + n_z DDE, adaptive
              Bogacki–Shampine, step_on_discontinuities, then integrate() to each of the
              10⁵ grid times (the samples ours returns), and to 1 000 times (integration
              alone).  Compile time reported separately.  Tolerances: the loosest
              atol = rtol in 1e-4 … 1e-10 whose error is ≤ ours ("equal accuracy").

Accuracy: max over t and components of |s − s_ref| / max|s_ref| (per component) for
s = (x, ξ), reference = ours at dt = h/400 (order 4: ~250× below dt = 1e-4), cross-checked
against jitcdde at the tightest tolerance.

Every observer through the one engine
    ``simulate_observer(design, …)`` end to end (plant + observer), steps per second:
    the Zheng–Bejarano observer on the paper-001 example above, and the normal-form
    observer (paper 000's aircraft, n = 7, Simulation 1) for each discretisation of its
    differentiators.

Usage::

    python benchmarks/bench_sim.py            # full table (jitcdde if installed)
    python benchmarks/bench_sim.py --quick    # 1 s horizon, no jitcdde: a smoke test

Timings are never asserted in tests.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from sys import path as sys_path

import numpy as np

from uio_ring import DelaySystem, design_zheng_bejarano
from uio_ring.numeric.convert import coefficient_arrays, poly_matmul
from uio_ring.numeric.taps import delayed_sum
from uio_ring.sim import simulate

PAPER = dict(
    A="[[0,-1,1,0],[-1,d,0,0],[1,0,1,0],[d,1,1,-1]]",
    B="[[0,0],[0,0],[1,1],[0,d]]",
    C="[[d,0,0,0],[0,1,0,0],[0,0,1,1]]",
    D="[[1,d],[0,0],[1,d]]",
)
PHI = np.array([1.0, 0.0, -1.0, 0.5])


def w_num(t):
    t = np.asarray(t, dtype=float)
    return np.array([-10.0 * np.sin(100.0 * t), 20.0 * np.sin(20.0 * t)])


def ours(sys, design, h, dt, t_final):
    """Plant + observer with the same conventions as the DDE above; returns t, x, ξ."""
    plant = simulate(sys, h=h, t_final=t_final, dt=dt, w=w_num, x0=PHI)
    obs = design.numeric(h=h).stepper(dt)
    xi = obs.trajectories(plant.y, y_history=true_y_history(sys, design, h, dt)).xi
    return plant.t, plant.x, xi


def true_y_history(sys, design, h, dt):
    """y(t) = C(δ)φ + D(δ)w(t) at the negative grid times the observer reads."""
    probe = design.numeric(h=h).stepper(dt)
    L, N = probe.history_length, probe.N
    C = coefficient_arrays(sys.C)
    D = coefficient_arrays(sys.D)
    K = C.shape[0] - 1
    tt = np.arange(-L - K * N, 0) * dt
    X = np.tile(PHI, (len(tt), 1))
    W = w_num(tt).T
    off = K * N + L
    return (delayed_sum(C, X, -L, -1, N, off) + delayed_sum(D, W, -L, -1, N, off)).T


def build_jitcdde(sys, design, h):
    import symengine as se
    from jitcdde import jitcdde, t, y  # benchmark-only dependency

    A, B, C, D = (coefficient_arrays(getattr(sys, k)) for k in "ABCD")
    Lam = coefficient_arrays(design.Lam)
    JL = poly_matmul(coefficient_arrays(design.J), Lam)
    L0 = coefficient_arrays(design.L0)[0]
    n, nz = A.shape[1], L0.shape[0]

    def w_sym(tau):
        return [-10 * se.sin(100 * (t - tau)), 20 * se.sin(20 * (t - tau))]

    def x_sym(tau):
        return [y(i, t - tau) if tau else y(i) for i in range(n)]

    def y_out(tau):  # C(δ) x + D(δ) w at t − tau
        out = [0] * C.shape[1]
        for i in range(C.shape[0]):
            xs = x_sym(tau + i * h)
            for r in range(C.shape[1]):
                out[r] += sum(float(C[i, r, c]) * xs[c] for c in range(n) if C[i, r, c])
        for i in range(D.shape[0]):
            ws = w_sym(tau + i * h)
            for r in range(D.shape[1]):
                out[r] += sum(float(D[i, r, c]) * ws[c] for c in range(D.shape[2]) if D[i, r, c])
        return out

    f = []
    for r in range(n):
        e = 0
        for i in range(A.shape[0]):
            xs = x_sym(i * h)
            e += sum(float(A[i, r, c]) * xs[c] for c in range(n) if A[i, r, c])
        for i in range(B.shape[0]):
            ws = w_sym(i * h)
            e += sum(float(B[i, r, c]) * ws[c] for c in range(B.shape[2]) if B[i, r, c])
        f.append(e)
    ys = [y_out(i * h) for i in range(JL.shape[0])]
    for r in range(nz):
        e = sum(float(L0[r, c]) * y(n + c) for c in range(nz) if L0[r, c])
        for i in range(JL.shape[0]):
            e += sum(float(JL[i, r, c]) * ys[i][c] for c in range(JL.shape[2]) if JL[i, r, c])
        f.append(e)
    max_delay = h * (JL.shape[0] - 1 + C.shape[0] - 1 + max(A.shape[0], B.shape[0], D.shape[0]))
    dde = jitcdde(f, max_delay=max_delay, verbose=False)
    return dde, n, nz


def run_jitcdde(dde, n, nz, tol, times):
    dde.purge_past()
    dde.constant_past(np.concatenate([PHI, np.zeros(nz)]), time=0.0)
    dde.set_integration_parameters(atol=tol, rtol=tol, first_step=1e-5, max_step=1e-2)
    t0 = time.perf_counter()
    dde.step_on_discontinuities()
    first = int(np.searchsorted(times, dde.t - 1e-12))
    out = np.empty((len(times), n + nz))
    out[:first] = np.nan  # before the discontinuity steps: not compared
    for k in range(first, len(times)):
        out[k] = dde.integrate(times[k])
    return time.perf_counter() - t0, out, first


def rel_error(s, ref):
    """max over t and components of |s − ref| / max_t |ref| (NaN samples ignored)."""
    scale = np.nanmax(np.abs(ref), axis=1, keepdims=True)
    scale[scale == 0] = 1.0
    return float(np.nanmax(np.abs(s - ref) / scale))


def best_time(f, repeats=5):
    return min(_timed(f) for _ in range(repeats))


def main() -> None:
    import warnings

    warnings.filterwarnings("ignore", message="The target time is smaller")
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true", help="1 s horizon, no jitcdde")
    ap.add_argument("--t-final", type=float, default=10.0)
    ap.add_argument("--h", type=float, default=0.01)
    ap.add_argument("--dt", type=float, default=1e-4)
    ap.add_argument("--no-jitcdde", action="store_true")
    args = ap.parse_args()
    T, h, dt = (1.0 if args.quick else args.t_final), args.h, args.dt
    sys = DelaySystem(PAPER["A"], PAPER["B"], PAPER["C"], PAPER["D"])
    design = design_zheng_bejarano(sys, poles=[-10, -25, -50])
    steps = int(round(T / dt))
    print(f"Zheng et al. (2015) §5: plant 4 states + observer n_z = {design.n_z}, h = {h}, {T:g} s")

    # reference: ours at dt = h/400, on the grid of dt = h/100 … h/10
    N_ref = 400
    t_ref, x_ref, xi_ref = ours(sys, design, h, h / N_ref, T)
    ref = np.concatenate([x_ref, xi_ref])

    def ref_on(N):
        return ref[:, :: N_ref // N]

    # 1. speed at dt (10⁵ steps for the defaults)
    t0 = time.perf_counter()
    tg, x, xi = ours(sys, design, h, dt, T)
    cold = time.perf_counter() - t0
    warm = best_time(lambda: ours(sys, design, h, dt, T))
    N0 = int(round(h / dt))
    err0 = rel_error(np.concatenate([x, xi]), ref_on(N0)) if N_ref % N0 == 0 else float("nan")
    print(f"\n1. speed at dt = {dt:g} ({steps} plant+observer steps)")
    print(f"{'':<28} {'time [s]':>9} {'steps/s':>10} {'max rel error':>14}")
    print(f"{'ours, warm (best of 5)':<28} {warm:9.4f} {steps / warm:10.3g} {err0:14.2e}")
    print(f"{'ours, cold (first call)':<28} {cold:9.4f} {steps / cold:10.3g} {err0:14.2e}")

    # 2. accuracy ladder of ours
    ladder = []
    for N in (2, 4, 5, 10, 20, 50, 100):
        tt, xx, xxi = ours(sys, design, h, h / N, T)
        el = best_time(lambda N=N: ours(sys, design, h, h / N, T), 3)
        ladder.append((N, el, rel_error(np.concatenate([xx, xxi]), ref_on(N))))
    print("\n2. ours: accuracy vs step (error against dt = h/400)")
    print(f"{'dt':>10} {'steps':>8} {'time [s]':>9} {'max rel error':>14}")
    for N, el, e in ladder:
        print(f"{h / N:10.2e} {int(round(T * N / h)):8d} {el:9.4f} {e:14.2e}")

    engine_table(sys, design, h, 0.5 if args.quick else 5.0)
    if args.quick or args.no_jitcdde:
        return
    try:
        import jitcdde  # noqa: F401
    except ImportError:
        print("\njitcdde not installed (pip install jitcdde): comparison skipped")
        return
    c0 = time.perf_counter()
    dde, n, nz = build_jitcdde(sys, design, h)
    dde.compile_C(verbose=False)
    print(f"\n3. jitcdde (compile {time.perf_counter() - c0:.1f} s, not counted), equal accuracy")
    print("   jitcdde sampled on the grid of the matching run of ours; ours = the coarsest dt")
    print("   of the ladder with an error ≤ jitcdde's.")
    print(f"{'jitcdde tol':>11} {'time [s]':>9} {'error':>9} | {'ours dt':>9} {'time [s]':>9} {'error':>9} | {'ratio':>6}")
    rows = []
    for tol in (1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10):
        match = next(((N, el, e) for N, el, e in ladder if e <= 1.0), None)
        try:
            # error on the finest common grid (h/100), time with samples on the grid of the match
            _, s_fine, _ = run_jitcdde(dde, n, nz, tol, t_ref[:: N_ref // 100])
            e_j = rel_error(s_fine.T, ref_on(100))
        except Exception as exc:  # jitcdde.UnsuccessfulIntegration
            print(f"{tol:11.0e} failed ({type(exc).__name__})")
            continue
        match = next(((N, el, e) for N, el, e in ladder if e <= e_j), None)
        if match is None:
            print(f"{tol:11.0e} {'':>9} {e_j:9.2e} | none of ours is as coarse: use ours at dt = {dt:g}")
            match = (N0, warm, err0)
        N, el, e = match
        grid = t_ref[:: N_ref // N]
        el_j = min(run_jitcdde(dde, n, nz, tol, grid)[0] for _ in range(2))
        rows.append((tol, el_j, e_j, N, el, e))
        print(f"{tol:11.0e} {el_j:9.3f} {e_j:9.2e} | {h / N:9.1e} {el:9.4f} {e:9.2e} | {el_j / el:6.1f}")
    print("(ratio = jitcdde time / ours time at equal or better accuracy of ours)")


def engine_table(sys, design, h, t_final: float) -> None:
    """Both observers through ``simulate_observer`` (plant + observer, end to end)."""
    root = Path(__file__).resolve().parents[1] / "tests"
    if str(root) not in sys_path:
        sys_path.insert(0, str(root))
    from design import paper000

    from uio_ring import design_normal_form, simulate_observer

    nf = design_normal_form(paper000.aircraft(), ["0.02"], gains=paper000.GAINS_89)
    delta = lambda t: 0.008 + 0.01 * np.sin(2 * t) + 0.002 * np.cos(13 * t)  # noqa: E731
    runs = [("zheng-bejarano", "", lambda: simulate_observer(design, sys, h=h, t_final=t_final, dt=1e-4,
                                                               w=w_num, x0=PHI))]
    for disc in ("implicit", "explicit", "euler"):
        runs.append(("normal-form", disc, lambda disc=disc: simulate_observer(
            nf, t_final=t_final, dt=1e-4, w=delta, x0=paper000.X0, discretisation=disc)))
    print(f"\n4. every observer through simulate_observer (plant + observer, dt = 1e-4, {t_final:g} s)")
    print(f"{'method':<16} {'discretisation':<15} {'steps':>7} {'time [s]':>9} {'steps/s':>10} {'final error':>12}")
    for name, disc, run in runs:
        r = run()
        el = best_time(run, 3)
        steps = r.t.size - 1
        print(f"{name:<16} {disc or '-':<15} {steps:>7} {el:>9.3f} {steps / el:>10.3g} {r.error_norm()[-1]:>12.2e}")


def _timed(f) -> float:
    t0 = time.perf_counter()
    f()
    return time.perf_counter() - t0


if __name__ == "__main__":
    main()
