"""LTL formulas: parsing, finite-trace semantics, flloat agreement, the template."""

import numpy as np
import pandas as pd
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from bsi_sklearn import ltl
from bsi_sklearn.data.preprocessing import add_negations
from bsi_sklearn.ltl import (
    And,
    Atom,
    Constant,
    Eventually,
    Globally,
    Implies,
    Next,
    Not,
    Or,
    Release,
    Until,
    evaluation,
    parse_ltl,
)
from bsi_sklearn.specification import Specification

ATOMS = ["a", "b", "c"]


def tr(*rows):
    """A trace over (a, b, c) from strings like "ab", "", "c"."""
    return pd.DataFrame([[name in row for name in ATOMS] for row in rows], columns=ATOMS)


def holds(text, *rows):
    return parse_ltl(text).satisfied_by(tr(*rows))


# -- parsing --------------------------------------------------------------------------------


@pytest.mark.parametrize("text", [
    "G(!(x0))", "->(F(x1),U(!(x0),x1))", "|(|(G(!(x0)),F(&(x0,F(x1)))),|(G(!(x3)),F(x3)))",
    "G(&(x0,->(!(x1),U(!(x1),&(x2,!(x1))))))", "F(&(a,F(&(b,F(c)))))", "X(R(a,<->(b,true)))",
    "false",
])
def test_prefix_round_trip(text):
    phi = parse_ltl(text)
    assert phi.to_prefix() == text
    assert parse_ltl(phi.to_prefix()) == phi
    assert parse_ltl(str(phi), notation="infix") == phi


def test_infix_precedence_and_associativity():
    assert parse_ltl("a & b | c") == Or(And(Atom("a"), Atom("b")), Atom("c"))
    assert parse_ltl("a -> b -> c") == Implies(Atom("a"), Implies(Atom("b"), Atom("c")))
    assert parse_ltl("!b U a & c") == And(Until(Not(Atom("b")), Atom("a")), Atom("c"))
    assert parse_ltl("a U b U c") == Until(Atom("a"), Until(Atom("b"), Atom("c")))
    assert parse_ltl("G F a") == Globally(Eventually(Atom("a")))
    assert parse_ltl("X !a R b") == Release(Next(Not(Atom("a"))), Atom("b"))
    assert parse_ltl("TRUE | False") == Or(Constant(True), Constant(False))
    assert parse_ltl('G("my prop")') == Globally(Atom("my prop"))
    assert str(Globally(Atom("my prop"))) == 'G("my prop")'
    assert str(Atom("G")) == '"G"'


def test_nary_prefix_and_or_fold_left():
    assert parse_ltl("&(a,b,c)") == And(And(Atom("a"), Atom("b")), Atom("c"))


def test_operators_build_formulas():
    phi = Atom("a") & ~Atom("b") | "F(c)"
    assert phi == Or(And(Atom("a"), Not(Atom("b"))), Eventually(Atom("c")))
    assert phi.atoms == {"a", "b", "c"}
    assert phi.size == 7 and phi.depth == 3
    assert eval(repr(phi), {"parse_ltl": parse_ltl}) == phi


@pytest.mark.parametrize("text, message", [
    ("", "empty formula"),
    ("&(a)", "takes 2 arguments"),
    ("U(a,b,c)", "takes 2 arguments"),
    ("F(a", "expected '\\)'"),
    ("a $ b", "unexpected character '\\$' at position 2"),
    ("G(a,b)", "cannot parse"),
    ("a & ", "unexpected end"),
    ("(a & b))", "unexpected '\\)'"),
])
def test_parse_errors(text, message):
    with pytest.raises(ValueError, match=message):
        parse_ltl(text)


def test_parse_rejects_bad_arguments():
    with pytest.raises(ValueError, match="notation"):
        parse_ltl("a", notation="polish")
    with pytest.raises(ValueError, match="must be a string"):
        parse_ltl(3)
    with pytest.raises(ValueError, match="position 0"):
        parse_ltl("U(a,b)", notation="infix")
    with pytest.raises(TypeError):
        Not("a")


# -- semantics (last state repeats forever) -------------------------------------------------


def test_hand_checked_semantics():
    assert holds("G(a)", "a", "ab", "ac")
    assert not holds("G(a)", "a", "b")
    assert holds("F(b)", "a", "", "b")
    assert not holds("F(b)", "a", "c")
    assert holds("!b U a", "", "c", "ab")  # a and b together at the first a is fine
    assert not holds("!b U a", "b", "a")
    assert not holds("!b U a", "", "")  # strong until: a must happen
    assert holds("a U b", "a", "a", "b") and not holds("a U b", "a", "", "b")
    assert holds("a R b", "b", "b") and holds("a R b", "b", "ab", "")
    assert not holds("a R b", "b", "")


def test_next_on_the_last_step_reads_the_repeated_last_state():
    assert holds("X(a)", "a")  # flloat's strong X is false here, weak X true
    assert not holds("X(b)", "b", "a")
    assert holds("X(X(X(b)))", "a", "b")
    assert holds("G(a -> X(a))", "", "a") and not holds("G(a -> X(a))", "a", "")


def test_evaluate_accepts_every_trace_format():
    phi = parse_ltl("F(x1) & G(!x0 | x1)")
    arrays3 = np.array([[[0, 0], [0, 1]], [[1, 0], [0, 1]]])
    expected = np.array([True, False])
    names = ["x0", "x1"]
    np.testing.assert_array_equal(phi.evaluate(arrays3, feature_names=names), expected)
    np.testing.assert_array_equal(phi.evaluate(list(arrays3), feature_names=names), expected)
    frames = [pd.DataFrame(t, columns=names) for t in arrays3]
    np.testing.assert_array_equal(phi.evaluate(frames), expected)
    flat = np.array([[0, 1], [1, 1], [0, 0]])  # 2-D: traces of length one
    np.testing.assert_array_equal(phi.evaluate(flat, feature_names=names), [True, True, False])
    # decimal atoms read column indices when the traces have no names
    np.testing.assert_array_equal(parse_ltl("F(1)").evaluate(arrays3), [True, True])


def test_evaluate_errors_name_the_proposition():
    with pytest.raises(ValueError, match="'z' is not among"):
        parse_ltl("F(z)").evaluate([tr("a")])
    with pytest.raises(ValueError, match="no proposition names"):
        parse_ltl("F(a)").evaluate([np.ones((2, 2))])
    with pytest.raises(ValueError, match="feature_names has 1 entries"):
        parse_ltl("F(a)").evaluate([np.ones((2, 2))], feature_names=["a"])
    with pytest.raises(ValueError, match="demonstration 1, step 0, proposition 0 has value 2"):
        parse_ltl("F(a)").evaluate([np.ones((2, 1)), np.full((2, 1), 2)], feature_names=["a"])


def test_chunked_evaluation_matches(monkeypatch):
    rng = np.random.default_rng(0)
    traces = [rng.random((int(rng.integers(1, 30)), 3)) < 0.5 for _ in range(60)]
    phi = parse_ltl("G(a -> F(b U c)) | X(X(!a R c))")
    whole = phi.evaluate(traces, feature_names=ATOMS)
    monkeypatch.setattr(evaluation, "_MAX_CELLS", 40)
    np.testing.assert_array_equal(phi.evaluate(traces, feature_names=ATOMS), whole)
    single = [phi.satisfied_by(t, feature_names=ATOMS) for t in traces]
    np.testing.assert_array_equal(whole, single)


# -- against flloat -------------------------------------------------------------------------

formulas = st.recursive(
    st.sampled_from([Atom(a) for a in ATOMS] + [Constant(True), Constant(False)]),
    lambda sub: st.one_of(
        st.builds(Not, sub), st.builds(Next, sub), st.builds(Eventually, sub),
        st.builds(Globally, sub), st.builds(And, sub, sub), st.builds(Or, sub, sub),
        st.builds(Implies, sub, sub), st.builds(ltl.Equivalent, sub, sub),
        st.builds(Until, sub, sub), st.builds(Release, sub, sub),
    ),
    max_leaves=6,
)
traces = st.lists(arrays(np.bool_, st.tuples(st.integers(1, 6), st.just(3))),
                  min_size=1, max_size=4)


def to_flloat(phi):
    """flloat text with the same meaning: X(p) on the last step reads p there."""
    if isinstance(phi, Atom):
        return phi.name
    if isinstance(phi, Constant):
        return "true" if phi.value else "false"
    if isinstance(phi, Next):
        inner = to_flloat(phi.operand)
        return f"(X({inner}) | (last & {inner}))"
    if isinstance(phi, (Not, Eventually, Globally)):
        return f"{phi.symbol}({to_flloat(phi.operand)})"
    return f"({to_flloat(phi.left)} {phi.symbol} {to_flloat(phi.right)})"


@pytest.fixture(scope="module")
def flloat_parser():
    parser_module = pytest.importorskip("flloat.parser.ltlf")
    return parser_module.LTLfParser()


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(phi=formulas, demos=traces)
def test_agrees_with_flloat(flloat_parser, phi, demos):
    reference = flloat_parser(to_flloat(phi))
    expected = [reference.truth([dict(zip(ATOMS, map(bool, row))) for row in t], 0)
                for t in demos]
    np.testing.assert_array_equal(phi.evaluate(demos, feature_names=ATOMS), expected)


def test_x_differs_from_flloat_only_on_the_last_step(flloat_parser):
    last_only = [dict(a=True, b=False, c=False)]
    assert not flloat_parser("X(a)").truth(last_only, 0)
    assert parse_ltl("X(a)").satisfied_by(tr("a"))


@settings(max_examples=150, deadline=None)
@given(phi=formulas, demos=traces, extra=st.integers(1, 4))
def test_repeating_the_last_state_changes_nothing(phi, demos, extra):
    padded = [np.vstack([t] + [t[-1:]] * extra) for t in demos]
    np.testing.assert_array_equal(phi.evaluate(demos, feature_names=ATOMS),
                                  phi.evaluate(padded, feature_names=ATOMS))


@settings(max_examples=150, deadline=None)
@given(phi=formulas)
def test_text_round_trips(phi):
    assert parse_ltl(phi.to_prefix(), notation="prefix") == phi
    assert parse_ltl(str(phi), notation="infix") == phi


# -- the BSI template -----------------------------------------------------------------------


@pytest.mark.parametrize("text, expected", [
    ("true", Specification()),
    ("G(a)", Specification(globals=["a"])),
    ("G(a & !b) & G(G(c))", Specification(globals=["a", "!b", "c"])),
    ("&(F(a),F(b))", Specification(eventuals=["a", "b"])),
    ("F(!a)", Specification(eventuals=["!a"])),
    ("!b U a", Specification(orders=[("a", "b")])),
    ("b U a", Specification(orders=[("a", "!b")])),
    ("!a U a", Specification(eventuals=["a"])),
    ("true U a", Specification(eventuals=["a"])),
    ("p -> (F(a) & (!b U a))",
     Specification(eventuals=["a"], orders=[("a", "b")], conditions={"a": "p"})),
    ("!p | F(a)", Specification(eventuals=["a"], conditions={"a": "p"})),
    ("(!b U a) & (!c U b)", Specification(orders=[("a", "b"), ("b", "c"), ("a", "c")])),
    ("(p -> (!b U a)) & (!c U b)",
     Specification(orders=[("a", "b"), ("b", "c")], conditions={"a": "p"})),
])
def test_to_specification_in_template(text, expected):
    assert parse_ltl(text).to_specification() == expected


@pytest.mark.parametrize("text", [
    "a", "X(a)", "F(a & F(b))", "G(a -> b)", "G(a) | F(b)", "F(a) & (p -> F(a))",
    "(!b U a) & (!a U b)", "(!b U a) & (p -> (!c U b))", "(p -> F(a)) & (q -> (!b U a))",
    "G(false)", "false", "F(a) & false", "G(a) R b", "F(a) | F(b)", "(a & b) U c",
])
def test_to_specification_outside_template(text):
    assert parse_ltl(text).to_specification() is None


def test_to_specification_names():
    phi = parse_ltl("G(!x0) & F(x1)")
    assert phi.to_specification(names=["x0", "x1"]) is None
    assert phi.to_specification(names={"!x0": 2, "x1": 1}) == Specification(
        globals=[2], eventuals=[1])
    assert parse_ltl("F(1) & G(0)").to_specification(names=range(3)) == Specification(
        globals=[0], eventuals=[1])
    assert phi.to_specification(negation_prefix="not_") == Specification(
        globals=["not_x0"], eventuals=["x1"])
    with pytest.raises(ValueError, match="sequence or a mapping"):
        phi.to_specification(names="x0")


SUBTASKS = ["a", "b", "c", "d"]


@st.composite
def specifications(draw):
    order = draw(st.permutations(SUBTASKS))
    pairs = [(order[i], order[j]) for i in range(4) for j in range(i + 1, 4)]
    orders = draw(st.lists(st.sampled_from(pairs), max_size=4, unique=True))
    globals_ = draw(st.lists(st.sampled_from(["a", "b", "!c", "!d", "p"]), unique=True))
    eventuals = draw(st.lists(st.sampled_from(SUBTASKS + ["!a"]), unique=True))
    conditions = draw(st.dictionaries(st.sampled_from(SUBTASKS + ["!a"]),
                                      st.sampled_from(["p", "!p"]), max_size=3))
    return Specification(globals=globals_, eventuals=eventuals, orders=orders,
                         conditions=conditions)


PROPS = SUBTASKS + ["p"]
prop_traces = st.lists(arrays(np.bool_, st.tuples(st.integers(1, 6), st.just(len(PROPS)))),
                       min_size=1, max_size=6)


@settings(max_examples=200, deadline=None)
@given(spec=specifications(), demos=prop_traces)
def test_specification_text_round_trip_and_semantics(spec, demos):
    """Specification.to_ltl() re-parses to the same specification and the same truth."""
    phi = parse_ltl(spec.to_ltl())
    augmented = add_negations([pd.DataFrame(t, columns=PROPS) for t in demos])
    assert phi.to_specification(names=list(augmented[0].columns)) == spec
    np.testing.assert_array_equal(phi.evaluate(demos, feature_names=PROPS),
                                  [spec.satisfied_by(t) for t in augmented])


template_clauses = st.one_of(
    st.builds(lambda p: f"G({p})", st.sampled_from(PROPS + ["!a", "!p"])),
    st.builds(lambda w: f"F({w})", st.sampled_from(SUBTASKS + ["!b"])),
    st.builds(lambda a, b: f"({b} U {a})", st.sampled_from(SUBTASKS),
              st.sampled_from(["!a", "!b", "!c", "!d", "a", "true"])),
    st.builds(lambda c, w: f"({c} -> F({w}))", st.sampled_from(["p", "!p"]),
              st.sampled_from(SUBTASKS)),
    st.builds(lambda c, a, b: f"({c} -> (!{b} U {a}))", st.sampled_from(["p", "!p"]),
              st.sampled_from(SUBTASKS), st.sampled_from(SUBTASKS)),
)


@settings(max_examples=300, deadline=None)
@given(clauses=st.lists(template_clauses, min_size=1, max_size=5), demos=prop_traces)
def test_to_specification_is_sound(clauses, demos):
    """Whenever a conjunction is recognised, the specification means the same thing."""
    phi = parse_ltl(" & ".join(clauses))
    spec = phi.to_specification()
    if spec is None:
        return
    augmented = add_negations([pd.DataFrame(t, columns=PROPS) for t in demos])
    np.testing.assert_array_equal(phi.evaluate(demos, feature_names=PROPS),
                                  [spec.satisfied_by(t) for t in augmented])
