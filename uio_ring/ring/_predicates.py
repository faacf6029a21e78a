"""Bottom layer of the algorithm modules: rank, determinant and the normal-form
predicates on raw rows.

Every algorithm module (and the :class:`~uio_ring.ring.matrix.PolyMatrix`
façade) may import this module; it imports only the scalar backend, the dense
kernels and the evaluation helpers.  This keeps the import graph of
``uio_ring.ring`` acyclic: ``matrix`` calls :func:`det_raw`/:func:`rank_raw`
instead of importing ``rank``, and ``hermite``/``smith`` certify their results
with :func:`is_unimodular_raw` instead of importing ``inverse``.

Rank
    ``rank M(x) ≤ rank M`` for every rational x, and a nonzero k×k minor (degree
    ≤ b_k, see :func:`~uio_ring.ring._evaluation.minor_degree_bound`) vanishes at
    no more than b_k points.  So if ``b_{r+1} + 1`` distinct points all give rank
    ≤ r while some point gives r, the rank is exactly r.  Evaluation stops at
    once when the rank reaches min(m, n); δ = 0 comes first, from the constant
    coefficients alone.
Determinant
    Bareiss' fraction-free elimination over Z[δ] (:mod:`uio_ring.ring._fraction_free`)
    for small n, high degree or large coefficients; otherwise ``det M(x)`` at
    ``b_n + 1`` points, then interpolation.

Degrees: ``deg 0 = -1``.
"""

from __future__ import annotations

import random

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring import _evaluation as ev
from uio_ring.ring import _fraction_free as ff
from uio_ring.ring._echelon import max_bits
from uio_ring.ring._modular import PRIME, det_mod_p, gcd_mod_p

__all__ = [
    "rank_raw",
    "det_raw",
    "full_rank_at_zero",
    "is_unimodular_raw",
    "unimodular_given_hermite",
    "unimodular_given_smith",
    "is_hermite_raw",
    "is_smith_raw",
    "coprime_maximal_minors",
    "det_not_constant_mod_p",
    "det_below_echelon",
    "left_unimodular_proved",
    "minors_work",
]


def full_rank_at_zero(a: dn.Rows, m: int, n: int) -> bool:
    """True if the constant coefficient M(0) has rank min(m, n) — then so has M (a
    sufficient test, one rational rank of the constant terms).

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> full_rank_at_zero([[d + 1, d], [d, d + 1]], 2, 2), full_rank_at_zero([[d]], 1, 1)
    (True, False)
    """
    c = flint.fmpq_mat(m, n, [p[0] for r in a for p in r])
    if m == n:  # a determinant: a fifth of the time of a rank at 4×4
        return bk.mat_det(c) != 0
    return bk.mat_rank(c) == min(m, n)


def rank_raw(a: dn.Rows, m: int, n: int) -> int:
    """Rank over Q[δ] of the m×n rows ``a`` (deterministic, exact).
    Precondition: ``a`` has shape m×n (not checked)."""
    if m == 0 or n == 0 or all(p.is_zero() for r in a for p in r):
        return 0
    top = min(m, n)
    if full_rank_at_zero(a, m, n):
        return top  # rank M(0) ≤ rank M ≤ min(m, n); M(0) needs no other coefficient
    coeffs = ev.coefficient_mats(a, m, n)
    best = 0
    needed = ev.minor_degree_bound(a, m, n, 1) + 1
    used = 0
    for x in ev.points():
        r = bk.mat_rank(ev.evaluate(coeffs, x))
        used += 1
        if r > best:
            best = r
            if best == top:
                return best
            needed = ev.minor_degree_bound(a, m, n, best + 1) + 1
        # Invariant: best = max rank seen; no (best+1)-minor is nonzero at `used` points.
        if used >= needed:
            return best
    raise AssertionError("unreachable")  # pragma: no cover


def det_raw(a: dn.Rows, n: int) -> flint.fmpq_poly:
    """Determinant of the n×n rows ``a``.  Precondition: square (not checked)."""
    if n <= dn.CLOSED_FORM_MAX_SIZE:  # no evaluation (a 2×2 of degree 256 has 513 points)
        return dn.det_closed_form(a, n)
    if ff.prefer_fraction_free(a, n):
        return ff.det_fraction_free(a, n)
    coeffs = ev.coefficient_mats(a, n, n)
    bound = ev.minor_degree_bound(a, n, n, n)
    xs = ev.first_points(bound + 1)
    ys = [ev.det_at(coeffs, x) for x in xs]
    return ev.interpolate(xs, ys)


def is_unimodular_raw(a: dn.Rows, m: int, n: int) -> bool:
    """Square with a nonzero constant determinant (0×0 counts).
    Precondition: ``a`` has shape m×n (not checked)."""
    return m == n and det_raw(a, n).degree() == 0


def _independent_block(a: dn.Rows, m: int, n: int, r: int) -> tuple[list[int], list[int]] | None:
    """Rows R and columns C (r each) with ``det M[R, C] ≠ 0``, read at the first point
    where M has rank r (one exists when rank M = r: a nonzero r×r minor has at most
    ``minor_degree_bound`` roots); None when none of those points gives rank r."""
    coeffs = ev.coefficient_mats(a, m, n)
    for x in ev.first_points(ev.minor_degree_bound(a, m, n, r) + 1):
        at = ev.evaluate(coeffs, x)
        rref, rank = at.rref()
        if rank == r:
            cols = [next(c for c in range(n) if rref[i, c] != 0) for i in range(r)]
            sub = bk.mat_from_rows([[at[i, c] for c in cols] for i in range(m)], m, r)
            rref_t, _ = sub.transpose().rref()
            return [next(c for c in range(m) if rref_t[i, c] != 0) for i in range(r)], cols
    return None


def unimodular_given_hermite(u: dn.Rows, a: dn.Rows, h: dn.Rows, m: int, n: int) -> bool:
    """Whether the m×m rows ``u`` are unimodular, given ``U·M = H`` exactly for the m×n
    rows ``a`` (M) and ``h`` (H) in row Hermite form — without det U, whose evaluation
    needs Σ (row degrees of U) + 1 points: a 16×16 U of degree 112 with 11-kbit
    coefficients took 49 s by Bareiss.

    With J the pivot columns of H (r of them), T = H[:r, J] (upper triangular, det T the
    product of the pivots), N = M[:, J] (rank r, as ``U·N = [T; 0]``), R a set of r rows
    with ``μ = det N[R, :] ≠ 0`` (read at a point) and I the other rows:
    ``U·[N | E_I] = [[T, U_top[:, I]], [0, U_bot[:, I]]]`` with E_I the unit columns of I,
    so ``det U · (±μ) = det T · det U[r:, I]``.  Hence U is unimodular exactly when
    ``det U[r:, I] ≠ 0`` and ``deg det T + deg det U[r:, I] = deg μ``: two determinants of
    M's small entries and of U's kernel block (one entry for a corank-1 M).
    Precondition: ``U·M == H`` and H is a row Hermite form (not checked here: the caller's
    certificate checks both).

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> a = [[d, bk.ONE], [d * d, d]]                 # rank 1, kernel row (δ, −1)
    >>> h = [[d, bk.ONE], [bk.ZERO, bk.ZERO]]
    >>> unimodular_given_hermite([[bk.ONE, bk.ZERO], [d, -bk.ONE]], a, h, 2, 2)
    True
    >>> unimodular_given_hermite([[bk.ONE, bk.ZERO], [d * d, -d]], a, h, 2, 2)  # δ·kernel row
    False
    """
    pivots = [j for j in (next((j for j, p in enumerate(row) if p), -1) for row in h) if j >= 0]
    r = len(pivots)
    if r == 0:
        return is_unimodular_raw(u, m, m)
    N = [[row[j] for j in pivots] for row in a]
    block = _independent_block(N, m, r, r)
    if block is None:  # pragma: no cover - N has rank r
        return is_unimodular_raw(u, m, m)
    R = block[0]
    mu = det_raw([N[i] for i in R], r)
    chosen = set(R)
    rest = [i for i in range(m) if i not in chosen]
    d_k = det_raw([[u[i][c] for c in rest] for i in range(r, m)], m - r)
    if d_k.is_zero():
        return False
    deg_t = sum(h[i][j].degree() for i, j in enumerate(pivots))
    return deg_t + d_k.degree() == mu.degree()


def unimodular_given_smith(u: dn.Rows, v: dn.Rows, um: dn.Rows, a: dn.Rows, s: dn.Rows, m: int, n: int) -> bool:
    """Whether U (m×m) and V (n×n) are both unimodular, given ``um = U·M`` and
    ``U·M·V = S`` exactly for M (``a``, m×n) and S (``s``) in Smith form of rank r —
    without det U and det V.

    With R, C rows and columns of M where ``μ = det M[R, C] ≠ 0`` (read at a point), I and
    L the other rows and columns, D = S[:r, :r] and A = U·M: when ``A[r:, :] = 0`` (else V
    is singular: ``A[r:, :]·V = 0``), ``U·[M[:, C] | E_I]`` is block upper triangular and
    ``[A[:r, :]; E_Lᵀ]·V`` block lower triangular (E the unit vectors), so ``det U·(±μ) =
    det A[:r, C]·det U[r:, I]`` and ``det V·(±det A[:r, C]) = det D·det V[L, r:]``.  Hence
    U and V are both unimodular exactly when ``det U[r:, I]`` and ``det V[L, r:]`` are
    nonzero and ``deg det D + deg det U[r:, I] + deg det V[L, r:] = deg μ`` (det A[:r, C]
    cancels; when it is zero, so is det V[L, r:]).  For a square nonsingular M: ``deg det M
    = Σ deg s_i``.  Determinants of M's small entries and of the kernel blocks only (a
    16×16 U of degree 112 with 11-kbit coefficients: 49 s for det U by Bareiss).
    Precondition: ``um == U·M``, ``um·V == S``, S in Smith form (not checked here: the
    caller's certificate checks them).

    >>> from uio_ring.ring import _backend as bk
    >>> d, o, z = bk.from_coeffs([0, 1]), bk.ONE, bk.ZERO
    >>> a, s = [[d, o], [d * d, d]], [[o, z], [z, z]]      # rank 1: S = diag(1, 0)
    >>> u, v, um = [[o, z], [d, -o]], [[z, -o], [o, d]], [[d, o], [z, z]]
    >>> unimodular_given_smith(u, v, um, a, s, 2, 2)
    True
    >>> unimodular_given_smith([[o, z], [d * d, -d]], v, um, a, s, 2, 2)  # δ·kernel row
    False
    """
    r = sum(1 for i in range(min(m, n)) if s[i][i])
    if any(p for row in um[r:] for p in row):
        return False
    if r == 0:
        return is_unimodular_raw(u, m, m) and is_unimodular_raw(v, n, n)
    block = _independent_block(a, m, n, r)
    if block is None:  # pragma: no cover - rank M = r
        return is_unimodular_raw(u, m, m) and is_unimodular_raw(v, n, n)
    R, C = block
    mu = det_raw([[a[i][c] for c in C] for i in R], r)
    chosen_rows, chosen_cols = set(R), set(C)
    rows_i = [i for i in range(m) if i not in chosen_rows]
    cols_l = [c for c in range(n) if c not in chosen_cols]
    d_u = det_raw([[u[i][c] for c in rows_i] for i in range(r, m)], m - r)
    d_v = det_raw([[v[l][c] for c in range(r, n)] for l in cols_l], n - r)
    if d_u.is_zero() or d_v.is_zero():
        return False
    deg_d = sum(s[i][i].degree() for i in range(r))
    return deg_d + d_u.degree() + d_v.degree() == mu.degree()


def is_hermite_raw(a: dn.Rows, m: int) -> bool:
    """The normalised row Hermite form test of :func:`uio_ring.ring.hermite.is_hermite`.
    Precondition: ``a`` has m rows (not checked)."""
    last = -1
    seen_zero = False
    pivots: list[tuple[int, int]] = []
    for k, row in enumerate(a):
        j = next((c for c, p in enumerate(row) if not p.is_zero()), None)
        if j is None:
            seen_zero = True
            continue
        if seen_zero or j <= last:
            return False
        if bk.lc(row[j]) != 1:
            return False
        pivots.append((k, j))
        last = j
    for k, j in pivots:
        dp = a[k][j].degree()
        for i in range(m):
            if i != k and a[i][j].degree() >= (dp if i < k else 0):
                return False
    return True


def is_smith_raw(a: dn.Rows, m: int, n: int) -> bool:
    """The Smith form test of :func:`uio_ring.ring.smith.is_smith`.
    Precondition: ``a`` has shape m×n (not checked)."""
    for i in range(m):
        for j in range(n):
            if i != j and not a[i][j].is_zero():
                return False
    diag = [a[i][i] for i in range(min(m, n))]
    r = sum(1 for p in diag if not p.is_zero())
    if any(p.is_zero() for p in diag[:r]) or any(not p.is_zero() for p in diag[r:]):
        return False
    if any(bk.lc(p) != 1 for p in diag[:r]):
        return False
    return all((diag[i + 1] % diag[i]).is_zero() for i in range(r - 1))


def lone_entry_column(a: dn.Rows, m: int, n: int) -> bool:
    """True when some column of the m×n rows ``a`` (m ≥ n) is zero or has one nonzero entry,
    of positive degree: then that entry divides every n×n minor (Laplace expansion along
    the column), so M is not left unimodular and its Hermite form is not ``[I; 0]``.
    O(m·n) tests, no arithmetic: sparse matrices often have such a column, where the
    compressed minors of :func:`coprime_maximal_minors` cost more than the elimination.

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> lone_entry_column([[d, bk.ONE], [bk.ZERO, d], [bk.ZERO, bk.ONE]], 3, 2)
    True
    >>> lone_entry_column([[bk.ONE, d], [bk.ZERO, d], [bk.ZERO, bk.ONE]], 3, 2)
    False
    """
    for j in range(n):
        entries = [row[j] for row in a if row[j]]
        if not entries or (len(entries) == 1 and entries[0].degree() > 0):
            return True
    return False


def coprime_maximal_minors(a: dn.Rows, m: int, n: int, *, exact: bool = True, routing: bool = False) -> bool:
    """True when two compressed maximal minors ``det(Q_i·M)`` (fixed pseudo-random
    integer Q_i, n×m) are coprime: each is a Q-linear combination of the n×n minors
    (Cauchy–Binet), so their gcd is a multiple of the gcd of all the minors, which
    is then 1 — M is left unimodular.  Coprimality is first proved modulo one prime
    (:mod:`uio_ring.ring._modular`: the first determinant reaches its degree bound mod
    p and the gcd mod p is 1), else decided exactly — unless ``exact=False``, when only
    the modular proof is tried.  A square M (m = n) has only constant multiples of det M
    as compressions: there det M decides, exactly (``exact=False``: False).  False says
    nothing.  ``routing``: for a caller that only chooses a path with this answer (every
    path correct): False without the exact minors when the modular test sees a common
    factor (:func:`~uio_ring.ring._modular.gcd_mod_p` of positive degree, with the
    first minor at its degree bound or not) — a wrong False then costs time, not
    correctness (a singular 10×10 of degree 8 with a zero column: 5.0 → 1.5 ms; the 16×15
    Hermite rows of a rank-deficient 24×20 with factors δ + 1, …, whose first minor falls
    short of its bound: 21 s of exact minors → 0.03 s).
    Precondition: m ≥ n ≥ 1."""
    if m == n:  # every compression is det M times a constant: the one exact answer is det M
        return exact and is_unimodular_raw(a, n, n)
    if lone_entry_column(a, m, n):
        return False
    rng = random.Random(15)  # fixed: the answer depends only on M
    qa = []
    for _ in range(2):
        q = [[bk.const(rng.randint(-9, 9)) for _ in range(m)] for _ in range(n)]
        qa.append(dn.matmul(q, a, n, m, n))
    shared = gcd_mod_p(qa[0], qa[1], n)
    if shared.proves_coprime:  # a proof modulo one prime (see _modular)
        return True
    if not exact or (routing and shared.degree > 0):  # routing: evidence, bound or not
        return False
    if _coprime_with_the_top_minor(a, qa[0], n):
        return True
    f1 = det_raw(qa[0], n)
    if f1.is_zero():  # an unlucky compression ([[−1], [1/3]] against (−3, −9)), or rank < n
        qa.reverse()
        f1 = det_raw(qa[0], n)
        if f1.is_zero():
            return False
    # one exact minor is enough when its degree survives modulo p (the second is then
    # reduced mod p only): 8×8 compressed minors of degree 165 with 4.9-kbit coefficients,
    # 7 s each, in the proof for a 7-output spec of δ-degree 16
    if _coprime_mod_p(f1, qa[1], n):
        return True
    return bk.gcd(f1, det_raw(qa[1], n)).is_one()


def minors_work(a: dn.Rows, n: int) -> int:
    """``n⁵·deg·bits`` of the rows ``a`` with n columns: an estimate of the work on an exact
    n×n minor of them (the budgets below are in this unit)."""
    return n**5 * max(dn.mat_degree(a), 1) * max(max_bits(a), 1)


#: The largest n⁵·deg·bits of the first n rows for which :func:`_coprime_with_the_top_minor`
#: computes their determinant exactly (about a second) when they are not triangular.
TOP_MINOR_BUDGET = 10**9


def _coprime_with_the_top_minor(a: dn.Rows, compressed: dn.Rows, n: int) -> bool:
    """True when f₁ = det of the first n rows (exact: the product of the diagonal when they
    are upper triangular, else when its work is within ``TOP_MINOR_BUDGET``) and the
    compressed minor f₂ = det(Q·M) are coprime, proved modulo a prime (:func:`_coprime_mod_p`).
    Both are Q-linear combinations of the maximal minors, so M is left unimodular.
    The exact minor is the one whose degree is known —
    where the compressed minors miss their degree bound (Ō = [C̄; C̄Ā; …] is not column
    reduced), C̄ on top is small: a 16×8 Ō of degree 207 with 9550-bit coefficients is
    proved in about a second, against 44 s for two exact compressed minors."""
    top = a[:n]
    f1: flint.fmpq_poly | None
    if all(not top[i][j] for i in range(n) for j in range(i)):  # triangular (C̄ is a Hermite form)
        f1 = bk.ONE
        for i in range(n):
            f1 = f1 * top[i][i]
    else:
        f1 = det_below_echelon(top, n)  # C̄ of n − 1 rows and one row of C̄Ā
        if f1 is None and minors_work(top, n) <= TOP_MINOR_BUDGET:
            f1 = det_raw(top, n)
    return f1 is not None and not f1.is_zero() and _coprime_mod_p(f1, compressed, n)


def det_below_echelon(a: dn.Rows, n: int) -> flint.fmpq_poly | None:
    """det of the n×n rows ``a`` when its first n − 1 rows E are in echelon form (each row's
    first nonzero entry strictly right of the one above), else None.

    With J the pivot columns of E and f the one column left, the Schur complement of the
    upper triangular ``E_J`` gives ``±det = D·a_f − y·E_f`` where ``D = det E_J`` (the product
    of the pivots) and ``y = a_J·adj(E_J)`` solves ``y·E_J = D·a_J`` — by substitution, each
    step an exact division by a pivot.  O(n²) products instead of an elimination: the top
    minor of an observability matrix ``[C̄; C̄Ā; …]`` whose Hermite form C̄ has n − 1 rows
    (8×8 of degree 164 with 4.9-kbit coefficients: 0.3 s by Bareiss, whose work estimate
    was 60 times over the budget).

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> det_below_echelon([[bk.ONE, d, bk.ONE], [bk.ZERO, bk.ZERO, d], [d, bk.ONE, bk.ONE]], 3)
    x^3 + (-1)*x
    """
    pivots: list[int] = []
    for row in a[: n - 1]:
        j = next((c for c, e in enumerate(row) if e), n)
        if j == n or (pivots and j <= pivots[-1]):
            return None
        pivots.append(j)
    free = next(c for c in range(n) if c not in pivots)
    E, last = a[: n - 1], a[n - 1]
    D = bk.ONE
    for i, j in enumerate(pivots):
        D = D * E[i][j]
    y: list[flint.fmpq_poly] = []
    for k, j in enumerate(pivots):
        s = D * last[j]
        for i in range(k):
            if y[i] and E[i][j]:
                s = s - y[i] * E[i][j]
        q, r = divmod(s, E[k][j])
        if not r.is_zero():  # pragma: no cover - y is a polynomial vector (y = a_J·adj E_J)
            raise ArithmeticError("det_below_echelon: inexact division")
        y.append(q)
    det = D * last[free]
    for i in range(n - 1):
        if y[i] and E[i][free]:
            det = det - y[i] * E[i][free]
    # columns in the order (J, f): the sign of that permutation
    order = pivots + [free]
    inversions = sum(1 for x in range(n) for z in range(x + 1, n) if order[x] > order[z])
    return det if inversions % 2 == 0 else -det


def _coprime_mod_p(f1: flint.fmpq_poly, b: dn.Rows, n: int) -> bool:
    """True when the exact nonzero f₁ and f₂ = det of the n×n rows ``b`` are proved coprime
    modulo a prime: f₁ scaled to Z[δ] keeps its degree mod p, and its gcd with f₂ mod p
    (:func:`~uio_ring.ring._modular.det_mod_p`) is 1.  (A primitive common factor h of the
    integer forms: p does not divide lc f₁, hence not lc h, and h mod p of positive degree
    would divide both reductions.)  False proves nothing."""
    z = f1.numer()  # f1 times a positive integer: a primitive multiple's degree is f1's
    f1p = flint.nmod_poly([int(c) % PRIME for c in z.coeffs()], PRIME)
    if f1p.degree() != f1.degree():
        return False
    f2p, _ = det_mod_p(b, n)
    return bool(f1p.gcd(f2p).is_one())


def det_not_constant_mod_p(a: dn.Rows, n: int) -> bool:
    """True when det M of the n×n rows ``a`` is proved not to be a constant: its reduction
    modulo a prime (rows scaled to Z[δ], :func:`~uio_ring.ring._modular.det_mod_p`) has
    positive degree, so the integer determinant has a nonzero coefficient there.  Then M
    is not unimodular and has no polynomial inverse.  False proves nothing.

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> det_not_constant_mod_p([[d, bk.ONE], [bk.ONE, bk.ZERO]], 2), det_not_constant_mod_p([[d, bk.ONE], [bk.ONE, d]], 2)
    (False, True)
    """
    return n > 0 and det_mod_p(a, n)[0].degree() > 0


#: The largest n⁵·deg·bits (an estimate of the work on the two compressed n×n minors of an
#: m×n matrix of that δ-degree and coefficient size) for which a failed modular proof of
#: :func:`left_unimodular_proved` is completed by the exact minors.  The modular proof
#: fails on matrices that are not column reduced (the observability matrices Ō of a
#: design), and the solve the callers fall back to can cost far more than these minors
#: there: 8×4 of degree 71 with 1121 bits, 8·10⁷, 37 ms (the solve: 7 s); 14×8 of degree
#: 20 with 416 bits, 3·10⁸, 46 ms; 24×12 of degree 33 with 1853 bits, 1.5·10¹⁰, 5.1 s
#: (the solve: 77 s); 14×8 of degree 165 with 4858 bits, 2.6·10¹⁰, 13 s (the solve: over
#: 4 min); 16×8 of degree 207 with 9550 bits, 6.5·10¹⁰, 44 s (the solve: over 10 min) —
#: while at 216×32 of degree 23 with 2598 bits, 2·10¹², the minors take 84 s and the
#: solve 2 s.
EXACT_MINORS_BUDGET = 10**11


def left_unimodular_proved(a: dn.Rows, m: int, n: int, *, cheap_only: bool = False) -> bool:
    """True only when the m×n rows ``a`` (m ≥ n ≥ 1) are proved left unimodular by two
    coprime compressed maximal minors (:func:`coprime_maximal_minors`): modulo a prime,
    and exactly when that is inconclusive and the exact minors are cheap
    (``EXACT_MINORS_BUDGET``).  ``cheap_only``: False at once when they are not (for a
    caller whose other way is usually cheaper then: the modular attempt alone costs 1.2 s
    at 216×32).  False proves nothing.

    >>> from uio_ring.ring import _backend as bk
    >>> d = bk.from_coeffs([0, 1])
    >>> left_unimodular_proved([[d, bk.ONE], [bk.ONE, bk.ZERO], [d, d]], 3, 2)
    True
    """
    cheap = minors_work(a, n) <= EXACT_MINORS_BUDGET
    if cheap_only and not cheap:
        return False
    return coprime_maximal_minors(a, m, n, exact=cheap)
