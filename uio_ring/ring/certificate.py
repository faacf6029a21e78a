"""Certificates: named exact identities, each with its verdict.

A :class:`Certificate` is what every exact result can hand back to prove
itself: a list of :class:`Check` objects (name, verdict, residual when the
check fails, and a one-line statement of the identity).  ``cert.ok`` is true
only if every check holds.  The design layer (:mod:`uio_ring.verify`) builds
larger certificates from the same two classes.

>>> c = Certificate("demo", [Check("1 + 1 == 2", True)])
>>> c.ok, len(c), c["1 + 1 == 2"].ok
(True, 1, True)
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Check", "Certificate"]


@dataclass(frozen=True)
class Check:
    """One named identity and its verdict.

    ``residual`` is the left-hand side minus the right-hand side (or any object
    that shows the failure) and is ``None`` when the check holds.
    """

    name: str
    ok: bool
    residual: Any = None
    statement: str = ""

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {"name": self.name, "ok": bool(self.ok)}
        if self.statement:
            out["statement"] = self.statement
        if self.residual is not None:
            out["residual"] = str(self.residual)
        return out

    def __str__(self) -> str:
        mark = "ok  " if self.ok else "FAIL"
        text = f"[{mark}] {self.name}"
        if self.statement:
            text += f" — {self.statement}"
        if not self.ok and self.residual is not None:
            text += f"\n       residual: {self.residual}"
        return text


@dataclass(frozen=True)
class Certificate:
    """An ordered collection of :class:`Check`; true iff all checks hold."""

    title: str
    checks: Sequence[Check] = field(default_factory=tuple)

    def __post_init__(self) -> None:
        object.__setattr__(self, "checks", tuple(self.checks))

    @property
    def ok(self) -> bool:
        return all(c.ok for c in self.checks)

    @property
    def failed(self) -> tuple[Check, ...]:
        return tuple(c for c in self.checks if not c.ok)

    def __bool__(self) -> bool:
        return self.ok

    def __len__(self) -> int:
        return len(self.checks)

    def __iter__(self) -> Iterator[Check]:
        return iter(self.checks)

    def __getitem__(self, name: str) -> Check:
        for c in self.checks:
            if c.name == name:
                return c
        raise KeyError(f"no check named {name!r}; the checks are {[c.name for c in self.checks]}")

    def names(self) -> list[str]:
        return [c.name for c in self.checks]

    def to_dict(self) -> dict[str, Any]:
        return {"title": self.title, "ok": self.ok, "checks": [c.to_dict() for c in self.checks]}

    def __str__(self) -> str:
        head = f"{self.title}: {'all checks hold' if self.ok else f'{len(self.failed)} check(s) FAIL'}"
        return "\n".join([head] + ["  " + str(c).replace("\n", "\n  ") for c in self.checks])

    def _repr_html_(self) -> str:
        import html

        rows = "".join(
            f"<tr><td>{'✔' if c.ok else '✘'}</td><td>{html.escape(c.name)}</td>"
            f"<td>{html.escape(c.statement)}</td>"
            f"<td>{'' if c.ok or c.residual is None else html.escape(str(c.residual))}</td></tr>"
            for c in self.checks
        )
        verdict = "all checks hold" if self.ok else f"{len(self.failed)} check(s) fail"
        return (
            f"<b>{html.escape(self.title)}</b>: {verdict}"
            f"<table><tr><th></th><th>check</th><th>identity</th><th>residual</th></tr>{rows}</table>"
        )
