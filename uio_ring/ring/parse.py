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
1/10, ``1e-3`` is 1/1000).

Work is bounded before it is done, so hostile text fails fast instead of
hanging: a number may imply at most ``MAX_NUMBER_DIGITS`` decimal digits
(digits written plus the size of its exponent, so ``1e99999999`` is refused
before ``10**99999999`` is built); the degree of every sum, product and power
is known before it is computed and may not exceed ``max_degree`` (default
``MAX_DEGREE``); coefficients may not exceed ``max_bits`` bits (estimated
before each product and power); parentheses nest at most ``MAX_NESTING``
deep.  Unary signs are read iteratively (any number of them).  The indeterminate is ``d`` by default and ``δ``
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

__all__ = [
    "parse_poly",
    "parse_matrix",
    "decimal_fraction",
    "MAX_DEGREE",
    "MAX_BITS",
    "MAX_NESTING",
    "MAX_NUMBER_DIGITS",
    "canonical_var",
    "var_aliases",
]

#: Largest degree (of any exponent, product or result) accepted in text; larger ones
#: are refused rather than expanded.
MAX_DEGREE = 4096
#: Largest coefficient size accepted in text, in bits of numerator plus denominator
#: (estimated before each product or power is computed).
MAX_BITS = 65536
#: Deepest nesting of parentheses accepted in text.
MAX_NESTING = 100
#: Most decimal digits a number in text may imply: the digits written plus the
#: absolute value of its exponent (``1e-5`` implies 6).  ``10**1000`` fits.
MAX_NUMBER_DIGITS = 1000

_DECIMAL = re.compile(r"\s*([+-]?)(\d*)(?:\.(\d*))?(?:[eE]([+-]?\d+))?\s*\Z")


def decimal_fraction(text: str, where: str = "number", *, max_digits: int = MAX_NUMBER_DIGITS) -> Fraction:
    """The exact value of decimal text (``"0.1"``, ``"-2.5e-3"``, ``"7"``, ``"1/3"``), bounded.

    Unlike ``Fraction(text)``, the size is checked before the number is built:
    text implying more than ``max_digits`` (default ``MAX_NUMBER_DIGITS``) digits raises
    :class:`DomainError` at once (``Fraction("1e99999999")`` would build
    ``10**99999999``).  Malformed text raises :class:`ParseError`.

    >>> decimal_fraction("0.1"), decimal_fraction("-1e-3"), decimal_fraction("2/6")
    (Fraction(1, 10), Fraction(-1, 1000), Fraction(1, 3))
    >>> decimal_fraction("1e99999999")
    Traceback (most recent call last):
    ...
    uio_ring.ring.errors.DomainError: number: '1e99999999' implies more than 1000 digits (uio_ring.ring.parse.MAX_NUMBER_DIGITS); write it with fewer digits or a smaller exponent
    """
    if not isinstance(text, str):
        raise DomainError(f"{where}: expected decimal text, got {type(text).__name__}")
    if "/" in text and text.count("/") == 1:
        num, den = text.split("/")
        if "." in num + den or "e" in (num + den).lower():
            raise ParseError(f"{where}: cannot read {_short(text)} as a number", text=text, position=0)
        q = decimal_fraction(den, where, max_digits=max_digits)
        if q == 0:
            raise ParseError(f"{where}: division by zero in {_short(text)}", text=text, position=0)
        return decimal_fraction(num, where, max_digits=max_digits) / q
    m = _DECIMAL.match(text.replace("_", "")) if len(text) <= 2 * max_digits + 16 else None
    if m is None or not (m.group(2) or m.group(3)):
        if len(text) > 2 * max_digits + 16 and _DECIMAL.match(text[:64]):
            raise DomainError(f"{where}: a number of {len(text)} characters exceeds {max_digits} digits "
                              "(uio_ring.ring.parse.MAX_NUMBER_DIGITS)")
        raise ParseError(f"{where}: cannot read {_short(text)} as a number", text=text, position=0)
    sign, whole, frac, exp = m.groups()
    frac = frac or ""
    digits = (whole + frac).lstrip("0")
    if exp is not None and len(exp.lstrip("+-")) > 9:
        size = max_digits + 1
    else:
        e = int(exp) if exp else 0
        size = len(digits) + abs(e - len(frac)) if digits else 0
    if size > max_digits:
        raise DomainError(
            f"{where}: {_short(text)} implies more than {max_digits} digits "
            "(uio_ring.ring.parse.MAX_NUMBER_DIGITS); write it with fewer digits or a smaller exponent"
        )
    if not digits:
        return Fraction(0)
    value = Fraction(int(flint.fmpz(digits))) * Fraction(10) ** (e - len(frac))  # fmpz: no 4300-digit limit
    return -value if sign == "-" else value


def _short(text: str) -> str:
    return repr(text) if len(text) <= 40 else repr(text[:30] + "…") + f" ({len(text)} characters)"


def _bits(p: flint.fmpq_poly) -> int:
    """Size of the largest coefficient in bits (numerator height plus denominator)."""
    return int(p.numer().height_bits()) + int(p.denom().bit_length())

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
                f"cannot parse {_short(text)} at column {m.start() + 1}: unexpected character {m.group()!r}",
                text=text,
                position=m.start(),
            )
        tokens.append((kind, m.group(), m.start()))
    tokens.append(("end", "", len(text)))
    return tokens


class _Parser:
    def __init__(
        self, text: str, var: str, max_degree: int = MAX_DEGREE, max_bits: int = MAX_BITS, max_digits: int = MAX_NUMBER_DIGITS
    ):
        self.text = text
        self.var = var
        self.names = var_aliases(var)
        self.tokens = _tokenize(text)
        self.i = 0
        self.depth = 0
        self.max_degree = max_degree
        self.max_bits = max_bits
        self.max_digits = max_digits

    def too_big(self, pos: int, what: str) -> DomainError:
        return DomainError(f"{_short(self.text)}, column {pos + 1}: {what}")

    def check_size(self, value: flint.fmpq_poly, pos: int) -> None:
        """Refuse a sum or quotient (computed in linear time) whose coefficients grew too large."""
        bits = _bits(value)
        if bits > self.max_bits:
            raise self.too_big(pos, f"the coefficients need {bits} bits, above the limit {self.max_bits}")

    def check_product(self, a: flint.fmpq_poly, b: flint.fmpq_poly, pos: int) -> None:
        """Refuse ``a*b`` before computing it when its degree or coefficients would be too large."""
        if a.is_zero() or b.is_zero():
            return
        deg = a.degree() + b.degree()
        if deg > self.max_degree:
            raise self.too_big(pos, f"the product has degree {deg}, above the limit {self.max_degree}")
        bits = _bits(a) + _bits(b) + min(a.degree(), b.degree()).bit_length()
        if bits > self.max_bits:
            raise self.too_big(pos, f"the product's coefficients would need about {bits} bits, above the limit {self.max_bits}")

    # -- helpers --------------------------------------------------------------
    @property
    def tok(self) -> tuple[str, str, int]:
        return self.tokens[self.i]

    def error(self, expected: str) -> ParseError:
        kind, value, pos = self.tok
        found = "the end of the text" if kind == "end" else repr(value)
        return ParseError(
            f"cannot parse {_short(self.text)} at column {pos + 1}: expected {expected} but found {found}",
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
            pos = self.tok[2]
            rhs = self.term()
            value = value + rhs if op == "+" else value - rhs  # linear in the operands' size
            self.check_size(value, pos)
        return value

    def term(self) -> flint.fmpq_poly:
        value = self.unary()
        while True:
            kind, tv, pos = self.tok
            if kind == "op" and tv == "*":
                self.i += 1
                rhs = self.unary()
                self.check_product(value, rhs, pos)
                value = value * rhs
            elif kind == "op" and tv == "/":
                self.i += 1
                divisor = self.unary()
                if divisor.is_zero():
                    raise ParseError(
                        f"cannot parse {_short(self.text)} at column {pos + 1}: division by zero",
                        text=self.text,
                        position=pos,
                    )
                if divisor.degree() > 0:
                    raise DomainError(
                        f"{_short(self.text)}, column {pos + 1}: division by the non-constant "
                        f"{bk.to_str(divisor, self.var)!r} does not give a polynomial in "
                        f"{self.var!r}; entries must be polynomials, divide only by nonzero constants"
                    )
                value = value / divisor[0]
                self.check_size(value, pos)
            elif kind == "name" or (kind == "op" and tv == "("):
                rhs = self.power()  # juxtaposition: 2d, 3(d + 1); never before a number
                self.check_product(value, rhs, pos)
                value = value * rhs
            else:
                return value

    def unary(self) -> flint.fmpq_poly:
        negative = False
        while self.tok[0] == "op" and self.tok[1] in "+-":  # iterative: any number of signs
            negative ^= self.tok[1] == "-"
            self.i += 1
        value = self.power()
        return -value if negative else value

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
            if len(tv) > 6 or int(tv) > MAX_DEGREE:
                raise self.too_big(pos, f"exponent {tv if len(tv) <= 12 else tv[:10] + '…'} exceeds the limit "
                                   f"{MAX_DEGREE} (uio_ring.ring.parse.MAX_DEGREE)")
            e = int(tv)
            if base.degree() > 0 and base.degree() * e > self.max_degree:
                raise self.too_big(pos, f"the power has degree {base.degree() * e}, above the limit {self.max_degree}")
            if not base.is_zero() and e > 1:
                bits = e * (_bits(base) + (base.degree() + 1).bit_length())
                if bits > self.max_bits:
                    raise self.too_big(pos, f"the power's coefficients would need about {bits} bits, "
                                       f"above the limit {self.max_bits}")
            return base**e
        return base

    def atom(self) -> flint.fmpq_poly:
        kind, tv, pos = self.tok
        if kind == "num":
            self.i += 1
            try:
                return bk.const(decimal_fraction(tv, max_digits=self.max_digits))
            except DomainError:
                raise self.too_big(pos, f"the number {_short(tv)} implies more than {self.max_digits} digits "
                                   "(uio_ring.ring.parse.MAX_NUMBER_DIGITS)") from None
        if kind == "name":
            self.i += 1
            if tv in self.names:
                return bk.GEN
            if tv in _FUNCTIONS:
                raise DomainError(
                    f"{_short(self.text)}, column {pos + 1}: {_short(tv)} is not rational; coefficients "
                    "must be exact rationals such as 2, -1/3 or 0.25"
                )
            raise DomainError(
                f"{_short(self.text)}, column {pos + 1}: unknown symbol {_short(tv)}; the indeterminate is "
                f"{' or '.join(repr(n) for n in self.names)}"
            )
        if kind == "op" and tv == "(":
            if self.depth >= MAX_NESTING:
                raise self.too_big(pos, f"parentheses nested deeper than {MAX_NESTING} (uio_ring.ring.parse.MAX_NESTING)")
            self.i += 1
            self.depth += 1
            value = self.expr()
            self.depth -= 1
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


def parse_poly(
    text: str, var: str = "d", *, max_degree: int = MAX_DEGREE, max_bits: int = MAX_BITS, max_digits: int = MAX_NUMBER_DIGITS
) -> flint.fmpq_poly:
    """Parse one polynomial (raises :class:`ParseError` / :class:`DomainError`).

    ``max_degree`` and ``max_bits`` bound every intermediate result, checked
    before it is computed, and ``max_digits`` every number written (see the
    module docstring).
    """
    if not text.strip():
        raise ParseError("cannot parse an empty text as a polynomial", text=text, position=0)
    p = _Parser(text, canonical_var(var), max_degree, max_bits, max_digits)
    value = p.expr()
    p.finish()
    return value


def parse_matrix(
    text: str, var: str = "d", *, max_degree: int = MAX_DEGREE, max_bits: int = MAX_BITS, max_digits: int = MAX_NUMBER_DIGITS
) -> list[list[flint.fmpq_poly]]:
    """Parse ``[[a, b], [c, d]]`` into rows of polynomials (rows may be ragged; the caller checks).

    ``max_degree``, ``max_bits`` and ``max_digits`` bound every entry as in :func:`parse_poly`.
    """
    if not text.strip():
        raise ParseError("cannot parse an empty text as a matrix", text=text, position=0)
    p = _Parser(text, canonical_var(var), max_degree, max_bits, max_digits)
    rows = p.matrix()
    p.finish()
    return rows
