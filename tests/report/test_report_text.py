"""Clause sentences, LTL strings and violated clauses of hand-built specifications."""

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn import Specification
from bsi_sklearn.report import (
    clause_sentence,
    clause_specification,
    describe_specification,
    ordered_clauses,
    violated_clauses,
)

DESC = {
    "strikers_alive": "the strikers are alive",
    "omega_1": "POI 1 is visited",
    "omega_3": "POI 3 is visited",
    "pi_1": "POI 1 is accessible",
    "pi_3": "POI 3 is accessible",
}
COND = {"omega_1": "pi_1", "omega_3": "pi_3"}


@pytest.mark.parametrize("clause, conditions, expected", [
    (("G", "strikers_alive"), None, "Always, the strikers are alive."),
    (("F", "omega_3"), None, "Eventually, POI 3 is visited."),
    (("F", "omega_3"), COND, "If POI 3 is accessible, eventually POI 3 is visited."),
    (("U", "omega_1", "omega_3"), None, "POI 1 is visited before POI 3 is visited."),
    (("U", "omega_1", "omega_3"), COND,
     "If POI 1 is accessible, POI 1 is visited before POI 3 is visited."),
    # the condition of an order is its predecessor's: omega_3 -> pi_3 plays no part here
    (("U", "omega_1", "omega_3"), {"omega_3": "pi_3"},
     "POI 1 is visited before POI 3 is visited."),
])
def test_sentences_with_descriptions(clause, conditions, expected):
    assert clause_sentence(clause, conditions, DESC) == expected


@pytest.mark.parametrize("clause, expected", [
    (("G", "tau_1"), "Always, tau_1 holds."),
    (("F", "omega_2"), "If pi_2 holds, eventually omega_2 holds."),
    (("F", "w"), "Eventually, w holds."),
    (("U", "omega_2", "w"), "If pi_2 holds, omega_2 holds before w holds."),
    (("U", "w", "omega_2"), "w holds before omega_2 holds."),  # names are not capitalised
    (("G", 0), "Always, 0 holds."),
])
def test_sentences_without_descriptions(clause, expected):
    assert clause_sentence(clause, {"omega_2": "pi_2"}) == expected


def test_partial_descriptions_and_capitalisation():
    d = {"a": "the arm is raised", "b": "UAV 2 lands"}
    assert clause_sentence(("U", "a", "c"), descriptions=d) == \
        "The arm is raised before c holds."
    assert clause_sentence(("U", "b", "a"), descriptions=d) == \
        "UAV 2 lands before the arm is raised."
    # whitespace in descriptions is normalised
    assert clause_sentence(("G", "a"), descriptions={"a": "  the arm\n is  raised "}) == \
        "Always, the arm is raised."


def test_describe_specification_reading_order():
    spec = Specification(globals=["strikers_alive"], eventuals=["omega_3", "omega_1"],
                         orders=[("omega_1", "omega_3")], conditions=COND)
    assert ordered_clauses(spec) == [("G", "strikers_alive"), ("F", "omega_1"),
                                     ("F", "omega_3"), ("U", "omega_1", "omega_3")]
    assert describe_specification(spec, DESC) == [
        "Always, the strikers are alive.",
        "If POI 1 is accessible, eventually POI 1 is visited.",
        "If POI 3 is accessible, eventually POI 3 is visited.",
        "If POI 1 is accessible, POI 1 is visited before POI 3 is visited.",
    ]
    assert describe_specification(Specification()) == []


def test_ordered_clauses_follow_clause_strings():
    spec = Specification(globals=["z", "y"], eventuals=[3, 1, 2],
                         orders=[(2, 1), (3, 2)], conditions={3: "c"})
    keys = ordered_clauses(spec)
    assert set(keys) == spec.clauses()
    singles = [clause_specification(k, spec.conditions).to_ltl() for k in keys]
    assert singles == spec.clause_strings()


@pytest.mark.parametrize("clause, conditions, plain, latex", [
    (("G", "safe"), None, "G(safe)", r"\mathbf{G}(\mathit{safe})"),
    (("F", "omega_1"), COND, "(pi_1 -> F(omega_1))",
     r"(\mathit{pi\_1} \rightarrow \mathbf{F}(\mathit{omega\_1}))"),
    (("F", "w"), None, "F(w)", r"\mathbf{F}(\mathit{w})"),
    (("U", "omega_1", "omega_3"), COND, "(pi_1 -> (!omega_3 U omega_1))",
     r"(\mathit{pi\_1} \rightarrow (\neg \mathit{omega\_3}\,\mathbf{U}\,\mathit{omega\_1}))"),
    (("U", "a", "b"), None, "(!b U a)", r"(\neg \mathit{b}\,\mathbf{U}\,\mathit{a})"),
])
def test_clause_ltl_strings(clause, conditions, plain, latex):
    spec = clause_specification(clause, conditions)
    assert spec.clauses() == {clause}
    assert spec.to_ltl() == plain
    assert spec.to_ltl(latex=True) == latex


@pytest.mark.parametrize("bad", [("X", "a"), ("G",), ("U", "a"), ("F", "a", "b"), "G(a)",
                                 ["G", "a"]])
def test_bad_clause_keys(bad):
    with pytest.raises(ValueError, match="not a clause key"):
        clause_sentence(bad)
    with pytest.raises(ValueError, match="not a clause key"):
        clause_specification(bad)


def test_bad_descriptions():
    with pytest.raises(ValueError, match=r"descriptions\['a'\] must be a non-empty string"):
        clause_sentence(("G", "a"), descriptions={"a": ""})
    with pytest.raises(ValueError, match=r"descriptions\['a'\]"):
        clause_sentence(("G", "a"), descriptions={"a": 3})
    with pytest.raises(ValueError, match="descriptions must be a mapping"):
        clause_sentence(("G", "a"), descriptions=["a"])
    with pytest.raises(ValueError, match="must be a Specification"):
        describe_specification("G(a)")


# ---------------------------------------------------------------------------- violations
NAMES = ["safe", "a", "b", "a_ok", "b_ok"]
SPEC = Specification(globals=["safe"], eventuals=["a", "b"], orders=[("a", "b")],
                     conditions={"a": "a_ok", "b": "b_ok"})


def trace(steps, T=5, a_ok=True, b_ok=True, unsafe=()):
    """Propositions become (and stay) true at the given steps."""
    tr = np.zeros((T, len(NAMES)), dtype=bool)
    tr[:, 0] = True
    tr[:, 3], tr[:, 4] = a_ok, b_ok
    for p, t in steps.items():
        tr[t:, NAMES.index(p)] = True
    for t in unsafe:
        tr[t, 0] = False
    return pd.DataFrame(tr, columns=NAMES)


@pytest.mark.parametrize("steps, kwargs, expected", [
    ({"a": 1, "b": 3}, {}, []),
    ({"a": 2, "b": 2}, {}, []),  # together at the first a is fine
    ({"a": 1, "b": 3}, {"unsafe": [4]}, [("G", "safe")]),
    ({"a": 3, "b": 1}, {}, [("U", "a", "b")]),
    ({"b": 1}, {}, [("F", "a"), ("U", "a", "b")]),  # strong until: a must happen
    ({}, {}, [("F", "a"), ("F", "b"), ("U", "a", "b")]),
    ({"b": 1}, {"a_ok": False}, []),  # a's condition false: F(a) and the order are vacuous
    ({"a": 1}, {"b_ok": False}, []),
    ({"a": 1}, {}, [("F", "b")]),
    ({"a": 3, "b": 1}, {"b_ok": False, "unsafe": [0, 2]}, [("G", "safe"), ("U", "a", "b")]),
])
def test_violated_clauses(steps, kwargs, expected):
    tr = trace(steps, **kwargs)
    assert violated_clauses(SPEC, tr) == expected
    # same answer from a plain array with feature names, and consistent with the formula
    assert violated_clauses(SPEC, tr.to_numpy(), feature_names=NAMES) == expected
    assert SPEC.satisfied_by(tr) == (not expected)


def test_violated_clauses_integer_identifiers():
    spec = Specification(globals=[0], eventuals=[1], orders=[(1, 2)])
    tr = np.array([[1, 0, 1], [0, 1, 1]])
    assert violated_clauses(spec, tr) == [("G", 0), ("U", 1, 2)]


def test_order_edges_are_the_orders_not_implied():
    # The DAG figure draws the chain form's orders (Specification.implied_orders).
    closed = Specification(orders=[("a", "b"), ("b", "c"), ("c", "d"), ("a", "e"),
                                   ("x", "d")])
    assert sorted(closed.orders - closed.implied_orders()) == [
        ("a", "b"), ("a", "e"), ("b", "c"), ("c", "d"), ("x", "d")]
    assert Specification().implied_orders() == frozenset()
