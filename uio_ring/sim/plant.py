"""Simulation of the plant ``x' = A(δ)x + B(δ)w + E(δ)u``, ``y = C(δ)x + D(δ)w + F(δ)u``."""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any

import numpy as np

from uio_ring.errors import DimensionError
from uio_ring.numeric.convert import coefficient_arrays
from uio_ring.numeric.grid import as_float, step_count, steps_per_delay
from uio_ring.numeric.history import sample_history
from uio_ring.numeric.progress import Progress, want_progress
from uio_ring.numeric.taps import delayed_sum
from uio_ring.numeric.threads import blas_single_thread
from uio_ring.sim._blocks import block_integrator
from uio_ring.sim.errors import SimulationError
from uio_ring.sim.result import SimulationResult
from uio_ring.sim.signals import as_noise, input_samples

__all__ = ["simulate", "resolve_h", "SystemArrays", "perturbed_plant"]


@dataclass(frozen=True)
class SystemArrays:
    """Float64 coefficient stacks ``(deg + 1, rows, cols)`` of a delay system."""

    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    D: np.ndarray
    E: np.ndarray
    F: np.ndarray
    n_x: int
    n_w: int
    n_u: int
    n_y: int

    @classmethod
    def from_system(cls, sys: Any) -> SystemArrays:
        mats = {}
        for name in "ABCDEF":
            M = getattr(sys, name, None)
            mats[name] = None if M is None else coefficient_arrays(M, name=f"sys.{name}")
        A, C = mats["A"], mats["C"]
        if A is None or C is None:
            raise SimulationError("sys needs the matrices A and C")
        n_x, n_y = A.shape[1], C.shape[1]
        if A.shape[2] != n_x or C.shape[2] != n_x:
            raise SimulationError(f"sys.A is {A.shape[1:]} and sys.C is {C.shape[1:]}: A must be square, C n_y × {n_x}")
        B = mats["B"] if mats["B"] is not None else np.zeros((0, n_x, 0))
        n_w = B.shape[2]
        D = mats["D"] if mats["D"] is not None else np.zeros((0, n_y, n_w))
        E = mats["E"] if mats["E"] is not None else np.zeros((0, n_x, 0))
        n_u = E.shape[2]
        F = mats["F"] if mats["F"] is not None else np.zeros((0, n_y, n_u))
        for name, M, shape in (("B", B, (n_x, n_w)), ("D", D, (n_y, n_w)), ("E", E, (n_x, n_u)), ("F", F, (n_y, n_u))):
            if M.shape[1:] != shape:
                raise SimulationError(f"sys.{name} is {M.shape[1]}×{M.shape[2]}; expected {shape[0]}×{shape[1]}")
        return cls(A, B, C, D, E, F, n_x, n_w, n_u, n_y)

    @staticmethod
    def deg(M: np.ndarray) -> int:
        """Delay degree of a coefficient stack (the same for a stack per plant, ``(K, deg + 1, ·, ·)``)."""
        return M.shape[-3] - 1

    @classmethod
    def stack(cls, plants: list[SystemArrays], *, label: str = "plant", reference: str = "the first plant",
              ref: SystemArrays | None = None) -> SystemArrays:
        """One plant per scenario: every matrix ``(K, deg + 1, rows, cols)``.  The plants must
        have the same sizes and the same delay degree of each matrix as ``ref`` (default the first;
        else DimensionError naming ``label`` k and ``reference``).

        >>> one = SystemArrays.from_system(type("P", (), {"A": [[[-1.0]]], "C": [[[1.0]]]}))
        >>> SystemArrays.stack([one, one]).A.shape
        (2, 1, 1, 1)
        """
        ref = plants[0] if ref is None else ref
        for k, p in enumerate(plants):
            for name in "ABCDEF":
                got, want = getattr(p, name).shape, getattr(ref, name).shape
                if got != want:
                    raise DimensionError(
                        f"{label} {k}: the plant's {name} has {got[0]} delay coefficients of size {got[1]}×{got[2]}; "
                        f"{reference} has {want[0]} of {want[1]}×{want[2]}: every plant of a batch needs the same "
                        "sizes and delays")
        A, B, C, D, E, F = (np.stack([getattr(p, name) for p in plants]) for name in "ABCDEF")
        return cls(A, B, C, D, E, F, ref.n_x, ref.n_w, ref.n_u, ref.n_y)

    @property
    def state_delay(self) -> int:
        """Largest delay multiple of x needed: ``max(deg A, deg C, 0)``."""
        return max(self.deg(self.A), self.deg(self.C), 0)

    @property
    def input_delay(self) -> int:
        return max(self.deg(self.B), self.deg(self.D), self.deg(self.E), self.deg(self.F), 0)


def perturbed_plant(system: Any, eps: float, seed: int) -> Any:
    """``system`` with every coefficient matrix ``M ∘ (1 + ε R)``, ``R`` uniform in [−1, 1]
    (seeded by ``seed``; zeros stay zero): a plant for :func:`simulate`,
    :func:`~uio_ring.sim.engine.simulate_observer` and ``Scenario(plant=…)`` of
    :func:`~uio_ring.sim.batch.simulate_batch` (same sizes, delay degrees and h).
    ``eps = 0`` returns ``system`` itself.

    >>> from uio_ring import DelaySystem
    >>> sys = DelaySystem("[[-1, d], [0, -2]]", "[[1], [0]]", "[[1, 0]]", None, h="1/10")
    >>> p = perturbed_plant(sys, 0.1, seed=3)
    >>> p.A.shape, bool(p.A[1, 1, 0] == 0), bool(abs(p.A[0, 0, 0] + 1) <= 0.1), p.h == sys.h
    ((2, 2, 2), True, True, True)
    """
    if eps == 0:
        return system
    S = SystemArrays.from_system(system)
    rng = np.random.default_rng([seed, 7919])
    mats = {name: getattr(S, name) * (1.0 + eps * rng.uniform(-1.0, 1.0, size=getattr(S, name).shape))
            for name in "ABCDEF"}
    return SimpleNamespace(**mats, h=system.h, is_delay_free=system.is_delay_free,
                           state_names=system.state_names, output_names=system.output_names,
                           unknown_input_names=system.unknown_input_names,
                           known_input_names=system.known_input_names)


def resolve_h(h: Any, sys_h: Any, *, what: str = "the system") -> float:
    """The basic delay to use: ``h`` if given (it must agree with ``sys_h`` if that is set)."""
    if h is None and sys_h is None:
        raise SimulationError(f"h is required: {what} has no h")
    hv = as_float(sys_h if h is None else h, "h")
    if sys_h is not None and h is not None:
        hs = as_float(sys_h, "sys.h")
        if abs(hs - hv) > 1e-12 * hs:
            raise SimulationError(f"h={h} differs from the h={sys_h} of {what}")
    return hv


class _BlockSteps:
    """Adapts the integrator's block count to steps for a progress updater."""

    def __init__(self, bar: Any, N: int):
        self.bar, self.N = bar, N

    def update(self, k: int) -> None:
        self.bar.update(k * self.N)


def plant_run(
    sys: Any,
    *,
    h: Any,
    t_final: Any,
    dt: Any,
    w: Any = None,
    u: Any = None,
    x0: Any = None,
    noise: Any = None,
    progress: bool | None = None,
    bar: Any = None,
) -> SimulationResult:
    """:func:`simulate` without its docstring (shared with :func:`simulate_observer`);
    ``bar``: an updater ``bar.update(steps done)`` of an enclosing progress bar."""
    with blas_single_thread():
        return _plant_run(sys, h=h, t_final=t_final, dt=dt, w=w, u=u, x0=x0, noise=noise, progress=progress,
                          bar=bar)


def _plant_run(sys: Any, *, h: Any, t_final: Any, dt: Any, w: Any, u: Any, x0: Any, noise: Any,
               progress: bool | None, bar: Any = None) -> SimulationResult:
    S = SystemArrays.from_system(sys)
    hv = resolve_h(h, getattr(sys, "h", None), what="sys")
    dtv = as_float(dt, "dt")
    N = steps_per_delay(hv, dtv)
    dtv = hv / N
    tf = as_float(t_final, "t_final")
    n_steps = step_count(tf, dtv)
    nblocks = -(-n_steps // N)
    J = nblocks * N  # last simulated grid index (≥ n_steps)

    KA = max(S.deg(S.A), 0)
    Kx = S.state_delay
    Kh = Kx  # x history length in blocks
    Kin = S.input_delay
    hist = sample_history(x0, S.n_x, N=N, k=Kx, dt=dtv, name="x0")
    # X rows: x(t_j) = X[Kh N + j], j = −Kh N … J
    X = np.empty((Kh * N + J + 1, S.n_x))
    X[: Kh * N + 1] = hist.T
    W = input_samples(w, S.n_w, j_min=-Kin * N, j_max=J, n_steps=n_steps, dt=dtv, name="w").T
    U = input_samples(u, S.n_u, j_min=-Kin * N, j_max=J, n_steps=n_steps, dt=dtv, name="u").T
    off_in = Kin * N
    fin = delayed_sum(S.B, W, 0, J, N, off_in) + delayed_sum(S.E, U, 0, J, N, off_in)

    # arrays start at 0 (zero before): B_i w(t − i h) jumps at t = i h, the right end of
    # block i − 1, where that block needs the left limit (0), not w(0)
    end_fix = np.zeros((nblocks, S.n_x))
    for M, sig, arr in ((S.B, w, W), (S.E, u, U)):
        if sig is not None and not callable(sig) and arr.shape[1] and off_in > 0:
            jump = arr[off_in] - arr[off_in - 1]  # w(0) − w(0⁻): 0 for a constant vector
            for i in range(1, min(M.shape[0], nblocks + 1)):
                end_fix[i - 1] -= M[i] @ jump
    integ = block_integrator(S.A, N, dtv)
    show = want_progress(progress, J)
    # the integrator wants exactly KA blocks of history before 0
    base = (Kh - KA) * N
    fix = end_fix if np.any(end_fix) else None
    if bar is not None:  # a stage of the caller's bar, counted in steps
        integ.run(X[base:], fin, nblocks, _BlockSteps(bar, N), end_fix=fix)
    else:
        with Progress(J, show, "plant") as own:
            integ.run(X[base:], fin, nblocks, _BlockSteps(own, N), end_fix=fix)

    off_x = Kh * N
    Y = (
        delayed_sum(S.C, X, 0, n_steps, N, off_x)
        + delayed_sum(S.D, W, 0, n_steps, N, off_in)
        + delayed_sum(S.F, U, 0, n_steps, N, off_in)
    )
    y_clean = Y.T
    nz = as_noise(noise)
    nu = nz.samples(S.n_y, n_steps + 1) if nz is not None else None
    y = y_clean + nu if nu is not None else y_clean.copy()
    t = np.arange(n_steps + 1) * dtv
    if nu is not None and not np.all(np.isfinite(y)):
        raise SimulationError("noise: the noisy output is not finite")
    if not np.all(np.isfinite(X[off_x : off_x + n_steps + 1])):
        msg = "the state left the float64 range (unstable plant over a long horizon?)"
        raise SimulationError(msg)
    return SimulationResult(
        t=t,
        x=X[off_x : off_x + n_steps + 1].T.copy(),
        y=y,
        w=W[off_in : off_in + n_steps + 1].T.copy(),
        u=U[off_in : off_in + n_steps + 1].T.copy(),
        h=hv,
        dt=dtv,
        state_names=tuple(getattr(sys, "state_names", None) or ()),
        output_names=tuple(getattr(sys, "output_names", None) or ()),
        unknown_input_names=tuple(getattr(sys, "unknown_input_names", None) or ()),
        known_input_names=tuple(getattr(sys, "known_input_names", None) or ()),
        noise=nu,
    )


def simulate(
    sys: Any,
    *,
    h: Any = None,
    t_final: Any,
    dt: Any,
    w: Any = None,
    u: Any = None,
    x0: Any = None,
    noise: Any = None,
    progress: bool | None = None,
) -> SimulationResult:
    """Simulate ``x' = A(δ)x + B(δ)w + E(δ)u``, ``y = C(δ)x + D(δ)w + F(δ)u``, ``δx(t) = x(t − h)``.

    Parameters
    ----------
    sys : DelaySystem
        Anything with the polynomial matrices ``A, B, C, D, E, F`` (E, F may be absent).
    h : float, Fraction or str, optional
        Basic delay; defaults to ``sys.h``; must agree with it when both are set.
    t_final : float
        Horizon; the grid is ``t_j = j·dt``, ``j = 0 … ceil(t_final/dt)``.
    dt : float
        Step; ``dt = h/N`` for a positive integer N (else :class:`SimulationError`
        naming the N that fit).  Delays are exact grid shifts.
    w, u : callable, array or None
        Unknown / known inputs: callables of t (vectorised, returning ``(n, len(t))``,
        or scalar), constant vectors, or samples ``(n, T)`` on the grid (zero before 0).
    x0 : callable, array or None
        Initial state, or the history of x on ``[−k h, 0]``, ``k = max(deg A, deg C)``: a
        callable of t, a constant vector, or ``(n_x, k N + 1)`` samples.  None: zero.
    noise : float, array or UniformNoise, optional
        Output noise, uniform in ``[−a, a]``, seeded (``UniformNoise(a, seed=…)``).
    progress : bool, optional
        Progress bar on stderr; by default only for long interactive runs.

    Returns
    -------
    SimulationResult
        ``t, x, y, w, u`` (time on the last axis), labels, ``.plot()``.

    Algorithm
    ---------
    Exponential integrator on blocks of length h (:mod:`uio_ring.sim._blocks`):
    ``x_{j+1} = e^{A_0 dt} x_j + Σ_m W_m f_{j+q_m}`` with the delayed terms and the inputs
    as known forcing ``f``, interpolated by four-point Lagrange stencils inside each
    block.  Global error O(dt⁴) for smooth inputs (tested against the method of steps).

    Examples
    --------
    >>> import numpy as np
    >>> class Scalar:  # x' = -x(t - h), constant history 1
    ...     A = np.array([[[0.0]], [[-1.0]]]); C = np.array([[[1.0]]]); h = None
    >>> r = simulate(Scalar(), h=1.0, t_final=2.0, dt=0.25, x0=[1.0])
    >>> abs(round(float(r.x[0, 4]), 12)), round(float(r.x[0, -1]), 6)   # x(1) = 1 − 1 = 0, x(2) = −1/2
    (0.0, -0.5)
    """
    return plant_run(sys, h=h, t_final=t_final, dt=dt, w=w, u=u, x0=x0, noise=noise, progress=progress)
