"""W_k from φ (uio_ring.analysis.jacobian_basis): the decomposition is exact, the W_k are
independent, and the paper's Examples 1–2 give one W each (so shaping succeeds)."""

from __future__ import annotations

import pytest
import sympy

from analysis import paper004 as ex
from uio_ring import PolyMatrix, shape
from uio_ring.analysis import jacobian_basis
from uio_ring.errors import DimensionError, DomainError

x = sympy.symbols("x11 x12 x21 x22 x23")
t = sympy.Symbol("t")
mu = sympy.Function("mu")(t)


def _rebuilt(jb):
    return sum((z * sympy.Matrix(W.to_sympy()) for z, W in zip(jb.zeta, jb.W, strict=True)),
               sympy.zeros(*jb.jacobian.shape))


def test_example1_one_W():
    x11, x12, x21, x22, x23 = x
    phi = [mu * (-x12 + x22), mu * x23, mu * (-x12 + x22), mu * (x11 + x23), mu * x12]
    jb = jacobian_basis(phi, x)
    assert jb.W == (PolyMatrix(ex.W1_EXAMPLE1),) and jb.zeta == (mu,)
    assert sympy.simplify(_rebuilt(jb) - jb.jacobian) == sympy.zeros(5, 5)
    r = shape(ex.A, ex.C, jb.W)
    assert r.found and r.order == 1


def test_example2_unknown_function():
    f = sympy.Function("phi11")
    jb = jacobian_basis([f(x[4]), 0, 0, 0, 0], x)
    assert jb.W == (PolyMatrix(ex.W1_EXAMPLE2),)
    assert shape(ex.A, ex.C, jb.W).order == 2


def test_dependent_terms_are_merged_and_independent_ones_kept():
    x1, x2 = sympy.symbols("x1 x2")
    nu = sympy.Function("nu")(t)
    # μ and ν multiply the same pattern: one W with ζ = μ + ν; sin(x1) another pattern
    phi = [(mu + nu) * x2 + sympy.sin(x1), 3 * (mu + nu) * x2]
    jb = jacobian_basis(phi, [x1, x2])
    assert len(jb.W) == 2
    assert sympy.simplify(_rebuilt(jb) - jb.jacobian) == sympy.zeros(2, 2)
    assert {sympy.expand(z) for z in jb.zeta} == {mu + nu, sympy.cos(x1)}


def test_linear_and_empty():
    x1, x2 = sympy.symbols("x1 x2")
    assert jacobian_basis([0, 0], [x1, x2]).W == ()
    jb = jacobian_basis([2 * x2, sympy.Rational(1, 2) * x1], [x1, x2])  # constant Jacobian: one W, ζ = 1
    assert jb.zeta == (1,) and jb.W == (PolyMatrix([[0, 2], [sympy.Rational(1, 2), 0]]),)


def test_errors():
    x1, x2 = sympy.symbols("x1 x2")
    with pytest.raises(DimensionError, match="2 states"):
        jacobian_basis([x1], [x1, x2])
    with pytest.raises(DomainError, match="sympy"):
        jacobian_basis(["x1**2"], [x1])
