"""The ladder adapted to the posterior by the burn-in's pilot (issue 29): the rule against its
definition, the kernel's acceptance probabilities against the swaps it counts, and the sampler
that uses it against exact enumeration."""

import numpy as np
import pytest

from bsi_sklearn.inference._ladder import (
    PILOT_MIN,
    adapted_ladder,
    swap_tries,
    temperature_ladder,
)
from bsi_sklearn.inference.diagnostics import total_variation
from bsi_sklearn.inference.exact import exact_posterior
from bsi_sklearn.inference.mcmc import ChainRun, deduplicate_demos, sample_posterior
from bsi_sklearn.model import make_model


def _barrier_at(betas, rejection, beta):
    # The communication barrier Lambda(beta), piecewise linear in log beta between rungs.
    cum = np.concatenate([[0.0], np.cumsum(rejection)])
    return float(np.interp(-np.log(beta), -np.log(betas), cum))


@pytest.mark.parametrize("seed", range(20))
def test_adapted_ladder_equalises_the_barrier(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 16))
    betas = 0.5 ** np.arange(n)
    betas[-1] = betas[-2] * rng.uniform(0.5, 0.99)
    rejection = rng.random(n - 1) * (rng.random(n - 1) < 0.5)  # plateaus of zero rejection
    out = adapted_ladder(betas, rejection)
    total = rejection.sum()
    assert len(out) == min(n, max(2, 1 + int(np.ceil(2 * total - 1e-9))))
    assert out[0] == 1.0 and out[-1] == betas[-1]
    assert np.all(np.diff(out) < 0) or len(out) == 2 and out[1] < 1
    if len(out) == n:
        assert out is betas or np.array_equal(out, betas)  # never more rungs: unchanged
        return
    # Equal steps of the barrier between consecutive new rungs (where the barrier rises).
    levels = [_barrier_at(betas, rejection, b) for b in out]
    assert levels == pytest.approx(np.linspace(0, total, len(out)), abs=1e-9)


def test_adapted_ladder_edge_cases():
    betas = 0.5 ** np.arange(6)
    assert adapted_ladder(betas, np.zeros(5)).tolist() == [1.0, betas[-1]]
    assert adapted_ladder(betas, np.ones(5)).tolist() == betas.tolist()  # Lambda = 5: keep all
    assert adapted_ladder(betas[:2], np.ones(1)).tolist() == betas[:2].tolist()
    # Rejection estimates a hair outside [0, 1] (rounding) are clipped, not extrapolated.
    out = adapted_ladder(betas, np.array([0, 0, 1.0000001, 0, -1e-12]))
    assert len(out) == 3 and out[1] == pytest.approx(betas[2] * 0.5 ** 0.5)


def test_swap_tries_counts_the_kernel_parity():
    # Pair k proposes after the sweeps of k's parity: sweeps 0, 2, 4 for even pairs.
    assert swap_tries(5, 4).tolist() == [3, 2, 3, 2]
    assert swap_tries(0, 3).tolist() == [0, 0, 0]


def _problem(seed=3, n_g=2, n=3, n_demos=40, epsilon=None):
    rng = np.random.default_rng(seed)
    truth = (rng.random((n_demos, n_g + n + n * n)) < 0.75).astype(np.uint8)
    y01 = (rng.random(n_demos) < 0.7).astype(np.int64)
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=n_g, n_subtasks=n,
                       epsilon=epsilon)
    return truth, y01, model


def test_acceptance_probabilities_match_the_counted_swaps():
    """The kernel's summed acceptance probabilities (what the pilot reads) and the swaps it
    accepted have the same mean."""
    truth, y01, model = _problem()
    demos = deduplicate_demos(truth, y01)
    betas = temperature_ladder(demos, model)
    assert len(betas) >= 4
    run = ChainRun(0, demos, model, betas).advance(20_000)
    tries = swap_tries(int(run.loop.counters[0]), len(betas) - 1)
    counted, expected = run.loop.swaps / tries, run.loop.accept / tries
    assert np.abs(counted - expected).max() < 0.03, (counted, expected)
    assert (expected < 0.99).any()  # some swaps are refused: the check is not vacuous


def test_the_pilot_adapts_the_default_ladder_only():
    truth, y01, model = _problem()
    demos = deduplicate_demos(truth, y01)
    default = temperature_ladder(demos, model)
    res = sample_posterior(truth, y01, model, [0, 1, 2, 3])
    diag = res.diagnostics
    ladder = diag["ladder"]
    assert np.array_equal(ladder["default_betas"], default)
    assert ladder["pilot_rejection"].shape == (len(default) - 1,)
    assert ladder["barrier"] == pytest.approx(ladder["pilot_rejection"].sum())
    assert ladder["restarted"] == []  # every pilot ends within the margin of the best
    adapted = adapted_ladder(default, ladder["pilot_rejection"])
    assert np.array_equal(ladder["adapted_betas"], adapted)
    # The first round ran on one rung and the stopping rule held after it (a peaked
    # posterior): its samples are reported; otherwise the adapted ladder's.
    assert ladder["untempered"]
    assert np.array_equal(diag["betas"], [1.0])
    assert diag["swap_rate"].shape == (4, len(diag["betas"]) - 1)
    # The pilot's sweeps are burned sweeps.
    assert (diag["burn_in_per_chain"] >= 100).all()
    # A fixed number of rungs, or a burn-in too short for a pilot: the ladder is not adapted.
    fixed = sample_posterior(truth, y01, model, [0, 1], n_temperatures=4).diagnostics
    assert fixed["ladder"] is None and len(fixed["betas"]) == 4
    short = sample_posterior(truth, y01, model, [0, 1], burn_in=PILOT_MIN - 1).diagnostics
    assert short["ladder"] is None and np.array_equal(short["betas"], default)


# A peaked posterior and a flatter one (38 specifications, MAP 0.40), both reported from the
# untempered first round, and one whose untempered round does not satisfy the stopping rule,
# so that the rounds start over on the adapted ladder (6 -> 6 rungs).
@pytest.mark.parametrize("seed, epsilon, untempered", [(3, None, True), (4, 0.05, True),
                                                       (6, 0.05, False)])
def test_adapted_sampler_is_reproducible_and_agrees_with_exact(seed, epsilon, untempered):
    truth, y01, model = _problem(seed, epsilon=epsilon)
    a = sample_posterior(truth, y01, model, [0, 1, 2, 3], n_jobs=1)
    b = sample_posterior(truth, y01, model, [0, 1, 2, 3], n_jobs=2)
    ladder = a.diagnostics["ladder"]
    assert ladder["untempered"] is untempered
    used = [1.0] if untempered else ladder["adapted_betas"]
    assert np.array_equal(a.diagnostics["betas"], used)
    assert len(ladder["adapted_betas"]) <= len(ladder["default_betas"])
    # Burned: the pilot's sweeps, and the untempered round's where it was not kept.
    burned = int(a.diagnostics["burn_in_per_chain"].min())
    assert burned >= 100 if untempered else burned >= 100 + 500
    assert np.array_equal(a.diagnostics["betas"], b.diagnostics["betas"])
    assert np.array_equal(a.probabilities, b.probabilities)
    assert np.array_equal(a.structures, b.structures)
    exact = exact_posterior(truth, y01, model, tol=0.0)

    def as_dict(r, probs):
        rows = np.concatenate([r.tau_masks, r.w1_masks, r.structures], axis=1)
        return {tuple(x): p for x, p in zip(rows.astype(int).tolist(), probs)}

    assert total_variation(as_dict(exact, np.exp(exact.log_prob)),
                           as_dict(a, a.probabilities)) <= 0.02


def test_a_likelihood_of_steps_under_a_nat_gets_one_rung_at_beta_one():
    # CI with epsilon = 0.4: a demonstration changing side moves the likelihood by |log 0.4|
    # = 0.92 nats, under one, so no tempering is needed. The ladder was [1 / 0.92] = [1.09]:
    # one replica at beta above 1, sampling a sharpened posterior (its sample frequencies
    # 0.06 off exact in a clause's inclusion after 10,000 sweeps, hidden where the states
    # found are reweighted exactly).
    from poi_problems import make_poi_problem

    from bsi_sklearn import BSIClassifier

    X, y, roles = make_poi_problem(n_demos=18, n_threats=2, n_pois=4, chain=(0, 2),
                                   n_negative=6, seed=3, always_violated=(1,))
    kw = dict(roles, likelihood="ci", epsilon=0.4)
    model = make_model(prior="sets_of_chains", likelihood="ci", n_globals=2, n_subtasks=4,
                       epsilon=0.4)
    demos = deduplicate_demos(np.eye(3, 8, dtype=np.uint8), np.array([1.0, 0.0, 1.0]))
    assert temperature_ladder(demos, model).tolist() == [1.0]
    exact = BSIClassifier(inference="exact", **kw).fit(X, y)
    clf = BSIClassifier(inference="mcmc", n_samples=10_000, random_state=0, **kw).fit(X, y)
    assert clf.mcmc_diagnostics_["betas"].tolist() == [1.0]
    post = clf.posterior_
    sampled = clf.mcmc_diagnostics_["sample_frequencies"] @ post.clause_matrix()
    np.testing.assert_allclose(sampled, exact.posterior_.clause_marginals(), atol=0.02)


@pytest.mark.parametrize("seed, epsilon, untempered", [(3, None, True), (6, 0.05, False)])
def test_a_fixed_number_of_samples_is_recorded_on_the_ladder_the_first_round_chose(
        seed, epsilon, untempered):
    """A fixed ``n_samples`` above the first round: the first round on one rung decides, by
    the stopping rule, whether the rest runs untempered; every chain records ``n_samples``."""
    from bsi_sklearn.inference.stopping import FIRST_ROUND

    truth, y01, model = _problem(seed, epsilon=epsilon)
    res = sample_posterior(truth, y01, model, [0, 1, 2, 3], n_samples=2 * FIRST_ROUND)
    diag = res.diagnostics
    assert diag["ladder"]["untempered"] is untempered
    assert diag["n_samples"] == 2 * FIRST_ROUND
    assert np.array_equal(diag["betas"], [1.0] if untempered
                          else diag["ladder"]["adapted_betas"])
    exact = exact_posterior(truth, y01, model, tol=0.0)
    rows = np.concatenate([res.tau_masks, res.w1_masks, res.structures], axis=1)
    got = dict(zip(map(tuple, rows.astype(int).tolist()), res.probabilities))
    ex_rows = np.concatenate([exact.tau_masks, exact.w1_masks, exact.structures], axis=1)
    want = dict(zip(map(tuple, ex_rows.astype(int).tolist()), np.exp(exact.log_prob)))
    assert total_variation(want, got) <= 0.02
    # No more than the first round: no room for a trial, the adapted ladder as before.
    short = sample_posterior(truth, y01, model, [0, 1], n_samples=FIRST_ROUND).diagnostics
    assert not short["ladder"]["untempered"]
    assert np.array_equal(short["betas"], short["ladder"]["adapted_betas"])
