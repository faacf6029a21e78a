"""Which unknown-input observers exist for a delay-free system: Table 1 of Tranninger et al. (2021).

From the special coordinate basis (:mod:`uio_ring.analysis.scb`):

* ``n_c > 0`` (not left invertible) or an invariant zero with ``Re ≥ 0``: **no** UIO of
  any kind (not strongly detectable; Lemma 4 ii);
* ``n_a > 0`` with ``A_a`` Hurwitz: **asymptotic only** — ``x_a`` is copied open loop
  and converges at the rate of the invariant zeros, which nothing can change;
* ``n_a = 0`` (strongly observable): **finite- or fixed-time** observers exist
  (nonlinear on both ``x_b`` and ``x_d``);
* all ``q_i = 1`` (strong* detectable): ``x_d`` is read off the outputs, the observer
  is **linear**; otherwise ``x_d`` needs sliding-mode differentiators (HOSMO/DBHO).

The parts, as Table 1: ``x̂_a`` linear (asymptotic) when ``n_a > 0``; ``x̂_b`` linear
(asymptotic, assignable rate) or CBHO (fixed-time); ``x̂_d`` linear exact
(``x̂_d = y_d``) or 1-SMO when every ``q_i = 1``, else HOSMO (finite-time) or DBHO.

>>> from uio_ring import DelaySystem
>>> rep = observer_options(DelaySystem("[[-2, 1, 0], [0, 0, 1], [0, 0, 0]]", "[[0], [0], [1]]",
...                                    "[[0, 1, 0]]", None))
>>> rep.holds, rep.convergence, rep.x_d[0]
(True, 'asymptotic', 'HOSMO (finite-time)')
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from uio_ring.analysis.report import Report
from uio_ring.analysis.scb import (
    SCBDimensions,
    SpecialCoordinateBasis,
    scb_dimensions,
    special_coordinate_basis,
)
from uio_ring.analysis.strong_observability import format_root, is_hurwitz_polynomial
from uio_ring.ring.errors import DimensionError
from uio_ring.ring.matrix import Poly
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["ObserverOptions", "observer_options"]


def _roots(p: Poly) -> str:
    if p.degree() < 1:
        return "none"
    return "{" + ", ".join(format_root(complex(x)) for x in p.roots()) + "}"


@dataclass(frozen=True)
class ObserverOptions(Report):
    """The observer classes that exist for a system (Table 1), and why.

    Attributes
    ----------
    holds
        Some unknown-input observer exists (strongly detectable).
    reason
        Why none exists (empty when one does).
    dimensions
        ``(n_a, n_b, n_c, n_d, m_0)`` (:class:`~uio_ring.analysis.scb.SCBDimensions`); ``None`` for delay systems.
    scb
        The special coordinate basis (``None`` when ``n_c > 0`` or the system has delays).
    strongly_observable, strongly_detectable, strong_star_detectable
        Lemma 4's verdicts read off the SCB.
    convergence
        ``"finite-time"`` (strongly observable: finite/fixed time possible), ``"asymptotic"``
        (stable invariant zeros fix the rate of ``x_a``) or ``"none"``.
    x_a, x_b, x_d
        The observer choices of Table 1 for each part (empty when the part is absent).
    """

    holds: bool
    reason: str
    dimensions: SCBDimensions | None
    scb: SpecialCoordinateBasis | None
    strongly_observable: bool
    strongly_detectable: bool
    strong_star_detectable: bool
    convergence: str
    x_a: tuple[str, ...] = ()
    x_b: tuple[str, ...] = ()
    x_d: tuple[str, ...] = ()
    zero_polynomial: Poly | None = None

    name = "unknown-input observers that exist (Tranninger et al. 2021, Table 1)"

    @property
    def linear(self) -> bool:
        """A linear UIO exists (strong* detectable)."""
        return self.strong_star_detectable

    def _detail_lines(self) -> list[str]:
        lines = []
        if self.dimensions is not None:
            d = self.dimensions
            q = f", q = {self.scb.q}, l = {self.scb.l}" if self.scb is not None else ""
            lines.append(f"SCB: (n_a, n_b, n_c, n_d) = ({d.n_a}, {d.n_b}, {d.n_c}, {d.n_d}), m_0 = {d.m_0}{q}")
        if self.zero_polynomial is not None and self.zero_polynomial.degree() > 0:
            lines.append(f"invariant zeros {_roots(self.zero_polynomial)} (roots of {self.zero_polynomial})")
        lines.append(f"strongly observable: {_yn(self.strongly_observable)}; strongly detectable: "
                     f"{_yn(self.strongly_detectable)}; strong* detectable: {_yn(self.strong_star_detectable)}")
        if self.holds:
            lines.append(f"convergence: {self.convergence}" + (
                " (x_a converges at the rate of the invariant zeros)" if self.convergence == "asymptotic" else
                " possible (nonlinear observers on x_b and x_d; uio_ring's scb observer is linear on x_b, "
                "hierarchical-sta and normal-form are finite-time)"))
            for part, choices in (("x_a", self.x_a), ("x_b", self.x_b), ("x_d", self.x_d)):
                if choices:
                    lines.append(f"{part}: " + " or ".join(choices))
        return lines

    def to_dict(self) -> dict[str, Any]:
        return {
            "holds": self.holds, "reason": self.reason, "convergence": self.convergence,
            "strongly_observable": self.strongly_observable, "strongly_detectable": self.strongly_detectable,
            "strong_star_detectable": self.strong_star_detectable,
            "dimensions": None if self.dimensions is None else vars(self.dimensions).copy(),
            "q": None if self.scb is None else list(self.scb.q), "l": None if self.scb is None else list(self.scb.l),
            "x_a": list(self.x_a), "x_b": list(self.x_b), "x_d": list(self.x_d),
        }


def _yn(b: bool) -> str:
    return "yes" if b else "no"


def observer_options(sys: DelaySystem) -> ObserverOptions:
    """Table 1 of Tranninger et al. (2021) for a delay-free system: which observers exist and why.

    Parameters
    ----------
    sys
        Any :class:`~uio_ring.DelaySystem`; systems with delays get ``holds = False`` with
        the reason (this classification is for δ-degree 0).

    Returns
    -------
    ObserverOptions
        A report (``holds``: some UIO exists); ``uio-ring check`` prints it.

    Examples
    --------
    Paper 001's assumptions at δ = 0 are the last column of Table 1 (strongly
    observable and strong* detectable):

    >>> from uio_ring import DelaySystem
    >>> rep = observer_options(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None))
    >>> rep.strongly_observable, rep.linear, rep.convergence, rep.x_d[0]
    (True, True, 'finite-time', 'linear, exact (x̂_d = y_d)')
    """
    if not sys.is_delay_free:
        return ObserverOptions(False, "Table 1 classifies delay-free systems; this one has delays (see the "
                               "Zheng-Bejarano analysis)", None, None, False, False, False, "none")
    try:
        dims = scb_dimensions(sys)
    except DimensionError as exc:  # dependent unknown-input columns or outputs: the SCB is not defined
        return ObserverOptions(False, f"the special coordinate basis is not defined: {exc}", None, None, False, False,
                               False, "none")
    if dims.n_c:
        return ObserverOptions(
            False, f"not strongly detectable: the system is not left invertible (n_c = {dims.n_c}): some state "
            "directions are masked by the unknown input for every s, so no observer of any kind exists",
            dims, special_coordinate_basis(sys), False, False, False, "none")
    scb = special_coordinate_basis(sys)
    zp = scb.invariant_zero_polynomial
    stable = is_hurwitz_polynomial(zp)
    observable = scb.n_a == 0
    star = stable and all(k == 1 for k in scb.q)
    if not stable:
        bad = [r for r in (complex(x) for x in zp.roots()) if r.real >= -1e-12]
        shown = ", ".join(format_root(r) for r in bad) or _roots(zp)
        return ObserverOptions(
            False, f"not strongly detectable: invariant zero(s) with Re ≥ 0 ({shown}; roots of {zp}): the zero "
            "dynamics x_a cannot be reconstructed, not even asymptotically", dims, scb, False, False, False, "none",
            zero_polynomial=zp)
    x_a = ("linear copy, asymptotic at the invariant zeros' rate",) if scb.n_a else ()
    x_b = ("linear (asymptotic, assignable poles)", "CBHO (fixed-time)") if scb.n_b else ()
    if not scb.n_d:
        x_d: tuple[str, ...] = ()
    elif all(k == 1 for k in scb.q):
        x_d = ("linear, exact (x̂_d = y_d)", "1-SMO (finite-time)")
    else:
        x_d = ("HOSMO (finite-time)", "DBHO (finite-/fixed-time)")
    return ObserverOptions(True, "", dims, scb, observable, True, star, "finite-time" if observable else "asymptotic",
                           x_a, x_b, x_d, zero_polynomial=zp)
