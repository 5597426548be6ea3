"""Priors: closed forms against exhaustive enumeration of the paper's programs and sampling."""

import math
from collections import Counter

import numpy as np
import pytest
from _reference import program_distribution

from bsi_sklearn.model import make_model
from bsi_sklearn.model.priors import (
    count_structures,
    enumerate_structures,
    log_prior_structure,
    sample_order_structure,
)


def _model(prior, p_part, n_new):
    # log_prior_structure reads the prior and its parameters; sizes come from the parent array.
    return make_model(prior=prior, likelihood="cb", n_globals=0, n_subtasks=0, p_part=p_part,
                      n_new=n_new)


@pytest.mark.parametrize("prior", ["linear_chain", "sets_of_chains", "forest"])
@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_closed_form_matches_program_enumeration(prior, n):
    dist = program_distribution(prior, n, p_part=0.35, n_new=2.5)
    structures = enumerate_structures(prior, n)
    assert len(structures) == count_structures(prior, n) == len(dist)
    total = 0.0
    for parent in structures:
        lp = log_prior_structure(parent, _model(prior, 0.35, 2.5))
        assert math.exp(lp) == pytest.approx(dist[tuple(parent)], rel=1e-9)
        total += math.exp(lp)
    assert total == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("prior", ["sets_of_chains", "forest"])
def test_closed_form_sums_to_one_n5(prior):
    structures = enumerate_structures(prior, 5)
    lp = [log_prior_structure(s, _model(prior, 0.3, 5.0)) for s in structures]
    assert math.fsum(np.exp(lp)) == pytest.approx(1.0, abs=1e-12)


@pytest.mark.parametrize("prior", ["linear_chain", "sets_of_chains", "forest"])
def test_sampler_frequencies_match_closed_form(prior):
    rng = np.random.default_rng(0)
    n, draws = 4, 40_000
    counts = Counter(tuple(sample_order_structure(prior, n, rng, 0.3, 5.0)) for _ in range(draws))
    structures = enumerate_structures(prior, n)
    probs = {tuple(s): math.exp(log_prior_structure(s, _model(prior, 0.3, 5.0)))
             for s in structures}
    assert set(counts) <= set(probs)
    # chi-square goodness of fit
    chi2 = sum((counts.get(k, 0) - draws * p) ** 2 / (draws * p) for k, p in probs.items())
    dof = len(probs) - 1
    assert chi2 < dof + 5 * math.sqrt(2 * dof)


def test_structures_outside_support_have_zero_probability():
    two_roots = np.array([-1, -1, 0])
    branching = np.array([-1, 0, 0])
    assert log_prior_structure(two_roots, _model("linear_chain", 0.3, 5.0)) == -np.inf
    assert log_prior_structure(branching, _model("sets_of_chains", 0.3, 5.0)) == -np.inf
    assert np.isfinite(log_prior_structure(branching, _model("forest", 0.3, 5.0)))


@pytest.mark.parametrize("prior", ["linear_chain", "sets_of_chains", "forest"])
@pytest.mark.parametrize("n", [0, 1, 3])
def test_what_the_engines_ask_of_a_prior(prior, n):
    # The engines' questions (priors.py) answer as the prior codes' meanings did there.
    from bsi_sklearn.model.priors import (
        count_hypotheses,
        count_model_hypotheses,
        first_structure,
        is_forest,
        structures_are_sets,
        whole_structure_log_factor,
    )

    model = make_model(prior=prior, likelihood="cb", n_globals=2, n_subtasks=n)
    assert is_forest(model) == (prior == "forest")
    assert structures_are_sets(model) == (prior != "linear_chain")
    np.testing.assert_array_equal(first_structure(model), enumerate_structures(prior, n)[0])
    assert count_model_hypotheses(model) == count_hypotheses(prior, 2, n)
    blocks = np.arange(1, n + 1)
    want = (np.full(n, model.forest_const) if prior == "forest"
            else np.asarray(model.lp_chains)[blocks])
    np.testing.assert_array_equal(whole_structure_log_factor(model, blocks), want)
