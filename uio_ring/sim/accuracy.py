"""A-posteriori accuracy check of a simulation: the same run with ``dt/2`` on a window.

The engine is exact for the linear part of the plant and of the observer, but the
inputs and the measured output are known only on the grid and are interpolated
between samples.  When a signal has features shorter than ``dt`` (a plant pole far
beyond ``1/dt`` makes a boundary layer in y; a discontinuous input) and the observer
multiplies y by large gains, the interpolation error is amplified and the estimate
is wrong by far more than the error it reports.  Nothing on the grid reveals it,
but a second run with half the step does: where the run is resolved, the two agree
to the order of the method (Richardson); where it is not, they differ by about the
error itself.

:func:`check_accuracy` compares the errors ``x − x̂`` (and ``w − ŵ``) of the two runs,
both without output noise (the noise sequence depends on the grid), at their common
grid times on ``[0, window]`` with ``window = min(t_final, max(2000 dt, 10 h))``.  The
run is *trusted* when the largest difference is at most ``rtol`` times the peak of the
plant's states and inputs and of the initial errors on the window: ``rtol = 2 %`` for
linear observers (the stepper is of order 3–4 there), ``10 %`` for observers with a
discontinuous injection term (first-order differentiators, whose estimates chatter at
the scale of dt).  An unresolved run differs by about its own error (50 % and more).

>>> c = AccuracyCheck(estimate=1e-6, scale=2.0, window=1.0, dt=1e-3)
>>> c.ok, c.reason
(True, '')
>>> AccuracyCheck(estimate=1.0, scale=2.0, window=0.05, dt=0.01).reason[:50]
'not resolved by dt = 0.01: with dt/2 the error on '
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["AccuracyCheck", "AccuracyWarning", "RTOL", "RTOL_INJECTION", "WINDOW_BLOCKS", "WINDOW_STEPS", "check_accuracy",
           "window_steps"]

RTOL = 0.02  # largest trusted difference, relative to the peak of the plant's signals
RTOL_INJECTION = 0.10  # the same for observers with an injection term (first order in dt)
WINDOW_STEPS = 2000  # the window is at least this many steps …
WINDOW_BLOCKS = 10  # … and at least this many delay blocks (or the whole run when shorter)


class AccuracyWarning(UserWarning):
    """A simulation whose result is not resolved by its step ``dt`` (see :class:`AccuracyCheck`)."""


@dataclass(frozen=True)
class AccuracyCheck:
    """The outcome of :func:`check_accuracy`.

    ``estimate``: the largest ``|e_dt − e_{dt/2}|`` on ``[0, window]`` (``e`` the error
    ``x − x̂``, and ``w − ŵ`` when w is estimated); ``scale``: the peak of ``|x|``,
    ``|w|`` and of the errors at t = 0 there; ``ok``: ``estimate ≤ rtol · scale``.
    """

    estimate: float
    scale: float
    window: float
    dt: float
    rtol: float = RTOL

    @property
    def ok(self) -> bool:
        return bool(self.estimate <= self.rtol * self.scale)

    @property
    def reason(self) -> str:
        """One sentence when the check fails, ``""`` when it holds."""
        if self.ok:
            return ""
        share = self.estimate / self.scale if self.scale > 0 else np.inf
        return (f"not resolved by dt = {self.dt:g}: with dt/2 the error on [0, {self.window:g}] s changes by "
                f"{self.estimate:.3g} ({100 * share:.3g} % of the signals' peak {self.scale:.3g}, "
                f"tolerance {100 * self.rtol:g} %); reduce dt")


def window_steps(steps: int, N: int) -> int:
    """Steps of the checked window: ``min(steps, max(WINDOW_STEPS, WINDOW_BLOCKS · N))``.

    >>> window_steps(3000, 10), window_steps(500, 10), window_steps(10**6, 1000)
    (2000, 500, 10000)
    """
    return min(steps, max(WINDOW_STEPS, WINDOW_BLOCKS * N))


def _compared(res: Any, stride: int, count: int) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The signals of ``res`` at samples ``0, stride, …`` (``count`` of them): the errors, and
    what sets the scale (the plant's states and inputs, the initial errors)."""
    sl = slice(0, stride * (count - 1) + 1, stride)
    errors = [res.error[:, sl]]
    if res.w_hat is not None:
        errors.append(res.w[:, sl] - res.w_hat[:, sl])
    return errors, [res.x[:, sl], res.w[:, sl]] + [e[:, :1] for e in errors]


def check_accuracy(coarse: Any, rerun: Callable[[float, float], Any], *, dt: float, steps: int,
                   rtol: float = RTOL) -> AccuracyCheck:
    """Compare the first ``steps`` steps of ``coarse`` (a noise-free run with step ``dt``) with
    ``rerun(steps · dt, dt / 2)`` (the same run, noise-free, with half the step)."""
    count = steps + 1
    window = float(coarse.t[steps])
    fine = rerun(window, dt / 2)
    ec, sc = _compared(coarse, 1, count)
    ef, sf = _compared(fine, 2, count)
    estimate = max(float(np.max(np.abs(a - b), initial=0.0)) for a, b in zip(ec, ef, strict=True))
    scale = max(float(np.max(np.abs(a), initial=0.0)) for a in sc + sf)
    if not np.isfinite(estimate):
        estimate = float("inf")
    return AccuracyCheck(estimate=estimate, scale=scale, window=window, dt=dt, rtol=rtol)
