"""Strong observability, detectability and invariant zeros of a delay-free system (exact).

For ``x' = A x + B w + E u``, ``y = C x + D w + F u`` (all matrices of δ-degree
0; ``w`` unknown) the Rosenbrock matrix over Q[s] is

    P(s) = [[s I − A, −B], [C, D]]          ((n_x + n_y) × (n_x + n_w))

Its *invariant zeros* are the roots of its non-unit invariant factors (the λ
with ``rank P(λ) < normrank P``).  Hautus (1983); Tranninger et al. (2021), Def. 3 / Prop. 1:

* strongly observable  ⇔ ``V* = {0}`` ⇔ ``rank P(λ) = n_x + rank [B; D]`` for all λ ∈ C
  (left invertible and no invariant zeros);
* strongly detectable  ⇔ ``rank P(λ) = n_x + rank [B; D]`` for all ``Re λ ≥ 0``
  (left invertible and every invariant zero in the open left half plane);
* strong* detectable   ⇔ strongly detectable and the rank (observer-matching)
  condition ``rank [[C B, D], [D, 0]] = rank D + rank [B; D]``.

``rank [B; D]`` (not ``n_w``) makes the test about the *state*: redundant
unknown-input columns do not spoil it.  This is Remark 2, eq. (7) of Zheng et al. (2015),
so Assumption 1 of Zheng et al. (2015) agrees with strong observability on delay-free
systems.  Both the Smith form of ``P(s)`` and the weakly unobservable subspace
``V*`` are computed, and the report says if they disagree (they never should).

Known inputs play no part.

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None)
>>> rep = is_strongly_observable(sys)
>>> rep.holds, rep.invariant_zeros.polynomial
(True, 1)
>>> is_strongly_observable(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[0, 1]]", None)).reason
'invariant zero(s): roots of s ≈ {0}'
>>> print(is_strongly_observable(DelaySystem("[[0, 1], [0, 0]]", "[[1, 0], [0, 1]]", "[[1, 0]]", None)).reason)
the system is not left invertible: normrank P(s) = 3 < n_x + rank [B; D] = 4 (some state directions are masked by the unknown input for every s)
"""

from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction
from typing import Any

from uio_ring.analysis.rank_condition import check_rank_condition
from uio_ring.analysis.report import RankConditionReport, Report
from uio_ring.ring.errors import DomainError
from uio_ring.ring.matrix import Poly, PolyMatrix
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.ring.smith import invariant_factors
from uio_ring.systems.delay_system import DelaySystem

__all__ = [
    "rosenbrock_matrix",
    "invariant_zeros",
    "InvariantZeros",
    "weakly_unobservable_subspace",
    "is_hurwitz_polynomial",
    "StrongObservabilityReport",
    "is_strongly_observable",
    "is_strongly_detectable",
    "is_strong_star_detectable",
    "constant_matrices",
]


def constant_matrices(sys: DelaySystem) -> dict[str, QMatrix]:
    """``A, B, C, D, E, F`` of a delay-free system as exact :class:`~uio_ring.ring.QMatrix`.

    Raises
    ------
    DomainError
        A matrix depends on δ (the message names it).
    """
    out = {}
    for name, M in sys.matrices().items():
        if M.degree() > 0:
            raise DomainError(
                f"{name} has δ-degree {M.degree()}: this analysis is for delay-free systems "
                "(use sys.at_delta(0) for the delay-free part, or the delay analysis of Zheng et al. (2015))"
            )
        out[name] = QMatrix.from_polymatrix(M, name=name)
    return out


def rosenbrock_matrix(sys: DelaySystem, var: str = "s") -> PolyMatrix:
    """``P(s) = [[s I − A, −B], [C, D]]`` over Q[s] for a delay-free system.

    >>> from uio_ring import DelaySystem
    >>> rosenbrock_matrix(DelaySystem("[[1]]", "[[2]]", "[[3]]", "[[4]]"))
    PolyMatrix([[s - 1, -2], [3, 4]])
    """
    M = constant_matrices(sys)
    n, m, p = sys.n_x, sys.n_w, sys.n_y
    A, B, C, D = (M[k].tolist() for k in "ABCD")
    s = Poly.gen(var)
    rows: list[list[Any]] = []
    for i in range(n):
        rows.append([(s if i == j else Poly(0, var)) - A[i][j] for j in range(n)] + [-B[i][j] for j in range(m)])
    for i in range(p):
        rows.append([C[i][j] for j in range(n)] + [D[i][j] for j in range(m)])
    if not rows:
        return PolyMatrix.zeros(0, n + m, var)
    if n + m == 0:
        return PolyMatrix.zeros(n + p, 0, var)
    return PolyMatrix([[Poly(x, var) if not isinstance(x, Poly) else x for x in r] for r in rows], var)


@dataclass(frozen=True)
class InvariantZeros:
    """The invariant zeros of ``P(s)``: exactly as polynomials, numerically as roots.

    Attributes
    ----------
    rosenbrock
        ``P(s)``.
    invariant_factors
        All nonzero invariant factors of ``P(s)`` (monic, each dividing the next).
    factors
        The non-unit ones; their roots are the invariant zeros.
    polynomial
        Their product (``1`` when there are no invariant zeros); its roots with
        multiplicity are the zeros.
    normal_rank
        ``normrank P(s)``.
    roots
        Numerical roots of ``polynomial`` (display only; decisions are exact).
    """

    rosenbrock: PolyMatrix
    invariant_factors: tuple[Poly, ...]
    factors: tuple[Poly, ...]
    polynomial: Poly
    normal_rank: int
    roots: tuple[complex, ...]

    @property
    def count(self) -> int:
        """Number of invariant zeros with multiplicity (degree of ``polynomial``)."""
        return max(self.polynomial.degree(), 0)

    def __str__(self) -> str:
        if not self.factors:
            return f"no invariant zeros (normrank P(s) = {self.normal_rank})"
        rts = ", ".join(f"{r:.6g}" for r in self.roots)
        return f"invariant zeros: roots of {self.polynomial} ≈ {{{rts}}} (normrank P(s) = {self.normal_rank})"

    def to_dict(self) -> dict[str, Any]:
        return {
            "factors": [str(f) for f in self.factors],
            "polynomial": str(self.polynomial),
            "normal_rank": self.normal_rank,
            "roots": [[r.real, r.imag] for r in self.roots],
        }


def invariant_zeros(sys: DelaySystem) -> InvariantZeros:
    """Invariant zeros of a delay-free system from the Smith form of ``P(s)``.

    Parameters
    ----------
    sys
        A delay-free :class:`~uio_ring.systems.DelaySystem` (δ-degree 0).

    Returns
    -------
    InvariantZeros
        ``factors`` (non-unit invariant factors), their product ``polynomial``,
        ``normal_rank`` and numeric ``roots``.

    Algorithm
    ---------
    Invariant factors of ``P(s)`` by the ring (:func:`uio_ring.ring.invariant_factors`);
    Rosenbrock (1970); Tranninger et al. (2021), Def. 2.

    Examples
    --------
    ``1/(s+2)`` realised with a zero at −1: ``x' = −2x + w``, ``y = x + w``.

    >>> from uio_ring import DelaySystem
    >>> z = invariant_zeros(DelaySystem("[[-2]]", "[[1]]", "[[1]]", "[[1]]"))
    >>> z.polynomial, z.roots
    (s + 3, ((-3+0j),))
    """
    P = rosenbrock_matrix(sys)
    fs = tuple(invariant_factors(P)) if P.rows and P.cols else ()
    non_unit = tuple(f for f in fs if not f.is_unit())
    prod = Poly(1, "s")
    for f in non_unit:
        prod = prod * f
    roots = tuple(complex(r) for r in prod.roots()) if prod.degree() > 0 else ()
    return InvariantZeros(P, fs, non_unit, prod, len(fs), roots)


def weakly_unobservable_subspace(sys: DelaySystem) -> QMatrix:
    """A basis (columns) of ``V*``: the initial states that some ``w`` keeps invisible (``y ≡ 0``).

    Recursion ``V_0 = Qⁿ``, ``V_{k+1} = {x : ∃ w, A x + B w ∈ V_k, C x + D w = 0}``
    (Trentelman, Stoorvogel & Hautus 2001, Thm. 7.11), exact over Q.  The basis is
    the transposed reduced row echelon form (unique for the subspace).

    >>> from uio_ring import DelaySystem
    >>> weakly_unobservable_subspace(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[0, 1]]", None))
    QMatrix([[1], [0]])
    """
    M = constant_matrices(sys)
    A, B, C, D = M["A"], M["B"], M["C"], M["D"]
    n, p = sys.n_x, sys.n_y
    V = QMatrix.identity(n)
    while True:
        # invariant: V_k ⊇ V* and V_{k+1} ⊆ V_k; the dimension drops until it is constant
        r = V.cols
        # [[A, B, -V], [C, D, 0]] [x; w; ξ] = 0
        K = QMatrix.block([[A, B, -V], [C, D, QMatrix.zeros(p, r)]]).nullspace()
        echelon = K[0:n, :].T.rref()
        Vn = echelon.R[0 : echelon.rank, :].T
        if Vn.cols == r:
            return Vn
        V = Vn


def is_hurwitz_polynomial(p: Poly) -> bool:
    """True iff every root of ``p`` has negative real part (exact Routh test; constants: True).

    >>> s = Poly.gen("s")
    >>> is_hurwitz_polynomial(s**2 + 3*s + 2), is_hurwitz_polynomial(s**2 + 1), is_hurwitz_polynomial(s - 1)
    (True, False, False)
    """
    if p.is_zero():
        return False
    cs = list(reversed(p.coeffs()))  # highest degree first
    deg = len(cs) - 1
    if deg == 0:
        return True
    if cs[0] < 0:
        cs = [-c for c in cs]
    width = deg // 2 + 1
    row0 = (cs[0::2] + [Fraction(0)] * width)[:width]
    row1 = (cs[1::2] + [Fraction(0)] * width)[:width]
    first = [row0[0]]
    for _ in range(deg):
        if row1[0] <= 0:
            return False
        first.append(row1[0])
        new = [row0[k + 1] - row0[0] * row1[k + 1] / row1[0] for k in range(width - 1)] + [Fraction(0)]
        row0, row1 = row1, new
    return all(c > 0 for c in first)


@dataclass(frozen=True)
class StrongObservabilityReport(Report):
    """Verdict on strong observability, strong detectability or strong* detectability.

    Attributes
    ----------
    kind
        ``"strongly observable"``, ``"strongly detectable"`` or ``"strong* detectable"``.
    holds
        The verdict.
    reason
        Why it fails (empty when it holds).
    n_x, rank_BD
        ``n_x`` and ``rank [B; D]``; the target rank of ``P(λ)`` is their sum.
    zeros
        The :class:`InvariantZeros` (with ``normal_rank``).
    left_invertible
        ``normrank P(s) = n_x + rank [B; D]``.
    dim_V_star
        ``dim V*`` from the subspace recursion (0 iff strongly observable);
        ``None`` when the cross-check was skipped (``cross_check=False``).
    rank_condition
        For strong* detectability: the rank (observer-matching) report; else ``None``.
    """

    kind: str
    holds: bool
    reason: str
    n_x: int
    rank_BD: int
    zeros: InvariantZeros
    left_invertible: bool
    dim_V_star: int | None
    rank_condition: RankConditionReport | None = None

    @property
    def invariant_zeros(self) -> InvariantZeros:
        return self.zeros

    @property
    def name(self) -> str:
        return f"{self.kind} (Hautus 1983; Tranninger et al. 2021, Prop. 1)"

    def _detail_lines(self) -> list[str]:
        lines = [
            f"normrank P(s) = {self.zeros.normal_rank}, n_x + rank [B; D] = {self.n_x + self.rank_BD}, "
            f"dim V* = {'not computed' if self.dim_V_star is None else self.dim_V_star}",
            str(self.zeros),
        ]
        if self.rank_condition is not None:
            lines.append("rank condition: " + ("holds" if self.rank_condition.holds else "fails"))
        return lines

    def to_dict(self) -> dict[str, Any]:
        return {
            "property": self.kind,
            "holds": self.holds,
            "reason": self.reason,
            "n_x": self.n_x,
            "rank_BD": self.rank_BD,
            "left_invertible": self.left_invertible,
            "dim_V_star": self.dim_V_star,
            "invariant_zeros": self.zeros.to_dict(),
            "rank_condition": None if self.rank_condition is None else self.rank_condition.to_dict(),
        }


def _common(sys: DelaySystem, cross_check: bool = True) -> tuple[InvariantZeros, int, bool, int | None, str]:
    M = constant_matrices(sys)
    rank_BD = QMatrix.vstack(M["B"], M["D"]).rank()
    z = invariant_zeros(sys)
    left_inv = z.normal_rank == sys.n_x + rank_BD
    dimV = weakly_unobservable_subspace(sys).cols if cross_check else None
    why_not_left = (
        f"the system is not left invertible: normrank P(s) = {z.normal_rank} < n_x + rank [B; D] = "
        f"{sys.n_x + rank_BD} (some state directions are masked by the unknown input for every s)"
    )
    return z, rank_BD, left_inv, dimV, why_not_left


def _consistency(so: bool, dimV: int | None) -> None:
    if dimV is not None and so != (dimV == 0):  # pragma: no cover - would be a ring bug
        raise AssertionError(f"Smith form and V* disagree on strong observability (dim V* = {dimV})")


def is_strongly_observable(sys: DelaySystem, *, cross_check: bool = True) -> StrongObservabilityReport:
    """Strong observability: ``rank P(λ) = n_x + rank [B; D]`` for every λ ∈ C.

    Equivalently ``V* = {0}``: ``y ≡ 0`` forces ``x ≡ 0`` whatever the unknown
    input.  This is what the observer normal form of Niederwieser et al. (2022) needs (its
    Assumption 2.3), and what Assumption 1 of Zheng et al. (2015) says at δ = 0.

    Parameters
    ----------
    sys
        A delay-free system.
    cross_check
        Also compute ``V*`` by the subspace recursion and insist that it agrees
        with the Smith form (default).  ``False`` skips it (faster for large n).

    Returns
    -------
    StrongObservabilityReport
        Never raises because the property fails; ``reason`` names the invariant
        zeros or the loss of left invertibility.

    Examples
    --------
    >>> from uio_ring import DelaySystem
    >>> rep = is_strongly_observable(DelaySystem("[[-2]]", "[[1]]", "[[1]]", "[[1]]"))
    >>> rep.holds, rep.reason
    (False, 'invariant zero(s): roots of s + 3 ≈ {-3}')
    """
    z, rank_BD, left_inv, dimV, why = _common(sys, cross_check)
    holds = left_inv and not z.factors
    _consistency(holds, dimV)
    if holds:
        reason = ""
    elif not left_inv:
        reason = why
    else:
        reason = f"invariant zero(s): roots of {z.polynomial} ≈ {{{', '.join(format_root(r) for r in z.roots)}}}"
    return StrongObservabilityReport("strongly observable", holds, reason, sys.n_x, rank_BD, z, left_inv, dimV)


def format_root(r: complex) -> str:
    """A root for display: ``-10``, ``-0.5+0.866025j``.

    >>> format_root(complex(-10, 0)), format_root(complex(-0.5, 3 ** 0.5 / 2))
    ('-10', '-0.5+0.866025j')
    """
    if abs(r.imag) < 1e-12 * max(1.0, abs(r.real)):
        return f"{r.real:.6g}"
    return f"{r.real:.6g}{r.imag:+.6g}j"


def is_strongly_detectable(sys: DelaySystem) -> StrongObservabilityReport:
    """Strong detectability: ``rank P(λ) = n_x + rank [B; D]`` for every ``Re λ ≥ 0``.

    Left invertible and minimum phase (all invariant zeros in the open left half
    plane, decided exactly by a Routh test on the zero polynomial).

    Examples
    --------
    >>> from uio_ring import DelaySystem
    >>> sys = DelaySystem("[[-2]]", "[[1]]", "[[1]]", "[[1]]")   # zero at −3
    >>> is_strongly_detectable(sys).holds, is_strongly_observable(sys).holds
    (True, False)
    """
    z, rank_BD, left_inv, dimV, why = _common(sys)
    stable = is_hurwitz_polynomial(z.polynomial)
    holds = left_inv and stable
    if holds:
        reason = ""
    elif not left_inv:
        reason = why
    else:
        bad = [r for r in z.roots if r.real >= -1e-12]
        reason = (
            f"non-minimum phase: the invariant zeros (roots of {z.polynomial}) include "
            f"{{{', '.join(format_root(r) for r in bad) or 'a root on the imaginary axis'}}} with Re ≥ 0"
        )
    return StrongObservabilityReport("strongly detectable", holds, reason, sys.n_x, rank_BD, z, left_inv, dimV)


def is_strong_star_detectable(sys: DelaySystem) -> StrongObservabilityReport:
    """Strong* detectability: strongly detectable and the rank condition
    ``rank [[C B, D], [D, 0]] = rank D + rank [B; D]`` (Hautus 1983; Tranninger et al. 2021, (8)).

    It is what a *linear* unknown-input observer needs.

    Examples
    --------
    >>> from uio_ring import DelaySystem
    >>> rep = is_strong_star_detectable(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", None))
    >>> rep.holds, rep.reason.split(":")[0]
    (False, 'the rank (observer-matching) condition fails')
    """
    det = is_strongly_detectable(sys)
    rc = check_rank_condition(sys)
    hautus = rc.hautus_rank_condition
    holds = det.holds and hautus
    if holds:
        reason = ""
    elif not det.holds:
        reason = det.reason
    else:
        reason = (
            f"the rank (observer-matching) condition fails: rank [[CB, D], [D, 0]] = {rc.rank_M} ≠ "
            f"rank D + rank [B; D] = {rc.rank_D} + {rc.rank_BD}"
        )
    return StrongObservabilityReport(
        "strong* detectable", holds, reason, det.n_x, det.rank_BD, det.zeros, det.left_invertible,
        det.dim_V_star, rc,
    )
