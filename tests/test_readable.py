"""Readable formulas (issue 20, item 4): orders as chains and untested clauses set apart.

The chain form must mean what the full formula means. Both texts are parsed by the project's
own LTL reader (``bsi_sklearn.ltl``) and evaluated on every trace up to three steps over the
propositions: an independent reference that knows nothing of ``implied_orders``.
"""

import itertools

import numpy as np
import pytest

from bsi_sklearn import Specification
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.ltl import parse_ltl
from bsi_sklearn.ltl.evaluation import evaluate_traces

SUBTASKS = ["a", "b", "c"]
NAMES = ["a", "b", "c", "p", "q"]  # p and q serve as conditions (and as globals)


def _all_traces(n_props, max_len):
    """Every 0/1 trace of 1..max_len steps, one 3-D block per length."""
    states = np.array(list(itertools.product([0, 1], repeat=n_props)), dtype=np.uint8)
    blocks = []
    for t in range(1, max_len + 1):
        idx = np.array(list(itertools.product(range(len(states)), repeat=t)))
        blocks.append(check_traces(states[idx]))
    return blocks


TRACES = _all_traces(len(NAMES), 3)


def truth(text):
    formula = parse_ltl(text)
    return np.concatenate([evaluate_traces(formula, tr, NAMES) for tr in TRACES])


def _random_spec(rng, conditions=True):
    order = list(rng.permutation(SUBTASKS))
    pairs = [(order[i], order[j]) for i in range(3) for j in range(i + 1, 3) if rng.random() < 0.6]
    eventuals = [w for w in SUBTASKS if rng.random() < 0.5]
    globals_ = [p for p in ("p", "q") if rng.random() < 0.25]
    conds = {}
    if conditions:
        conds = {w: str(rng.choice(["p", "q"])) for w in SUBTASKS if rng.random() < 0.6}
    return Specification(globals=globals_, eventuals=eventuals, orders=pairs, conditions=conds)


def _specs(conditions, n=40, seed=0):
    rng = np.random.default_rng(seed)
    return [_random_spec(rng, conditions) for _ in range(n)]


@pytest.mark.parametrize("conditions", [False, True])
def test_chain_form_agrees_with_the_full_formula_on_every_short_trace(conditions):
    reduced = 0
    for spec in _specs(conditions):
        full = truth(spec.to_ltl())
        np.testing.assert_array_equal(truth(spec.to_ltl(chains=True)), full,
                                      err_msg=spec.to_ltl())
        reduced += bool(spec.implied_orders())
    assert reduced >= 5  # the test exercises reductions, not only formulas without any


def test_hand_picked_conditions():
    cases = [
        # (orders, conditions, globals, implied)
        ([("a", "b"), ("b", "c")], {}, [], {("a", "c")}),
        ([("a", "b"), ("b", "c")], {"a": "p"}, [], {("a", "c")}),           # b unconditioned
        ([("a", "b"), ("b", "c")], {"b": "p"}, [], set()),                  # b may be off
        ([("a", "b"), ("b", "c")], {"a": "p", "b": "p"}, [], {("a", "c")}),  # same condition
        ([("a", "b"), ("b", "c")], {"a": "p", "b": "q"}, [], set()),
        ([("a", "b"), ("b", "c")], {"a": "p", "b": "q"}, ["q"], {("a", "c")}),  # G(q)
    ]
    for orders, conds, globals_, implied in cases:
        spec = Specification(globals=globals_, orders=orders, conditions=conds)
        assert spec.implied_orders() == implied, (orders, conds, globals_)
        np.testing.assert_array_equal(truth(spec.to_ltl(chains=True)), truth(spec.to_ltl()))


def test_dropping_an_order_that_is_not_implied_is_caught():
    # The reference can fail: with b's condition off, c may come before a.
    spec = Specification(orders=[("a", "b"), ("b", "c")], conditions={"b": "p"})
    naive = "(!b U a) & (p -> (!c U b))"
    assert (truth(naive) != truth(spec.to_ltl())).any()
    # and without the eventual clauses the chain still implies its orders (strong until)
    spec = Specification(orders=[("a", "b"), ("b", "c")])
    assert not spec.eventuals
    np.testing.assert_array_equal(truth("(!b U a) & (!c U b)"), truth(spec.to_ltl()))


def test_without_conditions_the_chain_form_is_the_transitive_reduction():
    for spec in _specs(conditions=False, n=60, seed=1):
        closed = spec.orders
        reduction = {(a, c) for a, c in closed
                     if not any((a, b) in closed and (b, c) in closed for b in SUBTASKS)}
        assert closed - spec.implied_orders() == reduction
        # none of the orders kept can go: each one changes the formula on some trace
        kept = sorted(reduction)
        for drop in kept:
            rest = Specification(globals=spec.globals, eventuals=spec.eventuals,
                                 orders=[o for o in kept if o != drop])
            if rest.orders != closed:
                assert (truth(rest.to_ltl()) != truth(spec.to_ltl())).any()


def test_str_is_the_chain_form_and_to_ltl_stays_full():
    spec = Specification(eventuals=["a"], orders=[("a", "b"), ("b", "c")])
    assert spec.to_ltl() == "F(a) & (!b U a) & (!c U a) & (!c U b)"
    assert str(spec) == spec.to_ltl(chains=True) == "F(a) & (!b U a) & (!c U b)"
    assert spec.clause_strings(chains=True) == ["F(a)", "(!b U a)", "(!c U b)"]
    assert spec.to_ltl(latex=True, chains=True).count(r"\mathbf{U}") == 2
    assert Specification().to_ltl(chains=True) == "true"


@pytest.mark.parametrize("conditions", [False, True])
def test_readable_text_with_untested_clauses_is_the_full_formula(conditions):
    rng = np.random.default_rng(2)
    for spec in _specs(conditions, n=25, seed=3):
        keys = sorted(spec.clauses(), key=repr)
        vacuous = {k for k in keys if rng.random() < 0.4}
        text = spec.readable(vacuous)
        shown, _, rest = text.partition("  [untested: ")
        assert ("[untested" in text) == bool(vacuous - {("U", *o) for o in
                                                        spec.implied_orders()})
        whole = shown if not rest else f"({shown}) & ({rest.removesuffix(']')})"
        np.testing.assert_array_equal(truth(whole), truth(spec.to_ltl()), err_msg=text)


def test_readable_leaves_out_what_a_global_implies():
    # G(w): w holds at the first step, so F(w) and every (!b U w) hold too
    spec = Specification(globals=["a"], eventuals=["a", "b"], orders=[("a", "b"), ("b", "c")])
    assert spec.readable() == "G(a) & F(b) & (!c U b)"
    rng = np.random.default_rng(4)
    dropped = 0
    for _ in range(30):
        base = _random_spec(rng)
        spec = Specification(globals=[g for g in NAMES if rng.random() < 0.3],
                             eventuals=base.eventuals, orders=base.orders,
                             conditions=base.conditions)
        text = spec.readable()
        np.testing.assert_array_equal(truth(text), truth(spec.to_ltl()), err_msg=text)
        dropped += text.count("&") < spec.to_ltl(chains=True).count("&")
    assert dropped >= 5


def test_readable_marks_only_the_clauses_it_has():
    spec = Specification(globals=["safe"], eventuals=["a"], orders=[("a", "b")])
    assert spec.readable() == spec.readable([("G", "other"), ("U", "b", "a")]) == str(spec)
    assert spec.readable({("G", "safe"), ("F", "a"), ("U", "a", "b")}) == \
        "true  [untested: G(safe) & F(a) & (!b U a)]"


@pytest.mark.parametrize("bad", ["G", [("X", "a")], [("U", "a")], [("G", "a", "b")], 3])
def test_readable_rejects_what_is_not_a_clause_key(bad):
    with pytest.raises(ValueError, match="vacuous"):
        Specification(globals=["a"]).readable(bad)


# ------------------------------------------------------------------ untested clauses of a fit
FIT_NAMES = ["safe", "a", "b", "c"]


def _demo(events, T=4):
    """safe always holds and c from the first step, in every demonstration."""
    tr = np.zeros((T, 4), dtype=np.uint8)
    tr[:, 0] = tr[:, 3] = 1
    for p, t in events:
        tr[t:, FIT_NAMES.index(p)] = 1
    return tr


FIT_X = [_demo([("a", 1), ("b", 2)]), _demo([("a", 1), ("b", 3)]),  # acceptable
         _demo([("b", 1), ("a", 2)]), _demo([("a", 1)])]           # b before a; b never
FIT_Y = [1, 1, 0, 0]
FIT_ROLES = dict(global_candidates=[0], subtasks=[1, 2, 3])


def _satisfied_by_all(key, X):
    kind, *ids = key
    spec = (Specification(globals=ids) if kind == "G" else Specification(eventuals=ids)
            if kind == "F" else Specification(orders=[tuple(ids)]))
    return all(spec.satisfied_by(x) for x in X)


@pytest.fixture(scope="module")
def fitted():
    from bsi_sklearn import BSIClassifier

    return BSIClassifier(**FIT_ROLES, random_state=0).fit(FIT_X, FIT_Y)


def test_vacuous_clauses_are_those_every_demonstration_satisfies(fitted):
    keys = fitted.posterior_.clause_keys()
    expected = {k for k in keys if _satisfied_by_all(k, FIT_X)}
    # by hand: safe always, a always done, c from the start (so c precedes a and b)
    assert expected == {("G", 0), ("F", 1), ("F", 3), ("U", 3, 1), ("U", 3, 2)}
    assert fitted.vacuous_clauses_ == expected == fitted.posterior_.vacuous_clauses


def test_the_fitted_displays_set_untested_clauses_apart(fitted):
    spec = fitted.map_specification_
    assert spec == Specification(globals=[0], eventuals=[1, 2, 3],
                                 orders=[(3, 1), (1, 2)])  # (3, 2) by closure
    text = spec.readable(fitted.vacuous_clauses_)
    assert text == "F(2) & (!2 U 1)  [untested: G(0) & F(1) & F(3) & (!1 U 3)]"
    frame = fitted.posterior_.to_frame(k=3)
    assert frame["readable"].iloc[0] == text
    assert list(frame["ltl"]) == [s.to_ltl() for s, _ in fitted.posterior_.top(3)]
    assert frame["ltl"].iloc[0] == (
        "G(0) & F(1) & F(2) & F(3) & (!2 U 1) & (!1 U 3) & (!2 U 3)")


def test_positive_only_fits_and_files_mark_nothing(fitted):
    from bsi_sklearn import BSIClassifier, Posterior

    clf = BSIClassifier(**FIT_ROLES, random_state=0).fit(FIT_X[:2])
    assert clf.vacuous_clauses_ == frozenset()
    assert clf.posterior_.to_frame()["readable"].iloc[0] == str(clf.map_specification_)
    again = Posterior.from_json(fitted.posterior_.to_json())
    assert again.vacuous_clauses == frozenset()
    assert again.to_frame()["ltl"].iloc[0] == fitted.map_specification_.to_ltl()
    assert again.mark_vacuous(FIT_X, FIT_Y) == fitted.vacuous_clauses_


@pytest.mark.parametrize("y", [[1, 0], [1, 2, 0, 0], [[1, 1, 0, 0]]])
def test_mark_vacuous_checks_the_labels(fitted, y):
    with pytest.raises(ValueError, match="mark_vacuous: y must be one 0/1 label"):
        fitted.posterior_.mark_vacuous(FIT_X, y)
