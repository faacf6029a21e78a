"""Writing plain data as YAML text, fast and readably (the design files).

A design file of a 32-state system holds about 240 000 scalars; PyYAML spends
about a second on them (its representer and resolver run in Python for every
scalar, even with libyaml's emitter).  The data written here is plain — mappings
with string keys, lists, strings, integers, floats, booleans, ``None`` and
``Fraction`` (written as its exact text ``'1/3'``) — so this module writes it
directly in one pass:

* a list whose items are all scalars is one line in flow style,
  ``[-3*d, 2*d + 1, '0']``: a matrix row per line;
* a string is written plain only when no YAML reader can take it for anything
  but that string: it uses only the characters of polynomial text (letters,
  digits, ``_ * + - / ( ) . ^`` and single inner spaces), it is not a
  number, a boolean or null under YAML 1.1 or 1.2 (``'0'``, ``'1e5'``, ``'yes'``,
  ``'.inf'`` are quoted), and it neither starts with an indicator
  (``*``, a lone ``-``, a document marker ``---``) nor ends with a space;
* every other string is double-quoted with YAML escapes (``\\n``, ``\\x85``,
  ``\\u2028``, ``\\U0001d173``) for the characters a YAML stream may not carry
  raw, so any text round-trips.

``yaml.safe_load(dump_plain_yaml(x)) == x`` for every such ``x`` (Fractions read
back as their text); the tests check it with hypothesis against PyYAML's reader
and against this package's exact reader.  Cost: one pass over the data, O(size
of the text).

>>> print(dump_plain_yaml({"A": [["d", "0"], ["1/3", "-2*d + 1"]], "lag": 1, "ok": True}), end="")
A:
- [d, '0']
- [1/3, -2*d + 1]
lag: 1
ok: true
"""

from __future__ import annotations

import functools
import json
import math
import re
from fractions import Fraction
from typing import Any

import yaml

__all__ = ["dump_plain_yaml"]

#: Characters of polynomial text; a plain scalar uses nothing else.
_PLAIN = re.compile(r"[A-Za-z0-9_*+/().^-]+(?: [A-Za-z0-9_*+/().^-]+)*")
#: A character that no number, date, boolean or null of YAML 1.1 or 1.2 contains.
_NOT_A_VALUE = re.compile(r"[*/()^ ]")
_STR = "tag:yaml.org,2002:str"


@functools.lru_cache(maxsize=4096)
def _resolves_to_str(s: str) -> bool:
    """Both readers — PyYAML's YAML 1.1 rules and this package's YAML 1.2 core rules —
    read the plain scalar ``s`` as a string (not ``0``, ``1e5``, ``yes``, ``.inf``,
    ``2001-12-14`` …)."""
    from uio_ring.spec.yaml_io import _ExactLoader

    # both resolvers keep their tables on the class: the class itself serves as ``self``
    return all(r.resolve(r, yaml.ScalarNode, s, (True, False)) == _STR  # type: ignore[arg-type]
               for r in (yaml.resolver.Resolver, _ExactLoader))


def _plain_ok(s: str) -> bool:
    """May ``s`` be written as a plain scalar (also inside a flow sequence)?"""
    if not _PLAIN.fullmatch(s) or s == "-" or s.startswith(("- ", "---", "...", "*")):
        return False  # "-" and "- x" are sequence entries ("-x" is fine); "*x" an alias
    # polynomial text ("2*d + 1") is never a number: the resolvers only decide the rest
    return bool(_NOT_A_VALUE.search(s)) or _resolves_to_str(s)


def _escape(ch: str) -> str:
    code = ord(ch)
    if code <= 0xFF:
        return f"\\x{code:02x}"
    return f"\\u{code:04x}" if code <= 0xFFFF else f"\\U{code:08x}"


def _quoted(s: str) -> str:
    """A double-quoted YAML scalar for any text."""
    if s.isprintable():  # only '"' and '\\' need escapes: the JSON string is a YAML one
        return json.dumps(s, ensure_ascii=False)
    body = "".join(
        "\\\\" if ch == "\\" else '\\"' if ch == '"' else (ch if ch.isprintable() else _escape(ch))
        for ch in s
    )
    return f'"{body}"'


def _scalar(value: Any) -> str:
    if type(value) is str:  # the common case first: the exact coefficients' text
        if _plain_ok(value):
            return value
        return f"'{value}'" if _PLAIN.fullmatch(value) else _quoted(value)
    if value is None:
        return "null"
    if value is True:
        return "true"
    if value is False:
        return "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):  # PyYAML's text of a float (readable back by both schemas)
        if math.isnan(value):
            return ".nan"
        if math.isinf(value):
            return ".inf" if value > 0 else "-.inf"
        text = repr(value).lower()
        if "." not in text and "e" in text:
            text = text.replace("e", ".0e", 1)
        return text
    if isinstance(value, (Fraction, str)):
        return _scalar(str(value))
    raise TypeError(f"cannot write {type(value).__name__} as YAML")


_SCALAR_TYPES = frozenset({str, int, float, bool, type(None), Fraction})


def _is_scalar(value: Any) -> bool:
    return type(value) in _SCALAR_TYPES or isinstance(value, (str, int, float, Fraction))


def _lines(value: Any, indent: str, out: list[str]) -> None:
    """Append the block lines of a mapping or list ``value`` at ``indent``."""
    if isinstance(value, dict):
        for key, item in value.items():
            if not isinstance(key, str):
                raise TypeError(f"cannot write a {type(key).__name__} key as YAML")
            head = f"{indent}{_scalar(key)}:"
            _item(head, item, indent, out)
    else:
        for item in value:
            _item(f"{indent}-", item, indent + "  ", out, in_list=True)


def _item(head: str, item: Any, indent: str, out: list[str], *, in_list: bool = False) -> None:
    """Append ``head`` (``key:`` or ``-``) with ``item``; a nested block of a list entry
    starts on the entry's line (``- - a``, ``- key: v``), as PyYAML writes it."""
    if _is_scalar(item):
        out.append(f"{head} {_scalar(item)}")
        return
    if isinstance(item, (list, tuple)) and all(_is_scalar(x) for x in item):
        out.append(f"{head} [{', '.join(_scalar(x) for x in item)}]")
        return
    if isinstance(item, dict) and not item:
        out.append(f"{head} {{}}")
        return
    if not isinstance(item, (list, tuple, dict)):
        raise TypeError(f"cannot write {type(item).__name__} as YAML")
    block: list[str] = []
    _lines(item, indent + "  " if isinstance(item, dict) and not in_list else indent, block)
    if in_list:
        out.append(f"{head} {block[0][len(indent):]}")
        out.extend(block[1:])
    else:
        out.append(head)
        out.extend(block)


def dump_plain_yaml(data: dict[str, Any]) -> str:
    """YAML text of a mapping of plain data (see the module docstring)."""
    if not isinstance(data, dict):
        raise TypeError("dump_plain_yaml writes a mapping")
    if not data:
        return "{}\n"
    out: list[str] = []
    _lines(data, "", out)
    return "\n".join(out) + "\n"
