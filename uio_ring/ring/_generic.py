"""Fast paths for the generic square case, by evaluation and interpolation.

For a nonsingular n×n matrix M the Hermite form is usually
``H = [[I, h], [0, δ_n]]`` with ``δ_n = det M / lc``.  That shape holds iff the
(n−1)-minors of the first n−1 columns are coprime, and it is *certified* here:

* ``c = adj(M)·r`` for a fixed rational vector r.  Its last entry is a Q-linear
  combination of those minors and ``det M`` is another (Laplace along the last
  column), so ``gcd(c_n, det M) = 1`` proves the shape.
* Every row ``e_i + h_i e_n`` of H lies in the row module, i.e.
  ``(e_i + h_i e_n)·adj(M) ≡ 0 (mod det M)``; with ``c`` this gives
  ``h_i ≡ −c_i·c_n⁻¹ (mod det M)``, and ``deg h_i < deg det M`` fixes h_i.
* ``U = H·M⁻¹ = H·adj(M)/det M`` is then polynomial.  adj(M) is interpolated
  from its exact values ``det M(x)·M(x)⁻¹`` (integers for an integer M: cheap
  rational products) at the degree bound of the (n−1)-minors plus one points,
  and ``U_i = (adj_i + h_i·adj_n) / det M``: the polynomial part of
  ``adj_n·h_i/det M`` from a power series when ``deg adj_i < deg det M``
  (:func:`_polynomial_parts`), else by exact division.
* ``V = [[I, −h], [0, 1]]`` gives ``H·V = diag(1, …, 1, δ_n)``: the Smith form.

All linear algebra runs over Q in C (flint).  Points are the fixed sequence
0, 1, −1, 2, …; a point where M(x) is singular is skipped.  When the certificate
fails (``None`` is returned) the callers fall back to elimination.
"""

from __future__ import annotations

import flint

from uio_ring.ring import _backend as bk
from uio_ring.ring import _dense as dn
from uio_ring.ring import _evaluation as ev

__all__ = [
    "generic_hermite",
    "generic_last_factor",
    "generic_invariant_factors",
    "generic_solve_left",
    "GENERIC_MIN_SIZE",
    "GENERIC_MIN_SIZE_FACTORS",
    "GENERIC_MIN_WORK",
    "generic_first",
]

#: Hermite/Smith with transforms: below this size elimination is as fast
#: (random degree-1/2 matrices: equal at n = 5, generic 1.6× faster at n = 8).
GENERIC_MIN_SIZE = 6
#: Invariant factors alone: the generic path wins from n = 4 (0.11 vs 0.16 ms, degree 2).
GENERIC_MIN_SIZE_FACTORS = 4
#: Below ``GENERIC_MIN_SIZE``, from n = 3 on, the generic path also goes first when
#: ``n³·deg ≥ GENERIC_MIN_WORK``: 3×3 from δ-degree 14, 4×4 from 6, 5×5 from 3.  The
#: elimination's remainders swell with the degree (random entries in [−3, 3], ms,
#: elimination / generic Hermite with U): 3×3 of degree 12 0.76 / 1.25, 16 2.5 / 2.4, 24
#: 12.6 / 7.4; 4×4 of degree 4 0.36 / 0.41, 6 1.23 / 0.90, 16 41 / 9.8, 32 781 / 52;
#: 5×5 of degree 2 0.35 / 0.34, 3 0.86 / 0.55, 16 462 / 32, 32 11 524 / 165, 64 329 439 /
#: 4265.  At 2×2 the pairwise extended gcd stays faster at every degree (degree 64: 1.3 /
#: 20.5).
GENERIC_MIN_WORK = 375


def generic_first(rows: dn.Rows, n: int) -> bool:
    """Whether a square n×n matrix tries the generic path before elimination (see
    ``GENERIC_MIN_SIZE`` and ``GENERIC_MIN_WORK``).

    >>> generic_first([[flint.fmpq_poly([1] * 7)] * 4] * 4, 4), generic_first([[flint.fmpq_poly([0, 1])] * 4] * 4, 4)
    (True, False)
    """
    if n >= GENERIC_MIN_SIZE:
        return True
    return n >= 3 and n**3 * dn.mat_degree(rows) >= GENERIC_MIN_WORK


def _sample(a: dn.Rows, n: int, count: int, need_inverse: bool):
    """Evaluate at the first ``count`` points where M(x) is nonsingular.

    Returns (xs, dets, inverses or solutions of M(x)·y = r with r = (1, 2, …, n)),
    or None if M is singular at too many points (then M is singular or unlucky).
    """
    coeffs = ev.coefficient_mats(a, n, n)
    rhs = flint.fmpq_mat(n, 1, [k + 1 for k in range(n)])
    xs, dets, sols = [], [], []
    misses = 0
    for x in ev.points():
        mx = ev.evaluate(coeffs, x)
        dx = mx.det()
        if dx == 0:
            misses += 1
            if misses > count + n:
                return None
            continue
        xs.append(x)
        dets.append(dx)
        sols.append(mx.inv() if need_inverse else mx.solve(rhs))
        if len(xs) == count:
            return xs, dets, sols
    return None  # pragma: no cover


def _adjugate_column(a: dn.Rows, n: int, need_inverse: bool):
    """det M and c = adj(M)·r as polynomials, plus the samples used."""
    dbound = ev.minor_degree_bound(a, n, n, n)
    sample = _sample(a, n, dbound + 1, need_inverse)
    if sample is None:
        return None
    xs, dets, sols = sample
    det = ev.interpolate_columns(flint.fmpq_mat(len(dets), 1, dets), xs)[0]
    if det.is_zero():
        return None
    rhs = flint.fmpq_mat(n, 1, [k + 1 for k in range(n)])
    cols = []
    for dx, s in zip(dets, sols, strict=True):
        y = s * rhs if need_inverse else s
        cols.append([dx * y[i, 0] for i in range(n)])
    abound = ev.minor_degree_bound(a, n, n, n - 1)
    k = abound + 1
    c = ev.interpolate_columns(flint.fmpq_mat(k, n, [v for row in cols[:k] for v in row]), xs[:k])
    return det, c, sample, abound


def generic_last_factor(a: dn.Rows, n: int) -> flint.fmpq_poly | None:
    """``monic(det M)`` if the invariant factors of M are (1, …, 1, det M / lc),
    certified by ``gcd(c_n, det M) = 1``; otherwise None."""
    got = _adjugate_column(a, n, need_inverse=False)
    if got is None:
        return None
    det, c, _, _ = got
    if not bk.gcd(c[n - 1], det).is_one():
        return None
    return bk.monic(det)


def _compressed_minor(a: dn.Rows, n: int, k: int, seed: int) -> flint.fmpq_poly:
    """``det(P·M·Q)`` for fixed pseudo-random integer P (k×n) and Q (n×k): a Q-linear
    combination of the k×k minors of M (Cauchy–Binet), by evaluation."""
    import random

    rng = random.Random(seed)  # fixed seed: the result depends only on M
    P = [[bk.const(rng.randint(-9, 9)) for _ in range(n)] for _ in range(k)]
    Q = [[bk.const(rng.randint(-9, 9)) for _ in range(k)] for _ in range(n)]
    coeffs = ev.coefficient_mats(dn.matmul(dn.matmul(P, a, k, n, n), Q, k, n, k), k, k)
    count = k * max(dn.mat_degree(a), 0) + 1
    ys = [ev.evaluate(coeffs, x).det() for x in ev.first_points(count)]
    return ev.interpolate_columns(flint.fmpq_mat(count, 1, ys))[0]


def generic_invariant_factors(a: dn.Rows, n: int) -> list[flint.fmpq_poly] | None:
    """Invariant factors of a nonsingular n×n M when at most two are non-trivial, else None.

    Tier 1: ``gcd(c_n, det) = 1`` proves (1, …, 1, det).  Tier 2: the whole adjugate
    is interpolated; the gcd of its entries is exactly ``d_{n−1}`` (the gcd of the
    (n−1)-minors), so ``s_n = det / d_{n−1}``; two compressed (n−2)-minors with
    gcd 1 prove ``d_{n−2} = 1``, hence ``s_{n−1} = d_{n−1}`` and the others are 1.
    """
    got = _adjugate_column(a, n, need_inverse=True)
    if got is None:
        return None
    det, c, (xs, dets, invs), abound = got
    one = bk.ONE
    monic_det = bk.monic(det)
    if bk.gcd(c[n - 1], det).is_one():
        return [one] * (n - 1) + [monic_det]
    k = abound + 1
    if n < 3:
        return None
    values = [(dx * inv).entries() for dx, inv in zip(dets[:k], invs[:k], strict=True)]
    adj = ev.interpolate_columns(flint.fmpq_mat(k, n * n, [v for row in values for v in row]), xs[:k])
    g = bk.ZERO
    for p in adj:
        g = bk.gcd(g, p)
        if g.is_one():
            return [one] * (n - 1) + [monic_det]
    g1 = _compressed_minor(a, n, n - 2, seed=1)
    g2 = _compressed_minor(a, n, n - 2, seed=2)
    if g1.is_zero() or g2.is_zero() or not bk.gcd(g1, g2).is_one():
        return None
    return [one] * (n - 2) + [bk.monic(g), monic_det // bk.monic(g)]


def generic_hermite(a: dn.Rows, n: int) -> tuple[dn.Rows, dn.Rows, list[flint.fmpq_poly]] | None:
    """``(H, U, h)`` for a nonsingular n×n M of generic Hermite shape, else None.

    ``H = [[I, h], [0, monic det M]]``, ``U = H·M⁻¹`` (unique), ``h`` the last
    column above the corner.  Precondition: n ≥ 1.
    """
    got = _adjugate_column(a, n, need_inverse=True)
    if got is None:
        return None
    det, c, (xs, dets, invs), abound = got
    g, s, _ = bk.xgcd(c[n - 1], det)
    if not g.is_one():
        return None
    dn_ = bk.monic(det)
    h = [(-(c[i] * s)) % dn_ for i in range(n - 1)]
    H = dn.identity(n)
    for i in range(n - 1):
        H[i][n - 1] = h[i]
    H[n - 1][n - 1] = dn_
    # adj M at abound + 1 points (exact values det·M(x)⁻¹, integers for integer M),
    # interpolated; then U = H·adj(M)/det M row by row:
    #   U_i = (adj_i + h_i·adj_n) / det  (i < n),   U_n = adj_n / lc(det).
    k = abound + 1
    values = [(dx * inv).entries() for dx, inv in zip(dets[:k], invs[:k], strict=True)]
    polys = ev.interpolate_columns(flint.fmpq_mat(k, n * n, [v for row in values for v in row]), xs[:k])
    adj = [polys[i * n : (i + 1) * n] for i in range(n)]
    last = adj[n - 1]
    if all(p.degree() < det.degree() for row in adj[: n - 1] for p in row):
        U = _polynomial_parts(h, last, det)
    else:
        U = []
        for i in range(n - 1):
            row = []
            for a_ij, a_nj in zip(adj[i], last, strict=True):
                q, r = divmod(a_ij + h[i] * a_nj, det)
                if not r.is_zero():  # pragma: no cover - U = H·M⁻¹ is polynomial (certified shape)
                    return None
                row.append(q)
            U.append(row)
    lcd = bk.lc(det)
    U.append([a / lcd for a in last])
    return H, U, h


def _polynomial_parts(h: list[flint.fmpq_poly], w: list[flint.fmpq_poly], det: flint.fmpq_poly) -> dn.Rows:
    """``U_ij = (adj_ij + h_i·w_j) / det`` for i < n − 1 when every ``adj_ij`` there has a
    degree below ``deg det``, without dividing: U_ij is a polynomial, so it is its own
    polynomial part, which is linear and zero on ``adj_ij / det``, so ``U_ij`` is the
    polynomial part of ``w_j·(h_i/det)``.  With ``deg h_i < deg det`` the expansion
    ``h_i/det = Σ_l c_l δ^(−1−l)`` at infinity is the power series ``rev h_i / rev det``
    (reversed coefficients), of which the terms l < K = max deg w + 1 reach the
    polynomial part: ``U_ij = (C_i·w_j) >> K`` with ``C_i = Σ_(l<K) c_l δ^(K−1−l)``.
    One power-series inverse of ``rev det`` (Newton), n − 1 truncated products and
    (n − 1)·n products; the exact divisions it replaces cost about three times the
    products (a random 32×32 of degree 2, h of 13.4-kbit coefficients: 3.15 s of
    divisions and 1.26 s of products, against 1.2–1.95 s here).

    >>> d = bk.from_coeffs([0, 1])
    >>> det = d * d + 1                       # U = (adj + h·w)/det with adj = −1 − d
    >>> _polynomial_parts([d + 2], [d * d * d + 3], det) == [[((-1 - d) + (d + 2) * (d * d * d + 3)) // det]]
    True
    """
    dd = det.degree()
    K = max(p.degree() for p in w) + 1
    inv = _inverse_series(flint.fmpq_poly(det.coeffs()[::-1]), K)
    U = []
    for hi in h:
        hc = hi.coeffs()
        rev = flint.fmpq_poly([flint.fmpq(0)] * (dd - len(hc)) + hc[::-1])
        c = (rev * inv).truncate(K).coeffs()
        ci = flint.fmpq_poly((c + [0] * (K - len(c)))[::-1])
        U.append([(ci * wj).right_shift(K) for wj in w])
    return U


def _inverse_series(f: flint.fmpq_poly, k: int) -> flint.fmpq_poly:
    """``1/f mod δ^k`` for ``f(0) ≠ 0``, by Newton's iteration ``g ← g·(2 − f·g)``.

    >>> _inverse_series(flint.fmpq_poly([1, -1]), 4)        # 1/(1 − δ)
    x^3 + x^2 + x + 1
    """
    g = flint.fmpq_poly([1 / f[0]])
    prec = 1
    while prec < k:
        prec = min(2 * prec, k)
        g = (g * (2 - (f.truncate(prec) * g).truncate(prec))).truncate(prec)
    return g


def generic_solve_left(v: dn.Rows, w: dn.Rows, n: int, m: int) -> dn.Rows | None:
    """The unique X with ``X V = W`` for a nonsingular n×n V, or None if V is singular.

    ``Y = W·adj(V)`` is interpolated from ``det V(x)·W(x)·V(x)⁻¹`` (degree at most
    ``deg W + b_{n−1}``); then ``X = Y / det V`` entry by entry.  Raises
    ``ArithmeticError`` naming the entry when a division leaves a remainder
    (then no polynomial X exists).  Precondition: W is m×n.
    """
    dbound = ev.minor_degree_bound(v, n, n, n)
    wdeg = max(dn.mat_degree(w), 0)
    ybound = wdeg + ev.minor_degree_bound(v, n, n, n - 1)
    count = max(dbound, ybound) + 1
    xs = ev.first_points(count)
    vc = ev.coefficient_mats(v, n, n)
    wc = ev.coefficient_mats(w, m, n) if m else None
    dets: list[flint.fmpq] = []
    ys: list[list[flint.fmpq] | None] = []
    for x in xs:
        vx = ev.evaluate(vc, x)
        dx = vx.det()
        dets.append(dx)
        if dx == 0:
            ys.append(None)
            continue
        if wc is not None:
            wx = ev.evaluate(wc, x)
            # X(x) V(x) = W(x)  <=>  V(x)^T X(x)^T = W(x)^T
            sol = vx.transpose().solve(wx.transpose()).transpose()
            ys.append([dx * e for e in sol.entries()])
        else:
            ys.append([])
    det = ev.interpolate_columns(flint.fmpq_mat(count, 1, dets))[0] if count else bk.ZERO
    if det.is_zero():
        return None
    if any(y is None for y in ys):
        return _solve_by_points_avoiding_roots(vc, wc, n, m, det, ybound)
    entries = ev.interpolate_columns(flint.fmpq_mat(count, m * n, [e for y in ys if y for e in y])) if m else []
    return _divide_exactly(entries, det, m, n)


def _solve_by_points_avoiding_roots(
    vc: ev.Coefficients, wc: ev.Coefficients | None, n: int, m: int, det: flint.fmpq_poly, ybound: int
) -> dn.Rows:
    """Like :func:`generic_solve_left`, sampling only points where V(x) is nonsingular."""
    if wc is None:  # no rows to solve for (W has none)
        return []
    xs: list[int] = []
    ys: list[list[flint.fmpq]] = []
    for x in ev.points():
        if len(xs) == ybound + 1:
            break
        vx = ev.evaluate(vc, x)
        dx = vx.det()
        if dx == 0:
            continue
        wx = ev.evaluate(wc, x)
        sol = vx.transpose().solve(wx.transpose()).transpose()
        xs.append(x)
        ys.append([dx * e for e in sol.entries()])
    entries = ev.interpolate_columns(flint.fmpq_mat(len(xs), m * n, [e for y in ys for e in y]), xs)
    return _divide_exactly(entries, det, m, n)


def _divide_exactly(entries: list[flint.fmpq_poly], det: flint.fmpq_poly, m: int, n: int) -> dn.Rows:
    out: dn.Rows = []
    for i in range(m):
        row = []
        for j in range(n):
            q, r = divmod(entries[i * n + j], det)
            if not r.is_zero():
                raise ArithmeticError(f"row {i}, column {j}")
            row.append(q)
        out.append(row)
    return out
