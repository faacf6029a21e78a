"""The certificate of a hierarchical super-twisting design: the identities its levels rely on.

>>> from uio_ring import DelaySystem
>>> from uio_ring.design.hierarchical_sta import design_hierarchical_sta
>>> cert = design_hierarchical_sta(DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None)).certificate()
>>> cert.ok, len(cert.checks) >= 6
(True, True)
"""

from __future__ import annotations

from typing import Any

from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.verify.checks import residual_check

__all__ = ["hierarchical_sta_certificate"]


def hierarchical_sta_certificate(d: Any) -> Certificate:
    """Exact checks: ``D^⊥ D = 0`` and ``M_1 = D^⊥ C``; ``T_{k,b} [M_k B; D] = 0`` and
    ``M_{k+1} = T_{k,b} [M_k A; C]`` (the unknown input is annihilated at every level);
    ``rank M_l = n``; ``M_l^+ M_l = I``; the levels' ``S_k``; ``A − K C`` Hurwitz (Routh)."""
    from uio_ring.analysis.strong_observability import is_hurwitz_polynomial
    from uio_ring.ring.charpoly import charpoly

    sys = d.system
    A, B, C, D = sys.A, sys.B, sys.C, sys.D
    n = sys.n_x
    checks: list[Check] = []

    def add(name: str, statement: str, fn: Any) -> None:
        checks.append(residual_check(name, statement, fn))

    T0 = d.T_b[0]
    add("D^⊥ D = 0", "T_{0,b} annihilates the feed-through of w", lambda: {"T0 D": T0 @ D})
    add("M_1 = D^⊥ C", "the first row block", lambda: {"M1 − T0 C": d.M[0] - T0 @ C})
    for k in range(1, d.l):
        Mk, T = d.M[k - 1], d.T_b[k]
        add(f"T_{k},b [M_{k} B; D] = 0", "level k sees no unknown input",
            lambda Mk=Mk, T=T: {"T [M B; D]": T @ PolyMatrix.vstack(Mk @ B, D)})
        add(f"M_{k + 1} = T_{k},b [M_{k} A; C]", "Molinari's recursion (8)",
            lambda k=k, Mk=Mk, T=T: {"residual": d.M[k] - T @ PolyMatrix.vstack(Mk @ A, C)})
    add("rank M_l = n", "strong observability: the last M has full column rank",
        lambda: None if d.M[-1].rank() == n else f"rank M_l = {d.M[-1].rank()} < n = {n}")
    add("M_l^+ M_l = I", "the last level recovers x − x̃", lambda: {"M+ M − I": d.M_l_pinv @ d.M[-1] - PolyMatrix.identity(n)})
    for k, S in enumerate(d.S, start=1):
        want = d.T_b[k] if k < len(d.S) else d.M_l_pinv @ d.T_b[k]
        add(f"S_{k}", "T_{k,b} (the last level: M_l^+ T_{l−1,b})", lambda S=S, want=want: {"S − want": S - want})
    add("A − K C Hurwitz", "the Luenberger part converges (exact Routh test)",
        lambda: None if is_hurwitz_polynomial(charpoly(A - d.K @ C)) else "A − K C has a root with Re ≥ 0")
    add("gains positive", "λ_k > 0, α_k > 0 on every level",
        lambda: None if all(g > 0 for pair in d.gains for g in pair) else "a gain is not positive")
    return Certificate("hierarchical super-twisting observer (Bejarano, Fridman & Poznyak 2007)", tuple(checks))
