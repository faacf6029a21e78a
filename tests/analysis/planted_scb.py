"""Systems with a planted special coordinate basis (test data generator).

``planted(n_a, l, q, m_0, rng)`` builds blocks in the form (17a)–(23) with random
small rationals, then maps them by random nonsingular rational ``Ts, Ti, To``:
the SCB invariants of the result are the planted ones.
"""

from __future__ import annotations

import random
from dataclasses import dataclass
from fractions import Fraction

from uio_ring import DelaySystem
from uio_ring.ring.charpoly import charpoly
from uio_ring.ring.matrix import Poly
from uio_ring.ring.qmatrix import QMatrix as Q


@dataclass(frozen=True)
class Planted:
    system: DelaySystem
    n_a: int
    l: tuple[int, ...]
    q: tuple[int, ...]
    m_0: int
    zero_polynomial: Poly


def _rand(rng: random.Random, r: int, c: int, lo: int = -3, hi: int = 3) -> Q:
    return Q([[Fraction(rng.randint(lo, hi), rng.choice((1, 1, 2))) for _ in range(c)] for _ in range(r)], shape=(r, c))


def _unimodular_ish(rng: random.Random, k: int) -> Q:
    while True:
        M = _rand(rng, k, k)
        if k == 0 or M.det() != 0:
            return M


def _shift(lengths):
    n = sum(lengths)
    rows = [[0] * n for _ in range(n)]
    s = 0
    for L in lengths:
        for k in range(L - 1):
            rows[s + k][s + k + 1] = 1
        s += L
    return Q(rows, shape=(n, n))


def _sel(lengths, end: bool) -> Q:
    n = sum(lengths)
    idx, s = [], 0
    for L in lengths:
        idx.append(s + L - 1 if end else s)
        s += L
    M = Q([[1 if j == i else 0 for j in range(n)] for i in idx], shape=(len(idx), n))
    return M.T if end else M


def planted(n_a: int, l: tuple[int, ...], q: tuple[int, ...], m_0: int, rng: random.Random,
            A_a: Q | None = None, n_c: int = 0, m_c: int = 0) -> Planted:
    l = tuple(sorted(l, reverse=True))
    q = tuple(sorted(q, reverse=True))
    nb, nd, md, pb = sum(l), sum(q), len(q), len(l)
    n, m, p = n_a + nb + nd, m_0 + md, m_0 + md + pb
    Cb, Cd, Bd = _sel(l, False), _sel(q, False), _sel(q, True)
    Z = Q.zeros
    nc, mc = n_c, m_c
    n, m = n + nc, m + mc
    Aa = _rand(rng, n_a, n_a) if A_a is None else A_a
    Ab = _shift(l) + _rand(rng, nb, pb) @ Cb
    Ad = _shift(q) + Bd @ _rand(rng, md, nd) + _rand(rng, nd, md) @ Cd
    while True:  # (A_c, B_c) controllable with B_c of full column rank
        Ac, Bc = _rand(rng, nc, nc), _rand(rng, nc, mc)
        ctrb = Q.hstack(*[(Ac ** k) @ Bc for k in range(max(nc, 1))], rows=nc) if nc else Q.zeros(0, 0)
        if nc == 0 or (ctrb.rank() == nc and Bc.rank() == mc):
            break
    As = Q.block([
        [Aa, _rand(rng, n_a, pb) @ Cb, Z(n_a, nc), _rand(rng, n_a, md) @ Cd],
        [Z(nb, n_a), Ab, Z(nb, nc), _rand(rng, nb, md) @ Cd],
        [Bc @ _rand(rng, mc, n_a), _rand(rng, nc, pb) @ Cb, Ac, _rand(rng, nc, md) @ Cd],
        [Bd @ _rand(rng, md, n_a), Bd @ _rand(rng, md, nb), Bd @ _rand(rng, md, nc), Ad],
    ])
    B0, C0 = _rand(rng, n, m_0), _rand(rng, m_0, n)
    Abar = As + B0 @ C0
    Bbar = Q.hstack(B0, Q.vstack(Z(n_a + nb + nc, md), Bd, cols=md),
                    Q.vstack(Z(n_a + nb, mc), Bc, Z(nd, mc), cols=mc), rows=n)
    Cbar = Q.vstack(C0, Q.hstack(Z(md, n_a + nb + nc), Cd, rows=md), Q.hstack(Z(pb, n_a), Cb, Z(pb, nc + nd), rows=pb),
                    cols=n)
    Dbar = Q([[1 if (i == j and i < m_0) else 0 for j in range(m)] for i in range(p)], shape=(p, m))
    Ts, Ti, To = _unimodular_ish(rng, n), _unimodular_ish(rng, m), _unimodular_ish(rng, p)
    Tsi, Tii = Ts.inverse(), Ti.inverse()
    A, B, C, D = Ts @ Abar @ Tsi, Ts @ Bbar @ Tii, To @ Cbar @ Tsi, To @ Dbar @ Tii
    sys = DelaySystem(A.to_polymatrix(), B.to_polymatrix(), C.to_polymatrix(), D.to_polymatrix())
    return Planted(sys, n_a, l, q, m_0, charpoly(Aa))
