"""``DelayUIODesign``: the result of the Zheng–Bejarano design (Zheng et al. 2015), as named matrices.

The observer (21) with the corrected gains (22′) (docs/errata.md, Z1)::

    ξ' = L0 ξ + J(δ) Λ(δ) y + J_u(δ) u
    ẑ  = ξ + H(δ) Λ(δ) y + H_u(δ) u
    x̂  = T_L⁻¹(δ) ẑ

Built by :func:`uio_ring.design.zheng_bejarano.design_zheng_bejarano`; the
float model (:meth:`DelayUIODesign.numeric`) reads ``L0, J, H, Lam, T, T_left_inverse,
n_z, lag`` (and ``J_u, H_u`` for known inputs).

>>> from uio_ring import DelaySystem, design_zheng_bejarano
>>> des = design_zheng_bejarano(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None))
>>> des.n_z, des.lag, [F.shape for F in des.F_blocks()]
(2, 0, [(2, 2)])
"""

from __future__ import annotations

from dataclasses import dataclass, field
from fractions import Fraction
from typing import Any, ClassVar

from uio_ring.analysis.report import AssumptionsReport
from uio_ring.design.base import ObserverDesign, _text_size_above, matrix_outline, matrix_to_data
from uio_ring.ring.certificate import Certificate
from uio_ring.ring.matrix import PolyMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["DelayUIODesign", "guard_blocks_for", "krylov_matrix"]


def krylov_matrix(C_bar: PolyMatrix, A_bar: PolyMatrix, l: int) -> PolyMatrix:
    """``Ō_l = [C̄; C̄Ā; …; C̄Ā^{l−1}]`` (l ≥ 1), block by block: ``l − 1`` products
    ``r × n`` by ``n × n`` (each block's product is sized by its own degree and
    coefficients, cheaper than one product of the stacked blocks).

    >>> krylov_matrix(PolyMatrix("[[1, 0]]"), PolyMatrix("[[0, 1], [d, 0]]"), 3)
    PolyMatrix([[1, 0], [0, 1], [d, 0]])
    """
    blocks = [C_bar]
    for _ in range(l - 1):
        blocks.append(blocks[-1] @ A_bar)
    return PolyMatrix.vstack(*blocks)


def guard_blocks_for(sys: DelaySystem) -> int:
    """Blocks ``[0, M h]`` in which y, y' or y'' may jump at the multiples of h.

    x' jumps at 0 (history vs. dynamics), x^{(q)} at ``i h`` for ``i ≤ (q − 1) deg A``
    (plus the input degrees when w, u start at 0), and y = C(δ)x + D(δ)w + F(δ)u shifts
    them by up to ``max(deg C, deg D, deg F)``.  Beyond, y is C³ across block ends, where
    a centred cubic stencil keeps the local error O(dt⁵).

    >>> from uio_ring import DelaySystem
    >>> guard_blocks_for(DelaySystem("[[d]]", "[[1]]", "[[1]]", None))
    4
    """
    deg = {k: max(M.degree(), 0) for k, M in sys.matrices().items()}
    return (2 * deg.get("A", 0) + max(deg.get("B", 0), deg.get("E", 0))
            + max(deg.get("C", 0), deg.get("D", 0), deg.get("F", 0)) + 2)


# ----------------------------------------------------------------------------------------
#: ``str(design)`` outlines a matrix whose text would exceed about this many characters
#: (shape, degree, coefficient bits) instead of printing it.
TEXT_MATRIX_CHARS = 20_000


@dataclass(frozen=True, repr=False)
class DelayUIODesign(ObserverDesign):
    """The Zheng–Bejarano delay UIO: every matrix of Steps 1–5, named as in Zheng et al. (2015).

    Step 1: ``U M = [V; 0]`` (``M = [[CB, D], [D, 0]]``), ``Vbar V = [[B, 0], [D, 0]]``,
    ``W = [Vbar, 0] U = [K; Gamma] = [[K1, K2], [Gamma1, Gamma2]]``.
    Step 2: ``A_bar = A − K [CA; C]``, ``C_tilde = C − Gamma [CA; C]``,
    ``Lam C_tilde = [C_bar; 0]`` with ``r = rank C_tilde``.
    Step 3: ``O = Ō_{l*} = [C_bar; C_bar A_bar; …]`` left unimodular,
    ``[F_{l*}, …, F_1] = C_bar A_bar^{l*} O_left_inverse`` (16), ``F_stack = [F_1; …; F_{l*}]``
    (the paper's F; renamed so that ``F`` always means the system's known-input feed-through),
    ``T`` from (15) and ``T_left_inverse`` with ``T_left_inverse T = I``.
    Step 4: ``A0``, ``C0`` (14), ``Gamma{1,2}_bar = Lam Gamma{1,2} Lam⁻¹`` (11),
    ``K{1,2}_bar = T K{1,2} Lam⁻¹`` (20).
    Step 5: ``L0 = A0 − G0 C0`` and ``H``, ``J`` from (22′).

    ``n_z = r·l*`` is the observer order and ``lag`` the δ-degree of
    ``T_left_inverse``: ``x̂(t)`` estimates ``x(t)`` itself (not a past value)
    and is computed from ``ẑ`` over ``[t − lag·h, t]``, so it needs ``lag·h``
    of history.  ``poles`` are the
    ``l*`` requested eigenvalues of ``A0 − G0 C0`` on each of the ``r`` output
    channels; ``G0`` places them, and with ``poles="min-noise"`` may also couple the
    channels (a strictly block-triangular part: ``det(sI − L0)`` is unchanged, the
    certificate checks it).  ``choice`` says how U, Λ and the left inverses were chosen.
    """

    method: ClassVar[str] = "zheng-bejarano"
    #: ``Ō_{l*}`` is written to design files as derived: it is ``krylov_matrix(C_bar, A_bar,
    #: l_star)`` (the certificate's check (12) proves it), and by far the largest matrix
    #: (216 × 32 of δ-degree 23 with 1400-bit coefficients, 50 MB of text, for 32 states).
    derived_fields: ClassVar[dict[str, str]] = {"O": "[C̄; C̄Ā; …; C̄Ā^{l*−1}] from C_bar, A_bar and l_star"}

    system: DelaySystem
    U: PolyMatrix
    V: PolyMatrix
    Vbar: PolyMatrix
    W: PolyMatrix
    K: PolyMatrix
    Gamma: PolyMatrix
    K1: PolyMatrix
    K2: PolyMatrix
    Gamma1: PolyMatrix
    Gamma2: PolyMatrix
    A_bar: PolyMatrix
    C_tilde: PolyMatrix
    Lam: PolyMatrix
    Lam_inverse: PolyMatrix
    C_bar: PolyMatrix
    r: int
    l_star: int
    O: PolyMatrix
    O_left_inverse: PolyMatrix
    F_stack: PolyMatrix
    T: PolyMatrix
    T_left_inverse: PolyMatrix
    A0: PolyMatrix
    C0: PolyMatrix
    K1_bar: PolyMatrix
    K2_bar: PolyMatrix
    Gamma1_bar: PolyMatrix
    Gamma2_bar: PolyMatrix
    poles: tuple[Fraction, ...]
    G0: PolyMatrix
    L0: PolyMatrix
    H: PolyMatrix
    J: PolyMatrix
    H_u: PolyMatrix
    J_u: PolyMatrix
    choice: str = ""
    assumptions: AssumptionsReport | None = field(default=None, compare=False)

    @property
    def n_z(self) -> int:
        """Observer order ``r·l*`` (rows of ``T``)."""
        return self.T.rows

    @property
    def lag(self) -> int:
        """δ-degree of ``T_left_inverse``: ``x̂(t)`` uses ``ẑ`` up to ``lag·h`` in the past."""
        return max(0, self.T_left_inverse.degree())

    def F_blocks(self) -> tuple[PolyMatrix, ...]:
        """``(F_1, …, F_{l*})``, the ``r × r`` blocks of ``F_stack`` (F_1 on top)."""
        r = self.r
        return tuple(self.F_stack[i * r : (i + 1) * r, 0:r] for i in range(self.l_star))

    def certificate(self) -> Certificate:
        """Every identity of Steps 1–5 and Theorem 4, checked exactly (see
        :func:`uio_ring.verify.delay_uio_certificate`); computed once per design object."""
        from uio_ring.verify.delay_uio import delay_uio_certificate

        return self._memo("certificate", lambda: delay_uio_certificate(self))  # type: ignore[no-any-return]

    @classmethod
    def derive_field(cls, name: str, fields: dict[str, Any]) -> Any:
        """``O`` from ``C_bar``, ``A_bar`` and ``l_star`` (:func:`krylov_matrix`); the caller
        has checked their types.  The work is bounded before it is done: ``1 ≤ l_star ≤ n``
        (Cayley–Hamilton: the design's l* never exceeds n) and the δ-degree of Ō within the
        parser's bound (``ValueError`` otherwise).

        >>> des = DelayUIODesign.derive_field("O", {"C_bar": PolyMatrix("[[1, 0]]"),
        ...                                         "A_bar": PolyMatrix("[[0, 1], [d, 0]]"), "l_star": 2})
        >>> des
        PolyMatrix([[1, 0], [0, 1]])
        """
        if name != "O":
            raise KeyError(name)
        C_bar, A_bar, l_star = fields["C_bar"], fields["A_bar"], fields["l_star"]
        from uio_ring.ring.parse import MAX_DEGREE

        if not (C_bar.cols == A_bar.rows == A_bar.cols):
            raise ValueError(f"C_bar {C_bar.shape} and A_bar {A_bar.shape} do not make Ō_l*")
        if not 1 <= l_star <= max(A_bar.cols, 1):
            raise ValueError(f"l_star = {l_star} does not give Ō_l*: 1 ≤ l* ≤ n = {A_bar.cols}")
        if (l_star - 1) * max(A_bar.degree(), 0) + max(C_bar.degree(), 0) > MAX_DEGREE:
            raise ValueError(f"Ō would have δ-degree above {MAX_DEGREE}")
        return krylov_matrix(C_bar, A_bar, l_star)

    def numeric(self, *, h: Any = None) -> Any:
        """The float observer model (one :class:`~uio_ring.numeric.model.ObserverModel`):
        ``F = L0``, ``G_y = JΛ``, ``G_u = J_u``, ``D_y = HΛ``, ``D_u = H_u``, ``X = T_L⁻¹``.

        ``h`` is needed when the system has none (and the observer has delayed taps).
        Built once per design object and ``h`` (the model is a frozen dataclass).

        >>> from uio_ring import DelaySystem, design_zheng_bejarano
        >>> des = design_zheng_bejarano(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0], [0, 1]]", None))
        >>> des.numeric()
        ObserverModel(zheng-bejarano: n_z=2, n_y=2, n_u=0, n_x=2, n_w=0, lag=0)
        """
        from uio_ring.numeric.build import model_from_exact

        sys = self.system
        h = sys.h if h is None else h
        return self._memo(("numeric", h), lambda: model_from_exact(  # once per design and h
            F=self.L0, G_y=self.J @ self.Lam, G_u=self.J_u, D_y=self.H @ self.Lam, D_u=self.H_u,
            X=self.T_left_inverse, initial=self.T.eval(1), h=h,
            guard_blocks=guard_blocks_for(sys), z_of_x=self.T, method=self.method,
        ))

    # -- display and data -----------------------------------------------------------
    def __repr__(self) -> str:
        return (
            f"DelayUIODesign(n_z={self.n_z}, lag={self.lag}, r={self.r}, l_star={self.l_star}, "
            f"poles={[str(p) for p in self.poles]})"
        )

    def __str__(self) -> str:
        lines = [
            f"Zheng–Bejarano delay UIO: n_z = {self.n_z} (r = {self.r} channels × l* = {self.l_star}), "
            f"lag = {self.lag} (x̂(t) estimates x(t) from ẑ over the last {self.lag}·h)",
            f"  poles of A0 − G0 C0 on each channel: {[str(p) for p in self.poles]}",
            "  ξ' = L0 ξ + J Λ y" + (" + J_u u" if self.system.n_u else ""),
            "  ẑ  = ξ + H Λ y" + (" + H_u u" if self.system.n_u else ""),
            "  x̂  = T_L⁻¹ ẑ",
        ]
        for name in ("Lam", "L0", "H", "J", "T_left_inverse"):
            M = getattr(self, name)
            if _text_size_above(M, TEXT_MATRIX_CHARS):  # e.g. T_L⁻¹ of a 32-state design: 2 MB
                o = matrix_outline(M)
                lines.append(f"  {name}: {o['shape'][0]}×{o['shape'][1]}, δ-degree {o['degree']}, coefficients "
                             f"of up to {o['coefficient_bits']} bits: not shown (large); the exact matrix is "
                             f"the field {name} of the design file")
                continue
            lines.append(f"  {name} =\n    " + str(M).replace("\n", "\n    "))
        if self.choice:
            lines.append(f"  choice: {self.choice}")
        return "\n".join(lines)

    def to_latex(self) -> str:
        eqs = [
            r"\dot{\hat\xi} = L_0 \hat\xi + J(\delta)\Lambda(\delta) y"
            + (r" + J_u(\delta) u" if self.system.n_u else ""),
            r"\hat z = \hat\xi + H(\delta)\Lambda(\delta) y" + (r" + H_u(\delta) u" if self.system.n_u else ""),
            r"\hat x = T_L^{-1}(\delta)\hat z",
        ]
        mats = [
            (r"\Lambda", self.Lam),
            ("L_0", self.L0),
            ("H", self.H),
            ("J", self.J),
            (r"T_L^{-1}", self.T_left_inverse),
        ]
        body = r" \\ ".join(eqs) + r" \\ " + r" \\ ".join(f"{n} = {M.to_latex()}" for n, M in mats)
        return (
            r"\begin{gathered}"
            + rf"\text{{Zheng–Bejarano UIO: }} n_z = {self.n_z},\ \text{{lag}} = {self.lag} \\ "
            + body
            + r"\end{gathered}"
        )

    _MATRICES: ClassVar[tuple[str, ...]] = (
        "U", "V", "Vbar", "W", "K", "Gamma", "K1", "K2", "Gamma1", "Gamma2", "A_bar", "C_tilde",
        "Lam", "Lam_inverse", "C_bar", "O", "O_left_inverse", "F_stack", "T", "T_left_inverse", "A0",
        "C0", "K1_bar", "K2_bar", "Gamma1_bar", "Gamma2_bar", "G0", "L0", "H", "J", "H_u", "J_u",
    )

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {
            "method": self.method,
            "system": self.system.to_dict(),
            "r": self.r,
            "l_star": self.l_star,
            "n_z": self.n_z,
            "lag": self.lag,
            "poles": [str(p) for p in self.poles],
            "choice": self.choice,
        }
        out["matrices"] = {name: matrix_to_data(getattr(self, name)) for name in self._MATRICES}
        return out
