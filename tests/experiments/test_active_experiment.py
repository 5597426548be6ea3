"""`bsi reproduce active --quick`: paired curves, summary, claims and files."""

import numpy as np
import pandas as pd
import pytest

from bsi_sklearn.datasets import make_poi_threat_demos
from bsi_sklearn.experiments.active import active_learning_curve, run_active


@pytest.fixture(scope="module")
def data():
    return make_poi_threat_demos(1, n_demos=3, n_negative=3, random_state=0)


def test_curves_add_one_label_per_fit(data):
    for strategy in ("entropy", "random"):
        curve = active_learning_curve(data, strategy, first=0, n_queries=3, random_state=0)
        assert curve["n_labels"].tolist() == [1, 2, 3, 4]
        queried = curve["queried"].tolist()
        assert queried[-1] == -1 and 0 not in queried and len(set(queried[:-1])) == 3
        assert curve["label"].tolist()[:-1] == data.labels[queried[:-1]].tolist()
        assert ((curve["expected_similarity"] >= 0) & (curve["expected_similarity"] <= 1)).all()
    with pytest.raises(ValueError, match="strategy must be one of"):
        active_learning_curve(data, "greedy", first=0, n_queries=1)


def test_entropy_strategy_asks_the_most_uncertain(data):
    from bsi_sklearn import BSIClassifier
    from bsi_sklearn.active import vote_entropy

    curve = active_learning_curve(data, "entropy", first=0, n_queries=1)
    # the experiment's likelihood: the paper's (CB)
    clf = BSIClassifier(**data.roles, likelihood="cb", random_state=0).fit(
        [data.traces[0]], data.labels[[0]])
    h = vote_entropy(clf, data.traces)
    h[0] = -1
    assert curve["queried"].iloc[0] == int(np.argmax(h))


def test_bsi_reproduce_active_quick(tmp_path, capsys):
    from bsi_sklearn.cli import main

    assert main(["reproduce", "active", "--quick", "--out", str(tmp_path)]) == 0
    printed = capsys.readouterr().out
    assert "AL1-labels" in printed and "claims pass" in printed
    names = {p.name for p in tmp_path.iterdir()}
    assert {"active_curves.csv", "active_summary.csv", "active_claims.csv",
            "active_config.json", "active_report.md", "active_curves.png"} <= names
    curves = pd.read_csv(tmp_path / "active_curves.csv")
    # paired: both strategies start from the same demonstration, so the first fit agrees
    first = curves[curves["n_labels"] == 1].groupby("seed")["entropy"].nunique()
    assert (first == 1).all()
    report = (tmp_path / "active_report.md").read_text()
    assert "Labels until the MAP is the ground truth" in report


def test_run_active_result():
    result = run_active(quick=True, n_seeds=1, n_queries=1)
    assert result.files == [] and result.config["n_seeds"] == 1
    assert set(result.summary["strategy"]) == {"entropy", "random"}
    assert result.claims["status"].isin(["PASS", "FALL SHORT"]).all()
