"""A minimal text progress bar on stderr, for long runs from the CLI or a notebook.

``progress=None`` means automatic: shown when the run is long (≥ 2·10⁶ steps),
stderr is a terminal or an IPython kernel is running, and not under pytest.
"""

from __future__ import annotations

import os
import sys
import time

LONG_RUN_STEPS = 2_000_000


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

    def __enter__(self) -> Progress:
        self._t0 = time.perf_counter()
        return self

    def update(self, done: int) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if now - self._last < 0.2 and done < self.total:
            return
        self._last = now
        frac = min(done / self.total, 1.0)
        bar = "#" * int(30 * frac)
        sys.stderr.write(f"\r{self.desc}: [{bar:<30}] {100 * frac:5.1f}% {now - self._t0:6.1f}s")
        sys.stderr.flush()

    def __exit__(self, *exc: object) -> None:
        if self.enabled:
            self.update(self.total)
            sys.stderr.write("\n")
            sys.stderr.flush()
