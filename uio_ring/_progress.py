"""What a long exact analysis is doing now: one line for the CLI's "still working" messages.

A single module-level note, replaced (never accumulated) by the analysis at each
step of a long loop and cleared when it ends; :mod:`uio_ring.cli` appends it to the
line it prints every few seconds, so a check that runs for minutes says which step
it is at and how large its data have grown.  Reading and writing one str reference
is atomic in CPython, so the printing thread needs no lock.

>>> note("step 3")
>>> current()
'step 3'
>>> note("")
>>> current()
''
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from contextlib import contextmanager
from typing import Any

__all__ = ["note", "current", "set_sink", "step", "detail", "size_text"]

_NOTE = [""]
_SINK: list[Callable[[str], None] | None] = [None]


def note(text: str) -> None:
    """Replace the note (``""`` clears it); a sink set by :func:`set_sink` gets it too."""
    _NOTE[0] = text
    sink = _SINK[0]
    if sink is not None:
        sink(text)


def set_sink(sink: Callable[[str], None] | None) -> None:
    """Also hand every new note to ``sink`` (None: no longer) — the CLI's heartbeat process,
    which cannot read this module's memory."""
    _SINK[0] = sink


def current() -> str:
    """The note ('' when no long analysis runs)."""
    return _NOTE[0]


@contextmanager
def step(text: str) -> Iterator[None]:
    """``with step("…"):`` — the note while the block runs, cleared after it (also on error).

    >>> with step("solving"):
    ...     current()
    'solving'
    >>> current()
    ''
    """
    note(text)
    try:
        yield
    finally:
        note("")


@contextmanager
def detail(text: str) -> Iterator[Callable[[str], None]]:
    """``with detail("…") as tell:`` — ``text`` appended to the current note while the block
    runs, ``tell(more)`` appending ``more`` to that (each call replaces the previous one),
    and the note as it was restored after: for a long loop inside one step (the primes of
    a Chinese remaindering inside ``uio-ring check``'s step).

    >>> with step("step 2"):
    ...     with detail("remaindering") as tell:
    ...         tell("prime 3 of at most 40")
    ...         current()
    ...     current()
    'step 2; remaindering: prime 3 of at most 40'
    'step 2'
    """
    outer = current()
    head = f"{outer}; {text}" if outer else text
    note(head)
    try:
        yield lambda more: note(f"{head}: {more}")
    finally:
        note(outer)


def size_text(M: Any) -> str:
    """``"14×8 of δ-degree 20 with 416-bit coefficients"`` for a PolyMatrix: what makes exact
    work on it long."""
    from uio_ring.ring._echelon import max_bits

    return f"{M.rows}×{M.cols} of δ-degree {M.degree()} with {max_bits(M._r)}-bit coefficients"
