"""The inclusion probability learned (``p_global="learned"``, ``p_eventual="learned"``).

Uniform on (0, 1) and integrated out (Scott and Berger 2010): a subset of ``k`` of ``n``
clauses has prior ``k! (n - k)! / (n + 1)!``, every size equally probable. Checked against a
first-principles posterior (exact engine), the exact posterior (sampler), and its own closed
forms; a fixed probability is untouched (``test_posterior_values`` pins it to the bit).
"""

import math

import numpy as np
import pytest
from _reference import brute_force_posterior
from poi_problems import make_poi_problem

from bsi_sklearn import BSIClassifier
from bsi_sklearn.inference.diagnostics import total_variation
from bsi_sklearn.model import make_model
from bsi_sklearn.model.priors import (
    LEARNED,
    draw_hypothesis,
    log_prior_subset,
    subset_inclusion,
)


@pytest.mark.parametrize("n", [0, 1, 5, 40])
def test_every_size_is_equally_probable_and_the_subsets_sum_to_one(n):
    sizes = [math.comb(n, k) * math.exp(log_prior_subset(k, n, LEARNED)) for k in range(n + 1)]
    np.testing.assert_allclose(sizes, 1.0 / (n + 1), rtol=1e-12)
    assert math.fsum(sizes) == pytest.approx(1.0, rel=1e-12)


@pytest.mark.parametrize("p", [0.8, 0.2, LEARNED])
def test_one_more_item_is_weighed_by_the_change_of_the_subset_prior(p):
    n = 7
    for k in range(n):  # k of the other n - 1 items in
        lin, lout = subset_inclusion(k, n, p)
        assert lin - lout == pytest.approx(
            log_prior_subset(k + 1, n, p) - log_prior_subset(k, n, p), rel=1e-12, abs=1e-12)


def test_drawn_subsets_have_every_size_alike():
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=6, n_subtasks=3,
                       p_global="learned")
    rng = np.random.default_rng(0)
    sizes = np.bincount([int(draw_hypothesis(model, rng)[0].sum()) for _ in range(7000)],
                        minlength=7)
    # 1,000 expected of each of the 7 sizes; binomial sd about 29
    assert np.abs(sizes - 1000).max() < 130, sizes


def _problem(seed=3):
    X, y, roles = make_poi_problem(n_demos=6, n_threats=2, n_pois=3, chain=(0, 2),
                                   n_negative=4, seed=seed, always_violated=(1,))
    return X, y, roles


@pytest.mark.parametrize("prior", ["sets_of_chains", "forest"])
@pytest.mark.parametrize("likelihood", ["cb", "calibrated"])
def test_exact_matches_first_principles(prior, likelihood):
    X, y, roles = _problem()
    names = list(X[0].columns)
    ref = brute_force_posterior(X, y, names, roles["global_candidates"], roles["subtasks"],
                                roles["conditions"], prior, likelihood, p_global="learned",
                                p_eventual="learned")
    clf = BSIClassifier(prior=prior, likelihood=likelihood, inference="exact", tol=0.0,
                        p_global="learned", p_eventual="learned", **roles).fit(X, y)
    assert clf.n_hypotheses_ == len(ref)
    assert total_variation(clf.posterior_, ref) < 1e-9


@pytest.mark.parametrize("prior", ["sets_of_chains", "forest"])
def test_the_sampler_agrees_with_exact(prior):
    X, y, roles = _problem(seed=5)
    params = dict(prior=prior, likelihood="calibrated", p_global="learned",
                  p_eventual="learned", **roles)
    exact = BSIClassifier(inference="exact", **params).fit(X, y)
    mcmc = BSIClassifier(inference="mcmc", random_state=0, **params).fit(X, y)
    assert total_variation(exact.posterior_, mcmc.posterior_) < 0.02
    np.testing.assert_allclose(mcmc.posterior_.clause_marginals(),
                               exact.posterior_.clause_marginals(), atol=0.02)


def test_clauses_no_demonstration_tests_keep_the_prior_over_their_number():
    # Ten propositions true throughout every demonstration: their G clauses hold on every
    # one, and no label can test them. With p_global = 0.8 each is kept at 0.8 and the MAP
    # has all ten; learned, their number is uniform over 0..10 a posteriori as a priori, so
    # each clause's inclusion is 0.5, and the subsets of the extreme sizes (none, all ten:
    # one subset each) are the most probable.
    rng = np.random.default_rng(0)
    X = [np.c_[np.ones((4, 10), dtype=int), rng.integers(0, 2, (4, 1))] for _ in range(12)]
    y = np.array([1, 0] * 6)
    roles = dict(global_candidates=list(range(10)), subtasks=[], conditions={})
    fixed = BSIClassifier(likelihood="calibrated", **roles).fit(X, y)
    learned = BSIClassifier(likelihood="calibrated", p_global="learned", **roles).fit(X, y)
    np.testing.assert_allclose(fixed.posterior_.clause_marginals(), 0.8, atol=1e-9)
    np.testing.assert_allclose(learned.posterior_.clause_marginals(), 0.5, atol=1e-9)
    assert len(fixed.map_specification_.globals) == 10
    sizes = np.zeros(11)
    for spec, p in zip(learned.posterior_.specifications, learned.posterior_.probabilities):
        sizes[len(spec.globals)] += p
    np.testing.assert_allclose(sizes, 1 / 11, atol=1e-9)
    assert len(learned.map_specification_.globals) in (0, 10)


@pytest.mark.parametrize("n", [1, 2, 5, 12])
def test_learned_chains_make_every_number_of_chains_equally_probable(n):
    # Prior 2 with p_part learned: m chains of n subtasks, of which there are the Lah number
    # n! / m! C(n - 1, m - 1) structures, have prior mass 1 / n together.
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=0, n_subtasks=n,
                       p_part="learned")
    mass = [math.factorial(n) / math.factorial(m) * math.comb(n - 1, m - 1)
            * math.exp(model.lp_chains[m]) for m in range(1, n + 1)]
    np.testing.assert_allclose(mass, 1.0 / n, rtol=1e-10)
    fixed = make_model(prior="sets_of_chains", likelihood="cb", n_globals=0, n_subtasks=n)
    assert math.fsum(math.factorial(n) / math.factorial(m) * math.comb(n - 1, m - 1)
                     * math.exp(fixed.lp_chains[m]) for m in range(1, n + 1)) == \
        pytest.approx(1.0, rel=1e-10)


def test_drawn_structures_have_every_number_of_chains_alike():
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=0, n_subtasks=4,
                       p_part="learned")
    rng = np.random.default_rng(1)
    chains = np.bincount([int((draw_hypothesis(model, rng)[2] < 0).sum()) for _ in range(4000)],
                         minlength=5)[1:]
    # 1,000 expected of each of the 4 numbers; binomial sd about 27
    assert np.abs(chains - 1000).max() < 120, chains


@pytest.mark.parametrize("likelihood", ["cb", "calibrated"])
def test_learned_chains_exact_matches_first_principles(likelihood):
    X, y, roles = _problem()
    names = list(X[0].columns)
    ref = brute_force_posterior(X, y, names, roles["global_candidates"], roles["subtasks"],
                                roles["conditions"], "sets_of_chains", likelihood,
                                p_eventual="learned", p_part="learned")
    clf = BSIClassifier(likelihood=likelihood, inference="exact", tol=0.0,
                        p_eventual="learned", p_part="learned", **roles).fit(X, y)
    assert clf.n_hypotheses_ == len(ref)
    assert total_variation(clf.posterior_, ref) < 1e-9


def test_learned_chains_the_sampler_agrees_with_exact():
    X, y, roles = _problem(seed=5)
    params = dict(likelihood="calibrated", p_eventual="learned", p_part="learned", **roles)
    exact = BSIClassifier(inference="exact", **params).fit(X, y)
    mcmc = BSIClassifier(inference="mcmc", random_state=0, **params).fit(X, y)
    assert total_variation(exact.posterior_, mcmc.posterior_) < 0.02
    np.testing.assert_allclose(mcmc.posterior_.clause_marginals(),
                               exact.posterior_.clause_marginals(), atol=0.02)


def test_learned_is_validated_like_a_probability():
    X, y, roles = _problem()
    with pytest.raises(ValueError, match="p_eventual"):
        BSIClassifier(p_eventual="learnt", **roles).fit(X, y)
    with pytest.raises(ValueError, match="p_part"):
        BSIClassifier(p_part="Learned", **roles).fit(X, y)
