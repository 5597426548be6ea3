"""Tempering, the joint structure moves, the beam optimum and the completed support, each
against exact enumeration on small random problems (issue 19)."""

import warnings

import numpy as np
import pytest
from sklearn.exceptions import ConvergenceWarning

from bsi_sklearn import BSIClassifier
from bsi_sklearn.inference._chain_kernel import score_one
from bsi_sklearn.inference._local_search import n_neighbours_max, neighbourhood
from bsi_sklearn.inference.diagnostics import disagreement_problems, total_variation
from bsi_sklearn.inference.exact import exact_posterior
from bsi_sklearn.inference.mcmc import (
    deduplicate_demos,
    deterministic_optimum,
    run_chain,
    sample_posterior,
    score_states,
    temperature_ladder,
)
from bsi_sklearn.model import make_model
from bsi_sklearn.model.priors import PRIORS


def _problem(prior, likelihood="ci", epsilon=0.2, seed=1, n_g=1, n=3, n_demos=12):
    # Random clause truth (the sampler reads nothing else), 70% acceptable demonstrations.
    rng = np.random.default_rng(seed)
    truth = (rng.random((n_demos, n_g + n + n * n)) < 0.8).astype(np.uint8)
    y01 = (rng.random(n_demos) < 0.7).astype(np.int64)
    model = make_model(prior=prior, likelihood=likelihood, n_globals=n_g, n_subtasks=n,
                       epsilon=epsilon)
    return truth, y01, model


def _support(truth, y01, model):
    # Every hypothesis of the support (tol=0 lists them all) as sampler rows, and the exact
    # log prior and log-likelihood of each.
    res = exact_posterior(truth, y01, model, tol=0.0)
    rows = np.concatenate([res.tau_masks, res.w1_masks, res.structures], axis=1).astype(np.int16)
    demos = deduplicate_demos(truth, y01)
    n_g, n = model.n_g, model.n
    parts = np.array([score_one(r[:n_g].astype(np.int64), r[n_g:n_g + n].astype(np.int64),
                                r[n_g + n:].astype(np.int64), demos, model) for r in rows])
    return rows, parts[:, 0], parts[:, 1], res


def _tempered(rows, lp, ll, beta):
    w = lp + beta * ll
    p = np.exp(w - w.max())
    return {tuple(r): q for r, q in zip(rows.tolist(), p / p.sum())}


def _frequencies(truth, y01, model, betas, n_samples, seeds=(0, 1)):
    demos = deduplicate_demos(truth, y01)
    freq = {}
    for seed in seeds:  # each chain from its own draws of the prior
        out = run_chain(seed, demos, model, n_samples, 100, betas)
        for r, c in zip(out.states.tolist(), out.counts):
            freq[tuple(r)] = freq.get(tuple(r), 0) + c
    total = sum(freq.values())
    return {k: v / total for k, v in freq.items()}, out


@pytest.mark.parametrize("prior", PRIORS)
def test_tempered_chain_samples_the_exact_posterior(prior):
    """The beta = 1 replica's sample frequencies (not reweighted) match the exact posterior:
    swaps, tempered moves and the structure moves with the eventual bit leave it invariant."""
    truth, y01, model = _problem(prior)
    rows, lp, ll, _ = _support(truth, y01, model)
    freq, out = _frequencies(truth, y01, model, [1.0, 0.4, 0.05], 150_000)
    assert total_variation(_tempered(rows, lp, ll, 1.0), freq) <= 0.01
    assert (out.swap_rate > 0.1).all()  # the swaps did happen


@pytest.mark.parametrize("prior", PRIORS)
def test_one_rung_at_a_lower_beta_samples_the_tempered_target(prior):
    """A replica at beta < 1 samples prior x likelihood^beta: the moves temper correctly."""
    truth, y01, model = _problem(prior, likelihood="cb", epsilon=0.05, seed=2)
    rows, lp, ll, _ = _support(truth, y01, model)
    freq, _ = _frequencies(truth, y01, model, [0.3], 250_000)
    assert total_variation(_tempered(rows, lp, ll, 0.3), freq) <= 0.01


def test_ladder_rule():
    truth, y01, model = _problem("sets_of_chains", likelihood="cb", epsilon=None)
    demos = deduplicate_demos(truth, y01)
    betas = temperature_ladder(demos, model)
    scale = max(-model.log_eps, demos.n_pos * np.log(2))
    assert betas[0] == 1.0 and betas[-1] == pytest.approx(1 / scale)
    assert len(betas) == 1 + int(np.ceil(np.log2(scale)))
    assert np.all(np.diff(betas) < 0)
    assert np.all(betas[1:-1] == 0.5 ** np.arange(1, len(betas) - 1))
    assert temperature_ladder(demos, model, 1).tolist() == [1.0]
    three = temperature_ladder(demos, model, 3)
    assert three[0] == 1.0 and three[-1] == pytest.approx(1 / scale)
    assert three[1] == pytest.approx(np.sqrt(three[2]))


@pytest.mark.parametrize("prior", PRIORS)
def test_neighbourhood_is_every_one_block_change(prior):
    """The local search's neighbours of a hypothesis are exactly the hypotheses of the support
    that differ from it in one global bit, or in one subtask's eventual bit and place."""
    truth, y01, model = _problem(prior, n_g=2)
    rows, lp, ll, _ = _support(truth, y01, model)
    demos = deduplicate_demos(truth, y01)
    n_g, n = model.n_g, model.n
    support = {tuple(r) for r in rows.tolist()}

    def moved(a, b, v):
        # b is a with subtask v (its subtree, for forests) placed elsewhere: the rest of the
        # order structure is the same once v is taken out.
        pa, pb = np.array(a[n_g + n:]), np.array(b[n_g + n:])
        if model.forest:
            return all(pa[u] == pb[u] for u in range(n) if u != v)

        def without(p):
            p = p.copy()
            p[p == v] = p[v]
            p[v] = -1
            return p.tolist()
        return without(pa) == without(pb)

    for a in list(support)[::7]:
        want = set()
        for b in support:
            diff = [i for i in range(n_g + n) if a[i] != b[i]]
            if diff and all(i < n_g for i in diff) and len(diff) == 1 and \
                    a[n_g + n:] == b[n_g + n:]:
                want.add(b)
            for v in range(n):
                if all(a[i] == b[i] for i in range(n_g + n) if i != n_g + v) and moved(a, b, v):
                    want.add(b)
        got, got_lp = neighbourhood(np.array([a], dtype=np.int64), demos, model, -np.inf)
        got_set = {tuple(r) for r in got.tolist()} & support  # Prior 1: no new chains
        assert got_set == want
        assert len(got) <= n_neighbours_max(n_g, n)
        assert np.allclose(got_lp, score_states(got, demos, model), rtol=0, atol=1e-9)


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("seed", [3, 4])
def test_deterministic_optimum_is_the_exact_map(prior, seed):
    truth, y01, model = _problem(prior, likelihood="cb", epsilon=0.05, seed=seed, n_g=2)
    rows, lp, ll, _ = _support(truth, y01, model)
    demos = deduplicate_demos(truth, y01)
    row, score = deterministic_optimum(demos, model)
    assert score == pytest.approx(score_states(row[None, :], demos, model)[0], abs=1e-9)
    assert score == pytest.approx((lp + ll).max(), abs=1e-9)


@pytest.mark.parametrize("prior", PRIORS)
def test_reported_posterior_is_exact_on_its_support(prior):
    """Visited states, the optimum and the completed neighbourhood: every probability is the
    exact posterior restricted to the reported support, renormalised."""
    truth, y01, model = _problem(prior, seed=5)
    rows, lp, ll, _ = _support(truth, y01, model)
    exact = _tempered(rows, lp, ll, 1.0)
    res = sample_posterior(truth, y01, model, [1, 2], n_samples=200, burn_in=10)
    got = np.concatenate([res.tau_masks, res.w1_masks, res.structures], axis=1).astype(np.int16)
    keys = [tuple(r) for r in got.tolist()]
    assert len(set(keys)) == len(keys) and set(keys) <= set(exact)
    want = np.array([exact[k] for k in keys])
    assert np.allclose(res.probabilities, want / want.sum(), rtol=1e-9, atol=1e-15)
    assert np.all(np.diff(res.probabilities) <= 0)
    diag = res.diagnostics
    assert diag["n_added"] == len(keys) - diag["n_visited"] >= 0
    assert diag["sample_frequencies"].sum() == pytest.approx(1.0)


def _trap():
    # Globals only, one-step traces. G0 and G1 each exclude three negatives, and both fail the
    # three acceptable demonstrations of kind B; G2 excludes all six and fails no acceptable
    # one. From the empty hypothesis Gibbs adds G0 and G1 (each gains more than the B
    # demonstrations cost), then G2, and stays: dropping G0 or G1 alone still fails B and
    # loses the size reward of 20 acceptable demonstrations (about 15 nats a step), while
    # {G2} alone is e^16 times more probable than {G0, G1, G2}.
    rows = [(1, 1, 1)] * 20 + [(0, 0, 1)] * 3 + [(0, 1, 0)] * 3 + [(1, 0, 0)] * 3
    y = np.array([1] * 23 + [0] * 6)
    roles = dict(global_candidates=[0, 1, 2], subtasks=[], epsilon=1e-6)
    return np.array(rows, dtype=bool), y, roles


def _fit_recording(X, y, **params):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        clf = BSIClassifier(**params).fit(X, y)
    return clf, [w for w in caught if issubclass(w.category, ConvergenceWarning)]


def test_chains_start_at_the_optimum_that_untempered_gibbs_cannot_reach():
    X, y, roles = _trap()
    exact = BSIClassifier(inference="exact", **roles).fit(X, y)
    assert exact.map_specification_.globals == {2}
    # From the empty hypothesis, an untempered chain climbs to {G0, G1, G2} and stays:
    # run_chain with that start shows the trap, and the deterministic optimum the gap.
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=3, n_subtasks=0,
                       epsilon=1e-6)
    truth = X.astype(np.uint8)  # globals only: the clause truth is the trace itself
    demos = deduplicate_demos(truth, y)
    optimum, optimum_lp = deterministic_optimum(demos, model)
    stuck = run_chain(0, demos, model, 500, 100, None, np.zeros(3, dtype=np.int64))
    assert stuck.states.tolist() == [[1, 1, 1]]
    gap = optimum_lp - float(score_states(stuck.states.astype(np.int64), demos, model)[0])
    assert gap == pytest.approx(16.39, abs=0.01)
    diag = {"optimum_gap": gap, "max_missed_mass": 0.0, "missed_mass_per_chain": [0.0],
            "rhat": 1.0}
    assert ["missed a mode" in m for m in disagreement_problems(diag)] == [True]
    # The estimator's chains start at the optimum: without tempering too, they report the
    # exact posterior, and nothing is said.
    for n_temperatures in (1, "auto"):
        clf, caught = _fit_recording(X, y, inference="mcmc", n_temperatures=n_temperatures,
                                     random_state=0, **roles)
        assert caught == [] and clf.mcmc_diagnostics_["optimum_gap"] <= 0.0
        assert total_variation(exact.posterior_, clf.posterior_) <= 1e-6


def test_no_wrong_mode_warning_on_an_easy_problem():
    X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
         np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])] * 3
    clf, caught = _fit_recording(X, None, inference="mcmc", global_candidates=[0],
                                 subtasks=[1, 2], n_samples=500, random_state=0)
    assert caught == []
    assert clf.mcmc_diagnostics_["optimum_gap"] <= 0.0
