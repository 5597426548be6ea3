"""Roles read from the demonstrations: BSIClassifier(roles="infer") and roles_ (issue 20)."""

import pickle
import warnings

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn import BSIClassifier
from bsi_sklearn.data.inferred_roles import infer_condition, infer_roles, proposition_statistics
from bsi_sklearn.data.traces import check_traces


def _roles(X, y, **given):
    return infer_roles(check_traces(X), np.asarray(y), **given)


def test_statistics_match_a_step_by_step_reading():
    rng = np.random.default_rng(0)
    X = [rng.integers(0, 2, size=(int(rng.integers(1, 6)), 4)) for _ in range(30)]
    initial, ever, always = proposition_statistics(check_traces(X))
    for i, x in enumerate(X):
        for p in range(4):
            column = [bool(v) for v in x[:, p]]
            assert initial[i, p] == column[0]
            assert ever[i, p] == any(column)
            assert always[i, p] == all(column)


# ---------------------------------------------------------------- global candidates
def test_a_global_candidate_holds_throughout_some_acceptable_demonstration():
    # 0: throughout both positives; 1: throughout one; 2: never throughout a positive
    # (throughout the negative only); 3: never true.
    X = [np.array([[1, 1, 0, 0], [1, 1, 1, 0]]),
         np.array([[1, 0, 1, 0], [1, 1, 0, 0]]),
         np.array([[0, 0, 1, 0], [1, 0, 1, 0]])]
    assert _roles(X, [1, 1, 0]).global_idx.tolist() == [0, 1]


def test_an_untested_global_candidate_stays_with_or_without_negatives():
    # Column 0 holds throughout every demonstration, acceptable or not: its G clause is
    # untested, and stays a candidate (the prior decides it).
    X = [np.array([[1, 0], [1, 1]]), np.array([[1, 1], [1, 1]]), np.array([[1, 0]])]
    assert 0 in _roles(X, [1, 1, 0]).global_idx
    assert 0 in _roles(X, [1, 1, 1]).global_idx


# ---------------------------------------------------------------- subtasks
def test_a_subtask_is_false_at_the_start_and_true_later_in_some_demonstration():
    # 0: true from the first step everywhere (F p vacuous); 1: rises; 2: constant within each
    # demonstration, different between them (a state, not a completion); 3: never true;
    # 4: rises in the unacceptable demonstration only.
    X = [np.array([[1, 0, 1, 0, 0], [1, 1, 1, 0, 0]]),
         np.array([[1, 0, 0, 0, 0], [1, 1, 0, 0, 0]]),
         np.array([[1, 0, 0, 0, 0], [1, 0, 0, 0, 1]])]
    assert _roles(X, [1, 1, 0]).subtask_idx.tolist() == [1, 4]


def test_length_one_demonstrations_have_no_subtasks():
    X = np.array([[1, 0], [0, 1], [1, 1]])
    roles = _roles(list(X[:, None, :]), [1, 1, 0])
    assert roles.subtask_idx.tolist() == [] and roles.global_idx.tolist() == [0, 1]


# ---------------------------------------------------------------- conditions
def _condition_by_hand(initial, done, subtask):
    """The documented rule, one column at a time in plain Python."""
    best = None
    if all(done):
        return None
    for c in range(len(initial[0])):
        if c == subtask:
            continue
        n11 = sum(1 for row, d in zip(initial, done) if row[c] and d)
        n10 = sum(1 for row, d in zip(initial, done) if row[c] and not d)
        n01 = sum(1 for row, d in zip(initial, done) if not row[c] and d)
        n00 = sum(1 for row, d in zip(initial, done) if not row[c] and not d)
        if n11 > n10 and n00 > n01:
            key = (-(n11 + n00), n10, c)
            best = key if best is None or key < best else best
    return None if best is None else best[2]


def test_the_condition_rule_matches_its_plain_reading_on_random_data():
    rng = np.random.default_rng(1)
    found = 0
    for _ in range(500):
        n, k = int(rng.integers(1, 9)), int(rng.integers(1, 6))
        initial = rng.random((n, k)) < rng.random()
        done = rng.random(n) < 0.6
        subtask = int(rng.integers(k))
        got = infer_condition(initial, done, subtask)
        assert got == _condition_by_hand(initial.tolist(), done.tolist(), subtask)
        found += got is not None
    assert 50 < found < 450  # both outcomes are exercised


def test_condition_branches():
    done = np.array([True, True, False, False, True])
    initial = np.array([[1, 0, 1, 1],
                        [1, 0, 1, 1],
                        [0, 0, 0, 1],
                        [0, 0, 1, 0],
                        [1, 0, 0, 1]], dtype=bool)
    # column 0 separates exactly (agrees on 5); column 3 is eligible and agrees on 4;
    # column 2 fails the majority test where it is false (one skip, one completion)
    assert infer_condition(initial, done, subtask=1) == 0
    # the subtask itself is never its own condition: without column 0, column 3
    assert infer_condition(initial, done, subtask=0) == 3
    # every acceptable demonstration completes the subtask: condition true
    assert infer_condition(initial, np.ones(5, dtype=bool), subtask=1) is None
    # a tie in agreement goes to the fewest violations, then to the first column
    done = np.array([True, True, True, False, False, False])
    a = np.array([1, 1, 1, 1, 0, 0], dtype=bool)  # n11=3 n10=1 n01=0 n00=2: agrees on 5
    b = np.array([1, 1, 0, 0, 0, 0], dtype=bool)  # n11=2 n10=0 n01=1 n00=3: agrees on 5
    none = np.zeros(6, dtype=bool)
    assert infer_condition(np.c_[a, b, none], done, subtask=2) == 1
    assert infer_condition(np.c_[b, a, none], done, subtask=2) == 0
    assert infer_condition(np.c_[b, b, none], done, subtask=2) == 0


def test_a_condition_that_most_demonstrations_contradict_is_not_taken():
    # The skipping demonstration is explained by column 0, but column 0 also fails on two
    # demonstrations that complete the subtask: the majority test refuses it.
    initial = np.array([[1], [0], [0], [0]], dtype=bool)
    done = np.array([True, True, True, False])
    assert infer_condition(np.c_[initial, np.zeros((4, 1), bool)], done, subtask=1) is None


def test_infer_roles_finds_the_condition_from_the_acceptable_demonstrations_only():
    # columns: closed (at the start), opened, done
    X = [np.array([[1, 0, 0], [1, 1, 0], [0, 1, 1]]),    # closed: opens, then done
         np.array([[0, 0, 0], [0, 0, 1]]),               # open already: done
         np.array([[1, 0, 0], [1, 0, 1]]),               # closed, not opened: unacceptable
         np.array([[0, 0, 0], [0, 1, 1]])]               # noise in the negatives is ignored
    roles = _roles(X, [1, 1, 0, 0])
    assert roles.subtask_idx.tolist() == [1, 2]
    assert roles.condition_names() == {1: 0}


# ---------------------------------------------------------------- explicit roles win
X_COND = [np.array([[1, 1, 0, 0], [1, 1, 1, 0], [1, 1, 1, 1]]),
          np.array([[1, 0, 0, 0], [1, 0, 0, 1]]),
          np.array([[1, 1, 0, 0], [1, 1, 0, 1]]),
          np.array([[1, 0, 0, 0], [0, 0, 0, 1]])]
Y_COND = [1, 1, 0, 0]


def test_each_explicit_role_is_used_as_given_and_the_others_are_inferred():
    inferred = _roles(X_COND, Y_COND)
    assert inferred.global_idx.tolist() == [0, 1]
    assert inferred.subtask_idx.tolist() == [2, 3]
    assert inferred.condition_names() == {2: 1}
    r = _roles(X_COND, Y_COND, global_candidates=[3])
    assert r.global_idx.tolist() == [3] and r.subtask_idx.tolist() == [2, 3]
    assert r.condition_names() == {2: 1}
    # explicit subtasks: their conditions are inferred
    r = _roles(X_COND, Y_COND, subtasks=[3, 2])
    assert r.subtask_idx.tolist() == [3, 2] and r.condition_names() == {2: 1}
    # explicit conditions are the whole role: {} means none
    assert _roles(X_COND, Y_COND, conditions={}).condition_names() == {}
    r = _roles(X_COND, Y_COND, conditions={3: 0})
    assert r.condition_names() == {3: 0}
    # a subtask named by the conditions joins the inferred subtasks
    r = _roles(X_COND, Y_COND, conditions={0: 1})
    assert r.subtask_idx.tolist() == [0, 2, 3] and r.condition_names() == {0: 1}
    # everything given: the rule reads nothing
    r = _roles(X_COND, Y_COND, global_candidates=[], subtasks=[1], conditions={})
    assert (r.global_idx.tolist(), r.subtask_idx.tolist()) == ([], [1])


@pytest.mark.parametrize("given, match", [
    (dict(global_candidates=["nope"]), "global_candidates: unknown proposition"),
    (dict(subtasks=[9]), "subtasks: proposition index 9 is out of range"),
    (dict(conditions={"nope": 0}), "conditions: unknown proposition"),
    (dict(conditions=[1, 2]), "conditions must be None or a mapping"),
    (dict(subtasks=[2], conditions={3: 0}), "conditions: 3 is not one of the subtasks"),
])
def test_explicit_roles_are_still_validated(given, match):
    with pytest.raises(ValueError, match=match):
        _roles(X_COND, Y_COND, **given)


# ---------------------------------------------------------------- the estimator
def test_roles_param_is_validated():
    with pytest.raises(ValueError, match="roles"):
        BSIClassifier(roles="some").fit(X_COND, Y_COND)


@pytest.mark.parametrize("roles", ["all", "infer"])
def test_roles_after_fit_by_index_for_arrays_and_by_name_for_frames(roles):
    names = ["safe", "closed", "opened", "done"]
    clf = BSIClassifier(roles=roles, random_state=0).fit(X_COND, Y_COND)
    frames = [pd.DataFrame(x, columns=names).astype(bool) for x in X_COND]
    named = BSIClassifier(roles=roles, random_state=0).fit(frames, Y_COND)
    if roles == "all":
        assert clf.roles_ == {"global_candidates": [0, 1, 2, 3], "subtasks": [0, 1, 2, 3],
                              "conditions": {}}
    else:
        assert clf.roles_ == {"global_candidates": [0, 1], "subtasks": [2, 3],
                              "conditions": {2: 1}}
    assert named.roles_ == {key: ([names[i] for i in v] if isinstance(v, list)
                                  else {names[k]: names[c] for k, c in v.items()})
                            for key, v in clf.roles_.items()}
    assert all(type(v) is str for v in named.roles_["global_candidates"])
    assert all(type(v) is int for v in clf.roles_["subtasks"])
    # the roles_ refit gives the same posterior
    again = BSIClassifier(random_state=0, **named.roles_).fit(frames, Y_COND)
    assert again.posterior_.specifications == named.posterior_.specifications
    np.testing.assert_array_equal(again.posterior_.probabilities,
                                  named.posterior_.probabilities)


def test_explicit_roles_show_in_roles_under_both_settings():
    given = dict(global_candidates=[0], subtasks=[2, 3], conditions={2: 1})
    for roles in ("all", "infer"):
        clf = BSIClassifier(roles=roles, random_state=0, **given).fit(X_COND, Y_COND)
        assert clf.roles_ == {"global_candidates": [0], "subtasks": [2, 3],
                              "conditions": {2: 1}}


def test_roles_all_is_every_proposition_in_every_role():
    a = BSIClassifier(roles="all", random_state=0).fit(X_COND, Y_COND)
    b = BSIClassifier(roles="infer", random_state=0, global_candidates=[0, 1, 2, 3],
                      subtasks=[0, 1, 2, 3], conditions={}).fit(X_COND, Y_COND)
    assert BSIClassifier().get_params()["roles"] == "infer"  # the default
    assert a.posterior_.specifications == b.posterior_.specifications
    np.testing.assert_array_equal(a.posterior_.probabilities, b.posterior_.probabilities)


def test_inferred_roles_pickle_and_are_deterministic():
    clf = BSIClassifier(roles="infer", random_state=0).fit(X_COND, Y_COND)
    back = pickle.loads(pickle.dumps(clf))
    assert back.roles_ == clf.roles_
    np.testing.assert_array_equal(back.predict_proba(X_COND), clf.predict_proba(X_COND))
    other = BSIClassifier(roles="infer", random_state=1).fit(X_COND, Y_COND)
    assert other.roles_ == clf.roles_


def test_inferred_roles_do_not_claim_the_default_roles_in_warnings():
    X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]])] * 3
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        BSIClassifier(roles="infer", max_exact_hypotheses=1, n_samples=20, n_chains=1,
                      random_state=0).fit(X)
    assert not [w for w in caught if "roles='all'" in str(w.message)]


# ---------------------------------------------------------------- a conditional step
def _conditional_task(n, seed):
    """safe throughout; closed at the start half of the time, then opened must come first;
    reach, grasp, place in order; a light that toggles. Unacceptable ones break one rule."""
    rng = np.random.default_rng(seed)
    X, y = [], []
    for _ in range(n):
        good = rng.random() < 0.5
        fault = None if good else ["unsafe", "not_opened", "swap"][int(rng.integers(3))]
        closed = fault == "not_opened" or rng.random() < 0.5
        events = (["opened"] if closed and fault != "not_opened" else []) + [3, 4, 5]
        events = [2 if e == "opened" else e for e in events]
        if fault == "swap":
            events[-1], events[-2] = events[-2], events[-1]
        times = np.sort(rng.choice(np.arange(1, 10), size=len(events), replace=False))
        x = np.zeros((int(times[-1]) + 2, 7), dtype=bool)
        x[:, 0] = True
        x[:, 6] = rng.random(len(x)) < 0.5
        for e, t in zip(events, times):
            x[t:, e] = True
        x[:, 1] = closed & ~x[:, 2]
        if fault == "unsafe":
            x[int(rng.integers(len(x))), 0] = False
        X.append(x)
        y.append(int(good))
    return X, np.array(y)


def test_inferred_roles_let_the_map_hold_the_conditional_clause():
    X, y = _conditional_task(30, seed=0)
    Xt, yt = _conditional_task(300, seed=1)
    infer = BSIClassifier(roles="infer", inference="exact", random_state=0).fit(X, y)
    every = BSIClassifier(roles="all", inference="exact", random_state=0).fit(X, y)
    assert infer.roles_["conditions"] == {2: 1}
    spec = infer.map_specification_
    assert 2 in spec.eventuals and "1 -> F(2)" in spec.to_ltl()
    assert "->" not in every.map_specification_.to_ltl()
    # the closed-and-never-opened demonstrations: rejected with the inferred roles
    skipped = [x for x, label in zip(Xt, yt) if x[0, 1] and not x[:, 2].any()]
    assert len(skipped) > 10
    assert infer.predict(skipped).tolist() == [0] * len(skipped)
    assert infer.score(Xt, yt) > every.score(Xt, yt)
