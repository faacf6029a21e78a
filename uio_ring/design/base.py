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

__all__ = ["ObserverDesign", "matrix_to_data", "matrix_text_memo", "abridged_matrices", "matrix_outline"]

#: Inside :func:`matrix_text_memo`: ``id(M) -> (M, rows of strings)`` for the matrices already written.
_TEXTS: ContextVar[dict[int, tuple[PolyMatrix, list[list[str]]]] | None] = ContextVar("_TEXTS", default=None)
#: Inside :func:`abridged_matrices`: the text size (characters) above which a matrix is outlined.
_ABRIDGE: ContextVar[int | None] = ContextVar("_ABRIDGE", default=None)


@contextmanager
def abridged_matrices(limit: int) -> Iterator[None]:
    """Within the block, :func:`matrix_to_data` gives the :func:`matrix_outline` of a matrix
    whose text would exceed about ``limit`` characters instead of its entries (the summary of
    a design file: the exact matrices are in its ``fields`` already, a 216 × 32 matrix of
    degree 23 is 50 MB of text).  The size is estimated from the coefficients' bit lengths,
    without writing the text.

    >>> M = PolyMatrix("[[d, 1/2]]")
    >>> with abridged_matrices(4):
    ...     matrix_to_data(M)["shape"]
    [1, 2]
    >>> with abridged_matrices(100):
    ...     matrix_to_data(M)
    [['d', '1/2']]
    """
    token = _ABRIDGE.set(limit)
    try:
        yield
    finally:
        _ABRIDGE.reset(token)


def _text_size_above(M: PolyMatrix, limit: int) -> bool:
    """Whether the text of M has (about) more than ``limit`` characters: each coefficient
    takes ``0.302·bits + 4`` characters (numerator, denominator, ``*d**k``, sign), each entry
    4 more (quotes, comma); stops as soon as the limit is passed."""
    total = 0
    for row in M._r:
        for p in row:
            total += 4
            if not p.is_zero():
                bits = p.numer().height_bits() + p.denom().bit_length()
                total += (p.degree() + 1) * (bits * 302 // 1000 + 4)
        if total > limit:
            return True
    return total > limit


def matrix_outline(M: PolyMatrix) -> dict[str, Any]:
    """Shape, δ-degree and the largest coefficient (bits of numerator and denominator) of M:
    what a summary shows of a matrix too large to print.

    >>> matrix_outline(PolyMatrix("[[d, 1/2], [0, 3*d**2]]"))
    {'shape': [2, 2], 'degree': 2, 'coefficient_bits': 2, 'entries': 'omitted (large); the exact matrix is in the fields'}
    """
    bits = max((max(p.numer().height_bits(), p.denom().bit_length()) for row in M._r for p in row
                if not p.is_zero()), default=0)
    return {"shape": list(M.shape), "degree": M.degree(), "coefficient_bits": bits,
            "entries": "omitted (large); the exact matrix is in the fields"}


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


def matrix_to_data(M: PolyMatrix) -> Any:
    """A matrix as nested lists of polynomial strings (for JSON/YAML); inside
    :func:`abridged_matrices` a large one as its :func:`matrix_outline` (a dict).

    Each call returns new lists (a YAML emitter would write lists shared between two
    places as anchors and aliases); inside :func:`matrix_text_memo` the strings of a
    matrix already written are reused.

    >>> matrix_to_data(PolyMatrix("[[d, 1/2]]"))
    [['d', '1/2']]
    """
    limit = _ABRIDGE.get()
    if limit is not None and _text_size_above(M, limit):
        return matrix_outline(M)
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
    #: Fields a design file writes as recomputed from the other fields (:meth:`derive_field`),
    #: with how: ``{name: description}``.
    derived_fields: ClassVar[dict[str, str]] = {}

    def _memo(self, key: Any, make: Any) -> Any:
        """``make()``, computed once per design object and key (a design is immutable; the
        memo lives in the instance's ``__dict__``, which a frozen dataclass leaves writable,
        and is neither compared nor copied by ``dataclasses.replace``)."""
        memo = self.__dict__.setdefault("_memo_results", {})
        if key not in memo:
            memo[key] = make()
        return memo[key]

    def certified(self) -> bool:
        """True when :meth:`certificate` was already computed for this object and holds
        (never computes it)."""
        cert = self.__dict__.get("_memo_results", {}).get("certificate")
        return cert is not None and bool(cert.ok)

    @classmethod
    def derive_field(cls, name: str, fields: dict[str, Any]) -> Any:
        """The value of the derived field ``name`` from the other fields (decoded, typed);
        raises ``KeyError`` for a field that is not in :attr:`derived_fields`."""
        raise KeyError(name)

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
        (:meth:`linear_model`, :attr:`noise_scope`), else ``NotSupportedError``.  Computed
        once per design object and ``(h, tolerance)`` (the command line prints them and
        writes them to the design file).

        >>> from uio_ring import DelaySystem, design_zheng_bejarano
        >>> des = design_zheng_bejarano(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None),
        ...                             poles=[-2])
        >>> p = des.performance()
        >>> p.decay_rate, p.order, [round(float(g), 3) for g in p.noise_gain]
        (2.0, 2, [1.5, 1.0])
        """
        from uio_ring.numeric.performance import performance

        system = getattr(self, "system", None)
        key = ("performance", getattr(system, "h", None) if h is None else h, tolerance)
        return self._memo(key, lambda: performance(self.linear_model(h=h), tolerance=tolerance,
                                                   scope=self.noise_scope))

    @abstractmethod
    def to_dict(self) -> dict[str, Any]:
        """Plain data: matrices as lists of polynomial strings."""

    @abstractmethod
    def to_latex(self) -> str:
        """The observer equations and its main matrices, as LaTeX (no surrounding ``$``)."""

    def _repr_latex_(self) -> str:
        return "$$" + self.to_latex() + "$$"
