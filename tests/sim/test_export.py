"""The observer taken into other tools: design files -> ObserverModel -> python-control."""

from __future__ import annotations

import json

import numpy as np
import pytest
from design import paper001

from uio_ring import DelaySystem, PolyMatrix, design_normal_form, design_zheng_bejarano
from uio_ring.errors import DomainError, NotSupportedError
from uio_ring.numeric.model import ObserverModel
from uio_ring.sim import simulate_observer
from uio_ring.spec.designs import load_observer_model, save_design

control = pytest.importorskip("control")


def test_design_file_to_python_control_matches_the_engine(tmp_path):
    """A delay-free linear observer, written to a design file, read back as a float model,
    turned into a python-control StateSpace and simulated there on the same output record:
    the estimates agree with simulate_observer to the accuracy of python-control's
    first-order hold (O(dt²))."""
    sys = paper001.system().at_delta(0)
    design = design_zheng_bejarano(sys, poles=[-2, -3, -4])
    json_path, yaml_path = save_design(design, tmp_path / "zb0", formats=("json", "yaml"))
    assert "numeric_derived" in json.loads(json_path.read_text())
    w = lambda t: np.array([np.sin(t) + 0 * t, 0.5 * np.cos(2 * t) + 0 * t])  # noqa: E731
    res = simulate_observer(design, t_final=4.0, dt=1e-3, w=w, x0=[1.0, -1.0, 0.5, 0.2])
    for path in (json_path, yaml_path):
        model = load_observer_model(path)
        obs = model.to_control()
        assert obs.ninputs == sys.n_y and obs.noutputs == sys.n_x and obs.nstates == design.n_z
        out = control.forced_response(obs, T=res.t, U=res.y, X0=np.zeros(design.n_z))
        x_hat = np.asarray(out.outputs)
        scale = np.abs(res.x_hat).max()
        assert np.abs(x_hat - res.x_hat).max() <= 1e-4 * scale
        # the eigenvalues of the exported observer are the requested poles (each r times)
        assert np.allclose(np.sort(np.linalg.eigvals(obs.A).real), np.repeat([-4.0, -3.0, -2.0], design.r))


def test_model_round_trip_with_delays_and_injection():
    sys = paper001.system()
    m = design_zheng_bejarano(sys, poles=[-10, -25, -50]).numeric(h="1/100")
    back = ObserverModel.from_dict(json.loads(json.dumps(m.to_dict())))
    for name in ("F", "G_y", "G_u", "D_y", "D_u", "X", "initial", "z_of_x"):
        assert np.array_equal(getattr(back, name), getattr(m, name)), name
    assert back.h == m.h == 0.01 and back.lag == m.lag
    with pytest.raises(NotSupportedError, match="delayed taps"):
        m.to_control()
    nf = design_normal_form(DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None), [1]).numeric()
    back = ObserverModel.from_dict(json.loads(json.dumps(nf.to_dict())))
    assert back.injection is not None and back.injection.gains == nf.injection.gains
    with pytest.raises(NotSupportedError, match="nonlinear injection"):
        nf.to_control()


def test_polymatrix_to_numpy_and_array():
    M = PolyMatrix("[[1 + d/2, 3], [0, -d**2]]")
    stack = M.to_numpy()
    assert stack.shape == (3, 2, 2) and stack[1, 0, 0] == 0.5 and stack[2, 1, 1] == -1.0
    assert PolyMatrix.zeros(2, 3).to_numpy().shape == (0, 2, 3)
    assert np.array_equal(np.asarray(PolyMatrix("[[1/4, 2]]")), [[0.25, 2.0]])
    with pytest.raises(DomainError, match="δ-degree 1"):
        np.asarray(PolyMatrix("[[d]]"))


def test_from_control_round_trip_keeps_names():
    g = control.ss([[0, 1], [-2, -3]], [[0, 0], [1, 0.1]], [[1, 0]], [[0, 0]],
                   inputs=["fault", "demand"], outputs=["pos"], states=["p", "v"])
    sys = DelaySystem.from_control(g, unknown_inputs=["fault"], h="1/10")
    assert sys.E == PolyMatrix("[[0], [1/10]]")  # 0.1 read as 1/10, exactly
    assert (sys.state_names, sys.output_names, sys.unknown_input_names, sys.known_input_names) == (
        ("p", "v"), ("pos",), ("fault",), ("demand",))
    back = sys.to_control()
    assert np.allclose(back.A, g.A) and np.allclose(back.B, g.B) and list(back.state_labels) == ["p", "v"]
    assert DelaySystem.from_control(g, unknown_inputs=1).n_w == 1
