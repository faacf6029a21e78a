"""High-gain observers with dynamic output shaping (Grip & Saberi 2010).

For ``x' = A x + E u + φ(t, x)``, ``y = C x + F u`` with ``∂φ/∂x = Σ_k ζ_k(t, x) W_k``
(the ζ_k unknown, bounded), the design needs only (A, C, W_1, …, W_v):

1. **shape** — if the set is not admissible, a minimal-order output filter
   ``(A_z, B_z, C_z, D_z)`` makes the extended set (A_e, C_e, W_e) admissible
   (:func:`uio_ring.analysis.output_shaping.shape`; the identity filter when it
   already is);
2. **canonical form** — Γ_x, Γ_y, the chain lengths q and L of (A_e, C_e)
   (:func:`uio_ring.analysis.canonical_form.canonical_form`);
3. **gains** — per chain a Hurwitz polynomial ``s^q + k*_1 s^{q−1} + … + k*_q``,
   scaled ``K̃_j = k*_j / ε^j``; ``K̄ = blkdiag(K̃_i) + L`` (eq. (12)) and
   ``K = Γ_x K̄ Γ_y⁻¹ = [K_z; K_x]``.

The error ``x̃_e = [z̃; x − x̂]`` then obeys ``x̃_e' = (A_e − K C_e) x̃_e + Σ μ_k W_ek x̃_e``,
whose linear part has exactly the requested spectrum scaled by 1/ε.  The
observer is implemented without separate filter states (eq. (22))::

    z̃' = (A_z − K_z C_z) z̃ + (B_z − K_z D_z)(y − F u − C x̂)
    x̂' = A x̂ + E u + φ(t, x̂) + K_x (C_z z̃ + D_z (y − F u − C x̂))

(``numeric()`` holds the linear part and ``phi_map = [0; I]``, the place where φ(t, x̂)
enters; ``simulate_observer(design, phi=…)`` supplies φ.)

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [0]]", "[[1, 0]]", None)
>>> d = design_high_gain(sys, W=[[[0, 0], [1, 0]]], poles=[-1, -2], epsilon="1/2")
>>> d.K, d.certificate().ok
(PolyMatrix([[6], [8]]), True)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, ClassVar

from uio_ring.analysis.canonical_form import CanonicalForm, canonical_form, chain_blocks
from uio_ring.analysis.high_gain_applicability import HighGainApplicability, high_gain_applicable
from uio_ring.analysis.output_shaping import ShapingResult, shape
from uio_ring.analysis.strong_observability import is_hurwitz_polynomial
from uio_ring.design.base import ObserverDesign, matrix_to_data
from uio_ring.errors import DimensionError, DomainError, NotObservableError
from uio_ring.ring import constant as qc
from uio_ring.ring.certificate import Certificate
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import Poly, exact_fraction
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["HighGainDesign", "design_high_gain", "chain_gains", "theorem1_bound", "lyapunov_solution"]


def chain_gains(coefficients: Sequence[Fraction], epsilon: Fraction) -> tuple[Fraction, ...]:
    """``K̃ = (k*_1/ε, k*_2/ε², …, k*_q/ε^q)`` for one chain (Grip & Saberi 2010, Theorem 1).

    >>> chain_gains([Fraction(9, 10), Fraction(7, 25), Fraction(1, 25)], Fraction(3, 10))
    (Fraction(3, 1), Fraction(28, 9), Fraction(40, 27))
    """
    return tuple(Fraction(k) / Fraction(epsilon) ** (j + 1) for j, k in enumerate(coefficients))


def chain_polynomial(coefficients: Sequence[Fraction], var: str = "s") -> Poly:
    """``s^q + k*_1 s^{q−1} + … + k*_q``."""
    return Poly.from_coeffs([*reversed([Fraction(k) for k in coefficients]), Fraction(1)], var)


@dataclass(frozen=True, repr=False)
class HighGainDesign(ObserverDesign):
    """A high-gain observer with output shaping (Grip & Saberi 2010); constant exact matrices.

    Attributes
    ----------
    system
        The plant (delay-free, ``B = D = 0``).
    W
        The ``W_k`` of the Jacobian of φ (n×n each), as given.
    epsilon
        The high-gain parameter ε ∈ (0, 1].
    coefficients
        ``k*_i`` per chain (chain order of the canonical form, longest first).
    q
        Chain lengths (observability indices of (A_e, C_e)).
    A_z, B_z, C_z, D_z
        The output filter (order ``n_f``; 0 when (A, C, W) is admissible).
    A_e, C_e, W_e
        The extended set (filter states first), eqs. (18)–(19).
    Gamma_x, Gamma_y, L
        Its canonical form: ``x_e = Γ_x x̄``, ``y_f = Γ_y ȳ``, ``Ā = blkdiag(A_{q_i}) + L C̄``.
    K
        ``Γ_x K̄ Γ_y⁻¹`` (n_e × p); ``K_z`` its first n_f rows, ``K_x`` the rest.
    mu_bounds
        Bounds ``μ_k,max`` of ``|ζ_k|`` when given: then :attr:`epsilon_bound` is Theorem 1's ε*.
    shaping, canonical, applicability
        The analysis records (not compared, not saved).
    """

    method: ClassVar[str] = "high-gain"

    system: DelaySystem
    W: tuple[PolyMatrix, ...]
    epsilon: Fraction
    coefficients: tuple[tuple[Fraction, ...], ...]
    q: tuple[int, ...]
    A_z: PolyMatrix
    B_z: PolyMatrix
    C_z: PolyMatrix
    D_z: PolyMatrix
    A_e: PolyMatrix
    C_e: PolyMatrix
    W_e: tuple[PolyMatrix, ...]
    Gamma_x: PolyMatrix
    Gamma_y: PolyMatrix
    L: PolyMatrix
    K: PolyMatrix
    mu_bounds: tuple[Fraction, ...] | None = None
    shaping: ShapingResult | None = field(default=None, compare=False)
    canonical: CanonicalForm | None = field(default=None, compare=False)
    applicability: HighGainApplicability | None = field(default=None, compare=False)

    # -- derived -----------------------------------------------------------------------
    @property
    def n_f(self) -> int:
        """Order of the output filter."""
        return self.A_z.rows

    @property
    def K_z(self) -> PolyMatrix:
        return self.K[: self.n_f, :]

    @property
    def K_x(self) -> PolyMatrix:
        return self.K[self.n_f:, :]

    @property
    def K_bar(self) -> PolyMatrix:
        """``blkdiag(K̃_i) + L`` (eq. (12)) in canonical coordinates."""
        return _k_tilde(self.q, self.coefficients, self.epsilon) + self.L

    @property
    def epsilon_bound(self) -> Fraction | None:
        """Theorem 1's sufficient bound: the error is exponentially stable for ``0 < ε < epsilon_bound``
        (None without ``mu_bounds``); see :func:`theorem1_bound`."""
        if self.mu_bounds is None:
            return None
        return theorem1_bound(self.q, self.coefficients, self.Gamma_x, self.W_e, self.mu_bounds)

    def error_matrix(self) -> PolyMatrix:
        """``A_e − K C_e``: the linear part of the error dynamics of ``[z̃; x − x̂]``."""
        return self.A_e - self.K @ self.C_e

    def characteristic_polynomial(self) -> Poly:
        """The requested ``Π_i ε^{−q_i} p_i(ε s)`` (monic), p_i the chain polynomials."""
        out = Poly(1, "s")
        for ks in self.coefficients:
            out = out * chain_polynomial(chain_gains(ks, self.epsilon))
        return out

    def filter_loop(self) -> PolyMatrix:
        """``A_z − K_z C_z``: the filter part of (22a) on its own (n_f × n_f)."""
        return self.A_z - self.K_z @ self.C_z

    @property
    def filter_loop_hurwitz(self) -> bool:
        """Is ``A_z − K_z C_z`` Hurwitz (exact Routh test; true without a filter)?

        The paper asserts that it always is.  It is not: it need not be once the
        filter has four or more states (a counterexample is in the tests).  The
        observer (22) as a whole is stable regardless — its matrix is similar to
        ``A_e − K C_e`` (see the certificate) — so this is reported, not required.
        """
        if not self.n_f:
            return True
        F = self.filter_loop()
        return is_hurwitz_polynomial(charpoly(F))

    def observer_matrices(self) -> dict[str, PolyMatrix]:
        """``F, G_y, G_u, X, initial`` of the implementation (22) with state ``ξ = [z̃; x̂]``."""
        sysm = self.system
        A, C, E, Fu = sysm.A, sysm.C, sysm.E, sysm.F
        n, nf = sysm.n_x, self.n_f
        Kz, Kx = self.K_z, self.K_x
        Rz = self.B_z - Kz @ self.D_z  # filter gain on the residual
        F = PolyMatrix.block([[self.A_z - Kz @ self.C_z, -(Rz @ C)], [Kx @ self.C_z, A - Kx @ self.D_z @ C]])
        G_y = PolyMatrix.vstack(Rz, Kx @ self.D_z)
        G_u = PolyMatrix.vstack(-(Rz @ Fu), E - Kx @ self.D_z @ Fu)
        X = PolyMatrix.hstack(PolyMatrix.zeros(n, nf), PolyMatrix.identity(n))
        initial = PolyMatrix.vstack(PolyMatrix.zeros(nf, n), PolyMatrix.identity(n))
        return {"F": F, "G_y": G_y, "G_u": G_u, "X": X, "initial": initial}

    def certificate(self) -> Certificate:
        """Every identity of the design, exactly (see :func:`uio_ring.verify.high_gain.high_gain_certificate`)."""
        from uio_ring.verify.high_gain import high_gain_certificate

        return high_gain_certificate(self)

    def numeric(self, *, h: Any = None) -> Any:
        """The float observer model of (22): ``ξ = [z̃; x̂]``, ``x̂ = [0, I] ξ``, ``ξ(0) = [0; x̂0]``;
        φ(t, x̂) enters through ``phi_map = [0; I]`` when the engine is given ``phi``
        (``simulate_observer(d, phi=…)``).  Delay-free (``h`` is accepted for the common signature).

        >>> from uio_ring import DelaySystem
        >>> sys = DelaySystem("[[0, 1], [0, 0]]", "[[0], [0]]", "[[1, 0]]", None)
        >>> design_high_gain(sys, poles=[-1, -2]).numeric()
        ObserverModel(high-gain: n_z=2, n_y=1, n_u=0, n_x=2, n_w=0, lag=0)
        """
        from uio_ring.numeric.build import model_from_exact

        m = self.observer_matrices()
        G_u = m["G_u"] if self.system.n_u else None
        return model_from_exact(F=m["F"], G_y=m["G_y"], G_u=G_u, X=m["X"], initial=m["initial"],
                                method=self.method, phi_map=m["initial"])  # φ(t, x̂) enters x̂' only

    # -- display and data ------------------------------------------------------------------
    def __repr__(self) -> str:
        bound = "" if self.mu_bounds is None else f", epsilon_bound={self.epsilon_bound}"
        return (f"HighGainDesign(q={self.q}, n_f={self.n_f}, epsilon={self.epsilon}{bound}, "
                f"coefficients={[[str(k) for k in ks] for ks in self.coefficients]})")

    def __str__(self) -> str:
        lines = [repr(self)]
        if self.n_f:
            lines += [f"A_z =\n{self.A_z}", f"B_z =\n{self.B_z}", f"C_z =\n{self.C_z}", f"D_z =\n{self.D_z}",
                      f"K_z =\n{self.K_z}"]
        lines += [f"K_x =\n{self.K_x}", f"Gamma_x =\n{self.Gamma_x}", f"Gamma_y =\n{self.Gamma_y}", f"L =\n{self.L}"]
        return "\n".join(lines)

    def to_latex(self) -> str:
        if self.n_f:
            return (
                r"\dot{\tilde z} = (A_z - K_z C_z)\tilde z + (B_z - K_z D_z)(y - C\hat x),\;"
                r"\dot{\hat x} = A\hat x + \varphi(t,\hat x) + K_x (C_z \tilde z + D_z (y - C\hat x)),\;"
                rf"A_z = {self.A_z.to_latex()},\; B_z = {self.B_z.to_latex()},\; C_z = {self.C_z.to_latex()},\;"
                rf"D_z = {self.D_z.to_latex()},\; K_z = {self.K_z.to_latex()},\; K_x = {self.K_x.to_latex()},\;"
                rf"\varepsilon = {self.epsilon}"
            )
        return (r"\dot{\hat x} = A\hat x + \varphi(t,\hat x) + K (y - C\hat x),\;"
                rf"K = {self.K.to_latex()},\; \varepsilon = {self.epsilon}")

    def to_dict(self) -> dict[str, Any]:
        return {
            "method": self.method,
            "epsilon": str(self.epsilon),
            "q": list(self.q),
            "coefficients": [[str(k) for k in ks] for ks in self.coefficients],
            "filter_order": self.n_f,
            "A_z": matrix_to_data(self.A_z), "B_z": matrix_to_data(self.B_z),
            "C_z": matrix_to_data(self.C_z), "D_z": matrix_to_data(self.D_z),
            "Gamma_x": matrix_to_data(self.Gamma_x), "Gamma_y": matrix_to_data(self.Gamma_y),
            "L": matrix_to_data(self.L),
            "K_z": matrix_to_data(self.K_z), "K_x": matrix_to_data(self.K_x),
            "filter_loop_hurwitz": self.filter_loop_hurwitz,
            "mu_bounds": None if self.mu_bounds is None else [str(m) for m in self.mu_bounds],
            "epsilon_bound": None if self.mu_bounds is None else str(self.epsilon_bound),
        }


# ----------------------------------------------------------------------------------------
# the steps
# ----------------------------------------------------------------------------------------
def _read_W(W: Any, n: int) -> tuple[PolyMatrix, ...]:
    if W is None:
        return ()
    if isinstance(W, (str, bytes)) or not isinstance(W, Sequence):
        raise DomainError(f"W must be a list of {n}×{n} rational matrices, not {W!r}")
    out = []
    for k, Wk in enumerate(W):
        M = qc.to_polymatrix(qc.qmat(Wk, f"W[{k}]"))
        if M.shape != (n, n):
            raise DimensionError(f"W[{k}] is {M.rows}×{M.cols}; expected {n}×{n} (= shape of A)")
        out.append(M)
    return tuple(out)


def _read_epsilon(epsilon: Any) -> Fraction:
    e = exact_fraction(epsilon, "epsilon")
    if not 0 < e <= 1:
        raise DomainError(f"epsilon = {e}; the high-gain parameter must lie in (0, 1]")
    return e


def _chain_coefficients(q: tuple[int, ...], poles: Any, coefficients: Any) -> tuple[tuple[Fraction, ...], ...]:
    """``k*_i`` per chain from real ``poles`` (chain i uses the first q_i) or explicit
    ``coefficients`` (one row per chain, or one row for chains that all have its length)."""
    if poles is not None and coefficients is not None:
        raise DomainError("give poles or coefficients, not both")
    if isinstance(poles, str):
        raise DomainError(f"poles = {poles!r}: the high-gain method takes a list of negative rationals")
    if coefficients is not None:
        rows = [tuple(exact_fraction(k, f"coefficients[{i}][{j}]") for j, k in enumerate(r))
                for i, r in enumerate(coefficients)]
        if len(rows) == 1 and len(q) > 1:
            rows = rows * len(q)
        if len(rows) != len(q):
            raise DimensionError(f"coefficients has {len(rows)} rows; expected {len(q)} (one per chain, q = {q})")
        for i, (r, qi) in enumerate(zip(rows, q, strict=True)):
            if len(r) != qi:
                raise DimensionError(f"coefficients[{i}] has {len(r)} entries; expected {qi} (chain lengths q = {q})")
            if not is_hurwitz_polynomial(chain_polynomial(r)):
                raise DomainError(f"coefficients[{i}] = {[str(k) for k in r]} do not give a Hurwitz polynomial")
        return tuple(rows)
    qmax = max(q, default=0)
    vals = tuple(Fraction(-(j + 1)) for j in range(qmax)) if poles is None else \
        tuple(exact_fraction(v, f"poles[{j}]") for j, v in enumerate(poles))
    if len(vals) < qmax:
        raise DimensionError(f"poles has {len(vals)} values; expected at least {qmax} (the longest chain, q = {q})")
    bad = [str(v) for v in vals if v >= 0]
    if bad:
        raise DomainError(f"poles must be negative (Hurwitz); got {', '.join(bad)}")
    out = []
    for qi in q:
        p = Poly(1, "s")
        for v in vals[:qi]:
            p = p * Poly.from_coeffs([-v, 1], "s")
        out.append(tuple(reversed(p.coeffs()[:-1])))
    return tuple(out)


def _k_tilde(q: tuple[int, ...], coeffs: tuple[tuple[Fraction, ...], ...], epsilon: Fraction) -> PolyMatrix:
    """``blkdiag(K̃_1, …, K̃_p)`` (n×p): chain i's scaled gains in column i.

    Precondition: ``len(coeffs[i]) == q[i]`` (not checked).
    """
    n, p = sum(q), len(q)
    rows = [[Fraction(0)] * p for _ in range(n)]
    for i, (s, _) in enumerate(chain_blocks(q)):
        for j, g in enumerate(chain_gains(coeffs[i], epsilon)):
            rows[s + j][i] = g
    return PolyMatrix(rows) if n and p else PolyMatrix.zeros(n, p)


def _gain(cf: CanonicalForm, coeffs: tuple[tuple[Fraction, ...], ...], epsilon: Fraction) -> PolyMatrix:
    """``K = Γ_x (blkdiag(K̃_i) + L) Γ_y⁻¹`` (eq. (12) and §3.2)."""
    Kb = _k_tilde(cf.q, coeffs, epsilon) + cf.L
    K = qc.qmat(cf.Gamma_x) * qc.qmat(Kb) * qc.qinverse(qc.qmat(cf.Gamma_y), "Γ_y")
    return qc.to_polymatrix(K)


def lyapunov_solution(H: PolyMatrix) -> PolyMatrix:
    """The symmetric ``P`` with ``P H + Hᵀ P = −I`` (exact; H Hurwitz), by the Kronecker form.

    >>> lyapunov_solution(PolyMatrix([[-1]]))
    PolyMatrix([[1/2]])
    """
    q = H.rows
    Hq = qc.qmat(H)
    n2 = q * q
    M = qc.qzeros(n2, n2)
    rhs = qc.qzeros(n2, 1)
    # row-major vec: (P H)_{ab} = Σ_c P_{ac} H_{cb},  (Hᵀ P)_{ab} = Σ_c H_{ca} P_{cb}
    for a in range(q):
        for b in range(q):
            r = a * q + b
            rhs[r, 0] = -1 if a == b else 0
            for c in range(q):
                M[r, a * q + c] += Hq[c, b]
                M[r, c * q + b] += Hq[c, a]
    P = qc.qsolve(M, rhs, "the Lyapunov equation")
    return PolyMatrix([[qc.frac(P[a * q + b, 0]) for b in range(q)] for a in range(q)]) if q else PolyMatrix.zeros(0, 0)


def _norm1(rows: list[list[Fraction]]) -> Fraction:
    """Largest absolute column sum (0 for an empty matrix)."""
    if not rows or not rows[0]:
        return Fraction(0)
    return max(sum((abs(r[j]) for r in rows), Fraction(0)) for j in range(len(rows[0])))


def theorem1_bound(q: tuple[int, ...], coefficients: tuple[tuple[Fraction, ...], ...], Gamma_x: PolyMatrix,
                   W_e: Sequence[PolyMatrix], mu_bounds: Sequence[Any]) -> Fraction:
    """Theorem 1 of Grip & Saberi (2010) as an exact sufficient bound: stable for ``0 < ε < bound``.

    ``bound = min(1, 1 / (2 Σ_i ‖P_i‖ Σ_k Σ_j μ_k,max M_kij))`` with ``P_i H_i + H_iᵀ P_i = −I``,
    ``H_i = A_{q_i} − K*_i C_{q_i}``, and rational upper bounds of the 2-norms:
    ``‖P_i‖₂ ≤ ‖P_i‖₁`` (P symmetric) and ``M_kij = max(‖|W̄_kij|‖₁, ‖|W̄_kij|‖_∞)``
    (for ε ≤ 1 every entry of ``Θ_i W̄_kij Θ_j⁻¹`` is at most the entry of ``W̄_kij`` in size).
    Very conservative, as the paper says; a little more so than with 2-norms.

    >>> theorem1_bound((1,), ((Fraction(2),),), PolyMatrix([[1]]), [PolyMatrix([[1]])], [1])
    Fraction(1, 1)
    """
    if len(mu_bounds) != len(W_e):
        raise DimensionError(f"mu_bounds has {len(mu_bounds)} values; expected {len(W_e)} (one per W_k)")
    mus = [exact_fraction(m, f"mu_bounds[{k}]") for k, m in enumerate(mu_bounds)]
    if any(m < 0 for m in mus):
        raise DomainError("mu_bounds must be non-negative")
    Gx = qc.qmat(Gamma_x)
    Gxi = qc.qinverse(Gx, "Γ_x")
    Wb = [qc.to_fractions(Gxi * qc.qmat(W) * Gx) for W in W_e]
    blocks = chain_blocks(q)
    total = Fraction(0)
    for i, (si, qi) in enumerate(blocks):
        H = [[Fraction(1) if c == r + 1 else Fraction(0) for c in range(qi)] for r in range(qi)]
        for r in range(qi):
            H[r][0] -= Fraction(coefficients[i][r])
        P = lyapunov_solution(PolyMatrix(H))
        normP = _norm1([[Fraction(x) for x in row] for row in P.coefficient_lists()[0]])
        inner = Fraction(0)
        for k, Wk in enumerate(Wb):
            for sj, qj in blocks:
                blk = [[abs(Wk[si + r][sj + c]) for c in range(qj)] for r in range(qi)]
                M = max(_norm1(blk), _norm1([list(col) for col in zip(*blk, strict=True)]))
                inner += mus[k] * M
        total += normP * inner
    return Fraction(1) if total == 0 else min(Fraction(1), 1 / (2 * total))


def design_high_gain(sys: DelaySystem, *, W: Any = None, phi: Any = None, poles: Any = None,
                     coefficients: Any = None, epsilon: Any = 1, max_order: Any = None, mu_bounds: Any = None,
                     rate: Any = None, criterion: str | None = None,
                     report: HighGainApplicability | None = None) -> HighGainDesign:
    """A high-gain observer for ``x' = A x + E u + φ(t, x)``, ``y = C x + F u`` (Grip & Saberi 2010).

    Parameters
    ----------
    sys
        Delay-free, ``B = D = 0`` (no unknown input), ``rank C = p``, (A, C) observable.
    W
        The ``W_k`` (n×n rational) with ``∂φ/∂x = Σ ζ_k W_k``; default none (linear plant).
        Use a linearly independent set: splitting one ζ into several can make a
        solvable problem unsolvable (the paper's §5.6).
    phi
        Instead of ``W``: φ(t, x) as n sympy expressions in ``sympy.Symbol(name)`` for
        the system's state names (and any other symbols, e.g. t); the ``W_k`` are then
        :func:`~uio_ring.analysis.jacobian_basis.jacobian_basis` of φ.
    poles
        Real negative rationals; chain i gets ``Π_{j ≤ q_i} (s − poles[j])``
        (default ``−1, −2, …``).  ``"min-noise"``: the poles of least noise gain of the
        observer (linear: φ is not part of the figure) among ``−ε·rate·(1, q, q², …)``
        (:func:`~uio_ring.design.noise.search_poles`; the error's chain poles are
        ``poles/ε``, so every one is at least as fast as ``−rate``).
    rate, criterion
        With ``poles="min-noise"`` only: the slowest decay rate allowed (default
        ``⌈‖A‖∞⌉``) and ``"peak"`` (default) or ``"h2"`` (the figure minimised).
    coefficients
        Instead of poles: ``[k*_1, …, k*_q]`` per chain (the chain polynomial
        ``s^q + k*_1 s^{q−1} + … + k*_q``, Hurwitz), chains longest first; one row
        is used for every chain when all chains have its length.
    epsilon
        ε ∈ (0, 1] (exact; ``"0.3"`` is 3/10).  Theorem 1: small enough ε works
        for bounded ζ_k (see ``mu_bounds``).
    max_order
        Cap of the output filter's order (default n).
    mu_bounds
        Bounds of ``|ζ_k|`` (one per ``W_k``): the design then reports Theorem 1's
        sufficient bound ``epsilon_bound`` next to ε (exact, very conservative).
    report
        The applicability report, when the caller has it.

    Returns
    -------
    HighGainDesign

    Raises
    ------
    NotObservableError
        A system-level assumption fails, or no output filter of order ≤ ``max_order`` was found.
    DimensionError, DomainError
        Options of the wrong size, non-Hurwitz coefficients, ε outside (0, 1].

    Examples
    --------
    Example 3 of the paper (Example 1 shaped by one integrator), at ε = 3/10:

    >>> from uio_ring import DelaySystem
    >>> A = "[[0,1,0,0,0],[0,0,0,0,0],[0,0,0,1,0],[0,0,0,0,1],[0,0,0,0,0]]"
    >>> W1 = [[0,-1,0,1,0],[0,0,0,0,1],[0,-1,0,1,0],[1,0,0,0,1],[0,1,0,0,0]]
    >>> sys = DelaySystem(A, [[0]] * 5, "[[1,0,0,0,0],[0,0,1,0,0]]", None)
    >>> d = design_high_gain(sys, W=[W1], coefficients=[["0.9", "0.28", "0.04"]], epsilon="0.3")
    >>> d.n_f, d.q, d.K_z
    (1, (3, 3), PolyMatrix([[3, 1]]))
    """
    if report is None:
        report = high_gain_applicable(sys)
    if not report.holds:
        raise NotObservableError(f"the high-gain observer does not apply: {report.reason}", report=report)
    n = sys.n_x
    if phi is not None:
        if W is not None:
            raise DomainError("give W or phi, not both")
        import sympy

        from uio_ring.analysis.jacobian_basis import jacobian_basis

        W = jacobian_basis(phi, [sympy.Symbol(name) for name in sys.state_names]).W
    Ws = _read_W(W, n)
    eps = _read_epsilon(epsilon)
    cap = None if max_order is None else int(exact_fraction(max_order, "max_order"))
    shaping = shape(sys.A, sys.C, Ws, max_order=cap)
    if not shaping.found:
        raise NotObservableError(f"output shaping: {shaping.message}", report=shaping)
    cf = canonical_form(shaping.A_e, shaping.C_e, shaping.W_e)
    if isinstance(poles, str):
        from uio_ring.design.noise import read_noise_options, search_poles

        if coefficients is not None:
            raise DomainError("give poles or coefficients, not both")
        alpha, crit = read_noise_options(sys, poles, rate, criterion)
        return search_poles(
            lambda pat: design_high_gain(sys, W=Ws, poles=[eps * p for p in pat], epsilon=eps, max_order=max_order,
                                         mu_bounds=mu_bounds, report=report),
            max(cf.q), rate=alpha, criterion=crit, model=lambda d: d.numeric())[1]
    if rate is not None or criterion is not None:
        raise DomainError("rate and criterion apply to poles='min-noise' only")
    coeffs = _chain_coefficients(cf.q, poles, coefficients)
    mus = None
    if mu_bounds is not None:
        mus = tuple(exact_fraction(m, f"mu_bounds[{k}]") for k, m in enumerate(mu_bounds))
        theorem1_bound(cf.q, coeffs, cf.Gamma_x, shaping.W_e, mus)  # validates the bounds
    f = shaping.filter
    return HighGainDesign(
        system=sys, W=Ws, epsilon=eps, coefficients=coeffs, q=cf.q,
        A_z=f.A_z, B_z=f.B_z, C_z=f.C_z, D_z=f.D_z, A_e=shaping.A_e, C_e=shaping.C_e, W_e=shaping.W_e,
        Gamma_x=cf.Gamma_x, Gamma_y=cf.Gamma_y, L=cf.L, K=_gain(cf, coeffs, eps), mu_bounds=mus,
        shaping=shaping, canonical=cf, applicability=report,
    )
