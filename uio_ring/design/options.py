"""Typed design options: one record per option, one converter and one JSON Schema per kind.

A method's options are declared once (in its registry entry); the spec loader
reads them with :meth:`MethodOption.read` and the JSON Schema of spec files is
generated from :meth:`MethodOption.schema`.  Numbers are exact: decimal text
``"0.1"`` and the float ``0.1`` both read as 1/10 (floats through their shortest
``repr``, as everywhere in the package).

>>> opt = MethodOption("poles", "rationals", "the observer's poles")
>>> opt.read(["-1/2", 0.25], "design.poles")
(Fraction(-1, 2), Fraction(1, 4))
>>> opt.schema()["type"]
'array'
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from uio_ring.errors import DomainError, ParseError, SpecError

__all__ = ["MethodOption", "KINDS"]

_SCALAR = {"$ref": "#/$defs/scalar"}

#: kind -> JSON Schema fragment
KINDS: dict[str, dict[str, Any]] = {
    "rational": _SCALAR,
    "rationals": {"type": "array", "items": _SCALAR},
    "rational_or_rationals": {"anyOf": [_SCALAR, {"type": "array", "items": _SCALAR}]},
    "rational_rows": {"type": "array", "items": {"type": "array", "items": _SCALAR}},
    "bool": {"type": "boolean"},
    "poles": {"anyOf": [{"type": "array", "items": _SCALAR}, {"enum": ["min-noise"]}]},
    "rational_matrices": {"type": "array", "items": {"type": "array", "items": {"type": "array", "items": _SCALAR}}},
    "integer": {"type": "integer", "minimum": 0},
    "criterion": {"enum": ["peak", "h2"]},
}


def _exact(value: Any, path: str) -> Fraction:
    from uio_ring.ring.poly import exact_fraction

    if isinstance(value, bool):
        raise SpecError(f"{value!r} is a boolean, not a number", path=path)
    if isinstance(value, float) and not math.isfinite(value):
        raise SpecError(f"{value} is not a finite number", path=path)
    try:
        return exact_fraction(value, path)
    except (DomainError, ParseError) as exc:
        raise SpecError(f"{value!r} is not an exact rational ({exc})", path=path) from None


def _list(value: Any, path: str) -> list[Any]:
    if not isinstance(value, (list, tuple)):
        raise SpecError(f"expected a list, got {type(value).__name__} {value!r}", path=path)
    return list(value)


def _rows(value: Any, path: str) -> tuple[tuple[Fraction, ...], ...]:
    return tuple(tuple(_exact(v, f"{path}[{i}][{j}]") for j, v in enumerate(_list(row, f"{path}[{i}]")))
                 for i, row in enumerate(_list(value, path)))


@dataclass(frozen=True)
class MethodOption:
    """One keyword option of a design method.

    ``name`` is the keyword of the design function and the key in the spec's
    ``design:`` section; ``kind`` one of :data:`KINDS`; ``doc`` one line for the
    schema and ``uio-ring schema``; ``required`` options have no default;
    ``nonnegative`` options refuse negative numbers (the error names the entry).
    """

    name: str
    kind: str
    doc: str
    required: bool = False
    nonnegative: bool = False

    def __post_init__(self) -> None:
        if self.kind not in KINDS:
            raise ValueError(f"option {self.name!r}: unknown kind {self.kind!r}")  # noqa: TRY003

    def read(self, value: Any, path: str) -> Any:
        """The option's value from plain data (a spec), exact; errors name ``path``."""
        out = self._read(value, path)
        if self.nonnegative:
            self._check_nonnegative(out, path)
        return out

    def _check_nonnegative(self, value: Any, path: str) -> None:
        if isinstance(value, tuple):
            for i, v in enumerate(value):
                self._check_nonnegative(v, f"{path}[{i}]")
        elif isinstance(value, Fraction) and value < 0:
            raise SpecError(f"{value} is negative; {self.name} must be ≥ 0", path=path)

    def _read(self, value: Any, path: str) -> Any:
        if self.kind == "bool":
            if not isinstance(value, bool):
                raise SpecError(f"expected true or false, got {value!r}", path=path)
            return value
        if self.kind == "rational":
            return _exact(value, path)
        if self.kind == "poles":
            if isinstance(value, str):
                if value != "min-noise":
                    raise SpecError(f"expected a list of rationals or 'min-noise', got {value!r}", path=path)
                return value
            return tuple(_exact(v, f"{path}[{i}]") for i, v in enumerate(_list(value, path)))
        if self.kind == "criterion":
            if value not in KINDS["criterion"]["enum"]:
                raise SpecError(f"expected one of {', '.join(KINDS['criterion']['enum'])}, got {value!r}", path=path)
            return value
        if self.kind == "rationals":
            return tuple(_exact(v, f"{path}[{i}]") for i, v in enumerate(_list(value, path)))
        if self.kind == "integer":
            if isinstance(value, bool) or not isinstance(value, int) or value < 0:
                raise SpecError(f"expected a non-negative integer, got {value!r}", path=path)
            return value
        if self.kind == "rational_matrices":
            return tuple(_rows(M, f"{path}[{k}]") for k, M in enumerate(_list(value, path)))
        if self.kind == "rational_or_rationals":
            if isinstance(value, (list, tuple)):
                return tuple(_exact(v, f"{path}[{i}]") for i, v in enumerate(value))
            return _exact(value, path)
        return _rows(value, path)  # rational_rows

    def schema(self) -> dict[str, Any]:
        """JSON Schema of the option's value, with its description."""
        return {**KINDS[self.kind], "description": self.doc}
