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

__all__ = ["note", "current"]

_NOTE = [""]


def note(text: str) -> None:
    """Replace the note (``""`` clears it)."""
    _NOTE[0] = text


def current() -> str:
    """The note ('' when no long analysis runs)."""
    return _NOTE[0]
