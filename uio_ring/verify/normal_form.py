"""Certificate of an observer-normal-form design (Niederwieser et al. 2022): every identity, exactly.

The checks read the design's named matrices (duck-typed).  Coordinates:
``x̄ = T⁻¹ x`` of the *model* (the plant after the feed-through reduction and,
for input reconstruction, the augmentation ``[x; w]``).

Package notation: ``B̄ = T⁻¹ B`` (unknown input; the paper's D̄), ``Ē = T⁻¹ E``
(known inputs; the paper's B̄).

* (21a)–(21c): ``T Ā = A T``, ``T B̄ = B``, ``Γ C T = C̄``; ``T Ē = E`` (known inputs).
* (11b): shift chains, ``α`` only in the first column of each block, ``β`` only
  at rows ``e_r`` of later blocks with ``l ≥ μ_r`` (53); Remark 3.2: ``(Ā − Π̄ C̄)ⁿ = 0``.
* (11c): ``B̄`` zero outside the last row of each chain; (11d): ``C̄ = [e_{b_j+1}ᵀ]``.
* (12): ``μ`` nonincreasing, ``Σ μ = n``.  Step 1: ``Ǎ = A + Ξ C``, ``Č = Γ C``,
  (27) ``č_j Ǎ^i B = 0`` for ``i ≤ μ_j − 2``; ``O_R`` as in (25), nonsingular.
* Plant ↔ model: the observer's signals ``ȳ = output_map [y; u]`` and
  ``ū = input_map [y; u]`` satisfy ``ȳ = C̄ x̄`` and ``x̄' = Ā x̄ + B̄ w̃ + Ē ū`` for
  every plant trajectory (Appendix A.1; Section 5.4).
* (18): ``κ_{j,0} > Σ_i L_i |b̄_{e_j,i}|``.

>>> from uio_ring import DelaySystem, design_normal_form
>>> des = design_normal_form(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None), [1])
>>> cert = normal_form_certificate(des)
>>> cert.ok, len(cert) > 10
(True, True)
"""

from __future__ import annotations

from typing import Any

from uio_ring.ring.certificate import Certificate
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.verify.checks import residual_check

__all__ = ["normal_form_certificate"]

_Z = PolyMatrix.zeros
_I = PolyMatrix.identity




def _entries(M: PolyMatrix) -> list[list[Any]]:
    if M.rows == 0 or M.cols == 0:
        return [[] for _ in range(M.rows)]
    return M.coefficient_lists()[0]


def _structure_11b(d: Any) -> str | None:
    mu, n = d.mu, d.n
    starts, ends = d.block_starts, d.block_ends
    block = [j for j, m in enumerate(mu) for _ in range(m)]
    A = _entries(d.A_bar)
    bad = []
    for c in range(n):
        j = block[c]
        if c == starts[j]:
            continue  # α column (dense)
        l = c - starts[j]  # column b_j + l + 1 (1-based) ⇒ l = 1 … μ_j − 1
        for r in range(n):
            v = A[r][c]
            if r == c - 1:
                if v != 1:
                    bad.append(f"Ā[{r + 1},{c + 1}] = {v}, expected 1 (shift chain)")
                continue
            rb = block[r]
            if r == ends[rb] and rb > j and l >= mu[rb]:
                continue  # β_{j, rb, l}
            if v != 0:
                bad.append(f"Ā[{r + 1},{c + 1}] = {v}, expected 0")
    return "; ".join(bad[:5]) or None


def _b_bar_rows(d: Any) -> str | None:
    Bb = _entries(d.B_bar)
    ends = set(d.block_ends)
    bad = [f"B̄[{r + 1},{c + 1}] = {Bb[r][c]}" for r in range(d.n) if r not in ends for c in range(d.B_bar.cols) if Bb[r][c] != 0]
    return ("nonzero outside the last rows: " + "; ".join(bad[:5])) if bad else None


def _c_bar(d: Any) -> dict[str, PolyMatrix]:
    E = _Z(d.p, d.n)
    rows = [[1 if c == s else 0 for c in range(d.n)] for s in d.block_starts]
    E = PolyMatrix(rows) if rows else E
    return {"C̄ − [e_{b_j+1}ᵀ]": d.C_bar - E}


def _mu(d: Any) -> str | None:
    mu = list(d.mu)
    if mu != sorted(mu, reverse=True) or sum(mu) != d.n or any(m < 1 for m in mu):
        return f"mu = {tuple(mu)}, n = {d.n}"
    return None


def _eq27(d: Any) -> str | None:
    B = d.model.B
    bad = []
    for j, m in enumerate(d.mu):
        r = d.C_check[j : j + 1, 0 : d.n]
        for i in range(m - 1):
            if not (r @ B).is_zero():
                bad.append(f"č_{j + 1} Ǎ^{i} B ≠ 0")
            r = r @ d.A_check
    return "; ".join(bad) or None


def _O_R(d: Any) -> dict[str, PolyMatrix] | str:
    rows = []
    for j, m in enumerate(d.mu):
        r = d.C_check[j : j + 1, 0 : d.n]
        for _ in range(m):
            rows.append(r)
            r = r @ d.A_check
    O = PolyMatrix.vstack(*rows)
    if O.rank() < d.n:
        return f"O_R has rank {O.rank()} < {d.n}"
    return {"O_R − [č_j Ǎ^i]": d.O_R - O}


def _plant_model(d: Any) -> dict[str, PolyMatrix]:
    """ȳ = C̄ x̄ and x̄' = Ā x̄ + B̄ w̃ + Ē ū along every plant trajectory.

    Plant signals ``s = [x; w; u]`` (without reconstruction) or, with it,
    ``[x; w; u]`` with the model state ``χ = [x; w]`` and new input ``w'``.
    """
    sys = d.system
    n, m, nu = sys.n_x, sys.n_w, sys.n_u
    A, B, C, D, E, F = sys.A, sys.B, sys.C, sys.D, sys.E, sys.F
    # measured [y; u] as a function of s = [x; w; u]
    yu = PolyMatrix.block([[C, D, F], [_Z(nu, n), _Z(nu, m), _I(nu)]])
    Ti = d.T_inverse
    if d.reconstruct_input:
        # χ = [x; w]: χ = P s with P = [[I, 0, 0], [0, I, 0]]
        P = PolyMatrix.block([[_I(n), _Z(n, m), _Z(n, nu)], [_Z(m, n), _I(m), _Z(m, nu)]])
        # χ' = [A x + B w + E u; w'] : split into the part in s and the part in w'
        ds = PolyMatrix.block([[A, B, E], [_Z(m, n), _Z(m, m), _Z(m, nu)]])
        dw = PolyMatrix.vstack(_Z(n, m), _I(m))
        lhs_s = Ti @ ds - d.A_bar @ Ti @ P - d.E_bar @ d.input_map @ yu
        lhs_w = Ti @ dw - d.B_bar  # the model's unknown input is w' itself
        return {
            "ȳ − C̄ x̄": d.output_map @ yu - d.C_bar @ Ti @ P,
            "x̄' − (Ā x̄ + Ē ū) [s-part]": lhs_s,
            "x̄' − B̄ w' [w'-part]": lhs_w,
            "x − state_map x̄": PolyMatrix.hstack(_I(n), _Z(n, m)) - d.state_map @ Ti,
            "w − w_map x̄": PolyMatrix.hstack(_Z(m, n), _I(m)) - d.w_map @ Ti,
        }
    P = PolyMatrix.hstack(_I(n), _Z(n, m + nu))
    # the model's unknown input: w̃_1 = (V⁻¹ w)_{rank_D:}; B̄ w̃_1 = B̄ Vinv_1 w
    Vinv = d.V.eval(0) if m else d.V
    Vinv = _inverse(Vinv) if m else Vinv
    W1 = PolyMatrix.hstack(_Z(m - d.rank_D, n), Vinv[d.rank_D : m, 0:m], _Z(m - d.rank_D, nu)) if m > d.rank_D else _Z(0, n + m + nu)
    ds = PolyMatrix.hstack(A, B, E)
    lhs = Ti @ ds - d.A_bar @ Ti @ P - d.E_bar @ d.input_map @ yu
    if W1.rows:
        lhs = lhs - d.B_bar @ W1
    return {
        "ȳ − C̄ x̄": d.output_map @ yu - d.C_bar @ Ti @ P,
        "x̄' − (Ā x̄ + B̄ w̃ + Ē ū)": lhs,
        "x − state_map x̄": _I(n) - d.state_map @ Ti,
    }


def _inverse(V: PolyMatrix) -> PolyMatrix:
    return QMatrix(V).inverse(name="V").to_polymatrix(V.var)


def _feedthrough(d: Any) -> dict[str, PolyMatrix] | None:
    sys = d.system
    if d.reconstruct_input or sys.n_w == 0 or sys.n_y == 0:
        return None
    r, p, m = d.rank_D, sys.n_y, sys.n_w
    target = PolyMatrix.block([[_I(r), _Z(r, m - r)], [_Z(p - r, r), _Z(p - r, m - r)]])
    return {"U D V − [[I, 0], [0, 0]]": d.U @ sys.D @ d.V - target}


def _cond18(d: Any) -> str | None:
    bad = []
    for j, (k0, need) in enumerate(d.condition_18()):
        if need and not k0 > need:
            bad.append(f"κ_{j + 1},0 = {k0} ≤ {need}")
        if any(k <= 0 for k in d.kappa[j]):
            bad.append(f"chain {j + 1} has a gain ≤ 0")
    return "; ".join(bad) or None


def normal_form_certificate(design: Any) -> Certificate:
    """All identities of the observer normal form (11), Steps 1–4, Appendix A and (18).

    Parameters
    ----------
    design
        A :class:`~uio_ring.design.normal_form.NormalFormDesign`.

    Returns
    -------
    Certificate
        One :class:`Check` per identity; ``ok`` iff all hold exactly.
    """
    d = design
    A, B, C, E = d.model.A, d.model.B, d.model.C, d.model.E
    n = d.n
    checks = [
        residual_check("T nonsingular", "det T ≠ 0 (Lemma 4.1(b))", lambda: None if d.T.rank() == n else "T is singular"),
        residual_check("T T⁻¹ = I", "T_inverse is the inverse of T", lambda: {"T T⁻¹ − I": d.T @ d.T_inverse - _I(n)}),
        residual_check("Γ nonsingular", "det Γ ≠ 0", lambda: None if d.Gamma.rank() == d.Gamma.rows else "Γ is singular"),
        residual_check("(21a) T⁻¹ A T = Ā", "T Ā = A T", lambda: {"T Ā − A T": d.T @ d.A_bar - A @ d.T}),
        residual_check("(21b) T⁻¹ B = B̄", "T B̄ = B (the unknown input; paper's D̄ = T⁻¹ D)", lambda: {"T B̄ − B": d.T @ d.B_bar - B}),
        residual_check("(21c) Γ C T = C̄", "Γ C T = C̄", lambda: {"Γ C T − C̄": d.Gamma @ C @ d.T - d.C_bar}),
        residual_check("Ē = T⁻¹ E", "T Ē = E (known inputs; paper's B̄ = T⁻¹ B)", lambda: {"T Ē − E": d.T @ d.E_bar - E}),
        residual_check("(12) μ", "μ_1 ≥ … ≥ μ_p ≥ 1, Σ μ = n", lambda: _mu(d)),
        residual_check("(11b) structure of Ā", "shift chains; α in first-of-block columns; β at rows e_r, r > j, l ≥ μ_r", lambda: _structure_11b(d)),
        residual_check("(13c) Π̄", "Π̄ = first-of-block columns of Ā",
             lambda: {"Π̄ − Ā[:, b_j+1]": d.Pi_bar - PolyMatrix.hstack(*[d.A_bar[0:n, s : s + 1] for s in d.block_starts])}),
        residual_check("Remark 3.2: Ā − Π̄ C̄ nilpotent", "(Ā − Π̄ C̄)ⁿ = 0", lambda: {"(Ā − Π̄C̄)ⁿ": (d.A_bar - d.Pi_bar @ d.C_bar) ** n}),
        residual_check("(11c) B̄", "B̄ is zero outside the rows e_1, …, e_p", lambda: _b_bar_rows(d)),
        residual_check("(11d) C̄", "C̄ = [e_{b_j+1}ᵀ]", lambda: _c_bar(d)),
        residual_check("(22) Ǎ = A + Ξ C", "Ǎ − A − Ξ C = 0", lambda: {"Ǎ − A − ΞC": d.A_check - A - d.Xi @ C}),
        residual_check("(24) Č = Γ C", "Č − Γ C = 0", lambda: {"Č − ΓC": d.C_check - d.Gamma @ C}),
        residual_check("(27) relative degrees", "č_j Ǎ^i B = 0 for i ≤ μ_j − 2", lambda: _eq27(d)),
        residual_check("(25) O_R", "O_R = [č_j Ǎ^i], nonsingular", lambda: _O_R(d)),
        residual_check("plant ↔ normal form", "ȳ = C̄ x̄, x̄' = Ā x̄ + B̄ w̃ + Ē ū along every plant trajectory", lambda: _plant_model(d)),
        residual_check("(18) κ_{j,0} > Σ L_i |b̄_{e_j,i}|", "the necessary gain condition, exactly", lambda: _cond18(d)),
    ]
    ft = _feedthrough(d)
    if ft is not None:
        checks.append(residual_check("(A1) U D V", "U D V = [[I_{rank_D}, 0], [0, 0]]", lambda: ft))
    return Certificate("observer normal form (Niederwieser et al. 2022)", checks)
