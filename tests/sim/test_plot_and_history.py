"""History buffer, scan kernel, plotting, and the lightness of ``import uio_ring``."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

from uio_ring.numeric.expint import LinearScan, stencil_weights
from uio_ring.sim import HistoryBuffer, SimulationError, simulate, simulate_observer
from uio_ring.sim.errors import DimensionError

from .conftest import paper_w


def test_history_lookup_is_exact_and_wraps():
    buf = HistoryBuffer(2, h=0.5, dt=0.125, max_delay=2, phi=lambda t: np.array([t, 2 * t]))
    assert buf.capacity == 2 * 4 + 1
    assert np.array_equal(buf.lookup(2), [-1.0, -2.0]) and np.array_equal(buf.lookup(0), [0.0, 0.0])
    for k in range(1, 30):  # many wraps of the ring
        buf.push([k * 0.125, k * 0.25])
        assert buf.lookup(1) == pytest.approx([k * 0.125 - 0.5, k * 0.25 - 1.0])
        assert buf.lookup(2) == pytest.approx([k * 0.125 - 1.0, k * 0.25 - 2.0])
    assert buf.t_now == pytest.approx(29 * 0.125)
    assert buf.window(3)[:, 0] == pytest.approx([27 * 0.125, 28 * 0.125, 29 * 0.125])


@pytest.mark.parametrize(
    "phi", [np.array([1.0, 2.0]), lambda t: np.array([1.0, 2.0]), np.tile([[1.0], [2.0]], (1, 5))]
)
def test_history_forms(phi):
    buf = HistoryBuffer(2, h=1.0, dt=0.25, max_delay=1, phi=phi)
    assert np.array_equal(buf.window(5), np.tile([1.0, 2.0], (5, 1)))


def test_history_errors():
    with pytest.raises(DimensionError, match=r"phi has shape \(2, 4\); expected .*\(2, 5\)"):
        HistoryBuffer(2, h=1.0, dt=0.25, max_delay=1, phi=np.zeros((2, 4)))
    with pytest.raises(SimulationError, match="dt=0.3 is not h/N"):
        HistoryBuffer(2, h=1.0, dt=0.3, max_delay=1)
    buf = HistoryBuffer(1, h=1.0, dt=0.5, max_delay=1)
    with pytest.raises(SimulationError, match="reaches 4 samples back; the buffer holds 3"):
        buf.lookup(2)
    with pytest.raises(DimensionError, match=r"sample has shape"):
        buf.push([1.0, 2.0])


def test_linear_scan_matches_the_loop():
    rng = np.random.default_rng(0)
    Phi = np.eye(3) * 0.9 + 0.05 * rng.standard_normal((3, 3))
    g = rng.standard_normal((1000, 3))
    x = rng.standard_normal(3)
    ref = np.empty_like(g)
    for j in range(len(g)):
        x_prev = x if j == 0 else ref[j - 1]
        ref[j] = Phi @ x_prev + g[j]
    for chunk in (4, 16, 64):
        assert np.allclose(LinearScan(Phi, chunk=chunk).run(x, g), ref, rtol=1e-12, atol=1e-12)


def test_stencil_weights_integrate_cubics_exactly():
    """∫_0^dt e^{A(dt−s)} p(s) ds for cubic p: the weights reproduce the exact integral."""
    from scipy.integrate import quad_vec
    from scipy.linalg import expm

    A = np.array([[-1.0, 2.0], [0.0, -3.0]])
    dt = 0.1
    p = lambda s: np.array([1 + s - 3 * s**3, 2 * s**2])  # noqa: E731
    nodes = (-2, -1, 0, 1)
    W = stencil_weights(A * dt, dt, nodes)
    approx = sum(W[m] @ p(q * dt) for m, q in enumerate(nodes))
    exact = quad_vec(lambda s: expm(A * (dt - s)) @ p(s), 0, dt, epsabs=1e-15)[0]
    assert np.allclose(approx, exact, rtol=1e-12, atol=1e-15)


def test_plot_observer_and_plant(paper_design):
    pytest.importorskip("matplotlib")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    r = simulate_observer(paper_design, h=0.01, t_final=0.2, dt=0.001, w=paper_w, x0=[1, 0, 0, 0])
    fig = r.plot(figsize=(6, 4))
    ax_x, ax_w, ax_err = fig.axes
    # 4 states + 4 estimates + 2 style keys; w1, w2 (not reconstructed); 4 errors + the lag line
    assert len(ax_x.lines) == 10 and len(ax_w.lines) == 2
    assert ax_err.get_yscale() == "log" and len(ax_err.lines) == 5
    lo, hi = ax_err.get_ylim()
    assert hi / lo <= 10.0 ** 13  # limited to the meaningful range
    p = simulate(paper_design.system, h=0.01, t_final=0.2, dt=0.001, w=paper_w).plot()
    assert len(p.axes[1].lines) == 3
    plt.close("all")


def test_import_uio_ring_stays_light():
    code = "import sys, uio_ring, uio_ring.plot; print('numpy' in sys.modules, 'matplotlib' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["False", "False"]


def test_progress_bar_shows_the_time_left(monkeypatch, capsys):
    """The bar's estimate of the time left, on a controlled clock (a real run may be too fast to show one)."""
    from uio_ring.numeric import progress as pr

    clock = iter([0.0, 0.0, 1.0, 2.0, 3.0])
    monkeypatch.setattr(pr.time, "perf_counter", lambda: next(clock))
    with pr.Progress(100, enabled=True) as p:
        p.update(25)  # 1 s for a quarter: 3 s left
    err = capsys.readouterr().err
    assert "25.0%" in err and "3.0s left" in err and "100.0%" in err


def test_progress_bar_on_request(paper_design, capsys):
    """Off by default in tests; ``progress=True`` draws a bar on stderr."""
    simulate(paper_design.system, h=0.01, t_final=0.2, dt=0.001, progress=True)
    err = capsys.readouterr().err
    assert "plant: [" in err and "100.0%" in err
    # one bar for a whole observer run, plant and observer (here the loop of a differentiator)
    from uio_ring import DelaySystem, design_normal_form, simulate_observer

    des = design_normal_form(DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None), [1])
    simulate_observer(des, t_final=3.0, dt=1e-4, x0=[1, 0], progress=True)
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "simulate: [" in err and "100.0%" in err
    from uio_ring.numeric.progress import want_progress

    assert want_progress(None, 10**9) is False  # PYTEST_CURRENT_TEST is set


def test_to_pandas_or_a_clear_missing_dependency(paper_design):
    from uio_ring.errors import MissingDependencyError

    r = simulate_observer(paper_design, h=0.01, t_final=0.02, dt=0.001, w=paper_w)
    try:
        import pandas  # noqa: F401
    except ImportError:
        with pytest.raises(MissingDependencyError, match="pandas"):
            r.to_pandas()
    else:
        df = r.to_pandas()
        assert list(df.columns[:2]) == ["x.x[0]", "x.x[1]"] and "error.x[3]" in df.columns and len(df) == 21


def test_result_repr_and_labels(paper_design):
    r = simulate_observer(paper_design, h=0.01, t_final=0.02, dt=0.001, w=paper_w)
    assert "plant+observer" in repr(r) and r.errors["x[2]"].shape == (21,)
    with pytest.raises(KeyError, match="no such signal"):
        r.states["z"]
    assert np.array_equal(np.asarray(r.estimates), r.x_hat)
