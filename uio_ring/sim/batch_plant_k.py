"""The plant of a batch scenario-innermost: block integration and outputs in compiled loops.

:class:`~uio_ring.sim.batch._BatchPlant` with ``kernel="numba"`` and one plant whose blocks
run step by step (:meth:`~uio_ring.sim._blocks.BlockIntegrator.run_rows`: N > 16 steps per
block; smaller blocks keep their grouped block maps) runs its segments here, every array
laid out ``(rows, columns, K)``:

* the input forcing ``B(δ) w + E(δ) u`` on the segment's points (one tap pass per stack);
* per block: the delayed forcing ``Σ_{i≥1} A_i x(t − i h)`` on the block's N + 1 points added
  to it, then, per group of steps with the same stencil nodes, the quadrature and the steps
  ``x_{r+1} = Φ x_r + Σ_m W_m f(r + q_m)`` in one fused pass
  (:func:`~uio_ring.numeric.scenario_kernel.stencil_scan_k`);
* the outputs ``y = C(δ) x + D(δ) w + F(δ) u``.

The same map as ``run_rows`` (the stencils of :mod:`uio_ring.sim._blocks`), up to rounding.
Complexity: ``O(n² K)`` per step (the recursion) plus ``O(P r K)`` per tap stack of P
nonzero coefficient rows; memory: the segment's arrays.

>>> import numpy as np
>>> from uio_ring.sim._blocks import block_integrator
>>> integ = block_integrator(np.array([[[-1.0]], [[0.5]]]), 20, 0.05)   # x' = −x + ½ x(t − 1), N = 20
>>> XT = np.ones((20 + 40 + 1, 1, 2)); fin = np.zeros((41, 1, 2))
>>> run_blocks_k(integ, XT, fin, 2)
>>> X = np.ones((61, 2, 1)); integ.run_rows(X, np.zeros((41, 2, 1)), 2)
>>> bool(np.allclose(XT[:, 0, 0], X[:, 0, 0], rtol=1e-13, atol=0))
True
"""

from __future__ import annotations

from typing import Any

import numpy as np

from uio_ring.numeric.scenario_kernel import TapPairs, stencil_scan_k, tap_pairs, tap_sum_k

__all__ = ["run_blocks_k"]


def run_blocks_k(integ: Any, XT: np.ndarray, finT: np.ndarray, nblocks: int, end_fix: np.ndarray | None = None) -> None:
    """:meth:`~uio_ring.sim._blocks.BlockIntegrator.run_rows` scenario-innermost: ``XT``
    ``(K N + nblocks N + 1, n, S)`` (the window before the first block filled), ``finT``
    ``(nblocks N + 1, n, S)``, ``end_fix`` ``(S, nblocks, n)``; ``XT`` filled in place."""
    N, Kd = integ.N, integ.K
    A, groups, PhiT = _tables(integ)
    KN = Kd * N
    for k in range(nblocks):
        a = k * N
        if A is not None:  # the delayed states on the block's points, plus the input forcing
            F = tap_sum_k(XT, a + (Kd - 1 - np.arange(Kd)) * N, A, np.empty((N + 1,) + XT.shape[1:]))
            F += finT[a : a + N + 1]
        else:
            F = finT[a : a + N + 1].copy()
        if end_fix is not None:
            F[N] += end_fix[:, k].T
        for r0, r1, starts, W in groups:  # quadrature and steps, one fused pass per group of steps
            stencil_scan_k(F, starts, W, PhiT, XT[a + KN + r0], XT[a + KN + 1 + r0 : a + KN + 1 + r1])


def _tables(integ: Any) -> tuple[TapPairs | None, list[tuple[int, int, np.ndarray, TapPairs]], np.ndarray]:
    """The integrator's coefficient rows, once per integrator: the delayed stacks ``A_1 … A_K``
    (row form; tap i − 1 is ``A_i``), per group of steps its nodes and stencil weights, and Φᵀ."""
    tab = getattr(integ, "_k_tables", None)
    if tab is None:
        Kd = integ.K
        A = tap_pairs(np.stack([integ.A[i].T for i in range(1, Kd + 1)])) if Kd else None
        groups = [(r0, r1, r0 + np.array(nodes, dtype=np.int64), tap_pairs(np.stack(WT)))
                  for r0, r1, nodes, WT in integ.row_groups]
        tab = integ._k_tables = (A, groups, np.ascontiguousarray(integ.Phi.T))
    return tab
