"""``PolyMatrix``: immutable matrices over Q[δ] (or Q[s], any one indeterminate).

The façade validates, converts and delegates; algorithms live in their own
modules (:mod:`~uio_ring.ring.hermite`, :mod:`~uio_ring.ring.smith`, …).
The degree of the zero polynomial (and of a zero matrix) is ``-1``.

Construction reads exact rationals only: strings are parsed (``"1/3"``,
``"0.1"`` = 1/10), Python floats are read through their decimal text
(``0.1`` → 1/10, i.e. ``Fraction(repr(x))``), never their binary value.

>>> M = PolyMatrix("[[d, 1 + 2*d], [0, d**2 - 1/3]]")
>>> M.shape, M.degree(), M[0, 1]
((2, 2), 2, 2*d + 1)
>>> M.coefficients()[1]
PolyMatrix([[1, 2], [0, 0]])
>>> M @ PolyMatrix.identity(2) == M, M.det()
(True, d**3 - d/3)
"""

from __future__ import annotations

import operator
from collections.abc import Iterable, Mapping, Sequence, Set
from fractions import Fraction
from typing import Any

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring._predicates import det_raw, rank_raw
from uio_ring.ring.errors import DimensionError, DomainError
from uio_ring.ring.parse import canonical_var, parse_matrix
from uio_ring.ring.poly import Poly, exact_fraction, to_raw

__all__ = ["PolyMatrix", "Poly", "require_matrix"]

_MAX_REPR_ROWS = 40



def binary_power(base: Any, e: int, one: Any) -> Any:
    """``base**e`` by repeated squaring (``one`` is the identity), for any ``@``-multipliable square matrix.

    >>> binary_power(PolyMatrix("[[1, d], [0, 1]]"), 3, PolyMatrix.identity(2))
    PolyMatrix([[1, 3*d], [0, 1]])
    """
    out = one
    while e:
        if e & 1:
            out = out @ base
        base = base @ base
        e >>= 1
    return out

class PolyMatrix:
    """A matrix with entries in Q[var]; ``var`` is δ (written ``d``) by default.

    Parameters
    ----------
    data
        Text ``"[[d, 1], [0, d**2 - 1/3]]"`` (``δ`` accepted for ``d``), or
        nested lists whose entries are int, Fraction, str, :class:`Poly`, or
        float (read through its decimal text), or another PolyMatrix.
    var
        The indeterminate's name; ``"d"`` and ``"δ"`` are the same.
    shape
        Needed only for empty matrices given as lists (``[]`` is 0×0).

    Raises
    ------
    ParseError, DomainError, DimensionError
        Malformed text, non-rational values, ragged rows.
    """

    __slots__ = ("_r", "_m", "_n", "var")
    _r: dn.Rows
    _m: int
    _n: int
    var: str
    _is_polymatrix = True

    def __init__(self, data: Any, var: str = "d", *, shape: tuple[int, int] | None = None):
        var = canonical_var(var)
        if isinstance(data, PolyMatrix):
            if data.var != var:
                raise DomainError(f"matrix over {data.var!r} given where the indeterminate is {var!r}")
            rows, m, n = data._r, data._m, data._n
        else:
            if isinstance(data, str):
                rows = parse_matrix(data, var)
            elif hasattr(data, "tolist") and hasattr(data, "shape") and not isinstance(data, (list, tuple)):
                if hasattr(data, "free_symbols"):
                    return self._init_from(PolyMatrix.from_sympy(data, var))
                if len(data.shape) != 2:
                    raise DimensionError(
                        f"a {len(data.shape)}-dimensional array of shape {tuple(data.shape)} is not a matrix; "
                        "give a 2-dimensional array (e.g. a.reshape(1, -1) for one row)"
                    )
                items = data.tolist() if getattr(data, "dtype", None) is None or data.dtype.kind != "f" else [
                    list(r) for r in data  # NumPy floats keep their type: read through their own decimal text
                ]
                rows = [[to_raw(x, var, f"entry ({i}, {j})") for j, x in enumerate(r)] for i, r in enumerate(items)]
            elif isinstance(data, (Set, Mapping)):
                raise DimensionError(
                    f"a {type(data).__name__} has no order; a matrix is a list of rows, e.g. [[1, 'd'], [0, 1]]"
                )
            elif isinstance(data, Iterable):
                rows = []
                for i, r in enumerate(data):
                    if isinstance(r, (Set, Mapping)):
                        raise DimensionError(
                            f"row {i} is a {type(r).__name__}, which has no order; give each row as a list"
                        )
                    if isinstance(r, (str, bytes)) or not isinstance(r, Iterable):
                        raise DimensionError(
                            f"row {i} is {r!r}; a matrix is a list of rows, e.g. [[1, 'd'], [0, 1]]"
                        )
                    rows.append([to_raw(x, var, f"entry ({i}, {j})") for j, x in enumerate(r)])
            else:
                raise DomainError(f"cannot make a PolyMatrix from {type(data).__name__}")
            m = len(rows)
            n = len(rows[0]) if rows else 0
            for i, r in enumerate(rows):
                if len(r) != n:
                    raise DimensionError(
                        f"row {i} has {len(r)} entries but row 0 has {n}; all rows need the same length"
                    )
            if shape is not None:
                if m == 0 or n == 0:
                    if (m == 0 and shape[0] != 0) or (m and n == 0 and shape[0] != m):
                        raise DimensionError(f"data has {m} rows but shape says {shape}")
                    m, n = shape
                    rows = [[] for _ in range(m)] if n == 0 else rows
                elif (m, n) != tuple(shape):
                    raise DimensionError(f"data is {m}×{n} but shape says {shape[0]}×{shape[1]}")
        self._init(rows, m, n, var)

    def _init(self, rows: dn.Rows, m: int, n: int, var: str) -> None:
        object.__setattr__(self, "_r", rows)
        object.__setattr__(self, "_m", m)
        object.__setattr__(self, "_n", n)
        object.__setattr__(self, "var", var)

    def _init_from(self, other: PolyMatrix) -> None:
        self._init(other._r, other._m, other._n, other.var)

    @classmethod
    def _new(cls, rows: dn.Rows, m: int, n: int, var: str) -> PolyMatrix:
        """Wrap rows without validation. Precondition: rows is m lists of n fmpq_poly,
        owned by the new matrix (never mutated afterwards)."""
        obj = object.__new__(cls)
        obj._init(rows, m, n, var)
        return obj

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("PolyMatrix is immutable; operations return new matrices")

    # -- constructors ---------------------------------------------------------------
    @classmethod
    def identity(cls, n: int, var: str = "d") -> PolyMatrix:
        """The n×n identity."""
        return cls._new(dn.identity(_count(n, "n")), n, n, canonical_var(var))

    @classmethod
    def zeros(cls, rows: int, cols: int, var: str = "d") -> PolyMatrix:
        """The rows×cols zero matrix."""
        return cls._new(dn.zeros(_count(rows, "rows"), _count(cols, "cols")), rows, cols, canonical_var(var))

    @classmethod
    def diag(cls, *entries: Any, var: str = "d") -> PolyMatrix:
        """Square diagonal matrix with the given entries."""
        var = canonical_var(var)
        n = len(entries)
        rows = dn.zeros(n, n)
        for i, e in enumerate(entries):
            rows[i][i] = to_raw(e, var, f"diagonal entry {i}")
        return cls._new(rows, n, n, var)

    @classmethod
    def from_coefficients(cls, coefficients: Sequence[Any], var: str = "d") -> PolyMatrix:
        """``Σ coefficients[i]·δ^i`` from constant matrices (lists or PolyMatrix).

        >>> PolyMatrix.from_coefficients([[[1, 0]], [[0, 2]]])
        PolyMatrix([[1, 2*d]])
        """
        var = canonical_var(var)
        if len(coefficients) == 0:
            raise DimensionError("from_coefficients needs at least one coefficient matrix")
        mats = [c if isinstance(c, PolyMatrix) else PolyMatrix(c, var) for c in coefficients]
        m, n = mats[0].shape
        out = dn.zeros(m, n)
        for e, mat in enumerate(mats):
            if mat.shape != (m, n):
                raise DimensionError(
                    f"coefficient {e} is {mat._m}×{mat._n} but coefficient 0 is {m}×{n}"
                )
            if mat.degree() > 0:
                raise DomainError(f"coefficient {e} is not a constant matrix")
            shift = bk.monomial(flint.fmpq(1), e)
            for i in range(m):
                for j in range(n):
                    if not mat._r[i][j].is_zero():
                        out[i][j] = out[i][j] + mat._r[i][j] * shift
        return cls._new(out, m, n, var)

    @classmethod
    def hstack(cls, *blocks: PolyMatrix) -> PolyMatrix:
        """Blocks side by side (same number of rows)."""
        blocks = tuple(_as_matrix(b, None, "hstack") for b in blocks)
        if not blocks:
            raise DimensionError("hstack needs at least one matrix")
        var = _common_var(blocks)
        m = blocks[0]._m
        for k, b in enumerate(blocks):
            if b._m != m:
                raise DimensionError(
                    f"hstack: block {k} is {b._m}×{b._n} but block 0 is {m}×{blocks[0]._n}; "
                    "blocks side by side need the same number of rows"
                )
        rows = [[p for b in blocks for p in b._r[i]] for i in range(m)]
        return cls._new(rows, m, sum(b._n for b in blocks), var)

    @classmethod
    def vstack(cls, *blocks: PolyMatrix) -> PolyMatrix:
        """Blocks on top of each other (same number of columns)."""
        blocks = tuple(_as_matrix(b, None, "vstack") for b in blocks)
        if not blocks:
            raise DimensionError("vstack needs at least one matrix")
        var = _common_var(blocks)
        n = blocks[0]._n
        for k, b in enumerate(blocks):
            if b._n != n:
                raise DimensionError(
                    f"vstack: block {k} is {b._m}×{b._n} but block 0 is {blocks[0]._m}×{n}; "
                    "stacked blocks need the same number of columns"
                )
        rows = [list(r) for b in blocks for r in b._r]
        return cls._new(rows, sum(b._m for b in blocks), n, var)

    @classmethod
    def block(cls, blocks: Sequence[Sequence[PolyMatrix]]) -> PolyMatrix:
        """Block matrix ``[[A, B], [C, D]]``; every block row needs equal heights, every
        block column equal widths."""
        return cls.vstack(*[cls.hstack(*row) for row in blocks])

    @classmethod
    def from_sympy(cls, m: Any, var: str = "d") -> PolyMatrix:
        """From a sympy Matrix whose entries are polynomials in ``var`` with rational coefficients."""
        var = canonical_var(var)
        rows_, cols_ = m.shape
        rows = [[to_raw(m[i, j], var, f"entry ({i}, {j})") for j in range(cols_)] for i in range(rows_)]
        return cls._new(rows, rows_, cols_, var)

    # -- basic queries --------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, int]:
        return (self._m, self._n)

    @property
    def rows(self) -> int:
        return self._m

    @property
    def cols(self) -> int:
        return self._n

    @property
    def T(self) -> PolyMatrix:
        return PolyMatrix._new(dn.transpose(self._r, self._m, self._n), self._n, self._m, self.var)

    def degree(self) -> int:
        """Largest entry degree; ``-1`` for a zero (or empty) matrix."""
        return dn.mat_degree(self._r)

    def row_degrees(self) -> list[int]:
        return [dn.row_degree(r) for r in self._r]

    def column_degrees(self) -> list[int]:
        return [dn.row_degree([r[j] for r in self._r]) for j in range(self._n)]

    def is_zero(self) -> bool:
        return all(p.is_zero() for r in self._r for p in r)

    def is_constant(self) -> bool:
        return self.degree() <= 0

    def is_square(self) -> bool:
        return self._m == self._n

    def coefficients(self) -> list[PolyMatrix]:
        """``[M0, M1, …, Md]`` constant matrices with ``M = Σ Mi δ^i`` (``[0]`` for a zero matrix)."""
        deg = max(self.degree(), 0)
        out = []
        for e in range(deg + 1):
            rows = [[bk.const(0) if p.degree() < e else _coef(p, e) for p in r] for r in self._r]
            out.append(PolyMatrix._new(rows, self._m, self._n, self.var))
        return out

    def coefficient_lists(self) -> list[list[list[Fraction]]]:
        """Like :meth:`coefficients`, as nested lists of Fractions (for numeric code)."""
        deg = max(self.degree(), 0)
        out = []
        for e in range(deg + 1):
            out.append(
                [[bk.to_fraction(p[e]) if p.degree() >= e else Fraction(0) for p in r] for r in self._r]
            )
        return out

    def tolist(self) -> list[list[Poly]]:
        return [[Poly._wrap(p, self.var) for p in r] for r in self._r]

    def eval(self, value: Any) -> PolyMatrix:
        """The constant matrix M(value), exactly (value: int, Fraction, decimal str)."""
        x = bk.to_rat(exact_fraction(value, "eval point"))
        rows = [[bk.const(0) if p.is_zero() else flint.fmpq_poly([p(x)]) for p in r] for r in self._r]
        return PolyMatrix._new(rows, self._m, self._n, self.var)

    def map(self, f: Any) -> PolyMatrix:
        """Apply ``f: Poly -> Poly`` entrywise."""
        rows = [[to_raw(f(Poly._wrap(p, self.var)), self.var) for p in r] for r in self._r]
        return PolyMatrix._new(rows, self._m, self._n, self.var)

    # -- algebra delegated to algorithm modules ---------------------------------------
    def det(self) -> Poly:
        """Determinant over Q[δ] (square matrices)."""
        if self._m != self._n:
            raise DimensionError(f"det needs a square matrix; this one is {self._m}×{self._n}")
        return Poly._wrap(det_raw(self._r, self._n), self.var)

    def rank(self) -> int:
        """Rank over Q[δ] (equivalently over the fraction field Q(δ))."""
        return rank_raw(self._r, self._m, self._n)

    # -- indexing -------------------------------------------------------------------
    def __getitem__(self, key: Any) -> Any:
        if not isinstance(key, tuple) or len(key) != 2:
            raise DimensionError("index a PolyMatrix with two indices: M[i, j], M[i, :], M[:, a:b]")
        ki, kj = _as_index(key[0]), _as_index(key[1])
        if isinstance(ki, int) and isinstance(kj, int):
            i, j = _index(ki, self._m, "row"), _index(kj, self._n, "column")
            return Poly._wrap(self._r[i][j], self.var)
        ri = _range(ki, self._m, "row")
        rj = _range(kj, self._n, "column")
        rows = [[self._r[i][j] for j in rj] for i in ri]
        return PolyMatrix._new(rows, len(ri), len(rj), self.var)

    def row(self, i: int) -> PolyMatrix:
        return self[i : i + 1 if i != -1 else None, :]

    def col(self, j: int) -> PolyMatrix:
        return self[:, j : j + 1 if j != -1 else None]

    # -- arithmetic -----------------------------------------------------------------
    def _check(self, op: str, other: Any) -> PolyMatrix:
        if not isinstance(other, PolyMatrix):
            raise DomainError(f"{op}: expected a PolyMatrix, got {type(other).__name__}")
        if other.var != self.var:
            raise DomainError(
                f"{op}: matrices over different indeterminates ({self.var!r} and {other.var!r})"
            )
        return other

    #: NumPy defers to our reflected operators instead of building object arrays.
    __array_ufunc__ = None

    def __add__(self, other: Any) -> PolyMatrix:
        if not isinstance(other, PolyMatrix):
            return _no_array("+", other)
        o = self._check("+", other)
        if o.shape != self.shape:
            raise DimensionError(f"cannot add a {self._m}×{self._n} and a {o._m}×{o._n} matrix")
        rows = [[a + b for a, b in zip(ra, rb, strict=True)] for ra, rb in zip(self._r, o._r, strict=True)]
        return PolyMatrix._new(rows, self._m, self._n, self.var)

    def __radd__(self, other: Any) -> PolyMatrix:
        return _no_array("+", other)

    def __rsub__(self, other: Any) -> PolyMatrix:
        return _no_array("-", other)

    def __rmatmul__(self, other: Any) -> PolyMatrix:
        return _no_array("@", other)

    def __sub__(self, other: Any) -> PolyMatrix:
        if not isinstance(other, PolyMatrix):
            return _no_array("-", other)
        o = self._check("-", other)
        if o.shape != self.shape:
            raise DimensionError(f"cannot subtract a {o._m}×{o._n} from a {self._m}×{self._n} matrix")
        rows = [[a - b for a, b in zip(ra, rb, strict=True)] for ra, rb in zip(self._r, o._r, strict=True)]
        return PolyMatrix._new(rows, self._m, self._n, self.var)

    def __neg__(self) -> PolyMatrix:
        return PolyMatrix._new([[-a for a in r] for r in self._r], self._m, self._n, self.var)

    def __pos__(self) -> PolyMatrix:
        return self

    def __matmul__(self, other: Any) -> PolyMatrix:
        if not isinstance(other, PolyMatrix):
            return _no_array("@", other)
        o = self._check("@", other)
        if self._n != o._m:
            raise DimensionError(
                f"cannot multiply a {self._m}×{self._n} by a {o._m}×{o._n} matrix "
                f"({self._n} columns vs {o._m} rows)"
            )
        return PolyMatrix._new(dn.matmul(self._r, o._r, self._m, self._n, o._n), self._m, o._n, self.var)

    def __mul__(self, c: Any) -> PolyMatrix:
        if isinstance(c, PolyMatrix):
            raise DomainError("use @ for the matrix product; * multiplies by a scalar")
        if isinstance(c, float):
            raise DomainError("a Python float in exact arithmetic; use Fraction or a decimal string")
        p = to_raw(c, self.var, "scalar")
        return PolyMatrix._new([[a * p for a in r] for r in self._r], self._m, self._n, self.var)

    __rmul__ = __mul__

    def __pow__(self, e: int) -> PolyMatrix:
        if self._m != self._n:
            raise DimensionError(f"only square matrices have powers; this one is {self._m}×{self._n}")
        if not isinstance(e, int) or e < 0:
            raise DomainError(f"exponent must be a non-negative int, got {e!r}")
        return binary_power(self, e, PolyMatrix.identity(self._m, self.var))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, PolyMatrix):
            return NotImplemented
        return self.shape == other.shape and self.var == other.var and self._r == other._r

    def __hash__(self) -> int:
        return hash((self._m, self._n, self.var, tuple(str(p) for r in self._r for p in r)))

    # -- conversion and display --------------------------------------------------------
    def to_sympy(self, var: str | None = None) -> Any:
        """A sympy Matrix in the symbol ``var`` (default: this matrix's indeterminate)."""
        import sympy

        name = var or self.var
        return sympy.Matrix(self._m, self._n, lambda i, j: Poly._wrap(self._r[i][j], self.var).to_sympy(name))

    def _entry_strings(self) -> list[list[str]]:
        return [[bk.to_str(p, self.var) for p in r] for r in self._r]

    def __repr__(self) -> str:
        if self._m == 0 or self._n == 0:
            return f"PolyMatrix.zeros({self._m}, {self._n})"
        inner = ", ".join("[" + ", ".join(r) + "]" for r in self._entry_strings())
        return f"PolyMatrix([{inner}])"

    def __str__(self) -> str:
        if self._m == 0 or self._n == 0:
            return f"[{self._m}×{self._n} matrix]"
        cells = self._entry_strings()
        widths = [max(len(cells[i][j]) for i in range(self._m)) for j in range(self._n)]
        lines = ["[" + "  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) + "]" for r in cells]
        return "\n".join(lines)

    def to_latex(self) -> str:
        """LaTeX ``pmatrix`` with δ written ``\\delta``."""
        if self._m == 0 or self._n == 0:
            return rf"0_{{{self._m}\times{self._n}}}"
        sym = r"\delta" if self.var == "d" else self.var
        body = r" \\ ".join(" & ".join(bk.to_latex(p, sym) for p in r) for r in self._r)
        return r"\begin{pmatrix} " + body + r" \end{pmatrix}"

    def _repr_latex_(self) -> str:
        return f"${self.to_latex()}$"

    def to_numpy(self) -> Any:
        """The coefficient stack as float64: shape ``(deg + 1, rows, cols)``, entry ``[i]`` the
        coefficient of ``δ^i`` (``(0, rows, cols)`` for the zero matrix).  Numeric hand-over:
        the exact values are rounded here.  Needs numpy.

        >>> PolyMatrix("[[1 + d/2, 3]]").to_numpy().tolist()
        [[[1.0, 3.0]], [[0.5, 0.0]]]
        """
        import numpy as np

        if self.is_zero():
            return np.zeros((0, self._m, self._n))
        return np.array([[[float(c) for c in row] for row in M] for M in self.coefficient_lists()], dtype=float)

    def __array__(self, dtype: Any = None, copy: Any = None) -> Any:
        """``np.asarray(M)`` for a constant matrix (δ-degree ≤ 0): its float64 values.  A matrix
        with delays has no single array; :meth:`to_numpy` gives its coefficient stack."""
        if self.degree() > 0:
            raise DomainError(
                f"np.asarray needs a constant matrix; this one has δ-degree {self.degree()} "
                "(use M.to_numpy() for the coefficient stack (deg + 1, rows, cols))"
            )
        stack = self.to_numpy()
        import numpy as np

        out = stack[0] if stack.shape[0] else np.zeros((self._m, self._n))
        return out if dtype is None else out.astype(dtype)

    def __iter__(self):  # pragma: no cover - explicit refusal
        raise TypeError("PolyMatrix is not iterable; use M.tolist() or M[i, :]")

    def __bool__(self) -> bool:
        raise TypeError("the truth value of a PolyMatrix is ambiguous; use M.is_zero() or ==")


def require_matrix(M: Any, func: str) -> PolyMatrix:
    """The argument check of every public ring function: a PolyMatrix, or a
    :class:`DomainError` that says how to make one (nothing is coerced).

    >>> require_matrix([[1, 2]], "hermite")
    Traceback (most recent call last):
    ...
    uio_ring.ring.errors.DomainError: hermite: expected a PolyMatrix, got list; wrap it: hermite(PolyMatrix(...))
    """
    if isinstance(M, PolyMatrix):
        return M
    raise DomainError(f"{func}: expected a PolyMatrix, got {type(M).__name__}; wrap it: {func}(PolyMatrix(...))")


def _no_array(op: str, other: Any) -> Any:
    """Arrays (NumPy, lists of lists) are not coerced by operators: refuse with the fix."""
    if hasattr(other, "__array__") or hasattr(other, "__array_interface__") or isinstance(other, (list, tuple)):
        raise DomainError(
            f"{op}: a PolyMatrix and a {type(other).__name__} do not combine; convert the other operand "
            "with PolyMatrix(...) first (floats are read through their decimal text)"
        )
    return NotImplemented


def _coef(p: flint.fmpq_poly, e: int) -> flint.fmpq_poly:
    c = p[e]
    return flint.fmpq_poly([c]) if c != 0 else bk.const(0)


def _count(n: Any, name: str) -> int:
    if not isinstance(n, int) or isinstance(n, bool) or n < 0:
        raise DimensionError(f"{name} must be a non-negative int, got {n!r}")
    return n


def _as_index(k: Any) -> Any:
    """Integers of other libraries (numpy, sympy) through ``__index__``; slices stay."""
    if isinstance(k, (int, slice)) or isinstance(k, bool) or not hasattr(k, "__index__"):
        return k
    return operator.index(k)


def _index(k: int, size: int, what: str) -> int:
    if not -size <= k < size:
        raise IndexError(f"{what} index {k} out of range for size {size}")
    return k % size


def _range(k: Any, size: int, what: str) -> range:
    if isinstance(k, slice):
        return range(*k.indices(size))
    if isinstance(k, int):
        i = _index(k, size, what)
        return range(i, i + 1)
    if isinstance(k, (list, tuple)):
        raise DimensionError(f"fancy {what} indexing is not supported; use slices")
    raise DimensionError(f"bad {what} index {k!r}")


def _as_matrix(b: Any, var: str | None, op: str) -> PolyMatrix:
    if isinstance(b, PolyMatrix):
        return b
    raise DomainError(f"{op}: expected PolyMatrix blocks, got {type(b).__name__}")


def _common_var(blocks: Sequence[PolyMatrix]) -> str:
    vars_ = {b.var for b in blocks}
    if len(vars_) > 1:
        raise DomainError(f"blocks over different indeterminates: {sorted(vars_)}")
    return blocks[0].var
