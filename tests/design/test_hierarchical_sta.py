"""The hierarchical super-twisting observer (Bejarano, Fridman & Poznyak 2007, Section 2).

Measured at the time of writing on Example 1 (paper gains, K = 0, x0 = [1, −1, 0.5, 0, 2],
x̃(0) = 0): |x̂ − x|∞ < 1e-2 from t = 0.73 s on; max over [2, 10] s 6.2e-4 at dt = 1e-3 and
3.1e-4 at dt = 5e-4 (first order in dt, as a backward-Euler set-valued step gives).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from uio_ring import DelaySystem, PolyMatrix, check_assumptions, simulate, simulate_observer
from uio_ring.analysis.molinari import molinari_sequence
from uio_ring.design.hierarchical_sta import design_hierarchical_sta
from uio_ring.design.methods import design_auto
from uio_ring.errors import NotObservableError

from . import paper002 as P


@pytest.fixture(scope="module")
def example1():
    return P.example1()


@pytest.fixture(scope="module")
def design1(example1):
    return design_hierarchical_sta(example1, gains=P.GAINS)


def test_molinari_sequence_of_example_1(example1):
    seq = molinari_sequence(example1)
    assert seq.ranks == (2, 4, 5) and seq.l == 3 and seq.holds
    assert [M.shape for M in seq.M] == [(2, 5), (4, 5), (5, 5)]
    assert (seq.T_b[0] @ example1.D).is_zero()  # F^⊥ F = 0 in the paper's letters
    # the row space of M_1 is the paper's: span{[13, −2, −3, 0, 0], [0, −3, 2, 0, 0]} (its F^⊥ C)
    paper_rows = PolyMatrix("[[13, -2, -3, 0, 0], [0, -3, 2, 0, 0]]")
    assert PolyMatrix.vstack(seq.M[0], paper_rows).rank() == 2
    # the printed M_3 is nonsingular: so is ours (only that is choice-invariant)
    assert not seq.M[2].det().is_zero()


def test_zheng_bejarano_refuses_and_auto_picks_the_hierarchy(example1):
    assert not check_assumptions(example1).holds  # the matching condition fails
    res = design_auto(example1)
    assert res.method == "hierarchical-sta" and res.design.certificate().ok
    assert any(name == "zheng-bejarano" for name, _ in res.skipped)


def test_certificate_and_its_failure(design1):
    cert = design1.certificate()
    assert cert.ok, str(cert)
    import dataclasses

    bad = dataclasses.replace(design1, K=PolyMatrix.identity(5)[:, 0:3] * -10)  # A + 10 [I; 0] C: unstable
    assert not bad.certificate()["A − K C Hurwitz"].ok
    wrong = dataclasses.replace(design1, M_l_pinv=design1.M_l_pinv * 2)
    assert not wrong.certificate()["M_l^+ M_l = I"].ok


@pytest.mark.slow
def test_example_1_converges_in_finite_time_at_order_one(design1):
    errs = []
    for dt in (1e-3, 5e-4):
        r = simulate_observer(design1, t_final=6.0, dt=dt, w=P.w, u=P.u, x0=P.X0)
        e = r.error_norm()
        bad = np.nonzero(e >= 1e-2)[0]
        assert r.t[bad[-1] + 1] < 1.5  # finite-time convergence (measured 0.73 s)
        errs.append(e[r.t >= 2.0].max())
    assert errs[0] < 2e-3, errs  # the bound; measured 6.2e-4
    assert 0.35 <= errs[1] / errs[0] <= 0.65, errs  # first order in dt


def test_pole_placed_gain_is_exact_and_converges(example1):
    """Ackermann's formula (one combined output) places the poles exactly; its gains are larger
    (up to 16 here) than a multi-output placement, and the paper's gains still dominate."""
    poles = ["-2", "-2.5", "-3", "-3.5", "-4"]
    des = design_hierarchical_sta(example1, poles=poles, gains=P.GAINS)
    assert des.certificate().ok
    from uio_ring.ring.charpoly import charpoly

    char = charpoly(example1.A - des.K @ example1.C)
    expected = PolyMatrix("[[(s + 2)*(s + 5/2)*(s + 3)*(s + 7/2)*(s + 4)]]", var="s")[0, 0]
    assert char == expected  # exactly the requested spectrum
    r = simulate_observer(des, t_final=4.0, dt=1e-3, w=P.w, u=P.u, x0=P.X0)
    assert r.error_norm()[r.t >= 2.0].max() < 5e-3  # measured 2.0e-3


def test_a_given_gain_placing_the_same_poles_numerically(example1):
    """K from a numerical multi-output placement at {−2, …, −4} (3 decimals, read exactly):
    smaller gains, faster convergence (measured: from 0.70 s, 3.5e-4 after 2 s)."""
    K = PolyMatrix("[[2.562, 0.296, 1.155], [0.988, 1.933, -1.438], [-0.857, 0.802, 3.715],"
                   " [-1.042, 0.084, 0.788], [0.217, 2.269, -0.727]]")
    des = design_hierarchical_sta(example1, K=K, gains=P.GAINS)
    assert des.certificate().ok
    r = simulate_observer(des, t_final=10.0, dt=1e-3, w=P.w, u=P.u, x0=P.X0)
    assert np.abs(r.x_hat - r.x)[:, r.t >= 2.0].max() < 2e-3  # the bound on [2, 10]


def test_levels_recover_their_targets_whatever_w(design1, example1):
    """Once sliding, level 1's z equals M_2 (x − x̃) whatever the unknown input is."""
    model = design1.numeric()
    dt = 1e-3
    for w in (P.w, lambda t: np.array([3 * np.sin(5 * np.asarray(t)), np.ones_like(np.asarray(t, float))])):
        plant = simulate(example1, h=dt, t_final=4.0, dt=dt, w=w, u=P.u, x0=P.X0)
        traj = model.stepper(dt).trajectories(plant.y, plant.u)
        n = example1.n_x
        x_tilde = traj.xi[:n]
        z1 = traj.xi[2 * n + example1.n_y + 1 : 2 * n + example1.n_y + 8 : 2]  # z of level 1's 4 chains
        M2 = np.array([[float(v) for v in row] for row in design1.M[1].coefficient_lists()[0]])
        late = plant.t >= 2.0
        assert np.abs(z1 - M2 @ (plant.x - x_tilde))[:, late].max() < 5e-3


def test_refusals():
    with pytest.raises(NotObservableError, match="strong observability"):
        # an invariant zero at −1: x1' = −x1 + w, y = x2 with x2' = x1 − x2 … (not strongly observable)
        design_hierarchical_sta(DelaySystem("[[-1, 0], [0, -2]]", "[[1], [0]]", "[[0, 1]]", None))
    with pytest.raises(NotObservableError, match="delay-free"):
        design_hierarchical_sta(DelaySystem("[[d]]", "[[1]]", "[[1]]", None))


def _orthonormal_molinari(A, B, C, D):
    """Molinari's M_2 in the paper's convention (orthonormal left null spaces by SVD), in floats:
    an independent implementation, for the norms of the paper's sufficient condition."""
    from scipy.linalg import null_space

    T0 = null_space(D.T).T
    M1 = T0 @ C
    T1 = null_space(np.vstack([M1 @ B, D]).T).T
    return T1 @ np.vstack([M1 @ A, C])


def test_the_papers_gains_do_not_satisfy_its_sufficient_condition(example1):
    """With K = 0, ‖w‖ ≤ 0.96 (max 0.9586) and ‖x − x̃‖ ≤ 1 (the simulated steady error is
    about 1.15), (16) asks for α1 > β1 = ‖M_2‖(‖A‖ ẽ⁺ + ‖B‖ w⁺): even in the paper's own
    orthonormal basis β1 ≈ 21 > α1 = 10.  The exact report says FAILS, and the observer converges."""
    f = lambda M: np.array([[float(v) for v in row] for row in M.coefficient_lists()[0]])  # noqa: E731
    A, B, C, D = (f(example1.A), f(example1.B), f(example1.C), f(example1.D))
    M2 = _orthonormal_molinari(A, B, C, D)
    beta_paper = np.linalg.norm(M2, 2) * (np.linalg.norm(A, 2) * 1.0 + np.linalg.norm(B, 2) * 0.96)
    assert beta_paper > 2 * P.GAINS[0][1]
    des = design_hierarchical_sta(example1, gains=P.GAINS, w_bound="0.96", e_bound=1)
    rep = des.gain_report
    assert not rep.holds and not rep.levels[0].holds and "conservative" in rep.reason
    assert rep.levels[0].beta >= beta_paper * 0.99  # an upper bound (Frobenius, another basis)
    assert rep.levels[0].alpha_margin < 1 and "not satisfied" in str(rep)


def test_gains_from_the_bounds_satisfy_the_condition_exactly_and_converge(example1):
    from fractions import Fraction

    des = design_hierarchical_sta(example1, w_bound="0.96", e_bound="1.2")
    rep = des.gain_report
    assert rep.holds and rep.theta == Fraction(1, 10)
    th = rep.theta
    for lv, (lam, alpha) in zip(rep.levels, des.gains, strict=True):
        assert alpha > lv.beta  # (16), and λ by its squared form: no square root
        assert lam**2 * (alpha - lv.beta) * (1 - th) ** 2 > 2 * (alpha + lv.beta) ** 2 * (1 + th) ** 2
        assert 1 <= lv.lambda_margin(th) < 1.01 and lv.alpha_margin >= 2
    # β1 bounds ‖M_2‖ (‖A‖ e + ‖B‖ w) from above (2-norms in floats, this design's M_2)
    f = lambda M: np.array([[float(v) for v in row] for row in M.coefficient_lists()[0]])  # noqa: E731
    beta1 = np.linalg.norm(f(des.M[1]), 2) * (np.linalg.norm(f(example1.A), 2) * 1.2 + np.linalg.norm(f(example1.B), 2) * 0.96)
    assert float(rep.levels[0].beta) >= beta1
    r = simulate_observer(des, t_final=4.0, dt=1e-3, w=P.w, u=P.u, x0=P.X0)
    assert r.error_norm()[r.t >= 2.0].max() < 2e-3  # measured 6.2e-4
    # given gains are checked, not replaced; bounds without w_bound are refused
    assert design_hierarchical_sta(example1, gains=P.GAINS, w_bound=1, e_bound=1).gains[0] == (15, 10)
    from uio_ring.errors import DomainError

    with pytest.raises(DomainError, match="e_bound"):
        design_hierarchical_sta(example1, w_bound=1)
    with pytest.raises(DomainError, match="theta"):
        design_hierarchical_sta(example1, w_bound=1, e_bound=1, theta=1)
    with pytest.raises(DomainError, match="go with w_bound"):
        design_hierarchical_sta(example1, e_bound=1)


@given(st.fractions(min_value=0, max_value=10**6))
def test_sqrt_up_is_an_upper_bound_within_1e_9(x):
    from uio_ring.design.sta_gains import sqrt_up

    s = sqrt_up(x)
    assert s * s >= x and float(s) - math.sqrt(x) < 1e-8 * max(1.0, math.sqrt(x))


@pytest.mark.parametrize(("options", "path"), [
    ("  w_bound: 1\n  e_bound: 1\n  theta: 2\n", "design.theta"),
    ("  w_bound: 1\n", "design.e_bound"),
    ("  K: [[1, 0, 0]]\n", "design.K"),
    ("  gains: [[15, 10]]\n", "design.gains"),
])
def test_cli_names_the_option_that_does_not_fit(tmp_path, capsys, options, path):
    """Exit 2, one line, at the option's spec path (not only ``design``)."""
    from pathlib import Path

    from uio_ring.cli import main

    text = (Path(__file__).resolve().parents[2] / "examples" / "bejarano2007_example1.yaml").read_text(encoding="utf-8")
    head = text[: text.index("design:")]
    spec = tmp_path / "s.yaml"
    spec.write_text(head + "design:\n  method: hierarchical-sta\n" + options, encoding="utf-8")
    code = main(["design", str(spec), "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and path in err, err
