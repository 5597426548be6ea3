"""The calibrated likelihood and CI with the flip rate integrated (issue 20, items 2 and 3).

Each against a reference written independently of the kernels: per-demonstration formulas,
a numerical integral over the flip rate, the enumeration of every specification from first
principles, the ungrouped exact engine, and MCMC.
"""

import math
import pickle

import numpy as np
import pytest
from _exact_checks import _assert_same_posterior
from _exact_checks import _problem as _grouped_problem
from _reference import brute_force_posterior
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from poi_problems import make_absence_problem, make_poi_problem
from scipy import integrate, stats

import bsi_sklearn.inference._exact_kernels as kernels
from bsi_sklearn import BSIClassifier
from bsi_sklearn.inference.diagnostics import total_variation
from bsi_sklearn.inference.exact import exact_posterior
from bsi_sklearn.model import make_model
from bsi_sklearn.model.flip_rate import log_flip_marginals
from bsi_sklearn.model.likelihood import (
    default_log_epsilon,
    flip_rate_posterior,
    likelihood_code,
    log_likelihood,
    log_likelihood_reference,
)
from bsi_sklearn.model.priors import PRIORS

#: (likelihood, flip_prior) of the new settings.
NEW = [("calibrated", None), ("ci", (1.0, 9.0)), ("calibrated", (1.0, 9.0)), ("ci", (2.5, 0.7)),
       ("calibrated", (2.5, 0.7))]


def _kernel(sat, y, n_conj, log_eps, likelihood, flip_prior):
    sat, y = np.asarray(sat, bool), np.asarray(y)
    flips = (log_flip_marginals(len(y), *flip_prior) if flip_prior is not None
             else np.zeros(0))
    return log_likelihood(float((sat & (y == 1)).sum()), float((sat & (y == 0)).sum()),
                          float((y == 1).sum()), float((y == 0).sum()), n_conj, log_eps,
                          likelihood_code(likelihood, flip_prior), flips)


@pytest.mark.parametrize("likelihood, flip_prior", NEW)
def test_kernel_matches_the_per_demonstration_reference(likelihood, flip_prior):
    rng = np.random.default_rng(3)
    for _ in range(200):
        n = int(rng.integers(1, 30))
        y = rng.integers(0, 2, size=n)
        sat = rng.random(n) < rng.random()
        n_conj = int(rng.integers(1, 40))
        log_eps = -float(rng.uniform(0.1, 60))
        ref = log_likelihood_reference(sat, y, n_conj, log_eps, likelihood, flip_prior)
        got = _kernel(sat, y, n_conj, log_eps, likelihood, flip_prior)
        assert got == pytest.approx(ref, rel=1e-11, abs=1e-9)


@pytest.mark.parametrize("a, b", [(1.0, 1.0), (1.0, 9.0), (0.5, 0.5), (3.0, 0.8)])
def test_integrated_flip_rate_is_the_integral_over_epsilon(a, b):
    # The product of per-demonstration CI likelihoods, integrated numerically over the Beta
    # restricted to (0, 1/2), divided by its mass there.
    rng = np.random.default_rng(int(10 * a + b))
    for _ in range(5):
        n = int(rng.integers(1, 25))
        y = rng.integers(0, 2, size=n)
        sat = rng.random(n) < 0.6
        wrong = int(((sat == 1) != (y == 1)).sum())

        def integrand(eps, wrong=wrong, n=n):
            return eps**wrong * (1 - eps) ** (n - wrong) * stats.beta.pdf(eps, a, b)

        value, _ = integrate.quad(integrand, 0, 0.5, epsabs=0, epsrel=1e-12, limit=200)
        value /= stats.beta.cdf(0.5, a, b)
        got = _kernel(sat, y, 3, -5.0, "ci", (a, b))
        assert got == pytest.approx(math.log(value), rel=1e-8, abs=1e-8)
        # Calibrated: each label right with 1 - eps, flipped with eps, and each correctly
        # classified demonstration's density 1 / m on ext(phi), 1 / (1 - m) off it.
        m = (sat.sum() + 1.0) / (n + 2.0)
        ok = sat == (y == 1)
        density = (ok & sat).sum() * -math.log(m) + (ok & ~sat).sum() * -math.log1p(-m)
        got = _kernel(sat, y, 3, -5.0, "calibrated", (a, b))
        assert got == pytest.approx(math.log(value) + density, rel=1e-8, abs=1e-8)


def test_calibrated_flips_cost_what_the_flip_rate_says():
    # A flipped label costs about log(n / v) nats, not epsilon's penalty: one clause that
    # moves a flipped unacceptable demonstration out of ext(phi) gains a few nats.
    y = np.array([1] * 140 + [0] * 60)
    sat = y == 1
    sat[140:150] = True  # ten unacceptable demonstrations the formula satisfies (flipped)
    fixed = sat.copy()
    fixed[140] = False
    gain = (_kernel(fixed, y, 3, -9.0, "calibrated", (1.0, 9.0))
            - _kernel(sat, y, 3, -9.0, "calibrated", (1.0, 9.0)))
    assert 2.0 < gain < 5.0
    assert (_kernel(fixed, y, 3, -200.0, "calibrated", None)
            - _kernel(sat, y, 3, -200.0, "calibrated", None)) > 200.0
    # Acceptable demonstrations only: violating v of them costs about v log(n / v) nats
    # (the size principle's gain pays for none of it), more for every one more up to a flip
    # rate of a quarter.
    y = np.ones(200, int)
    lls = [_kernel(np.arange(200) >= v, y, 3, -9.0, "calibrated", (1.0, 9.0))
           for v in range(0, 51, 10)]
    assert np.all(np.diff(lls) < -5.0)
    assert lls[1] - lls[0] < -10 * math.log(200 / 10) + 10


def test_calibrated_does_not_depend_on_conjuncts_and_a_vacuous_clause_earns_nothing():
    y = np.array([1, 1, 1, 0, 0, 1])
    sat = np.array([1, 1, 1, 0, 1, 1], bool)
    values = {_kernel(sat, y, k, -9.0, "calibrated", None) for k in (1, 2, 7, 300)}
    assert len(values) == 1
    # A clause every demonstration satisfies changes neither count: nothing to earn. Under CB
    # the same clause pays log 2 for every satisfying acceptable demonstration.
    assert _kernel(sat, y, 4, -9.0, "cb", None) - _kernel(sat, y, 3, -9.0, "cb", None) == \
        pytest.approx(4 * math.log(2) - math.log((2**4 - 1) / 2**4) - math.log(8 / 7))
    # Joint in the counts: moving a negative from violated to satisfied changes what every
    # satisfied positive earns (not a positives' term plus a negatives' term).
    base = _kernel(sat, y, 3, -9.0, "calibrated", None)
    sat2 = sat.copy()
    sat2[3] = True
    m1, m2 = 6 / 8, 7 / 8
    assert _kernel(sat2, y, 3, -9.0, "calibrated", None) - base == pytest.approx(
        -9.0 + math.log(1 - m1) + 4 * (math.log(m1) - math.log(m2)))


def _small_problem(seed=3):
    return make_poi_problem(n_demos=6, n_threats=2, n_pois=3, chain=(0, 2), n_negative=4,
                            seed=seed, always_violated=(1,))


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("likelihood, flip_prior", NEW[:3])
def test_exact_matches_first_principles(prior, likelihood, flip_prior):
    X, y, roles = _small_problem()
    names = list(X[0].columns)
    ref = brute_force_posterior(X, y, names, roles["global_candidates"], roles["subtasks"],
                                roles["conditions"], prior, likelihood, flip_prior=flip_prior)
    clf = BSIClassifier(prior=prior, likelihood=likelihood, flip_prior=flip_prior,
                        inference="exact", tol=0.0, **roles).fit(X, y)
    assert total_variation(clf.posterior_, ref) < 1e-9
    marg = clf.posterior_.clause_marginals()
    for key, value in marg.items():
        assert value == pytest.approx(sum(p for s, p in ref.items() if key in s.clauses()),
                                      abs=1e-9)


@settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), prior=st.sampled_from(PRIORS),
       setting=st.sampled_from(NEW), n_g=st.integers(0, 3), n=st.integers(0, 4),
       n_demos=st.integers(1, 80), frac_pos=st.sampled_from([0.0, 0.5, 0.8, 1.0]),
       p_true=st.floats(0.3, 0.97), epsilon=st.sampled_from([None, 0.01, 0.2]),
       tol=st.sampled_from([1e-9, 1e-4, 0.0]))
def test_grouped_equals_ungrouped(seed, prior, setting, n_g, n, n_demos, frac_pos, p_true,
                                  epsilon, tol):
    likelihood, flip_prior = setting
    truth, y, _ = _grouped_problem(seed, prior, "cb", n_g, n, n_demos, frac_pos, p_true, None)
    model = make_model(prior=prior, likelihood=likelihood, n_globals=n_g, n_subtasks=n,
                       epsilon=None if flip_prior else epsilon, flip_prior=flip_prior,
                       n_demos=len(y))
    a = exact_posterior(truth, y, model, tol=tol)
    b = exact_posterior(truth, y, model, tol=tol, grouped=False)
    _assert_same_posterior(a, b)
    assert np.abs(a.violation_mass - b.violation_mass).max() < 1e-12
    assert a.violation_mass.sum() == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("setting", [("cb", None), ("ci", None), *NEW])
def test_the_likelihood_from_counts_equals_its_table(monkeypatch, setting):
    # Above MAX_CELLS a joint likelihood is computed from the counts instead of a table.
    likelihood, flip_prior = setting
    truth, y, _ = _grouped_problem(7, "sets_of_chains", "cb", 2, 4, 60, 0.6, 0.8, None)
    model = make_model(prior="sets_of_chains", likelihood=likelihood, n_globals=2,
                       n_subtasks=4, flip_prior=flip_prior, n_demos=len(y))
    table = exact_posterior(truth, y, model)
    monkeypatch.setattr(kernels, "MAX_CELLS", 0)
    counts = exact_posterior(truth, y, model)
    _assert_same_posterior(table, counts)


@pytest.mark.parametrize("setting", [("cb", None), ("ci", None), *NEW])
def test_the_bound_bounds_every_pair(setting):
    likelihood, flip_prior = setting
    n_pos, n_neg, max_conj = 7, 5, 10
    model = make_model(prior="forest", likelihood=likelihood, n_globals=1, n_subtasks=3,
                       epsilon=None if flip_prior else 0.1, flip_prior=flip_prior,
                       n_demos=n_pos + n_neg)
    lik = kernels.likelihood_tables(n_pos, n_neg, max_conj, model)
    for k in range(max_conj + 1):
        grid = np.array([[kernels.pair_ll(lik, k, ps, ns) for ns in range(n_neg + 1)]
                         for ps in range(n_pos + 1)])
        if k == 0:  # no conjunct: only (n_pos, n_neg) occurs
            grid = np.full_like(grid, -np.inf)
            grid[n_pos, n_neg] = kernels.pair_ll(lik, 0, n_pos, n_neg)
        best = np.maximum.accumulate(grid.max(axis=1))
        assert np.all(lik.bound[k] >= best - 1e-12)
        if k > 0:  # and it is tight (the engine skips no more than it must)
            assert np.allclose(lik.bound[k], best)


def test_violation_mass_is_the_posterior_of_the_misclassified_count():
    X, y, roles = _small_problem(seed=5)
    names = list(X[0].columns)
    ref = brute_force_posterior(X, y, names, roles["global_candidates"], roles["subtasks"],
                                roles["conditions"], "sets_of_chains", "ci",
                                flip_prior=(1.0, 4.0))
    want = np.zeros(len(y) + 1)
    for spec, p in ref.items():
        sat = np.array([spec.satisfied_by(x, feature_names=names) for x in X])
        want[int((sat != (np.asarray(y) == 1)).sum())] += p
    seen = []
    clf = BSIClassifier(likelihood="ci", flip_prior=(1.0, 4.0), inference="exact", tol=0.0,
                        **roles)
    real = exact_posterior

    def recording(*args, **kwargs):
        seen.append(real(*args, **kwargs))
        return seen[-1]

    import bsi_sklearn.inference.policy as policy_module

    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(policy_module, "exact_posterior", recording)
        clf.fit(X, y)
    assert np.abs(seen[0].violation_mass - want).max() < 1e-10


def _flip_rate_by_integration(X, y, roles, a, b):
    # The flip rate's marginal posterior density, summed over every specification, on a grid
    # over (0, 1/2), where its prior restricts it.
    names = list(X[0].columns)
    ref = brute_force_posterior(X, y, names, roles["global_candidates"], roles["subtasks"],
                                roles["conditions"], "sets_of_chains", "ci",
                                flip_prior=(a, b))
    grid = np.linspace(0, 0.5, 200_001)[1:-1]
    log_dens = np.full_like(grid, -np.inf)
    labels = np.asarray(y) == 1
    log_prior_eps = stats.beta.logpdf(grid, a, b)
    for spec, p in ref.items():
        sat = np.array([spec.satisfied_by(x, feature_names=names) for x in X])
        wrong = int((sat != labels).sum())
        # p(h | D) p(eps | h, D): the posterior of h times the normalised conditional density.
        cond = wrong * np.log(grid) + (len(y) - wrong) * np.log1p(-grid) + log_prior_eps
        cond -= np.logaddexp.reduce(cond) + np.log(grid[1] - grid[0])
        log_dens = np.logaddexp(log_dens, math.log(p) + cond)
    dens = np.exp(log_dens)
    step = grid[1] - grid[0]
    cdf = np.cumsum(dens) * step
    return (float((grid * dens).sum() * step),
            (float(np.interp(0.025, cdf, grid)), float(np.interp(0.975, cdf, grid))))


@pytest.mark.parametrize("a, b", [(1.0, 9.0), (2.0, 3.0)])
def test_flip_rate_posterior_against_numerical_integration(a, b):
    X, y, roles = make_poi_problem(n_demos=5, n_threats=1, n_pois=2, chain=(0, 1),
                                   n_negative=3, seed=2, always_violated=())
    y = np.asarray(y).copy()
    y[0] = 0  # a flipped label
    clf = BSIClassifier(likelihood="ci", flip_prior=(a, b), inference="exact", tol=0.0,
                        **roles).fit(X, y)
    mean, (lo, hi) = _flip_rate_by_integration(X, y, roles, a, b)
    assert clf.flip_rate_ == pytest.approx(mean, abs=1e-6)
    assert clf.flip_rate_interval_[0] == pytest.approx(lo, abs=1e-4)
    assert clf.flip_rate_interval_[1] == pytest.approx(hi, abs=1e-4)


def _restricted(alpha, beta):
    # Beta(alpha, beta) restricted to (0, 1/2): its cdf there and its mean, by scipy.
    dist = stats.beta(alpha, beta)
    return (lambda x: dist.cdf(x) / dist.cdf(0.5),
            dist.expect(lambda e: e, lb=0.0, ub=0.5, conditional=True))


def test_flip_rate_posterior_of_one_beta_and_of_a_mixture():
    mean, (lo, hi) = flip_rate_posterior([3], [1.0], 20, (2.0, 5.0))
    cdf, want = _restricted(5.0, 22.0)
    assert mean == pytest.approx(want, rel=1e-10)
    assert (cdf(lo), cdf(hi)) == pytest.approx((0.025, 0.975), abs=1e-9)
    mean, (lo, hi) = flip_rate_posterior([0, 4], [0.25, 0.75], 10, (1.0, 1.0))
    (cdf1, mean1), (cdf5, mean5) = _restricted(1, 11), _restricted(5, 7)
    mix_cdf = lambda x: 0.25 * cdf1(x) + 0.75 * cdf5(x)  # noqa: E731
    assert mix_cdf(lo) == pytest.approx(0.025, abs=1e-9)
    assert mix_cdf(hi) == pytest.approx(0.975, abs=1e-9)
    assert mean == pytest.approx(0.25 * mean1 + 0.75 * mean5, rel=1e-10)
    assert hi < 0.5
    assert flip_rate_posterior([0], [1.0], 3, None) == (None, None)


def test_the_flip_rate_stays_under_one_half():
    # A formula that misclassifies every demonstration would explain the labels as well as
    # one that misclassifies none if the rate could pass one half (each label flipped): under
    # the restricted prior it is the least likely, and its rate's posterior stays below 1/2.
    table = log_flip_marginals(24, 1.0, 9.0)
    assert np.all(np.diff(table) < 0)
    assert table[24] < table[12] < table[0]
    mean, (lo, hi) = flip_rate_posterior([24], [1.0], 24, (1.0, 9.0))
    assert lo < mean < hi < 0.5
    # The table against scipy where scipy's incomplete Beta function is representable.
    from scipy.special import betainc, betaln
    v = np.arange(25.0)
    want = (betaln(1 + v, 9 + 24 - v) + np.log(betainc(1 + v, 9 + 24 - v, 0.5))
            - betaln(1, 9) - np.log(betainc(1, 9, 0.5)))
    np.testing.assert_allclose(table, want, rtol=1e-12)
    # Far past n / 2 it is below the smallest float and still exact in log space.
    big = log_flip_marginals(5000, 1.0, 9.0)
    assert np.all(np.isfinite(big)) and big[-1] < -3000


def test_a_formula_read_upside_down_is_not_the_map():
    # G(!p) is outside the template without negations (p never holds in the acceptable
    # demonstrations, once or more in the others); q holds throughout every demonstration.
    # With the flip rate free on (0, 1), F(p) (every label wrong) and G(q) & F(p) won, read as
    # "every label flipped" (0.93 of the mass under the calibrated likelihood). Restricted to
    # (0, 1/2), a formula misclassifying most labels is no better than one that says nothing
    # (near eps = 1/2 every formula fits alike): never the MAP, less mass than the others.
    X, y = make_absence_problem()
    X = [t.astype(int) for t in X]
    for likelihood in ("ci", "calibrated"):
        clf = BSIClassifier(likelihood=likelihood, flip_prior=(1, 9), inference="exact",
                            tol=0.0, global_candidates=[1], subtasks=[0],
                            conditions={}).fit(X, y)
        wrong = np.array([sum(spec.satisfied_by(x) != bool(label) for x, label in zip(X, y))
                          for spec in clf.posterior_.specifications])
        upside_down = clf.posterior_.probabilities[wrong > 12].sum()
        assert wrong[clf.posterior_.map_index] <= 12
        assert upside_down < 0.5 * (1 - upside_down), (likelihood, upside_down)
        assert clf.flip_rate_interval_[1] < 0.5


@pytest.fixture(scope="module")
def poi():
    return make_poi_problem(n_demos=50, n_negative=10, seed=11)


@pytest.mark.parametrize("likelihood, flip_prior", NEW[:3])
def test_mcmc_agrees_with_exact(poi, likelihood, flip_prior):
    X, y, roles = poi
    kw = dict(prior="sets_of_chains", likelihood=likelihood, flip_prior=flip_prior, **roles)
    exact = BSIClassifier(inference="exact", **kw).fit(X, y)
    mcmc = BSIClassifier(inference="mcmc", random_state=0, **kw).fit(X, y)
    tv = total_variation(exact.posterior_, mcmc.posterior_)
    assert tv <= 0.02, tv
    assert np.abs(exact.predict_proba(X) - mcmc.predict_proba(X)).max() <= 0.02
    if flip_prior is not None:
        assert mcmc.flip_rate_ == pytest.approx(exact.flip_rate_, abs=0.005)
        assert np.allclose(mcmc.flip_rate_interval_, exact.flip_rate_interval_, atol=0.01)
    else:
        assert mcmc.flip_rate_ is None and exact.flip_rate_ is None


@pytest.mark.parametrize("params, match", [
    (dict(likelihood="cb", flip_prior=(1, 9)), "'ci' and 'calibrated', not likelihood='cb'"),
    (dict(likelihood="calibrated", flip_prior=(1, 9), epsilon=0.1), "leave epsilon=None"),
    (dict(likelihood="ci", flip_prior=(1, 9), epsilon=0.1), "leave epsilon=None"),
    (dict(likelihood="ci", flip_prior=(0, 9)), "flip_prior must be"),
    (dict(likelihood="ci", flip_prior=(1, 2, 3)), "flip_prior must be"),
    (dict(likelihood="ci", flip_prior=(True, 2)), "flip_prior must be"),
    (dict(likelihood="ci", flip_prior="ab"), "flip_prior must be"),
    (dict(likelihood="ci", flip_prior=(1, math.inf)), "flip_prior must be"),
    (dict(likelihood="size"), "likelihood must be"),
])
def test_bad_flip_prior_is_a_clear_error(params, match):
    X, y, roles = _small_problem()
    with pytest.raises(ValueError, match=match):
        BSIClassifier(**params, **roles).fit(X, y)


def test_new_settings_are_reproducible_and_pickle():
    X, y, roles = _small_problem(seed=1)
    for likelihood, flip_prior in NEW[:3]:
        for inference in ("exact", "mcmc"):
            kw = dict(likelihood=likelihood, flip_prior=flip_prior, inference=inference,
                      n_samples=1000, random_state=3, **roles)
            a = BSIClassifier(**kw).fit(X, y)
            b = pickle.loads(pickle.dumps(BSIClassifier(**kw).fit(X, y)))
            assert np.array_equal(a.posterior_.probabilities, b.posterior_.probabilities)
            assert np.array_equal(a.predict_proba(X), b.predict_proba(X))
            assert a.flip_rate_ == b.flip_rate_
            assert a.flip_rate_interval_ == b.flip_rate_interval_


def test_default_epsilon_is_the_papers_for_the_calibrated_likelihood():
    model = make_model(prior="forest", likelihood="calibrated", n_globals=2, n_subtasks=3)
    assert model.log_eps == pytest.approx(default_log_epsilon(2, 3))
    assert (model.flip_a, model.flip_b) == (0.0, 0.0)
