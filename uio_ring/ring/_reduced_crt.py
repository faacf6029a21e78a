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
correctness.  With |Δ|, |Y| ≤ 2^H (H: Hadamard's bound of T' with b,
:func:`_hadamard_bits`), the remainders are exact once the product of the primes
exceeds 2^(H+1), so the loop ends there at the latest.  Since T' is nonsingular modulo
each prime used, a solution over Q reduces modulo p to the unique one modulo p, and an
inconsistency modulo p proves that no solution exists (the argument of
:func:`~uio_ring.ring._kernel_basis._consistent_mod_p`).  A 28×24 matrix of degree 2
with 24 right-hand sides (X of 1078-bit numerators and a 1074-bit denominator): 20
primes of 61 bits, about 2 ms each.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> from uio_ring.ring._kernel_basis import _integer_coefficients
>>> M = PolyMatrix("[[1], [d], [d**2 + 1]]")    # kernel [d, −1, 0], [1, d, −1]: pivots 0, 1
>>> b = [[1], [0], [0], [0]]                    # B = 1: coefficients 0, …, D + 2 (D = 1)
>>> # Δ·X = [1, 0, 0] and Δ = 1 (entries of X as coefficient lists, degrees 0 and 1)
>>> solve_reduced_crt(_integer_coefficients(M._r, 3, 1), 2, 3, 1, 1, {0: 1, 1: 1}, b, 1)
([[[1, 0], [0, 0], [0, 0]]], 1)
"""

from __future__ import annotations

import math
from typing import Any

import flint
from flint.utils.flint_exceptions import DomainError

IntCoeffs = list[list[list[Any]]]  # [row j][column l] -> integer coefficients, low to high

__all__ = ["solve_reduced_crt", "NO_SOLUTION", "word_primes"]

#: Returned when a prime proves that ``X·M = B`` has no solution of degree ≤ D.
NO_SOLUTION = "no solution"

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
    exactly before returning."""
    piv = sorted(lead)
    rest = [j for j in range(m) if j not in lead]
    if len(rest) != n or not lead or D < max(lead.values()) or dm == 0 or not any(lead.values()):
        return None
    # P-unknowns (j, e), e < d_j, and the integer blocks of the recurrence
    pu = [(j, e) for j in piv for e in range(lead[j])]
    up = len(pu)
    nt = D + dm + 1

    def coef(j: int, col: int, s: int) -> Any:
        cs = mi[j][col]
        return cs[s] if 0 <= s < len(cs) else 0

    a_int = [flint.fmpz_mat(n, n, [coef(j, col, s) for j in rest for col in range(n)]) for s in range(dm + 1)]
    h_int = [flint.fmpz_mat(up, n, [coef(j, col, t - e) for j, e in pu for col in range(n)]) for t in range(nt)]
    b_int = [flint.fmpz_mat(k, n, [b[t * n + col][v] for v in range(k) for col in range(n)]) for t in range(nt)]
    r_int = [flint.fmpz_mat(k + up, n, [b[t * n + col][v] for v in range(k) for col in range(n)]
                            + [-coef(j, col, t - e) for j, e in pu for col in range(n)]) for t in range(nt)]
    # 0/1 matrices: the tail blocks side by side, the top k / bottom u_P rows
    wide = dm * n
    emb = [flint.fmpz_mat(n, wide, [int(c == i * n + r) for r in range(n) for c in range(wide)]) for i in range(dm)]
    top = flint.fmpz_mat(k, k + up, [int(c == r) for r in range(k) for c in range(k + up)])
    bot = flint.fmpz_mat(up, k + up, [int(c == k + r) for r in range(up) for c in range(k + up)])
    columns = [e * m + j for j in rest for e in range(D + 1)] + [e * m + j for j, e in pu]
    bound = _hadamard_bits(mi, m, columns, [[b[r][v] for r in range(len(b))] for v in range(k)])

    sel = None  # the columns C, as a wide × u_P 0/1 matrix
    delta = flint.fmpz(0)
    y_p = flint.fmpz_mat(k, up)
    modulus = flint.fmpz(1)
    primes = word_primes(bound // 60 + 12)
    for p in primes:
        got = _solve_mod_p(p, a_int, r_int, emb, top, bot, D, dm, k, up, sel)
        if got is None:
            if sel is None:
                return None  # A_0 or E_G singular modulo the first prime
            continue  # an unlucky prime for the fixed subsystem
        if isinstance(got, str):
            return NO_SOLUTION
        x_p, det_p, sel = got
        if modulus != 1 and int(delta % p) == det_p and flint.nmod_mat(y_p, p) == x_p * det_p:
            done = _finish(delta, y_p, a_int, h_int, b_int, D, dm, k)
            if done is not None:
                return _rows(done, y_p, delta, rest, pu, m, D, k), delta
        # Garner: the remainders modulo modulus·p, symmetric
        inv = pow(int(modulus % p), -1, p)
        t_delta = (det_p - int(delta % p)) * inv % p
        delta += modulus * (t_delta if t_delta <= p // 2 else t_delta - p)
        diff = (x_p * det_p - flint.nmod_mat(y_p, p)) * inv
        half = p // 2
        y_p += flint.fmpz_mat(k, up, [v if v <= half else v - p for v in map(int, diff.entries())]) * modulus
        modulus *= p
        if modulus.bit_length() > bound + 1:
            done = _finish(delta, y_p, a_int, h_int, b_int, D, dm, k)
            if done is None:  # pragma: no cover - exact remainders of a solution pass the check
                return None
            return _rows(done, y_p, delta, rest, pu, m, D, k), delta
    return None  # pragma: no cover - the primes exceed the bound


def _solve_mod_p(
    p: int, a_int: list[flint.fmpz_mat], r_int: list[flint.fmpz_mat], emb: list[flint.fmpz_mat],
    top: flint.fmpz_mat, bot: flint.fmpz_mat, D: int, dm: int, k: int, up: int,
    sel: flint.fmpz_mat | None,
) -> tuple[flint.nmod_mat, int, flint.fmpz_mat] | str | None:
    """``(X_P mod p, Δ mod p, C)`` by the block elimination of the module text (C chosen
    here when ``sel`` is None); None when A_0 or ``E_G[:, C]`` is singular modulo p;
    :data:`NO_SOLUTION` when the remaining equations are inconsistent modulo p."""
    a = [flint.nmod_mat(x, p) for x in a_int]
    try:
        a0inv = a[0].inv()
    except ZeroDivisionError:
        return None
    z: list[flint.nmod_mat] = []
    for t in range(D + 1):
        acc = flint.nmod_mat(r_int[t], p)
        for s in range(1, min(t, dm) + 1):
            acc -= z[t - s] * a[s]
        z.append(acc * a0inv)
    tail = None
    for i, t in enumerate(range(D + 1, D + dm + 1)):
        acc = flint.nmod_mat(r_int[t], p)
        for e in range(t - dm, D + 1):
            acc -= z[e] * a[t - e]
        part = acc * flint.nmod_mat(emb[i], p)
        tail = part if tail is None else tail + part
    assert tail is not None
    ef = flint.nmod_mat(top, p) * tail
    eg = flint.nmod_mat(bot, p) * tail
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
    x_p = -(ef * sel_p) * sq.inv()
    if x_p * eg != -ef:
        return NO_SOLUTION
    det_p = int(a[0].det()) ** (D + 1) * det_s % p
    return x_p, det_p, sel


def _finish(
    delta: flint.fmpz, y_p: flint.fmpz_mat, a_int: list[flint.fmpz_mat], h_int: list[flint.fmpz_mat],
    b_int: list[flint.fmpz_mat], D: int, dm: int, k: int,
) -> list[flint.fmpz_mat] | None:
    """``Y_R,t = Δ·X_R,t`` for t = 0, …, D from the recurrence over Z, and the exact check of
    every coefficient of ``Y·M = Δ·B``; None when a division is not exact or the check
    fails (a wrong candidate)."""
    if delta == 0:
        return None
    inv0 = flint.fmpq_mat(a_int[0]).inv()
    num0, den0 = inv0.numer_denom()
    yr: list[flint.fmpz_mat] = []
    try:
        for t in range(D + 1):
            acc = b_int[t] * delta - y_p * h_int[t]
            for s in range(1, min(t, dm) + 1):
                acc -= yr[t - s] * a_int[s]
            yr.append(acc * num0 / den0)
    except DomainError:  # not an exact division
        return None
    for t in range(len(b_int)):
        acc = y_p * h_int[t]
        for e in range(max(t - dm, 0), min(t, D) + 1):
            acc += yr[e] * a_int[t - e]
        if acc != b_int[t] * delta:
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
