"""``QMatrix``: immutable matrices over Q, the façade of the ring's exact constant algebra.

The delay-free methods (Niederwieser et al. 2022 and related papers) and the delay-free analysis
work with constant matrices only.  ``QMatrix`` is what the layers above the
ring see of them: entries are exact rationals (read as :class:`~fractions.Fraction`),
operations return new matrices, nothing is mutated in place.  The algorithms
(rank, reduced row echelon form, null spaces, inverse, solving, the
minimum-norm left solution, substitution for triangular-up-to-permutation
systems) live in :mod:`uio_ring.ring.constant`; the façade validates, converts
and delegates.

Construction reads exact rationals only, as :class:`~uio_ring.ring.matrix.PolyMatrix`
does: ints, Fractions, decimal strings (``"0.1"`` is 1/10), and floats through
their decimal text (``0.1`` → 1/10), never their binary value.

>>> M = QMatrix([[1, 2], [2, 4]])
>>> M.shape, M.rank(), M[0, 1], M.nullspace()
((2, 2), 1, Fraction(2, 1), QMatrix([[-2], [1]]))
>>> N = QMatrix([[2, 1], [1, 1]])
>>> N @ N.inverse() == QMatrix.identity(2), (N.T @ M)[1, :]
(True, QMatrix([[3, 6]]))
"""

from __future__ import annotations

import operator
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from fractions import Fraction
from numbers import Rational
from typing import Any

import flint

from uio_ring.ring import constant as kernel
from uio_ring.ring.errors import DimensionError, DomainError
from uio_ring.ring.matrix import PolyMatrix, binary_power
from uio_ring.ring.poly import exact_fraction

__all__ = ["QMatrix", "RowEchelon"]


@dataclass(frozen=True)
class RowEchelon:
    """Reduced row echelon form ``R`` of a matrix ``M`` and its pivot columns.

    ``R = U M`` for some invertible ``U``; the first ``len(pivots)`` rows of
    ``R`` are nonzero, with a 1 in column ``pivots[i]`` of row ``i`` and zeros
    elsewhere in that column; the remaining rows are zero.
    """

    R: QMatrix
    pivots: tuple[int, ...]

    @property
    def rank(self) -> int:
        return len(self.pivots)


def _rat(value: Any, where: str) -> flint.fmpq:
    f = exact_fraction(value, where)
    return flint.fmpq(f.numerator, f.denominator)


def _frac(q: flint.fmpq) -> Fraction:
    return Fraction(int(q.p), int(q.q))


def _count(n: Any, name: str) -> int:
    if not isinstance(n, int) or isinstance(n, bool) or n < 0:
        raise DimensionError(f"{name} must be a non-negative int, got {n!r}")
    return n


def _scalar(c: Any, op: str) -> flint.fmpq:
    """int or Rational (never float) as a flint rational."""
    if isinstance(c, bool) or not isinstance(c, (int, Rational)):
        raise DomainError(f"{op}: expected an int or Fraction scalar, got {type(c).__name__}")
    return flint.fmpq(int(c.numerator), int(c.denominator))


def _indices(idx: Any, size: int, what: str) -> list[int]:
    out = []
    for k in idx:
        k = operator.index(k)
        if not -size <= k < size:
            raise IndexError(f"{what} index {k} out of range for size {size}")
        out.append(k % size)
    return out


def _range(k: Any, size: int, what: str) -> range:
    if isinstance(k, slice):
        return range(*k.indices(size))
    if hasattr(k, "__index__") and not isinstance(k, bool):
        i = operator.index(k)
        if not -size <= i < size:
            raise IndexError(f"{what} index {i} out of range for size {size}")
        return range(i % size, i % size + 1)
    raise DimensionError(f"bad {what} index {k!r}; use an int or a slice (take_rows/take_cols for lists)")


class QMatrix:
    """An immutable matrix over Q.

    Parameters
    ----------
    data
        Nested lists (rows) of int, Fraction, decimal str or float (read through
        its decimal text); a :class:`~uio_ring.ring.matrix.PolyMatrix` of δ-degree ≤ 0;
        or a ``QMatrix``.
    shape
        Needed only for empty matrices given as lists (``[]`` is 0×0).

    Raises
    ------
    DomainError
        A non-rational entry, or a PolyMatrix that depends on its indeterminate.
    DimensionError
        Ragged rows, or data that contradict ``shape``.
    """

    __slots__ = ("_q",)
    _q: flint.fmpq_mat

    def __init__(self, data: Any, *, shape: tuple[int, int] | None = None):
        if isinstance(data, QMatrix):
            q = data._q
        elif isinstance(data, PolyMatrix):
            q = QMatrix.from_polymatrix(data)._q
        elif isinstance(data, Iterable) and not isinstance(data, (str, bytes)):
            rows = []
            for i, r in enumerate(data):
                if isinstance(r, (str, bytes)) or not isinstance(r, Iterable):
                    raise DimensionError(f"row {i} is {r!r}; a matrix is a list of rows, e.g. [[1, 2], [0, 1]]")
                rows.append([_rat(x, f"entry ({i}, {j})") for j, x in enumerate(r)])
            m = len(rows)
            n = len(rows[0]) if rows else 0
            for i, r in enumerate(rows):
                if len(r) != n:
                    raise DimensionError(f"row {i} has {len(r)} entries but row 0 has {n}; all rows need the same length")
            if shape is not None and (m, n) != tuple(shape):
                if m * n or (m and m != shape[0]):
                    raise DimensionError(f"data is {m}×{n} but shape says {shape[0]}×{shape[1]}")
                m, n = _count(shape[0], "rows"), _count(shape[1], "cols")
            q = flint.fmpq_mat(m, n, [x for r in rows for x in r]) if m * n else flint.fmpq_mat(m, n)
        else:
            raise DomainError(f"cannot make a QMatrix from {type(data).__name__}")
        object.__setattr__(self, "_q", q)

    @classmethod
    def _wrap(cls, q: flint.fmpq_mat) -> QMatrix:
        """Wrap without copying.  Precondition: ``q`` is owned by the new matrix and never
        mutated afterwards (not checked)."""
        obj = object.__new__(cls)
        object.__setattr__(obj, "_q", q)
        return obj

    def __setattr__(self, name: str, value: Any) -> None:
        raise AttributeError("QMatrix is immutable; operations return new matrices")

    # -- constructors ----------------------------------------------------------------------
    @classmethod
    def zeros(cls, rows: int, cols: int) -> QMatrix:
        """The rows×cols zero matrix."""
        return cls._wrap(flint.fmpq_mat(_count(rows, "rows"), _count(cols, "cols")))

    @classmethod
    def identity(cls, n: int) -> QMatrix:
        """The n×n identity."""
        return cls._wrap(kernel.qidentity(_count(n, "n")))

    @classmethod
    def unit(cls, n: int, i: int) -> QMatrix:
        """The i-th unit column vector of length n (0-based)."""
        q = flint.fmpq_mat(_count(n, "n"), 1)
        q[_indices([i], n, "unit")[0], 0] = 1
        return cls._wrap(q)

    @classmethod
    def from_polymatrix(cls, P: PolyMatrix, *, name: str = "matrix") -> QMatrix:
        """A PolyMatrix of degree ≤ 0 as a QMatrix (``DomainError`` naming ``name`` otherwise)."""
        return cls._wrap(kernel.qmat(P, name))

    @classmethod
    def hstack(cls, *blocks: QMatrix, rows: int | None = None) -> QMatrix:
        """Blocks side by side (same number of rows); ``rows`` gives the height when there are none."""
        bs = _blocks(blocks, "hstack")
        if not bs:
            return cls.zeros(rows or 0, 0)
        m = bs[0]._q.nrows()
        for k, b in enumerate(bs):
            if b._q.nrows() != m:
                raise DimensionError(f"hstack: block {k} is {b.rows}×{b.cols} but block 0 has {m} rows")
        n = sum(b._q.ncols() for b in bs)
        if m * n == 0:
            return cls.zeros(m, n)
        lists = [b._q.tolist() for b in bs]
        return cls._wrap(flint.fmpq_mat(m, n, [x for i in range(m) for L in lists for x in L[i]]))

    @classmethod
    def vstack(cls, *blocks: QMatrix, cols: int | None = None) -> QMatrix:
        """Blocks on top of each other (same number of columns); ``cols`` gives the width when
        there are none."""
        bs = _blocks(blocks, "vstack")
        if not bs:
            return cls.zeros(0, cols or 0)
        n = bs[0]._q.ncols()
        for k, b in enumerate(bs):
            if b._q.ncols() != n:
                raise DimensionError(f"vstack: block {k} is {b.rows}×{b.cols} but block 0 has {n} columns")
        m = sum(b._q.nrows() for b in bs)
        if m * n == 0:
            return cls.zeros(m, n)
        return cls._wrap(flint.fmpq_mat(m, n, [x for b in bs for x in b._q.entries()]))

    @classmethod
    def block(cls, blocks: Sequence[Sequence[QMatrix]]) -> QMatrix:
        """Block matrix ``[[A, B], [C, D]]``."""
        return cls.vstack(*[cls.hstack(*row) for row in blocks])

    # -- queries -----------------------------------------------------------------------------
    @property
    def shape(self) -> tuple[int, int]:
        return (self._q.nrows(), self._q.ncols())

    @property
    def rows(self) -> int:
        return self._q.nrows()

    @property
    def cols(self) -> int:
        return self._q.ncols()

    @property
    def T(self) -> QMatrix:
        """The transpose."""
        return QMatrix._wrap(self._q.transpose())

    def is_zero(self) -> bool:
        return kernel.is_qzero(self._q)

    def is_square(self) -> bool:
        return self._q.nrows() == self._q.ncols()

    def tolist(self) -> list[list[Fraction]]:
        """Entries as nested lists of Fractions."""
        return [[_frac(x) for x in r] for r in self._q.tolist()] if self.cols else [[] for _ in range(self.rows)]

    def to_polymatrix(self, var: str = "d") -> PolyMatrix:
        """The same matrix as a constant :class:`~uio_ring.ring.matrix.PolyMatrix` in ``var``."""
        return kernel.to_polymatrix(self._q, var)

    # -- indexing ----------------------------------------------------------------------------
    def __getitem__(self, key: Any) -> Any:
        """``M[i, j]`` is a Fraction; with a slice in either place, a QMatrix."""
        if not isinstance(key, tuple) or len(key) != 2:
            raise DimensionError("index a QMatrix with two indices: M[i, j], M[i, :], M[:, a:b]")
        ki, kj = (k if isinstance(k, slice) or not hasattr(k, "__index__") else operator.index(k) for k in key)
        if isinstance(ki, int) and isinstance(kj, int):
            m, n = self.shape
            if not (-m <= ki < m and -n <= kj < n):
                raise IndexError(f"index ({ki}, {kj}) out of range for a {m}×{n} matrix")
            return _frac(self._q[ki % m, kj % n])
        ri = _range(ki, self.rows, "row")
        rj = _range(kj, self.cols, "column")
        return self._select(list(ri), list(rj))

    def take_rows(self, indices: Iterable[int]) -> QMatrix:
        """The rows at ``indices`` (in that order, repeats allowed)."""
        return self._select(_indices(indices, self.rows, "row"), list(range(self.cols)))

    def take_cols(self, indices: Iterable[int]) -> QMatrix:
        """The columns at ``indices`` (in that order, repeats allowed)."""
        return self._select(list(range(self.rows)), _indices(indices, self.cols, "column"))

    def _select(self, ri: list[int], rj: list[int]) -> QMatrix:
        """Precondition: indices in range (not checked)."""
        q = self._q
        if not ri or not rj:
            return QMatrix.zeros(len(ri), len(rj))
        return QMatrix._wrap(flint.fmpq_mat(len(ri), len(rj), [q[i, j] for i in ri for j in rj]))

    def row(self, i: int) -> QMatrix:
        return self.take_rows([i])

    def col(self, j: int) -> QMatrix:
        return self.take_cols([j])

    # -- arithmetic --------------------------------------------------------------------------
    def _check(self, op: str, other: Any) -> QMatrix:
        if not isinstance(other, QMatrix):
            raise DomainError(f"{op}: expected a QMatrix, got {type(other).__name__}")
        if op in "+-" and other.shape != self.shape:
            raise DimensionError(f"{op}: a {self.rows}×{self.cols} and a {other.rows}×{other.cols} matrix")
        if op == "@" and self.cols != other.rows:
            raise DimensionError(
                f"cannot multiply a {self.rows}×{self.cols} by a {other.rows}×{other.cols} matrix "
                f"({self.cols} columns vs {other.rows} rows)"
            )
        return other

    def __add__(self, other: Any) -> QMatrix:
        if not isinstance(other, QMatrix):
            return NotImplemented
        return QMatrix._wrap(self._q + self._check("+", other)._q)

    def __sub__(self, other: Any) -> QMatrix:
        if not isinstance(other, QMatrix):
            return NotImplemented
        return QMatrix._wrap(self._q - self._check("-", other)._q)

    def __neg__(self) -> QMatrix:
        return QMatrix._wrap(-self._q)

    def __pos__(self) -> QMatrix:
        return self

    def __matmul__(self, other: Any) -> QMatrix:
        if not isinstance(other, QMatrix):
            return NotImplemented
        o = self._check("@", other)
        if self.rows == 0 or o.cols == 0 or self.cols == 0:
            return QMatrix.zeros(self.rows, o.cols)
        return QMatrix._wrap(self._q * o._q)

    def __mul__(self, c: Any) -> QMatrix:
        if isinstance(c, QMatrix):
            raise DomainError("use @ for the matrix product; * multiplies by a scalar")
        return QMatrix._wrap(self._q * _scalar(c, "*"))

    __rmul__ = __mul__

    def __pow__(self, e: int) -> QMatrix:
        if not self.is_square():
            raise DimensionError(f"only square matrices have powers; this one is {self.rows}×{self.cols}")
        if not isinstance(e, int) or isinstance(e, bool) or e < 0:
            raise DomainError(f"exponent must be a non-negative int, got {e!r}")
        return binary_power(self, e, QMatrix.identity(self.rows))

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, QMatrix):
            return NotImplemented
        return self.shape == other.shape and (self.rows * self.cols == 0 or self._q == other._q)

    def __hash__(self) -> int:
        return hash((self.shape, tuple(str(x) for x in self._q.entries()) if self.rows * self.cols else ()))

    # -- exact linear algebra (delegated to uio_ring.ring.constant) ---------------------------
    def rank(self) -> int:
        """Rank over Q."""
        return kernel.qrank(self._q)

    def det(self) -> Fraction:
        """Determinant (square matrices)."""
        if not self.is_square():
            raise DimensionError(f"det needs a square matrix; this one is {self.rows}×{self.cols}")
        return _frac(self._q.det()) if self.rows else Fraction(1)

    def rref(self) -> RowEchelon:
        """Reduced row echelon form and pivot columns.

        >>> QMatrix([[0, 2, 4], [0, 1, 3]]).rref().pivots
        (1, 2)
        """
        R, piv = kernel.rref(self._q)
        return RowEchelon(QMatrix._wrap(R), piv)

    def nullspace(self) -> QMatrix:
        """A basis of ``{v : M v = 0}`` as the columns of an n×k matrix (from the rref)."""
        return QMatrix._wrap(kernel.nullspace(self._q))

    def left_nullspace(self) -> QMatrix:
        """A basis of ``{v : v M = 0}`` as the rows of a k×m matrix."""
        return QMatrix._wrap(kernel.left_nullspace(self._q))

    def row_basis(self) -> tuple[int, ...]:
        """Indices of the first rows that form a basis of the row space (greedy, in order)."""
        return kernel.row_basis(self._q)

    def inverse(self, *, name: str = "matrix") -> QMatrix:
        """The inverse; ``DimensionError`` (naming ``name``) if not square or singular."""
        return QMatrix._wrap(kernel.qinverse(self._q, name))

    def solve(self, B: QMatrix, *, name: str = "matrix") -> QMatrix:
        """``X`` with ``M X = B`` for a square nonsingular ``M`` (``DimensionError`` otherwise)."""
        return QMatrix._wrap(kernel.qsolve(self._q, self._check("solve", B)._q, name))

    def min_norm_left_solve(self, b: QMatrix) -> QMatrix | None:
        """The minimum-norm ``ζ`` with ``ζ M = b`` (``b`` one row), or ``None`` if there is none.

        Equal to ``b M⁺`` (Moore–Penrose) whenever a solution exists.

        >>> QMatrix([[2], [0]]).min_norm_left_solve(QMatrix([[3]]))
        QMatrix([[3/2, 0]])
        """
        b = self._check("min_norm_left_solve", b)
        if b.cols != self.cols:
            raise DimensionError(f"min_norm_left_solve: b has {b.cols} columns; expected {self.cols}")
        z = kernel.min_norm_left_solve(self._q, b._q)
        return None if z is None else QMatrix._wrap(z)

    def solve_by_peeling(self, w: QMatrix) -> QMatrix | None:
        """Solve ``M β = w`` (square, one column) by substitution when ``M`` is triangular up to
        row and column permutations; ``None`` if it is not (see
        :func:`uio_ring.ring.constant.solve_by_peeling`).

        >>> QMatrix([[0, 2], [1, 3]]).solve_by_peeling(QMatrix([[4], [5]]))
        QMatrix([[-1], [2]])
        """
        z = kernel.solve_by_peeling(self._q, self._check("solve_by_peeling", w)._q)
        return None if z is None else QMatrix._wrap(z)

    # -- display -----------------------------------------------------------------------------
    def _entry_strings(self) -> list[list[str]]:
        return [[str(x) for x in r] for r in self._q.tolist()]

    def __repr__(self) -> str:
        if self.rows == 0 or self.cols == 0:
            return f"QMatrix.zeros({self.rows}, {self.cols})"
        return "QMatrix([" + ", ".join("[" + ", ".join(r) + "]" for r in self._entry_strings()) + "])"

    def __str__(self) -> str:
        if self.rows == 0 or self.cols == 0:
            return f"[{self.rows}×{self.cols} matrix]"
        cells = self._entry_strings()
        widths = [max(len(cells[i][j]) for i in range(self.rows)) for j in range(self.cols)]
        return "\n".join("[" + "  ".join(c.rjust(w) for c, w in zip(r, widths, strict=True)) + "]" for r in cells)

    def to_latex(self) -> str:
        if self.rows == 0 or self.cols == 0:
            return rf"0_{{{self.rows}\times{self.cols}}}"

        def tex(x: flint.fmpq) -> str:  # FLINT writes the digits: any size
            if x.q == 1:
                return str(x.p)
            sign = "-" if x < 0 else ""
            return rf"{sign}\frac{{{abs(x.p)}}}{{{x.q}}}"

        body = r" \\ ".join(" & ".join(tex(x) for x in r) for r in self._q.tolist())
        return r"\begin{pmatrix} " + body + r" \end{pmatrix}"

    def _repr_latex_(self) -> str:
        return f"${self.to_latex()}$"

    def __iter__(self):  # pragma: no cover - explicit refusal
        raise TypeError("QMatrix is not iterable; use M.tolist() or M[i, :]")

    def __bool__(self) -> bool:
        raise TypeError("the truth value of a QMatrix is ambiguous; use M.is_zero() or ==")


def _blocks(blocks: Sequence[Any], op: str) -> list[QMatrix]:
    for b in blocks:
        if not isinstance(b, QMatrix):
            raise DomainError(f"{op}: expected QMatrix blocks, got {type(b).__name__}")
    return list(blocks)
