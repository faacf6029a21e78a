"""The matrices W_k of a nonlinearity: ``∂φ/∂x = Σ_k ζ_k(t, x) W_k`` (Grip & Saberi 2010, §2, §5.6).

Given φ(t, x) as sympy expressions, :func:`jacobian_basis` expands every entry of
the Jacobian into terms ``c·τ`` (c rational, τ the rest: ``μ(t)``, ``cos(x1)``,
``x2**2``, an unknown ``Derivative(f(x3), x3)`` …), gives each distinct term τ its
coefficient matrix ``M_τ``, and keeps a linearly independent subset of the ``M_τ``
as the ``W_k`` (the others are combinations of them, folded into the ζ_k).  The
paper's §5.6 is why: a *dependent* decomposition (one W per Jacobian entry when
several entries share one function) can make a solvable shaping problem
unsolvable; only ``span{W_k}`` matters for admissibility and shaping.

Distinct expanded terms are treated as linearly independent functions; when they
are not (``sin(x)**2``, ``cos(x)**2`` and ``1``), the result is still a valid
decomposition, only possibly larger than necessary.  A constant term (a linear
part of φ) gets its own W; moving it into A is better.

>>> import sympy
>>> x1, x2, t = sympy.symbols("x1 x2 t")
>>> mu = sympy.Function("mu")(t)
>>> jb = jacobian_basis([mu * x2, -mu * x1 + mu * x2], [x1, x2])
>>> jb.W, jb.zeta
((PolyMatrix([[0, 1], [-1, 1]]),), (mu(t),))
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from uio_ring.analysis import _subspaces as sp
from uio_ring.errors import DimensionError, DomainError
from uio_ring.ring import constant as qc
from uio_ring.ring.matrix import PolyMatrix

__all__ = ["JacobianBasis", "jacobian_basis"]


@dataclass(frozen=True)
class JacobianBasis:
    """``∂φ/∂x = Σ_k zeta[k] · W[k]`` with linearly independent ``W[k]`` (constant ``PolyMatrix``).

    ``terms`` are the distinct expanded terms τ of the Jacobian (sympy expressions),
    ``jacobian`` the Jacobian itself (a sympy Matrix).
    """

    W: tuple[PolyMatrix, ...]
    zeta: tuple[Any, ...]
    terms: tuple[Any, ...]
    jacobian: Any


def _split(expr: Any) -> list[tuple[Fraction, Any]]:
    """``expr`` (expanded) as ``[(c, τ), …]`` with rational c."""
    import sympy

    out = []
    for term, coeff in sympy.expand(expr).as_coefficients_dict().items():
        if isinstance(coeff, sympy.Rational):
            out.append((Fraction(int(coeff.p), int(coeff.q)), term))
        else:  # an irrational or float coefficient stays in the term
            out.append((Fraction(1), coeff * term))
    return out


def jacobian_basis(phi: Sequence[Any], states: Sequence[Any]) -> JacobianBasis:
    """The W_k of φ: a linearly independent basis of the span of its Jacobian's coefficient matrices.

    Parameters
    ----------
    phi
        n sympy expressions, the components of φ(t, x).
    states
        The n sympy symbols of x, in the order of the system's state.

    Returns
    -------
    JacobianBasis
        ``W`` (n×n each), ``zeta`` with ``∂φ/∂x = Σ ζ_k W_k`` exactly.

    Raises
    ------
    DimensionError
        ``len(phi) != len(states)``.
    DomainError
        An entry is not a sympy expression (text is not parsed here: use ``sympy.sympify``
        on trusted input, or the spec layer's parser).

    Examples
    --------
    Example 2 of the paper, φ_11 an unknown function of x23:

    >>> import sympy
    >>> x = sympy.symbols("x11 x12 x21 x22 x23")
    >>> f = sympy.Function("phi11")
    >>> jb = jacobian_basis([f(x[4]), 0, 0, 0, 0], x)
    >>> jb.W[0][0, 4], len(jb.W)
    (1, 1)
    """
    import sympy

    if len(phi) != len(states):
        raise DimensionError(f"phi has {len(phi)} components and there are {len(states)} states; expected equal")
    exprs = []
    for i, e in enumerate(phi):
        if isinstance(e, str):
            raise DomainError(f"phi[{i}] is text; give sympy expressions (sympy.sympify(text) on trusted input)")
        exprs.append(sympy.sympify(e) if isinstance(e, (int, Fraction)) else e)
    n = len(states)
    J = sympy.Matrix(exprs).jacobian(list(states))
    coeffs: dict[Any, dict[tuple[int, int], Fraction]] = {}
    for i in range(n):
        for j in range(n):
            if J[i, j] == 0:
                continue
            for c, term in _split(J[i, j]):
                entry = coeffs.setdefault(term, {})
                entry[(i, j)] = entry.get((i, j), Fraction(0)) + c
    terms = sorted((t for t, m in coeffs.items() if any(m.values())), key=sympy.default_sort_key)
    if not terms:
        return JacobianBasis((), (), (), J)
    V = qc.qzeros(len(terms), n * n)
    for r, term in enumerate(terms):
        for (i, j), c in coeffs[term].items():
            V[r, i * n + j] = qc.qmat([[c]])[0, 0]
    basis = list(qc.row_basis(V))
    B = sp.vstack([_row(V, r) for r in basis], n * n)
    zeta = [sympy.Integer(0)] * len(basis)
    for r, term in enumerate(terms):
        x = sp.left_solve(B, _row(V, r))
        if x is None:  # pragma: no cover - every row lies in the span of the basis rows
            raise DimensionError("internal: a coefficient matrix is outside the span of the basis")
        for k in range(len(basis)):
            if x[0, k] != 0:
                c = qc.frac(x[0, k])
                zeta[k] = zeta[k] + sympy.Rational(c.numerator, c.denominator) * term
    Ws = []
    for r in basis:
        M = [[qc.frac(V[r, i * n + j]) for j in range(n)] for i in range(n)]
        Ws.append(PolyMatrix(M))
    return JacobianBasis(tuple(Ws), tuple(zeta), tuple(terms), J)


def _row(M: qc.QMat, i: int) -> qc.QMat:
    out = qc.qzeros(1, M.ncols())
    for c in range(M.ncols()):
        out[0, c] = M[i, c]
    return out
