"""The special coordinate basis (SCB) of a delay-free system, exactly over Q.

For ``x' = A x + B w``, ``y = C x + D w`` (δ-degree 0, ``w`` unknown) the SCB
of Sannuti & Saberi (1987) (Chen, Lin & Shamash 2004, Thm. 5.4.1; the form
used by Tranninger et al. 2021, Prop. 2) is a triple of nonsingular
transformations, new → old::

    x = Ts x̄,   w = Ti w̄,   y = To ȳ
    x̄ = [x_a; x_b; x_c; x_d],   w̄ = [w_0; w_d; w_c],   ȳ = [y_0; y_d; y_b]

in which ``Ā − B̄_0 C̄_0`` has the block pattern (17a) and ``C̄``, ``D̄`` the
pattern (17b): ``x_a`` the zero dynamics (the eigenvalues of ``A_a`` are the
invariant zeros), ``x_b`` observable chains reached by no input, ``x_c`` the
part that makes the system not left invertible, ``x_d`` integrator chains of
lengths ``q_1 ≥ … ≥ q_{m_d}`` from ``w_d`` to ``y_d`` (the infinite zeros).

**Algorithm** (ours, exact; no step decides a rank in floating point).  The
literature's constructive algorithms (Sannuti & Saberi 1987; the numerically
stable one of Chu, Liu & Tan 2002 behind the Linear Systems Toolkit) use
orthogonal transformations, which leave Q (the paper's example needs √15 and
√10).  Any nonsingular rational ``Ts, Ti, To`` giving the pattern is an SCB and
the structural invariants do not depend on the choice, so we build one from
the geometric characterisation, every step a rational linear solve:

1. *Feed-through* (``m_0 = rank D``): ``To⁻¹ D Ti = [[I, 0], [0, 0]]``; with
   ``w_0 = y_0 − C_0 x`` the rest is the strictly proper ``(A − B_0 C_0, B_1, C_1)``.
2. *Zero dynamics*: ``V*`` (weakly unobservable subspace) is ``X_a`` when the
   system is left invertible; ``A T_a = T_a A_a + B G`` defines ``A_a``.
3. *Infinite-zero chains* (columns of ``X_d = S*``): chains grown from the input
   directions, ``t_{k−1} = A t_k − B f``, kept in ``ker C`` until their images
   ``C t`` become independent of the images of the chains already closed —
   the dual of Silverman's structure algorithm (:func:`input_chains`).
4. *Observable chains* (rows of ``X_b``): the functionals annihilating
   ``V* + S*`` carry an observable pair; its Brunovsky observer form with
   output injection is :func:`~uio_ring.analysis.canonical_form.canonical_form`
   (the same construction as the high-gain method's).
5. *Rows of x_a and x_d*: ``x_d`` rows from the ``y_d`` functionals by
   ``φ_{k+1} = φ_k A − h y_d`` with ``h`` chosen so that ``Φ_d T_d = I``;
   ``x_a`` rows corrected by a triangular recursion along the b chains so that
   ``x_a'`` sees ``x_b`` only through ``y_b`` (:func:`zero_dynamics_rows`).

``Ts⁻¹`` is then these rows; every identity of (17a)–(23) and Lemma 3 is
re-checked exactly by :meth:`SpecialCoordinateBasis.verify`.

6. *Not left invertible* (``n_c = dim R* > 0``, :func:`~uio_ring.analysis.scb_steps.controllable_part_scb`):
   ``X_c = R*``, a controllability subspace in ``ker C``; with a friend ``K``
   the quotient by ``R*``, driven by the inputs that do not point into ``R*``,
   is left invertible and gets steps 2–5; its columns are lifted by ``R*``
   components solving triangular recursions (and one Sylvester equation for
   ``x_a``) so that ``x_c'`` sees the other parts only as (17a) allows.  No
   unknown-input observer exists for such systems; the basis shows why.

>>> from uio_ring import DelaySystem
>>> scb = special_coordinate_basis(DelaySystem("[[0, 1, 0], [0, 0, 1], [-1, -2, -3]]",
...                                            "[[0], [0], [1]]", "[[1, 0, 0]]", None))
>>> (scb.n_a, scb.n_b, scb.n_c, scb.n_d), scb.q, scb.verify().ok
((0, 0, 0, 3), (3,), True)
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property
from typing import Any

from uio_ring.analysis.report import _matrix_str
from uio_ring.analysis.scb_steps import (
    NotLeftInvertibleError,
    SCBDimensions,
    chain_ends,
    chain_starts,
    controllable_part_scb,
    intersection,
    left_invertible_scb,
    left_solve,
    reduce_system,
    selector,
    shift_matrix,
)
from uio_ring.ring.certificate import Certificate
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.matrix import Poly, PolyMatrix
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = [
    "SpecialCoordinateBasis",
    "special_coordinate_basis",
    "SCBDimensions",
    "scb_dimensions",
    "NotLeftInvertibleError",
]

Q = QMatrix


@dataclass(frozen=True)
class SpecialCoordinateBasis:
    """The special coordinate basis of a left-invertible delay-free system (exact).

    Orderings: ``x̄ = [x_a; x_b; x_c; x_d]``, ``w̄ = [w_0; w_d; w_c]``, ``ȳ = [y_0; y_d; y_b]``;
    ``x = Ts x̄``, ``w = Ti w̄``, ``y = To ȳ``.  ``x_c`` (and ``w_c``) exist only when the system is
    not left invertible (``n_c > 0``; then no unknown-input observer exists).  (17a) for ``x_c``:
    ``x_c' = B_c F_ca x_a + H_cb y_b + A_c x_c + H_cd y_d + B_c w_c`` (+ ``B_0c y_0``).

    Attributes
    ----------
    Ts, Ti, To
        Nonsingular rational transformations (new → old).
    A_bar, B_bar, C_bar, D_bar
        ``Ts⁻¹ A Ts``, ``Ts⁻¹ B Ti``, ``To⁻¹ C Ts``, ``To⁻¹ D Ti``.
    n_a, n_b, n_c, n_d, m_0, m_d, p_b
        Block sizes.
    q
        Lengths of the ``x_d`` chains (infinite-zero orders), non-increasing.
    l
        Lengths of the ``x_b`` chains (observability indices of ``(A_b, C_b)``), non-increasing.
    A_a, A_b, A_d, B_d, C_b, C_d
        Diagonal blocks; ``A_b = A_b* + H_bb C_b``, ``A_d = A_d* + B_d F_dd + H_dd C_d``.
    H_ab, H_ad, H_bb, H_bd, H_dd, F_da, F_db, F_dd
        Couplings of (17a), with the chain-start columns in the ``H`` blocks.
    B_0, C_0
        ``B̄_0`` (n×m_0) and ``C̄_0`` (m_0×n): the feed-through, ``Ā = Ā_s + B̄_0 C̄_0``.
    system
        The analysed system.
    """

    system: DelaySystem
    Ts: PolyMatrix
    Ti: PolyMatrix
    To: PolyMatrix
    A_bar: PolyMatrix
    B_bar: PolyMatrix
    C_bar: PolyMatrix
    D_bar: PolyMatrix
    n_a: int
    m_0: int
    q: tuple[int, ...]
    l: tuple[int, ...]
    n_c: int = 0

    # -- sizes ---------------------------------------------------------------------------------
    @property
    def n_b(self) -> int:
        return sum(self.l)

    @property
    def n_d(self) -> int:
        return sum(self.q)

    @property
    def m_d(self) -> int:
        return len(self.q)

    @property
    def p_b(self) -> int:
        return len(self.l)

    @property
    def dimensions(self) -> SCBDimensions:
        return SCBDimensions(self.n_a, self.n_b, self.n_c, self.n_d, self.m_0)

    def _idx(self, part: str) -> list[int]:
        start = {"a": 0, "b": self.n_a, "c": self.n_a + self.n_b, "d": self.n_a + self.n_b + self.n_c}[part]
        size = {"a": self.n_a, "b": self.n_b, "c": self.n_c, "d": self.n_d}[part]
        return list(range(start, start + size))

    @property
    def m_c(self) -> int:
        """Number of unknown inputs ``w_c`` (the part that makes the system not left invertible)."""
        return self.system.n_w - self.m_0 - self.m_d

    def _q(self, M: PolyMatrix) -> QMatrix:
        return Q(M)

    @cached_property
    def A_s(self) -> PolyMatrix:
        """``Ā_s = Ā − B̄_0 C̄_0``: the state matrix with the feed-through eliminated (17a)."""
        return (self._q(self.A_bar) - Q(self.B_0) @ Q(self.C_0)).to_polymatrix()

    @property
    def B_0(self) -> PolyMatrix:
        return self._q(self.B_bar).take_cols(range(self.m_0)).to_polymatrix()

    @property
    def C_0(self) -> PolyMatrix:
        return self._q(self.C_bar).take_rows(range(self.m_0)).to_polymatrix()

    def _block(self, rows: Sequence[int], cols: Sequence[int]) -> PolyMatrix:
        return Q(self.A_s).take_rows(rows).take_cols(cols).to_polymatrix()

    @property
    def A_a(self) -> PolyMatrix:
        return self._block(self._idx("a"), self._idx("a"))

    @property
    def A_b(self) -> PolyMatrix:
        return self._block(self._idx("b"), self._idx("b"))

    @property
    def A_d(self) -> PolyMatrix:
        return self._block(self._idx("d"), self._idx("d"))

    @property
    def B_d(self) -> PolyMatrix:
        return selector(self.q, at_end=True).to_polymatrix()

    @property
    def C_d(self) -> PolyMatrix:
        return selector(self.q, at_end=False).to_polymatrix()

    @property
    def C_b(self) -> PolyMatrix:
        return selector(self.l, at_end=False).to_polymatrix()

    def _starts(self, part: str) -> list[int]:
        return chain_starts(self.q if part == "d" else self.l, self._idx(part)[0] if self._idx(part) else 0)

    def _ends(self, part: str) -> list[int]:
        return chain_ends(self.q, self._idx("d")[0] if self.n_d else 0)

    @property
    def H_ab(self) -> PolyMatrix:
        return self._block(self._idx("a"), self._starts("b"))

    @property
    def H_ad(self) -> PolyMatrix:
        return self._block(self._idx("a"), self._starts("d"))

    @property
    def H_bd(self) -> PolyMatrix:
        return self._block(self._idx("b"), self._starts("d"))

    @property
    def H_bb(self) -> PolyMatrix:
        return self._block(self._idx("b"), self._starts("b"))

    @property
    def H_dd(self) -> PolyMatrix:
        d0 = self.n_a + self.n_b + self.n_c
        return (Q(self._block(self._idx("d"), self._starts("d"))) - shift_matrix(self.q).take_cols(
            [s - d0 for s in self._starts("d")])).to_polymatrix()

    @property
    def F_da(self) -> PolyMatrix:
        return self._block(self._ends("d"), self._idx("a"))

    @property
    def F_db(self) -> PolyMatrix:
        return self._block(self._ends("d"), self._idx("b"))

    @property
    def F_dd(self) -> PolyMatrix:
        """Rows of ``A_d − A_d* − H_dd C_d`` at the chain ends (zero in the chain-start columns)."""
        rest = Q(self.A_d) - shift_matrix(self.q) - Q(self.H_dd) @ selector(self.q, at_end=False)
        d0 = self.n_a + self.n_b + self.n_c
        return rest.take_rows([e - d0 for e in self._ends("d")]).to_polymatrix()

    @property
    def A_c(self) -> PolyMatrix:
        return self._block(self._idx("c"), self._idx("c"))

    @property
    def B_c(self) -> PolyMatrix:
        """``B̄`` rows of ``x_c``, columns of ``w_c``."""
        return Q(self.B_bar).take_rows(self._idx("c")).take_cols(
            range(self.m_0 + self.m_d, self.m_0 + self.m_d + self.m_c)).to_polymatrix()

    @property
    def H_cb(self) -> PolyMatrix:
        return self._block(self._idx("c"), self._starts("b"))

    @property
    def H_cd(self) -> PolyMatrix:
        return self._block(self._idx("c"), self._starts("d"))

    @property
    def F_ca(self) -> PolyMatrix:
        """``F_ca`` with ``B_c F_ca`` the ``x_a`` columns of the ``x_c`` rows."""
        if not self.n_c or not self.n_a:
            return PolyMatrix.zeros(self.m_c, self.n_a)
        # B_c F_ca = Ā_s[c, a]: a right solve (B_c has full column rank); UioRingError if there is none
        return left_solve(Q(self.B_c).T, Q(self._block(self._idx("c"), self._idx("a"))).T, "B_c F_ca").T.to_polymatrix()

    @property
    def F_dc(self) -> PolyMatrix:
        return self._block(self._ends("d"), self._idx("c"))

    @property
    def invariant_zero_polynomial(self) -> Poly:
        """``det(s I − A_a)``: its roots are the invariant zeros (Lemma 3 (p.2))."""
        return charpoly(Q(self.A_a))

    # -- display -------------------------------------------------------------------------------
    def __str__(self) -> str:
        lines = [
            "special coordinate basis (Sannuti & Saberi 1987; exact over Q)",
            f"  (n_a, n_b, n_c, n_d) = ({self.n_a}, {self.n_b}, {self.n_c}, {self.n_d}); "
            f"m_0 = {self.m_0}, m_d = {self.m_d}, p_b = {self.p_b}",
            f"  infinite-zero chains q = {self.q}; observable chains l = {self.l}",
            f"  invariant-zero polynomial det(sI − A_a) = {self.invariant_zero_polynomial}",
        ]
        if self.n_a:
            lines.append("  A_a =\n" + _matrix_str(self.A_a))
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        import html

        return "<pre>" + html.escape(str(self)) + "</pre>"

    def to_dict(self) -> dict[str, Any]:
        return {
            "n_a": self.n_a, "n_b": self.n_b, "n_c": self.n_c, "n_d": self.n_d,
            "m_0": self.m_0, "m_d": self.m_d, "p_b": self.p_b, "q": list(self.q), "l": list(self.l),
            "invariant_zero_polynomial": str(self.invariant_zero_polynomial),
            "Ts": str(self.Ts), "Ti": str(self.Ti), "To": str(self.To),
        }

    def verify(self) -> Certificate:
        """Exact checks of (17a)–(23) and Lemma 3 (p.1)–(p.7); see :func:`scb_certificate`."""
        from uio_ring.analysis.scb_certificate import scb_certificate

        return scb_certificate(self)


def scb_dimensions(sys: DelaySystem) -> SCBDimensions:
    """``(n_a, n_b, n_c, n_d, m_0)`` of a delay-free system, also when it is not left invertible.

    >>> from uio_ring import DelaySystem
    >>> scb_dimensions(DelaySystem("[[0, 1], [0, 0]]", "[[1, 0], [0, 1]]", "[[1, 0]]", None))
    SCBDimensions(n_a=0, n_b=0, n_c=1, n_d=1, m_0=0)
    """
    return reduce_system(sys).dims


def special_coordinate_basis(sys: DelaySystem) -> SpecialCoordinateBasis:
    """The special coordinate basis of a delay-free system, exactly over Q.

    Parameters
    ----------
    sys
        δ-degree 0, independent unknown-input columns (``rank [B; D] = n_w``) and
        outputs (``rank [C, D] = n_y``); known inputs play no part.

    Returns
    -------
    SpecialCoordinateBasis
        ``Ts, Ti, To``, the transformed matrices, the sizes, the chain lengths
        ``q`` and ``l`` and the blocks of (17a)–(23); ``.verify()`` checks them.

    Raises
    ------
    DomainError
        A matrix depends on δ.
    DimensionError
        Dependent unknown-input columns or outputs.

    Algorithm
    ---------
    Steps 1–5 of the module docstring: the feed-through split, ``V*`` and ``S*`` by
    their recursions, input chains grown in ``ker C`` (dual Silverman structure
    algorithm), the Brunovsky observer form of the functionals vanishing on
    ``V* + S*`` (:func:`~uio_ring.analysis.canonical_form.canonical_form`) and the
    rows of ``x_a``, ``x_d`` by triangular recursions.  All exact linear algebra over Q.

    Examples
    --------
    A double integrator ``y = x_2``, ``x_3' = w`` driving ``x_1' = −2 x_1 + x_2``, which
    ``y`` does not see: a zero at −2 (``x_a``) and one chain of length 2 (``x_d``):

    >>> from uio_ring import DelaySystem
    >>> sys = DelaySystem("[[-2, 1, 0], [0, 0, 1], [0, 0, 0]]", "[[0], [0], [1]]", "[[0, 1, 0]]", None)
    >>> scb = special_coordinate_basis(sys)
    >>> (scb.n_a, scb.n_b, scb.n_d), scb.q, scb.l, scb.invariant_zero_polynomial
    ((1, 0, 2), (2,), (), s + 2)
    """
    red = reduce_system(sys)
    ft = red.ft
    A, B1, C1 = ft.A_star, ft.B1, ft.C1
    if red.dims.n_c:
        core = controllable_part_scb(A, B1, C1, intersection(red.V, red.S))
    else:
        core = left_invertible_scb(A, B1, C1, red.V)
    Ts, Ti1, To1 = core.Ts, core.Ti, core.To
    m0 = ft.m0
    p, m = red.D.shape
    Ti = ft.Ti0 @ Q.block([[Q.identity(m0), Q.zeros(m0, m - m0)], [Q.zeros(m - m0, m0), Ti1]]) if m else Q.zeros(0, 0)
    To = ft.To0 @ Q.block([[Q.identity(m0), Q.zeros(m0, p - m0)], [Q.zeros(p - m0, m0), To1]]) if p else Q.zeros(0, 0)
    Tsi = Ts.inverse(name="Ts")
    Toi = To.inverse(name="To") if p else To
    return SpecialCoordinateBasis(
        system=sys,
        Ts=Ts.to_polymatrix(), Ti=Ti.to_polymatrix(), To=To.to_polymatrix(),
        A_bar=(Tsi @ red.A @ Ts).to_polymatrix(),
        B_bar=(Tsi @ red.B @ Ti).to_polymatrix(),
        C_bar=(Toi @ red.C @ Ts).to_polymatrix(),
        D_bar=(Toi @ red.D @ Ti).to_polymatrix(),
        n_a=core.n_a, m_0=m0, q=core.q, l=core.l, n_c=core.n_c,
    )
