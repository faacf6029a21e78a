"""The noise kernel stepped in blocks, the refinement that reuses the previous grid, and the
shortcuts of the convergence time, against direct computations."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.linalg import expm

from uio_ring.numeric import performance as perf
from uio_ring.numeric.model import ObserverModel


def _model(seed: int, n_z: int, n_x: int, n_y: int, taps_x: int, taps_g: int) -> ObserverModel:
    rng = np.random.default_rng(seed)
    F = rng.normal(size=(n_z, n_z)) - (np.sqrt(n_z) + 1.0) * np.eye(n_z)  # Hurwitz by Gershgorin-ish margin
    G = rng.normal(size=(taps_g, n_z, n_y))
    X = rng.normal(size=(taps_x, n_x, n_z))
    if taps_g > 1:
        G[1] = 0.0  # a missing tap is skipped
    return ObserverModel(F=F, G_y=G, X=X, h=0.1)


def _direct(model: ObserverModel, step: float, T: int) -> np.ndarray:
    """K[k] = Σ_{(a+b)h ≤ k·step} X_a e^{F (k·step − (a+b)h)} G_b, each term by expm."""
    per = round(model.h / step)
    K = np.zeros((T, model.n_x, model.n_y))
    for k in range(T):
        for a in range(model.X.shape[0]):
            for b in range(model.G_y.shape[0]):
                s = (a + b) * per
                if s <= k:
                    K[k] += model.X[a] @ expm(model.F * ((k - s) * step)) @ model.G_y[b]
    return K


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n_z=st.integers(1, 6), n_x=st.integers(1, 3), n_y=st.integers(1, 3),
       taps_x=st.integers(1, 2), taps_g=st.integers(1, 3), block=st.integers(1, 5), per=st.sampled_from([2, 4]))
def test_blocks_and_the_halved_grid_give_the_kernel(seed, n_z, n_x, n_y, taps_x, taps_g, block, per):
    model = _model(seed, n_z, n_x, n_y, taps_x, taps_g)
    step = 0.1 / per
    T = 4 * per + 3
    old, perf._BLOCK = perf._BLOCK, block  # many blocks on a short grid
    try:
        want = _direct(model, step, T)
        K = perf._kernel_chain(model, step, T)
        coarse = perf._kernel(model, 2 * step, (T + 1) // 2)
        halved = perf._kernel(model, step, T, coarse)
    finally:
        perf._BLOCK = old
    scale = max(1.0, float(np.abs(want).max()))
    assert np.allclose(K, want, rtol=1e-9, atol=1e-9 * scale)
    assert np.allclose(halved, want, rtol=1e-9, atol=1e-9 * scale)
    assert np.array_equal(halved[0::2], coarse[: (T + 1) // 2])  # the even points are the coarse grid's


def test_halved_grid_of_a_delay_free_model():
    model = _model(7, 4, 2, 2, 1, 1)
    model = ObserverModel(F=model.F, G_y=model.G_y, X=model.X)  # no h: no delays
    step, T = 0.01, 23
    coarse = perf._kernel(model, 2 * step, (T + 1) // 2)
    halved = perf._kernel(model, step, T, coarse)
    want = np.stack([model.X[0] @ expm(model.F * (k * step)) @ model.G_y[0] for k in range(T)])
    assert np.allclose(halved, want, rtol=1e-9, atol=1e-12)
    assert np.array_equal(halved[0::2], coarse)


def _last_above_stepped(Phi: np.ndarray, M: int, tolerance: float) -> int:
    E, last = np.eye(Phi.shape[0]), 0
    for m in range(1, M + 1):
        E = Phi @ E
        if np.abs(E).sum(axis=1).max() > tolerance:
            last = m
    return last


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), n=st.integers(1, 5), scale=st.floats(0.05, 1.5),
       M=st.integers(0, 80), tolerance=st.sampled_from([1e-3, 0.1, 0.5, 2.0]))
def test_last_above_is_the_stepped_answer(seed, n, scale, M, tolerance):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    Phi = scale * A / max(1e-12, float(np.max(np.abs(np.linalg.eigvals(A)))))  # spectral radius = scale
    Phi = Phi + np.triu(rng.normal(size=(n, n)), 1)  # non-normal: transient growth
    want = _last_above_stepped(Phi, M, tolerance)
    got = perf._last_above(Phi, M, tolerance)
    if got != want:  # only where a norm sits within rounding of the tolerance
        E = np.linalg.matrix_power(Phi, max(got, want))
        assert abs(np.abs(E).sum(axis=1).max() - tolerance) <= 1e-9 * max(1.0, tolerance)


def test_last_above_does_not_stop_at_a_dip():
    """‖Φ^m‖∞ of a slowly turning, eccentric rotation dips below the tolerance near m = 40
    (a half turn) and rises again: the run of good m must reach 2m₀ before the stepping stops;
    Φ^80 is below the tolerance, so the shortcut at M does not answer."""
    theta, S = np.pi / 40, np.diag([1.0, 10.0])
    R = np.array([[np.cos(theta), -np.sin(theta)], [np.sin(theta), np.cos(theta)]])
    Phi = 0.98 * S @ R @ np.linalg.inv(S)
    want = _last_above_stepped(Phi, 80, 1.0)
    assert 60 < want < 80
    assert perf._last_above(Phi, 80, 1.0) == want
