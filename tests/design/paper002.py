"""Data of Bejarano, Fridman & Poznyak (2007), Example 1 (Section 2), in the package's letters
(the paper's D, F, B are B, D, E here).  Test data only."""

from __future__ import annotations

import numpy as np

from uio_ring import DelaySystem

A = ("[[-0.86, 0.68, 0.12, 0.66, -1.03], [0.23, -1.56, -2.58, 1.23, -0.21], [-1.2, 1.83, -0.56, 0.51, -1.83],"
     " [-1.77, 1.08, -1.2, -1.74, -1.87], [-0.52, 1.2, -1.48, 1.06, -2.07]]")
B = "[[0, 0], [0, 0], [0, 0], [0.5, 0], [1, 0]]"
C = "[[1, 0, 0, 0, 0], [0, 1, 0, 0, 0], [0, 0, 1, 0, 0]]"
D = "[[0, 0.5], [0, 1], [0, 1.5]]"
E = "[[1], [0.5], [0.7], [1.2], [1.4]]"
X0 = [1.0, -1.0, 0.5, 0.0, 2.0]
GAINS = [[15, 10], [20, 10]]  # (λ, α) of levels 1 and 2


def example1() -> DelaySystem:
    return DelaySystem(A, B, C, D, E=E)


def w(t):
    t = np.asarray(t, dtype=float)
    return np.array([0.5 * np.cos(2 * t) + 0.43, 0.2 * np.sin(t) + 0.23])


def u(t):
    return 1.5 * np.sin(2 * np.asarray(t, dtype=float))


# Example 2 (Section 3): parametric uncertainty w = ΔA G x, G = I, F = 0, matching holds.
A2 = "[[0, -4, 5.5], [1, -5, 4.5], [1, -1, -1]]"
B2 = "[[1], [0], [1]]"  # the paper's D
C2 = "[[1, 2, 1], [2, 1, 1]]"
E2 = "[[1], [1], [1]]"  # the paper's B
DELTA_A = np.array([[0.1, -0.15, 0.2]])
X0_2 = [1.0, -1.0, 0.5]
GAINS_2 = [[30, 20]]  # (λ1, α1) = (30, 20), the paper's
# printed in the paper (3 decimals, truncated): P, P⁻¹, A11, A12, B1, C̄ in its orthonormal bases
P_PRINTED = [[0, 1, 0], [-0.7071, 0, 0.7071], [0.6154, 0.5385, 0.3846]]
P_INV_PRINTED = [[-0.538, -0.543, 1], [1, 0, 0], [-0.538, 0.870, 1]]
A11_PRINTED = [[-7.961, 3.372], [4.215, -4.384]]
A12_PRINTED = [[5.5], [-3.889]]
B1_PRINTED = [[1], [0]]
C_BAR_PRINTED = [[-1.109, -0.392]]


def example2() -> DelaySystem:
    return DelaySystem(A2, B2, C2, None, E=E2)


def example2_true_plant() -> DelaySystem:
    """The plant with its uncertainty closed: x' = (A + B ΔA G) x + E u (w = ΔA x enters through B)."""
    A = np.array([[0, -4, 5.5], [1, -5, 4.5], [1, -1, -1]]) + np.array([[1], [0], [1]]) @ DELTA_A
    return DelaySystem(A.tolist(), B2, C2, None, E=E2)


def u2(t):
    return 4 * np.sin(np.asarray(t, dtype=float))
