"""The time grid ``t_j = j·dt`` with ``dt = h/N``: validation of ``h``, ``dt``, ``t_final``."""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any

from uio_ring.errors import SimulationError

__all__ = ["as_float", "steps_per_delay", "step_count"]


def as_float(value: Any, name: str) -> float:
    """A positive finite float from an int, float, Fraction or decimal string."""
    from uio_ring.errors import UioRingError

    try:
        v = float(_exact_text(value, name) if isinstance(value, str) else value)
    except UioRingError as exc:  # decimal text refused before it was built
        raise SimulationError(str(exc)) from None
    except (TypeError, ValueError, ZeroDivisionError) as exc:
        raise SimulationError(f"{name}={str(value)[:40]!r} is not a number") from exc
    except OverflowError:
        raise SimulationError(f"{name} is beyond float64 (about 1.8e308)") from None
    if not math.isfinite(v) or v <= 0:
        raise SimulationError(f"{name}={value!r} must be a positive finite number")
    return v


def _exact_text(text: str, name: str) -> Fraction:
    """Decimal text read exactly and bounded before it is built (``"1e99999999"`` is refused)."""
    from uio_ring.ring.parse import decimal_fraction

    return decimal_fraction(text, name)


def steps_per_delay(h: float, dt: float) -> int:
    """``N = h/dt`` if it is a positive integer (to 1e-9 relative), else a :class:`SimulationError`.

    >>> steps_per_delay(0.01, 0.001)
    10
    >>> steps_per_delay(0.01, 0.003)
    Traceback (most recent call last):
    ...
    uio_ring.errors.SimulationError: dt=0.003 is not h/N for a positive integer N (h=0.01, h/dt = 3.333…): use N = 3 (dt = 0.00333333) or N = 4 (dt = 0.0025)
    """
    ratio = h / dt
    N = round(ratio)
    if N >= 1 and abs(ratio - N) <= 1e-9 * max(ratio, 1.0):
        return int(N)
    lo, hi = max(math.floor(ratio), 1), max(math.ceil(ratio), 1)
    if lo == hi:
        hi = lo + 1
    raise SimulationError(
        f"dt={dt:g} is not h/N for a positive integer N (h={h:g}, h/dt = {ratio:.4g}…): "
        f"use N = {lo} (dt = {h / lo:g}) or N = {hi} (dt = {h / hi:g})"
    )


def step_count(t_final: float, dt: float) -> int:
    """Number of steps to reach ``t_final`` (rounded up when it is not a multiple of dt)."""
    ratio = t_final / dt
    n = round(ratio)
    if abs(ratio - n) <= 1e-9 * max(ratio, 1.0):
        return int(n)
    return int(math.ceil(ratio))
