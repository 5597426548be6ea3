"""make_process_log: labelled event logs of random process trees (issue 27)."""

import hashlib

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn import Specification
from bsi_sklearn.datasets import ProcessLog, make_process_log
from bsi_sklearn.datasets.process_logs import RULE_PATTERNS
from bsi_sklearn.param_validation import InvalidParameterError


def _sequences(log):
    """Activity names per case, read from the event table alone (sorted by time)."""
    ev = log.events.sort_values(["case:concept:name", "time:timestamp"], kind="stable")
    return {case: list(g["concept:name"]) for case, g in ev.groupby("case:concept:name")}


def _brute_force(pattern, acts, seq):
    """Each pattern's LTLf definition, position by position (nothing shared with the module)."""
    n = len(seq)
    at = [[seq[t] == x for x in acts] for t in range(n)]
    if pattern == "existence":  # F(a)
        return any(at[t][0] for t in range(n))
    if pattern == "absence":  # G(!a)
        return all(not at[t][0] for t in range(n))
    if pattern == "at_most_once":  # !F(a & X(F(a)))
        return not any(at[t][0] and any(at[s][0] for s in range(t + 1, n)) for t in range(n))
    if pattern == "precedence":  # (!b U a), strong
        return any(at[t][0] and not any(at[s][1] for s in range(t)) for t in range(n))
    if pattern == "response":  # G(a -> F(b))
        return all(not at[t][0] or any(at[s][1] for s in range(t, n)) for t in range(n))
    raise AssertionError(pattern)


def _occurred(seq, names):
    """The "occurred" encoding of DESIGN section 11, built here: (k + 1, n) booleans."""
    x = np.zeros((len(seq) + 1, len(names)), dtype=bool)
    for t, a in enumerate(seq, start=1):
        x[t:, names.index(a)] = True
    return x


def test_a_seed_gives_the_same_log_and_another_seed_another():
    a = make_process_log(20, 300, random_state=7)
    b = make_process_log(20, 300, random_state=7)
    c = make_process_log(20, 300, random_state=8)
    assert isinstance(a, ProcessLog)
    pd.testing.assert_frame_equal(a.events, b.events)
    pd.testing.assert_series_equal(a.labels, b.labels)
    pd.testing.assert_series_equal(a.clean_labels, b.clean_labels)
    assert (a.rule, a.rule_clauses, a.tree) == (b.rule, b.rule_clauses, b.tree)
    assert a.tree != c.tree
    assert not a.events.equals(c.events)


def test_the_log_is_bit_identical_to_the_recorded_one():
    # Generator streams and integer arithmetic only: every machine draws these bytes.
    log = make_process_log(12, 50, rule="declare", random_state=3)
    ev = log.events
    text = "\n".join(f"{c},{a},{t.value}" for c, a, t in zip(
        ev["case:concept:name"], ev["concept:name"], ev["time:timestamp"]))
    text += "\n" + ",".join(map(str, log.labels)) + "\n" + log.rule
    digest = hashlib.sha256(text.encode()).hexdigest()[:16]
    assert digest == RECORDED_DIGEST, (digest, log.rule)


RECORDED_DIGEST = "1ded6cbe6e3aa97a"  # recorded on x86-64 Linux, numpy 2.4 (integer timestamps)


@pytest.mark.parametrize("n_activities", [10, 40, 100])
@pytest.mark.parametrize("rule", ["template", "declare"])
def test_sizes_columns_and_times(n_activities, rule):
    log = make_process_log(n_activities, 400, rule=rule, noise=0.0, random_state=n_activities)
    ev = log.events
    assert list(ev.columns) == ["case:concept:name", "concept:name", "time:timestamp"]
    assert len(log.activities) == n_activities and len(set(log.activities)) == n_activities
    assert set(ev["concept:name"]) <= set(log.activities)
    assert pd.api.types.is_datetime64_any_dtype(ev["time:timestamp"])
    assert ev.groupby("case:concept:name")["time:timestamp"].apply(
        lambda s: s.is_monotonic_increasing and s.is_unique).all()
    assert len(log.labels) == 400 and log.labels.index.is_unique
    assert list(log.labels.index) == list(dict.fromkeys(ev["case:concept:name"]))
    assert set(log.labels) == {0, 1}
    assert 0.15 <= 1 - log.clean_labels.mean() <= 0.75
    assert {p for p, _ in log.rule_clauses} <= set(RULE_PATTERNS[rule])
    assert all(a in log.activities for _, acts in log.rule_clauses for a in acts)


@pytest.mark.parametrize("rule", ["template", "declare"])
@pytest.mark.parametrize("seed", range(4))
def test_the_clean_label_is_the_rule_by_brute_force(rule, seed):
    log = make_process_log(15, 250, rule=rule, noise=0.2, random_state=seed)
    seqs = _sequences(log)
    truth = pd.Series({case: int(all(_brute_force(p, acts, seq) for p, acts in log.rule_clauses))
                       for case, seq in seqs.items()})
    assert (truth.reindex(log.clean_labels.index) == log.clean_labels).all()
    assert [c for c in log.cases()] == [seqs[c] for c in log.labels.index]


@pytest.mark.parametrize("seed", range(3))
def test_a_template_rule_is_a_specification_on_the_occurred_encoding(seed):
    log = make_process_log(12, 150, rule="template", noise=0.0, random_state=seed)
    spec = log.specification()
    assert isinstance(spec, Specification)
    names = list(log.activities)
    for case, seq in _sequences(log).items():
        ok = spec.satisfied_by(_occurred(seq, names), feature_names=names)
        assert ok == bool(log.clean_labels[case])


@pytest.mark.parametrize("seed", range(12))
def test_a_declare_rule_is_a_specification_on_the_encoder_columns_or_an_error(seed):
    from bsi_sklearn.io import EventLogEncoder

    log = make_process_log(10, 150, rule="declare", noise=0.0, random_state=seed)
    patterns = {p for p, _ in log.rule_clauses}
    if patterns - {"absence", "existence", "precedence"}:
        with pytest.raises(ValueError, match=r"outside BSI's template on the occurred"):
            log.specification()
        return
    spec = log.specification()
    assert spec.globals == {"!" + acts[0] for p, acts in log.rule_clauses if p == "absence"}
    traces = EventLogEncoder().fit(log.cases()).transform(log.cases())
    assert [spec.satisfied_by(t) for t in traces] == log.clean_labels.astype(bool).tolist()


def test_noise_flips_about_the_asked_fraction():
    log = make_process_log(10, 20_000, noise=0.1, random_state=1)
    rate = float((log.labels != log.clean_labels).mean())
    assert abs(rate - 0.1) < 0.01
    clean = make_process_log(10, 2_000, noise=0.0, random_state=1)
    assert (clean.labels == clean.clean_labels).all()


def test_positive_only_keeps_acceptable_cases():
    log = make_process_log(20, 300, positive_only=True, noise=0.0, random_state=2)
    assert len(log.labels) == 300 and (log.labels == 1).all() and (log.clean_labels == 1).all()
    noisy = make_process_log(20, 2_000, positive_only=True, noise=0.1, random_state=2)
    assert (noisy.labels == 1).all()
    assert 0 < (noisy.clean_labels == 0).mean() < 0.2  # contaminated by the flips


@pytest.mark.parametrize("kwargs, match", [
    ({"n_activities": 2}, "n_activities"),
    ({"n_activities": 10.5}, "n_activities"),
    ({"n_cases": 0}, "n_cases"),
    ({"rule": "ltl"}, "rule"),
    ({"noise": 1.5}, "noise"),
    ({"noise": -0.1}, "noise"),
    ({"positive_only": "yes"}, "positive_only"),
    ({"random_state": "seed"}, "random_state"),
])
def test_bad_parameters_are_named(kwargs, match):
    with pytest.raises(InvalidParameterError, match=f"make_process_log: {match}"):
        make_process_log(**kwargs)
    assert issubclass(InvalidParameterError, ValueError)
