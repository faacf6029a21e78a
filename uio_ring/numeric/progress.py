"""A minimal text progress bar on stderr, for long runs from the CLI or a notebook.

``progress=None`` means automatic: shown when the run is long (≥ 2·10⁶ steps),
stderr is a terminal or an IPython kernel is running, and not under pytest.  One bar
covers a whole run (plant and observer: :meth:`Progress.part` gives each stage its
share), with the elapsed time and the time left.

>>> p = Progress(100, enabled=False)
>>> with p:
...     half = p.part(offset=50, scale=1)
...     half.update(10)
>>> p.done
60
"""

from __future__ import annotations

import os
import sys
import time
from typing import Protocol

LONG_RUN_STEPS = 2_000_000


class Updater(Protocol):
    """What a long loop reports to: :class:`Progress`, one of its parts, or an adapter."""

    def update(self, done: int) -> None: ...


def _interactive() -> bool:
    if "PYTEST_CURRENT_TEST" in os.environ:
        return False
    if "ipykernel" in sys.modules:
        return True
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):  # pragma: no cover
        return False


def want_progress(progress: bool | None, steps: int) -> bool:
    if progress is None:
        return steps >= LONG_RUN_STEPS and _interactive()
    return bool(progress)


class Progress:
    """``with Progress(total, enabled, desc) as p: p.update(k)`` — k counts done units."""

    def __init__(self, total: int, enabled: bool, desc: str = "simulate"):
        self.total, self.enabled, self.desc = max(int(total), 1), enabled, desc
        self._last = 0.0
        self.done = 0
        self._t0 = time.perf_counter()

    def __enter__(self) -> Progress:
        self._t0 = time.perf_counter()
        return self

    def part(self, *, offset: int, scale: float) -> _Part:
        """An updater for one stage: ``part.update(k)`` sets ``done = offset + k·scale``."""
        return _Part(self, offset, scale)

    def update(self, done: int) -> None:
        self.done = int(done)
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last < 0.2 and done < self.total:
            return
        self._last = now
        frac = min(done / self.total, 1.0)
        bar = "#" * int(30 * frac)
        elapsed = now - self._t0
        left = f", {elapsed * (1 - frac) / frac:6.1f}s left" if 0 < frac < 1 else ""
        sys.stderr.write(f"\r{self.desc}: [{bar:<30}] {100 * frac:5.1f}% {elapsed:6.1f}s{left}   ")
        sys.stderr.flush()

    def __exit__(self, *exc: object) -> None:
        if self.enabled:
            self.update(self.total)
            sys.stderr.write("\n")
            sys.stderr.flush()


class _Part:
    """One stage of a :class:`Progress` bar (see :meth:`Progress.part`)."""

    def __init__(self, bar: Progress, offset: int, scale: float):
        self.bar, self.offset, self.scale = bar, offset, scale

    def update(self, k: int) -> None:
        self.bar.update(self.offset + int(k * self.scale))
