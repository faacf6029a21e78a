"""Report objects of the structural analysis (Assumptions 1 and 2 of Zheng et al. (2015)).

A ``check_*`` function never raises because an assumption fails: it returns
a frozen report, whose ``holds`` says the verdict and ``reason`` says why not.
Every verdict report of the analysis layer derives from :class:`Report`, which
writes the display once: ``str`` (a headline, the report's detail lines, the
reason when it fails) and ``_repr_html_`` for notebooks.  Reports also convert
to plain data (``to_dict``).

>>> from uio_ring import PolyMatrix, Poly
>>> r = RankConditionReport(M=PolyMatrix("[[1]]"), M_with_B=PolyMatrix("[[1], [0]]"),
...     factors_without_B=(Poly(1),), factors_with_B=(Poly(1),),
...     rank_M=1, rank_BD=1, rank_D=0, holds=True, reason="")
>>> r.to_dict()["holds"], "holds" in str(r)
(True, True)
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from uio_ring.ring.matrix import Poly, PolyMatrix

__all__ = ["Report", "ObservabilityReport", "RankConditionReport", "AssumptionsReport"]


def _factors_str(fs: Sequence[Poly]) -> str:
    return "{" + ", ".join(str(f) for f in fs) + "}"


def _factors_latex(fs: Sequence[Poly]) -> str:
    return r"\{" + ", ".join(f.to_latex() for f in fs) + r"\}"


def _matrix_str(M: PolyMatrix, indent: str = "      ") -> str:
    return str(M).replace("\n", "\n" + indent)


def _verdict(holds: bool) -> str:
    return "holds" if holds else "FAILS"


class Report:
    """Base of the verdict reports: ``holds``, ``reason`` and the display, written once.

    A subclass (a frozen dataclass) provides ``holds`` (the verdict), ``reason``
    (why it fails; empty when it holds) and ``name`` (what was checked), as
    fields or properties, and may list details: :meth:`_detail_lines` (plain
    text, one item per line; items may span lines) and :meth:`_detail_html`
    (defaults to the escaped lines).

    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Demo(Report):
    ...     holds: bool
    ...     reason: str = ""
    ...     name = "demo property"
    ...     def _detail_lines(self) -> list[str]:
    ...         return ["x = 1"]
    >>> print(Demo(False, "x is odd"))
    demo property: FAILS
      x = 1
      reason: x is odd
    >>> Demo(True)._repr_html_()
    '<b>demo property</b>: holds<br>x = 1'
    """

    if TYPE_CHECKING:

        @property
        def holds(self) -> bool: ...

        @property
        def reason(self) -> str: ...

        @property
        def name(self) -> str: ...

    def _detail_lines(self) -> list[str]:
        """Lines shown under the headline (plain text)."""
        return []

    def _detail_html(self) -> str:
        """HTML shown under the headline (default: the detail lines, escaped)."""
        return "<br>".join(html.escape(line).replace("\n", "<br>") for line in self._detail_lines())

    def __str__(self) -> str:
        lines = [f"{self.name}: {_verdict(self.holds)}"]
        lines += ["  " + line.replace("\n", "\n  ") for line in self._detail_lines()]
        if not self.holds:
            lines.append(f"  reason: {self.reason}")
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        reason = "" if self.holds else f"<br>reason: {html.escape(self.reason)}"
        details = self._detail_html()
        return f"<b>{html.escape(self.name)}</b>: {_verdict(self.holds)}{reason}" + (f"<br>{details}" if details else "")


@dataclass(frozen=True)
class ObservabilityReport(Report):
    """Algorithm (4)–(5) of Zheng et al. (2015) and the verdict on Assumption 1.

    Attributes
    ----------
    n_x
        Number of states.
    Delta, N, M
        The sequences ``Δ_k``, ``N_k`` and ``M_k`` for ``k = 0, …, k*+1``
        (``Δ_0 = N_0`` has no rows; ``M_k = diag(ψ_1^k, …)`` holds the invariant
        factors of ``N_k``).
    invariant_factors
        ``invariant_factors[k]`` are the (nonzero) invariant factors of ``N_k``.
    k_star
        The least k with ``M_{k+1} = M_k``.
    rank
        ``rank M_{k*}`` (= rank of ``N_{k*}`` over Q[δ]).
    holds
        Assumption 1: ``rank M_{k*} = n_x`` and ``M_{k*}`` unimodular.
    reason
        Why it fails (empty when it holds).
    non_unit_factors
        The invariant factors of ``N_{k*}`` that are not units.
    """

    n_x: int
    Delta: tuple[PolyMatrix, ...]
    N: tuple[PolyMatrix, ...]
    M: tuple[PolyMatrix, ...]
    invariant_factors: tuple[tuple[Poly, ...], ...]
    k_star: int
    rank: int
    holds: bool
    reason: str
    non_unit_factors: tuple[Poly, ...] = ()

    @property
    def name(self) -> str:
        return "Assumption 1 (unknown-input observability, algorithm (4)–(5))"

    def _detail_lines(self) -> list[str]:
        lines = [f"k* = {self.k_star}, rank M_k* = {self.rank}, n_x = {self.n_x}"]
        for k, fs in enumerate(self.invariant_factors):
            if not fs:
                M = "[] (0×0)"
            elif all(f.is_unit() for f in fs):
                M = f"I_{len(fs)}"
            else:
                M = "diag" + _factors_str(fs)
            lines.append(
                f"k = {k}: Δ_{k} has {self.Delta[k].rows} row(s); M_{k} = {M} "
                f"(invariant factors of N_{k}: {_factors_str(fs)})"
            )
        return lines

    def _detail_html(self) -> str:
        rows = "".join(
            f"<tr><td>{k}</td><td>\\({self.Delta[k].to_latex()}\\)</td>"
            f"<td>\\({self.M[k].to_latex()}\\)</td></tr>"
            for k in range(len(self.M))
        )
        return (
            f"k* = {self.k_star}, rank M<sub>k*</sub> = {self.rank}, n<sub>x</sub> = {self.n_x}"
            f"<table><tr><th>k</th><th>Δ<sub>k</sub></th><th>M<sub>k</sub></th></tr>{rows}</table>"
        )

    def _repr_latex_(self) -> str:
        ms = r",\; ".join(f"M_{{{k}}} = {M.to_latex()}" for k, M in enumerate(self.M))
        return rf"$$\text{{Assumption 1 {_verdict(self.holds)}}}:\; k^* = {self.k_star},\; {ms}$$"

    def to_dict(self) -> dict[str, Any]:
        return {
            "assumption": 1,
            "holds": self.holds,
            "reason": self.reason,
            "k_star": self.k_star,
            "rank": self.rank,
            "n_x": self.n_x,
            "invariant_factors": [[str(f) for f in fs] for fs in self.invariant_factors],
            "non_unit_factors": [str(f) for f in self.non_unit_factors],
            "Delta": [[[str(x) for x in row] for row in D.tolist()] for D in self.Delta],
        }


@dataclass(frozen=True)
class RankConditionReport(Report):
    """Assumption 2 of Zheng et al. (2015): ``Inv_S [[CB, D], [D, 0], [B, 0]] = Inv_S [[CB, D], [D, 0]]``.

    For a delay-free system this is the observer-matching / rank condition of
    Hautus; Zheng et al. (2015), (3): ``rank M = rank [B; D] + rank D`` with
    ``M = [[CB, D], [D, 0]]`` (together with ``rank [M; [B, 0]] = rank M``).

    Attributes
    ----------
    M, M_with_B
        ``[[CB, D], [D, 0]]`` and ``[[CB, D], [D, 0], [B, 0]]``.
    factors_without_B, factors_with_B
        Their nonzero invariant factors.
    rank_M, rank_BD, rank_D
        Ranks over Q[δ] of ``M``, ``[B; D]`` and ``D``.
    holds, reason
        The verdict and, when it fails, why.
    """

    M: PolyMatrix
    M_with_B: PolyMatrix
    factors_without_B: tuple[Poly, ...]
    factors_with_B: tuple[Poly, ...]
    rank_M: int
    rank_BD: int
    rank_D: int
    holds: bool
    reason: str

    @property
    def name(self) -> str:
        return "Assumption 2 (rank / observer-matching condition (6))"

    @property
    def hautus_rank_condition(self) -> bool:
        """Zheng et al. (2015), (3): ``rank M = rank [B; D] + rank D`` (ranks over Q(δ))."""
        return self.rank_M == self.rank_BD + self.rank_D

    def _detail_lines(self) -> list[str]:
        return [
            f"Inv_S [[CB, D], [D, 0], [B, 0]] = {_factors_str(self.factors_with_B)}",
            f"Inv_S [[CB, D], [D, 0]]         = {_factors_str(self.factors_without_B)}",
            f"rank M = {self.rank_M}, rank [B; D] + rank D = {self.rank_BD} + {self.rank_D}",
        ]

    def _detail_html(self) -> str:
        return (
            f"\\(\\operatorname{{Inv}}_S {self.M_with_B.to_latex()} = {_factors_latex(self.factors_with_B)}\\), "
            f"\\(\\operatorname{{Inv}}_S {self.M.to_latex()} = {_factors_latex(self.factors_without_B)}\\)"
        )

    def _repr_latex_(self) -> str:
        return (
            rf"$$\text{{Assumption 2 {_verdict(self.holds)}}}:\;"
            rf"\operatorname{{Inv}}_S {self.M_with_B.to_latex()} = {_factors_latex(self.factors_with_B)},\;"
            rf"\operatorname{{Inv}}_S {self.M.to_latex()} = {_factors_latex(self.factors_without_B)}$$"
        )

    def to_dict(self) -> dict[str, Any]:
        return {
            "assumption": 2,
            "holds": self.holds,
            "reason": self.reason,
            "factors_with_B": [str(f) for f in self.factors_with_B],
            "factors_without_B": [str(f) for f in self.factors_without_B],
            "rank_M": self.rank_M,
            "rank_BD": self.rank_BD,
            "rank_D": self.rank_D,
        }


@dataclass(frozen=True)
class AssumptionsReport(Report):
    """Both assumptions of Zheng et al. (2015) for one system; ``holds`` iff both hold."""

    observability: ObservabilityReport
    rank_condition: RankConditionReport

    @property
    def holds(self) -> bool:
        return self.observability.holds and self.rank_condition.holds

    @property
    def failed(self) -> tuple[str, ...]:
        """Names of the failed assumptions, e.g. ``("Assumption 2",)``."""
        out = []
        if not self.observability.holds:
            out.append("Assumption 1")
        if not self.rank_condition.holds:
            out.append("Assumption 2")
        return tuple(out)

    @property
    def reason(self) -> str:
        parts = []
        if not self.observability.holds:
            parts.append(f"Assumption 1 fails: {self.observability.reason}")
        if not self.rank_condition.holds:
            parts.append(f"Assumption 2 fails: {self.rank_condition.reason}")
        return "; ".join(parts)

    @property
    def name(self) -> str:
        return "Assumptions 1 and 2 (Zheng et al. 2015)"

    def _detail_lines(self) -> list[str]:
        return [str(self.observability), str(self.rank_condition)]

    def _detail_html(self) -> str:
        return self.observability._repr_html_() + "<br>" + self.rank_condition._repr_html_()

    def to_dict(self) -> dict[str, Any]:
        return {
            "holds": self.holds,
            "failed": list(self.failed),
            "reason": self.reason,
            "assumption_1": self.observability.to_dict(),
            "assumption_2": self.rank_condition.to_dict(),
        }
