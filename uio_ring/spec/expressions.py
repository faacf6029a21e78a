"""Signals written as expressions in ``t``, parsed safely (no ``eval``).

Grammar: numbers, ``t``, ``pi``, ``e``, ``+ - * / ** ^``, parentheses, and the
functions ``sin cos tan exp log sqrt abs sign tanh sinh cosh atan``, plus
``step(t - a)`` (Heaviside, 1 for arguments ≥ 0).  The result is a function of a
NumPy array of times.  Numeric side only (floats are fine here).

>>> import numpy as np
>>> f = parse_signal("-10*sin(100*t)")
>>> float(f(np.array([np.pi / 200]))[0])
-10.0
>>> parse_signal("t + ")
Traceback (most recent call last):
...
uio_ring.errors.SpecError: cannot parse 't + ' at column 5: expected a number, 't', a function or '(' but found the end of the text
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from typing import Any

from uio_ring.errors import SpecError

__all__ = ["parse_signal", "FUNCTIONS", "MAX_LENGTH"]

#: Longest expression accepted (characters).
MAX_LENGTH = 2000

FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "sqrt", "abs", "sign", "tanh", "sinh", "cosh", "atan", "step")
_CONSTANTS = {"pi": math.pi, "e": math.e}

_TOKEN = re.compile(
    r"(?P<ws>\s+)|(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<pow>\*\*|\^)"
    r"|(?P<op>[-+*/(),])|(?P<name>[A-Za-z_]\w*)|(?P<bad>.)"
)

Node = tuple[Any, ...]


class _Parser:
    def __init__(self, text: str):
        self.text = text
        self.tokens: list[tuple[str, str, int]] = []
        for m in _TOKEN.finditer(text):
            kind = m.lastgroup or "bad"
            if kind == "ws":
                continue
            if kind == "bad":
                raise SpecError(f"cannot parse {text!r} at column {m.start() + 1}: unexpected {m.group()!r}")
            self.tokens.append((kind, m.group(), m.start()))
        self.tokens.append(("end", "", len(text)))
        self.i = 0

    def error(self, expected: str) -> SpecError:
        kind, value, pos = self.tokens[self.i]
        found = "the end of the text" if kind == "end" else repr(value)
        return SpecError(f"cannot parse {self.text!r} at column {pos + 1}: expected {expected} but found {found}")

    def peek(self) -> tuple[str, str, int]:
        return self.tokens[self.i]

    def take(self, value: str) -> bool:
        if self.tokens[self.i][1] == value and self.tokens[self.i][0] in ("op", "pow"):
            self.i += 1
            return True
        return False

    def expr(self) -> Node:
        node = self.term()
        while self.peek()[0] == "op" and self.peek()[1] in "+-":
            op = self.peek()[1]
            self.i += 1
            node = (op, node, self.term())
        return node

    def term(self) -> Node:
        node = self.unary()
        while self.peek()[0] == "op" and self.peek()[1] in "*/":
            op = self.peek()[1]
            self.i += 1
            node = (op, node, self.unary())
        return node

    def unary(self) -> Node:
        if self.peek()[0] == "op" and self.peek()[1] in "+-":
            op = self.peek()[1]
            self.i += 1
            inner = self.unary()
            return ("neg", inner) if op == "-" else inner
        return self.power()

    def power(self) -> Node:
        base = self.atom()
        if self.peek()[0] == "pow":
            self.i += 1
            return ("**", base, self.unary())
        return base

    def atom(self) -> Node:
        kind, value, pos = self.peek()
        if kind == "num":
            self.i += 1
            return ("num", float(value))
        if kind == "name":
            self.i += 1
            if value == "t":
                return ("t",)
            if value in _CONSTANTS:
                return ("num", _CONSTANTS[value])
            if value in FUNCTIONS:
                if not self.take("("):
                    raise self.error(f"'(' after {value}")
                arg = self.expr()
                if not self.take(")"):
                    raise self.error("')'")
                return ("call", value, arg)
            raise SpecError(
                f"cannot parse {self.text!r} at column {pos + 1}: unknown name {value!r}; "
                f"use t, pi, e or one of {', '.join(FUNCTIONS)}"
            )
        if self.take("("):
            node = self.expr()
            if not self.take(")"):
                raise self.error("')'")
            return node
        raise self.error("a number, 't', a function or '('")


def _compile(node: Node) -> Callable[[Any], Any]:
    import numpy as np

    kind = node[0]
    if kind == "num":
        value = node[1]
        return lambda t: np.full_like(t, value, dtype=float)
    if kind == "t":
        return lambda t: np.asarray(t, dtype=float)
    if kind == "neg":
        f = _compile(node[1])
        return lambda t: -f(t)
    if kind == "call":
        name, f = node[1], _compile(node[2])
        if name == "step":
            return lambda t: np.where(f(t) >= 0, 1.0, 0.0)
        fn = {"abs": np.abs, "atan": np.arctan}.get(name) or getattr(np, name)
        return lambda t: fn(f(t))
    a, b = _compile(node[1]), _compile(node[2])
    ops = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.divide, "**": np.power}
    op = ops[kind]
    return lambda t: op(a(t), b(t))


def parse_signal(text: Any) -> Callable[[Any], Any]:
    """A vectorised function of t from an expression (or a constant number)."""
    if not isinstance(text, str):
        value = float(text)
        text = repr(value)
    if len(text) > MAX_LENGTH:
        raise SpecError(f"expression longer than {MAX_LENGTH} characters")
    if not text.strip():
        raise SpecError("an empty expression; write e.g. 0 or sin(t)")
    p = _Parser(text)
    node = p.expr()
    if p.peek()[0] != "end":
        raise p.error("an operator or the end of the text")
    return _compile(node)
