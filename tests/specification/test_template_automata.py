"""The templates' DFAs against the reference truth (pattern_truth) on every short trace."""

import itertools

import numpy as np
import pytest

from bsi_sklearn.model.patterns import pattern_truth
from bsi_sklearn.specification.template_automata import (
    OPEN,
    SATISFIED,
    VIOLATED,
    template_dfa,
)
from bsi_sklearn.specification.templates import TEMPLATES, get_template

USER = ["G(x -> F(y))", "x U (y & X(z))", "WX(x) | G(!x)", "x R (y | WX(false))",
        "X(X(x)) <-> F(y)", "!(x U y) & true"]
TEMPLATE_NAMES = [*TEMPLATES, *USER]
MAX_LEN = 5
# The minimal sizes (the start state rejects: a trace is never empty); a change is a question.
SIZES = {"Existence": 2, "Absence": 3, "Response": 3, "Precedence": 4, "Succession": 5,
         "Choice": 2, "Universality": 3, "G(x -> F(y))": 3, "x U (y & X(z))": 5}


def _words(k, length):
    """Every word of ``length`` letters over ``k`` slots, shape (2 ** (k * length), length)."""
    return np.array(list(itertools.product(range(1 << k), repeat=length)), dtype=np.int64)


def _reference(template, words):
    """pattern_truth of the template on every word, slot i read from column i."""
    k = len(get_template(template).slots)
    n, length = words.shape
    data = ((words.reshape(-1, 1) >> np.arange(k)) & 1).astype(np.uint8)
    offsets = np.arange(n + 1, dtype=np.int64) * length
    return pattern_truth(template, data, offsets, [list(range(k))])[:, 0].astype(bool)


def _runs(dfa, words):
    state = np.full(words.shape[0], dfa.start)
    for t in range(words.shape[1]):
        state = dfa.delta[state, words[:, t]]
    return state


@pytest.fixture(scope="module")
def truth():
    """(template, word tuple) -> reference truth, every word of 1..MAX_LEN letters."""
    out = {}
    for name in TEMPLATE_NAMES:
        k = len(get_template(name).slots)
        for length in range(1, MAX_LEN + 1):
            words = _words(k, length)
            for w, v in zip(map(tuple, words.tolist()), _reference(name, words)):
                out[name, w] = bool(v)
    return out


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_dfa_verdict_equals_pattern_truth_on_every_short_trace(name, truth):
    dfa = template_dfa(name)
    k = len(get_template(name).slots)
    assert dfa.delta.shape == (dfa.n_states, 1 << k)
    assert not dfa.accepting[dfa.start]  # the empty trace is not a demonstration
    for length in range(1, MAX_LEN + 1):
        words = _words(k, length)
        verdict = dfa.accepting[_runs(dfa, words)]
        expected = np.array([truth[name, w] for w in map(tuple, words.tolist())])
        bad = np.flatnonzero(verdict != expected)
        assert bad.size == 0, f"{name}: the DFA says {verdict[bad[0]]} on {words[bad[0]]}"


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_decided_states_never_change_their_verdict(name, truth):
    dfa = template_dfa(name)
    k = len(get_template(name).slots)
    for length in range(1, 3):
        for prefix in map(tuple, _words(k, length).tolist()):
            code = dfa.permanence[dfa.run(prefix)]
            if code == OPEN:
                continue
            for more in range(0, MAX_LEN - length + 1):
                for ext in map(tuple, _words(k, more).tolist()) if more else [()]:
                    assert truth[name, prefix + ext] is bool(code == SATISFIED)


@pytest.mark.parametrize("name", TEMPLATE_NAMES)
def test_permanence_is_exact_and_the_dfa_is_minimal(name):
    dfa = template_dfa(name)
    n = dfa.n_states
    # Words of length 0..n reach every reachable state and tell any two states apart.
    reach = [{s} for s in range(n)]
    for _ in range(n):
        reach = [r | {int(t) for q in r for t in dfa.delta[q]} for r in reach]
    for s in range(n):
        acc = {bool(dfa.accepting[q]) for q in reach[s]}
        want = SATISFIED if acc == {True} else VIOLATED if acc == {False} else OPEN
        assert dfa.permanence[s] == want
    assert reach[dfa.start] == set(range(n))  # every state reachable
    # Moore: no two states have the same acceptance on every word of length < n.
    words = [()] + [tuple(w) for m in range(1, n) for w in _words(dfa.delta.shape[1]
                                                                   .bit_length() - 1, m)]
    rows = {tuple(bool(dfa.accepting[dfa.run(w, s)]) for w in words) for s in range(n)}
    assert len(rows) == n
    if name in SIZES:
        assert n == SIZES[name]
    assert (dfa.permanence == SATISFIED).sum() <= 1 and (dfa.permanence == VIOLATED).sum() <= 1


def test_the_dfa_is_cached_and_read_only():
    assert template_dfa("Response") is template_dfa(TEMPLATES["Response"])
    with pytest.raises(ValueError):
        template_dfa("Response").delta[0, 0] = 1
    with pytest.raises(ValueError, match="unknown template"):
        template_dfa("Responze")
