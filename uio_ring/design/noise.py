"""Choosing a design for noise: default observer rates, and the one least-noise search.

The figures come from the float model (:mod:`uio_ring.numeric.performance`); the choice
they lead to is then built exactly and certified like any other design.  Every search
here is finite or a fixed-start Nelder–Mead run, so the same system (and options) gives
the same design.

Criteria (``criterion``): ``"peak"`` — the peak-to-peak gain of the worst state (the
largest estimation error for output noise bounded by 1 on every output); ``"h2"`` — the
H2 gain of the worst state (white noise of unit intensity on every output), refused
when it is infinite for every candidate (a read-out that passes ``y`` straight to
``x̂``).

What is searched:

* :func:`search_poles` (every method whose linear part has free poles): the pole sets
  of :func:`pole_patterns` — ``−α·(1, q, q², …)``, ``q`` in :data:`SPREADS`;
* Zheng–Bejarano (:func:`least_noise`): that search on the first assemblies of each
  ``l*``, then :func:`couple` on the best: a strictly block-triangular part added to
  ``G0`` (it leaves ``det(sI − L0)`` and so the poles unchanged).

>>> from uio_ring import DelaySystem
>>> default_rate(DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None))
Fraction(5, 1)
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import replace
from fractions import Fraction
from typing import TYPE_CHECKING, Any

from uio_ring.errors import DomainError, SimulationError
from uio_ring.ring.poly import exact_fraction
from uio_ring.systems.delay_system import DelaySystem

if TYPE_CHECKING:  # numpy is imported where it is used: ``uio-ring check`` needs none of it
    import numpy as np

__all__ = ["default_rate", "pole_patterns", "search_poles", "least_noise", "couple", "coupled_models", "read_noise_options",
           "figure", "NOISE_CHOICES", "CRITERIA", "SPREADS"]

#: The words ``poles`` accepts besides a list of rationals.
NOISE_CHOICES = ("min-noise",)
#: What the least-noise search minimises (see the module docstring).
CRITERIA = ("peak", "h2")
#: Ratios of a geometric pole pattern ``−α·(1, q, q², …)`` tried by the least-noise search.
SPREADS = (Fraction(1), Fraction(11, 10), Fraction(5, 4), Fraction(3, 2), Fraction(2))
#: Decay rates tried, as multiples of the requested rate α (faster poles amplify noise more:
#: measured on the examples, the slowest allowed rate always won).
SPEEDS = (Fraction(1),)
#: Significant digits kept of the coupling entries found by :func:`couple` (exact rationals).
COUPLING_DIGITS = 3


def default_rate(sys: DelaySystem) -> Fraction:
    """The observer rate used when none is given: ``⌈‖A(1)‖∞⌉`` (at least 1).

    ``‖A(1)‖∞`` (largest absolute row sum of ``A(δ)`` at ``δ = 1``, exact) bounds the
    modulus of every eigenvalue of ``A(1)``, the plant seen by slow signals; an observer
    whose error decays at least that fast is not slower than the plant it watches.  The
    rounding keeps the poles small integers.
    """
    A1 = sys.A.eval(1).coefficient_lists()
    rows = A1[0] if A1 else []
    norm = max((sum(abs(v) for v in row) for row in rows), default=Fraction(0))
    return Fraction(max(1, math.ceil(norm)))


def read_noise_options(sys: DelaySystem, choice: Any, rate: Any, criterion: Any) -> tuple[Fraction, str]:
    """``(α, criterion)`` checked: ``choice`` in :data:`NOISE_CHOICES`, ``α > 0`` (default
    :func:`default_rate`), ``criterion`` in :data:`CRITERIA` (default ``"peak"``)."""
    if choice not in NOISE_CHOICES:
        raise DomainError(f"poles = {choice!r}: expected a list of rationals or one of {NOISE_CHOICES}")
    alpha = default_rate(sys) if rate is None else exact_fraction(rate, "rate")
    if alpha <= 0:
        raise DomainError(f"rate = {alpha} must be > 0 (the slowest decay rate allowed)")
    crit = "peak" if criterion is None else criterion
    if crit not in CRITERIA:
        raise DomainError(f"criterion = {criterion!r}: expected one of {CRITERIA}")
    return alpha, crit


def check_criterion(criterion: Any, poles: Any) -> None:
    """``criterion`` only goes with ``poles="min-noise"`` (it says what that search minimises)."""
    if criterion is not None and not isinstance(poles, str):
        raise DomainError(f"criterion = {criterion!r} applies to poles='min-noise' only")


def pole_patterns(count: int, rate: Fraction) -> list[tuple[Fraction, ...]]:
    """The pole sets tried: ``−s·α·(1, q, …, q^{count−1})`` for ``s`` in :data:`SPEEDS` and
    ``q`` in :data:`SPREADS` — every pole at least as fast as ``−α``; repeated poles
    (``q = 1``) first.

    >>> pole_patterns(2, Fraction(10))[:2]
    [(Fraction(-10, 1), Fraction(-10, 1)), (Fraction(-10, 1), Fraction(-11, 1))]
    """
    out: list[tuple[Fraction, ...]] = []
    for s in SPEEDS:
        for q in SPREADS:
            pat = tuple(-s * rate * q**i for i in range(count))
            if pat not in out:
                out.append(pat)
    return out


def figure(gains: tuple[np.ndarray, np.ndarray | None], criterion: str) -> float:
    """The number a search minimises: the worst state's peak-to-peak or H2 gain (``inf``
    when the H2 gain is infinite).

    >>> import numpy as np
    >>> figure((np.array([1.0, 3.0]), None), "h2"), figure((np.array([1.0, 3.0]), None), "peak")
    (inf, 3.0)
    """
    import numpy as np

    p2p, h2 = gains
    if criterion == "h2":
        return math.inf if h2 is None else float(np.max(h2))
    return float(np.max(p2p))


def _estimate(model: Any) -> tuple[np.ndarray, np.ndarray | None]:
    from uio_ring.numeric.performance import gain_estimate

    return gain_estimate(model)


def _refuse_infinite_h2(scored: Sequence[tuple[float, Any]], what: str) -> None:
    if scored and all(math.isinf(g) for g, _ in scored):
        raise DomainError(
            f"criterion='h2': the H2 gain is infinite for every {what} tried — the observer's read-out "
            "passes the output straight to the estimate (a direct feed-through), so white noise has an "
            "unbounded effect; use criterion='peak' (the peak-to-peak gain is finite)"
        )


def search_poles(build: Callable[[tuple[Fraction, ...]], Any], count: int, *, rate: Fraction, criterion: str,
                 model: Callable[[Any], Any], refuse: bool = True) -> tuple[float, Any]:
    """``(figure, design)`` of least :func:`figure` among ``build(p)`` for the pole sets
    ``p`` of :func:`pole_patterns` (``count`` poles, every one at least as fast as
    ``−rate``); ``model(design)`` is the linear float model whose gain is measured.
    Ties keep the earlier pattern.  ``DomainError`` for ``criterion="h2"`` when every
    candidate has an infinite H2 gain (unless ``refuse`` is false: the caller decides).
    """
    from uio_ring.numeric.threads import blas_single_thread

    scored: list[tuple[float, Any]] = []
    with blas_single_thread():
        for pat in pole_patterns(count, rate):
            design = build(pat)
            scored.append((figure(_estimate(model(design)), criterion), design))
    if criterion == "h2" and refuse:
        _refuse_infinite_h2(scored, "pole set")
    best = scored[0]
    for item in scored[1:]:
        if item[0] < best[0] * (1 - 1e-9):
            best = item
    return best


# ----------------------------------------------------------------------------------------
# Zheng–Bejarano: the assemblies of the design search, then the coupling of G0
# ----------------------------------------------------------------------------------------
def least_noise(sys: DelaySystem, ranked: Sequence[Any], choice: str, *, rate: Any, assemble: Callable[..., Any],
                criterion: Any = None, report: Any = None, candidates: int = 3) -> Any:
    """The Zheng–Bejarano design of least noise gain (:func:`figure`, ``criterion``).

    1. For each ``l*`` the design search found, its first ``candidates`` assemblies
       (least lag first), each with every pole set of :func:`pole_patterns`
       (:func:`search_poles`);
    2. on the best of them, :func:`couple`: ``G0`` plus a strictly block-triangular part
       (same poles), kept when it lowers the gain.

    ``rate`` (α) is the slowest decay allowed (default :func:`default_rate`).  Needs the
    system's ``h`` when it has delays (the gain depends on it).  Ties keep the earlier
    candidate (smaller lag) and the earlier pattern.
    """
    from uio_ring.numeric.threads import blas_single_thread

    with blas_single_thread():  # hundreds of tiny products: BLAS threads only hand over (threads.py)
        return _least_noise(sys, ranked, choice, rate=rate, assemble=assemble, criterion=criterion, report=report,
                            candidates=candidates)


def _least_noise(sys: DelaySystem, ranked: Sequence[Any], choice: str, *, rate: Any, assemble: Callable[..., Any],
                 criterion: Any, report: Any, candidates: int) -> Any:
    alpha, crit = read_noise_options(sys, choice, rate, criterion)
    if not sys.is_delay_free and sys.h is None:
        raise SimulationError("poles='min-noise' needs the system's h (the noise gain depends on the delay)")
    per_l: dict[int, list[Any]] = {}
    for asm in ranked:
        group = per_l.setdefault(asm.index.l_star, [])
        if len(group) < candidates:
            group.append(asm)
    label = f"poles of least {'peak-to-peak' if crit == 'peak' else 'H2'} noise gain at rate ≥ {alpha}"

    def builder(asm: Any, G0_extra: Any = None, note: str = "") -> Callable[[tuple[Fraction, ...]], Any]:
        return lambda pat: assemble(
            sys, asm.steps12, asm.Lam, index=asm.index, F_stack=asm.F_stack, O_left_inverse=asm.O_left_inverse,
            T_left_inverse=asm.T_left_inverse, poles=pat, G0_extra=G0_extra, choice=f"{asm.choice}; {label}{note}",
            assumptions=report, T=asm.T)

    scored = [(*search_poles(builder(asm), asm.index.l_star, rate=alpha, criterion=crit,
                             model=lambda d: d.numeric(h=sys.h), refuse=False), asm)
              for group in per_l.values() for asm in group]
    if crit == "h2":
        _refuse_infinite_h2([(g, d) for g, d, _ in scored], "design (assemblies × pole sets)")
    best_gain, best, asm = scored[0]
    for g, d, a in scored[1:]:
        if g < best_gain * (1 - 1e-9):
            best_gain, best, asm = g, d, a
    found = couple(best, sys.h, crit)
    if found is None:
        return best
    extra, how = found
    coupled = builder(asm, extra, f"; G0 coupled ({how})")(best.poles)
    if figure(_estimate(coupled.numeric(h=sys.h)), crit) < best_gain * (1 - 1e-6):
        return coupled
    return best


def _coupling_slots(r: int, l: int, upper: bool) -> list[tuple[int, int]]:
    """Entries ``(row, col)`` of ``G0`` (``r l × r``) strictly above (or below) the diagonal
    of each ``r × r`` block."""
    return [(k * r + i, j) for k in range(l) for i in range(r) for j in range(r) if (i < j if upper else i > j)]


def _round_sig(x: float, digits: int) -> Fraction:
    """``x`` rounded to ``digits`` significant digits, as an exact rational."""
    if x == 0 or not math.isfinite(x):
        return Fraction(0)
    e = math.floor(math.log10(abs(x))) - digits + 1
    return Fraction(round(x / 10.0**e)) * Fraction(10) ** e


def coupled_models(design: Any, h: Any) -> Callable[[np.ndarray], Any]:
    """``ΔG ↦`` the float model of the Zheng–Bejarano ``design`` with ``G0 + ΔG`` (``ΔG`` a
    constant float ``r l* × r`` array), in closed form: with ``Δ = [ΔG, 0]``,
    ``L0' = L0 − ΔG C0``, ``(HΛ)' = HΛ − Δ Γ̄1 Λ`` and
    ``(JΛ)' = JΛ + Δ (I − Γ̄2) Λ + L0' (HΛ)' − L0 HΛ`` — (22′) with the new ``G0``, no
    exact arithmetic (``ΔG = 0`` gives ``design.numeric(h)``).
    """
    import numpy as np

    from uio_ring.numeric.convert import coefficient_arrays
    from uio_ring.ring.matrix import PolyMatrix

    base = design.numeric(h=h)
    p, r = base.n_y, design.r
    P1 = coefficient_arrays(design.Gamma1_bar @ design.Lam, name="Γ̄1 Λ")
    P2 = coefficient_arrays((PolyMatrix.identity(p) - design.Gamma2_bar) @ design.Lam, name="(I − Γ̄2) Λ")
    C0 = coefficient_arrays(design.C0, name="C0")[0]
    n_taps = max(base.G_y.shape[0], base.D_y.shape[0], P1.shape[0], P2.shape[0], 1)

    def taps(a: np.ndarray) -> np.ndarray:
        return np.concatenate([a, np.zeros((n_taps - a.shape[0], *a.shape[1:]))]) if a.shape[0] < n_taps else a

    G, D, P1t, P2t = (taps(a) for a in (base.G_y, base.D_y, P1, P2))
    FD = np.einsum("ij,kjl->kil", base.F, D)

    def model(delta: np.ndarray) -> Any:
        Dp = np.hstack([delta, np.zeros((delta.shape[0], p - r))])
        F = base.F - delta @ C0
        D2 = D - np.einsum("ij,kjl->kil", Dp, P1t)
        G2 = G + np.einsum("ij,kjl->kil", Dp, P2t) + np.einsum("ij,kjl->kil", F, D2) - FD
        return replace(base, F=F, G_y=G2, D_y=D2)

    return model


def couple(design: Any, h: Any, criterion: str = "peak", *, max_evaluations: int = 80) -> tuple[Any, str] | None:
    """A strictly block-triangular ``ΔG0`` lowering the noise gain of a Zheng–Bejarano design,
    as ``(exact rl × r PolyMatrix, description)``, or ``None`` (``r = 1``, or no gain).

    With ``G0 = [G_1; …; G_l]`` and each ``G_k = g_k I_r + N_k``, ``N_k`` strictly upper
    (or lower) triangular, ``A0 − G0 C0`` is block-companion with the triangular polynomial
    matrix ``s^l I + Σ G_k s^{l−k}``: its determinant is ``(s^l + Σ g_k s^{l−k})^r``
    whatever the ``N_k`` — the same poles (certified exactly), only the error's mixing
    between channels changes, and with it the noise gain.

    Search (deterministic): for the upper, then the lower pattern, a Nelder–Mead run from
    ``N = 0`` (initial simplex steps ``|g_k|``, at most ``max_evaluations`` evaluations of
    the one-grid estimate :func:`~uio_ring.numeric.performance.gain_estimate` on a float
    model updated in closed form); the better pattern's entries are rounded to
    :data:`COUPLING_DIGITS` significant digits (exact rationals).  The run is deterministic
    on one platform (fixed start, fixed budget, BLAS on one thread); another floating-point
    library could round a last digit differently — the design stays certified either way.

    On paper 001's example (rate 10, r = 2, l* = 3) it finds ``N_k`` above the diagonal
    (172/25, −467/5, 937): worst-state gain 91.5 → 34.7 with the same poles.
    """
    import numpy as np
    from scipy.optimize import minimize

    from uio_ring.numeric.convert import coefficient_arrays
    from uio_ring.ring.matrix import PolyMatrix

    r, l = design.r, design.l_star
    if r < 2:
        return None
    base = design.numeric(h=h)
    model = coupled_models(design, h)
    g = [float(coefficient_arrays(design.G0, name="G0")[0][k * r, 0]) for k in range(l)]

    best: tuple[float, np.ndarray, str] | None = None
    f0 = figure(_estimate(base), criterion)
    if not math.isfinite(f0):
        return None
    for upper in (True, False):
        slots = _coupling_slots(r, l, upper)
        scale = np.array([abs(g[i // r]) or 1.0 for i, _ in slots])

        def delta_of(x: np.ndarray, slots: list[tuple[int, int]] = slots) -> np.ndarray:
            d = np.zeros((r * l, r))
            for (i, j), v in zip(slots, x, strict=True):
                d[i, j] = v
            return d

        def objective(x: np.ndarray, delta_of: Callable[[np.ndarray], np.ndarray] = delta_of) -> float:
            return figure(_estimate(model(delta_of(x))), criterion)

        x0 = np.zeros(len(slots))
        simplex = np.vstack([x0, np.diag(scale)])
        res = minimize(objective, x0, method="Nelder-Mead",
                       options={"initial_simplex": simplex, "maxfev": max_evaluations, "fatol": 1e-3 * f0,
                                "xatol": 1e-3 * float(scale.min())})
        if best is None or res.fun < best[0]:
            best = (float(res.fun), delta_of(res.x), "upper" if upper else "lower")
    assert best is not None
    if not best[0] < f0 * (1 - 1e-3):
        return None
    exact = PolyMatrix([[_round_sig(float(v), COUPLING_DIGITS) for v in row] for row in best[1]],
                       shape=(r * l, r))
    return exact, f"strictly {best[2]} block-triangular part, same poles"
