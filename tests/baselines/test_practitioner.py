"""The practitioner's baselines: temporal features + logistic regression, and MiniRocket."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

from baselines._minirocket import (
    KERNEL_INDICES,
    _kernel_output,
    fit_dilations,
    fit_minirocket,
    transform_minirocket,
)
from baselines._sequences import check_sequences
from baselines.practitioner import (
    PRACTITIONER_BASELINES,
    TEMPORAL_FEATURES,
    DropDuplicateColumns,
    MiniRocketClassifier,
    TemporalLogisticRegression,
    make_practitioner_baseline,
    temporal_features,
)

ROOT = Path(__file__).resolve().parents[2]


def _rule_data(n=24, seed=0):
    """Sequences of 3 propositions; label: proposition 0 turns true before step 10."""
    rng = np.random.default_rng(seed)
    X, y = [], []
    for _ in range(n):
        t = int(rng.integers(20, 30))
        onset = int(rng.integers(2, 18))
        x = np.zeros((t, 3), dtype=bool)
        x[onset:, 0] = True
        x[:, 1] = rng.random(t) < 0.5
        x[: int(rng.integers(1, t)), 2] = True
        X.append(x)
        y.append(int(onset < 10))
    return X, np.array(y)


def test_temporal_features_by_hand():
    x = np.array([[0, 1, 0], [1, 1, 0], [1, 0, 0], [0, 0, 0]])
    features = temporal_features([x, x[:1]])
    assert features.shape == (2, 3 * len(TEMPORAL_FEATURES))
    by_prop = features[0].reshape(3, 5)
    # first, last, fraction true, first step true, last step false
    assert by_prop[0].tolist() == [0, 0, 0.5, 1, 3]
    assert by_prop[1].tolist() == [1, 0, 0.5, 0, 3]
    assert by_prop[2].tolist() == [0, 0, 0.0, 4, 3]  # never true: T
    one = features[1].reshape(3, 5)
    assert one[1].tolist() == [1, 1, 1.0, 0, -1]  # never false: -1


def test_temporal_features_read_frames_and_lengths():
    frames = [pd.DataFrame({"a": [False, True, True], "b": [True, True, False]}),
              pd.DataFrame({"a": [True] * 5, "b": [False] * 5})]
    arrays = [f.to_numpy() for f in frames]
    np.testing.assert_array_equal(temporal_features(frames), temporal_features(arrays))
    # monotone "a" (turns true once and stays): last false is first true - 1
    first_true, last_false = temporal_features(frames)[:, 3], temporal_features(frames)[:, 4]
    np.testing.assert_array_equal(last_false, first_true - 1)


def test_drop_duplicate_columns():
    rng = np.random.default_rng(0)
    a, b = rng.random(10), rng.random(10)
    X = np.column_stack([a, np.ones(10), 3 * a - 2, b, -a, a.copy(), (b > 0.5) * 1.0])
    drop = DropDuplicateColumns().fit(X)
    assert drop.keep_.tolist() == [0, 3, 6]  # constant, affine and negated copies dropped
    np.testing.assert_array_equal(drop.transform(X), X[:, [0, 3, 6]])
    assert DropDuplicateColumns().fit(np.ones((4, 3))).keep_.tolist() == [0]


def test_structural_duplicates_of_lfe_missions_are_dropped():
    from lfe import LFEPropositionExtractor, make_lfe_dataset

    ds = make_lfe_dataset(8, random_state=0)
    props = LFEPropositionExtractor().fit_transform(ds.scenarios)
    features = temporal_features(props)
    kept = DropDuplicateColumns().fit(features).keep_
    assert len(kept) < features.shape[1]
    # target_hit turns true once and stays true: its last false step is redundant
    j = list(props[0].columns).index("target_hit") * 5
    assert np.array_equal(features[:, j + 4], features[:, j + 3] - 1)
    assert not (j + 4 in kept and j + 3 in kept)


def test_logistic_learns_a_rule_and_is_deterministic():
    X, y = _rule_data()
    Xt, yt = _rule_data(seed=1)
    clf = TemporalLogisticRegression(random_state=0).fit(X, y)
    assert np.mean(clf.predict(Xt) == yt) >= 0.9
    again = TemporalLogisticRegression(random_state=0).fit(X, y)
    np.testing.assert_array_equal(clf.predict(Xt), again.predict(Xt))
    assert clf.chosen_C_ == again.chosen_C_ and clf.chosen_C_[0] in clf.Cs
    np.testing.assert_array_equal(clf.classes_, [0, 1])


def test_logistic_several_objectives_and_edge_cases():
    X, y = _rule_data()
    Y = np.column_stack([y, 1 - y, np.ones_like(y)])  # the third objective has one class
    clf = TemporalLogisticRegression(random_state=0).fit(X, Y)
    pred = clf.predict(X)
    assert pred.shape == (len(X), 3) and (pred[:, 2] == 1).all()
    assert clf.chosen_C_[2] is None
    single = TemporalLogisticRegression(random_state=0).fit(X, y)
    np.testing.assert_array_equal(pred[:, 0], single.predict(X))
    # one mission of a class: nothing to cross-validate, C = 1
    y1 = np.zeros(len(X), dtype=int)
    y1[0] = 1
    assert TemporalLogisticRegression(random_state=0).fit(X, y1).chosen_C_ == [1.0]
    with pytest.raises(ValueError, match="max_folds"):
        TemporalLogisticRegression(max_folds=1).fit(X, y)
    with pytest.raises(ValueError, match="features"):
        clf.predict([x[:, :2] for x in X])


def test_logistic_probabilities_agree_with_its_decisions():
    X, y = _rule_data()
    Y = np.column_stack([y, np.ones_like(y)])  # the second objective has one class
    clf = TemporalLogisticRegression(random_state=0).fit(X, Y)
    proba = clf.predict_proba(X)
    assert len(proba) == 2 and proba[0].shape == (len(X), 2) and proba[1].shape == (len(X), 1)
    np.testing.assert_allclose(proba[0].sum(axis=1), 1.0)
    np.testing.assert_array_equal(proba[1], 1.0)
    pred = clf.predict(X)
    np.testing.assert_array_equal(clf.classes_[0][proba[0].argmax(axis=1)], pred[:, 0])
    # the pipeline's own probabilities, for 1-D y as for one column of 2-D y
    single = TemporalLogisticRegression(random_state=0).fit(X, y)
    np.testing.assert_allclose(single.predict_proba(X), proba[0])
    est = single.estimators_[0]
    np.testing.assert_allclose(single.predict_proba(X), est.predict_proba(temporal_features(X)))
    # MiniRocket's ridge classifier has no probabilities: neither has the row
    assert not hasattr(MiniRocketClassifier(num_kernels=84), "predict_proba")


def test_minirocket_learns_a_rule_and_is_deterministic():
    X, y = _rule_data(30)
    Xt, yt = _rule_data(30, seed=1)
    clf = MiniRocketClassifier(num_kernels=840, random_state=0).fit(X, y)
    assert np.mean(clf.predict(Xt) == yt) >= 0.8
    again = MiniRocketClassifier(num_kernels=840, random_state=0).fit(X, y)
    np.testing.assert_array_equal(clf.predict(Xt), again.predict(Xt))
    np.testing.assert_array_equal(clf.scaler_.mean_, again.scaler_.mean_)
    other = MiniRocketClassifier(num_kernels=840, random_state=1).fit(X, y)
    assert not np.array_equal(clf.scaler_.mean_, other.scaler_.mean_)
    Y = np.column_stack([y, np.zeros_like(y)])
    pred = MiniRocketClassifier(num_kernels=840, random_state=0).fit(X, Y).predict(Xt)
    assert pred.shape == (len(Xt), 2) and (pred[:, 1] == 0).all()
    np.testing.assert_array_equal(pred[:, 0], clf.predict(Xt))


def test_factory_and_no_torch():
    assert isinstance(make_practitioner_baseline("Logistic regression", random_state=1),
                      TemporalLogisticRegression)
    assert isinstance(make_practitioner_baseline("MiniRocket"), MiniRocketClassifier)
    assert list(PRACTITIONER_BASELINES) == ["Logistic regression", "MiniRocket"]
    with pytest.raises(ValueError, match="unknown practitioner baseline"):
        make_practitioner_baseline("SVM")
    code = "import sys, baselines.practitioner; print('torch' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=ROOT, check=True).stdout.strip()
    assert out == "False"


def _naive_output(x, dilation, channels, top):
    """The kernel's output by its definition: weights -1, and 2 at ``top``, zero padding."""
    weights = np.full(9, -1.0)
    weights[list(top)] = 2.0
    summed = x[:, channels].sum(axis=1)
    padded = np.concatenate([np.zeros(4 * dilation), summed, np.zeros(4 * dilation)])
    return np.array([sum(weights[j] * padded[t + j * dilation] for j in range(9))
                     for t in range(len(x))])


def test_minirocket_kernels_and_dilations():
    assert KERNEL_INDICES.shape == (84, 3)
    assert len({tuple(k) for k in KERNEL_INDICES}) == 84 and KERNEL_INDICES.max() == 8
    # the reference code's dilations: 2 ** x, x evenly spaced up to log2((L - 1) / 8)
    dilations, per_dilation = fit_dilations(260, 10_000, 32)
    assert dilations[0] == 1 and dilations[-1] == 32 and (np.diff(dilations) > 0).all()
    assert per_dilation.sum() == 10_000 // 84
    dilations, per_dilation = fit_dilations(9, 84, 32)
    assert dilations.tolist() == [1] and per_dilation.tolist() == [1]


def test_minirocket_transform_matches_its_definition():
    rng = np.random.default_rng(0)
    X = [rng.random((int(rng.integers(9, 40)), 3)) for _ in range(6)]
    seqs = check_sequences(X)
    params = fit_minirocket(seqs.data, seqs.offsets, num_features=840, seed=0)
    assert params.n_features == 840 - 840 % 84
    for x in X[:2]:
        for d in params.dilations[:3]:
            for k in (0, 41, 83):
                out = np.empty(len(x))
                _kernel_output(x, d, np.array([0, 2]), KERNEL_INDICES[k], out)
                np.testing.assert_allclose(out, _naive_output(x, d, [0, 2], KERNEL_INDICES[k]),
                                           atol=1e-12)
    features = transform_minirocket(seqs.data, seqs.offsets, params)
    assert features.shape == (6, params.n_features)
    assert ((features >= 0) & (features <= 1)).all()
    # the first pair (smallest dilation, first kernel): PPV against each of its biases
    x = X[4]
    channels = params.channels[:params.channels_per_pair[0]]
    out = _naive_output(x, params.dilations[0], channels, KERNEL_INDICES[0])
    for f in range(params.features_per_dilation[0]):
        assert features[4, f] == pytest.approx(np.mean(out > params.biases[f]))
    # every bias is a quantile of the output of one training sequence
    outputs = [_naive_output(x, params.dilations[0], channels, KERNEL_INDICES[0]) for x in X]
    assert any(params.biases[0] == pytest.approx(np.quantile(o, (1 + 5 ** 0.5) / 2 % 1))
               for o in outputs)


def test_minirocket_is_seeded_and_reads_each_sequence_alone():
    rng = np.random.default_rng(1)
    X = [rng.integers(0, 2, (int(rng.integers(9, 30)), 4)) for _ in range(8)]
    seqs = check_sequences(X)
    a = fit_minirocket(seqs.data, seqs.offsets, num_features=168, seed=5)
    b = fit_minirocket(seqs.data, seqs.offsets, num_features=168, seed=5)
    c = fit_minirocket(seqs.data, seqs.offsets, num_features=168, seed=6)
    np.testing.assert_array_equal(a.biases, b.biases)
    np.testing.assert_array_equal(a.channels, b.channels)
    assert not np.array_equal(a.channels, c.channels) or not np.array_equal(a.biases, c.biases)
    every = transform_minirocket(seqs.data, seqs.offsets, a)
    one = check_sequences(X[3:4])
    np.testing.assert_array_equal(transform_minirocket(one.data, one.offsets, a), every[3:4])
    with pytest.raises(ValueError, match="at least 9 steps"):
        short = check_sequences([np.zeros((8, 2))])
        fit_minirocket(short.data, short.offsets)
    with pytest.raises(ValueError, match="fitted on 4 channels"):
        transform_minirocket(seqs.data[:, :3], seqs.offsets, a)
