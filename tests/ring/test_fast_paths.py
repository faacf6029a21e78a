"""Fast paths of issue 15 against the elimination path and against the definitions.

* the Popov kernel basis from one block-Toeplitz nullspace
  (:mod:`uio_ring.ring._kernel_basis`) equals the elimination + Mulders–Storjohann
  Popov basis (the Popov basis of a module is unique);
* the one-step Popov division (:mod:`uio_ring.ring._division`) equals the
  term-by-term reduction (the remainder modulo a Popov basis is unique);
* high-degree 2×2 matrices (the xgcd column step) at k = 32, and tall
  (n+4)×n matrices, through hermite, smith, left_kernel, left_inverse, solve_left;
* the import graph of ``uio_ring.ring`` is acyclic, with no imports inside
  functions.
"""

from __future__ import annotations

import ast
import contextlib
import importlib
import pathlib
import random
from unittest import mock

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from uio_ring.ring import (
    PolyMatrix,
    hermite,
    is_hermite,
    is_left_unimodular,
    is_smith,
    is_unimodular,
    left_inverse,
    left_kernel,
    smith,
    solve_left,
)
from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring._division import reduce_modulo_popov
from uio_ring.ring._kernel_basis import popov_left_kernel
from uio_ring.ring.hermite import hermite_by_elimination
from uio_ring.ring.kernel import left_kernel_by_elimination

hermite_module = importlib.import_module("uio_ring.ring.hermite")

from .strategies import (  # noqa: E402
    P,
    assert_popov,
    assert_unimodular,
    dense_matrices,
    heavy,
    matrices,
    rank_deficient_matrices,
)


def random_matrix(rng: random.Random, m: int, n: int, deg: int) -> PolyMatrix:
    return PolyMatrix(
        [["+".join(f"({rng.randint(-3, 3)})*d**{e}" for e in range(deg + 1)) for _ in range(n)]
         for _ in range(m)]
    )


def high_degree(k: int) -> PolyMatrix:
    """The 2×2 family of issue 15."""
    return PolyMatrix([[f"(1 + d)**{k}", f"d**{k - 1} + 1"], [f"d**{k} - 1", f"(d - 1)**{k}"]])


# ----------------------------------------------------------------------------
# Toeplitz kernel basis vs elimination
# ----------------------------------------------------------------------------
def toeplitz_kernel(M: PolyMatrix) -> PolyMatrix:
    """The Toeplitz path at every size (the public functions use it from 6 rows)."""
    K = popov_left_kernel(M._r, *M.shape, min_rows=0)
    assert K is not None
    return PolyMatrix._new(K, len(K), M.rows, M.var)


@given(matrices())
def test_toeplitz_kernel_equals_elimination_kernel(M):
    K = toeplitz_kernel(M)
    assert K == left_kernel_by_elimination(M) == left_kernel(M)
    assert (K @ M).is_zero()
    assert_popov(K)


@given(rank_deficient_matrices())
def test_toeplitz_kernel_rank_deficient(M):
    K = toeplitz_kernel(M)
    assert K.rows == M.rows - M.rank()
    assert K == left_kernel_by_elimination(M)


@heavy()
@given(st.integers(1, 5).flatmap(lambda n: dense_matrices(rows=n + 4, cols=n, max_degree=2)))
def test_toeplitz_kernel_tall(M):
    K = toeplitz_kernel(M)
    assert K == left_kernel_by_elimination(M)
    # minimal: the row degrees of a minimal basis add up to at most those of any other
    # basis, e.g. the kernel rows of an (unreduced) elimination transform
    assert sum(K.row_degrees()) <= sum(left_kernel_by_elimination(M).row_degrees())


def test_toeplitz_kernel_known():
    M = PolyMatrix("[[1], [d], [d**2]]")
    assert toeplitz_kernel(M) == PolyMatrix("[[d, -1, 0], [0, d, -1]]")
    # rational coefficients: the kernel does not depend on the column scaling
    N = PolyMatrix("[[1/2, d/3], [d, 2*d**2/3], [0, 1/5]]")
    assert toeplitz_kernel(N) == left_kernel_by_elimination(N)
    assert popov_left_kernel(PolyMatrix.zeros(3, 2)._r, 3, 2, min_rows=0) == dn.identity(3)
    assert popov_left_kernel(PolyMatrix.identity(2)._r, 2, 2, min_rows=0) == []
    assert popov_left_kernel(M._r, 3, 1) is None  # below TOEPLITZ_MIN_ROWS: elimination


def test_toeplitz_kernel_high_degree():
    """Kernel of a column with entries of degree 32: minimal indices up to 32."""
    M = PolyMatrix([["(1 + d)**32"], ["d**31 + 1"], ["d**32 - 1"]])
    K = toeplitz_kernel(M)
    assert K == left_kernel_by_elimination(M)
    assert (K @ M).is_zero() and K.rows == 2


# ----------------------------------------------------------------------------
# Hermite / left inverse from Toeplitz systems vs elimination
# ----------------------------------------------------------------------------
@given(st.one_of(matrices(min_rows=1), rank_deficient_matrices(),
                 st.integers(1, 4).flatmap(lambda n: dense_matrices(rows=n + 2, cols=n, max_degree=2))))
def test_toeplitz_hermite_equals_elimination(M):
    """rank < rows: U = [X; K] with X reduced modulo the Popov kernel K is unique, so
    the Toeplitz path and the elimination path (U reduced by Popov division) agree
    entry by entry.  The Toeplitz path is forced at every size."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hermite_module, "TOEPLITZ_MIN_ROWS", 1)
        h = hermite(M)
    ref = hermite_by_elimination(M)
    assert h.H == ref.H and h.rank == ref.rank and h.pivots == ref.pivots
    assert h.U @ M == h.H and is_unimodular(h.U)
    if h.rank < M.rows:
        assert h.U == ref.U


@given(st.integers(2, 5).flatmap(lambda n: dense_matrices(rows=n, cols=n, max_degree=2)))
def test_one_row_kernel_reduction_equals_the_popov_division(T):
    """reduce_transform with a one-row kernel (corank 1): the row made monic at its leading
    entry and one Euclidean quotient per top row give exactly the Popov form and the
    remainder of the general division."""
    from uio_ring.ring import _dense as dn
    from uio_ring.ring import _division as dv
    from uio_ring.ring._echelon import _reduce_by_one_row

    u = dn.copy(T._r)
    r = len(u) - 1
    if not any(u[r]):
        return
    kern = [list(u[r])]
    dn.weak_popov(kern)
    dn.popov(kern)
    expected = dv.reduce_modulo_popov(u[:r], kern) + kern
    _reduce_by_one_row(u, r)
    assert u == expected


@given(st.one_of(matrices(min_rows=1, max_cols=3), rank_deficient_matrices(max_cols=3)), st.data())
def test_hermite_without_zero_columns_equals_elimination(M, data):
    """Zero columns are set aside (hermite builds H from the form of the other columns):
    H, U, rank and pivots equal the elimination's on the whole matrix — U is unique
    (square nonsingular, or reduced modulo the Popov kernel rows)."""
    at = sorted(data.draw(st.lists(st.integers(0, M.cols), min_size=1, max_size=2)))
    cols = [M[:, j : j + 1] for j in range(M.cols)]
    for k, j in enumerate(at):
        cols.insert(j + k, PolyMatrix.zeros(M.rows, 1))
    P = PolyMatrix.hstack(*cols)
    h, ref = hermite(P), hermite_by_elimination(P)
    assert h.H == ref.H and h.rank == ref.rank and h.pivots == ref.pivots
    assert h.U == ref.U
    assert h.U @ P == h.H and is_unimodular(h.U)


@heavy()
@given(st.integers(1, 5).flatmap(lambda n: dense_matrices(rows=n + 3, cols=n, max_degree=2)))
def test_left_inverse_fast_path_is_the_reduced_inverse(M):
    if not is_left_unimodular(M):
        return
    X = left_inverse(M)
    assert X @ M == PolyMatrix.identity(M.cols)
    h = hermite_by_elimination(M)  # H = [I; 0]: its U's top rows are the reduced inverse
    assert X == h.U[: M.cols, :]


# ----------------------------------------------------------------------------
# Popov division
# ----------------------------------------------------------------------------
@given(st.data())
def test_popov_division_is_the_unique_remainder(data):
    M = data.draw(rank_deficient_matrices(min_rows=2))
    K = left_kernel(M)
    if K.rows == 0:
        return
    X = data.draw(dense_matrices(rows=3, cols=M.rows, max_degree=6))
    got = reduce_modulo_popov(X._r, K._r)
    ref = dn.copy(X._r)
    pivots = [dn.leading_position(row)[::-1] for row in K._r]
    dn.reduce_rows(ref, range(3), pivots, basis=K._r)  # term by term (reference)
    assert got == ref
    R = PolyMatrix._new(got, 3, M.rows, "d")
    assert (R @ M) == (X @ M)  # differs from X by kernel rows
    for (deg, col) in (dn.leading_position(row) for row in K._r):
        assert all(r[col].degree() < deg for r in got)


# ----------------------------------------------------------------------------
# high degree (xgcd steps), k = 32 in the suite
# ----------------------------------------------------------------------------
@pytest.mark.parametrize("k", [8, 32])
def test_hermite_high_degree(k):
    M = high_degree(k)
    h = hermite(M)
    assert h.U @ M == h.H and is_hermite(h.H) and is_unimodular(h.U)
    assert h.verify(M).ok
    a, c = M[0, 0], M[1, 0]
    assert h.H[0, 0] == a.gcd(c)  # the pivot of column 0 is the gcd of the column
    assert h.H[0, 0] * h.H[1, 1] == M.det().monic()


@pytest.mark.parametrize("k", [8, 32])
def test_smith_high_degree(k):
    M = high_degree(k)
    s = smith(M)
    assert s.U @ M @ s.V == s.S and is_smith(s.S)
    assert_unimodular(s.U, 2)
    assert_unimodular(s.V, 2)
    g = M[0, 0]
    for e in (M[0, 1], M[1, 0], M[1, 1]):
        g = g.gcd(e)
    assert s.invariant_factors == (g, (M.det() // g).monic())


# ----------------------------------------------------------------------------
# small square matrices of high degree: the elimination while it stays small, then
# evaluation and interpolation (``generic_first``), then the elimination without cap
# ----------------------------------------------------------------------------
smith_module = importlib.import_module("uio_ring.ring.smith")


def _recording(real, calls: list[bool]):
    """``real`` (generic_hermite), appending to ``calls`` whether each call answered."""
    def spy(a, n):
        got = real(a, n)
        calls.append(got is not None)
        return got

    return spy


def _spy_generic(monkeypatch) -> list[bool]:
    """Record, for each call of generic_hermite by hermite or smith, whether it succeeded."""
    calls: list[bool] = []
    spy = _recording(hermite_module.generic_hermite, calls)
    monkeypatch.setattr(hermite_module, "generic_hermite", spy)
    monkeypatch.setattr(smith_module, "generic_hermite", spy)
    return calls


def _unimodular(rng: random.Random, n: int) -> PolyMatrix:
    """L·R, L unit lower and R unit upper triangular with entries of degree ≤ 1."""
    def entry():
        return f"({rng.randint(-2, 2)}) + ({rng.randint(-2, 2)})*d"

    L = PolyMatrix([[1 if i == j else (entry() if j < i else 0) for j in range(n)] for i in range(n)])
    R = PolyMatrix([[1 if i == j else (entry() if j > i else 0) for j in range(n)] for i in range(n)])
    return L @ R


@pytest.mark.parametrize("n,deg", [(3, 16), (4, 8), (5, 4)])
def test_small_square_of_high_degree_takes_the_generic_path(monkeypatch, n, deg):
    """Random entries swell the elimination past its cap: the generic path answers, with
    the elimination's H and U (U = H·M⁻¹ is unique) and a Smith form from the same H."""
    M = random_matrix(random.Random(n * 100 + deg), n, n, deg)
    calls = _spy_generic(monkeypatch)
    h = hermite(M)
    assert calls == [True]
    e = hermite_by_elimination(M)
    assert (h.H, h.U) == (e.H, e.U)
    s = smith(M)
    assert calls == [True, True]
    assert s.U @ M @ s.V == s.S and is_smith(s.S)
    assert_unimodular(s.U, n)
    assert_unimodular(s.V, n)
    assert s.S == smith_module.smith_by_elimination(M).S
    assert s.S[n - 1, n - 1] == M.det().monic()


def test_small_square_of_high_degree_with_small_coefficients_stays_in_the_elimination(monkeypatch):
    """A product of unimodular factors and diag(1, 1, δ+1, (δ+1)(δ−2)) keeps its
    coefficients small: the capped elimination answers, the generic path is not tried."""
    rng = random.Random(4)
    S = PolyMatrix.diag(1, 1, "d + 1", "(d + 1)*(d - 2)")
    M = _unimodular(rng, 4) @ _unimodular(rng, 4) @ S @ _unimodular(rng, 4) @ _unimodular(rng, 4)
    assert hermite_module.generic_first(M._r, 4)  # high degree: the generic path would be tried
    calls = _spy_generic(monkeypatch)
    h, s = hermite(M), smith(M)
    assert calls == []
    assert (h.H, h.U) == (hermite_by_elimination(M).H, hermite_by_elimination(M).U)
    assert s.U @ M @ s.V == s.S and s.S == S
    assert_unimodular(s.U, 4)
    assert_unimodular(s.V, 4)


@contextlib.contextmanager
def _generic_calls(module):
    """Record, inside the block, whether each call of ``module.generic_hermite`` answered
    (without pytest's monkeypatch fixture, which hypothesis tests cannot take)."""
    calls: list[bool] = []
    with mock.patch.object(module, "generic_hermite", _recording(module.generic_hermite, calls)):
        yield calls


def _rows_of_degrees(rng: random.Random, degrees: list[int]) -> PolyMatrix:
    """A square matrix whose row i has entries of degree ≤ degrees[i], one of them exactly."""
    def entry(d: int, lead: bool) -> str:
        coeffs = [rng.randint(-3, 3) for _ in range(d)] + [rng.choice([-2, -1, 1, 2]) if lead else rng.randint(-3, 3)]
        return " + ".join(f"({c})*d**{e}" for e, c in enumerate(coeffs))

    n = len(degrees)
    return PolyMatrix([[entry(d, j == i % n) for j in range(n)] for i, d in enumerate(degrees)])


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 10**6), low=st.lists(st.integers(0, 2), min_size=1, max_size=5),
       high=st.lists(st.integers(14, 24), min_size=1, max_size=2))
def test_square_with_few_rows_of_high_degree_takes_the_elimination(seed, low, high):
    """Row degrees such as 0, 2, 1, 16, 24 (``few_high_rows``; 3 to 7 rows): the elimination under
    ``unbalanced_cap`` answers, without the generic path, and gives the unique H and U; with
    the cap at zero it gives way and the other paths give the same H and U."""
    degrees = low + high
    assume(len(degrees) >= 3)
    M = _rows_of_degrees(random.Random(seed), degrees)
    assume(not M.det().is_zero())
    n = len(degrees)
    assert hermite_module.generic_first(M._r, n) and hermite_module.few_high_rows(M._r)
    ref = hermite_by_elimination(M)
    with _generic_calls(hermite_module) as calls:
        h = hermite(M)
        assert calls == []
        assert (h.H, h.U) == (ref.H, ref.U) and h.U @ M == h.H
        with mock.patch.object(hermite_module, "UNBALANCED_CAP_FACTOR", 0):
            g = hermite(M)
    assert (g.H, g.U) == (ref.H, ref.U)


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10**6), low=st.lists(st.integers(0, 2), min_size=2, max_size=4),
       high=st.integers(14, 24))
def test_smith_of_rows_far_apart_goes_through_the_transpose(seed, low, high):
    """Row degrees such as 0, 2, 1, 20 (``transposed_route``): S from the transpose, with
    the row of greatest degree last, is the Smith form, and V, the transform that is
    large there, has entries of degree ≤ Σ row degrees − the greatest (the bound of
    the transposed route; the direct route's V holds h, of degree up to deg det − 1)."""
    degrees = low + [high]
    M = _rows_of_degrees(random.Random(seed), degrees)
    n = len(degrees)
    assume(smith_module.full_rank_at_zero(M._r, n, n))  # M(0) nonsingular: the route's precondition
    assert smith_module.transposed_route(M._r, n) is not None
    with _generic_calls(smith_module) as answered:
        s = smith(M)
    assert s.U @ M @ s.V == s.S and is_smith(s.S)
    assert_unimodular(s.U, n)
    assert_unimodular(s.V, n)
    assert s.S == smith_module.smith_by_elimination(M).S
    assume(answered == [True])  # the generic path answered for the transpose
    assert max(s.V[i, j].degree() for i in range(n) for j in range(n)) <= sum(degrees) - high


@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 10**6), n=st.integers(6, 10))
def test_very_sparse_square_takes_the_elimination(seed, n):
    """δI − A with A of one or two small constants a row (``_very_sparse``): the capped
    elimination answers, without the generic path, with the unique H and U."""
    rng = random.Random(seed)
    rows = [[0] * n for _ in range(n)]
    for i in range(n):
        rows[i][i] = f"d - {rng.randint(-2, 2)}"
        for j in rng.sample([j for j in range(n) if j != i], rng.randint(0, 1)):
            rows[i][j] = rng.choice([-3, -2, -1, 1, 2, 3])
    M = PolyMatrix(rows)
    assert hermite_module._very_sparse(M._r, n) and hermite_module.generic_first(M._r, n)
    with _generic_calls(hermite_module) as calls:
        h = hermite(M)
    assert calls == []
    ref = hermite_by_elimination(M)
    assert (h.H, h.U) == (ref.H, ref.U) and h.U @ M == h.H
    assert_unimodular(h.U, n)


def test_few_high_rows():
    """At most two rows above a third of the greatest degree, and the others a block
    the elimination handles (len³·degree < GENERIC_MIN_WORK)."""
    def rows(*degrees):
        return [[bk.from_coeffs([1] * (d + 1))] for d in degrees]

    assert hermite_module.few_high_rows(rows(0, 1, 4, 16, 32))
    assert hermite_module.few_high_rows(rows(3, 3, 3, 40))
    assert hermite_module.few_high_rows(rows(0, 8, 16, 24))
    assert not hermite_module.few_high_rows(rows(1, 6, 12, 32, 32))  # three above 32/3
    assert not hermite_module.few_high_rows(rows(8, 8, 8, 8, 8))
    assert not hermite_module.few_high_rows(rows(32, 32, 32, 128, 128))  # 27·32 ≥ 375
    assert hermite_module.few_high_rows(rows(13, 13, 13, 128, 128))  # 27·13 < 375
    big = rows(0, 1, 4, 16, 32)
    big[0][0] = bk.from_coeffs([2**80 + 1])
    assert not hermite_module.few_high_rows(big)  # coefficients beyond UNBALANCED_MAX_BITS


@pytest.mark.parametrize("at_zero", [True, False])
def test_small_square_that_swells_and_is_not_generic(monkeypatch, at_zero):
    """Random entries of high degree times diag(1, 1, δ+1, δ+1) (or δ·(δ+1) in the last
    place, so that M(0) is singular): the capped elimination swells, the generic shape fails
    (two non-trivial invariant factors), and the elimination without cap (or, without a
    nonsingular M(0), the Toeplitz path) gives the unique H and U."""
    A = random_matrix(random.Random(8), 4, 4, 8)
    M = A @ PolyMatrix.diag(1, 1, "d + 1", "d + 1" if at_zero else "d**2 + d")
    calls = _spy_generic(monkeypatch)
    h = hermite(M)
    assert calls == [False]
    e = hermite_by_elimination(M)
    assert (h.H, h.U) == (e.H, e.U) and h.U @ M == h.H
    s = smith(M)
    assert calls == [False, False]
    assert s.U @ M @ s.V == s.S and is_smith(s.S)
    assert s.S == smith_module.smith_by_elimination(M).S
    assert_unimodular(s.U, 4)
    assert_unimodular(s.V, 4)


def test_xgcd_step_keeps_divisible_pivots():
    """A constant pivot must not trade places with the other row (the Smith passes
    would alternate for ever)."""
    M = PolyMatrix("[[2, 1/2], [5, -5*d**2/2 + 1]]")
    s = smith(M)
    assert s.verify(M).ok
    assert s.invariant_factors == (P("1"), (M.det()).monic())


# ----------------------------------------------------------------------------
# tall (n+4)×n: hermite, left_inverse, solve_left
# ----------------------------------------------------------------------------
@pytest.mark.parametrize("n", [2, 4, 6])
def test_tall_family(n):
    rng = random.Random(n)
    M = random_matrix(rng, n + 4, n, 2)
    h = hermite(M)
    assert h.U @ M == h.H and is_hermite(h.H) and is_unimodular(h.U)
    K = h.U[h.rank:, :]
    assert K == left_kernel(M) == left_kernel_by_elimination(M)
    if is_left_unimodular(M):
        X = left_inverse(M)
        assert X @ M == PolyMatrix.identity(n)
    W = random_matrix(rng, 2, n + 4, 1) @ M
    Y = solve_left(M, W)
    assert Y @ M == W
    # reduced modulo the kernel: pivot columns of lower degree than the pivots
    for deg, col in (dn.leading_position(row) for row in K._r):
        assert all(Y[i, col].degree() < deg for i in range(2))


def test_rank_deficient_square_smith_transforms():
    rng = random.Random(7)
    M = random_matrix(rng, 6, 4, 1) @ random_matrix(rng, 4, 6, 1)
    s = smith(M)
    assert s.verify(M).ok and s.rank == 4
    assert s.U[4:, :] == left_kernel(M)
    assert s.V[:, 4:].T == left_kernel(M.T)


# ----------------------------------------------------------------------------
# layers: the import graph of uio_ring.ring
# ----------------------------------------------------------------------------
RING = pathlib.Path(__file__).resolve().parents[2] / "uio_ring" / "ring"


def _ring_imports(path: pathlib.Path) -> tuple[set[str], list[str]]:
    """(modules of uio_ring.ring imported at module level, imports found inside functions)."""
    tree = ast.parse(path.read_text())
    top: set[str] = set()
    nested: list[str] = []

    def names(node: ast.ImportFrom) -> set[str]:
        if node.module == "uio_ring.ring":
            return {a.name for a in node.names}
        return {node.module.split(".")[2]} if node.module else set()

    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("uio_ring.ring"):
            top |= names(node)
        if isinstance(node, ast.If):  # `if TYPE_CHECKING:` imports count as edges too
            for sub in ast.walk(node):
                if isinstance(sub, ast.ImportFrom) and sub.module and sub.module.startswith("uio_ring"):
                    top |= names(sub)
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            for sub in ast.walk(node):
                if isinstance(sub, (ast.Import, ast.ImportFrom)):
                    mod = sub.module if isinstance(sub, ast.ImportFrom) else sub.names[0].name
                    if mod and mod.startswith("uio_ring"):
                        nested.append(f"{path.name}: {node.name} imports {mod}")
    return top, nested


def test_ring_import_graph_is_acyclic():
    graph: dict[str, set[str]] = {}
    nested: list[str] = []
    for f in sorted(RING.glob("*.py")):
        if f.stem == "__init__":
            continue
        deps, inner = _ring_imports(f)
        graph[f.stem] = deps - {f.stem, "__init__"}
        nested += inner
    assert nested == []
    state: dict[str, int] = {}

    def visit(u: str, path: list[str]) -> None:
        state[u] = 1
        for v in sorted(graph.get(u, ())):
            assert state.get(v) != 1, f"import cycle: {' -> '.join(path + [u, v])}"
            if v not in state:
                visit(v, path + [u])
        state[u] = 2

    for u in sorted(graph):
        if u not in state:
            visit(u, [])
    for low in ("_predicates", "_echelon", "_dense", "_backend"):
        assert not graph[low] & {"matrix", "hermite", "smith", "inverse", "rank"}


def test_scalar_gcd_helper_is_monic():
    assert bk.gcd(bk.from_coeffs([2, 2]), bk.from_coeffs([0, 4, 4])) == bk.from_coeffs([1, 1])
