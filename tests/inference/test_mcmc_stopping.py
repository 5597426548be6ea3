"""``n_samples="auto"``: chains run in rounds and stop once they agree and find nothing more.

Rounds resume the chains exactly (a chain run in rounds records what one call records), the
stopping rule stops a peaked posterior after the first round and lets a flat one run to the
most, and the posterior it reports is the exact one on the problems users bring.
"""

import warnings

import numpy as np
import pytest
from poi_problems import make_poi_problem
from sklearn.exceptions import ConvergenceWarning

from bsi_sklearn import BSIClassifier
from bsi_sklearn.datasets import make_process_log
from bsi_sklearn.inference.diagnostics import total_variation
from bsi_sklearn.inference.mcmc import (
    ChainRun,
    deduplicate_demos,
    deterministic_optimum,
    run_chain,
    temperature_ladder,
)
from bsi_sklearn.inference.stopping import (
    FIRST_ROUND,
    MAX_SAMPLES,
    STOP_INCLUSION,
    STOP_LATE,
    inclusion_by_chain,
    rounds,
    should_stop,
)
from bsi_sklearn.io import EventLogEncoder, read_event_log
from bsi_sklearn.model import make_model
from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order, n_clauses
from bsi_sklearn.model.priors import PRIORS


def _poi(**kw):
    return make_poi_problem(n_demos=18, n_threats=2, n_pois=4, chain=(0, 2), n_negative=6,
                            seed=3, always_violated=(1,), **kw)


def _log(n_activities, n_cases, seed):
    log = make_process_log(n_activities, n_cases, random_state=seed)
    cases, y, _ = read_event_log(log.events, labels=log.labels)
    return EventLogEncoder().fit_transform(cases), y


@pytest.mark.parametrize("prior", PRIORS)
def test_a_chain_run_in_rounds_records_what_one_call_records(prior):
    rng = np.random.default_rng(5)
    truth = (rng.random((30, 2 + 4 + 16)) < 0.75).astype(np.uint8)
    y01 = (rng.random(30) < 0.6).astype(np.int64)
    model = make_model(prior=prior, likelihood="ci", n_globals=2, n_subtasks=4, epsilon=0.1)
    demos = deduplicate_demos(truth, y01)
    betas = temperature_ladder(demos, model, 4)
    start, lp = deterministic_optimum(demos, model)
    whole = run_chain(3, demos, model, 1000, 50, betas, start, target=lp - 3.0, max_extra=1000)
    run = ChainRun(3, demos, model, betas, start, burn_in=50, target=lp - 3.0, max_extra=1000)
    for n in (1, 299, 200, 500):
        run.advance(n)
    parts = run.result()
    # Run-length rows may be split at a round's end: compare the expanded samples.
    expand = lambda r: np.repeat(r.states, r.counts, axis=0)  # noqa: E731
    assert np.array_equal(expand(whole), expand(parts))
    assert np.array_equal(whole.trace_lp, parts.trace_lp)
    assert np.array_equal(whole.swap_rate, parts.swap_rate)
    assert (whole.move_rate, whole.n_updates, whole.n_burned) == \
        (parts.move_rate, parts.n_updates, parts.n_burned)


def test_rounds_double_up_to_the_most():
    assert rounds() == [500, 1000, 2000, 4000, 8000, 10_000]
    assert rounds(FIRST_ROUND, 700) == [500, 700] and rounds(800, 300) == [300]
    assert MAX_SAMPLES == 10_000


def test_the_stopping_rule_weighs_agreement_r_hat_and_late_discoveries():
    probs = np.array([0.99, 0.01])
    both = [np.array([0, 1]), np.array([0, 1])]
    flat = np.zeros((2, 10))
    assert should_stop(both, probs, np.array([0, 2]), flat)[0]
    # A state first found in the second half, holding more than 0.1%: not yet.
    stop, detail = should_stop(both, probs, np.array([0, 5]), flat)
    assert not stop and detail["late_mass"] == pytest.approx(0.01)
    # A chain that never visited 1% of the mass: the chains disagree.
    stop, detail = should_stop([np.array([0]), np.array([0, 1])], probs, np.array([0, 2]), flat)
    assert not stop and detail["max_missed_mass"] == pytest.approx(0.01)
    # ... unless its share holds that state (it reached it, weighing it one block from one it
    # visited): they agree; the late mass still counts when the state was first found.
    reached = [np.array([0, 1]), np.array([0, 1])]
    assert should_stop(reached, probs, np.array([0, 2]), flat)[0]
    assert not should_stop(reached, probs, np.array([0, 5]), flat)[0]
    # Chains on different levels: R-hat is infinite.
    assert not should_stop(both, probs, np.array([0, 2]), np.array([[0.0] * 10, [1.0] * 10]))[0]


def _auto_fit(X, y, **kw):
    with warnings.catch_warnings():
        warnings.simplefilter("error", ConvergenceWarning)
        return BSIClassifier(inference="mcmc", random_state=0, **kw).fit(X, y)


@pytest.mark.parametrize("case", ["poi_roles", "poi_no_roles", "log_peaked", "log_spread"])
def test_auto_stops_after_the_first_round_on_a_peaked_posterior_and_is_exact(case):
    if case.startswith("poi"):
        X, y, roles = _poi()
        kw = roles if case == "poi_roles" else {}
    else:
        X, y = _log(8, 400, 2) if case == "log_peaked" else _log(10, 40, 8)
        kw = {}
    exact = BSIClassifier(inference="exact", **kw).fit(X, y)
    clf = _auto_fit(X, y, **kw)
    diag = clf.mcmc_diagnostics_
    assert diag["n_samples"] == FIRST_ROUND and diag["stopping"]["stopped_early"]
    assert [r["n_samples"] for r in diag["stopping"]["rounds"]] == [FIRST_ROUND]
    assert total_variation(exact.posterior_, clf.posterior_) < 1e-6
    assert clf.map_specification_ == exact.map_specification_


@pytest.mark.parametrize("epsilon", [0.3, 0.4])
def test_auto_stops_a_flat_posterior_once_nothing_more_is_found_and_is_close_to_exact(epsilon):
    X, y, roles = _poi()
    kw = dict(roles, likelihood="ci", epsilon=epsilon)
    exact = BSIClassifier(inference="exact", **kw).fit(X, y)
    assert exact.posterior_.probabilities[0] < 0.3 and len(exact.posterior_.probabilities) > 4000
    clf = _auto_fit(X, y, **kw)
    diag = clf.mcmc_diagnostics_
    # What the visited states lead to is weighed, reported and counts as found: the chains
    # stop after the first round, where counting visits ran all 10,000 sweeps.
    assert diag["stopping"]["stopped_early"] and diag["n_samples"] == FIRST_ROUND
    assert diag["stopping"]["rounds"][-1]["late_mass"] <= 0.001
    assert total_variation(exact.posterior_, clf.posterior_) < 0.001


@pytest.mark.parametrize("epsilon", [0.2, 0.3, 0.4])
def test_auto_past_the_closure_budget_stops_once_the_chains_agree_on_every_clause(
        monkeypatch, epsilon):
    from bsi_sklearn.inference import _closure

    monkeypatch.setattr(_closure, "CLOSURE_WORK", 0.0)
    X, y, roles = _poi()
    kw = dict(roles, likelihood="ci", epsilon=epsilon)
    exact = BSIClassifier(inference="exact", **kw).fit(X, y)
    clf = _auto_fit(X, y, **kw)
    diag = clf.mcmc_diagnostics_
    # Counting visits, the chains keep finding states that hold mass (the first rule's late
    # mass stays above its threshold; it ran all 10,000 sweeps before the second rule); they
    # agree on every clause's inclusion after the first round, and stop there.
    last = diag["stopping"]["rounds"][-1]
    assert diag["stopping"]["stopped_early"] and diag["n_samples"] == FIRST_ROUND
    assert last["late_mass"] > STOP_LATE and last["max_inclusion_gap"] <= STOP_INCLUSION
    # What is reported of the posterior is exact's to a hundredth: each clause's inclusion and
    # every demonstration's predictive; the posterior over the listed specifications to 0.02
    # (0.003 or less for epsilon 0.2 and 0.3).
    exact_inclusion = exact.posterior_.clause_marginals()
    gap = exact_inclusion - clf.posterior_.clause_marginals().reindex(exact_inclusion.index)
    assert np.abs(gap).max() < 0.01
    assert np.abs(exact.predict_proba(X) - clf.predict_proba(X)).max() < 0.01
    assert total_variation(exact.posterior_, clf.posterior_) < (0.02 if epsilon > 0.3 else 0.003)
    fixed = _auto_fit(X, y, n_samples=diag["n_samples"], **kw)
    assert np.array_equal(fixed.mcmc_diagnostics_["log_posterior_traces"],
                          diag["log_posterior_traces"])


def test_past_the_closure_budget_chains_that_disagree_on_a_clause_go_on():
    probs = np.array([0.5, 0.5])
    shares = [np.array([0, 1]), np.array([0, 1])]
    late = np.array([0, 9])  # the second state found late: the first rule says go on
    flat = np.zeros((2, 10))
    inclusion = np.array([[0.5, 1.0], [0.505, 1.0], [0.495, 1.0]])
    stop, detail = should_stop(shares, probs, late, flat, inclusion)
    assert stop and detail["max_inclusion_gap"] == pytest.approx(0.005)
    inclusion[1, 0] = 0.52
    stop, detail = should_stop(shares, probs, late, flat, inclusion)
    assert not stop and detail["max_inclusion_gap"] == pytest.approx(0.02)
    # R-hat still counts
    assert not should_stop(shares, probs, late, np.array([[0.0] * 10, [1.0] * 10]),
                           np.array([[0.5, 1.0]] * 3))[0]
    # Without the closure's budget passed, no inclusion: the first rule alone.
    assert "max_inclusion_gap" not in should_stop(shares, probs, late, flat)[1]


@pytest.mark.parametrize("block", [7, 4096])  # several blocks of states, and one
def test_inclusion_by_chain_sums_each_clause_over_the_states_holding_it(monkeypatch, block):
    from bsi_sklearn.inference import diagnostics

    monkeypatch.setattr(diagnostics, "INCLUSION_BLOCK", block)
    rng = np.random.default_rng(3)
    n_g, n = 3, 4
    states = []
    for _ in range(40):
        tau, w1 = rng.integers(0, 2, n_g), rng.integers(0, 2, n)
        order = rng.permutation(n)  # a chain over some subtasks: parent of order[i] is order[i-1]
        parent = np.full(n, -1)
        for i in range(1, rng.integers(1, n + 1)):
            parent[order[i]] = order[i - 1]
        states.append(np.concatenate([tau, w1, parent]))
    states = np.array(states)
    probs = rng.random(40)
    probs /= probs.sum()
    shares = [np.arange(0, 25), np.arange(20, 40), np.array([], dtype=np.int64)]
    got = inclusion_by_chain(states, probs, shares, n_g, n)

    def holds(state):  # brute force: the clause keys of one state
        keys = {("G", j) for j in range(n_g) if state[j]}
        keys |= {("F", w) for w in range(n) if state[n_g + w]}
        parent = state[n_g + n:]
        for v in range(n):
            a = parent[v]
            while a >= 0:
                keys.add(("U", a, v))
                a = parent[a]
        return keys

    slot = {("G", j): j for j in range(n_g)}
    slot.update({("F", w): clause_index_eventual(w, n_g) for w in range(n)})
    slot.update({("U", a, b): clause_index_order(a, b, n_g, n)
                 for a in range(n) for b in range(n) if a != b})
    expected = np.zeros((4, got.shape[1]))
    weights = [probs] + [np.where(np.isin(np.arange(40), s), probs, 0.0) for s in shares]
    for k, w in enumerate(weights):
        w = w / w.sum() if w.sum() > 0 else w
        for h, state in enumerate(states):
            for key in holds(state):
                expected[k, slot[key]] += w[h]
    np.testing.assert_allclose(got, expected, rtol=0, atol=1e-12)
    assert got.shape[1] % 64 == 0 and got.shape[1] >= n_clauses(n_g, n)


def test_auto_is_independent_of_n_jobs():
    X, y, roles = _poi()
    kw = dict(roles, likelihood="ci", epsilon=0.2, n_chains=3)
    a, b = (_auto_fit(X, y, n_jobs=j, **kw) for j in (1, 2))
    assert a.posterior_.specifications == b.posterior_.specifications
    assert np.array_equal(a.posterior_.probabilities, b.posterior_.probabilities)
    assert a.mcmc_diagnostics_["stopping"] == b.mcmc_diagnostics_["stopping"]
    assert np.array_equal(a.mcmc_diagnostics_["log_posterior_traces"],
                          b.mcmc_diagnostics_["log_posterior_traces"])


def test_n_samples_accepts_auto_or_a_positive_integer():
    X, y, roles = _poi()
    for bad in ("all", 0, 2.5):
        with pytest.raises(ValueError, match="n_samples"):
            BSIClassifier(n_samples=bad, inference="mcmc", **roles).fit(X, y)
    assert BSIClassifier().get_params()["n_samples"] == "auto"
