"""Extended gcd over Q[δ] by Chinese remaindering, with an exact check.

python-flint's ``fmpq_poly.xgcd`` (FLINT ``fmpq_poly_xgcd``) divides both
polynomials by their gcd G, takes the primitive parts C, D (coprime) and calls
``_fmpz_poly_xgcd``, which works modulo enough primes to exceed an a-priori
(Hadamard) bound on the resultant — on the 2×2 ``[[(1+δ)^k, …], [δ^k − 1, …]]``
of the benchmark (coefficients of 250 bits at k = 256) that bound is ≈ 130 000
bits, while the cofactors need ≈ 4000: 185 ms of the 190 ms of its Hermite form.

:func:`xgcd` returns the same (g, s, t) with the bound replaced by early
termination and a proof.  The cofactors ``s, t`` with ``s·a + t·b = g`` (g monic),
``deg s < deg b − deg g`` and ``deg t < deg a − deg g`` are unique (``s`` is the inverse
of ``a/g`` modulo ``b/g``), and FLINT returns exactly those (its ``_fmpz_poly_xgcd`` of the
coprime C, D has ``len S < len D``, ``len T < len C``).  With ``R = res(C, D)``, the
numerator ``R·s'`` of the cofactor of C is an integer polynomial (Cramer's rule on the
Sylvester matrix; C and D are the primitive parts of the numerators, whose contents
would only inflate the bound and the residues); modulo a word prime p that divides neither leading coefficient nor R
it is ``R_p·s_p``, from ``nmod_poly.xgcd`` and ``nmod_poly.resultant``.  Prime by prime,
a few of these integers (and R) are lifted by Garner's step; once none of them changed
for one prime, all residues are combined (one ``fmpz_mat`` product with the CRT weights)
and lifted to the symmetric range, and s follows (after a failed candidate, the next
one waits until the number of primes has doubled, so the CRTs cost O(1) final ones).  The candidate is accepted only when
``t = (g − s·a) / b`` is exact, with ``deg s < deg b − deg g`` and ``deg t < deg a − deg g``:
then ``s·a + t·b = g`` with both degree bounds, which proves it is the unique pair above
(otherwise more primes, up to FLINT's Hadamard bound, then FLINT's own ``xgcd``).
Multimodular xgcd with early termination: von zur Gathen & Gerhard, *Modern Computer
Algebra* (3rd ed., 2013), §6.11 and §5.10; cost O(N·d²) word operations for N primes and
degree d, one CRT of N·d numbers, and the check (one product and one division of degree
2d).  Benchmark 2×2 (cofactors of degree k − 2): k = 64 1.3 ms against FLINT's 2.0, k =
128 6.6 against 17.9, k = 256 37 against 185; below degree :data:`MIN_DEGREE` FLINT's is
faster (k = 32: 0.16 against 0.26 ms).

The early termination only pays when the cofactors are far smaller than FLINT's bound.
On polynomials whose coefficients are not the product of cancellation — random ones,
and the high-degree entries of the benchmark's highdeg4, rowdeg and sparse Smith forms
— FLINT's ``xgcd`` is 1.2–1.7× faster (degree 48–128, random coefficients in [−3, 3]:
0.52 against 0.90 ms at 48, 5.1 against 6.1 ms at 128; the sparse 10×10 Smith form's
degree-62/71 gcd, 179 against 215 ms).  The two are told apart by Graeffe's root
squaring (:func:`_bound_overestimates`): the resultant, hence the cofactors, is bounded
through the Mahler measure, which two squarings bound far below the coefficient norms
when the coefficients come from cancellation — (1 + δ)^k has norm about 2^k and
measure 1 — and not otherwise.  Given up by that rule: random 60-bit coefficients from
degree 128 on, where the modular path is 1.0–1.4× faster (degree 192: 353 against
503 ms).  FLINT's own speed depends on its version: python-flint 0.8 ships FLINT 3.3.1,
whose ``xgcd`` takes 4.9 ms on two random polynomials of degree 128 where FLINT 3.6
(python-flint 0.9, and SageMath's) takes 4.0, so shapes that are one large gcd (a 2×1
column of degree 96–192) stay at 0.8–1.0× SageMath.
"""

from __future__ import annotations

from fractions import Fraction

import flint

__all__ = ["xgcd", "MIN_DEGREE", "MODULAR_MAX_RATIO"]

#: Below this degree (of the smaller polynomial) FLINT's ``xgcd`` is used directly.
MIN_DEGREE = 48

#: The modular path is taken when the Graeffe bound on the resultant has at most this
#: fraction of the bits of the coefficient-norm bound (:func:`_bound_overestimates`):
#: 0.25 for the binomials of the benchmark's highdeg family (modular 1.5–5.8× faster
#: than FLINT's at k = 64–256), 0.38 for ``(1 + δ)^k`` against ``(δ − 1)^k + δ^(k−1) + 1``
#: (the two paths within 0.7–1.0× of each other), 0.64–0.99 for random coefficients
#: (FLINT's 1.2–1.7× faster up to degree 128).  It only chooses a route: both give the
#: same triple.
MODULAR_MAX_RATIO = Fraction(1, 3)

#: Graeffe steps of that bound (each squares the roots, so the bound on log M improves
#: by up to half; two cost 0.03–0.2 ms at degree 48–128, a few % of either xgcd).
GRAEFFE_STEPS = 2

_PRIMES: list[int] = []


def _prime(i: int) -> int:
    """The i-th prime below 2⁶² (descending), cached."""
    while len(_PRIMES) <= i:
        p = (_PRIMES[-1] if _PRIMES else 2**62) - 1
        while not flint.fmpz(p).is_prime():
            p -= 1
        _PRIMES.append(p)
    return _PRIMES[i]


def xgcd(a: flint.fmpq_poly, b: flint.fmpq_poly) -> tuple[flint.fmpq_poly, flint.fmpq_poly, flint.fmpq_poly]:
    """``a.xgcd(b)``: ``(g, s, t)`` with ``g = s·a + t·b`` monic, the cofactors of least
    degree — the same three polynomials, faster for large degrees (see the module text).

    >>> x = flint.fmpq_poly([0, 1])
    >>> xgcd((1 + x)**60, x**60 - 1) == ((1 + x)**60).xgcd(x**60 - 1)
    True
    """
    if min(a.degree(), b.degree()) < MIN_DEGREE or not _bound_overestimates(a.numer(), b.numer()):
        return a.xgcd(b)
    got = _xgcd_modular(a, b)
    return a.xgcd(b) if got is None else got


def _graeffe(c: flint.fmpz_poly) -> flint.fmpz_poly:
    """Graeffe's root squaring: G with ``G(δ²) = c(δ)·c(−δ)`` up to sign, that is
    ``c_e² − δ·c_o²`` for ``c = c_e(δ²) + δ·c_o(δ²)``; its roots are the squares of c's,
    so its Mahler measure is M(c)².

    >>> _graeffe(flint.fmpz_poly([1, 1])**4) == flint.fmpz_poly([1, -1])**4
    True
    """
    cs = c.coeffs()
    even, odd = flint.fmpz_poly(cs[0::2]), flint.fmpz_poly(cs[1::2])
    return even * even - (odd * odd).left_shift(1)


def _norm_bits2(c: flint.fmpz_poly) -> int:
    """An integer ≥ 2·log₂‖c‖₂: twice the bits of the largest coefficient, plus the bits
    of the number of coefficients."""
    return 2 * int(c.height_bits()) + (c.degree() + 1).bit_length()


def _resultant_bound(a: flint.fmpz_poly, b: flint.fmpz_poly, steps: int) -> int:
    """An integer ≥ 2^(steps+1)·log₂|res(a, b)| for nonzero integer polynomials a, b,
    through ``steps`` Graeffe root squarings (steps = 0: the coefficient-norm bound).

    ``|res(a, b)| ≤ M(a)^deg b · M(b)^deg a`` (a product over the roots), with Landau's
    ``M(c) ≤ ‖c‖₂`` and ``M(G^j(c)) = M(c)^(2^j)``, so ``log M(c) ≤ log‖G^j(c)‖₂ / 2^j``
    for every j (Mignotte & Ştefănescu, *Polynomials: An Algorithmic Approach*, 1999,
    §2.2 and §4.3).  The bound on the binomial ``(1 + δ)^k`` falls from about k bits to
    a quarter of that in two steps (its measure is 1); on a random polynomial it hardly
    moves.  Integer arithmetic only.

    >>> x = flint.fmpz_poly([0, 1])
    >>> (1 + x).resultant(x - 3)                      # |res| = 4: 2 bits
    -4
    >>> [_resultant_bound(1 + x, x - 3, j) for j in (0, 1)]   # at least 2·2 and 4·2
    [10, 14]
    """
    ga, gb = a, b
    for _ in range(steps):
        ga, gb = _graeffe(ga), _graeffe(gb)
    return b.degree() * _norm_bits2(ga) + a.degree() * _norm_bits2(gb)


def _bound_overestimates(a: flint.fmpz_poly, b: flint.fmpz_poly) -> bool:
    """Whether the resultant bound of :data:`GRAEFFE_STEPS` root squarings has at most
    :data:`MODULAR_MAX_RATIO` of the bits of the coefficient-norm bound
    (:func:`_resultant_bound`; a, b: the numerators, nonzero, their contents removed
    first): then the cofactors lie far below the bound that FLINT's ``xgcd`` works to,
    and the modular path with early termination is the faster.  A route, not a result.

    >>> x = flint.fmpz_poly([0, 1])
    >>> _bound_overestimates((1 + x)**64, x**64 - 1)
    True
    >>> _bound_overestimates(x**64 + 3*x**7 - 2*x + 1, 2*x**64 - x**30 + 3)
    False
    """
    a, b = a // a.content(), b // b.content()
    norms = _resultant_bound(a, b, 0) << GRAEFFE_STEPS
    return _resultant_bound(a, b, GRAEFFE_STEPS) <= MODULAR_MAX_RATIO * norms


def _xgcd_modular(
    a: flint.fmpq_poly, b: flint.fmpq_poly
) -> tuple[flint.fmpq_poly, flint.fmpq_poly, flint.fmpq_poly] | None:
    g = a.gcd(b)
    c, d = a // g, b // g  # coprime, exact quotients
    if c.degree() < 1 or d.degree() < 1:  # one divides the other: nothing to gain
        return None
    # primitive integer parts: c = cz·kc / c.denom(), likewise d (the numerators of rational
    # inputs can carry contents of thousands of bits that would inflate the bound and
    # every residue: a W-step of ``uio-ring check``, 4379 of 4682 bits, 9.5 s → 0.1 s)
    cz, dz = c.numer(), d.numer()
    kc = cz.content()
    cz, dz = cz // kc, dz // dz.content()
    lcc, lcd = int(cz.leading_coefficient()), int(dz.leading_coefficient())
    lens = dz.degree()  # deg s < deg d
    # Hadamard bound on the minors of the Sylvester matrix of cz, dz (R and the
    # coefficients of R·s'): past it the symmetric lift is exact, and a candidate that
    # fails the check means a bug — FLINT's xgcd then (never seen)
    bound = (dz.degree() * (int(cz.height_bits()) + (cz.degree() + 1).bit_length())
             + cz.degree() * (int(dz.height_bits()) + (dz.degree() + 1).bit_length()) + 2)
    primes: list[int] = []
    residues: list[list[int]] = []  # per prime: the coefficients of R·s', then R
    # early termination: a few entries of (R·s', R) lifted prime by prime (Garner); the
    # whole vector is combined once they have not changed for one prime
    watch = sorted({0, lens // 2, lens - 1, lens})
    value = [0] * len(watch)
    modulus = 1
    i = 0
    next_try = 3  # a failed candidate waits for twice as many primes: O(1) CRTs per doubling
    while modulus.bit_length() <= bound + 64:
        p = _prime(i)
        i += 1
        if lcc % p == 0 or lcd % p == 0:
            continue
        cp, dp = flint.nmod_poly(cz, p), flint.nmod_poly(dz, p)
        gp, sp, _ = cp.xgcd(dp)
        if not gp.is_one():  # p divides the resultant
            continue
        rp = cp.resultant(dp)
        sv = [int(x) for x in (sp * rp).coeffs()]
        row = sv + [0] * (lens - len(sv)) + [int(rp)]
        residues.append(row)
        primes.append(p)
        stable = True
        for w, j in enumerate(watch):
            delta = (row[j] - value[w]) % p
            if delta:
                stable = False
                value[w] += modulus * (delta * pow(modulus, -1, p) % p)
                if 2 * value[w] > modulus * p:
                    value[w] -= modulus * p
        modulus *= p
        if not stable or len(primes) < next_try:
            continue
        next_try = 2 * len(primes)
        s = _candidate(primes, residues, lens, flint.fmpq(int(c.denom()), int(kc)))
        if s is None or s.degree() >= lens:
            continue
        t, rem = divmod(g - s * a, b)  # then s·a + t·b = g
        if rem.is_zero() and t.degree() < c.degree():
            return g, s, t
    return None


def _candidate(
    primes: list[int], residues: list[list[int]], lens: int, scale: flint.fmpq
) -> flint.fmpq_poly | None:
    """The cofactor s from the residues: CRT in the symmetric range, then ``·scale / R``
    (``scale`` = c_den / content: from the cofactor of the primitive part to that of c)."""
    modulus = 1
    for p in primes:
        modulus *= p
    weights = []
    for p in primes:
        co = modulus // p
        weights.append(co * pow(co % p, -1, p))
    n, width = len(primes), len(residues[0])
    w = flint.fmpz_mat(1, n, weights)
    r = flint.fmpz_mat(n, width, [x for row in residues for x in row])
    combined = (w * r).entries()
    half = modulus // 2
    vals = []
    for x in combined:
        v = int(x) % modulus
        vals.append(v - modulus if v > half else v)
    res = vals[-1]
    if res == 0:
        return None
    return flint.fmpq_poly(vals[:lens]) * (scale / res)
