"""The extractor feeding `BSIClassifier` in a scikit-learn pipeline, inside cross-validation."""

import numpy as np
import pytest
from sklearn.model_selection import cross_val_score
from sklearn.pipeline import make_pipeline

from bsi_sklearn import BSIClassifier
from lfe import LFEPropositionExtractor, make_lfe_dataset, proposition_roles


@pytest.fixture(scope="module")
def small():
    return make_lfe_dataset(8, random_state=0)


def _pipe(propositions="paper"):
    roles = proposition_roles(propositions)
    return make_pipeline(
        LFEPropositionExtractor(propositions=propositions),
        BSIClassifier(global_candidates=roles["global_candidates"], subtasks=roles["subtasks"],
                      conditions=roles["conditions"], inference="mcmc", n_samples=300,
                      burn_in=20, n_chains=1, random_state=0),
    )


def test_pipeline_inside_cross_val_score(small):
    y = small.labels["MO1"].to_numpy()
    assert set(y) == {0, 1}
    scores = cross_val_score(_pipe(), small.scenarios, y, cv=2)
    assert scores.shape == (2,)
    assert np.all((scores >= 0) & (scores <= 1))


def test_fitted_pipeline_predicts_every_scenario(small):
    y = small.labels["MO2"].to_numpy()
    pipe = _pipe("extended").fit(small.scenarios, y)
    clf = pipe[-1]
    proba = pipe.predict_proba(small.scenarios)
    assert proba.shape == (8, 2)
    np.testing.assert_allclose(proba.sum(axis=1), 1.0)
    assert set(pipe.predict(small.scenarios)) <= {0, 1}
    assert list(clf.feature_names_in_) == list(pipe[0].get_feature_names_out())
