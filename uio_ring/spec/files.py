"""Files in and out, safely: bounded reads, safe names, all-or-nothing writes.

* :func:`read_text_limited` reads at most ``max_bytes`` from a *regular* file.
  Devices (``/dev/zero``), FIFOs and sockets are refused without reading, so a
  pipe with no writer cannot block and an endless stream cannot fill memory.
* :func:`safe_name` accepts a name only if it is one safe file name (no
  separators, no ``..``, no leading dot, no control characters, at most
  ``MAX_NAME`` characters), so a spec received from someone else cannot
  direct output outside the output folder.
* :class:`Outputs` writes every file under a temporary name in the target
  folder and renames them all at the end.  A run that fails or is interrupted
  (Ctrl-C) leaves no partial file.  An existing file is never replaced unless
  ``force=True``; the check is made before any work, and again just before
  the rename.  The one exception is a *shared* file (a design's JSON, YAML or
  LaTeX, which ``design`` and ``simulate`` both write): it may exist if it holds
  exactly the bytes this run would write, and is then left as it is (nothing
  is replaced); with other bytes the run is refused before anything is written.

>>> safe_name("zheng2015", "name")
'zheng2015'
>>> safe_name("../x", "name")
Traceback (most recent call last):
...
uio_ring.errors.SpecError: name: '../x' is not a safe file name: it contains '/'; use letters, digits, '_', '-' and '.' (not first)
"""

from __future__ import annotations

import os
import re
import stat
from collections.abc import Callable
from pathlib import Path
from typing import Any

from uio_ring.errors import SpecError

__all__ = ["read_text_limited", "safe_name", "sanitise_name", "Outputs", "MAX_NAME"]

#: Longest name (spec ``name``, file stem) accepted.
MAX_NAME = 100

_UNSAFE = re.compile(r"[/\\:*?\"<>|\x00-\x1f\x7f]")


def read_text_limited(path: str | Path, *, max_bytes: int, what: str = "spec") -> str:
    """The UTF-8 text of a regular file of at most ``max_bytes`` bytes (else :class:`SpecError`)."""
    if not isinstance(path, (str, os.PathLike)):
        raise SpecError(f"expected a file name, got {type(path).__name__}")
    p = Path(path)
    if "\x00" in str(path):
        raise SpecError(f"the file name {str(path)!r} contains a NUL character")
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0) | getattr(os, "O_BINARY", 0)
    try:
        fd = os.open(p, flags)  # non-blocking: opening a FIFO without a writer returns at once
    except FileNotFoundError:
        raise SpecError(f"no such file: {p}") from None
    except IsADirectoryError:
        raise SpecError(f"{p} is a directory; give the {what} file (.yaml)") from None
    except OSError as exc:
        raise SpecError(f"cannot read {p}: {exc.strerror}") from None
    try:
        info = os.fstat(fd)
        if stat.S_ISDIR(info.st_mode):
            raise SpecError(f"{p} is a directory; give the {what} file (.yaml)")
        if not stat.S_ISREG(info.st_mode):
            raise SpecError(f"{p} is not a regular file (a device, pipe or socket); give the {what} file (.yaml)")
        if info.st_size > max_bytes:
            raise SpecError(f"{p} is larger than {max_bytes} bytes; a {what} is a few kilobytes")
        chunks = []
        size = 0
        while size <= max_bytes:
            chunk = os.read(fd, min(1 << 20, max_bytes + 1 - size))
            if not chunk:
                break
            chunks.append(chunk)
            size += len(chunk)
        if size > max_bytes:
            raise SpecError(f"{p} is larger than {max_bytes} bytes; a {what} is a few kilobytes")
    except OSError as exc:
        raise SpecError(f"cannot read {p}: {exc.strerror}") from None
    finally:
        os.close(fd)
    try:
        return b"".join(chunks).decode("utf-8")
    except UnicodeDecodeError:
        raise SpecError(f"{p} is not UTF-8 text; a {what} is a YAML file") from None


def safe_name(name: str, path: str) -> str:
    """``name`` if it is one safe file name, else :class:`SpecError` at ``path`` saying why."""
    why = None
    m = _UNSAFE.search(name)
    if not name.strip():
        why = "it is empty"
    elif m:
        why = f"it contains {m.group()!r}"
    elif name.startswith(".") or name in (".", ".."):
        why = "it starts with '.'"
    elif len(name) > MAX_NAME:
        why = f"it has {len(name)} characters (at most {MAX_NAME})"
    elif name != name.strip():
        why = "it starts or ends with a space"
    if why:
        shown = repr(name) if len(name) <= 60 else repr(name[:50] + "…")
        raise SpecError(
            f"{shown} is not a safe file name: {why}; use letters, digits, '_', '-' and '.' (not first)", path=path
        )
    return name


def sanitise_name(name: str) -> str:
    """A safe file name made from any text (for names not chosen in a spec, e.g. a file's stem)."""
    clean = _UNSAFE.sub("_", name).strip().lstrip(".")[:MAX_NAME] or "design"
    return clean


class Outputs:
    """All-or-nothing writing of the output files of one run into one folder.

    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> with Outputs(folder) as out:
    ...     path = out.write_text(folder / "a.txt", "hello")
    >>> sorted(p.name for p in folder.iterdir()), path.read_text()
    (['a.txt'], 'hello')
    """

    def __init__(self, folder: str | Path, *, force: bool = False, where: str | None = None):
        self.folder = Path(folder)
        self.force = force
        self.where = where
        self._staged: list[tuple[Path, Path]] = []
        self._created: list[Path] = []
        self._shared: set[Path] = set()
        #: shared targets found holding the run's bytes already, so not written again
        self.unchanged: list[Path] = []

    # -- checks before any work ----------------------------------------------------
    def prepare(self, targets: list[Path], *, shared: list[Path] = ()) -> None:  # type: ignore[assignment]
        """Check, before any work, that the folder is usable and no target exists (unless ``force``).

        ``shared`` targets may exist: whether they would change is known only once
        their text is, and :meth:`refuse_changed` checks it then.
        Missing folders are created and a probe file is written and removed, so an
        unwritable place (permissions, a read-only or virtual file system) is refused
        now, not after the work; :meth:`cleanup` removes the folders again when the
        run writes nothing.
        """
        folder = self.folder
        text = str(folder)
        if "\x00" in text:
            raise SpecError(f"the output folder name {_short(text)} contains a NUL character", path=self.where)
        for part in folder.parts:
            if len(part.encode("utf-8", "replace")) > 255:
                raise SpecError(f"a folder name of {len(part)} characters is too long (at most 255)", path=self.where)
        try:
            if folder.exists() and not folder.is_dir():
                raise SpecError(f"{_short(text)} exists and is not a folder", path=self.where)
            existing = folder
            while not existing.exists() and existing.parent != existing:
                existing = existing.parent
            if existing.exists() and not existing.is_dir():
                raise SpecError(f"{_short(str(existing))} is a file, so {_short(text)} cannot be a folder", path=self.where)
            missing = []
            parent = folder
            while not parent.exists() and parent.parent != parent:
                missing.append(parent)
                parent = parent.parent
            for d in reversed(missing):
                d.mkdir()
                self._created.append(d)
            probe = folder / f".uio-ring-probe.{os.getpid()}"
            probe.write_bytes(b"")
            probe.unlink()
        except SpecError:
            self.cleanup()
            raise
        except OSError as exc:
            self.cleanup()
            reason = exc.strerror or str(exc)
            raise SpecError(f"cannot write into {_short(text)}: {reason}", path=self.where) from None
        self._shared = {Path(p) for p in shared}
        self.refuse_existing([t for t in targets if Path(t) not in self._shared])

    def cleanup(self) -> None:
        """Remove the folders :meth:`prepare` created if the run wrote nothing into them."""
        for d in reversed(self._created):
            try:
                d.rmdir()  # only when empty
            except OSError:
                break
        self._created = []

    def refuse_existing(self, paths: list[Path]) -> None:
        if self.force:
            return
        existing = [p for p in paths if os.path.lexists(p)]
        if existing:
            shown = ", ".join(str(p) for p in existing[:3]) + (" …" if len(existing) > 3 else "")
            raise SpecError(
                f"{shown} already exist{'s' if len(existing) == 1 else ''}; "
                "pass --force to overwrite, or choose another --out",
                path=self.where,
            )

    def refuse_changed(self, texts: dict[Path, str]) -> None:
        """Refuse (unless ``force``) when a shared target exists with other bytes than ``texts`` gives it.

        Call it as soon as the texts are known, before the rest of the work.

        >>> import tempfile
        >>> folder = Path(tempfile.mkdtemp())
        >>> (folder / "d.json").write_text("{}")
        2
        >>> out = Outputs(folder); out.prepare([folder / "d.json"], shared=[folder / "d.json"])
        >>> out.refuse_changed({folder / "d.json": "{}"})  # the same bytes: accepted
        >>> out.refuse_changed({folder / "d.json": "[]"})
        Traceback (most recent call last):
        ...
        uio_ring.errors.SpecError: .../d.json already exists with other content; pass --force to overwrite, or choose another --out
        """
        if self.force:
            return
        changed = [p for p, text in texts.items() if os.path.lexists(p) and not _holds(p, text.encode("utf-8"))]
        if changed:
            shown = ", ".join(str(p) for p in changed[:3]) + (" …" if len(changed) > 3 else "")
            one = len(changed) == 1
            what = ("with other content" if all(_is_regular(p) for p in changed)
                    else "and is not a regular file" if one else "and are not all regular files")
            raise SpecError(
                f"{shown} already exist{'s' if one else ''} {what}; "
                "pass --force to overwrite, or choose another --out",
                path=self.where,
            )

    # -- staged writes ---------------------------------------------------------------
    def _temp(self, target: Path) -> Path:
        return target.with_name(f".{target.name}.{os.getpid()}.part")

    def write_with(self, target: str | Path, writer: Callable[[Path], Any]) -> Path:
        """Stage ``target``: ``writer(temp_path)`` writes it; it gets its name at :meth:`commit`."""
        target = Path(target)
        temp = self._temp(target)
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
            self._staged.append((temp, target))
            writer(temp)
        except OSError as exc:
            raise SpecError(f"cannot write {target}: {exc.strerror}", path=self.where) from None
        return target

    def write_text(self, name: str | Path, text: str) -> Path:
        """Stage ``text`` (UTF-8) for ``name``; a shared file already holding it is left as it is."""
        target, data = Path(name), text.encode("utf-8")  # bytes: the same on every platform
        if not self.force and target in self._shared and _holds(target, data):
            self.unchanged.append(target)
            return target
        return self.write_with(target, lambda p: p.write_bytes(data))

    def commit(self) -> list[Path]:
        """Rename every staged file to its name (refusing to replace one unless ``force``)."""
        self.refuse_existing([t for _, t in self._staged])
        done = []
        try:
            for temp, target in self._staged:
                os.replace(temp, target)
                done.append(target)
            self._created = []  # the folders hold the run's files now
        except OSError as exc:
            raise SpecError(f"cannot write {target}: {exc.strerror}", path=self.where) from None
        finally:
            self.discard()
        return done

    def discard(self) -> None:
        for temp, _ in self._staged:
            try:
                temp.unlink(missing_ok=True)
            except OSError:
                pass
        self._staged = []

    def __enter__(self) -> Outputs:
        return self

    def __exit__(self, kind: Any, exc: Any, tb: Any) -> None:
        if kind is None:
            self.commit()
        else:
            self.discard()  # also on KeyboardInterrupt: nothing half-written remains
        self.cleanup()


def _is_regular(path: Path) -> bool:
    try:
        return stat.S_ISREG(os.lstat(path).st_mode)
    except OSError:
        return False


def _holds(path: Path, data: bytes) -> bool:
    """True when ``path`` is a regular file (not a link, FIFO or device) holding exactly ``data``.

    Its size is compared first, so no more than ``len(data)`` bytes are ever read."""
    try:
        info = os.lstat(path)
        if not stat.S_ISREG(info.st_mode) or info.st_size != len(data):
            return False
        with open(path, "rb") as fh:
            return fh.read(len(data) + 1) == data
    except OSError:
        return False


def _short(text: str) -> str:
    return repr(text) if len(text) <= 80 else repr(text[:60] + "…") + f" ({len(text)} characters)"
