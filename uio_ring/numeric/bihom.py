"""Bi-homogeneous injection functions (Moreno's differentiator; Tranninger et al. 2021, (11)–(13)).

For a chain of length ``q`` and an exponent profile ``(d0, d_inf, mu)``::

    r_{·,i} = 1 − (q − i) d_·          (i = 1 … q + 1; r_{·,q} = 1, r_{·,q+1} = 1 + d_·)
    p_{·,i} = r_{·,i+1} / r_{·,i}
    φ_i(z)  = μ ⌈z⌋^{p_{0,i}} + (1 − μ) ⌈z⌋^{p_{∞,i}}      (one power when p_{0,i} = p_{∞,i})
    Φ_j     = φ_j ∘ … ∘ φ_1

``⌈z⌋^a = sign(z)|z|^a`` and ``⌈z⌋^0 = sign z`` (``Φ_j(0) = 0``; the set-valued sign
is the stepper's business).  With ``d0 = d_inf = −1``, ``Φ_j(z) = ⌈z⌋^{(q−j)/q}``:
Levant's differentiator.

>>> prof = chain_exponents(3, -1.0, -1.0)
>>> [round(v, 12) for v in phi_values(8.0, *prof, 0.5)]
[4.0, 2.0, 1.0]
"""

from __future__ import annotations

import math
import sys

__all__ = ["chain_exponents", "phi_values", "phi_values_and_slopes", "solve_bihom_chain"]


def chain_exponents(q: int, d0: float, d_inf: float) -> tuple[list[float], list[float]]:
    """``(p_0, p_∞)``: the exponents ``p_{·,i}``, ``i = 1 … q`` (floats; the exact ones are in
    :func:`uio_ring.design.bihom.exponents`).

    >>> chain_exponents(2, -1.0, 0.5)
    ([0.5, 0.0], [2.0, 1.5])
    """
    def p(d: float) -> list[float]:
        r = [1.0 - (q - i) * d for i in range(1, q + 2)]
        return [r[i + 1] / r[i] for i in range(q)]

    return p(d0), p(d_inf)


def phi_values(z: float, p0: list[float], pinf: list[float], mu: float) -> list[float]:
    """``[Φ_1(z), …, Φ_q(z)]`` (odd; ``Φ_j(0) = 0``)."""
    if z == 0.0:
        return [0.0] * len(p0)
    v, out = abs(z), []
    for a, b in zip(p0, pinf, strict=True):
        v = v**a if a == b else mu * v**a + (1.0 - mu) * v**b
        out.append(v)
    return [math.copysign(x, z) for x in out]


def phi_values_and_slopes(s: float, p0: list[float], pinf: list[float], mu: float) -> tuple[list[float], list[float]]:
    """``Φ_j(s)`` and ``Φ_j'(s)`` for ``s > 0`` (precondition), by the chain rule."""
    v, dv = s, 1.0
    vals, slopes = [], []
    for a, b in zip(p0, pinf, strict=True):
        if a == b:
            nv = v**a
            dv = (a * nv / v) * dv
        else:
            va, vb = v**a, v**b
            nv = mu * va + (1.0 - mu) * vb
            dv = (mu * a * va + (1.0 - mu) * b * vb) / v * dv
        v = nv
        vals.append(v)
        slopes.append(dv)
    return vals, slopes


def solve_bihom_chain(a: float, coef: list[float], p0: list[float], pinf: list[float], mu: float,
                      guess: float = 0.0) -> tuple[float, float]:
    """Solve ``σ + Σ_{k=1}^{q} coef_k Φ_k(σ) ∋ a`` (``coef_k > 0``); return ``(σ, v)`` with ``v`` the
    value of ``coef_q Φ_q`` at the solution (the set-valued part's value when ``σ = 0``).

    The left side is odd and strictly increasing; it jumps at 0 by ``±J``, ``J = coef_q w_0``,
    ``w_0`` the weight of the zero powers of ``φ_q`` (``μ`` for a DBHO with ``d0 = −1 < d_inf``,
    1 for Levant's, 0 for a continuous profile).  So ``σ = 0`` when ``|a| ≤ J``; otherwise the
    root in ``(0, |a|)`` by Newton's method kept inside a shrinking bracket (bisection when a
    step leaves it, geometric while the bracket spans decades), started from ``guess`` (the
    last step's ``|σ|``).

    >>> p0, pinf = chain_exponents(1, -1.0, -1.0)
    >>> solve_bihom_chain(0.5, [1.0], p0, pinf, 0.5), solve_bihom_chain(3.0, [1.0], p0, pinf, 0.5)
    ((0.0, 0.5), (2.0, 1.0))
    """
    q = len(coef)
    w0 = (mu if p0[-1] == 0.0 else 0.0) + ((1.0 - mu) if pinf[-1] == 0.0 else 0.0)
    if p0[-1] == 0.0 and pinf[-1] == 0.0:
        w0 = 1.0
    jump = coef[-1] * w0
    c = abs(a)
    if c <= jump:
        return 0.0, a
    lo, hi = 0.0, c
    s = guess if 0.0 < guess < c else 0.5 * c
    for _ in range(300):
        if s <= 0.0:  # the root underflows: σ = the bracket's top (below the smallest double's reach)
            s = hi
            break
        try:
            vals, slopes = phi_values_and_slopes(s, p0, pinf, mu)
        except ZeroDivisionError:  # an inner value underflowed: step by bisection
            lo, s = s, (hi / 256.0 if s == 0.0 else math.sqrt(s * hi))
            continue
        f = s - c
        df = 1.0
        for k in range(q):
            f += coef[k] * vals[k]
            df += coef[k] * slopes[k]
        if f > 0.0:
            hi = s
        elif f < 0.0:
            lo = s
        else:
            break
        s_new = s - f / df
        if not (lo < s_new < hi):  # bisection: geometric while the bracket spans decades (tiny roots)
            s_new = hi / 256.0 if lo == 0.0 else (math.sqrt(lo * hi) if hi > 4.0 * lo else 0.5 * (lo + hi))
        if abs(s_new - s) <= 4e-16 * s or hi - lo <= 4e-16 * hi:
            s = s_new
            break
        s = s_new
    if s < sys.float_info.min:  # Newton's steps round to nothing among the subnormals: bisect them
        s = _subnormal_root(lo, hi, lambda z: z - c + sum(k * v for k, v in zip(coef, phi_values(z, p0, pinf, mu),
                                                                                  strict=True)))
    vals = phi_values(s, p0, pinf, mu)
    return math.copysign(s, a), math.copysign(coef[-1] * vals[-1], a)


def _subnormal_root(lo: float, hi: float, f) -> float:
    """The float nearest the root of the increasing ``f`` in the bracket ``(lo, hi]``
    (``f(lo) < 0 < f(hi)``, ``hi`` subnormal): bisection down to adjacent floats, then the one
    with the smaller ``|f|`` — never 0, whose inclusion belongs to the jump test.

    Among the subnormals a float step is ``2^-1074`` whatever the size, so Newton's
    correction rounds to nothing several floats from the root (a steep ``Φ_q`` near 0).

    >>> _subnormal_root(0.0, 1e-320, lambda z: z - 3e-323)
    3e-323
    """
    while math.nextafter(lo, math.inf) < hi:
        mid = lo + (hi - lo) / 2.0
        if mid <= lo or mid >= hi:  # two floats apart: the float between them
            mid = math.nextafter(lo, math.inf)
        fm = f(mid)
        if fm == 0.0:
            return mid
        if fm > 0.0:
            hi = mid
        else:
            lo = mid
    if lo == 0.0 or abs(f(hi)) <= abs(f(lo)):
        return hi
    return lo
