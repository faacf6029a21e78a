"""simulate_batch with one plant per scenario: the numbers of K runs of simulate_observer,
each on its own (perturbed) plant."""

from __future__ import annotations

import importlib.util
import sys as _sys
from dataclasses import replace
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from design import paper000, paper001

from uio_ring import DelaySystem, design_normal_form, design_zheng_bejarano, simulate_observer
from uio_ring.errors import DimensionError, SimulationError
from uio_ring.numeric.convert import coefficient_arrays
from uio_ring.sim._blocks import BlockIntegrator, StackedBlockIntegrator
from uio_ring.sim.batch import Scenario, simulate_batch

_sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from analysis.paper003 import system as paper003  # noqa: E402


def perturbed(sys: DelaySystem, eps: float, seed: int) -> DelaySystem:
    """``sys`` with every nonzero coefficient times ``1 + ε r`` (r uniform in [−1, 1], rational)."""
    rng = np.random.default_rng(seed)

    def entry(c: np.ndarray) -> str:
        terms = [f"({Fraction(float(v)).limit_denominator(10**6) * Fraction(1 + eps * rng.uniform(-1, 1)).limit_denominator(10**6)})*d**{i}"
                 for i, v in enumerate(c) if v != 0]
        return " + ".join(terms) or "0"

    mats = {}
    for name in "ABCDEF":
        M = coefficient_arrays(getattr(sys, name))
        if M.shape[2] == 0:
            mats[name] = None
            continue
        mats[name] = [[entry(M[:, i, j]) for j in range(M.shape[2])] for i in range(M.shape[1])] if M.shape[0] else \
            [[0] * M.shape[2] for _ in range(M.shape[1])]
    return DelaySystem(mats["A"], mats["B"], mats["C"], mats["D"], mats["E"], mats["F"], h=sys.h)


def _w(a, f):
    return lambda t: np.array([a * np.sin(f * np.asarray(t, float)), 20 * np.cos(20 * np.asarray(t, float))])


def _check(des, runs, res, **kw):
    for k, (plant, s) in enumerate(runs):
        r = simulate_observer(des, plant, w=s.w, u=s.u, x0=s.x0, noise=s.noise, seed=s.seed, x_hat0=s.x_hat0,
                              check=False, **kw)
        scale = max(np.max(np.abs(r.x)), 1.0)
        for name, rel in (("x", 1e-12), ("y", 1e-12), ("x_hat", 1e-11)):  # x̂ differentiates y: last bits × ~10
            dev = np.max(np.abs(getattr(r, name) - getattr(res, name)[k]))
            assert dev <= rel * scale, (k, name, dev)


@pytest.mark.parametrize("kernel", ["python", pytest.param("numba", marks=pytest.mark.skipif(
    importlib.util.find_spec("numba") is None, reason="numba is not installed"))])
@pytest.mark.parametrize("dt, K", [(1e-3, 5), (5e-4, 9), (1e-4, 3)])  # N = 10 (super), 20 (sub), 100 (sub, m = 25)
def test_zheng_bejarano_delay_plants(dt, K, kernel):
    base = paper001.system()
    des = design_zheng_bejarano(base, poles=[-10, -25, -50])
    rng = np.random.default_rng(K)
    plants = [base if k == 0 else perturbed(base, 0.05, k) for k in range(K)]
    sc = [Scenario(x0=rng.normal(size=4), w=_w(rng.uniform(1, 10), rng.uniform(10, 100)), plant=p,
                   noise=0.01 if k % 3 == 1 else None, seed=k, x_hat0=rng.normal(size=4) if k % 2 else None)
          for k, p in enumerate(plants)]
    res = simulate_batch(des, sc, t_final=0.1, dt=dt, trajectories=True, segment_steps=70, kernel=kernel)
    _check(des, list(zip(plants, sc, strict=True)), res, t_final=0.1, dt=dt)


@pytest.mark.parametrize("disc", ["implicit", "euler"])
def test_normal_form_plants(disc):
    base = paper000.aircraft()
    des = design_normal_form(base, ["0.02"], gains=paper000.GAINS_89)
    plants = [perturbed(base, 0.02, k) for k in range(3)]
    sc = [Scenario(x0=np.array(paper000.X0) * f, w=lambda t, a=a: 0.008 + a * np.sin(2 * t), u=[0.0, 0.01], plant=p)
          for p, (f, a) in zip(plants, [(1.0, 0.01), (0.5, 0.0), (1.5, 0.005)], strict=True)]
    res = simulate_batch(des, sc, t_final=0.05, dt=1e-4, trajectories=True, segment_steps=123, discretisation=disc)
    _check(des, list(zip(plants, sc, strict=True)), res, t_final=0.05, dt=1e-4, discretisation=disc)


def test_scb_plants():
    from uio_ring.design.scb import design_scb

    base = paper003()
    des = design_scb(base, poles_b=[-8, -6], input_ranges=[[-2, 1], [0, 1]])
    plants = [perturbed(base, 0.01, k) for k in range(3)]
    x0 = np.array([1, -0.1, 2, -0.3, 0.5, 0.2, -0.5, -0.2])
    w = lambda t: np.array([1.5 * np.sin(np.asarray(t, float)) + 0.5, 0 * np.asarray(t, float)])  # noqa: E731
    sc = [Scenario(x0=x0 * (1 + 0.2 * k), w=w, plant=p) for k, p in enumerate(plants)]
    res = simulate_batch(des, sc, t_final=0.2, dt=1e-3, trajectories=True, segment_steps=50)
    _check(des, list(zip(plants, sc, strict=True)), res, t_final=0.2, dt=1e-3)


@pytest.mark.parametrize("method, N", [("super", 4), ("sub", 20), ("dense", 6), ("chunked", 40),
                                       ("scan", 20), ("scan", 17), ("scan", 3)])
def test_stacked_integrator_is_each_integrator(method, N):
    """The stacked block maps give each plant's own integration (two-delay plants, inputs)."""
    rng = np.random.default_rng(N)
    S_, n, nb = 3, 2, 5
    A = rng.normal(size=(S_, 3, n, n))
    X = np.zeros((S_, 2 * N + nb * N + 1, n))
    X[:, : 2 * N + 1] = rng.normal(size=(S_, 1, n))
    fin = rng.normal(size=(S_, nb * N + 1, n))
    fix = rng.normal(size=(S_, nb, n))
    from uio_ring.numeric.progress import Progress

    StackedBlockIntegrator(A, N, 0.01, method=method).run(X, fin, nb, Progress(1, False), end_fix=fix)
    for s in range(S_):
        Xs = np.zeros_like(X[s])
        Xs[: 2 * N + 1] = X[s, : 2 * N + 1]
        BlockIntegrator(A[s], N, 0.01, method="auto" if method == "scan" else method).run(Xs, fin[s], nb, Progress(1, False), end_fix=fix[s])
        np.testing.assert_allclose(X[s], Xs, rtol=1e-13, atol=1e-13 * np.max(np.abs(Xs)))


@pytest.mark.parametrize("kernel", ["python", pytest.param("numba", marks=pytest.mark.skipif(
    importlib.util.find_spec("numba") is None, reason="numba is not installed"))])
@pytest.mark.parametrize("N", [1, 2, 3, 20, 37, 100])
def test_time_major_integration_is_the_block_maps(N, kernel):
    """BlockIntegrator.run_rows (time-major, per step) gives the numbers of run (the block maps
    of its method) for S trajectories of one two-delay plant with inputs and end fixes."""
    from uio_ring.numeric.progress import Progress

    rng = np.random.default_rng(N)
    S_, n, nb = 3, 2, 4
    A = rng.normal(size=(3, n, n))
    X = np.zeros((S_, 2 * N + nb * N + 1, n))
    X[:, : 2 * N + 1] = rng.normal(size=(S_, 2 * N + 1, n))
    fin = rng.normal(size=(S_, nb * N + 1, n))
    fix = rng.normal(size=(S_, nb, n))
    integ = BlockIntegrator(A, N, 0.01)
    Xr = np.ascontiguousarray(X.transpose(1, 0, 2))
    integ.run_rows(Xr, np.ascontiguousarray(fin.transpose(1, 0, 2)), nb, end_fix=fix, kernel=kernel)
    integ.run(X, fin, nb, Progress(1, False), end_fix=fix)
    np.testing.assert_allclose(Xr.transpose(1, 0, 2), X, rtol=1e-12, atol=1e-12 * np.max(np.abs(X)))


def test_plants_must_match():
    base = paper001.system()
    des = design_zheng_bejarano(base, poles=[-10, -25, -50])
    other = DelaySystem("[[0, -1, 1, 0], [-1, d**2, 0, 0], [1, 0, 1, 0], [d, 1, 1, -1]]", paper001.B, paper001.C,
                        paper001.D, h="1/100")
    with pytest.raises(DimensionError, match="scenario 1: the plant's A has 3 delay coefficients"):
        simulate_batch(des, [Scenario(), Scenario(plant=other)], t_final=0.01, dt=1e-3)
    with pytest.raises(SimulationError, match="scenario 0: the plant's h = 1/50"):
        simulate_batch(des, [Scenario(plant=paper001.system("1/50"))], t_final=0.01, dt=1e-3)


def test_perturbed_plant_arrays_mixed_with_the_design_plant():
    """Coefficient-stack plants (perturbed_plant, as the sweeps make them) next to the design's
    own plant and to scenarios without a plant (the batch's plant)."""
    from uio_ring.sim.plant import perturbed_plant

    base = paper001.system()
    des = design_zheng_bejarano(base, poles=[-10, -25, -50])
    plants = [None, base, perturbed_plant(base, 0.1, 4), perturbed_plant(base, 0.02, 5)]
    x0 = np.random.default_rng(1).normal(size=4)
    sc = [Scenario(x0=x0, w=_w(3.0, 50.0), plant=p) for p in plants]
    res = simulate_batch(des, sc, t_final=0.2, dt=5e-4, trajectories=True)
    _check(des, [(base if p is None else p, s) for p, s in zip(plants, sc, strict=True)], res, t_final=0.2, dt=5e-4)
    assert np.array_equal(res.x[0], res.x[1])  # the batch's plant is the design's
    assert not np.allclose(res.y[2], res.y[1], rtol=1e-3)  # same x0 and w, another plant


@pytest.mark.parametrize("dt, exact", [(1e-3, False), (2.5e-4, False), (1e-3, True)])  # plant blocks of 10–12
def test_plants_of_several_delays_in_one_batch(dt, exact):  # steps (grouped maps), 40–48 (time-major)
    """Scenario(plant_h=…): the plants of each true delay integrated together, the one observer on
    all of them — the numbers of one batch per delay; another delay changes the run."""
    from uio_ring.sim.plant import perturbed_plant

    base = paper001.system()
    des = design_zheng_bejarano(base, poles=[-10, -25, -50])
    rng = np.random.default_rng(5)
    hs = [None, 0.011, 0.012, 0.011, None, 0.012]
    sc = [Scenario(x0=rng.normal(size=4), w=_w(rng.uniform(1, 5), rng.uniform(10, 50)), plant_h=h,
                   plant=perturbed_plant(base, 0.05, k) if k == 3 else None) for k, h in enumerate(hs)]
    res = simulate_batch(des, sc, t_final=0.15, dt=dt, trajectories=True, segment_steps=50, exact_start=exact)
    for h in (None, 0.011, 0.012):
        ks = [k for k, hk in enumerate(hs) if hk == h]
        one = simulate_batch(des, [sc[k] for k in ks], plant_h=h, t_final=0.15, dt=dt, trajectories=True,
                             exact_start=exact)
        for name, rel in (("x", 1e-13), ("y", 1e-13), ("x_hat", 1e-11)):  # x̂ differentiates y: last bits × ~100
            ref = getattr(one, name)
            assert np.max(np.abs(getattr(res, name)[ks] - ref)) <= rel * np.max(np.abs(ref)), (h, name)
        for m, v in res.metrics.items():  # errors to the rounding of x (an exact start's are ~1e-9)
            np.testing.assert_allclose(v[ks], one.metrics[m], rtol=1e-9, atol=1e-12 * np.max(np.abs(one.x)), err_msg=m)
    same = simulate_batch(des, [Scenario(x0=sc[2].x0, w=sc[2].w)], t_final=0.15, dt=dt, trajectories=True,
                          exact_start=exact)
    assert np.max(np.abs(same.x[0] - res.x[2])) > 1e-3  # h = 0.012 is another plant than h = 0.01


def test_one_delay_of_the_scenarios_is_the_batch_delay():
    """Every scenario with the same plant_h: the batch's plant_h (one group)."""
    des = design_zheng_bejarano(paper001.system(), poles=[-10, -25, -50])
    sc = Scenario(x0=[1.0, 0.0, 0.0, 0.0], w=_w(2.0, 30.0))
    a = simulate_batch(des, [replace(sc, plant_h=0.012)] * 2, t_final=0.1, dt=1e-3, trajectories=True)
    b = simulate_batch(des, [sc], plant_h=0.012, t_final=0.1, dt=1e-3, trajectories=True)
    np.testing.assert_allclose(a.x[1], b.x[0], rtol=0, atol=1e-13 * np.max(np.abs(b.x)))
    np.testing.assert_allclose(a.x_hat[0], b.x_hat[0], rtol=0, atol=1e-11 * np.max(np.abs(b.x)))
    c = simulate_batch(des, [sc], t_final=0.1, dt=1e-3, trajectories=True)  # h = 0.01: another plant
    assert np.max(np.abs(c.x[0] - b.x[0])) > 1e-3
