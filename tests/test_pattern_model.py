"""Pattern clauses in the model (DESIGN §12): candidates, prior, exact and sampled posteriors."""

import pickle

import numpy as np
import pytest
from _reference import brute_force_posterior, instance_holds
from sklearn.base import clone
from sklearn.exceptions import ConvergenceWarning

from bsi_sklearn import BSIClassifier
from bsi_sklearn.data.roles import Roles
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.inference.diagnostics import total_variation
from bsi_sklearn.model.bundle import make_model
from bsi_sklearn.model.clauses import clause_truth
from bsi_sklearn.model.pattern_candidates import (
    FAMILY_P,
    check_templates,
    pattern_candidates,
    pattern_probabilities,
)
from bsi_sklearn.model.patterns import FAMILIES, TEMPLATES, instantiate
from bsi_sklearn.model.priors import log_prior_globals

NAMES = ["g", "a", "b"]


def _response_data(n=14, seed=0, p=0.35, steps=4):
    """Demonstrations over (g, a, b), labelled by Response(a, b) and G(g)."""
    rng = np.random.default_rng(seed)
    X, y = [], []
    for _ in range(n):
        x = (rng.random((steps, 3)) < p).astype(int)
        x[:, 0] = rng.random() < 0.85  # g holds throughout, mostly
        X.append(x)
        y.append(int(instance_holds("Response", [1, 2], x) and x[:, 0].all()))
    return X, np.array(y)


def _clf(**kw):
    return BSIClassifier(global_candidates=["g"], subtasks=["a", "b"], conditions={},
                         templates=["Response"], random_state=0, **kw)


def _frames(X):
    import pandas as pd
    return [pd.DataFrame(x, columns=NAMES) for x in X]


def _reference(X, y, clf, prior="sets_of_chains", likelihood="cb"):
    probs = pattern_probabilities(("Response",), clf.p_patterns)
    pats = [(name, tuple(props), probs[name]) for name, props in clf.pattern_candidates_]
    return brute_force_posterior(X, y, NAMES, ["g"], ["a", "b"], {}, prior, likelihood,
                                 patterns=pats)


@pytest.mark.parametrize("prior", ["sets_of_chains", "forest"])
@pytest.mark.parametrize("likelihood", ["cb", "ci"])
def test_exact_posterior_with_patterns_matches_first_principles(prior, likelihood):
    X, y = _response_data()
    X = _frames(X)
    clf = _clf(prior=prior, likelihood=likelihood, inference="exact", tol=0.0).fit(X, y)
    # every instance over the three propositions, but those every demonstration satisfies
    assert 0 < len(clf.pattern_candidates_) <= 6
    ref = _reference(X, y, clf, prior, likelihood)
    assert clf.inference_ == "exact"
    assert total_variation(clf.posterior_, ref) < 1e-9
    best = max(ref, key=ref.get)
    assert ref[clf.map_specification_] == pytest.approx(ref[best], rel=1e-9)
    marg = clf.posterior_.clause_marginals()
    for key, value in marg.items():
        if key[0] == "P":
            expected = sum(p for s, p in ref.items() if key[1:] in s.patterns)
            assert value == pytest.approx(expected, abs=1e-9)


def test_sampler_with_patterns_agrees_with_exact():
    X, y = _response_data(n=20, seed=3)
    X = _frames(X)
    exact = _clf(inference="exact", tol=0.0).fit(X, y)
    mcmc = _clf(inference="mcmc").fit(X, y)
    assert mcmc.inference_ == "mcmc"
    ref = dict(zip(exact.posterior_.specifications, exact.posterior_.probabilities))
    assert total_variation(mcmc.posterior_, ref) < 0.02
    assert mcmc.map_specification_ == exact.map_specification_


def test_the_rule_is_the_map_and_predictions_use_the_pattern_truth():
    X, y = _response_data(n=40, seed=1, steps=5)
    X = _frames(X)
    clf = _clf().fit(X, y)
    assert ("Response", ("a", "b")) in clf.map_specification_.patterns
    Xn, yn = _response_data(n=60, seed=7, steps=5)
    Xn = _frames(Xn)
    assert np.mean(clf.predict(Xn) == yn) >= 0.9
    # without the pattern, the paper's template cannot say it
    paper = clone(clf).set_params(templates="paper").fit(X, y)
    assert paper.map_specification_.patterns == frozenset()
    assert paper.pattern_candidates_ == []
    again = pickle.loads(pickle.dumps(clf))
    np.testing.assert_array_equal(again.predict_proba(Xn), clf.predict_proba(Xn))


def test_candidates_leave_out_vacuous_instances_and_idle_propositions():
    x = np.array([[1, 0, 0], [1, 1, 0], [1, 0, 1]])
    traces = check_traces([x, x[:2]])
    cands, truth, n_vacuous = pattern_candidates(traces, ("Absence", "Existence"))
    # columns 0 and 1 hold in both demonstrations: their Existence is vacuous; column 2 only
    # in the first, so Existence(2) and every Absence are violated by some demonstration
    assert ("Existence", (0,)) not in cands and ("Existence", (1,)) not in cands
    assert ("Existence", (2,)) in cands
    assert ("Absence", (0,)) in cands and ("Absence", (2,)) in cands
    assert n_vacuous == 2
    # the truth the candidates were chosen by is the clause truth's own pattern block
    roles = Roles(np.arange(3), np.zeros(0, np.int64), np.zeros(0, np.int64), [0, 1, 2], cands)
    np.testing.assert_array_equal(clause_truth(traces, roles, truth),
                                  clause_truth(traces, roles))
    idle = check_traces([np.zeros((3, 2), dtype=int), np.array([[1, 0], [0, 0]])])
    cands, truth_idle, _ = pattern_candidates(idle, ("Response",))
    assert cands == ()  # column 1 never holds: no slot for it, and no instance left
    assert truth_idle.shape == (2, 0)
    with pytest.raises(ValueError, match="more than 2"):
        pattern_candidates(traces, ("Response",), max_candidates=2)


def test_template_and_probability_parameters_are_checked():
    assert check_templates("paper") == ()
    assert check_templates(("Response", "G(x -> F(y))")) == ("Response", "G(x -> F(y))")
    # the named sets: one-slot templates, Declare's, all; each a tuple of catalogue names
    assert check_templates("all") == tuple(TEMPLATES)
    assert all(len(TEMPLATES[t].slots) == 1 for t in check_templates("unary"))
    assert {"Response", "Precedence", "ChainResponse"} <= set(check_templates("declare"))
    assert not any(TEMPLATES[t].family == "scoped" for t in check_templates("declare"))
    for bad, match in [("Response", "list of one template"), ("every", "'unary', 'declare'"),
                       ([], "empty list"),
                       (["Respons"], "unknown template"),
                       (["Response", "Response"], "more than once"),
                       (["G(true)"], "no placeholder")]:
        with pytest.raises(ValueError, match=match):
            check_templates(bad)
    assert set(FAMILY_P) == set(FAMILIES)
    got = pattern_probabilities(tuple(TEMPLATES), {"relation": 0.3, "Response": 0.01})
    assert got["Response"] == 0.01 and got["Precedence"] == 0.3
    assert got["Absence"] == FAMILY_P["absence"]
    assert set(pattern_probabilities(("Response", "Absence"), 0.4).values()) == {0.4}
    with pytest.raises(ValueError, match="Response"):
        pattern_probabilities(("Response",), {"Response": 1.0})
    X, y = _response_data()
    for params in [dict(templates="everything"), dict(templates=["Respons"]),
                   dict(templates=["Response"], p_patterns=1.5),
                   dict(templates=["Response"], p_patterns=["x"])]:
        with pytest.raises(ValueError):
            BSIClassifier(**params).fit(X, y)


def test_the_pattern_prior_is_each_slots_own_inclusion():
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=3, n_subtasks=1,
                       p_global=0.8, p_patterns=[0.1, 0.3])
    tau = np.array([1, 0, 1])  # G slot in, first pattern out, second in
    expected = np.log(0.8) + np.log(0.9) + np.log(0.3)
    assert log_prior_globals(tau, model) == pytest.approx(expected)
    with pytest.raises(ValueError, match="p_patterns"):
        make_model(prior="sets_of_chains", likelihood="cb", n_globals=1, n_subtasks=1,
                   p_patterns=[0.1, 0.2])


@pytest.mark.parametrize("template", sorted(TEMPLATES))
def test_the_reference_evaluator_agrees_with_the_kernels(template):
    # the brute-force posterior's truth (definitions) against pattern_truth (recurrences)
    from bsi_sklearn.model.patterns import pattern_truth

    rng = np.random.default_rng(len(template))
    cols = np.array(instantiate(template, [0, 1, 2]))
    for _ in range(30):
        x = (rng.random((int(rng.integers(1, 6)), 3)) < 0.4).astype(np.uint8)
        truth = pattern_truth(template, x, np.array([0, len(x)]), cols)[0]
        assert [instance_holds(template, c, x) for c in cols] == truth.astype(bool).tolist()


def test_every_use_of_a_fitted_pattern_posterior_agrees():
    # text, file, automaton and monitor of a posterior with pattern clauses, from a fit
    from bsi_sklearn import Posterior
    from bsi_sklearn.ltl import parse_ltl

    X, y = _response_data(n=40, seed=1, steps=5)
    X = _frames(X)
    clf = _clf(likelihood="ci").fit(X, y)
    spec = clf.map_specification_
    assert "Response(a, b)" in spec.to_ltl()
    assert parse_ltl(spec.to_ltl()).to_specification() == spec
    Xn, _ = _response_data(n=30, seed=11, steps=5)
    Xn = _frames(Xn)
    # the file keeps the pattern candidates: the same predictions read back
    again = Posterior.from_json(clf.posterior_.to_json())
    np.testing.assert_allclose(again.predict_proba(Xn), clf.posterior_.predict_proba(Xn))
    # the MAP's automaton and its evaluation agree with the clause truth the fit used
    dfa = spec.to_automaton()
    sat = clf.posterior_.satisfaction(Xn)[0]
    for x, s in zip(Xn, sat):
        assert dfa.accepts(x) == spec.satisfied_by(x) == bool(s)
    # the monitor's closed verdict is the paper's vote
    vote = clone(clf).set_params(vote="satisfaction").fit(X, y).predict_proba(Xn)[:, 1]
    closed = [rows[-1] for rows in clf.monitor_proba(Xn)]
    monitor = clf.monitor()
    for x, p in zip(Xn, vote):
        for t in range(len(x)):
            monitor.update(x.iloc[t].to_numpy())
        assert monitor.finish().p_satisfied == pytest.approx(p, abs=1e-12)
        monitor.reset()
    assert len(closed) == len(Xn)


def test_readable_leaves_out_the_pattern_clauses_another_implies():
    from bsi_sklearn import Specification
    from bsi_sklearn.specification.implied_patterns import implied_patterns, implies

    spec = Specification(globals=["g"], eventuals=["pay"], orders=[("pay", "ship")],
                         patterns=[("Absence", ["refund"]), ("Response", ["refund", "pay"]),
                                   ("Existence", ["pay"]), ("Universality", ["g"]),
                                   ("G(x -> F(y))", ["order", "pay"]),
                                   ("Response", ["order", "pay"]),
                                   ("Precedence", ["pay", "ship"])])
    # Absence => Response from it; F(pay) == Existence(pay); G(g) == Universality(g);
    # (!ship U pay) => Precedence(pay, ship); of the two equal responses the catalogue's stays
    assert implied_patterns(spec) == {
        ("P", "Response", ("refund", "pay")), ("P", "Existence", ("pay",)),
        ("P", "Universality", ("g",)), ("P", "G(x -> F(y))", ("order", "pay")),
        ("P", "Precedence", ("pay", "ship"))}
    text = spec.readable()
    assert "Absence(refund)" in text and "Response(order, pay)" in text
    assert "Existence" not in text and "Precedence" not in text and "{" not in text
    # the shorter text means the same formula: the same verdict on every trace over its props
    from bsi_sklearn.ltl import parse_ltl

    shorter = parse_ltl(text).to_specification()
    props = ["g", "pay", "ship", "refund", "order"]
    rng = np.random.default_rng(0)
    for _ in range(300):
        x = (rng.random((int(rng.integers(1, 5)), len(props))) < 0.5).astype(int)
        assert shorter.satisfied_by(x, props) == spec.satisfied_by(x, props)
    assert not implies(("Response", ("a", "b")), ("Absence", ("a",)))
    assert implies(("Succession", ("a", "b")), ("Response", ("a", "b")))
    assert not implies(("Response", ("a", "b")), ("Response", ("b", "a")))


def test_readable_leaves_out_the_pattern_clauses_the_others_imply_together():
    from _reference import all_traces

    from bsi_sklearn import Specification
    from bsi_sklearn.specification.implied_patterns import implied_patterns

    def dropped(**kw):
        return implied_patterns(Specification(**kw))

    # two clauses together, none alone
    assert dropped(eventuals=["a", "b"], patterns=[("CoExistence", ["a", "b"])]) == {
        ("P", "CoExistence", ("a", "b"))}
    assert dropped(patterns=[("Response", ["a", "b"]), ("Response", ["b", "c"]),
                             ("Response", ["a", "c"])]) == {("P", "Response", ("a", "c"))}
    # a contradiction is shown whole (F(b) & F(c) imply the co-existence, but not with the
    # not-co-existence); clauses over other propositions do not take part
    assert dropped(eventuals=["b", "c"], patterns=[("NotCoExistence", ["b", "c"]),
                                                   ("CoExistence", ["b", "c"])]) == set()
    assert dropped(eventuals=["a", "c"], patterns=[("CoExistence", ["a", "b"])]) == set()
    # random specifications: what is left means the same, on every trace up to 3 steps
    names = ["a", "b", "c"]
    traces = list(all_traces(3, 3))
    rng = np.random.default_rng(1)
    pool = [t for t in TEMPLATES if len(TEMPLATES[t].slots) <= 2]
    for _ in range(15):
        pats = {(t, tuple(rng.choice(names, len(TEMPLATES[t].slots), replace=False)))
                for t in rng.choice(pool, int(rng.integers(2, 6)))}
        spec = Specification(eventuals=list(rng.choice(names, int(rng.integers(0, 3)),
                                                       replace=False)),
                             patterns=[(t, list(p)) for t, p in pats])
        gone = implied_patterns(spec)
        kept = Specification(eventuals=spec.eventuals, conditions=spec.conditions,
                             patterns=[(t, list(p)) for t, p in spec.patterns
                                       if ("P", t, p) not in gone])
        assert ([spec.satisfied_by(x, names) for x in traces]
                == [kept.satisfied_by(x, names) for x in traces])


def test_hundreds_of_pattern_clauses_never_crash_the_exact_engine():
    # 870 global slots: the exact budget's estimate passes the floats (2**870 rows); exact
    # says so in words, auto samples
    rng = np.random.default_rng(0)
    X = [(rng.random((6, 30)) < 0.3).astype(int) for _ in range(20)]
    y = rng.integers(0, 2, 20)
    roles = dict(global_candidates=[], subtasks=[0, 1], conditions={}, templates=["Response"])
    with pytest.raises(ValueError, match=r"870 global slots \(0 global candidates, 870 "
                                         r"pattern clauses\).*e\+\d+ TiB"):
        BSIClassifier(inference="exact", **roles).fit(X, y)
    # 50 sweeps cannot describe the calibrated likelihood's posterior over 870 clauses on
    # random labels, where every formula that classifies them alike ties: it says so
    with pytest.warns(ConvergenceWarning, match="MCMC chains disagree"):
        clf = BSIClassifier(n_samples=50, random_state=0, **roles).fit(X, y)
    assert clf.inference_ == "mcmc" and len(clf.pattern_candidates_) == 870
