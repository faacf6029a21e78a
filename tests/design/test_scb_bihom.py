"""The bi-homogeneous observers of method 'scb' (Tranninger et al. 2021, §5.3–5.4): Moreno's
injection (identity with Levant's, oddness, monotonicity), the exponent ranges, our gain rule,
the certificate, fixed- and finite-time convergence through the one engine, spec errors."""

from __future__ import annotations

import math
import subprocess
import sys as _sys
from dataclasses import replace
from fractions import Fraction as Fr
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring import DelaySystem
from uio_ring.design.bihom import exponents, zero_limit_coefficients
from uio_ring.design.red_gains import levant_gains
from uio_ring.design.scb import design_scb
from uio_ring.errors import OptionError, SpecError
from uio_ring.numeric.bihom import (
    chain_exponents,
    phi_values,
    phi_values_and_slopes,
    solve_bihom_chain,
)
from uio_ring.ring.qmatrix import QMatrix as Q
from uio_ring.sim.engine import simulate_observer

_sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from analysis.paper003 import system as paper003  # noqa: E402

# strongly observable (n_a = 0): a b chain of length 2 (no input) and a d chain of length 3
STRONG = DelaySystem("[[0,1,0,0,0],[0,0,0,0,0],[0,0,0,1,0],[0,0,0,0,1],[0,0,0,0,0]]", "[[0],[0],[0],[0],[1]]",
                     "[[1,0,0,0,0],[0,0,1,0,0]]", None)
X0 = np.array([1.0, -1, 0.5, 0, 0.2])
V = np.array([1.0, 1, 1, -1, 1])


def _w(t):
    return np.atleast_2d(np.cos(2 * np.asarray(t, float)))  # |w| ≤ 1


def _settle(t: np.ndarray, e: np.ndarray, tol: float = 1e-2) -> float:
    """The first time after which every component of e stays below tol (inf: never)."""
    bad = np.nonzero(np.max(np.abs(e), axis=0) >= tol)[0]
    if bad.size == 0:
        return 0.0
    return np.inf if bad[-1] == t.size - 1 else float(t[bad[-1] + 1])


def _errors(d, scale: float, t_final: float, dt: float = 2e-3, check: bool = True) -> tuple[np.ndarray, np.ndarray]:
    res = simulate_observer(d, t_final=t_final, dt=dt, w=_w, x0=X0, x_hat0=X0 + scale * V, progress=False,
                            check=check)
    Tsi = np.linalg.inv(np.array(Q(d.scb.Ts).tolist(), float))
    return res.t, Tsi @ (res.x - res.x_hat)


# -- Φ ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("q", [1, 2, 3, 4, 5])
def test_levant_identity(q):
    """d0 = d_inf = −1: Φ_j = ⌈z⌋^{(q−j)/q} — the exponent product exactly, the values to rounding."""
    for j in range(1, q + 1):
        prod = Fr(1)
        for p in exponents(q, Fr(-1))[:j]:
            prod *= p
        assert prod == Fr(q - j, q)
    p0, pi = chain_exponents(q, -1.0, -1.0)
    for z in (-7.3, -1e-6, 0.25, 3.0, 1e5):
        got = phi_values(z, p0, pi, 0.3)
        want = [np.sign(z) * abs(z) ** ((q - j) / q) for j in range(1, q + 1)]
        assert np.allclose(got, want, rtol=1e-13, atol=0)
    assert zero_limit_coefficients(q, Fr(-1), Fr(-1), Fr(1, 3)) == (1.0,) * q


_PROFILES = st.sampled_from([(-1.0, -1.0), (-1.0, -0.5), (-1.0, 0.2), (-0.5, 0.3), (-0.2, 0.0), (-0.9, 0.45)])


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 3), _PROFILES, st.floats(0.05, 0.95), st.floats(1e-6, 1e4), st.floats(1e-6, 1e4))
def test_phi_odd_and_increasing(q, prof, mu, a, b):
    p0, pi = chain_exponents(q, *prof)
    lo, hi = min(a, b), max(a, b)
    assert phi_values(-a, p0, pi, mu) == [-v for v in phi_values(a, p0, pi, mu)]
    assert all(x <= y for x, y in zip(phi_values(lo, p0, pi, mu), phi_values(hi, p0, pi, mu), strict=True))
    # the slope of the chain rule against a difference quotient
    vals, slopes = phi_values_and_slopes(a, p0, pi, mu)
    h = 1e-4 * a  # truncation error ~(h/a)² relative: far below the tolerance
    num = (np.array(phi_values(a + h, p0, pi, mu)) - np.array(phi_values(a - h, p0, pi, mu))) / (2 * h)
    # the quotient's rounding error, eps·|Φ|/h, dominates where a sign term (slope 0) sits beside
    # a small slope: e.g. q = 1, profile (−1, 0.2), a = 6e-5
    rounding = 4 * np.finfo(float).eps * np.abs(vals) / h
    assert np.all(np.abs(slopes - num) <= 1e-5 * np.abs(num) + 1e-9 + rounding)


@settings(max_examples=80, deadline=None)
@given(st.integers(1, 3), _PROFILES, st.floats(0.05, 0.95), st.floats(-1e4, 1e4).filter(lambda x: abs(x) > 1e-30),
       st.lists(st.floats(0.01, 50), min_size=3, max_size=3))
def test_implicit_chain_solution(q, prof, mu, a, coef):
    """σ + Σ coef_k Φ_k(σ) ∋ a: σ = 0 exactly inside the jump, else the residual vanishes."""
    p0, pi = chain_exponents(q, *prof)
    c = coef[:q]
    sig, v = solve_bihom_chain(a, c, p0, pi, mu)
    if sig == 0.0:
        w0 = 1.0 if prof == (-1.0, -1.0) else (mu if prof[0] == -1.0 else 0.0)
        assert abs(a) <= c[-1] * w0 and v == a
    else:
        def lhs(s):
            return s + sum(ck * f for ck, f in zip(c, phi_values(s, p0, pi, mu), strict=True))

        # the residual vanishes, or σ is the root rounded to a float: a lies between the left-hand
        # sides at σ's neighbouring floats (near 0 the nested powers Φ_q ~ |σ|^0.04 are so steep
        # that the root of a tiny a is below the smallest subnormal)
        res = lhs(sig) - a
        below, above = sorted((lhs(math.nextafter(sig, -math.inf)), lhs(math.nextafter(sig, math.inf))))
        assert abs(res) <= 1e-11 * max(1.0, abs(a)) or below <= a <= above
        assert np.sign(sig) == np.sign(a)


def test_chain_root_among_the_subnormals():
    """A steep profile puts the root of a tiny ``a`` below the smallest subnormal step: Newton's
    correction rounds to nothing two floats away; the answer is the float the root rounds to."""
    p0, pi = chain_exponents(3, -0.9, 0.45)
    c = [1.0, 1.0, 9.0]

    def lhs(s):
        return s + sum(ck * f for ck, f in zip(c, phi_values(s, p0, pi, 0.5), strict=True))

    sig, _ = solve_bihom_chain(1e-12, c, p0, pi, 0.5)
    assert sig > 0.0 and lhs(math.nextafter(sig, -math.inf)) <= 1e-12 <= lhs(sig)
    sig, _ = solve_bihom_chain(-1e-12, c, p0, pi, 0.5)
    assert sig < 0.0 and lhs(sig) <= -1e-12 <= lhs(math.nextafter(sig, math.inf))


# -- design --------------------------------------------------------------------------------------
def test_dbho_design_gains_and_certificate():
    d = design_scb(paper003(), poles_b=[-8, -6], input_ranges=[[-2, 1], [0, 1]], d_observer="dbho")
    assert d.d_profile == (-1, Fr(2, 5), Fr(1, 2))  # default: 4/5 of 1/(max q − 1) = 1/2
    cert = d.certificate()
    assert cert.ok, str(cert)
    # our rule: at the origin the chains are Levant's with Theorem 2's gains (κ_j c_j = Levant's)
    for ks, qi, D in zip(d.kappa, d.scb.q, d.Delta_d, strict=True):
        cs = zero_limit_coefficients(qi, *d.d_profile)
        assert np.allclose([float(k) * c for k, c in zip(ks, cs, strict=True)],
                           [float(x) for x in levant_gains(qi, D)], rtol=1e-11)
        assert Fr(1, 2) * ks[-1] == Fr(11, 10) * D  # exact: the sign term dominates by 10 %
    # d_inf = −1: exactly the HOSMO (same gains, same numbers through the engine)
    lev = design_scb(paper003(), poles_b=[-8, -6], input_ranges=[[-2, 1], [0, 1]], d_observer="dbho", d_inf=-1)
    hos = design_scb(paper003(), poles_b=[-8, -6], input_ranges=[[-2, 1], [0, 1]])
    assert lev.kappa == hos.kappa
    y = np.vstack([np.sin(np.arange(300) * 0.01), np.cos(np.arange(300) * 0.02), np.arange(300) * 1e-3])
    assert np.array_equal(lev.numeric().stepper(0.01).run(y), hos.numeric().stepper(0.01).run(y))


def test_certificate_catches_bad_profiles():
    d = design_scb(STRONG, poles_b=[-2, -2], input_bounds=[1], d_observer="dbho", b_observer="cbho")
    assert d.certificate().ok
    bad = replace(d, d_profile=(Fr(-1), Fr(1), Fr(1, 2)))  # d_inf above 1/(q − 1) = 1/2
    assert not bad.certificate()["Theorem 4: DBHO exponents"].ok
    bad = replace(d, b_profile=(Fr(-1), Fr(1, 2), Fr(1, 2)))  # d0 = −1 is not continuous
    assert not bad.certificate()["Theorem 3: CBHO exponents"].ok
    weak = replace(d, kappa=((Fr(4), Fr(6), Fr(3, 2)),))  # μ κ_q = 3/4 < Δ = 1
    assert not weak.certificate()["DBHO: mu κ_{i,q_i} > Δ_{d,i}"].ok


@pytest.mark.parametrize(("kw", "option", "match"), [
    ({"d_observer": "dbho", "d_inf": 0}, "d_inf", "linear at infinity"),
    ({"d_observer": "dbho", "d_inf": Fr(1, 2)}, "d_inf", r"not below 1/\(q_i - 1\) = 1/2"),
    ({"d_observer": "dbho", "d_inf": -2}, "d_inf", "below -1"),
    ({"d_observer": "dbho", "mu": 1}, "mu", r"\(0, 1\)"),
    ({"b_observer": "cbho", "b_d0": -1}, "b_d0", "-1 < d0 < 0"),
    ({"b_observer": "cbho", "b_d_inf": 1}, "b_d_inf", "0 < d_inf < min 1/"),
    ({"d_inf": Fr(1, 4)}, "d_inf", "option of d_observer: dbho"),
    ({"b_observer": "cbho", "poles_b": [-1, 2]}, "poles_b", "negative poles"),
])
def test_refused_profiles(kw, option, match):
    with pytest.raises(OptionError, match=match) as exc:
        design_scb(STRONG, **{"poles_b": [-2, -2], "input_bounds": [1], **kw})
    assert exc.value.option == option


def test_spec_error_names_the_option(tmp_path):
    from uio_ring.design.methods import get_method

    m = get_method("scb")
    assert m.read_options({"d_observer": "dbho", "d_inf": "1/4", "mu": "1/3"})["d_inf"] == Fr(1, 4)
    with pytest.raises(SpecError) as exc:
        m.read_options({"b_d0": "x"})
    assert exc.value.path == "design.b_d0"
    spec = tmp_path / "s.yaml"
    spec.write_text("system:\n  A: [[0, 1], [0, 0]]\n  B: [[0], [1]]\n  C: [[1, 0]]\n"
                    "design:\n  method: scb\n  d_observer: dbho\n  input_bounds: [1]\n  d_inf: 2\n")
    r = subprocess.run([_sys.executable, "-m", "uio_ring.cli", "design", str(spec)], capture_output=True, text=True)
    assert r.returncode == 2, r.stdout + r.stderr
    assert "design.d_inf" in r.stderr and "1/(q_i - 1)" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_design_round_trips_through_design_files():
    from uio_ring.spec.designs import design_from_data, design_to_data

    d = design_scb(STRONG, poles_b=[-2, -2], input_bounds=[1], d_observer="dbho", b_observer="cbho", mu="1/3")
    assert design_from_data(design_to_data(d)) == d
    m = d.numeric()
    from uio_ring.numeric.model import ObserverModel

    again = ObserverModel.from_dict(m.to_dict())
    assert again.injection.profiles == m.injection.profiles


# -- convergence through the engine ------------------------------------------------------------
SCALES = (1.0, 1e2, 1e4)


@pytest.fixture(scope="module")
def settle_times():
    """Settle times (|e| < 1e-2 for good) of the x_b and x_d errors over the initial error's size."""
    designs = {
        "bihom": design_scb(STRONG, poles_b=[-2, -2], input_bounds=[1], d_observer="dbho", b_observer="cbho"),
        "linear+hosmo": design_scb(STRONG, poles_b=[-2, -2], input_bounds=[1], d_observer="hosmo"),
    }
    out = {}
    for name, d in designs.items():
        rows = []
        for sc in SCALES:
            # a fixed-time observer peaks without bound as dt shrinks (its injection grows like |e|^(1+d_inf)
            # at infinity), so the engine's accuracy check rightly calls the transient unresolved for large
            # errors; the settle time is what is measured, and its convergence in dt is tested below
            t, e = _errors(d, sc, 30.0, check=False)
            rows.append((_settle(t, e[:2]), _settle(t, e[2:])))
        out[name] = rows
    return out


def test_fixed_time_settle_times_converge_in_dt():
    """The settle times of the bi-homogeneous observers are numerically converged (dt vs dt/2), although
    the peak of the transient is not: it grows as dt shrinks."""
    d = design_scb(STRONG, poles_b=[-2, -2], input_bounds=[1], d_observer="dbho", b_observer="cbho")
    got = []
    for dt in (2e-3, 1e-3):
        t, e = _errors(d, 1e4, 25.0, dt=dt, check=False)
        got.append((_settle(t, e[:2]), _settle(t, e[2:]), np.max(np.abs(e))))
    (b1, d1, p1), (b2, d2, p2) = got
    assert abs(b1 - b2) < 0.05 and abs(d1 - d2) < 0.2, got
    assert p2 > 2 * p1  # the peak is not resolved: it grows as dt halves


def test_fixed_time_dbho_and_cbho(settle_times):
    """Strongly observable: the bi-homogeneous observers settle within a bound that does not grow
    with the initial error; the HOSMO's (and Luenberger's) settle times grow with it."""
    bi, lin = settle_times["bihom"], settle_times["linear+hosmo"]
    tb = [r[0] for r in bi]
    td = [r[1] for r in bi]
    assert max(td) < 20.0 and max(tb) < 5.0, bi
    # from 1e2 to 1e4 (the part at infinity dominates) the settle time hardly moves
    assert td[2] - td[1] < 3.0 and tb[2] - tb[1] < 1.0, bi
    # Levant's differentiator: settle time grows (linearly in the last error), beyond the horizon here
    ld = [r[1] for r in lin]
    assert ld[0] < 10.0 and ld[1] > 30.0 and ld[2] > 30.0, lin
    # Luenberger: logarithmic growth, each factor 100 costs the same time
    lb = [r[0] for r in lin]
    assert lb[1] - lb[0] > 2.0 and lb[2] - lb[1] > 2.0, lin


def test_finite_time_dbho():
    """d_inf < 0: finite time, the error vanishes to the discretisation's accuracy (not only decays),
    and bigger errors take longer (no fixed-time bound)."""
    d = design_scb(STRONG, poles_b=[-2, -2], input_bounds=[1], d_observer="dbho", d_inf=Fr(-1, 2))
    assert d.certificate().ok
    t, e = _errors(d, 1.0, 8.0, dt=1e-3)
    ts = _settle(t, e[2:])
    assert ts < 4.0
    late = t >= ts + 1
    # sliding: the first error is O(dt³), far below an exponential tail's
    assert np.max(np.abs(e[2, late])) < 1e-6
    t2, e2 = _errors(d, 1e2, 8.0, dt=1e-3)
    assert _settle(t2, e2[2:]) > ts


def test_paper_example_with_dbho_and_cbho():
    """Paper 003's example (n_a = 1: asymptotic overall): e_a still decays exactly like e^{−10t};
    the DBHO chains settle as the HOSMO's do: max |e_d| < 1e-2 for t ≥ 7 s."""
    d = design_scb(paper003(), poles_b=[-8, -6], input_ranges=[[-2, 1], [0, 1]], d_observer="dbho",
                   b_observer="cbho")
    x0 = np.array([1, -0.1, 2, -0.3, 0.5, 0.2, -0.5, -0.2])

    def w(t):
        t = np.asarray(t, float)
        return np.array([1.5 * np.sin(t) + 0.5, ((t >= 1) & (t < 4)).astype(float)])

    res = simulate_observer(d, t_final=10.0, dt=1e-3, w=w, x0=x0, x_hat0=np.zeros(8), progress=False)
    e = np.linalg.inv(np.array(Q(d.scb.Ts).tolist(), float)) @ (res.x - res.x_hat)
    assert np.max(np.abs(e[0] - e[0, 0] * np.exp(-10 * res.t))) < 1e-5  # O(dt²) forcing interpolation
    late = res.t >= 7
    assert np.max(np.abs(e[1:, late])) < 1e-2
