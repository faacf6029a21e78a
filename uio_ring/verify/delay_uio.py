"""Certificate of a Zheng–Bejarano delay UIO (Zheng et al. 2015): every identity, exactly.

The checks read the design's named matrices and its ``system`` (duck-typed, so
this module depends on the ring only).  Each check holds iff its residual is
exactly zero; a failed check carries the nonzero residual(s).

The decisive one is *Theorem 4*: with ``z = T x``, the observer
``ξ' = L0 ξ + J Λ y + J_u u``, ``ẑ = ξ + H Λ y + H_u u`` and ``e = z − ẑ``,

    e' − L0 e = [T A − (J − L0 H) Λ C − H Λ C A − L0 T] x
              + [T B − (J − L0 H) Λ D − H Λ C B] w − H Λ D w'
              + [T E − (J − L0 H) Λ F − H Λ C E − J_u + L0 H_u] u − (H Λ F + H_u) u'

(docs/errata.md, Z2; the ``u`` terms are ours).  The observer is exact iff all
these coefficients vanish.

>>> from uio_ring import DelaySystem, design_zheng_bejarano
>>> des = design_zheng_bejarano(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None))
>>> cert = delay_uio_certificate(des)
>>> cert.ok, cert["Theorem 4: e' − L0 e = 0"].ok
(True, True)
"""

from __future__ import annotations

import functools
from typing import Any

from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.inverse import is_unimodular
from uio_ring.ring.kernel import left_kernel
from uio_ring.ring.matrix import Poly, PolyMatrix
from uio_ring.verify.checks import residual_check

__all__ = ["delay_uio_certificate", "charpoly"]

_Z = PolyMatrix.zeros
_I = PolyMatrix.identity


def delay_uio_certificate(design: Any) -> Certificate:
    """All identities of Steps 1–5 and Theorem 4 of Zheng et al. (2015) for ``design``.

    Parameters
    ----------
    design
        A :class:`~uio_ring.design.zheng_bejarano.DelayUIODesign` (or any object
        with the same attribute names and a ``system``).

    Returns
    -------
    Certificate
        Named checks; ``.ok`` iff all hold.  The checks, in order: Step 1
        (``U`` unimodular, ``U M = [V; 0]``), Lemma 2 (1) and (2), Step 2
        definitions of ``Ā`` and ``C̃``, (9) for ``Λ``, (12) for ``Ō_{l*}``
        and its left inverse, Theorem 2 (``T Ā = A0 T + F C̄``, ``C0 T = C̄``),
        ``T_L⁻¹ T = I``, (11)/(20), the normal form (19′) (state and output
        equations), (22′) for ``H`` and ``J``, Theorem 4, and the spectrum of
        ``A0 − G0 C0`` (requested values, and Hurwitz).
    """
    d = design
    sys = d.system
    A, B, C, D, E, Fu = sys.A, sys.B, sys.C, sys.D, sys.E, sys.F
    n, m, p = sys.n_x, sys.n_w, sys.n_y
    checks: list[Check] = []

    def add(name: str, statement: str, fn: Any) -> None:
        checks.append(residual_check(name, statement, fn))

    M = PolyMatrix.block([[C @ B, D], [D, _Z(p, m)]])

    # Step 1 ---------------------------------------------------------------------
    def step1() -> Any:
        if not is_unimodular(d.U):
            return f"U is not unimodular (det U = {d.U.det()})"
        return {"U M − [V; 0]": d.U @ M - PolyMatrix.vstack(d.V, _Z(2 * p - d.V.rows, 2 * m))}

    add("Step 1: U M = [V; 0]", "U unimodular, U [[CB, D], [D, 0]] = [V; 0]", step1)
    target = PolyMatrix.block([[B, _Z(n, m)], [D, _Z(p, m)]])
    add("Lemma 2(1): W M = [[B, 0], [D, 0]]", "W = [Vbar, 0] U, W [[CB, D], [D, 0]] = [[B, 0], [D, 0]]",
        lambda: {"W M − [[B, 0], [D, 0]]": d.W @ M - target,
                 "W − [Vbar, 0] U": d.W - PolyMatrix.hstack(d.Vbar, _Z(n + p, 2 * p - d.V.rows)) @ d.U})
    add("Lemma 2(2): annihilators of [B; D] annihilate W",
        "N [B; D] = 0 ⇒ N W = 0, for a basis N of the left kernel of [B; D]",
        lambda: {"N W": left_kernel(PolyMatrix.vstack(B, D)) @ d.W})

    # Step 2 ---------------------------------------------------------------------
    CA_C = PolyMatrix.vstack(C @ A, C)
    add("Step 2: Ā and C̃", "W = [[K1, K2], [Γ1, Γ2]], Ā = A − K [CA; C], C̃ = C − Γ [CA; C]",
        lambda: {
            "Ā − (A − K [CA; C])": d.A_bar - (A - d.K @ CA_C),
            "C̃ − (C − Γ [CA; C])": d.C_tilde - (C - d.Gamma @ CA_C),
            "[K; Γ] − W": PolyMatrix.vstack(d.K, d.Gamma) - d.W,
            "[K1, K2] − K": PolyMatrix.hstack(d.K1, d.K2) - d.K,
            "[Γ1, Γ2] − Γ": PolyMatrix.hstack(d.Gamma1, d.Gamma2) - d.Gamma,
        })

    def lam() -> Any:
        if not is_unimodular(d.Lam):
            return f"Λ is not unimodular (det Λ = {d.Lam.det()})"
        if d.C_tilde.rank() != d.r:
            return f"r = {d.r} but rank C̃ = {d.C_tilde.rank()}"
        return {
            "Λ C̃ − [C̄; 0]": d.Lam @ d.C_tilde - PolyMatrix.vstack(d.C_bar, _Z(p - d.r, n)),
            "Λ Λ⁻¹ − I": d.Lam @ d.Lam_inverse - _I(p),
        }

    add("(9): Λ C̃ = [C̄; 0]", "Λ unimodular, Λ C̃ = [C̄; 0], r = rank C̃", lam)

    # Step 3 ---------------------------------------------------------------------
    def obs() -> Any:
        # Ō = [C̄; C̄Ā; …; C̄Ā^{l*−1}] ⇔ its first block is C̄ and each next block is the one
        # before times Ā (induction): one product Ō_top Ā, Ō_top = Ō without its last block.
        # A polynomial Ō_L⁻¹ with Ō_L⁻¹ Ō = I is what "Ō left unimodular" means
        # (uio_ring.ring.inverse): the zero residual proves it, no elimination of Ō needed.
        r_, rows = d.C_bar.rows, d.O.rows
        if rows != r_ * d.l_star:
            return f"Ō_{{l*}} has {rows} rows, not r·l* = {r_}·{d.l_star}"
        # block by block: each product is sized by its own block's degree and coefficients
        # (one product of the stacked blocks pads every block to the largest)
        steps = [d.O[k * r_:(k + 1) * r_, :] - d.O[(k - 1) * r_:k * r_, :] @ d.A_bar for k in range(1, d.l_star)]
        return {"Ō − [C̄; C̄Ā; …]": PolyMatrix.vstack(d.O[:r_, :] - d.C_bar, *steps),
                "Ō_L⁻¹ Ō − I": d.O_left_inverse @ d.O - _I(n)}

    add("(12): Ō_{l*} left unimodular", "Ō_{l*} = [C̄; …; C̄Ā^{l*−1}] left unimodular, Ō_L⁻¹ Ō = I", obs)
    add("Theorem 2: T Ā = A0 T + F C̄", "z = T x brings (13) to the normal form",
        lambda: {"T Ā − A0 T − F C̄": d.T @ d.A_bar - d.A0 @ d.T - d.F_stack @ d.C_bar})
    add("Theorem 2: C0 T = C̄", "output of the normal form",
        lambda: {"C0 T − C̄": d.C0 @ d.T - d.C_bar})
    add("(15): T_L⁻¹ T = I", "T is a bicausal generalised change of coordinates",
        lambda: {"T_L⁻¹ T − I": d.T_left_inverse @ d.T - _I(n)})

    # Step 4 ---------------------------------------------------------------------
    add("(11), (20): Γ̄i and K̄i", "Γ̄i = Λ Γi Λ⁻¹, K̄i = T Ki Λ⁻¹",
        lambda: {
            "Γ̄1 − Λ Γ1 Λ⁻¹": d.Gamma1_bar - d.Lam @ d.Gamma1 @ d.Lam_inverse,
            "Γ̄2 − Λ Γ2 Λ⁻¹": d.Gamma2_bar - d.Lam @ d.Gamma2 @ d.Lam_inverse,
            "K̄1 − T K1 Λ⁻¹": d.K1_bar - d.T @ d.K1 @ d.Lam_inverse,
            "K̄2 − T K2 Λ⁻¹": d.K2_bar - d.T @ d.K2 @ d.Lam_inverse,
        })

    nz, r = d.T.rows, d.r
    F0 = PolyMatrix.hstack(d.F_stack, _Z(nz, p - r))
    L = d.Lam
    @functools.cache
    def small() -> tuple[PolyMatrix, ...]:
        # the small products of Λ with the system, once, inside the first check that needs
        # them (shapes that do not fit fail that check): a tall X times Λ C A costs an
        # n_z × n_y × n_x product instead of n_z × n_x × n_x; the residuals are the same
        LC = L @ C
        return LC, L @ D, L @ Fu, LC @ A, LC @ B, LC @ E

    @functools.cache
    def t_products() -> tuple[PolyMatrix, PolyMatrix]:
        return d.T @ A, d.T @ B  # in (19′) and in Theorem 4

    def nf_state() -> Any:
        # z = T x, z' = T(Ax + Bw), ȳ = Λ(Cx + Dw), ȳ' = Λ(CAx + CBw + Dw'), u = 0
        LC, LD, _, LCA, LCB, _ = small()
        TA, TB = t_products()
        P1 = d.K1_bar - F0 @ d.Gamma1_bar
        P2 = F0 + d.K2_bar - F0 @ d.Gamma2_bar
        return {
            "x": TA - d.A0 @ d.T - P2 @ LC - P1 @ LCA,
            "w": TB - P2 @ LD - P1 @ LCB,
            "w'": P1 @ LD,
        }

    add("(19′) state equation",
        "z' = A0 z + [F,0]ȳ + (K̄1 − [F,0]Γ̄1)ȳ' + (K̄2 − [F,0]Γ̄2)ȳ along solutions with u = 0",
        nf_state)

    def nf_output() -> Any:
        LC, LD, _, LCA, LCB, _ = small()
        C0z = PolyMatrix.vstack(d.C0, _Z(p - r, nz))
        return {
            "x": LC - C0z @ d.T - d.Gamma1_bar @ LCA - d.Gamma2_bar @ LC,
            "w": LD - d.Gamma1_bar @ LCB - d.Gamma2_bar @ LD,
            "w'": d.Gamma1_bar @ LD,
        }

    add("(19′) output equation", "ȳ = [C0; 0] z + Γ̄1 ȳ' + Γ̄2 ȳ along solutions with u = 0", nf_output)

    # Step 5 ---------------------------------------------------------------------
    def gains() -> Any:
        FG0 = PolyMatrix.hstack(d.F_stack + d.G0, _Z(nz, p - r))
        H = d.K1_bar - FG0 @ d.Gamma1_bar
        return {
            "L0 − (A0 − G0 C0)": d.L0 - (d.A0 - d.G0 @ d.C0),
            "H − (22′)": d.H - H,
            "J − (22′)": d.J - (FG0 @ (_I(p) - d.Gamma2_bar) + d.K2_bar + d.L0 @ H),
        }

    add("(22′): L0, H, J", "L0 = A0 − G0C0, H = K̄1 − [F+G0,0]Γ̄1, J = [F+G0,0](I−Γ̄2) + K̄2 + L0H", gains)

    def theorem4() -> Any:
        LC, LD, LF, LCA, LCB, LCE = small()
        TA, TB = t_products()
        JL = d.J - d.L0 @ d.H
        parts = {
            "x": TA - JL @ LC - d.H @ LCA - d.L0 @ d.T,
            "w": TB - JL @ LD - d.H @ LCB,
            "w'": d.H @ LD,
        }
        if sys.n_u:
            parts["u"] = d.T @ E - JL @ LF - d.H @ LCE - d.J_u + d.L0 @ d.H_u
            parts["u'"] = d.H @ LF + d.H_u
        return parts

    add("Theorem 4: e' − L0 e = 0",
        "the coefficients of x, w, w' (and u, u') in e' − L0 e vanish, e = T x − ẑ", theorem4)

    def spectrum() -> Any:
        want = Poly(1, "s")
        for q in d.poles:
            want = want * (Poly.gen("s") - Poly(q, "s"))
        want = want**r
        got = charpoly(d.L0)
        return None if got == want else f"det(sI − L0) = {got}; requested {want}"

    add("spectrum of A0 − G0 C0", "det(sI − (A0 − G0C0)) = Π(s − p_i)^r for the requested poles p_i",
        spectrum)
    add("A0 − G0 C0 Hurwitz", "every requested pole is negative",
        lambda: None if all(q < 0 for q in d.poles)
        else f"poles {[str(q) for q in d.poles if q >= 0]} are not negative")
    return Certificate("Zheng–Bejarano delay UIO (Zheng et al. 2015)", checks)
