"""The examples of Grip & Saberi (2010), "High-gain observer design for multi-output
systems: transformation to a canonical form by dynamic output shaping", as data,
plus random coordinate changes and random admissible sets for property tests.

State order ``x = [x11, x12, x21, x22, x23]``; outputs ``y1 = x11``, ``y2 = x21``.
The paper's displays of (A, C, W_1) are lost in its text version; they follow
from the printed equations (both examples say A and C are already in form (8)–(9)).
"""

from __future__ import annotations

import random

import sympy

A = [[0, 1, 0, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1], [0, 0, 0, 0, 0]]
C = [[1, 0, 0, 0, 0], [0, 0, 1, 0, 0]]

# Example 1: x11' = x12 + μ(−x12 + x22), x12' = μ x23, x21' = x22 + μ(−x12 + x22),
# x22' = x23 + μ(x11 + x23), x23' = μ x12: one W_1 (every entry is a multiple of μ).
W1_EXAMPLE1 = [[0, -1, 0, 1, 0], [0, 0, 0, 0, 1], [0, -1, 0, 1, 0], [1, 0, 0, 0, 1], [0, 1, 0, 0, 0]]

# Example 2: x11' = x12 + φ11(x23): the Jacobian's single entry is at (x11, x23).
W1_EXAMPLE2 = [[0, 0, 0, 0, 1], [0] * 5, [0] * 5, [0] * 5, [0] * 5]

# Example 2's extension by hand, eq. (16): x_e = [z1, z2, x11, x12, x21, x22, x23]
A_E16 = [[0, 1, 0, 0, 0, 0, 0], [0, 0, 1, 0, 0, 0, 0], [0, 0, 0, 1, 0, 0, 0], [0] * 7,
         [0, 0, 0, 0, 0, 1, 0], [0, 0, 0, 0, 0, 0, 1], [0] * 7]
C_E16 = [[1, 0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 1, 0, 0]]
W_E16 = [[0] * 7, [0] * 7, [0, 0, 0, 0, 0, 0, 1], [0] * 7, [0] * 7, [0] * 7, [0] * 7]


def split_example1() -> list[list[list[int]]]:
    """Example 1 with W_1 split into one single-entry matrix per nonzero entry (§5.6)."""
    out = []
    for i in range(5):
        for j in range(5):
            if W1_EXAMPLE1[i][j]:
                M = [[0] * 5 for _ in range(5)]
                M[i][j] = W1_EXAMPLE1[i][j]
                out.append(M)
    return out


def unimodular(n: int, rng: random.Random) -> sympy.Matrix:
    """A random integer matrix with determinant ±1 (so its inverse is an integer matrix)."""
    Lo = sympy.eye(n)
    U = sympy.eye(n)
    for i in range(n):
        U[i, i] = rng.choice([1, -1])
        for j in range(i):
            Lo[i, j] = rng.randint(-2, 2)
            U[j, i] = rng.randint(-2, 2)
    P = sympy.eye(n)[rng.sample(range(n), n), :]
    return P * Lo * U


def transform(A, C, W, Gx: sympy.Matrix, Gy: sympy.Matrix):
    """The set in the coordinates ``x' = Γ_x x``, ``y' = Γ_y y``: (Γ_x A Γ_x⁻¹, Γ_y C Γ_x⁻¹, Γ_x W_k Γ_x⁻¹)."""
    A, C = sympy.Matrix(A), sympy.Matrix(C)
    Gxi = Gx.inv()
    return (Gx * A * Gxi).tolist(), (Gy * C * Gxi).tolist(), [(Gx * sympy.Matrix(Wk) * Gxi).tolist() for Wk in W]


def random_canonical(q: tuple[int, ...], v: int, rng: random.Random, *, upward: bool = False):
    """(A, C, W) in canonical form (8)–(11) with chain lengths ``q``, random L and random
    generalised lower-triangular W blocks; ``upward`` adds one entry above a block diagonal
    (then the set is not admissible, by Theorem 2)."""
    n, p = sum(q), len(q)
    starts = [sum(q[:i]) for i in range(p)]
    A = sympy.zeros(n, n)
    C = sympy.zeros(p, n)
    for i, (s, qi) in enumerate(zip(starts, q, strict=True)):
        C[i, s] = 1
        for r in range(qi - 1):
            A[s + r, s + r + 1] = 1
    L = sympy.Matrix(n, p, lambda i, j: rng.randint(-2, 2))
    A = A + L * C
    Ws = []
    for _ in range(v):
        Wk = sympy.zeros(n, n)
        for si, qi in zip(starts, q, strict=True):
            for sj, qj in zip(starts, q, strict=True):
                for r in range(qi):
                    for c in range(min(r + 1, qj)):
                        Wk[si + r, sj + c] = rng.randint(-2, 2)
        Ws.append(Wk)
    if upward:
        cands = [(si + r, sj + c) for si, qi in zip(starts, q, strict=True) for sj, qj in zip(starts, q, strict=True)
                 for r in range(qi) for c in range(r + 1, qj)]
        if cands:
            Ws[0][rng.choice(cands)] = rng.choice([1, -1, 2])
    return A.tolist(), C.tolist(), [Wk.tolist() for Wk in Ws]


def sympy_admissible(A, C, W) -> bool:
    """Definition 2 directly with sympy (an independent implementation)."""
    A, C = sympy.Matrix(A), sympy.Matrix(C)
    n = A.shape[0]
    O = sympy.zeros(0, n)
    row = C
    for _ in range(n):
        O = O.col_join(row)
        row = row * A
        N = O.nullspace()
        for Wk in W:
            for v in N:
                if not (O * sympy.Matrix(Wk) * v).is_zero_matrix:
                    return False
    return True
