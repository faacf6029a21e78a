"""The model the normal form is computed for: feed-through reduction and input augmentation.

Paper 000 treats ``x' = A x + B w``, ``y = C x`` (package notation; the paper
writes D for our B).  A plant with known inputs and a feed-through of the
unknown input::

    x' = A x + B w + E u,      y = C x + D w + F u

is brought to that shape first:

* **augmentation** (Section 5.4, with ``reconstruct_input``): the state
  ``χ = [x; w]`` with ``A_χ = [[A, B], [0, 0]]``, ``B_χ = [0; I]``,
  ``C_χ = [C, D]``; the new unknown input is ``w'`` and there is no feed-through;
* **feed-through reduction** (Appendix A.1): regular ``U``, ``V`` with
  ``U D V = [[I_r, 0], [0, 0]]`` (``r = rank D``) split the outputs
  ``ỹ = U (y − F u) = [ỹ_0; ỹ_1]`` and the inputs ``V⁻¹ w = [w̃_0; w̃_1]``.  Then
  ``w̃_0 = ỹ_0 − C̃_0 x`` is known from the measurement, and the model is
  ``x' = (A − B̃_0 C̃_0) x + B̃_1 w̃_1 + [E, B̃_0] [u; ỹ_0]``, ``ỹ_1 = C̃_1 x``
  (redundant rows of ``C̃_1`` dropped).

>>> from uio_ring import DelaySystem
>>> m = reduced_model(DelaySystem("[[0, 1], [0, 0]]", "[[0], [1]]", "[[1, 0]]", "[[1]]"))
>>> m.A, m.B.shape, m.C.shape, m.E, m.rank_D
(QMatrix([[0, 1], [-1, 0]]), (2, 0), (0, 2), QMatrix([[0], [1]]), 1)
"""

from __future__ import annotations

from dataclasses import dataclass

from uio_ring.analysis.strong_observability import constant_matrices
from uio_ring.ring.qmatrix import QMatrix
from uio_ring.systems.delay_system import DelaySystem

__all__ = ["NormalFormModel", "FeedthroughSplit", "feedthrough_split", "reduced_model"]


@dataclass(frozen=True)
class FeedthroughSplit:
    """Regular ``U`` (p×p), ``V`` (m×m) with ``U D V = [[I_r, 0], [0, 0]]`` (A1), ``r = rank D``."""

    U: QMatrix
    V: QMatrix
    rank: int


@dataclass(frozen=True)
class NormalFormModel:
    """``x_m' = A x_m + B w_m + E ū``, ``ỹ_1 = C x_m``: what Steps 1–4 transform.

    Attributes
    ----------
    A, B, C, E
        The model's matrices: ``B`` its unknown input ``w_m`` (the paper's D),
        ``E`` its known inputs ``ū = [u; ỹ_0]`` (the paper's B).
    output_map
        ``ỹ_1 = output_map · [y; u]``.
    input_map
        ``ū = input_map · [y; u]``.
    state_map
        ``x = state_map · x_m``.
    w_map
        ``w = w_map · x_m`` with the augmentation, else ``None``.
    split
        The feed-through reduction ``U D V = [[I_r, 0], [0, 0]]``.
    w_transform
        ``w_m = w_transform · w`` (or ``· w'`` with the augmentation).
    """

    A: QMatrix
    B: QMatrix
    C: QMatrix
    E: QMatrix
    output_map: QMatrix
    input_map: QMatrix
    state_map: QMatrix
    w_map: QMatrix | None
    split: FeedthroughSplit
    w_transform: QMatrix

    @property
    def rank_D(self) -> int:
        """``rank D`` of the plant (the model's inputs ``ỹ_0`` count this many)."""
        return self.split.rank


def feedthrough_split(D: QMatrix) -> FeedthroughSplit:
    """``U``, ``V`` with ``U D V = [[I_r, 0], [0, 0]]`` (Appendix A, (A1)).

    ``V`` moves ``r`` independent columns ``D_J`` of ``D`` first and clears the
    others (``D V = [D_J, 0]``); ``U = [L; N]`` with ``L D_J = I_r`` and ``N`` a basis
    of the left null space of ``D_J``.

    >>> s = feedthrough_split(QMatrix([[1, 2], [2, 4]]))
    >>> s.rank, s.U @ QMatrix([[1, 2], [2, 4]]) @ s.V
    (1, QMatrix([[1, 0], [0, 0]]))
    """
    p, m = D.shape
    r = D.rank()
    if r == 0:
        return FeedthroughSplit(QMatrix.identity(p), QMatrix.identity(m), 0)
    J = list(D.T.row_basis())  # independent columns of D
    rest = [j for j in range(m) if j not in J]
    P = QMatrix.identity(m).take_cols(J + rest)  # D P = [D_J, D_rest]
    DJ, Dr = D.take_cols(J), D.take_cols(rest)
    R = list(DJ.row_basis())  # r independent rows of D_J
    DJR = DJ.take_rows(R)
    K = DJR.solve(Dr.take_rows(R), name="D") if rest else QMatrix.zeros(r, 0)  # D_rest = D_J K
    V = P @ QMatrix.block([[QMatrix.identity(r), -K], [QMatrix.zeros(m - r, r), QMatrix.identity(m - r)]])
    L = DJR.inverse(name="D") @ QMatrix.identity(p).take_rows(R)
    U = QMatrix.vstack(L, DJ.left_nullspace())
    return FeedthroughSplit(U, V, r)


def reduced_model(sys: DelaySystem, *, reconstruct_input: bool = False) -> NormalFormModel:
    """The model of a delay-free plant: augmentation (Section 5.4) when ``reconstruct_input``,
    then the feed-through reduction (Appendix A.1).

    Precondition: ``sys`` is delay-free (checked by ``constant_matrices``).
    """
    n, m, p, n_u = sys.n_x, sys.n_w, sys.n_y, sys.n_u
    Z, I = QMatrix.zeros, QMatrix.identity
    # χ = [x; w] (Section 5.4): the new unknown input is w'
    M = constant_matrices(sys.input_augmented() if reconstruct_input else sys)
    A, B, C, D, E, F = (M[k] for k in "ABCDEF")
    if reconstruct_input:
        state_map = QMatrix.hstack(I(n), Z(n, m))
        w_map: QMatrix | None = QMatrix.hstack(Z(m, n), I(m))
        n_m = n + m
    else:
        state_map, w_map, n_m = I(n), None, n
    split = feedthrough_split(D)
    U, V, r = split.U, split.V, split.rank
    # ỹ = U (y − F u) = [ỹ_0; ỹ_1],  B V = [B̃_0, B̃_1],  U C = [C̃_0; C̃_1]
    BV, UC = B @ V, U @ C
    B0, B1 = BV[:, :r], BV[:, r:]
    C0, C1 = UC[:r, :], UC[r:, :]
    Uyu = U @ QMatrix.hstack(I(p), -F)  # ỹ = Uyu [y; u]
    Y0, Y1 = Uyu[:r, :], Uyu[r:, :]
    # drop redundant rows of C̃_1 (they carry no information: ỹ_1 = C̃_1 x exactly)
    keep = C1.row_basis()
    u_part = QMatrix.hstack(Z(n_u, p), I(n_u))
    return NormalFormModel(
        A=A - B0 @ C0,
        B=B1,
        C=C1.take_rows(keep),
        E=QMatrix.hstack(E, B0, rows=n_m),
        output_map=Y1.take_rows(keep),
        input_map=QMatrix.vstack(u_part, Y0),
        state_map=state_map,
        w_map=w_map,
        split=split,
        w_transform=V.inverse(name="V")[r:, :],
    )
