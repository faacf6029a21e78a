"""The scenario-innermost compiled loops (uio_ring.numeric.scenario_kernel) against plain numpy sums,
and the batch's linear-observer path built on them (uio_ring.sim.batch_linear) against the numpy path."""

from __future__ import annotations

import importlib.util
import sys

import numpy as np
import pytest
from design import paper001

from uio_ring import design_zheng_bejarano
from uio_ring.sim.batch import METRICS, Scenario, simulate_batch

needs_numba = pytest.mark.skipif(importlib.util.find_spec("numba") is None,
                                 reason="numba is not installed (pip install 'uio-ring[fast]')")


def _stack(rng, m, c, r, density):
    """A random tap stack (m, c, r) with whole zero rows (skipped taps) and scattered zeros."""
    M = rng.normal(size=(m, c, r)) * (rng.random((m, c, r)) < density)
    M[rng.random((m, c)) < 0.3] = 0.0
    return M


def _reference_taps(S, starts, M, L):
    """``out[l, :, k] = Σ_i M[i]ᵀ S[starts[i] + l, :, k]`` by numpy, tap by tap."""
    out = np.zeros((L, M.shape[2], S.shape[2]))
    for i, s in enumerate(starts):
        out += np.einsum("cr,lck->lrk", M[i], S[s : s + L])
    return out


@needs_numba
@pytest.mark.parametrize("r", [1, 3, 4, 6])
@pytest.mark.parametrize("K", [1, 7, 37])
def test_tap_sum_k_equals_numpy(r, K):
    from uio_ring.numeric.scenario_kernel import tap_pairs, tap_sum_k

    rng = np.random.default_rng(10 * r + K)
    m, c, L = 4, 3, 23
    M = _stack(rng, m, c, r, 0.7)
    S = rng.normal(size=(L + 30, c, K))
    starts = np.array([30, 20, 10, 0])
    out = tap_sum_k(S, starts, tap_pairs(M), np.full((L, r, K), np.nan))
    ref = _reference_taps(S, starts, M, L)
    assert np.max(np.abs(out - ref)) <= 1e-12 * max(np.max(np.abs(ref)), 1.0)
    base = rng.normal(size=(L, r, K))
    acc = tap_sum_k(S, starts, tap_pairs(M), base.copy(), accumulate=True)  # added in the same pass
    assert np.max(np.abs(acc - (base + ref))) <= 1e-12 * max(np.max(np.abs(ref)), 1.0)


@needs_numba
def test_tap_sum_k_of_an_all_zero_stack_is_zero():
    from uio_ring.numeric.scenario_kernel import tap_pairs, tap_sum_k

    out = tap_sum_k(np.ones((5, 2, 9)), np.array([0, 1]), tap_pairs(np.zeros((2, 2, 3))), np.full((4, 3, 9), np.nan))
    assert np.array_equal(out, np.zeros((4, 3, 9)))


@needs_numba
@pytest.mark.parametrize("n, K", [(1, 5), (2, 16), (6, 40), (5, 33)])
def test_stencil_scan_k_equals_the_recursion(n, K):
    """``x_{s+1} = Φ x_s + Σ_m W_m g(s + m)``: the fused pass against forcing and steps in numpy."""
    from uio_ring.numeric.scenario_kernel import stencil_scan_k, tap_pairs

    rng = np.random.default_rng(n * K)
    L = 50
    W = _stack(rng, 4, n, n, 0.8)
    Phi = rng.normal(size=(n, n)) * (0.5 / np.sqrt(n)) * (rng.random((n, n)) < 0.6)
    G = rng.normal(size=(L + 3, n, K))
    x0 = rng.normal(size=(n, K))
    out = stencil_scan_k(G, np.arange(4), tap_pairs(W), Phi.T, x0, np.empty((L, n, K)))
    F = _reference_taps(G, np.arange(4), W, L)
    x, ref = x0, np.empty_like(out)
    for s in range(L):
        x = Phi @ x + F[s]
        ref[s] = x
    assert np.max(np.abs(out - ref)) <= 1e-12 * np.max(np.abs(ref))


def _w(a):
    return lambda t: np.array([a * np.sin(40 * np.asarray(t, float)), 20 * np.cos(20 * np.asarray(t, float))])


def _batch(zb, kernel, **kw):
    rng = np.random.default_rng(7)
    exact = kw.get("exact_start", False)
    sc = [Scenario(x0=rng.normal(size=4), w=_w(rng.uniform(1, 3)), x_hat0=rng.normal(size=4) if k % 2 and not exact
                   else None, noise=0.01 if k == 3 else None, seed=k) for k in range(12)]
    return simulate_batch(zb, sc, t_final=0.2, dt=2.5e-4, trajectories=True, kernel=kernel, **kw)


@needs_numba
@pytest.mark.parametrize("kw", [{"segment_steps": 300}, {"segment_steps": 30}, {"exact_start": True, "segment_steps": 300}])
def test_linear_observer_scenario_innermost_equals_numpy(kw, monkeypatch):
    """Paper 001 (N = 40: 240 guarded start steps) with the observer's segments scenario-innermost
    (guarded start blocks, then the fused stencil and steps; segments shorter than a delay block;
    exact start): x, y, x̂ within 1e-12 of the
    numpy path, the same convergence times; and the path is taken (its segment is called)."""
    import uio_ring.sim.batch_linear as bl

    zb = design_zheng_bejarano(paper001.system(), poles=[-10, -25, -50])
    seen = []
    seg = bl.LinearObserverK.segment
    monkeypatch.setattr(bl.LinearObserverK, "segment", lambda self, *a: seen.append(a[0]) or seg(self, *a))
    ref = _batch(zb, "python", **kw)
    assert not seen
    res = _batch(zb, "numba", **kw)
    assert len(seen) >= 2
    for name in ("x", "y", "x_hat"):
        a, b = getattr(res, name), getattr(ref, name)
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b)), name
    assert np.array_equal(res.metrics["t_converge"], ref.metrics["t_converge"], equal_nan=True)
    # |x − x̂| differs by at most the trajectories' difference, asserted above on their scale; with an
    # exact start the settled errors are that rounding itself (≈ 5e-11), so atol is on that scale too
    scale = max(np.max(np.abs(ref.x)), np.max(np.abs(ref.x_hat)))
    for name in METRICS:
        assert np.allclose(res.metrics[name], ref.metrics[name], rtol=1e-9, atol=1e-12 * scale, equal_nan=True), name


def test_without_numba_the_numpy_path_runs(monkeypatch):
    """numba hidden: kernel="auto" runs the numpy path (no scenario-innermost segment) and gives
    the numbers of kernel="python"."""
    import uio_ring.sim.batch_linear as bl

    zb = design_zheng_bejarano(paper001.system(), poles=[-10, -25, -50])
    ref = _batch(zb, "python")
    monkeypatch.setitem(sys.modules, "numba", None)  # import numba now raises ImportError
    monkeypatch.delenv("UIO_RING_KERNEL", raising=False)
    monkeypatch.setattr(bl.LinearObserverK, "segment", None)  # would fail if called
    res = _batch(zb, "auto")
    assert np.array_equal(res.x_hat, ref.x_hat)


@needs_numba
def test_compiled_metrics_equal_numpy_metrics():
    """The compiled one-pass metrics (uio_ring.numeric.metrics_kernel) against _Metrics.update on the
    same errors, across segments: converging, diverging (inf, NaN) and oscillating runs, a settle
    time inside a segment; indices and maxima exactly, sums of squares to rounding."""
    from uio_ring.sim.batch import _Metrics

    rng = np.random.default_rng(4)
    K, n, T = 6, 3, 230
    t = np.arange(T)[:, None, None] * 0.01
    X = rng.normal(size=(T, K, n)) * np.exp(-t * np.array([1, 5, 20, 0.0, -3, 10])[None, :, None])
    X[100:, 4, 1] = np.inf  # diverges at sample 100
    X[150, 5, 0] = np.nan  # one NaN, then recovers
    X[:, 3] = 0.5 * np.sin(7 * t[:, :, 0])  # oscillates around tol
    xh = np.zeros_like(X)
    a, b = (_Metrics(K, 0.01, 0.05, 1e3, 0.9, kernel=k) for k in ("python", "numba"))
    for lo, hi in ((0, 70), (70, 71), (71, 160), (160, T)):
        a.update_xy(lo, X[lo:hi], xh[lo:hi])
        b.update_xy(lo, X[lo:hi], xh[lo:hi])
    ra, rb = a.result(T - 1), b.result(T - 1)
    for name in METRICS:
        exact = name not in ("rms_after", "rms_settled")
        if exact:
            assert np.array_equal(ra[name], rb[name], equal_nan=True), name
        else:
            assert np.allclose(ra[name], rb[name], rtol=1e-13, atol=0, equal_nan=True), name
    assert np.isfinite(ra["t_diverge"][4]) and np.isnan(ra["t_diverge"][0])


@needs_numba
@pytest.mark.parametrize("delays, N", [(0, 17), (1, 20), (2, 33)])
def test_plant_blocks_scenario_innermost_equal_run_rows(delays, N):
    """run_blocks_k (the plant's blocks scenario-innermost) against BlockIntegrator.run_rows (numpy):
    delayed states, input forcing and left limits at the block ends (end_fix), to 1e-12."""
    from uio_ring.sim._blocks import BlockIntegrator
    from uio_ring.sim.batch_plant_k import run_blocks_k

    rng = np.random.default_rng(N)
    n, K, nb = 3, 11, 3
    A = rng.normal(size=(delays + 1, n, n))
    A[0] -= 2 * np.eye(n)
    integ = BlockIntegrator(A, N, 0.3 / N)
    X = rng.normal(size=(delays * N + nb * N + 1, K, n))
    fin, fix = rng.normal(size=(nb * N + 1, K, n)), rng.normal(size=(K, nb, n))
    XT = np.ascontiguousarray(X.transpose(0, 2, 1))
    integ.run_rows(X, fin, nb, end_fix=fix)
    run_blocks_k(integ, XT, np.ascontiguousarray(fin.transpose(0, 2, 1)), nb, end_fix=fix)
    assert np.max(np.abs(XT.transpose(0, 2, 1) - X)) <= 1e-12 * np.max(np.abs(X))


def test_generated_loops_are_written_once_per_source(tmp_path, monkeypatch):
    """The loops' source modules live in $UIO_RING_KERNEL_DIR, one file per source text (named by its
    hash), never rewritten (a rewrite would invalidate numba's cache of it); the text is the generator's."""
    import uio_ring.numeric.scenario_kernel as sk

    monkeypatch.setenv(sk.KERNEL_DIR_ENV, str(tmp_path / "k"))
    src = sk._source("tap", 3)
    a = sk._module_path(src, "tap_r3")
    stamp = a.stat().st_mtime_ns
    b = sk._module_path(src, "tap_r3")
    assert a == b and a.parent == tmp_path / "k" and a.read_text() == src and b.stat().st_mtime_ns == stamp
    c = sk._module_path(sk._source("scan", 3), "scan_r3")
    assert c != a and "def loop(S, prow, pcol, W, PhiT, x0, out, k0, k1):" in c.read_text()
    compile(c.read_text(), str(c), "exec")  # valid Python


@needs_numba
def test_generated_loops_without_a_writable_directory(tmp_path, monkeypatch):
    """No directory for the loops' source: compiled in the process (no disk cache), the same sums."""
    import uio_ring.numeric.scenario_kernel as sk

    blocker = tmp_path / "file"
    blocker.write_text("")
    monkeypatch.setenv(sk.KERNEL_DIR_ENV, str(blocker / "k"))  # below a file: mkdir fails
    monkeypatch.setattr(sk, "_compiled", sk._compiled.__wrapped__)  # not the process's compiled loops
    M = np.arange(12.0).reshape(2, 2, 3)
    S = np.random.default_rng(0).normal(size=(6, 2, 5))
    out = sk.tap_sum_k(S, np.array([1, 0]), sk.tap_pairs(M), np.empty((4, 3, 5)))
    assert np.allclose(out, _reference_taps(S, np.array([1, 0]), M, 4), rtol=1e-13, atol=1e-13)
    assert not (blocker / "k").exists()


def test_generated_loops_are_never_imported_from_a_directory_others_may_write(tmp_path, monkeypatch):
    """The source modules are imported: a directory writable by others is refused, and so is a
    file whose text is not the generator's (both make the caller compile in memory)."""
    import uio_ring.numeric.scenario_kernel as sk

    shared = tmp_path / "shared"
    shared.mkdir(mode=0o777)
    shared.chmod(0o777)
    monkeypatch.setenv(sk.KERNEL_DIR_ENV, str(shared))
    src = sk._source("tap", 2)
    with pytest.raises(PermissionError):
        sk._module_path(src, "tap_r2")
    assert not list(shared.iterdir())

    own = tmp_path / "own"
    monkeypatch.setenv(sk.KERNEL_DIR_ENV, str(own))
    path = sk._module_path(src, "tap_r2")
    assert own.stat().st_mode & 0o777 == 0o700
    path.write_text(src + "import os\n")  # planted code under the expected name
    with pytest.raises(PermissionError):
        sk._module_path(src, "tap_r2")


def test_generated_loops_default_to_the_users_cache(monkeypatch, tmp_path):
    import uio_ring.numeric.scenario_kernel as sk

    monkeypatch.delenv(sk.KERNEL_DIR_ENV, raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert sk._kernel_dir() == tmp_path / "uio_ring" / "kernels"
