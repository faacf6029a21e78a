"""simulate_batch(feedback=…): K closed loops in lockstep, the numbers of K closed-loop runs of
simulate_observer (the same feedback law, one row per scenario)."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from design import paper000, paper001

from uio_ring import design_normal_form, design_zheng_bejarano, simulate_observer
from uio_ring.errors import NotSupportedError, SimulationError
from uio_ring.sim.batch import Scenario, simulate_batch

GAIN = np.array([[float(Fraction(x)) for x in r] for r in paper000.K_97])
H = np.array([1.0, 0.0])  # D = B h: the reconstructed rudder fault enters u as in paper 000 (96)


@pytest.fixture(scope="module")
def sim2():
    return design_normal_form(paper000.aircraft(), ["0.046"], reconstruct_input=True, gains=paper000.GAINS_95)


def law(t, x_hat, w_hat):
    """u = −[K h] χ̂ for the K rows at once (K, 7) → (K, 2)."""
    return -x_hat @ GAIN.T - w_hat[:, :1] * H + 0.01 * np.sin(5 * t)


def one(t, x_hat, w_hat):  # the same law for one run of simulate_observer
    return law(t, x_hat[None], w_hat[None])[0]


@pytest.mark.parametrize("disc, scalar_below", [("implicit", 100), ("implicit", 0), ("explicit", 0), ("euler", 0)])
def test_closed_loop_batch_equals_separate_runs(sim2, disc, scalar_below, monkeypatch):
    import uio_ring.sim.batch as batch

    monkeypatch.setattr(batch, "SCALAR_CHAINS_BELOW", scalar_below)  # the injection's scalar / vectorised solver
    w = [lambda t, a=a: 0.01 + a * np.sin(2 * t) for a in (0.0, 0.01, 0.005)]
    sc = [Scenario(x0=np.array(paper000.X0) * f, w=w[k], noise=0.001 if k == 1 else None, seed=4,
                   x_hat0=np.zeros(8) if k == 2 else None) for k, f in enumerate((1.0, 0.5, 1.5))]
    res = simulate_batch(sim2, sc, t_final=0.06, dt=2e-4, feedback=law, trajectories=True, segment_steps=70,
                         discretisation=disc)
    assert res.x.shape == (3, 7, 301)
    for k, s in enumerate(sc):
        r = simulate_observer(sim2, t_final=0.06, dt=2e-4, w=s.w, x0=s.x0, noise=s.noise, seed=s.seed,
                              x_hat0=s.x_hat0, feedback=one, discretisation=disc)
        scale = max(np.max(np.abs(r.x)), 1.0)
        for name in ("x", "y", "x_hat", "w_hat"):
            dev = np.max(np.abs(getattr(r, name) - getattr(res, name)[k]))
            assert dev <= 1e-10 * scale, (k, name, dev)
        e = np.max(np.abs(r.error), axis=0)
        assert res.metrics["peak"][k] == pytest.approx(e.max(), rel=1e-9)
        assert res.metrics["final"][k] == pytest.approx(e[-1], rel=1e-9)


def test_closed_loop_segments_carry_u(sim2):
    """on_segment sees the inputs the law produced: u(t_j) = law(t_j, x̂(t_j), ŵ(t_j)), held at the end."""
    seen = []
    simulate_batch(sim2, [Scenario(x0=paper000.X0), Scenario()], t_final=0.01, dt=1e-3, feedback=law,
                   on_segment=seen.append, segment_steps=4)
    t = np.concatenate([s.t for s in seen])
    u = np.concatenate([s.u for s in seen])
    xh = np.concatenate([s.x_hat for s in seen])
    wh = np.concatenate([s.w_hat for s in seen])
    assert np.allclose(t, np.arange(11) * 1e-3)
    for j in range(10):
        assert np.allclose(u[j], law(t[j], xh[j], wh[j]), rtol=1e-14, atol=0)
    assert np.array_equal(u[10], u[9])


def test_closed_loop_refusals(sim2):
    with pytest.raises(SimulationError, match="u or feedback"):
        simulate_batch(sim2, [Scenario(u=[0.0, 0.0])], t_final=0.01, dt=1e-3, feedback=law)
    with pytest.raises(SimulationError, match="exact_start is for open-loop"):
        simulate_batch(sim2, [Scenario()], t_final=0.01, dt=1e-3, feedback=law, exact_start=True)
    with pytest.raises(SimulationError, match=r"expected \(2, 2\) finite values"):
        simulate_batch(sim2, [Scenario(), Scenario()], t_final=0.01, dt=1e-3, feedback=lambda t, x, w: np.zeros(2))
    zb = design_zheng_bejarano(paper001.system(), poles=[-10, -25, -50])
    with pytest.raises((NotSupportedError, SimulationError), match="delay-free plants|no known input"):
        simulate_batch(zb, [Scenario()], t_final=0.01, dt=1e-3, feedback=lambda t, x, w: np.zeros((1, 0)))
