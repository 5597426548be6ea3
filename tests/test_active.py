"""entropy_sampling: the vote's entropy ranks the pool, most informative first."""

import numpy as np
import pytest
from sklearn.exceptions import NotFittedError

from bsi_sklearn import BSIClassifier
from bsi_sklearn.active import entropy_sampling, vote_entropy


@pytest.fixture(scope="module")
def clf():
    X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]), np.array([[1, 0, 0], [1, 1, 1]])]
    return BSIClassifier(random_state=0).fit(X)


def _pool(n=30, seed=0):
    rng = np.random.default_rng(seed)
    return [rng.integers(0, 2, size=(int(rng.integers(1, 5)), 3)) for _ in range(n)]


def test_ranking_follows_the_entropy_of_the_vote(clf):
    pool = _pool()
    p = clf.posterior_.predict_proba(pool)[:, 1]  # the vote, not the predictive
    h = vote_entropy(clf, pool)
    assert np.array_equal(p, clf.set_params(vote="satisfaction").predict_proba(pool)[:, 1])
    clf.set_params(vote="predictive")  # whatever vote says, the scores are the vote's
    np.testing.assert_array_equal(vote_entropy(clf, pool), h)
    expected = -p * np.log2(p, where=p > 0, out=np.zeros_like(p)) - (1 - p) * np.log2(
        1 - p, where=p < 1, out=np.zeros_like(p))
    np.testing.assert_allclose(h, expected, atol=1e-12)
    assert ((h >= 0) & (h <= 1)).all()
    idx = entropy_sampling(clf, pool, n_instances=len(pool))
    assert sorted(idx.tolist()) == list(range(len(pool)))
    assert (np.diff(h[idx]) <= 0).all()
    # the most informative is the one whose vote is closest to a half
    assert idx[0] == int(np.argmin(np.abs(p - 0.5)))
    np.testing.assert_array_equal(entropy_sampling(clf, pool, n_instances=3), idx[:3])


def test_ties_keep_the_pool_order(clf):
    trace = np.array([[1, 0, 0], [1, 1, 1]])
    assert entropy_sampling(clf, [trace, trace, trace], n_instances=3).tolist() == [0, 1, 2]


def test_errors(clf):
    with pytest.raises(ValueError, match="entropy_sampling: n_instances must be"):
        entropy_sampling(clf, _pool(3), n_instances=0)
    with pytest.raises(ValueError, match="n_instances=4 is more than the 3 demonstrations"):
        entropy_sampling(clf, _pool(3), n_instances=4)
    with pytest.raises(NotFittedError):
        entropy_sampling(BSIClassifier(), _pool(3))
    with pytest.raises(ValueError, match="X has 2 features"):
        entropy_sampling(clf, [np.ones((2, 2))])
