"""Simulation of the normal-form observer through the one engine: paper 000's
Simulations 1 and 2 (convergence times and error bounds), implicit vs explicit Euler at equal
step, independence of the known input, the paper-001 cross case, the streaming API."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from design import paper000, paper001

from uio_ring import DelaySystem, design_normal_form, design_zheng_bejarano
from uio_ring.sim import simulate_observer
from uio_ring.sim.errors import NotSupportedError, SimulationError


def delta(t):
    """(88): the rudder fault, |Δ| ≤ 0.02, |Δ'| ≤ 0.046."""
    return 0.008 + 0.01 * np.sin(2 * t) + 0.002 * np.cos(13 * t)


def _settle_time(res, bound, signal=None):
    """First grid time after which ``signal`` (default ‖x − x̂‖∞) stays below ``bound``."""
    e = res.error_norm() if signal is None else signal
    bad = np.nonzero(e >= bound)[0]
    return 0.0 if bad.size == 0 else (res.t[bad[-1] + 1] if bad[-1] + 1 < res.t.size else np.inf)


def _window(res, a, b=None):
    return (res.t >= a) & (res.t <= (res.t[-1] if b is None else b))


@pytest.fixture(scope="module")
def sim1_design():
    return design_normal_form(paper000.aircraft(), ["0.02"], gains=paper000.GAINS_89)


@pytest.fixture(scope="module")
def sim2_design():
    return design_normal_form(paper000.aircraft(), ["0.046"], reconstruct_input=True, gains=paper000.GAINS_95)


# ---------------------------------------------------------------------------- Simulation 1
def test_simulation_1_converges_after_about_two_seconds(sim1_design):
    res = simulate_observer(sim1_design, t_final=6, dt=2e-4, w=delta, x0=paper000.X0)
    e = res.error_norm()
    assert e[_window(res, 1.5, 1.5)].max() > 0.5  # not yet converged at 1.5 s
    t_conv = _settle_time(res, 1e-2)
    assert 1.8 < t_conv < 2.0  # ≈ 2 s (1.94 s in a reference run)
    assert e[_window(res, 2.0)].max() < 1e-2
    assert e[_window(res, 3.0)].max() < 5e-3  # residual of the implicit discretisation at dt = 2e-4
    assert np.abs(res.x[:, -1]).max() < 0.3  # the plant drifts slowly (unstable, max|x| ≈ 0.24)
    assert res.errors["x[0]"].shape == res.t.shape and res.extra["stepper"].discretisation == "implicit"


def test_implicit_beats_explicit_euler_at_equal_step(sim1_design):
    dt = 5e-4
    err = {}
    for method in ("implicit", "euler"):
        res = simulate_observer(sim1_design, t_final=6, dt=dt, w=delta, x0=paper000.X0, discretisation=method)
        err[method] = res.error_norm()[_window(res, 3.0)].max()
    # measured: implicit 6.4e-3, explicit Euler 1.7e-2
    assert err["implicit"] < 1e-2 < err["euler"]
    assert err["implicit"] < 0.5 * err["euler"]


# ---------------------------------------------------------------------------- Simulation 2
@pytest.mark.slow
def test_simulation_2_reconstructs_the_input_in_closed_loop(sim2_design):
    K = np.array([[float(Fraction(x)) for x in r] for r in paper000.K_97])
    h = np.array([1.0, 0.0])  # D = B h (matched rudder fault)

    def feedback(t, x_hat, w_hat):  # (96): u = −[K h] χ̂
        return -K @ x_hat - h * w_hat[0]

    res = simulate_observer(sim2_design, t_final=15, dt=2e-4, w=delta, x0=paper000.X0,
                                        feedback=feedback)
    e, ew = res.error_norm(), np.abs((res.w - res.w_hat)[0])
    assert 2.3 < _settle_time(res, 1e-2) < 2.7  # ≈ 2.5 s (2.47–2.54 s in reference runs)
    assert _settle_time(res, 1e-2, ew) < 2.6
    late = _window(res, 2.7)
    assert e[late].max() < 1e-2 and ew[late].max() < 1e-2
    assert ew[_window(res, 5.0)].max() < 5e-4
    assert np.abs(res.x[:, -1]).max() < 2e-2  # the closed loop drives x to 0 (6e-3 at 15 s in a reference run)
    assert 1.0 < np.abs(res.x[:, _window(res, 1.0, 1.0)]).max() < 20  # bounded transient (≈ 8.8)
    # explicit Euler of the observer at the same step does not converge in this closed loop
    bad = simulate_observer(sim2_design, t_final=8, dt=2e-4, w=delta, x0=paper000.X0,
                                        feedback=feedback, discretisation="euler")
    assert bad.error_norm()[_window(bad, 5.0)].max() > 0.1


def test_known_input_does_not_change_the_error(sim2_design):
    """The error dynamics do not depend on u: the held input's effect over a step is exact (ZOH),
    including its effect on the interpolated outputs."""
    u = lambda t: np.array([np.sin(t) + 0 * t, np.cos(3 * t) + 0 * t])  # noqa: E731
    runs = [simulate_observer(sim2_design, t_final=4, dt=5e-4, w=delta, x0=paper000.X0, u=uu)
            for uu in (None, u)]
    assert np.abs(runs[1].x - runs[0].x).max() > 1.0  # the plants move very differently
    late = _window(runs[0], 3.0)
    ex = [r.error_norm()[late].max() for r in runs]
    ew = [np.abs((r.w - r.w_hat)[0])[late].max() for r in runs]
    assert max(ex) < 1e-2 and max(ew) < 1e-3
    assert ex[1] < 1.2 * ex[0] and ew[1] < 2 * ew[0] + 1e-4
    # the error in the smooth (undisturbed-chain-free) directions coincides: rows 1 and 5 of x̄
    Ti = np.array([[float(c) for c in row] for row in sim2_design.T_inverse.coefficient_lists()[0]])
    e = [Ti @ np.vstack([r.error, (r.w - r.w_hat)]) for r in runs]
    assert np.abs(e[1] - e[0])[[0, 4]][:, late].max() < 1e-9


# ---------------------------------------------------------------------------- cross-method
def test_paper001_at_delta_zero_both_observers_converge():
    sys = paper001.system().at_delta(0)  # h = 1/100 kept, degree 0
    w = lambda t: np.array([np.sin(t) + 0 * t, 0.5 * np.cos(2 * t) + 0 * t])  # noqa: E731
    x0 = np.array([1.0, -1.0, 0.5, 0.2])
    zb = design_zheng_bejarano(sys, poles=[-2, -3, -4])
    r_zb = simulate_observer(zb, t_final=5, dt=1e-3, w=w, x0=lambda t: x0)
    nf = design_normal_form(sys, [1, "0.5"])
    r_nf = simulate_observer(nf, t_final=5, dt=1e-3, w=w, x0=x0)
    assert np.abs(r_nf.x - r_zb.x).max() < 1e-6 * np.abs(r_zb.x).max()  # same plant trajectory
    for res in (r_zb, r_nf):
        e = np.abs(res.error).max(axis=0)
        assert e[res.t <= 0.3].max() > 0.05
        assert e[res.t >= 3.0].max() < 1e-2
    # finite time vs exponential: the normal-form error is already small at 2 s
    assert np.abs(r_nf.error[:, r_nf.t >= 2.0]).max() < 1e-2


def test_bounded_output_noise_gives_a_bounded_error(sim1_design):
    """Remark 3.7: with |v_j| ≤ η the error stays bounded.  A third-order differentiator is very
    sensitive (the last derivative's error scales like η^{1/4}): η = 1e-4 gives ≈ 0.1."""
    eta = 1e-4
    res = simulate_observer(sim1_design, t_final=4, dt=5e-4, w=delta, x0=paper000.X0, noise=eta)
    assert res.noise is not None and 0 < np.abs(res.noise).max() <= eta
    assert res.error_norm()[_window(res, 3.0)].max() < 0.5


# ---------------------------------------------------------------------------- API
def test_streaming_observer_reproduces_the_simulation(sim1_design):
    res = simulate_observer(sim1_design, t_final=0.5, dt=1e-3, w=delta, x0=paper000.X0)
    obs = sim1_design.numeric().stepper(1e-3)
    xh = [obs.start(res.y[:, 0], res.u[:, 0])]
    for k in range(1, res.t.size):
        xh.append(obs.step(res.y[:, k], res.u[:, k]))
    assert np.abs(np.array(xh).T - res.x_hat).max() < 1e-12


def test_errors():
    d = design_normal_form(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None), [1])
    with pytest.raises(SimulationError, match="discretisation"):
        simulate_observer(d, t_final=1, dt=1e-3, discretisation="rk4")
    with pytest.raises(SimulationError, match="u or feedback"):
        simulate_observer(d, t_final=1, dt=1e-3, u=0, feedback=lambda t, x, w: 0)
    with pytest.raises(NotSupportedError, match="delay-free plants"):
        simulate_observer(d, DelaySystem("[[d, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None, h=1),
                          t_final=1, dt=1e-3, feedback=lambda t, x, w: 0)
    with pytest.raises(Exception, match=r"x0 has shape"):
        simulate_observer(d, t_final=1, dt=1e-3, x0=[1, 2, 3])
    with pytest.raises(SimulationError, match="start"):
        d.numeric().stepper(1e-3).step([0.0])
