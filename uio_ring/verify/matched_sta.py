"""The certificate of a matched super-twisting design: the identities of the reduction (31)–(35)
and of the levels.

>>> from uio_ring import DelaySystem
>>> from uio_ring.design.matched_sta import design_matched_sta
>>> sys = DelaySystem("[[0, 1, 0], [0, 0, 1], [-1, -2, -3]]", "[[0], [0], [1]]", "[[1, 0, 0], [0, 0, 1]]", None)
>>> cert = design_matched_sta(sys).certificate()
>>> cert.ok, len(cert.checks) >= 10
(True, True)
"""

from __future__ import annotations

from typing import Any

from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.verify.checks import residual_check

__all__ = ["matched_sta_certificate"]


def matched_sta_certificate(d: Any) -> Certificate:
    """Exact checks: ``P P⁻¹ = I``; ``B^⊥ B = 0``, ``(C B)^+ C B = I``, ``(C B)^⊥ C B = 0``;
    ``P B = [0; I]`` (w reaches ``r_2`` only); ``C P⁻¹ = [·, C B]`` split by ``(C B)^⊥`` into
    ``[C̄, 0]`` and by ``(C B)^+`` into ``[0, I]`` (33); the blocks of ``P A P⁻¹`` and ``P E``;
    ``M_k = [C̄; …; C̄ A11^{k−1}]`` with ``rank M_l = n − q``; ``M_l^+ M_l = I``;
    ``A11 − K C̄`` Hurwitz (Routh); positive gains."""
    from uio_ring.analysis.strong_observability import is_hurwitz_polynomial
    from uio_ring.ring.charpoly import charpoly

    sys, red = d.system, d.reduction
    A, B, C, E = sys.A, sys.B, sys.C, sys.E
    n, q = sys.n_x, sys.n_w
    m = n - q
    I = PolyMatrix.identity
    Z = PolyMatrix.zeros
    checks: list[Check] = []

    def add(name: str, statement: str, fn: Any) -> None:
        checks.append(residual_check(name, statement, fn))

    CB = C @ B
    add("P P⁻¹ = I", "the formula (31) for P⁻¹ inverts P", lambda: {"P P⁻¹ − I": red.P @ red.P_inv - I(n)})
    add("B^⊥ B = 0", "r_1 = B^⊥ x does not see w", lambda: {"B^⊥ B": red.B_perp @ B})
    add("(CB)^+ CB = I", "the matching condition rank C B = q (A4)", lambda: {"(CB)^+ CB − I": red.CB_pinv @ CB - I(q)})
    add("(CB)^⊥ CB = 0", "ȳ_1 does not see w", lambda: {"(CB)^⊥ CB": red.CB_perp @ CB})
    add("P B = [0; I]", "w enters the r_2 block only (32a)",
        lambda: {"P B − [0; I]": red.P @ B - PolyMatrix.vstack(Z(m, q), I(q))})
    add("(CB)^⊥ C P⁻¹ = [C̄, 0]", "ȳ_1 = C̄ r_1 (33a)",
        lambda: {"residual": red.CB_perp @ C @ red.P_inv - PolyMatrix.hstack(red.C_bar, Z(red.C_bar.rows, q))})
    add("(CB)^+ C P⁻¹ = [0, I]", "r_2 is measured (33b)",
        lambda: {"residual": red.CB_pinv @ C @ red.P_inv - PolyMatrix.hstack(Z(q, m), I(q))})

    def blocks() -> dict[str, PolyMatrix]:
        PAPi, PE = red.P @ A @ red.P_inv, red.P @ E
        want = PolyMatrix.block([[red.A11, red.A12], [red.A21, red.A22]])
        return {"P A P⁻¹ − [A11 A12; A21 A22]": PAPi - want, "P E − [B1; B2]": PE - PolyMatrix.vstack(red.B1, red.B2)}

    add("P A P⁻¹, P E", "the blocks of (32a)", blocks)

    def sequence() -> dict[str, PolyMatrix]:
        out, power = {}, I(m)
        rows = []
        for k, M in enumerate(red.M, start=1):
            rows.append(red.C_bar @ power)
            power = power @ red.A11
            out[f"M_{k} − [C̄; …; C̄ A11^{k - 1}]"] = M - PolyMatrix.vstack(*rows)
        return out

    add("M_k = [C̄; C̄ A11; …]", "the observability sequence of (A11, C̄) (35)", sequence)
    add("rank M_l = n − q", "(A11, C̄) observable: the system is strongly observable (Lemma 2)",
        lambda: None if red.M[-1].rank() == m else f"rank M_l = {red.M[-1].rank()} < n − q = {m}")
    add("M_l^+ M_l = I", "the levels recover r_1 − r̃ (41)", lambda: {"M+ M − I": d.M_l_pinv @ red.M[-1] - I(m)})
    add("A11 − K C̄ Hurwitz", "the reduced Luenberger part converges (exact Routh test)",
        lambda: None if is_hurwitz_polynomial(charpoly(red.A11 - d.K @ red.C_bar)) else
        "A11 − K C̄ has a root with Re ≥ 0")
    add("gains positive", "λ_k, α_k and λ_w, α_w > 0",
        lambda: None if all(g > 0 for pair in (*d.gains, d.w_gains) for g in pair) else "a gain is not positive")
    return Certificate("matched super-twisting observer with w reconstruction (Bejarano, Fridman & Poznyak 2007, "
                       "Section 3)", tuple(checks))
