"""The one exception hierarchy of uio_ring.

Every class also inherits the builtin that a Python user would expect, so
``except ValueError`` keeps working::

    UioRingError
    ├── DimensionError(ValueError)        shapes that do not fit
    ├── ParseError(ValueError)            text that is not a polynomial matrix
    ├── DomainError(TypeError)            non-rational numbers, mixed indeterminates
    ├── NotUnimodularError(ArithmeticError)
    ├── NoPolynomialSolutionError(ArithmeticError)
    └── MissingDependencyError(ImportError)

The layers above add ``NotObservableError`` and ``SpecError`` in
:mod:`uio_ring.errors`.
"""

from __future__ import annotations

__all__ = [
    "UioRingError",
    "DimensionError",
    "ParseError",
    "DomainError",
    "NotUnimodularError",
    "NoPolynomialSolutionError",
    "MissingDependencyError",
    "require",
]


class UioRingError(Exception):
    """Base class of every error raised on purpose by uio_ring."""


class DimensionError(UioRingError, ValueError):
    """Matrices or vectors whose shapes do not fit; the message names both shapes."""


class ParseError(UioRingError, ValueError):
    """Text that cannot be read as a polynomial (matrix).

    ``text`` is the offending string and ``position`` the 0-based column of the
    problem (``None`` when it concerns the whole text).
    """

    def __init__(self, message: str, *, text: str | None = None, position: int | None = None):
        super().__init__(message)
        self.text = text
        self.position = position


class DomainError(UioRingError, TypeError):
    """A value outside Q[δ]: a float where exactness is required, sqrt(2), an unknown
    symbol, or two matrices over different indeterminates."""


class NotUnimodularError(UioRingError, ArithmeticError):
    """A matrix that should be (left/right) unimodular is not; the message names the
    obstruction (rank, or the non-unit invariant factor)."""


class NoPolynomialSolutionError(UioRingError, ArithmeticError):
    """``X·V = W`` has no solution with polynomial entries."""


class MissingDependencyError(UioRingError, ImportError):
    """An optional dependency is not installed; the message gives the pip command."""


def require(module: str, *, extra: str):
    """Import an optional dependency or raise :class:`MissingDependencyError`.

    >>> require("math", extra="plot").__name__
    'math'
    """
    import importlib

    try:
        return importlib.import_module(module)
    except ImportError as exc:  # pragma: no cover - depends on the environment
        raise MissingDependencyError(
            f"{module} is needed for this; install it with: pip install 'uio-ring[{extra}]'"
        ) from exc
