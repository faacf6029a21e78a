"""The observer of paper 001 (Theorem 4) on the example of §5.

Figures measured at the time of writing (dt = 1e-3, design of design_zheng_bejarano
with poles −10, −25, −50, lag 3; the paper's printed design has lag 4):

* log-error slope on [0.5, 1.5] s: −10.00 (h = 0.01) and −9.99 (h = 0.1);
* final error at t = 3 s: 2.9e-7 (h = 0.01), 2.6e-7 (h = 0.1), i.e. 2.5e-9 relative to |x|;
  halving dt divides it by 14–17 (order ≈ 4: it is integration error);
* exact start: the error drops from ≥ 1e-2 to ≤ 1e-5 exactly at t = lag·h;
* noise uniform in [−2, 2]: for t ≥ 2 s, |e_noisy − e_clean| ≤ bound = 2 Σ_j ‖impulse
  response‖₁ = (85.6, 2.8, 656, 581) per state; observed 18–29 % of it.  (An earlier bound
  put the impulse at t = 0, where the observer's start-up hold of ẑ turned it into a step:
  (289, 1.8, 6633, 5707), up to 12× too loose.)
"""

from __future__ import annotations

import numpy as np
import pytest

from uio_ring.sim import (
    SimulationError,
    UniformNoise,
    simulate,
    simulate_observer,
)
from uio_ring.sim.errors import DimensionError

from .conftest import paper_phi, paper_w

CONST_PHI = [1.0, 0.0, -1.0, 0.5]


def log_slope(t, e, a, b):
    m = (t >= a) & (t <= b)
    return np.polyfit(t[m], np.log(e[m]), 1)[0]


@pytest.mark.parametrize("h", [0.01, 0.1])
def test_error_converges_at_the_slowest_pole(paper_design, h):
    """Fitted log-error slope = −10 (slowest pole) within 10 %, for both delays."""
    r = simulate_observer(paper_design, h=h, t_final=1.6, dt=1e-3, w=paper_w, x0=CONST_PHI)
    slope = log_slope(r.t, r.error_norm(), 0.5, 1.5)
    assert slope == pytest.approx(-10.0, rel=0.10)
    assert slope == pytest.approx(-10.0, rel=0.01)  # measured −10.00 / −9.99


@pytest.mark.parametrize("h", [0.01, 0.1])
def test_final_error_is_integration_error(paper_design, h):
    """Noise-free: at t = 3 s the error is ≤ 1e-6 (measured 2.6–2.9e-7, 2.5e-9 relative to |x|)
    and falls like dt⁴ on halving dt (ratio ≥ 2³; measured 14–17): integration error."""
    finals = []
    for dt in (1e-3, 5e-4):
        r = simulate_observer(paper_design, h=h, t_final=3.0, dt=dt, w=paper_w, x0=CONST_PHI)
        finals.append(r.error_norm()[-1])
        assert finals[-1] <= 1e-8 * np.max(np.abs(r.x[:, -1])) * 1e1
    assert finals[0] <= 1e-6
    assert finals[0] / finals[1] >= 8.0, finals


@pytest.mark.parametrize("which", ["paper_design", "printed_design"])
@pytest.mark.parametrize("h", [0.01, 0.1])
def test_estimate_is_delayed_by_lag_h(which, h, request):
    """With the true past given to the observer, ẑ = z from t = 0, and x̂ = T_L⁻¹(δ)ẑ is right
    exactly from t = lag·h on (0.04 s and 0.4 s for the paper's printed T_L⁻¹, lag 4)."""
    design = request.getfixturevalue(which)
    r = simulate_observer(design, h=h, t_final=1.0, dt=1e-3, w=paper_w, x0=paper_phi, exact_start=True)
    e = r.error_norm()
    k = r.lag * r.N
    assert r.lag == (4 if which == "printed_design" else design.lag)
    assert e[:k].max() >= 1e-2
    assert e[k - 1] >= 10 * e[k:].max()  # the drop is at index lag·N exactly
    assert e[k:].max() <= 1e-5
    assert r.t[k] == pytest.approx(r.lag * h)


def test_noise_keeps_the_error_bounded(paper_design):
    """Uniform output noise in [−2, 2] (seeded): after the start-up (t ≥ 2 s), the change of the
    error is bounded, per state, by 2·Σ_j ‖h_ij‖₁ (impulse responses of the discretised
    observer) — the worst case over all noise sequences bounded by 2."""
    kw = dict(h=0.01, t_final=5.0, dt=1e-3, w=paper_w, x0=CONST_PHI)
    clean = simulate_observer(paper_design, **kw)
    noisy = simulate_observer(paper_design, noise=UniformNoise(2.0, seed=1), **kw)
    assert np.all(np.abs(noisy.noise) <= 2.0) and np.abs(noisy.noise).max() > 1.9
    bound = noisy.extra["stepper"].noise_gain() @ np.full(3, 2.0)
    late = noisy.t >= 2.0
    dev = np.abs(noisy.error - clean.error)[:, late].max(axis=1)
    assert np.all(dev <= bound * (1 + 1e-6)), (dev, bound)
    assert np.all(dev >= 0.05 * bound)  # measured 18–29 % of the worst case
    # over the whole run (start-up included) the error stays within twice the bound + the clean error
    whole = np.abs(noisy.error).max(axis=1)
    assert np.all(whole <= 2 * bound + np.abs(clean.error).max(axis=1))
    # the bound depends on the design's choices (U, Λ, left inverses), not only on its poles
    assert np.all(np.isfinite(bound)) and np.all(bound > 0)


def test_step_equals_run(paper_design):
    """Streaming (one sample in, one estimate out) gives the numbers of the vectorised run."""
    plant = simulate(paper_design.system, h=0.01, t_final=0.3, dt=0.002, w=paper_w, x0=CONST_PHI,
                     noise=0.5)
    obs = paper_design.numeric(h=0.01).stepper(0.002)
    x_hat0 = [1.0, 2.0, 3.0, 4.0]
    online = [obs.start(plant.y[:, 0], x_hat0=x_hat0)]
    online += [obs.step(plant.y[:, k]) for k in range(1, plant.y.shape[1])]
    online = np.stack(online, axis=1)
    offline = obs.run(plant.y, x_hat0=x_hat0)
    assert np.allclose(online, offline, rtol=1e-10, atol=1e-9 * np.abs(offline).max())
    assert np.allclose(online[:, 0], x_hat0)  # x̂(0) = x_hat0
    # constant memory: the buffers do not grow with the number of steps
    assert obs._Y.shape[0] == obs.history_length + 1 and obs._Z.shape[0] == obs.lag * obs.N + 1
    assert np.allclose(obs.start(plant.y[:, 0], x_hat0=x_hat0), offline[:, 0])


def test_observer_order_against_exact_start(paper_design):
    """The post-lag error of an exact start is pure integration error: order ≥ 3.5 (measured ≈ 3.8–4)."""
    errs = []
    for dt in (2e-3, 1e-3, 5e-4):
        r = simulate_observer(paper_design, h=0.01, t_final=1.0, dt=dt, w=paper_w, x0=paper_phi,
                              exact_start=True)
        errs.append(r.error_norm()[r.lag * r.N :].max())
    p = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(p >= 3.5), (errs, p)


def test_stepper_matches_design_interface(paper_design):
    obs = paper_design.numeric(h=0.1).stepper(0.01)
    assert (obs.n_z, obs.n_x, obs.n_y, obs.lag) == (paper_design.n_z, 4, 3, paper_design.lag)
    assert "lag=" in repr(obs)


def test_bad_observer_input(paper_design):
    obs = paper_design.numeric(h=0.01).stepper(0.001)
    with pytest.raises(SimulationError, match="call start"):
        obs.step([0.0, 0.0, 0.0])
    obs.start([0.0, 0.0, 0.0])
    with pytest.raises(SimulationError, match=r"y_k is not finite"):
        obs.step([0.0, np.nan, 0.0])
    with pytest.raises(DimensionError, match=r"y_k has shape \(2,\); expected \(3,\)"):
        obs.step([0.0, 0.0])
    with pytest.raises(SimulationError, match=r"y is not finite at index \(1, 4\)"):
        y = np.zeros((3, 10))
        y[1, 4] = np.inf
        obs.run(y)
    with pytest.raises(DimensionError, match=r"y has shape \(10, 3\); expected \(3, T\)"):
        obs.run(np.zeros((10, 3)))
    with pytest.raises(DimensionError, match=r"u_k has shape \(1,\); expected \(0,\)"):
        obs.step([0.0, 0.0, 0.0], u_k=[1.0])
    with pytest.raises(SimulationError, match=r"dt=0.0015 is not h/N"):
        paper_design.numeric(h=0.01).stepper(0.0015)
    with pytest.raises(DimensionError, match=r"x_hat0 has shape \(3,\); expected \(4,\)"):
        obs.run(np.zeros((3, 5)), x_hat0=[1, 2, 3])


def test_design_and_plant_with_different_h(paper_design):
    from uio_ring import DelaySystem

    s = paper_design.system
    plant = DelaySystem(s.A, s.B, s.C, s.D, h="0.1")
    with pytest.raises(SimulationError, match=r"h=0.01 differs from the h=1/10 of the plant"):
        simulate_observer(paper_design, plant, h=0.01, t_final=0.1, dt=0.001)


def test_design_without_known_inputs_on_a_plant_with_them(paper_design):
    from uio_ring import DelaySystem

    s = paper_design.system
    with_u = DelaySystem(s.A, s.B, s.C, s.D, E="[[1],[0],[0],[0]]", F="[[0],[0],[0]]")
    with pytest.raises(DimensionError, match=r"the plant has 1 known inputs; the design was made for 0"):
        simulate_observer(paper_design, with_u, h=0.01, t_final=0.1, dt=0.001)


def test_exact_start_needs_callable_w(paper_design):
    with pytest.raises(SimulationError, match="w: exact_start=True needs w as a callable"):
        simulate_observer(paper_design, h=0.01, t_final=0.05, dt=0.001, w=np.zeros((2, 51)), exact_start=True)


def test_observer_order_through_the_start_up(paper_design):
    """From an arbitrary start (ξ = 0, y held before 0) the break points at 0, h, 2h, … are kept
    out of the stencils: x̂ converges with order ≥ 2.8 on the whole of [0, 0.5] s (measured ≈ 3;
    crossing them with the cubic stencil gave order 2)."""
    xs = {}
    for N in (5, 10, 20, 80):
        r = simulate_observer(paper_design, h=0.01, t_final=0.5, dt=0.01 / N, w=paper_w, x0=CONST_PHI)
        xs[N] = r.x_hat[:, :: N // 5]
    errs = [np.abs(xs[N] - xs[80]).max() for N in (5, 10, 20)]
    p = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(p >= 2.8), (errs, p)


def test_run_outputs_are_consistent(paper_design):
    """x̂ = T_L⁻¹(δ) ẑ and ẑ = ξ + (HΛ)(δ) y, checked on the arrays the stepper returns."""
    from uio_ring.numeric.convert import coefficient_arrays, poly_matmul

    r = simulate(paper_design.system, h=0.01, t_final=0.2, dt=0.002, w=paper_w, x0=CONST_PHI)
    obs = paper_design.numeric(h=0.01).stepper(0.002)
    traj = obs.trajectories(r.y)
    z, xh = traj.z, traj.x_hat
    N, k = obs.N, np.arange(40, r.y.shape[1])  # t ≥ 0.08 s: every delayed sample is inside the record
    TL = coefficient_arrays(paper_design.T_left_inverse)
    assert np.allclose(xh[:, k], sum(TL[i] @ z[:, k - i * N] for i in range(len(TL))))
    # ξ = ẑ − (HΛ)(δ) y obeys ξ' = L0 ξ + (JΛ)(δ) y: check with a centred difference
    HL = poly_matmul(coefficient_arrays(paper_design.H), coefficient_arrays(paper_design.Lam))
    JL = poly_matmul(coefficient_arrays(paper_design.J), coefficient_arrays(paper_design.Lam))
    L0 = coefficient_arrays(paper_design.L0)[0]
    xi = z[:, k] - sum(HL[i] @ r.y[:, k - i * N] for i in range(len(HL)))
    rhs = L0 @ xi + sum(JL[i] @ r.y[:, k - i * N] for i in range(len(JL)))
    dxi = (xi[:, 2:] - xi[:, :-2]) / (2 * 0.002)
    assert np.abs(dxi - rhs[:, 1:-1]).max() <= 1e-2 * np.abs(rhs).max()  # centred difference: O(dt²)
