"""The one float model of every observer: ``ObserverModel``.

Every design (``ObserverDesign.numeric()``) fills in this record; the engine
(:class:`~uio_ring.numeric.stepper.ObserverStepper`) steps it without knowing
which method made it.  With coefficient stacks ``M = (M_0, M_1, …)`` standing
for ``M(δ) = Σ_i M_i δ^i`` (``δ s(t) = s(t − h)``)::

    ξ'(t) = F ξ(t) + G_y(δ) y(t) + G_u(δ) u(t) + K l(σ(t))      (linear part + injection)
    ẑ(t)  = ξ(t) + D_y(δ) y(t) + D_u(δ) u(t)                      (read-out)
    x̂(t)  = X(δ) ẑ(t),      ŵ(t) = W(δ) ẑ(t)                      (output maps)

* Zheng–Bejarano: ``F = L0``, ``G_y = JΛ``, ``G_u = J_u``, ``D_y = HΛ``,
  ``D_u = H_u``, ``X = T_L⁻¹``; no injection.
* Observer normal form: ``ξ = x̂̄``, ``F = Ā − Π̄ C̄`` (nilpotent), ``G_y``/``G_u``
  the injection of the measured signals and the known inputs, ``X`` = state map,
  ``W`` = input map; the injection is a :class:`LevantInjection`.

A delay-free model has ``h = None`` and stacks of length ≤ 1.

>>> import numpy as np
>>> m = ObserverModel(F=np.array([[-1.0]]), G_y=np.array([[[1.0]]]), X=np.array([[[1.0]]]))
>>> m.n_z, m.n_y, m.n_u, m.n_x, m.is_delay_free
(1, 1, 0, 1, True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from uio_ring.errors import DimensionError, SimulationError

__all__ = ["ObserverModel", "LevantInjection", "HeldInput", "DISCRETISATIONS", "INTERPOLATIONS"]

#: How an injection term is discretised: σ at the new time (set-valued sign, no
#: chattering), σ at the old time (explicit), or explicit Euler of the whole observer.
DISCRETISATIONS = ("implicit", "explicit", "euler")
#: How the measured forcing is interpolated over a step: causal cubic (4 nodes, for
#: smooth observers) or linear (2 nodes, for sliding-mode observers and held inputs).
INTERPOLATIONS = ("cubic", "linear")


def _stack(a: Any, rows: int, cols: int, name: str) -> np.ndarray:
    """A coefficient stack ``(k + 1, rows, cols)`` (zero matrices may have length 0)."""
    if a is None:
        return np.zeros((0, rows, cols))
    arr = np.asarray(a, dtype=float)
    if arr.ndim == 2:
        arr = arr[None]
    if arr.ndim != 3 or arr.shape[1:] != (rows, cols):
        raise DimensionError(f"ObserverModel.{name} has shape {np.shape(a)}; expected (k + 1, {rows}, {cols})")
    if not np.all(np.isfinite(arr)):
        raise SimulationError(f"ObserverModel.{name} has non-finite coefficients")
    arr = np.ascontiguousarray(arr)
    arr.setflags(write=False)
    return arr


@dataclass(frozen=True, eq=False)
class LevantInjection:
    """Robust exact differentiators, one chain per measured channel (Niederwieser et al. 2022, (13)–(14)).

    ``σ = sigma_y y + sigma_u u + sigma_xi ξ − ξ[starts]`` (one entry per chain; ``sigma_xi``
    optional: a chain's measured signal may be built from other observer states, as in the
    levels of a hierarchical super-twisting observer).  Chain ``j``
    occupies the states ``starts[j] … starts[j] + lengths[j] − 1``; its row ``k``
    (``k = 1 … μ``, ``μ = lengths[j]``) gets ``gains[j][k − 1] ⌈σ_j⌋^{(μ − k)/μ}``
    (``⌈σ⌋^0 = sign σ``).  The term enters ``ξ'`` with the identity (``K = I``).

    ``discretisation`` is one of :data:`DISCRETISATIONS` (default ``"implicit"``).  The
    implicit step solves the chains in order: ``σ_j`` may read the states of earlier chains
    and of the linear part, not those of chain ``j`` or later ones (checked by the stepper).

    ``profiles`` (optional, one entry per chain, None = Levant's): the exponent profile
    ``(d0, d_inf, mu)`` of a bi-homogeneous chain (Moreno's differentiator): row ``k`` gets
    ``gains[j][k − 1] Φ_k(σ_j)`` with Φ of :mod:`uio_ring.numeric.bihom`.  ``(−1, −1, any)`` is
    Levant's chain (and is stepped by the same code).  ``−1 ≤ d0 ≤ d_inf``, ``0 < mu < 1``,
    ``r_{·,i} = 1 − (μ − i) d > 0`` for ``i < μ``.
    """

    starts: tuple[int, ...]
    lengths: tuple[int, ...]
    gains: tuple[tuple[float, ...], ...]
    sigma_y: np.ndarray
    sigma_u: np.ndarray
    discretisation: str = "implicit"
    sigma_xi: Any = None
    profiles: tuple[tuple[float, float, float] | None, ...] | None = None

    def __post_init__(self) -> None:
        if self.discretisation not in DISCRETISATIONS:
            raise SimulationError(f"discretisation={self.discretisation!r}; expected one of {DISCRETISATIONS}")
        if not (len(self.starts) == len(self.lengths) == len(self.gains) == self.sigma_y.shape[0]):
            raise DimensionError("LevantInjection: starts, lengths, gains and sigma_y disagree on the number of chains")
        for j, (g, m) in enumerate(zip(self.gains, self.lengths, strict=True)):
            if len(g) != m or any(not (x > 0) for x in g):
                raise SimulationError(f"LevantInjection: chain {j + 1} needs {m} positive gains, got {g}")
        if self.profiles is not None:
            if len(self.profiles) != len(self.starts):
                raise DimensionError("LevantInjection: one exponent profile (or None) per chain")
            for j, (prof, m) in enumerate(zip(self.profiles, self.lengths, strict=True)):
                if prof is None:
                    continue
                d0, dinf, mu = (float(x) for x in prof)
                if not (-1.0 <= d0 <= dinf and 0.0 < mu < 1.0 and 1.0 - (m - 1) * dinf > 0.0):
                    raise SimulationError(f"LevantInjection: chain {j + 1}: the profile (d0, d_inf, mu) = {prof} "
                                          f"needs -1 <= d0 <= d_inf < 1/(q - 1) (q = {m}) and 0 < mu < 1")

    def profile(self, j: int) -> tuple[float, float, float] | None:
        """Chain ``j``'s exponent profile; None for Levant's (also when given as ``(−1, −1, ·)``)."""
        prof = None if self.profiles is None else self.profiles[j]
        if prof is None or (prof[0] == -1 and prof[1] == -1):
            return None
        return (float(prof[0]), float(prof[1]), float(prof[2]))

    def with_discretisation(self, discretisation: str) -> LevantInjection:
        """The same term, discretised another way."""
        return LevantInjection(self.starts, self.lengths, self.gains, self.sigma_y, self.sigma_u, discretisation,
                               self.sigma_xi, self.profiles)


@dataclass(frozen=True, eq=False)
class HeldInput:
    """The observer's own copy of the plant, for known inputs held over a step.

    The plant in the observer's coordinates is ``ξ_p' = A ξ_p + B u + …``; ``B u`` is the
    part of ``G_u u`` that enters ``ξ'`` directly, and ``M ξ_p`` the part of the forcing
    that comes through the measurements.  Over a step with ``u`` held, the stepper
    integrates ``B u`` exactly (``Γ u``, ``Γ = ∫_0^dt e^{A r} dr B``) and removes the held
    input's response ``M Γ u`` from the forcing before interpolating it, so a known input
    that jumps every step (closed loop) leaves no residual in the error.
    """

    A: np.ndarray
    B: np.ndarray
    M: np.ndarray


@dataclass(frozen=True, eq=False)
class ObserverModel:
    """Float image of an observer design; see the module docstring for the equations.

    Parameters
    ----------
    F : (n_z, n_z)
    G_y, G_u, D_y, D_u : coefficient stacks ``(k + 1, n_z, n_y | n_u)``
    X : stack ``(k + 1, n_x, n_z)`` — ``x̂ = X(δ) ẑ``
    W : stack ``(k + 1, n_w, n_z)`` or None — ``ŵ = W(δ) ẑ`` when the method reconstructs w
    h : basic delay (None for a delay-free model)
    initial : ``(n_z, n_init)`` — ``ẑ(0) = initial · x̂0`` for a given initial estimate
        (``n_init`` = n_x, or n_x + n_w for models that also estimate w); default ``X(1)⁺``
    injection : :class:`LevantInjection` or None
    held_input : :class:`HeldInput` or None (for closed-loop known inputs)
    interpolation : ``"cubic"`` or ``"linear"`` (see :data:`INTERPOLATIONS`)
    guard_blocks : blocks ``[k h, (k + 1) h]`` from 0 in which y may have derivative jumps
    z_of_x : stack ``(k + 1, n_z, n_x)`` or None — ``ẑ = z_of_x(δ) x`` along exact trajectories
        (the observer's exact initial state from the plant's; ``exact_start`` runs)
    method : the registry name of the method that made it
    phi_map : ``(n_z, n_x)`` or None — how a plant nonlinearity enters the observer:
        ``ξ' = … + phi_map · φ(t, x̂)`` (observers that copy the plant, e.g. the
        high-gain observer); ``simulate_observer(…, phi=…)`` needs it
    """

    F: np.ndarray
    G_y: np.ndarray
    X: np.ndarray
    G_u: Any = None
    D_y: Any = None
    D_u: Any = None
    W: Any = None
    h: float | None = None
    initial: Any = None
    injection: LevantInjection | None = None
    held_input: HeldInput | None = None
    interpolation: str = "cubic"
    guard_blocks: int = 0
    z_of_x: Any = None
    method: str = ""
    phi_map: Any = None

    def __post_init__(self) -> None:
        F = np.asarray(self.F, dtype=float)
        if F.ndim != 2 or F.shape[0] != F.shape[1]:
            raise DimensionError(f"ObserverModel.F has shape {F.shape}; expected square")
        n_z = F.shape[0]
        G_y = np.asarray(self.G_y, dtype=float)
        n_y = G_y.shape[-1]
        X = np.asarray(self.X, dtype=float)
        n_x = X.shape[-2]
        n_u = 0
        for a in (self.G_u, self.D_u):
            if a is not None:
                n_u = np.asarray(a).shape[-1]
        put = object.__setattr__
        put(self, "F", _stack(F, n_z, n_z, "F")[0])
        put(self, "G_y", _stack(G_y, n_z, n_y, "G_y"))
        put(self, "G_u", _stack(self.G_u, n_z, n_u, "G_u"))
        put(self, "D_y", _stack(self.D_y, n_z, n_y, "D_y"))
        put(self, "D_u", _stack(self.D_u, n_z, n_u, "D_u"))
        put(self, "X", _stack(X, n_x, n_z, "X"))
        if self.W is not None:
            put(self, "W", _stack(self.W, np.asarray(self.W).shape[-2], n_z, "W"))
        if self.z_of_x is not None:
            put(self, "z_of_x", _stack(self.z_of_x, n_z, n_x, "z_of_x"))
        if self.initial is None:
            X1 = self.X.sum(axis=0) if self.X.shape[0] else np.zeros((n_x, n_z))
            put(self, "initial", np.linalg.pinv(X1))
        init = np.asarray(self.initial, dtype=float)
        if init.ndim != 2 or init.shape[0] != n_z:
            raise DimensionError(f"ObserverModel.initial has shape {init.shape}; expected ({n_z}, n_init)")
        put(self, "initial", init)
        if self.phi_map is not None:
            pm = np.asarray(self.phi_map, dtype=float)
            if pm.shape != (n_z, n_x):
                raise DimensionError(f"ObserverModel.phi_map has shape {pm.shape}; expected ({n_z}, {n_x})")
            put(self, "phi_map", pm)
        if self.interpolation not in INTERPOLATIONS:
            raise SimulationError(f"interpolation={self.interpolation!r}; expected one of {INTERPOLATIONS}")
        if self.h is not None and not (np.isfinite(self.h) and self.h > 0):
            raise SimulationError(f"ObserverModel.h = {self.h!r} must be a positive number")

    # -- sizes -------------------------------------------------------------------------------
    @property
    def n_z(self) -> int:
        return int(self.F.shape[0])

    @property
    def n_y(self) -> int:
        return int(self.G_y.shape[2])

    @property
    def n_u(self) -> int:
        return int(self.G_u.shape[2])

    @property
    def n_x(self) -> int:
        return int(self.X.shape[1])

    @property
    def n_w(self) -> int:
        """Rows of ``ŵ`` (0 when the method does not reconstruct the unknown input)."""
        return 0 if self.W is None else int(self.W.shape[1])

    @property
    def lag(self) -> int:
        """δ-degree of the output map: ``x̂(t)`` reads ẑ over ``[t − lag·h, t]``."""
        return max(self.X.shape[0] - 1, 0)

    @property
    def max_delay(self) -> int:
        """Largest multiple of h that any tap reads."""
        stacks = [self.G_y, self.G_u, self.D_y, self.D_u, self.X] + ([self.W] if self.W is not None else [])
        return max(max(s.shape[0] - 1, 0) for s in stacks)

    @property
    def is_delay_free(self) -> bool:
        return self.max_delay == 0

    def with_discretisation(self, discretisation: str) -> ObserverModel:
        """The same model with its injection term discretised another way (no injection: unchanged)."""
        if self.injection is None or self.injection.discretisation == discretisation:
            if discretisation not in DISCRETISATIONS:
                raise SimulationError(f"discretisation={discretisation!r}; expected one of {DISCRETISATIONS}")
            return self
        from dataclasses import replace

        return replace(self, injection=self.injection.with_discretisation(discretisation))

    # -- hand-over to other tools -----------------------------------------------------------
    _STACKS = ("G_y", "G_u", "D_y", "D_u", "X", "W", "z_of_x")

    def to_dict(self) -> dict[str, Any]:
        """Plain data (floats; stacks as nested lists ``[M_0, M_1, …]``, ``M_i`` the coefficient
        of ``δ^i``); :meth:`from_dict` reads it back.  The injection term and the held-input
        copy are included.

        >>> import numpy as np
        >>> m = ObserverModel(F=[[-1.0]], G_y=[[[1.0]], [[0.5]]], X=[[[1.0]]], h=0.1)
        >>> d = m.to_dict(); d["G_y"], d["h"]
        ([[[1.0]], [[0.5]]], 0.1)
        >>> ObserverModel.from_dict(d).G_y[1, 0, 0]
        np.float64(0.5)
        """
        out: dict[str, Any] = {
            "format": "uio_ring observer model 1",
            "equations": "xi' = F xi + G_y(d) y + G_u(d) u + l(sigma); z = xi + D_y(d) y + D_u(d) u; "
                         "x_hat = X(d) z; w_hat = W(d) z; d^i s(t) = s(t - i h)",
            "method": self.method, "h": self.h, "F": self.F.tolist(), "initial": self.initial.tolist(),
            "interpolation": self.interpolation, "guard_blocks": self.guard_blocks,
        }
        for name in self._STACKS:
            a = getattr(self, name)
            out[name] = None if a is None else a.tolist()
        out["shapes"] = {name: list(getattr(self, name).shape) for name in self._STACKS
                         if getattr(self, name) is not None}
        inj = self.injection
        out["injection"] = None if inj is None else {
            "kind": "levant", "starts": list(inj.starts), "lengths": list(inj.lengths),
            "gains": [list(g) for g in inj.gains], "sigma_y": inj.sigma_y.tolist(),
            "sigma_u": inj.sigma_u.tolist(), "discretisation": inj.discretisation,
            "sigma_xi": None if inj.sigma_xi is None else np.asarray(inj.sigma_xi).tolist(),
        }
        if inj is not None and inj.profiles is not None:
            out["injection"]["profiles"] = [None if p is None else [float(x) for x in p] for p in inj.profiles]
        hi = self.held_input
        out["held_input"] = None if hi is None else {"A": hi.A.tolist(), "B": hi.B.tolist(), "M": hi.M.tolist()}
        return out

    @classmethod
    def from_dict(cls, data: Any) -> ObserverModel:
        """The model written by :meth:`to_dict` (shapes restored for empty stacks)."""
        if not isinstance(data, dict) or not str(data.get("format", "")).startswith("uio_ring observer model"):
            raise SimulationError("not a uio_ring observer model (no 'format: uio_ring observer model …')")
        shapes = data.get("shapes", {})

        def stack(name: str) -> Any:
            v = data.get(name)
            if v is None:
                return None
            return np.asarray(v, dtype=float).reshape(shapes.get(name, np.shape(v)))

        inj = data.get("injection")
        n_u = stack("G_u").shape[-1] if stack("G_u") is not None else 0
        injection = None if inj is None else LevantInjection(
            starts=tuple(inj["starts"]), lengths=tuple(inj["lengths"]),
            gains=tuple(tuple(g) for g in inj["gains"]), sigma_y=np.asarray(inj["sigma_y"], float),
            sigma_u=np.asarray(inj["sigma_u"], float).reshape(len(inj["starts"]), n_u),
            discretisation=inj["discretisation"],
            sigma_xi=None if inj.get("sigma_xi") is None else np.asarray(inj["sigma_xi"], float),
            profiles=None if inj.get("profiles") is None else tuple(
                None if p is None else (float(p[0]), float(p[1]), float(p[2])) for p in inj["profiles"]),
        )
        hi = data.get("held_input")
        held = None if hi is None else HeldInput(*(np.asarray(hi[k], float) for k in "ABM"))
        return cls(
            F=np.asarray(data["F"], float), G_y=stack("G_y"), X=stack("X"), G_u=stack("G_u"), D_y=stack("D_y"),
            D_u=stack("D_u"), W=stack("W"), h=data.get("h"), initial=np.asarray(data["initial"], float),
            injection=injection, held_input=held, interpolation=data.get("interpolation", "cubic"),
            guard_blocks=int(data.get("guard_blocks", 0)), z_of_x=stack("z_of_x"), method=data.get("method", ""),
        )

    def to_control(self) -> Any:
        """A python-control ``StateSpace`` of a linear, delay-free observer: input ``[y; u]``,
        output ``x̂`` (and ``ŵ`` below it when the model reconstructs w), state ``ξ``.

        Needs the optional dependency ``control`` (``pip install 'uio-ring[control]'``).

        Raises
        ------
        NotSupportedError
            For observers with delayed taps (no finite-dimensional state space) or with a
            nonlinear injection term (sliding-mode / differentiator observers).
        """
        from uio_ring.errors import NotSupportedError, require

        if self.injection is not None:
            raise NotSupportedError(f"to_control: the {self.method or 'observer'} model has a nonlinear "
                                    "injection term (it is not a linear system)")
        if not self.is_delay_free:
            raise NotSupportedError(f"to_control: the {self.method or 'observer'} model has delayed taps "
                                    f"(δ-degree {self.max_delay}); use to_dict() for its realisation")
        control = require("control", extra="control")

        def first(a: np.ndarray, rows: int, cols: int) -> np.ndarray:
            return a[0] if a.shape[0] else np.zeros((rows, cols))

        nz, ny, nu = self.n_z, self.n_y, self.n_u
        B = np.hstack([first(self.G_y, nz, ny), first(self.G_u, nz, nu)])
        Dz = np.hstack([first(self.D_y, nz, ny), first(self.D_u, nz, nu)])
        outs = [first(self.X, self.n_x, nz)] + ([first(self.W, self.n_w, nz)] if self.W is not None else [])
        C = np.vstack(outs)
        return control.ss(self.F, B, C, C @ Dz)

    def stepper(self, dt: Any, **options: Any) -> Any:
        """The discrete observer with step ``dt``: ``start``, ``step``, ``run``
        (see :class:`~uio_ring.numeric.stepper.ObserverStepper` for the options)."""
        from uio_ring.numeric.stepper import ObserverStepper

        return ObserverStepper(self, dt, **options)

    def __repr__(self) -> str:
        inj = "" if self.injection is None else f", injection={self.injection.discretisation}"
        h = "" if self.h is None else f", h={self.h:g}"
        return (f"ObserverModel({self.method or 'observer'}: n_z={self.n_z}, n_y={self.n_y}, n_u={self.n_u}, "
                f"n_x={self.n_x}, n_w={self.n_w}, lag={self.lag}{h}{inj})")
