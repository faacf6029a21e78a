"""Exception hierarchy of uio_ring (see :mod:`uio_ring.ring.errors` for the root).

``NotObservableError`` carries the analysis report that explains which
assumption failed; ``SpecError`` carries the path inside a spec file.
"""

from __future__ import annotations

from typing import Any, TypeVar

from uio_ring.ring.errors import (
    DimensionError,
    DomainError,
    MissingDependencyError,
    NoPolynomialSolutionError,
    NotUnimodularError,
    ParseError,
    UioRingError,
    require,
)

__all__ = [
    "UioRingError",
    "DimensionError",
    "ParseError",
    "DomainError",
    "NotUnimodularError",
    "NoPolynomialSolutionError",
    "MissingDependencyError",
    "NotObservableError",
    "SpecError",
    "OptionError",
    "for_option",
    "SimulationError",
    "NotSupportedError",
    "require",
]


E = TypeVar("E", bound=BaseException)


class NotObservableError(UioRingError, ValueError):
    """A design method refuses a system because one of its assumptions fails.

    ``report`` is the analysis report (with ``.reason``) that shows which one.
    """

    def __init__(self, message: str, *, report: Any = None):
        super().__init__(message)
        self.report = report


class SpecError(UioRingError, ValueError):
    """A spec file (or dict) that cannot be used; ``path`` is where, e.g. ``system.C[2][1]``."""

    def __init__(self, message: str, *, path: str | None = None):
        super().__init__(f"{path}: {message}" if path else message)
        self.path = path
        self.detail = message


class OptionError(DomainError):
    """A design option's value outside its admissible range; ``option`` names it (a spec
    reports it at ``design.<option>``)."""

    def __init__(self, message: str, *, option: str):
        super().__init__(message)
        self.option = option


def for_option(exc: E, option: str) -> E:
    """``exc`` (any of the package's errors) marked as caused by design option ``option``, so that a
    spec reports it at ``design.<option>`` — for errors whose class says what is wrong (a
    ``DimensionError`` for a wrong count) while the option says where.

    >>> err = for_option(DimensionError("poles has 1 value"), "poles")
    >>> type(err).__name__, err.option
    ('DimensionError', 'poles')
    """
    exc.option = option  # type: ignore[attr-defined]
    return exc


class SimulationError(UioRingError, ValueError):
    """Simulation arguments that cannot be used (a step that is not ``h/N``, a history of
    the wrong shape, NaN in a signal, mismatched delays); the message names the argument."""


class NotSupportedError(UioRingError, NotImplementedError):
    """A case the implemented theory does not cover; the message says which and why."""
