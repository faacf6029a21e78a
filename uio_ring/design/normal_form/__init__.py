"""The observer normal form of Niederwieser, Tranninger, Seeber & Reichhartinger (2022).

For a strongly observable delay-free system (package notation; the paper's
``D`` is our ``B``, its ``B`` our ``E``, its ``F`` our ``D``)::

    x' = A x + B w + E u,      y = C x + D w + F u

Section 4.1 constructs ``T`` (n×n) and ``Γ`` (p×p) such that ``x̄ = T⁻¹ x``,
``ȳ = Γ y`` are in the observer normal form (11)::

    x̄' = Ā x̄ + B̄ w + Ē u,   ȳ = C̄ x̄,
    Ā = T⁻¹ A T (11b),  B̄ = T⁻¹ B (11c),  C̄ = Γ C T (11d),  Ē = T⁻¹ E

p single-output chains of lengths ``μ_1 ≥ … ≥ μ_p`` (Σ μ = n), coupled only by
output injection (``Π̄``, the first column of each block) and by the
couplings ``β`` into the last rows of later chains.  The observer (13)–(14) is
one Levant robust exact differentiator per chain::

    x̂' = Ā x̂ + Ē u + Π̄ σ + l̄(σ),   σ = ȳ − C̄ x̂

It converges in finite time if ``|w_i| ≤ L_i`` and the gains satisfy (18).

* ``D ≠ 0`` (direct feed-through of w): the reduction of Appendix A.1 is applied
  first (``U D V = [[I, 0], [0, 0]]``; ``ỹ_0`` becomes a known input).
* ``reconstruct_input=True``: Section 5.4, the system augmented with ``χ = [x; w]``
  (then ``input_bounds`` bound ``|w'|``), so that the observer also estimates ``w``.

Modules, in the order of the algorithm: :mod:`.model` (the feed-through
reduction and the augmentation), :mod:`.step1` (Γ, Ξ, chain lengths),
:mod:`uio_ring.analysis.chain_basis` (Step 2: ``O_R``, ``t_{e_j}``),
:mod:`uio_ring.analysis.chain_couplings` (Step 3: β; ``T`` of (54), shared with the special
coordinate basis), :mod:`.step4` (``T`` and
the normal form), :mod:`.gains` (RED gains, (18)), :mod:`.design` (the design
object, with the table paper ↔ package), :mod:`.algorithm` (``design_normal_form``).

Everything is exact (rationals, :class:`~uio_ring.ring.QMatrix`): float64 rank
decisions gave structurally wrong normal forms on ill-conditioned systems in our
tests (docs/errata.md, N5).

>>> from uio_ring import DelaySystem
>>> sys = DelaySystem("[[0, 1], [-2, -3]]", "[[0], [1]]", "[[1, 0]]", None)
>>> des = design_normal_form(sys, [1])
>>> des.mu, des.A_bar, des.certificate().ok
((2,), PolyMatrix([[-3, 1], [-2, 0]]), True)
"""

from uio_ring.design.normal_form.algorithm import design_normal_form
from uio_ring.design.normal_form.design import NormalFormDesign
from uio_ring.design.normal_form.step1 import Step1Trace

__all__ = ["NormalFormDesign", "design_normal_form", "Step1Trace"]
