"""Reading YAML exactly and safely.

* Numbers keep their decimal text: ``0.01`` is read as ``Fraction(1, 100)``,
  never through a binary float (PyYAML's float constructor is replaced).
* One rule for plain scalars, YAML 1.2's core schema: numbers are decimal
  (``017`` is 17, ``1:30``, ``0x1F``, ``0o17`` and ``1_000`` are text, not
  numbers — YAML 1.1's sexagesimal, octal and hexadecimal forms are not
  used), booleans are ``true``/``false`` only (``yes``, ``no``, ``on``,
  ``off`` are text), and dates stay text.  Explicitly tagged ``!!int`` and
  ``!!float`` values must be decimal too.
* Numbers are bounded before they are built (``uio_ring.ring.parse.MAX_NUMBER_DIGITS``
  digits): ``1e99999999`` is refused, not expanded.
* A key may appear once in a mapping: a repeated ``A`` (or ``0`` and
  ``'0'``) is an error naming the path, never "the last one wins".
* Only the safe subset of YAML (no Python objects).
* Limits against hostile files: the text size, the number of aliases
  (a "billion laughs" bomb expands a few aliases into gigabytes) and the
  nesting depth.

>>> load_yaml_text("h: 0.01\\nk: [1, 2.5e-1]")
{'h': Fraction(1, 100), 'k': [1, Fraction(1, 4)]}
"""

from __future__ import annotations

import re
from typing import Any

import yaml

from uio_ring.errors import SpecError

__all__ = ["load_yaml_text", "dump_yaml", "MAX_BYTES", "MAX_ALIASES", "MAX_DEPTH"]

#: Largest spec text accepted (bytes).
MAX_BYTES = 1_000_000
#: Most aliases (``*name``) accepted in one document.
MAX_ALIASES = 20
#: Deepest nesting of lists/mappings accepted.
MAX_DEPTH = 20


_MERGE = "tag:yaml.org,2002:merge"


class _ExactLoader(yaml.SafeLoader):
    """SafeLoader with YAML 1.2 core scalars, exact numbers, unique keys and alias/depth limits."""

    def __init__(self, stream: str):
        super().__init__(stream)
        self._aliases = 0
        self._depth = 0
        self._path: list[Any] = []

    def path_text(self, extra: Any = None) -> str:
        out = ""
        for part in [*self._path, *([] if extra is None else [extra])]:
            out = f"{out}[{part}]" if isinstance(part, int) else (f"{out}.{part}" if out else str(part))
        return out

    def compose_node(self, parent: Any, index: Any) -> Any:  # type: ignore[override]
        if self.check_event(yaml.AliasEvent):
            self._aliases += 1
            if self._aliases > MAX_ALIASES:
                mark = self.peek_event().start_mark
                raise SpecError(
                    f"more than {MAX_ALIASES} YAML aliases (line {mark.line + 1}); aliases are "
                    "limited to refuse 'billion laughs' files — write the values out"
                )
        self._depth += 1
        pushed = index is not None
        if pushed:
            self._path.append(index if isinstance(index, int) else getattr(index, "value", "?"))
        try:
            if self._depth > MAX_DEPTH:
                mark = self.peek_event().start_mark
                raise SpecError(f"nesting deeper than {MAX_DEPTH} levels (line {mark.line + 1})", path=self.path_text() or None)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1
            if pushed:
                self._path.pop()

    def compose_scalar_node(self, anchor: Any) -> Any:
        node = super().compose_scalar_node(anchor)
        if node.tag == "tag:yaml.org,2002:int":
            _exact_int(self, node)  # checked here, where the path is known
        elif node.tag == "tag:yaml.org,2002:float":
            _exact_float(self, node)
        return node

    def compose_mapping_node(self, anchor: Any) -> Any:
        node = super().compose_mapping_node(anchor)
        seen: dict[Any, int] = {}
        for key, _ in node.value:
            if not isinstance(key, yaml.ScalarNode) or key.tag == _MERGE:
                continue
            text = str(key.value).strip()
            line = key.start_mark.line + 1
            ident = _key_identity(text)
            if ident in seen:
                raise SpecError(
                    f"the key {text!r} appears twice (lines {seen[ident]} and {line}); each key may appear once"
                    " (0, '0' and 0.0 are the same key)",
                    path=self.path_text(text),
                )
            seen[ident] = line
        return node


def _key_identity(text: str) -> Any:
    """Keys that name the same thing collide: ``0``, ``'0'`` and ``0.0`` are one key."""
    from uio_ring.ring.parse import decimal_fraction

    if len(text) <= 40 and re.fullmatch(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?", text):
        try:
            return ("number", decimal_fraction(text))
        except (ValueError, TypeError):
            pass
    return ("text", text)


# YAML 1.2 core schema for plain scalars (PyYAML implements YAML 1.1's wider rules).
_ExactLoader.yaml_implicit_resolvers = {}
for _tag, _regexp, _first in (
    ("tag:yaml.org,2002:bool", r"^(?:true|True|TRUE|false|False|FALSE)$", "tTfF"),
    ("tag:yaml.org,2002:int", r"^[-+]?[0-9]+$", "-+0123456789"),
    (
        "tag:yaml.org,2002:float",
        r"^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?|[-+]?\.(?:inf|Inf|INF)|\.(?:nan|NaN|NAN))$",
        "-+0123456789.",
    ),
    ("tag:yaml.org,2002:null", r"^(?:~|null|Null|NULL|)$", ["~", "n", "N", ""]),
    (_MERGE, r"^(?:<<)$", "<"),
):
    _ExactLoader.add_implicit_resolver(_tag, re.compile(_regexp), list(_first))


def _number_error(loader: _ExactLoader, node: yaml.ScalarNode, message: str) -> SpecError:
    return SpecError(f"{message} (line {node.start_mark.line + 1})", path=loader.path_text() or None)


def _exact_float(loader: _ExactLoader, node: yaml.ScalarNode) -> Any:
    from uio_ring.ring.errors import DomainError, ParseError
    from uio_ring.ring.parse import decimal_fraction

    text = str(loader.construct_scalar(node))
    low = text.lower()
    if low in (".inf", "+.inf", "-.inf", ".nan"):
        return float(low.replace(".", "", 1))  # rejected later with a clear message
    try:
        return decimal_fraction(text)
    except DomainError as exc:
        raise _number_error(loader, node, str(exc).removeprefix("number: ")) from None
    except ParseError:
        raise _number_error(loader, node, f"{text!r} is not a decimal number") from None


def _exact_int(loader: _ExactLoader, node: yaml.ScalarNode) -> Any:
    from uio_ring.ring.parse import MAX_NUMBER_DIGITS

    text = str(loader.construct_scalar(node)).strip()
    if not re.fullmatch(r"[-+]?[0-9]+", text):
        raise _number_error(loader, node, f"{text!r} is not a decimal integer (numbers are read by YAML 1.2's rule)")
    if len(text.lstrip("+-").lstrip("0")) > MAX_NUMBER_DIGITS:
        raise _number_error(
            loader, node, f"an integer of {len(text)} digits exceeds {MAX_NUMBER_DIGITS} digits (uio_ring.ring.parse.MAX_NUMBER_DIGITS)"
        )
    return int(text)


_ExactLoader.add_constructor("tag:yaml.org,2002:float", _exact_float)
_ExactLoader.add_constructor("tag:yaml.org,2002:int", _exact_int)


def load_yaml_text(text: str, *, max_bytes: int = MAX_BYTES) -> Any:
    """Parse YAML text into plain data with exact numbers (raises :class:`SpecError`)."""
    if len(text) > max_bytes or len(text.encode("utf-8", errors="replace")) > max_bytes:
        raise SpecError(f"the file is larger than {max_bytes} bytes; a spec is a few kilobytes")
    if not text.strip():
        raise SpecError("the file is empty; a spec needs at least a 'system' section")
    try:
        return yaml.load(text, Loader=_ExactLoader)  # noqa: S506 - SafeLoader subclass
    except SpecError:
        raise
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark else ""
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise SpecError(f"not valid YAML{where}: {problem}") from exc
    except (ValueError, TypeError, RecursionError) as exc:
        raise SpecError(f"not valid YAML: {exc}") from exc


def dump_yaml(data: dict[str, Any]) -> str:
    """YAML text of a mapping of plain data; Fractions are written as exact strings
    (``1/3``), each list of scalars on one line (a matrix row per line).  See
    :mod:`uio_ring.spec.yaml_writer` (PyYAML's representer took a second for a
    design file of 240 000 scalars)."""
    from uio_ring.spec.yaml_writer import dump_plain_yaml

    return dump_plain_yaml(data)
