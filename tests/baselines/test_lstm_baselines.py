import copy
import pickle

import numpy as np
import pandas as pd
import pytest
import sklearn
import torch
from sklearn.base import clone
from sklearn.exceptions import NotFittedError
from sklearn.model_selection import cross_validate
from sklearn.utils.estimator_checks import parametrize_with_checks

from baselines import (
    PAPER_BASELINES,
    LSTMSequenceClassifier,
    make_paper_baseline,
    paper_baselines,
)


def temporal_dataset(n, seed, t_min=12, t_max=24):
    """Sequences of three propositions whose labels need memory of the past.

    Propositions ``a`` and ``b`` switch on once and stay on, so at the last step both are on
    in every sequence: objective 0 is "``a`` switched on before ``b``". Proposition ``c`` is a
    single-step pulse in about half of the sequences: objective 1 is "``c`` happened". The
    phase of a step is the number of ``a``, ``b`` switched on so far (three phases).
    """
    rng = np.random.default_rng(seed)
    X, y, phases = [], [], []
    for _ in range(n):
        length = int(rng.integers(t_min, t_max + 1))
        t_a, t_b = rng.choice(np.arange(1, length - 1), size=2, replace=False)
        x = np.zeros((length, 3), dtype=bool)
        x[t_a:, 0] = True
        x[t_b:, 1] = True
        pulse = bool(rng.random() < 0.5)
        if pulse:
            x[int(rng.integers(0, length)), 2] = True
        X.append(x)
        y.append([int(t_a < t_b), int(pulse)])
        phases.append(x[:, 0].astype(int) + x[:, 1].astype(int))
    return X, np.array(y), phases


X_TRAIN, Y_TRAIN, PH_TRAIN = temporal_dataset(64, seed=0)
X_TEST, Y_TEST, PH_TEST = temporal_dataset(100, seed=1)
FAST = {"max_epochs": 8, "hidden_size": 8, "n_phases": 3}


@pytest.fixture(scope="module")
def trained():
    """The four paper baselines trained once on the temporal task (defaults, n_phases=3)."""
    models = paper_baselines(random_state=0, n_phases=3)
    for clf in models.values():
        clf.fit(X_TRAIN, Y_TRAIN, phases=PH_TRAIN)
    return models


@pytest.mark.parametrize("name", list(PAPER_BASELINES))
def test_each_variant_learns_a_temporal_pattern(trained, name):
    clf = trained[name]
    pred = clf.predict(X_TEST)
    assert pred.shape == (100, 2)
    accuracy = (pred == Y_TEST).mean(axis=0)
    # a majority-class predictor scores about 0.5 on both objectives
    assert np.all(accuracy >= 0.85), accuracy
    proba = clf.predict_proba(X_TEST)
    assert isinstance(proba, list) and len(proba) == 2
    for k, p in enumerate(proba):
        assert p.shape == (100, 2)
        np.testing.assert_allclose(p.sum(axis=1), 1.0)
        np.testing.assert_array_equal(clf.classes_[k][p.argmax(axis=1)], pred[:, k])
    assert clf.n_outputs_ == 2 and clf.n_features_in_ == 3
    assert 1 <= clf.best_epoch_ <= clf.n_epochs_ <= clf.max_epochs
    assert clf.best_loss_ == pytest.approx(min(h["valid_loss"] for h in clf.history_))


@pytest.mark.parametrize("name", ["LSTM Coupled", "Bi-LSTM Coupled"])
def test_coupled_models_learn_the_phases(trained, name):
    predicted = trained[name].predict_phases(X_TEST)
    assert [len(p) for p in predicted] == [len(x) for x in X_TEST]
    accuracy = np.mean(np.concatenate(predicted) == np.concatenate(PH_TEST))
    assert accuracy >= 0.9


def test_predict_phases_needs_a_coupled_model(trained):
    with pytest.raises(ValueError, match="coupled=True"):
        trained["LSTM"].predict_phases(X_TEST[:2])


@pytest.mark.parametrize("name", list(PAPER_BASELINES))
@pytest.mark.parametrize("pooling", ["last", "mean", "max"])
def test_padding_does_not_change_predictions(name, pooling):
    clf = make_paper_baseline(name, random_state=0, pooling=pooling, **FAST)
    clf.fit(X_TRAIN, Y_TRAIN, phases=PH_TRAIN)
    rng = np.random.default_rng(3)
    longer = [rng.integers(0, 2, size=(int(rng.integers(40, 80)), 3)) for _ in range(5)]
    for i in range(4):
        alone = clf.predict_proba([X_TEST[i]])
        batch = clf.predict_proba(longer[:2] + [X_TEST[i]] + longer[2:])
        for a, b in zip(alone, batch, strict=True):
            np.testing.assert_allclose(a[0], b[2], rtol=0, atol=1e-6)
    if clf.coupled:
        alone = clf.predict_phases([X_TEST[0]])[0]
        batch = clf.predict_phases(longer + [X_TEST[0]])[-1]
        np.testing.assert_array_equal(alone, batch)


@pytest.mark.parametrize("name", ["Bi-LSTM", "LSTM Coupled"])
def test_same_seed_same_model_and_global_rng_untouched(name):
    torch_state = torch.get_rng_state()
    np_state = np.random.get_state()[1].copy()
    threads = torch.get_num_threads()
    fits = [
        make_paper_baseline(name, random_state=seed, dropout=0.2, **FAST).fit(
            X_TRAIN, Y_TRAIN, phases=PH_TRAIN
        )
        for seed in (7, 7, 8)
    ]
    assert torch.equal(torch.get_rng_state(), torch_state)
    np.testing.assert_array_equal(np.random.get_state()[1], np_state)
    assert torch.get_num_threads() == threads
    p = [np.column_stack(clf.predict_proba(X_TEST)) for clf in fits]
    np.testing.assert_array_equal(p[0], p[1])
    assert fits[0].history_ == fits[1].history_
    assert not np.allclose(p[0], p[2])


@pytest.mark.parametrize("name", ["LSTM Coupled", "Bi-LSTM Coupled"])
def test_coupled_without_phases_is_an_error(name):
    clf = make_paper_baseline(name, **FAST)
    with pytest.raises(ValueError, match=r"coupled=True\) needs the phase labels"):
        clf.fit(X_TRAIN, Y_TRAIN)
    with pytest.raises(ValueError, match="phases of sequence 1 has"):
        clf.fit(X_TRAIN, Y_TRAIN, phases=[PH_TRAIN[0]] * len(X_TRAIN))
    with pytest.raises(ValueError, match=r"n_phases=3"):
        clf.fit(X_TRAIN, Y_TRAIN, phases=[p + 1 for p in PH_TRAIN])


def test_standalone_ignores_phases():
    a = LSTMSequenceClassifier(random_state=0, **FAST).fit(X_TRAIN, Y_TRAIN)
    b = LSTMSequenceClassifier(random_state=0, **FAST).fit(X_TRAIN, Y_TRAIN, phases=PH_TRAIN)
    np.testing.assert_array_equal(a.predict_proba(X_TEST)[0], b.predict_proba(X_TEST)[0])


def test_metadata_routing_with_cross_validate():
    X, y, phases = X_TRAIN[:36], Y_TRAIN[:36, 0], PH_TRAIN[:36]
    with sklearn.config_context(enable_metadata_routing=True):
        coupled = make_paper_baseline("LSTM Coupled", random_state=0, **FAST)
        coupled.set_fit_request(phases=True)
        result = cross_validate(coupled, X, y, cv=3, params={"phases": phases},
                                return_estimator=True)
        assert len(result["test_score"]) == 3
        assert all(est.predict_phases(X[:1])[0].shape == (len(X[0]),)
                   for est in result["estimator"])
        # phases that nothing requests are an error of scikit-learn's router
        unrequested = clone(coupled).set_fit_request(phases=False)
        with pytest.raises(TypeError, match="not routed to any object"):
            cross_validate(unrequested, X, y, cv=3, params={"phases": phases})
        # a standalone model may request them too (one loop over the four baselines); it
        # ignores them
        standalone = make_paper_baseline("LSTM", random_state=0, **FAST)
        standalone.set_fit_request(phases=True)
        with_phases = cross_validate(standalone, X, y, cv=3, params={"phases": phases})
        without = cross_validate(clone(standalone), X, y, cv=3)
        np.testing.assert_array_equal(with_phases["test_score"], without["test_score"])
    # without routing, params go straight to fit
    result = cross_validate(clone(coupled), X, y, cv=3, params={"phases": phases})
    assert np.all(np.isfinite(result["test_score"]))


def test_pickle_and_deepcopy_round_trip():
    clf = make_paper_baseline("Bi-LSTM Coupled", random_state=0, **FAST)
    clf.fit(X_TRAIN, Y_TRAIN, phases=PH_TRAIN)
    expected = clf.predict_proba(X_TEST)
    for restored in (pickle.loads(pickle.dumps(clf)), copy.deepcopy(clf)):
        for a, b in zip(expected, restored.predict_proba(X_TEST), strict=True):
            np.testing.assert_array_equal(a, b)
        np.testing.assert_array_equal(clf.predict_phases(X_TEST[:3])[2],
                                      restored.predict_phases(X_TEST[:3])[2])
    # pickling leaves the original usable
    np.testing.assert_array_equal(clf.predict_proba(X_TEST)[0], expected[0])


def test_one_dimensional_labels_and_string_classes():
    y = np.where(Y_TRAIN[:, 0] == 1, "before", "after")
    clf = LSTMSequenceClassifier(random_state=0, **FAST).fit(X_TRAIN, y)
    assert clf.classes_.tolist() == ["after", "before"]
    assert clf.n_outputs_ == 1
    pred = clf.predict(X_TEST)
    proba = clf.predict_proba(X_TEST)
    assert pred.shape == (100,) and proba.shape == (100, 2)
    np.testing.assert_array_equal(clf.classes_[proba.argmax(axis=1)], pred)
    with pytest.raises(ValueError, match="Only binary classification is supported"):
        clf.fit(X_TRAIN, np.arange(len(X_TRAIN)) % 3)
    with pytest.raises(ValueError, match="Unknown label type: continuous"):
        clf.fit(X_TRAIN, np.linspace(0, 1, len(X_TRAIN)))
    with pytest.raises(ValueError, match="inconsistent numbers of samples"):
        clf.fit(X_TRAIN, y[:-1])


def test_objective_with_a_single_label_is_predicted_constant():
    y = Y_TRAIN.copy()
    y[:, 1] = 1
    clf = LSTMSequenceClassifier(random_state=0, **FAST).fit(X_TRAIN, y)
    assert clf.classes_[1].tolist() == [1]
    assert np.all(clf.predict(X_TEST)[:, 1] == 1)
    assert clf.predict_proba(X_TEST)[1].shape == (100, 1)


def test_dataframes_numeric_features_and_names():
    rng = np.random.default_rng(0)
    frames = [
        pd.DataFrame({"a": x[:, 0], "b": x[:, 1], "c": x[:, 2],
                      "altitude": 1000 + 300 * rng.normal(size=len(x))})
        for x in X_TRAIN
    ]
    clf = LSTMSequenceClassifier(random_state=0, **FAST).fit(frames, Y_TRAIN)
    assert clf.feature_names_in_.tolist() == ["a", "b", "c", "altitude"]
    assert clf.feature_mean_[3] == pytest.approx(1000, abs=30)
    assert clf.predict(frames[:5]).shape == (5, 2)
    renamed = [f.rename(columns={"altitude": "speed"}) for f in frames[:2]]
    with pytest.raises(ValueError, match="feature names should match"):
        clf.predict(renamed)
    with pytest.raises(ValueError, match="X has 3 features"):
        clf.predict(X_TEST[:2])


def test_class_weight_moves_predictions():
    y = Y_TRAIN[:, 0]
    heavy = {0: 1.0, 1: 1e-4}
    clf = LSTMSequenceClassifier(random_state=0, class_weight=heavy, **FAST).fit(X_TRAIN, y)
    assert np.mean(clf.predict(X_TEST) == 0) > 0.9
    balanced = LSTMSequenceClassifier(random_state=0, class_weight="balanced", **FAST)
    assert balanced.fit(X_TRAIN, Y_TRAIN).predict(X_TEST).shape == (100, 2)
    with pytest.raises(ValueError, match="list of dicts, one per objective"):
        LSTMSequenceClassifier(class_weight=heavy, **FAST).fit(X_TRAIN, Y_TRAIN)


def test_early_stopping_restores_the_best_epoch():
    clf = LSTMSequenceClassifier(random_state=0, max_epochs=60, patience=5, hidden_size=8)
    clf.fit(X_TRAIN, Y_TRAIN)
    valid = [h["valid_loss"] for h in clf.history_]
    assert clf.best_epoch_ == int(np.argmin(valid)) + 1
    assert clf.n_epochs_ == clf.max_epochs or clf.n_epochs_ - clf.best_epoch_ == clf.patience
    no_valid = LSTMSequenceClassifier(random_state=0, validation_fraction=None, **FAST)
    no_valid.fit(X_TRAIN, Y_TRAIN)
    assert all(np.isnan(h["valid_loss"]) for h in no_valid.history_)
    assert no_valid.best_loss_ == min(h["train_loss"] for h in no_valid.history_)


def test_refit_trains_on_every_sequence_for_the_chosen_epochs():
    params = dict(random_state=0, max_epochs=40, patience=5, hidden_size=8, batch_size=4)
    stopped = LSTMSequenceClassifier(**params).fit(X_TRAIN, Y_TRAIN)
    refitted = LSTMSequenceClassifier(refit=True, **params).fit(X_TRAIN, Y_TRAIN)
    # the same early-stopping run chooses the epoch count; the refit then runs exactly that
    assert refitted.history_ == stopped.history_
    assert refitted.best_epoch_ == stopped.best_epoch_ == refitted.refit_epochs_ >= 1
    assert stopped.refit_epochs_ == 0
    assert not np.allclose(refitted.predict_proba(X_TEST)[0], stopped.predict_proba(X_TEST)[0])
    again = LSTMSequenceClassifier(refit=True, **params).fit(X_TRAIN, Y_TRAIN)
    for a, b in zip(again.predict_proba(X_TEST), refitted.predict_proba(X_TEST)):
        np.testing.assert_array_equal(a, b)
    # nothing to refit without a validation split
    plain = LSTMSequenceClassifier(refit=True, validation_fraction=None, **params)
    assert plain.fit(X_TRAIN, Y_TRAIN).refit_epochs_ == 0
    assert not torch.are_deterministic_algorithms_enabled()  # the setting is restored


@pytest.mark.parametrize(
    "params, match",
    [
        ({"hidden_size": 0}, "hidden_size must be an integer >= 1"),
        ({"lr": -1.0}, "lr must be a number"),
        ({"validation_fraction": 1.0}, "validation_fraction must be a number"),
        ({"pooling": "first"}, "pooling must be one of"),
        ({"coupled": True, "n_phases": 1}, "n_phases must be an integer >= 2"),
        ({"class_weight": "auto"}, "class_weight must be None"),
        ({"device": "no-such-device"}, "is not a torch device"),
        ({"n_threads": 0}, "n_threads must be an integer >= 1"),
    ],
)
def test_bad_hyperparameters(params, match):
    with pytest.raises(ValueError, match=match):
        LSTMSequenceClassifier(**params).fit(X_TRAIN[:4], Y_TRAIN[:4], phases=PH_TRAIN[:4])


def test_unfitted_and_paper_constructors():
    with pytest.raises(NotFittedError):
        LSTMSequenceClassifier().predict(X_TEST)
    models = paper_baselines(hidden_size=16)
    assert [(m.bidirectional, m.coupled) for m in models.values()] == [
        (False, False), (True, False), (False, True), (True, True)
    ]
    assert all(m.hidden_size == 16 for m in models.values())
    with pytest.raises(ValueError, match="unknown baseline"):
        make_paper_baseline("GRU")
    with pytest.raises(ValueError, match="set by the baseline name"):
        make_paper_baseline("LSTM", coupled=True)


@parametrize_with_checks([LSTMSequenceClassifier(max_epochs=50, random_state=0)])
def test_sklearn_compatible_estimator(estimator, check):
    check(estimator)


def test_score_is_subset_accuracy_for_several_objectives(trained):
    clf = trained["LSTM"]
    pred = clf.predict(X_TEST)
    assert clf.score(X_TEST, Y_TEST) == pytest.approx(np.mean(np.all(pred == Y_TEST, axis=1)))
    labels = np.where(Y_TEST == 1, "yes", "no")
    strings = LSTMSequenceClassifier(random_state=0, **FAST).fit(
        X_TRAIN, np.where(Y_TRAIN == 1, "yes", "no")
    )
    assert 0.0 <= strings.score(X_TEST, labels) <= 1.0


def test_batches_padded_once_equal_batches_padded_one_by_one():
    from baselines._network import Batches, make_batch
    from baselines._sequences import length_mask, pad_sequences

    rng = np.random.default_rng(0)
    lengths = rng.integers(3, 12, size=9)
    offsets = np.concatenate([[0], np.cumsum(lengths)])
    data = rng.normal(size=(offsets[-1], 3)).astype(np.float32)
    phases = rng.integers(0, 4, size=offsets[-1])
    y01 = rng.integers(0, 2, size=(9, 2)).astype(np.float32)
    weights = rng.uniform(0.5, 2.0, size=(9, 2)).astype(np.float32)
    batches = Batches(data, offsets, y01, weights, phases, torch.device("cpu"))
    for indices in ([4, 0, 7], [2], np.arange(9), [8, 1]):
        indices = np.asarray(indices)
        x, lens, rev, target, weight, phase_target, mask = batches.batch(indices)
        ref = make_batch(data, offsets, indices, torch.device("cpu"))
        for got, want in zip((x, lens, rev), ref):
            assert got.dtype == want.dtype and got.is_contiguous()
            assert torch.equal(got, want)
        padded, _ = pad_sequences(phases, offsets, indices, fill=0)
        assert torch.equal(phase_target, torch.as_tensor(padded))
        assert torch.equal(mask, torch.as_tensor(length_mask(lengths[indices], x.shape[1])))
        assert torch.equal(target, torch.as_tensor(y01[indices]))
        assert torch.equal(weight, torch.as_tensor(weights[indices]))


def test_fit_restores_torch_determinism_settings():
    fill = torch.utils.deterministic.fill_uninitialized_memory
    LSTMSequenceClassifier(hidden_size=4, max_epochs=2, random_state=0).fit(X_TRAIN, Y_TRAIN)
    assert not torch.are_deterministic_algorithms_enabled()
    assert torch.utils.deterministic.fill_uninitialized_memory == fill
