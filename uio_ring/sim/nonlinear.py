"""A delay-free plant with a nonlinearity: ``x' = A x + B w + E u + φ(t, x)``, ``y = C x + D w + F u``.

``φ(t, x)`` is a Python callable of a float ``t`` and a state vector ``(n_x,)``
returning ``(n_x,)`` (the high-gain designs of Grip & Saberi (2010) are for such
plants).  The plant is integrated by the classical fourth-order Runge–Kutta
method on the grid ``t_j = j·dt``; inputs are sampled on the grid and taken at the
midpoints as the mean of their neighbours (second order in dt for smooth inputs).
:func:`uio_ring.sim.engine.simulate_observer` uses this when given ``phi=``.

>>> import numpy as np
>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0]]", [], "[[1]]", None)
>>> res = simulate_nonlinear(sys, lambda t, x: -x**3, t_final=1.0, dt=0.01, x0=[1.0])
>>> bool(abs(res.x[0, -1] - 1 / np.sqrt(3.0)) < 1e-9)     # x' = −x³: x = 1/√(1 + 2t)
True
"""

from __future__ import annotations

from typing import Any

import numpy as np

from uio_ring.numeric.grid import as_float, step_count
from uio_ring.numeric.nonlinearity import check_phi
from uio_ring.sim.errors import DimensionError, SimulationError
from uio_ring.sim.plant import SystemArrays
from uio_ring.sim.result import SimulationResult
from uio_ring.sim.signals import as_noise, input_samples

__all__ = ["simulate_nonlinear"]


def simulate_nonlinear(sys: Any, phi: Any, *, t_final: Any, dt: Any, w: Any = None, u: Any = None, x0: Any = None,
                       noise: Any = None) -> SimulationResult:
    """Simulate a delay-free plant with the nonlinearity ``phi`` (RK4 on the grid ``j·dt``).

    Parameters
    ----------
    sys : DelaySystem
        Delay-free (every matrix of δ-degree 0).
    phi : callable
        ``phi(t, x) -> (n_x,)``.
    t_final, dt, w, u, x0, noise
        As for :func:`uio_ring.sim.plant.simulate` (``x0`` a vector, or a callable of t
        of which only ``x(0)`` is used; default 0).

    Returns
    -------
    SimulationResult
        ``t, x, y, w, u`` on the grid (time on the last axis).
    """
    S = SystemArrays.from_system(sys)
    if any(M.shape[0] > 1 for M in (S.A, S.B, S.C, S.D, S.E, S.F)):
        raise SimulationError("phi: nonlinear plants are simulated for delay-free systems only")
    A, B, C, D, E, F = (M[0] if M.shape[0] else np.zeros(M.shape[1:]) for M in (S.A, S.B, S.C, S.D, S.E, S.F))
    f = check_phi(phi, S.n_x)
    dtv = as_float(dt, "dt")
    n = step_count(as_float(t_final, "t_final"), dtv)
    t = np.arange(n + 1) * dtv
    W = input_samples(w, S.n_w, j_min=0, j_max=n, n_steps=n, dt=dtv, name="w")
    U = input_samples(u, S.n_u, j_min=0, j_max=n, n_steps=n, dt=dtv, name="u")
    lin = B @ W + E @ U  # (n_x, n + 1)
    if callable(x0):  # a history x(t), t ≤ 0 (delay-free: only x(0) is used)
        x0 = x0(np.zeros(1))
    x = np.zeros(S.n_x) if x0 is None else np.asarray(x0, dtype=float).reshape(-1)
    if x.shape != (S.n_x,):
        raise DimensionError(f"x0 has shape {np.shape(x0)}; expected ({S.n_x},)")
    X = np.empty((S.n_x, n + 1))
    X[:, 0] = x
    for k in range(n):
        tk, g0, g1 = t[k], lin[:, k], lin[:, k + 1]
        gm = 0.5 * (g0 + g1)
        k1 = A @ x + g0 + f(tk, x)
        k2 = A @ (x + 0.5 * dtv * k1) + gm + f(tk + 0.5 * dtv, x + 0.5 * dtv * k1)
        k3 = A @ (x + 0.5 * dtv * k2) + gm + f(tk + 0.5 * dtv, x + 0.5 * dtv * k2)
        k4 = A @ (x + dtv * k3) + g1 + f(tk + dtv, x + dtv * k3)
        x = x + dtv / 6.0 * (k1 + 2 * k2 + 2 * k3 + k4)
        X[:, k + 1] = x
        if k % 1024 == 0 and not np.all(np.isfinite(x)):
            raise SimulationError(f"the plant diverged near t = {t[k + 1]:g}")
    nz = as_noise(noise)
    Nz = None if nz is None else nz.samples(S.n_y, n + 1)
    Y = C @ X + D @ W + F @ U + (0.0 if Nz is None else Nz)
    return SimulationResult(
        t=t, x=X, y=Y, w=W, u=U, h=dtv, dt=dtv, state_names=sys.state_names, output_names=sys.output_names,
        unknown_input_names=sys.unknown_input_names, known_input_names=sys.known_input_names, noise=Nz,
    )
