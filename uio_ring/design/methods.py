"""The one registry of design methods, and ``design_auto``.

A method is one record, :class:`DesignMethod`: its name (one spelling, used by
the registry, ``design.method``, design files and the CLI), its design class,
its typed options, the applicability check (a report with ``.holds`` and
``.reason``; never raises for a failed assumption), the design function
(``design(sys, *, report=None, **options)``) and its certificate.  The spec
loader, the JSON Schema of spec files and the CLI only loop over
:data:`METHODS`.  A new method registers with :func:`register_method`.

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)
>>> result = design_auto(sys, poles=[-2])
>>> result.method, result.design.method, result.design.certificate().ok
('zheng-bejarano', 'zheng-bejarano', True)
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from uio_ring.design.options import MethodOption
from uio_ring.errors import NotObservableError, SpecError
from uio_ring.systems.delay_system import DelaySystem

__all__ = [
    "DesignMethod",
    "MethodOption",
    "AutoResult",
    "METHODS",
    "register_method",
    "get_method",
    "design_auto",
    "design_with",
]


@dataclass(frozen=True)
class DesignMethod:
    """A design method as the registry, the spec layer and ``auto`` see it.

    Attributes
    ----------
    name : str
        The one spelling of the method (``"zheng-bejarano"``); equals ``design_class.method``.
    summary : str
        One line for ``uio-ring check`` and the schema.
    design_class : type
        The :class:`~uio_ring.design.base.ObserverDesign` subclass it returns.
    check : callable
        ``check(sys)`` → report with ``.holds`` and ``.reason``.
    design : callable
        ``design(sys, *, report=None, **options)`` → design, or ``NotObservableError``.
    certificate : callable
        ``certificate(design)`` → :class:`~uio_ring.ring.certificate.Certificate`.
    options : tuple of MethodOption
        The keyword options (spec keys) it takes.
    delay_free_only : bool
        The method applies to delay-free systems only.
    preview : callable, optional
        ``preview(sys)`` → one line that ``uio-ring check`` prints when the method applies:
        what the design will be and what its options must be (e.g. how many poles).
    """

    name: str
    summary: str
    design_class: type
    check: Callable[[DelaySystem], Any]
    design: Callable[..., Any]
    certificate: Callable[[Any], Any]
    options: tuple[MethodOption, ...] = ()
    delay_free_only: bool = False
    preview: Callable[[DelaySystem], str] | None = None

    @property
    def option_names(self) -> tuple[str, ...]:
        return tuple(o.name for o in self.options)

    @property
    def required(self) -> tuple[str, ...]:
        return tuple(o.name for o in self.options if o.required)

    def applies(self, sys: DelaySystem) -> tuple[bool, Any, str]:
        """``(holds, report, reason)`` — without running the check when the system's kind rules it out."""
        if self.delay_free_only and not sys.is_delay_free:
            return False, None, "applies to delay-free systems only (this one has delays)"
        report = self.check(sys)
        return bool(report.holds), report, "" if report.holds else report.reason

    def read_options(self, data: Mapping[str, Any], path: str = "design") -> dict[str, Any]:
        """Exact option values from plain data; refuses unknown keys and names missing ones."""
        known = {o.name: o for o in self.options}
        unknown = sorted(set(data) - set(known))
        if unknown:
            raise SpecError(
                f"option(s) {', '.join(unknown)} do not apply to method {self.name!r} "
                f"(its options: {', '.join(known) or 'none'})",
                path=f"{path}.{unknown[0]}",
            )
        missing = [k for k in self.required if k not in data]
        if missing:
            raise SpecError(f"method {self.name!r} needs {', '.join(missing)}", path=f"{path}.{missing[0]}")
        return {k: known[k].read(v, f"{path}.{k}") for k, v in data.items()}


@dataclass(frozen=True)
class AutoResult:
    """What :func:`design_auto` chose.

    ``design`` is the design, ``method`` the name of its method, ``skipped`` the
    ``(name, reason)`` of every method tried before it, ``report`` the analysis
    report of the chosen method (computed once, passed to its design function).
    """

    design: Any
    method: str
    skipped: tuple[tuple[str, str], ...] = ()
    report: Any = field(default=None, compare=False)

    def explanation(self) -> str:
        lines = [f"method: {self.method}"]
        lines += [f"skipped {name}: {why}" for name, why in self.skipped]
        return "\n".join(lines)


METHODS: dict[str, DesignMethod] = {}


def register_method(method: DesignMethod) -> None:
    """Add a method (its name must be new and equal ``method.design_class.method``)."""
    if method.name in METHODS:
        raise ValueError(f"design method {method.name!r} is already registered")  # noqa: TRY003
    if getattr(method.design_class, "method", method.name) != method.name:
        raise ValueError(  # noqa: TRY003
            f"design method {method.name!r}: its design class spells it {getattr(method.design_class, 'method', '')!r}"
        )
    METHODS[method.name] = method


def get_method(name: str) -> DesignMethod:
    """The registry entry of ``name``; ``SpecError`` (path ``design.method``) naming the known ones."""
    try:
        return METHODS[name]
    except KeyError:
        import difflib

        close = difflib.get_close_matches(str(name), ["auto", *METHODS], n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ""
        known = ", ".join(["auto", *METHODS])
        raise SpecError(f"unknown design method {name!r}{hint} (known: {known})", path="design.method") from None


def design_with(name: str, sys: DelaySystem, *, report: Any = None, **options: Any) -> Any:
    """Design with one named method (keyword options checked against its list)."""
    method = get_method(name)
    missing = [k for k in method.required if k not in options]
    if missing:
        raise SpecError(f"method {name!r} needs the option(s) {', '.join(missing)}", path="design")
    unknown = sorted(set(options) - set(method.option_names))
    if unknown:
        raise SpecError(
            f"option(s) {', '.join(unknown)} do not apply to method {name!r} "
            f"(its options: {', '.join(method.option_names) or 'none'})",
            path="design",
        )
    return method.design(sys, report=report, **options)


def design_auto(sys: DelaySystem, **options: Any) -> AutoResult:
    """Design with the first registered method whose check holds (each check runs once).

    Keyword options go to the method that is chosen; options that a method does not
    take are not passed to it, and a method whose required options are missing is
    skipped.  Raises ``NotObservableError`` naming every method and why it does not
    apply when none does.
    """
    skipped: list[tuple[str, str]] = []
    last_report = None
    for method in METHODS.values():
        missing = [k for k in method.required if k not in options]
        if missing:
            skipped.append((method.name, f"needs design option(s) {', '.join(missing)}"))
            continue
        holds, report, reason = method.applies(sys)
        last_report = report if report is not None else last_report
        if not holds:
            skipped.append((method.name, reason))
            continue
        mine = {k: v for k, v in options.items() if k in method.option_names}
        return AutoResult(method.design(sys, report=report, **mine), method.name, tuple(skipped), report)
    detail = "; ".join(f"{name}: {why}" for name, why in skipped)
    raise NotObservableError(f"no design method applies — {detail}", report=last_report)


def _register_builtin() -> None:
    from uio_ring.analysis.assumptions import check_assumptions
    from uio_ring.analysis.high_gain_applicability import high_gain_applicable
    from uio_ring.analysis.matched_reduction import matched_reduction
    from uio_ring.analysis.molinari import molinari_sequence
    from uio_ring.analysis.normal_form_applicability import normal_form_applicable
    from uio_ring.analysis.observer_classes import observer_options
    from uio_ring.design.delay_uio_design import DelayUIODesign
    from uio_ring.design.hierarchical_sta import HierarchicalSTADesign, design_hierarchical_sta
    from uio_ring.design.high_gain import HighGainDesign, design_high_gain
    from uio_ring.design.matched_sta import MatchedSTADesign, design_matched_sta
    from uio_ring.design.noise import CRITERIA
    from uio_ring.design.normal_form import NormalFormDesign, design_normal_form
    from uio_ring.design.scb import B_OBSERVERS, D_OBSERVERS, SCBDesign, design_scb
    from uio_ring.design.zheng_bejarano import design_zheng_bejarano
    from uio_ring.verify.delay_uio import delay_uio_certificate
    from uio_ring.verify.hierarchical_sta import hierarchical_sta_certificate
    from uio_ring.verify.high_gain import high_gain_certificate
    from uio_ring.verify.matched_sta import matched_sta_certificate
    from uio_ring.verify.normal_form import normal_form_certificate
    from uio_ring.verify.scb import scb_design_certificate

    register_method(
        DesignMethod(
            name="zheng-bejarano",
            summary="delay UIO of Zheng, Bejarano, Perruquetti & Richard (2015); exact error dynamics "
            "e' = (A0 - G0 C0) e",
            design_class=DelayUIODesign,
            check=check_assumptions,
            design=design_zheng_bejarano,
            certificate=delay_uio_certificate,
            preview=_preview_zheng_bejarano,
            options=(
                MethodOption("poles", "poles", "l* exact rationals: the spectrum of A0 - G0 C0 on each "
                             "output channel; or min-noise: the poles of least peak-to-peak noise gain with "
                             "every pole at least as fast as -rate (default: l* poles at -rate)"),
                MethodOption("rate", "rational", "the slowest decay rate of the observer error "
                             "(default: ceil(||A(1)||_inf), at least 1)"),
                MethodOption("criterion", "choice", "with poles: min-noise, the figure minimised: peak "
                             "(peak-to-peak gain of the worst state, default) or h2 (its H2 gain; refused when "
                             "infinite for every candidate)", choices=CRITERIA),
                MethodOption("search", "bool", "try the variants of the design choices and keep the "
                             "smallest observer with the least lag (default true)"),
            ),
        )
    )
    register_method(
        DesignMethod(
            name="normal-form",
            summary="observer normal form with robust exact differentiators (Niederwieser et al. 2022); "
            "delay-free, strongly observable systems, no matching condition needed",
            design_class=NormalFormDesign,
            check=normal_form_applicable,
            design=design_normal_form,
            certificate=normal_form_certificate,
            options=(
                MethodOption("input_bounds", "rational_or_rationals", "bounds of |w| (of |w'| with "
                             "reconstruct_input), one per unknown input or one for all", required=True,
                             nonnegative=True),
                MethodOption("reconstruct_input", "bool", "also reconstruct the unknown input w "
                             "(augmented state [x; w])"),
                MethodOption("gains", "rational_rows", "differentiator gains per chain, top to bottom "
                             "(default: Levant's parameters scaled by the Lipschitz constants; no free poles: "
                             "the linear part is nilpotent, so no poles: min-noise)"),
                MethodOption("lipschitz", "rationals", "Lipschitz constants per chain (default from "
                             "the input bounds)"),
                MethodOption("safety", "rational", "safety factor of the default Lipschitz rule (default 8)"),
                MethodOption("lipschitz_floor", "rational", "smallest Lipschitz constant of the default "
                             "rule (default 10)"),
                MethodOption("lambdas", "rationals", "differentiator parameters for chains longer than "
                             "Levant's list"),
            ),
            delay_free_only=True,
        )
    )
    register_method(
        DesignMethod(
            name="hierarchical-sta",
            summary="hierarchical super-twisting observer (Bejarano, Fridman & Poznyak 2007); delay-free, "
            "strongly observable systems, feed-through of w allowed, no matching condition needed",
            design_class=HierarchicalSTADesign,
            check=molinari_sequence,
            design=design_hierarchical_sta,
            certificate=hierarchical_sta_certificate,
            preview=_preview_hierarchical_sta,
            options=(
                MethodOption("K", "rational_rows", "Luenberger gain, n_x x n_y, A - K C Hurwitz (default: 0 "
                             "when A is Hurwitz, else the gain placing poles)"),
                MethodOption("poles", "poles", "n_x exact rationals: spec(A - K C) (default -1, ..., -n_x "
                             "when A is not Hurwitz); or min-noise: the poles of least noise gain of the "
                             "Luenberger stage (noise -> x~) with every pole at least as fast as -rate"),
                MethodOption("rate", "rational", "with poles: min-noise, the slowest decay rate allowed "
                             "(default ceil(||A||_inf), at least 1)"),
                MethodOption("criterion", "choice", "with poles: min-noise, the figure minimised: peak "
                             "(peak-to-peak gain of the worst state, default) or h2 (its H2 gain; refused when "
                             "infinite for every candidate)", choices=CRITERIA),
                MethodOption("gains", "rational_rows", "[lambda, alpha] of the super-twisting terms per level "
                             "(l - 1 levels; default [15, 10])"),
                MethodOption("w_bound", "rational", "a bound of ||w||: without gains, the gains of the sufficient "
                             "condition (16)/(21); with gains, a check of it (needs e_bound)", nonnegative=True),
                MethodOption("e_bound", "rational", "a bound of ||x - x_tilde|| after the Luenberger transient, "
                             "for w_bound", nonnegative=True),
                MethodOption("theta", "rational", "theta in (0, 1) of the gain condition (default 1/10)"),
            ),
            delay_free_only=True,
        )
    )
    register_method(
        DesignMethod(
            name="matched-sta",
            summary="reduced-order super-twisting observer with reconstruction of w (Bejarano, Fridman & "
            "Poznyak 2007, Section 3); delay-free, strongly observable, D = 0 and rank C B = rank B < n_y "
            "(matching)",
            design_class=MatchedSTADesign,
            check=matched_reduction,
            design=design_matched_sta,
            certificate=matched_sta_certificate,
            preview=_preview_matched_sta,
            options=(
                MethodOption("K", "rational_rows", "Luenberger gain of the w-free part, (n_x - n_w) x (n_y - n_w), "
                             "A11 - K C_bar Hurwitz (default: 0 when A11 is Hurwitz, else the gain placing poles)"),
                MethodOption("poles", "rationals", "n_x - n_w exact rationals: spec(A11 - K C_bar) (default -1, "
                             "-2, ... when A11 is not Hurwitz)"),
                MethodOption("gains", "rational_rows", "[lambda, alpha] of the super-twisting terms per level "
                             "(l - 1 levels; default [30, 20])"),
                MethodOption("w_gains", "rationals", "[lambda, alpha] of the loop that reconstructs w "
                             "(default [60, 60]; alpha above a bound of |w'|)"),
            ),
            delay_free_only=True,
        )
    )
    register_method(
        DesignMethod(
            name="high-gain",
            summary="high-gain observer with dynamic output shaping (Grip & Saberi 2010); delay-free "
            "x' = A x + φ(t, x), y = C x with the Jacobian of φ spanned by given W_k",
            design_class=HighGainDesign,
            check=high_gain_applicable,
            design=design_high_gain,
            certificate=high_gain_certificate,
            options=(
                MethodOption("W", "rational_matrices", "the n×n matrices W_k with dφ/dx = Σ ζ_k W_k "
                             "(linearly independent; default none)"),
                MethodOption("poles", "poles", "real negative poles; chain i gets the first q_i "
                             "(default -1, -2, ...); or min-noise: the poles of least noise gain (phi not "
                             "counted) with every error pole (poles/epsilon) at least as fast as -rate"),
                MethodOption("rate", "rational", "with poles: min-noise, the slowest decay rate allowed "
                             "(default ceil(||A||_inf), at least 1)"),
                MethodOption("criterion", "choice", "with poles: min-noise, the figure minimised: peak "
                             "(peak-to-peak gain of the worst state, default) or h2 (its H2 gain; refused when "
                             "infinite for every candidate)", choices=CRITERIA),
                MethodOption("coefficients", "rational_rows", "instead of poles: k*_1..k*_q per chain "
                             "(s^q + k*_1 s^(q-1) + ... + k*_q Hurwitz), chains longest first"),
                MethodOption("epsilon", "rational", "the high-gain parameter in (0, 1] (default 1)"),
                MethodOption("max_order", "integer", "cap of the output filter's order (default n)"),
                MethodOption("mu_bounds", "rationals", "bounds of |zeta_k|, one per W_k: report Theorem 1's "
                             "sufficient bound on epsilon"),
            ),
            delay_free_only=True,
        )
    )
    register_method(
        DesignMethod(
            name="scb",
            summary="observer in the special coordinate basis (Tranninger et al. 2021); delay-free, strongly "
            "detectable systems: stable invariant zeros allowed (asymptotic), sliding-mode chains for q_i > 1",
            design_class=SCBDesign,
            check=observer_options,
            design=design_scb,
            certificate=scb_design_certificate,
            preview=_preview_scb,
            options=(
                MethodOption("b_observer", "choice", "observer of the x_b part: linear (Luenberger (39)) or cbho "
                             "(continuous bi-homogeneous (56), fixed-time)", choices=B_OBSERVERS),
                MethodOption("d_observer", "choice", "observer of the x_d part: linear (x_d = y_d, all q_i = 1), "
                             "1-smo, hosmo or dbho (discontinuous bi-homogeneous (60)) (default: linear when all "
                             "q_i = 1, else hosmo)", choices=D_OBSERVERS),
                MethodOption("d_inf", "rational", "dbho: degree at infinity, -1 <= d_inf < 0 (finite-time) or "
                             "0 < d_inf < 1/(q_i - 1) (fixed-time; default 4/5 of the bound, 1 if all q_i = 1)"),
                MethodOption("mu", "rational", "cbho/dbho: weight of the two limits of the injection, in (0, 1) "
                             "(default 1/2)"),
                MethodOption("b_d0", "rational", "cbho: degree at the origin, -1 < b_d0 < 0 (default -1/2)"),
                MethodOption("b_d_inf", "rational", "cbho: degree at infinity, 0 < b_d_inf < 1/(l_i - 1) "
                             "(default 4/5 of the bound, 1 if all l_i = 1)"),
                MethodOption("poles_b", "rationals", "n_b exact rationals: spec(A_b - L_b C_b) (default: n_b poles "
                             "at -ceil(||A||_inf))"),
                MethodOption("input_bounds", "rational_or_rationals", "bounds |w_i| <= L_i (one per unknown input, "
                             "or one for all) for the sliding-mode gains", nonnegative=True),
                MethodOption("input_ranges", "rational_rows", "instead of input_bounds: [lo, hi] per unknown input "
                             "(the bound (45) of w_d is tight for a box)"),
                MethodOption("gains", "rational_rows", "explicit differentiator gains per x_d chain, top row first "
                             "(default: Levant's, from the bounds)"),
                MethodOption("reconstruct_input", "bool", "also estimate w (the design is made for [x; w] driven "
                             "by w'; the bounds are then those of |w'|)"),
            ),
            delay_free_only=True,
        )
    )


def _preview_scb(sys: DelaySystem) -> str:
    from uio_ring.analysis.observer_classes import observer_options

    rep = observer_options(sys)
    scb = rep.scb
    assert scb is not None
    d = "x̂_d = y_d (linear)" if all(k == 1 for k in scb.q) else \
        "sliding-mode or bi-homogeneous chains (needs input_bounds or input_ranges)"
    return (f"(n_a, n_b, n_d) = ({scb.n_a}, {scb.n_b}, {scb.n_d}), q = {scb.q}: poles_b takes n_b = {scb.n_b} "
            f"value(s); x_d: {d}; convergence {rep.convergence}")


def _preview_hierarchical_sta(sys: DelaySystem) -> str:
    from uio_ring.analysis.molinari import molinari_sequence

    seq = molinari_sequence(sys)
    return (f"l = {seq.l}: {max((seq.l or 1) - 1, 0)} super-twisting level(s); gains takes "
            f"{max((seq.l or 1) - 1, 0)} pair(s) [lambda, alpha]")


def _preview_matched_sta(sys: DelaySystem) -> str:
    from uio_ring.analysis.matched_reduction import matched_reduction

    red = matched_reduction(sys)
    levels = max((red.l or 1) - 1, 0)
    return (f"n - q = {sys.n_x - sys.n_w}, l = {red.l}: {levels} super-twisting level(s) and one loop "
            f"reconstructing w; gains takes {levels} pair(s) [lambda, alpha], K is "
            f"{sys.n_x - sys.n_w} x {sys.n_y - sys.n_w}")


def _preview_zheng_bejarano(sys: DelaySystem) -> str:
    from uio_ring.design.noise import default_rate
    from uio_ring.design.zheng_bejarano import smallest_observer_orders

    n_z, options = smallest_observer_orders(sys)
    ls = " or ".join(str(l) for l in options)
    rate = default_rate(sys)
    return (f"smallest observer: n_z = {n_z}; poles takes l* = {ls} value(s); default: l* poles at "
            f"-{rate} (rate = ceil(||A(1)||_inf)); poles: min-noise chooses them for noise")


_register_builtin()
