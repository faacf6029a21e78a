"""Exact algebra over Q[δ]: polynomial matrices and their normal forms.

Importing this package loads python-flint; ``import uio_ring`` alone does not.
"""

from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.errors import (
    DimensionError,
    DomainError,
    MissingDependencyError,
    NoPolynomialSolutionError,
    NotUnimodularError,
    ParseError,
    UioRingError,
)
from uio_ring.ring.hermite import HermiteResult, hermite, is_hermite
from uio_ring.ring.inverse import (
    is_left_unimodular,
    is_right_unimodular,
    is_unimodular,
    left_inverse,
    right_inverse,
)
from uio_ring.ring.kernel import left_kernel, right_kernel
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import Poly
from uio_ring.ring.qmatrix import QMatrix, RowEchelon
from uio_ring.ring.rank import det, rank
from uio_ring.ring.smith import SmithResult, invariant_factors, is_smith, smith
from uio_ring.ring.solve import solve_left, solve_right

__all__ = [
    "Certificate",
    "Check",
    "DimensionError",
    "DomainError",
    "MissingDependencyError",
    "NoPolynomialSolutionError",
    "NotUnimodularError",
    "ParseError",
    "UioRingError",
    "HermiteResult",
    "hermite",
    "is_hermite",
    "is_left_unimodular",
    "is_right_unimodular",
    "is_unimodular",
    "left_inverse",
    "right_inverse",
    "left_kernel",
    "right_kernel",
    "PolyMatrix",
    "Poly",
    "QMatrix",
    "RowEchelon",
    "det",
    "rank",
    "SmithResult",
    "invariant_factors",
    "is_smith",
    "smith",
    "solve_left",
    "solve_right",
]
