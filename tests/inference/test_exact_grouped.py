"""The grouped exact engine against the ungrouped enumeration and brute force.

The engine sums interchangeable parts into groups and skips, with a bound, what cannot add
more than 1e-17 of the evidence; none of it may change the posterior beyond rounding.
"""

import itertools
import math

import numpy as np
import pytest
from _exact_checks import _assert_same_posterior, _problem
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from bsi_sklearn.inference._exact_parts import structure_groups
from bsi_sklearn.inference._grouping import group_rows
from bsi_sklearn.inference._structures import structure_tables
from bsi_sklearn.inference.exact import ExactWorkExceeded, exact_posterior
from bsi_sklearn.model import make_model
from bsi_sklearn.model.clauses import pack_rows
from bsi_sklearn.model.priors import (
    PRIORS,
    count_structures,
    enumerate_structures,
    log_prior_structure,
    structure_log_prior,
)


def _brute_structures(prior, n):
    out = []
    for par in itertools.product(range(-1, n), repeat=n):
        if any(par[v] == v for v in range(n)):
            continue
        ok = True
        for v in range(n):
            a, steps = par[v], 0
            while a >= 0 and steps <= n:
                a, steps = par[a], steps + 1
            ok &= a < 0
        if not ok:
            continue
        children = [sum(p == v for p in par) for v in range(n)]
        if prior != "forest" and max(children, default=0) > 1:
            continue
        if prior == "linear_chain" and n and sum(p < 0 for p in par) != 1:
            continue
        out.append(par)
    return sorted(out)


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("n", range(0, 6))
def test_depth_first_structures_are_the_support_in_order(prior, n):
    got = [tuple(r) for r in enumerate_structures(prior, n).tolist()]
    assert len(got) == count_structures(prior, n)
    assert got == _brute_structures(prior, n)  # lexicographic, no duplicates


@pytest.mark.parametrize("prior", PRIORS)
def test_depth_first_counts_up_to_eight(prior):
    for n in (6, 7, 8):
        assert len(enumerate_structures(prior, n)) == count_structures(prior, n)


@pytest.mark.parametrize("prior", PRIORS)
def test_structure_log_prior_matches_closed_form(prior):
    model = make_model(prior=prior, likelihood="cb", n_globals=1, n_subtasks=5, p_part=0.37,
                       n_new=2.5)
    scratch = np.zeros(5, dtype=np.int64)
    total = 0.0
    for parent in enumerate_structures(prior, 5):
        ref = log_prior_structure(parent, model)
        assert structure_log_prior(parent, model, scratch) == pytest.approx(ref, abs=1e-12)
        total += math.exp(ref)
    assert total == pytest.approx(1.0, abs=1e-12)  # the skip bound relies on it


def test_group_rows_sums_weights_in_order_of_first_appearance():
    bits = np.array([[3], [1], [3], [3]], dtype=np.uint64)
    size = np.array([2, 1, 2, 1])
    lp = np.log([0.1, 0.2, 0.3, 0.4])
    gid, g = group_rows(bits, size, lp)
    assert gid.tolist() == [0, 1, 0, 2]
    assert np.allclose(g.weight * np.exp(g.ref), [0.4, 0.2, 0.4])
    assert np.allclose(g.best, np.log([0.3, 0.2, 0.4]))


def _structure_bits(parent, truth, n):
    # Brute force: a structure's demonstration bitset (as a bool row) and number of orders.
    orders = [(a, v) for v in range(n) for a in _ancestors(parent, v)]
    sat = np.ones(truth.shape[0], bool)
    for a, v in orders:
        sat &= truth[:, n + a * n + v] == 1
    return sat, len(orders)


@pytest.mark.parametrize("prior", PRIORS)
@pytest.mark.parametrize("n", [0, 1, 4, 5])
def test_structure_tables_group_exactly_the_structures_satisfying_thr_positives(prior, n):
    rng = np.random.default_rng(4 + n)
    n_demos = 40
    truth = (rng.random((n_demos, n + n * n)) < 0.85).astype(np.uint8)  # no globals
    y = rng.random(n_demos) < 0.6
    clause_bits = pack_rows(np.ascontiguousarray(truth.T))
    full = pack_rows(np.ones((1, n_demos), dtype=np.uint8))[0]
    pos = pack_rows(y.astype(np.uint8)[None])[0]
    model = make_model(prior=prior, likelihood="cb", n_globals=0, n_subtasks=n, p_part=0.4,
                       n_new=2.5)
    for thr in (0, int(y.sum()) - 2, int(y.sum())):
        want = {}
        for parent in enumerate_structures(prior, n):
            sat, size = _structure_bits(parent, truth, n)
            if (sat & y).sum() >= thr:
                key = (tuple(pack_rows(sat.astype(np.uint8)[None])[0].tolist()), size)
                w, c, b = want.get(key, (0.0, 0, -np.inf))
                lp = log_prior_structure(parent, model)
                want[key] = (w + math.exp(lp), c + 1, max(b, lp))
        tables, work = structure_tables(clause_bits, full, pos, thr, model)
        groups, members, _ = structure_groups(tables, model)
        got = {(tuple(b), int(s)): (w * math.exp(groups.ref), int(m), best)
               for b, s, w, m, best in zip(groups.bits.tolist(), groups.size, groups.weight,
                                           members, groups.best)}
        assert set(got) == set(want)
        for key, (w, c, b) in want.items():
            assert got[key][0] == pytest.approx(w, rel=1e-12)
            assert got[key][1] == c
            assert got[key][2] == pytest.approx(b, abs=1e-12)
        assert work > 0 or n == 0


def _ancestors(parent, v):
    out, a = [], parent[v]
    while a >= 0:
        out.append(a)
        a = parent[a]
    return out


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), prior=st.sampled_from(PRIORS),
       likelihood=st.sampled_from(["cb", "ci"]), n_g=st.integers(0, 3), n=st.integers(0, 4),
       n_demos=st.integers(1, 80), frac_pos=st.sampled_from([0.0, 0.5, 0.8, 1.0]),
       p_true=st.floats(0.3, 0.97), epsilon=st.sampled_from([None, 0.01, 0.2]),
       tol=st.sampled_from([1e-9, 1e-4, 0.0]))
def test_grouped_equals_ungrouped(seed, prior, likelihood, n_g, n, n_demos, frac_pos, p_true,
                                  epsilon, tol):
    truth, y, model = _problem(seed, prior, likelihood, n_g, n, n_demos, frac_pos, p_true,
                               epsilon)
    a = exact_posterior(truth, y, model, tol=tol)
    b = exact_posterior(truth, y, model, tol=tol, grouped=False)
    _assert_same_posterior(a, b)


@pytest.mark.parametrize("prior", PRIORS)
def test_grouped_equals_ungrouped_on_a_larger_support(prior):
    truth, y, model = _problem(11, prior, "cb", 2, 5, 70, 0.75, 0.8, None)
    _assert_same_posterior(exact_posterior(truth, y, model),
                           exact_posterior(truth, y, model, grouped=False))


def test_max_kept_keeps_the_most_probable_and_reports_the_rest():
    truth, y, model = _problem(2, "sets_of_chains", "ci", 1, 4, 30, 0.8, 0.8, 0.45)
    full = exact_posterior(truth, y, model, tol=1e-9)
    few = exact_posterior(truth, y, model, tol=1e-9, max_kept=25)
    assert len(full.log_prob) > 25 and len(few.log_prob) == 25
    assert np.array_equal(few.log_prob, full.log_prob[:25])
    assert few.dropped_mass == pytest.approx(1 - np.exp(full.log_prob[:25]).sum(), abs=1e-12)
    assert np.array_equal(few.clause_marginals, full.clause_marginals)


def test_structure_groups_hold_the_whole_prior():
    truth, y, model = _problem(5, "forest", "cb", 1, 5, 50, 0.7, 0.8, None)
    clause_bits = pack_rows(np.ascontiguousarray(truth.T))
    full = pack_rows(np.ones((1, len(y)), dtype=np.uint8))[0]
    pos = pack_rows((y == 1).astype(np.uint8)[None])[0]
    tables, work = structure_tables(clause_bits, full, pos, 0, model)
    groups, members, _ = structure_groups(tables, model)
    assert (groups.weight * np.exp(groups.ref)).sum() == pytest.approx(1.0, abs=1e-12)
    assert len(groups.size) < count_structures("forest", 5)
    assert members.sum() == count_structures("forest", 5)
    assert structure_tables(clause_bits, full, pos, 0, model, max_work=work - 1)[0] is None
    assert structure_tables(clause_bits, full, pos, 0, model, max_work=work)[0] is not None


def test_work_budget_stops_before_the_work_and_is_deterministic():
    truth, y, model = _problem(2, "sets_of_chains", "ci", 1, 5, 40, 0.8, 0.8, 0.45)
    with pytest.raises(ExactWorkExceeded, match="work budget"):
        exact_posterior(truth, y, model, max_work=1e4)
    ok = exact_posterior(truth, y, model, max_work=1e9)
    _assert_same_posterior(ok, exact_posterior(truth, y, model))


def test_auto_enumerates_the_dinner_table_exactly_and_n_jobs_does_not_matter():
    from bsi_sklearn import BSIClassifier
    from bsi_sklearn.datasets import make_dinner_table_demos

    d = make_dinner_table_demos(30, n_negative=8, random_state=1)
    fits = [BSIClassifier(**d.roles, n_jobs=n_jobs).fit(d.traces, d.labels) for n_jobs in (1, 2)]
    assert [f.inference_ for f in fits] == ["exact", "exact"]
    assert fits[0].n_hypotheses_ == 201_908_736
    assert np.array_equal(fits[0].posterior_.probabilities, fits[1].posterior_.probabilities)
    assert fits[0].map_specification_ == fits[1].map_specification_


def test_auto_samples_when_the_enumeration_is_over_its_budget(monkeypatch):
    import bsi_sklearn.inference.auto_budget as auto_budget
    from bsi_sklearn import BSIClassifier

    truth_x = [np.array([[1, 0, 1], [1, 1, 1]]), np.array([[1, 0, 0], [1, 1, 1]])]
    monkeypatch.setattr(auto_budget, "AUTO_EXACT_WORK", 1.0)
    monkeypatch.setattr(auto_budget, "SAMPLING_TO_EXACT", 0.0)
    # 200 samples: enough for 4 chains to agree on these 24 hypotheses (50 left one short)
    clf = BSIClassifier(global_candidates=[0], subtasks=[1, 2], n_samples=200,
                        random_state=0).fit(truth_x)
    assert clf.inference_ == "mcmc"
    with pytest.raises(ValueError, match="max_exact_hypotheses"):
        BSIClassifier(global_candidates=[0], subtasks=[1, 2], inference="exact",
                      max_exact_hypotheses=3).fit(truth_x)
