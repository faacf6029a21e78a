"""Data of paper 001 (Zheng, Bejarano, Perruquetti & Richard 2015), Section 5.

Test data only (no paper example matrices in library modules).  The
printed values listed as wrong in docs/errata.md are kept here under names
that say so, for the tests that must show them failing.
"""

from __future__ import annotations

from uio_ring import DelaySystem, PolyMatrix

A = "[[0, -1, 1, 0], [-1, d, 0, 0], [1, 0, 1, 0], [d, 1, 1, -1]]"
B = "[[0, 0], [0, 0], [1, 1], [0, d]]"
C = "[[d, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 1]]"
D = "[[1, d], [0, 0], [1, d]]"


def system(h: str | None = "1/100") -> DelaySystem:
    return DelaySystem(A, B, C, D, h=h)


# Step 1
U = PolyMatrix(
    "[[d, 0, -d, 1, 0, d], [-1, 0, 1, 0, 0, -1], [1, 0, 0, 0, 0, 0],"
    " [0, 1, 0, 0, 0, 0], [0, 0, 0, -1, 0, 1], [0, 0, 0, 0, 1, 0]]"
)
V = PolyMatrix("[[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, d]]")
VBAR = PolyMatrix(
    "[[0, 0, 1, 0, 1, 0, 1], [0, 0, 1, d, d, 0, d], [0, 0, 0, 0, 0, 0, 0]]"
).T
W = PolyMatrix(
    "[[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0], [d - 1, 0, 1 - d, 1, 0, d - 1],"
    " [-d, 0, d, 0, 0, -d], [0, 0, 0, 1, 0, 0], [0, 0, 0, 0, 0, 0], [0, 0, 0, 1, 0, 0]]"
)
# Step 2 (the paper prints C̃ under the name C̄)
A_BAR = PolyMatrix(
    "[[0, -1, 1, 0], [-1, d, 0, 0],"
    " [d**2 - d, d**2 - 1, -d**2 + 2*d, -2*d + 2],"
    " [-d**2, 1 - d - d**2, 1 - d + d**2, 2*d - 1]]"
)
C_TILDE = PolyMatrix("[[0, 0, 0, 0], [0, 1, 0, 0], [-d, 0, 1, 1]]")
LAM = PolyMatrix("[[0, 1, 0], [0, 0, 1], [1, 0, 0]]")
C_BAR = PolyMatrix("[[0, 1, 0, 0], [-d, 0, 1, 1]]")
# Step 3
O3 = PolyMatrix(
    "[[0, 1, 0, 0], [-d, 0, 1, 1], [-1, d, 0, 0], [-d, 0, 1, 1],"
    " [-d, 1 + d**2, -1, 0], [-d, 0, 1, 1]]"
)
O3_LEFT_INVERSE = PolyMatrix(
    "[[d, 0, -1, 0, 0, 0], [1, 0, 0, 0, 0, 0], [1, 0, d, 0, -1, 0],"
    " [d**2 - 1, 1, -2*d, 0, 1, 0]]"
)
F = PolyMatrix(
    "[[-2 - d**2 + 5*d, 0], [0, 0], [1 + 3*d - 5*d**2 + d**3, 0], [0, 0],"
    " [3 - 4*d - d**2 + d**3, 2*d - 2], [0, 1]]"
)
T = PolyMatrix(
    "[[0, 1, 0, 0], [-d, 0, 1, 1], [-1, 2 - 4*d + d**2, 0, 0], [-d, 0, 1, 1],"
    " [-2 + 4*d - d**2, -d + d**2, -1, 0], [-d, 0, 1, 1]]"
)
T_LEFT_INVERSE = PolyMatrix(
    "[[2 - 4*d + d**2, 0, -1, 0, 0, 0], [1, 0, 0, 0, 0, 0],"
    " [-19*d**2 + 15*d + 8*d**3 - 4 - d**4, 0, -4*d + 2 + d**2, 0, -1, 0],"
    " [15*d**2 - 13*d - 7*d**3 + 4 + d**4, 0, 3*d - 2 - d**2, 1, 1, 0]]"
)
# Step 4
K_BAR = PolyMatrix(  # [K̄1, K̄2]
    "[[0, 0, 0, 0, 0, 0], [0, 1, -1, 0, -1, 1], [0, 0, 0, 0, 0, 0],"
    " [0, 1, -1, 0, -1, 1], [0, d - 1, 1 - d, 0, 1 - d, -1], [0, 1, -1, 0, -1, 1]]"
)
GAMMA_BAR = PolyMatrix(  # [Γ̄1, Γ̄2]
    "[[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 1], [0, 0, 0, 0, 0, 1]]"
)
POLES = [-10, -25, -50]
G0 = PolyMatrix("[[85, 0, 2000, 0, 12500, 0], [0, 85, 0, 2000, 0, 12500]]").T
L0 = PolyMatrix(
    "[[-85, 0, 1, 0, 0, 0], [0, -85, 0, 1, 0, 0], [-2000, 0, 0, 0, 1, 0],"
    " [0, -2000, 0, 0, 0, 1], [-12500, 0, 0, 0, 0, 0], [0, -12500, 0, 0, 0, 0]]"
)
H = PolyMatrix(
    "[[0, 0, 0], [0, 1, -1], [0, 0, 0], [0, 1, -1], [0, d - 1, 1 - d], [0, 1, -1]]"
)
# (22) as printed: WRONG in entries (5,3) and (6,3) (docs/errata.md, Z1)
J_PRINTED = PolyMatrix(
    "[[83 + 5*d - d**2, 0, 0], [0, 0, 0], [2001 - 5*d**2 + 3*d + d**3, d - 1, 1 - d],"
    " [0, 0, 0], [12503 - 4*d - d**2 + d**3, d - 1, -1], [0, 0, 1]]"
)
# (22') corrected: J(5,3) = 1 − 2δ, J(6,3) = 0
J_CORRECTED = PolyMatrix(
    "[[83 + 5*d - d**2, 0, 0], [0, 0, 0], [2001 - 5*d**2 + 3*d + d**3, d - 1, 1 - d],"
    " [0, 0, 0], [12503 - 4*d - d**2 + d**3, d - 1, 1 - 2*d], [0, 0, 0]]"
)
