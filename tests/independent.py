"""Independent checks for the analysis tests: sympy only, no uio_ring algorithm.

* ``determinantal_factors(M)``: invariant factors from the determinantal
  divisors ``d_k = gcd of the k×k minors`` (``ψ_k = d_k / d_{k−1}``).
* ``weakly_unobservable_dim(A, B, C, D)``: ``dim V*`` of a constant system by
  the classical recursion ``V_{k+1} = {x : ∃w, Ax + Bw ∈ V_k, Cx + Dw = 0}``
  (strongly observable iff 0).
"""

from __future__ import annotations

from itertools import combinations

import sympy

from uio_ring import PolyMatrix

d = sympy.Symbol("d")


def to_sympy(M: PolyMatrix) -> sympy.Matrix:
    rows = [[sympy.sympify(str(x)) for x in row] for row in M.tolist()]
    return sympy.Matrix(M.rows, M.cols, [x for row in rows for x in row])


def determinantal_factors(M: PolyMatrix) -> tuple[sympy.Poly, ...]:
    """Monic invariant factors of M over Q[d] via gcds of minors (small matrices only)."""
    S = to_sympy(M)
    m, n = S.shape
    prev = sympy.Poly(1, d, domain="QQ")
    out = []
    for k in range(1, min(m, n) + 1):
        g = sympy.Poly(0, d, domain="QQ")
        for rows in combinations(range(m), k):
            for cols in combinations(range(n), k):
                minor = sympy.Poly(S.extract(list(rows), list(cols)).det(method="berkowitz"), d, domain="QQ")
                g = minor if g.is_zero else sympy.gcd(g, minor)
                if g.is_ground and not g.is_zero:
                    break
            if g.is_ground and not g.is_zero:
                break
        if g.is_zero:
            break
        g = g.monic()
        out.append(sympy.div(g, prev)[0].monic())
        prev = g
    return tuple(out)


def factors_as_sympy(factors) -> tuple[sympy.Poly, ...]:
    return tuple(sympy.Poly(sympy.sympify(str(f)), d, domain="QQ").monic() for f in factors)


def weakly_unobservable_dim(A, B, C, D) -> int:
    """dim V* of x' = Ax + Bw, y = Cx + Dw (constant sympy matrices)."""
    n = A.shape[0]
    p = C.shape[0]
    V = sympy.eye(n)
    while True:
        k = V.shape[1]
        big = sympy.Matrix(sympy.BlockMatrix([
            [A, B, -V if k else sympy.zeros(n, 0)],
            [C, D, sympy.zeros(p, k)],
        ])) if k else sympy.Matrix(sympy.BlockMatrix([[A, B], [C, D]]))
        null = big.nullspace()
        xs = [v[:n, :] for v in null]
        newV = sympy.Matrix.hstack(*xs) if xs else sympy.zeros(n, 0)
        if newV.shape[1]:
            basis = newV.columnspace()
            newV = sympy.Matrix.hstack(*basis) if basis else sympy.zeros(n, 0)
        if newV.shape[1] == V.shape[1]:
            return newV.shape[1]
        V = newV


def system_at(sys, value) -> tuple[sympy.Matrix, ...]:
    """The constant matrices A, B, C, D of ``sys`` with δ = value, as sympy matrices."""
    return tuple(to_sympy(M.eval(value)) for M in (sys.A, sys.B, sys.C, sys.D))
