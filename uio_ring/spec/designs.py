"""Saving designs to JSON/YAML (exact values as strings) and loading them back.

``load_design(save_design(d, ...)[0]) == d`` for every design class: the files
hold every field of the design dataclass (matrices as lists of polynomial
strings, with their shapes so that empty matrices keep them).

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
from pathlib import Path
from typing import Any

from uio_ring.errors import SpecError, UioRingError

__all__ = ["design_to_data", "design_from_data", "save_design", "load_design", "load_observer_model"]

FORMAT_VERSION = 1


def _design_classes() -> dict[str, type]:
    """``{method name: design class}`` from the registry of methods."""
    from uio_ring.design.methods import METHODS

    return {name: m.design_class for name, m in METHODS.items()}


def _encode(value: Any) -> Any:
    """Tagged plain data: JSON scalars stay; everything else is ``{"$tag": …}``."""
    from uio_ring.ring.matrix import PolyMatrix
    from uio_ring.systems.delay_system import DelaySystem

    if value is None or isinstance(value, (bool, int, str)):
        return value
    if isinstance(value, PolyMatrix):
        return {"$matrix": [[str(p) for p in row] for row in value.tolist()], "shape": list(value.shape)}
    if isinstance(value, DelaySystem):
        return {"$system": value.to_dict(), "shapes": {k: list(M.shape) for k, M in value.matrices().items()}}
    if isinstance(value, Fraction):
        return {"$q": str(value)}
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
    fields = {f.name: _encode(getattr(design, f.name)) for f in dataclasses.fields(design) if f.compare}
    out = {"uio_ring_design": FORMAT_VERSION, "method": design.method, "fields": fields, "summary": design.to_dict(),
           "numeric_derived": design.numeric().to_dict()}
    try:
        out["performance_derived"] = design.performance().to_dict()
    except UioRingError as exc:  # nonlinear observer, or delays without h: say why
        out["performance_derived"] = {"not_computed": str(exc)}
    return out


def load_observer_model(path: str | Path) -> Any:
    """The float observer model stored in a design file (its ``numeric_derived`` section),
    ready for :meth:`~uio_ring.numeric.model.ObserverModel.stepper` or
    :meth:`~uio_ring.numeric.model.ObserverModel.to_control`."""
    from uio_ring.numeric.model import ObserverModel

    data = _read_design_file(Path(path))
    if not isinstance(data, dict) or "numeric_derived" not in data:
        raise SpecError("the design file has no 'numeric_derived' section (written by an older uio_ring?)",
                        path="numeric_derived")
    return ObserverModel.from_dict(data["numeric_derived"])


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
            return PolyMatrix(value["$matrix"], shape=(rows, cols)) if rows and cols else PolyMatrix.zeros(rows, cols)
        if "$system" in value:
            data = dict(value["$system"])
            for k, (r, c) in value["shapes"].items():
                if r == 0 or c == 0:
                    data[k] = PolyMatrix.zeros(r, c)
            return DelaySystem.from_dict(data)
        if "$q" in value:
            return Fraction(value["$q"])
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
    except (KeyError, TypeError, ValueError, ZeroDivisionError) as exc:
        raise SpecError(f"malformed value ({exc})", path=where) from None
    raise SpecError(f"unknown tag in {sorted(value)}", path=where)


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
    fields = data.get("fields") or {}
    kwargs = {}
    for f in dataclasses.fields(cls):
        if not f.compare:
            continue
        if f.name not in fields:
            raise SpecError(f"the design file has no field {f.name!r}", path="fields")
        kwargs[f.name] = _decode(fields[f.name], f"fields.{f.name}", helpers)
    return cls(**kwargs)


def save_design(design: Any, stem: str | Path, *, formats: Sequence[str] = ("json", "yaml")) -> list[Path]:
    """Write ``stem.json`` / ``stem.yaml`` (and ``stem.tex`` for ``"latex"``); returns the paths."""
    from uio_ring.spec.yaml_io import dump_yaml

    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    data = design_to_data(design)
    out = []
    for fmt in formats:
        if fmt == "json":
            p = stem.with_suffix(".json")
            p.write_text(json.dumps(data, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
        elif fmt == "yaml":
            p = stem.with_suffix(".yaml")
            p.write_text(dump_yaml(data), encoding="utf-8")
        elif fmt == "latex":
            p = stem.with_suffix(".tex")
            p.write_text(design.to_latex() + "\n", encoding="utf-8")
        else:
            continue
        out.append(p)
    return out


def _read_design_file(p: Path) -> Any:
    from uio_ring.spec.yaml_io import load_yaml_text

    try:
        text = p.read_text(encoding="utf-8")
    except OSError as exc:
        raise SpecError(f"cannot read {p}: {exc.strerror}") from None
    if p.suffix == ".json":
        try:
            return json.loads(text)
        except json.JSONDecodeError as exc:
            raise SpecError(f"{p}: not valid JSON ({exc})") from None
    return load_yaml_text(text)


def load_design(path: str | Path) -> Any:
    """Load a design written by :func:`save_design` (``.json`` or ``.yaml``)."""
    return design_from_data(_read_design_file(Path(path)))
