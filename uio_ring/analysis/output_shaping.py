"""Dynamic output shaping (Grip & Saberi 2010, §5): a minimal-order output filter
that makes an inadmissible set (A, C, W_1, …, W_v) admissible.

The filter ``z' = A_z z + B_z y``, ``y_f = C_z z + D_z y`` gives the extended set
(filter states first, eqs. (18)–(19))::

    A_e = [[A_z, B_z C], [0, A]],  C_e = [C_z, D_z C],  W_ek = [[0, 0], [0, W_k]].

:func:`shape` is the paper's main algorithm, :func:`extend` its sub-algorithm.
When no filter exists the paper's loop never ends: :func:`shape` stops at a cap
on the filter order (or on the iterations) and says "no filter found within
order N" — it never claims the problem unsolvable.

The filter is also returned as a polynomial matrix: each ``extend`` step is
``G̃(s) = diag(s⁻¹ I_ℓ, I) M`` with M constant and invertible, so the whole
filter ``G(s) = C_z (sI − A_z)⁻¹ B_z + D_z`` has the polynomial inverse
``P(s) = G(s)⁻¹`` over Q[s] with ``det P = c·s^{n_f}`` (the paper's Remark 4).

>>> A = [[0, 1], [0, 0]]; C = [[1, 0]]
>>> r = shape(A, C, [[[0, 0], [0, 0]]])      # admissible: the identity filter
>>> r.found, r.order, r.iterations
(True, 0, 3)
"""

from __future__ import annotations

import html
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from uio_ring.analysis import _subspaces as sp
from uio_ring.analysis.admissibility import admissibility
from uio_ring.analysis.canonical_form import observability_indices_of
from uio_ring.errors import DimensionError, NotObservableError
from uio_ring.ring import constant as qc
from uio_ring.ring.certificate import Certificate, Check
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.ring.poly import Poly

__all__ = ["Filter", "ExtendStep", "ShapingStep", "ShapingResult", "extend", "shape", "extended_set"]

QMat = qc.QMat


# ----------------------------------------------------------------------------------------------- records


@dataclass(frozen=True)
class Filter:
    """A linear filter ``z' = A_z z + B_z y``, ``y_f = C_z z + D_z y`` (constant ``PolyMatrix``).

    ``order`` is the number of states.  :meth:`P` is the polynomial inverse of
    its transfer matrix (see :class:`ShapingResult`).
    """

    A_z: PolyMatrix
    B_z: PolyMatrix
    C_z: PolyMatrix
    D_z: PolyMatrix

    @property
    def order(self) -> int:
        return self.A_z.rows

    def to_dict(self) -> dict[str, Any]:
        return {k: [[str(x) for x in row] for row in getattr(self, k).tolist()] for k in ("A_z", "B_z", "C_z", "D_z")}


@dataclass(frozen=True)
class ExtendStep:
    """What one call of :func:`extend` computed (all exact).

    Attributes
    ----------
    m
        The level inspected.
    r, r_tilde
        ``rank R`` and ``rank R̃`` (R = [C̃; …; C̃ Ã^{m−2}], R̃ = [R; C̃ Ã^{m−1}]).
    S22, S31, S32
        The row compression: ``S22 C̃Ã^{m−1} = R̃*`` (full row rank) and
        ``S32 C̃Ã^{m−1} + S31 R = 0``, ``[S22; S32]`` nonsingular.
    E_sigma
        Basis (columns) of the smallest W̃-invariant subspace containing ker R̃.
    ell
        ``rank(R̃* E_σ)``: the order of the returned filter.
    T1, T2
        ``T1`` spans the left kernel of ``R̃* E_σ``; ``[T1; T2]`` nonsingular.
    M
        ``[𝓑; 𝓓]`` (p×p, invertible): the new outputs are ``diag(s⁻¹ I_ℓ, I) M y``.
    filter
        The returned filter (Ã_z, B̃_z, C̃_z, D̃_z).
    """

    m: int
    r: int
    r_tilde: int
    S22: PolyMatrix
    S31: PolyMatrix
    S32: PolyMatrix
    E_sigma: PolyMatrix
    ell: int
    T1: PolyMatrix
    T2: PolyMatrix
    M: PolyMatrix
    filter: Filter


@dataclass(frozen=True)
class ShapingStep:
    """One iteration of :func:`shape` that called ``extend``: level ``m``, order ``ell``
    of the filter it added, and the extended order ``n_e`` before the call."""

    iteration: int
    m: int
    ell: int
    n_e: int


@dataclass(frozen=True)
class ShapingResult:
    """Result of :func:`shape`.

    Attributes
    ----------
    found
        A filter was found (the extended set is admissible and observable).
    message
        One line: the filter order and iteration count, or "no filter found within order N".
    filter
        The cascaded filter (the filter found, or the last one when ``found`` is false).
    A_e, C_e, W_e
        The extended set of the filter (eqs. (18)–(19)).
    trace
        Every iteration that called ``extend`` (:class:`ShapingStep`), in order.
    steps
        The :class:`ExtendStep` of every iteration with ``ell > 0`` (the filter's factors).
    iterations
        The iteration at which the loop stopped (the paper counts the final
        termination test as an iteration: Example 1 stops "at iteration 8").
    max_order, max_iterations
        The caps used.
    """

    found: bool
    message: str
    filter: Filter
    A_e: PolyMatrix
    C_e: PolyMatrix
    W_e: tuple[PolyMatrix, ...]
    trace: tuple[ShapingStep, ...]
    steps: tuple[ExtendStep, ...]
    iterations: int
    max_order: int
    max_iterations: int

    @property
    def order(self) -> int:
        """Order of the filter (number of integrators added)."""
        return self.filter.order

    @property
    def ell_sequence(self) -> tuple[int, ...]:
        return tuple(s.ell for s in self.trace)

    @property
    def m_sequence(self) -> tuple[int, ...]:
        return tuple(s.m for s in self.trace)

    @property
    def P(self) -> PolyMatrix:
        """``P(s) = G(s)⁻¹`` over Q[s]: the product of ``M_j⁻¹ diag(s I_ℓ, I)`` over the steps."""
        p = self.filter.D_z.rows
        Pq = PolyMatrix.identity(p, var="s")
        for st in self.steps:
            Minv = qc.to_polymatrix(qc.qinverse(qc.qmat(st.M), "M"), "s")
            Pq = Pq @ Minv @ _delta(p, st.ell)
        return Pq

    @property
    def transfer(self) -> tuple[PolyMatrix, int]:
        """``(N(s), d)`` with ``G(s) = C_z (sI − A_z)⁻¹ B_z + D_z = N(s) / s^d``.

        ``A_z`` is nilpotent (every added state is an integrator), so
        ``G(s) = D_z + Σ_{j<n_f} C_z A_z^j B_z s^{−j−1}``; d is the smallest power
        that clears the denominators.
        """
        f = self.filter
        Az, Bz, Cz, Dz = (qc.qmat(f.A_z), qc.qmat(f.B_z), qc.qmat(f.C_z), qc.qmat(f.D_z))
        p = Dz.nrows()
        terms = [Dz]  # coefficient of s^{-j}
        Mk = Bz
        for _ in range(f.order):
            terms.append(Cz * Mk)
            Mk = Az * Mk
        while len(terms) > 1 and qc.is_qzero(terms[-1]):
            terms.pop()
        d = len(terms) - 1
        s = Poly.gen("s")
        N = PolyMatrix.zeros(p, p, "s")
        for j, T in enumerate(terms):
            N = N + qc.to_polymatrix(T, "s") * (s ** (d - j))
        return N, d

    def G_sympy(self) -> Any:
        """``G(s)`` as a sympy Matrix of rational functions (sympy is imported here)."""
        import sympy

        N, d = self.transfer
        return sympy.simplify(N.to_sympy() / sympy.Symbol("s") ** d)

    def certificate(self) -> Certificate:
        """Exact checks: the extended set is built from the filter (18)–(19); when
        ``found``, it is admissible and observable; ``P(s) G(s) = I``; ``det P = c·s^{n_f}``
        with ``c ≠ 0`` (Remark 4)."""
        checks: list[Check] = []

        def add(name: str, ok: bool, statement: str, residual: Any = None) -> None:
            checks.append(Check(name, bool(ok), None if ok else residual, statement))

        if self.found:
            adm = admissibility(self.A_e, self.C_e, self.W_e)
            add("extended set admissible", adm.holds, "W_ek 𝒮_i ⊂ 𝒮_i for all i, k", adm.reason)
            q = observability_indices_of(self.A_e, self.C_e)
            add("(A_e, C_e) observable", sum(q) == self.A_e.rows, "observability indices sum to n_e",
                f"indices {q}, n_e = {self.A_e.rows}")
        P = self.P
        N, d = self.transfer
        s = Poly.gen("s")
        r = P @ N - PolyMatrix.identity(P.rows, "s") * (s ** d)
        add("P(s) G(s) = I", r.is_zero(), "P(s) N(s) = s^d I with G = N / s^d", r)
        det = P.det()
        ok = det.degree() == self.order and all(c == 0 for c in det.coeffs()[:-1])
        add("det P = c·s^n_f", ok, f"det P(s) = c·s^{self.order} with c ≠ 0 (Remark 4)", det)
        return Certificate("output shaping (Grip & Saberi 2010)", checks)

    def __str__(self) -> str:
        return self.message

    def __repr__(self) -> str:
        return f"ShapingResult(found={self.found}, order={self.order}, iterations={self.iterations})"

    def _repr_html_(self) -> str:
        return html.escape(self.message)

    def to_dict(self) -> dict[str, Any]:
        return {
            "found": self.found, "message": self.message, "order": self.order, "iterations": self.iterations,
            "filter": self.filter.to_dict(),
            "trace": [{"iteration": s.iteration, "m": s.m, "ell": s.ell, "n_e": s.n_e} for s in self.trace],
            "P": [[str(x) for x in row] for row in self.P.tolist()],
        }


def _delta(p: int, ell: int) -> PolyMatrix:
    """``diag(s I_ℓ, I_{p−ℓ})`` over Q[s]."""
    return PolyMatrix.diag(*(["s"] * ell + [1] * (p - ell)), var="s")


# ----------------------------------------------------------------------------------------------- extend


def _pm(Q: QMat) -> PolyMatrix:
    return qc.to_polymatrix(Q)


def _row_compression(R: QMat, last: QMat) -> tuple[int, int, QMat, QMat, QMat]:
    """``r, r̃, S22, S31, S32`` of ``extend``'s step 2, greedy in natural row order.

    One echelon form of ``[R; last]ᵀ`` (last = C̃ Ã^{m−1}) picks the rows greedily:
    a row of ``last`` independent of the rows of ``R`` and of the rows of ``last``
    kept before it is kept (a unit row of ``S22``); a dependent row j, with
    ``last_j = a·R + b·kept`` read off the echelon form, gives the row ``e_j − b``
    of ``S32`` and ``−a`` of ``S31``.  ``r`` and ``r̃`` are the pivot counts.

    Precondition: ``R`` and ``last`` have the same number of columns (not checked).
    """
    p, n = last.nrows(), last.ncols()
    mR = R.nrows()
    E, piv = qc.rref(sp.vstack([R, last], n).transpose())
    pivots = list(piv)
    r = sum(1 for c in pivots if c < mR)
    s22: list[QMat] = []
    s31: list[QMat] = []
    s32: list[QMat] = []
    for j in range(p):
        col = mR + j
        if col in pivots:
            e = qc.qzeros(1, p)
            e[0, j] = 1
            s22.append(e)
            continue
        # column col of the echelon form: its coordinates on the pivot columns before it
        a = qc.qzeros(1, mR)
        b = qc.qzeros(1, p)
        b[0, j] = 1
        for k, c in enumerate(pivots):
            if c >= col:
                break
            if c < mR:
                a[0, c] = -E[k, col]
            else:
                b[0, c - mR] = -E[k, col]
        s31.append(a)
        s32.append(b)
    return r, len(pivots), sp.vstack(s22, p), sp.vstack(s31, mR), sp.vstack(s32, p)


def _row(M: QMat, i: int) -> QMat:
    out = qc.qzeros(1, M.ncols())
    for c in range(M.ncols()):
        out[0, c] = M[i, c]
    return out


def _invariant_closure(E0: QMat, Ws: Sequence[QMat]) -> QMat:
    """Basis of the smallest subspace containing im ``E0`` and invariant under every ``W``.

    Precondition: ``E0`` has independent columns (not checked).
    """
    E = E0
    # invariant: im E ⊂ the smallest invariant superspace of im E0
    while True:
        if E.ncols() == 0:
            return E
        F = sp.column_basis(sp.hstack([E] + [W * E for W in Ws], E.nrows()))
        if F.ncols() == E.ncols():
            return F
        E = F


def _completion(T1: QMat, size: int) -> QMat:
    """Unit rows ``e_j`` (j scanned from the last index down) that complete ``T1`` to a
    nonsingular matrix (the tie-break that reproduces the paper's (23)).

    Precondition: ``T1`` has independent rows and ``size`` columns (not checked).
    """
    rows: list[QMat] = []
    rank = T1.nrows()
    for j in reversed(range(size)):
        if rank == size:
            break
        e = qc.qzeros(1, size)
        e[0, j] = 1
        if qc.qrank(sp.vstack([T1, *rows, e], size)) > rank:
            rows.append(e)
            rank += 1
    rows.reverse()
    return sp.vstack(rows, size)


def extend(A: Any, C: Any, W: Sequence[Any], m: int) -> ExtendStep:
    """One step of output shaping: a filter of order ℓ that fixes level ``m``.

    Parameters
    ----------
    A, C, W
        The current *extended* set (Ã, C̃, W̃_k): constant rational, ñ×ñ, p×ñ, ñ×ñ.
    m
        The level inspected (≥ 1).

    Returns
    -------
    ExtendStep
        ``ell = 0`` and the identity filter when level m is fine; otherwise the
        filter ``Ã_z = 0_ℓ``, ``B̃_z = 𝓑``, ``C̃_z = [I_ℓ; 0]``, ``D̃_z = [0; 𝓓]``.

    Algorithm
    ---------
    Grip & Saberi (2010), algorithm ``extend`` and eq. (20).  S and T are not unique;
    the choices here (greedy rows in natural order for S, the echelon left kernel
    for T1, unit rows from the last index for T2) reproduce the paper's (23) and (24).

    Examples
    --------
    Example 1 at m = 1 gives the paper's filter (23):

    >>> A = [[0,1,0,0,0],[0,0,0,0,0],[0,0,0,1,0],[0,0,0,0,1],[0,0,0,0,0]]
    >>> C = [[1,0,0,0,0],[0,0,1,0,0]]
    >>> W1 = [[0,-1,0,1,0],[0,0,0,0,1],[0,-1,0,1,0],[1,0,0,0,1],[0,1,0,0,0]]
    >>> st = extend(A, C, [W1], 1)
    >>> st.ell, st.filter.B_z, st.filter.D_z
    (1, PolyMatrix([[0, 1]]), PolyMatrix([[0, 0], [-1, 1]]))
    """
    Aq, Cq, Ws = sp.read_triple(A, C, W)
    if not isinstance(m, int) or m < 1:
        raise DimensionError(f"m = {m!r}; expected an integer ≥ 1")
    return _extend(Aq, Cq, Ws, m).publish()


@dataclass(frozen=True)
class _RawStep:
    """What :func:`_extend` computed, as ``fmpq_mat`` (published as :class:`ExtendStep`
    only for the steps that are kept)."""

    m: int
    r: int
    r_tilde: int
    S22: QMat
    S31: QMat
    S32: QMat
    E_sigma: QMat
    ell: int
    T1: QMat
    T2: QMat
    M: QMat
    A_z: QMat
    B_z: QMat
    C_z: QMat
    D_z: QMat

    def publish(self) -> ExtendStep:
        filt = Filter(_pm(self.A_z), _pm(self.B_z), _pm(self.C_z), _pm(self.D_z))
        return ExtendStep(self.m, self.r, self.r_tilde, _pm(self.S22), _pm(self.S31), _pm(self.S32),
                          _pm(self.E_sigma), self.ell, _pm(self.T1), _pm(self.T2), _pm(self.M), filt)


def _extend(A: QMat, C: QMat, Ws: Sequence[QMat], m: int) -> _RawStep:
    """:func:`extend` on checked matrices.

    Precondition: shapes fit and ``m ≥ 1`` (not checked).
    """
    n, p = A.nrows(), C.nrows()
    R = sp.observability_stack(A, C, m - 1)
    last = C
    for _ in range(m - 1):
        last = last * A
    r, rt, S22, S31, S32 = _row_compression(R, last)
    Rstar = S22 * last
    E = _invariant_closure(sp.kernel(sp.vstack([R, last], n)), Ws)
    X = Rstar * E
    ell = qc.qrank(X)
    k = rt - r
    if ell == 0:
        return _RawStep(m, r, rt, S22, S31, S32, E, 0, qc.qidentity(k), qc.qzeros(0, k), qc.qidentity(p),
                        qc.qzeros(0, 0), qc.qzeros(0, p), qc.qzeros(p, 0), qc.qidentity(p))
    T1 = sp.kernel(X.transpose()).transpose()  # echelon basis of the left kernel
    T2 = _completion(T1, k)
    Bcal = T2 * S22
    Dcal = sp.vstack([S32, T1 * S22], p)
    M = sp.vstack([Bcal, Dcal], p)
    Cz = sp.vstack([qc.qidentity(ell), qc.qzeros(p - ell, ell)], ell)
    Dz = sp.vstack([qc.qzeros(ell, p), Dcal], p)
    return _RawStep(m, r, rt, S22, S31, S32, E, ell, T1, T2, M, qc.qzeros(ell, ell), Bcal, Cz, Dz)


# ----------------------------------------------------------------------------------------------- shape


def _extended(A: QMat, C: QMat, Ws: Sequence[QMat], Az: QMat, Bz: QMat, Cz: QMat, Dz: QMat,
              ) -> tuple[QMat, QMat, tuple[QMat, ...]]:
    """Eqs. (18)–(19).  Precondition: shapes fit (not checked)."""
    nf, n = Az.nrows(), A.nrows()
    Ae = sp.vstack([sp.hstack([Az, Bz * C], nf), sp.hstack([qc.qzeros(n, nf), A], n)], nf + n)
    Ce = sp.hstack([Cz, Dz * C], C.nrows())
    We = tuple(sp.vstack([qc.qzeros(nf, nf + n), sp.hstack([qc.qzeros(n, nf), W], n)], nf + n) for W in Ws)
    return Ae, Ce, We


def extended_set(A: Any, C: Any, W: Sequence[Any], filt: Filter) -> tuple[PolyMatrix, PolyMatrix,
                                                                          tuple[PolyMatrix, ...]]:
    """``(A_e, C_e, (W_e1, …))`` of eqs. (18)–(19) for a filter (its states first).

    >>> f = Filter(PolyMatrix("[[0]]"), PolyMatrix("[[1]]"), PolyMatrix("[[1]]"), PolyMatrix("[[0]]"))
    >>> extended_set([[0]], [[1]], [], f)[:2]
    (PolyMatrix([[0, 1], [0, 0]]), PolyMatrix([[1, 0]]))
    """
    Aq, Cq, Ws = sp.read_triple(A, C, W)
    Ae, Ce, We = _extended(Aq, Cq, Ws, *(qc.qmat(M) for M in (filt.A_z, filt.B_z, filt.C_z, filt.D_z)))
    return _pm(Ae), _pm(Ce), tuple(_pm(W) for W in We)


def shape(A: Any, C: Any, W: Sequence[Any], *, max_order: int | None = None,
          max_iterations: int | None = None) -> ShapingResult:
    """A minimal-order output filter that makes (A, C, W) admissible, or "none within the cap".

    Parameters
    ----------
    A, C, W
        n×n, p×n and the ``W_k`` (n×n), constant rational; (A, C) observable
        with ``rank C = p`` (Problem 1 asks for an observable extended pair).
    max_order
        Stop when the filter order would exceed this (default ``n``).
    max_iterations
        Stop after this many iterations (default ``(N + 1)(n + N + 1) + 1`` with
        N = ``max_order``: enough for every filter of order ≤ N to be found).

    Returns
    -------
    ShapingResult
        ``found``, ``message``, the filter, the extended set, the trace of
        (m, ℓ) per iteration, ``P(s)`` and a certificate.

    Raises
    ------
    NotObservableError
        ``rank C < p`` or (A, C) not observable (no filter can help).
    DimensionError
        Shapes that do not fit.

    Algorithm
    ---------
    Grip & Saberi (2010), algorithm ``shape``: start with the identity filter and
    m = 1; at each iteration build (A_e, C_e, W_e); stop successfully when
    m = n_e + 1 (before calling ``extend``); otherwise call ``extend`` at level m,
    set m ← m + 1 when ℓ = 0 and m ← 1 otherwise, and cascade the new filter
    after the old one with its states first (Remark 5).  Theorem 3: when a
    filter of order N exists the loop ends with one of order ≤ N.  The paper has
    no stopping rule when none exists; the caps are ours.

    Examples
    --------
    Example 2 of the paper: the filter integrates y_1 twice (order 2, iteration 11):

    >>> A = [[0,1,0,0,0],[0,0,0,0,0],[0,0,0,1,0],[0,0,0,0,1],[0,0,0,0,0]]
    >>> C = [[1,0,0,0,0],[0,0,1,0,0]]
    >>> W1 = [[0,0,0,0,1]] + [[0] * 5] * 4
    >>> r = shape(A, C, [W1])
    >>> r.found, r.order, r.iterations, r.ell_sequence
    (True, 2, 11, (1, 0, 1, 0, 0, 0, 0, 0, 0, 0))
    >>> r.P, r.certificate().ok
    (PolyMatrix([[s**2, 0], [0, 1]]), True)
    """
    Aq, Cq, Ws = sp.read_triple(A, C, W)
    n, p = Aq.nrows(), Cq.nrows()
    if qc.qrank(Cq) < p:
        raise NotObservableError(f"C has rank {qc.qrank(Cq)} < {p} rows; output shaping needs a full-row-rank C "
                                 "(remove the dependent outputs)")
    if sum(observability_indices_of(Aq, Cq)) < n:
        raise NotObservableError("(A, C) is not observable; output shaping needs an observable pair "
                                 "(no filter on y can make it observable)")
    N = n if max_order is None else int(max_order)
    cap = (N + 1) * (n + N + 1) + 1 if max_iterations is None else int(max_iterations)
    Az, Bz, Cz, Dz = qc.qzeros(0, 0), qc.qzeros(0, p), qc.qzeros(p, 0), qc.qidentity(p)
    m = 1
    trace: list[ShapingStep] = []
    steps: list[_RawStep] = []
    found = False
    message = ""
    iteration = 0
    Ae, Ce, We = _extended(Aq, Cq, Ws, Az, Bz, Cz, Dz)
    # invariant (Lemma 2): at the top of the loop, 𝒮_i(A_e, C_e) is W_e-invariant for all i ≤ m − 1;
    # (A_e, C_e, W_e) is the extended set of the current filter (rebuilt only when it grows)
    while True:
        iteration += 1
        ne = Ae.nrows()
        if m == ne + 1:
            found = True
            message = (f"filter of order {Az.nrows()} found at iteration {iteration} "
                       f"(extended order {ne}, m = {m})")
            break
        if iteration > cap:
            iteration -= 1
            message = (f"no filter found within {cap} iterations (filter order so far {Az.nrows()}); "
                       "the paper's algorithm has no stopping rule — this is not a proof that none exists")
            break
        st = _extend(Ae, Ce, We, m)
        trace.append(ShapingStep(iteration, m, st.ell, ne))
        if st.ell == 0:
            m += 1
            continue
        if Az.nrows() + st.ell > N:
            message = (f"no filter found within order {N} (iteration {iteration} would raise the order to "
                       f"{Az.nrows() + st.ell}); the paper's algorithm has no stopping rule — this is not a proof "
                       "that none exists")
            break
        steps.append(st)
        m = 1
        tAz, tBz, tCz, tDz = st.A_z, st.B_z, st.C_z, st.D_z
        ell, nf = tAz.nrows(), Az.nrows()
        Az = sp.vstack([sp.hstack([tAz, tBz * Cz], ell), sp.hstack([qc.qzeros(nf, ell), Az], nf)], ell + nf)
        Bz = sp.vstack([tBz * Dz, Bz], p)
        Cz = sp.hstack([tCz, tDz * Cz], p)
        Dz = tDz * Dz
        Ae, Ce, We = _extended(Aq, Cq, Ws, Az, Bz, Cz, Dz)
    filt = Filter(_pm(Az), _pm(Bz), _pm(Cz), _pm(Dz))
    return ShapingResult(found, message, filt, _pm(Ae), _pm(Ce), tuple(_pm(W) for W in We), tuple(trace),
                         tuple(st.publish() for st in steps), iteration, N, cap)
