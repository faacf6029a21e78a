"""Many scenarios of one design in one vectorised run: ``simulate_batch``.

K scenarios (each with its own initial state or history, unknown input w, known
input u, output noise and seed, initial estimate, and optionally its own plant)
share the observer, so every product of the plant integrator
(:class:`~uio_ring.sim._blocks.BlockIntegrator`: time-major, one ``(K, n) @ (n, n)``
product per step, ``run_rows``; blocks of at most 16 steps by grouped block maps) and
every step of the observer has K rows.  With one plant per scenario (``Scenario(plant=…)``: perturbed
matrices of the same sizes, delay degrees and h), the plant's block maps are stacked
(:class:`~uio_ring.sim._blocks.StackedBlockIntegrator`: one matrix exponential and
φ-function table per plant, one batched product ``X[k] @ M[k]`` per block over the K
plants) and the output and input products are batched the same way; the observer is
the same for all.  For the observer: a linear observer is one linear recursion for all K columns
at once; an observer with a Levant injection term is one loop over the steps whose
body (the implicit chain equations included) works on all K scenarios together.

The horizon is cut into segments of whole delay blocks; the plant, the output and
the observer carry only the tails they read (the delays, the stencils) from one
segment to the next, so memory stays bounded for long horizons.  Error metrics are
accumulated on the fly; full trajectories are kept only with ``trajectories=True``.
The numbers are those of :func:`~uio_ring.sim.engine.simulate_observer` run once per
scenario, ``exact_start`` and closed loops (``feedback``, :mod:`uio_ring.sim.batch_loop`)
included, up to rounding: ~1e-14 relative in x and y, ≲ 1e-12 in x̂ (which reads
differences of y).  Plants of different true delays (``Scenario(plant_h=…)``) are
integrated in groups, one per delay (its own block length), for the one observer.

>>> import numpy as np
>>> from uio_ring import DelaySystem, design_zheng_bejarano
>>> sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None)
>>> des = design_zheng_bejarano(sys, poles=[-10])          # e' = −10 e
>>> runs = [Scenario(x0=[1.0, 0.0]), Scenario(x0=[0.0, 2.0], w=lambda t: np.sin(t))]
>>> res = simulate_batch(des, runs, t_final=2.0, dt=1e-3, tol=1e-3)
>>> np.round(res.metrics["t_converge"], 3).tolist()        # e^{−10 t} ≤ 1e-3 from t = 0.691
[0.691, 0.0]
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from uio_ring.errors import DimensionError, SimulationError
from uio_ring.numeric.backend import resolve_kernel
from uio_ring.numeric.expint import LinearScan
from uio_ring.numeric.grid import as_float, step_count, steps_per_delay
from uio_ring.numeric.history import sample_history, sample_signal
from uio_ring.numeric.progress import Progress, want_progress
from uio_ring.numeric.threads import batch_threads, blas_single_thread
from uio_ring.sim._blocks import StackedBlockIntegrator, block_integrator, scan_rows, tap_rows
from uio_ring.sim.engine import shifted, warm_steps
from uio_ring.sim.plant import SystemArrays
from uio_ring.sim.signals import UniformNoise, as_noise, input_samples

__all__ = ["Scenario", "BatchResult", "Segment", "simulate_batch", "METRICS"]

#: Input samples evaluated per call of a scenario's signal (values, all scenarios together).
INPUT_WINDOW = 1 << 21

#: Per-scenario metrics of :func:`simulate_batch`; ``e(t) = ‖x(t) − x̂(t)‖_∞``.
METRICS = {
    "t_converge": "first grid time after which e(t) ≤ tol up to t_final (NaN: not converged)",
    "max_after": "max of e(t) for t ≥ t_converge",
    "rms_after": "RMS of e(t) for t ≥ t_converge",
    "peak": "max of e(t) over the run",
    "t_peak": "time of the peak",
    "final": "e(t_final)",
    "max_settled": "max of e(t) for t ≥ settle (a bias that does not decay shows here)",
    "rms_settled": "RMS of e(t) for t ≥ settle",
    "t_diverge": "first time e(t) > diverge or not finite (NaN: never)",
}


@dataclass(frozen=True, eq=False)
class Segment:
    """Consecutive samples of a batch run (``on_segment``): ``t`` ``(S,)`` and time-major
    arrays ``(S, K, ·)`` of the plant (``x, y, w, u``) and the observer (``x_hat``, ``w_hat``
    or None).  Segments follow each other without overlap and cover ``t = 0 … t_final``."""

    t: np.ndarray
    x: np.ndarray
    y: np.ndarray
    w: np.ndarray
    u: np.ndarray
    x_hat: np.ndarray
    w_hat: np.ndarray | None


@dataclass(frozen=True)
class Scenario:
    """One run of a batch: the arguments of :func:`~uio_ring.sim.engine.simulate_observer`
    that may differ between runs.

    ``x0`` (vector, callable history or samples), ``w``, ``u`` (callables of t, constant
    vectors or samples on the grid), ``noise`` (output-noise amplitude, a number or one
    per output; uniform, seeded with ``seed``, default 0), ``x_hat0`` (initial estimate),
    ``plant`` (this run's plant, e.g. a perturbed one; default: the batch's plant),
    ``plant_h`` (this run's true delay; default: the batch's ``plant_h``).
    """

    x0: Any = None
    w: Any = None
    u: Any = None
    noise: Any = None
    seed: int | None = None
    x_hat0: Any = None
    plant: Any = None
    plant_h: Any = None

    def noise_model(self) -> UniformNoise | None:
        nz = as_noise(self.noise)
        if nz is not None and self.seed is not None:
            nz = UniformNoise(nz.amplitude, seed=self.seed)
        return nz


@dataclass(frozen=True, eq=False)
class BatchResult:
    """What :func:`simulate_batch` returns.

    Attributes
    ----------
    metrics : dict of (K,) arrays — see :data:`METRICS`
    t : (T,) grid times (made when asked: a long run keeps only ``dt`` and ``n_steps``)
    x, y, x_hat, error : (K, n, T) arrays, or None unless ``trajectories=True``
    w_hat : (K, n_w, T) array or None (models that reconstruct w, with trajectories)
    tol, diverge : the thresholds of the metrics
    """

    metrics: dict[str, np.ndarray]
    dt: float
    n_steps: int
    tol: float
    diverge: float
    x: np.ndarray | None = None
    y: np.ndarray | None = None
    x_hat: np.ndarray | None = None
    w_hat: np.ndarray | None = None
    extra: dict = field(default_factory=dict)

    @property
    def t(self) -> np.ndarray:
        return np.arange(self.n_steps + 1) * self.dt

    @property
    def error(self) -> np.ndarray | None:
        return None if self.x is None or self.x_hat is None else self.x - self.x_hat

    @property
    def K(self) -> int:
        return int(self.metrics["peak"].shape[0])

    def rows(self) -> list[dict[str, float]]:
        """One dict of metrics per scenario."""
        return [{k: float(v[i]) for k, v in self.metrics.items()} for i in range(self.K)]

    def __repr__(self) -> str:
        conv = int(np.sum(np.isfinite(self.metrics["t_converge"])))
        return (f"<BatchResult: {self.K} scenarios, t = 0…{self.n_steps * self.dt:g} ({self.n_steps + 1} samples), "
                f"{conv} converged to {self.tol:g}>")


# ---------------------------------------------------------------------------------- kernels
def _bsum(M: np.ndarray, S: np.ndarray, j0: int, j1: int, N: int, offset: int, kernel: str = "python") -> np.ndarray:
    """``Σ_i M_i s(t_j − i h)`` for ``j = j0 … j1`` and every scenario: ``(j1 − j0 + 1, K, rows)``.

    Time-major: ``S`` has shape ``(rows_S, K, cols)`` with ``S[offset + j] = s(t_j)``; ``M`` is
    ``(deg + 1, rows, cols)``, or ``(K, deg + 1, rows, cols)`` for one plant per scenario.  The
    delayed windows are laid side by side and multiplied by the stacked ``M_iᵀ`` in one
    product (one pass over the output instead of one per delay).  One matrix stack: :func:`tap_rows`
    (``kernel="numba"``: one compiled pass).
    Precondition: every index is inside S, S C-contiguous (not checked).
    """
    L, K = j1 - j0 + 1, S.shape[1]
    per = M.ndim == 4  # one coefficient stack per scenario: (K, deg + 1, rows, cols)
    Mi = M.transpose(1, 0, 2, 3) if per else M  # coefficient i first
    idx = [i for i in range(Mi.shape[0]) if np.any(Mi[i])]
    if not idx:
        return np.zeros((L, K, M.shape[-2]))
    if not per:
        return tap_rows(S, [offset + j0 - i * N for i in idx], [M[i].T for i in idx], L, kernel)
    wins = [S[offset + j0 - i * N : offset + j0 - i * N + L] for i in idx]
    # time-major (L, K, Σ cols) times (K, Σ cols, rows), one matrix per scenario
    stacked = wins[0] if len(wins) == 1 else np.concatenate(wins, axis=2)
    Mst = np.concatenate([M[:, i].transpose(0, 2, 1) for i in idx], axis=1)
    return np.einsum("lkc,kcr->lkr", stacked, Mst, optimize=True)  # (measured: ~10× a transposed matmul)


def _scan_k(scan: LinearScan, x0: np.ndarray, g: np.ndarray) -> np.ndarray:
    """:meth:`LinearScan.run` for K columns: ``x0`` ``(K, n)``, ``g`` ``(K, M, n)`` → ``(K, M, n)``."""
    K, M, n = g.shape
    m = scan.m
    if M <= 2 * m:
        out = np.empty((K, M, n))
        x, PhiT = x0, scan.Phi.T
        for j in range(M):
            x = x @ PhiT + g[:, j]
            out[:, j] = x
        return out
    C = -(-M // m)
    gp = np.zeros((K, C * m, n))
    gp[:, :M] = g
    Yp = (gp.reshape(K * C, m * n) @ scan.TT).reshape(K, C, m, n)
    starts = np.empty((K, C, n))
    starts[:, 0] = x0
    if C > 1:
        starts[:, 1:] = _scan_k(scan._outer(), x0, Yp[:, :-1, -1])
    X = (starts.reshape(K * C, n) @ scan.Pstack).reshape(K, C, m, n)
    X += Yp
    return X.reshape(K, C * m, n)[:, :M]


def solve_chains(a: np.ndarray, coef: Sequence[float], s0: float, mu: int) -> tuple[np.ndarray, np.ndarray]:
    """:func:`~uio_ring.numeric.stepper.solve_chain` for a vector of right-hand sides ``a``.

    The same Newton iteration, entry by entry, on the entries outside the sign's
    set-valued band only, dropping each entry as soon as its iteration stops.
    Precondition: ``coef ≥ 0``, ``s0 > 0`` (not checked).

    >>> sig, sg = solve_chains(np.array([0.5, 3.0, -3.0]), [], 1.0, 1)
    >>> sig.tolist(), sg.tolist()
    ([0.0, 2.0, -2.0], [0.5, 1.0, -1.0])
    """
    absa = np.abs(a)
    out = np.flatnonzero(absa > s0)
    sg = a / s0
    sig = np.zeros_like(a)
    if out.size == 0:
        return sig, sg
    ao = a[out]
    sg[out] = np.sign(ao)
    c = absa[out] - s0
    if mu == 1:
        sig[out] = np.copysign(c, ao)
        return sig, sg
    s = c ** (1.0 / mu)
    act = np.ones(s.size, dtype=bool)
    f, df = np.empty_like(s), np.empty_like(s)
    for _ in range(100):
        f.fill(1.0)
        df.fill(0.0)
        for ck in coef:  # Horner: f(s) = s^μ + Σ coef_k s^{μ−k} − c
            df *= s
            df += f
            f *= s
            f += ck
        df *= s
        df += f
        f *= s
        f -= c
        act &= (f > 0.0) & (df > 0.0)  # the others stop where they are
        if not act.any():
            break
        s_new = s - np.divide(f, df, out=np.zeros_like(f), where=act)
        done = act & ((s_new >= s) | (s - s_new <= 1e-15 * s))
        s = np.where(done, np.maximum(s_new, 0.0), np.where(act, s_new, s))
        act &= ~done
    sig[out] = np.copysign(s**mu, ao)
    return sig, sg


#: Below this many scenarios, the implicit chain equations are solved row by row with the
#: scalar solver (each vectorised Newton step costs a few µs of numpy overhead whatever K is).
SCALAR_CHAINS_BELOW = 24  # measured crossover (bench: aircraft, K = 2 … 32)


class _BatchInjection:
    """The stepper's injection tables applied to K rows at once."""

    def __init__(self, inj: Any):
        self.inj = inj
        self.bihom = any(b is not None for b in inj.bihom)  # such chains: the stepper's scalar step, row by row
        self.KlT = inj.Kl.T.copy()
        self.RT = inj.R.T.copy()  # σ = meas + R ξ (R = sigma_xi − the chains' first states)

    def measured(self, Y: np.ndarray, U: np.ndarray) -> np.ndarray:
        out = Y @ self.inj.Sy.T
        return out + U @ self.inj.Su.T if self.inj.Su.shape[1] else out

    def l_of(self, sigma: np.ndarray) -> np.ndarray:
        inj = self.inj
        if self.bihom:
            return np.stack([inj.l_of(row) for row in sigma]) if sigma.shape[0] else np.zeros((0, inj.n))
        out = np.zeros((sigma.shape[0], inj.n))
        for j, (s, m) in enumerate(zip(inj.starts, inj.mu, strict=True)):
            sj = sigma[:, j : j + 1]
            out[:, s : s + m] = inj.kappa[j] * np.abs(sj) ** inj.exponents[j] * np.sign(sj)
        return out

    def implicit(self, lin: np.ndarray, meas_next: np.ndarray) -> np.ndarray:
        inj = self.inj
        if lin.shape[0] < SCALAR_CHAINS_BELOW or self.bihom:  # few rows: the scalar solver costs less per row
            return np.stack([inj.implicit(lin[k], meas_next[k]) for k in range(lin.shape[0])])
        lvec = np.zeros_like(lin)
        base = meas_next + lin @ self.RT  # σ with no injection at all
        for j, (s, m) in enumerate(zip(inj.starts, inj.mu, strict=True)):
            a = base[:, j]
            if j:
                a = a + lvec @ inj.RK[j]  # earlier chains only (later entries are still 0)
            kap, ex = inj.kap[j], inj.exp[j]
            if m == 2:  # super-twisting: the stepper's closed form, s = |σ|^½ from s² + c1 s = |a| − s0
                c1, s0 = inj.coef[j][0], inj.s0[j]
                excess = np.abs(a) - s0
                sliding = excess <= 0.0
                sr = np.where(sliding, 0.0, (-c1 + np.sqrt(c1 * c1 + 4.0 * np.maximum(excess, 0.0))) / 2.0)
                sgn = np.sign(a)
                lvec[:, s] = kap[0] * sr * sgn
                lvec[:, s + 1] = kap[1] * np.where(sliding, a / s0, sgn)
                continue
            sig, sg = solve_chains(a, inj.coef[j], inj.s0[j], m)
            mag, sgn = np.abs(sig), np.sign(sig)
            for k in range(m - 1):
                lvec[:, s + k] = kap[k] * mag ** ex[k] * sgn
            lvec[:, s + m - 1] = kap[m - 1] * sg
        return lin + lvec @ self.KlT


# ---------------------------------------------------------------------------------- plant
class _BatchPlant:
    """The plant for K scenarios, one segment of whole blocks at a time."""

    def __init__(self, S: SystemArrays, h: float, dt: float, n_steps: int, scenarios: Sequence[Scenario],
                 kernel: str = "python"):
        self.S, self.h = S, h
        self.kernel = kernel  # "numba": the linear loops compiled (uio_ring.numeric.linear_kernel)
        self.N = N = steps_per_delay(h, dt)
        self.dt = dt
        self.n_steps = n_steps
        self.scen = scenarios
        self.KA, self.Kx, self.Kin = max(S.deg(S.A), 0), S.state_delay, S.input_delay
        self.integ = block_integrator(S.A, N, dt)
        hist = [sample_history(sc.x0, S.n_x, N=N, k=self.Kx, dt=dt, name="x0").T for sc in scenarios]
        self.Xtail = np.stack(hist, axis=1)  # rows j = b0 N − Kx N … b0 N, time-major (rows, K, n)
        #: time-major block integration (:meth:`~uio_ring.sim._blocks.BlockIntegrator.run_rows`): one
        #: plant and blocks of more than SUPER_MAX_N steps (else the grouped block maps of ``run``)
        self.rows = not isinstance(self.integ, StackedBlockIntegrator) and self.integ.method != "super"
        #: numba and the time-major steps: the segments scenario-innermost (:mod:`uio_ring.sim.batch_plant_k`;
        #: not the grouped block maps of N ≤ 16, whose rounding simulate_observer shares: a sliding-mode
        #: observer amplifies the last-bit differences of a step-by-step plant)
        self.pairs = None
        if self.rows and kernel == "numba":
            from uio_ring.numeric.scenario_kernel import tap_pairs
            from uio_ring.sim.batch_linear import row_form

            self.pairs = {name: tap_pairs(row_form(M)) if M.shape[0] else None
                          for name, M in (("B", S.B), ("E", S.E), ("C", S.C), ("D", S.D), ("F", S.F))}
        self.b0 = 0
        self.noise = [sc.noise_model() for sc in scenarios]
        self._cache: dict[str, tuple[int, int, np.ndarray]] = {}
        # array inputs jump at 0 (zero before): the left limit at the right end of blocks i − 1
        Kin = self.Kin
        self.end_fix = np.zeros((len(scenarios), max(Kin, 1), S.n_x))
        off = Kin * N
        if off > 0:
            for k, sc in enumerate(scenarios):
                for M, sig, n, name in ((S.B, sc.w, S.n_w, "w"), (S.E, sc.u, S.n_u, "u")):
                    if sig is None or callable(sig) or n == 0:
                        continue
                    arr = input_samples(sig, n, j_min=-1, j_max=0, n_steps=n_steps, dt=dt, name=name)
                    jump = arr[:, 1] - arr[:, 0]
                    Mk = M[k] if M.ndim == 4 else M
                    for i in range(1, Mk.shape[0]):
                        self.end_fix[k, i - 1] -= Mk[i] @ jump

    def _inputs(self, which: str, n: int, j_min: int, j_max: int) -> np.ndarray:
        """Samples at ``j_min … j_max``, time-major ``(rows, K, n)`` (a view of scenario-innermost
        ``(rows, n, K)`` samples for the compiled segments: :meth:`_inputs_k`); sampled in windows of
        at least ~2²¹ values (one call of each scenario's signal per window, not per segment)."""
        cache = self._cache.get(which)
        if cache is None or j_min < cache[0] or j_max > cache[1]:
            K = len(self.scen)
            # (not past the last block: a short run samples its horizon only)
            hi = max(j_max, min(j_min + INPUT_WINDOW // max(K * n, 1), self.n_steps + self.N))
            arr = np.empty((hi - j_min + 1, n, K)) if self.pairs is not None else np.empty((hi - j_min + 1, K, n))
            view = arr.transpose(0, 2, 1) if self.pairs is not None else arr
            t = np.arange(j_min, hi + 1) * self.dt  # (as input_samples: one time grid for every callable)
            for k, sc in enumerate(self.scen):
                sig = getattr(sc, which)
                view[:, k] = (sample_signal(sig, t, n, which) if callable(sig) and n else
                              input_samples(sig, n, j_min=j_min, j_max=hi, n_steps=self.n_steps, dt=self.dt,
                                            name=which)).T
            cache = self._cache[which] = (j_min, hi, view)
        return cache[2][j_min - cache[0] : j_max - cache[0] + 1]

    def _inputs_k(self, which: str, n: int, j_min: int, j_max: int) -> np.ndarray:
        """:meth:`_inputs` scenario-innermost ``(rows, n, K)``, contiguous (no copy)."""
        return self._inputs(which, n, j_min, j_max).transpose(0, 2, 1)

    def _noise(self, n_y: int, j0: int, j1: int) -> np.ndarray | None:
        if all(nz is None for nz in self.noise):
            return None
        m, T = j1 - j0 + 1, self.n_steps + 1
        out = np.zeros((m, len(self.scen), n_y))
        for k, nz in enumerate(self.noise):
            if nz is None:
                continue
            amp = nz.bound(n_y)
            if np.any(~np.isfinite(amp)) or np.any(amp < 0):
                raise SimulationError(f"noise amplitude {nz.amplitude!r} must be finite and ≥ 0")
            for i in range(n_y):  # the stream of UniformNoise.samples(n_y, T), row i, columns j0 … j1
                bg = np.random.PCG64(nz.seed)
                bg.advance(i * T + j0)
                out[:, k, i] = np.random.Generator(bg).uniform(-1.0, 1.0, size=m) * amp[i]
        return out

    def _fix(self, nb: int) -> np.ndarray | None:
        """The left limits at the ends of the segment's first blocks (array inputs that jump at 0)."""
        if not (self.Kin and self.b0 < self.Kin and np.any(self.end_fix)):
            return None
        fix = np.zeros((len(self.scen), nb, self.S.n_x))
        c = min(self.Kin - self.b0, nb)
        fix[:, :c] = self.end_fix[:, self.b0 : self.b0 + c]
        return fix

    def _segment_k(self, nb: int) -> tuple[int, int, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """:meth:`segment` scenario-innermost (``(rows, ·, K)`` arrays, compiled loops); x and y are
        handed out as time-major views."""
        from uio_ring.numeric.scenario_kernel import delayed_sum_k
        from uio_ring.sim.batch_plant_k import run_blocks_k

        S, N, b0, P = self.S, self.N, self.b0, self.pairs
        assert P is not None
        K, a0 = len(self.scen), b0 * N
        KxN, KinN = self.Kx * N, self.Kin * N
        WT = self._inputs_k("w", S.n_w, a0 - KinN, a0 + nb * N)
        UT = self._inputs_k("u", S.n_u, a0 - KinN, a0 + nb * N)
        W, U = WT.transpose(0, 2, 1), UT.transpose(0, 2, 1)

        def taps(name: str, rows: np.ndarray | None, j0: int, L: int, off: int, into: np.ndarray) -> None:
            pairs = P[name]
            if pairs is not None and rows is not None:
                delayed_sum_k(pairs, rows, j0, L, off, N, into=into)

        fin = (np.zeros((nb * N + 1, S.n_x, K)) if P["B"] is None else
               delayed_sum_k(P["B"], WT, 0, nb * N + 1, KinN, N))
        taps("E", UT, 0, nb * N + 1, KinN, fin)
        XT = np.empty((KxN + nb * N + 1, S.n_x, K))  # XT[KxN + j − a0] = x(t_j)
        XT[: KxN + 1] = self.Xtail.transpose(0, 2, 1)
        run_blocks_k(self.integ, XT[(self.Kx - self.KA) * N :], fin, nb, self._fix(nb))
        jlo = 0 if b0 == 0 else a0 + 1
        jhi = min(a0 + nb * N, self.n_steps)
        self.Xtail = XT[nb * N :].copy().transpose(0, 2, 1)  # time-major view (the closed loop reads x(0))
        L = jhi - jlo + 1
        YT = np.zeros((L, S.n_y, K))
        taps("C", XT, jlo, L, KxN - a0, YT)
        taps("D", WT, jlo, L, KinN - a0, YT)
        taps("F", UT, jlo, L, KinN - a0, YT)
        nz = self._noise(S.n_y, jlo, jhi)
        if nz is not None:
            YT += nz.transpose(0, 2, 1)
        self.b0 = b0 + nb
        sl = slice(KxN + jlo - a0, KxN + jhi - a0 + 1)
        rows = slice(KinN + jlo - a0, KinN + jhi - a0 + 1)
        return jlo, jhi, XT[sl].transpose(0, 2, 1), YT.transpose(0, 2, 1), W[rows], U[rows]

    def segment(self, nb: int) -> tuple[int, int, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Integrate ``nb`` blocks; return ``(jlo, jhi, X, Y, W, U)`` for the new samples ``jlo … jhi``
        (time-major: ``(jhi − jlo + 1, K, ·)``; the first segment includes ``j = 0``)."""
        S, N = self.S, self.N
        K = len(self.scen)
        b0 = self.b0
        a0 = b0 * N
        nb = max(1, min(nb, -(-(self.n_steps - a0) // N)))  # not past the horizon
        if self.pairs is not None:
            return self._segment_k(nb)
        KxN, KinN = self.Kx * N, self.Kin * N
        X = np.empty((KxN + nb * N + 1, K, S.n_x))  # time-major: X[KxN + j − a0] = x(t_j)
        X[: KxN + 1] = self.Xtail
        W = self._inputs("w", S.n_w, a0 - KinN, a0 + nb * N)
        U = self._inputs("u", S.n_u, a0 - KinN, a0 + nb * N)
        kern = self.kernel
        fin = _bsum(S.B, W, 0, nb * N, N, KinN, kern) + _bsum(S.E, U, 0, nb * N, N, KinN, kern)
        fix = None
        if self.Kin and b0 < self.Kin and np.any(self.end_fix):
            fix = np.zeros((K, nb, S.n_x))
            c = min(self.Kin - b0, nb)
            fix[:, :c] = self.end_fix[:, b0 : b0 + c]
        base = (self.Kx - self.KA) * N
        if self.rows:
            self.integ.run_rows(X[base:], fin, nb, end_fix=fix, kernel=kern)
        else:  # the integrator's own layout, trajectory-major
            Xk = np.ascontiguousarray(X[base:].transpose(1, 0, 2))
            with Progress(nb, False, "plant") as bar:
                self.integ.run(Xk, np.ascontiguousarray(fin.transpose(1, 0, 2)), nb, bar, end_fix=fix)
            X[base:] = Xk.transpose(1, 0, 2)
        jlo = 0 if b0 == 0 else a0 + 1
        jhi = min(a0 + nb * N, self.n_steps)
        self.Xtail = X[nb * N :].copy()
        # rows of X: x(t_j) = X[KxN + j − a0]; of W, U: [KinN + j − a0]
        Y = (_bsum(S.C, X, jlo, jhi, N, KxN - a0, kern) + _bsum(S.D, W, jlo, jhi, N, KinN - a0, kern)
             + _bsum(S.F, U, jlo, jhi, N, KinN - a0, kern))
        nz = self._noise(S.n_y, jlo, jhi)
        if nz is not None:
            Y += nz
        self.b0 = b0 + nb
        sl = slice(KxN + jlo - a0, KxN + jhi - a0 + 1)
        rows = slice(KinN + jlo - a0, KinN + jhi - a0 + 1)
        return jlo, jhi, X[sl], Y, W[rows], U[rows]


# ---------------------------------------------------------------------------------- observer
class _BatchObserver:
    """The stepper's recursion (``ObserverStepper.trajectories``) for K scenarios, by segments.

    Arrays are time-major, ``(steps, K, ·)``."""

    def __init__(self, stepper: Any, scenarios: Sequence[Scenario], u_history: np.ndarray, kernel: str = "python"):
        self.st = st = stepper
        self.kernel = kernel  # "numba": the linear loops compiled (uio_ring.numeric.linear_kernel)
        self.scen = scenarios
        self.u_history = u_history  # (L, K, n_u): u at j = −L … −1
        self.Lt = st.history_length + 1
        self.pad = max(st.lag * st.N, 0 if st.Wm is None else (st.Wm.shape[0] - 1) * st.N)
        self.scan = LinearScan(st.Phi, chunk=16) if st.inj is None else None
        self.PhiT = st.Phi.T.copy()
        self.binj = None if st.inj is None else _BatchInjection(st.inj)
        self.Ytail: np.ndarray | None = None
        self.Utail = self.Ztail = self.xi = np.zeros(0)
        self.started = False
        self.z0: np.ndarray | None = None
        #: numba, a linear observer with the cubic forcing, K ≥ 8 (fewer: the chunked LinearScan of
        #: simulate_observer, whose rounding it shares): every segment scenario-innermost, compiled
        self.lin_k = None
        if kernel == "numba" and st.inj is None and st.cubic and len(scenarios) >= 8:
            from uio_ring.sim.batch_linear import LinearObserverK

            self.lin_k = LinearObserverK(st, u_history, self.pad, self._xi_from)

    def start_exact(self, Yp: np.ndarray, Up: np.ndarray, z0: np.ndarray) -> None:
        """Start from the true past (``exact_start``): y, u at ``j = −Lt … −1`` (time-major rows)
        and ``ẑ(0)`` ``(K, n_z)``, instead of y held at y(0), u from its history and x̂(0)."""
        self.Ytail, self.Utail, self.z0 = Yp, Up, z0
        if self.lin_k is not None:
            self.lin_k.start_exact(Yp, Up)

    def _xi0(self, Yrows: np.ndarray, Urows: np.ndarray, off: int) -> np.ndarray:
        st = self.st
        D0 = _bsum(st.Dy, Yrows, 0, 0, st.N, off)[0]
        if st.n_u:
            D0 = D0 + _bsum(st.Du, Urows, 0, 0, st.N, off)[0]
        return self._xi_from(D0)

    def _xi_from(self, D0: np.ndarray) -> np.ndarray:
        """``ξ(0)`` ``(K, n_z)`` from ``D(δ) y`` (and u) at t = 0: ``ẑ(0) − D0`` for ``exact_start``,
        else ``initial · x̂(0) − D0`` for the scenarios with ``x_hat0``, else 0."""
        st = self.st
        K = len(self.scen)
        if self.z0 is not None:
            return self.z0 - D0
        xi = np.zeros((K, st.n_z))
        n_init = st.model.initial.shape[1]
        for k, sc in enumerate(self.scen):
            if sc.x_hat0 is not None:
                v = np.asarray(sc.x_hat0, dtype=float).reshape(-1)
                if v.shape != (n_init,) or not np.all(np.isfinite(v)):
                    raise DimensionError(f"scenario {k}: x_hat0 = {sc.x_hat0!r}; expected {n_init} finite values")
                xi[k] = st.model.initial @ v - D0[k]
        return xi

    def segment(self, jlo: int, Y: np.ndarray, U: np.ndarray) -> tuple[np.ndarray, np.ndarray | None]:
        """``x̂`` (and ``ŵ``) at the new samples ``jlo …`` from y, u there: ``(S, K, n_x)``."""
        st, N, Lt = self.st, self.st.N, self.Lt
        Sn, K = Y.shape[0], Y.shape[1]
        if self.lin_k is not None:
            self.started = True
            return self.lin_k.segment(jlo, Y, U)
        if st.n_u == 0:
            U = np.zeros((Sn, K, 0))
        first, self.started = not self.started, True
        Yt: np.ndarray
        if self.Ytail is None:  # y held at y(0) before 0; u from its history (and one more row, never read)
            Yt = np.repeat(Y[:1], Lt, axis=0)
            Ut = np.concatenate([self.u_history[:1], self.u_history], axis=0)
        else:
            Yt, Ut = self.Ytail, self.Utail  # the previous segment's (or the true past: start_exact)
        Yrows = np.concatenate([Yt, Y], axis=0)  # Yrows[Lt + j − jlo] = y(t_j)
        Urows = np.concatenate([Ut, U], axis=0)
        off = Lt - jlo
        j1 = jlo + Sn - 1
        kern = self.kernel
        G = _bsum(st.Gy, Yrows, jlo - 3, j1, N, off, kern)  # G[j − jlo + 3] = g(t_j)
        D = _bsum(st.Dy, Yrows, jlo, j1, N, off, kern)
        if st.n_u:
            G += _bsum(st.Gu, Urows, jlo - 3, j1, N, off, kern)
            D += _bsum(st.Du, Urows, jlo, j1, N, off, kern)
        steps = np.arange(jlo - 1 if not first else 0, j1)  # the steps j → j + 1 of this segment
        xi_prev = self._xi0(Yrows, Urows, off) if first else self.xi
        if self.binj is not None:
            Xi = self._loop(xi_prev, self._forcing(G, steps, jlo), G, Yrows, Urows, off, steps, jlo)
        elif K >= 8 or steps.size <= 32:  # one small product per step carries K scenarios
            Xi = scan_rows(self.PhiT, xi_prev, self._forcing(G, steps, jlo), kern)  # the forcing: this segment's own array
        else:
            Fq = self._forcing(G, steps, jlo)
            assert self.scan is not None  # linear models have one
            Xi = _scan_k(self.scan, xi_prev, np.ascontiguousarray(Fq.transpose(1, 0, 2))).transpose(1, 0, 2)
        if first:
            Xi = np.concatenate([xi_prev[None], Xi], axis=0)
        self.xi = Xi[-1].copy()
        Zrows = np.empty((self.pad + Xi.shape[0],) + Xi.shape[1:])  # ẑ = ξ + D(δ) y after its tail
        np.add(Xi, D, out=Zrows[self.pad :])
        Zrows[: self.pad] = Zrows[self.pad] if first else self.Ztail  # held at ẑ(0) before 0
        zoff = self.pad - jlo
        xh = _bsum(st.X, Zrows, jlo, j1, N, zoff, kern)
        wh = None if st.Wm is None else _bsum(st.Wm, Zrows, jlo, j1, N, zoff, kern)
        self.Ytail, self.Utail = Yrows[-Lt:].copy(), Urows[-Lt:].copy()
        self.Ztail = Zrows[Zrows.shape[0] - self.pad :].copy()
        return xh, wh

    def _forcing(self, G: np.ndarray, steps: np.ndarray, jlo: int) -> np.ndarray:
        """Forcing of the steps ``j → j + 1`` (``ObserverStepper._forcing_table``): ``(len, K, n_z)``."""
        st, N = self.st, self.st.N
        M, K = steps.size, G.shape[1]
        nz = st.n_z
        Fq = np.zeros((M * K, nz))
        if M == 0:
            return Fq.reshape(0, K, nz)
        g0 = int(steps[0]) - (jlo - 3)  # G index of g(t_j) for the first step

        def stencil(shifts: tuple[int, ...], W: np.ndarray) -> np.ndarray:  # one product per node
            return tap_rows(G, [g0 + sh for sh in shifts], [Wm.T for Wm in W], M, self.kernel)

        Wf = st.W_first
        if st.cubic:
            Fq = stencil((-2, -1, 0, 1), st.W)
            end = st.guard_blocks * N
        else:
            Fq = stencil((0, 1), Wf)
            end = 0
        Fq = Fq.reshape(M, K, nz)
        if end and steps[0] < end:
            gi = steps - (jlo - 3)
            r = steps % N
            sel = np.nonzero((steps < end) & (r == 0))[0]
            Fq[sel] = G[gi[sel]] @ Wf[0].T + G[gi[sel] + 1] @ Wf[1].T
            if N > 1:
                Ws = st.W_second
                sel = np.nonzero((steps < end) & (r == 1))[0]
                Fq[sel] = G[gi[sel] - 1] @ Ws[0].T + G[gi[sel]] @ Ws[1].T + G[gi[sel] + 1] @ Ws[2].T
        return Fq

    def _loop(self, xi: np.ndarray, Fq: np.ndarray, G: np.ndarray, Yrows: np.ndarray, Urows: np.ndarray,
              off: int, steps: np.ndarray, jlo: int) -> np.ndarray:
        """Models with an injection term: one step at a time, all K scenarios per step."""
        st, binj = self.st, self.binj
        assert binj is not None  # only for models with injection
        M = steps.size
        out = np.empty((M,) + xi.shape)
        if M == 0:
            return out
        PhiT, KlT, FT, dt = st.Phi.T, binj.KlT, st.model.F.T, st.dt
        method, RT = binj.inj.method, binj.RT
        j0 = int(steps[0])
        rows = slice(off + j0, off + j0 + M + 1)
        Meas = binj.measured(Yrows[rows], Urows[rows])  # Meas[q] at t_{j0 + q}
        g0 = j0 - (jlo - 3)
        if st._tables is not None:  # the compiled loop (uio_ring.numeric.kernel), all K scenarios
            from uio_ring.numeric.kernel import explicit_steps, implicit_steps

            if method == "euler":
                Fq = dt * G[g0 : g0 + M]
            run = implicit_steps if method == "implicit" else explicit_steps
            c = np.ascontiguousarray
            run(st._tables, c(Fq), c(Meas), c(xi), out)
            return out
        with np.errstate(all="ignore"):
            for q in range(M):
                if method == "implicit":
                    xi = binj.implicit(xi @ PhiT + Fq[q], Meas[q + 1])
                elif method == "explicit":
                    xi = xi @ PhiT + Fq[q] + binj.l_of(Meas[q] + xi @ RT) @ KlT
                else:  # euler: g(t_j) over the step j → j + 1
                    xi = xi + dt * (xi @ FT + G[g0 + q] + binj.l_of(Meas[q] + xi @ RT))
                out[q] = xi
        return out


# ---------------------------------------------------------------------------------- metrics
def _error_norm(X: np.ndarray, xh: np.ndarray) -> np.ndarray:
    """``‖x − x̂‖_∞`` per sample of time-major ``(S, K, n)`` arrays: ``(S, K)`` (a maximum over a few
    strided columns: a reduction over a short last axis costs ~10× more).

    >>> _error_norm(np.array([[[1.0, -3.0]]]), np.zeros((1, 1, 2))).tolist()
    [[3.0]]
    """
    if X.shape[2] == 0:
        return np.zeros(X.shape[:2])
    d = np.subtract(X, xh)
    np.abs(d, out=d)
    e = d[..., 0].copy()
    for i in range(1, d.shape[2]):
        np.maximum(e, d[..., i], out=e)  # NaN propagates, as in np.max
    return e


class _Metrics:
    """On-the-fly error metrics of K runs (see :data:`METRICS`)."""

    def __init__(self, K: int, dt: float, tol: float, diverge: float, settle: float, kernel: str = "python"):
        self.dt, self.tol, self.diverge = dt, tol, diverge
        self.kernel = kernel  # "numba": error and statistics in one compiled pass (numeric.metrics_kernel)
        self.j_settle = int(np.ceil(settle / dt - 1e-9))
        self.max_set = np.zeros(K)
        self.sq_set = np.zeros(K)
        self.n_set = 0
        nan = np.full(K, np.nan)
        self.last_bad = np.full(K, -1)  # last index with e > tol (or not finite)
        self.max_after = np.zeros(K)
        self.sumsq = np.zeros(K)
        self.count = np.zeros(K, dtype=np.int64)
        self.peak = np.zeros(K)
        self.t_peak = np.zeros(K)
        self.final = nan.copy()
        self.t_diverge = nan.copy()

    def update_xy(self, jlo: int, X: np.ndarray, xh: np.ndarray) -> None:
        """:meth:`update` with the error of the samples ``x``, ``x̂`` (time-major ``(S, K, n)``)."""
        if self.kernel != "numba":
            self.update(jlo, _error_norm(X, xh).T)
            return
        from uio_ring.numeric.metrics_kernel import update_metrics

        update_metrics(X, xh, jlo, self.dt, self.tol, self.diverge, self.j_settle, self.last_bad, self.max_after,
                       self.sumsq, self.count, self.peak, self.t_peak, self.final, self.t_diverge, self.max_set,
                       self.sq_set)
        self.n_set += max(0, X.shape[0] - max(self.j_settle - jlo, 0))

    def update(self, jlo: int, e: np.ndarray) -> None:
        """``e`` ``(K, S)``: the error norm at ``j = jlo … jlo + S − 1``."""
        K, S = e.shape
        idx = np.arange(S)
        finite = np.isfinite(e)
        bad = ~finite | (e > self.tol)
        any_bad = bad.any(axis=1)
        last = np.where(any_bad, S - 1 - np.argmax(bad[:, ::-1], axis=1), -1)
        after = idx[None, :] > last[:, None]
        ea = np.where(after, e, 0.0)
        smax, ssq, scnt = ea.max(axis=1, initial=0.0), (ea * ea).sum(axis=1), after.sum(axis=1)
        self.max_after = np.where(any_bad, smax, np.maximum(self.max_after, smax))
        self.sumsq = np.where(any_bad, ssq, self.sumsq + ssq)
        self.count = np.where(any_bad, scnt, self.count + scnt)
        self.last_bad = np.where(any_bad, jlo + last, self.last_bad)
        ep = np.where(finite, e, np.inf)
        kp = np.argmax(ep, axis=1)
        pk = ep[np.arange(K), kp]
        better = pk > self.peak
        self.peak = np.where(better, pk, self.peak)
        self.t_peak = np.where(better, (jlo + kp) * self.dt, self.t_peak)
        div = ~finite | (e > self.diverge)
        first = np.argmax(div, axis=1)
        new = div.any(axis=1) & np.isnan(self.t_diverge)
        self.t_diverge = np.where(new, (jlo + first) * self.dt, self.t_diverge)
        self.final = e[:, -1]
        es = e[:, max(self.j_settle - jlo, 0) :]
        if es.shape[1]:
            self.max_set = np.maximum(self.max_set, np.where(np.isfinite(es), es, np.inf).max(axis=1))
            self.sq_set = self.sq_set + (es * es).sum(axis=1)
            self.n_set += es.shape[1]

    def result(self, n_last: int) -> dict[str, np.ndarray]:
        conv = self.last_bad < n_last
        with np.errstate(invalid="ignore", divide="ignore"):
            rms = np.sqrt(self.sumsq / self.count)
        nan = np.nan
        return {
            "t_converge": np.where(conv, (self.last_bad + 1) * self.dt, nan),
            "max_after": np.where(conv, self.max_after, nan),
            "rms_after": np.where(conv, rms, nan),
            "peak": self.peak,
            "t_peak": self.t_peak,
            "final": self.final,
            "t_diverge": self.t_diverge,
            "max_settled": self.max_set if self.n_set else np.full_like(self.peak, np.nan),
            "rms_settled": np.sqrt(self.sq_set / self.n_set) if self.n_set else np.full_like(self.peak, np.nan),
        }


# ---------------------------------------------------------------------------------- driver
def _delay_groups(scen: Sequence[Scenario], ph: float, delay_model: bool) -> list[tuple[float, list[int]]]:
    """Scenarios by the plant's true delay (``Scenario.plant_h``, default ``ph``): ``(h, indices)``
    in order of first appearance."""
    groups: list[tuple[float, list[int]]] = []
    for k, sc in enumerate(scen):
        if sc.plant_h is None:
            h = ph
        elif not delay_model:
            raise SimulationError(f"scenario {k}: plant_h is for observers with delays (the design's h)")
        else:
            h = as_float(sc.plant_h, "plant_h")
        for hg, ks in groups:
            if _same_h(h, hg):
                ks.append(k)
                break
        else:
            groups.append((h, [k]))
    return groups


class _PlantGroups:
    """Plants of different true delays in one batch: one :class:`_BatchPlant` per delay (its own
    blocks), their samples put side by side in scenario order; :meth:`segment` as
    :meth:`_BatchPlant.segment`, in blocks of the first group's N (each group integrates whole
    blocks of its own and keeps what it has beyond the samples handed out)."""

    def __init__(self, plants: list[_BatchPlant], cols: list[list[int]], scenarios: Sequence[Scenario]):
        self.plants, self.cols, self.scen = plants, [np.array(c) for c in cols], scenarios
        self.N, self.n_steps, self.b0 = plants[0].N, plants[0].n_steps, 0
        self.S = plants[0].S
        self.buf: list[list[np.ndarray] | None] = [None] * len(plants)  # rows from self.j on: X, Y, W, U
        self.j = 0  # first sample not handed out

    def segment(self, nb: int) -> tuple[int, int, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        jlo = self.j
        jhi = min((self.b0 + nb) * self.N, self.n_steps)
        K = len(self.scen)
        out: list[np.ndarray] = []
        for g, (bp, cols) in enumerate(zip(self.plants, self.cols, strict=True)):
            buf = self.buf[g]
            while buf is None or jlo + buf[0].shape[0] - 1 < jhi:
                _, _, *new = bp.segment(max(1, -(-(jhi - bp.b0 * bp.N) // bp.N)))
                buf = new if buf is None else [np.concatenate([a, b], axis=0) for a, b in zip(buf, new, strict=True)]
            rows = jhi - jlo + 1
            if not out:
                out = [np.empty((rows, K) + a.shape[2:]) for a in buf]
            for o, a in zip(out, buf, strict=True):
                o[:, cols] = a[:rows]
            self.buf[g] = [a[rows:] for a in buf]
        self.j, self.b0 = jhi + 1, self.b0 + nb
        return jlo, jhi, out[0], out[1], out[2], out[3]


def _open_loop(bp: _BatchPlant | _PlantGroups, bo: _BatchObserver, nb: int, s0: int,
               z_of_x: np.ndarray | None) -> Iterator[tuple[int, tuple[Any, ...]]]:
    """Segments ``(j0, (X, Y, W, U, x̂, ŵ))`` of an open-loop batch, ``j0`` in observer time (0 at
    t = 0); the plant runs ``s0`` steps before t = 0 for ``exact_start`` (then ``z_of_x`` is given)."""
    K = len(bp.scen)
    while bp.b0 == 0 or bp.b0 * bp.N < bp.n_steps:
        jlo, _, X, Y, W, U = bp.segment(max(nb, -(-s0 // bp.N)) if bp.b0 == 0 else nb)
        if s0 and not bo.started:  # the first segment reaches t = 0: the observer's true past
            assert z_of_x is not None  # exact_start checked it (warm_steps)
            q, Lt = s0 - jlo, bo.Lt
            Up = U[q - Lt : q] if bo.st.n_u else np.zeros((Lt, K, 0))
            bo.start_exact(Y[q - Lt : q].copy(), Up.copy(), _bsum(z_of_x, X, 0, 0, bo.st.N, q)[0])
            X, Y, W, U = X[q:], Y[q:], W[q:], U[q:]
            jlo = s0
        yield jlo - s0, (X, Y, W, U) + bo.segment(jlo - s0, Y, U)
        if bp.n_steps == 0:
            break


def _segment_blocks(K: int, N: int, width: int, segment_steps: int | None) -> int:
    """Blocks per segment: about 2²⁰ floats per (steps, K, width) array unless told (measured on
    paper 001, K = 100: segments that fit the cache run up to twice as fast as long ones)."""
    steps = segment_steps if segment_steps is not None else max(N, (1 << 20) // max(K * width, 1))
    return max(1, int(steps) // N)


def _same_h(a: Any, b: Any) -> bool:
    if a is None or b is None:
        return a is None and b is None
    fa, fb = as_float(a, "h"), as_float(b, "h")
    return abs(fa - fb) <= 1e-12 * max(abs(fa), abs(fb))


def _plant_arrays(sys: Any, scen: Sequence[Scenario]) -> SystemArrays:
    """The plant's arrays: one stack ``(deg + 1, ·, ·)`` if every scenario runs on ``sys``,
    else one per scenario ``(K, deg + 1, ·, ·)`` (same sizes, delay degrees and h as ``sys``)."""
    S = SystemArrays.from_system(sys)
    if all(sc.plant is None or sc.plant is sys for sc in scen):
        return S
    arrays = []
    for k, sc in enumerate(scen):
        p = sys if sc.plant is None else sc.plant
        if not _same_h(getattr(p, "h", None), getattr(sys, "h", None)):
            raise SimulationError(f"scenario {k}: the plant's h = {getattr(p, 'h', None)} differs from the h = "
                                  f"{getattr(sys, 'h', None)} of the batch's plant (one grid per batch)")
        arrays.append(S if p is sys else SystemArrays.from_system(p))
    return SystemArrays.stack(arrays, label="scenario",
                              reference="the batch's plant (the design's system unless plant= is given)", ref=S)


def simulate_batch(
    design: Any,
    scenarios: Sequence[Scenario],
    *,
    t_final: Any,
    dt: Any,
    plant: Any = None,
    plant_h: Any = None,
    tol: float = 1e-3,
    diverge: float = 1e6,
    settle: float | None = None,
    trajectories: bool = False,
    discretisation: str | None = None,
    segment_steps: int | None = None,
    progress: bool | None = None,
    on_segment: Callable[[Segment], None] | None = None,
    kernel: str | None = None,
    exact_start: bool = False,
    feedback: Callable[[float, np.ndarray, np.ndarray | None], Any] | None = None,
) -> BatchResult:
    """Run ``len(scenarios)`` scenarios of ``design`` in one vectorised call (one plant, or one per scenario).

    Parameters
    ----------
    design : ObserverDesign
        Any design (its ``numeric()`` model runs, as in :func:`simulate_observer`).
    scenarios : sequence of Scenario
        What differs between runs: x0, w, u, noise and seed, x_hat0, the plant
        (``Scenario(plant=…)``; it must have the sizes, delay degrees and h of ``plant``)
        and its true delay (``Scenario(plant_h=…)``).
    t_final, dt : float
        Horizon and step (``dt`` divides the observer's h and the plant's).
    plant : DelaySystem, optional
        The plant of every scenario without a plant of its own (default ``design.system``;
        e.g. a perturbed one).  Scenarios with plants of their own are integrated together
        with it in the same vectorised call (stacked block maps, one per plant).
    plant_h : float, optional
        The plant's true delay (default: the design's h).  ``plant_h ≠ h`` simulates a
        delay mismatch: the observer still reads its taps at multiples of the design's h.
        Scenarios may have their own (``Scenario(plant_h=…)``; dt must divide each): the
        plants of each delay are integrated together (blocks of ``plant_h / dt`` steps, whose
        stencils stay inside each block: the derivative jumps of a delay system sit at
        multiples of its delay), their samples side by side for the one observer.
    tol : float
        Tolerance of the convergence time (on ``‖x − x̂‖_∞``).
    diverge : float
        An error above this (or not finite) marks the run as diverged (``t_diverge``).
    settle : float, optional
        Start of the window of ``max_settled`` and ``rms_settled`` (default ``t_final / 2``).
    trajectories : bool
        Keep ``x, y, x̂`` (and ``ŵ``) of every scenario (memory ∝ K · steps); default: metrics only.
    discretisation : str, optional
        Of injection terms, as in :func:`simulate_observer`.
    segment_steps : int, optional
        Steps per segment (rounded down to whole delay blocks); default: bounded memory.
    progress : bool, optional
        Progress bar on stderr.
    on_segment : callable, optional
        Called with each :class:`Segment` as soon as it is computed (stream the trajectories
        to disk with bounded memory: the segment's arrays are not kept).
    kernel : str, optional
        Backend of the observer's step loop (injection terms), as in :func:`simulate_observer`:
        with numba, one compiled loop over the K scenarios and their steps; numba also runs the
        linear loops of an open loop with the scenarios innermost (one plant's steps, forcing and
        outputs: :mod:`uio_ring.sim.batch_plant_k`; a linear observer with the cubic forcing:
        :mod:`uio_ring.sim.batch_linear`; other observers' taps: :mod:`uio_ring.numeric.linear_kernel`)
        and the error metrics in one pass (:mod:`uio_ring.numeric.metrics_kernel`), which agree
        with numpy's up to rounding.
    exact_start : bool
        As in :func:`simulate_observer`: every plant starts earlier (whole blocks of h; w and u
        callables or None, shifted), and the observer gets the true past of y and u and its
        exact initial state ``ẑ(0) = z_of_x(δ) x(0)`` (no ``x_hat0``).
    feedback : callable, optional
        Closed loop, as in :func:`simulate_observer` (delay-free plants, u held over each step):
        ``feedback(t, x_hat, w_hat) -> u`` with one row per scenario — ``x_hat`` ``(K, n_x)``,
        ``w_hat`` ``(K, n_w)`` or None, ``u`` ``(K, n_u)`` — called once per step for all K
        (:mod:`uio_ring.sim.batch_loop`; observers without delayed taps; scenarios give no u;
        the observer's step runs in numpy, whatever ``kernel``).

    Returns
    -------
    BatchResult
        ``metrics`` (one (K,) array per entry of :data:`METRICS`) and, on request, trajectories.

    Raises
    ------
    SimulationError
        For inputs that :func:`simulate_observer` would refuse (a run that diverges is not an
        error: its metrics say so), and scenario plants whose h differs from ``plant``'s.
    DimensionError
        Scenario plants whose matrices differ from ``plant``'s in size or delay degree.
    NotSupportedError
        As :func:`simulate_observer`: ``exact_start`` for a model without ``z_of_x``, ``feedback``
        on delay plants or with ``F ≠ 0``; and ``feedback`` with an observer that has delayed taps.

    A closed loop steps plant and observer together, one step at a time for all K scenarios
    (one call of ``feedback`` per step); an open loop runs by segments of whole blocks.
    """
    sys = plant if plant is not None else getattr(design, "system", None)
    if sys is None:
        raise SimulationError("plant is required: the design has no system")
    scen = list(scenarios)
    if not scen or not all(isinstance(s, Scenario) for s in scen):
        raise SimulationError("scenarios: expected a non-empty sequence of Scenario(...)")
    dtv = as_float(dt, "dt")
    tolv, divv = float(tol), float(diverge)
    if not (tolv > 0 and divv > 0):
        raise SimulationError(f"tol={tol!r} and diverge={diverge!r} must be positive")
    model = design.numeric(h=getattr(sys, "h", None))
    S = _plant_arrays(sys, scen)
    if (model.n_x, model.n_y) != (S.n_x, S.n_y) or (S.n_u and model.n_u != S.n_u):
        raise DimensionError(f"the design is for {model.n_x} states, {model.n_y} outputs and {model.n_u} known "
                             f"inputs; the plant has {S.n_x}, {S.n_y} and {S.n_u}")
    stepper = model.stepper(dtv, discretisation=discretisation, kernel=kernel)
    if model.h is not None:
        dtv = stepper.dt
        ph = float(model.h) if plant_h is None else as_float(plant_h, "plant_h")
    else:  # a delay-free observer: the plant's h (its delays), else one block per step
        sys_h = getattr(sys, "h", None) if plant_h is None else plant_h
        ph = dtv if sys_h is None else as_float(sys_h, "h")
        dtv = ph / round(ph / dtv)
    n_steps = step_count(as_float(t_final, "t_final"), dtv)
    K = len(scen)
    s0, plant_scen = 0, scen  # s0: plant steps before t = 0 (exact_start)
    if exact_start and feedback is not None:
        raise SimulationError("exact_start is for open-loop runs (no feedback)")
    if exact_start:
        if any(sc.x_hat0 is not None for sc in scen):
            raise SimulationError("give x_hat0 or exact_start=True, not both")
        for sc in scen:
            s0 = warm_steps(model, stepper, max(S.deg(S.C), 0), sc.w, sc.u)
        stepper = type(stepper)(stepper.model, stepper.dt, guard_blocks=0, kernel=stepper.kernel_option)  # y smooth at 0
        plant_scen = [replace(sc, w=shifted(sc.w, s0 * dtv), u=shifted(sc.u, s0 * dtv)) for sc in scen]
    if feedback is not None:
        from uio_ring.sim.batch_loop import check_closed_loop

        check_closed_loop(S, stepper, scen)
        ph = dtv  # a delay-free plant: one step a block
    groups = _delay_groups(scen, ph, model.h is not None)
    if feedback is not None and len(groups) > 1:
        raise SimulationError("plant_h: a closed loop runs delay-free plants (one h)")
    lin = resolve_kernel(stepper.kernel_option)  # the linear loops of plant and observer too
    run = _Run(sys=sys, model=model, stepper=stepper, dtv=dtv, n_steps=n_steps, s0=s0, ph=ph, lin=lin,
               tol=tolv, diverge=divv, settle=(n_steps * dtv) / 2 if settle is None else float(settle),
               segment_steps=segment_steps, trajectories=trajectories, on_segment=on_segment,
               exact_start=exact_start, feedback=feedback)
    # chunks of scenarios (cache-sized; whole chunks on threads): not with a closed loop (one call
    # of the law per step for all K), nor on_segment (segments of all K scenarios), nor an injection
    # term stepped in Python (its per-step overhead is shared by the K rows: measured on the aircraft,
    # K = 400 in chunks of 100 ran 2.3× slower)
    n_thr = batch_threads()
    python_steps = getattr(stepper, "inj", None) is not None and getattr(stepper, "_tables", None) is None
    whole = feedback is not None or on_segment is not None or python_steps
    parts = [(0, K)] if whole else chunk_bounds(K, n_thr)
    with blas_single_thread(), Progress(len(parts) * (n_steps + 1), want_progress(progress, n_steps * K),
                                        "batch") as bar:
        done = [0] * len(parts)

        def one(i: int) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
            k0, k1 = parts[i]

            def tick(d: int) -> None:
                done[i] = d
                bar.update(sum(done))

            return run.chunk(scen[k0:k1], plant_scen[k0:k1], tick)

        if n_thr > 1 and len(parts) > 1:
            from concurrent.futures import ThreadPoolExecutor

            with ThreadPoolExecutor(min(n_thr, len(parts))) as ex:  # whole chunks per thread
                res = list(ex.map(one, range(len(parts))))
        else:
            res = [one(i) for i in range(len(parts))]
    met = {k: np.concatenate([r[0][k] for r in res]) for k in res[0][0]}
    out = {k: np.concatenate([r[1][k] for r in res]) for k in res[0][1]}
    return BatchResult(metrics=met, dt=dtv, n_steps=n_steps, tol=tolv, diverge=divv,
                       extra={"model": model, "stepper": stepper, "plant_h": groups[0][0] if len(groups) == 1 else ph},
                       **out)


#: Scenarios per chunk (:func:`chunk_bounds`): a batch of more runs in consecutive chunks of at most
#: this many, each a complete simulation of its scenarios (measured on paper 001, dt = 1e-4: the
#: arrays of a segment over more scenarios leave the cache; K = 400 ran at 0.74× the K = 100 rate).
CHUNK = 128

#: Fewest scenarios of a chunk: the batch's paths are chosen by the number of rows (a linear
#: observer's recursion: one product per step from 8 rows on; the chain equations of an injection
#: term: vectorised from :data:`SCALAR_CHAINS_BELOW` rows on), so every chunk of at least this many
#: takes the path of the whole batch and computes each scenario by the same operations.
MIN_CHUNK = max(SCALAR_CHAINS_BELOW, 8)


def chunk_bounds(K: int, threads: int = 1) -> list[tuple[int, int]]:
    """Consecutive ranges ``[k0, k1)`` of K scenarios, of equal sizes (±1): the fewest chunks of
    at most :data:`CHUNK`, at least one per thread, none of fewer than :data:`MIN_CHUNK`
    (a batch of fewer is one chunk).

    >>> chunk_bounds(100), chunk_bounds(400)
    ([(0, 100)], [(0, 100), (100, 200), (200, 300), (300, 400)])
    >>> chunk_bounds(50, threads=2), chunk_bounds(40, threads=2)
    ([(0, 25), (25, 50)], [(0, 40)])
    """
    n = max(-(-K // CHUNK), threads)
    n = max(1, min(n, K // MIN_CHUNK))
    q, r = divmod(K, n)
    edges = np.cumsum([0] + [q + (i < r) for i in range(n)])
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:], strict=True)]


@dataclass(frozen=True)
class _Run:
    """What the chunks of one :func:`simulate_batch` call share; :meth:`chunk` runs some of its scenarios."""

    sys: Any
    model: Any
    stepper: Any
    dtv: float
    n_steps: int
    s0: int
    ph: float
    lin: str
    tol: float
    diverge: float
    settle: float
    segment_steps: int | None
    trajectories: bool
    on_segment: Callable[[Segment], None] | None
    exact_start: bool
    feedback: Any

    def chunk(self, scen: Sequence[Scenario], plant_scen: Sequence[Scenario], tick: Callable[[int], None],
              ) -> tuple[dict[str, np.ndarray], dict[str, np.ndarray]]:
        """Metrics and trajectories (``(k, n, T)``, if kept) of the scenarios ``scen``."""
        model, stepper, dtv, n_steps, s0, lin = self.model, self.stepper, self.dtv, self.n_steps, self.s0, self.lin
        sys, feedback, on_segment, exact_start = self.sys, self.feedback, self.on_segment, self.exact_start
        K = len(scen)
        S = _plant_arrays(sys, scen)
        groups = _delay_groups(scen, self.ph, model.h is not None)
        ph, n_plant = self.ph, n_steps + s0
        bp: _BatchPlant | _PlantGroups
        if len(groups) == 1:
            ph = groups[0][0]
            bp = _BatchPlant(S, ph, dtv, n_plant, plant_scen, lin)
        else:
            bp = _PlantGroups([_BatchPlant(_plant_arrays(sys, [plant_scen[k] for k in ks]), h, dtv, n_plant,
                                           [plant_scen[k] for k in ks], lin) for h, ks in groups],
                              [ks for _, ks in groups], plant_scen)
        L = stepper.history_length
        uh = np.zeros((L, K, model.n_u))
        if model.n_u and not exact_start and feedback is None:
            for k, sc in enumerate(scen):
                uh[:, k] = input_samples(sc.u, model.n_u, j_min=-L, j_max=-1, n_steps=n_steps, dt=dtv, name="u").T
        bo = _BatchObserver(stepper, scen, uh, lin)
        met = _Metrics(K, dtv, self.tol, self.diverge, self.settle, lin)
        width = max(S.n_x, S.n_y, model.n_z, S.n_w + S.n_u, 1) * 4
        nb = _segment_blocks(K, bp.N, width, self.segment_steps)
        if feedback is None:
            segments = _open_loop(bp, bo, nb, s0, model.z_of_x)
        else:
            from uio_ring.sim.batch_loop import ClosedLoop

            segments = ClosedLoop(bp, bo, bo.binj, feedback).segments(n_steps, nb * bp.N)
        keep: list[tuple[Any, ...]] = []
        with np.errstate(all="ignore"):
            for jo, (X, Y, W, U, xh, wh) in segments:
                if on_segment is not None:
                    t = np.arange(jo, jo + X.shape[0]) * dtv
                    on_segment(Segment(t=t, x=X, y=Y, w=W, u=U, x_hat=xh, w_hat=wh))
                met.update_xy(jo, X, xh)
                if self.trajectories:
                    keep.append((X, Y, xh, wh))
                tick(jo + X.shape[0])
        out: dict[str, np.ndarray] = {}
        if self.trajectories:
            for i, name in enumerate(("x", "y", "x_hat", "w_hat")):
                if name != "w_hat" or model.W is not None:  # (T, K, n) → (K, n, T)
                    out[name] = np.ascontiguousarray(np.concatenate([k[i] for k in keep], axis=0).transpose(1, 2, 0))
        return met.result(n_steps), out
