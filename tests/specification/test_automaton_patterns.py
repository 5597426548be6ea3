"""The specification DFA with pattern clauses: the template clauses AND each pattern."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from bsi_sklearn import Specification
from bsi_sklearn.model.patterns import pattern_truth
from bsi_sklearn.specification.automaton import specification_dfa
from bsi_sklearn.specification.templates import TEMPLATES, get_template

NAMES = ["s", "a", "b", "c"]
TEMPLATE_CHOICES = [*TEMPLATES, "G(x -> F(y))", "x U (y & X(z))", "WX(x) | G(!x)"]
TRACES = arrays(np.uint8, st.tuples(st.integers(1, 6), st.just(len(NAMES))),
                elements=st.integers(0, 1))


@st.composite
def _patterns(draw):
    name = draw(st.sampled_from(TEMPLATE_CHOICES))
    k = len(get_template(name).slots)
    return name, tuple(draw(st.permutations(NAMES))[:k])


_SPECS = st.builds(
    lambda g, e, o, c, p: (dict(globals=g, eventuals=e, orders=o,
                                conditions={"b": "c"} if c else None), p),
    st.lists(st.sampled_from(["s", "c"]), max_size=1, unique=True),
    st.lists(st.sampled_from(["a", "b"]), max_size=2, unique=True),
    st.sampled_from([[], [("a", "b")], [("b", "a")]]),
    st.booleans(),
    st.lists(_patterns(), min_size=1, max_size=3),
)


def _accepts(dfa, trace):
    columns = {name: trace[:, k] for k, name in enumerate(NAMES)}
    return bool(dfa.accepting[dfa.run(dfa.letters(columns, trace.shape[0]))])


def _expected(parts, patterns, trace):
    paper = Specification(**parts).satisfied_by(trace, feature_names=NAMES)
    offsets = np.array([0, trace.shape[0]])
    return paper and all(
        pattern_truth(name, trace, offsets, [[NAMES.index(p) for p in props]])[0, 0] == 1
        for name, props in patterns)


@settings(max_examples=80, deadline=None)
@given(drawn=_SPECS, traces=st.lists(TRACES, min_size=1, max_size=8))
def test_the_dfa_is_the_conjunction_of_the_clauses_and_the_patterns(drawn, traces):
    parts, patterns = drawn
    spec = Specification(**parts, patterns=patterns)
    dfa = specification_dfa(spec)
    for trace in traces:
        assert _accepts(dfa, trace) is _expected(parts, spec.patterns, trace)


def test_pattern_propositions_extend_the_letters():
    spec = Specification(globals=["s"], eventuals=["a"],
                         patterns=[("Response", ("b", "c")), ("Absence", ("s",))])
    dfa = specification_dfa(spec)
    assert dfa.globals == ("s",) and dfa.atoms == ("a", "b", "c", "s")
    assert dfa.delta.shape[1] == 1 << 5
    alone = specification_dfa(Specification(patterns=[("Response", ("b", "c"))]))
    assert alone.n_states == 3 and alone.atoms == ("b", "c")  # the template's own DFA
    # G(s) and Absence(s): no trace satisfies both (s is two letter bits, the global's and
    # the pattern's; the letters where they differ never occur)
    never = specification_dfa(Specification(globals=["s"], patterns=[("Absence", ("s",))]))
    for column in ([0], [1], [1, 1], [0, 0, 0], [1, 0, 1]):
        column = np.array(column, dtype=bool)
        assert not never.accepting[never.run(never.letters({"s": column}, len(column)))]


def test_a_pattern_never_violated_for_good_joins_the_product():
    spec = Specification(globals=["s"], patterns=[("Existence", ("a",))])
    dfa = specification_dfa(spec)
    trace = np.array([[1, 0], [1, 1], [0, 1]], dtype=np.uint8)
    letters = dfa.letters({"s": trace[:, 0], "a": trace[:, 1]}, 3)
    assert not dfa.accepting[dfa.run(letters)]  # s fails at the last step
    assert dfa.accepting[dfa.run(letters[:2])]


def test_too_many_letter_bits_name_the_pattern_propositions():
    spec = Specification(patterns=[("Existence", (f"p{k}",)) for k in range(21)])
    with pytest.raises(ValueError, match="propositions of pattern clauses"):
        specification_dfa(spec)
