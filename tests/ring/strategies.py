"""Hypothesis strategies and independent checkers shared by the ring tests.

Nothing here calls the algorithm under test.  The checkers re-state the
mathematical definitions (normalised Hermite form, Smith form, unimodularity)
directly on the entries, and the reference values come from sympy
(``sympy.matrices.normalforms`` and ``DomainMatrix``), an independent
implementation.

Matrices are built from their *text* (``"3/2*d**2 - d + 1"``), the most
basic documented input, so a test failure points at the algorithm rather than
at a converter.  Degrees, sizes and coefficients are kept small enough that
sympy answers in milliseconds.
"""

from __future__ import annotations

from fractions import Fraction

import sympy as sp
from hypothesis import settings
from hypothesis import strategies as st
from sympy.matrices.normalforms import invariant_factors as sympy_invariant_factors
from sympy.polys.matrices import DomainMatrix

from uio_ring import PolyMatrix

D_SYM = sp.Symbol("d")
QQd = sp.QQ[D_SYM]

MAX_DIM = 6
MAX_DEGREE = 3


def heavy() -> settings:
    """Settings for tests on 6..8-sized matrices (sympy references cost ~0.1-1 s each):
    a quarter of the active profile's examples, at least 5."""
    return settings(max_examples=max(5, settings.default.max_examples // 4))


# ----------------------------------------------------------------------------
# building matrices from coefficients
# ----------------------------------------------------------------------------
def _frac_text(c: Fraction) -> str:
    return str(c.numerator) if c.denominator == 1 else f"{c.numerator}/{c.denominator}"


def poly_text(coeffs: list[Fraction], var: str = "d") -> str:
    """``[c0, c1, c2]`` (low to high) as text, e.g. ``"3/2*d**2 - d + 1"``."""
    terms: list[str] = []
    for k in range(len(coeffs) - 1, -1, -1):
        c = Fraction(coeffs[k])
        if c == 0:
            continue
        sign = "-" if c < 0 else "+"
        a = abs(c)
        if k == 0:
            body = _frac_text(a)
        else:
            mono = var if k == 1 else f"{var}**{k}"
            body = mono if a == 1 else f"{_frac_text(a)}*{mono}"
        terms.append(f"{sign} {body}")
    if not terms:
        return "0"
    text = " ".join(terms)
    return text[2:] if text.startswith("+ ") else "-" + text[2:]


def matrix_from_coeffs(rows: list[list[list[Fraction]]], p: int, q: int, var: str = "d") -> PolyMatrix:
    """A p×q PolyMatrix whose (i, j) entry has coefficients ``rows[i][j]`` (low to high)."""
    if p == 0 or q == 0:
        return PolyMatrix.zeros(p, q)
    return PolyMatrix([[poly_text(c, var) for c in row] for row in rows], var=var)


def P(text: str, var: str = "d"):
    """The Poly written ``text`` (read through the documented matrix parser)."""
    return PolyMatrix([[text]], var=var)[0, 0]


def unit_matrix(n: int, i: int, j: int, entry: str) -> PolyMatrix:
    """Identity plus ``entry`` at (i, j)  (i != j): an elementary unimodular matrix."""
    rows = [["1" if r == c else "0" for c in range(n)] for r in range(n)]
    rows[i][j] = entry
    return PolyMatrix(rows)


def permutation_matrix(perm: list[int]) -> PolyMatrix:
    n = len(perm)
    if n == 0:
        return PolyMatrix.identity(0)
    return PolyMatrix([[1 if perm[r] == c else 0 for c in range(n)] for r in range(n)])


# ----------------------------------------------------------------------------
# strategies
# ----------------------------------------------------------------------------
small_ints = st.integers(-3, 3).map(Fraction)
small_rationals = st.fractions(min_value=-3, max_value=3, max_denominator=4)


def coefficients(rational: bool = True) -> st.SearchStrategy[Fraction]:
    return st.one_of(small_ints, small_rationals) if rational else small_ints


@st.composite
def poly_coeffs(draw, max_degree: int = MAX_DEGREE, rational: bool = True, zero_prob: float = 0.25):
    """Coefficients (low to high) of a random polynomial of degree <= max_degree, often 0."""
    if draw(st.floats(0, 1)) < zero_prob:
        return []
    deg = draw(st.integers(0, max_degree))
    return [draw(coefficients(rational)) for _ in range(deg + 1)]


@st.composite
def dense_matrices(
    draw,
    min_rows: int = 0,
    max_rows: int = MAX_DIM,
    min_cols: int = 0,
    max_cols: int = MAX_DIM,
    max_degree: int = MAX_DEGREE,
    rational: bool = True,
    rows: int | None = None,
    cols: int | None = None,
):
    """Random p×q matrices with independent entries (zero entries are common)."""
    p = rows if rows is not None else draw(st.integers(min_rows, max_rows))
    q = cols if cols is not None else draw(st.integers(min_cols, max_cols))
    zero_prob = draw(st.sampled_from([0.0, 0.25, 0.6]))
    data = [
        [draw(poly_coeffs(max_degree, rational, zero_prob)) for _ in range(q)] for _ in range(p)
    ]
    return matrix_from_coeffs(data, p, q)


@st.composite
def rank_deficient_matrices(draw, min_rows: int = 1, max_rows: int = MAX_DIM, min_cols: int = 1,
                            max_cols: int = MAX_DIM, rows: int | None = None, cols: int | None = None):
    """p×q products A·B of a p×r and an r×q matrix with r < min(p, q) (degrees <= 1 + 2)."""
    p = rows if rows is not None else draw(st.integers(min_rows, max_rows))
    q = cols if cols is not None else draw(st.integers(min_cols, max_cols))
    r = draw(st.integers(0, max(0, min(p, q) - 1)))
    A = draw(dense_matrices(rows=p, cols=r, max_degree=1))
    B = draw(dense_matrices(rows=r, cols=q, max_degree=2))
    if r == 0:
        return PolyMatrix.zeros(p, q)
    return A @ B


def matrices(min_rows: int = 0, max_rows: int = MAX_DIM, min_cols: int = 0, max_cols: int = MAX_DIM,
             **kw) -> st.SearchStrategy[PolyMatrix]:
    """General random matrices: independent entries, or low-rank products."""
    return st.one_of(
        dense_matrices(min_rows=min_rows, max_rows=max_rows, min_cols=min_cols, max_cols=max_cols, **kw),
        rank_deficient_matrices(min_rows=max(1, min_rows), max_rows=max(1, max_rows),
                                min_cols=max(1, min_cols), max_cols=max(1, max_cols)),
    )


def square_matrices(min_n: int = 0, max_n: int = MAX_DIM, **kw) -> st.SearchStrategy[PolyMatrix]:
    return st.integers(min_n, max_n).flatmap(
        lambda n: st.one_of(dense_matrices(rows=n, cols=n, **kw),
                            rank_deficient_matrices(rows=max(n, 1), cols=max(n, 1)))
        if n > 0 else st.just(PolyMatrix.zeros(0, 0))
    )


@st.composite
def unimodular_matrices(draw, n: int, steps: int | None = None, max_degree: int = 1):
    """A random n×n unimodular matrix: product of elementary matrices (row additions with
    polynomial multipliers of degree <= max_degree, a permutation, nonzero constant scalings)."""
    if n == 0:
        return PolyMatrix.identity(0)
    U = permutation_matrix(draw(st.permutations(list(range(n)))))
    k = steps if steps is not None else draw(st.integers(0, 2 * n))
    for _ in range(k if n > 1 else 0):
        i = draw(st.integers(0, n - 1))
        j = draw(st.integers(0, n - 1).filter(lambda x, i=i: x != i))
        c = draw(poly_coeffs(max_degree, rational=True, zero_prob=0.0))
        U = unit_matrix(n, i, j, poly_text(c) if c else "1") @ U
    scale = [draw(st.sampled_from(["1", "-1", "2", "-1/3"])) for _ in range(n)]
    return PolyMatrix.diag(*scale) @ U


# ----------------------------------------------------------------------------
# sympy reference values
# ----------------------------------------------------------------------------
def to_sympy_poly(p) -> sp.Poly:
    """Our Poly as a sympy Poly in d, through its coefficient list."""
    cs = list(p.coeffs())
    return sp.Poly(sum((sp.Rational(c.numerator, c.denominator) * D_SYM**k for k, c in enumerate(cs)),
                       sp.Integer(0)), D_SYM, domain=sp.QQ)


def sympy_matrix(M: PolyMatrix) -> sp.Matrix:
    return M.to_sympy(var="d")


def reference_invariant_factors(M: PolyMatrix) -> list[sp.Poly]:
    """Monic nonzero invariant factors of M according to sympy."""
    if M.rows == 0 or M.cols == 0:
        return []
    fs = sympy_invariant_factors(sympy_matrix(M), domain=QQd)
    return [sp.Poly(f, D_SYM, domain=sp.QQ).monic() for f in fs if sp.expand(f) != 0]


def reference_rank(M: PolyMatrix) -> int:
    if M.rows == 0 or M.cols == 0:
        return 0
    dM = DomainMatrix.from_Matrix(sympy_matrix(M)).convert_to(QQd.get_field())
    return dM.rank()


def reference_det(M: PolyMatrix) -> sp.Poly:
    if M.rows == 0:
        return sp.Poly(1, D_SYM, domain=sp.QQ)
    dM = DomainMatrix.from_Matrix(sympy_matrix(M)).convert_to(QQd)
    return sp.Poly(QQd.to_sympy(dM.det()), D_SYM, domain=sp.QQ)


def same_poly(p, q: sp.Poly) -> bool:
    return to_sympy_poly(p) == q


# ----------------------------------------------------------------------------
# independent checkers (definitions written out on the entries)
# ----------------------------------------------------------------------------
def assert_unimodular(U: PolyMatrix, n: int | None = None) -> None:
    """U square (n×n when given) with determinant a nonzero constant (checked with sympy too)."""
    assert U.rows == U.cols, f"transform is {U.shape}, not square"
    if n is not None:
        assert U.shape == (n, n), f"transform is {U.shape}; expected {(n, n)}"
    det = U.det()
    assert det.degree() == 0, f"det U = {det} is not a nonzero constant"
    ref = reference_det(U)
    assert ref.degree() == 0 and not ref.is_zero, f"sympy: det U = {ref}"
    assert same_poly(det, ref)


def leading_position(row) -> int | None:
    for j, e in enumerate(row):
        if e.degree() >= 0:
            return j
    return None


def assert_hermite_normalised(H: PolyMatrix, pivots=None, rank: int | None = None) -> None:
    """The normalised row Hermite form, entry by entry:
    zero rows last; each nonzero row's first nonzero entry (pivot) strictly right of the
    pivot above; pivots monic; entries above a pivot of lower degree than the pivot."""
    rows = H.tolist()
    found: list[int] = []
    seen_zero = False
    for i, row in enumerate(rows):
        j = leading_position(row)
        if j is None:
            seen_zero = True
            continue
        assert not seen_zero, f"nonzero row {i} below a zero row"
        if found:
            assert j > found[-1], f"pivot of row {i} at column {j}, not right of {found[-1]}"
        piv = row[j]
        assert piv.coeffs()[-1] == 1, f"pivot H[{i},{j}] = {piv} is not monic"
        for k in range(i):
            assert rows[k][j].degree() < piv.degree(), (
                f"H[{k},{j}] = {rows[k][j]} not of lower degree than pivot H[{i},{j}] = {piv}")
        found.append(j)
    if pivots is not None:
        assert tuple(pivots) == tuple(found), f"pivots {tuple(pivots)}; entries say {tuple(found)}"
    if rank is not None:
        assert rank == len(found)


def assert_smith_form(S: PolyMatrix, factors) -> None:
    """S is diag(f1, ..., fr, 0, ...) padded with zeros, fi monic and fi | f(i+1)."""
    r = len(factors)
    rows = S.tolist()
    for i, row in enumerate(rows):
        for j, e in enumerate(row):
            if i == j and i < r:
                assert e == factors[i], f"S[{i},{i}] = {e}; invariant factor is {factors[i]}"
            else:
                assert e.degree() == -1, f"S[{i},{j}] = {e} should be 0"
    for i, f in enumerate(factors):
        assert f.degree() >= 0 and f.coeffs()[-1] == 1, f"invariant factor {i} = {f} not monic"
        if i + 1 < r:
            assert (factors[i + 1] % f).degree() == -1, f"{f} does not divide {factors[i + 1]}"


def row_degrees(M: PolyMatrix) -> list[int]:
    return [max((e.degree() for e in row), default=-1) for row in M.tolist()]


def column_leading_matrix_rank(M: PolyMatrix) -> int:
    """Rank over Q of the column-leading coefficient matrix (M is column reduced iff this
    equals the number of columns and no column is zero)."""
    cols = M.T.tolist()
    data = []
    for col in cols:
        c = max((e.degree() for e in col), default=-1)
        data.append([e.coeffs()[c] if e.degree() == c else Fraction(0) for e in col])
    if not data or not data[0]:
        return 0
    return sp.Matrix(data).rank()


def assert_popov(K: PolyMatrix) -> None:
    """Row-wise Popov form (zero shift): each nonzero row's pivot is its rightmost entry of
    maximal degree; pivots monic, in distinct columns; every other entry in a pivot's column
    has lower degree than the pivot; rows sorted by nondecreasing degree.  A Popov matrix is
    row reduced (its leading coefficient matrix has full row rank)."""
    rows = K.tolist()
    pcols: list[int] = []
    degs: list[int] = []
    for i, row in enumerate(rows):
        dg = max((e.degree() for e in row), default=-1)
        assert dg >= 0, f"row {i} of the basis is zero"
        j = max(c for c, e in enumerate(row) if e.degree() == dg)
        assert row[j].coeffs()[-1] == 1, f"Popov pivot K[{i},{j}] = {row[j]} not monic"
        pcols.append(j)
        degs.append(dg)
    assert len(set(pcols)) == len(pcols), f"pivot columns {pcols} repeat"
    for i, j in enumerate(pcols):
        for k in range(len(rows)):
            if k != i:
                assert rows[k][j].degree() < degs[i], (
                    f"K[{k},{j}] = {rows[k][j]} not of lower degree than pivot K[{i},{j}]")
    assert degs == sorted(degs), f"row degrees {degs} not sorted"
    # row reduced: leading coefficient matrix of full row rank
    if rows:
        lead = [[e.coeffs()[dg] if e.degree() == dg else Fraction(0) for e in row]
                for row, dg in zip(rows, degs, strict=True)]
        assert sp.Matrix(lead).rank() == len(rows), "basis not row reduced"


# ----------------------------------------------------------------------------
# paper 001 (Zheng, Bejarano, Perruquetti, Richard), Section 5: A, B, C, D as printed
# ----------------------------------------------------------------------------
def paper_001_system() -> dict[str, PolyMatrix]:
    """A(δ), B(δ), C(δ), D(δ) of the illustrative example (none listed in docs/errata.md)."""
    return {
        "A": PolyMatrix("[[0, -1, 1, 0], [-1, δ, 0, 0], [1, 0, 1, 0], [δ, 1, 1, -1]]"),
        "B": PolyMatrix("[[0, 0], [0, 0], [1, 1], [0, δ]]"),
        "C": PolyMatrix("[[δ, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 1]]"),
        "D": PolyMatrix("[[1, δ], [0, 0], [1, δ]]"),
    }


def paper_001_M() -> PolyMatrix:
    """Step 1's matrix M = [[C B, D], [D, 0]] (6×4), computed from the system."""
    s = paper_001_system()
    C, B, D = s["C"], s["B"], s["D"]
    return PolyMatrix.block([[C @ B, D], [D, PolyMatrix.zeros(D.rows, D.cols)]])


# ----------------------------------------------------------------------------
# adversarial inputs for evaluation/interpolation code paths
# ----------------------------------------------------------------------------
#: vanishes at 0, 1, −1, 2, −2, 3, −3: the first small integers any evaluation scheme tries
VANISHING = "d*(d - 1)*(d + 1)*(d - 2)*(d + 2)*(d - 3)*(d + 3)"


@st.composite
def singular_at_sample_points(draw, min_n: int = 4, max_n: int = 8):
    """(M, diag) with M = P·diag·Q, P and Q unimodular, diag = (1, …, 1, f[, f·(d − 5)], 0…)
    where f vanishes at the first seven small integers: M(x) loses rank at every one of them."""
    n = draw(st.integers(min_n, max_n))
    k = draw(st.integers(1, 2))
    z = draw(st.integers(0, 1))
    tail = [VANISHING] if k == 1 else [VANISHING, f"({VANISHING})*(d - 5)"]
    diag = ["1"] * (n - k - z) + tail + ["0"] * z
    Pm = draw(unimodular_matrices(n, steps=draw(st.integers(n, 2 * n))))
    Q = draw(unimodular_matrices(n, steps=draw(st.integers(n, 2 * n))))
    return Pm @ PolyMatrix.diag(*diag) @ Q, diag
