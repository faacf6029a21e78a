"""Reading polynomials and polynomial matrices from text, exactly.

Grammar (whitespace is ignored)::

    matrix := '[' row (',' row)* ']'  |  '[' ']'      (a flat '[a, b]' is one row)
    row    := '[' expr (',' expr)* ']' |  '[' ']'
    expr   := term (('+'|'-') term)*
    term   := unary (('*'|'/') unary | power)*        (2d = 2*d; a number never follows juxtaposed)
    unary  := ('+'|'-') unary | power                 (-d**2 = -(d**2); 1 + -2 is fine)
    power  := atom [('**'|'^') ['+'] INTEGER]
    atom   := NUMBER | VAR | '(' expr ')'

Numbers are read from their decimal text as exact rationals (``0.1`` is
1/10, ``1e-3`` is 1/1000).  The indeterminate is ``d`` by default and ``δ``
is accepted for it; another name (``s``) is chosen with ``var``.  Division is
allowed by nonzero constants only.  Errors give the 1-based column.

>>> from uio_ring.ring._backend import to_str
>>> to_str(parse_poly("(1 + 2δ)^2 - 0.5", "d"), "d")
'4*d**2 + 4*d + 1/2'
>>> parse_poly("1+*d", "d")
Traceback (most recent call last):
...
uio_ring.ring.errors.ParseError: cannot parse '1+*d' at column 3: expected a number, 'd' or '(' but found '*'
"""

from __future__ import annotations

import re
from fractions import Fraction

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring.errors import DomainError, ParseError

__all__ = ["parse_poly", "parse_matrix", "MAX_DEGREE", "canonical_var", "var_aliases"]

#: Largest exponent accepted in text; larger ones are refused rather than expanded.
MAX_DEGREE = 4096

_FUNCTIONS = {"sqrt", "exp", "log", "ln", "sin", "cos", "tan", "pi", "e", "E", "I", "j", "oo"}

_TOKEN = re.compile(
    r"""
    (?P<ws>\s+)
  | (?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?)
  | (?P<pow>\*\*|\^)
  | (?P<op>[-+*/(),\[\]])
  | (?P<name>[^\W\d]\w*)
  | (?P<bad>.)
    """,
    re.VERBOSE,
)


def canonical_var(var: str) -> str:
    """``'δ'`` and ``'d'`` name the same indeterminate, stored as ``'d'``."""
    if not isinstance(var, str) or not var.isidentifier():
        raise DomainError(f"the indeterminate must be a name such as 'd' or 's', got {var!r}")
    return "d" if var in ("d", "δ") else var


def var_aliases(var: str) -> tuple[str, ...]:
    return ("d", "δ") if var == "d" else (var,)


def _tokenize(text: str) -> list[tuple[str, str, int]]:
    tokens = []
    for m in _TOKEN.finditer(text):
        kind = m.lastgroup
        assert kind is not None
        if kind == "ws":
            continue
        if kind == "bad":
            raise ParseError(
                f"cannot parse {text!r} at column {m.start() + 1}: unexpected character {m.group()!r}",
                text=text,
                position=m.start(),
            )
        tokens.append((kind, m.group(), m.start()))
    tokens.append(("end", "", len(text)))
    return tokens


class _Parser:
    def __init__(self, text: str, var: str):
        self.text = text
        self.var = var
        self.names = var_aliases(var)
        self.tokens = _tokenize(text)
        self.i = 0

    # -- helpers --------------------------------------------------------------
    @property
    def tok(self) -> tuple[str, str, int]:
        return self.tokens[self.i]

    def error(self, expected: str) -> ParseError:
        kind, value, pos = self.tok
        found = "the end of the text" if kind == "end" else repr(value)
        return ParseError(
            f"cannot parse {self.text!r} at column {pos + 1}: expected {expected} but found {found}",
            text=self.text,
            position=pos,
        )

    def accept(self, value: str) -> bool:
        if self.tok[1] == value and self.tok[0] in ("op", "pow"):
            self.i += 1
            return True
        return False

    def expect(self, value: str, expected: str | None = None) -> None:
        if not self.accept(value):
            raise self.error(expected or repr(value))

    # -- grammar --------------------------------------------------------------
    def expr(self) -> flint.fmpq_poly:
        value = self.term()
        while self.tok[0] == "op" and self.tok[1] in "+-":
            op = self.tok[1]
            self.i += 1
            rhs = self.term()
            value = value + rhs if op == "+" else value - rhs
        return value

    def term(self) -> flint.fmpq_poly:
        value = self.unary()
        while True:
            kind, tv, pos = self.tok
            if kind == "op" and tv == "*":
                self.i += 1
                value = value * self.unary()
            elif kind == "op" and tv == "/":
                self.i += 1
                divisor = self.unary()
                if divisor.is_zero():
                    raise ParseError(
                        f"cannot parse {self.text!r} at column {pos + 1}: division by zero",
                        text=self.text,
                        position=pos,
                    )
                if divisor.degree() > 0:
                    raise DomainError(
                        f"{self.text!r}, column {pos + 1}: division by the non-constant "
                        f"{bk.to_str(divisor, self.var)!r} does not give a polynomial in "
                        f"{self.var!r}; entries must be polynomials, divide only by nonzero constants"
                    )
                value = value / divisor[0]
            elif kind == "name" or (kind == "op" and tv == "("):
                value = value * self.power()  # juxtaposition: 2d, 3(d + 1); never before a number
            else:
                return value

    def unary(self) -> flint.fmpq_poly:
        kind, tv, _ = self.tok
        if kind == "op" and tv in "+-":
            self.i += 1
            value = self.unary()
            return -value if tv == "-" else value
        return self.power()

    def power(self) -> flint.fmpq_poly:
        base = self.atom()
        if self.tok[0] == "pow":
            self.i += 1
            self.accept("+")
            kind, tv, pos = self.tok
            if kind != "num" or not tv.isdigit():
                raise self.error("a non-negative integer exponent")
            self.i += 1
            e = int(tv)
            if e > MAX_DEGREE:
                raise DomainError(
                    f"{self.text!r}, column {pos + 1}: exponent {e} exceeds the limit "
                    f"{MAX_DEGREE} (uio_ring.ring.parse.MAX_DEGREE)"
                )
            if base.degree() > 0 and base.degree() * e > MAX_DEGREE:
                raise DomainError(
                    f"{self.text!r}, column {pos + 1}: the power has degree "
                    f"{base.degree() * e}, above the limit {MAX_DEGREE}"
                )
            return base**e
        return base

    def atom(self) -> flint.fmpq_poly:
        kind, tv, pos = self.tok
        if kind == "num":
            self.i += 1
            return bk.const(Fraction(tv))
        if kind == "name":
            self.i += 1
            if tv in self.names:
                return bk.GEN
            if tv in _FUNCTIONS:
                raise DomainError(
                    f"{self.text!r}, column {pos + 1}: {tv!r} is not rational; coefficients "
                    "must be exact rationals such as 2, -1/3 or 0.25"
                )
            raise DomainError(
                f"{self.text!r}, column {pos + 1}: unknown symbol {tv!r}; the indeterminate is "
                f"{' or '.join(repr(n) for n in self.names)}"
            )
        if kind == "op" and tv == "(":
            self.i += 1
            value = self.expr()
            self.expect(")", "')'")
            return value
        raise self.error(f"a number, {self.names[0]!r} or '('")

    def row(self) -> list[flint.fmpq_poly]:
        self.expect("[", "'['")
        if self.accept("]"):
            return []
        entries = [self.expr()]
        while self.accept(","):
            entries.append(self.expr())
        self.expect("]", "',' or ']'")
        return entries

    def matrix(self) -> list[list[flint.fmpq_poly]]:
        if self.tok[1] != "[":
            # a single polynomial is a 1×1 matrix
            return [[self.expr()]]
        if self.tokens[self.i + 1][1] != "[":
            return [self.row()]  # flat '[a, b]': one row
        self.expect("[")
        rows = [self.row()]
        while self.accept(","):
            rows.append(self.row())
        self.expect("]", "',' or ']'")
        return rows

    def finish(self) -> None:
        if self.tok[0] != "end":
            raise self.error("an operator or the end of the text")


def parse_poly(text: str, var: str = "d") -> flint.fmpq_poly:
    """Parse one polynomial (raises :class:`ParseError` / :class:`DomainError`)."""
    if not text.strip():
        raise ParseError("cannot parse an empty text as a polynomial", text=text, position=0)
    p = _Parser(text, canonical_var(var))
    value = p.expr()
    p.finish()
    return value


def parse_matrix(text: str, var: str = "d") -> list[list[flint.fmpq_poly]]:
    """Parse ``[[a, b], [c, d]]`` into rows of polynomials (rows may be ragged; the caller checks)."""
    if not text.strip():
        raise ParseError("cannot parse an empty text as a matrix", text=text, position=0)
    p = _Parser(text, canonical_var(var))
    rows = p.matrix()
    p.finish()
    return rows
