"""``Poly``: an immutable polynomial in one indeterminate with rational coefficients.

It is the scalar that :class:`~uio_ring.ring.matrix.PolyMatrix` hands out
(``M[i, j]``) and the type of invariant factors and determinants.  It compares
equal to ints and Fractions when constant.

>>> d = Poly.gen()
>>> p = (d + 1) * (d - 2)
>>> p, p.degree(), p.eval(2), p // (d + 1), p.is_unit()
(d**2 - d - 2, 2, Fraction(0, 1), d - 2, False)
"""

from __future__ import annotations

from fractions import Fraction
from numbers import Integral, Rational
from typing import Any

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring.errors import DomainError
from uio_ring.ring.parse import _short, canonical_var, decimal_fraction, parse_poly

__all__ = ["Poly", "to_raw", "exact_fraction", "MAX_POWER_DEGREE"]

#: Largest degree a power ``p**e`` may have (checked before it is computed).
MAX_POWER_DEGREE = 1_000_000


def exact_fraction(value: Any, where: str = "value") -> Fraction:
    """An exact Fraction from int, Fraction, str, or float (read through its decimal text).

    One rule for every binary floating-point number: it is read through its
    shortest decimal text, never its binary value.  That holds for Python
    floats (``0.1`` → 1/10) and for NumPy floating scalars (``np.float64(0.1)``
    and ``np.float32(0.1)`` → 1/10, the text NumPy prints).  NumPy integers are
    integers; ``decimal.Decimal`` is read from its text.  Text and decimals are
    bounded (``uio_ring.ring.parse.MAX_NUMBER_DIGITS``) before they are built.
    Bools, complex numbers, NaN and infinities raise :class:`DomainError`.

    >>> exact_fraction(0.1), exact_fraction("2/6")
    (Fraction(1, 10), Fraction(1, 3))
    """
    if isinstance(value, bool) or type(value).__name__ == "bool_":
        raise DomainError(f"{where}: a bool is not a number")
    if isinstance(value, Fraction):
        return value
    if isinstance(value, Integral):
        return Fraction(int(value))
    if isinstance(value, Rational):
        return Fraction(int(value.numerator), int(value.denominator))
    if isinstance(value, float) and type(value) is float:
        if value != value or value in (float("inf"), float("-inf")):
            raise DomainError(f"{where}: {value} is not a finite number")
        return Fraction(repr(value))  # decimal text: 0.1 -> 1/10
    if isinstance(value, flint.fmpq):
        return bk.to_fraction(value)
    if isinstance(value, str):
        p = parse_poly(value, "d")
        if p.degree() > 0:
            raise DomainError(f"{where}: {_short(value)} is not a constant")
        return bk.to_fraction(p[0]) if not p.is_zero() else Fraction(0)
    module = type(value).__module__
    if module == "numpy" and hasattr(value, "dtype"):
        if getattr(value, "ndim", 0) != 0:
            raise DomainError(f"{where}: an array of shape {value.shape} is not a number")
        kind = value.dtype.kind
        if kind in "iu":
            return Fraction(int(value))
        if kind == "f":  # NumPy prints the shortest text that reads back to the same value
            text = str(value)
            if text in ("nan", "inf", "-inf"):
                raise DomainError(f"{where}: {text} is not a finite number")
            return decimal_fraction(text, where)
        raise DomainError(f"{where}: a NumPy {value.dtype} value {value!r} is not a rational number")
    if module == "decimal" and type(value).__name__ == "Decimal":
        if not value.is_finite():
            raise DomainError(f"{where}: {value} is not a finite number")
        return decimal_fraction(str(value), where)
    if isinstance(value, float):  # a float subclass other than NumPy's
        return exact_fraction(float(value), where)
    raise DomainError(
        f"{where}: cannot read {_short(repr(value))} ({type(value).__name__}) as an exact rational; "
        "give an int, a Fraction, a float or decimal text such as '0.1' or '1/3'"
    )


def to_raw(value: Any, var: str, where: str = "entry") -> flint.fmpq_poly:
    """Convert an int, Fraction, float (decimal text), str, Poly or sympy expression
    into the backend polynomial, checking the indeterminate."""
    if isinstance(value, Poly):
        if value.var != var:
            raise DomainError(
                f"{where}: polynomial in {value.var!r} where the indeterminate is {var!r}"
            )
        return value._p
    if isinstance(value, flint.fmpq_poly):
        return value
    if isinstance(value, str):
        return parse_poly(value, var)
    if hasattr(value, "free_symbols") and hasattr(value, "as_poly"):
        return _from_sympy_expr(value, var, where)
    return bk.const(exact_fraction(value, where))


def _from_sympy_expr(expr: Any, var: str, where: str) -> flint.fmpq_poly:
    import sympy

    names = {str(s) for s in expr.free_symbols}
    allowed = {"d", "δ"} if var == "d" else {var}
    extra = names - allowed
    if extra:
        raise DomainError(f"{where}: unknown symbol(s) {sorted(extra)}; the indeterminate is {var!r}")
    syms = [s for s in expr.free_symbols]
    if not syms:
        value = sympy.nsimplify(expr) if expr.is_Float else expr
        if not value.is_Rational:
            raise DomainError(f"{where}: {expr} is not rational")
        return bk.const(Fraction(int(value.p), int(value.q)))
    try:
        poly = sympy.Poly(expr, syms[0], domain="QQ")
    except (sympy.PolynomialError, sympy.polys.polyerrors.CoercionFailed) as exc:
        raise DomainError(f"{where}: {expr} is not a polynomial with rational coefficients") from exc
    cs = [Fraction(int(c.p), int(c.q)) for c in reversed(poly.all_coeffs())]
    return bk.from_coeffs(cs)


class Poly:
    """A polynomial in ``var`` (default δ, written ``d``) with rational coefficients."""

    __slots__ = ("_p", "var")
    _p: flint.fmpq_poly
    var: str

    def __init__(self, value: Any = 0, var: str = "d"):
        var = canonical_var(var)
        object.__setattr__(self, "var", var)
        object.__setattr__(self, "_p", to_raw(value, var, "Poly"))

    @classmethod
    def _wrap(cls, p: flint.fmpq_poly, var: str) -> Poly:
        obj = object.__new__(cls)
        object.__setattr__(obj, "_p", p)
        object.__setattr__(obj, "var", var)
        return obj

    @classmethod
    def gen(cls, var: str = "d") -> Poly:
        """The indeterminate itself."""
        return cls._wrap(bk.GEN, canonical_var(var))

    @classmethod
    def from_coeffs(cls, coeffs: list[Any], var: str = "d") -> Poly:
        """``Σ coeffs[i]·var**i`` (constant term first)."""
        return cls._wrap(bk.from_coeffs([exact_fraction(c, "coefficient") for c in coeffs]), canonical_var(var))

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("Poly is immutable")

    # -- queries ----------------------------------------------------------------
    def degree(self) -> int:
        """Degree; ``-1`` for the zero polynomial."""
        return bk.degree(self._p)

    def coeffs(self) -> list[Fraction]:
        """Coefficients as Fractions, constant term first (``[]`` for zero)."""
        return bk.coeffs(self._p)

    def lc(self) -> Fraction:
        """Leading coefficient (0 for the zero polynomial)."""
        return Fraction(0) if self._p.is_zero() else bk.to_fraction(bk.lc(self._p))

    def is_zero(self) -> bool:
        return self._p.is_zero()

    def is_constant(self) -> bool:
        return self._p.degree() <= 0

    def is_unit(self) -> bool:
        """True for nonzero constants (the units of Q[δ])."""
        return self._p.degree() == 0

    def monic(self) -> Poly:
        return Poly._wrap(bk.monic(self._p), self.var)

    def eval(self, value: Any) -> Fraction:
        """Exact value at a rational point."""
        return bk.to_fraction(self._p(bk.to_rat(exact_fraction(value, "eval point"))))

    def gcd(self, other: Any) -> Poly:
        return Poly._wrap(bk.gcd(self._p, self._coerce(other)), self.var)

    def roots(self) -> list[complex]:
        """Numerical roots (complex floats) — for display, never for decisions."""
        if self._p.degree() <= 0:
            return []
        found: Any = self._p.complex_roots()  # [(acb, multiplicity), ...]
        return [complex(r) for r, mult in found for _ in range(mult)]

    def to_sympy(self, var: str | None = None) -> Any:
        import sympy

        x = sympy.Symbol(var or self.var)
        return sum((sympy.Rational(c.numerator, c.denominator) * x**i for i, c in enumerate(self.coeffs())), sympy.Integer(0))

    def to_latex(self) -> str:
        return bk.to_latex(self._p, r"\delta" if self.var == "d" else self.var)

    # -- arithmetic -------------------------------------------------------------
    def _coerce(self, other: Any) -> flint.fmpq_poly:
        if isinstance(other, Poly):
            if other.var != self.var:
                raise DomainError(f"cannot combine polynomials in {self.var!r} and {other.var!r}")
            return other._p
        if isinstance(other, float):
            raise DomainError("a Python float in exact arithmetic; use Fraction or a decimal string")
        return to_raw(other, self.var, "operand")

    def __add__(self, other: Any) -> Poly:
        return Poly._wrap(self._p + self._coerce(other), self.var)

    __radd__ = __add__

    def __sub__(self, other: Any) -> Poly:
        return Poly._wrap(self._p - self._coerce(other), self.var)

    def __rsub__(self, other: Any) -> Poly:
        return Poly._wrap(self._coerce(other) - self._p, self.var)

    def __mul__(self, other: Any) -> Any:
        if getattr(other, "_is_polymatrix", False):
            return NotImplemented
        return Poly._wrap(self._p * self._coerce(other), self.var)

    __rmul__ = __mul__

    def __neg__(self) -> Poly:
        return Poly._wrap(-self._p, self.var)

    def __pos__(self) -> Poly:
        return self

    def __pow__(self, e: int) -> Poly:
        if not isinstance(e, int) or isinstance(e, bool) or e < 0:
            raise DomainError(f"exponent must be a non-negative int, got {e!r}")
        if self.degree() > 0 and self.degree() * e > MAX_POWER_DEGREE:
            raise DomainError(
                f"({self})**{e} would have degree {self.degree() * e}, above {MAX_POWER_DEGREE} "
                "(uio_ring.ring.poly.MAX_POWER_DEGREE); it would not fit in memory"
            )
        return Poly._wrap(self._p**e, self.var)

    def __floordiv__(self, other: Any) -> Poly:
        return Poly._wrap(self._p // self._nonzero(other), self.var)

    def __mod__(self, other: Any) -> Poly:
        return Poly._wrap(self._p % self._nonzero(other), self.var)

    def __divmod__(self, other: Any) -> tuple[Poly, Poly]:
        q, r = divmod(self._p, self._nonzero(other))
        return Poly._wrap(q, self.var), Poly._wrap(r, self.var)

    def __truediv__(self, other: Any) -> Poly:
        """Division by a nonzero constant, or exact division by a polynomial."""
        o = self._nonzero(other)
        q, r = divmod(self._p, o)
        if not r.is_zero():
            raise DomainError(
                f"{self} is not divisible by {Poly._wrap(o, self.var)}; use // and % for division with remainder"
            )
        return Poly._wrap(q, self.var)

    def _nonzero(self, other: Any) -> flint.fmpq_poly:
        o = self._coerce(other)
        if o.is_zero():
            raise ZeroDivisionError("division by the zero polynomial")
        return o

    def __call__(self, value: Any) -> Fraction:
        return self.eval(value)

    # -- comparison / display -------------------------------------------------------
    def __eq__(self, other: object) -> bool:
        if isinstance(other, Poly):
            return self.var == other.var and self._p == other._p
        if isinstance(other, (int, Fraction)) and not isinstance(other, bool):
            return self._p == bk.const(other)
        return NotImplemented

    def __hash__(self) -> int:
        cs = tuple(self.coeffs())
        return hash(cs[0]) if len(cs) == 1 else hash((self.var, cs))

    def __bool__(self) -> bool:
        return not self._p.is_zero()

    def __float__(self) -> float:
        """The value of a constant polynomial (degree ≤ 0) as a float (rounded).

        >>> float(Poly("1/4")), float(Poly(0))
        (0.25, 0.0)
        """
        if self._p.degree() > 0:
            raise DomainError(f"float() needs a constant; {self} has δ-degree {self._p.degree()}")
        return float(bk.to_fraction(self._p[0]))

    def __repr__(self) -> str:
        return bk.to_str(self._p, self.var)

    __str__ = __repr__

    def _repr_latex_(self) -> str:
        return f"${self.to_latex()}$"

