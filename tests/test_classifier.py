"""BSIClassifier as a scikit-learn estimator."""

import pickle

import numpy as np
import pandas as pd
import pytest
from poi_problems import make_poi_problem
from sklearn.base import BaseEstimator, TransformerMixin, clone
from sklearn.exceptions import NotFittedError
from sklearn.model_selection import GridSearchCV, StratifiedKFold, cross_val_score
from sklearn.pipeline import Pipeline
from sklearn.utils.estimator_checks import parametrize_with_checks

from bsi_sklearn import BSIClassifier, Specification

EXPECTED_FAILED_CHECKS = {
    **{
        name: (
            "labels other than 0/1 or booleans need pos_label (see the README); this check "
            "fits with labels such as {1, 2} or strings and no pos_label"
        )
        for name in [
            "check_estimators_dtypes",
            "check_classifiers_classes",
            "check_fit2d_1feature",
        ]
    },
    "check_classifier_data_not_an_array": (
        "labels {1, 2} without pos_label; and its PandasDataframe variant passes one DataFrame "
        "as the 2-D format, which BSI rejects on purpose (a single DataFrame is one "
        "demonstration's steps far more often than length-one traces: pass [df], a list of "
        "DataFrames, or a long-format frame with demo_id; see the README's Input paragraph)"
    ),
}


def _checked():
    # binarize=0.0 lets the generic numeric data of the checks stand for boolean traces.
    # The default (roles="infer") and the paper's every-proposition-everywhere setting.
    return [BSIClassifier(binarize=0.0, n_samples=200, n_chains=2, random_state=0),
            BSIClassifier(roles="all", binarize=0.0, n_samples=200, n_chains=2,
                          random_state=0)]


@parametrize_with_checks(_checked(), expected_failed_checks=lambda est: EXPECTED_FAILED_CHECKS)
def test_sklearn_compatible(estimator, check):
    check(estimator)


@pytest.fixture(scope="module")
def data():
    X, y, roles = make_poi_problem(n_demos=30, n_negative=12, seed=5)
    return X, y, roles


def test_fit_attributes_and_predict(data):
    X, y, roles = data
    clf = BSIClassifier(random_state=0, **roles)
    assert clf.fit(X, y) is clf
    assert clf.classes_.tolist() == [0, 1]
    assert clf.n_features_in_ == 15
    assert list(clf.feature_names_in_) == list(X[0].columns)
    assert isinstance(clf.map_specification_, Specification)
    assert clf.map_specification_ == clf.posterior_.specifications[0]
    assert clf.n_unique_specifications_ == len(clf.posterior_)
    proba = clf.predict_proba(X)
    assert proba.shape == (len(X), 2) and np.allclose(proba.sum(1), 1)
    assert np.array_equal(clf.predict(X), clf.classes_[(proba[:, 1] >= 0.5).astype(int)])
    assert clf.score(X, y) > 0.9
    assert set(clf.map_specification_.globals) == {"tau_0", "tau_1", "tau_2", "tau_3"}


def test_positive_only(data):
    X, y, roles = data
    pos = [x for x, label in zip(X, y) if label == 1]
    a = BSIClassifier(random_state=0, **roles).fit(pos)
    b = BSIClassifier(random_state=0, **roles).fit(pos, np.ones(len(pos), dtype=int))
    assert a.classes_.tolist() == [0, 1]
    assert a.predict_proba(X).shape == (len(X), 2)
    assert a.posterior_.specifications[:5] == b.posterior_.specifications[:5]
    with pytest.raises(ValueError, match="only unacceptable"):
        BSIClassifier(**roles).fit(pos, np.zeros(len(pos), dtype=int))


def test_string_labels_with_pos_label(data):
    X, y, roles = data
    labels = np.where(y == 1, "ok", "bad")
    clf = BSIClassifier(pos_label="ok", random_state=0, **roles).fit(X, labels)
    assert clf.classes_.tolist() == ["bad", "ok"]
    assert set(clf.predict(X)) <= {"bad", "ok"}
    with pytest.raises(ValueError, match="pos_label"):
        BSIClassifier(**roles).fit(X, labels)


def test_not_fitted():
    with pytest.raises(NotFittedError):
        BSIClassifier().predict([np.ones((2, 2))])


@pytest.mark.parametrize("inference", ["exact", "mcmc"])
def test_pickle_round_trip(data, inference):
    X, y, roles = data
    clf = BSIClassifier(inference=inference, n_samples=500, random_state=0, **roles).fit(X, y)
    clone_ = pickle.loads(pickle.dumps(clf))
    assert np.array_equal(clf.predict_proba(X), clone_.predict_proba(X))
    assert clone_.map_specification_ == clf.map_specification_


def test_cross_val_and_grid_search(data):
    X, y, roles = data
    cv = StratifiedKFold(3, shuffle=True, random_state=0)
    scores = cross_val_score(BSIClassifier(random_state=0, **roles), X, y, cv=cv)
    assert scores.shape == (3,) and scores.mean() > 0.8
    grid = GridSearchCV(
        BSIClassifier(random_state=0, **roles),
        {"prior": ["sets_of_chains", "forest"], "p_part": [0.1, 0.5]},
        cv=cv,
    ).fit(X, y)
    assert grid.best_params_["prior"] in {"sets_of_chains", "forest"}
    assert grid.best_score_ > 0.8


class FrameNamer(TransformerMixin, BaseEstimator):
    """Turns arrays into DataFrames with given names (a transformer in front of BSI)."""

    def __init__(self, names=None):
        self.names = names

    def fit(self, X, y=None):
        return self

    def transform(self, X):
        return [pd.DataFrame(np.asarray(x).astype(bool), columns=self.names) for x in X]


def test_pipeline(data):
    X, y, roles = data
    names = list(X[0].columns)
    arrays = [x.to_numpy() for x in X]
    pipe = Pipeline([("names", FrameNamer(names)),
                     ("bsi", BSIClassifier(random_state=0, **roles))])
    pipe.fit(arrays, y)
    assert pipe.score(arrays, y) > 0.9
    assert clone(pipe).get_params()["bsi__prior"] == "sets_of_chains"


def test_fit_does_not_mutate_params_and_refit_is_identical(data):
    X, y, roles = data
    clf = BSIClassifier(inference="mcmc", n_samples=300, random_state=3, **roles)
    before = clf.get_params()
    p1 = clf.fit(X, y).predict_proba(X)
    assert clf.get_params() == before
    p2 = clf.fit(X, y).predict_proba(X)
    assert np.array_equal(p1, p2)


@pytest.mark.parametrize("inference", ["exact", "mcmc"])
@pytest.mark.parametrize("roles", [dict(subtasks=[]), dict(global_candidates=[]),
                                   dict(subtasks=[], global_candidates=[]), dict(subtasks=[1])])
def test_degenerate_templates(inference, roles):
    X = [np.array([[1, 0], [1, 1]]), np.array([[1, 1]])]
    clf = BSIClassifier(inference=inference, n_samples=50, random_state=0, **roles).fit(X)
    assert np.isclose(clf.posterior_.probabilities.sum(), 1.0)
    assert clf.predict_proba(X).shape == (2, 2)
    if roles == dict(subtasks=[], global_candidates=[]):
        assert clf.map_specification_ == Specification()


def test_warnings_point_at_the_callers_line():
    # fit -> _fit -> _warn_*: stacklevel must reach the user's call, not the package's.
    import warnings

    rng = np.random.RandomState(0)
    X = [rng.randint(0, 2, size=(5, 4)) for _ in range(12)]
    y = rng.randint(0, 2, 12)
    clf = BSIClassifier(roles="all", likelihood="cb", inference="mcmc", n_samples=4,
                        n_chains=2, n_temperatures=1, burn_in=0, random_state=0)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        clf.fit(X, y)
    # 4 untempered samples on random data: the chains have not mixed (R-hat); each reaches
    # what the others found, so they do not disagree (that warning is raised by the same call).
    assert [str(w.message)[:29] for w in caught] == ["MCMC chains have not mixed: t"]
    assert all(w.filename == __file__ for w in caught), [w.filename for w in caught]


def test_docstring_states_what_the_roles_left_at_none_become():
    # roles="infer" is the default: help(BSIClassifier) must not say None means every
    # proposition for global_candidates and subtasks (that is roles="all")
    doc = " ".join(BSIClassifier.__doc__.split())
    for param in ("global_candidates", "subtasks", "conditions"):
        entry = doc.split(f"{param} : ")[1].split(" : ")[0]
        assert "``None``: all" not in entry, entry
        assert "read from the training demonstrations by default (``roles=\"infer\"``)" in entry
