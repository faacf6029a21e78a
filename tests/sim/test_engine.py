"""The one engine: known inputs end to end, collision-free result columns, one protocol.

Known inputs: the error dynamics of the Zheng–Bejarano observer with J_u, H_u are
e' = L0 e whatever u is, so the error trajectory with and without a known input must
agree to integration accuracy.  The input is u(t) = sin 3t switched on at t = 0 (zero
before, as for sampled inputs), so plant and observer see the same u history.
"""

from __future__ import annotations

import numpy as np
import pytest
from design import paper001

from uio_ring import DelaySystem, design_normal_form, design_zheng_bejarano
from uio_ring.sim import SimulationResult, simulate_observer

from .conftest import paper_w

X0 = [1.0, 0.0, -1.0, 0.5]


def u_sin(t):
    t = np.asarray(t, dtype=float)
    return np.where(t >= 0, np.sin(3 * t), 0.0)[None, :]


def _with_u(sys: DelaySystem, E: str, F: str) -> DelaySystem:
    return DelaySystem(sys.A, sys.B, sys.C, sys.D, E=E, F=F, h=sys.h)


def _error_independent_of_u(sys: DelaySystem, w, *, poles=None, dt=1e-3, t_final=2.0, x0=X0):
    design = design_zheng_bejarano(sys, poles=poles)
    assert design.certificate().ok
    assert not design.J_u.is_zero() or not design.H_u.is_zero()  # the known input is really used
    runs = [simulate_observer(design, t_final=t_final, dt=dt, w=w, u=u, x0=x0) for u in (None, u_sin)]
    scale = np.abs(runs[0].error).max()
    moved = np.abs(runs[1].x - runs[0].x).max()
    diff = np.abs(runs[1].error - runs[0].error).max()
    return design, runs, scale, moved, diff


def test_known_input_does_not_change_the_error_paper001():
    sys = _with_u(paper001.system(), E="[[0], [1], [d], [0]]", F="[[1], [0], [1 + d]]")
    design, runs, scale, moved, diff = _error_independent_of_u(sys, paper_w, poles=[-10, -25, -50])
    assert moved > 0.05  # u moves the plant
    assert np.abs(runs[1].u).max() > 0.9 and runs[1].known_input_names == ("u[0]",)
    assert diff <= 1e-5 * scale, (diff, scale)  # measured 5.1e-6 of 6.7 (at t ≈ 2h, start-up)
    # and the error still converges at the slowest pole
    late = runs[1].t >= 1.5
    assert runs[1].error_norm()[late].max() < 1e-4


def test_known_input_does_not_change_the_error_holdout():
    """A hold-out built the same way: another delay system (state delay, delayed output and
    input maps) with a known input through E(δ) and F(δ)."""
    sys = DelaySystem(
        "[[-1, d, 0], [0, 0, 1], [1, -d, -2]]", "[[1], [0], [0]]", "[[1, 0, 0], [0, 1, 0], [0, 0, d + 1]]",
        "[[0], [0], [0]]", E="[[d], [0], [1]]", F="[[0], [1], [2 - d]]", h="1/20",
    )
    w = lambda t: np.array([np.cos(5 * np.asarray(t)) + 0.3])  # noqa: E731
    design, runs, scale, moved, diff = _error_independent_of_u(sys, w, dt=1e-3, x0=[1.0, -1.0, 0.5])
    assert moved > 0.05
    assert diff <= 1e-5 * scale, (diff, scale)


def test_error_with_known_input_is_integration_error():
    """Halving dt shrinks the u-dependence of the error at order ≥ 2.5 (ratio ≥ 6; measured
    7.6–7.9 from dt = 2e-3 to 2.5e-4): it is integration error, not a modelling error."""
    sys = _with_u(paper001.system(), E="[[0], [1], [d], [0]]", F="[[1], [0], [1 + d]]")
    diffs = [_error_independent_of_u(sys, paper_w, poles=[-10, -25, -50], dt=dt, t_final=0.5)[4]
             for dt in (2e-3, 1e-3)]
    assert diffs[1] <= diffs[0] / 6, diffs


def test_normal_form_error_independent_of_u():
    """The normal-form observer on the same engine: u through E changes the plant, not the error.

    The sliding-mode residual (≈ 2e-3 at dt = 1e-3) is the same with and without u to 0.2 %
    (measured 3.3e-6; 2.6e-7 at dt = 5e-4): what differs is integration error."""
    sys = DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None, E="[[1], [0]]")
    des = design_normal_form(sys, [1])
    w = lambda t: np.sin(np.asarray(t))  # noqa: E731
    runs = [simulate_observer(des, t_final=3.0, dt=1e-3, w=w, u=u, x0=[1.0, 0.0]) for u in (None, u_sin)]
    assert np.abs(runs[1].x - runs[0].x).max() > 0.1
    late = runs[0].t >= 2.0
    residual = np.abs(runs[0].error[:, late]).max()
    assert 0 < residual < 1e-2
    assert np.abs(runs[1].error - runs[0].error)[:, late].max() < 1e-2 * residual


# ------------------------------------------------------------------------- result columns
def _result(states, outputs):
    T = 3
    return SimulationResult(
        t=np.arange(T, dtype=float), x=np.ones((len(states), T)), y=2 * np.ones((len(outputs), T)),
        w=np.zeros((1, T)), u=np.zeros((0, T)), h=1.0, dt=1.0, state_names=states, output_names=outputs,
        unknown_input_names=("t",), x_hat=3 * np.ones((len(states), T)), error=-2 * np.ones((len(states), T)),
        w_hat=np.full((1, T), 7.0),
    )


@pytest.mark.parametrize(
    "states, outputs",
    [(("p", "v"), ("p", "v")), (("t", "x"), ("x_hat", "error_p")), (("w",), ("t",))],
)
def test_columns_never_collide(states, outputs):
    r = _result(states, outputs)
    cols = r.columns()
    n = 1 + 3 * len(states) + len(outputs) + 2  # t; x, x_hat, error per state; y; w, w_hat
    assert len(cols) == n  # nothing replaced
    for s in states:
        assert np.all(cols[f"x.{s}"] == 1.0) and np.all(cols[f"x_hat.{s}"] == 3.0)
    for o in outputs:
        assert np.all(cols[f"y.{o}"] == 2.0)  # the measurement is not taken for a state
    assert np.all(cols["t"] == np.arange(3.0)) and np.all(cols["w.t"] == 0.0) and np.all(cols["w_hat.t"] == 7.0)


def test_to_pandas_has_the_same_columns():
    pd = pytest.importorskip("pandas")
    r = _result(("p", "v"), ("p", "v"))
    df = r.to_pandas()
    assert isinstance(df, pd.DataFrame) and df.index.name == "t"
    assert list(df.columns) == list(r.columns())[1:]
    assert (df["y.p"] == 2.0).all() and (df["x.p"] == 1.0).all()


def test_w_hat_reaches_the_result():
    sys = DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None)
    des = design_normal_form(sys, ["1/2"], reconstruct_input=True)
    r = simulate_observer(des, t_final=6.0, dt=1e-3, w=lambda t: 0.2 * np.sin(np.asarray(t)), x0=[1.0, 0.0])
    assert r.w_hat is not None and r.w_hat.shape == r.w.shape
    assert np.abs(r.w - r.w_hat)[:, r.t >= 4.0].max() < 1e-2
    assert "w_hat.w[0]" in r.columns()
