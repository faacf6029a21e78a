"""Chinese remaindering and rational reconstruction of polynomial images (ring._crt)."""

from __future__ import annotations

import flint
from hypothesis import given, settings
from hypothesis import strategies as st

from uio_ring.ring._crt import images_combined, proportional_integers, rational_reconstruction
from uio_ring.ring._reduced_crt import word_primes

fractions = st.builds(lambda p, q: flint.fmpq(p, q), st.integers(-(1 << 40), 1 << 40), st.integers(1, 1 << 40))
polys = st.lists(fractions, min_size=0, max_size=3).map(flint.fmpq_poly)


def _image(x: flint.fmpq_poly, p: int) -> flint.nmod_poly:
    return flint.nmod_poly(x.numer(), p) * pow(int(x.denom()), -1, p)


@settings(max_examples=60, deadline=None)
@given(st.lists(polys, min_size=1, max_size=2))
def test_enough_primes_give_the_vector_up_to_a_constant(xs):
    # at most 6 coefficients, numerators and denominators below 2^40: a common denominator
    # below 2^240 and scaled numerators below 2^280, so Wang's bound needs a modulus above
    # 2^561; 12 word primes give about 732 bits
    acc, modulus = None, 1
    for p in word_primes(12):
        acc = images_combined(acc, modulus, [_image(x, p) for x in xs], p)
        modulus *= p
    got = proportional_integers(acc, modulus)
    assert got is not None
    nonzero = [(g, x) for g, x in zip(got, xs, strict=True) if not x.is_zero()]
    assert all(g.is_zero() for g, x in zip(got, xs, strict=True) if x.is_zero())
    if nonzero:
        g0, x0 = nonzero[0]
        # one constant c with got = c·xs
        c = flint.fmpq_poly(g0)[g0.degree()] / x0[x0.degree()]
        assert c != 0 and all(flint.fmpq_poly(g) == x * c for g, x in zip(got, xs, strict=True))


@settings(max_examples=100, deadline=None)
@given(st.integers(-(1 << 40), 1 << 40), st.integers(1, 1 << 40))
def test_rational_reconstruction_inverts_the_residue(num, den):
    m = word_primes(2)[0] * word_primes(2)[1]  # about 2^122 > 2·2^40·2^40
    g = flint.fmpz(num).gcd(den)
    num, den = int(num // g), int(den // g)
    assert rational_reconstruction(num * pow(den, -1, m) % m, m) == (num, den)
