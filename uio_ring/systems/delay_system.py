"""``DelaySystem``: a linear system with commensurate delays over Q[δ].

The one notation of the package (docs/notation.md)::

    x'(t) = A(δ) x + B(δ) w + E(δ) u        δ x(t) = x(t − h)
    y(t)  = C(δ) x + D(δ) w + F(δ) u

``w`` is the unknown input (Zheng et al.'s ``u``), ``u`` the known input
(optional; ``E`` and ``F`` default to zero matrices with no columns).  A
delay-free system is a ``DelaySystem`` whose matrices all have δ-degree 0.

>>> sys = DelaySystem("[[0, 1], [-1, d]]", "[[0], [1]]", "[[1, 0]]", "[[0]]", h="0.1")
>>> sys.n_x, sys.n_w, sys.n_u, sys.n_y, sys.max_delay_degree, sys.is_delay_free, sys.h
(2, 1, 0, 1, 1, False, Fraction(1, 10))
>>> sys.at_delta(0).is_delay_free
True
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from uio_ring.errors import DimensionError, DomainError, require
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import exact_fraction

__all__ = ["DelaySystem", "delay_system"]

MatrixLike = Any  # PolyMatrix, text "[[d, 1]]", or nested lists
NamesLike = Sequence[str] | int | None

_MATRIX_NAMES = ("A", "B", "C", "D", "E", "F")


def _as_polymatrix(value: MatrixLike, name: str, empty_shape: tuple[int, int] | None = None) -> PolyMatrix:
    """Convert one system matrix; the error names the matrix.

    An empty list (``[]`` or rows without entries) becomes the zero matrix of
    ``empty_shape`` (a matrix with no columns, e.g. ``B`` without unknown inputs).
    """
    if isinstance(value, PolyMatrix):
        return value
    if (
        empty_shape is not None
        and isinstance(value, (list, tuple))
        and all(isinstance(r, (list, tuple)) and len(r) == 0 for r in value)
    ):
        return PolyMatrix.zeros(*empty_shape)
    try:
        return PolyMatrix(value)
    except (DimensionError, DomainError) as exc:
        raise type(exc)(f"{name}: {exc}") from exc


def _names(value: NamesLike, count: int, prefix: str, what: str) -> tuple[str, ...]:
    """Signal names: ``None`` -> ``prefix[i]``; a count must equal ``count``."""
    if value is None:
        return tuple(f"{prefix}[{i}]" for i in range(count))
    if isinstance(value, int) and not isinstance(value, bool):
        if value != count:
            raise DimensionError(f"{what}={value} but the system has {count} of them")
        return tuple(f"{prefix}[{i}]" for i in range(count))
    if isinstance(value, (str, bool)) or not isinstance(value, Sequence):
        raise DomainError(f"{what} must be a list of names or a count, not {value!r}")
    names = tuple(value)
    if len(names) != count:
        raise DimensionError(f"{what} has {len(names)} names; expected {count}")
    for n in names:
        if not isinstance(n, str) or not n:
            raise DomainError(f"{what}: {n!r} is not a non-empty string")
        if "." in n:
            raise DomainError(f"{what}: name {n!r} contains '.', which is reserved")
    if len(set(names)) != len(names):
        raise DimensionError(f"{what} has repeated names: {list(names)}")
    return names


@dataclass(frozen=True, init=False, eq=True, repr=False)
class DelaySystem:
    """``x' = A(δ)x + B(δ)w + E(δ)u``, ``y = C(δ)x + D(δ)w + F(δ)u`` over Q[δ].

    Parameters
    ----------
    A, B, C, D
        System matrices: PolyMatrix, text such as ``"[[0, 1], [-1, d]]"`` (``δ``
        accepted for ``d``), or nested lists of int/Fraction/str.  ``D=None``
        means the zero ``n_y × n_w`` matrix.
    E, F
        Known-input matrices (default: no known input, ``n_u = 0``).  If only
        one is given the other is the zero matrix of the fitting shape.
    h
        The basic delay (positive rational; ``"0.01"`` is 1/100, a float is read
        through its decimal text), or ``None`` when not fixed.  Exact design does
        not need it; simulation does.
    state_names, output_names, unknown_input_names, known_input_names
        Lists of names (no ``.``) or ``None`` for ``x[i]``, ``y[i]``, ``w[i]``, ``u[i]``.

    Raises
    ------
    DimensionError
        A matrix whose shape does not fit, naming it and the expected shape, e.g.
        ``"B has 3 rows; expected 2 (= rows of A)"``.
    DomainError
        A non-rational entry, or a non-positive ``h``.

    Examples
    --------
    >>> sys = DelaySystem([[0, 1], [0, "d"]], [[0], [1]], [[1, 0]], None)
    >>> sys.D
    PolyMatrix([[0]])
    >>> DelaySystem([[0, 1], [0, 0]], [[0], [1], [2]], [[1, 0]], None)
    Traceback (most recent call last):
    ...
    uio_ring.ring.errors.DimensionError: B has 3 rows; expected 2 (= rows of A)
    """

    A: PolyMatrix
    B: PolyMatrix
    C: PolyMatrix
    D: PolyMatrix
    E: PolyMatrix
    F: PolyMatrix
    h: Fraction | None
    state_names: tuple[str, ...]
    output_names: tuple[str, ...]
    unknown_input_names: tuple[str, ...]
    known_input_names: tuple[str, ...]

    def __init__(
        self,
        A: MatrixLike,
        B: MatrixLike,
        C: MatrixLike,
        D: MatrixLike | None,
        E: MatrixLike | None = None,
        F: MatrixLike | None = None,
        *,
        h: Any = None,
        state_names: NamesLike = None,
        output_names: NamesLike = None,
        unknown_input_names: NamesLike = None,
        known_input_names: NamesLike = None,
    ) -> None:
        A_ = _as_polymatrix(A, "A")
        if A_.rows != A_.cols:
            raise DimensionError(f"A is {A_.rows}×{A_.cols}; it must be square (n_x × n_x)")
        n = A_.rows
        if n == 0:
            raise DimensionError("A is 0×0: a system without states has nothing to observe; give at least one state")
        C_ = _as_polymatrix(C, "C")
        if C_.cols != n:
            raise DimensionError(f"C has {C_.cols} columns; expected {n} (= columns of A)")
        p = C_.rows
        B_ = _as_polymatrix(B, "B", (n, 0))
        if B_.rows != n:
            raise DimensionError(f"B has {B_.rows} rows; expected {n} (= rows of A)")
        m = B_.cols
        D_ = PolyMatrix.zeros(p, m) if D is None else _as_polymatrix(D, "D", (p, m))
        if D_.shape != (p, m):
            raise DimensionError(
                f"D is {D_.rows}×{D_.cols}; expected {p}×{m} (= rows of C × columns of B)"
            )
        if E is None and F is None:
            E_, F_ = PolyMatrix.zeros(n, 0), PolyMatrix.zeros(p, 0)
        elif E is None:
            F_ = _as_polymatrix(F, "F", (p, 0))
            E_ = PolyMatrix.zeros(n, F_.cols)
        else:
            E_ = _as_polymatrix(E, "E", (n, 0))
            F_ = PolyMatrix.zeros(p, E_.cols) if F is None else _as_polymatrix(F, "F", (p, E_.cols))
        if E_.rows != n:
            raise DimensionError(f"E has {E_.rows} rows; expected {n} (= rows of A)")
        if F_.rows != p:
            raise DimensionError(f"F has {F_.rows} rows; expected {p} (= rows of C)")
        if F_.cols != E_.cols:
            raise DimensionError(
                f"F has {F_.cols} columns; expected {E_.cols} (= columns of E, the known inputs)"
            )
        vars_ = {M.var for M in (A_, B_, C_, D_, E_, F_)}
        if len(vars_) != 1:
            raise DomainError(f"the matrices use different indeterminates: {sorted(vars_)}")
        h_ = None if h is None else exact_fraction(h, "h")
        if h_ is not None and h_ <= 0:
            raise DomainError(f"h = {h_} must be positive")
        set_ = object.__setattr__
        for name, M in zip(_MATRIX_NAMES, (A_, B_, C_, D_, E_, F_), strict=True):
            set_(self, name, M)
        set_(self, "h", h_)
        set_(self, "state_names", _names(state_names, n, "x", "state_names"))
        set_(self, "output_names", _names(output_names, p, "y", "output_names"))
        set_(self, "unknown_input_names", _names(unknown_input_names, m, "w", "unknown_input_names"))
        set_(self, "known_input_names", _names(known_input_names, E_.cols, "u", "known_input_names"))

    # -- constructors -------------------------------------------------------------
    @classmethod
    def from_coefficients(
        cls,
        *,
        A: Sequence[Any],
        B: Sequence[Any],
        C: Sequence[Any],
        D: Sequence[Any] | None = None,
        E: Sequence[Any] | None = None,
        F: Sequence[Any] | None = None,
        h: Any = None,
        state_names: NamesLike = None,
        output_names: NamesLike = None,
        unknown_input_names: NamesLike = None,
        known_input_names: NamesLike = None,
    ) -> DelaySystem:
        """The paper's form (1): ``A = [A0, A1, …]`` means ``A(δ) = Σ A_i δ^i``.

        >>> sys = DelaySystem.from_coefficients(A=[[[0]], [[1]]], B=[[[1]]], C=[[[1]]])
        >>> sys.A, sys.max_delay_degree
        (PolyMatrix([[d]]), 1)
        """

        def conv(coeffs: Sequence[Any] | None, name: str) -> PolyMatrix | None:
            if coeffs is None:
                return None
            try:
                return PolyMatrix.from_coefficients(list(coeffs))
            except (DimensionError, DomainError) as exc:
                raise type(exc)(f"{name}: {exc}") from exc

        return cls(
            conv(A, "A"),
            conv(B, "B"),
            conv(C, "C"),
            conv(D, "D"),
            conv(E, "E"),
            conv(F, "F"),
            h=h,
            state_names=state_names,
            output_names=output_names,
            unknown_input_names=unknown_input_names,
            known_input_names=known_input_names,
        )

    # -- sizes and structure --------------------------------------------------------
    @property
    def n_x(self) -> int:
        """Number of states."""
        return self.A.rows

    @property
    def n_w(self) -> int:
        """Number of unknown inputs."""
        return self.B.cols

    @property
    def n_u(self) -> int:
        """Number of known inputs."""
        return self.E.cols

    @property
    def n_y(self) -> int:
        """Number of outputs."""
        return self.C.rows

    def matrices(self) -> dict[str, PolyMatrix]:
        """``{"A": A, …, "F": F}`` in that order."""
        return {name: getattr(self, name) for name in _MATRIX_NAMES}

    @property
    def max_delay_degree(self) -> int:
        """Largest δ-degree over all six matrices (0 for a delay-free system)."""
        return max(0, *(M.degree() for M in self.matrices().values()))

    @property
    def is_delay_free(self) -> bool:
        """True when every matrix has δ-degree 0 (or is zero)."""
        return self.max_delay_degree == 0

    def at_delta(self, value: Any = 0) -> DelaySystem:
        """The delay-free system with δ replaced by ``value`` (``0`` drops every delayed term).

        Note that this is a different system, not an approximation: unimodularity
        over Q[δ] cannot be read off at δ = 0.
        """
        return DelaySystem(
            *(M.eval(value) for M in self.matrices().values()),
            h=self.h,
            state_names=self.state_names,
            output_names=self.output_names,
            unknown_input_names=self.unknown_input_names,
            known_input_names=self.known_input_names,
        )

    def input_augmented(self) -> DelaySystem:
        """The system of ``χ = [x; w]`` driven by ``w'`` (to estimate ``w`` as a state)::

            χ' = [[A, B], [0, 0]] χ + [0; I] w' + [E; 0] u,    y = [C, D] χ + F u

        >>> DelaySystem("[[0]]", "[[1]]", "[[1]]", "[[2]]").input_augmented().A
        PolyMatrix([[0, 1], [0, 0]])
        """
        n, m, p, nu = self.n_x, self.n_w, self.n_y, self.n_u
        Z, I = PolyMatrix.zeros, PolyMatrix.identity
        w_names = tuple(self.unknown_input_names)
        return DelaySystem(
            PolyMatrix.vstack(PolyMatrix.hstack(self.A, self.B), Z(m, n + m)),
            PolyMatrix.vstack(Z(n, m), I(m)),
            PolyMatrix.hstack(self.C, self.D),
            Z(p, m),
            PolyMatrix.vstack(self.E, Z(m, nu)) if nu else None,
            self.F if nu else None,
            h=self.h,
            state_names=tuple(self.state_names) + w_names,
            output_names=self.output_names,
            unknown_input_names=tuple(f"d{name}" for name in w_names),
            known_input_names=self.known_input_names,
        )

    # -- conversions ----------------------------------------------------------------
    def to_control(self) -> Any:
        """A python-control ``StateSpace`` of a delay-free system (inputs ``[w; u]``).

        Needs the optional dependency ``control`` (``pip install 'uio-ring[control]'``).
        The entries become floats here: this is a numeric hand-over, not exact.

        Raises
        ------
        DomainError
            If the system has delays.
        MissingDependencyError
            If python-control is not installed.
        """
        if not self.is_delay_free:
            raise DomainError(
                f"to_control needs a delay-free system; this one has δ-degree {self.max_delay_degree} "
                "(use at_delta(0) to drop the delayed terms, which changes the system)"
            )
        control = require("control", extra="control")

        def num(M: PolyMatrix) -> list[list[float]]:
            return [[float(x) for x in row] for row in M.coefficient_lists()[0]]

        Bu = PolyMatrix.hstack(self.B, self.E)
        Du = PolyMatrix.hstack(self.D, self.F)
        return control.ss(
            num(self.A),
            num(Bu) if Bu.cols else [[]] * self.n_x,
            num(self.C),
            num(Du) if Du.cols else [[]] * self.n_y,
            states=list(self.state_names),
            inputs=list(self.unknown_input_names + self.known_input_names),
            outputs=list(self.output_names),
        )

    @classmethod
    def from_control(cls, ss: Any, *, unknown_inputs: Any = None, h: Any = None) -> DelaySystem:
        """A delay-free system from a python-control ``StateSpace``, keeping its signal names.

        The inputs of ``ss`` are split into unknown inputs ``w`` (the first ``unknown_inputs``
        of them when it is a count, or the inputs with these names / indices; default: all)
        and known inputs ``u`` (the rest): ``A, [B, E], C, [D, F]``.  Entries are read
        through their shortest decimal text (``0.1`` → 1/10), as floats are everywhere in
        the package.

        >>> import control
        >>> g = control.ss([[0, 1], [-2, -3]], [[0, 0], [1, 1]], [[1, 0]], [[0, 0]],
        ...                inputs=["fault", "demand"], outputs=["pos"], states=["p", "v"])
        >>> sys = DelaySystem.from_control(g, unknown_inputs=["fault"])
        >>> sys.n_w, sys.n_u, sys.state_names, sys.known_input_names
        (1, 1, ('p', 'v'), ('demand',))
        """
        require("control", extra="control")
        A, B, C, D = (getattr(ss, k) for k in "ABCD")
        names_in = list(getattr(ss, "input_labels", None) or [f"u[{i}]" for i in range(B.shape[1])])
        m_all = B.shape[1]
        if unknown_inputs is None:
            w_idx = list(range(m_all))
        elif isinstance(unknown_inputs, int):
            if not 0 <= unknown_inputs <= m_all:
                raise DimensionError(f"unknown_inputs = {unknown_inputs}; the StateSpace has {m_all} inputs")
            w_idx = list(range(unknown_inputs))
        else:
            w_idx = []
            for k in unknown_inputs:
                if isinstance(k, str):
                    if k not in names_in:
                        raise DimensionError(f"unknown_inputs: no input named {k!r} (inputs: {names_in})")
                    w_idx.append(names_in.index(k))
                else:
                    w_idx.append(int(k))
        u_idx = [i for i in range(m_all) if i not in w_idx]

        def rows(M: Any, cols: list[int] | None = None) -> PolyMatrix:
            arr = [[repr(float(v)) for v in (r if cols is None else [r[c] for c in cols])] for r in M.tolist()]
            n_cols = M.shape[1] if cols is None else len(cols)
            return PolyMatrix(arr, shape=(M.shape[0], n_cols))

        return cls(
            rows(A), rows(B, w_idx), rows(C), rows(D, w_idx), E=rows(B, u_idx), F=rows(D, u_idx), h=h,
            state_names=list(getattr(ss, "state_labels", None) or []) or None,
            output_names=list(getattr(ss, "output_labels", None) or []) or None,
            unknown_input_names=[names_in[i] for i in w_idx] if w_idx else None,
            known_input_names=[names_in[i] for i in u_idx] if u_idx else None,
        )

    def to_dict(self) -> dict[str, Any]:
        """Plain data (matrices as lists of polynomial strings, ``h`` as a string)."""
        return {
            **{name: [[str(x) for x in row] for row in M.tolist()] for name, M in self.matrices().items()},
            "h": None if self.h is None else str(self.h),
            "state_names": list(self.state_names),
            "output_names": list(self.output_names),
            "unknown_input_names": list(self.unknown_input_names),
            "known_input_names": list(self.known_input_names),
        }

    @classmethod
    def from_dict(cls, data: dict[str, Any]) -> DelaySystem:
        """Inverse of :meth:`to_dict`.

        >>> sys = DelaySystem("[[d]]", "[[1]]", "[[1]]", None, h="1/2")
        >>> DelaySystem.from_dict(sys.to_dict()) == sys
        True
        """
        d = dict(data)
        shapes = {}
        n = len(d["A"])
        p = len(d["C"])
        shapes["B"], shapes["D"] = (n, 0), (p, 0)
        shapes["E"], shapes["F"] = (n, 0), (p, 0)

        def get(name: str) -> Any:
            v = d.get(name)
            if v is None:
                return None
            if isinstance(v, list) and (not v or not v[0]):
                return PolyMatrix.zeros(*shapes[name]) if name in shapes else v
            return v

        return cls(
            get("A"),
            get("B"),
            get("C"),
            get("D"),
            get("E"),
            get("F"),
            h=d.get("h"),
            state_names=d.get("state_names"),
            output_names=d.get("output_names"),
            unknown_input_names=d.get("unknown_input_names"),
            known_input_names=d.get("known_input_names"),
        )

    # -- display --------------------------------------------------------------------
    def __repr__(self) -> str:
        parts = [f"{name}={M!r}" for name, M in self.matrices().items() if name in "ABCD" or M.cols]
        if self.h is not None:
            parts.append(f"h={self.h}")
        return "DelaySystem(" + ", ".join(parts) + ")"

    def __str__(self) -> str:
        head = (
            f"DelaySystem: n_x={self.n_x}, n_w={self.n_w} (unknown), n_u={self.n_u} (known), "
            f"n_y={self.n_y}, δ-degree {self.max_delay_degree}"
            + ("" if self.h is None else f", h={self.h}")
        )
        lines = [head, "  x' = A x + B w" + (" + E u" if self.n_u else ""),
                 "  y  = C x + D w" + (" + F u" if self.n_u else "")]
        for name, M in self.matrices().items():
            if name in "EF" and not self.n_u:
                continue
            lines.append(f"  {name} = " + str(M).replace("\n", "\n      "))
        return "\n".join(lines)

    def to_latex(self) -> str:
        """The system equations with its matrices, as LaTeX (δ printed)."""
        eqs = [r"\dot x = A(\delta)x + B(\delta)w" + (r" + E(\delta)u" if self.n_u else ""),
               r"y = C(\delta)x + D(\delta)w" + (r" + F(\delta)u" if self.n_u else "")]
        mats = [f"{name} = {_bare_latex(M)}" for name, M in self.matrices().items()
                if name in "ABCD" or self.n_u]
        return r"\begin{gathered}" + r" \\ ".join(eqs) + r" \\ " + r",\; ".join(mats) + r"\end{gathered}"

    def _repr_latex_(self) -> str:
        return "$$" + self.to_latex() + "$$"


def _bare_latex(M: PolyMatrix) -> str:
    """LaTeX of a matrix without surrounding ``$``."""
    text = M.to_latex()
    return text.strip("$").strip()


def delay_system(
    A: MatrixLike,
    B: MatrixLike,
    C: MatrixLike,
    D: MatrixLike | None = None,
    *,
    E: MatrixLike | None = None,
    F: MatrixLike | None = None,
    h: Any = None,
    states: NamesLike = None,
    outputs: NamesLike = None,
    unknown_inputs: NamesLike = None,
    inputs: NamesLike = None,
) -> DelaySystem:
    """Factory in the python-control style; same as :class:`DelaySystem`.

    >>> delay_system("[[d]]", "[[1]]", "[[1]]", states=["p"]).state_names
    ('p',)
    """
    return DelaySystem(
        A, B, C, D, E, F, h=h, state_names=states, output_names=outputs,
        unknown_input_names=unknown_inputs, known_input_names=inputs,
    )
