"""Paper 003's example (Tranninger et al.), Section 6: CB = 0, D = 0 (test data only)."""

from __future__ import annotations

from uio_ring import DelaySystem

A = (
    "[[-4, 6, -5, 11, 8, -5, 22, 0], [-3, 0, 2, -2, -1, 1, -3, -12],"
    " [-3, -2, 3, -9, -2, 6, -8, -2], [0, 0, 0, -2, 1, 0, -2, 0],"
    " [3, 0, -1, 3, 1, 0, 4, 11], [3, 1, -4, 6, 1, -7, 3, 2],"
    " [0, 0, 0, -1, 0, 0, -1, 1], [-3, 0, 1, -5, -1, 1, -7, -10]]"
)
B = "[[0, -2], [0, 1], [-1, 1], [0, 0], [0, -1], [1, -1], [0, 0], [0, 1]]"
C = "[[0, 0, 0, 1, 0, 0, 1, 0], [0, 0, 0, 0, 0, 0, 1, 0], [0, -2, 1, 0, -2, 1, -2, 0]]"


def system() -> DelaySystem:
    return DelaySystem(A, B, C, None)
