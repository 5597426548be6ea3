"""The webppl reference driver (benchmarks/reference/webppl.py) and bench_reference helpers.

Everything but the last tests runs without node: demonstrations -> the program's JSON input,
webppl formula keys -> ``Specification``, distributions and TV, MAP agreement, sample planning.
The webppl tests run only when node and an already-installed webppl are present (never
installing: tests stay offline).
"""

import math
import shutil

import _scripts  # noqa: F401  (puts benchmarks/ on sys.path)
import numpy as np
import pytest
from reference.webppl import (  # noqa: E402
    WEBPPL_BIN,
    WebpplUnavailable,
    find_webppl,
    key_to_specification,
    map_agrees,
    most_probable,
    plan_samples,
    problem_from_demos,
    run_webppl,
    to_specification_dist,
)

from bsi_sklearn import BSIClassifier, Specification  # noqa: E402
from bsi_sklearn.inference.diagnostics import total_variation  # noqa: E402
from bsi_sklearn.model.clauses import clause_index_order  # noqa: E402
from bsi_sklearn.model.likelihood import default_log_epsilon  # noqa: E402

# columns: safe (global), a, b (subtasks), a_ok (condition of a)
ROLES = {"global_candidates": [0], "subtasks": [1, 2], "conditions": {1: 3}}
X = [
    np.array([[1, 0, 0, 1], [1, 1, 0, 1], [1, 1, 1, 1]]),  # a then b, a required
    np.array([[1, 0, 1, 1], [0, 1, 1, 1]]),                # b before a, safe broken
    np.array([[1, 0, 0, 0], [1, 0, 1, 0]]),                # a not required, b only
]
Y = [1, 0, 1]


def _roles():
    return problem_from_demos(X, Y, ROLES)[1]


# ------------------------------------------------------------------ demonstrations -> JSON
def test_problem_truth_layout_matches_hand_computed_clauses():
    problem, r = problem_from_demos(X, Y, ROLES, prior="forest", likelihood="ci")
    assert (problem["n_globals"], problem["n_subtasks"]) == (1, 2)
    assert problem["prior"] == "forest" and problem["likelihood"] == "ci"
    assert problem["labels"] == [1, 0, 1]
    assert problem["log_eps"] == pytest.approx(default_log_epsilon(1, 2))
    # slots: G(safe), a_ok -> F a, F b, then a*n + b over (a, b) in {a, b}^2
    truth = problem["truth"]
    assert len(truth) == 3 and all(len(row) == 1 + 2 + 4 for row in truth)
    ab, ba = clause_index_order(0, 1, 1, 2), clause_index_order(1, 0, 1, 2)
    assert truth[0][:3] == [1, 1, 1] and truth[0][ab] == 1 and truth[0][ba] == 0
    assert truth[1][:3] == [0, 1, 1] and truth[1][ab] == 0 and truth[1][ba] == 1
    # demo 3: a's condition is false, so F a and "a before b" hold vacuously; "b before a"
    # holds because b happens and a never does
    assert truth[2][:3] == [1, 1, 1] and truth[2][ab] == 1 and truth[2][ba] == 1
    assert r.global_names() == [0] and r.subtask_names() == [1, 2]


def test_problem_traces_layout():
    problem, _ = problem_from_demos(X, None, ROLES, input="traces")
    assert "truth" not in problem and problem["labels"] == [1, 1, 1]
    first = problem["traces"][0]
    assert first["tau"] == [[1, 1, 1]]
    assert first["omega"] == [[0, 1, 1], [0, 0, 1]]
    assert first["pi"] == [1, 1]  # a's condition at t = 0; b has none
    assert problem["traces"][2]["pi"] == [0, 1]


@pytest.mark.parametrize("kwargs, match", [
    ({"prior": "linear_chain"}, "prior"),
    ({"likelihood": "xx"}, "likelihood"),
    ({"input": "csv"}, "input"),
])
def test_problem_rejects_bad_options(kwargs, match):
    with pytest.raises(ValueError, match=match):
        problem_from_demos(X, Y, ROLES, **kwargs)


def test_problem_rejects_bad_labels():
    with pytest.raises(ValueError, match="0/1 label"):
        problem_from_demos(X, [1, 2, 1], ROLES)
    with pytest.raises(ValueError, match="0/1 label"):
        problem_from_demos(X, [1, 0], ROLES)


def test_run_webppl_rejects_bad_method_before_running():
    with pytest.raises(ValueError, match="method"):
        run_webppl({}, seed=0, method="SMC", webppl="/nonexistent")


# ------------------------------------------------------------------ keys -> Specification
def test_key_to_specification_maps_indices_to_names():
    spec = key_to_specification("g:0|f:0,1|o:0>1", _roles())
    assert spec == Specification(globals=[0], eventuals=[1, 2], orders=[(1, 2)],
                                 conditions={1: 3})
    assert spec.conditions == {1: 3}
    assert key_to_specification("g:|f:|o:", _roles()) == Specification()


def test_key_canonicalisation_closes_orders_and_ignores_listing_order():
    roles = problem_from_demos([np.zeros((2, 4), dtype=int)], None,
                               {"global_candidates": [], "subtasks": [0, 1, 2, 3],
                                "conditions": None})[1]
    chain_edges = key_to_specification("g:|f:|o:0>1,1>2", roles)
    closed = key_to_specification("g:|f:|o:1>2,0>2,0>1", roles)
    assert chain_edges == closed
    assert closed.orders == frozenset({(0, 1), (0, 2), (1, 2)})
    assert closed.n_conjuncts == 3
    assert key_to_specification("g:|f:2,1|o:", roles) == key_to_specification(
        "g:|f:1,2|o:", roles)


@pytest.mark.parametrize("key", ["g:0|f:0", "g:0|f:x|o:", "g:5|f:|o:", "g:|f:|o:0>7",
                                 "g:|f:|o:0>1>0", "nonsense"])
def test_key_to_specification_rejects_malformed_keys(key):
    with pytest.raises(ValueError, match="malformed webppl formula key"):
        key_to_specification(key, _roles())


def test_key_with_cycle_is_rejected():
    with pytest.raises(ValueError, match="cycle"):
        key_to_specification("g:|f:|o:0>1,1>0", _roles())


# ------------------------------------------------------------------ distributions and TV
def test_specification_distribution_merges_equal_formulas_and_tv():
    roles = _roles()
    webppl = {"g:0|f:0,1|o:0>1": 0.5, "g:0|f:1,0|o:0>1": 0.25, "g:|f:|o:": 0.25}
    dist = to_specification_dist(webppl, roles)
    full = Specification(globals=[0], eventuals=[1, 2], orders=[(1, 2)], conditions={1: 3})
    assert dist == {full: 0.75, Specification(): 0.25}
    exact = {full: 0.5, Specification(globals=[0]): 0.5}
    # |0.75-0.5| + |0.25-0| + |0-0.5| = 1.0, halved
    assert total_variation(dist, exact) == pytest.approx(0.5)
    assert total_variation(dist, dist) == 0.0


def test_tv_against_a_fitted_exact_posterior():
    clf = BSIClassifier(**ROLES, inference="exact", tol=0).fit(X, Y)
    exact = dict(zip(clf.posterior_.specifications, clf.posterior_.probabilities))
    assert math.isclose(sum(exact.values()), 1.0)
    # a point mass on the MAP is at TV 1 - p(MAP) from the posterior
    map_spec = clf.map_specification_
    assert total_variation({map_spec: 1.0}, exact) == pytest.approx(1.0 - exact[map_spec])
    assert map_agrees(map_spec, exact)


def test_most_probable_and_map_agreement_with_ties():
    a, b, c = Specification(globals=[0]), Specification(), Specification(eventuals=[1])
    assert most_probable({a: 0.2, b: 0.5, c: 0.3}) == b
    exact = {a: 0.45, b: 0.45, c: 0.1}
    assert map_agrees(a, exact) and map_agrees(b, exact)
    assert not map_agrees(c, exact)
    assert not map_agrees(Specification(globals=[9]), exact)
    with pytest.raises(ValueError, match="empty"):
        most_probable({})
    with pytest.raises(ValueError, match="empty"):
        map_agrees(a, {})


def test_plan_samples():
    assert plan_samples(rate=1000.0, samples=10_000, max_seconds=60) == (10_000, False)
    n, extrapolated = plan_samples(rate=10.0, samples=10_000, max_seconds=120)
    assert extrapolated and n == 1_000 and n / 10.0 <= 120
    n, _ = plan_samples(rate=3.0, samples=10_000, max_seconds=120)
    assert n == 300
    assert plan_samples(rate=0.01, samples=10_000, max_seconds=1) == (100, True)
    with pytest.raises(ValueError, match="positive"):
        plan_samples(rate=0.0, samples=10, max_seconds=1)


def test_find_webppl_without_install_says_why(monkeypatch):
    if not WEBPPL_BIN.exists():
        with pytest.raises(WebpplUnavailable):
            find_webppl(install=False)
    monkeypatch.setattr(shutil, "which", lambda name: None)
    with pytest.raises(WebpplUnavailable, match="node is not installed"):
        find_webppl(install=False)


# ------------------------------------------------------------------ webppl itself
needs_webppl = pytest.mark.skipif(
    shutil.which("node") is None or not WEBPPL_BIN.exists(),
    reason="node or an installed webppl (npm install in benchmarks/reference/) is absent",
)


@needs_webppl
def test_webppl_enumeration_equals_our_exact_posterior():
    # The paper's program, enumerated exactly, is our model: same posterior over formulas.
    for prior in ("sets_of_chains", "forest"):
        problem, r = problem_from_demos(X, Y, ROLES, prior=prior, input="traces")
        res = run_webppl(problem, seed=1, method="enumerate", timeout=120)
        # The program's likelihood is CB's (the classifier's default until 2026-12-07).
        ours = BSIClassifier(**ROLES, prior=prior, likelihood="cb", inference="exact",
                             tol=0).fit(X, Y)
        assert total_variation(to_specification_dist(res["dist"], r), ours.posterior_) < 1e-9


@needs_webppl
def test_webppl_mcmc_tiny_run():
    problem, r = problem_from_demos(X, Y, ROLES, input="truth")
    res = run_webppl(problem, seed=3, samples=200, burn=10, timeout=120)
    assert math.isclose(sum(res["dist"].values()), 1.0)
    assert res["inference_s"] >= 0 and res["process_s"] >= res["inference_s"]
    dist = to_specification_dist(res["dist"], r)
    assert all(isinstance(s, Specification) for s in dist)
    # frequencies of 200 samples: multiples of 1/200
    assert all(abs(p * 200 - round(p * 200)) < 1e-6 for p in dist.values())
    again = run_webppl(problem, seed=3, samples=200, burn=10, timeout=120)
    assert again["dist"] == res["dist"]  # seeded
