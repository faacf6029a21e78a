"""The one simulation engine: any observer design on its plant (or another one).

``simulate_observer(design, plant)`` runs the plant with the one plant
integrator (:mod:`uio_ring.sim._blocks`; a delay-free plant is its δ-degree-0
case) and the design's float model (``design.numeric()``) with the one stepper
(:class:`~uio_ring.numeric.stepper.ObserverStepper`).  Nothing here knows which
method made the design.

>>> import numpy as np
>>> from uio_ring import DelaySystem, design_zheng_bejarano
>>> sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)
>>> des = design_zheng_bejarano(sys, poles=[-10])          # e' = −10 e
>>> r = simulate_observer(des, t_final=2.0, dt=1e-3, w=lambda t: np.sin(t), x0=[1.0, 0.0])
>>> bool(abs(r.error[0, -1] - np.exp(-20.0)) < 1e-12), r.w_hat is None
(True, True)
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from dataclasses import replace
from typing import Any

import numpy as np

from uio_ring.errors import DimensionError, NotSupportedError, SimulationError
from uio_ring.numeric.convert import coefficient_arrays
from uio_ring.numeric.grid import as_float, step_count
from uio_ring.numeric.progress import Progress, want_progress
from uio_ring.numeric.taps import delayed_sum
from uio_ring.numeric.threads import blas_single_thread
from uio_ring.sim._blocks import BlockIntegrator
from uio_ring.sim.accuracy import (
    RTOL,
    RTOL_INJECTION,
    AccuracyCheck,
    AccuracyWarning,
    check_accuracy,
    window_steps,
)
from uio_ring.sim.plant import SystemArrays, plant_run, resolve_h
from uio_ring.sim.result import SimulationResult
from uio_ring.sim.signals import as_noise, input_samples

__all__ = ["simulate_observer"]


def _grid_h(model: Any, sys: Any, h: Any, dt: float) -> float:
    """The basic delay of the run: the plant's, the model's, or ``h``; ``dt`` when both are delay-free."""
    sys_h = getattr(sys, "h", None)
    plant_delays = not getattr(sys, "is_delay_free", True)
    if model.h is None and not plant_delays:
        return dt if h is None and sys_h is None else resolve_h(h, sys_h, what="the plant")
    hv = resolve_h(h, sys_h if sys_h is not None else model.h, what="the plant")
    if model.h is not None:
        resolve_h(hv, model.h, what="the design: a design is simulated with the plant's h")
    return hv


def _check_sizes(model: Any, sys: Any) -> None:
    S = SystemArrays.from_system(sys)  # a DelaySystem, or coefficient stacks (e.g. perturbed_plant)
    n_x, n_y, n_u = S.n_x, S.n_y, S.n_u
    if (model.n_x, model.n_y) != (n_x, n_y):
        raise DimensionError(
            f"the design is for {model.n_x} states and {model.n_y} outputs; the plant has {n_x} and {n_y}"
        )
    if n_u and model.n_u != n_u:
        raise DimensionError(f"the plant has {n_u} known inputs; the design was made for {model.n_u}")


def simulate_observer(
    design: Any,
    plant: Any = None,
    *,
    t_final: Any,
    dt: Any,
    w: Any = None,
    u: Any = None,
    x0: Any = None,
    noise: Any = None,
    x_hat0: Any = None,
    seed: int | None = None,
    progress: bool | None = None,
    h: Any = None,
    feedback: Callable[[float, np.ndarray, np.ndarray | None], Any] | None = None,
    discretisation: str | None = None,
    exact_start: bool = False,
    phi: Callable[[float, np.ndarray], Any] | None = None,
    check: bool = True,
    kernel: str | None = None,
) -> SimulationResult:
    """Simulate the plant and the observer of ``design`` on it.

    Parameters
    ----------
    design : ObserverDesign
        Any design (its ``numeric()`` model is what runs).
    plant : DelaySystem, optional
        The plant (default ``design.system``; e.g. a perturbed one).
    t_final, dt : float
        Horizon and step; ``dt = h/N`` for a delay plant.  A delay-free plant needs no h.
    w, u : callable, array or None
        Unknown and known inputs: callables of t (vectorised or scalar), constant vectors,
        or samples ``(n, T)`` on the grid (zero before 0).  The observer reads u and its
        delays, as the plant does.
    x0 : array or callable, optional
        Initial state, or the history ``x(t), t ≤ 0`` as a callable (delay plants).  Default 0.
    noise : float, array or UniformNoise, optional
        Bounded output noise added to the measured y (the plant is unaffected).
    x_hat0 : array, optional
        Initial estimate (of ``[x; w]`` for designs that reconstruct w); default: observer
        state 0.
    seed : int, optional
        Seed of the noise when ``noise`` is an amplitude.
    progress : bool, optional
        Progress bar on stderr (default: only for long interactive runs).
    h : float, optional
        Basic delay when neither the plant nor the design has one.
    feedback : callable, optional
        ``feedback(t, x_hat, w_hat) -> u`` instead of ``u`` (closed loop; delay-free plants):
        u is held over each step, in the plant and in the observer.
    discretisation : str, optional
        Of the observer's injection terms: ``"implicit"`` (default), ``"explicit"``, ``"euler"``.
    exact_start : bool
        Start the plant earlier (w a callable or None) and give the observer the true past
        and its exact initial state (designs whose model has ``z_of_x``).
    phi : callable, optional
        ``phi(t, x) -> (n_x,)``: the plant is ``x' = A x + B w + E u + φ(t, x)`` (delay-free;
        integrated by :func:`uio_ring.sim.nonlinear.simulate_nonlinear`) and the observer
        copies ``φ(t, x̂)`` through its model's ``phi_map`` (e.g. the high-gain observer).
        Open loop only.
    check : bool
        A-posteriori accuracy check (open-loop runs with inputs given as callables or
        constants; :mod:`uio_ring.sim.accuracy`): the start of the run is repeated with
        ``dt/2``, without noise; when the two disagree the result has ``success=False``,
        its ``message`` says why and an :class:`~uio_ring.sim.accuracy.AccuracyWarning`
        is issued.  ``result.accuracy`` holds the figures (None when not checked).
    kernel : str, optional
        Backend of the observer's step loop when it has an injection term: ``"auto"``,
        ``"python"`` or ``"numba"`` (default: ``$UIO_RING_KERNEL``, else ``"auto"`` — numba
        when installed; :mod:`uio_ring.numeric.backend`).  The accuracy check uses the same.

    Returns
    -------
    SimulationResult
        ``t, x, y, w, u, x_hat, error = x − x_hat`` and ``w_hat`` (time on the last axis).
    """
    args = dict(t_final=t_final, dt=dt, w=w, u=u, x0=x0, noise=noise, x_hat0=x_hat0, seed=seed, progress=progress,
                h=h, feedback=feedback, discretisation=discretisation, exact_start=exact_start, phi=phi, kernel=kernel)
    result = _simulate(design, plant, **args)
    if not check or feedback is not None or np.ndim(w) == 2 or np.ndim(u) == 2:
        return result  # held inputs and sampled signals depend on the grid: no dt/2 run to compare with
    return _checked(result, design, plant, args)


def _checked(result: SimulationResult, design: Any, plant: Any, args: dict[str, Any]) -> SimulationResult:
    """``result`` with its :class:`~uio_ring.sim.accuracy.AccuracyCheck` (and flagged when it fails)."""
    steps = result.t.size - 1
    N = max(1, round(result.h / result.dt)) if result.h else 1
    window = window_steps(steps, N)
    quiet = {**args, "noise": None, "seed": None, "progress": False}

    def rerun(t_final: float, dt: float) -> SimulationResult:
        return _simulate(design, plant, **{**quiet, "t_final": t_final, "dt": dt})

    with np.errstate(all="ignore"):
        try:
            coarse = result if args["noise"] is None else rerun(window * result.dt, result.dt)
            rtol = RTOL if result.extra["model"].injection is None else RTOL_INJECTION
            chk = check_accuracy(coarse, rerun, dt=result.dt, steps=window, rtol=rtol)
        except SimulationError:  # the half-step run diverged
            chk = AccuracyCheck(estimate=float("inf"), scale=1.0, window=window * result.dt, dt=result.dt)
    extra = {**result.extra, "accuracy": chk}
    if chk.ok:
        return replace(result, extra=extra)
    warnings.warn(f"simulate_observer: {chk.reason}", AccuracyWarning, stacklevel=3)
    return replace(result, extra=extra, success=False, message=chk.reason)


def _simulate(design: Any, plant: Any, *, t_final: Any, dt: Any, w: Any, u: Any, x0: Any, noise: Any, x_hat0: Any,
              seed: int | None, progress: bool | None, h: Any, feedback: Any, discretisation: str | None,
              exact_start: bool, phi: Any, kernel: str | None = None) -> SimulationResult:
    sys = plant if plant is not None else getattr(design, "system", None)
    if sys is None:
        raise SimulationError("plant is required: the design has no system")
    dtv = as_float(dt, "dt")
    model = design.numeric(h=h if h is not None else getattr(sys, "h", None))
    _check_sizes(model, sys)
    hv = _grid_h(model, sys, h, dtv)
    stepper = model.stepper(dtv, discretisation=discretisation, kernel=kernel)
    stepper_dt = stepper.dt if model.h is not None else hv / round(hv / dtv)
    nz = as_noise(noise)
    if nz is not None and seed is not None:
        nz = type(nz)(nz.amplitude, seed=seed)
    if phi is not None:
        if feedback is not None or exact_start:
            raise NotSupportedError("phi: nonlinear plants are simulated open loop (no feedback, no exact_start)")
        from uio_ring.sim.nonlinear import simulate_nonlinear

        res = simulate_nonlinear(sys, phi, t_final=t_final, dt=stepper_dt, w=w, u=u, x0=x0, noise=nz)
        u_hist = None
        if model.n_u:
            u_hist = input_samples(u, model.n_u, j_min=-stepper.history_length, j_max=-1, n_steps=res.t.size - 1,
                                   dt=stepper_dt, name="u")
        traj = stepper.trajectories(res.y, res.u if model.n_u else None, x_hat0=x_hat0, u_history=u_hist, phi=phi)
        return _result(res, traj, stepper, model)
    if feedback is not None:
        if u is not None:
            raise SimulationError("give u or feedback, not both")
        if exact_start:
            raise SimulationError("exact_start is for open-loop runs (no feedback)")
        return _closed_loop(model, stepper, sys, t_final, stepper_dt, w, x0, nz, x_hat0, feedback)
    if exact_start:
        if x_hat0 is not None:
            raise SimulationError("give x_hat0 or exact_start=True, not both")
        return _warm(model, stepper, sys, hv, t_final, w, u, x0, nz, progress)
    steps = step_count(as_float(t_final, "t_final"), stepper_dt)
    observer_steps = steps if model.injection is not None else 0  # a linear model runs vectorised
    with Progress(steps + observer_steps, want_progress(progress, steps), "simulate") as bar:
        res = plant_run(sys, h=hv, t_final=t_final, dt=stepper_dt, w=w, u=u, x0=x0, noise=nz,
                        bar=bar.part(offset=0, scale=1))
        L = stepper.history_length
        u_hist = None
        if model.n_u:
            u_hist = input_samples(u, model.n_u, j_min=-L, j_max=-1, n_steps=res.t.size - 1, dt=stepper_dt,
                                   name="u")
        traj = stepper.trajectories(res.y, res.u if model.n_u else None, x_hat0=x_hat0, u_history=u_hist,
                                    progress=bar.part(offset=steps, scale=1))
    return _result(res, traj, stepper, model)


def _result(res: SimulationResult, traj: Any, stepper: Any, model: Any) -> SimulationResult:
    if not (np.all(np.isfinite(traj.x_hat)) and (traj.w_hat is None or np.all(np.isfinite(traj.w_hat)))):
        raise SimulationError(f"the observer diverged (dt = {stepper.dt:g}): its estimate is not finite")
    return SimulationResult(
        t=res.t, x=res.x, y=res.y, w=res.w, u=res.u, h=res.h, dt=res.dt,
        state_names=res.state_names, output_names=res.output_names,
        unknown_input_names=res.unknown_input_names, known_input_names=res.known_input_names, noise=res.noise,
        x_hat=traj.x_hat, error=res.x - traj.x_hat, w_hat=traj.w_hat, lag=model.lag,
        extra={"stepper": stepper, "model": model},
    )


def _closed_loop(model: Any, stepper: Any, sys: Any, t_final: Any, dt: float, w: Any, x0: Any, nz: Any,
                 x_hat0: Any, feedback: Callable[..., Any]) -> SimulationResult:
    """Plant and observer in lockstep with ``u = feedback(t, x̂, ŵ)`` held over each step."""
    if not sys.is_delay_free:
        raise NotSupportedError("feedback: closed-loop runs are implemented for delay-free plants")
    S = SystemArrays.from_system(sys)
    if S.n_u == 0:
        raise SimulationError("feedback: the plant has no known input u")
    if S.F.shape[0] and np.any(S.F):
        raise NotSupportedError("feedback with a known-input feed-through F ≠ 0 is an algebraic loop")
    A, C = (M[0] if M.shape[0] else np.zeros(M.shape[1:]) for M in (S.A, S.C))
    B, D, E = (M[0] if M.shape[0] else np.zeros(M.shape[1:]) for M in (S.B, S.D, S.E))
    n_steps = step_count(as_float(t_final, "t_final"), dt)
    t = np.arange(n_steps + 1) * dt
    W = input_samples(w, S.n_w, j_min=0, j_max=n_steps, n_steps=n_steps, dt=dt, name="w")
    integ = BlockIntegrator(A[None], 1, dt, method="dense")  # the plant integrator, one step a block
    BW = B @ W
    x = np.zeros(S.n_x) if x0 is None else np.asarray(x0(np.zeros(1)) if callable(x0) else x0, float).reshape(-1)
    if x.shape != (S.n_x,):
        raise DimensionError(f"x0 has shape {np.shape(x0)}; expected ({S.n_x},)")
    Nz = np.zeros((S.n_y, n_steps + 1)) if nz is None else nz.samples(S.n_y, n_steps + 1)
    X, Y, U = np.empty((S.n_x, n_steps + 1)), np.empty((S.n_y, n_steps + 1)), np.empty((S.n_u, n_steps + 1))
    XH = np.empty((model.n_x, n_steps + 1))
    WH = None if model.W is None else np.empty((model.n_w, n_steps + 1))

    def u_at(k: int, xh: np.ndarray) -> np.ndarray:
        v = np.asarray(feedback(t[k], xh, stepper.w_hat()), dtype=float).reshape(-1)
        if v.shape != (S.n_u,) or not np.all(np.isfinite(v)):
            raise SimulationError(f"feedback returned {v!r} at t = {t[k]:g}; expected {S.n_u} finite values")
        return v

    X[:, 0] = x
    Y[:, 0] = C @ x + D @ W[:, 0] + Nz[:, 0]
    with blas_single_thread():
        xh = stepper.start(Y[:, 0], np.zeros(S.n_u), x_hat0=x_hat0)
        for k in range(n_steps):
            XH[:, k] = xh
            if WH is not None:
                WH[:, k] = stepper.w_hat()
            uk = u_at(k, xh)
            U[:, k] = uk
            Eu = E @ uk
            x = integ.step_block(x[None, :], np.stack([BW[:, k] + Eu, BW[:, k + 1] + Eu]))[0]
            X[:, k + 1] = x
            Y[:, k + 1] = C @ x + D @ W[:, k + 1] + Nz[:, k + 1]
            xh = stepper.step(Y[:, k + 1], uk, held=True)
            if k % 1024 == 0 and not np.all(np.isfinite(xh)):
                raise SimulationError(f"the observer diverged near t = {t[k + 1]:g} (dt = {dt:g})")
        XH[:, n_steps] = xh
        if WH is not None:
            WH[:, n_steps] = stepper.w_hat()
        U[:, n_steps] = U[:, n_steps - 1] if n_steps else 0.0
    res = SimulationResult(
        t=t, x=X, y=Y, w=W, u=U, h=dt, dt=dt, state_names=sys.state_names, output_names=sys.output_names,
        unknown_input_names=sys.unknown_input_names, known_input_names=sys.known_input_names,
        noise=None if nz is None else Nz,
    )
    from uio_ring.numeric.stepper import ObserverTrajectories

    return _result(res, ObserverTrajectories(x_hat=XH, w_hat=WH, z=np.zeros((0, 0)), xi=np.zeros((0, 0))), stepper, model)


def shifted(f: Any, t0: float) -> Any:
    """The signal ``t ↦ f(t − t0)`` (None stays None): an input of a run that starts ``t0`` earlier.

    >>> float(shifted(lambda t: 2 * t, 1.0)(3.0)), shifted(None, 1.0)
    (4.0, None)
    """
    return None if f is None else (lambda t: f(np.asarray(t) - t0))


def warm_steps(model: Any, stepper: Any, c_degree: int, w: Any = None, u: Any = None) -> int:
    """Steps of the plant before t = 0 for ``exact_start`` (whole blocks of the observer's h): enough
    for ``ẑ(0) = z_of_x(δ) x(0)``, the observer's taps of y and u and the plant's output delays.
    Checks the run allows an exact start (``z_of_x`` known; w, u callables or None).

    >>> from uio_ring import DelaySystem, design_zheng_bejarano
    >>> des = design_zheng_bejarano(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None), poles=[-10])
    >>> m = des.numeric(); warm_steps(m, m.stepper(0.1), 0)     # delay-free: blocks of one step
    3
    """
    if model.z_of_x is None:
        raise NotSupportedError(f"exact_start: the {model.method} model does not say how z depends on x")
    if w is not None and not callable(w):
        raise SimulationError("w: exact_start=True needs w as a callable of t (or None)")
    if u is not None and not callable(u):
        raise SimulationError("u: exact_start=True needs u as a callable of t (or None)")
    N, L = stepper.N, stepper.history_length
    blocks = (model.z_of_x.shape[0] - 1) + stepper.Gy.shape[0] + stepper.Dy.shape[0] + c_degree + 1
    return max(blocks, -(-L // N) + 1, stepper.guard_blocks + 1) * N


def _warm(model: Any, stepper: Any, sys: Any, h: float, t_final: Any, w: Any, u: Any, x0: Any, nz: Any,
          progress: bool | None) -> SimulationResult:
    """Plant run from ``−t_warm``; the observer gets the true past and ``ẑ(0) = z_of_x(δ) x(0)``."""
    C = coefficient_arrays(sys.C, name="sys.C")
    s0 = warm_steps(model, stepper, max(C.shape[0] - 1, 0), w, u)
    N, L = stepper.N, stepper.history_length
    t_warm = s0 * stepper.dt
    shift = lambda f: shifted(f, t_warm)  # noqa: E731
    full = plant_run(sys, h=h, t_final=as_float(t_final, "t_final") + t_warm, dt=stepper.dt, w=shift(w),
                     u=shift(u), x0=x0, noise=nz, progress=progress)
    z0 = delayed_sum(model.z_of_x, full.x.T, 0, 0, N, s0)[0]
    sl = slice(s0, None)
    res = SimulationResult(
        t=full.t[sl] - t_warm, x=full.x[:, sl], y=full.y[:, sl], w=full.w[:, sl], u=full.u[:, sl],
        h=full.h, dt=full.dt, state_names=full.state_names, output_names=full.output_names,
        unknown_input_names=full.unknown_input_names, known_input_names=full.known_input_names,
        noise=None if full.noise is None else full.noise[:, sl],
    )
    exact = type(stepper)(stepper.model, stepper.dt, guard_blocks=0, kernel=stepper.kernel_option)  # break points before 0
    traj = exact.trajectories(res.y, res.u if model.n_u else None, z0=z0,
                              y_history=full.y[:, s0 - L : s0], u_history=full.u[:, s0 - L : s0] if model.n_u else None)
    return _result(res, traj, exact, model)
