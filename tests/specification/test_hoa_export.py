"""HOA v1 export of the project's automata, read back by a small reader of the format.

The reader follows the grammar of the Hanoi Omega-Automata format, version 1 (header items,
``--BODY--``, ``State:`` lines, explicit labels as Boolean expressions over AP numbers, C-like
strings, nested comments). The tests check that the text parses, that the automaton it
describes is deterministic and complete as its ``properties:`` claim, and that running it
over finite traces (accepting when the run ends in acceptance set 0) agrees with
``Specification.satisfied_by``.
"""

import itertools
import re

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from bsi_sklearn import Specification

# ------------------------------------------------------------------ a small HOA v1 reader
_TOKEN = re.compile(r"""
    (?P<space>\s+)
  | (?P<string>"(?:\\.|[^\\"])*")
  | (?P<marker>--BODY--|--END--|--ABORT--)
  | (?P<header>[A-Za-z_][0-9A-Za-z_-]*:)
  | (?P<int>0|[1-9][0-9]*)
  | (?P<ident>[A-Za-z_][0-9A-Za-z_-]*)
  | (?P<aname>@[0-9A-Za-z_-]+)
  | (?P<punct>[\[\]{}()!&|])
""", re.VERBOSE)


_STRING = re.compile(r'"(?:\\.|[^\\"])*"')


def _strip_comments(text):
    """``text`` without its ``/* ... */`` comments (nested), strings kept whole."""
    out, depth, k = [], 0, 0
    while k < len(text):
        if depth == 0 and text[k] == '"':
            m = _STRING.match(text, k)
            assert m, "unclosed string"
            out.append(m.group())
            k = m.end()
        elif text.startswith("/*", k):
            depth, k = depth + 1, k + 2
        elif depth and text.startswith("*/", k):
            depth, k = depth - 1, k + 2
        else:
            if depth == 0:
                out.append(text[k])
            k += 1
    assert depth == 0, "unclosed comment"
    return "".join(out)


def _tokens(text):
    text, pos, out = _strip_comments(text), 0, []
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        assert m, f"bad token at {text[pos:pos + 20]!r}"
        pos = m.end()
        if m.lastgroup != "space":
            out.append((m.lastgroup, m.group()))
    return out


def _unquote(token):
    return re.sub(r"\\(.)", r"\1", token[1:-1])


class _Labels:
    """label-expr: ``|`` below ``&`` below ``!``; atoms t, f, AP numbers, parentheses."""

    def __init__(self, tokens, k):
        self.tokens, self.k = tokens, k

    def peek(self):
        return self.tokens[self.k][1]

    def take(self, expected=None):
        kind, value = self.tokens[self.k]
        assert expected is None or value == expected, (value, expected)
        self.k += 1
        return kind, value

    def parse(self):
        terms = [self.conj()]
        while self.peek() == "|":
            self.take()
            terms.append(self.conj())
        return ("or", terms)

    def conj(self):
        factors = [self.neg()]
        while self.peek() == "&":
            self.take()
            factors.append(self.neg())
        return ("and", factors)

    def neg(self):
        if self.peek() == "!":
            self.take()
            return ("not", self.neg())
        kind, value = self.take()
        if value == "(":
            inner = self.parse()
            self.take(")")
            return inner
        if kind == "ident" and value in ("t", "f"):
            return ("const", value == "t")
        assert kind == "int", (kind, value)
        return ("ap", int(value))


def _holds(expr, valuation):
    op, arg = expr
    if op == "or":
        return any(_holds(e, valuation) for e in arg)
    if op == "and":
        return all(_holds(e, valuation) for e in arg)
    if op == "not":
        return not _holds(arg, valuation)
    if op == "const":
        return arg
    return valuation[arg]


def read_hoa(text):
    """Parse one HOA v1 automaton with explicit labels: a dict of what it says."""
    tokens = _tokens(text) + [("eof", "")]
    assert tokens[0] == ("header", "HOA:") and tokens[1] == ("ident", "v1"), tokens[:2]
    k, header = 2, {}
    while tokens[k][1] != "--BODY--":
        kind, name = tokens[k]
        assert kind == "header", f"expected a header item, got {name!r}"
        k += 1
        values = []
        while tokens[k][0] not in ("header", "marker"):
            values.append(tokens[k])
            k += 1
        if name not in ("Start:", "Alias:", "properties:"):
            assert name not in header, f"{name} given twice"
        header.setdefault(name, []).append(values)
    assert "Acceptance:" in header
    n_states = int(header["States:"][0][0][1])
    starts = [int(v[0][1]) for v in header.get("Start:", [])]
    ap_values = header["AP:"][0]
    assert ap_values[0][0] == "int" and all(kind == "string" for kind, _ in ap_values[1:])
    aps = [_unquote(v) for _, v in ap_values[1:]]
    assert len(aps) == int(ap_values[0][1]) and len(set(aps)) == len(aps)
    k += 1
    states = {}
    while tokens[k][1] != "--END--":
        assert tokens[k][1] == "State:", tokens[k]
        k += 1
        assert tokens[k][1] != "[", "state labels are not used"
        state = int(tokens[k][1])
        k += 1
        if tokens[k][0] == "string":
            k += 1
        acc = set()
        if tokens[k][1] == "{":
            k += 1
            while tokens[k][1] != "}":
                acc.add(int(tokens[k][1]))
                k += 1
            k += 1
        edges = []
        while tokens[k][1] == "[":
            labels = _Labels(tokens, k + 1)
            expr = labels.parse()
            labels.take("]")
            k = labels.k
            assert tokens[k][0] == "int", tokens[k]
            edges.append((expr, int(tokens[k][1])))
            k += 1
            assert tokens[k][1] != "{", "transition-based acceptance is not used"
        assert state not in states
        states[state] = (acc, edges)
    assert sorted(states) == list(range(n_states))
    properties = {v for values in header.get("properties:", []) for _, v in values}
    acceptance = " ".join(v for _, v in header["Acceptance:"][0])
    return {"name": _unquote(header["name:"][0][0][1]), "aps": aps, "starts": starts,
            "states": states, "properties": properties, "acceptance": acceptance,
            "header": header}


def run_hoa(aut, valuations):
    """The run over a finite word (one AP valuation a step): accepted when it ends in set 0."""
    (state,) = aut["starts"]
    for valuation in valuations:
        targets = [t for expr, t in aut["states"][state][1] if _holds(expr, valuation)]
        assert len(targets) == 1
        state = targets[0]
    return 0 in aut["states"][state][0]


# ------------------------------------------------------------------ the tests
NAMES = ["safe", 'say "hi"', "back\\slash", "c ok"]  # names HOA must quote and escape
TRACES = arrays(np.uint8, st.tuples(st.integers(1, 5), st.just(4)), elements=st.integers(0, 1))
SPECS = st.builds(
    lambda g, e, o, c: Specification(globals=[NAMES[i] for i in g],
                                     eventuals=[NAMES[i] for i in e],
                                     orders=[(NAMES[a], NAMES[b]) for a, b in o],
                                     conditions={NAMES[1]: NAMES[3]} if c else None),
    st.lists(st.sampled_from([0, 3]), max_size=2, unique=True),
    st.lists(st.sampled_from([1, 2]), max_size=2, unique=True),
    st.sampled_from([[], [(1, 2)], [(2, 1)]]),
    st.booleans(),
)


def _valuations(aut, frame):
    return [[bool(row[name]) for name in aut["aps"]] for _, row in frame.iterrows()]


@settings(max_examples=60, deadline=None)
@given(spec=SPECS, traces=st.lists(TRACES, min_size=1, max_size=5))
def test_hoa_parses_and_accepts_exactly_the_satisfying_traces(spec, traces):
    automaton = spec.to_automaton()
    aut = read_hoa(automaton.to_hoa())
    assert aut["name"] == spec.to_ltl()
    assert aut["starts"] == [0] and aut["acceptance"] == "1 Inf ( 0 )"
    assert sorted(aut["aps"]) == sorted(map(str, automaton.propositions))
    assert {"deterministic", "complete", "explicit-labels", "state-acc"} <= aut["properties"]
    # deterministic and complete: exactly one edge of every state holds on every letter
    for _, edges in aut["states"].values():
        for valuation in itertools.product([False, True], repeat=len(aut["aps"])):
            assert sum(_holds(expr, valuation) for expr, _ in edges) == 1
    for data in traces:
        frame = pd.DataFrame(data.astype(bool), columns=NAMES)
        assert run_hoa(aut, _valuations(aut, frame)) is spec.satisfied_by(frame)


def test_hoa_of_the_empty_specification_and_of_a_proposition_in_two_roles():
    aut = read_hoa(Specification().to_automaton().to_hoa())
    assert aut["aps"] == [] and len(aut["states"]) == 1
    assert run_hoa(aut, [[]]) is True
    spec = Specification(globals=["a"], eventuals=["a", "b"], orders=[("a", "b")])
    aut = read_hoa(spec.to_automaton().to_hoa())
    assert aut["aps"] == ["a", "b"]
    for rows in ([[1, 0], [1, 1]], [[1, 1]], [[0, 1], [1, 1]], [[1, 0], [0, 1]]):
        frame = pd.DataFrame(np.array(rows, bool), columns=["a", "b"])
        assert run_hoa(aut, _valuations(aut, frame)) is spec.satisfied_by(frame)


def test_reader_rejects_what_the_format_forbids():
    good = Specification(eventuals=["a"]).to_automaton().to_hoa()
    commented = good.replace("--BODY--", '/* a /* nested */ comment */ --BODY--')
    assert read_hoa(commented)["aps"] == ["a"]
    assert read_hoa(good.replace('"a"', '"a /* not a comment */"'))["aps"] == [
        "a /* not a comment */"]
    with pytest.raises(AssertionError):
        read_hoa(good.replace("States: 2", "States: 2 States: 2"))
    with pytest.raises(AssertionError):
        read_hoa(good.replace("HOA: v1", "HOA: v2"))
    with pytest.raises(AssertionError):
        read_hoa(good.replace('AP: 1 "a"', 'AP: 2 "a"'))
