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
