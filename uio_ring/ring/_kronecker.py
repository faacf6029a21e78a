"""Product of polynomial matrices over Q[δ] by Kronecker substitution: one integer
matrix product in C.

Clear denominators by a scale per row of A and per column of B (``A = D_A⁻¹·Â``,
``B = B̂·D_B⁻¹`` with Â, B̂ over Z[δ]), substitute ``δ = 2^s`` into every entry, multiply
the two integer matrices (``fmpz_mat`` product: flint's classical, Strassen or
multimodular algorithm, in C), and read each entry of ``Â(2^s)·B̂(2^s)`` back as the
base-2^s digits of ``(Â·B̂)(δ)``.  The digits are exact when every coefficient of
``Â·B̂`` has absolute value < 2^(s−1): with ``|â| < 2^α``, ``|b̂| < 2^β`` and k terms
of at most ``1 + min(deg Â, deg B̂)`` products each, ``s = α + β + bitlen(k·(1 + min
deg)) + 2`` suffices (rounded up to whole bytes).  Adding 2^(s−1) to every digit makes
them all non-negative, so the digits are byte slices of one integer.  (Kronecker 1882;
Schönhage 1982; von zur Gathen & Gerhard, *Modern Computer Algebra*, §8.4.)

Cost: one m×k by k×n integer product with entries of about ``(1 + deg)·s`` bits, and
O(m·k + k·n + m·n) Python steps to pack and unpack, each linear in the size of its
integer (packing shifts and adds the coefficients; flint's evaluation at ``2^s`` by Horner
would be quadratic: 1.4 s instead of 0.2 s for the 216×32 Krylov matrix of degree 23 and
1400-bit coefficients of a 32-state design) — against m·k·n polynomial
products, each a Python call, in the entry-by-entry loop (a 9×32 by 32×32 product of
degree 1: 19 ms → 2 ms).

>>> from uio_ring.ring import _backend as bk
>>> d = bk.from_coeffs([0, 1])
>>> a = [[d + 1, bk.const(-2)]]
>>> b = [[d - 1], [d / 3]]
>>> bk.to_str(matmul_kronecker(a, b, 1, 2, 1)[0][0], "d")    # (δ + 1)(δ − 1) − 2δ/3
'd**2 - 2*d/3 - 1'
"""

from __future__ import annotations

import flint

from uio_ring.ring import _backend as bk

__all__ = ["matmul_kronecker", "matmul_stacked", "scaled_numerator"]

Rows = list[list[flint.fmpq_poly]]


def scaled_numerator(p: flint.fmpq_poly, c: flint.fmpz) -> flint.fmpz_poly:
    """``p·c`` for a multiple c of the denominator of p, as an integer polynomial: the
    numerator times ``c / den`` (an exact quotient), without the content gcd that the
    product ``p * c`` of fmpq_poly computes to put its result in canonical form.

    >>> scaled_numerator(flint.fmpq_poly([1, 2], 3), flint.fmpz(6))
    4*x + 2
    """
    q = p.denom()
    return p.numer() * (c // q) if q != c else p.numer()


def _value_at_power_of_two(p: flint.fmpz_poly, s: int) -> int:
    """``p(2^s)`` as the sum of the shifted coefficients: linear in the size of the result
    (flint's Horner evaluation at a large point multiplies full-size numbers, quadratic).

    >>> _value_at_power_of_two(flint.fmpz_poly([3, -1, 2]), 8) == 3 - 2**8 + 2 * 2**16
    True
    """
    return sum(int(c) << (s * e) for e, c in enumerate(p.coeffs()))


#: The coefficient-stacked product (:func:`_matmul_stacked`) is taken when one factor has
#: δ-degree at most this (or by the rule of :func:`_stack_wins`) and coefficients of at
#: most ``STACK_MAX_BITS`` bits.  The bit bound was 128; on the supports of the products
#: (see :func:`matmul_kronecker`) the stacked product also won with big coefficients on
#: both sides: Ō_L⁻¹·Ō of a 32-state design (32×32×32, degrees 1 and 23, 1579- and
#: 1418-bit) 0.49 s → 0.40 s, C̄Ā^l·Ō_L⁻¹ (9×32×32, degrees 24 and 1) 0.32 s → 0.12 s, so
#: it is now only a safety cap.
STACK_MAX_DEGREE = 2
STACK_MAX_BITS = 1 << 20


#: From this many bits in the larger coefficients on, the stacked product is also taken when
#: ``STACK_BITS_PER_PRODUCT·(min deg + 1)·⌈min bits / 64⌉`` does not exceed them
#: (:func:`_stack_wins`).
STACK_MIN_BIG_BITS = 2048
#: The bits of the larger coefficients that pay for one coefficient product of the stack
#: against the Kronecker product (:func:`_stack_wins`).
STACK_BITS_PER_PRODUCT = 24


def _stack_wins(da: int, db: int, alpha: int, beta: int, s: int) -> bool:
    """Whether the coefficient-stacked product beats the Kronecker one: one factor of
    δ-degree at most ``STACK_MAX_DEGREE``, or ``(min deg + 1)·⌈min bits / 64⌉ ≤
    log₂((max deg + 1)·s)``, or — big coefficients against small ones — ``max bits ≥
    STACK_MIN_BIG_BITS`` and ``STACK_BITS_PER_PRODUCT·(min deg + 1)·⌈min bits / 64⌉ ≤ max
    bits``.  Per entry product the stack multiplies (min deg + 1)·(max deg + 1) coefficient
    pairs, each about as costly as the larger coefficient times the smaller one's limbs;
    the Kronecker product multiplies two numbers of (max deg + 1)·s bits, whose FFT costs
    about that many bits times their logarithm, and pads the small coefficients to s bits.
    Measured (CPU, n×n by n×n, n = 8, 16, 32; degree/bits of the factors): 240/6000 by 16/3, 8.3 → 2.0 s
    at n = 16 (the check U·M = H of a 16×16 Hermite form of degree 16); 120/8000 by 8/3,
    7.5–8.4× faster; 32/3000 by 8/4, 4.0–6.6×; 16/1000 by 4/4, 1.2–4.6×; but 64/500 by
    16/3, 0.6–0.95× (log₂ = 15 < 17: Kronecker), 16/1000 twice, 0.4–0.8× (Kronecker).
    The third rule (1×16 by 16×16 and squares up to 16×16×16, big factor of degree 60–300):
    300/2000–16000 by 32/3, 32/20 and 64/3, 1.65–5× faster stacked (the second rule said
    Kronecker from degree 32 on); 8×8 by 8×8, 300/2500 by 64/20, 1.3×; 4×32 by 32×32,
    200/8000 by 32/3, 4.4 against 20.6 s; at 500 bits it would not pay (300/500 by 64/3,
    0.6×)."""
    low, high = min(da, db), max(da, db)
    if low <= STACK_MAX_DEGREE:
        return True
    products = (low + 1) * -(-min(alpha, beta) // 64)
    if max(alpha, beta) >= STACK_MIN_BIG_BITS and STACK_BITS_PER_PRODUCT * products <= max(alpha, beta):
        return True
    return products <= ((high + 1) * s).bit_length() - 1


def _matmul_stacked(
    an: list[list[flint.fmpz_poly]], bn: list[list[flint.fmpz_poly]], m: int, k: int, n: int,
    da: int, db: int, row_scale: list[flint.fmpz], col_scale: list[flint.fmpz],
) -> Rows:
    """``(Â·B̂)`` scaled back, from one integer product of a coefficient stack of the factor
    of higher degree and a block-Toeplitz matrix of the other.  With ``L = da + db + 1``:
    when ``da ≥ db``, ``T_A`` (m·L × k·(db+1)) has entry ``â_(i,t)`` coefficient ``c − f`` at
    row (c, i), column (f, t), and ``P_B`` (k·(db+1) × n) the δ^f-coefficient of ``b̂_(t,j)``
    at row (f, t); then ``(T_A P_B)[(c, i), j] = Σ_f Σ_t â_(i,t),c−f · b̂_(t,j),f`` is the
    δ^c-coefficient of entry (i, j) of Â·B̂ — exact integer sums, no digit bound — and the
    L coefficients of that entry are one stride of the flat product (a Python slice).
    When ``da < db`` the roles swap (``P_A`` m × k·(da+1) times ``T_B``
    k·(da+1) × L·n).  When one factor has low degree and small coefficients this
    multiplies big coefficients by small ones, where the Kronecker product multiplies two
    numbers of the big size (Ō-block times Ā of a 32-state design, 9×32 by 32×32 of
    degrees 23 and 1: about 4× faster).  Cost: one ``fmpz_mat`` product of
    m·k·n·L·(min(da, db) + 1) entry products (the zeros of the Toeplitz blocks included:
    L / (max(da, db) + 1) < 2 times the products of the plain coefficient stacks, close
    to 1 when the degrees are far apart) and O(m·L·k + k·n) Python steps to pack, m·n
    slices to unpack.
    """
    length = da + db + 1
    if da >= db:
        acs = [[p.coeffs() for p in row] for row in an]
        ta = flint.fmpz_mat(m * length, k * (db + 1), [
            cs[c - f] if 0 <= c - f < len(cs) else 0
            for c in range(length) for i in range(m) for f in range(db + 1) for cs in acs[i]
        ])
        bcs = [[p.coeffs() for p in row] for row in bn]
        pb = flint.fmpz_mat(k * (db + 1), n, [
            cs[f] if f < len(cs) else 0 for f in range(db + 1) for t in range(k) for cs in bcs[t]
        ])
        flat = (ta * pb).entries()  # index ((c·m + i)·n + j)
        stride = m * n
        return [[flint.fmpq_poly(flat[i * n + j::stride], row_scale[i] * col_scale[j]) for j in range(n)]
                for i in range(m)]
    acs = [[p.coeffs() for p in row] for row in an]
    pa = flint.fmpz_mat(m, k * (da + 1), [
        cs[e] if e < len(cs) else 0 for i in range(m) for e in range(da + 1) for cs in acs[i]
    ])
    bcs = [[p.coeffs() for p in row] for row in bn]
    tb = flint.fmpz_mat(k * (da + 1), length * n, [
        cs[c - e] if 0 <= c - e < len(cs) else 0
        for e in range(da + 1) for t in range(k) for c in range(length) for cs in bcs[t]
    ])
    flat = (pa * tb).entries()  # index (i·L·n + c·n + j)
    width = length * n
    return [[flint.fmpq_poly(flat[i * width + j:(i + 1) * width:n], row_scale[i] * col_scale[j]) for j in range(n)]
            for i in range(m)]


def matmul_kronecker(a: Rows, b: Rows, m: int, k: int, n: int) -> Rows:
    """``a @ b`` for a (m×k) and b (k×n), exactly (see the module text), on the support:
    the inner indices t where column t of a and row t of b are both nonzero, the rows of a
    and the columns of b that are nonzero there (the other entries of the product are
    zero).  A left inverse reduced modulo a constant kernel basis is zero outside n_x of
    its columns: Ō_L⁻¹·Ō of a 32-state design, 32×216 by 216×32, is a 32×32 by 32×32
    product (0.95 s → 0.15 s).  Precondition: shapes fit, m, k, n ≥ 1 (not checked)."""
    got = _on_support(a, b, m, k, n, stacked_only=False)
    assert got is not None  # only ``stacked_only`` declines
    return got


def matmul_stacked(a: Rows, b: Rows, m: int, k: int, n: int) -> Rows | None:
    """:func:`matmul_kronecker` when it would take the coefficient-stacked product
    (:func:`_stack_wins`), else None: for few entry products, which
    :func:`~uio_ring.ring._dense.matmul` otherwise forms one by one — flint's product of a
    polynomial with big coefficients by one with small ones pads the small coefficients to
    the size of the big ones (Kronecker substitution): Δ_k·B of a 32-state check, 1×32 by
    32×8 with 17-kbit coefficients of degree 500 against 2-bit ones of degree 16, 6.0 s
    entry by entry, 0.9 s stacked.  Precondition: shapes fit, m, k, n ≥ 1 (not checked)."""
    return _on_support(a, b, m, k, n, stacked_only=True)


def _on_support(a: Rows, b: Rows, m: int, k: int, n: int, *, stacked_only: bool) -> Rows | None:
    """:func:`_matmul_packed` on the support (:func:`matmul_kronecker`)."""
    inner = [t for t in range(k) if any(not p.is_zero() for p in b[t]) and any(not r[t].is_zero() for r in a)]
    rows = [i for i in range(m) if any(not a[i][t].is_zero() for t in inner)]
    cols = [j for j in range(n) if any(not b[t][j].is_zero() for t in inner)]
    if not rows or not cols:
        return [[bk.ZERO] * n for _ in range(m)]
    if len(inner) == k and len(rows) == m and len(cols) == n:
        return _matmul_packed(a, b, m, k, n, stacked_only=stacked_only)
    part = _matmul_packed([[a[i][t] for t in inner] for i in rows], [[b[t][j] for j in cols] for t in inner],
                          len(rows), len(inner), len(cols), stacked_only=stacked_only)
    if part is None:
        return None
    out = [[bk.ZERO] * n for _ in range(m)]
    for i, prow in zip(rows, part, strict=True):
        orow = out[i]
        for j, v in zip(cols, prow, strict=True):
            orow[j] = v
    return out


def _matmul_packed(a: Rows, b: Rows, m: int, k: int, n: int, *, stacked_only: bool = False) -> Rows | None:
    """:func:`matmul_kronecker` on all indices; None when ``stacked_only`` and the rule
    takes the Kronecker product.  Precondition: shapes fit, m, k, n ≥ 1 (not checked)."""
    row_scale = [bk.denominator_lcm(a[i]) for i in range(m)]
    col_scale = [bk.denominator_lcm(b[t][j] for t in range(k)) for j in range(n)]
    an = [[scaled_numerator(a[i][t], row_scale[i]) for t in range(k)] for i in range(m)]
    bn = [[scaled_numerator(b[t][j], col_scale[j]) for j in range(n)] for t in range(k)]
    da = max((p.degree() for r in an for p in r), default=-1)
    db = max((p.degree() for r in bn for p in r), default=-1)
    if da < 0 or db < 0:
        return [[bk.ZERO] * n for _ in range(m)]
    alpha = max(p.height_bits() for r in an for p in r)  # bits of the largest |coefficient|
    beta = max(p.height_bits() for r in bn for p in r)
    s = alpha + beta + (k * (1 + min(da, db))).bit_length() + 2
    s = -(-s // 8) * 8
    if min(alpha, beta) <= STACK_MAX_BITS and _stack_wins(da, db, alpha, beta, s):
        return _matmul_stacked(an, bn, m, k, n, da, db, row_scale, col_scale)
    if stacked_only:
        return None
    pa = flint.fmpz_mat(m, k, [_value_at_power_of_two(p, s) for r in an for p in r])
    pb = flint.fmpz_mat(k, n, [_value_at_power_of_two(p, s) for r in bn for p in r])
    prod = pa * pb
    digits = da + db + 1
    nbytes = s // 8
    half = 1 << (s - 1)
    offset = sum(half << (s * e) for e in range(digits))
    out: Rows = []
    for i in range(m):
        row = []
        for j in range(n):
            v = int(prod[i, j])
            if v == 0:
                row.append(bk.ZERO)
                continue
            raw = (v + offset).to_bytes(nbytes * digits, "little")
            cs = [int.from_bytes(raw[e * nbytes:(e + 1) * nbytes], "little") - half for e in range(digits)]
            row.append(flint.fmpq_poly(cs, row_scale[i] * col_scale[j]))
        out.append(row)
    return out
