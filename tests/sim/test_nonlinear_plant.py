"""The nonlinear delay-free plant x' = A x + B w + E u + φ(t, x) (uio_ring.sim.nonlinear)."""

from __future__ import annotations

import numpy as np
import pytest

from uio_ring import DelaySystem
from uio_ring.errors import DimensionError, SimulationError
from uio_ring.sim.nonlinear import simulate_nonlinear


def test_cubic_decay_is_fourth_order():
    sys = DelaySystem("[[0]]", [], "[[2]]", None)
    errs = []
    for dt in (0.05, 0.025):
        res = simulate_nonlinear(sys, lambda t, x: -(x**3), t_final=2.0, dt=dt, x0=[1.0])
        exact = 1 / np.sqrt(1 + 2 * res.t)
        errs.append(np.max(np.abs(res.x[0] - exact)))
        assert np.allclose(res.y[0], 2 * res.x[0])
    assert errs[0] / errs[1] > 8  # → 2⁴ = 16


def test_linear_part_inputs_and_time_dependence():
    # x' = -x + u + sin(t) with u = 1: x = 1 + (sin t − cos t)/2 + c e^{−t}
    sys = DelaySystem("[[-1]]", [], "[[1]]", None, E="[[1]]")
    res = simulate_nonlinear(sys, lambda t, x: np.array([np.sin(t)]), t_final=3.0, dt=1e-2, u=lambda t: np.ones_like(t),
                             x0=[0.5])
    t = res.t
    exact = 1 + (np.sin(t) - np.cos(t)) / 2 + 0.0 * np.exp(-t)
    assert np.max(np.abs(res.x[0] - exact)) < 1e-5


@pytest.mark.parametrize("sys, phi, kw, err, match", [
    (DelaySystem("[[d]]", [], "[[1]]", None), lambda t, x: x, {}, SimulationError, "delay-free"),
    (DelaySystem("[[0]]", [], "[[1]]", None), lambda t, x: [x[0], x[0]], {}, DimensionError, "shape"),
    (DelaySystem("[[0]]", [], "[[1]]", None), lambda t, x: x, {"x0": [1.0, 2.0]}, DimensionError, "x0"),
    (DelaySystem("[[0]]", [], "[[1]]", None), lambda t, x: np.inf * x, {"x0": [1.0]}, SimulationError, "finite"),
])
def test_errors(sys, phi, kw, err, match):
    with pytest.raises(err, match=match):
        simulate_nonlinear(sys, phi, t_final=0.1, dt=0.01, **kw)
