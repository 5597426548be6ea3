"""PosteriorMonitor with pattern clauses: closed, the vote from the clauses' truth."""

import itertools

import numpy as np
import pandas as pd
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from bsi_sklearn import Posterior
from bsi_sklearn.data.roles import Roles, resolve_roles
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.model.clauses import clause_index_eventual, clause_index_order
from bsi_sklearn.model.patterns import pattern_truth
from bsi_sklearn.monitor.posterior_monitor import PosteriorMonitor, monitor_traces
from bsi_sklearn.specification.templates import TEMPLATES, get_template

NAMES = ["safe", "a", "b", "c_ok"]
USER = ["G(x -> F(y))", "x U (y & X(z))", "WX(x) | G(!x)"]


def _instances():
    """Every template once or twice, over varied columns."""
    out = []
    orders = list(itertools.permutations(range(len(NAMES)), 3))
    for k, name in enumerate([*TEMPLATES, *USER]):
        n_slots = len(get_template(name).slots)
        out.append((name, orders[k % len(orders)][:n_slots]))
        if k % 3 == 0:
            out.append((name, orders[(5 * k + 7) % len(orders)][:n_slots]))
    return tuple(out)


def _posterior(conditions, n_specs=60, seed=0, p_pattern=0.1):
    """A posterior over G, pattern, F and U clauses, laid out as a pattern-aware fit lays it
    (pattern candidate ``k`` is global slot ``n_globals + k``)."""
    rng = np.random.default_rng(seed)
    plain = resolve_roles(["safe", "c_ok"], ["a", "b", "c_ok"], conditions, 4, NAMES)
    patterns = _instances()
    roles = Roles(plain.global_idx, plain.subtask_idx, plain.condition_idx, plain.names,
                  patterns)
    n, n_g = roles.n_subtasks, roles.n_globals
    structures = np.full((n_specs, n), -1)
    for h in range(n_specs):
        order = rng.permutation(n)
        for k in range(1, n):
            if rng.random() < 0.5:
                structures[h, order[k]] = order[rng.integers(k)]
    tau = np.concatenate([rng.random((n_specs, n_g)) < 0.3,
                          rng.random((n_specs, len(patterns))) < p_pattern], axis=1)
    probs = np.sort(rng.dirichlet(np.ones(n_specs)))[::-1]
    return Posterior(structures, tau, rng.random((n_specs, n)) < 0.4, probs, roles)


POSTERIORS = {"plain": _posterior(None),
              "conditions": _posterior({"a": "c_ok", "b": "safe"}, seed=1),
              "only patterns": _posterior(None, seed=2, p_pattern=0.05)}


def _truth_bits(roles, trace):
    """Every clause slot's truth on the whole trace (LTLf for the patterns)."""
    n_g, n = roles.n_globals + roles.n_patterns, roles.n_subtasks
    bits = {}
    for j, col in enumerate(roles.global_idx):
        bits[j] = trace[:, col].all()
    offsets = np.array([0, len(trace)])
    for k, (name, cols) in enumerate(roles.patterns):
        bits[roles.n_globals + k] = pattern_truth(name, trace, offsets, [cols])[0, 0] == 1
    s, c = roles.subtask_idx, roles.condition_idx
    for a in range(n):
        free = c[a] >= 0 and not trace[0, c[a]]
        has_a = trace[:, s[a]].astype(bool)
        bits[clause_index_eventual(a, n_g)] = free or has_a.any()
        for b in range(n):
            first = int(np.argmax(has_a)) if has_a.any() else None
            ok = free or (first is not None and not trace[:first, s[b]].any())
            bits[clause_index_order(a, b, n_g, n)] = a == b or ok
    return bits


def _vote(post, trace):
    bits = _truth_bits(post.roles, trace)
    words = np.unpackbits(post._masks.view(np.uint8), axis=1, bitorder="little")
    held = np.zeros(words.shape[1], dtype=np.uint8)
    held[[j for j, v in bits.items() if v]] = 1
    ok = ~(words & ~held).astype(bool).any(axis=1)
    return float(post.probabilities[ok].sum())


TRACES = arrays(np.uint8, st.tuples(st.integers(1, 6), st.just(4)), elements=st.integers(0, 1))


@pytest.mark.parametrize("name", POSTERIORS)
@settings(max_examples=40, deadline=None)
@given(trace=TRACES)
def test_closed_verdict_is_the_vote_of_the_truth(name, trace):
    post = POSTERIORS[name]
    mon = PosteriorMonitor(post)
    keys = {k for _, k in mon._keys.items()}
    rows, decided = [], {}
    for t in range(len(trace)):
        v = mon.update(trace[t])
        rows.append([v.p_satisfied, v.p_violated, v.p_open])
        for e in v.events:
            assert e.clause in keys
            assert e.clause not in decided  # a decided clause never changes
            decided[e.clause] = e.state
        # a pattern decided at step t is decided for the prefix and whatever follows
        for tname, cols in post.roles.patterns:
            key = ("P", tname, tuple(NAMES[c] for c in cols))
            if key in decided:
                truth = pattern_truth(tname, trace[:t + 1], [0, t + 1], [cols])[0, 0]
                assert truth == (decided[key] == "satisfied")
    final = mon.finish()
    for e in final.events:
        assert e.clause not in decided
    assert final.p_open == 0.0
    np.testing.assert_allclose(final.p_satisfied, _vote(post, trace), atol=1e-12)
    np.testing.assert_allclose(final.p_violated, 1.0 - _vote(post, trace), atol=1e-9)
    # the batch kernel gives the same rows as the steps
    batch = monitor_traces(post, check_traces([trace]))[0]
    np.testing.assert_allclose(batch, rows, atol=1e-12)


def test_every_template_decides_as_its_truth_on_every_short_trace():
    post = POSTERIORS["plain"]
    patterns = post.roles.patterns
    first = post.roles.n_globals
    for length in range(1, 4):
        for flat in itertools.product([0, 1], repeat=4 * length):
            trace = np.array(flat, dtype=np.uint8).reshape(length, 4)
            mon = PosteriorMonitor(post)
            for row in trace:
                mon.update(row)
            before = mon._state.copy()
            mon.finish()
            for k, (name, cols) in enumerate(patterns):
                want = pattern_truth(name, trace, [0, length], [cols])[0, 0] == 1
                assert mon._state[first + k] == (1 if want else 2), (name, cols, trace)
                if before[first + k] != 0:
                    assert before[first + k] == mon._state[first + k]


def test_pattern_events_name_the_template_and_propositions():
    post = POSTERIORS["only patterns"]
    mon = PosteriorMonitor(post)
    mon.update([0, 1, 0, 0])
    mon.update([0, 0, 1, 0])
    final = mon.finish()
    expected = {("P", name, tuple(NAMES[c] for c in cols)) for name, cols in post.roles.patterns}
    keys = [e.clause for e in final.events if e.clause[0] == "P"]
    assert keys and set(keys) <= expected
    used = [k for k in mon.clause_states().index if k[0] == "P"]
    assert used and set(mon.clause_states()[used]) <= {"satisfied", "violated"}
    assert all(0.0 < e.inclusion_probability <= 1.0 for e in final.events)


def test_a_posterior_laid_out_without_the_patterns_is_refused():
    post = _posterior(None)
    plain = Posterior(post._structures, post._tau[:, :2], post._w1, post.probabilities,
                      resolve_roles(["safe", "c_ok"], ["a", "b", "c_ok"], None, 4, NAMES))
    plain.roles = post.roles
    with pytest.raises(ValueError, match="pattern candidates"):
        PosteriorMonitor(plain)


def test_the_monitors_keys_are_the_posteriors():
    # with pattern clauses and without, the clause keys the events name are the posterior's
    for post in POSTERIORS.values():
        assert list(PosteriorMonitor(post)._keys.values()) == post.clause_keys()
        assert any(k[0] == "P" for k in post.clause_keys())
    roles = resolve_roles(["safe", "c_ok"], ["a", "b", "c_ok"], None, 4, NAMES)
    post = Posterior(np.full((1, 3), -1), np.ones((1, 2), bool), np.ones((1, 3), bool),
                     [1.0], roles)
    assert list(PosteriorMonitor(post)._keys.values()) == post.clause_keys()
    frame = pd.DataFrame([[1, 1, 1, 1]], columns=NAMES)
    mon = PosteriorMonitor(post)
    assert mon.update(frame.iloc[0]).p_open == 1.0  # G(...) open until the close
    assert mon.finish().p_satisfied == 1.0
