"""Compiled (numba) tap sums and recursions over scenario-innermost arrays ``(rows, c, K)``.

A linear observer's segment of a batch (:class:`uio_ring.sim.batch._BatchObserver`) is made
of products with a handful of columns over K scenarios: the delayed taps of y and ẑ, the
cubic stencil of its forcing and the recursion ``ξ_{j+1} = Φ ξ_j + f_j``.  With the
scenarios innermost (each column of a sample a contiguous run of K values), one
coefficient row ``(i, q)`` of a tap stack is one pass over K values that updates all r
outputs at once: the input is loaded once for r products, against once per product (and
the output loaded and stored per product) in the time-major loops of
:mod:`uio_ring.numeric.linear_kernel` (measured on paper 001, K = 104: 1.4–1.8× on its
taps).  The r outputs are held in r row views, so the loop body is generated for each r
(source text, compiled by numba once per r and process).

* :func:`tap_sum_k`: ``out[l, j, k] = Σ_p w[p, j] S[starts[tap_p] + l, col_p, k]`` over the
  nonzero coefficient rows ``p = (tap_p, col_p)`` (:func:`tap_pairs`);
* :func:`stencil_scan_k`: the recursion ``x_{s+1} = Φ x_s + Σ_p …`` of the same sums, in one
  pass (a linear observer's stencil forcing and steps; the forcing is never stored).

Complexity: ``O(L · P · r · K)`` for P nonzero coefficient rows (plus ``O(L n² K)`` for the
recursion); memory: the output only.  Each scenario is computed by the same operations
whatever the range of scenarios of a call (threads: whole chunks of scenarios,
:func:`uio_ring.sim.batch.simulate_batch` with ``UIO_RING_THREADS``).  Without fastmath (no
contraction, no reassociation) every value is the one of the plain loops, whatever the
vectorisation.

The numpy reference is :func:`uio_ring.sim._blocks.taps` (time-major); the two agree up to
rounding (summation order).

>>> import numpy as np
>>> S = np.arange(6.0).reshape(3, 2, 1)            # rows, columns, one scenario
>>> out = np.empty((2, 2, 1))
>>> tap_sum_k(S, np.array([0, 1]), tap_pairs(np.stack([np.eye(2), 2 * np.eye(2)])), out)[:, :, 0].tolist()
[[4.0, 7.0], [10.0, 13.0]]
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import os
import sys
import threading
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

__all__ = ["TapPairs", "tap_pairs", "tap_sum_k", "delayed_sum_k", "stencil_scan_k"]


@dataclass(frozen=True, eq=False)
class TapPairs:
    """The nonzero coefficient rows of a tap stack ``M`` ``(m, c, r)`` (row-vector form):
    ``taps[p], cols[p]`` and ``weights[p] = M[taps[p], cols[p]]`` ``(P, r)``."""

    taps: np.ndarray
    cols: np.ndarray
    weights: np.ndarray

    @property
    def r(self) -> int:
        return int(self.weights.shape[1])


def tap_pairs(M: np.ndarray) -> TapPairs:
    """:class:`TapPairs` of ``M`` ``(m, c, r)``: its rows ``M[i, q]`` that are not all zero.

    >>> tap_pairs(np.array([[[0.0, 0.0], [1.0, 0.0]]])).cols.tolist()
    [1]
    """
    M = np.asarray(M, dtype=float)
    nz = np.argwhere(np.any(M != 0.0, axis=2))  # (P, 2): (i, q) in order
    return TapPairs(nz[:, 0].astype(np.int64), nz[:, 1].astype(np.int64),
                    np.ascontiguousarray(M[nz[:, 0], nz[:, 1]]).reshape(len(nz), M.shape[2]))


def tap_sum_k(S: np.ndarray, starts: np.ndarray, pairs: TapPairs, out: np.ndarray, accumulate: bool = False,
              ) -> np.ndarray:
    """``out[l, j, k] = Σ_p pairs.weights[p, j] · S[starts[pairs.taps[p]] + l, pairs.cols[p], k]``
    for ``l < len(out)`` (``accumulate``: added to ``out``, in the same pass); returns ``out``.

    ``S`` ``(R, c, K)``, ``out`` ``(L, r, K)``; C-contiguous float64.  No pair: zeros (or ``out``).
    Precondition: every row read is inside ``S`` (not checked).
    """
    prow = np.asarray(starts, dtype=np.int64)[pairs.taps]
    _run("acc" if accumulate else "tap", pairs.r, S, prow, pairs.cols, pairs.weights, out)
    return out


def delayed_sum_k(pairs: TapPairs, S: np.ndarray, j0: int, L: int, offset: int, N: int,
                  into: np.ndarray | None = None) -> np.ndarray:
    """``Σ_i M_i s(t_j − i h)`` for ``j = j0 … j0 + L − 1`` (``S[offset + j] = s(t_j)``, h = N steps;
    ``pairs`` of the stack ``M``): ``(L, r, K)`` (:func:`tap_sum_k` at the starts ``offset + j0 − i N``),
    added to ``into`` (and returned) when given.

    >>> S = np.arange(8.0).reshape(4, 2, 1)
    >>> delayed_sum_k(tap_pairs(np.stack([np.eye(2), np.eye(2)])), S, 1, 2, 0, 1)[:, :, 0].tolist()
    [[2.0, 4.0], [6.0, 8.0]]
    """
    starts = offset + j0 - N * np.arange(int(pairs.taps.max(initial=0)) + 1)
    if into is not None:
        return tap_sum_k(S, starts, pairs, into, accumulate=True)
    return tap_sum_k(S, starts, pairs, np.empty((L, pairs.r, S.shape[2])))


def stencil_scan_k(S: np.ndarray, starts: np.ndarray, pairs: TapPairs, PhiT: np.ndarray, x0: np.ndarray,
                   out: np.ndarray) -> np.ndarray:
    """``out[s] = Φ out[s − 1] + f_s`` (``out[−1] = x0``), ``f_s`` the :func:`tap_sum_k` row s:
    ``out`` ``(L, n, K)`` becomes ``x_1 … x_L``; ``PhiT = Φᵀ`` ``(n, n)``, ``x0`` ``(n, K)``.

    >>> S = np.ones((4, 1, 1)); out = np.empty((3, 1, 1))
    >>> pairs = tap_pairs(np.full((2, 1, 1), 0.5))
    >>> stencil_scan_k(S, np.array([0, 1]), pairs, np.array([[0.5]]), np.array([[1.0]]), out)[:, 0, 0].tolist()
    [1.5, 1.75, 1.875]
    """
    prow = np.asarray(starts, dtype=np.int64)[pairs.taps]
    _run("scan", pairs.r, S, prow, pairs.cols, pairs.weights, np.ascontiguousarray(PhiT),
         np.ascontiguousarray(x0), out)
    return out


def _run(kind: str, r: int, *args: np.ndarray) -> None:
    """The loop ``kind`` for r outputs over the K scenarios (last axis of the last array)."""
    out = args[-1]
    K = out.shape[2]
    if K == 0 or out.shape[0] == 0:
        return
    with _COMPILE_LOCK:  # chunks of a batch on threads: one compilation
        loop = _compiled(kind, r)
    loop(*args, 0, K)


def _pair_pass(r: int, srcs: list[str], weights: list[str], op: str) -> list[str]:
    """Source of one pass over the K-range applying one or two coefficient rows:
    ``o[j, k] op Σ_p w_p[j] · src_p[k]``."""
    lines = [f"w{p}_{j} = {w}, {j}]" for p, w in enumerate(weights) for j in range(r)]
    lines.append("for k in range(u0, u1):")
    lines += [f"    s{p} = {src}[k]" for p, src in enumerate(srcs)]
    lines += [f"    o[{j}, k] {op} " + " + ".join(f"w{p}_{j} * s{p}" for p in range(len(srcs))) for j in range(r)]
    return lines


def _indent(lines: list[str], n: int) -> list[str]:
    return [" " * (4 * n) + s for s in lines]


_COMPILE_LOCK = threading.Lock()

#: Coefficient rows applied per pass over the outputs (their loads and stores shared).
GROUP = 4

#: The scenario range as unsigned integers: indices numba need not wrap around (a signed index
#: may be negative, and the test for it keeps the loop from vectorising: measured 2.2× slower).
_RANGE = ["u0, u1 = np.uint64(k0), np.uint64(k1)"]


def _source(kind: str, r: int) -> str:
    """Source text of the loop ``kind`` (``"tap"``, ``"acc"``: the taps added to the output, or
    ``"scan"``) for r outputs."""
    def srcs(m: int) -> list[str]:
        return [f"src{i} = S[prow[p + {i}] + l, pcol[p + {i}]]" for i in range(m)]

    def rows_pass(m: int, op: str) -> list[str]:
        return srcs(m) + _pair_pass(r, [f"src{i}" for i in range(m)], [f"W[p + {i}" for i in range(m)], op)

    tap_body = ["P = prow.shape[0]", "p = 0", f"rem = P % {GROUP}", "if P == 0:"]
    tap_body += _indent(["for k in range(u0, u1):"] + _indent([f"o[{j}, k] = 0.0" for j in range(r)], 1), 1)
    for m in range(1, GROUP + 1):  # the first pass stores: the remainder's rows, or a whole group
        tap_body += [f"elif rem == {m % GROUP}:"] + _indent(rows_pass(m, "=") + [f"p = {m}"], 1)
    tap_body += ["while p < P:"] + _indent(rows_pass(GROUP, "+=") + [f"p += {GROUP}"], 1)
    if kind == "acc":  # every pass adds
        tap_body = ["P = prow.shape[0]", "p = 0", f"rem = P % {GROUP}"]
        for m in range(1, GROUP):
            tap_body += [f"{'if' if m == 1 else 'elif'} rem == {m}:"] + _indent(rows_pass(m, "+=") + [f"p = {m}"], 1)
        tap_body += ["while p < P:"] + _indent(rows_pass(GROUP, "+=") + [f"p += {GROUP}"], 1)
    if kind in ("tap", "acc"):
        head = "def loop(S, prow, pcol, W, out, k0, k1):"
        body = _RANGE + ["for l in range(out.shape[0]):"] + _indent(["o = out[l]"] + tap_body, 1)
    else:
        head = "def loop(S, prow, pcol, W, PhiT, x0, out, k0, k1):"
        step = ["prev = x0 if l == 0 else out[l - 1]", "q = 0", "while q + 1 < PhiT.shape[0]:"]  # Φ x, rows in pairs
        step += _indent(["xa, xb = prev[q], prev[q + 1]"]
                        + _pair_pass(r, ["xa", "xb"], ["PhiT[q", "PhiT[q + 1"], "+=") + ["q += 2"], 1)
        step += ["if q < PhiT.shape[0]:"] + _indent(["xa = prev[q]"] + _pair_pass(r, ["xa"], ["PhiT[q"], "+="), 1)
        body = _RANGE + ["for l in range(out.shape[0]):"] + _indent(["o = out[l]"] + tap_body + step, 1)
    module = ["import numpy as np", "from numba import njit", "",
              "", "@njit(nogil=True, cache=True)", head] + _indent(body, 1)
    return "\n".join(module) + "\n"


@functools.cache
def _compiled(kind: str, r: int) -> Any:
    """The loop for ``kind`` and r outputs, from its source
    module (:func:`_module_path`: numba caches the compiled loops beside it, so a new process
    loads them instead of compiling)."""
    from uio_ring.errors import require

    require("numba", extra="fast")
    source = _source(kind, r)
    name = f"_uio_ring_scenario_{kind}_r{r}"
    try:
        path = _module_path(source, f"{kind}_r{r}")
    except OSError:  # no writable directory: compiled in this process only (numba cannot cache them)
        ns: dict[str, Any] = {"__name__": name}
        exec(compile(source.replace(", cache=True)", ")"), f"<{name}>", "exec"), ns)  # noqa: S102
        return ns["loop"]
    spec = importlib.util.spec_from_file_location(name, path)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # importable by name: numba's cache reloads the loops' module by it
    spec.loader.exec_module(mod)
    return mod.loop


#: The environment variable with the directory of the generated loops' source modules (default:
#: ``$XDG_CACHE_HOME/uio_ring/kernels``, else ``~/.cache/uio_ring/kernels``).
KERNEL_DIR_ENV = "UIO_RING_KERNEL_DIR"


def _kernel_dir() -> Path:
    """The directory of the loops' source modules: ``$UIO_RING_KERNEL_DIR``, else the user's cache.

    Never the shared temporary directory: a file imported from there could have been put
    there by another user."""
    env = os.environ.get(KERNEL_DIR_ENV)
    if env:
        return Path(env)
    cache = os.environ.get("XDG_CACHE_HOME") or str(Path.home() / ".cache")
    return Path(cache) / "uio_ring" / "kernels"


def _private(root: Path) -> bool:
    """True if ``root`` belongs to this user and no one else may write into it (POSIX; on
    other systems the user's profile directory is private already)."""
    if not hasattr(os, "getuid"):
        return True
    st = root.stat()
    return st.st_uid == os.getuid() and not st.st_mode & 0o022


def _module_path(source: str, name: str) -> Path:
    """The file holding ``source`` (named by its hash: a changed generator writes a new file; an
    existing file is never rewritten, which would invalidate numba's cache of it).

    The file is imported, so it must be ours: the directory is created private (mode 0700)
    and refused (``PermissionError``, the caller then compiles in memory) unless it belongs
    to this user and is not writable by others, and an existing file must hold exactly
    ``source``."""
    root = _kernel_dir()
    root.mkdir(mode=0o700, parents=True, exist_ok=True)
    if not _private(root):
        raise PermissionError(f"{root} is writable by other users")
    path = root / f"scenario_{name}_{hashlib.sha256(source.encode()).hexdigest()[:16]}.py"
    if not path.exists():
        tmp = path.with_suffix(f".{os.getpid()}.tmp")
        tmp.write_text(source)
        os.replace(tmp, path)
    if path.read_text() != source:
        raise PermissionError(f"{path} does not hold the generated source")
    return path
