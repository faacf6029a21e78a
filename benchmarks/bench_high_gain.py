#!/usr/bin/env python
"""Benchmark of the exact algorithms of the high-gain observer with output shaping
(Grip & Saberi 2010): admissibility, the canonical form, ``shape`` and the full design.

For n = 5, 10, 20, 40 (seeded), three families of sets (A, C, W), each hidden by
random integer coordinate changes ``x' = Γ_x x``, ``y' = Γ_y y`` (det ±1):

* ``admissible`` — a canonical form (chains of lengths about n/p, p = max(2, n // 10)
  outputs, random output injection L, two W_k with random generalised
  lower-triangular blocks): admissible, ``shape`` returns the identity filter at
  iteration n + 1;
* ``example-2-like`` — the same with one extra entry of W_1 from the bottom of the
  longest chain into the top of the shortest (as in the paper's Example 2), and no
  entries (of W or of L) from the shortest chain into the others: inadmissible,
  solved by integrating one output (filter order q_longest − 1);
* ``upward`` — one random entry above a block diagonal; ``shape`` runs with
  ``max_order = 2`` (it may hit the cap: reported, not an error).

Printed per set: the time of ``admissibility``, ``canonical_form`` (inadmissible
sets: the form of (A, C) with the W̄ blocks that violate (11)), ``shape``, the
filter order, iterations, and ``design_high_gain`` (shape + canonical form +
gains) plus its certificate.  The paper's Examples 1 and 2 are timed first.
Timings are never asserted.

Usage::

    python benchmarks/bench_high_gain.py            # n = 5, 10, 20, 40
    python benchmarks/bench_high_gain.py --sizes 5 10
    python benchmarks/bench_high_gain.py --quick    # n = 5
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

import sympy  # noqa: E402

from uio_ring import DelaySystem, admissibility, canonical_form, design_high_gain, shape  # noqa: E402

EX_A = [[0, 1, 0, 0, 0], [0, 0, 0, 0, 0], [0, 0, 0, 1, 0], [0, 0, 0, 0, 1], [0, 0, 0, 0, 0]]
EX_C = [[1, 0, 0, 0, 0], [0, 0, 1, 0, 0]]
EX_W1 = [[0, -1, 0, 1, 0], [0, 0, 0, 0, 1], [0, -1, 0, 1, 0], [1, 0, 0, 0, 1], [0, 1, 0, 0, 0]]
EX_W2 = [[0, 0, 0, 0, 1], [0] * 5, [0] * 5, [0] * 5, [0] * 5]


def unimodular(n: int, rng: random.Random) -> sympy.Matrix:
    """Random integer matrix with det ±1 (sparse triangular factors, entries in [−1, 1])."""
    lo, up = sympy.eye(n), sympy.eye(n)
    for i in range(n):
        up[i, i] = rng.choice([1, -1])
        for j in range(max(0, i - 3), i):
            lo[i, j] = rng.randint(-1, 1)
            up[j, i] = rng.randint(-1, 1)
    perm = sympy.eye(n)[rng.sample(range(n), n), :]
    return perm * lo * up


def canonical_set(n: int, family: str, rng: random.Random):
    p = max(2, n // 10)
    q = [n // p + (1 if i < n % p else 0) for i in range(p)]
    starts = [sum(q[:i]) for i in range(p)]
    A, C = sympy.zeros(n, n), sympy.zeros(p, n)
    for i, (s, qi) in enumerate(zip(starts, q, strict=True)):
        C[i, s] = 1
        for r in range(qi - 1):
            A[s + r, s + r + 1] = 1
    longest, shortest = 0, p - 1  # q is non-increasing
    L = sympy.Matrix(n, p, lambda i, j: rng.randint(-1, 1))
    if family == "example-2-like":
        L[:, shortest] = sympy.zeros(n, 1)  # y_shortest will be integrated: keep it out of the other chains
    A += L * C
    Ws = []
    for _ in range(2):
        W = sympy.zeros(n, n)
        for si, qi in zip(starts, q, strict=True):
            for sj, qj in zip(starts, q, strict=True):
                if family == "example-2-like" and sj == starts[shortest] and si != sj:
                    continue  # integrators on the shortest chain would turn these upward
                for r in range(qi):
                    for c in range(min(r + 1, qj)):
                        if rng.random() < 0.2:
                            W[si + r, sj + c] = rng.randint(-2, 2)
        Ws.append(W)
    if family == "example-2-like":
        Ws[0][starts[shortest], starts[longest] + q[longest] - 1] = 1
    elif family == "upward":
        cands = [(si + r, sj + c) for si, qi in zip(starts, q, strict=True) for sj, qj in zip(starts, q, strict=True)
                 for r in range(qi) for c in range(r + 1, qj)]
        Ws[0][rng.choice(cands)] = 1
    Gx, Gy = unimodular(n, rng), unimodular(p, rng)
    Gxi = Gx.inv()
    return (Gx * A * Gxi).tolist(), (Gy * C * Gxi).tolist(), [(Gx * W * Gxi).tolist() for W in Ws]


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t


def row(label: str, A, C, W, max_order=None) -> None:
    adm, t_adm = timed(lambda: admissibility(A, C, W))
    cf, t_cf = timed(lambda: canonical_form(A, C, W))
    res, t_sh = timed(lambda: shape(A, C, W, max_order=max_order))
    if res.found:
        sysm = DelaySystem(A, [], C, None)
        d, t_des = timed(lambda: design_high_gain(sysm, W=W, epsilon="1/2", max_order=max_order))
        cert, t_cert = timed(d.certificate)
        design = f"{t_des:9.3f} {t_cert:9.3f}  {'ok' if cert.ok else 'FAIL'}"
    else:
        design = "        —         —  cap hit"
    print(f"{label:<28} {str(adm.holds):>5} {t_adm:9.4f} {t_cf:9.4f} {len(cf.violations):>5} {t_sh:9.3f} "
          f"{res.order:>3} {res.iterations:>5} {design}", flush=True)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="*", default=[5, 10, 20, 40])
    ap.add_argument("--quick", action="store_true", help="n = 5 only")
    ap.add_argument("--seed", type=int, default=12)
    args = ap.parse_args(argv)
    sizes = [5] if args.quick else args.sizes
    print("high-gain observer with output shaping: exact algorithms over Q (times in seconds)")
    print(f"{'set':<28} {'adm':>5} {'t_adm':>9} {'t_canon':>9} {'viol':>5} {'t_shape':>9} {'n_f':>3} {'iter':>5} "
          f"{'t_design':>9} {'t_cert':>9}  cert")
    row("paper Example 1", EX_A, EX_C, [EX_W1])
    row("paper Example 2", EX_A, EX_C, [EX_W2])
    for n in sizes:
        rng = random.Random(args.seed * 1000 + n)
        for family in ("admissible", "example-2-like", "upward"):
            A, C, W = canonical_set(n, family, rng)
            row(f"n={n} {family}", A, C, W, max_order=2 if family == "upward" else None)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
