"""Clause semantics against a brute-force evaluator and the flloat LTLf library."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.model.clauses import clause_truth


def brute_force(trace, g_idx, s_idx, c_idx):
    """Direct reading of the finite-trace semantics, one clause at a time."""
    T = trace.shape[0]
    out = []
    for g in g_idx:
        out.append(all(trace[t, g] for t in range(T)))
    n = len(s_idx)
    for w in range(n):
        active = c_idx[w] < 0 or trace[0, c_idx[w]]
        out.append((not active) or any(trace[t, s_idx[w]] for t in range(T)))
    for a in range(n):
        active = c_idx[a] < 0 or trace[0, c_idx[a]]
        for b in range(n):
            if a == b or not active:
                out.append(True)
                continue
            holds = False
            for t in range(T):  # !b U a
                if trace[t, s_idx[a]]:
                    holds = True
                    break
                if trace[t, s_idx[b]]:
                    break
            out.append(holds)
    return np.array(out, dtype=np.uint8)


traces_strategy = st.lists(
    arrays(np.bool_, st.tuples(st.integers(1, 6), st.just(4))), min_size=1, max_size=5
)


@settings(max_examples=150, deadline=None)
@given(traces_strategy, st.lists(st.integers(-1, 3), min_size=3, max_size=3))
def test_clause_truth_matches_brute_force(traces, conds):
    roles = resolve_roles([0, 3], [0, 1, 2], {w: c for w, c in enumerate(conds)
                                                    if c >= 0 and c != w}, 4)
    truth = clause_truth(check_traces(traces), roles)
    for i, tr in enumerate(traces):
        expected = brute_force(tr, roles.global_idx, roles.subtask_idx, roles.condition_idx)
        assert np.array_equal(truth[i], expected)


def test_edge_cases_length_one_simultaneous_vacuous():
    roles = resolve_roles([0], [1, 2], {2: 3}, 4)
    n_g, n = 1, 2
    order = lambda a, b: n_g + n + a * n + b  # noqa: E731
    # length one, a and b at the same step: !b U a holds both ways
    t = clause_truth(check_traces([np.array([[1, 1, 1, 1]])]), roles)[0]
    assert t[0] == 1 and t[order(0, 1)] == 1 and t[order(1, 0)] == 1
    # condition of subtask b (prop 3) false at t=0: F(b) and (b precedes a) are vacuous
    t = clause_truth(check_traces([np.array([[0, 0, 0, 0], [0, 1, 0, 1]])]), roles)[0]
    assert t[0] == 0 and t[n_g + 1] == 1 and t[order(1, 0)] == 1 and t[order(0, 1)] == 1
    # strong until: condition holds but the predecessor never happens
    t = clause_truth(check_traces([np.array([[1, 0, 0, 1]])]), roles)[0]
    assert t[order(1, 0)] == 0 and t[n_g + 1] == 0


flloat = __import__("pytest").importorskip("flloat.parser.ltlf")


def _flloat_holds(formula, trace, names):
    parser = flloat.LTLfParser()
    steps = [{names[p]: bool(row[p]) for p in range(len(names))} for row in trace]
    return parser(formula).truth(steps, 0)


@settings(max_examples=60, deadline=None)
@given(arrays(np.bool_, st.tuples(st.integers(1, 5), st.just(4))))
def test_clause_truth_matches_flloat(trace):
    names = ["g", "a", "b", "c"]
    roles = resolve_roles([0], [1, 2], {1: 3}, 4)
    t = clause_truth(check_traces([trace]), roles)[0]
    n_g, n = 1, 2
    assert t[0] == _flloat_holds("G(g)", trace, names)
    assert t[n_g + 0] == _flloat_holds("c -> F(a)", trace, names)
    assert t[n_g + 1] == _flloat_holds("F(b)", trace, names)
    assert t[n_g + n + 0 * n + 1] == _flloat_holds("c -> (!b U a)", trace, names)
    assert t[n_g + n + 1 * n + 0] == _flloat_holds("!a U b", trace, names)
