"""Plant simulator: convergence order against closed-form solutions, and bad input."""

from __future__ import annotations

from functools import cache

import numpy as np
import pytest
import sympy as sp

from uio_ring.sim import SimulationError, simulate
from uio_ring.sim._blocks import BlockIntegrator
from uio_ring.sim.errors import DimensionError

from .conftest import ArraySystem


@cache
def method_of_steps(a, b, h, blocks, history):
    """Exact solution of ``x' = a x + b x(t − h)`` with constant history, block by block.

    On ``[(k−1)h, kh]``: ``x_k(t) = e^{a(t−(k−1)h)} x_k((k−1)h) + ∫ e^{a(t−s)} b x_{k−1}(s−h) ds``
    — polynomial times exponential pieces.  Returns the pieces as sympy expressions in t.
    """
    t, s = sp.symbols("t s", real=True)
    pieces = [sp.Integer(history)]
    for k in range(1, blocks + 1):
        prev = pieces[-1]
        start = prev.subs(t, (k - 1) * h)
        nxt = sp.exp(a * (t - (k - 1) * h)) * start + sp.integrate(
            sp.exp(a * (t - s)) * b * prev.subs(t, s - h), (s, (k - 1) * h, t)
        )
        pieces.append(sp.expand(nxt))
    return t, pieces


def exact_on_grid(a, b, h, blocks, history, t_grid):
    t, pieces = method_of_steps(a, b, h, blocks, history)
    out = np.empty_like(t_grid)
    for i, tj in enumerate(t_grid):
        k = min(max(int(np.ceil(tj / float(h) - 1e-12)), 1), blocks) if tj > 0 else 0
        out[i] = float(pieces[k].subs(t, tj)) if k else float(history)
    return out


def observed_orders(errors):
    e = np.asarray(errors)
    return np.log2(e[:-1] / e[1:])


def test_order_four_against_method_of_steps(scalar_dde):
    """Max error on [0, 3h] falls like dt⁴: order ≥ 3.7 on the last halvings (measured 3.86, 3.93)."""
    a, b, h = sp.Rational(-1, 2), sp.Rational(-3, 2), sp.Integer(1)
    errs = []
    for N in (16, 32, 64, 128):
        r = simulate(scalar_dde, h=1.0, t_final=3.0, dt=1.0 / N, x0=[1.0])
        coarse = r.t[::4]
        exact = exact_on_grid(a, b, h, 3, 1, coarse)
        errs.append(np.max(np.abs(r.x[0, ::4] - exact)))
    p = observed_orders(errs)
    assert np.all(p[1:] >= 3.7), (errs, p)
    assert p[0] >= 3.0, (errs, p)
    assert errs[-1] < 2e-10


def test_break_points_on_the_grid_keep_the_order():
    """A history that does not match x' at 0 (jump of x' at 0, of x'' at h, …): still order ≥ 3.7.

    x' = −x(t − 1), φ(t) = 1 + t on [−1, 0] (φ' = 1, but x'(0⁺) = −φ(−1) = 0).
    """
    sys = ArraySystem(A=[[[0.0]], [[-1.0]]], C=[[[1.0]]])
    t, s = sp.symbols("t s", real=True)
    # method of steps with a linear history
    pieces = {0: 1 + t}
    for k in range(1, 4):
        prev = pieces[k - 1]
        start = prev.subs(t, k - 1)
        pieces[k] = sp.expand(start - sp.integrate(prev.subs(t, s - 1), (s, k - 1, t)))
    exact = float(pieces[3].subs(t, 3))
    errs = [abs(simulate(sys, h=1, t_final=3, dt=1 / N, x0=lambda tt: 1 + tt).x[0, -1] - exact) for N in (8, 16, 32)]
    # the pieces are polynomials of degree ≤ 4: the cubic stencil is exact up to the φ-part
    assert max(errs) < 1e-12 or np.all(observed_orders(errs) >= 3.7), errs


def test_input_and_delayed_output_order():
    """x' = −x + x(t−h) + w(t−h), y = x(t) + 2 x(t−h) + w, w = sin(5t): Richardson order → 4."""
    sys = ArraySystem(
        A=[[[-1.0]], [[1.0]]], C=[[[1.0]], [[2.0]]], B=[[[0.0]], [[1.0]]], D=[[[1.0]]]
    )
    w = lambda t: np.sin(5 * np.asarray(t))  # noqa: E731
    ys = [simulate(sys, h=0.5, t_final=2.0, dt=0.5 / N, w=w, x0=[0.3]).y[0, -1] for N in (10, 20, 40, 80)]
    d = np.abs(np.diff(ys))
    p = np.log2(d[:-1] / d[1:])  # measured 3.47, 3.84
    assert p[0] >= 3.0 and p[-1] >= 3.7, d


def test_constant_coefficient_system_is_exact_for_polynomial_input():
    """x' = A0 x + w with w cubic: the exponential integrator with cubic stencils is exact."""
    A0 = np.array([[0.0, 1.0], [-4.0, -0.4]])
    sys = ArraySystem(A=[A0], C=[np.eye(2)], B=[np.eye(2)])
    w = lambda t: np.array([np.asarray(t) ** 3, 1.0 - np.asarray(t) ** 2])  # noqa: E731
    r = simulate(sys, h=0.25, t_final=1.0, dt=0.05, w=w, x0=[1.0, 0.0])
    fine = simulate(sys, h=0.25, t_final=1.0, dt=0.25 / 50, w=w, x0=[1.0, 0.0])
    assert np.max(np.abs(r.x[:, -1] - fine.x[:, -1])) < 1e-12


@pytest.mark.parametrize("N, nblocks, K", [(4, 23, 1), (50, 5, 1), (3, 11, 2), (40, 4, 2), (1, 9, 1)])
def test_block_evaluations_agree(N, nblocks, K):
    """The four evaluations of the block map (per block, per sub-block, per group of blocks,
    scan) agree; 23 blocks of 4 = groups of 8 plus a remainder, N = 50 = 2 sub-blocks of 25."""
    from uio_ring.numeric.progress import Progress

    A = np.array([[[-0.5, 1.0], [0.0, -2.0]], [[0.3, 0.0], [-1.0, 0.2]], [[0.1, -0.2], [0.0, 0.3]]])[: K + 1]
    X0 = np.zeros((K * N + nblocks * N + 1, 2))
    X0[: K * N + 1] = np.linspace(0, 1, K * N + 1)[:, None] * [1.0, -1.0]
    fin = np.sin(np.arange(nblocks * N + 1)[:, None] * [0.1, 0.05])
    outs = []
    for method in ("dense", "chunked", "sub", "super"):
        X = X0.copy()
        BlockIntegrator(A, N, 0.01, method=method).run(X, fin, nblocks, Progress(1, False))
        outs.append(X)
    for other in outs[1:]:
        assert np.max(np.abs(outs[0] - other)) < 1e-12 * np.max(np.abs(outs[0]))


def test_result_layout_and_labels(paper_system):
    r = simulate(paper_system, h=0.01, t_final=0.05, dt=0.001, w=lambda t: np.zeros((2, np.size(t))))
    assert r.t.shape == (51,) and r.x.shape == (4, 51) and r.y.shape == (3, 51) and r.w.shape == (2, 51)
    assert r.states["x[0]"] is not None and r.outputs[2].shape == (51,)
    assert r.N == 10 and r.t[-1] == pytest.approx(0.05)
    # zero input, zero history: the plant stays at rest
    assert np.all(r.x == 0)


def test_input_arrays_equal_callables(paper_system):
    """Inputs given as samples on the grid give the same run as the callable (zero before 0)."""
    f = lambda t: np.array([np.sin(30 * np.asarray(t)), np.asarray(t) ** 2])  # noqa: E731
    r1 = simulate(paper_system, h=0.01, t_final=0.2, dt=0.002, w=f)
    r2 = simulate(paper_system, h=0.01, t_final=0.2, dt=0.002, w=r1.w)
    # f(t) = 0 for t = 0 in both components and f is used at t < 0 only through δ: compare after 2h
    assert np.allclose(r1.x[:, -1], r2.x[:, -1], rtol=1e-3, atol=1e-6)


BAD = [
    (dict(dt=0.003), SimulationError, r"dt=0.003 is not h/N .*N = 3 .*N = 4"),
    (dict(dt=0.02), SimulationError, r"dt=0.02 is not h/N .*N = 1"),
    (dict(dt=-1), SimulationError, r"dt=-1 must be a positive"),
    (dict(x0=np.zeros((4, 3))), DimensionError, r"x0 has shape \(4, 3\); expected .*\(4, 11\)"),
    (dict(x0=[1.0, 2.0]), DimensionError, r"x0 has shape"),
    (dict(w=np.zeros((2, 7))), DimensionError, r"w has shape \(2, 7\); expected .*\(2, 51\)"),
    (dict(w=np.full((2, 51), np.nan)), SimulationError, r"w is not finite at component 0, sample 0"),
    (dict(w=lambda t: np.array([np.inf * np.asarray(t), 0 * np.asarray(t)])), SimulationError, r"w is not finite"),
    (dict(x0=lambda t: np.full((4, np.size(t)), np.nan)), SimulationError, r"x0 is not finite"),
    (dict(u=lambda t: t), DimensionError, r"u was given, but the system has no u inputs"),
    (dict(h=None), SimulationError, r"h is required"),
]


@pytest.mark.parametrize("kwargs, exc, match", BAD)
def test_bad_input(paper_system, kwargs, exc, match):
    args = dict(h=0.01, t_final=0.05, dt=0.001)
    args.update(kwargs)
    with pytest.raises(exc, match=match):
        simulate(paper_system, **args)


def test_h_must_agree_with_the_system():
    from uio_ring import DelaySystem

    sys = DelaySystem("[[d]]", "[[1]]", "[[1]]", "[[0]]", h="0.1")
    with pytest.raises(SimulationError, match=r"h=0.01 differs from the h=1/10 of sys"):
        simulate(sys, h=0.01, t_final=0.1, dt=0.001)
    assert simulate(sys, t_final=0.2, dt=0.01).h == pytest.approx(0.1)  # h taken from the system


def test_no_progress_output_in_tests(paper_system, capsys):
    simulate(paper_system, h=0.01, t_final=0.1, dt=0.001)
    assert capsys.readouterr().err == ""


def test_known_input_in_the_plant():
    """x' = −x + u(t − h), u ≡ 1 from t = 0 (zero before): x = 1 − e^{−(t−h)} for t ≥ h."""
    from uio_ring import DelaySystem

    sys = DelaySystem("[[-1]]", "[[0]]", "[[1]]", "[[0]]", E="[[d]]", F="[[0]]")
    r = simulate(sys, h=0.5, t_final=2.0, dt=0.05, u=np.ones((1, 41)))
    t = r.t[r.t >= 0.5]
    assert np.allclose(r.x[0, r.t >= 0.5], 1 - np.exp(-(t - 0.5)), atol=1e-7)
    assert np.all(r.x[0, r.t <= 0.5] == 0)


def test_constant_vector_input_has_no_jump():
    """A constant vector is constant for all t (also before 0): x' = −x + u(t − h), u ≡ 1, x(0) = 1."""
    from uio_ring import DelaySystem

    sys = DelaySystem("[[-1]]", "[[0]]", "[[1]]", "[[0]]", E="[[d]]", F="[[0]]")
    r = simulate(sys, h=0.5, t_final=2.0, dt=0.05, u=[1.0], x0=[1.0])
    assert np.allclose(r.x, 1.0, atol=1e-12)
