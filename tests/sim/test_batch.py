"""simulate_batch: K scenarios in one vectorised run, the same numbers as K runs of simulate_observer."""

from __future__ import annotations

import importlib.util

import numpy as np
import pytest
from design import paper000, paper001

from uio_ring import design_normal_form, design_zheng_bejarano, simulate_observer
from uio_ring.errors import SimulationError
from uio_ring.sim.batch import METRICS, Scenario, simulate_batch, solve_chains


@pytest.fixture(scope="module")
def zb():
    return design_zheng_bejarano(paper001.system(), poles=[-10, -25, -50])


@pytest.fixture(scope="module")
def nf():
    return design_normal_form(paper000.aircraft(), ["0.02"], gains=paper000.GAINS_89)


needs_numba = pytest.mark.skipif(importlib.util.find_spec("numba") is None,
                                 reason="numba is not installed (pip install 'uio-ring[fast]')")


def numba_case(*values):
    """A case of the compiled step loop (uio_ring.numeric.kernel); the "python" cases run the
    Python one (vectorised over K; the scalar solver below SCALAR_CHAINS_BELOW rows)."""
    return pytest.param(*values, "numba", marks=needs_numba)


def _w(a, f):
    return lambda t: np.array([a * np.sin(f * np.asarray(t, float)), 20 * np.cos(20 * np.asarray(t, float))])


def _same(res, k, r, rel=1e-12):
    scale = max(np.max(np.abs(r.x)), 1.0)
    for name in ("x", "y", "x_hat"):
        assert np.max(np.abs(getattr(r, name) - getattr(res, name)[k])) <= (1e-12 if name != "x_hat" else rel) * scale, name


LINEAR_KERNELS = ["python", pytest.param("numba", marks=needs_numba)]  # the linear loops (linear_kernel)


@pytest.mark.parametrize("kernel", LINEAR_KERNELS)
@pytest.mark.parametrize("K", [3, 9])  # K < 8: chunked scan; K ≥ 8: one product per step
def test_batch_equals_separate_runs_delay_observer(zb, K, kernel):
    rng = np.random.default_rng(K)
    sc = [Scenario(x0=rng.normal(size=4), w=_w(rng.uniform(1, 10), rng.uniform(10, 100)),
                   noise=0.01 if k % 3 == 1 else None, seed=k,
                   x_hat0=rng.normal(size=4) if k % 2 else None) for k in range(K)]
    res = simulate_batch(zb, sc, t_final=0.25, dt=1e-3, trajectories=True, segment_steps=70, kernel=kernel)
    assert res.x.shape == (K, 4, 251) and res.t.shape == (251,)
    for k in (0, 1, K - 1):
        s = sc[k]
        r = simulate_observer(zb, t_final=0.25, dt=1e-3, w=s.w, x0=s.x0, noise=s.noise, seed=s.seed,
                              x_hat0=s.x_hat0)
        _same(res, k, r)
        e = np.max(np.abs(r.error), axis=0)
        assert res.metrics["peak"][k] == pytest.approx(e.max(), rel=1e-9)
        assert res.metrics["final"][k] == pytest.approx(e[-1], rel=1e-9)


@pytest.mark.parametrize("kernel", LINEAR_KERNELS)
@pytest.mark.parametrize("dt", [5e-4, 1e-4])  # N = 20, 100: the time-major plant integration (run_rows)
def test_batch_equals_separate_runs_fine_grid(zb, dt, kernel):
    """Array inputs (a jump at t = 0 read through the delayed input: end fixes), callables, noise."""
    rng = np.random.default_rng(7)
    sc = [Scenario(x0=rng.normal(size=4), w=[1.0, -2.0] if k % 2 else _w(3.0, 40.0), noise=0.01 if k == 2 else None,
                   seed=k) for k in range(9)]
    res = simulate_batch(zb, sc, t_final=0.06, dt=dt, trajectories=True, segment_steps=230, kernel=kernel)
    for k in (0, 1, 2):
        s = sc[k]
        r = simulate_observer(zb, t_final=0.06, dt=dt, w=s.w, x0=s.x0, noise=s.noise, seed=s.seed, check=False)
        _same(res, k, r, rel=1e-11)  # x, y to 1e-12; x̂ reads differences of y (rounding × ~100 at dt = 1e-4)


@pytest.mark.parametrize("disc, scalar_below, kernel", [
    ("implicit", 0, "python"), ("implicit", 100, "python"), ("explicit", 0, "python"), ("euler", 0, "python"),
    numba_case("implicit", 0), numba_case("explicit", 0), numba_case("euler", 0)])
def test_batch_equals_separate_runs_normal_form(nf, disc, scalar_below, kernel, monkeypatch):
    import uio_ring.sim.batch as batch

    monkeypatch.setattr(batch, "SCALAR_CHAINS_BELOW", scalar_below)  # vectorised / scalar chain solver
    u_sine = lambda t: np.array([0.01 * np.sin(np.asarray(t, float)), 0 * np.asarray(t, float)])  # noqa: E731
    sc = [Scenario(x0=np.array(paper000.X0) * f, w=lambda t, a=a: 0.008 + a * np.sin(2 * t),
                   u=u_sine if k % 2 else [0.0, 0.01], noise=0.001 if k == 2 else None, seed=3)
          for k, (f, a) in enumerate([(1.0, 0.01), (0.5, 0.0), (1.5, 0.005)])]
    res = simulate_batch(nf, sc, t_final=0.05, dt=1e-4, trajectories=True, segment_steps=123,
                         discretisation=disc, kernel=kernel)
    for k, s in enumerate(sc):
        r = simulate_observer(nf, t_final=0.05, dt=1e-4, w=s.w, u=s.u, x0=s.x0, noise=s.noise, seed=s.seed,
                              discretisation=disc, kernel=kernel)
        _same(res, k, r)


def test_metrics_of_a_known_error():
    from uio_ring import DelaySystem

    sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)
    des = design_zheng_bejarano(sys, poles=[-10])  # e' = −10 e: e(t) = e(0) e^{−10 t}
    sc = [Scenario(x0=[1.0, 0.0]), Scenario(x0=[1e-4, 0.0]), Scenario(x0=[1e9, 0.0])]
    res = simulate_batch(des, sc, t_final=1.0, dt=1e-3, tol=1e-3, diverge=1e6, segment_steps=100)
    m = res.metrics
    assert set(m) == set(METRICS)
    assert m["t_converge"][0] == pytest.approx(np.ceil(np.log(1e3) / 10 / 1e-3) * 1e-3)
    assert m["max_after"][0] <= 1e-3 and m["rms_after"][0] <= m["max_after"][0]
    assert m["t_converge"][1] == 0.0 and m["peak"][1] == pytest.approx(1e-4)
    assert np.isnan(m["t_diverge"][0]) and m["t_diverge"][2] == 0.0
    assert res.rows()[0]["peak"] == pytest.approx(1.0) and "converged" in repr(res)


def test_solve_chains_matches_the_scalar_solver():
    from uio_ring.numeric.stepper import solve_chain

    a = np.array([-7.0, -1.2, -0.3, 0.0, 0.4, 2.0, 55.0])
    for coef, s0, mu in (([], 1.0, 1), ([0.3], 0.5, 2), ([0.2, 0.7, 0.1], 0.9, 4)):
        sig, sg = solve_chains(a, coef, s0, mu)
        ref = np.array([solve_chain(float(v), coef, s0, mu) for v in a])
        np.testing.assert_allclose(sig, ref[:, 0], rtol=1e-14, atol=1e-15)
        np.testing.assert_allclose(sg, ref[:, 1], rtol=1e-14)


def test_bad_input(zb):
    with pytest.raises(SimulationError, match="Scenario"):
        simulate_batch(zb, [], t_final=0.1, dt=1e-3)
    with pytest.raises(SimulationError, match="dt"):
        simulate_batch(zb, [Scenario()], t_final=0.1, dt=3e-3)


@pytest.mark.parametrize("scalar_below, kernel", [(0, "python"), (100, "python"), numba_case(0)])
def test_batch_equals_separate_runs_hierarchical_sta(scalar_below, kernel, monkeypatch):
    """Chains coupled through sigma_xi (the levels of a hierarchical super-twisting observer).

    Each level differentiates the one below: simulate_observer itself moves x̂ by 5e-11 when y
    moves by 1e-15 (measured), so the last-bit differences of y between a batch and single
    runs (other BLAS blockings) show in x̂ at that size; x and y agree to 1e-12."""
    from design import paper002

    import uio_ring.sim.batch as batch
    from uio_ring.design.hierarchical_sta import design_hierarchical_sta

    monkeypatch.setattr(batch, "SCALAR_CHAINS_BELOW", scalar_below)
    des = design_hierarchical_sta(paper002.example1(), gains=paper002.GAINS)
    sc = [Scenario(x0=np.array(paper002.X0) * f, w=paper002.w, u=paper002.u) for f in (1.0, -0.5, 2.0)]
    res = simulate_batch(des, sc, t_final=0.3, dt=1e-3, trajectories=True, segment_steps=77, kernel=kernel)
    for k, s in enumerate(sc):
        _same(res, k, simulate_observer(des, t_final=0.3, dt=1e-3, w=s.w, u=s.u, x0=s.x0, kernel=kernel), rel=1e-9)


@pytest.mark.parametrize("disc", ["implicit", "explicit"])
def test_batch_equals_separate_runs_bihomogeneous_chains(disc, monkeypatch):
    """Bi-homogeneous chains (Moreno's injection, the scb design's DBHO and CBHO) in a batch whose
    rows take the vectorised path: their injection is Φ_k of the profile, not Levant's powers
    (they are solved row by row with the stepper's scalar step)."""
    from design.test_scb_bihom import STRONG

    import uio_ring.sim.batch as batch
    from uio_ring.design.scb import design_scb

    monkeypatch.setattr(batch, "SCALAR_CHAINS_BELOW", 0)
    des = design_scb(STRONG, poles_b=[-2, -2], input_bounds=[1], d_observer="dbho", b_observer="cbho")
    assert des.numeric().injection.profiles is not None
    rng = np.random.default_rng(4)
    sc = [Scenario(x0=rng.normal(size=5), w=lambda t: 0.5 * np.sin(t)) for _ in range(3)]
    res = simulate_batch(des, sc, t_final=0.5, dt=1e-3, trajectories=True, discretisation=disc)
    for k, s in enumerate(sc):
        _same(res, k, simulate_observer(des, t_final=0.5, dt=1e-3, w=s.w, x0=s.x0, discretisation=disc, check=False),
              rel=1e-9)


@pytest.mark.parametrize("kernel", LINEAR_KERNELS)
@pytest.mark.parametrize("dt", [1e-3, 2.5e-4])  # plant blocks of 10 (grouped maps), 40 steps (time-major)
def test_exact_start_equals_separate_runs(zb, dt, kernel):
    """exact_start: each scenario's plant starts earlier, the observer gets the true past and ẑ(0);
    the numbers of simulate_observer(exact_start=True) per scenario."""
    rng = np.random.default_rng(11)
    hist = lambda t: np.array([np.cos(t), 1.0 + 0 * t, np.sin(3 * t), 0.5 + 0 * t])  # noqa: E731
    sc = [Scenario(x0=hist if k == 0 else rng.normal(size=4), w=_w(rng.uniform(1, 10), rng.uniform(10, 100)),
                   noise=0.01 if k == 1 else None, seed=k) for k in range(4)]
    res = simulate_batch(zb, sc, t_final=0.1, dt=dt, trajectories=True, segment_steps=60, exact_start=True,
                         kernel=kernel)
    for k, s in enumerate(sc):
        r = simulate_observer(zb, t_final=0.1, dt=dt, w=s.w, x0=s.x0, noise=s.noise, seed=s.seed, exact_start=True,
                              check=False)
        _same(res, k, r, rel=1e-10)
        e = np.max(np.abs(r.error), axis=0)
        assert res.metrics["peak"][k] == pytest.approx(e.max(), rel=1e-9)
    lag = r.lag * r.N  # without noise, x̂ = x (up to integration error) from lag·h on: the start is exact
    assert np.max(np.abs(res.error[[0, 2, 3], :, lag:])) <= 1e-5 * np.max(np.abs(res.x))


def test_exact_start_refuses_what_simulate_observer_refuses(zb):
    with pytest.raises(SimulationError, match="x_hat0 or exact_start"):
        simulate_batch(zb, [Scenario(x_hat0=np.zeros(4))], t_final=0.01, dt=1e-3, exact_start=True)
    with pytest.raises(SimulationError, match="w: exact_start=True needs w as a callable"):
        simulate_batch(zb, [Scenario(), Scenario(w=[1.0, 0.0])], t_final=0.01, dt=1e-3, exact_start=True)


@needs_numba
@pytest.mark.parametrize("dt, perturb", [(1e-3, False), (5e-4, False), (1e-4, False), (1e-4, True)])
def test_compiled_linear_loops_equal_numpy(zb, dt, perturb, monkeypatch):
    """The compiled linear loops (plant recursion and quadrature, taps, observer recursion) give the
    numpy path's x, y, x̂ to 1e-12 (paper 001; N = 10, 20, 100; callables and array inputs with a
    jump at 0; perturbed plants); kernel="python" is the numpy path whatever UIO_RING_KERNEL says."""
    from uio_ring.sim.plant import perturbed_plant

    rng = np.random.default_rng(3)
    base = paper001.system()
    sc = [Scenario(x0=rng.normal(size=4), w=[1.0, -2.0] if k % 3 == 2 else _w(rng.uniform(1, 10), 40.0),
                   noise=0.01 if k == 1 else None, seed=k, x_hat0=rng.normal(size=4) if k % 2 else None,
                   plant=perturbed_plant(base, 0.05, k) if perturb and k else None) for k in range(9)]
    kw = dict(t_final=0.08, dt=dt, trajectories=True, segment_steps=230)
    import uio_ring.numeric.linear_kernel as lk
    import uio_ring.numeric.scenario_kernel as sk

    calls = []
    for mod, name in ((lk, "tap_sum"), (lk, "scan_rows"), (sk, "_run")):  # count the compiled loops' calls
        f = getattr(mod, name)
        monkeypatch.setattr(mod, name, lambda *a, f=f, name=name: calls.append(a[0] if name == "_run" else name) or f(*a))
    ref = simulate_batch(zb, sc, kernel="python", **kw)
    assert not calls
    res = simulate_batch(zb, sc, kernel="numba", **kw)
    # plant (N = h/dt > 16: its steps) and observer scenario-innermost: taps (set or added), the stencil
    # forcing with the steps in one pass; N = 10: the plant's grouped block maps and its taps time-major
    # (tap_sum); perturbed plants: stacked block maps, in numpy
    assert set(calls) == {"tap", "acc", "scan"} | ({"tap_sum"} if dt == 1e-3 and not perturb else set())
    for name in ("x", "y", "x_hat"):
        a, b = getattr(res, name), getattr(ref, name)
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b)), name
    assert np.array_equal(res.metrics["t_converge"], ref.metrics["t_converge"], equal_nan=True)


@needs_numba
def test_time_major_loops_equal_numpy():
    """The time-major compiled loops (linear_kernel.tap_sum, scan_rows: the forcing of observers with an
    injection term, linear observers without the cubic forcing) equal numpy (uio_ring.sim._blocks) to
    1e-12, and each scenario's numbers do not depend on the others (a range of scenarios alone:
    bit-identical)."""
    import uio_ring.numeric.linear_kernel as lk
    from uio_ring.sim._blocks import scan_rows, taps

    rng = np.random.default_rng(8)
    K, L = 37, 40
    S, M = rng.normal(size=(L + 20, K, 3)), rng.normal(size=(3, 3, 5))
    PhiT, x0, G = 0.3 * rng.normal(size=(5, 5)), rng.normal(size=(K, 5)), rng.normal(size=(L, K, 5))
    starts = np.array([20, 10, 0])
    t_all, s_all = lk.tap_sum(S, starts, M, np.empty((L, K, 5))), lk.scan_rows(PhiT, x0, G.copy())
    t_part = lk.tap_sum(np.ascontiguousarray(S[:, 19:]), starts, M, np.empty((L, K - 19, 5)))
    s_part = lk.scan_rows(PhiT, x0[19:], np.ascontiguousarray(G[:, 19:]))
    assert np.array_equal(t_all[:, 19:], t_part) and np.array_equal(s_all[:, 19:], s_part)
    ref_t = taps([S[s : s + L] for s in starts], list(M)).reshape(L, K, 5)
    ref_s = scan_rows(PhiT, x0, G.copy())
    assert np.max(np.abs(t_all - ref_t)) <= 1e-12 * np.max(np.abs(ref_t))
    assert np.max(np.abs(s_all - ref_s)) <= 1e-12 * np.max(np.abs(ref_s))
