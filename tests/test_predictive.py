"""The posterior predictive (issue 31): ``predict_proba`` includes the label noise.

Checked against references written independently of ``bsi_sklearn.predictive``: every
specification enumerated from first principles (``_reference.brute_force_posterior``) and, with
a flip prior, the flip rate integrated numerically over the joint posterior of (specification,
flip rate); MCMC against exact inference; and the paper's vote, bit for bit, under
``vote="satisfaction"``.
"""

import math
import pickle

import numpy as np
import pytest
from _reference import brute_force_posterior
from poi_problems import make_poi_problem
from scipy import integrate, stats

from bsi_sklearn import BSIClassifier
from bsi_sklearn.predictive import fixed_noise, learned_noise, predictive_log_proba


def _small_problem(seed=3):
    # 6 acceptable and 4 unacceptable demonstrations; one acceptable label flipped.
    X, y, roles = make_poi_problem(n_demos=6, n_threats=2, n_pois=3, chain=(0, 2),
                                   n_negative=4, seed=seed, always_violated=(1,))
    y = y.copy()
    y[0] = 0
    return X, y, roles


def _new_demos(n=12, seed=17):
    # Fresh demonstrations of the same task (same propositions), acceptable or not.
    X, _, _ = make_poi_problem(n_demos=n // 2, n_threats=2, n_pois=3, chain=(0, 2),
                               n_negative=n - n // 2, seed=seed, always_violated=(1,))
    return X


def _satisfied(spec, X, names):
    return np.array([spec.satisfied_by(x, feature_names=names) for x in X])


def _reference(X, y, roles, prior, likelihood, names=None, **kw):
    names = list(X[0].columns) if names is None else names
    return brute_force_posterior(X, y, names, roles["global_candidates"],
                                 roles["subtasks"], roles["conditions"], prior, likelihood,
                                 **kw)


@pytest.mark.parametrize("prior", ["sets_of_chains", "forest"])
@pytest.mark.parametrize("likelihood, epsilon", [("cb", None), ("ci", None), ("ci", 0.2),
                                                 ("calibrated", None), ("cb", 0.05)])
def test_fixed_epsilon_predictive_from_first_principles(prior, likelihood, epsilon):
    X, y, roles = _small_problem()
    clf = BSIClassifier(prior=prior, likelihood=likelihood, epsilon=epsilon,
                        label_noise="likelihood", inference="exact", tol=0.0,
                        **roles).fit(X, y)
    log_eps = clf.log_epsilon_
    ref = _reference(X, y, roles, prior, likelihood, log_eps=log_eps)
    X_new = X + _new_demos()
    names = list(X[0].columns)
    # P(y = 1 | x) = sum_phi P(phi | D) [(1 - eps) if x |= phi else eps], summed per side.
    sat_mass = np.zeros(len(X_new))
    for spec, p in ref.items():
        sat_mass += p * _satisfied(spec, X_new, names)
    viol_mass = np.array([math.fsum(p for s, p in ref.items()
                                    if not s.satisfied_by(x, feature_names=names))
                          for x in X_new])
    eps = math.exp(log_eps)
    want_1 = sat_mass * (1 - eps) + viol_mass * eps
    want_0 = viol_mass * (1 - eps) + sat_mass * eps
    proba = clf.predict_proba(X_new)
    np.testing.assert_allclose(proba[:, 1], want_1, rtol=1e-9, atol=1e-15)
    np.testing.assert_allclose(proba[:, 0], want_0, rtol=1e-9, atol=1e-15)
    # log space: log P(0) of a demonstration (nearly) every formula accepts is ~log eps
    # (relative); a log near 0 is compared absolutely (log of a float near 1 loses digits).
    np.testing.assert_allclose(clf.predict_log_proba(X_new),
                               np.log(np.column_stack([want_0, want_1])), rtol=1e-9,
                               atol=1e-15)


@pytest.mark.parametrize("prior", ["sets_of_chains", "forest"])
@pytest.mark.parametrize("likelihood, epsilon", [("cb", None), ("ci", 0.2), ("calibrated", None)])
def test_learned_noise_predictive_from_first_principles(prior, likelihood, epsilon):
    # label_noise="learned" (the default): every specification of the exact posterior keeps
    # its posterior mass and labels with the flip rate Beta(1 + v, 1 + n - v)'s mean, v the
    # training demonstrations it misclassifies, counted here from the traces.
    X, y, roles = _small_problem()
    clf = BSIClassifier(prior=prior, likelihood=likelihood, epsilon=epsilon,
                        inference="exact", tol=0.0, **roles).fit(X, y)
    ref = _reference(X, y, roles, prior, likelihood, log_eps=clf.log_epsilon_)
    names = list(X[0].columns)
    labels = np.asarray(y) == 1
    X_new = X + _new_demos()
    want = np.zeros(len(X_new))
    for spec, p in ref.items():
        v = int((_satisfied(spec, X, names) != labels).sum())
        rho = (1.0 + v) / (2.0 + len(y))
        want += p * np.where(_satisfied(spec, X_new, names), 1.0 - rho, rho)
    proba = clf.predict_proba(X_new)
    np.testing.assert_allclose(proba[:, 1], want, rtol=1e-9)
    np.testing.assert_allclose(proba[:, 0], 1.0 - want, rtol=1e-9)
    # No probability below the smallest flip rate, 1 / (n + 2), on either side.
    assert proba.min() >= 1.0 / (2.0 + len(y)) * (1 - 1e-12)
    # The likelihood's own epsilon is one set_params away, without a refit.
    fixed = clf.set_params(label_noise="likelihood").predict_proba(X_new)
    assert not np.allclose(fixed, proba)


def _joint_predictive(X, y, roles, prior, a, b, X_new):
    # P(y = 1 | x, D) over the joint posterior of (specification, flip rate): the prior of
    # every specification (its likelihood on no data), times the Beta(a, b) density of the
    # flip rate and the labels' likelihood given both, integrated over the flip rate by
    # quadrature over (0, 1/2), where the prior restricts it (the restricted prior's
    # normaliser is common to every term). Nothing here uses the Beta function's closed form.
    names = list(X[0].columns)
    prior_of = _reference(X[:0], y[:0], roles, prior, "ci", names=names, flip_prior=(a, b))
    labels = np.asarray(y) == 1
    num, den = np.zeros(len(X_new)), 0.0
    for spec, p in prior_of.items():
        v = int((_satisfied(spec, X, names) != labels).sum())
        n = len(y)

        def weight(e, v=v, n=n):
            return e ** (a - 1 + v) * (1 - e) ** (b - 1 + n - v) / math.gamma(a) \
                / math.gamma(b) * math.gamma(a + b)

        z = integrate.quad(weight, 0, 0.5, epsabs=0, epsrel=1e-12, limit=200)[0]
        m = integrate.quad(lambda e: e * weight(e), 0, 0.5, epsabs=0, epsrel=1e-12,
                           limit=200)[0]
        sat = _satisfied(spec, X_new, names)
        num += p * np.where(sat, z - m, m)
        den += p * z
    return num / den


@pytest.mark.parametrize("prior", ["sets_of_chains", "linear_chain"])
@pytest.mark.parametrize("a, b", [(1.0, 9.0), (2.0, 3.0)])
def test_flip_prior_predictive_against_numerical_integration(prior, a, b):
    X, y, roles = _small_problem()
    clf = BSIClassifier(prior=prior, likelihood="ci", flip_prior=(a, b), inference="exact",
                        tol=0.0, **roles).fit(X, y)
    X_new = X + _new_demos()
    want = _joint_predictive(X, y, roles, prior, a, b, X_new)
    proba = clf.predict_proba(X_new)
    np.testing.assert_allclose(proba[:, 1], want, rtol=1e-8)
    np.testing.assert_allclose(proba[:, 0], 1 - want, rtol=1e-8)
    # The flip rate matters here: the vote alone is far from the predictive.
    vote = clf.set_params(vote="satisfaction").predict_proba(X_new)[:, 1]
    assert np.abs(vote - want).max() > 0.05


def test_flip_rates_per_specification_match_the_engines_violation_mass():
    # The exact engine sums the misclassified count by mass over the whole support; fit counts
    # it per listed specification: both give the same distribution of the count.
    X, y, roles = _small_problem(seed=5)
    clf = BSIClassifier(likelihood="ci", flip_prior=(1.0, 4.0), inference="exact", tol=0.0,
                        **roles).fit(X, y)
    noise = clf._noise()
    names = list(X[0].columns)
    post = clf.posterior_
    labels = np.asarray(y) == 1
    v = np.array([(_satisfied(s, X, names) != labels).sum() for s in post.specifications])
    rho = np.exp(noise.log_rho[noise.group])
    # the mean of Beta(1 + v, 4 + n - v) restricted to (0, 1/2), by scipy's quadrature
    want = [stats.beta(1.0 + k, 4.0 + len(y) - k).expect(lambda e: e, lb=0.0, ub=0.5,
                                                         conditional=True) for k in v]
    np.testing.assert_allclose(rho, want, rtol=1e-9)
    # The flip rate's posterior mean is the predictive's flip rate averaged over the posterior.
    assert float(post.probabilities @ rho) == pytest.approx(clf.flip_rate_, rel=1e-9)


@pytest.fixture(scope="module")
def poi():
    return make_poi_problem(n_demos=50, n_negative=10, seed=11)


@pytest.mark.parametrize("likelihood, flip_prior", [("cb", None), ("ci", (1.0, 9.0)),
                                                   ("calibrated", None)])
def test_mcmc_predictive_agrees_with_exact(poi, likelihood, flip_prior):
    X, y, roles = poi
    y = y.copy()
    y[[0, 1, 2]] = 0  # flipped labels, so the noise model has something to say
    kw = dict(likelihood=likelihood, flip_prior=flip_prior, **roles)
    exact = BSIClassifier(inference="exact", **kw).fit(X, y)
    mcmc = BSIClassifier(inference="mcmc", n_samples=2000, random_state=0, **kw).fit(X, y)
    X_new = X + make_poi_problem(n_demos=20, n_negative=20, seed=12)[0]
    gap = np.abs(exact.predict_proba(X_new) - mcmc.predict_proba(X_new)).max()
    assert gap <= 0.02, gap


def _settings():
    return [dict(), dict(likelihood="ci"), dict(likelihood="calibrated"),
            dict(likelihood="ci", flip_prior=(1, 9)),
            dict(likelihood="ci", flip_prior=(1, 9), inference="mcmc", n_samples=2000,
                 random_state=0)]


@pytest.mark.parametrize("kw", _settings())
def test_rows_sum_to_one_and_predict_is_the_argmax(poi, kw):
    X, y, roles = poi
    clf = BSIClassifier(**roles, **kw).fit(X[:30] + X[50:], np.r_[y[:30], y[50:]])
    X_new = X + make_poi_problem(n_demos=20, n_negative=20, seed=12)[0]
    proba = clf.predict_proba(X_new)
    assert proba.shape == (len(X_new), 2) and np.all((proba >= 0) & (proba <= 1))
    np.testing.assert_allclose(proba.sum(axis=1), 1.0, rtol=0, atol=4e-16)
    pred = clf.predict(X_new)
    untied = proba[:, 0] != proba[:, 1]
    np.testing.assert_array_equal(pred[untied], clf.classes_[proba.argmax(axis=1)][untied])
    np.testing.assert_array_equal(pred, clf.classes_[(proba[:, 1] >= proba[:, 0]).astype(int)])
    log_proba = clf.predict_log_proba(X_new)
    assert np.isfinite(log_proba).all()
    np.testing.assert_allclose(np.exp(log_proba), proba, rtol=1e-15, atol=0)


def test_a_tie_goes_to_acceptable():
    # Half the mass satisfies x0: both labels exactly 1/2, as the vote's ">= 1/2" decided.
    masks = np.array([[1], [3]], dtype=np.uint64)
    words = np.array([[1]], dtype=np.uint64)
    for noise in (fixed_noise(2, math.log(0.1)), learned_noise([1, 1], 10, (1.0, 9.0))):
        lp = predictive_log_proba(masks, np.array([0.5, 0.5]), words, noise)
        assert lp[0, 0] == lp[0, 1] == pytest.approx(math.log(0.5))


def _old_vote(clf, X):
    # The vote as main computed it (Posterior.predict_proba, before issue 31), rewritten here:
    # the probabilities of the satisfied specifications summed in posterior order, clipped.
    post = clf.posterior_
    sat = post.satisfaction(X)
    p1 = np.empty(sat.shape[1])
    for i in range(sat.shape[1]):
        acc = 0.0
        for h in range(sat.shape[0]):
            if sat[h, i]:
                acc += float(post.probabilities[h])
        p1[i] = acc
    p1 = np.clip(p1, 0.0, 1.0)
    return np.column_stack([1.0 - p1, p1])


@pytest.mark.parametrize("kw", _settings())
def test_satisfaction_is_the_papers_vote_bit_for_bit(poi, kw):
    X, y, roles = poi
    clf = BSIClassifier(vote="satisfaction", **roles, **kw).fit(X, y)
    X_new = X + make_poi_problem(n_demos=20, n_negative=20, seed=12)[0]
    old = _old_vote(clf, X_new)
    proba = clf.predict_proba(X_new)
    assert np.array_equal(proba, old)
    assert np.array_equal(proba, clf.posterior_.predict_proba(X_new))
    with np.errstate(divide="ignore"):
        assert np.array_equal(clf.predict_log_proba(X_new), np.log(old))
    np.testing.assert_array_equal(clf.predict(X_new), (old[:, 1] >= 0.5).astype(int))
    # The same fit predicts both ways: vote is read at prediction time.
    predictive = clf.set_params(vote="predictive").predict_proba(X_new)
    assert not np.array_equal(predictive, old)
    assert np.array_equal(clf.set_params(vote="satisfaction").predict_proba(X_new), old)


def test_a_tiny_epsilon_keeps_log_proba_exact():
    # CB's default log epsilon is -4 log(2) M: -2000 for M = 721 clause slots, where epsilon
    # itself is 0 as a float. Every formula accepts x0; only a flip makes it unacceptable.
    masks = np.array([[1], [3], [0]], dtype=np.uint64)
    words = np.array([[3], [1], [0]], dtype=np.uint64)
    probs = np.array([0.6, 0.3, 0.1])
    lp = predictive_log_proba(masks, probs, words, fixed_noise(3, -2000.0))
    assert np.isfinite(lp).all()
    assert lp[0].tolist() == [-2000.0, 0.0]
    assert lp[1, 1] == pytest.approx(math.log(0.7)) and lp[1, 0] == pytest.approx(math.log(0.3))
    assert lp[2, 1] == pytest.approx(math.log(0.1))
    assert lp[2, 0] == pytest.approx(math.log(0.9), abs=1e-15)
    assert np.exp(lp)[0].tolist() == [0.0, 1.0]


def test_a_demonstration_every_formula_accepts_has_log_proba_log_epsilon():
    # With its conditions false at the first step, every F and U clause holds vacuously and
    # every formula accepts the demonstration: P(unacceptable) = epsilon = 1e-300, which
    # 1 - P(acceptable) would round to 0, is kept, and its log is exact.
    X, y, roles = _small_problem()
    clf = BSIClassifier(likelihood="ci", epsilon=1e-300, label_noise="likelihood",
                        inference="exact", **roles).fit(X, y)
    x = X[0].copy()
    x.loc[:, :] = False
    x[["tau_0", "tau_1"]] = True
    assert clf.posterior_.satisfaction([x]).all()
    log_proba = clf.predict_log_proba([x])
    assert log_proba[0, 0] == pytest.approx(math.log(1e-300), rel=1e-15)
    assert log_proba[0, 1] == 0.0
    assert clf.predict_proba([x])[0, 0] == pytest.approx(1e-300, rel=1e-12)
    with np.errstate(divide="ignore"):
        assert clf.set_params(vote="satisfaction").predict_log_proba([x])[0, 0] < -30


@pytest.mark.parametrize("kw", [dict(), dict(likelihood="ci", flip_prior=(1, 9)),
                                dict(likelihood="ci", flip_prior=(1, 9), inference="mcmc",
                                     n_samples=2000)])
def test_pickle_preserves_predictions(poi, kw):
    X, y, roles = poi
    clf = BSIClassifier(random_state=0, **roles, **kw).fit(X, y)
    again = pickle.loads(pickle.dumps(clf))
    assert np.array_equal(clf.predict_proba(X), again.predict_proba(X))
    assert np.array_equal(clf.predict_log_proba(X), again.predict_log_proba(X))
    assert np.array_equal(clf.predict(X), again.predict(X))


def test_a_bad_label_noise_is_a_clear_error(poi):
    X, y, roles = poi
    with pytest.raises(ValueError, match="label_noise"):
        BSIClassifier(label_noise="epsilon", **roles).fit(X, y)
    clf = BSIClassifier(**roles).fit(X, y).set_params(label_noise=0.1)
    with pytest.raises(ValueError, match="label_noise"):
        clf.predict_proba(X)


def test_a_bad_vote_is_a_clear_error(poi):
    X, y, roles = poi
    with pytest.raises(ValueError, match="vote"):
        BSIClassifier(vote="majority", **roles).fit(X, y)
    clf = BSIClassifier(**roles).fit(X, y).set_params(vote="mass")
    with pytest.raises(ValueError, match="vote"):
        clf.predict_proba(X)
    with pytest.raises(ValueError, match="vote"):
        clf.predict(X)
