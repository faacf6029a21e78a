"""The a-posteriori accuracy check: untrustworthy runs are flagged, accurate ones are not.

Two stiff cases of issue 16:

* observer poles (−10⁶, −25, −50) on paper 001's example, dt = 1e-3: the reported
  error after 0.2 s (8.4) is *right*.  It is the peaking of a high-gain observer: the
  start-up error (the observer starts from ξ = 0 with y held before 0) is amplified by
  the fast pole into the slow modes (≈ 86 at t = 0.1 s), which then decay at the rate
  25.  Shown independently: (i) the same run with dt/10 gives the same error to 1e-6,
  (ii) on [0.1, 0.2] s the error ``e = z_of_x(δ) x − ẑ`` obeys ``e(t₂) = e^{L0 (t₂−t₁)} e(t₁)``
  (Theorem 4, exact error dynamics, evaluated with ``expm``), (iii) with the true past
  (``exact_start``) the error is below 1e-6.
* a plant pole at −10⁶ with dt = 0.01: the output has a boundary layer of width 1e-6 s
  that the grid cannot see, the observer multiplies y by 10⁶, and the reported error
  (about 5000) is wrong — the true error obeys e' = −e from |e(0)| = 1.  The check
  flags it; with dt small enough to resolve the layer the check passes and the error
  is the true one.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from scipy.linalg import expm

from uio_ring import DelaySystem, design_zheng_bejarano
from uio_ring.sim import AccuracyCheck, AccuracyWarning, UniformNoise, simulate_observer

from .conftest import PAPER, paper_w

X0 = [1.0, -1.0, 0.5, 0.0]


@pytest.fixture(scope="module")
def stiff_observer():
    sys = DelaySystem(PAPER["A"], PAPER["B"], PAPER["C"], PAPER["D"], h="1/100")
    return design_zheng_bejarano(sys, poles=[-10**6, -25, -50])


@pytest.fixture(scope="module")
def stiff_plant():
    sys = DelaySystem("[[-1000000, 0], [1, -1]]", "[[0], [1]]", "[[1, 0], [0, 1]]", "[[0], [0]]")
    return design_zheng_bejarano(sys, poles=[-1])


def quiet_run(design, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("error", AccuracyWarning)  # an accurate run must not warn
        return simulate_observer(design, **kw)


def test_stiff_observer_error_is_right_and_trusted(stiff_observer):
    coarse = quiet_run(stiff_observer, t_final=0.2, dt=1e-3, w=paper_w, x0=X0)
    assert coarse.success and coarse.accuracy.ok
    assert coarse.accuracy.estimate < 1e-6 * coarse.accuracy.scale * 100  # measured 5.2e-5 of 20
    e = np.abs(coarse.error[:, -1]).max()
    assert 8.0 < e < 9.0  # the figure of the issue (8.4)
    fine = simulate_observer(stiff_observer, t_final=0.2, dt=1e-4, w=paper_w, x0=X0, check=False)
    assert np.abs(fine.error[:, -1] - coarse.error[:, -1]).max() < 1e-6 * e  # measured 2e-8


def test_stiff_observer_obeys_the_exact_error_dynamics(stiff_observer):
    r = simulate_observer(stiff_observer, t_final=0.2, dt=1e-3, w=paper_w, x0=X0)
    stepper, model = r.extra["stepper"], r.extra["model"]
    z = stepper.trajectories(r.y).z
    N, Zx = stepper.N, model.z_of_x

    def e_z(k):  # z_of_x(δ) x − ẑ at t_k
        return sum(Zx[i] @ r.x[:, k - i * N] for i in range(Zx.shape[0])) - z[:, k]

    k1, k2 = 100, 200  # t = 0.1 and 0.2 s, long after the start-up blocks
    predicted = expm(model.F * 0.1) @ e_z(k1)
    assert np.abs(e_z(k1)).max() > 50  # the peaking is real …
    assert np.abs(predicted - e_z(k2)).max() < 1e-6 * np.abs(e_z(k1)).max()  # … and then e' = L0 e


def test_stiff_observer_with_the_true_past_has_no_peaking(stiff_observer):
    r = quiet_run(stiff_observer, t_final=0.2, dt=1e-3, w=paper_w, x0=X0, exact_start=True)
    assert r.success and np.abs(r.error[:, r.t >= 0.05]).max() < 1e-6


def test_stiff_plant_is_flagged(stiff_plant):
    with pytest.warns(AccuracyWarning, match="not resolved by dt = 0.01"):
        r = simulate_observer(stiff_plant, t_final=0.05, dt=0.01, w=lambda t: np.sin(t), x0=[1.0, 0.0])
    assert not r.success and r.message.startswith("not resolved")
    assert np.abs(r.error).max() > 1000  # the wrong number the issue saw …
    assert r.accuracy.estimate > 0.3 * np.abs(r.error).max()  # … is of the size of the disagreement


@pytest.mark.parametrize("dt", [1e-3, 1e-5])
def test_stiff_plant_stays_flagged_until_resolved(stiff_plant, dt):
    with pytest.warns(AccuracyWarning):
        r = simulate_observer(stiff_plant, t_final=0.01, dt=dt, w=lambda t: np.sin(t), x0=[1.0, 0.0])
    assert not r.success


def test_resolved_stiff_plant_is_trusted_and_right(stiff_plant):
    r = quiet_run(stiff_plant, t_final=0.01, dt=1e-7, w=lambda t: np.sin(t), x0=[1.0, 0.0])
    assert r.success
    # e' = −e per channel from e(0) = x(0) − x̂(0): |e(t)| ≤ |e(0)| (bound of the continuous observer)
    assert np.abs(r.error).max() <= 1.0 + 1e-3


def test_noise_does_not_trip_the_check(stiff_observer):
    """The check compares noise-free runs (the noise sequence depends on the grid)."""
    r = quiet_run(stiff_observer, t_final=0.2, dt=1e-3, w=paper_w, x0=X0, noise=UniformNoise(0.01, seed=3))
    assert r.success and r.accuracy.ok


def test_unchecked_runs_say_so(paper_design):
    r = simulate_observer(paper_design, t_final=0.1, dt=1e-3, w=paper_w, h=0.01, check=False)
    assert r.accuracy is None and r.success
    samples = paper_w(np.arange(101) * 1e-3)  # sampled inputs depend on the grid: no dt/2 run
    assert simulate_observer(paper_design, t_final=0.1, dt=1e-3, w=samples, h=0.01).accuracy is None


def test_reason_is_one_sentence():
    c = AccuracyCheck(estimate=3.0, scale=1.0, window=0.5, dt=0.01)
    assert not c.ok and "\n" not in c.reason and "reduce dt" in c.reason
    assert AccuracyCheck(estimate=0.01, scale=1.0, window=0.5, dt=0.01).ok
