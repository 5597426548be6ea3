"""Pattern clauses in LTL text: ``Specification.to_ltl`` writes them, ``parse_ltl`` reads them."""

import numpy as np
import pytest

from bsi_sklearn.ltl import Pattern, parse_ltl
from bsi_sklearn.specification import Specification
from bsi_sklearn.specification.templates import TEMPLATES, get_template

_PROPS = ["a", "b", "c"]


def _spec_with(name, props, **kw):
    return Specification(globals=["s"], eventuals=["a"], orders=[("a", "b")],
                         conditions={"a": "c"}, patterns=[(name, props)], **kw)


@pytest.mark.parametrize("name", [*TEMPLATES, "G(x -> WX(!x))", "(x <-> y) U (x & !y)"])
def test_to_ltl_reads_back_to_the_same_specification(name):
    n = len(get_template(name).slots)
    spec = _spec_with(name, _PROPS[:n][::-1])
    for text in (spec.to_ltl(), str(spec), spec.readable(), spec.to_ltl(chains=True)):
        assert parse_ltl(text).to_specification() == spec, text
    assert parse_ltl(parse_ltl(spec.to_ltl()).to_prefix()).to_specification() == spec


def test_several_patterns_negated_and_quoted_propositions_read_back():
    spec = Specification(patterns=[("Response", ("!a", "b")), ("Choice", ("x", "w")),
                                   ("G(x -> F(y))", ("b", "a")), ("Existence", ["F1"])])
    assert parse_ltl(spec.to_ltl()).to_specification() == spec
    assert parse_ltl(spec.readable()).to_specification() == spec
    named = Specification(patterns=[("Response", ("!odd", "b"))])
    assert named.readable(negations=False) == 'Response("!odd", b)'
    assert parse_ltl(named.readable(negations=False)).to_specification() == named


@pytest.mark.parametrize("name", [*TEMPLATES, "G(x -> WX(!x))"])
def test_the_parsed_text_means_what_the_specification_means(name):
    n = len(get_template(name).slots)
    spec = _spec_with(name, _PROPS[1:1 + n] if n == 1 else _PROPS[:n][::-1])
    formula = parse_ltl(spec.to_ltl())
    rng = np.random.default_rng(3)
    traces = [rng.random((int(rng.integers(1, 6)), 4)) < 0.6 for _ in range(200)]
    names = [*_PROPS, "s"]
    # ragged traces: evaluate_traces pads them, the pattern reads each one's end
    got = formula.evaluate(traces, feature_names=names)
    expected = [spec.satisfied_by(tr, feature_names=names) for tr in traces]
    np.testing.assert_array_equal(got, expected)


def test_a_pattern_inside_another_operator_is_no_specification_but_evaluates():
    phi = parse_ltl("F(ChainResponse(a, b))")
    assert phi.to_specification() is None
    # step t reads the suffix from t: only the last step's, without an a, satisfies it
    trace = np.array([[0, 0], [1, 0], [0, 0]])
    assert phi.satisfied_by(trace, feature_names=["a", "b"])
    assert not phi.satisfied_by(trace[:2], feature_names=["a", "b"])
    assert parse_ltl("Response(a, a)").to_specification() is None


@pytest.mark.parametrize("text, message", [
    ("Respons(a, b)", "unknown template 'Respons'; the known templates are: Existence"),
    ("respond(a, b)", "unknown template 'respond'.*braces"),
    ("Response(a)", r"'Response' has 2 slots \(a, b\), got 1 arguments"),
    ("Response(a, b, c) & G(s)", "got 3 arguments"),
    ("{G(x -> F(y))}(a)", "got 1 arguments"),
    ("{G(x -> }(a)", "expected a formula"),
    ("Response(F(a), b)", "propositions or their negations, got F"),
])
def test_bad_pattern_clauses_are_refused_with_what_is_wrong(text, message):
    with pytest.raises(ValueError, match=message):
        parse_ltl(text)


def test_the_node_prints_in_both_notations():
    node = Pattern("Precedence", (parse_ltl("a"), parse_ltl("!b")))
    assert str(node) == "Precedence(a, !b)"
    assert node.to_prefix() == "Precedence(a,!(b))"
    assert parse_ltl(node.to_prefix()) == node
    assert node.atoms == {"a", "b"}
