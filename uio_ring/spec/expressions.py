"""Signals written as expressions in ``t``, parsed safely (no ``eval``).

Grammar: numbers, ``t``, ``pi``, ``e``, ``+ - * / ** ^``, parentheses, and the
functions ``sin cos tan exp log sqrt abs sign tanh sinh cosh atan``, plus
``step(t - a)`` (Heaviside, 1 for arguments ≥ 0).  The result is a function of a
NumPy array of times.  Numeric side only (floats are fine here).

Bounded: at most ``MAX_LENGTH`` characters, parentheses, function calls and
powers nested at most ``MAX_NESTING`` deep, any number of unary signs (read
iteratively), numbers that fit a float64.  Evaluation runs a flat program on
a stack, so a long chain ``t + t + … + t`` cannot exhaust Python's recursion.

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

import functools
import math
import re
from collections.abc import Callable
from typing import Any

from uio_ring.errors import SpecError

__all__ = ["parse_signal", "parse_state_function", "FUNCTIONS", "MAX_LENGTH", "MAX_NESTING"]

#: Longest expression accepted (characters).
MAX_LENGTH = 2000
#: Deepest nesting of parentheses, calls and powers accepted.
MAX_NESTING = 50

FUNCTIONS = ("sin", "cos", "tan", "exp", "log", "sqrt", "abs", "sign", "tanh", "sinh", "cosh", "atan", "step")
_CONSTANTS = {"pi": math.pi, "e": math.e}

_TOKEN = re.compile(
    r"(?P<ws>\s+)|(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)|(?P<pow>\*\*|\^)"
    r"|(?P<op>[-+*/(),])|(?P<name>[A-Za-z_]\w*)|(?P<bad>.)"
)

Node = tuple[Any, ...]


class _Parser:
    def __init__(self, text: str, variables: frozenset[str] = frozenset()):
        self.text = text
        self.variables = variables
        self.tokens: list[tuple[str, str, int]] = []
        for m in _TOKEN.finditer(text):
            kind = m.lastgroup or "bad"
            if kind == "ws":
                continue
            if kind == "bad":
                raise SpecError(f"cannot parse {_short(text)} at column {m.start() + 1}: unexpected {m.group()!r}")
            self.tokens.append((kind, m.group(), m.start()))
        self.tokens.append(("end", "", len(text)))
        self.i = 0
        self.depth = 0

    def enter(self) -> None:
        self.depth += 1
        if self.depth > MAX_NESTING:
            pos = self.peek()[2]
            raise SpecError(
                f"cannot parse {_short(self.text)} at column {pos + 1}: nested deeper than {MAX_NESTING} "
                "(parentheses, calls and powers)"
            )

    def error(self, expected: str) -> SpecError:
        kind, value, pos = self.tokens[self.i]
        found = "the end of the text" if kind == "end" else repr(value)
        return SpecError(f"cannot parse {_short(self.text)} at column {pos + 1}: expected {expected} but found {found}")

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
        negative = False
        while self.peek()[0] == "op" and self.peek()[1] in "+-":  # iterative: any number of signs
            negative ^= self.peek()[1] == "-"
            self.i += 1
        inner = self.power()
        return ("neg", inner) if negative else inner

    def power(self) -> Node:
        base = self.atom()
        if self.peek()[0] == "pow":
            self.i += 1
            self.enter()
            exponent = self.unary()
            self.depth -= 1
            return ("**", base, exponent)
        return base

    def atom(self) -> Node:
        kind, value, pos = self.peek()
        if kind == "num":
            self.i += 1
            number = float(value)
            if not math.isfinite(number):
                raise SpecError(
                    f"cannot parse {_short(self.text)} at column {pos + 1}: the number {_short(value)} "
                    "is too large for a float64"
                )
            return ("num", number)
        if kind == "name":
            self.i += 1
            if value == "t":
                return ("t",)
            if value in self.variables:
                return ("var", value)
            if value in _CONSTANTS:
                return ("num", _CONSTANTS[value])
            if value in FUNCTIONS:
                if not self.take("("):
                    raise self.error(f"'(' after {value}")
                self.enter()
                arg = self.expr()
                self.depth -= 1
                if not self.take(")"):
                    raise self.error("')'")
                return ("call", value, arg)
            names = "t, " + "".join(f"{v}, " for v in sorted(self.variables))
            raise SpecError(
                f"cannot parse {_short(self.text)} at column {pos + 1}: unknown name {_short(value)}; "
                f"use {names}pi, e or one of {', '.join(FUNCTIONS)}"
            )
        if self.take("("):
            self.enter()
            node = self.expr()
            self.depth -= 1
            if not self.take(")"):
                raise self.error("')'")
            return node
        raise self.error("a number, 't', a function or '('")


def _short(text: str) -> str:
    return repr(text) if len(text) <= 60 else repr(text[:40] + "…") + f" ({len(text)} characters)"


def _program(node: Node) -> list[Node]:
    """The tree as a postfix program, built without recursion."""
    out: list[Node] = []
    stack: list[tuple[Node, bool]] = [(node, False)]
    while stack:
        item, expanded = stack.pop()
        kind = item[0]
        if kind in ("num", "t", "var"):
            out.append(item)
        elif expanded:
            out.append((kind, item[1]) if kind == "call" else (kind,))
        else:
            stack.append((item, True))
            children = [item[2]] if kind == "call" else list(item[1:])
            for child in reversed(children):
                stack.append((child, False))
    return out


@functools.cache
def _numpy_operations() -> tuple[Any, dict[str, Any], dict[str, Any]]:
    """numpy, its binary operators and the functions of the grammar, imported at the first
    evaluation (once)."""
    import numpy as np

    binary = {"+": np.add, "-": np.subtract, "*": np.multiply, "/": np.divide, "**": np.power}
    functions = {name: ({"abs": np.abs, "atan": np.arctan}.get(name) or getattr(np, name, None)) for name in FUNCTIONS}
    return np, binary, functions


def _evaluator(node: Node) -> Callable[[Any, dict[str, Any], Any], Any]:
    """The postfix program of ``node`` (no recursion) as ``run(t, env, like)``: ``t`` the time,
    ``env`` the values of state names, numbers broadcast like ``like`` (or left scalar).
    numpy is imported at the first evaluation, not here: loading a spec (``uio-ring check``)
    evaluates nothing."""
    program = _program(node)

    def run(t: Any, env: dict[str, Any], like: Any) -> Any:
        np, binary, functions = _numpy_operations()
        stack: list[Any] = []
        with np.errstate(all="ignore"):  # non-finite values are caught where the simulation is checked
            for op in program:
                kind = op[0]
                if kind == "num":
                    stack.append(op[1] if like is None else np.full_like(like, op[1], dtype=float))
                elif kind == "t":
                    stack.append(t)
                elif kind == "var":
                    stack.append(env[op[1]])
                elif kind == "neg":
                    stack.append(-stack.pop())
                elif kind == "call":
                    x = stack.pop()
                    stack.append(np.where(x >= 0, 1.0, 0.0) if op[1] == "step" else functions[op[1]](x))
                else:
                    b = stack.pop()
                    stack.append(binary[kind](stack.pop(), b))
        return stack[0]

    return run


def _compile(node: Node) -> Callable[[Any], Any]:
    """A function of t (arrays broadcast)."""
    evaluate = _evaluator(node)

    def run(t: Any) -> Any:
        import numpy as np

        t = np.asarray(t, dtype=float)
        return evaluate(t, {}, t)

    return run


def _compile_env(node: Node) -> Callable[[dict[str, Any]], Any]:
    """Like :func:`_compile`, for a function of an environment ``{"t": …, name: …}``."""
    evaluate = _evaluator(node)

    def run(env: dict[str, Any]) -> Any:
        return evaluate(env["t"], env, None)

    return run


def parse_state_function(texts: Any, variables: Any) -> Callable[[float, Any], Any]:
    """``φ(t, x)`` from one expression per component, in ``t`` and the state names ``variables``.

    Same grammar as :func:`parse_signal`, plus the names in ``variables`` (identifiers:
    the state names of the system).  The result maps a float t and a vector x
    (``len(variables)`` entries) to an array of ``len(texts)`` floats.

    >>> import numpy as np
    >>> phi = parse_state_function(["sin(t)*x2", "-x1^3"], ["x1", "x2"])
    >>> phi(np.pi / 2, np.array([2.0, 3.0])).tolist()
    [3.0, -8.0]
    """
    names = list(variables)
    bad = [v for v in names if not re.fullmatch(r"[A-Za-z_]\w*", v) or v == "t" or v in _CONSTANTS or v in FUNCTIONS]
    if bad:
        raise SpecError(f"state name {bad[0]!r} cannot be used in an expression: name the states with "
                        "identifiers (letters, digits, _) other than t, pi, e and the function names")
    fs = []
    for text in texts:
        if not isinstance(text, str):
            text = repr(float(text))
        if len(text) > MAX_LENGTH:
            raise SpecError(f"expression longer than {MAX_LENGTH} characters")
        if not text.strip():
            raise SpecError("an empty expression; write e.g. 0 or sin(t)*x1")
        p = _Parser(text, frozenset(names))
        node = p.expr()
        if p.peek()[0] != "end":
            raise p.error("an operator or the end of the text")
        fs.append(_compile_env(node))

    def phi(t: float, x: Any) -> Any:
        np = _numpy_operations()[0]
        env = dict(zip(names, np.asarray(x, dtype=float).reshape(-1), strict=True))
        env["t"] = float(t)
        return np.array([float(f(env)) for f in fs])

    return phi


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
