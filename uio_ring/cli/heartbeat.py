"""The CLI's "still working" lines: what a long run is doing, every few seconds, on stderr.

Exact algebra on large, high-degree input can take minutes inside the documented
limits; a tool that is silent then looks hung.  ``with Heartbeat("checking …"):``
prints ``uio-ring: still checking … (20 s; Ctrl-C stops) — <step>`` every
:data:`HEARTBEAT_SECONDS`, with the step noted by the work itself
(:mod:`uio_ring._progress`).  Used by ``check``, ``design``, ``simulate`` and
the ``hermite``/``smith`` calculator.
"""

from __future__ import annotations

import os
import select
import signal
import sys
import time
import warnings
from typing import Any

__all__ = ["HEARTBEAT_SECONDS", "Heartbeat"]


#: Seconds between the "still working" lines of a long check or design.
HEARTBEAT_SECONDS = 10.0


class Heartbeat:
    """``with Heartbeat("checking …"):`` — a line on stderr every :data:`HEARTBEAT_SECONDS`
    while the block runs, saying what is taking long (exact algebra on large, high-degree
    systems can take minutes; Ctrl-C stops it cleanly) and the analysis' current step
    (:mod:`uio_ring._progress`).

    The lines come from a forked child process that the block's notes reach through a
    pipe: one call into FLINT can hold the interpreter for minutes (a Dixon solve of a
    434-unknown system with 31-kbit solutions), and a thread of this process could not
    print then.  The child ignores Ctrl-C (the parent handles it); it is killed at the end
    of the block and ends by itself when the parent dies (the pipe closes).  Without ``os.fork``
    (Windows), a thread prints instead.  Cost: one fork per block (≈ 6 ms)."""

    def __init__(self, what: str):
        self.what = what
        self._pid = 0
        self._pipe = -1
        self._thread: Any = None

    def __enter__(self) -> Heartbeat:
        from uio_ring import _progress

        if not hasattr(os, "fork"):  # pragma: no cover - Windows
            self._start_thread()
            return self
        sys.stderr.flush()
        read, write = os.pipe()
        with warnings.catch_warnings():
            # Python ≥ 3.12 warns on forking a process with threads (here BLAS's): the child
            # only reads a pipe and writes stderr, and is killed at the end of the block, so
            # a lock it inherited held can cost heartbeat lines, never a hang
            warnings.simplefilter("ignore", DeprecationWarning)
            pid = os.fork()
        if pid == 0:  # the child: print until the pipe closes, then leave without cleanup
            try:
                os.close(write)
                _beat(read, self.what, HEARTBEAT_SECONDS, _progress.current())
            finally:
                os._exit(0)
        os.close(read)
        self._pid, self._pipe = pid, write
        _progress.set_sink(self._send)
        return self

    def _send(self, text: str) -> None:
        try:
            os.write(self._pipe, " ".join(text.split()).encode()[:1000] + b"\n")
        except OSError:  # the child is gone: nothing to tell
            pass

    def _start_thread(self) -> None:  # pragma: no cover - Windows
        import threading

        from uio_ring._progress import current

        stop = threading.Event()

        def run() -> None:
            t0 = time.monotonic()
            while not stop.wait(HEARTBEAT_SECONDS):
                print(_beat_line(self.what, time.monotonic() - t0, current()), file=sys.stderr, flush=True)

        self._thread = (threading.Thread(target=run, daemon=True), stop)
        self._thread[0].start()

    def __exit__(self, *exc: object) -> None:
        from uio_ring import _progress

        if self._thread is not None:  # pragma: no cover - Windows
            self._thread[1].set()
            return
        _progress.set_sink(None)
        os.close(self._pipe)
        # the child has nothing to finish: stopped at once, so that no state it may have
        # inherited from another thread (a lock held at the fork) can keep us waiting
        os.kill(self._pid, signal.SIGKILL)
        os.waitpid(self._pid, 0)


def _beat_line(what: str, seconds: float, note: str) -> str:
    return f"uio-ring: still {what} ({seconds:.0f} s; Ctrl-C stops)" + (f" — {note}" if note else "")


def _beat(pipe: int, what: str, period: float, note: str) -> None:
    """The heartbeat child: a line every ``period`` seconds with the latest note read from
    ``pipe`` (one per line), until the pipe closes (the modules it uses are imported by the
    parent: an import in a forked child could wait on a lock another thread held)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the parent's to handle
    t0 = time.monotonic()
    due = t0 + period
    pending = b""
    while True:
        ready, _, _ = select.select([pipe], [], [], max(due - time.monotonic(), 0.0))
        if ready:
            data = os.read(pipe, 65536)
            if not data:
                return
            *lines, pending = (pending + data).split(b"\n")
            if lines:
                note = lines[-1].decode(errors="replace")
            continue
        now = time.monotonic()
        os.write(2, (_beat_line(what, now - t0, note) + "\n").encode())
        due = now + period
