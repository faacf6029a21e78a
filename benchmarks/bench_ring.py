#!/usr/bin/env python
"""Benchmark of the exact ring layer (uio_ring.ring) against sympy and SageMath.

One run prints one table: per (case, operation) our CPU time, sympy's and
SageMath's and the ratios, then the output sizes of ours and Sage's results, then
the import cost of ``uio_ring`` against ``sympy``.

Every (library, matrix) pair runs in its own worker process, so that a case
that exceeds the per-operation time budget is killed and reported as
``timeout`` instead of hanging the run; once an operation times out at some
size, larger sizes of the same family are reported ``skipped (> budget)``.
Times are the best CPU time (``time.process_time``) of up to ``--repeats`` runs
(repeats stop after ~1 s): on a loaded machine wall time would measure the load.

Output size (``deg/bits/total`` columns, for each output matrix: H, U, V, K, L, X)
    max degree of the entries / max bit length of the integers of the primitive
    integer form of each row (the row times the lcm of its denominators, divided by
    the gcd of the resulting integers; so a row scaled by a constant has the same
    size) / the sum of all those bit lengths in kbit.  ``ours larger`` names the
    matrices where ours exceeds Sage's in any of the three.
    Expected entries there:

    * ``U:bits+total`` / ``L:bits+total`` on the tall family: ``hermite``'s U (and
      ``left_inverse``) is reduced modulo the Popov basis of the left kernel — the
      representative of least degree, whatever algorithm computes it — while Sage
      returns its elimination transform unreduced: half the degree for more bits
      (tall 22×20: ours 14/161/383k, Sage 29/44/117k).  Both at once is not to be
      had: when deg L is below every minimal index (the kernel's row degrees), any
      other left inverse L + Y·K has a larger degree (predictable degree property of
      the row-reduced K), so L is the only left inverse of its degree — at 6×4, ours
      is the only one of degree 1 (9 bits) and Sage's has degree 5 (5 bits).  We keep
      least degree: in a delay observer the degree of a transform is the length of
      history it needs (its delay taps), the bits only its exact text.
    * Smith transforms are not unique: the two libraries split the work between U
      and V differently (ours, square nonsingular: U = the Hermite transform, V small;
      Sage: the reverse), so one of ours may exceed Sage's (``U:bits`` by a few bits, or
      ``U:deg``) while the pair is smaller (random 8×8: U + V 226 kbit against Sage's
      539 kbit; smith 12×12, ``--max-n 16``: 132 against 11 525 kbit).  On the rowdeg
      family ours goes through the transpose (``transposed_route``: the large transform
      is V there), and its small U, ``[[I, 0], [−l, 1]]`` up to a row order, can have a
      degree or two more than Sage's (``U:deg``; 3, 3, 3, 40: U 48/74/11k and V
      9/77/11k against Sage's 46/305/46k and 61/343/66k).  Rectangular and singular
      matrices go through Hermite forms and their unit pivots; there both of ours are
      smaller on every measure (rankdef 12×12: U 8/401/367k and V 5/358/74k against
      Sage's 100/3390/4152k and 89/3366/6303k).

    * ``K:bits+total`` on the tall family at some sizes: ours is the Popov basis of the
      left kernel (unique: monic pivots, other entries reduced below them), Sage's
      ``minimal_kernel_basis()`` an ordered weak Popov basis, unreduced; the same
      degrees.  Sage's own Popov basis (``normal_form=True``) has exactly our sizes
      (10×8: 4/28/1.8k against its weak Popov 4/21/1.5k; 14×12: 6/55/6.1k against
      6/52/6.0k; 18×16: 8/66/10.9k, where the weak Popov one is larger, 8/84/13.4k).
      The same on the narrow 4×2 of degree 16: ``K:bits`` 168 against 167, and Sage's
      Popov basis has 168 bits (its total, 21 425 bits, is below its weak Popov one's).

    Expected below 1× (time, not size): ``hermite`` and ``left_inverse`` on the column
    family, 0.2–0.9× (3×1 and 6×1 of degree 16: 0.5–0.8 ms against 0.3–0.5 ms; of
    degree 64: 8.5–9.1 ms against 1.4–2.8 ms; by instruction count,
    ``count_instructions.py``, 0.24–0.32×).  SageMath's
    ``hermite_form`` of a column is m − 1 extended gcds, its U left as they build it: its
    kernel rows are not a minimal basis (6×1 of degree 16: U of degree 31, the minimal
    indices are 3 and 4; degree 64: 127 against 13), and its left inverse is not reduced
    modulo one (degree 63 against 12).  Ours is the normalised U — the Popov basis of the
    kernel and X reduced modulo it, unique — which is a block-Toeplitz solve (97×97 for a
    3×1 of degree 64) and costs more than those gcds.  A structured alternative for 3×1
    columns was built and measured (half an extended gcd modulo word primes, Chinese
    remaindering, the same exact certificate): slower than that solve in C, 0.46–0.64
    against 0.36–0.49 ms at degree 16 and 8.6–9.1 against 6.3–6.4 ms at degree 64 (11
    primes; Wang's reconstruction of 700-bit residues in Python, about 0.25 ms each).  The
    kernel itself is 2.2–11× faster than SageMath's ``minimal_kernel_basis`` on the same
    columns.  Even SageMath's own algorithm would lose here through python-flint: the
    one nontrivial extended gcd of the 3×1 of degree 64 takes 1.3 ms in python-flint
    0.8's FLINT 3.3.1, 0.8 ms in SageMath's FLINT 3.6, whose whole ``hermite_form``
    takes 1.2 ms.  Sub-millisecond cells of one pass (highdeg 32 ``hermite``, highdeg
    ``det`` from k = 64, sparse 8 ``hermite``, narrow 2×4 ``hermite``) can show
    0.6–0.9×: ``bench_small_cells.py``, which interleaves the libraries, puts them at
    1.0–1.4×.

    Both libraries' results are verified
    after timing (U·M = H, U·M·V = S with U, V unimodular, K·M = 0 with
    rows − rank rows, L·M = I, X·M = W), and H, S (rows made monic), det, rank
    and the row degrees of the kernel bases (the minimal indices) are compared
    between the libraries; any failure is a WARNING and exit 1.

SageMath (optional, never a test dependency)
    The passagemath wheels give what is used here (``PolynomialRing(QQ, 'd')``,
    ``hermite_form``, ``smith_form``, ``minimal_kernel_basis``, ``popov_form``)
    with two distributions; keep them out of the project's environment::

        python -m venv /path/to/sagevenv
        /path/to/sagevenv/bin/pip install passagemath-flint passagemath-modules

    (about 225 MB of wheels for CPython 3.11 on x86-64 Linux, 0.9 GB installed, under a
    minute).  Then ``--sage-python /path/to/sagevenv/bin/python`` (or the
    environment variable ``UIO_SAGE_PYTHON``) runs Sage's workers in that
    interpreter (the job goes as JSON on stdin, results come back one JSON line
    each); without it Sage is imported lazily in this interpreter when present.

What is compared
    hermite          ours: hermite(M) (H and U);  sage: M.hermite_form(transformation=True)
    smith            ours: smith(M) (S, U, V);     sympy: smith_normal_decomp(M, domain=QQ[d]);
                     sage: M.smith_form()
    invariant_factors ours: invariant_factors(M);  sympy: invariant_factors(M, domain=QQ[d]);
                     sage: M.elementary_divisors()
    rank, det        sympy: DomainMatrix over QQ(d) / QQ[d] (sympy's fastest path);
                     sage: M.rank(), M.det()
    is_unimodular    sympy/sage: det is a nonzero constant
    left_kernel      ours: left_kernel(M) (Popov basis);  sage: M.minimal_kernel_basis()
                     (a weak Popov basis, Sage's default)
    left_inverse     ours: left_inverse(M);  sage: the first n rows of U from
                     M.hermite_form(transformation=True) = [I; 0] (Sage has no polynomial
                     left inverse of its own)
    solve_left       ours only (sage's solve_left answers over the fraction field)

Cases (seeded, identical for every library)
    random     n×n, entries of degree 2 with integer coefficients in [−3, 3]
    smith      P·diag(1, …, 1, δ+1, (δ+1)(δ−2))·Q, P and Q random unimodular
    tall       (n+2)×n left-unimodular: first n columns of a random unimodular matrix
    tall4      (n+4)×n, entries of degree 2 (coefficients in [−3, 3]); the left kernel
               has 4 rows of degree ≈ n/2 (n = 8 … 24)
    rankdef    n×n of rank n − 2: A·B with A n×(n−2), B (n−2)×n of degree 1
    highdeg    2×2 [[(1+δ)^k, δ^(k−1)+1], [δ^k − 1, (δ−1)^k]] (k = 16 … 256; the "n" column is k)
    highdeg4   4×4, entries of degree k with integer coefficients in [−3, 3] (k = 8 … 64; the
               "n" column is k): small and square, where Euclidean elimination swells
    sparse     n×n, each entry nonzero with probability 0.3 (degree 8, coefficients in
               [−3, 3]), one row zero (n = 8, 10, 12): rank-deficient and sparse
    triangular the rows of an upper triangular n×n in random order: diagonal δ, δ + 1, δ, …,
               entries above of degree 2 (coefficients in [−3, 3]); n = 8, 16, 24 — a
               cascade of subsystems, δI − A for a triangular A
    narrow     4×2 and 2×4, entries of degree k (k = 16, 32; the "n" column is k): few
               rows or columns of high degree
    column     3×1 and 6×1, entries of degree k (k = 16, 64; the "n" column is k): the input
               matrix B of a single-input system, the output row of a single-output one
    rowdeg     square, row i of degree d_i (coefficients in [−3, 3]; the "n" column is the
               greatest d_i): 0, 1, 4, 16, 32; 0, 8, 16, 24; 3, 3, 3, 40; 2, 2, 2, 2, 2, 30
               (channels of very different delays), and 1, 6, 12, 32, 32 with three rows of
               high degree
    paper001   M = [[C B, D], [D, 0]] of Zheng et al. §5 (6×4)

After the table: the fitted growth exponents of left_kernel, left_inverse, hermite and
solve_left on tall4 (least squares of log time against log n), for every library.

Usage::

    python benchmarks/bench_ring.py                 # every family, full sizes
    python benchmarks/bench_ring.py --max-n 12
    python benchmarks/bench_ring.py --families highdeg,tall4
    python benchmarks/bench_ring.py --sage          # fail if SageMath is not importable
    python benchmarks/bench_ring.py --sage-python /path/to/sagevenv/bin/python --no-sympy
    python benchmarks/bench_ring.py --quick         # tiny sizes: a smoke test
    PYTHONPATH=. python benchmarks/bench_ring.py    # this checkout rather than the installed one

Timings are never asserted anywhere; tests/test_benchmarks_smoke.py only checks
that ``--quick`` exits 0.
"""

from __future__ import annotations

import argparse
import hashlib
import importlib.util
import json
import math
import multiprocessing as mp
import os
import queue
import random
import subprocess
import sys
import threading
import time
from fractions import Fraction
from typing import Any

SIZES = [4, 8, 12, 16, 20]
QUICK_SIZES = [2, 3]
TALL4_SIZES = [8, 12, 16, 20, 24]
RANKDEF_SIZES = [4, 8, 12, 16]
HIGHDEG_KS = [16, 32, 64, 128, 256]
HIGHDEG4_KS = [8, 16, 32, 64]
QUICK_KS = [4, 8]
SPARSE_SIZES = [8, 10, 12]
TRIANGULAR_SIZES = [8, 16, 24]
NARROW_KS = [16, 32]
COLUMN_KS = [16, 64]
ROW_DEGREES = [[0, 1, 4, 16, 32], [0, 8, 16, 24], [3, 3, 3, 40], [2, 2, 2, 2, 2, 30], [1, 6, 12, 32, 32]]
FAMILIES = ["random", "smith", "tall", "tall4", "rankdef", "highdeg", "highdeg4", "sparse", "triangular",
            "narrow", "column", "rowdeg", "paper001"]

Coeffs = list[int]  # low to high
Data = list[list[Coeffs]]  # matrix of coefficient lists


# ----------------------------------------------------------------------------
# plain-Python polynomial matrices (so that every library gets the same data)
# ----------------------------------------------------------------------------
def _trim(p: Coeffs) -> Coeffs:
    p = list(p)
    while p and p[-1] == 0:
        p.pop()
    return p


def _padd(a: Coeffs, b: Coeffs) -> Coeffs:
    n = max(len(a), len(b))
    return _trim([(a[i] if i < len(a) else 0) + (b[i] if i < len(b) else 0) for i in range(n)])


def _pmul(a: Coeffs, b: Coeffs) -> Coeffs:
    if not a or not b:
        return []
    out = [0] * (len(a) + len(b) - 1)
    for i, x in enumerate(a):
        if x:
            for j, y in enumerate(b):
                out[i + j] += x * y
    return _trim(out)


def _matmul(A: Data, B: Data) -> Data:
    n, k, m = len(A), len(B), len(B[0]) if B else 0
    out = []
    for i in range(n):
        row = []
        for j in range(m):
            acc: Coeffs = []
            for t in range(k):
                acc = _padd(acc, _pmul(A[i][t], B[t][j]))
            row.append(acc)
        out.append(row)
    return out


def _random_matrix(rng: random.Random, n: int, m: int, degree: int, lo: int = -3, hi: int = 3) -> Data:
    return [[_trim([rng.randint(lo, hi) for _ in range(degree + 1)]) for _ in range(m)] for _ in range(n)]


def _rows_of_degrees(rng: random.Random, degrees: list[int]) -> Data:
    """Square; row i has entries of degree degrees[i] (nonzero leading coefficients)."""
    return [[[rng.randint(-3, 3) for _ in range(d)] + [rng.choice([-3, -2, -1, 1, 2, 3])] for _ in degrees]
            for d in degrees]


def _random_unimodular(rng: random.Random, n: int) -> Data:
    """L·U with L unit lower, U unit upper triangular, off-diagonal entries of degree <= 1."""
    L = [[[1] if i == j else (_trim([rng.randint(-2, 2), rng.randint(-2, 2)]) if j < i else [])
          for j in range(n)] for i in range(n)]
    U = [[[1] if i == j else (_trim([rng.randint(-2, 2), rng.randint(-2, 2)]) if j > i else [])
          for j in range(n)] for i in range(n)]
    return _matmul(L, U)


def _diag(entries: list[Coeffs], n: int) -> Data:
    return [[entries[i] if i == j else [] for j in range(n)] for i in range(n)]


def paper_001_matrix() -> Data:
    """M = [[C B, D], [D, 0]] from A, B, C, D of Zheng et al. §5 (A is not needed)."""
    d = [0, 1]
    B = [[[], []], [[], []], [[1], [1]], [[], d]]
    C = [[d, [], [], []], [[], [1], [], []], [[], [], [1], [1]]]
    D = [[[1], d], [[], []], [[1], d]]
    CB = _matmul(C, B)
    top = [CB[i] + D[i] for i in range(3)]
    bottom = [D[i] + [[], []] for i in range(3)]
    return top + bottom


def _binom_poly(k: int, sign: int) -> Coeffs:
    """(δ + sign)^k, low to high."""
    out = [1]
    for _ in range(k):
        out = _pmul(out, [sign, 1])
    return out


def high_degree_matrix(k: int) -> Data:
    """[[(1+δ)^k, δ^(k−1)+1], [δ^k − 1, (δ−1)^k]] (issue 15)."""
    return [
        [_binom_poly(k, 1), _padd([1], [0] * (k - 1) + [1])],
        [_padd([-1], [0] * k + [1]), _binom_poly(k, -1)],
    ]


def build_cases(sizes: list[int], seed: int, *, quick: bool = False, max_n: int = 10**9,
                families: list[str] | None = None) -> list[dict[str, Any]]:
    cases = _build_all(sizes, seed, quick=quick, max_n=max_n)
    return [c for c in cases if families is None or c["family"] in families]


def _build_all(sizes: list[int], seed: int, *, quick: bool, max_n: int) -> list[dict[str, Any]]:
    rng = random.Random(seed)
    cases: list[dict[str, Any]] = []
    square_ops = ["hermite", "smith", "invariant_factors", "rank", "det", "is_unimodular", "solve_left"]
    for n in sizes:
        M = _random_matrix(rng, n, n, 2)
        X0 = _random_matrix(rng, 2, n, 1)
        cases.append(dict(family="random", n=n, shape=(n, n), M=M, W=_matmul(X0, M), ops=square_ops))
    for n in sizes:
        k = min(2, n - 1)
        tail = [[1, 1], [-2, -1, 1]][2 - k:] if k > 0 else []  # δ+1, (δ+1)(δ−2)
        S = _diag([[1]] * (n - k) + tail, n)
        M = _matmul(_matmul(_random_unimodular(rng, n), S), _random_unimodular(rng, n))
        cases.append(dict(family="smith", n=n, shape=(n, n), M=M, W=None,
                          ops=["hermite", "smith", "invariant_factors", "rank", "det", "is_unimodular"]))
    for n in sizes:
        Uf = _random_unimodular(rng, n + 2)
        M = [row[:n] for row in Uf]
        cases.append(dict(family="tall", n=n, shape=(n + 2, n), M=M, W=None,
                          ops=["left_inverse", "left_kernel", "hermite", "is_unimodular_left"]))
    rng4 = random.Random(seed + 4)  # own streams: adding a family never changes the others
    for n in (QUICK_SIZES if quick else [n for n in TALL4_SIZES if n <= max_n]):
        M = _random_matrix(rng4, n + 4, n, 2)
        X0 = _random_matrix(rng4, 2, n + 4, 1)
        cases.append(dict(family="tall4", n=n, shape=(n + 4, n), M=M, W=_matmul(X0, M),
                          ops=["left_kernel", "hermite", "left_inverse", "solve_left"]))
    rng5 = random.Random(seed + 5)
    for n in (QUICK_SIZES[-1:] if quick else [n for n in RANKDEF_SIZES if n <= max_n]):
        M = _matmul(_random_matrix(rng5, n, n - 2, 1), _random_matrix(rng5, n - 2, n, 1))
        cases.append(dict(family="rankdef", n=n, shape=(n, n), M=M, W=None,
                          ops=["hermite", "smith", "invariant_factors", "rank", "left_kernel"]))
    for k in (QUICK_KS if quick else HIGHDEG_KS):
        cases.append(dict(family="highdeg", n=k, shape=(2, 2), M=high_degree_matrix(k), W=None,
                          ops=["hermite", "smith", "invariant_factors", "det"]))
    rng6 = random.Random(seed + 6)
    for k in (QUICK_KS if quick else HIGHDEG4_KS):
        cases.append(dict(family="highdeg4", n=k, shape=(4, 4), M=_random_matrix(rng6, 4, 4, k), W=None,
                          ops=["hermite", "smith", "invariant_factors", "det"]))
    rng7 = random.Random(seed + 7)
    for n in (QUICK_SIZES[-1:] if quick else [n for n in SPARSE_SIZES if n <= max_n]):
        M = [[_trim([rng7.randint(-3, 3) for _ in range(9)]) if rng7.random() < 0.3 else [] for _ in range(n)]
             for _ in range(n)]
        M[rng7.randrange(n)] = [[] for _ in range(n)]
        cases.append(dict(family="sparse", n=n, shape=(n, n), M=M, W=None,
                          ops=["hermite", "smith", "invariant_factors", "rank", "left_kernel"]))
    rng8 = random.Random(seed + 8)
    for n in (QUICK_SIZES[-1:] if quick else [n for n in TRIANGULAR_SIZES if n <= max_n]):
        T = _random_matrix(rng8, n, n, 2)
        for i in range(n):
            T[i][:i] = [[] for _ in range(i)]
            T[i][i] = [1, 1] if i % 2 else [0, 1]
        rng8.shuffle(T)
        cases.append(dict(family="triangular", n=n, shape=(n, n), M=T, W=None,
                          ops=["hermite", "smith", "invariant_factors", "rank", "det"]))
    rng9 = random.Random(seed + 9)
    for k in (QUICK_KS[:1] if quick else NARROW_KS):
        for shape in ((4, 2), (2, 4)):
            cases.append(dict(family="narrow", n=k, shape=shape, M=_random_matrix(rng9, *shape, k), W=None,
                              ops=["hermite", "smith", "invariant_factors", "left_kernel"]))
    rng10 = random.Random(seed + 10)
    for k in (QUICK_KS[:1] if quick else COLUMN_KS):
        for m in (3, 6):
            cases.append(dict(family="column", n=k, shape=(m, 1), M=_random_matrix(rng10, m, 1, k), W=None,
                              ops=["hermite", "left_inverse", "left_kernel"]))
    rng11 = random.Random(seed + 11)
    for degrees in (ROW_DEGREES[:2] if quick else ROW_DEGREES):
        M = _rows_of_degrees(rng11, degrees)
        cases.append(dict(family="rowdeg", n=max(degrees), shape=(len(M), len(M)), M=M, W=None,
                          ops=["hermite", "smith", "invariant_factors", "det"]))
    M = paper_001_matrix()
    cases.append(dict(family="paper001", n=6, shape=(6, 4), M=M, W=[M[0], M[2]],
                      ops=["hermite", "smith", "invariant_factors", "rank", "left_kernel", "solve_left"]))
    return cases


# ----------------------------------------------------------------------------
# workers: one per (library, case); they stream (op, seconds | error) back
# ----------------------------------------------------------------------------
def _poly_text(c: Coeffs) -> str:
    return " + ".join(f"({x})*d**{k}" for k, x in enumerate(c) if x) or "0"


def _setup_ours(case):
    from uio_ring import (
        Poly,
        PolyMatrix,
        hermite,
        invariant_factors,
        is_left_unimodular,
        is_unimodular,
        left_inverse,
        left_kernel,
        smith,
        solve_left,
    )

    M = PolyMatrix.from_coefficients(_coefficient_matrices(case["M"], *case["shape"]))
    W = None
    if case["W"] is not None:
        W = PolyMatrix.from_coefficients(_coefficient_matrices(case["W"], len(case["W"]), case["shape"][1]))

    def monic_factors():
        return [[str(c) for c in f.monic().coeffs()] for f in invariant_factors(M)]

    ops = {
        "hermite": lambda: hermite(M),
        "smith": lambda: smith(M),
        "invariant_factors": lambda: invariant_factors(M),
        "rank": lambda: M.rank(),
        "det": lambda: M.det(),
        "is_unimodular": lambda: is_unimodular(M),
        "is_unimodular_left": lambda: is_left_unimodular(M),
        "left_inverse": lambda: left_inverse(M),
        "left_kernel": lambda: left_kernel(M),
        "solve_left": lambda: solve_left(M, W),
    }

    def entries(A) -> Entries:
        return [[[(c.numerator, c.denominator) for c in A[i, j].coeffs()] for j in range(A.cols)]
                for i in range(A.rows)]

    def unimodular(T, *transforms) -> bool:
        """With ``U·M(·V) = T`` already checked: the transforms are unimodular.  For a
        square nonsingular M, ``det T = c·det M`` with c a nonzero constant proves it
        (det U·det V = c); otherwise their determinants are computed."""
        if M.rows == M.cols:
            dM = M.det()
            if not dM.is_zero():
                dT = Poly.from_coeffs([1])
                for i in range(T.rows):
                    dT = dT * T[i, i]
                return dT.degree() == dM.degree() and dT * dM.lc() == dM * dT.lc()
        return all(constant_det(X) for X in transforms)

    def constant_det(X) -> bool:
        """det X (degree ≤ D = sum of row degrees) is one nonzero constant at D + 1 points."""
        import flint

        D = sum(max(X[i, :].degree(), 0) for i in range(X.rows))
        dets = set()
        for x in range(D + 1):
            A = X.eval(x).coefficient_lists()[0]
            dets.add(flint.fmpq_mat(X.rows, X.cols, [flint.fmpq(f.numerator, f.denominator)
                                                     for row in A for f in row]).det())
            if len(dets) > 1:
                return False
        return dets != {0}

    def describe(op: str, out: Any) -> dict[str, Any]:
        if op == "hermite":
            return _report(lambda: out.U @ M == out.H and unimodular(out.H, out.U),
                           {"H": entries(out.H), "U": entries(out.U)}, _digest(entries(out.H)))
        if op == "smith":
            return _report(lambda: out.U @ M @ out.V == out.S and unimodular(out.S, out.U, out.V),
                           {"U": entries(out.U), "V": entries(out.V)}, _digest(entries(out.S)))
        if op == "left_kernel":
            K = entries(out)
            return _report(lambda: (out @ M).is_zero() and out.rows == M.rows - M.rank(),
                           {"K": K}, _row_degrees(K))
        if op == "left_inverse":
            return _report(lambda: out @ M == PolyMatrix.identity(M.cols), {"L": entries(out)}, None)
        if op == "solve_left":
            return _report(lambda: out @ M == W, {"X": entries(out)}, None)
        if op == "det":
            return _report(None, {}, _digest([[[(c.numerator, c.denominator) for c in out.coeffs()]]]))
        if op == "rank":
            return _report(None, {}, out)
        return {}

    return ops, monic_factors, describe


def _coefficient_matrices(data: Data, n: int, m: int) -> list[list[list[int]]]:
    deg = max((len(c) for row in data for c in row), default=0)
    return [[[c[k] if k < len(c) else 0 for c in row] for row in data] for k in range(max(deg, 1))]


def _setup_sympy(case):
    import sympy as sp
    from sympy.matrices.normalforms import invariant_factors, smith_normal_decomp
    from sympy.polys.matrices import DomainMatrix

    d = sp.Symbol("d")
    R = sp.QQ[d]
    n, m = case["shape"]
    M = sp.Matrix(n, m, lambda i, j: sum((x * d**k for k, x in enumerate(case["M"][i][j])), sp.Integer(0)))

    def det():
        return DomainMatrix.from_Matrix(M).convert_to(R).det()

    def is_unimodular():
        v = R.to_sympy(det())
        return v != 0 and sp.Poly(v, d).degree() == 0

    def monic_factors():
        fs = [f for f in invariant_factors(M, domain=R) if f != 0]
        return [[str(c) for c in reversed(sp.Poly(f, d, domain=sp.QQ).monic().all_coeffs())] for f in fs]

    ops = {
        "smith": lambda: smith_normal_decomp(M, domain=R),
        "invariant_factors": lambda: invariant_factors(M, domain=R),
        "rank": lambda: DomainMatrix.from_Matrix(M).convert_to(R.get_field()).rank(),
        "det": det,
        "is_unimodular": is_unimodular,
    }
    return ops, monic_factors, lambda op, out: {}


def _sage_names():
    """QQ, PolynomialRing, matrix from ``sage.all`` or, with only the modular
    passagemath wheels installed, from their ``sage.all__sagemath_*`` modules."""
    try:
        from sage.all import QQ, PolynomialRing, matrix  # type: ignore[import-not-found]
    except ImportError:
        import sage.all__sagemath_flint  # type: ignore[import-not-found]  # noqa: F401
        from sage.all__sagemath_modules import (  # type: ignore[import-not-found]
            QQ,
            PolynomialRing,
            matrix,
        )
    return QQ, PolynomialRing, matrix


_FIND_SAGE = ("import importlib.util, sys\n"
              "for name in ('sage.all', 'sage.all__sagemath_modules'):\n"
              "    try:\n"
              "        if importlib.util.find_spec(name) is not None: sys.exit(0)\n"
              "    except ImportError: pass\n"
              "sys.exit(1)\n")


def flint_is_stable_abi() -> bool:
    """python-flint is a stable-ABI (abi3) build: every call into it costs about 3x more
    than with a version-specific build (python-flint 0.9.0 on CPython < 3.13)."""
    try:
        from flint.types import fmpq_poly
    except ImportError:
        return False
    return ".abi3." in os.path.basename(getattr(fmpq_poly, "__file__", "") or "")


def sage_available(sage_python: str | None = None) -> bool:
    """SageMath importable in this interpreter, or (``sage_python``) in that one."""
    if sage_python is None:
        for name in ("sage.all", "sage.all__sagemath_modules"):
            try:
                if importlib.util.find_spec(name) is not None:
                    return True
            except ImportError:
                continue
        return False
    try:
        return subprocess.run([sage_python, "-c", _FIND_SAGE], timeout=120).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


def _setup_sage(case):
    QQ, PolynomialRing, matrix = _sage_names()

    R = PolynomialRing(QQ, "d")
    n, m = case["shape"]
    M = matrix(R, n, m, [R(list(c)) for row in case["M"] for c in row])

    def monic_factors():
        fs = [f for f in M.elementary_divisors() if f != 0]
        return [[str(c) for c in f.monic().list()] for f in fs]

    def left_inverse():
        # what Sage offers: U of the Hermite form [I; 0] = U·M; its first m rows
        H, U = M.__copy__().hermite_form(transformation=True)
        if H[:m] != 1:
            raise ValueError("not left unimodular")
        return U[:m]

    # Sage caches det, rank, forms … on the matrix: every call gets a fresh copy
    ops = {
        "hermite": lambda: M.__copy__().hermite_form(transformation=True),
        "smith": lambda: M.__copy__().smith_form(),
        "invariant_factors": lambda: M.__copy__().elementary_divisors(),
        "rank": lambda: M.__copy__().rank(),
        "det": lambda: M.__copy__().det(),
        "is_unimodular": lambda: M.is_square() and M.__copy__().det().degree() == 0,
        "left_kernel": lambda: M.__copy__().minimal_kernel_basis(),
        "left_inverse": left_inverse,
    }

    def entries(A) -> Entries:
        return [[[(int(c.numerator()), int(c.denominator())) for c in A[i, j].list()] if A[i, j] else []
                 for j in range(A.ncols())] for i in range(A.nrows())]

    def full_row_rank(K) -> bool:
        return any(K.apply_map(lambda p, x=x: p(x), QQ).rank() == K.nrows() for x in range(2, 12))

    def unimodular(T, *transforms) -> bool:  # as for ours: det T = c·det M, else det U
        if M.is_square():
            dM = M.det()
            if dM != 0:
                dT = R.one()
                for i in range(T.nrows()):
                    dT *= T[i, i]
                return dT.degree() == dM.degree() and dT * dM.leading_coefficient() == dM * dT.leading_coefficient()
        return all(constant_det(X) for X in transforms)

    def constant_det(X) -> bool:  # as for ours: one nonzero constant at D + 1 points
        D = sum(max((e.degree() for e in X.row(i) if e), default=0) for i in range(X.nrows()))
        dets = {X.apply_map(lambda p, x=x: p(x), QQ).det() for x in range(D + 1)}
        return len(dets) == 1 and dets != {0}

    def describe(op: str, out: Any) -> dict[str, Any]:
        if op == "hermite":
            H, U = out
            return _report(lambda: U * M == H and unimodular(H, U),
                           {"H": entries(H), "U": entries(U)}, _digest(entries(H)))
        if op == "smith":
            S, U, V = out
            return _report(lambda: U * M * V == S and unimodular(S, U, V),
                           {"U": entries(U), "V": entries(V)}, _digest(entries(S)))
        if op == "left_kernel":
            # Sage's rank over QQ[d] takes seconds from 12×12: K has full row rank at a
            # point instead; the row count is compared with ours through the row degrees
            K = entries(out)
            return _report(lambda: (out * M).is_zero() and full_row_rank(out),
                           {"K": K}, _row_degrees(K))
        if op == "left_inverse":
            return _report(lambda: out * M == 1, {"L": entries(out)}, None)
        if op == "det":
            return _report(None, {}, _digest([[[(int(c.numerator()), int(c.denominator())) for c in out.list()]]]))
        if op == "rank":
            return _report(None, {}, int(out))
        return {}

    return ops, monic_factors, describe


SETUP = {"ours": _setup_ours, "sympy": _setup_sympy, "sage": _setup_sage}


# ----------------------------------------------------------------------------
# output size, in one representation for every library
# ----------------------------------------------------------------------------
Entries = list[list[list[tuple[int, int]]]]  # rows of entries; an entry: (num, den) low to high


def matrix_size(A: Entries) -> tuple[int, int, int]:
    """(max degree, max bit length, total bit length) of a polynomial matrix over Q[δ].

    Bits are those of the primitive integer form of each row: the row times the
    lcm of its denominators, divided by the gcd of the resulting integers — a
    size that does not depend on how a library scales a row by a constant.  The
    total is the sum of the bit lengths of all those integers (what storing the
    matrix costs, up to the row scales).

    >>> matrix_size([[[(1, 2), (3, 4)], []], [[(5, 1)], [(0, 1), (0, 1), (7, 1)]]])
    (2, 3, 10)
    """
    deg, bits, total = -1, 0, 0
    for row in A:
        den = 1
        for e in row:
            for _, q in e:
                den = math.lcm(den, q)
        ints = [p * (den // q) for e in row for p, q in e]
        g = 0
        for x in ints:
            g = math.gcd(g, x)
        if g:
            lengths = [abs(x // g).bit_length() for x in ints]
            bits = max(bits, max(lengths))
            total += sum(lengths)
        deg = max(deg, max((len(e) - 1 for e in row), default=-1))
    return deg, bits, total


def _digest(A: Entries) -> str:
    """A short hash of A with each row divided by the leading coefficient of its first
    nonzero entry (so that Hermite and Smith forms normalised up to units compare equal)."""
    rows = []
    for row in A:
        lead = next((e[-1] for e in row if e), (1, 1))
        scale = Fraction(lead[1], lead[0])
        rows.append([[str(Fraction(p, q) * scale) for p, q in e] for e in row])
    return hashlib.sha256(repr(rows).encode()).hexdigest()[:16]


def _row_degrees(A: Entries) -> list[int]:
    """Sorted row degrees (of a minimal kernel basis: the minimal indices)."""
    return sorted(max((len(e) - 1 for e in row), default=-1) for row in A)


def _report(check: Any, mats: dict[str, Entries], canon: Any) -> dict[str, Any]:
    """Sizes and canonical form now; ``check`` (a callable proving the identities, or
    None) runs after the sizes have been sent, so a slow check loses only itself."""
    return {"check": check, "size": {k: matrix_size(v) for k, v in mats.items()}, "canon": canon}


# ----------------------------------------------------------------------------
# workers: one per (library, case); they stream (op, result | error) back
# ----------------------------------------------------------------------------
def _worker(lib: str, case: dict[str, Any], ops: list[str], repeats: int, send) -> None:
    """Time each op (best CPU time of up to ``repeats``), then describe its last result
    (verified identities, output sizes, a canonical form to compare); ``send``
    gets ``(op, {"t": …, "ok": …, "size": …, "canon": …})``, an error string or None."""
    try:
        table, monic_factors, describe = SETUP[lib](case)
    except Exception as exc:  # report, never hang
        send(("setup-error", f"{type(exc).__name__}: {exc}"))
        return
    send(("ready", None))
    for op in ops:
        if op == "__check__":
            try:
                send((op, monic_factors()))
            except Exception as exc:
                send((op, f"error: {type(exc).__name__}: {exc}"))
            continue
        fn = table.get(op)
        if fn is None:
            send((op, None))
            continue
        try:
            best = float("inf")
            spent = 0.0
            for _ in range(repeats):
                t0 = time.process_time()
                out = fn()
                t = time.process_time() - t0
                best = min(best, t)
                spent += t
                if spent > 1.0:
                    break
            result: dict[str, Any] = {"t": best}
            result.update(describe(op, out))
            check = result.pop("check", None)
            send((op, dict(result, pending=True)))  # time and sizes stand even if checking times out
            result["ok"] = bool(check()) if check is not None else True
            send((op, result))
        except Exception as exc:
            send((op, f"error: {type(exc).__name__}: {exc}"))


def _pipe_worker(lib: str, case: dict[str, Any], ops: list[str], repeats: int, conn) -> None:
    _worker(lib, case, ops, repeats, conn.send)


def _stdio_worker() -> None:
    """``python bench_ring.py --worker``: one worker in another interpreter (e.g. a
    venv with passagemath); JSON job on stdin, one JSON message a line on stdout."""
    job = json.loads(sys.stdin.read())
    out = sys.stdout

    def send(msg: Any) -> None:
        out.write(json.dumps(msg) + "\n")
        out.flush()

    sys.stdout = sys.stderr  # library chatter must not corrupt the channel
    _worker(job["lib"], job["case"], job["ops"], job["repeats"], send)


class _LineConnection:
    """``poll``/``recv`` over the JSON lines of a subprocess's stdout."""

    def __init__(self, proc: subprocess.Popen) -> None:
        self._queue: queue.Queue[Any] = queue.Queue()
        self._next: list[Any] = []

        def pump() -> None:
            assert proc.stdout is not None
            for line in proc.stdout:
                self._queue.put(tuple(json.loads(line)))
            self._queue.put(EOFError)

        threading.Thread(target=pump, daemon=True).start()

    def poll(self, timeout: float) -> bool:
        if not self._next:
            try:
                self._next.append(self._queue.get(timeout=timeout))
            except queue.Empty:
                return False
        return True

    def recv(self) -> Any:
        msg = self._next.pop() if self._next else self._queue.get()
        if msg is EOFError:
            self._next.append(msg)
            raise EOFError
        return msg

    def close(self) -> None:
        pass


def _die_with_parent() -> None:
    """Linux: the worker gets SIGKILL when the benchmark dies (no orphaned computation)."""
    try:
        import ctypes
        import signal

        ctypes.CDLL(None).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        pass


class _Subprocess:
    def __init__(self, python: str, job: dict[str, Any]) -> None:
        self.proc = subprocess.Popen([python, os.path.abspath(__file__), "--worker"], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, text=True, preexec_fn=_die_with_parent)
        assert self.proc.stdin is not None
        self.proc.stdin.write(json.dumps(job))
        self.proc.stdin.close()

    def is_alive(self) -> bool:
        return self.proc.poll() is None

    def kill(self) -> None:
        self.proc.kill()

    def join(self) -> None:
        self.proc.wait()


def _context():
    methods = mp.get_all_start_methods()
    return mp.get_context("fork" if "fork" in methods else "spawn")


def _start(lib: str, case: dict[str, Any], ops: list[str], repeats: int, python: str | None):
    if python is not None:  # another interpreter
        proc = _Subprocess(python, dict(lib=lib, case=case, ops=ops, repeats=repeats))
        return proc, _LineConnection(proc.proc)
    ctx = _context()
    parent, child = ctx.Pipe(duplex=False)
    proc = ctx.Process(target=_pipe_worker, args=(lib, case, ops, repeats, child), daemon=True)
    proc.start()
    child.close()
    return proc, parent


def run_case(lib: str, case: dict[str, Any], ops: list[str], repeats: int, budget: float,
             python: str | None = None) -> dict[str, Any]:
    """Run ``ops`` for one library on one case; each op gets ``budget`` seconds.
    ``python``: run the worker in that interpreter rather than a fork of this one."""
    results: dict[str, Any] = {}
    todo = list(ops)
    while todo:
        proc, parent = _start(lib, case, todo, repeats, python)
        try:
            if not parent.poll(max(budget, 60.0)):
                for op in todo:
                    results[op] = "setup timeout"
                break
            tag, msg = parent.recv()
            if tag == "setup-error":
                for op in todo:
                    results[op] = f"error: {msg}"
                break
            while todo:
                op = todo[0]
                if not parent.poll(budget):
                    results[op] = "timeout"
                    todo.pop(0)
                    break  # kill this worker; a fresh one continues with the rest
                got_op, value = parent.recv()
                results[got_op] = value
                todo.pop(0)
                if isinstance(value, dict) and value.pop("pending", False):
                    if not parent.poll(budget):
                        value["ok"] = None  # timed and measured, not verified
                        break
                    results[got_op] = parent.recv()[1]
        except EOFError:
            if todo:
                results[todo.pop(0)] = "crashed"
        finally:
            if proc.is_alive():
                proc.kill()
            proc.join()
            parent.close()
    return results


# ----------------------------------------------------------------------------
# import cost
# ----------------------------------------------------------------------------
_IMPORT_OURS = (
    "import time; t0 = time.perf_counter(); import uio_ring; t1 = time.perf_counter(); "
    "from uio_ring import PolyMatrix, smith; smith(PolyMatrix('[[d, 0], [0, d + 1]]')); "
    "t2 = time.perf_counter(); print(t1 - t0, t2 - t1)"
)
_IMPORT_SYMPY = (
    "import time; t0 = time.perf_counter(); import sympy; t1 = time.perf_counter(); "
    "from sympy.matrices.normalforms import invariant_factors; d = sympy.Symbol('d'); "
    "invariant_factors(sympy.Matrix([[d, 0], [0, d + 1]]), domain=sympy.QQ[d]); "
    "t2 = time.perf_counter(); print(t1 - t0, t2 - t1)"
)


def import_times(repeats: int) -> list[tuple[str, float, float, float]]:
    rows = []
    for label, code in (("uio_ring", _IMPORT_OURS), ("sympy", _IMPORT_SYMPY)):
        best = (float("inf"), float("inf"), float("inf"))
        for _ in range(repeats):
            t0 = time.perf_counter()
            out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                                 timeout=120, check=True)
            wall = time.perf_counter() - t0
            a, b = (float(x) for x in out.stdout.split())
            if a + b < best[0] + best[1]:
                best = (a, b, wall)
        rows.append((label, *best))
    return rows


# ----------------------------------------------------------------------------
# main
# ----------------------------------------------------------------------------
def _time(v: Any) -> Any:
    return v["t"] if isinstance(v, dict) else v


def _fmt(v: Any) -> str:
    v = _time(v)
    if v is None:
        return "n/a"
    if isinstance(v, float):
        return f"{v:.4f}" if v < 10 else f"{v:.1f}"
    return str(v)


def _ratio(other: Any, ours: Any) -> str:
    other, ours = _time(other), _time(ours)
    if isinstance(other, float) and isinstance(ours, float) and ours > 0:
        return f"{other / ours:.1f}x" if other / ours < 10 else f"{other / ours:.0f}x"
    return ""


Size = tuple[int, int, int]


def _sizes(v: Any) -> dict[str, Size]:
    return {k: tuple(x) for k, x in v.get("size", {}).items()} if isinstance(v, dict) else {}


def _fmt_size(sizes: dict[str, Size]) -> str:
    """``U 5/41/3k``: max degree / max bits (primitive rows) / total kbit of each output matrix."""
    return " ".join(f"{k} {d}/{b}/{_kbit(t)}" for k, (d, b, t) in sizes.items())


def _kbit(t: int) -> str:
    return f"{t / 1000:.0f}k" if t >= 1000 else f"{t / 1000:.1f}k"


def _larger(ours: dict[str, Size], other: dict[str, Size]) -> str:
    """The output matrices where ours is larger than the other library's: in max degree,
    max bits or total bits (``U:bits+total``)."""
    out = []
    for k, (d, b, t) in ours.items():
        if k in other:
            od, ob, ot = other[k]
            what = "+".join(name for name, worse in (("deg", d > od), ("bits", b > ob), ("total", t > ot)) if worse)
            if what:
                out.append(f"{k}:{what}")
    return " ".join(out) or "-"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="tiny sizes only (smoke test)")
    ap.add_argument("--max-n", type=int, default=max(TALL4_SIZES), help="largest n (default 24)")
    ap.add_argument("--budget", type=float, default=60.0, help="seconds per operation and library")
    ap.add_argument("--repeats", type=int, default=5, help="best of k for fast operations")
    ap.add_argument("--seed", type=int, default=20261123)
    ap.add_argument("--no-sympy", action="store_true", help="skip the sympy columns")
    ap.add_argument("--sage", action="store_true", help="require SageMath (exit 2 if not importable)")
    ap.add_argument("--no-sage", action="store_true", help="skip the SageMath columns")
    ap.add_argument("--sage-python", default=os.environ.get("UIO_SAGE_PYTHON") or None,
                    help="a Python interpreter with passagemath (default: $UIO_SAGE_PYTHON, "
                         "else SageMath in this interpreter)")
    ap.add_argument("--families", default=",".join(FAMILIES),
                    help=f"comma-separated subset of {','.join(FAMILIES)}")
    args = ap.parse_args(argv)

    sizes = QUICK_SIZES if args.quick else [n for n in SIZES if n <= args.max_n]
    budget = min(args.budget, 30.0) if args.quick else args.budget
    repeats = 1 if args.quick else args.repeats
    families = [f.strip() for f in args.families.split(",") if f.strip()]
    unknown = sorted(set(families) - set(FAMILIES))
    if unknown:
        ap.error(f"unknown families {unknown}; choose from {FAMILIES}")
    libs = ["ours"] + ([] if args.no_sympy else ["sympy"])
    if not args.no_sage and sage_available(args.sage_python):
        libs.append("sage")
    elif args.sage:
        where = args.sage_python or sys.executable
        print(f"--sage: SageMath is not importable by {where} (install the passagemath wheels "
              "passagemath-flint and passagemath-modules, e.g. in a venv named by --sage-python)")
        return 2
    python = {"sage": args.sage_python}

    import platform

    print(f"# uio_ring ring benchmark  (python {platform.python_version()}, {os.cpu_count()} cpu, "
          f"budget {budget:g} s/op, best CPU time of {repeats}, seed {args.seed})")
    versions = []
    for mod in ("uio_ring", "sympy", "flint"):
        try:
            versions.append(f"{mod} {__import__(mod).__version__}")
        except Exception:
            versions.append(f"{mod} ?")
    if flint_is_stable_abi():
        versions.append("flint: a stable-ABI (abi3) build, ~3x slower per small operation (see pyproject.toml)")
    try:  # a script's directory, not the working directory, leads sys.path: say which copy runs
        versions.append(f"uio_ring from {os.path.dirname(__import__('uio_ring').__file__)}")
    except Exception:
        pass
    if "sage" in libs:
        versions.append(f"sage: {args.sage_python or 'this interpreter'}")
    elif args.no_sage:
        versions.append("sage: skipped (--no-sage)")
    else:
        versions.append("sage: not installed (columns omitted)")
    print("# " + ", ".join(versions))

    cases = build_cases(sizes, args.seed, quick=args.quick, max_n=args.max_n, families=families)
    growth_ops = ["left_kernel", "left_inverse", "hermite", "solve_left"]
    growth_times: dict[tuple[str, str], list[tuple[int, float]]] = {
        (op, lib): [] for op in growth_ops for lib in libs}
    timed_out: set[tuple[str, str, str]] = set()  # (lib, family, op)
    header = ["family", "n", "shape", "operation", "ours [s]"]
    if "sympy" in libs:
        header += ["sympy [s]", "sympy/ours"]
    if "sage" in libs:
        header += ["sage [s]", "sage/ours"]
    header += ["ours deg/bits/total"]
    if "sage" in libs:
        header += ["sage deg/bits/total", "ours larger"]
    rows: list[list[str]] = []
    mismatches: list[str] = []
    unverified: list[str] = []
    start = time.perf_counter()
    for case in cases:
        res: dict[str, dict[str, Any]] = {}
        for lib in libs:
            ops = []
            skipped = {}
            for op in case["ops"]:
                if (lib, case["family"], op) in timed_out:
                    skipped[op] = "skipped (> budget)"
                else:
                    ops.append(op)
            if "invariant_factors" in ops:  # cross-check the (unique) invariant factors
                ops.append("__check__")
            r = run_case(lib, case, ops, repeats, budget, python.get(lib)) if ops else {}
            r.update(skipped)
            for op, v in r.items():
                if v == "timeout":
                    timed_out.add((lib, case["family"], op))
                if isinstance(v, dict) and v.get("ok", True) is False:
                    mismatches.append(f"{case['family']} n={case['n']} {op}: {lib}'s result fails its identities")
                if isinstance(v, dict) and v.get("ok", True) is None:
                    unverified.append(f"{case['family']} n={case['n']} {op} ({lib})")
            res[lib] = r
        ref = res["ours"].get("__check__")
        for lib in libs[1:]:
            other = res[lib].get("__check__")
            if isinstance(ref, list) and isinstance(other, list) and ref != other:
                mismatches.append(f"{case['family']} n={case['n']}: invariant factors differ, ours vs {lib}")
            for op in case["ops"]:
                a, b = res["ours"].get(op), res[lib].get(op)
                if (isinstance(a, dict) and isinstance(b, dict) and a.get("canon") is not None
                        and b.get("canon") is not None and a["canon"] != b["canon"]):
                    what = {"hermite": "H", "smith": "S", "left_kernel": "kernel row degrees"}.get(op, "value")
                    mismatches.append(f"{case['family']} n={case['n']} {op}: {what} differs, ours vs {lib}")
        if case["family"] == "tall4":
            for op in growth_ops:
                for lib in libs:
                    v = _time(res[lib].get(op))
                    if isinstance(v, float):
                        growth_times[op, lib].append((case["n"], v))
        for op in case["ops"]:
            ours = res["ours"].get(op)
            line = [case["family"], str(case["n"]), f"{case['shape'][0]}x{case['shape'][1]}",
                    op.replace("is_unimodular_left", "is_left_unimodular"), _fmt(ours)]
            for lib in libs[1:]:
                v = res[lib].get(op)
                line += [_fmt(v), _ratio(v, ours)]
            line.append(_fmt_size(_sizes(ours)))
            if "sage" in libs:
                theirs = _sizes(res["sage"].get(op))
                line += [_fmt_size(theirs), _larger(_sizes(ours), theirs) if theirs else ""]
            rows.append(line)
        _print_rows(header, rows)
        rows.clear()
    print(f"# total benchmark time {time.perf_counter() - start:.1f} s")
    if unverified:
        print("# timed but not verified (checking exceeded the budget): " + "; ".join(unverified))
    if mismatches:
        print("# WARNING: " + "; ".join(mismatches))
    else:
        print(f"# every {'other ' if unverified else ''}result verified (U·M = H, U·M·V = S, K·M = 0, X·M = I or W, U and V unimodular); "
              "invariant factors, H, S, det, rank and kernel row degrees agree between the libraries "
              "on every case where both finished")

    for op in growth_ops:
        for lib in libs:
            pts = growth_times[op, lib]
            if len(pts) >= 2:
                print(f"# {op} on tall4: fitted growth exponent ({lib}) "
                      f"{_growth_exponent(pts):.2f} over n = {', '.join(str(n) for n, _ in pts)}")

    print()
    k = 1 if args.quick else 3
    print(f"# import cost (fresh interpreter, best of {k}): import, first use, interpreter wall")
    for label, imp, first, wall in import_times(k):
        print(f"{label:10s} import {imp:7.3f} s   first use {first:7.3f} s   wall {wall:7.3f} s")
    return 1 if mismatches else 0


def _growth_exponent(points: list[tuple[int, float]]) -> float:
    """Least-squares slope of log(time) against log(n)."""
    import math

    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    sxx = sum((x - mx) ** 2 for x in xs)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys, strict=True)) / sxx


_printed_header = False


def _print_rows(header: list[str], rows: list[list[str]]) -> None:
    global _printed_header
    widths = [max(len(h), 11) for h in header]
    widths[0], widths[1], widths[2], widths[3] = 9, 3, 6, 18
    for i, h in enumerate(header):
        if "deg/bits" in h:
            widths[i] = 30
    if not _printed_header:
        print("  ".join(h.ljust(w) for h, w in zip(header, widths, strict=True)))
        print("  ".join("-" * w for w in widths))
        _printed_header = True
    for r in rows:
        print("  ".join(c.ljust(w) for c, w in zip(r, widths, strict=True)).rstrip(), flush=True)


if __name__ == "__main__":
    if sys.argv[1:] == ["--worker"]:
        _stdio_worker()
    else:
        sys.exit(main())
