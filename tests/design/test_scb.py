"""The special-coordinate-basis observer (method 'scb', Tranninger et al. 2021): paper 003's example,
error dynamics through the engine, the Table 1 decision, agreement with paper 001 at δ = 0."""

from __future__ import annotations

import random
import sys as _sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scipy.linalg import expm

from uio_ring import DelaySystem
from uio_ring.analysis.assumptions import check_assumptions
from uio_ring.analysis.observer_classes import observer_options
from uio_ring.design.methods import design_auto
from uio_ring.design.scb import design_scb
from uio_ring.design.zheng_bejarano import design_zheng_bejarano
from uio_ring.errors import (
    DimensionError,
    DomainError,
    NotObservableError,
    NotSupportedError,
    SpecError,
)
from uio_ring.ring.qmatrix import QMatrix as Q
from uio_ring.sim.engine import simulate_observer

_sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from analysis.paper003 import system as paper003  # noqa: E402
from analysis.planted_scb import planted  # noqa: E402

X0 = np.array([1, -0.1, 2, -0.3, 0.5, 0.2, -0.5, -0.2])


def _w(t):
    t = np.asarray(t, float)
    return np.array([1.5 * np.sin(t) + 0.5, ((t >= 1) & (t < 4)).astype(float)])


def _f(M) -> np.ndarray:
    return np.array(Q(M).tolist(), dtype=float)


@pytest.fixture(scope="module")
def paper_design():
    return design_scb(paper003(), poles_b=[-8, -6], input_ranges=[[-2, 1], [0, 1]])


def test_paper_example_design(paper_design):
    d = paper_design
    assert d.scb.q == (3, 2) and d.scb.l == (2,) and d.d_observer == "hosmo"
    assert Q(d.L_b) == Q([[13], [47]])  # the paper's L_b: our A_b is the paper's [[-1, 1], [-1, 0]]
    assert d.n_xi == 8
    cert = d.certificate()
    assert cert.ok, str(cert)
    # Theorem 2: the last gain of each chain is 1.1 Δ_d (Levant), strictly above Δ_d
    assert all(k[-1] == D * 11 / 10 for k, D in zip(d.kappa, d.Delta_d, strict=True))


def test_paper_example_zheng_bejarano_refuses_and_auto_picks_scb():
    with pytest.raises(NotObservableError, match="Assumption 1 fails.*Assumption 2 fails"):
        design_zheng_bejarano(paper003())
    res = design_auto(paper003(), input_ranges=[[-2, 1], [0, 1]])
    assert res.method == "scb"
    assert "zheng-bejarano" in dict(res.skipped)
    rep = observer_options(paper003())
    assert rep.holds and rep.convergence == "asymptotic" and not rep.linear and not rep.strongly_observable


def test_paper_example_simulation_error_dynamics(paper_design):
    """e_a = e_a(0) e^{−10 t} and e_b = exp((A_b − L_b C_b) t) e_b(0) to integration accuracy,
    whatever w does; the sliding-mode chains settle: max |e_d| < 1e-2 for t ≥ 7 s (paper's settings)."""
    d = paper_design
    res = simulate_observer(d, t_final=10.0, dt=1e-4, w=_w, x0=X0, x_hat0=np.zeros(8), progress=False)
    Tsi = np.linalg.inv(_f(d.scb.Ts))
    e = Tsi @ (res.x - res.x_hat)
    t = res.t
    assert np.max(np.abs(e[0] - e[0, 0] * np.exp(-10 * t))) < 1e-6
    Fb = _f(d.scb.A_b) - _f(d.L_b) @ _f(d.scb.C_b)
    idx = np.arange(0, t.size, 500)
    pred = np.stack([expm(Fb * t[k]) @ e[1:3, 0] for k in idx], axis=1)
    assert np.max(np.abs(e[1:3, idx] - pred)) < 1e-6
    late = t >= 7
    assert np.max(np.abs(e[3:, late])) < 1e-2
    assert np.max(np.abs((res.x - res.x_hat)[:, late])) < 1e-2
    # before the chains slide the error is large: the bound is not met trivially
    assert np.max(np.abs(e[3:, t < 1])) > 0.1


def _strong_star(seed: int = 36) -> DelaySystem:
    """A strong* detectable system with a stable zero at −3 and chains of length 1 (seed 36: the
    plant is stable too, its slowest eigenvalue has real part −1.18)."""
    return planted(1, (2,), (1, 1), 0, random.Random(seed), A_a=Q([[-3]])).system


def test_linear_observer_when_strong_star_detectable():
    """All q_i = 1: x̂_d = y_d, the observer is linear and its error does not see w at all.
    (With no initial estimate the model starts at ξ = 0, i.e. x̂_d(0) = y_d(0); a given x_hat0
    starts Remark 3's z_d at x̂_d0 − y_d(0), which decays.)"""
    sysm = _strong_star()
    d = design_scb(sysm, poles_b=[-4, -5])
    assert d.d_observer == "linear" and d.n_xi == 3 and d.certificate().ok
    x0 = np.linspace(-1, 1, sysm.n_x)
    Tsi = np.linalg.inv(_f(d.scb.Ts))
    errs = []
    for amp in (0.0, 50.0):
        res = simulate_observer(d, t_final=3.0, dt=1e-3, w=lambda t, a=amp: a * np.array([np.sin(3 * np.asarray(t)),
                                np.cos(np.asarray(t))]), x0=x0, progress=False)
        e = Tsi @ (res.x - res.x_hat)
        assert np.max(np.abs(e[3:])) < 1e-9  # x̂_d = y_d exactly
        assert np.max(np.abs(e[0] - e[0, 0] * np.exp(-3 * res.t))) < 1e-4  # integration accuracy (|e_a(0)| ≈ 2.5)
        errs.append(e)
    assert np.max(np.abs(errs[0] - errs[1])) < 1e-4  # the error is the same for w = 0 and for a large w
    res = simulate_observer(d, t_final=1.0, dt=1e-3, w=lambda t: np.zeros((2, np.size(t))), x0=x0,
                            x_hat0=np.zeros(sysm.n_x), progress=False)
    e = Tsi @ (res.x - res.x_hat)
    assert np.max(np.abs(e[3:, 0])) > 0.1 and np.max(np.abs(e[3:, res.t >= 0.5])) < 1e-9  # Remark 3's z_d decays
    perf = d.performance()
    assert abs(perf.decay_rate - 3.0) < 1e-9  # the zero at −3 is slower than the poles −4, −5


def test_first_order_sliding_mode_on_unit_chains():
    sysm = _strong_star()
    d = design_scb(sysm, d_observer="1-smo", poles_b=[-4, -5], input_bounds=[2, 2])
    assert d.d_observer == "1-smo" and d.n_xi == sysm.n_x and d.certificate().ok
    res = simulate_observer(d, t_final=4.0, dt=1e-4, w=lambda t: np.array([np.sin(np.asarray(t)),
                            np.cos(2 * np.asarray(t))]), x0=np.ones(sysm.n_x), x_hat0=np.zeros(sysm.n_x),
                            progress=False)
    # the unit chains slide in finite time (here by t ≈ 2.5 s: the last gain 1.1 Δ only slowly beats the
    # decaying x_a, x_b terms), then e_d = 0 up to rounding; x_a, x_b converge exponentially
    e = np.linalg.inv(_f(d.scb.Ts)) @ (res.x - res.x_hat)
    e_d = np.max(np.abs(e[3:]), axis=0)
    assert np.max(e_d[res.t >= 3]) < 1e-9 and np.max(e_d[res.t < 0.01]) > 1e-2
    assert np.max(np.abs(res.x - res.x_hat)[:, res.t >= 3.5]) < 1e-3


def test_input_reconstruction():
    """reconstruct_input: the design is made for [x; w] driven by w' (chains one longer); ŵ → w."""
    sysm = _strong_star()
    d = design_scb(sysm, poles_b=[-4, -5], reconstruct_input=True, input_bounds=[3, 3])
    assert d.scb.q == (2, 2) and d.n_xi == sysm.n_x + sysm.n_w
    cert = d.certificate()
    assert cert.ok and cert["the basis is of the system of [x; w]"].ok
    w = lambda t: np.array([np.sin(np.asarray(t)), 0.5 * np.cos(2 * np.asarray(t))])  # noqa: E731
    res = simulate_observer(d, t_final=5.0, dt=1e-4, w=w, x0=np.ones(sysm.n_x), progress=False)
    late = res.t >= 3
    assert np.max(np.abs(res.w_hat - res.w)[:, late]) < 1e-2
    assert np.max(np.abs(res.w_hat - res.w)[:, res.t < 0.5]) > 0.1  # it starts wrong
    assert np.max(np.abs(res.x - res.x_hat)[:, late]) < 1e-2


def test_certificate_catches_tampering(paper_design):
    from dataclasses import replace

    bad = replace(paper_design, L_b=(Q(paper_design.L_b) + Q([[1], [0]])).to_polymatrix())
    assert not bad.certificate()["(40) spec(A_b − L_b C_b) = poles_b"].ok
    weak = replace(paper_design, kappa=tuple((*k[:-1], D) for k, D in zip(paper_design.kappa, paper_design.Delta_d,
                                                                        strict=True)))
    assert not weak.certificate()["Theorem 2: κ_{i,q_i} > Δ_{d,i}"].ok


def test_refusals():
    s = Q([[1]])
    unstable = planted(1, (1,), (2,), 0, random.Random(1), A_a=s).system
    with pytest.raises(NotObservableError, match="invariant zero"):
        design_scb(unstable, input_bounds=1)
    with pytest.raises(DomainError, match="needs every chain of length 1"):
        design_scb(paper003(), d_observer="linear")
    with pytest.raises(NotSupportedError, match="one of linear, cbho"):
        design_scb(paper003(), b_observer="moreno")
    with pytest.raises(NotSupportedError, match="one of linear, 1-smo, hosmo, dbho"):
        design_scb(paper003(), d_observer="sliding")
    with pytest.raises(DimensionError, match="needs input_bounds or input_ranges"):
        design_scb(paper003())
    with pytest.raises(DimensionError, match="poles_b has 1"):
        design_scb(paper003(), poles_b=[-1], input_bounds=1)
    with pytest.raises(DomainError, match="Theorem 2"):
        design_scb(paper003(), input_bounds=1, gains=[[1, 1, "0.5"], [1, "0.5"]])
    with pytest.raises(NotObservableError, match="delays"):
        design_scb(DelaySystem("[[d]]", "[[1]]", "[[1]]", None))


def test_spec_options_are_checked():
    from uio_ring.design.methods import get_method

    m = get_method("scb")
    assert m.read_options({"d_observer": "hosmo", "poles_b": ["-8", -6]})["poles_b"] == (-8, -6)
    with pytest.raises(SpecError, match="expected one of linear, 1-smo, hosmo, dbho") as exc:
        m.read_options({"d_observer": "sliding"})
    assert exc.value.path == "design.d_observer"


_ENTRY = st.integers(-2, 2)


@st.composite
def _systems(draw):
    n = draw(st.integers(1, 4))
    m = draw(st.integers(1, 2))
    p = draw(st.integers(m, 3))

    def mat(r, c, zero=False):
        return [[0 if zero else draw(_ENTRY) for _ in range(c)] for _ in range(r)]

    D = mat(p, m, zero=draw(st.booleans()))
    return DelaySystem(str(mat(n, n)), str(mat(n, m)), str(mat(p, n)), str(D))


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(_systems())
def test_zheng_bejarano_at_delta_0_is_table1_last_column(sysm):
    """Paper 001's assumptions at δ = 0 hold ⇔ strongly observable and strong* detectable (Table 1's
    last column), on random systems (left-invertible or not)."""
    B = Q(sysm.B)
    D = Q(sysm.D)
    assume(Q.vstack(B, D).rank() == sysm.n_w and Q.hstack(Q(sysm.C), D).rank() == sysm.n_y)
    rep = observer_options(sysm)
    both = check_assumptions(sysm).holds
    assert both == (rep.strongly_observable and rep.strong_star_detectable)


@pytest.mark.parametrize(("options", "path", "match"), [
    ("  poles_b: [-1]\n  input_bounds: 1\n", "design.poles_b", "poles_b has 1"),
    ("  input_ranges: [[1, 0], [0, 1]]\n", "design.input_ranges", "lo ≤ hi"),
    ("  input_bounds: [1]\n", "design.input_bounds", "input_bounds has 1 entries"),
    ("  d_observer: linear\n", "design.d_observer", "needs every chain of length 1"),
    ("  input_bounds: 1\n  gains: [[1, 1, 0.5], [1, 0.5]]\n", "design.gains", "Theorem 2"),
    ("", "design.input_bounds", "needs input_bounds or input_ranges"),
])
def test_cli_names_the_option_that_does_not_fit(tmp_path, capsys, options, path, match):
    """A design option that does not fit the system: exit 2, one line, the option's spec path."""
    from uio_ring.cli import main

    spec = tmp_path / "s.yaml"
    text = (Path(__file__).resolve().parents[2] / "examples" / "tranninger2021.yaml").read_text(encoding="utf-8")
    head = text[: text.index("design:")]
    spec.write_text(head + "design:\n  method: scb\n" + options, encoding="utf-8")
    code = main(["design", str(spec), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2, err
    assert len(err.strip().splitlines()) == 1 and path in err and match in err, err
    assert not (tmp_path / "out").exists()
