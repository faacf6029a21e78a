"""Exponent profiles and gains of the bi-homogeneous observers (Tranninger et al. 2021, §3.3, §5.3–5.4).

A chain of length ``q`` with profile ``(d0, d_inf, mu)`` injects ``κ_j Φ_j(σ)`` into its row
``j`` (Moreno's differentiator; :mod:`uio_ring.numeric.bihom` evaluates Φ).  The exponents
are exact here: ``r_{·,i} = 1 − (q − i) d_·`` and ``p_{·,i} = r_{·,i+1}/r_{·,i}`` (the
printed ``(r+1)/r`` is a slip, see docs/errata.md T3).

Admissible profiles (Theorems 3 and 4):

* DBHO on ``x_d``: ``d0 = −1``; finite-time for ``−1 ≤ d_inf < 0``, fixed-time for
  ``0 < d_inf < 1/(q_i − 1)`` (every chain; no bound for ``q_i = 1``);
* CBHO on ``x_b``: ``−1 < d0 < 0 < d_inf < 1/(l_i − 1)``;
* ``0 < mu < 1``.

Gains (our rule — the paper gives none; docs/errata.md T5): near ``σ = 0`` the chain
behaves like ``Φ_j(σ) ≈ c_j ⌈σ⌋^{e_j}`` with ``c_1 = w_1``, ``c_j = w_j c_{j−1}^{p_{0,j}}``
(``w_i = μ``, or 1 when ``p_{0,i} = p_{∞,i}``).  We take ``κ_j = ρ_j / c_j`` for reference
gains ``ρ``: the homogeneous approximation at the origin is then exactly the reference
observer — Levant's differentiator with the gains of Theorem 2 for the DBHO (its last gain
``μ κ_q = 1.1 Δ`` dominates the input near the origin), the Luenberger observer of
``poles_b`` (made homogeneous of degree ``d0``) for the CBHO.  Nothing is claimed about
the approximation at infinity; the tests show convergence by simulation.

>>> from fractions import Fraction as Fr
>>> exponents(3, Fr(-1))
(Fraction(2, 3), Fraction(1, 2), Fraction(0, 1))
>>> [round(float(k), 6) for k in scaled_gains((Fr(2), Fr(1)), 2, Fr(-1), Fr(1, 2), Fr(1, 2))]
[4.0, 2.0]
"""

from __future__ import annotations

from collections.abc import Sequence
from fractions import Fraction

from uio_ring.errors import OptionError

__all__ = ["exponents", "zero_limit_coefficients", "scaled_gains", "check_mu", "check_dbho", "check_cbho", "default_d_inf",
           "default_cbho"]


def exponents(q: int, d: Fraction) -> tuple[Fraction, ...]:
    """``(p_1, …, p_q)``, ``p_i = r_{i+1}/r_i``, ``r_i = 1 − (q − i) d`` (exact; ``r_i > 0`` for
    ``i ≤ q`` is a precondition)."""
    r = [1 - (q - i) * d for i in range(1, q + 2)]
    return tuple(r[i + 1] / r[i] for i in range(q))


def zero_limit_coefficients(q: int, d0: Fraction, d_inf: Fraction, mu: Fraction, digits: int = 15) -> tuple[float, ...]:
    """``c_1 … c_q`` of ``Φ_j(σ) ≈ c_j ⌈σ⌋^{e_j}`` as ``σ → 0`` (floats: ``μ^{p}`` is irrational)."""
    p0, pi = exponents(q, d0), exponents(q, d_inf)
    out: list[float] = []
    c = 1.0
    for i in range(q):
        w = 1.0 if p0[i] == pi[i] else float(mu)
        c = w * (c ** float(p0[i]) if i else 1.0)
        out.append(round(c, digits))
    return tuple(out)


def scaled_gains(reference: Sequence[Fraction], q: int, d0: Fraction, d_inf: Fraction, mu: Fraction,
                 digits: int = 12) -> tuple[Fraction, ...]:
    """``κ_j = ρ_j / c_j`` rounded to ``digits`` significant digits (exact when every ``c_j`` is
    1 or ``μ``, e.g. Levant's profile: then ``κ = ρ``)."""
    cs = zero_limit_coefficients(q, d0, d_inf, mu)
    out = []
    for rho, c in zip(reference, cs, strict=True):
        if c == 1.0:
            out.append(Fraction(rho))
        elif c == float(mu):
            out.append(Fraction(rho) / mu)
        else:
            v = float(rho) / c
            out.append(Fraction(f"{v:.{digits}g}"))
    return tuple(out)


def _bound(lengths: Sequence[int]) -> Fraction | None:
    """``min 1/(q_i − 1)`` over the chains longer than 1 (None: no bound)."""
    longest = max(lengths, default=1)
    return None if longest <= 1 else Fraction(1, longest - 1)


def check_mu(mu: Fraction) -> None:
    """Refuse ``mu`` outside ``(0, 1)``."""
    if not 0 < mu < 1:
        raise OptionError(f"mu = {mu} must lie in (0, 1) (the weight of the two limits of φ_i)", option="mu")


def check_dbho(q: Sequence[int], d_inf: Fraction, mu: Fraction) -> str:
    """Refuse ``d_inf`` outside Theorem 4's ranges (with ``d0 = −1``); return ``"finite-time"`` or
    ``"fixed-time"``."""
    check_mu(mu)
    bound = _bound(q)
    if -1 <= d_inf < 0:
        return "finite-time"
    if d_inf > 0 and (bound is None or d_inf < bound):
        return "fixed-time"
    why = "d_inf = 0 is linear at infinity (neither range)" if d_inf == 0 else (
        f"d_inf = {d_inf} is below -1" if d_inf < -1 else
        f"d_inf = {d_inf} is not below 1/(q_i - 1) = {bound} for the longest chain (q = {tuple(q)})")
    raise OptionError(f"{why}: the DBHO needs -1 <= d_inf < 0 (finite-time) or 0 < d_inf < min 1/(q_i - 1) "
                      "(fixed-time)", option="d_inf")


def check_cbho(l: Sequence[int], d0: Fraction, d_inf: Fraction, mu: Fraction) -> None:  # noqa: E741
    """Refuse a profile outside Theorem 3's ``−1 < d0 < 0 < d_inf < min 1/(l_i − 1)``."""
    check_mu(mu)
    if not -1 < d0 < 0:
        raise OptionError(f"b_d0 = {d0}: the CBHO needs -1 < d0 < 0", option="b_d0")
    bound = _bound(l)
    if not (d_inf > 0 and (bound is None or d_inf < bound)):
        raise OptionError(f"b_d_inf = {d_inf}: the CBHO needs 0 < d_inf < min 1/(l_i - 1)"
                          + (f" = {bound}" if bound is not None else ""), option="b_d_inf")


def default_d_inf(q: Sequence[int]) -> Fraction:
    """Default ``d_inf`` of the DBHO: ``4/5`` of the bound ``1/(max q_i − 1)`` (1 when every chain
    has length 1) — fixed-time, inside the open range, and large enough that the part at
    infinity pulls big errors in quickly.

    >>> default_d_inf((3, 2)), default_d_inf((1,))
    (Fraction(2, 5), Fraction(1, 1))
    """
    b = _bound(q)
    return Fraction(1) if b is None else b * Fraction(4, 5)


def default_cbho(l: Sequence[int]) -> tuple[Fraction, Fraction]:  # noqa: E741
    """Default ``(d0, d_inf)`` of the CBHO: ``(−1/2, 4/5 · 1/(max l_i − 1))`` (``d_inf = 1`` when
    every chain has length 1), inside Theorem 3's ranges."""
    return Fraction(-1, 2), default_d_inf(l)
