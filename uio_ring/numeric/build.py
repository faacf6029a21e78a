"""From exact design matrices to the float :class:`~uio_ring.numeric.model.ObserverModel`.

Designs compute every product they need exactly (over Q[δ]) and hand the
results here; this is the one place where they become float64.

>>> from uio_ring.ring.matrix import PolyMatrix
>>> m = model_from_exact(F=PolyMatrix("[[-1]]"), G_y=PolyMatrix("[[1 + d]]"), X=PolyMatrix("[[1]]"), h="1/10")
>>> m.G_y[:, 0, 0], m.h, m.lag
(array([1., 1.]), 0.1, 0)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from uio_ring.errors import SimulationError
from uio_ring.numeric.convert import coefficient_arrays, exact_to_float
from uio_ring.numeric.model import HeldInput, LevantInjection, ObserverModel

__all__ = ["model_from_exact", "constant_array", "injection_from_exact", "held_input_from_exact"]


def constant_array(M: Any, name: str) -> np.ndarray:
    """A constant (δ-degree ≤ 0) exact matrix as a float64 array of its shape.

    >>> from uio_ring.ring.matrix import PolyMatrix
    >>> constant_array(PolyMatrix("[[1/2, 0]]"), "M")
    array([[0.5, 0. ]])
    """
    arr = coefficient_arrays(M, name=name)
    if arr.shape[0] > 1:
        raise SimulationError(f"{name} must be constant (degree 0 in δ)")
    return arr[0].copy() if arr.shape[0] else np.zeros(arr.shape[1:])


def _h(h: Any) -> float | None:
    if h is None:
        return None
    from uio_ring.numeric.grid import as_float

    return as_float(h, "h")


def model_from_exact(*, F: Any, G_y: Any, X: Any, G_u: Any = None, D_y: Any = None, D_u: Any = None,
                     W: Any = None, initial: Any = None, h: Any = None, injection: LevantInjection | None = None,
                     held_input: HeldInput | None = None, interpolation: str = "cubic", guard_blocks: int = 0,
                     z_of_x: Any = None, method: str = "", phi_map: Any = None) -> ObserverModel:
    """:class:`ObserverModel` from exact matrices (``PolyMatrix``; ``F``, ``initial`` and ``phi_map`` constant)."""
    stacks: dict[str, Any] = {name: None if M is None else coefficient_arrays(M, name=f"{method}.{name}")
              for name, M in (("G_y", G_y), ("X", X), ("G_u", G_u), ("D_y", D_y), ("D_u", D_u), ("W", W),
                              ("z_of_x", z_of_x))}
    delayed = any(a is not None and a.shape[0] > 1 for a in stacks.values())
    hv = _h(h) if delayed else None  # a delayed model without h can be exported, not stepped
    return ObserverModel(
        F=constant_array(F, f"{method}.F"), **stacks,
        initial=None if initial is None else constant_array(initial, f"{method}.initial"),
        h=hv, injection=injection, held_input=held_input, interpolation=interpolation,
        guard_blocks=guard_blocks, method=method,
        phi_map=None if phi_map is None else constant_array(phi_map, f"{method}.phi_map"),
    )


def injection_from_exact(*, starts: tuple[int, ...], lengths: tuple[int, ...], gains: Any, sigma_y: Any,
                         sigma_u: Any, sigma_xi: Any = None, discretisation: str = "implicit",
                         profiles: Any = None) -> LevantInjection:
    """:class:`LevantInjection` from exact gains and constant exact σ maps (``profiles``: per chain
    None or an exact ``(d0, d_inf, mu)``)."""
    return LevantInjection(
        starts=tuple(starts), lengths=tuple(lengths),
        gains=tuple(tuple(exact_to_float(k, f"gain {i}.{j}") for j, k in enumerate(ks)) for i, ks in enumerate(gains)),
        sigma_y=constant_array(sigma_y, "sigma_y"), sigma_u=constant_array(sigma_u, "sigma_u"),
        discretisation=discretisation, sigma_xi=None if sigma_xi is None else constant_array(sigma_xi, "sigma_xi"),
        profiles=None if profiles is None else tuple(
            None if p is None else (exact_to_float(p[0], "d0"), exact_to_float(p[1], "d_inf"), exact_to_float(p[2], "mu"))
            for p in profiles),
    )


def held_input_from_exact(*, A: Any, B: Any, M: Any) -> HeldInput:
    """:class:`HeldInput` from constant exact matrices."""
    return HeldInput(A=constant_array(A, "held.A"), B=constant_array(B, "held.B"), M=constant_array(M, "held.M"))
