"""The integral elimination, the division through the elimination's kernel rows and
the multimodular xgcd: each fast path against the plain one it replaces.

- :mod:`uio_ring.ring._integral`: ``row_echelon_int`` + ``normalise_int`` (fraction free)
  give exactly the rows of the rational ``row_echelon`` + ``normalise`` (the kernel rows
  of U up to a constant factor each);
  ``hermite`` / ``left_inverse`` with the integral path switched off give the same H, U, L.
- :class:`uio_ring.ring._division.PopovDivisor` ``via=(P, G)`` gives the same remainders
  as the division by the Popov basis itself.
- :func:`uio_ring.ring._xgcd.xgcd` gives python-flint's ``xgcd`` triple (forced onto the
  modular path for small degrees), and a wrong candidate is rejected by its check; the
  Graeffe bound that routes it bounds the resultant, and sends the benchmark's binomials
  to the modular path and random polynomials to FLINT's.
"""

from __future__ import annotations

import importlib

import flint
import pytest
from hypothesis import assume, given
from hypothesis import strategies as st

from uio_ring import PolyMatrix, hermite, left_inverse
from uio_ring.ring import _dense as dn
from uio_ring.ring import _division as dv
from uio_ring.ring import _integral as zi
from uio_ring.ring import _xgcd as xg
from uio_ring.ring._echelon import normalise, row_echelon
from uio_ring.ring.errors import NotUnimodularError
from uio_ring.ring.hermite import hermite_by_elimination

from .strategies import assert_unimodular, dense_matrices, heavy, unimodular_matrices

hermite_module = importlib.import_module("uio_ring.ring.hermite")  # the module, not the function


def _tall_unimodular_columns(draw, n: int, extra: int) -> PolyMatrix:
    U = draw(unimodular_matrices(n + extra, max_degree=1))
    return U[:, :n]


@st.composite
def integer_matrices(draw):
    """Integer matrices: independent entries, or columns of a unimodular matrix (whose
    elimination stays integral when the scalings are ±1)."""
    if draw(st.booleans()):
        return draw(dense_matrices(min_rows=1, max_rows=6, min_cols=1, max_cols=5, rational=False))
    n = draw(st.integers(1, 5))
    return _tall_unimodular_columns(draw, n, draw(st.integers(0, 3)))


def _plain(M: PolyMatrix):
    m, n = M.shape
    a, u = dn.copy(M._r), dn.identity(m)
    pivots = row_echelon(a, u, m, n)
    normalise(a, u, pivots)
    return a, u, pivots


def _fraction_free(M: PolyMatrix):
    """The fraction-free elimination and normalisation of M: (H rows, U rows, pivots,
    the integer rows and the packed integer transform after the elimination)."""
    m, n = M.shape
    z, scales = zi.to_integer_rows(M._r)
    uz = zi.identity(m, scales)
    pivots = zi.row_echelon_int(z, uz, m, n)
    zi.normalise_int(z, uz, pivots)
    divisors = zi.pivot_divisors(z, pivots)
    return zi.to_rational_rows(z, divisors), zi.to_rational_rows(uz, divisors), pivots, z, uz


def _proportional(x: list, y: list) -> bool:
    """x = c·y for a nonzero rational constant c."""
    k = next((i for i, e in enumerate(y) if not e.is_zero()), None)
    if k is None:
        return all(e.is_zero() for e in x)
    c = flint.fmpq_poly([x[k].coeffs()[-1] / y[k].coeffs()[-1]])
    return not c.is_zero() and all(e == c * f for e, f in zip(x, y, strict=True))


@given(st.one_of(integer_matrices(), dense_matrices(min_rows=1, max_rows=6, min_cols=1, max_cols=5)))
def test_fraction_free_elimination_equals_rational(M):
    # the same pivots, H and the rows of U above the rank exactly; the kernel rows of U up
    # to a constant factor each (a unit of Q[δ]); the integer rows before the final
    # division: U_Z·M = H_Z exactly, and every row of [H_Z | U_Z] primitive or unscaled
    m, n = M.shape
    h, u, pivots, z, uz = _fraction_free(M)
    a, ref_u, ref_pivots = _plain(M)
    r = len(pivots)
    assert pivots == ref_pivots
    assert h == a
    assert u[:r] == ref_u[:r]
    assert all(_proportional(u[k], ref_u[k]) for k in range(r, m))
    UZ = PolyMatrix._new(zi.to_rational_rows(uz), m, m, M.var)
    assert UZ @ M == PolyMatrix._new(zi.to_rational_rows(z), m, n, M.var)


def test_integer_rows_scale_each_row_by_its_denominators():
    z, scales = zi.to_integer_rows(PolyMatrix([["d/2", "1/3"], [1, "d"]])._r)
    assert scales == [6, 1]
    assert z == [[flint.fmpz_poly([0, 3]), flint.fmpz_poly([2])], [flint.fmpz_poly([1]), flint.fmpz_poly([0, 1])]]
    assert zi.to_integer_rows(PolyMatrix([[1, "d"]])._r)[1] is None


def test_columns_of_a_unimodular_matrix_eliminate_without_scaling():
    # unit pivots throughout: every quotient integral, no row scaled (the transform stays
    # an integer unimodular matrix with determinant ±1)
    M = PolyMatrix([[1, "d"], [0, 1], ["d", "d**2 + 1"], [2, "d - 1"]])
    z, scales = zi.to_integer_rows(M._r)
    uz = zi.identity(4)
    assert scales is None
    assert zi.row_echelon_int(z, uz, 4, 2) == [0, 1]
    U = PolyMatrix._new(zi.to_rational_rows(uz), 4, 4, M.var)
    assert U.det().degree() == 0 and abs(U.det().coeffs()[0]) == 1


def test_elimination_without_scaling_stops_at_the_first_scaled_row():
    # a quotient 1/2 (pivot 2δ + 1 of the first column) scales a row: refused without
    # scaling; the columns of a unimodular matrix need no scaling and pass
    N = PolyMatrix([["2*d + 1", 1], [2, 0], ["3*d", 1]])
    z, _ = zi.to_integer_rows(N._r)
    with pytest.raises(zi.Scaled):
        zi.row_echelon_int(z, zi.identity(3), 3, 2, scaling=False)
    M = PolyMatrix([[1, "d"], [0, 1], ["d", "d**2 + 1"], [2, "d - 1"]])
    z, _ = zi.to_integer_rows(M._r)
    assert zi.row_echelon_int(z, zi.identity(4), 4, 2, scaling=False) == [0, 1]


@given(st.lists(st.integers(-20, 20), min_size=1, max_size=6), st.lists(st.integers(-20, 20), min_size=1, max_size=4))
def test_quotient_clears_the_least_denominator(xs, ys):
    # D·x = Q·y + R with deg R < deg y, Q/D the rational quotient in lowest terms
    x, y = flint.fmpz_poly(xs), flint.fmpz_poly(ys)
    assume(not y.is_zero())
    Q, D, R = zi._quotient(x, y)
    assert D * x == Q * y + R and R.degree() < y.degree()
    qq, _ = divmod(flint.fmpq_poly(x), flint.fmpq_poly(y))
    assert flint.fmpq_poly(Q, D) == qq and qq.denom() == D


def test_quotient_examples():
    d = flint.fmpz_poly([0, 1])
    x, y = 4 * d**2 + 2 * d + 3, 2 * d + 1
    assert zi._quotient(x, y) == (2 * d, 1, flint.fmpz_poly([3]))  # integral quotient
    Q, D, R = zi._quotient(d**2, y)  # quotient δ/2 − 1/4
    assert (Q, D, R) == (2 * d - 1, 4, flint.fmpz_poly([1]))


def test_fraction_free_elimination_with_non_unit_pivots_equals_rational():
    # three rows in the first column (the quotient-and-remainder step) with the pivot
    # 2δ + 1; the normalisation divides by the pivots' leading coefficients at the end
    M = PolyMatrix([["2*d + 1", 0], ["4*d + 2", 1], ["6*d + 3", "d"], ["d", "d**2/3"]])
    h, u, pivots, _, _ = _fraction_free(M)
    a, ref_u, ref_pivots = _plain(M)
    assert (h, u[:2], pivots) == (a, ref_u[:2], ref_pivots)


def test_integral_bit_cap_same_results():
    # wherever the (integral or rational) elimination stops on its growth cap, hermite and
    # left_inverse finish on another path to the same H, U and L
    import random

    M = _seeded_tall_columns(random.Random(5), 6)
    ref = hermite_by_elimination(M)
    ref_inverse = left_inverse(M)
    for bits in (-60, -16, -14, -12, -10, -8, -6, -4, 0):
        for integral in (0, 10**9):
            with pytest.MonkeyPatch.context() as mp:
                mp.setattr(hermite_module, "ELIMINATION_BITS", bits)
                mp.setattr(hermite_module, "CAP_MIN_ENTRIES", 0)
                mp.setattr(hermite_module, "INTEGRAL_MIN_ENTRIES", integral)
                h = hermite(M)
                X = left_inverse(M)
            assert (h.H, h.U) == (ref.H, ref.U), (bits, integral)
            assert X == ref_inverse


@heavy()
@given(st.data())
def test_hermite_and_left_inverse_same_without_integral_path(data):
    n = data.draw(st.integers(1, 5))
    M = _tall_unimodular_columns(data.draw, n, data.draw(st.integers(1, 3)))
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hermite_module, "INTEGRAL_MIN_ENTRIES", 0)
        h, L = hermite(M), left_inverse(M)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hermite_module, "INTEGRAL_MIN_ENTRIES", 10**9)
        h0 = hermite(M)
        L0 = left_inverse(M)
    assert (h.H, h.U, h.rank, h.pivots) == (h0.H, h0.U, h0.rank, h0.pivots)
    assert L == L0
    assert h.U @ M == h.H
    assert L @ M == PolyMatrix.identity(n)
    assert_unimodular(h.U)


@heavy()
@given(dense_matrices(min_rows=2, max_rows=6, min_cols=1, max_cols=4, rational=False))
def test_hermite_by_elimination_same_without_integral_path(M):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hermite_module, "INTEGRAL_MIN_ENTRIES", 0)
        h = hermite(M)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hermite_module, "INTEGRAL_MIN_ENTRIES", 10**9)
        h0 = hermite(M)
    assert (h.H, h.U) == (h0.H, h0.U)
    assert h.U @ M == h.H


def test_integral_path_on_the_benchmark_tall_shape():
    # 12×10 columns of a unimodular matrix (above INTEGRAL_MIN_ENTRIES): the integral path
    # runs, and agrees with the rational one
    import random

    n = 10
    M = _seeded_tall_columns(random.Random(3), n)
    h_rows, u_rows, _, _, _ = _fraction_free(M)
    a, u, _ = _plain(M)
    assert h_rows == a and u_rows[:n] == u[:n]
    h = hermite(M)
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(hermite_module, "INTEGRAL_MIN_ENTRIES", 10**9)
        h0 = hermite(M)
    assert (h.H, h.U) == (h0.H, h0.U)
    assert h.H[:n, :] == PolyMatrix.identity(n)
    assert left_inverse(M) == h.U[:n, :]


def test_left_inverse_errors_unchanged():
    with pytest.raises(NotUnimodularError):
        left_inverse(PolyMatrix([["d", 0], [0, "d"], ["d", "d"]]))


# ----------------------------------------------------------------------------
# division through another basis of the module
# ----------------------------------------------------------------------------
@given(st.data())
def test_division_via_generators_same_remainder(data):
    n = data.draw(st.integers(1, 4))
    M = _tall_unimodular_columns(data.draw, n, data.draw(st.integers(1, 3)))
    m = M.rows
    a, u, pivots = _plain(M)
    r = len(pivots)
    gens = dn.copy(u[r:])
    kern, p = dn.copy(gens), dn.identity(m - r)
    dn.weak_popov(kern, p)
    dn.popov(kern, p)
    assert dn.matmul(p, gens, m - r, m - r, m) == kern
    x = data.draw(dense_matrices(rows=2, cols=m, max_degree=6))._r + u[:r]
    assert dv.reduce_modulo_popov(x, kern, (p, gens)) == dv.reduce_modulo_popov(x, kern)


def test_division_via_a_wrong_basis_changes_the_result():
    # deliberate breakage: a `via` that is not P·G = basis gives another remainder, so the
    # equality above is not vacuous
    d = flint.fmpq_poly([0, 1])
    one = flint.fmpq_poly([1])
    basis = [[d, one]]
    x = [[d**3 + 1, d]]
    good = dv.reduce_modulo_popov(x, basis, ([[one]], basis))
    bad = dv.reduce_modulo_popov(x, basis, ([[one]], [[d, one + one]]))
    assert good == dv.reduce_modulo_popov(x, basis)
    assert bad != good


# ----------------------------------------------------------------------------
# xgcd
# ----------------------------------------------------------------------------
rat_polys = st.lists(
    st.fractions(min_value=-5, max_value=5, max_denominator=6), min_size=1, max_size=14
).map(lambda cs: flint.fmpq_poly([flint.fmpq(c.numerator, c.denominator) for c in cs]))


@given(rat_polys, rat_polys, rat_polys)
def test_xgcd_modular_equals_flint(a, b, h):
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(xg, "MIN_DEGREE", 1)
        mp.setattr(xg, "_bound_overestimates", lambda a, b: True)
        got = xg.xgcd(a * h, b * h)
    assert got == (a * h).xgcd(b * h)


int_polys = st.lists(st.integers(-50, 50), min_size=2, max_size=16).map(flint.fmpz_poly).filter(
    lambda c: c.degree() >= 1)


@given(int_polys, int_polys, st.integers(0, 3))
def test_graeffe_bound_bounds_the_resultant(a, b, steps):
    # 2^(steps+1)·log2|res| ≤ bound, with log2|res| ≥ bits − 1
    res = abs(int(a.resultant(b)))
    assume(res != 0)
    assert (res.bit_length() - 1) << (steps + 1) <= xg._resultant_bound(a, b, steps)
    assert xg._resultant_bound(a, b, steps) <= xg._resultant_bound(a, b, 0) << steps


def test_xgcd_routes_by_the_graeffe_bound():
    # the benchmark's binomials (cofactors far below the norm bound) take the modular
    # path; random coefficients FLINT's, which is faster there; the same triple either way
    import random

    rng = random.Random(3)
    x = flint.fmpq_poly([0, 1])
    rand = [flint.fmpq_poly([rng.randint(-3, 3) for _ in range(64)]) + x**64 for _ in range(2)]
    calls = []
    real = xg._xgcd_modular
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(xg, "_xgcd_modular", lambda a, b: calls.append(a) or real(a, b))
        for a, b in (((1 + x) ** 64, x**64 - 1), (rand[0], rand[1])):
            assert xg.xgcd(a, b) == a.xgcd(b)
    assert calls == [(1 + x) ** 64]


def test_xgcd_benchmark_polynomials():
    x = flint.fmpq_poly([0, 1])
    for k in (48, 64, 100):
        a, b = (1 + x) ** k, x**k - 1
        assert xg._xgcd_modular(a, b) == a.xgcd(b)
        c, d = (x - 1) ** k, x ** (k - 1) + 1
        assert xg.xgcd(c, d) == c.xgcd(d)


@given(st.integers(0, 3000), st.integers(0, 3000), st.integers(1, 10**6))
def test_xgcd_of_numerators_with_large_contents(ka, kb, seed):
    # rational polynomials whose integer numerators carry thousands of bits of content
    # (what elimination over Q leaves): the same triple as FLINT's, from the primitive
    # parts — few primes, where the contents would inflate the bound to thousands
    import random

    rng = random.Random(seed)
    x = flint.fmpq_poly([0, 1])
    a = flint.fmpq_poly([rng.randint(-9, 9) for _ in range(50)]) + x**50
    b = flint.fmpq_poly([rng.randint(-9, 9) for _ in range(49)]) + 3 * x**49
    a, b = a * flint.fmpq(3**ka, 7), b * flint.fmpq(5**kb, 2**kb + 1)
    used = []
    real = xg._prime
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(xg, "_prime", lambda i: used.append(i) or real(i))
        got = xg._xgcd_modular(a, b)
    assert got == a.xgcd(b)
    assert len(used) < 100


def test_xgcd_rejects_a_wrong_candidate():
    # deliberate breakage: candidates off by one are refused by the exact check (the
    # result then comes from more primes or from FLINT, and is still right)
    x = flint.fmpq_poly([0, 1])
    a, b = (1 + x) ** 60, x**60 - 1
    real = xg._candidate
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(xg, "_candidate", lambda *args: real(*args) + 1)
        assert xg._xgcd_modular(a, b) is None
        assert xg.xgcd(a, b) == a.xgcd(b)


def test_highdeg_hermite_identities():
    M = PolyMatrix([["(1 + d)**64", "d**63 + 1"], ["d**64 - 1", "(d - 1)**64"]])
    h = hermite(M)
    assert h.U @ M == h.H
    ref = hermite_by_elimination(M)
    assert (h.H, h.U) == (ref.H, ref.U)
    assert_unimodular(h.U)


@given(st.data())
def test_packed_rows_follow_the_entrywise_operations(data):
    # a small stride forces repacking: every operation is compared with the same
    # operation on the unpacked rows
    m = data.draw(st.integers(1, 4))
    packed = zi.Packed(m, S=1)
    plain = [[flint.fmpz_poly([1]) if i == j else flint.fmpz_poly() for j in range(m)] for i in range(m)]
    small = st.lists(st.integers(-3, 3), min_size=0, max_size=4).map(flint.fmpz_poly)
    for _ in range(data.draw(st.integers(0, 8))):
        op = data.draw(st.sampled_from(["axpy", "swap", "scale", "combine"]))
        i = data.draw(st.integers(0, m - 1))
        j = data.draw(st.integers(0, m - 1))
        if op == "axpy" and i != j:
            q = data.draw(small)
            packed.axpy(i, q, j)
            plain[i] = [t - q * s for t, s in zip(plain[i], plain[j], strict=True)]
        elif op == "swap":
            packed.swap(i, j)
            plain[i], plain[j] = plain[j], plain[i]
        elif op == "scale" and i != j:
            q, c = data.draw(small), data.draw(st.integers(-3, 3).filter(bool))
            packed.axpy(i, q, j, flint.fmpz(c))
            plain[i] = [c * t - q * s for t, s in zip(plain[i], plain[j], strict=True)]
            g = packed.content(i)
            if g > 1:
                packed.divide(i, g)
                plain[i] = [t // g for t in plain[i]]
        elif op == "combine" and i != j:
            s, t, xg, yg = (data.draw(small) for _ in range(4))
            packed.combine(i, j, s, t, xg, yg)
            rp, ri = plain[i], plain[j]
            plain[i] = [s * e + t * f for e, f in zip(rp, ri, strict=True)]
            plain[j] = [xg * f - yg * e for e, f in zip(rp, ri, strict=True)]
        assert packed.entries() == plain
        assert zi.to_rational_rows(packed) == [[flint.fmpq_poly(e) for e in row] for row in plain]
        for k in range(m):
            assert packed.row_bits(k) == max((int(e.height_bits()) + 1 for e in plain[k] if not e.is_zero()), default=0)


def _seeded_tall_columns(rng, n: int) -> PolyMatrix:
    """The first n columns of L·U, with L unit lower and U unit upper triangular
    (n + 2)×(n + 2) with entries of degree ≤ 1: a left-unimodular (n + 2)×n matrix."""
    def entry(below: bool, i: int, j: int):
        return 1 if i == j else (f"{rng.randint(-2, 2)}*d + {rng.randint(-2, 2)}" if (j < i) == below and i != j else 0)

    L = PolyMatrix([[entry(True, i, j) for j in range(n + 2)] for i in range(n + 2)])
    U = PolyMatrix([[entry(False, i, j) for j in range(n + 2)] for i in range(n + 2)])
    return (L @ U)[:, :n]
