"""The registry of design methods, and ``design_auto``.

Each method has a name (as written in spec files), a check that returns a
report with ``.holds`` and ``.reason`` (never raises for a failed
assumption), and a design function.  ``design_auto`` tries the methods in
order and takes the first whose check holds, recording why each earlier one
was skipped.  New methods register with :func:`register_method`.

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)
>>> result = design_auto(sys)
>>> result.method, result.design.certificate().ok
('zheng-bejarano', True)
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

from uio_ring.errors import NotObservableError, SpecError
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["DesignMethod", "AutoResult", "METHODS", "register_method", "get_method", "design_auto", "design_with"]


@dataclass(frozen=True)
class DesignMethod:
    """A design method as the spec layer and ``auto`` see it.

    ``check(sys)`` returns a report with ``.holds`` and ``.reason``;
    ``design(sys, **options)`` returns an ``ObserverDesign`` or raises
    ``NotObservableError``; ``options`` names the keyword options the spec's
    ``design:`` section may pass (other keys are refused).
    """

    name: str
    summary: str
    check: Callable[[DelaySystem], Any]
    design: Callable[..., Any]
    options: tuple[str, ...] = ()
    required: tuple[str, ...] = ()
    delay_free_only: bool = False


@dataclass(frozen=True)
class AutoResult:
    """What ``design_auto`` chose: the design, its method, and why others were skipped."""

    design: Any
    method: str
    skipped: tuple[tuple[str, str], ...] = field(default=())

    def explanation(self) -> str:
        lines = [f"method: {self.method}"]
        lines += [f"skipped {name}: {why}" for name, why in self.skipped]
        return "\n".join(lines)


METHODS: dict[str, DesignMethod] = {}


def register_method(method: DesignMethod) -> None:
    """Add a method (its name must be new)."""
    if method.name in METHODS:
        raise ValueError(f"design method {method.name!r} is already registered")  # noqa: TRY003
    METHODS[method.name] = method


def get_method(name: str) -> DesignMethod:
    try:
        return METHODS[name]
    except KeyError:
        known = ", ".join(["auto", *METHODS])
        raise SpecError(f"unknown design method {name!r}; known: {known}", path="design.method") from None


def design_with(name: str, sys: DelaySystem, options: Mapping[str, Any] | None = None) -> Any:
    """Design with one named method (options checked against the method's list)."""
    method = get_method(name)
    opts = dict(options or {})
    missing = [k for k in method.required if k not in opts]
    if missing:
        raise SpecError(f"method {name!r} needs the option(s) {', '.join(missing)}", path="design")
    unknown = sorted(set(opts) - set(method.options))
    if unknown:
        raise SpecError(
            f"option(s) {', '.join(unknown)} do not apply to method {name!r} "
            f"(its options: {', '.join(method.options) or 'none'})",
            path="design",
        )
    return method.design(sys, **opts)


def design_auto(sys: DelaySystem, options: Mapping[str, Any] | None = None) -> AutoResult:
    """Design with the first registered method whose check holds.

    Options that a method does not take are not passed to it.  Raises
    ``NotObservableError`` naming every method and its failed assumption when
    none applies.
    """
    opts = dict(options or {})
    skipped: list[tuple[str, str]] = []
    last_report = None
    for method in METHODS.values():
        if method.delay_free_only and not sys.is_delay_free:
            skipped.append((method.name, "applies to delay-free systems only (this one has delays)"))
            continue
        missing = [k for k in method.required if k not in opts]
        if missing:
            skipped.append((method.name, f"needs design option(s) {', '.join(missing)}"))
            continue
        report = method.check(sys)
        last_report = report
        if not report.holds:
            skipped.append((method.name, report.reason))
            continue
        mine = {k: v for k, v in opts.items() if k in method.options}
        return AutoResult(method.design(sys, **mine), method.name, tuple(skipped))
    detail = "; ".join(f"{name}: {why}" for name, why in skipped)
    raise NotObservableError(f"no design method applies — {detail}", report=last_report)


def _register_builtin() -> None:
    from uio_ring.analysis.assumptions import check_assumptions
    from uio_ring.analysis.normal_form_applicability import normal_form_applicable
    from uio_ring.design.zheng_bejarano import design_zheng_bejarano

    register_method(
        DesignMethod(
            name="zheng-bejarano",
            summary="delay UIO of Zheng, Bejarano, Perruquetti & Richard (paper 001); exact error dynamics e' = (A0 - G0 C0) e",
            check=check_assumptions,
            design=design_zheng_bejarano,
            options=("poles",),
        )
    )
    register_method(
        DesignMethod(
            name="normal-form",
            summary="observer normal form with robust exact differentiators (paper 000); delay-free, "
            "strongly observable systems, no matching condition needed",
            check=normal_form_applicable,
            design=_design_normal_form,
            options=("input_bounds", "reconstruct_input", "gains", "lipschitz", "safety", "lipschitz_floor", "lambdas"),
            required=("input_bounds",),
            delay_free_only=True,
        )
    )


def _design_normal_form(sys: DelaySystem, **options: Any) -> Any:
    """``design_normal_form(sys, input_bounds, **rest)`` (it raises ``NotObservableError``)."""
    from uio_ring.design.normal_form import design_normal_form

    bounds = options.pop("input_bounds")
    return design_normal_form(sys, bounds, **options)


_register_builtin()
