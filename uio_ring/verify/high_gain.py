"""Certificate of a high-gain observer with output shaping (Grip & Saberi 2010).

Checks, exactly over Q:

* the extended set is the filter's (eqs. (18)–(19)), admissible, and (A_e, C_e) observable;
* the filter has the polynomial inverse ``P(s)`` with ``det P = c·s^{n_f}`` (Remark 4);
* Γ_x, Γ_y give the canonical form (8)–(9) and every W̄ block is generalised lower-triangular (11);
* ``K = Γ_x (blkdiag(K̃_i) + L) Γ_y⁻¹`` with ``K̃_j = k*_j / ε^j`` (eq. (12));
* ``Γ_x⁻¹ (A_e − K C_e) Γ_x = blkdiag(A_{q_i} − K̃_i C_{q_i})``;
* ``det(sI − (A_e − K C_e)) = Π_i ε^{−q_i} p_i(ε s)``: the requested spectrum scaled by 1/ε;
* every chain polynomial is Hurwitz;
* the implementation (22) has the error dynamics (21): with ``e = [z̃; x − x̂]``,
  ``e' = (A_e − K C_e) e`` whatever ``y`` and ``u`` are (so the observer matrix F of
  (22) is similar to ``A_e − K C_e`` and has the requested spectrum).

Not checked here: the paper's assertion that ``A_z − K_z C_z`` is always Hurwitz.
It is false in general (with four or more filter states the loop can be
unstable, while F above is not); the design reports it as
``HighGainDesign.filter_loop_hurwitz``.

>>> from uio_ring import DelaySystem, design_high_gain
>>> d = design_high_gain(DelaySystem("[[0, 1], [0, 0]]", "[[0], [0]]", "[[1, 0]]", None), poles=[-1, -2])
>>> high_gain_certificate(d).ok
True
"""

from __future__ import annotations

from fractions import Fraction
from typing import Any

from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.verify.checks import residual_check

__all__ = ["high_gain_certificate"]


def _chain_polynomial(coefficients: Any) -> Any:
    """``s^q + k*_1 s^{q−1} + … + k*_q``."""
    from uio_ring.ring.poly import Poly

    return Poly.from_coeffs([*reversed([Fraction(k) for k in coefficients]), 1], "s")


def high_gain_certificate(design: Any) -> Certificate:
    """All checks of a :class:`~uio_ring.design.high_gain.HighGainDesign` (see the module docstring)."""
    from uio_ring.analysis.admissibility import admissibility
    from uio_ring.analysis.canonical_form import (
        block_violations,
        chain_blocks,
        observability_indices_of,
        shift_blocks,
    )
    from uio_ring.analysis.output_shaping import Filter, extended_set
    from uio_ring.analysis.strong_observability import is_hurwitz_polynomial
    from uio_ring.ring import constant as qc

    d = design
    sysm = d.system
    checks: list[Check] = []
    add = checks.append
    n, p, nf = sysm.n_x, sysm.n_y, d.n_f
    ne = n + nf
    filt = Filter(d.A_z, d.B_z, d.C_z, d.D_z)

    def extended() -> dict[str, PolyMatrix]:
        Ae, Ce, We = extended_set(sysm.A, sysm.C, d.W, filt)
        out = {"A_e - (18)": d.A_e - Ae, "C_e - (18)": d.C_e - Ce}
        out.update({f"W_e[{k}] - (19)": a - b for k, (a, b) in enumerate(zip(d.W_e, We, strict=True))})
        return out

    add(residual_check("extended set (18)–(19)", "A_e = [[A_z, B_z C], [0, A]], C_e = [C_z, D_z C], "
                       "W_ek = [[0, 0], [0, W_k]]", extended))
    adm = admissibility(d.A_e, d.C_e, d.W_e)
    add(Check("extended set admissible", adm.holds, None if adm.holds else adm.reason,
              "W_ek 𝒮_i(A_e, C_e) ⊂ 𝒮_i(A_e, C_e) for all i, k"))
    q_obs = observability_indices_of(d.A_e, d.C_e)
    add(Check("(A_e, C_e) observable", sum(q_obs) == ne, None if sum(q_obs) == ne else f"indices {q_obs}",
              "rank of the observability matrix = n + n_f"))
    if d.shaping is not None:
        sc = d.shaping.certificate()
        for name in ("P(s) G(s) = I", "det P = c·s^n_f"):
            c = sc[name]
            add(Check(f"filter: {name}", c.ok, c.residual, c.statement))
    Gx, Gy = qc.qmat(d.Gamma_x), qc.qmat(d.Gamma_y)
    Gxi = qc.qinverse(Gx, "Γ_x")
    Gyi = qc.qinverse(Gy, "Γ_y")
    Ab = Gxi * qc.qmat(d.A_e) * Gx
    Cb = Gyi * qc.qmat(d.C_e) * Gx
    Aq, Cq = shift_blocks(d.q, ne)
    add(residual_check("canonical form (8)–(9)", "Γ_y⁻¹ C_e Γ_x = blkdiag(C_{q_i}), "
                       "Γ_x⁻¹ A_e Γ_x = blkdiag(A_{q_i}) + L C̄",
                       lambda: {"C̄ - blkdiag(C_q)": qc.to_polymatrix(Cb - Cq),
                                "Ā - blkdiag(A_q) - L C̄": qc.to_polymatrix(Ab - Aq - qc.qmat(d.L) * Cb)}))
    viol = block_violations([Gxi * qc.qmat(W) * Gx for W in d.W_e], d.q)
    add(Check("W̄ blocks lower-triangular (11)", not viol, f"entries above a block diagonal: {viol[:5]}" if viol
              else None, "entry (r, c) of every block W̄_kij is 0 when c > r"))
    # K̃ restated from the definition: chain i, level j (1-based) gets k*_ij / ε^j
    Kt = qc.qzeros(ne, p)
    for i, (s0, _) in enumerate(chain_blocks(d.q)):
        for j, k in enumerate(d.coefficients[i]):
            Kt[s0 + j, i] = qc.qmat([[Fraction(k) / d.epsilon ** (j + 1)]])[0, 0]
    add(residual_check("K = Γ_x K̄ Γ_y⁻¹ (12)", "K̄ = blkdiag(K̃_i) + L with K̃_ij = k*_ij / ε^j",
                       lambda: {"Γ_x⁻¹ K Γ_y - K̄": qc.to_polymatrix(Gxi * qc.qmat(d.K) * Gy - (Kt + qc.qmat(d.L)))}))
    E = qc.qmat(d.error_matrix())
    target = Aq - Kt * Cq
    add(residual_check("error matrix in canonical coordinates", "Γ_x⁻¹ (A_e − K C_e) Γ_x = "
                       "blkdiag(A_{q_i} − K̃_i C_{q_i})",
                       lambda: {"difference": qc.to_polymatrix(Gxi * E * Gx - target)}))
    got = charpoly(d.error_matrix())
    want = d.characteristic_polynomial()
    add(Check("spectrum of A_e − K C_e", got == want, None if got == want else f"{got} ≠ {want}",
              "det(sI − (A_e − K C_e)) = Π_i ε^{−q_i} p_i(ε s) (the requested poles divided by ε)"))
    bad = [i for i, ks in enumerate(d.coefficients) if not is_hurwitz_polynomial(_chain_polynomial(ks))]
    add(Check("chain polynomials Hurwitz", not bad, f"chains {bad}" if bad else None,
              "s^q + k*_1 s^{q−1} + … + k*_q Hurwitz for every chain (so is its ε-scaling)"))
    m = d.observer_matrices()

    def error_dynamics() -> dict[str, PolyMatrix]:
        J = PolyMatrix.block([[PolyMatrix.identity(nf), PolyMatrix.zeros(nf, n)],
                              [PolyMatrix.zeros(n, nf), -PolyMatrix.identity(n)]])
        Px = PolyMatrix.vstack(PolyMatrix.zeros(nf, n), PolyMatrix.identity(n))
        Ee = d.error_matrix()
        return {
            "J F - (A_e - K C_e) J": J @ m["F"] - Ee @ J,
            "J G_y C + [0; A] - (A_e - K C_e)[0; I]": J @ m["G_y"] @ sysm.C + Px @ sysm.A - Ee @ Px,
            "J (G_y F + G_u) + [0; E]": J @ (m["G_y"] @ sysm.F + m["G_u"]) + Px @ sysm.E,
        }

    add(residual_check("implementation (22) has error dynamics (21)",
                       "e = [z̃; x − x̂] obeys e' = (A_e − K C_e) e for every y = C x + F u and u", error_dynamics))
    return Certificate("high-gain observer with output shaping (Grip & Saberi 2010)", checks)
