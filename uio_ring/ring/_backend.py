"""Scalar arithmetic in Q[δ] — the only module that knows how a polynomial is stored.

Polynomials are python-flint ``fmpq_poly`` objects (exact rational coefficients,
arithmetic in C).  Everything else in :mod:`uio_ring.ring` goes through the
names defined here, so the representation can change in this one file.

Conventions: the degree of the zero polynomial is ``-1``; coefficients are
listed from the constant term upwards.

>>> p = from_coeffs([Fraction(1, 3), 0, 2])
>>> degree(p), coeffs(p), to_str(p, "d")
(2, [Fraction(1, 3), Fraction(0, 1), Fraction(2, 1)], '2*d**2 + 1/3')
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from fractions import Fraction

import flint

from uio_ring.ring import _xgcd

__all__ = [
    "Scalar",
    "RawPoly",
    "Rat",
    "ZERO",
    "ONE",
    "GEN",
    "const",
    "from_coeffs",
    "coeffs",
    "degree",
    "lc",
    "is_zero",
    "is_constant",
    "monic",
    "to_fraction",
    "to_rat",
    "evaluate",
    "to_str",
    "to_latex",
    "monomial",
    "xgcd",
    "gcd",
    "height",
    "bits",
    "mat_from_rows",
    "mat_rank",
    "mat_det",
    "mat_entries",
    "IntPoly",
    "denominator_lcm",
    "integer_row",
    "from_integer",
]

RawPoly = flint.fmpq_poly
#: Z[δ], for fraction-free elimination (:mod:`uio_ring.ring._fraction_free`).
IntPoly = flint.fmpz_poly
Rat = flint.fmpq
Scalar = int | Fraction

ZERO = flint.fmpq_poly()
ONE = flint.fmpq_poly([1])
GEN = flint.fmpq_poly([0, 1])


def to_rat(value: Scalar) -> flint.fmpq:
    """An exact flint rational from an int or Fraction (precondition: no float)."""
    if isinstance(value, Fraction):
        return flint.fmpq(value.numerator, value.denominator)
    return flint.fmpq(value)


def const(value: Scalar) -> flint.fmpq_poly:
    """The constant polynomial ``value``."""
    if isinstance(value, Fraction):
        return flint.fmpq_poly([value.numerator]) / value.denominator
    return flint.fmpq_poly([value])


def monomial(c: flint.fmpq, e: int) -> flint.fmpq_poly:
    """``c·δ**e`` (precondition: e ≥ 0, not checked)."""
    p = flint.fmpq_poly()
    p[e] = c
    return p


def from_coeffs(cs: Sequence[Scalar]) -> flint.fmpq_poly:
    """The polynomial ``Σ cs[i] δ^i`` (cs: ints or Fractions)."""
    p = flint.fmpq_poly()
    for i, c in enumerate(cs):
        if c:
            p[i] = to_rat(c)
    return p


def to_fraction(q: flint.fmpq) -> Fraction:
    return Fraction(int(q.p), int(q.q))


def coeffs(p: flint.fmpq_poly) -> list[Fraction]:
    """Coefficients as Fractions, constant term first; ``[]`` for zero."""
    return [to_fraction(c) for c in p.coeffs()]


def degree(p: flint.fmpq_poly) -> int:
    return int(p.degree())


def lc(p: flint.fmpq_poly) -> flint.fmpq:
    """Leading coefficient (precondition: p ≠ 0, not checked)."""
    return p[p.degree()]


def is_zero(p: flint.fmpq_poly) -> bool:
    return p.is_zero()


def is_constant(p: flint.fmpq_poly) -> bool:
    return p.degree() <= 0


def monic(p: flint.fmpq_poly) -> flint.fmpq_poly:
    """``p / lc(p)``; zero stays zero."""
    if p.is_zero():
        return p
    return p / p[p.degree()]


def evaluate(p: flint.fmpq_poly, x: flint.fmpq) -> flint.fmpq:
    return p(x)


def xgcd(a: flint.fmpq_poly, b: flint.fmpq_poly):
    """``(g, s, t)`` with ``g = s·a + t·b`` monic (``g = 0`` iff a = b = 0) and the
    cofactors of least degree: python-flint's ``a.xgcd(b)``, by certified Chinese
    remaindering for large degrees (:mod:`uio_ring.ring._xgcd`; the same result)."""
    return _xgcd.xgcd(a, b)


def gcd(a: flint.fmpq_poly, b: flint.fmpq_poly) -> flint.fmpq_poly:
    """Monic gcd (0 if both are 0)."""
    return a.gcd(b)


def bits(p: flint.fmpq_poly) -> int:
    """Bits of the largest numerator coefficient plus those of the denominator."""
    num: int = p.numer().height_bits()  # python-flint returns Python ints here
    den: int = p.denom().bit_length()
    return num + den


def height(p: flint.fmpq_poly) -> int:
    """A cheap size measure: bits of the numerator coefficients plus the denominator."""
    num = p.numer()
    return sum(abs(int(c)).bit_length() for c in num.coeffs()) + int(p.denom()).bit_length()


def rat_text(q: flint.fmpq | Fraction) -> str:
    """``a/b``, or ``a`` when b = 1, for a rational of any size: FLINT writes the digits
    (Python's own ``str(int)`` refuses more than 4300 digits and takes quadratic time;
    the transforms of a singular 16×16 of degree 16 have 8000-digit coefficients).

    >>> rat_text(Fraction(-3, 6)), rat_text(flint.fmpq(10) ** 5000)[:3]
    ('-1/2', '100')
    """
    if isinstance(q, Fraction):
        q = flint.fmpq(q.numerator, q.denominator)
    return str(q.p) if q.q == 1 else f"{q.p}/{q.q}"


def to_str(p: flint.fmpq_poly, var: str, *, power: str = "**", times: str = "*") -> str:
    """sympy-style text, highest power first: ``2*d**2 - d + 1/3`` (digits by
    :func:`rat_text`: any size)."""
    cs = p.coeffs()
    parts: list[str] = []
    for e in range(len(cs) - 1, -1, -1):
        c = cs[e]
        if c == 0:
            continue
        a = abs(c)
        num, den = a.p, a.q
        if e == 0:
            body = rat_text(a)
        else:
            mono = var if e == 1 else f"{var}{power}{e}"
            if a == 1:
                body = mono
            elif den == 1:
                body = f"{num}{times}{mono}"
            elif num == 1:
                body = f"{mono}/{den}"
            else:
                body = f"{num}{times}{mono}/{den}"
        parts.append(("-" if c < 0 else "") + body if not parts else (" - " if c < 0 else " + ") + body)
    return "".join(parts) or "0"


def to_latex(p: flint.fmpq_poly, sym: str) -> str:
    """LaTeX text, highest power first: ``\\tfrac{1}{3} \\delta^{2} - \\delta``."""
    cs = p.coeffs()
    parts: list[str] = []
    for e in range(len(cs) - 1, -1, -1):
        c = cs[e]
        if c == 0:
            continue
        a = abs(c)
        if a.q == 1:
            num = "" if (a == 1 and e > 0) else str(a.p)
        else:
            num = f"\\tfrac{{{a.p}}}{{{a.q}}}"
        mono = "" if e == 0 else (sym if e == 1 else f"{sym}^{{{e}}}")
        body = f"{num} {mono}".strip() if num and mono else (num or mono)
        parts.append(("-" if c < 0 else "") + body if not parts else f" {'-' if c < 0 else '+'} {body}")
    return "".join(parts) or "0"


# --- constant (rational) matrices, used by evaluation-based algorithms -------------


def mat_from_rows(rows: Sequence[Sequence[flint.fmpq]], m: int, n: int) -> flint.fmpq_mat:
    return flint.fmpq_mat(m, n, [c for row in rows for c in row])


def mat_rank(a: flint.fmpq_mat) -> int:
    return int(a.rank())


def mat_det(a: flint.fmpq_mat) -> flint.fmpq:
    return a.det()


def mat_entries(a: flint.fmpq_mat) -> list[flint.fmpq]:
    return list(a.entries())


def denominator_lcm(polys: Iterable[flint.fmpq_poly]) -> flint.fmpz:
    """The least common multiple (> 0) of the denominators of ``polys``: the least c with
    every ``c·p`` in Z[δ].

    >>> int(denominator_lcm([from_coeffs([Fraction(1, 2)]), from_coeffs([0, Fraction(1, 3)]), ONE]))
    6
    """
    den = flint.fmpz(1)
    for p in polys:
        q = p.denom()
        if q != 1:
            den = den * q // den.gcd(q)
    return den


def integer_row(row: Sequence[flint.fmpq_poly]) -> tuple[list[flint.fmpz_poly], flint.fmpz]:
    """``(c·row, c)`` with c > 0 the least common denominator of the row's coefficients:
    an integer row that spans the same Q[δ]-module (c is a unit of Q[δ]).

    >>> z, c = integer_row([from_coeffs([Fraction(1, 2)]), from_coeffs([0, Fraction(1, 3)])])
    >>> [p.coeffs() for p in z], int(c)
    ([[3], [0, 2]], 6)
    """
    den = denominator_lcm(row)
    return [(p * den).numer() for p in row], den


def from_integer(p: flint.fmpz_poly) -> flint.fmpq_poly:
    """The polynomial of Z[δ] as an element of Q[δ]."""
    return flint.fmpq_poly(p)
