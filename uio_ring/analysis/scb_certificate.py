"""The certificate of a special coordinate basis: (17a)–(23), Theorem 1 and Lemma 3 as named exact checks.

>>> from uio_ring import DelaySystem
>>> from uio_ring.analysis.scb import special_coordinate_basis
>>> scb_certificate(special_coordinate_basis(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None))).ok
True
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from uio_ring.analysis.scb_steps import (
    chain_starts,
    hstack,
    intersection,
    reduce_system,
    shift_matrix,
    vstack,
)
from uio_ring.analysis.strong_observability import (
    constant_matrices,
    invariant_zeros,
    is_strongly_observable,
    weakly_unobservable_subspace,
)
from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.errors import UioRingError
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.systems.delay_system import DelaySystem

if TYPE_CHECKING:
    from uio_ring.analysis.scb import SpecialCoordinateBasis

__all__ = ["scb_certificate"]

Q = QMatrix


def _check(name: str, lhs: QMatrix, rhs: QMatrix, statement: str = "") -> Check:
    ok = lhs.shape == rhs.shape and lhs == rhs
    return Check(name, ok, None if ok else (lhs - rhs if lhs.shape == rhs.shape else f"{lhs.shape} vs {rhs.shape}"),
                 statement)


def _assembled(scb: SpecialCoordinateBasis) -> QMatrix:
    """``Ā_s`` rebuilt from the blocks of (17a); ``UioRingError`` when the ``x_a`` columns of the
    ``x_c`` rows are not of the form ``B_c F_ca``."""
    na, nb, nc, nd = scb.n_a, scb.n_b, scb.n_c, scb.n_d
    Cb, Cd, Bd, Bc = Q(scb.C_b), Q(scb.C_d), Q(scb.B_d), Q(scb.B_c)
    Z = Q.zeros
    rows = [
        [Q(scb.A_a), Q(scb.H_ab) @ Cb, Z(na, nc), Q(scb.H_ad) @ Cd],
        [Z(nb, na), Q(scb.A_b), Z(nb, nc), Q(scb.H_bd) @ Cd],
        [Bc @ Q(scb.F_ca), Q(scb.H_cb) @ Cb, Q(scb.A_c), Q(scb.H_cd) @ Cd],
        [Bd @ Q(scb.F_da), Bd @ Q(scb.F_db), Bd @ Q(scb.F_dc), Q(scb.A_d)],
    ]
    n = na + nb + nc + nd
    return vstack([hstack(r, size) for r, size in zip(rows, (na, nb, nc, nd), strict=True)], n) if n else Z(0, 0)


def theorem1_violations(scb: SpecialCoordinateBasis) -> list[tuple[int, int]]:
    """Entries ``(i, col)`` of ``F_dd`` outside the pattern (24) (0-based chain i, d column)."""
    F = Q(scb.F_dd)
    starts = chain_starts(scb.q)
    owner = [j for j, qj in enumerate(scb.q) for _ in range(qj)]
    out = []
    for i in range(F.rows):
        for c in range(F.cols):
            if F[i, c] and (owner[c] >= i or c in starts):
                out.append((i, c))
    return out


def scb_certificate(scb: SpecialCoordinateBasis) -> Certificate:
    """Named exact checks of a :class:`SpecialCoordinateBasis`.

    The transformations (nonsingular; ``Ā = Ts⁻¹ A Ts`` etc.), the patterns (17a),
    (17b), (18)–(23), the dimension identities, and Lemma 3 of Tranninger et al. (2021):
    (p.1) normrank G = m_0 + m_d, (p.2) ``det(sI − A_a)`` is the invariant-zero
    polynomial of ``P(s)`` (Smith form), (p.3) (A_b, C_b) observable, (p.4)
    (A_d, B_d, C_d) strongly observable, (p.5) left invertible ⇔ n_c = 0, (p.6) the
    ``x_a`` and ``x_c`` columns of ``Ts`` span ``V*``, (p.7) the ``x_c`` columns span ``R*``.  The zeros are computed on
    the transformed system: its Rosenbrock matrix is ``diag(Ts⁻¹, To⁻¹) P(s) diag(Ts, Ti)`` (a constant
    unimodular equivalence once ``Ā = Ts⁻¹ A Ts`` etc. hold), so its invariant factors are those of ``P(s)``.
    """
    sys = scb.system
    M = constant_matrices(sys)
    A, B, C, D = M["A"], M["B"], M["C"], M["D"]
    Ts, Ti, To = Q(scb.Ts), Q(scb.Ti), Q(scb.To)
    n, m, p = sys.n_x, sys.n_w, sys.n_y
    checks: list[Check] = []
    nonsingular = all(T.is_square() and (T.rows == 0 or T.det() != 0) for T in (Ts, Ti, To))
    checks.append(Check("Ts, Ti, To nonsingular", nonsingular, None if nonsingular else "a singular transformation"))
    if not nonsingular:
        return Certificate("special coordinate basis", checks)
    Tsi = Ts.inverse() if n else Ts
    Toi = To.inverse() if p else To
    checks += [
        _check("Ā = Ts⁻¹ A Ts", Q(scb.A_bar), Tsi @ A @ Ts),
        _check("B̄ = Ts⁻¹ B Ti", Q(scb.B_bar), Tsi @ B @ Ti),
        _check("C̄ = To⁻¹ C Ts", Q(scb.C_bar), Toi @ C @ Ts),
        _check("D̄ = To⁻¹ D Ti", Q(scb.D_bar), Toi @ D @ Ti),
    ]
    na, nb, nc, nd, m0, md, pb = scb.n_a, scb.n_b, scb.n_c, scb.n_d, scb.m_0, scb.m_d, scb.p_b
    mc = scb.m_c
    sizes = (na + nb + nc + nd == n and m0 + md + mc == m and m0 + md + pb == p
             and list(scb.q) == sorted(scb.q, reverse=True) and all(k >= 1 for k in scb.q + scb.l)
             and (mc > 0) == (nc > 0))
    checks.append(Check("sizes: n = n_a + Σl + n_c + Σq, m = m_0 + m_d + m_c, p = m_0 + m_d + p_b, "
                        "q non-increasing", sizes,
                        None if sizes else (na, nb, nc, nd, m0, md, mc, pb, scb.q, scb.l)))
    if not sizes:
        return Certificate("special coordinate basis", checks)
    try:
        assembled: QMatrix | str = _assembled(scb)
    except UioRingError as exc:
        assembled = str(exc)
    if isinstance(assembled, str):
        checks.append(Check("(17a) Ā − B̄_0 C̄_0 has the SCB block pattern", False, assembled))
    else:
        checks.append(_check("(17a) Ā − B̄_0 C̄_0 has the SCB block pattern", Q(scb.A_s), assembled))
    Bd_full = vstack([Q.zeros(na + nb + nc, md), Q(scb.B_d)], md) if md else Q.zeros(n, 0)
    Bc_full = vstack([Q.zeros(na + nb, mc), Q(scb.B_c), Q.zeros(nd, mc)], mc) if mc else Q.zeros(n, 0)
    checks.append(_check("(17a) B̄ = [B̄_0, [0; 0; 0; B_d], [0; 0; B_c; 0]]", Q(scb.B_bar),
                         hstack([Q(scb.B_0), Bd_full, Bc_full], n)))
    Cbar = vstack([Q(scb.C_0),
                    hstack([Q.zeros(md, na + nb + nc), Q(scb.C_d)], md) if md else Q.zeros(0, n),
                    hstack([Q.zeros(pb, na), Q(scb.C_b), Q.zeros(pb, nc + nd)], pb) if pb else Q.zeros(0, n)], n)
    checks.append(_check("(17b) C̄ = [C̄_0; [0, 0, 0, C_d]; [0, C_b, 0, 0]]", Q(scb.C_bar), Cbar))
    Dbar = Q([[1 if (i == j and i < m0) else 0 for j in range(m)] for i in range(p)], shape=(p, m))
    checks.append(_check("(17b) D̄ = [[I_m0, 0], [0, 0]]", Q(scb.D_bar), Dbar))
    checks.append(_check("(18)–(19) A_b = A_b* + H_bb C_b", Q(scb.A_b),
                         shift_matrix(scb.l) + Q(scb.H_bb) @ Q(scb.C_b) if nb else Q.zeros(0, 0)))
    checks.append(_check("(20)–(23) A_d = A_d* + B_d F_dd + H_dd C_d", Q(scb.A_d),
                         shift_matrix(scb.q) + Q(scb.B_d) @ Q(scb.F_dd) + Q(scb.H_dd) @ Q(scb.C_d) if nd else Q.zeros(0, 0)))
    bad = theorem1_violations(scb)
    checks.append(Check("Theorem 1: F_dd lower triangular as (24) (row i only in columns 2…q_j of chains j < i)",
                        not bad, bad or None))
    # Lemma 3
    # P̄(s) = diag(Ts⁻¹, To⁻¹) P(s) diag(Ts, Ti) (identities checked above): the same invariant factors,
    # computed on the sparse SCB form (the original's entries can be large)
    zeros = invariant_zeros(DelaySystem(scb.A_bar, scb.B_bar, scb.C_bar, scb.D_bar))
    checks.append(Check("(p.1) normrank G(s) = m_0 + m_d", zeros.normal_rank - n == m0 + md,
                        None if zeros.normal_rank - n == m0 + md else f"normrank G = {zeros.normal_rank - n}"))
    zp, ap = zeros.polynomial, scb.invariant_zero_polynomial
    ok = ap == zp
    checks.append(Check("(p.2) det(sI − A_a) = invariant-zero polynomial of P(s)", ok,
                        None if ok else f"{ap} vs {zp}"))
    obs = Q(scb.C_b)
    Ab = Q(scb.A_b)
    stack, row = [], obs
    for _ in range(nb):
        stack.append(row)
        row = row @ Ab
    ok = nb == 0 or vstack(stack, nb).rank() == nb
    checks.append(Check("(p.3) (A_b, C_b) observable", ok, None if ok else "rank of the observability matrix < n_b"))
    if nd:
        so = is_strongly_observable(DelaySystem(scb.A_d, scb.B_d, scb.C_d, None), cross_check=False).holds
    else:
        so = True
    checks.append(Check("(p.4) (A_d, B_d, C_d) strongly observable (no invariant zeros)", so,
                        None if so else "the d subsystem has invariant zeros"))
    ok = (zeros.normal_rank == n + m) == (nc == 0)
    checks.append(Check("(p.5) left invertible (normrank P = n + m) ⇔ n_c = 0", ok,
                        None if ok else f"normrank P = {zeros.normal_rank}, n + m = {n + m}, n_c = {nc}"))
    V = weakly_unobservable_subspace(sys) if n else Q.zeros(0, 0)
    Tac = Ts.take_cols([*range(na), *range(na + nb, na + nb + nc)])
    ok = V.cols == na + nc and (V.cols == 0 or hstack([V, Tac], n).rank() == V.cols)
    checks.append(Check("(p.6) the x_a and x_c columns of Ts span V*", ok,
                        None if ok else f"dim V* = {V.cols}, n_a + n_c = {na + nc}"))
    red = reduce_system(sys)
    Tc = Ts.take_cols(range(na + nb, na + nb + nc))
    Tcd = Ts.take_cols(range(na + nb, n))
    R = intersection(red.V, red.S)
    ok = (R.cols == nc and (nc == 0 or hstack([R, Tc], n).rank() == nc)
          and hstack([red.S, Tcd], n).rank() == red.S.cols == nc + nd)
    checks.append(Check("(p.7) the x_c columns of Ts span R* = V* ∩ S* (and x_c, x_d span S*)", ok,
                        None if ok else f"dim R* = {R.cols}, dim S* = {red.S.cols}, n_c = {nc}, n_d = {nd}"))
    return Certificate("special coordinate basis", checks)
