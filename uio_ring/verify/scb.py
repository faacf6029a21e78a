"""The certificate of a special-coordinate-basis observer (Tranninger et al. 2021).

>>> from uio_ring import DelaySystem
>>> from uio_ring.design.scb import design_scb
>>> cert = design_scb(DelaySystem("[[-2, 1, 0], [0, 0, 1], [0, 0, 0]]", "[[0], [0], [1]]", "[[0, 1, 0]]", None),
...                   input_bounds=[1]).certificate()
>>> cert.ok, cert["error: Ā − G C̄ = F"].ok
(True, True)
"""

from __future__ import annotations

from typing import Any

from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.matrix import Poly
from uio_ring.ring.qmatrix import QMatrix as Q
from uio_ring.verify.checks import residual_check

__all__ = ["scb_design_certificate"]


def scb_design_certificate(d: Any) -> Certificate:
    """Exact checks of an :class:`~uio_ring.design.scb.SCBDesign`.

    Every check of the special coordinate basis (:func:`~uio_ring.analysis.scb.scb_certificate`),
    then the observer: ``A_a`` Hurwitz (e_a decays), ``spec(A_b − L_b C_b)`` equals ``poles_b``
    (40), the error identities ``Ā − G C̄ = F`` and ``B̄ − G D̄ = [0, [0; 0; B_d]]`` (the
    unknown input reaches the error only at the ends of the x_d chains — not at all when
    ``x̂_d = y_d``), the bounds (45) and Theorem 2's ``κ_{i,q_i} > Δ_{d,i}``; for the
    bi-homogeneous observers the exponent ranges of Theorems 3 and 4 and ``μ κ_{i,q_i} > Δ_{d,i}``.
    """
    from uio_ring.analysis.strong_observability import is_hurwitz_polynomial
    from uio_ring.design.scb import input_bound_d

    s = d.scb
    checks: list[Check] = list(s.verify().checks)

    def add(name: str, statement: str, fn: Any) -> None:
        checks.append(residual_check(name, statement, fn))

    if d.reconstruct_input:
        aug = d.system.input_augmented()
        add("the basis is of the system of [x; w]", "χ = [x; w], χ' = [[A, B], [0, 0]] χ + [0; I] w', y = [C, D] χ",
            lambda: {k: s.system.matrices()[k] - M for k, M in aug.matrices().items()})
    add("A_a Hurwitz", "the copy of the zero dynamics converges (strong detectability, (38))",
        lambda: None if is_hurwitz_polynomial(s.invariant_zero_polynomial) else
        f"det(sI − A_a) = {s.invariant_zero_polynomial} has a root with Re ≥ 0")

    def spectrum() -> Any:
        want = Poly(1, "s")
        for p in d.poles_b:
            want = want * (Poly.gen("s") - Poly(p, "s"))
        got = charpoly(Q(s.A_b) - Q(d.L_b) @ Q(s.C_b))
        return None if got == want else f"det(sI − A_b + L_b C_b) = {got}, wanted {want}"

    add("(40) spec(A_b − L_b C_b) = poles_b", "the x_b error decays with the chosen poles", spectrum)
    mats = d.observer_matrices()
    F, G = mats["F"], mats["G"]
    Abar, Bbar, Cbar, Dbar = Q(s.A_bar), Q(s.B_bar), Q(s.C_bar), Q(s.D_bar)
    nab, n = s.n_a + s.n_b, s.n_a + s.n_b + s.n_d
    wd = Q.vstack(Q.zeros(nab, s.m_d), Q(s.B_d), cols=s.m_d) if s.m_d else Q.zeros(n, 0)
    w_enters = Q.hstack(Q.zeros(n, s.m_0), wd, rows=n)
    if d.d_dynamic:
        add("error: Ā − G C̄ = F", "e = x̄ − ξ obeys e' = F e + (B̄ − G D̄) w̄ − L_d(σ)",
            lambda: {"Ā − G C̄ − F": (Abar - G @ Cbar - F).to_polymatrix()})
        add("error: B̄ − G D̄ = [0, [0; 0; B_d]]", "w enters the error only at the ends of the x_d chains",
            lambda: {"residual": (Bbar - G @ Dbar - w_enters).to_polymatrix()})
    else:
        rows = list(range(nab))
        add("error: Ā − G C̄ = F", "e_ab = x̄_ab − ξ obeys e_ab' = F e_ab (x̂_d = y_d exactly)",
            lambda: {"residual": (Abar.take_rows(rows) - G @ Cbar
                                  - Q.hstack(F, Q.zeros(nab, s.n_d), rows=nab)).to_polymatrix()})
        add("error: B̄ − G D̄ = 0 on x_a, x_b", "the unknown input does not reach the error",
            lambda: {"residual": (Bbar.take_rows(rows) - G @ Dbar).to_polymatrix()})
        add("(41) x̂_d = y_d", "every chain has length 1 and y_d = x_d exactly",
            lambda: None if all(k == 1 for k in s.q) else f"chains q = {s.q}")
    if d.input_ranges is not None and d.Delta_d:
        G_d = Q(s.Ti).inverse().take_rows(range(s.m_0, s.m_0 + s.m_d))
        add("(45) Δ_d", "the bound of w_d over the box of w",
            lambda: None if input_bound_d(G_d, d.input_ranges) == d.Delta_d else "Δ_d differs from (45)")
    if d.kappa and d.Delta_d:
        add("Theorem 2: κ_{i,q_i} > Δ_{d,i}", "the last gain of each chain dominates its unknown input",
            lambda: None if all(k[-1] > D for k, D in zip(d.kappa, d.Delta_d, strict=True)) else
            f"last gains {[str(k[-1]) for k in d.kappa]} vs Δ_d {[str(x) for x in d.Delta_d]}")
    _bihom_checks(d, add)
    return Certificate("special coordinate basis observer", checks)


def _bihom_checks(d: Any, add: Any) -> None:
    """Theorems 3 and 4: the exponent ranges of the bi-homogeneous observers, the exponents'
    ordering at 0 and ∞ and the sign term's dominance ``μ κ_{i,q_i} > Δ_{d,i}`` (exact)."""
    from fractions import Fraction

    from uio_ring.design.bihom import exponents
    from uio_ring.design.scb import sign_weight

    s = d.scb

    def ranges(lengths: Any, profile: Any, *, dbho: bool) -> Any:
        d0, dinf, mu = profile
        bound = None if max(lengths, default=1) <= 1 else Fraction(1, max(lengths) - 1)
        below = bound is None or dinf < bound
        ok = (d0 == -1 and (-1 <= dinf < 0 or (0 < dinf and below))) if dbho else (-1 < d0 < 0 < dinf and below)
        if not (ok and 0 < mu < 1):
            return f"(d0, d_inf, mu) = ({d0}, {dinf}, {mu}) outside the range for chains {tuple(lengths)}"
        bad = [(k, i) for k in lengths for i, (a, b) in enumerate(zip(exponents(k, d0), exponents(k, dinf),
                                                                     strict=True)) if not (0 <= a <= b)]
        return f"exponents p_0 > p_inf or negative at (chain length, row) {bad}" if bad else None

    if d.b_profile is not None:
        add("Theorem 3: CBHO exponents", "-1 < d0 < 0 < d_inf < min 1/(l_i - 1), 0 < mu < 1; 0 <= p_0,i <= p_inf,i",
            lambda: ranges(s.l, d.b_profile, dbho=False))
        add("CBHO gains positive", "one positive gain per row of each x_b chain",
            lambda: None if [len(k) for k in d.kappa_b] == list(s.l) and all(v > 0 for k in d.kappa_b for v in k)
            else f"gains {d.kappa_b} for chains {s.l}")
    if d.d_profile is not None:
        add("Theorem 4: DBHO exponents", "d0 = -1, -1 <= d_inf < 0 or 0 < d_inf < min 1/(q_i - 1), 0 < mu < 1; "
            "0 <= p_0,i <= p_inf,i", lambda: ranges(s.q, d.d_profile, dbho=True))
        if d.kappa and d.Delta_d:
            w = sign_weight(d.d_profile)
            add("DBHO: mu κ_{i,q_i} > Δ_{d,i}", "the sign term of Φ_q (weight mu at the origin) dominates the input",
                lambda: None if all(w * k[-1] > D for k, D in zip(d.kappa, d.Delta_d, strict=True)) else
                f"mu κ_q = {[str(w * k[-1]) for k in d.kappa]} vs Δ_d {[str(x) for x in d.Delta_d]}")
