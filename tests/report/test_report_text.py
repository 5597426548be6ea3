"""Clause sentences, LTL strings and violated clauses of hand-built specifications."""

import itertools

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


# ------------------------------------------------------------------ negated propositions
@pytest.mark.parametrize("clause, conditions, expected", [
    (("G", "!q"), None, "q never holds."),
    (("G", "!omega_3"), None, "Never, POI 3 is visited."),
    (("G", "!!q"), None, "Always, q holds."),
    (("F", "!q"), None, "Eventually, q does not hold."),
    (("F", "!omega_3"), None, "Eventually, it is not the case that POI 3 is visited."),
    (("F", "w"), {"w": "!c"}, "If c does not hold, eventually w holds."),
    (("F", "w"), {"w": "!w"}, "Eventually, w holds."),               # (!w -> F(w)) = F(w)
    (("U", "a", "!q"), None, "q holds until a holds."),              # (!!q U a) = (q U a)
    (("U", "omega_1", "!pi_1"), None, "POI 1 is accessible until POI 1 is visited."),
    (("U", "!q", "b"), None, "q does not hold before b holds."),
    (("U", "p", "!p"), None, "p holds at the first step."),          # (!!p U p) = p
    (("U", "!p", "p"), None, "p does not hold at the first step."),  # (!p U !p) = !p
    (("U", "omega_3", "!omega_3"), None, "POI 3 is visited at the first step."),
    (("U", "a", "!p"), {"a": "!c"}, "If c does not hold, p holds until a holds."),
])
def test_negations_read_as_not(clause, conditions, expected):
    assert clause_sentence(clause, conditions, DESC) == expected
    assert "!" not in expected


def test_a_negation_may_have_its_own_description_and_the_mapping_decides():
    d = {"!door": "the door is shut", "door": "the door is open"}
    assert clause_sentence(("G", "!door"), descriptions=d) == "Always, the door is shut."
    assert clause_sentence(("F", "!door"), descriptions=d) == "Eventually, the door is shut."
    # with no negations known "!x" is a proposition like any other
    assert clause_sentence(("G", "!x"), negations=False) == "Always, !x holds."
    assert clause_sentence(("G", "not_x"), negations={"not_x": "x"}) == "x never holds."
    # a condition that makes its clause hold at the first step is said as it is
    assert clause_sentence(("F", "w"), {"w": "!!w"}) == "If w holds, eventually w holds."
    spec = Specification(globals=["!r"], orders=[("a", "!p")])
    assert describe_specification(spec) == ["r never holds.", "p holds until a holds."]
    assert describe_specification(spec, negations=False) == [
        "Always, !r holds.", "a holds before !p holds."]


def _every_case(max_len=3, activities=("a", "b", "c")):
    return [list(s) for t in range(1, max_len + 1)
            for s in itertools.product(activities, repeat=t)]


@pytest.mark.parametrize("encoding", ["occurred", "current"])
def test_event_log_sentences_on_negations_say_what_every_case_does(encoding):
    from bsi_sklearn.io import EventLogEncoder
    from bsi_sklearn.report.wording import event_log_sentence

    cases = _every_case()
    enc = EventLogEncoder(encoding=encoding).fit(cases)
    traces = enc.transform(cases)
    claims = [
        (("F", "!a"), {}, "a has not occurred at some step: true of every case (at its start)."),
        (("U", "!a", "b"), {}, "(!b U !a): true of every case (a has not occurred at its start)."),
        (("U", "!a", "!b"), {}, "(b U !a): true of every case (a has not occurred at its start)."),
        (("U", "a", "!b"), {}, "b has occurred from the start until a occurs: true of no case "
                               "(nothing has occurred at its start)."),
        (("U", "!a", "a"), {}, "a has not occurred at the start: true of every case."),
        (("U", "a", "!a"), {}, "a has occurred at the start: true of no case (nothing has "
                               "occurred at its start)."),
        (("F", "a"), {"a": "!a"}, "existence(a): a occurs."),
        (("G", "!a"), {}, "absence(a): a never occurs."),
    ]
    for clause, conds, text in claims:
        assert event_log_sentence(clause, conds, negations=enc.negations_) == text
        assert event_log_sentence(clause, conds) == text  # the encoder's naming
        held = [clause_specification(clause, conds).satisfied_by(t) for t in traces]
        if "true of every case" in text:
            assert all(held), clause
        elif "true of no case" in text:
            assert not any(held), clause
    # F(a) with the condition !a is F(a): existence, true exactly where a occurs
    held = [clause_specification(("F", "a"), {"a": "!a"}).satisfied_by(t) for t in traces]
    assert held == ["a" in c for c in cases]
    assert event_log_sentence(("G", "!x"), negations={}) == "!x has occurred from the start."
