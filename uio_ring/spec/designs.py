"""Saving designs to JSON/YAML (exact values as strings) and loading them back.

``load_design(save_design(d, ...)[0]) == d`` for every design class: the files
hold every field of the design dataclass (matrices as lists of polynomial
strings, with their shapes so that empty matrices keep them), except the fields
the design class declares derived (``derived_fields``, e.g. the Krylov matrix
``Ō_{l*}`` of a Zheng–Bejarano design): those are written as
``{"$derived": how, "shape": …}`` when they equal their derivation (proved by the
design's certificate when it was computed, else compared exactly), and
recomputed exactly on loading.  The ``summary`` (the design's ``to_dict()``)
shows a matrix whose text exceeds ``SUMMARY_MATRIX_CHARS`` by its outline
(shape, δ-degree, coefficient bits) instead of its entries: the fields hold it.

A design file is not trusted.  :func:`load_design` reads at most
``MAX_DESIGN_BYTES`` from a regular file, bounds every number and matrix
before building it, checks that every field has its declared type (a
matrix where a matrix is expected, …), and then **re-runs the certificate**:
a file whose matrices were edited (or whose shapes no longer fit) is refused
with the first failing check.  ``verify=False`` skips only the certificate.
:func:`save_design` writes each file under a temporary name and renames it,
so a file is never half-written.

>>> import tempfile, pathlib
>>> from uio_ring import DelaySystem, design_zheng_bejarano
>>> d = design_zheng_bejarano(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None))
>>> folder = pathlib.Path(tempfile.mkdtemp())
>>> paths = save_design(d, folder / "demo", formats=("json", "yaml"))
>>> [p.suffix for p in paths], load_design(paths[0]) == d, load_design(paths[1]) == d
(['.json', '.yaml'], True, True)
"""

from __future__ import annotations

import dataclasses
import json
from collections.abc import Sequence
from fractions import Fraction
from os import PathLike
from pathlib import Path
from typing import Any

from uio_ring.errors import SpecError, UioRingError

__all__ = [
    "design_to_data",
    "design_from_data",
    "design_texts",
    "save_design",
    "load_design",
    "load_observer_model",
    "MAX_DESIGN_BYTES",
]

#: 2: derived fields (``$derived``) and outlined large matrices in the summary (files of
#: version 1 hold every field in full and load unchanged).
FORMAT_VERSION = 2
#: A summary matrix whose text would exceed this many characters is shown by its outline.
SUMMARY_MATRIX_CHARS = 20_000
#: Largest design file read (bytes).
MAX_DESIGN_BYTES = 50_000_000
#: Largest matrix dimension accepted in a design file.
MAX_DESIGN_DIMENSION = 4096
#: Largest number (decimal digits) and coefficient (bits) accepted in a design file:
#: designs multiply the spec's numbers, so their files hold larger ones than specs.
MAX_DESIGN_DIGITS = 100_000
MAX_DESIGN_BITS = 400_000


def _design_classes() -> dict[str, type]:
    """``{method name: design class}`` from the registry of methods."""
    from uio_ring.design.methods import METHODS

    return {name: m.design_class for name, m in METHODS.items()}


def _encode(value: Any) -> Any:
    """Tagged plain data: JSON scalars stay; everything else is ``{"$tag": …}``."""
    from uio_ring.design.base import matrix_to_data
    from uio_ring.ring.matrix import PolyMatrix
    from uio_ring.systems.delay_system import DelaySystem

    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, PolyMatrix):
        return {"$matrix": matrix_to_data(value), "shape": list(value.shape)}
    if isinstance(value, DelaySystem):
        return {"$system": value.to_dict(), "shapes": {k: list(M.shape) for k, M in value.matrices().items()}}
    if isinstance(value, Fraction):
        return {"$q": _fraction_text(value)}
    if isinstance(value, (tuple, list)):
        return {"$tuple": [_encode(v) for v in value]}
    if isinstance(value, dict):
        return {"$dict": [[_encode(k), _encode(v)] for k, v in value.items()]}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {
            "$dataclass": type(value).__name__,
            "fields": {f.name: _encode(getattr(value, f.name)) for f in dataclasses.fields(value) if f.compare},
        }
    raise TypeError(f"cannot serialise {type(value).__name__}")  # pragma: no cover


def design_to_data(design: Any) -> dict[str, Any]:
    """Plain data holding every compared field of a design (exact values as strings),
    the design's own readable ``summary`` (``to_dict()``), and ``numeric_derived``: the
    float observer model (:meth:`~uio_ring.numeric.model.ObserverModel.to_dict`: coefficient
    arrays per power of δ) for other tools.  ``numeric_derived`` is derived from the exact
    fields and ignored on loading: the exact fields are the design."""
    from uio_ring.design.base import abridged_matrices, matrix_text_memo

    with matrix_text_memo():  # the summary repeats the fields' matrices: their text is made once
        values = {f.name: getattr(design, f.name) for f in dataclasses.fields(design) if f.compare}
        derived = _derived_fields(design, values)
        fields = {name: derived[name] if name in derived else _encode(v) for name, v in values.items()}
        with abridged_matrices(SUMMARY_MATRIX_CHARS):
            summary = design.to_dict()
    out = {"uio_ring_design": FORMAT_VERSION, "method": design.method, "fields": fields, "summary": summary}
    try:
        out["numeric_derived"] = design.numeric().to_dict()
    except UioRingError as exc:  # e.g. exact coefficients beyond float64: the exact fields are still the design
        out["numeric_derived"] = {"not_computed": str(exc)}
    try:
        out["performance_derived"] = design.performance().to_dict()
    except UioRingError as exc:  # nonlinear observer, or delays without h: say why
        out["performance_derived"] = {"not_computed": str(exc)}
    return out


def _derived_fields(design: Any, values: dict[str, Any]) -> dict[str, Any]:
    """``{name: {"$derived": how, "shape": …}}`` for the design's derived fields that equal
    their derivation: proved by a certificate already computed and holding (the class
    declares only fields its certificate proves), else compared exactly here."""
    out = {}
    for name, how in getattr(type(design), "derived_fields", {}).items():
        value = values.get(name)
        if value is None or not hasattr(value, "shape"):
            continue
        if not design.certified():
            try:
                if type(design).derive_field(name, values) != value:
                    continue
            except (UioRingError, ValueError, KeyError):
                continue
        out[name] = {"$derived": how, "shape": list(value.shape)}
    return out


def load_observer_model(path: str | Path) -> Any:
    """The float observer model stored in a design file (its ``numeric_derived`` section),
    ready for :meth:`~uio_ring.numeric.model.ObserverModel.stepper` or
    :meth:`~uio_ring.numeric.model.ObserverModel.to_control`."""
    from uio_ring.numeric.model import ObserverModel

    if not isinstance(path, (str, PathLike)):
        raise SpecError(f"expected a file name, got {type(path).__name__}")
    data = _read_design_file(Path(path))
    if not isinstance(data, dict) or "numeric_derived" not in data:
        raise SpecError("the design file has no 'numeric_derived' section (written by an older uio_ring?)",
                        path="numeric_derived")
    numeric = data["numeric_derived"]
    if isinstance(numeric, dict) and "not_computed" in numeric:
        raise SpecError(f"the design has no float model: {numeric['not_computed']}", path="numeric_derived")
    return ObserverModel.from_dict(numeric)


def _decode(value: Any, where: str, helpers: dict[str, type]) -> Any:
    from uio_ring.ring.matrix import PolyMatrix
    from uio_ring.systems.delay_system import DelaySystem

    if not isinstance(value, dict):
        if isinstance(value, list):
            raise SpecError("a list where a tagged value was expected", path=where)
        return value
    try:
        if "$matrix" in value:
            rows, cols = value["shape"]
            if not all(isinstance(k, int) and not isinstance(k, bool) and 0 <= k <= MAX_DESIGN_DIMENSION for k in (rows, cols)):
                raise SpecError(f"shape {value['shape']!r} is not two whole numbers in 0 … {MAX_DESIGN_DIMENSION}", path=where)
            entries = value["$matrix"]
            if not isinstance(entries, list) or not all(isinstance(r, list) for r in entries):
                raise SpecError("a matrix is a list of rows", path=where)
            if any(not isinstance(x, (str, int)) or isinstance(x, bool) for r in entries for x in r):
                raise SpecError("matrix entries are polynomial strings such as '1/2*d + 1'", path=where)
            if not (rows and cols):
                return PolyMatrix.zeros(rows, cols)
            if len(entries) != rows or any(len(r) != cols for r in entries):
                raise SpecError(f"the entries do not form the {rows}×{cols} matrix the shape says", path=where)
            return PolyMatrix._new([[_poly(x, where) for x in r] for r in entries], rows, cols, "d")
        if "$system" in value:
            data = dict(value["$system"])
            for k, (r, c) in value["shapes"].items():
                if r == 0 or c == 0:
                    data[k] = PolyMatrix.zeros(r, c)
            return DelaySystem.from_dict(data)
        if "$q" in value:
            from uio_ring.ring.parse import decimal_fraction

            return decimal_fraction(str(value["$q"]), where, max_digits=MAX_DESIGN_DIGITS)
        if "$tuple" in value:
            return tuple(_decode(v, f"{where}[{i}]", helpers) for i, v in enumerate(value["$tuple"]))
        if "$dict" in value:
            return {_decode(k, where, helpers): _decode(v, where, helpers) for k, v in value["$dict"]}
        if "$dataclass" in value:
            cls = helpers.get(value["$dataclass"])
            if cls is None:
                raise SpecError(f"unknown record type {value['$dataclass']!r}", path=where)
            return cls(**{k: _decode(v, f"{where}.{k}", helpers) for k, v in value["fields"].items()})
    except SpecError:
        raise
    except UioRingError as exc:
        raise SpecError(str(exc), path=where) from None
    except (KeyError, TypeError, ValueError, ZeroDivisionError) as exc:
        raise SpecError(f"malformed value ({exc})", path=where) from None
    raise SpecError(f"unknown tag in {sorted(value)}", path=where)


def _poly(x: Any, where: str) -> Any:
    from uio_ring.ring import _backend as bk
    from uio_ring.ring.parse import MAX_DEGREE, parse_poly

    if isinstance(x, int):
        return bk.const(x)
    return parse_poly(x, "d", max_degree=MAX_DEGREE, max_bits=MAX_DESIGN_BITS, max_digits=MAX_DESIGN_DIGITS)


def _fraction_text(q: Fraction) -> str:
    """``'p/q'`` of any size (Python's int-to-text stops at 4 300 digits; FLINT's does not)."""
    import flint

    if q.numerator.bit_length() + q.denominator.bit_length() < 10_000:
        return str(q)
    return str(flint.fmpq(q.numerator, q.denominator))


def design_from_data(data: Any) -> Any:
    """Rebuild a design from :func:`design_to_data` output."""
    import sys

    if not isinstance(data, dict) or "uio_ring_design" not in data:
        raise SpecError("not a uio_ring design file (no 'uio_ring_design' key)")
    classes = _design_classes()
    cls = classes.get(data.get("method", ""))
    if cls is None:
        raise SpecError(f"unknown design method {data.get('method')!r}; known: {', '.join(classes)}", path="method")
    module = vars(sys.modules[cls.__module__])
    helpers = {name: obj for name, obj in module.items() if isinstance(obj, type) and dataclasses.is_dataclass(obj)}
    fields = data.get("fields", {})
    if not isinstance(fields, dict):
        raise SpecError("'fields' is not a mapping", path="fields")
    try:
        import typing

        hints = typing.get_type_hints(cls)
    except Exception:  # noqa: BLE001 - annotations that cannot be resolved are not checked
        hints = {}
    kwargs = {}
    later = []
    for f in dataclasses.fields(cls):
        if not f.compare:
            continue
        if f.name not in fields:
            raise SpecError(f"the design file has no field {f.name!r}", path="fields")
        raw = fields[f.name]
        if isinstance(raw, dict) and "$derived" in raw:
            later.append(f.name)
            continue
        kwargs[f.name] = _decode(raw, f"fields.{f.name}", helpers)
        _check_type(kwargs[f.name], hints.get(f.name, Any), f"fields.{f.name}")
    for name in later:
        kwargs[name] = _derive(cls, name, fields[name], kwargs)
        _check_type(kwargs[name], hints.get(name, Any), f"fields.{name}")
    try:
        return cls(**kwargs)
    except SpecError:
        raise
    except (UioRingError, TypeError, ValueError) as exc:
        raise SpecError(f"the fields do not make a {cls.__name__}: {exc}", path="fields") from None


def _derive(cls: type, name: str, raw: dict[str, Any], fields: dict[str, Any]) -> Any:
    """The derived field ``name`` recomputed from the decoded ``fields``: only a field the
    class declares derived, of a bounded shape, and the result must have that shape.  The
    class's ``derive_field`` bounds its own work before doing it (a Krylov matrix ``Ō_l``:
    ``l ≤ n`` and a δ-degree within the parser's bound)."""
    where = f"fields.{name}"
    if name not in getattr(cls, "derived_fields", {}):
        raise SpecError(f"the field {name!r} of a {cls.__name__} is not derived: write its value", path=where)
    shape = raw.get("shape")
    if (not isinstance(shape, list) or len(shape) != 2
            or not all(isinstance(k, int) and not isinstance(k, bool) and 0 <= k <= MAX_DESIGN_DIMENSION for k in shape)):
        raise SpecError(f"shape {shape!r} is not two whole numbers in 0 … {MAX_DESIGN_DIMENSION}", path=where)
    try:
        value = cls.derive_field(name, fields)  # type: ignore[attr-defined]
    except (UioRingError, ValueError, KeyError, TypeError, AttributeError) as exc:
        raise SpecError(f"cannot derive {name} from the other fields ({exc})", path=where) from None
    if list(value.shape) != shape:
        raise SpecError(f"the derived {name} is {value.shape[0]}×{value.shape[1]}: it does not give the "
                        f"{shape[0]} rows and {shape[1]} columns the file says", path=where)
    return value


def _check_type(value: Any, hint: Any, where: str) -> None:
    """``value`` has the declared type ``hint`` (PolyMatrix, int, Fraction, tuples, unions, …)."""
    import types
    import typing

    from uio_ring.ring.matrix import PolyMatrix

    origin = typing.get_origin(hint)
    args = typing.get_args(hint)
    if hint is Any or isinstance(hint, (str, typing.TypeVar)):
        return
    if origin in (typing.Union, types.UnionType):
        for h in args:
            try:
                _check_type(value, h, where)
                return
            except SpecError:
                continue
        raise SpecError(f"{_kind(value)} does not have the type {_hint_name(hint)}", path=where)
    if hint is type(None):
        ok = value is None
    elif hint is Fraction:
        ok = isinstance(value, (Fraction, int)) and not isinstance(value, bool)
    elif hint is int:
        ok = isinstance(value, int) and not isinstance(value, bool)
    elif origin is tuple:
        ok = isinstance(value, tuple)
        if ok and args and args[-1] is Ellipsis:
            for i, v in enumerate(value):
                _check_type(v, args[0], f"{where}[{i}]")
        elif ok and args:
            ok = len(value) == len(args)
            for i, (v, h) in enumerate(zip(value, args, strict=False)):
                _check_type(v, h, f"{where}[{i}]")
    elif origin is dict:
        ok = isinstance(value, dict)
        if ok and args:
            for k, v in value.items():
                _check_type(k, args[0], where)
                _check_type(v, args[1], where)
    elif isinstance(hint, type):
        ok = isinstance(value, hint)
    else:
        return
    if not ok:
        expected = "a matrix" if hint is PolyMatrix else _hint_name(hint)
        raise SpecError(f"{_kind(value)} where {expected} is expected", path=where)


def _hint_name(hint: Any) -> str:
    return getattr(hint, "__name__", None) or str(hint).replace("typing.", "")


def _kind(value: Any) -> str:
    if isinstance(value, tuple):
        return f"a list of {len(value)}"
    return f"{type(value).__name__} {str(value)[:40]!r}" if not hasattr(value, "shape") else f"a {value.shape[0]}×{value.shape[1]} matrix"


def design_texts(design: Any, formats: Sequence[str] = ("json", "yaml")) -> dict[str, str]:
    """The text of each design file by suffix (``".json"``, ``".yaml"``, ``".tex"``)."""
    from uio_ring.spec.yaml_io import dump_yaml

    data = design_to_data(design)
    out = {}
    for fmt in formats:
        if fmt == "json":
            out[".json"] = json.dumps(data, indent=1, ensure_ascii=False) + "\n"
        elif fmt == "yaml":
            out[".yaml"] = dump_yaml(data)
        elif fmt == "latex":
            out[".tex"] = design.to_latex() + "\n"
    return out


def save_design(design: Any, stem: str | Path, *, formats: Sequence[str] = ("json", "yaml")) -> list[Path]:
    """Write ``stem.json`` / ``stem.yaml`` (and ``stem.tex`` for ``"latex"``); returns the paths.

    Each file is written under a temporary name and renamed when all are
    written, so none is ever half-written.  Existing files are replaced (the
    command line refuses that without ``--force``).
    """
    from uio_ring.spec.files import Outputs

    stem = Path(stem)
    texts = design_texts(design, formats)
    with Outputs(stem.parent, force=True) as out:
        for suffix, text in texts.items():
            out.write_text(stem.with_suffix(suffix), text)
    return [stem.with_suffix(suffix) for suffix in texts]


def _bounded_int(text: str) -> int:
    if len(text.lstrip("-")) > 18:
        raise SpecError(f"an integer of {len(text)} digits in a design file; exact numbers are stored as strings")
    return int(text)


def _read_design_file(p: Path) -> Any:
    """Plain data of a design file: a regular file of at most ``MAX_DESIGN_BYTES``, integers
    bounded, nesting bounded (floats appear only in the derived numeric section)."""
    from uio_ring.spec.files import read_text_limited
    from uio_ring.spec.yaml_io import load_yaml_text

    text = read_text_limited(p, max_bytes=MAX_DESIGN_BYTES, what="design")
    if p.suffix == ".json":
        try:
            return json.loads(text, parse_int=_bounded_int)
        except json.JSONDecodeError as exc:
            raise SpecError(f"{p}: not valid JSON ({exc})") from None
        except RecursionError:
            raise SpecError(f"{p}: nested too deeply") from None
    return load_yaml_text(text, max_bytes=MAX_DESIGN_BYTES)


def load_design(path: str | Path, *, verify: bool = True) -> Any:
    """Load a design written by :func:`save_design` (``.json`` or ``.yaml``).

    The file is validated (types, shapes, bounded numbers) and, unless
    ``verify=False``, its certificate is re-run: an edited or corrupted design
    raises :class:`~uio_ring.errors.SpecError` naming the failing check.
    """
    if not isinstance(path, (str, PathLike)):
        raise SpecError(f"expected a file name, got {type(path).__name__}")
    p = Path(path)
    design = design_from_data(_read_design_file(p))
    if verify:
        try:
            cert = design.certificate()
        except UioRingError as exc:
            raise SpecError(f"{p}: the design's matrices do not fit together ({exc})") from None
        if not cert.ok:
            failed = cert.failed
            what = f" ({failed[0].name})" if failed else ""
            raise SpecError(
                f"{p}: the design fails its certificate{what}; the file was edited or corrupted "
                "(load_design(..., verify=False) loads it anyway)"
            )
    return design
