"""The flip rate's restricted Beta prior (bsi_sklearn.model.flip_rate) against scipy and mpmath.

scipy's incomplete Beta function loses relative precision far in its tail (about 1e-6 near
1e-290), so it is the reference down to 1e-200; mpmath (50 digits) is the reference beyond.
"""

import numpy as np
import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st
from scipy import stats
from scipy.special import betainc, betaln

from bsi_sklearn.model.flip_rate import log_betainc, log_flip_marginals, truncated_mean

shape = st.floats(0.05, 5000.0, allow_nan=False, allow_infinity=False)


@settings(max_examples=300, deadline=None)
@given(a=shape, b=shape, x=st.floats(0.001, 0.999))
def test_log_betainc_matches_scipy_where_it_is_representable(a, b, x):
    ref = betainc(a, b, x)
    got = float(log_betainc(a, b, x))
    if ref > 1e-200:
        assert np.isclose(np.exp(got), ref, rtol=1e-9, atol=0.0)
    else:  # far in the tail: the complement's identity, I_x(a, b) = 1 - I_(1-x)(b, a)
        assert got < np.log(1e-190)
        assert np.isclose(float(log_betainc(b, a, 1.0 - x)), np.log1p(-np.exp(got)),
                          rtol=0.0, atol=1e-12)


@settings(max_examples=40, deadline=None)
@given(a=st.floats(0.2, 3000.0), b=st.floats(0.2, 3000.0))
@example(a=2432.743489377577, b=2432.743489377577)  # found by a CI run: 1.7e-11 off
def test_log_betainc_far_in_the_tail_against_mpmath(a, b):
    mpmath = pytest.importorskip("mpmath")
    mpmath.mp.dps = 50
    want = float(mpmath.log(mpmath.betainc(a, b, 0, 0.5, regularized=True)))
    # The prefactor log[x^a (1 - x)^b / B(a, b)] is a sum of terms of size |betaln(a, b)|
    # (3,377 at a = b = 2,433) that cancel: doubles and scipy's betaln carry them to about
    # 1e-15 of their size each, so the result is good to that much of their sum, not to 1e-11.
    scale = (a + b) * np.log(2.0) + abs(betaln(a, b))
    assert abs(float(log_betainc(a, b, 0.5)) - want) <= 1e-11 * (1.0 + abs(want)) + 1e-14 * scale


@settings(max_examples=100, deadline=None)
@given(n=st.integers(0, 3000), a=st.floats(0.2, 20.0), b=st.floats(0.2, 20.0))
def test_the_table_is_the_restricted_marginal(n, a, b):
    table = log_flip_marginals(n, a, b)
    assert table.shape == (n + 1,) and np.all(np.isfinite(table))
    v = np.arange(n + 1.0)
    inc = betainc(a + v, b + n - v, 0.5)
    ok = inc > 1e-200  # where scipy's tail is precise (the module docstring)
    ref = (betaln(a + v[ok], b + n - v[ok]) + np.log(inc[ok])
           - betaln(a, b) - np.log(betainc(a, b, 0.5)))
    np.testing.assert_allclose(table[ok], ref, rtol=1e-9, atol=1e-9)
    # The probabilities of the labels given v sum, over every labelling, to one.
    from scipy.special import gammaln
    log_comb = gammaln(n + 1.0) - gammaln(v + 1.0) - gammaln(n - v + 1.0)
    assert np.isclose(np.logaddexp.reduce(table + log_comb), 0.0, atol=1e-9)


@settings(max_examples=100, deadline=None)
@given(alpha=st.floats(0.2, 400.0), beta=st.floats(0.2, 400.0))
def test_truncated_mean_against_scipy(alpha, beta):
    got = float(truncated_mean(alpha, beta))
    assert 0.0 < got < 0.5
    dist = stats.beta(alpha, beta)
    if dist.cdf(0.5) > 1e-8:  # where scipy's quadrature has mass to integrate
        want = dist.expect(lambda e: e, lb=0.0, ub=0.5, conditional=True)
        assert np.isclose(got, want, rtol=1e-6)


@given(alpha=st.floats(0.2, 5000.0))
def test_truncated_mean_in_closed_form(alpha):
    # Beta(alpha, 1) restricted to (0, 1/2): density alpha-proportional to x^(alpha - 1),
    # mean alpha / (alpha + 1) / 2, however little of the Beta's mass lies there.
    assert np.isclose(float(truncated_mean(alpha, 1.0)), alpha / (alpha + 1.0) / 2.0,
                      rtol=1e-10)
