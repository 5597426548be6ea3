"""Samples without posterior mass: the bound, the common burn-in, and the chains' bookkeeping.

A chain stuck far below what the others found (more than ``negligible_margin``) samples states
that together hold under 1e-17 of the mass; the sampler restarts it from the best state found
once, and otherwise burns or leaves out those samples (``inference/_negligible.py``).
"""

import math

import numpy as np
import pytest

from bsi_sklearn.inference._negligible import NEGLIGIBLE_MASS, common_burn_in, negligible_margin
from bsi_sklearn.inference._rounds import run_rounds
from bsi_sklearn.inference.mcmc import (
    ChainRun,
    _after_pilot,
    deduplicate_demos,
    deterministic_optimum,
    score_states,
    temperature_ladder,
)
from bsi_sklearn.model import make_model
from bsi_sklearn.model.priors import PRIORS, count_hypotheses


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("n_g, n", [(0, 1), (3, 2), (5, 5), (40, 8), (1586, 40)])
def test_the_margin_holds_every_prior_s_support(prior, n_g, n):
    # S exp(-margin) <= tol: the mass of every state below best - margin is under tol.
    log_s = math.log(count_hypotheses(prior, n_g, n))
    assert log_s <= negligible_margin(n_g, n) + math.log(NEGLIGIBLE_MASS) + 1e-9


def test_chains_that_start_within_the_margin_change_nothing():
    lp = np.array([0.0, -30.0, -60.0])
    rows = [np.array([0, 1]), np.array([2, 0])]
    counts = [np.array([5, 5]), np.array([3, 7])]
    skip, live = common_burn_in(rows, counts, lp, margin=100.0)
    assert skip == 0 and live.tolist() == [True, True]


def test_the_burn_in_is_the_latest_climb_of_the_first_half():
    lp = np.array([0.0, -500.0])
    rows = [np.array([1, 0]), np.array([1, 0]), np.array([1, 0])]
    counts = [np.array([3, 7]), np.array([5, 5]), np.array([6, 4])]
    skip, live = common_burn_in(rows, counts, lp, margin=100.0)
    # the third climbs after half its samples: left out; the others burn 5
    assert skip == 5 and live.tolist() == [True, True, False]


def test_a_late_climb_to_the_best_state_is_kept_when_no_chain_climbs_sooner():
    lp = np.array([0.0, -500.0, -900.0])
    rows = [np.array([1, 0]), np.array([2])]
    counts = [np.array([8, 2]), np.array([10])]
    skip, live = common_burn_in(rows, counts, lp, margin=100.0)
    assert skip == 8 and live.tolist() == [True, False]


def _problem():
    rng = np.random.default_rng(5)
    truth = (rng.random((30, 2 + 4 + 16)) < 0.75).astype(np.uint8)
    y01 = (rng.random(30) < 0.6).astype(np.int64)
    model = make_model(prior="sets_of_chains", likelihood="calibrated", n_globals=2,
                       n_subtasks=4)
    demos = deduplicate_demos(truth, y01)
    return demos, model, temperature_ladder(demos, model, 3)


def test_a_skipped_result_is_the_record_without_its_first_samples():
    demos, model, betas = _problem()
    start, _ = deterministic_optimum(demos, model)
    run = ChainRun(1, demos, model, betas, start, burn_in=20).advance(300).advance(200)
    whole, part = run.result(), run.result(137)
    expand = lambda r: np.repeat(r.states, r.counts, axis=0)  # noqa: E731
    assert np.array_equal(expand(whole)[137:], expand(part))
    assert np.array_equal(whole.trace_lp[137:], part.trace_lp)
    assert part.n_burned == whole.n_burned + 137 and part.counts.min() > 0


def test_a_discarded_record_counts_as_burned_and_the_chain_goes_on():
    demos, model, betas = _problem()
    start, _ = deterministic_optimum(demos, model)
    kept = ChainRun(2, demos, model, betas, start, burn_in=20).advance(100).advance(50)
    run = ChainRun(2, demos, model, betas, start, burn_in=20).advance(100).discard()
    run.advance(50)
    a, b = kept.result(), run.result()
    assert np.array_equal(a.trace_lp[100:], b.trace_lp)
    assert b.n_burned == a.n_burned + 100 and b.n_updates == a.n_updates


def test_a_restarted_chain_is_a_fresh_chain_from_the_row_with_the_same_generator():
    demos, model, betas = _problem()
    start, _ = deterministic_optimum(demos, model)
    old = ChainRun(3, demos, model, betas, start, burn_in=20).advance(100)
    row = old.result().states[-1].astype(np.int64)
    state = old.rng.bit_generator.state
    new = old.restarted_at(row).advance(200)
    twin = np.random.default_rng(0)
    twin.bit_generator.state = state
    fresh = ChainRun(twin, demos, model, betas, row).advance(200)
    a, b = new.result(), fresh.result()
    assert np.array_equal(a.trace_lp, b.trace_lp)
    assert a.n_burned == b.n_burned + old.result().n_burned + 100
    assert a.n_updates == b.n_updates + old.result().n_updates


def _stuck_problem():
    # 60 acceptable demonstrations, 80 global candidates; the first violates 40 of them. CB's
    # optimum keeps all 80 and gives the first up; a chain started from the 40 others, keeping
    # it, would have to add 40 clauses one at a time, each costing |log eps| until the last:
    # 1,442 nats below, where the bound is 95. Untempered, it never gets there. Returns the
    # model, the demonstrations, the optimum and that state (int64 rows).
    n_g, n_v = 80, 40
    truth = np.ones((60, n_g), dtype=np.uint8)
    truth[0, n_g - n_v:] = 0
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=n_g, n_subtasks=0)
    demos = deduplicate_demos(truth, np.ones(60, dtype=np.int64))
    optimum, _ = deterministic_optimum(demos, model)
    stuck = optimum.astype(np.int64).copy()
    stuck[n_g - n_v:n_g] = 0
    return model, demos, optimum.astype(np.int64), stuck


def test_a_chain_stuck_below_the_bound_goes_on_from_the_best_state():
    model, demos, optimum, stuck = _stuck_problem()
    n_g = model.n_g
    lp = score_states(optimum[None, :], demos, model)[0]
    assert lp - score_states(stuck[None, :], demos, model)[0] > negligible_margin(n_g, 0)
    runs = [ChainRun(s, demos, model, np.ones(1), optimum if s else stuck) for s in range(3)]
    results, visited, counts, _, visited_lp, stopping, _, _, _ = run_rounds(
        runs, [200], demos, model, 1, 0)
    assert stopping["restarted"] and stopping["lost_chains"] == []
    assert len(results) == 3 and all(len(r.trace_lp) == 200 for r in results)
    assert visited_lp.min() >= visited_lp.max() - negligible_margin(n_g, 0)
    assert results[0].n_burned == 200 and counts.sum() == 600


def test_a_pilot_left_below_the_bound_goes_on_from_the_best_pilot_s_state():
    # After the pilot, a chain whose beta = 1 replica is more than the margin below the best
    # pilot's starts the recorded sweeps from that state on every rung of the adapted
    # ladder, with its own generator; a chain within the margin goes on from its replicas.
    model, demos, optimum, stuck = _stuck_problem()
    pilot_betas, betas = np.array([1.0, 0.5, 0.25]), np.array([1.0, 0.25])
    pilots = [ChainRun(s, demos, model, pilot_betas, optimum if s else stuck)
              for s in range(3)]
    for p in pilots:
        p.advance(20)
    assert [p.coldest().tolist() for p in pilots[:1]] == [stuck.tolist()]  # still stuck
    twin = ChainRun(0, demos, model, pilot_betas, stuck).advance(20)
    runs, restarted = _after_pilot(pilots, betas, demos, model, {})
    assert restarted == [0]
    rows = np.stack([p.coldest() for p in pilots])
    best = rows[int(np.argmax(score_states(rows, demos, model)))]
    assert np.array_equal(runs[0].state.tau, np.tile(best[:80], (2, 1)))
    assert runs[0].pilot_sweeps == 20 and np.array_equal(runs[0].betas, betas)
    assert runs[0].rng.random() == twin.rng.random()  # the pilot's generator, where it was
    for run in runs[1:]:
        assert run.pilot_sweeps == 20 and np.array_equal(run.betas, betas)
    # every pilot within the margin: nothing restarted, each goes on from its own replicas
    runs, restarted = _after_pilot(pilots[1:], betas, demos, model, {})
    assert restarted == [] and all(np.array_equal(r.state.tau[0], p.coldest()[:80])
                                   for r, p in zip(runs, pilots[1:]))
