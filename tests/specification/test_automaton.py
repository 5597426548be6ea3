"""Export of specifications: LTLf text and flloat automata that agree with satisfied_by."""

import sys

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from bsi_sklearn import Specification
from bsi_sklearn.specification.ltlf_export import to_ltlf

NAMES = ["safe", "a", "b", "c_ok"]
SPECS = {
    "full": Specification(globals=["safe"], eventuals=["a", "b"], orders=[("a", "b")],
                          conditions={"b": "c_ok"}),
    "conditioned_order": Specification(orders=[("b", "a")], conditions={"b": "c_ok"}),
    "chain": Specification(eventuals=["a"], orders=[("a", "b"), ("b", "c_ok")]),
    "empty": Specification(),
}
TRACES = arrays(np.uint8, st.tuples(st.integers(1, 5), st.just(4)), elements=st.integers(0, 1))


@pytest.fixture(scope="module")
def automata():
    return {name: spec.to_automaton() for name, spec in SPECS.items()}


@pytest.mark.parametrize("name", SPECS)
@settings(max_examples=40, deadline=None)
@given(data=TRACES)
def test_automaton_accepts_exactly_the_satisfying_traces(automata, name, data):
    spec, dfa = SPECS[name], automata[name]
    frame = pd.DataFrame(data.astype(bool), columns=NAMES)
    expected = spec.satisfied_by(frame)
    assert dfa.accepts(frame) is expected
    assert dfa.accepts(data, feature_names=NAMES) is expected


_SMALL_SPECS = st.builds(
    lambda g, e, o, c: Specification(globals=g, eventuals=e, orders=o,
                                     conditions={1: 3} if c else None),
    st.lists(st.sampled_from([0, 3]), max_size=1, unique=True),
    st.lists(st.sampled_from([1, 2]), max_size=2, unique=True),
    st.sampled_from([[], [(1, 2)], [(2, 1)]]),
    st.booleans(),
)


@settings(max_examples=60, deadline=None)
@given(spec=_SMALL_SPECS, traces=st.lists(TRACES, min_size=1, max_size=6))
def test_random_specifications_agree_with_satisfied_by(spec, traces):
    dfa = spec.to_automaton()
    for trace in traces:  # integer identifiers are column indices
        assert dfa.accepts(trace) is spec.satisfied_by(trace)


def _flloat_accepts(automaton, trace):
    """flloat's reading of the automaton's formula (its own DFA construction)."""
    from flloat.parser.ltlf import LTLfParser

    formula = LTLfParser()(automaton.formula)
    word = [{f"p{k}": bool(row[int(i)]) for k, i in enumerate(automaton.propositions)}
            for row in trace]
    return formula.truth(word, 0)


@settings(max_examples=30, deadline=None)
@given(spec=_SMALL_SPECS, traces=st.lists(TRACES, min_size=1, max_size=4))
def test_the_project_dfa_agrees_with_flloat(spec, traces):
    pytest.importorskip("flloat")
    dfa = spec.to_automaton()
    for trace in traces:
        assert dfa.accepts(trace) is _flloat_accepts(dfa, trace)


def test_the_project_dfa_is_the_minimal_one_flloat_builds():
    pytest.importorskip("flloat")
    from flloat.parser.ltlf import LTLfParser

    for spec in [SPECS["full"], SPECS["chain"], Specification(eventuals=["a", "b"]),
                 Specification(globals=["safe"], orders=[("a", "b")],
                               conditions={"a": "c_ok"})]:
        ours = spec.to_automaton()
        theirs = LTLfParser()(ours.formula).to_automaton().minimize()
        # flloat's minimal DFA has no sink for the empty word's start; compare up to that.
        assert abs(ours.dfa.n_states - len(theirs.states)) <= 1, (spec, ours.dfa.n_states,
                                                                  len(theirs.states))


def _chain_spec(n_globals, n_subtasks):
    subtasks = [f"w{k}" for k in range(n_subtasks)]
    return Specification(globals=[f"g{k}" for k in range(n_globals)], eventuals=subtasks,
                         orders=[(subtasks[i], subtasks[i + 1]) for i in range(n_subtasks - 1)],
                         conditions={"w0": "start"})


def test_a_20_clause_automaton_is_fast():
    import time

    spec = _chain_spec(5, 6)  # 5 G + 6 F + 15 ordered pairs (closed) = 26 clauses
    assert spec.n_conjuncts >= 20
    start = time.perf_counter()
    dfa = spec.to_automaton()
    took = time.perf_counter() - start
    assert took < 0.5, took  # about 10 ms on an idle machine; shared cores are slower
    rng = np.random.default_rng(0)
    names = sorted(dfa.propositions)
    for _ in range(200):
        trace = rng.random((int(rng.integers(1, 12)), len(names))) < 0.8
        assert dfa.accepts(trace, feature_names=names) is spec.satisfied_by(
            trace, feature_names=names)


def test_to_ltlf_dialects():
    spec = SPECS["full"]
    text = "G(safe) & F(a) & (c_ok -> F(b)) & (!(b) U (a))"
    assert spec.to_ltlf() == text
    assert spec.to_ltlf(dialect="ltlf2dfa") == text
    assert Specification().to_ltlf(dialect="ltlf2dfa") == "true"
    odd = Specification(globals=["Threat-1", 0, "G"], eventuals=["x"])
    assert odd.to_ltlf() == 'G("0") & G("G") & G("Threat-1") & F(x)'
    with pytest.raises(ValueError, match="proposition 'G' is not an LTLf2DFA / flloat atom"):
        odd.to_ltlf(dialect="ltlf2dfa")
    renamed = odd.to_ltlf(dialect="ltlf2dfa", atoms={"Threat-1": "threat_1", 0: "p0",
                                                     "G": "g"})
    assert renamed == "G(p0) & G(g) & G(threat_1) & F(x)"
    with pytest.raises(ValueError, match="to_ltlf: dialect must be"):
        spec.to_ltlf(dialect="nusmv")


def test_ltlf2dfa_text_is_what_flloat_parses():
    from flloat.parser.ltlf import LTLfParser

    text = SPECS["full"].to_ltlf(dialect="ltlf2dfa")
    word = [{"safe": True, "a": True, "b": False, "c_ok": False}]
    assert LTLfParser()(text).truth(word, 0) is SPECS["full"].satisfied_by(
        pd.DataFrame([[1, 1, 0, 0]], columns=NAMES))


def test_any_identifier_works_in_the_automaton():
    spec = Specification(globals=["Threat-1"], eventuals=[0])
    dfa = spec.to_automaton()
    frame = pd.DataFrame([[1, 0], [1, 1]], columns=["Threat-1", 0])
    assert dfa.accepts(frame) and "p0" in dfa.formula
    assert "n_states" in repr(dfa)


def test_accepts_errors():
    dfa = SPECS["chain"].to_automaton()
    with pytest.raises(ValueError, match="proposition 'a' is not a column of the trace"):
        dfa.accepts(np.ones((2, 4)))
    with pytest.raises(ValueError, match="non-empty 2-D"):
        dfa.accepts(pd.DataFrame(np.zeros((0, 4)), columns=NAMES))
    with pytest.raises(ValueError, match="other than 0/1"):
        dfa.accepts(np.full((1, 4), 2), feature_names=NAMES)


def test_the_automaton_needs_no_flloat(monkeypatch):
    monkeypatch.setitem(sys.modules, "flloat", None)
    monkeypatch.setitem(sys.modules, "flloat.parser.ltlf", None)
    dfa = Specification(globals=["a"], eventuals=["b"]).to_automaton()
    assert dfa.accepts(pd.DataFrame([[1, 0], [1, 1]], columns=["a", "b"]))
    assert to_ltlf(Specification(globals=["a"])) == "G(a)"


def test_dot_export():
    dfa = SPECS["full"].to_automaton()
    dot = dfa.to_dot()
    assert dot.startswith('digraph "G(safe) & F(a) & (c_ok -> F(b)) & (!b U a)" {')
    assert dot.count("doublecircle") == int(dfa.dfa.accepting.sum())
    assert dot.count(" -> ") >= dfa.dfa.n_states + 1 and "label=" in dot
    empty = Specification().to_automaton()
    assert empty.dfa.n_states == 1 and empty.accepts(np.ones((1, 1)))
    assert 'label="true"' in empty.to_dot()
