"""High-gain observer with output shaping (uio_ring.design.high_gain, uio_ring.verify.high_gain):
Example 3 of Grip & Saberi (2010) through its unique quantities, the certificate on random
sets, the registry entry, the float model through the engine, and the error decay with the
paper's μ = sin t (integrated here from the exact error matrices: the engine has no φ)."""

from __future__ import annotations

import random
from fractions import Fraction

import numpy as np
import pytest
import sympy
from analysis import paper004 as ex
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring import (
    DelaySystem,
    HighGainDesign,
    PolyMatrix,
    design_auto,
    design_high_gain,
    simulate_observer,
)
from uio_ring.design.methods import design_with, get_method
from uio_ring.errors import DimensionError, DomainError, NotObservableError, SpecError

K_STAR = ["0.9", "0.28", "0.04"]  # s^3 + 0.9 s^2 + 0.28 s + 0.04 = (s^2 + 0.4 s + 0.08)(s + 0.5)


def example_system() -> DelaySystem:
    return DelaySystem(ex.A, [], ex.C, None)


def example3(epsilon="0.3") -> HighGainDesign:
    return design_high_gain(example_system(), W=[ex.W1_EXAMPLE1], coefficients=[K_STAR], epsilon=epsilon)


def test_example3_gains_exact():
    d = example3()
    assert isinstance(d, HighGainDesign) and d.method == "high-gain"
    assert d.n_f == 1 and d.q == (3, 3)
    # K_z = [3, 1] (the paper prints [2 0], which does not follow from its own data)
    assert d.K_z == PolyMatrix([[3, 1]])
    q = Fraction
    assert d.K_x == PolyMatrix([[q(28, 9), 0], [q(40, 27), 0], [q(28, 9), 3], [q(40, 27), q(28, 9)],
                                [0, q(40, 27)]])
    cert = d.certificate()
    assert cert.ok, str(cert)
    assert d.filter_loop() == PolyMatrix([[-3]]) and d.filter_loop_hurwitz


def test_example3_spectrum_is_the_requested_one_over_epsilon():
    for eps in ("0.3", "1", "1/7"):
        d = example3(eps)
        e = Fraction(eps)
        M = sympy.Matrix(d.error_matrix().to_sympy())
        s = sympy.Symbol("lambda")
        cp = sympy.factor(M.charpoly(s).as_expr())
        want = ((s**2 + sympy.Rational(2, 5) / e * s + sympy.Rational(2, 25) / e**2)
                * (s + sympy.Rational(1, 2) / e)) ** 2
        assert sympy.expand(cp - want) == 0
        assert d.certificate()["spectrum of A_e − K C_e"].ok


def test_example3_K_scales_with_epsilon():
    """K(ε) = [[0.9/ε, 1], [0.28/ε², 0], [0.04/ε³, 0], [0.28/ε², 0.9/ε], [0.04/ε³, 0.28/ε²], [0, 0.04/ε³]]."""
    e = Fraction(1, 2)
    d = example3(e)
    k1, k2, k3 = (Fraction(x) for x in K_STAR)
    assert d.K == PolyMatrix([[k1 / e, 1], [k2 / e**2, 0], [k3 / e**3, 0], [k2 / e**2, k1 / e],
                              [k3 / e**3, k2 / e**2], [0, k3 / e**3]])


def test_admissible_set_needs_no_filter_and_poles_option():
    d = design_high_gain(DelaySystem(ex.A_E16, [], ex.C_E16, None), W=[ex.W_E16], poles=[-1, -2, -3, -4],
                         epsilon="1/2")
    assert d.n_f == 0 and d.q == (4, 3) and d.certificate().ok
    assert d.coefficients[0] == (10, 35, 50, 24) and d.coefficients[1] == (6, 11, 6)


def test_example2_gets_two_integrators():
    d = design_high_gain(example_system(), W=[ex.W1_EXAMPLE2], epsilon="1/3")
    assert d.n_f == 2 and d.q == (4, 3) and d.certificate().ok


def test_filter_loop_need_not_be_hurwitz():
    """The paper asserts A_z − K_z C_z is always Hurwitz.  Counterexample: two chains of 5,
    the top of chain 2 driven by the bottom of chain 1 (Example 2's pattern): shaping adds
    four integrators on y_2; with a Hurwitz degree-9 chain polynomial whose first four
    coefficients are not, A_z − K_z C_z is unstable — while the observer (22) is stable
    (its matrix is similar to A_e − K C_e) and the error decays through the engine."""
    n = 10
    A = [[1 if (j == i + 1 and i != 4) else 0 for j in range(n)] for i in range(n)]
    C = [[1] + [0] * 9, [0] * 5 + [1] + [0] * 4]
    W = [[0] * n for _ in range(n)]
    W[5][4] = 1
    # (s + 2)(s² + s + 3)(2s² + s + 8)(5s² + 4s + 65)(5s² + 4s + 75)/50 for the long chain, (s + 1)^5
    coefficients = [["51/10", "2237/50", "7997/50", "15748/25", "78281/50", "160191/50", "260003/50", "25113/5",
                     "4680"], [5, 10, 10, 5, 1]]
    d = design_high_gain(DelaySystem(A, [], C, None), W=[W], coefficients=coefficients, epsilon=1)
    assert (d.q, d.n_f) == ((9, 5), 4)
    assert d.certificate().ok
    assert not d.filter_loop_hurwitz and d.to_dict()["filter_loop_hurwitz"] is False
    assert max(np.linalg.eigvals(np.array(d.filter_loop().to_sympy(), dtype=float)).real) > 0.5
    assert max(np.linalg.eigvals(d.numeric().F).real) == pytest.approx(-0.25)
    res = simulate_observer(d, t_final=30.0, dt=1e-3, x0=np.ones(n))
    assert np.abs(res.error[:, -1]).max() < 0.05 * np.abs(res.error[:, 0]).max()


def test_split_example_refused_with_the_cap_message():
    with pytest.raises(NotObservableError, match="no filter found within order 5") as info:
        design_high_gain(example_system(), W=ex.split_example1())
    assert not info.value.report.found


@pytest.mark.parametrize("kwargs, err, match", [
    ({"epsilon": 0}, DomainError, r"\(0, 1\]"),
    ({"epsilon": "3/2"}, DomainError, r"\(0, 1\]"),
    ({"poles": [-1, 2, -3]}, DomainError, "negative"),
    ({"poles": [-1]}, DimensionError, "at least 3"),
    ({"coefficients": [[1, 1]]}, DimensionError, "expected 3"),
    ({"coefficients": [[1, 1, 1]] * 3}, DimensionError, "one per chain"),
    ({"coefficients": [[1, 1, 1]]}, DomainError, "Hurwitz"),  # s^3 + s^2 + s + 1 has roots ±j
    ({"poles": [-1, -2, -3], "coefficients": [K_STAR]}, DomainError, "not both"),
    ({"W": [[[1]]]}, DimensionError, r"W\[0\] is 1×1"),
])
def test_option_errors(kwargs, err, match):
    kw = {"W": [ex.W1_EXAMPLE1], **kwargs}
    with pytest.raises(err, match=match):
        design_high_gain(example_system(), **kw)


@pytest.mark.parametrize("sys, match", [
    (DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None), "unknown input"),
    (DelaySystem("[[0, 0], [0, 0]]", [], "[[1, 0]]", None), "not observable"),
    (DelaySystem("[[d]]", [], "[[1]]", None), "delays"),
])
def test_refused_systems(sys, match):
    with pytest.raises(NotObservableError, match=match):
        design_high_gain(sys)


def test_registry_entry_and_spec_options():
    m = get_method("high-gain")
    assert m.delay_free_only and m.design_class is HighGainDesign
    opts = m.read_options({"W": [ex.W1_EXAMPLE1], "coefficients": [K_STAR], "epsilon": "0.3", "max_order": 3})
    assert opts["epsilon"] == Fraction(3, 10) and opts["W"][0][0][1] == -1
    d = m.design(example_system(), **opts)
    assert d.K_z == PolyMatrix([[3, 1]]) and m.certificate(d).ok
    with pytest.raises(SpecError, match="non-negative integer"):
        m.read_options({"max_order": -1})
    assert m.options[0].schema()["type"] == "array"


def test_registry_applies_and_design_with():
    m = get_method("high-gain")
    sys = DelaySystem("[[0, 1], [0, 0]]", [], "[[1, 0]]", None)
    holds, report, _ = m.applies(sys)
    assert holds and report.observability_indices == (2,) and "applies" in report.summary
    holds, _, reason = m.applies(DelaySystem("[[d]]", [], "[[1]]", None))
    assert not holds and "delay-free" in reason
    d = design_with("high-gain", sys, W=[[[0, 0], [1, 0]]], epsilon="1/2")
    assert d.certificate().ok
    with pytest.raises(SpecError, match="do not apply"):
        design_with("high-gain", sys, gains=[1])
    # auto passes the options a method takes; the first method that applies wins
    assert design_auto(sys, epsilon="1/2").design.certificate().ok


def test_known_inputs_and_feedthrough():
    sys = DelaySystem("[[0, 1], [-1, 0]]", [], "[[1, 0]]", None, E="[[0], [1]]", F="[[2]]")
    d = design_high_gain(sys, poles=[-2, -3], epsilon="1/2")
    assert d.certificate().ok
    res = simulate_observer(d, t_final=6.0, dt=1e-3, u=lambda t: np.sin(3 * t), x0=[1.0, -1.0])
    assert np.max(np.abs(res.error[:, -500:])) < 1e-3


def test_to_dict_latex_repr_and_save_load(tmp_path):
    from uio_ring import load_design, save_design

    d = example3()
    data = d.to_dict()
    assert data["K_z"] == [["3", "1"]] and data["filter_order"] == 1
    assert r"\varepsilon = 3/10" in d.to_latex() and "K_z" in d.to_latex()
    assert "n_f=1" in repr(d) and "K_x" in str(d)
    paths = save_design(d, tmp_path / "hg", formats=("json",))
    assert load_design(paths[0]) == d


def test_engine_on_the_linear_part_decays_at_the_designed_rate():
    """μ = 0: the error is governed by A_e − K C_e, slowest mode Re = −0.2/ε."""
    d = example3("0.3")
    res = simulate_observer(d, t_final=12.0, dt=1e-3, x0=[1.0, -0.5, 0.3, 0.2, -0.1])
    err = np.linalg.norm(res.error, axis=0)
    t = res.time
    late = (t > 4) & (err > 1e-12)
    rate = -np.polyfit(t[late], np.log(err[late]), 1)[0]
    assert 0.2 / 0.3 * 0.8 < rate < 0.2 / 0.3 * 1.6
    assert err[-1] < 1e-2 * err[0]  # double poles: t·e^{−0.2 t/ε} terms


def _floquet_radius(d: HighGainDesign) -> float:
    """Spectral radius of the monodromy matrix (period 2π) of the Example 3 error (21) with
    μ = sin t: e' = (A_e − K C_e + sin(t) W_e1) e, integrated here from the exact matrices."""
    from scipy.integrate import solve_ivp

    Ee = np.array(d.error_matrix().to_sympy().evalf(), dtype=float)
    We = np.array(d.W_e[0].to_sympy(), dtype=float)
    n = Ee.shape[0]

    def rhs(t, v):
        return ((Ee + np.sin(t) * We) @ v.reshape(n, n)).ravel()

    sol = solve_ivp(rhs, (0, 2 * np.pi), np.eye(n).ravel(), rtol=1e-10, atol=1e-12, method="DOP853")
    return float(np.max(np.abs(np.linalg.eigvals(sol.y[:, -1].reshape(n, n)))))


@pytest.mark.parametrize("eps, radius", [("0.3", 0.0188), ("1", 0.524)])
def test_error_decays_with_mu_sin_t(eps, radius):
    """Stable at ε = 0.3 (as the paper says) and also at ε = 1: the paper's claim of
    instability at ε = 1 does not reproduce with the gain its own data give (K_z = [3, 1]).
    The error shrinks by the Floquet multiplier per period 2π: rate = −ln(ρ)/(2π)."""
    rho = _floquet_radius(example3(eps))
    assert rho == pytest.approx(radius, rel=0.02)
    rate = -np.log(rho) / (2 * np.pi)
    assert rate > 0.1


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10**6), upward=st.booleans())
def test_certificate_on_random_sets(seed, upward):
    rng = random.Random(seed)
    q = rng.choice([(2, 1), (3, 2), (2, 2)])
    A, C, W = ex.random_canonical(q, 1, rng, upward=upward)
    A2, C2, W2 = ex.transform(A, C, W, ex.unimodular(sum(q), rng), ex.unimodular(len(q), rng))
    sys = DelaySystem(A2, [], C2, None)
    try:
        d = design_high_gain(sys, W=W2, epsilon=Fraction(rng.randint(1, 10), 10), max_order=4)
    except NotObservableError as exc:
        assert "no filter found within order 4" in str(exc)
        return
    cert = d.certificate()
    assert cert.ok, str(cert)
    assert d.n_f == 0 or upward


@pytest.mark.parametrize("eps, dt, periods, floquet", [("0.3", 2e-3, 3, 0.0188), ("1", 5e-3, 5, 0.524)])
def test_engine_with_the_nonlinear_plant_mu_sin_t(eps, dt, periods, floquet):
    """Example 3 through the one engine: plant x' = A x + sin(t) W_1 x, observer (22) with
    φ(t, x̂) = sin(t) W_1 x̂.  The fitted decay rate of |x − x̂| is near the Floquet rate
    −ln ρ / 2π (ρ from the monodromy matrix above) — at ε = 0.3 and at ε = 1."""
    W1 = np.array(ex.W1_EXAMPLE1, dtype=float)
    d = example3(eps)
    res = simulate_observer(d, t_final=periods * 2 * np.pi, dt=dt, x0=[1.0, -0.5, 0.3, 0.2, -0.1],
                            phi=lambda t, x: np.sin(t) * (W1 @ x))
    err = np.linalg.norm(res.error, axis=0)
    sel = res.time > 2 * np.pi
    rate = -np.polyfit(res.time[sel], np.log(err[sel]), 1)[0]
    expected = -np.log(floquet) / (2 * np.pi)
    assert 0.65 * expected < rate < 1.9 * expected
    assert err[-1] < 0.25 * err[0]


def test_engine_phi_errors():
    from uio_ring.errors import NotSupportedError, SimulationError

    d = example3()
    with pytest.raises(SimulationError, match="callable"):
        simulate_observer(d, t_final=0.1, dt=1e-2, phi=3)
    with pytest.raises(DimensionError, match="shape"):
        simulate_observer(d, t_final=0.1, dt=1e-2, phi=lambda t, x: x[:2])
    with pytest.raises(NotSupportedError, match="open loop"):
        simulate_observer(d, t_final=0.1, dt=1e-2, phi=lambda t, x: x, exact_start=True)
    nf = design_auto(DelaySystem("[[0, 1], [0, 0]]", [], "[[1, 0]]", None)).design  # no phi_map
    with pytest.raises(SimulationError, match="phi_map"):
        simulate_observer(nf, t_final=0.1, dt=1e-2, phi=lambda t, x: 0 * x)


def test_example_spec_through_the_cli(tmp_path, capsys):
    from pathlib import Path

    from uio_ring.cli import main
    from uio_ring.spec import load_design

    spec = Path(__file__).resolve().parents[2] / "examples" / "grip_saberi_example3.yaml"
    assert main(["design", str(spec), "--out", str(tmp_path)]) == 0
    assert "method high-gain, certificate ok" in capsys.readouterr().out
    d = load_design(tmp_path / "grip_saberi_example3.json")
    assert isinstance(d, HighGainDesign) and d.K_z == PolyMatrix([[3, 1]]) and d.K == example3().K
    assert main(["check", str(spec)]) == 0


def test_theorem1_bound_example3():
    """P_i of H_i = A_3 − K* C_3 (the paper's Lyapunov equation), and ε* with μ_max = 1: the 2-norm
    version gives 1/(4·104.06) ≈ 2.40e−3; the exact rational bound (1-norms) is a little smaller."""
    from uio_ring.design.high_gain import lyapunov_solution

    H = PolyMatrix([["-9/10", 1, 0], ["-7/25", 0, 1], ["-1/25", 0, 0]])
    P = lyapunov_solution(H)
    assert P @ H + H.T @ P == -PolyMatrix.identity(3) and P == P.T
    Pf = np.array(P.to_sympy(), dtype=float)
    assert np.linalg.norm(Pf, 2) == pytest.approx(104.0645, rel=1e-5)
    d = design_high_gain(example_system(), W=[ex.W1_EXAMPLE1], coefficients=[K_STAR], epsilon="0.3", mu_bounds=[1])
    b = d.epsilon_bound
    assert isinstance(b, Fraction) and b == 1 / (4 * Fraction(np.abs(Pf).sum(axis=0).max()).limit_denominator(10**6))
    assert 2.2e-3 < b < 1 / (4 * np.linalg.norm(Pf, 2)) < 2.41e-3
    assert "epsilon_bound=" in repr(d) and d.to_dict()["epsilon_bound"] == str(b)
    assert example3().epsilon_bound is None
    linear = design_high_gain(DelaySystem("[[0, 1], [0, 0]]", [], "[[1, 0]]", None), mu_bounds=[])
    assert linear.epsilon_bound == 1  # no nonlinearity: any ε in (0, 1]
    with pytest.raises(DimensionError, match="mu_bounds"):
        design_high_gain(example_system(), W=[ex.W1_EXAMPLE1], mu_bounds=[1, 2])
    assert get_method("high-gain").read_options({"mu_bounds": [1]})["mu_bounds"] == (1,)


def test_W_from_phi_as_sympy_expressions():
    import sympy

    names = ["x11", "x12", "x21", "x22", "x23"]
    x11, x12, x21, x22, x23 = (sympy.Symbol(n) for n in names)
    mu = sympy.sin(sympy.Symbol("t"))
    phi = [mu * (-x12 + x22), mu * x23, mu * (-x12 + x22), mu * (x11 + x23), mu * x12]
    sys = DelaySystem(ex.A, [], ex.C, None, state_names=names)
    d = design_high_gain(sys, phi=phi, coefficients=[K_STAR], epsilon="0.3")
    assert d.W == (PolyMatrix(ex.W1_EXAMPLE1),) and d.K_z == PolyMatrix([[3, 1]])
    with pytest.raises(DomainError, match="not both"):
        design_high_gain(sys, phi=phi, W=[ex.W1_EXAMPLE1])


def test_spec_nonlinearity_is_read_and_simulated():
    from pathlib import Path

    from uio_ring.cli.spec_commands import _simulate
    from uio_ring.design.methods import design_with
    from uio_ring.spec import load_spec_text

    path = Path(__file__).resolve().parents[2] / "examples" / "grip_saberi_example3.yaml"
    text = path.read_text(encoding="utf-8").replace("t_final: 20", "t_final: 4")
    spec = load_spec_text(text)
    assert spec.simulate.nonlinearity[1] == "sin(t)*x23"
    phi = spec.simulate.nonlinearity_function()
    assert phi(np.pi / 2, np.arange(5.0)).tolist() == (np.array(ex.W1_EXAMPLE1) @ np.arange(5.0)).tolist()
    d = design_with(spec.design.method, spec.system, **spec.design.options)
    res = _simulate(d, spec, False)
    W1 = np.array(ex.W1_EXAMPLE1, dtype=float)
    ref = simulate_observer(d, t_final=4.0, dt=0.002, x0=[1, -0.5, 0.3, 0.2, -0.1],
                            phi=lambda t, x: np.sin(t) * (W1 @ x))
    assert np.allclose(res.error, ref.error)
    bad = text.replace('"sin(t)*x23"', '"sin(t)*x24"')
    with pytest.raises(SpecError, match=r"unknown name 'x24'") as info:
        load_spec_text(bad)
    assert info.value.path == "simulate.nonlinearity[1]"
    with pytest.raises(SpecError, match="4 expression"):
        load_spec_text(text.replace('"sin(t)*x12"]', ']').replace(', ]', ']'))
