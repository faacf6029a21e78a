"""simulate_batch in chunks of scenarios, and the chunks on threads: the same numbers to rounding.

Not bit for bit: the BLAS may round a row of a product by the number of rows around it
(OpenBLAS 0.3.31, numpy 2.4: ``X[:K] @ A`` differs in the last bit of its last row when K is
odd) and by its thread setting at start-up.  The comparisons are ~10⁴ ulps of each
scenario's scale; a chunk that ran the wrong scenarios, in the wrong order or on the wrong
path differs by O(1)."""

from __future__ import annotations

import dataclasses
import importlib.util
import os
import threading

import numpy as np
import pytest
from design import paper000, paper001

import uio_ring.sim.batch as batch
from uio_ring import design_normal_form, design_zheng_bejarano
from uio_ring.errors import SimulationError
from uio_ring.numeric.threads import THREADS_ENV, batch_threads
from uio_ring.sim.batch import METRICS, Scenario, chunk_bounds, simulate_batch
from uio_ring.sim.plant import perturbed_plant

needs_numba = pytest.mark.skipif(importlib.util.find_spec("numba") is None,
                                 reason="numba is not installed (pip install 'uio-ring[fast]')")
KERNELS = ["python", pytest.param("numba", marks=needs_numba)]


@pytest.fixture(scope="module")
def zb():
    return design_zheng_bejarano(paper001.system(), poles=[-10, -25, -50])


def _w(a, f):
    return lambda t: np.array([a * np.sin(f * np.asarray(t, float)), 20 * np.cos(20 * np.asarray(t, float))])


def _scenarios(K, perturb=False):
    rng = np.random.default_rng(K)
    base = paper001.system()
    return [Scenario(x0=rng.normal(size=4), w=_w(rng.uniform(1, 10), 40.0), noise=0.01 if k % 5 == 1 else None,
                     seed=k, x_hat0=rng.normal(size=4) if k % 3 == 2 else None,
                     plant=perturbed_plant(base, 0.05, k) if perturb else None) for k in range(K)]


#: Agreement asked of two runs of the same scenarios, relative to each scenario's scale.
REL = 1e-12


def _assert_agree(a, b):
    """x, y, x̂, ŵ and every metric of the two results agree to rounding, scenario by scenario:
    values within ``REL`` of the scenario's largest |value| (of that signal; of the peak error for
    the metrics), times (convergence, peak, divergence) equal, and NaN where the other is NaN."""
    for name in ("x", "y", "x_hat", "w_hat"):
        va, vb = getattr(a, name), getattr(b, name)
        if va is None or vb is None:
            assert va is None and vb is None, name
            continue
        assert va.shape == vb.shape, name
        axes = tuple(range(1, va.ndim))
        scale = np.maximum(np.max(np.abs(va), axis=axes), 1e-300)
        assert np.all(np.max(np.abs(va - vb), axis=axes) <= REL * scale), name
    assert set(a.metrics) == set(b.metrics) == set(METRICS)
    peak = a.metrics["peak"]
    for name in METRICS:
        ma, mb = a.metrics[name], b.metrics[name]
        assert np.array_equal(np.isnan(ma), np.isnan(mb)), name
        ok = ~np.isnan(ma)
        if name.startswith("t_"):
            assert np.array_equal(ma[ok], mb[ok]), name
        else:
            assert np.all(np.abs(ma[ok] - mb[ok]) <= REL * peak[ok]), name


def test_chunk_bounds_cover_the_scenarios_in_order(monkeypatch):
    """Consecutive ranges covering 0 … K, each ≤ CHUNK and ≥ MIN_CHUNK (unless K is smaller: one
    chunk), sizes equal up to one, one per thread when MIN_CHUNK allows."""
    for chunk, low in ((10, 3), (128, batch.MIN_CHUNK)):
        monkeypatch.setattr(batch, "CHUNK", chunk)
        monkeypatch.setattr(batch, "MIN_CHUNK", low)
        for K in (1, 2, 9, 10, 11, 37, 100, 129, 400):
            for threads in (1, 2, 3):
                b = chunk_bounds(K, threads)
                assert b[0][0] == 0 and b[-1][1] == K and all(p[1] == q[0] for p, q in zip(b, b[1:], strict=False))
                sizes = [k1 - k0 for k0, k1 in b]
                assert max(sizes) - min(sizes) <= 1
                assert len(b) == 1 or min(sizes) >= low
                assert len(b) == max(1, min(max(-(-K // chunk), threads), K // low))
    assert batch.MIN_CHUNK >= batch.SCALAR_CHAINS_BELOW  # every chunk takes the batch's path
    assert chunk_bounds(400) == [(0, 100), (100, 200), (200, 300), (300, 400)]


@pytest.mark.parametrize("kernel", KERNELS)
@pytest.mark.parametrize(("dt", "perturb"), [(2.5e-4, False), (1e-3, False), (1e-3, True)])
def test_chunked_batch_agrees_with_one_chunk(zb, kernel, dt, perturb, monkeypatch):
    """K = 37 in chunks of ≤ 10 (10, 9, 9, 9; MIN_CHUNK = 8, the linear recursion's threshold) against
    one chunk: x, y, x̂ and every metric agree to rounding (each scenario is computed by the same
    operations whatever the others; the BLAS may still round a row by the rows around it); one
    plant, or one per scenario.  The comparison sees a scenario out of place."""
    sc = _scenarios(37, perturb)
    kw = dict(t_final=0.06, dt=dt, trajectories=True, segment_steps=120, kernel=kernel)
    one = simulate_batch(zb, sc, **kw)
    monkeypatch.setattr(batch, "CHUNK", 10)
    monkeypatch.setattr(batch, "MIN_CHUNK", 8)
    sizes = []
    run_chunk = batch._Run.chunk
    monkeypatch.setattr(batch._Run, "chunk", lambda self, s, *a: sizes.append(len(s)) or run_chunk(self, s, *a))
    cut = simulate_batch(zb, sc, **kw)
    assert sizes == [10, 9, 9, 9]
    _assert_agree(one, cut)
    swapped = dataclasses.replace(cut, x=cut.x[[1, 0] + list(range(2, 37))])
    with pytest.raises(AssertionError, match="x"):
        _assert_agree(one, swapped)


@needs_numba
def test_chunked_injection_observer_agrees_with_one_chunk(monkeypatch):
    """An observer with Levant differentiators stepped by the compiled loop (implicit chain equations):
    K = 52 in two chunks of 26, and K = 9 in chunks of ≤ 4, against one chunk (in Python it is never
    cut: test_python_injection_steps_are_one_chunk)."""
    nf = design_normal_form(paper000.aircraft(), ["0.02"], gains=paper000.GAINS_89)
    rng = np.random.default_rng(3)
    def w(a):
        return lambda t: 0.008 + a * np.sin(2 * t)

    sc = [Scenario(x0=np.array(paper000.X0) * rng.uniform(0.5, 1.5), w=w(rng.uniform(0, 0.01))) for _ in range(52)]
    kw = dict(t_final=0.005, dt=1e-4, trajectories=True, discretisation="implicit", kernel="numba")
    sizes = []
    run_chunk = batch._Run.chunk
    monkeypatch.setattr(batch._Run, "chunk", lambda self, s, *a: sizes.append(len(s)) or run_chunk(self, s, *a))
    for K, chunk, low, cut in ((52, 26, batch.MIN_CHUNK, [26, 26]), (9, 4, 1, [3, 3, 3])):
        monkeypatch.setattr(batch, "CHUNK", 1000)
        one = simulate_batch(nf, sc[:K], **kw)
        monkeypatch.setattr(batch, "CHUNK", chunk)
        monkeypatch.setattr(batch, "MIN_CHUNK", low)
        sizes.clear()
        _assert_agree(one, simulate_batch(nf, sc[:K], **kw))
        assert sizes == cut


@pytest.mark.parametrize("kernel", KERNELS)
def test_chunks_on_threads_agree_with_one_thread(zb, kernel, monkeypatch):
    """UIO_RING_THREADS=2: the chunks run on two threads of a pool (recorded), results in scenario
    order, the same numbers as one thread to rounding."""
    if (os.cpu_count() or 1) < 2:
        pytest.skip("one core: no second thread")
    sc = _scenarios(50)
    kw = dict(t_final=0.06, dt=1e-3, trajectories=True, segment_steps=120, kernel=kernel)
    monkeypatch.setenv(THREADS_ENV, "1")
    one = simulate_batch(zb, sc, **kw)
    monkeypatch.setenv(THREADS_ENV, "2")
    seen = []
    run_chunk = batch._Run.chunk
    monkeypatch.setattr(batch._Run, "chunk",
                        lambda self, s, *a: seen.append((len(s), threading.get_ident())) or run_chunk(self, s, *a))
    two = simulate_batch(zb, sc, **kw)
    assert sorted(n for n, _ in seen) == [25, 25]
    assert all(t != threading.main_thread().ident for _, t in seen)
    _assert_agree(one, two)


def test_python_injection_steps_are_one_chunk(monkeypatch):
    """An injection term stepped in Python shares its per-step overhead among all K rows: one chunk."""
    nf = design_normal_form(paper000.aircraft(), ["0.02"], gains=paper000.GAINS_89)
    monkeypatch.setattr(batch, "CHUNK", 4)
    monkeypatch.setattr(batch, "MIN_CHUNK", 1)
    sizes = []
    run_chunk = batch._Run.chunk
    monkeypatch.setattr(batch._Run, "chunk", lambda self, s, *a: sizes.append(len(s)) or run_chunk(self, s, *a))
    sc = [Scenario(x0=np.array(paper000.X0) * (1 + 0.1 * k)) for k in range(9)]
    simulate_batch(nf, sc, t_final=0.002, dt=1e-4, kernel="python")
    assert sizes == [9]


def test_no_chunks_with_on_segment_or_feedback(zb, monkeypatch):
    """on_segment sees segments of all K scenarios (one chunk), as before."""
    monkeypatch.setattr(batch, "CHUNK", 3)  # without on_segment: chunks of 3 and 2
    monkeypatch.setattr(batch, "MIN_CHUNK", 2)
    widths = []
    sc = _scenarios(5)
    res = simulate_batch(zb, sc, t_final=0.03, dt=1e-3, on_segment=lambda s: widths.append(s.x.shape[1]))
    assert widths and set(widths) == {5}
    _assert_agree(res, simulate_batch(zb, sc, t_final=0.03, dt=1e-3))


def test_batch_threads_reads_the_environment(monkeypatch):
    monkeypatch.setenv(THREADS_ENV, "64")
    assert batch_threads() == min(64, os.cpu_count() or 1)
    for bad in ("0", "two", "-1"):
        monkeypatch.setenv(THREADS_ENV, bad)
        with pytest.raises(SimulationError, match="UIO_RING_THREADS"):
            batch_threads()
