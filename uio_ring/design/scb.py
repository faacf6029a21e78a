"""Unknown-input observers in the special coordinate basis (Tranninger et al. 2021, Section 5).

In SCB coordinates ``x̄ = Ts⁻¹ x``, ``ȳ = To⁻¹ (y − F u)`` (see :mod:`uio_ring.analysis.scb`)
the observer is three pieces, each fed by the *measured* outputs:

* ``x̂_a' = A_a x̂_a + H_ab y_b + H_ad y_d + B_0a y_0``                      (37)
  — an open-loop copy, converging at the rate of the invariant zeros;
* ``x̂_b' = A_b x̂_b + H_bd y_d + B_0b y_0 + L_b (y_b − C_b x̂_b)``          (39)
  — Luenberger, ``spec(A_b − L_b C_b)`` assignable (``poles_b``); or the continuous
  bi-homogeneous observer (CBHO, (56)): ``L_b`` replaced by ``H_bb`` plus a Moreno
  injection ``κ_{b,j} Φ_j(y_{b,i} − x̂_{b,i,1})`` per chain (fixed-time, Theorem 3);
* ``x̂_d``: ``y_d`` itself when every chain has length 1 (41, exact from t = 0);
  otherwise the higher-order sliding-mode observer (47) with a Levant
  differentiator per chain (``1-smo`` when every ``q_i = 1``)::

      x̂_d' = (A_d − H_dd C_d) x̂_d + B_d (F_da x̂_a + F_db x̂_b) + B_0d y_0 + H_dd y_d + L_d(y_d − C_d x̂_d)

  with the gains of Theorem 2 from the input bounds (45) (Levant's parameters,
  ``κ_{i,q_i} = 1.1 Δ_{d,i} > Δ_{d,i}``); or the discontinuous bi-homogeneous observer
  (DBHO, (60)): the same linear part with Moreno's injection ``κ_j Φ_j(σ_i)``, ``d0 = −1``
  (finite-time for ``−1 ≤ d_inf < 0``, fixed-time for ``0 < d_inf < 1/(q_i − 1)``,
  Theorem 4).  The CBHO and DBHO gains are our rule (:mod:`uio_ring.design.bihom`).

Then ``x̂ = Ts x̂̄``.  The error of each piece is (38), (40), (52): ``e_a' = A_a e_a``,
``e_b' = (A_b − L_b C_b) e_b`` — exactly, whatever ``w`` does — and the chains of
``e_d`` converge in finite time, one after another.

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[-2, 1, 0], [0, 0, 1], [0, 0, 0]]", "[[0], [0], [1]]", "[[0, 1, 0]]", None)
>>> des = design_scb(sys, input_bounds=[1])
>>> des.d_observer, [float(k) for k in des.kappa[0]], des.certificate().ok
('hosmo', [1.5, 1.1], True)
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, ClassVar

from uio_ring.analysis.observer_classes import ObserverOptions, observer_options
from uio_ring.analysis.scb import SpecialCoordinateBasis
from uio_ring.analysis.scb_steps import chain_starts
from uio_ring.design.base import ObserverDesign, matrix_to_data
from uio_ring.design.bihom import check_cbho, check_dbho, default_cbho, default_d_inf, scaled_gains
from uio_ring.design.red_gains import levant_gains
from uio_ring.errors import (
    DimensionError,
    DomainError,
    NotObservableError,
    NotSupportedError,
    OptionError,
    for_option,
)
from uio_ring.ring.certificate import Certificate
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import exact_fraction
from uio_ring.ring.qmatrix import QMatrix as Q
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["SCBDesign", "design_scb", "input_bound_d", "sign_weight", "B_OBSERVERS", "D_OBSERVERS"]

#: Observers of the ``x_b`` part: Luenberger (39) or the continuous bi-homogeneous observer (56).
B_OBSERVERS = ("linear", "cbho")
#: Observers of the ``x_d`` part: (41), first-order SMO, HOSMO (47), discontinuous bi-homogeneous (60).
D_OBSERVERS = ("linear", "1-smo", "hosmo", "dbho")


def input_bound_d(G_d: Q, ranges: Sequence[tuple[Fraction, Fraction]]) -> tuple[Fraction, ...]:
    """(45): ``Δ_{d,i} = Σ_j |g_{ij}| u_{s,j} + |Σ_j g_{ij} u_{o,j}|`` — the largest ``|w_{d,i}|``
    over the box ``w_j ∈ [lo_j, hi_j]`` with ``w_d = G_d w`` (tight: a vertex attains it).

    >>> input_bound_d(Q([[1, 2]]), [(Fraction(-1), Fraction(1)), (Fraction(0), Fraction(1))])
    (Fraction(3, 1),)
    """
    uo = [(lo + hi) / 2 for lo, hi in ranges]
    us = [(hi - lo) / 2 for lo, hi in ranges]
    rows = G_d.tolist()
    return tuple(sum((abs(g) * s for g, s in zip(r, us, strict=True)), Fraction(0))
                 + abs(sum((g * o for g, o in zip(r, uo, strict=True)), Fraction(0))) for r in rows)


def _ranges(input_bounds: Any, input_ranges: Any, m: int) -> tuple[tuple[Fraction, Fraction], ...] | None:
    if input_bounds is not None and input_ranges is not None:
        raise for_option(DimensionError("give input_bounds (|w_i| ≤ L_i) or input_ranges ([lo_i, hi_i]), not both"),
                         "input_ranges")
    if input_ranges is not None:
        rows = [tuple(exact_fraction(v, f"input_ranges[{i}]") for v in r) for i, r in enumerate(input_ranges)]
        if len(rows) != m or any(len(r) != 2 for r in rows):
            raise for_option(DimensionError(f"input_ranges needs {m} pairs [lo, hi] (one per unknown input)"), "input_ranges")
        if any(lo > hi for lo, hi in rows):
            raise for_option(DomainError("input_ranges: every pair needs lo ≤ hi"), "input_ranges")
        return tuple((r[0], r[1]) for r in rows)
    if input_bounds is None:
        return None
    if isinstance(input_bounds, (int, float, str, Fraction)):
        input_bounds = [input_bounds] * m
    Ls = [exact_fraction(v, f"input_bounds[{i}]") for i, v in enumerate(input_bounds)]
    if len(Ls) != m:
        raise for_option(DimensionError(f"input_bounds has {len(Ls)} entries; expected {m} (one per unknown input)"),
                         "input_bounds")
    if any(L < 0 for L in Ls):
        raise for_option(DomainError("input_bounds must be ≥ 0"), "input_bounds")
    return tuple((-L, L) for L in Ls)


def _luenberger_gain(scb: SpecialCoordinateBasis, poles: Sequence[Fraction]) -> Q:
    """``L_b`` with ``spec(A_b − L_b C_b) = poles``: chain i (length l_i) gets the next l_i poles;
    ``A_b − L_b C_b = blkdiag(J − k_i e_1ᵀ)`` with ``s^l + k_1 s^{l−1} + … + k_l = Π (s − p)``."""
    from uio_ring.ring.matrix import Poly

    nb, pb = scb.n_b, scb.p_b
    K = [[Fraction(0)] * pb for _ in range(nb)]
    s0, used = 0, 0
    for i, li in enumerate(scb.l):
        poly = Poly(1, "s")
        for pole in poles[used:used + li]:
            poly = poly * (Poly.gen("s") - Poly(pole, "s"))
        cs = poly.coeffs()  # a_0 … a_l (a_l = 1)
        for k in range(li):
            K[s0 + k][i] = Fraction(cs[li - 1 - k])
        s0 += li
        used += li
    return Q(scb.H_bb) + Q(K, shape=(nb, pb)) if nb else Q.zeros(0, pb)


@dataclass(frozen=True)
class SCBDesign(ObserverDesign):
    """An unknown-input observer in the special coordinate basis (Tranninger et al. 2021).

    Attributes
    ----------
    system, scb, options
        The system, its :class:`~uio_ring.analysis.scb.SpecialCoordinateBasis` and the
        Table 1 report.
    b_observer, d_observer
        ``"linear"``; ``"linear"`` (x̂_d = y_d), ``"1-smo"`` or ``"hosmo"``.
    poles_b, L_b
        ``spec(A_b − L_b C_b)`` and the gain (n_b × p_b).
    input_ranges, Delta_d, kappa
        The box of ``w`` (of ``w'`` with ``reconstruct_input``), the bounds (45) of ``w_d``
        and the differentiator gains per chain (top row first); empty for the linear ``x_d``.
    reconstruct_input
        ``scb`` is the basis of the system of ``[x; w]`` driven by ``w'``
        (:meth:`~uio_ring.DelaySystem.input_augmented`): the observer estimates ``w`` as states.
    b_profile, kappa_b
        CBHO only: ``(d0, d_inf, mu)`` and the gains per ``x_b`` chain (top row first).
    d_profile
        DBHO only: ``(−1, d_inf, mu)`` (``kappa`` holds its gains).
    """

    method: ClassVar[str] = "scb"

    system: DelaySystem
    scb: SpecialCoordinateBasis
    b_observer: str
    d_observer: str
    poles_b: tuple[Fraction, ...]
    L_b: PolyMatrix
    input_ranges: tuple[tuple[Fraction, Fraction], ...] | None
    Delta_d: tuple[Fraction, ...]
    kappa: tuple[tuple[Fraction, ...], ...]
    reconstruct_input: bool = False
    b_profile: tuple[Fraction, Fraction, Fraction] | None = None
    kappa_b: tuple[tuple[Fraction, ...], ...] = ()
    d_profile: tuple[Fraction, Fraction, Fraction] | None = None
    options: ObserverOptions | None = field(default=None, compare=False, repr=False)

    @property
    def assumptions(self) -> ObserverOptions:
        """The Table 1 report this design rests on (printed by ``uio-ring design``)."""
        return self.options if self.options is not None else observer_options(self.system)

    # -- the observer in SCB coordinates ------------------------------------------------------
    @property
    def d_dynamic(self) -> bool:
        """``x̂_d`` has states (sliding-mode chains); otherwise ``x̂_d = y_d``."""
        return self.d_observer != "linear"

    @property
    def n_xi(self) -> int:
        """Order of the observer."""
        s = self.scb
        return s.n_a + s.n_b + (s.n_d if self.d_dynamic else 0)

    def observer_matrices(self) -> dict[str, Q]:
        """``F`` and ``G`` of ``ξ' = F ξ + G ȳ (+ L_d)`` in SCB coordinates (ξ = [x̂_a; x̂_b; x̂_d]).

        ``G`` acts on ``ȳ = [y_0; y_d; y_b]``.
        """
        s = self.scb
        na, nb, nd, m0, md, pb = s.n_a, s.n_b, s.n_d, s.m_0, s.m_d, s.p_b
        Z = Q.zeros
        B0 = Q(s.B_0)
        B0a, B0b, B0d = B0.take_rows(range(na)), B0.take_rows(range(na, na + nb)), B0.take_rows(range(na + nb, na + nb + nd))
        # the CBHO keeps only H_bb of L_b in its linear part: A_b − H_bb C_b = A_b* (Brunovsky), (56)
        Lb = Q(s.H_bb) if self.b_observer == "cbho" else Q(self.L_b)
        Fa = [Q(s.A_a), Z(na, nb)]
        Fb = [Z(nb, na), Q(s.A_b) - Lb @ Q(s.C_b)]
        Ga = Q.hstack(B0a, Q(s.H_ad), Q(s.H_ab), rows=na)
        Gb = Q.hstack(B0b, Q(s.H_bd), Lb, rows=nb)
        if not self.d_dynamic:
            F = Q.block([Fa, Fb]) if na + nb else Z(0, 0)
            return {"F": F, "G": Q.vstack(Ga, Gb, cols=m0 + md + pb)}
        Bd = Q(s.B_d)
        Fd = [Bd @ Q(s.F_da), Bd @ Q(s.F_db), Q(s.A_d) - Q(s.H_dd) @ Q(s.C_d)]
        F = Q.block([[*Fa, Z(na, nd)], [*Fb, Z(nb, nd)], Fd])
        Gd = Q.hstack(B0d, Q(s.H_dd), Z(nd, pb), rows=nd)
        return {"F": F, "G": Q.vstack(Ga, Gb, Gd, cols=m0 + md + pb)}

    # -- protocol ------------------------------------------------------------------------------
    def certificate(self) -> Certificate:
        from uio_ring.verify.scb import scb_design_certificate

        return scb_design_certificate(self)

    def numeric(self, *, h: Any = None) -> Any:
        """The float model: ``ξ`` in SCB coordinates, ``x̂ = Ts ξ̄`` (``y_d`` read through when
        ``x̂_d = y_d``), one Levant chain per ``x_d`` chain on ``σ_i = y_{d,i} − x̂_{d,i,1}``."""
        from uio_ring.numeric.build import injection_from_exact, model_from_exact

        s = self.scb
        sysm = s.system  # the plant, or the plant of [x; w] with reconstruct_input
        n, n_y, n_u = sysm.n_x, sysm.n_y, sysm.n_u
        n_x = self.system.n_x
        Ts, To_inv = Q(s.Ts), Q(s.To).inverse(name="To")
        Tsi = Ts.inverse(name="Ts")
        E = Q(sysm.E) if n_u else Q.zeros(n, 0)
        Fk = Q(sysm.F) if n_u else Q.zeros(n_y, 0)
        mats = self.observer_matrices()
        F, G = mats["F"], mats["G"]
        nab, nd = s.n_a + s.n_b, s.n_d
        Ebar = Tsi @ E
        yd = list(range(s.m_0, s.m_0 + s.m_d))
        Syd = To_inv.take_rows(yd)
        initial = Tsi
        D_y = D_u = None
        injection = None
        starts: list[int] = []
        lengths: list[int] = []
        gains: list[tuple[Fraction, ...]] = []
        profiles: list[Any] = []
        rows_y: list[Q] = []
        if self.b_observer == "cbho" and s.n_b:  # b chains first: the d chains may read x̂_b (F_db)
            starts += [s.n_a + k for k in chain_starts(s.l)]
            lengths += list(s.l)
            gains += list(self.kappa_b)
            profiles += [self.b_profile] * len(s.l)
            rows_y.append(To_inv.take_rows(range(s.m_0 + s.m_d, s.m_0 + s.m_d + s.p_b)))
        if self.d_dynamic:
            starts += [nab + k for k in chain_starts(s.q)]
            lengths += list(s.q)
            gains += list(self.kappa)
            profiles += [self.d_profile] * len(s.q)
            rows_y.append(Syd)
        if starts:
            Sy = Q.vstack(*rows_y, cols=n_y)
            injection = injection_from_exact(
                starts=tuple(starts), lengths=tuple(lengths), gains=gains, sigma_y=Sy.to_polymatrix(),
                sigma_u=(-(Sy @ Fk)).to_polymatrix(),
                profiles=None if all(p is None for p in profiles) else tuple(profiles))
        if not self.d_dynamic:
            # Remark 3: x̂_d = z_d + y_d with z_d' = −ρ z_d, z_d(0) = 0 is (41) exactly; ρ bounds the
            # spectrum of the x_a, x_b part (Gershgorin), so z_d never sets the decay rate
            rho = 1 + max((abs(v) for row in F.tolist() for v in row), default=0) * max(nab, 1)
            F = Q.block([[F, Q.zeros(nab, nd)], [Q.zeros(nd, nab), Q.identity(nd) * (-rho)]]) if nab else \
                Q.identity(nd) * (-rho)
            G = Q.vstack(G, Q.zeros(nd, G.cols), cols=G.cols)
            D_y = Q.vstack(Q.zeros(nab, n_y), Syd, cols=n_y).to_polymatrix()
            D_u = Q.vstack(Q.zeros(nab, n_u), -(Syd @ Fk), cols=n_u).to_polymatrix() if n_u else None
            initial = Q.vstack(Tsi.take_rows(range(nab)), Q.zeros(nd, n), cols=n)
            Ebar = Q.vstack(Ebar.take_rows(range(nab)), Q.zeros(nd, n_u), cols=n_u)
        G_y = G @ To_inv
        G_u = Ebar - G_y @ Fk
        W = Ts.take_rows(range(n_x, n)).to_polymatrix() if self.reconstruct_input else None
        return model_from_exact(
            F=F.to_polymatrix(), G_y=G_y.to_polymatrix(), G_u=G_u.to_polymatrix() if n_u else None,
            X=Ts.take_rows(range(n_x)).to_polymatrix(), W=W, D_y=D_y, D_u=D_u, initial=initial.to_polymatrix(),
            injection=injection, method=self.method, interpolation="linear" if injection else "cubic")

    def to_dict(self) -> dict[str, Any]:
        s = self.scb
        return {
            "method": self.method, "b_observer": self.b_observer, "d_observer": self.d_observer,
            "n_a": s.n_a, "n_b": s.n_b, "n_d": s.n_d, "m_0": s.m_0, "q": list(s.q), "l": list(s.l),
            "invariant_zero_polynomial": str(s.invariant_zero_polynomial),
            "Ts": matrix_to_data(s.Ts), "Ti": matrix_to_data(s.Ti), "To": matrix_to_data(s.To),
            "poles_b": [str(p) for p in self.poles_b], "L_b": matrix_to_data(self.L_b),
            "input_ranges": None if self.input_ranges is None else [[str(a), str(b)] for a, b in self.input_ranges],
            "Delta_d": [str(x) for x in self.Delta_d], "kappa": [[str(k) for k in ks] for ks in self.kappa],
            "reconstruct_input": self.reconstruct_input,
            "b_profile": None if self.b_profile is None else [str(x) for x in self.b_profile],
            "kappa_b": [[str(k) for k in ks] for ks in self.kappa_b],
            "d_profile": None if self.d_profile is None else [str(x) for x in self.d_profile],
        }

    def to_latex(self) -> str:
        s = self.scb
        parts = [r"x = T_s \bar x,\ \bar x = [x_a; x_b; x_d]"]
        if s.n_a:
            parts.append(r"\dot{\hat x}_a = A_a \hat x_a + H_{ab} y_b + H_{ad} y_d + B_{0a} y_0")
        if s.n_b:
            parts.append(r"\dot{\hat x}_b = A_b \hat x_b + H_{bd} y_d + B_{0b} y_0 + L_b (y_b - C_b \hat x_b)")
        if self.d_dynamic:
            parts.append(r"\dot{\hat x}_d = (A_d - H_{dd} C_d)\hat x_d + B_d (F_{da}\hat x_a + F_{db}\hat x_b)"
                         r" + B_{0d} y_0 + H_{dd} y_d + L_d(y_d - C_d \hat x_d)")
        elif s.n_d:
            parts.append(r"\hat x_d = y_d")
        parts.append(r"T_s = " + s.Ts.to_latex())
        return r" \\ ".join(parts)

    def __repr__(self) -> str:
        s = self.scb
        return (f"SCBDesign(n_a={s.n_a}, n_b={s.n_b}, n_d={s.n_d}, q={s.q}, l={s.l}, "
                f"b_observer={self.b_observer!r}, d_observer={self.d_observer!r})")

    def __str__(self) -> str:
        s = self.scb
        lines = [f"special coordinate basis observer (Tranninger et al. 2021): order {self.n_xi}"
                 + (" (state [x; w]: w is estimated)" if self.reconstruct_input else ""),
                 f"  (n_a, n_b, n_d) = ({s.n_a}, {s.n_b}, {s.n_d}), q = {s.q}, l = {s.l}"]
        if s.n_a:
            lines.append(f"  x_a: open-loop copy; error e_a' = A_a e_a, zeros of {s.invariant_zero_polynomial}")
        if s.n_b and self.b_profile is not None:
            d0, di, mu = self.b_profile
            lines.append(f"  x_b: continuous bi-homogeneous (d0 = {d0}, d_inf = {di}, mu = {mu}), gains from "
                         f"spec(A_b - L_b C_b) = {{{', '.join(str(p) for p in self.poles_b)}}}: "
                         + "; ".join("(" + ", ".join(f"{float(k):.6g}" for k in ks) + ")" for ks in self.kappa_b))
        elif s.n_b:
            lines.append(f"  x_b: Luenberger, spec(A_b - L_b C_b) = {{{', '.join(str(p) for p in self.poles_b)}}}")
        if s.n_d:
            what = {"linear": "x̂_d = y_d (exact)", "1-smo": "first-order sliding mode",
                    "hosmo": "higher-order sliding mode (Levant differentiators)",
                    "dbho": "discontinuous bi-homogeneous"}[self.d_observer]
            if self.d_profile is not None:
                _, di, mu = self.d_profile
                what += f" (d0 = -1, d_inf = {di}, mu = {mu}: {'fixed' if di > 0 else 'finite'}-time)"
            lines.append(f"  x_d: {what}")
            if self.kappa:
                lines.append("  Δ_d = (" + ", ".join(f"{float(x):.6g}" for x in self.Delta_d) + "); gains "
                             + "; ".join("(" + ", ".join(f"{float(k):.6g}" for k in ks) + ")" for ks in self.kappa))
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        return "<pre>" + html.escape(str(self)) + "</pre>"


def design_scb(
    sys: DelaySystem,
    *,
    b_observer: str = "linear",
    d_observer: str | None = None,
    poles_b: Sequence[Any] | None = None,
    input_bounds: Any = None,
    input_ranges: Any = None,
    gains: Sequence[Sequence[Any]] | None = None,
    reconstruct_input: bool = False,
    report: ObserverOptions | None = None,
    d_inf: Any = None,
    mu: Any = None,
    b_d0: Any = None,
    b_d_inf: Any = None,
) -> SCBDesign:
    """An unknown-input observer in the special coordinate basis (Tranninger et al. 2021, Section 5).

    Parameters
    ----------
    sys
        Delay-free and strongly detectable (:func:`~uio_ring.analysis.observer_options`).
    b_observer
        ``"linear"`` (39) or ``"cbho"`` (56): the continuous bi-homogeneous observer, whose
        gains are those of the Luenberger observer of ``poles_b`` divided by the
        coefficients of Φ's limit at 0 (our rule, :mod:`uio_ring.design.bihom`).
    d_observer
        ``"linear"`` (``x̂_d = y_d``, needs every ``q_i = 1``), ``"1-smo"``, ``"hosmo"``
        (47) or ``"dbho"`` (60); default ``"linear"`` when every ``q_i = 1``, else ``"hosmo"``.
        The DBHO's gains are Levant's (Theorem 2's, from the bounds) divided by the
        coefficients of Φ's limit at 0 (our rule), so its last gain times ``mu`` is ``1.1 Δ``.
    poles_b
        ``n_b`` exact rationals, ``spec(A_b − L_b C_b)``; chain i takes the next ``l_i``
        (default: ``n_b`` poles at ``−⌈‖A‖∞⌉``); negative for the CBHO.
    input_bounds, input_ranges
        ``|w_i| ≤ L_i`` or ``w_i ∈ [lo_i, hi_i]`` (one of them; needed by the sliding-mode
        observers): the bounds (45) of ``w_d`` and the gains of Theorem 2.
    gains
        Explicit gains per ``x_d`` chain (top row first) instead of Levant's.
    reconstruct_input
        Estimate ``w`` too: the design is made for the system of ``[x; w]`` driven by
        ``w'`` (its chains are one longer), and the bounds are those of ``|w'|``.
    report
        The :func:`~uio_ring.analysis.observer_options` report, when computed already.
    d_inf, mu
        DBHO: the degree at infinity (``d0 = −1``; default ``4/5 · 1/(max q_i − 1)``, fixed-time;
        ``−1 ≤ d_inf < 0`` is finite-time, ``−1`` is Levant's) and the weight ``mu ∈ (0, 1)``
        of the two limits (default 1/2, shared with the CBHO).
    b_d0, b_d_inf
        CBHO: ``−1 < b_d0 < 0 < b_d_inf < min 1/(l_i − 1)`` (default −1/2 and ``4/5 · 1/(max l_i − 1)``).

    Raises
    ------
    NotObservableError
        Not strongly detectable (the report says why), or the system has delays.
    OptionError
        A bi-homogeneous degree or ``mu`` outside the paper's ranges (the reason is said).
    DimensionError, DomainError
        Bad option shapes or values; ``x̂_d = y_d`` asked with a chain longer than 1;
        missing bounds for a sliding-mode observer; gains violating ``κ_{i,q_i} > Δ_{d,i}``.

    Examples
    --------
    A zero at −2 and one chain of length 2; the error of ``x̂_a`` decays like ``e^{−2t}``:

    >>> from uio_ring import DelaySystem
    >>> des = design_scb(DelaySystem("[[-2, 1, 0], [0, 0, 1], [0, 0, 0]]", "[[0], [0], [1]]", "[[0, 1, 0]]", None),
    ...                  input_ranges=[[-1, 3]])
    >>> des.Delta_d, des.n_xi
    ((Fraction(3, 1),), 3)
    """
    model = sys.input_augmented() if reconstruct_input else sys
    rep = observer_options(model) if report is None or reconstruct_input else report
    if not rep.holds:
        raise NotObservableError(f"no unknown-input observer exists: {rep.reason}", report=rep)
    s = rep.scb
    assert s is not None
    if b_observer not in B_OBSERVERS:
        raise NotSupportedError(f"b_observer={b_observer!r}: one of {', '.join(B_OBSERVERS)}")
    unit = all(k == 1 for k in s.q)
    d_obs = ("linear" if unit else "hosmo") if d_observer is None else d_observer
    if d_obs not in D_OBSERVERS:
        raise NotSupportedError(f"d_observer={d_obs!r}: one of {', '.join(D_OBSERVERS)}")
    if d_obs in ("linear", "1-smo") and not unit:
        raise for_option(DomainError(f"d_observer={d_obs!r} needs every chain of length 1 (strong* detectable); "
                                     f"the chains have lengths q = {s.q}: use 'hosmo'"), "d_observer")
    if poles_b is None:
        from uio_ring.design.noise import default_rate

        poles = tuple(Fraction(-default_rate(model)) for _ in range(s.n_b))
    else:
        poles = tuple(exact_fraction(p, f"poles_b[{i}]") for i, p in enumerate(poles_b))
        if len(poles) != s.n_b:
            raise for_option(DimensionError(f"poles_b has {len(poles)} entries; the x_b part has n_b = {s.n_b} "
                                            f"states (chains l = {s.l})"), "poles_b")
    mu_v = Fraction(1, 2) if mu is None else exact_fraction(mu, "mu")
    d_prof = b_prof = None
    if d_obs == "dbho":
        di = default_d_inf(s.q) if d_inf is None else exact_fraction(d_inf, "d_inf")
        check_dbho(s.q, di, mu_v)
        d_prof = (Fraction(-1), di, mu_v)
    elif d_inf is not None:
        raise OptionError("d_inf is an option of d_observer: dbho", option="d_inf")
    kappa_b: tuple[tuple[Fraction, ...], ...] = ()
    if b_observer == "cbho":
        dflt = default_cbho(s.l)
        bd0 = dflt[0] if b_d0 is None else exact_fraction(b_d0, "b_d0")
        bdi = dflt[1] if b_d_inf is None else exact_fraction(b_d_inf, "b_d_inf")
        check_cbho(s.l, bd0, bdi, mu_v)
        if any(p >= 0 for p in poles):
            raise OptionError("poles_b: the CBHO's gains come from a Luenberger design with negative poles",
                              option="poles_b")
        b_prof = (bd0, bdi, mu_v)
        K = Q(_luenberger_gain(s, poles)) - Q(s.H_bb)
        kappa_b = tuple(scaled_gains([K.tolist()[s0 + k][i] for k in range(li)], li, bd0, bdi, mu_v)
                        for i, (s0, li) in enumerate(zip(chain_starts(s.l), s.l, strict=True)))
    elif b_d0 is not None or b_d_inf is not None:
        raise OptionError("b_d0 and b_d_inf are options of b_observer: cbho",
                          option="b_d0" if b_d0 is not None else "b_d_inf")
    if mu is not None and d_prof is None and b_prof is None:
        raise OptionError("mu is an option of the bi-homogeneous observers (cbho, dbho)", option="mu")
    ranges = _ranges(input_bounds, input_ranges, sys.n_w)  # of w, or of w' with reconstruct_input
    Delta: tuple[Fraction, ...] = ()
    kappa: tuple[tuple[Fraction, ...], ...] = ()
    if d_obs != "linear" and s.n_d:
        G_d = Q(s.Ti).inverse(name="Ti").take_rows(range(s.m_0, s.m_0 + s.m_d))
        if ranges is not None:
            Delta = input_bound_d(G_d, ranges)
        if gains is not None:
            kappa = tuple(tuple(exact_fraction(k, f"gains[{i}][{j}]") for j, k in enumerate(ks))
                          for i, ks in enumerate(gains))
            if [len(k) for k in kappa] != list(s.q):
                raise for_option(DimensionError(f"gains: chains of lengths {s.q} need that many gains each"), "gains")
        elif ranges is None:
            raise for_option(DimensionError(f"d_observer={d_obs!r} needs input_bounds or input_ranges (the gains "
                                            "of Theorem 2 come from the bounds of the unknown input)"), "input_bounds")
        else:
            # Levant's gains need L > 0; a zero bound (w_d ≡ 0) still gets a small positive gain
            kappa = tuple(levant_gains(qi, D if D > 0 else Fraction(1, 10**6)) for qi, D in zip(s.q, Delta, strict=True))
            if d_prof is not None:
                kappa = tuple(scaled_gains(k, qi, *d_prof) for k, qi in zip(kappa, s.q, strict=True))
        w = sign_weight(d_prof)
        if Delta and any(w * k[-1] <= D for k, D in zip(kappa, Delta, strict=True)):
            raise for_option(DomainError(("gains: Theorem 2 needs κ_{i,q_i} > Δ_{d,i} (" if w == 1 else
                                          f"gains: the DBHO's sign term needs mu·κ_(i,q_i) > Δ_(d,i), mu = {w} (")
                                         + ", ".join(f"{float(w * k[-1]):.6g} vs {float(D):.6g}"
                                                     for k, D in zip(kappa, Delta, strict=True)) + ")"), "gains")
    return SCBDesign(system=sys, scb=s, b_observer=b_observer, d_observer=d_obs, poles_b=poles,
                     L_b=_luenberger_gain(s, poles).to_polymatrix(), input_ranges=ranges, Delta_d=Delta,
                     kappa=kappa, reconstruct_input=reconstruct_input, b_profile=b_prof, kappa_b=kappa_b,
                     d_profile=d_prof, options=rep)


def sign_weight(profile: tuple[Fraction, Fraction, Fraction] | None) -> Fraction:
    """The weight of the sign term in ``Φ_q`` at the origin: 1 for Levant's chains (and the DBHO
    with ``d_inf = −1``), ``mu`` for a DBHO with ``d_inf > −1``.

    >>> sign_weight(None), sign_weight((Fraction(-1), Fraction(1, 4), Fraction(1, 3)))
    (Fraction(1, 1), Fraction(1, 3))
    """
    if profile is None or profile[1] == profile[0]:
        return Fraction(1)
    return profile[2]
