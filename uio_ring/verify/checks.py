"""One way of turning an identity into a :class:`~uio_ring.ring.certificate.Check`,
shared by every design certificate.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> residual_check("A − A = 0", "trivial", lambda: {"A - A": PolyMatrix("[[d]]") - PolyMatrix("[[d]]")}).ok
True
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from uio_ring.ring.certificate import Check

__all__ = ["residual_check"]


def residual_check(name: str, statement: str, fn: Callable[[], Any]) -> Check:
    """Evaluate one check.

    ``fn()`` returns a dict of residual matrices (the check holds iff all are
    zero), a string describing a failure, or ``None`` for success.  An
    exception while evaluating (e.g. shapes that do not fit) is a failed check
    whose residual names the exception.
    """
    try:
        out = fn()
    except Exception as exc:  # noqa: BLE001 - any failure to evaluate is a failed check
        return Check(name, False, residual=f"{type(exc).__name__}: {exc}", statement=statement)
    if out is None:
        return Check(name, True, statement=statement)
    if isinstance(out, str):
        return Check(name, False, residual=out, statement=statement)
    bad = {k: v for k, v in out.items() if not v.is_zero()}
    return Check(name, not bad, residual=bad or None, statement=statement)
