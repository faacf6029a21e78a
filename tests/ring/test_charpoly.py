"""charpoly against det(sI − M) computed as a polynomial determinant by the ring, Cayley–Hamilton
(p(M) = 0), and flint's fmpq_mat.charpoly of the whole matrix on hidden block triangular ones;
strong_components against plain reachability."""

from __future__ import annotations

from fractions import Fraction

import flint
from hypothesis import given
from hypothesis import strategies as st

from uio_ring.ring import PolyMatrix
from uio_ring.ring.charpoly import charpoly, strong_components
from uio_ring.ring.matrix import Poly

from .strategies import dense_matrices


@given(dense_matrices(min_rows=1, max_rows=5, max_degree=0).filter(lambda M: M.rows == M.cols)
       | dense_matrices(rows=3, cols=3, max_degree=0))
def test_charpoly_is_det_of_s_minus_m_and_annihilates(M):
    n = M.rows
    s = Poly.gen("s")
    coeffs = M.coefficient_lists()[0]
    sI_M = PolyMatrix([[(s if i == j else Poly(0, "s")) - Poly(coeffs[i][j], "s") for j in range(n)]
                       for i in range(n)], var="s")
    p = charpoly(M)
    assert p == sI_M.det() and p.degree() == n and p.lc() == 1
    acc = PolyMatrix.zeros(n, n)
    for c in reversed(p.coeffs()):  # Horner: p(M) = 0
        acc = acc @ M + c * PolyMatrix.identity(n)
    assert acc.is_zero()


# --- block triangular form by strong components -------------------------------------------

def _reach(n, succ):
    """reach[i] = the vertices reachable from i (i included), by plain search."""
    out = []
    for i in range(n):
        seen, todo = {i}, [i]
        while todo:
            for w in succ[todo.pop()]:
                if w not in seen:
                    seen.add(w)
                    todo.append(w)
        out.append(seen)
    return out


@st.composite
def _digraphs(draw):
    n = draw(st.integers(0, 12))
    succ = [sorted(set(draw(st.lists(st.integers(0, n - 1), max_size=3)))) if n else [] for _ in range(n)]
    return n, succ


@given(_digraphs())
def test_strong_components_against_reachability(graph):
    """Two vertices share a component iff each reaches the other; a component comes after
    every component it has an edge to (Tarjan's reverse topological order)."""
    n, succ = graph
    comps = strong_components(n, succ)
    assert sorted(v for c in comps for v in c) == list(range(n)) and all(c == sorted(c) for c in comps)
    where = {v: k for k, c in enumerate(comps) for v in c}
    reach = _reach(n, succ)
    for i in range(n):
        for j in range(n):
            assert (where[i] == where[j]) == (j in reach[i] and i in reach[j])
            if j in succ[i]:
                assert where[j] <= where[i]


_square_blocks = st.integers(1, 3).flatmap(lambda k: dense_matrices(rows=k, cols=k, max_degree=0))


@given(st.lists(_square_blocks, min_size=1, max_size=4), st.randoms(use_true_random=False))
def test_charpoly_of_a_hidden_block_triangular_matrix(blocks, rnd):
    """Diagonal blocks, random entries above them, and a random symmetric permutation: charpoly
    (by components) equals flint's charpoly of the whole matrix and the product of the blocks'."""
    sizes = [B.rows for B in blocks]
    n = sum(sizes)
    a = [[Fraction(0)] * n for _ in range(n)]
    start = 0
    for B, k in zip(blocks, sizes, strict=True):
        c = B.coefficient_lists()[0]
        for i in range(k):
            for j in range(k):
                a[start + i][start + j] = Fraction(c[i][j])
            for j in range(start + k, n):
                a[start + i][j] = Fraction(rnd.randint(-3, 3), rnd.randint(1, 3))
        start += k
    perm = list(range(n))
    rnd.shuffle(perm)
    M = PolyMatrix([[str(a[perm[i]][perm[j]]) for j in range(n)] for i in range(n)])
    whole = flint.fmpq_mat(n, n, [flint.fmpq(x.numerator, x.denominator) for r in a for x in r]).charpoly()
    p = charpoly(M)
    assert p == Poly._wrap(whole, "s")
    prod = Poly(1, "s")
    for B in blocks:
        prod = prod * charpoly(B)
    assert p == prod


def test_the_observer_matrix_splits_into_its_channels():
    """L0 = A0 − G0 C0 of the delay UIO of Zheng et al. §5 is block companion: its r channels of
    l* states are its strongly connected components (r and l* depend on the design's choices: they
    are read from it), and its charpoly is the requested Π(s − p_i)^r."""
    from design import paper001

    from uio_ring import design_zheng_bejarano

    d = design_zheng_bejarano(paper001.system(), poles=[-10, -25, -50])
    n = d.L0.rows
    assert n == d.r * d.l_star and d.r >= 2
    succ = [[j for j in range(n) if j != i and not d.L0[i, j].is_zero()] for i in range(n)]
    assert sorted(len(c) for c in strong_components(n, succ)) == [d.l_star] * d.r
    s = Poly.gen("s")
    assert charpoly(d.L0) == ((s + 10) * (s + 25) * (s + 50)) ** d.r
