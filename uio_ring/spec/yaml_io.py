"""Reading YAML exactly and safely.

* Numbers keep their decimal text: ``0.01`` is read as ``Fraction(1, 100)``,
  never through a binary float (PyYAML's float constructor is replaced).
* Only the safe subset of YAML (no Python objects).
* Limits against hostile files: the text size, the number of aliases
  (a "billion laughs" bomb expands a few aliases into gigabytes) and the
  nesting depth.

>>> load_yaml_text("h: 0.01\\nk: [1, 2.5e-1]")
{'h': Fraction(1, 100), 'k': [1, Fraction(1, 4)]}
"""

from __future__ import annotations

from fractions import Fraction
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


class _ExactLoader(yaml.SafeLoader):
    """SafeLoader with exact numbers and alias/depth limits."""

    def __init__(self, stream: str):
        super().__init__(stream)
        self._aliases = 0
        self._depth = 0

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
        try:
            if self._depth > MAX_DEPTH:
                mark = self.peek_event().start_mark
                raise SpecError(f"nesting deeper than {MAX_DEPTH} levels (line {mark.line + 1})")
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1


def _exact_float(loader: yaml.SafeLoader, node: yaml.ScalarNode) -> Any:
    text = str(loader.construct_scalar(node)).replace("_", "")
    low = text.lower()
    if low in (".inf", "+.inf", "-.inf", ".nan"):
        return float(low.replace(".", "", 1))  # rejected later with a clear message
    try:
        return Fraction(text)
    except (ValueError, ZeroDivisionError):
        return text


_ExactLoader.add_constructor("tag:yaml.org,2002:float", _exact_float)


def load_yaml_text(text: str) -> Any:
    """Parse YAML text into plain data with exact numbers (raises :class:`SpecError`)."""
    if len(text.encode("utf-8", errors="replace")) > MAX_BYTES:
        raise SpecError(f"the file is larger than {MAX_BYTES} bytes; a spec is a few kilobytes")
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


def _represent_fraction(dumper: yaml.SafeDumper, value: Fraction) -> Any:
    text = str(value.numerator) if value.denominator == 1 else f"{value.numerator}/{value.denominator}"
    return dumper.represent_str(text)


class _Dumper(yaml.SafeDumper):
    pass


_Dumper.add_representer(Fraction, _represent_fraction)


def dump_yaml(data: Any) -> str:
    """YAML text of plain data; Fractions are written as exact strings (``'1/3'``)."""
    return yaml.dump(data, Dumper=_Dumper, sort_keys=False, allow_unicode=True, width=100)
