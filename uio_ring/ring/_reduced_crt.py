"""The reduced solution of ``X·M = B`` for a tall M of full column rank, by block
elimination modulo word primes and Chinese remaindering, certified exactly.

Notation of :mod:`uio_ring.ring._kernel_basis`: M is m×n of rank n and degree dm, K its
Popov left kernel basis with pivots π_i of degrees d_i; the reduced X (entries in column
π_i of degree < d_i, all of degree ≤ D) is the unique solution of the square system
``x·T_D[P] = b`` on the non-leading monomials P.  Split the columns of x into the pivot
columns π (unknowns ``x_P``: the coefficients e < d_i, u_P = Σ d_i of them) and the n
others R, and write ``M_R = Σ_s A_s δ^s`` for the rows R of M.  ``M_R`` is nonsingular
(a vector y with ``y·M_R = 0`` gives the kernel vector ``[0, y]``, a combination of the
rows of K whose pivot block ``K_P = diag(δ^(d_i)) + lower`` is nonsingular: so y = 0).
When ``A_0`` is invertible the coefficients t = 0, …, D of ``x·M = b`` give ``x_R``
block by block (the δ-adic expansion of ``M_R⁻¹`` to order D)::

    X_R,t = (B_t − Σ_s X_R,t−s·A_s − X_P·H_t)·A_0⁻¹ = F_t + X_P·G_t,

and the remaining n·dm coefficients leave a u_P-unknown system ``X_P·E_G = −E_F``: the
Schur complement of the block-triangular part, u_P × n·dm instead of the (n·(D + 1) +
u_P)-square Toeplitz system (48 instead of 360 unknowns for a 28×24 matrix of degree 2).
Modulo a word prime p this costs O((D + 1)·dm·(k + u_P)·n²) word operations (k: the rows
of B) instead of O(u³).

Chinese remaindering.  The columns C of ``E_G`` used (a nonsingular u_P × u_P block
modulo the first prime) are kept for every prime, so ``Δ = det A_0^(D+1)·det E_G[:, C]``
is, up to a fixed sign, the determinant of one fixed square integer subsystem T' of the
Toeplitz system, and ``Y = Δ·x`` is integral (Cramer's rule).  Δ and ``Y_P = Δ·X_P`` are
remaindered prime by prime (Garner, symmetric residues); once a further prime agrees
with the current remainders (the usual early termination of multimodular algorithms),
``Y_R`` follows exactly from the recurrence over Z (exact divisions by the denominator
of ``A_0⁻¹``) and the whole system ``Y·T = Δ·b`` is checked exactly: only a checked
candidate is returned, so the stopping rule costs time when it is wrong, never
correctness.  (When the residues modulo the first prime are all small, X is first tried
as an integral solution, Δ = 1: the same exact check.)  With |Δ|, |Y| ≤ 2^H (H: Hadamard's bound of T' with b,
:func:`_hadamard_bits`), the remainders are exact once the product of the primes
exceeds 2^(H+1), so the loop ends there at the latest.  Since T' is nonsingular modulo
each prime used, a solution over Q reduces modulo p to the unique one modulo p, and an
inconsistency modulo p proves that no solution exists (the argument of
:func:`~uio_ring.ring._kernel_basis._consistent_mod_p`).  A 28×24 matrix of degree 2
with 24 right-hand sides (X of 1078-bit numerators and a 1074-bit denominator): 20
primes of 61 bits, about 2 ms each.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> from uio_ring.ring._kernel_basis import _integer_coefficients
>>> M = PolyMatrix("[[1, 0], [0, 1], [d, d]]")   # kernel [d, d, −1]: pivot 1, degree 1
>>> b = [[1, 0], [0, 1], [0, 0], [0, 0], [0, 0], [0, 0]]   # B = I: coefficients 0, 1, 2
>>> # Δ·X = [[1, 0, 0], [0, 1, 0]] and Δ = 1 (entries as coefficient lists, degrees 0, 1)
>>> solve_reduced_crt(_integer_coefficients(M._r, 3, 2), 1, 3, 2, 1, {1: 1}, b, 2)
([[[1, 0], [0, 0], [0, 0]], [[0, 0], [1, 0], [0, 0]]], 1)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import flint
from flint.utils.flint_exceptions import DomainError

from uio_ring import _progress

IntCoeffs = list[list[list[Any]]]  # [row j][column l] -> integer coefficients, low to high

__all__ = ["solve_reduced_crt", "NO_SOLUTION", "word_primes", "worthwhile"]

#: Returned when a prime proves that ``X·M = B`` has no solution of degree ≤ D.
NO_SOLUTION = "no solution"
#: Residues of X_P modulo the first prime all below this (symmetric): X is tried as an
#: integral solution with Δ = 1 (``solve_left`` of W = X0·M with a small integral X0).
SMALL = 1 << 40

_PRIMES: list[int] = []


def word_primes(count: int) -> list[int]:
    """The ``count`` largest primes below 2⁶¹ (cached).

    >>> word_primes(2)
    [2305843009213693951, 2305843009213693921]
    """
    x = (1 << 61) if not _PRIMES else _PRIMES[-1]
    while len(_PRIMES) < count:
        x -= 1
        if flint.fmpz(x).is_prime():
            _PRIMES.append(x)
    return _PRIMES[:count]


def _hadamard_bits(mi: IntCoeffs, m: int, columns: list[int], b_cols: list[list[Any]]) -> int:
    """Bits of a bound on |Δ| and on every |Δ·x_i| (Hadamard's inequality for T' and for
    T' with one column replaced by a column of b: each unknown (e, j) of T has the
    coefficients of row j of M as its column, so its norm is that of row j)."""
    norms = [sum(int(c) ** 2 for cs in row for c in cs) for row in mi]
    log2 = sum(math.log2(max(norms[c % m], 1)) for c in columns) / 2
    bmax = max((sum(int(x) ** 2 for x in col) for col in b_cols), default=1)
    return int(log2 + math.log2(max(bmax, 1)) / 2) + 2


def solve_reduced_crt(
    mi: IntCoeffs, dm: int, m: int, n: int, D: int, lead: dict[int, int], b: list[list[Any]], k: int,
) -> tuple[list[list[list[Any]]], flint.fmpz] | str | None:
    """``(rows of Δ·X, Δ)`` for the reduced solution X of ``X·M = B`` of degree ≤ D
    (module text; ``mi``: the integer coefficients of M, of degree dm), :data:`NO_SOLUTION` when a prime proves that there is none,
    or None when this method does not apply (rank M < n, A_0 singular modulo the first
    prime) or gives up (then the caller solves the square Toeplitz system).

    ``b`` holds the integer coefficients of B: ``b[t·n + l][v]`` = coefficient t of
    entry (v, l), t = 0, …, D + dm; ``lead`` maps each pivot π_i to d_i ≤ D.  The rows of
    Δ·X are given by their integer coefficient lists (D + 1 per entry); X·M = B is checked
    exactly before returning.

    When ``A_0 = M_R(0)`` is singular (modulo the first prime) the system is solved for
    ``M(δ + α)`` and ``B(δ + α)`` at the first α of :data:`SHIFTS` where it is not, and
    the rows are shifted back: ``x̃·M(δ + α) = B(δ + α)`` is checked exactly, and
    applying the automorphism δ ↦ δ − α of Q[δ] gives ``x·M = B`` for ``x = x̃(δ − α)``,
    which has the same degrees in every column (so the same reducedness)."""
    rest = [j for j in range(m) if j not in lead]
    if not worthwhile(n, dm) or len(rest) != n or not lead or D < max(lead.values()) or not any(lead.values()):
        return None
    alpha = _shift_point(mi, rest, n)
    if alpha is None:
        return None
    if alpha == 0:
        return _solve_core(mi, dm, m, n, D, lead, b, k)
    # x̃(δ) = x(δ + α) solves x̃·M(δ + α) = B(δ + α): the same degrees, so the same leading
    # positions and the same reducedness; the substitution is an automorphism of Q[δ]
    mi_s = [[_taylor_shift(cs, alpha) for cs in row] for row in mi]
    b_s: list[list[Any]] = [[0] * k for _ in range(len(b))]
    for v in range(k):
        for col in range(n):
            shifted = _taylor_shift([b[t * n + col][v] for t in range(len(b) // n)], alpha)
            for t, x in enumerate(shifted):
                b_s[t * n + col][v] = x
    got = _solve_core(mi_s, dm, m, n, D, lead, b_s, k)
    if not isinstance(got, tuple):
        return got
    rows, delta = got
    return [[_taylor_shift(cs, -alpha) for cs in row] for row in rows], delta


def worthwhile(n: int, dm: int) -> bool:
    """Whether the block elimination pays for an M with n columns of degree dm: 0 < dm ≤ n.

    Its cost modulo each prime has a part of O((D + 1)·dm) Python-level matrix operations
    and one of O(dm²·u_P·n²) word operations for ``E_G`` (u_P ≤ n·dm); with a few columns
    of high degree both exceed the dense solve of the whole Toeplitz system (3×2 of degree
    127: 110 ms a prime against 1.2 s for the whole Hermite form by the dense solve),
    while a tall M of low degree (28×24 of degree 2) is the case it is made for.

    >>> worthwhile(24, 2), worthwhile(2, 127)
    (True, False)
    """
    return 0 < dm <= n


#: The points α tried for the substitution δ → δ + α when ``M_R(0)`` is singular.
SHIFTS = (1, -1, 2, -2, 3, -3)


def _shift_point(mi: IntCoeffs, rest: list[int], n: int) -> int | None:
    """The first α of 0 and :data:`SHIFTS` with ``M_R(α)`` nonsingular modulo the first
    word prime, or None (then ``M_R`` is singular at all of them modulo p)."""
    p = word_primes(1)[0]
    for alpha in (0, *SHIFTS):
        vals = [sum(int(c) * pow(alpha, s, p) for s, c in enumerate(mi[j][col])) % p for j in rest for col in range(n)]
        if flint.nmod_mat(n, n, vals, p).det() != 0:
            return alpha
    return None


def _taylor_shift(cs: list[Any], alpha: int) -> list[Any]:
    """The coefficients of c(δ + α), as many as those of c (integers).

    >>> _taylor_shift([1, 2, 1], -1)     # (δ − 1 + 1)² = δ²
    [0, 0, 1]
    """
    got = flint.fmpz_poly(cs)(flint.fmpz_poly([alpha, 1])).coeffs() if any(cs) else []
    return list(got) + [0] * (len(cs) - len(got))


def _solve_core(
    mi: IntCoeffs, dm: int, m: int, n: int, D: int, lead: dict[int, int], b: list[list[Any]], k: int,
) -> tuple[list[list[list[Any]]], flint.fmpz] | str | None:
    """:func:`solve_reduced_crt` once ``A_0`` is known nonsingular modulo the first prime."""
    piv = sorted(lead)
    rest = [j for j in range(m) if j not in lead]
    blocks = _Blocks.of(mi, dm, n, D, piv, lead, b, k)
    pu = blocks.pu
    columns = [e * m + j for j in rest for e in range(D + 1)] + [e * m + j for j, e in pu]
    bound = _hadamard_bits(mi, m, columns, [[b[r][v] for r in range(len(b))] for v in range(k)])
    up = blocks.up
    primes = word_primes(bound // 60 + 12)
    sel = None  # the columns C, as a wide × u_P 0/1 matrix
    delta = flint.fmpz(0)
    y_p = flint.fmpz_mat(k, up)
    modulus = flint.fmpz(1)
    with _progress.detail(f"a {n * (D + 1) + up}-unknown Toeplitz system modulo primes") as tell:
        for count, p in enumerate(primes, 1):
            tell(f"prime {count} of at most {len(primes)}")
            got = _solve_mod_p(p, blocks, sel)
            if got is None:
                if sel is None:
                    return None  # A_0 or E_G singular modulo the first prime
                continue  # an unlucky prime for the fixed subsystem
            if isinstance(got, str):
                return NO_SOLUTION
            x_p, det_p, sel = got
            half = p // 2
            if modulus == 1:  # an integral solution of small entries is its own residue
                small = [v if v <= half else v - p for v in map(int, x_p.entries())]
                if all(-SMALL < v < SMALL for v in small):
                    one = flint.fmpz(1)
                    y_one = flint.fmpz_mat(k, up, small)
                    done = _finish(one, y_one, blocks)
                    if done is not None:
                        return _rows(done, y_one, one, rest, pu, m, D, k), one
            if modulus != 1 and int(delta % p) == det_p and flint.nmod_mat(y_p, p) == x_p * det_p:
                done = _finish(delta, y_p, blocks)
                if done is not None:
                    return _rows(done, y_p, delta, rest, pu, m, D, k), delta
            # Garner: the remainders modulo modulus·p, symmetric
            inv = pow(int(modulus % p), -1, p)
            t_delta = (det_p - int(delta % p)) * inv % p
            delta += modulus * (t_delta if t_delta <= p // 2 else t_delta - p)
            diff = (x_p * det_p - flint.nmod_mat(y_p, p)) * inv
            y_p += flint.fmpz_mat(k, up, [v if v <= half else v - p for v in map(int, diff.entries())]) * modulus
            modulus *= p
            if modulus.bit_length() > bound + 1:
                done = _finish(delta, y_p, blocks)
                if done is None:  # pragma: no cover - exact remainders of a solution pass the check
                    return None
                return _rows(done, y_p, delta, rest, pu, m, D, k), delta
        return None  # pragma: no cover - the primes exceed the bound


@dataclass
class _Blocks:
    """The integer matrices of the elimination modulo p (module text), built once.

    ``g_t = −Σ_s g_(t−s)·A_s·A_0⁻¹ − H_t·A_0⁻¹`` is computed for the q pivot rows
    (j, 0) only: the unknown (j, e) is the shift δ^e of (j, 0), and the recurrence is
    shift invariant, so its row of G_t is row (j, 0) of G_(t−e) (zero for t < e).  The
    tail then reads ``E_G = −H_cat − Σ_w 𝒢_w·A_cat,w`` with ``𝒢_w`` the rows
    ``G^j_(D−e−w)`` for the unknowns (j, e), gathered from the ``g_u`` into ``g_star``
    (rows ``G^j_(D−e)``, e < d_j + dm − 1) and selected by ``sel_w``; and
    ``E_F = B_cat − Σ_v F_(D−v)·A_cat,v``, where ``A_cat,v`` holds ``A_(i+v)`` in block
    i = 1, …, dm (zero beyond dm)."""

    a: list[flint.fmpz_mat]  # A_s, n × n
    b: list[flint.fmpz_mat]  # B_t, k × n, t = 0, …, D + dm
    hb: list[flint.fmpz_mat]  # −H_t on the rows (j, 0), q × n, t = 0, …, dm
    acat: list[flint.fmpz_mat]  # A_cat,v, n × n·dm, v = 0, …, dm − 1
    bcat: flint.fmpz_mat  # B_(D+i) in block i, k × n·dm
    hcat: flint.fmpz_mat  # row (j, e), block i: coefficient D + i − e of M[j]; u_P × n·dm
    place: list[tuple[int, flint.fmpz_mat]]  # (u, g_star rows ← g_u)
    sel: list[flint.fmpz_mat]  # sel_w: u_P × rows of g_star
    pu: list[tuple[int, int]]  # the unknowns (j, e), e < d_j, of x_P, in the order of X_P's columns
    by_degree: list[list[tuple[int, int]]]  # for each e: (jj, column of (piv[jj], e) in X_P)
    D: int
    dm: int
    k: int
    up: int

    @classmethod
    def of(cls, mi: IntCoeffs, dm: int, n: int, D: int, piv: list[int], lead: dict[int, int],
           b: list[list[Any]], k: int) -> _Blocks:
        """The matrices for M (integer coefficients ``mi``, degree dm; ``piv``: the
        kernel's pivots, the others are the rows R, in order) and the right-hand sides ``b``
        (as for :func:`solve_reduced_crt`)."""
        rest = [j for j in range(len(mi)) if j not in lead]
        pu = [(j, e) for j in piv for e in range(lead[j])]
        q, up, wide, nt = len(piv), len(pu), dm * n, D + dm + 1
        a_lists: list[list[Any]] = [[0] * (n * n) for _ in range(dm + 1)]
        for r, j in enumerate(rest):
            for col, cs in enumerate(mi[j]):
                for s, x in enumerate(cs):
                    a_lists[s][r * n + col] = x
        b_lists = [[b[t * n + col][v] for v in range(k) for col in range(n)] for t in range(nt)]

        def coef(j: int, col: int, s: int) -> Any:
            cs = mi[j][col]
            return cs[s] if 0 <= s < len(cs) else 0

        hb = [flint.fmpz_mat(q, n, [-coef(j, col, t) for j in piv for col in range(n)]) for t in range(dm + 1)]
        acat = []
        for v in range(dm):
            xs: list[Any] = [0] * (n * wide)
            for i in range(1, dm - v + 1):
                src = a_lists[i + v]
                for r in range(n):
                    xs[r * wide + (i - 1) * n:r * wide + i * n] = src[r * n:(r + 1) * n]
            acat.append(flint.fmpz_mat(n, wide, xs))
        bcat = flint.fmpz_mat(k, wide, [b_lists[D + i][v * n + col] for v in range(k)
                                        for i in range(1, dm + 1) for col in range(n)])
        hcat = flint.fmpz_mat(up, wide, [coef(j, col, D + i - e) for j, e in pu
                                         for i in range(1, dm + 1) for col in range(n)])
        star = [(jj, e) for jj, j in enumerate(piv) for e in range(lead[j] + dm - 1)]
        row_of = {x: r for r, x in enumerate(star)}
        place = []
        for u in range(D + 1):
            hits = [(r, jj) for r, (jj, e) in enumerate(star) if D - e == u]
            if hits:
                xs = [0] * (len(star) * q)
                for r, jj in hits:
                    xs[r * q + jj] = 1
                place.append((u, flint.fmpz_mat(len(star), q, xs)))
        jj_of = {j: jj for jj, j in enumerate(piv)}
        sel = []
        for w in range(dm):
            xs = [0] * (up * len(star))
            for r, (j, e) in enumerate(pu):
                xs[r * len(star) + row_of[jj_of[j], e + w]] = 1
            sel.append(flint.fmpz_mat(up, len(star), xs))
        by_degree: list[list[tuple[int, int]]] = [[] for _ in range(max(lead.values()))]
        for c, (j, e) in enumerate(pu):
            by_degree[e].append((jj_of[j], c))
        return cls([flint.fmpz_mat(n, n, x) for x in a_lists], [flint.fmpz_mat(k, n, xs) for xs in b_lists],
                   hb, acat, bcat, hcat, place, sel, pu, by_degree, D, dm, k, up)


def _solve_mod_p(
    p: int, bl: _Blocks, sel: flint.fmpz_mat | None,
) -> tuple[flint.nmod_mat, int, flint.fmpz_mat] | str | None:
    """``(X_P mod p, Δ mod p, C)`` by the block elimination of the module text (C chosen
    here when ``sel`` is None); None when A_0 or ``E_G[:, C]`` is singular modulo p;
    :data:`NO_SOLUTION` when the remaining equations are inconsistent modulo p."""
    D, dm, up = bl.D, bl.dm, bl.up
    a = [flint.nmod_mat(x, p) for x in bl.a]
    try:
        a0inv = a[0].inv()
    except ZeroDivisionError:
        return None
    f: list[flint.nmod_mat] = []
    g: list[flint.nmod_mat] = []
    for t in range(D + 1):
        acc_f = flint.nmod_mat(bl.b[t], p)
        acc_g = flint.nmod_mat(bl.hb[t], p) if t <= dm else None
        for s in range(1, min(t, dm) + 1):
            acc_f -= f[t - s] * a[s]
            acc_g = -(g[t - s] * a[s]) if acc_g is None else acc_g - g[t - s] * a[s]
        f.append(acc_f * a0inv)
        assert acc_g is not None
        g.append(acc_g * a0inv)
    acat = [flint.nmod_mat(x, p) for x in bl.acat]
    ef = flint.nmod_mat(bl.bcat, p)
    for v in range(min(dm, D + 1)):
        ef -= f[D - v] * acat[v]
    star = None
    for u, pl in bl.place:
        part = flint.nmod_mat(pl, p) * g[u]
        star = part if star is None else star + part
    assert star is not None
    eg = -flint.nmod_mat(bl.hcat, p)
    for w in range(dm):
        eg -= flint.nmod_mat(bl.sel[w], p) * star * acat[w]
    if sel is None:
        red, rank = eg.rref()
        if rank < up:
            return None
        cols = []
        r = 0
        for c in range(eg.ncols()):
            if r < rank and red[r, c] != 0:
                cols.append(c)
                r += 1
        sel = flint.fmpz_mat(eg.ncols(), up, [int(cols[i] == r) for r in range(eg.ncols()) for i in range(up)])
    sel_p = flint.nmod_mat(sel, p)
    sq = eg * sel_p
    det_s = int(sq.det())
    if det_s == 0:
        return None
    # x_p·sq = −ef·sel_p by one LU solve of the transpose (256 unknowns, 16 right-hand
    # sides: 7 ms, against 25 ms for sq⁻¹ and the product)
    x_p = -((sq.transpose().solve((ef * sel_p).transpose())).transpose())
    if x_p * eg != -ef:
        return NO_SOLUTION
    det_p = int(a[0].det()) ** (D + 1) * det_s % p
    return x_p, det_p, sel


def _finish(delta: flint.fmpz, y_p: flint.fmpz_mat, bl: _Blocks) -> list[flint.fmpz_mat] | None:
    """``Y_R,t = Δ·X_R,t`` for t = 0, …, D from the recurrence over Z, and the exact check of
    ``Y·M = Δ·B``; None when a division is not exact or the check fails (a wrong candidate).

    Each ``Y_R,t`` is ``acc_t·A_0⁻¹`` with ``acc_t = Δ·B_t − Y_P·H_t − Σ_s Y_R,t−s·A_s``,
    computed as ``acc_t·N/d`` (``A_0⁻¹ = N/d``) with an exact division, which fails
    (DomainError) unless the quotient is integral; so ``Y_R,t·A_0 = acc_t`` holds exactly,
    which is coefficient t ≤ D of ``Y·M = Δ·B``.  The coefficients t = D + 1, …, D + dm are
    compared here: all of ``Y·M = Δ·B`` then holds exactly.  ``Y_P·H_t`` is
    ``Σ_e Y^(e)·M_P,t−e`` with ``Y^(e)`` the columns (j, e) of Y_P (the shift structure of
    :class:`_Blocks`)."""
    if delta == 0:
        return None
    D, dm, k = bl.D, bl.dm, bl.k
    num0, den0 = flint.fmpq_mat(bl.a[0]).inv().numer_denom()
    q = bl.hb[0].nrows()
    ent = y_p.entries()
    ys = []
    for cols in bl.by_degree:
        xs: list[Any] = [0] * (k * q)
        for jj, c in cols:
            for v in range(k):
                xs[v * q + jj] = ent[v * bl.up + c]
        ys.append(flint.fmpz_mat(k, q, xs))

    def minus_yh(t: int) -> flint.fmpz_mat:  # −Y_P·H_t (hb = −M_P)
        acc = None
        for e in range(max(t - dm, 0), min(t, len(ys) - 1) + 1):
            part = ys[e] * bl.hb[t - e]
            acc = part if acc is None else acc + part
        return acc if acc is not None else flint.fmpz_mat(k, bl.hb[0].ncols())

    yr: list[flint.fmpz_mat] = []
    try:
        for t in range(D + 1):
            acc = bl.b[t] * delta + minus_yh(t)
            for s in range(1, min(t, dm) + 1):
                acc -= yr[t - s] * bl.a[s]
            yr.append(acc * num0 / den0)
    except DomainError:  # not an exact division
        return None
    for t in range(D + 1, D + dm + 1):
        acc = bl.b[t] * delta + minus_yh(t)
        for e in range(max(t - dm, 0), D + 1):
            acc -= yr[e] * bl.a[t - e]
        if not acc.is_zero():
            return None
    return yr


def _rows(
    yr: list[flint.fmpz_mat], y_p: flint.fmpz_mat, delta: flint.fmpz, rest: list[int],
    pu: list[tuple[int, int]], m: int, D: int, k: int,
) -> list[list[list[Any]]]:
    """The k rows of Δ·X as coefficient lists (integers, low to high, D + 1 of them)."""
    coeffs: list[list[list[Any]]] = [[[0] * (D + 1) for _ in range(m)] for _ in range(k)]
    for e, blk in enumerate(yr):
        vals = blk.entries()
        n = len(rest)
        for v in range(k):
            row = coeffs[v]
            for i, j in enumerate(rest):
                row[j][e] = vals[v * n + i]
    vals = y_p.entries()
    up = len(pu)
    for v in range(k):
        row = coeffs[v]
        for i, (j, e) in enumerate(pu):
            row[j][e] = vals[v * up + i]
    return coeffs
