"""Spec files: from YAML text to a validated :class:`Spec`.

Every error is a :class:`~uio_ring.errors.SpecError` whose message starts with
the path inside the file (``system.C[2][1]``, indices from 0) and says what
would fix it.  Numbers are exact (``0.01`` is 1/100).  Limits refuse files that
would make the exact algebra hang: at most ``MAX_DIMENSION`` states, inputs or
outputs and δ-degree at most ``MAX_DELAY_DEGREE``.

>>> spec = load_spec_text('''
... system:
...   A: [[0, 1], [-1, -d]]
...   B: [[0], [1]]
...   C: [[1, 0], [0, 1]]
...   h: 0.05
... ''')
>>> spec.system.n_x, spec.system.h, spec.design.method
(2, Fraction(1, 20), 'auto')
"""

from __future__ import annotations

import difflib
import json
import math
import re
from dataclasses import dataclass, field
from fractions import Fraction
from importlib import resources
from os import PathLike
from pathlib import Path
from typing import Any

from uio_ring.errors import DimensionError, DomainError, ParseError, SpecError
from uio_ring.spec.yaml_io import load_yaml_text

__all__ = [
    "Spec",
    "DesignSpec",
    "SimulateSpec",
    "OutputSpec",
    "load_spec",
    "load_spec_text",
    "spec_from_dict",
    "schema",
    "MAX_DIMENSION",
    "MAX_DELAY_DEGREE",
    "MAX_STEPS",
    "MAX_RECORDED_VALUES",
    "MAX_COEFFICIENT_BITS",
    "MAX_SIMULATION_VALUE",
]

#: Largest number of states, outputs or inputs accepted in a spec.
MAX_DIMENSION = 64
#: Largest δ-degree accepted in a spec.
MAX_DELAY_DEGREE = 16
#: Most simulation steps accepted (t_final / dt).
MAX_STEPS = 20_000_000
#: Most values a simulation kept in memory records (steps × signals: t, x, x̂, error, y, w, ŵ,
#: u): runs written as NPZ and runs with a ``nonlinearity``.  Measured about 30 bytes of peak
#: memory per value (2·10⁶ steps of a 2-state system: 0.58 GB), so about 1.5 GB.  Longer CSV
#: runs are streamed to disk by segments (:mod:`uio_ring.cli.stream`), with bounded memory.
MAX_RECORDED_VALUES = 50_000_000
#: Largest coefficient in a spec matrix, in bits (numerator plus denominator; about
#: 3 600 decimal digits), bounded while parsing.
MAX_COEFFICIENT_BITS = 12_000
#: Largest single number (h, poles, options, simulation values), in bits: about 1 000 digits.
MAX_NUMBER_BITS = 3_400
#: Largest magnitude of a number the simulation uses (times, bounds, initial values):
#: float64 arithmetic on larger values overflows.
MAX_SIMULATION_VALUE = Fraction(10) ** 100
#: Signal names: at most this many characters, none of ``. , " '`` or control characters.
MAX_SIGNAL_NAME = 64

_MATRIX_KEYS = ("A", "B", "C", "D", "E", "F")


def schema() -> dict[str, Any]:
    """The JSON Schema of spec files: ``uio_ring/spec/schema.json`` with the ``design``
    section generated from the registry of methods (their names and typed options)."""
    from uio_ring.design.methods import METHODS

    text = resources.files("uio_ring.spec").joinpath("schema.json").read_text(encoding="utf-8")
    sch = json.loads(text)
    props: dict[str, Any] = {"method": {"enum": ["auto", *METHODS], "default": "auto",
                                        "description": "; ".join(f"{m.name}: {m.summary}" for m in METHODS.values())}}
    for m in METHODS.values():
        for opt in m.options:
            entry = props.setdefault(opt.name, {**opt.schema(), "description": ""})
            entry["description"] = (entry["description"] + "; " if entry["description"] else "") + f"{m.name}: {opt.doc}"
    sch["properties"]["design"] = {"type": "object", "additionalProperties": False, "properties": props}
    return sch


@dataclass(frozen=True)
class DesignSpec:
    """``design:`` — the method (``auto`` picks the first that applies) and its options."""

    method: str = "auto"
    options: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class SimulateSpec:
    """``simulate:`` — grid, inputs (expressions in t), initial history, noise."""

    t_final: Fraction
    dt: Fraction
    h: Fraction
    w: tuple[str, ...] = ()
    u: tuple[str, ...] = ()
    phi: tuple[str, ...] = ()
    x_hat0: tuple[Fraction, ...] | None = None
    noise_bound: tuple[Fraction, ...] | None = None
    noise_seed: int = 0
    settle: Fraction | None = None
    discretisation: str = "implicit"
    nonlinearity: tuple[str, ...] = ()
    state_names: tuple[str, ...] = ()

    def nonlinearity_function(self) -> Any:
        """``φ(t, x)`` of ``nonlinearity`` (expressions in t and the state names), or None."""
        if not self.nonlinearity:
            return None
        from uio_ring.spec.expressions import parse_state_function

        return parse_state_function(self.nonlinearity, self.state_names)

    def signal(self, which: str) -> Any:
        """A function ``t ↦ array (k, len(t))`` for ``w``, ``u`` or ``phi`` (None if absent)."""
        import numpy as np

        from uio_ring.spec.expressions import parse_signal

        texts = getattr(self, which)
        if not texts:
            return None
        fs = [parse_signal(s) for s in texts]

        def f(t: Any) -> Any:
            t = np.asarray(t, dtype=float)
            return np.stack([np.broadcast_to(g(t), t.shape) for g in fs])

        return f

    def noise(self) -> Any:
        if self.noise_bound is None:
            return None
        from uio_ring.sim.signals import UniformNoise

        amp = [float(b) for b in self.noise_bound]
        return UniformNoise(amp[0] if len(amp) == 1 else amp, seed=self.noise_seed)


@dataclass(frozen=True)
class OutputSpec:
    """``output:`` — where files go and which formats."""

    directory: str | None = None
    formats: tuple[str, ...] = ()


@dataclass(frozen=True)
class Spec:
    """A validated spec: the system, the design request, optional simulation and output."""

    system: Any
    design: DesignSpec
    simulate: SimulateSpec | None
    output: OutputSpec
    name: str = ""
    source: str | None = None


# ---------------------------------------------------------------------------------------
# entry points
# ---------------------------------------------------------------------------------------
def load_spec(path: str | Path) -> Spec:
    """Read and validate a spec file.

    Only a regular file of at most ``MAX_BYTES`` is read (devices and pipes are
    refused without reading).  Without a ``name:``, the spec is named after
    the file's stem, made into a safe file name.
    """
    from uio_ring.spec.files import read_text_limited, sanitise_name
    from uio_ring.spec.yaml_io import MAX_BYTES

    if not isinstance(path, (str, PathLike)):
        raise SpecError(f"expected a file name, got {type(path).__name__}")
    p = Path(path)
    text = read_text_limited(p, max_bytes=MAX_BYTES)
    spec = load_spec_text(text)
    return Spec(spec.system, spec.design, spec.simulate, spec.output, spec.name or sanitise_name(p.stem), str(p))


def load_spec_text(text: str) -> Spec:
    """Validate a spec given as YAML text."""
    if not isinstance(text, str):
        raise SpecError(f"expected the spec's text (str), got {type(text).__name__}; decode bytes as UTF-8 first")
    if "\x00" in text:
        raise SpecError("the text contains NUL bytes; a spec is a YAML file")
    return spec_from_dict(load_yaml_text(text))


def spec_from_dict(data: Any) -> Spec:
    """Validate a spec given as plain data (what YAML gives)."""
    if not isinstance(data, dict):
        raise SpecError(
            f"the top level is a {_kind(data)}; a spec is a mapping with a 'system' section "
            "(and optionally design, simulate, output)"
        )
    sch = schema()
    _check_keys(data, sch, "", sch)
    system = data.get("system")
    if isinstance(system, dict):
        for k in _MATRIX_KEYS:
            if isinstance(system.get(k), dict):
                for key in system[k]:
                    _delay_power(key, f"system.{k}")
    _check_name_lists(data.get("system"))
    if isinstance(data.get("name"), str):  # before the schema's terser pattern message
        from uio_ring.spec.files import safe_name

        safe_name(data["name"], "name")
    _validate_schema(data, sch)
    system = _read_system(data["system"])
    design = _read_design(data.get("design") or {})
    sim = _read_simulate(data["simulate"], system) if data.get("simulate") is not None else None
    output = _read_output(data.get("output") or {})
    name = data.get("name") or ""
    if name:
        from uio_ring.spec.files import safe_name

        safe_name(str(name), "name")
    return Spec(system, design, sim, output, str(name))


# ---------------------------------------------------------------------------------------
# structure: keys and schema
# ---------------------------------------------------------------------------------------
def _fmt(x: Fraction) -> str:
    """A rational as decimal text when it terminates (1/2 -> 0.5), else p/q."""
    q = x.denominator
    for prime in (2, 5):
        while q % prime == 0:
            q //= prime
    if q != 1:
        return f"{x.numerator}/{x.denominator}"
    try:
        text = f"{float(x):.15g}"
    except OverflowError:
        return f"{x.numerator}/{x.denominator}"
    return text if Fraction(text) == x else f"{x.numerator}/{x.denominator}"


def _kind(x: Any) -> str:
    if isinstance(x, dict):
        return "mapping"
    if isinstance(x, list):
        return "list"
    if x is None:
        return "empty value"
    return type(x).__name__


def _join(path: str, key: Any) -> str:
    return f"{path}.{key}" if path else str(key)


def _resolve(node: dict[str, Any], root: dict[str, Any]) -> dict[str, Any]:
    while "$ref" in node:
        ref = node["$ref"]
        target: Any = root
        for part in ref.lstrip("#/").split("/"):
            target = target[part]
        node = {**target, **{k: v for k, v in node.items() if k != "$ref"}}
    return node


def _check_keys(data: Any, node: dict[str, Any], path: str, root: dict[str, Any]) -> None:
    """Unknown keys, with a did-you-mean, before the schema's terser messages."""
    node = _resolve(node, root)
    props = node.get("properties")
    if props is None or not isinstance(data, dict):
        return
    for key in data:
        if not isinstance(key, str):
            raise SpecError(f"the key {key!r} is not a name", path=path or None)
        if key not in props:
            close = difflib.get_close_matches(key, list(props), n=1, cutoff=0.6)
            hint = f"; did you mean '{close[0]}'?" if close else f"; allowed: {', '.join(props)}"
            raise SpecError(f"unknown key '{key}'{hint}", path=_join(path, key))
        _check_keys(data[key], props[key], _join(path, key), root)


_NAME_KEYS = ("states", "outputs", "unknown_inputs", "known_inputs")
_BAD_NAME = re.compile(r"[.,\"'\x00-\x1f\x7f]")


def _check_name_lists(system: Any) -> None:
    """Signal names become CSV column names (``x.<name>``, ``y.<name>``, …) and plot labels:
    printable, at most ``MAX_SIGNAL_NAME`` characters, without ``. , " '`` or control characters."""
    if not isinstance(system, dict):
        return
    for key in _NAME_KEYS:
        names = system.get(key)
        if not isinstance(names, list):
            continue
        for i, n in enumerate(names):
            path = f"system.{key}[{i}]"
            if not isinstance(n, str):
                raise SpecError(f"{_kind(n)} {n!r} is not a name; quote it ('{n}') or use letters", path=path)
            bad = _BAD_NAME.search(n)
            if not n.strip() or n != n.strip():
                raise SpecError(f"{n!r}: a name is non-empty without leading or trailing spaces", path=path)
            if bad:
                raise SpecError(f"the name {n[:40]!r} contains {bad.group()!r}; names may not contain . , quotes "
                                "or control characters (they become CSV columns)", path=path)
            if len(n) > MAX_SIGNAL_NAME:
                raise SpecError(f"a name of {len(n)} characters is longer than {MAX_SIGNAL_NAME}", path=path)


def _stringify_keys(x: Any) -> Any:
    if isinstance(x, dict):
        return {str(k): _stringify_keys(v) for k, v in x.items()}
    if isinstance(x, list):
        return [_stringify_keys(v) for v in x]
    return x


def _validate_schema(data: dict[str, Any], sch: dict[str, Any]) -> None:
    import jsonschema

    def is_number(checker: Any, inst: Any) -> bool:
        return isinstance(inst, (int, float, Fraction)) and not isinstance(inst, bool)

    checker = jsonschema.Draft202012Validator.TYPE_CHECKER.redefine("number", is_number)
    cls = jsonschema.validators.extend(jsonschema.Draft202012Validator, type_checker=checker)
    validator = cls(sch)
    errors = sorted(validator.iter_errors(_stringify_keys(data)), key=lambda e: (len(e.absolute_path), str(e.absolute_path)))
    if not errors:
        return
    err = jsonschema.exceptions.best_match(errors) or errors[0]
    path = ""
    for part in err.absolute_path:
        path = f"{path}[{part}]" if isinstance(part, int) else _join(path, part)
    message = err.message
    if err.validator == "anyOf" and path.startswith("system."):
        message = (
            f"{_kind(err.instance)} is not a matrix; write rows [[a, b], [c, d]], the text "
            "\"[[a, b], [c, d]]\", or coefficients per delay {0: [[..]], 1: [[..]]}"
        )
    elif err.validator == "required":
        message = f"{err.message} (required)"
    elif err.validator == "enum":
        allowed = [str(v) for v in err.validator_value]
        close = difflib.get_close_matches(str(err.instance), allowed, n=1, cutoff=0.6)
        hint = f"; did you mean '{close[0]}'?" if close else ""
        message = f"unknown value {err.instance!r}{hint} (allowed: {', '.join(allowed)})"
    elif err.validator == "type":
        message = f"{_kind(err.instance)} {err.instance!r} is not of type {err.validator_value}"
    raise SpecError(message, path=path or None)


# ---------------------------------------------------------------------------------------
# system
# ---------------------------------------------------------------------------------------
def _entry(value: Any, path: str) -> Any:
    from uio_ring.ring.parse import parse_poly
    from uio_ring.ring.poly import to_raw

    if isinstance(value, float):
        raise SpecError(f"{value} is not a finite number", path=path)
    if isinstance(value, bool) or value is None:
        raise SpecError(f"{_kind(value)} is not a polynomial; write e.g. 0, 1/2 or 'd + 1'", path=path)
    try:
        if isinstance(value, str):
            return parse_poly(value, "d", max_degree=MAX_DELAY_DEGREE, max_bits=MAX_COEFFICIENT_BITS)
        return to_raw(value if not isinstance(value, int) else int(value), "d", path)
    except (ParseError, DomainError) as exc:
        msg = str(exc)
        if msg.startswith(path + ": "):
            msg = msg[len(path) + 2 :]
        raise SpecError(msg, path=path) from None


def _rows(value: Any, path: str) -> Any:
    from uio_ring.ring.matrix import PolyMatrix

    if not isinstance(value, list):
        raise SpecError(f"{_kind(value)} is not a list of rows", path=path)
    if len(value) > MAX_DIMENSION:
        raise SpecError(f"{len(value)} rows exceed the limit of {MAX_DIMENSION}", path=path)
    rows = []
    width = None
    for i, row in enumerate(value):
        if not isinstance(row, list):
            raise SpecError(f"row {i} is a {_kind(row)}; each row is a list [a, b, ...]", path=f"{path}[{i}]")
        if len(row) > MAX_DIMENSION:
            raise SpecError(f"{len(row)} columns exceed the limit of {MAX_DIMENSION}", path=f"{path}[{i}]")
        if width is None:
            width = len(row)
        elif len(row) != width:
            raise SpecError(f"row {i} has {len(row)} entries but row 0 has {width}", path=f"{path}[{i}]")
        rows.append([_entry(x, f"{path}[{i}][{j}]") for j, x in enumerate(row)])
    return PolyMatrix._new(rows, len(rows), width or 0, "d")


def _matrix(value: Any, path: str) -> Any:
    from uio_ring.ring.matrix import PolyMatrix

    if isinstance(value, str):
        from uio_ring.ring.parse import parse_matrix

        try:  # degrees and sizes are bounded while parsing, before anything is expanded
            rows = parse_matrix(value, "d", max_degree=MAX_DELAY_DEGREE, max_bits=MAX_COEFFICIENT_BITS)
            M = PolyMatrix._new(rows, len(rows), len(rows[0]) if rows else 0, "d") if _rect(rows) else PolyMatrix(rows)
        except (ParseError, DomainError, DimensionError) as exc:
            raise SpecError(str(exc), path=path) from None
    elif isinstance(value, dict):
        if not value:
            raise SpecError("an empty coefficient mapping; give {0: [[...]], 1: [[...]]}", path=path)
        terms = []
        seen: dict[int, Any] = {}
        for key, coeff in value.items():
            k = _delay_power(key, path)
            if k in seen:
                raise SpecError(
                    f"the keys {seen[k]!r} and {key!r} both name the coefficient of d^{k}; give each power once",
                    path=path,
                )
            seen[k] = key
            terms.append((k, _rows(coeff, f"{path}[{k}]")))
        shapes = {(k, M.shape) for k, M in terms}
        first_k, first = terms[0]
        for k, M in terms:
            if M.shape != first.shape:
                raise SpecError(
                    f"coefficient of d^{k} is {M.rows}×{M.cols} but that of d^{first_k} is "
                    f"{first.rows}×{first.cols}; all coefficients need one shape",
                    path=path,
                )
            if M.degree() > 0:
                raise SpecError(
                    f"coefficient of d^{k} contains d; in the coefficient form each entry is a number",
                    path=f"{path}[{k}]",
                )
        del shapes
        top = max(k for k, _ in terms)
        coeffs = [PolyMatrix.zeros(*first.shape)] * (top + 1)
        for k, M in terms:
            coeffs[k] = coeffs[k] + M
        M = PolyMatrix.from_coefficients(coeffs)
    else:
        M = _rows(value, path)
    if M.rows > MAX_DIMENSION or M.cols > MAX_DIMENSION:
        raise SpecError(f"{M.rows}×{M.cols} exceeds the limit of {MAX_DIMENSION} per dimension", path=path)
    if M.degree() > MAX_DELAY_DEGREE:
        raise SpecError(
            f"δ-degree {M.degree()} exceeds the limit of {MAX_DELAY_DEGREE} (uio_ring.spec.loader.MAX_DELAY_DEGREE)",
            path=path,
        )
    return M


def _rect(rows: list[list[Any]]) -> bool:
    return all(len(r) == len(rows[0]) for r in rows) if rows else True


def _delay_power(key: Any, path: str) -> int:
    from uio_ring.ring.parse import decimal_fraction

    text = _fmt(key) if isinstance(key, Fraction) else str(key).strip()
    try:
        value = decimal_fraction(text) if len(text) <= 40 else Fraction(MAX_DELAY_DEGREE + 1)
    except (ParseError, DomainError):
        raise SpecError(
            f"the key {text!r} is not a delay multiple; the keys are the powers of d (0, 1, 2, …)", path=path
        ) from None
    if value.denominator != 1 or value < 0:
        raise SpecError(
            f"delay multiple {text} is not a whole number ≥ 0; delays must be commensurate: "
            "multiples 0, 1, 2, … of the basic delay h (choose a smaller h to make them whole)",
            path=path,
        )
    if value > MAX_DELAY_DEGREE:
        raise SpecError(f"delay multiple {value} exceeds the limit of {MAX_DELAY_DEGREE}", path=path)
    return int(value)


def _positive(value: Any, path: str, what: str) -> Fraction:
    x = _exact(value, path, "a number")
    if x <= 0:
        raise SpecError(f"{what} must be positive, got {_fmt(x) if len(str(x.denominator)) < 40 else x}", path=path)
    return x


def _shape_text(M: Any) -> str:
    return f"{M.rows}×{M.cols}"


def _read_system(data: dict[str, Any]) -> Any:
    from uio_ring.ring.matrix import PolyMatrix
    from uio_ring.systems.delay_system import DelaySystem

    mats = {k: _matrix(data[k], f"system.{k}") for k in _MATRIX_KEYS if data.get(k) is not None}
    names = {k: data.get(k) for k in ("states", "outputs", "unknown_inputs", "known_inputs")}
    A = mats["A"]
    if A.rows != A.cols:
        raise SpecError(f"A is {_shape_text(A)}; it must be square (n_x × n_x)", path="system.A")
    n = A.rows
    C = mats["C"]
    p = C.rows
    if C.cols != n:
        raise SpecError(f"C is {_shape_text(C)} but A is {n}×{n}: C needs {n} columns", path="system.C")
    B = mats["B"]
    m_from = None
    if names["unknown_inputs"] is not None:
        m_from = (len(names["unknown_inputs"]), "unknown_inputs names it")
    elif "D" in mats:
        m_from = (mats["D"].cols, "D has that many columns")
    if B.rows != n or (m_from and B.cols != m_from[0]):
        extra = f" and w has {m_from[0]} components ({m_from[1]})" if m_from else ""
        raise SpecError(
            f"B is {_shape_text(B)} but A is {n}×{n}{extra}; B must be {n}×{m_from[0] if m_from else 'n_w'}",
            path="system.B",
        )
    m = B.cols
    D = mats.get("D", PolyMatrix.zeros(p, m))
    if D.shape != (p, m):
        raise SpecError(f"D is {_shape_text(D)} but C has {p} rows and B has {m} columns: D must be {p}×{m}", path="system.D")
    E = mats.get("E")
    F = mats.get("F")
    if E is not None and E.rows != n:
        raise SpecError(f"E is {_shape_text(E)} but A is {n}×{n}: E needs {n} rows", path="system.E")
    if F is not None and F.rows != p:
        raise SpecError(f"F is {_shape_text(F)} but C has {p} rows: F needs {p} rows", path="system.F")
    if E is not None and F is not None and E.cols != F.cols:
        raise SpecError(f"F is {_shape_text(F)} but E has {E.cols} columns (known inputs)", path="system.F")
    h = _positive(data["h"], "system.h", "the basic delay h (seconds)") if data.get("h") is not None else None
    if h is None and any(M.degree() > 0 for M in mats.values()):
        raise SpecError("the matrices contain d (delays) but h is not given; add h: <seconds>", path="system.h")
    for key, count, what in (
        ("states", n, "states (n_x)"),
        ("outputs", p, "outputs (rows of C)"),
        ("unknown_inputs", m, "unknown inputs (columns of B)"),
        ("known_inputs", E.cols if E is not None else (F.cols if F is not None else 0), "known inputs"),
    ):
        given = names[key]
        if given is not None and len(given) != count:
            raise SpecError(f"{len(given)} names given for {count} {what}", path=f"system.{key}")
    try:
        return DelaySystem(
            A,
            B,
            C,
            D,
            E,
            F,
            h=h,
            state_names=names["states"],
            output_names=names["outputs"],
            unknown_input_names=names["unknown_inputs"],
            known_input_names=names["known_inputs"],
        )
    except (DimensionError, DomainError) as exc:
        raise SpecError(str(exc), path="system") from None


# ---------------------------------------------------------------------------------------
# design, simulate, output
# ---------------------------------------------------------------------------------------
def _read_design(data: dict[str, Any]) -> DesignSpec:
    """``design:`` — the method and its options, read by the registry's option records."""
    from uio_ring.design.methods import METHODS, get_method

    method = data.get("method", "auto")
    if method != "auto":
        get_method(method)  # SpecError at design.method, with a suggestion
    raw = {k: v for k, v in data.items() if k != "method" and v is not None}
    if method != "auto":
        return DesignSpec(method=method, options=METHODS[method].read_options(raw))
    # auto: every key must belong to some method; each is read by the first method that has it
    owners: dict[str, Any] = {}
    for m in METHODS.values():
        for opt in m.options:
            owners.setdefault(opt.name, opt)
    unknown = sorted(set(raw) - set(owners))
    if unknown:
        raise SpecError(f"option {unknown[0]!r} belongs to no design method (known: {', '.join(owners)})",
                        path=f"design.{unknown[0]}")
    return DesignSpec(method=method, options={k: owners[k].read(v, f"design.{k}") for k, v in raw.items()})


def _exact(value: Any, path: str, what: str = "an exact rational") -> Fraction:
    """A number of a spec: exact, and bounded (at most ``MAX_NUMBER_BITS`` bits) before it is built."""
    from uio_ring.ring import _backend as bk
    from uio_ring.ring.parse import _short, parse_poly
    from uio_ring.ring.poly import exact_fraction

    if isinstance(value, float) and not math.isfinite(value):
        raise SpecError(f"{value} is not a finite number", path=path)
    try:
        if isinstance(value, str):
            p = parse_poly(value, "d", max_degree=MAX_DELAY_DEGREE, max_bits=MAX_NUMBER_BITS)
            if p.degree() > 0:
                raise SpecError(f"{_short(value)} is not {what}: it contains d", path=path)
            return bk.to_fraction(p[0]) if not p.is_zero() else Fraction(0)
        x = exact_fraction(value, path)
    except (DomainError, ParseError) as exc:
        msg = str(exc).removeprefix(f"{path}: ")
        raise SpecError(f"{_short(str(value))} is not {what} ({msg})", path=path) from None
    if x.numerator.bit_length() + x.denominator.bit_length() > MAX_NUMBER_BITS:
        raise SpecError(f"a number of more than {MAX_NUMBER_BITS} bits (about 1 000 digits) is refused", path=path)
    return x


def _texts(value: Any, count: int, path: str, what: str, *, allow_broadcast: bool = False) -> tuple[str, ...]:
    from uio_ring.spec.expressions import parse_signal

    items = value if isinstance(value, list) else [value]
    if len(items) == 1 and allow_broadcast and count > 1:
        items = items * count
    if len(items) != count:
        raise SpecError(f"{len(items)} expression(s) given for {count} {what}", path=path)
    out = []
    for i, item in enumerate(items):
        text = str(item) if not isinstance(item, Fraction) else f"({item.numerator})/({item.denominator})"
        sub = f"{path}[{i}]" if isinstance(value, list) else path
        try:
            parse_signal(text)
        except SpecError as exc:
            raise SpecError(str(exc), path=sub) from None
        out.append(text)
    return tuple(out)


def _sim_value(x: Fraction, path: str) -> Fraction:
    """A number the float64 simulation will use: refuse it when float64 cannot hold it."""
    if abs(x) > MAX_SIMULATION_VALUE or (x != 0 and abs(x) < 1 / MAX_SIMULATION_VALUE):
        raise SpecError(
            f"{_fmt(x) if len(str(x.numerator)) < 40 else 'the value'} is outside the range the float64 simulation "
            f"handles (magnitudes 1e-100 … 1e100; uio_ring.spec.loader.MAX_SIMULATION_VALUE)",
            path=path,
        )
    return x


def recorded_values(system: Any, t_final: Any, dt: Any) -> tuple[int, int]:
    """``(steps, columns)`` of a simulation's record: t, x, x̂, error, y, w, ŵ, u per step."""
    columns = 1 + 3 * system.n_x + system.n_y + 2 * system.n_w + system.n_u
    return math.ceil(Fraction(t_final) / Fraction(dt)), columns


def check_memory_budget(system: Any, t_final: Any, dt: Any, *, why: str) -> None:
    """Refuse (``SpecError`` at ``simulate``) a run kept in memory that records more than
    :data:`MAX_RECORDED_VALUES` values; ``why`` says why this run is not streamed."""
    steps, columns = recorded_values(system, t_final, dt)
    values = steps * columns
    if values > MAX_RECORDED_VALUES:
        raise SpecError(
            f"{steps} steps × {columns} recorded signals = {values:.3g} values exceed the memory budget of "
            f"{MAX_RECORDED_VALUES:.0e} (uio_ring.spec.loader.MAX_RECORDED_VALUES); {why}: choose a larger dt or "
            "a shorter t_final (CSV output without a nonlinearity is streamed to disk and has no such bound)",
            path="simulate",
        )


def _read_simulate(data: dict[str, Any], system: Any) -> SimulateSpec:
    t_final = _sim_value(_positive(data["t_final"], "simulate.t_final", "t_final"), "simulate.t_final")
    dt = _sim_value(_positive(data["dt"], "simulate.dt", "dt"), "simulate.dt")
    if system.h is not None:
        _sim_value(system.h, "system.h")
    h = system.h
    if h is None:
        h = dt  # a delay-free system: one grid step per "delay"
    ratio = h / dt
    if ratio.denominator != 1:
        n_lo = max(1, math.floor(ratio))
        examples = ", ".join(f"{_fmt(h / k)} (N = {k})" for k in sorted({n_lo, n_lo + 1, 10 * n_lo}))
        raise SpecError(
            f"h/dt = {_fmt(ratio)} is not a whole number; the grid needs dt = h/N with N a "
            f"positive integer (h = {_fmt(h)}), e.g. dt = {examples}",
            path="simulate.dt",
        )
    if t_final / dt > MAX_STEPS:
        raise SpecError(
            f"t_final/dt = {math.ceil(t_final / dt)} steps exceed the limit of {MAX_STEPS}", path="simulate"
        )
    if data.get("nonlinearity") is not None:  # simulated in memory (not streamed): bounded here
        check_memory_budget(system, t_final, dt, why="a run with a nonlinearity is kept in memory")
    w = _texts(data["w"], system.n_w, "simulate.w", "unknown inputs") if data.get("w") is not None else ()
    if not w and system.n_w:
        w = ("0",) * system.n_w
    u = _texts(data["u"], system.n_u, "simulate.u", "known inputs") if data.get("u") is not None else ()
    if not u and system.n_u:
        u = ("0",) * system.n_u
    phi = (
        _texts(data["phi"], system.n_x, "simulate.phi", "states", allow_broadcast=True)
        if data.get("phi") is not None
        else ()
    )
    x_hat0 = None
    if data.get("x_hat0") is not None:

        vals = data["x_hat0"]
        if len(vals) not in (system.n_x, system.n_x + system.n_w):
            raise SpecError(f"{len(vals)} values given for {system.n_x} states", path="simulate.x_hat0")
        x_hat0 = tuple(
            _sim_value(_exact(v, f"simulate.x_hat0[{i}]"), f"simulate.x_hat0[{i}]") for i, v in enumerate(vals)
        )
    noise_bound = None
    seed = 0
    if data.get("noise") is not None:
        nd = data["noise"]
        raw = nd["bound"] if isinstance(nd["bound"], list) else [nd["bound"]]
        if len(raw) not in (1, system.n_y):
            raise SpecError(f"{len(raw)} bounds given for {system.n_y} outputs", path="simulate.noise.bound")
        bounds = []
        for i, b in enumerate(raw):
            where = f"simulate.noise.bound[{i}]" if isinstance(nd["bound"], list) else "simulate.noise.bound"
            x = _sim_value(_exact(b, where), where)
            if x < 0:
                raise SpecError(f"the noise bound must be ≥ 0, got {_fmt(x)}", path=where)
            bounds.append(x)
        noise_bound = tuple(bounds)
        seed = nd.get("seed", 0)
        if not isinstance(seed, int) or isinstance(seed, bool) or not 0 <= seed < 2**63:
            raise SpecError(f"the seed must be a whole number in 0 … 2**63 − 1, got {seed!r}", path="simulate.noise.seed")
    settle = None
    if data.get("settle") is not None:

        settle = _exact(data["settle"], "simulate.settle")
        if not 0 <= settle < t_final:
            raise SpecError(f"settle = {_fmt(settle)} must lie in [0, t_final)", path="simulate.settle")
    nonlinearity: tuple[str, ...] = ()
    if data.get("nonlinearity") is not None:
        from uio_ring.spec.expressions import parse_state_function

        items = data["nonlinearity"]
        if len(items) != system.n_x:
            raise SpecError(f"{len(items)} expression(s) given for {system.n_x} states", path="simulate.nonlinearity")
        if system.max_delay_degree > 0:
            raise SpecError("a nonlinearity is simulated for delay-free systems only", path="simulate.nonlinearity")
        nonlinearity = tuple(str(v) for v in items)
        for i, text in enumerate(nonlinearity):
            try:
                parse_state_function([text], system.state_names)
            except SpecError as exc:
                raise SpecError(str(exc), path=f"simulate.nonlinearity[{i}]") from None
    return SimulateSpec(
        t_final, dt, h, w, u, phi, x_hat0, noise_bound, seed, settle, str(data.get("discretisation", "implicit")),
        nonlinearity, tuple(system.state_names),
    )


def _read_output(data: dict[str, Any]) -> OutputSpec:
    """``output.directory`` is relative to the spec's folder and stays inside it."""
    formats = tuple(data.get("formats") or ())
    directory = data.get("directory")
    if directory is not None:
        text = str(directory)
        parts = text.replace("\\", "/").split("/")
        if "\x00" in text or not text.strip():
            raise SpecError(f"{text!r} is not a folder name", path="output.directory")
        if Path(text).is_absolute() or text.startswith(("/", "\\", "~")) or (len(text) > 1 and text[1] == ":"):
            raise SpecError(
                f"{text!r} is absolute; output.directory is relative to the spec's folder "
                "(use --out to write elsewhere)",
                path="output.directory",
            )
        if ".." in parts:
            raise SpecError(
                f"{text!r} leaves the spec's folder ('..'); output.directory stays inside it "
                "(use --out to write elsewhere)",
                path="output.directory",
            )
        if len(text) > 255:
            raise SpecError(f"a folder name of {len(text)} characters is too long (at most 255)", path="output.directory")
    return OutputSpec(directory=directory, formats=formats)
