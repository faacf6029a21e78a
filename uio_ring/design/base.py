"""Conventions shared by every design method: the ``ObserverDesign`` base class.

A design is a frozen dataclass of named exact matrices.  Every design

* keeps the system it was made for in ``system``;
* proves itself with ``certificate()`` (a :class:`~uio_ring.verify.Certificate`
  of exact identities, built in :mod:`uio_ring.verify`);
* gives its float observer model with ``numeric()`` (what the simulation engine steps);
* converts to plain data with ``to_dict()`` and renders with ``to_latex()`` /
  ``_repr_latex_`` (δ printed);
* has a short ``repr`` (the matrices can be large).

>>> issubclass(ObserverDesign, object)
True
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Iterator
from contextlib import contextmanager
from contextvars import ContextVar
from typing import Any, ClassVar

from uio_ring.ring.certificate import Certificate
from uio_ring.ring.matrix import PolyMatrix

__all__ = ["ObserverDesign", "matrix_to_data", "matrix_text_memo"]

#: Inside :func:`matrix_text_memo`: ``id(M) -> (M, rows of strings)`` for the matrices already written.
_TEXTS: ContextVar[dict[int, tuple[PolyMatrix, list[list[str]]]] | None] = ContextVar("_TEXTS", default=None)


@contextmanager
def matrix_text_memo() -> Iterator[None]:
    """Within the block, :func:`matrix_to_data` writes each matrix object once: a design file
    holds its matrices in ``fields`` and again in the ``summary`` (the same objects), and the
    decimal text of big coefficients is the costly part (a 216 × 32 matrix of 1391-bit
    coefficients: ~2 s).  The memo lives for the block only (one file), never globally; it
    keeps the matrices alive, so an ``id`` is not reused while it stands.

    >>> M = PolyMatrix("[[d, 1/2]]")
    >>> with matrix_text_memo():
    ...     a, b = matrix_to_data(M), matrix_to_data(M)
    >>> a == b == [['d', '1/2']], a is b
    (True, False)
    """
    token = _TEXTS.set({})
    try:
        yield
    finally:
        _TEXTS.reset(token)


def matrix_to_data(M: PolyMatrix) -> list[list[str]]:
    """A matrix as nested lists of polynomial strings (for JSON/YAML).

    Each call returns new lists (a YAML emitter would write lists shared between two
    places as anchors and aliases); inside :func:`matrix_text_memo` the strings of a
    matrix already written are reused.

    >>> matrix_to_data(PolyMatrix("[[d, 1/2]]"))
    [['d', '1/2']]
    """
    memo = _TEXTS.get()
    if memo is None:
        return [[str(x) for x in row] for row in M.tolist()]
    hit = memo.get(id(M))
    if hit is None or hit[0] is not M:
        hit = (M, [[str(x) for x in row] for row in M.tolist()])
        memo[id(M)] = hit
    return [list(row) for row in hit[1]]


class ObserverDesign(ABC):
    """Base class of the design objects returned by ``design_*`` functions."""

    #: The method's registry name, e.g. ``"zheng-bejarano"`` (one spelling everywhere).
    method: ClassVar[str] = ""
    #: What :meth:`performance` measures when it is not the whole observer (empty: all of it).
    noise_scope: ClassVar[str] = ""

    @abstractmethod
    def certificate(self) -> Certificate:
        """The exact identities the method promises, each with its verdict."""

    @abstractmethod
    def numeric(self, *, h: Any = None) -> Any:
        """The float :class:`~uio_ring.numeric.model.ObserverModel` that the engine steps
        (``h``: the basic delay, when the design's system has none)."""

    def linear_model(self, *, h: Any = None) -> Any:
        """The linear float model whose figures :meth:`performance` gives: the whole observer
        (:meth:`numeric`) unless the method says otherwise (:attr:`noise_scope`)."""
        return self.numeric(h=h)

    def performance(self, *, h: Any = None, tolerance: float = 1e-3) -> Any:
        """Decay rate, convergence time, the peak-to-peak noise gain (delayed taps and direct
        feed-through included exactly), the H2 gain when finite, lag and order of a linear
        observer: :class:`~uio_ring.numeric.performance.ObserverPerformance`.  ``h`` is needed
        when the system has none and the observer has delays.  Observers with a nonlinear
        injection term: the figures of the linear stage their method names
        (:meth:`linear_model`, :attr:`noise_scope`), else ``NotSupportedError``.

        >>> from uio_ring import DelaySystem, design_zheng_bejarano
        >>> des = design_zheng_bejarano(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None),
        ...                             poles=[-2])
        >>> p = des.performance()
        >>> p.decay_rate, p.order, [round(float(g), 3) for g in p.noise_gain]
        (2.0, 2, [1.5, 1.0])
        """
        from uio_ring.numeric.performance import performance

        return performance(self.linear_model(h=h), tolerance=tolerance, scope=self.noise_scope)

    @abstractmethod
    def to_dict(self) -> dict[str, Any]:
        """Plain data: matrices as lists of polynomial strings."""

    @abstractmethod
    def to_latex(self) -> str:
        """The observer equations and its main matrices, as LaTeX (no surrounding ``$``)."""

    def _repr_latex_(self) -> str:
        return "$$" + self.to_latex() + "$$"
