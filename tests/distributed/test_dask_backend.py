"""Cross-validation and grid search on a dask.distributed cluster give the local results."""

import numpy as np
import pytest
from poi_problems import make_poi_problem
from sklearn.model_selection import GridSearchCV, StratifiedKFold, cross_val_score

from bsi_sklearn import BSIClassifier

distributed = pytest.importorskip("distributed")
joblib = pytest.importorskip("joblib")


@pytest.fixture(scope="module")
def cluster_client():
    # ":0": any free port, so that clusters in parallel test workers never both ask for 8787
    # (None still binds the scheduler's HTTP server there).
    cluster = distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                       dashboard_address=":0", silence_logs=40)
    client = distributed.Client(cluster)
    yield client
    client.close()
    cluster.close()


def test_cross_val_and_grid_search_on_dask_match_local(cluster_client):
    X, y, roles = make_poi_problem(n_demos=24, n_negative=9, seed=21)
    cv = StratifiedKFold(3, shuffle=True, random_state=0)
    est = BSIClassifier(inference="mcmc", n_samples=500, n_chains=2, random_state=0, **roles)
    grid = {"prior": ["sets_of_chains", "forest"], "p_part": [0.2, 0.4]}

    local_scores = cross_val_score(est, X, y, cv=cv, scoring="neg_log_loss", n_jobs=1)
    local_grid = GridSearchCV(est, grid, cv=cv, scoring="neg_log_loss", n_jobs=1).fit(X, y)
    with joblib.parallel_backend("dask"):
        dask_scores = cross_val_score(est, X, y, cv=cv, scoring="neg_log_loss", n_jobs=-1)
        dask_grid = GridSearchCV(est, grid, cv=cv, scoring="neg_log_loss", n_jobs=-1).fit(X, y)
    assert np.array_equal(local_scores, dask_scores)
    assert np.array_equal(local_grid.cv_results_["mean_test_score"],
                          dask_grid.cv_results_["mean_test_score"])
    assert local_grid.best_params_ == dask_grid.best_params_
    # the fits really ran on the worker processes
    loaded = cluster_client.run(lambda: "bsi_sklearn.classifier" in __import__("sys").modules)
    assert len(loaded) == 2 and all(loaded.values())
