"""``bsi-lfe study`` on --quick runs made smaller still (two tiny sizes, a small test set)."""

import contextlib
import io
import json
import re
import shutil

import numpy as np
import pandas as pd
import pytest

from lfe.cli import main
from lfe.study._cells import BSI_ROWS, PRACTITIONER, ROWS, derive_seed, draw_training_set
from lfe.study._stats import t_interval

TINY = ["--quick", "--sizes", "4", "--test-size", "6", "--repeats", "2", "--verbose", "0"]
TABLES = ("study.csv", "study_paired.csv", "study_paired_log_loss.csv", "study_runs.csv",
          "study_warnings.csv")
RAN = list(ROWS)


def _run(argv):
    printed, errors = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(printed), contextlib.redirect_stderr(errors):
        status = main(["study", *argv])
    return status, printed.getvalue(), errors.getvalue()


@pytest.fixture(scope="module")
def tiny_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("study") / "one"
    status, printed, _ = _run([*TINY, "--out", str(out), "--n-jobs", "1"])
    assert status == 0
    return out, printed


def _same_files(a, b):
    for name in (*TABLES, "study.md", "config.json"):
        assert (a / name).read_bytes() == (b / name).read_bytes(), name


def test_files_and_columns(tiny_run):
    out, printed = tiny_run
    for name in (*TABLES, "study.md", "config.json", "study_times.csv",
                 *(f"learning_curve_MO{k}.png" for k in (1, 2, 3))):
        assert (out / name).is_file(), name
    table = pd.read_csv(out / "study.csv")
    assert {"classifier", "objective", "n_train", "noise", "propositions", "mean", "ci_low",
            "ci_high", "n_runs"} <= set(table.columns)
    assert set(table["classifier"]) == set(RAN)
    assert {"Logistic regression", "MiniRocket", "BSI (Prior 2, CI)"} <= set(RAN)
    assert set(table["n_train"]) == {4}
    assert set(table["metric"]) == {"f1", "accuracy", "log_loss", "brier"}
    assert (table["n_runs"] == 2).all()
    paired = pd.read_csv(out / "study_paired.csv")
    assert {"bsi", "best_network", "objective", "n_train", "mean", "ci_low", "ci_high",
            "n_runs", "significant", "best_baseline", "baseline_mean", "baseline_ci_low",
            "baseline_ci_high", "baseline_significant"} <= set(paired.columns)
    assert len(paired) == (len(BSI_ROWS) + 1) * 1 * 3  # BSI rows x sizes x objectives
    runs = pd.read_csv(out / "study_runs.csv")
    for seed in ("dataset_seed", "label_seed", "split_seed", "model_seed"):
        assert runs[seed].notna().all()
    assert runs.groupby("repeat")["dataset_seed"].nunique().eq(1).all()
    assert runs["dataset_seed"].nunique() == 2  # each repeat its own dataset
    text = (out / "study.md").read_text()
    assert "t-interval" in text or "Student-t" in text
    assert "0.04" in text and "ceiling" in text
    assert "BSI minus the best network and minus the best baseline" in printed
    assert "Against the best baseline" in text and "BSI - best baseline" in text


def test_every_mean_inside_its_interval(tiny_run):
    out, _ = tiny_run
    for name in ("study.csv", "study_paired.csv"):
        table = pd.read_csv(out / name)
        # no interval only where no score: the rows without probabilities, for their scores
        blank = table["mean"].isna()
        if name == "study.csv":
            assert set(table[blank]["metric"]) <= {"log_loss", "brier"}
            assert set(table[blank]["classifier"]) == {"MiniRocket", "Noise-free rule (ceiling)"}
        else:
            assert not blank.any()
        table = table[~blank]
        assert (table["ci_low"] <= table["mean"] + 1e-12).all()
        assert (table["mean"] <= table["ci_high"] + 1e-12).all()
    table = pd.read_csv(out / "study.csv")
    f1 = table[table["metric"] == "f1"]
    assert f1["mean"].between(0, 1).all()
    ceiling = f1[f1["classifier"] == "Noise-free rule (ceiling)"]
    assert (ceiling["mean"] > 0.5).all()


def test_n_jobs_2_writes_identical_files(tiny_run, tmp_path):
    out, _ = tiny_run
    status, _, _ = _run([*TINY, "--out", str(tmp_path), "--n-jobs", "2"])
    assert status == 0
    _same_files(out, tmp_path)


def test_resume_runs_only_missing_cells(tiny_run, tmp_path):
    out, _ = tiny_run
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    for name in (*TABLES, "study.md"):
        (copy / name).unlink()
    cells = sorted((copy / "cells").glob("*.json"))
    assert len(cells) == 2
    kept = {p.name: p.stat().st_mtime_ns for p in cells[1:]}
    cells[0].unlink()
    status, _, _ = _run([*TINY, "--out", str(copy)])
    assert status == 0
    _same_files(out, copy)
    assert {p.name: p.stat().st_mtime_ns for p in cells[1:]} == kept  # not recomputed
    # other arguments into the same directory: refused, nothing overwritten
    status, _, err = _run([*TINY[:-2], "--repeats", "3", "--verbose", "0", "--out", str(copy)])
    assert status == 2 and "other arguments" in err


def test_each_repeat_is_simulated_once_for_all_its_cells(tmp_path, monkeypatch):
    import lfe.study

    real, simulated, seen = lfe.study.simulate_repeat, [], []
    real_cell = lfe.study.run_cell

    def counting(**kwargs):
        simulated.append(kwargs["dataset_seed"])
        return real(**kwargs)

    def cell(data, **kwargs):
        seen.append(id(data["clean"]))  # the repeat's own arrays, not a fresh simulation
        return real_cell(data, **kwargs)

    monkeypatch.setattr(lfe.study, "simulate_repeat", counting)
    monkeypatch.setattr(lfe.study, "run_cell", cell)
    status, _, _ = _run(["--quick", "--sizes", "3,4", "--noise", "0,0.04", "--test-size", "4",
                         "--repeats", "1", "--verbose", "0", "--out", str(tmp_path)])
    assert status == 0
    assert len(simulated) == 1 and len(seen) == 4 and len(set(seen)) == 1


SIZES = ("must be a non-empty list of distinct integers in [2, 500] (a repeat simulates at "
         "most 500 training missions), got ")
NOISE = ("must be a non-empty list of distinct numbers in [0, 0.5] (probabilities of flipping a "
         "verdict), got ")
SETS = "must be a non-empty list of distinct proposition sets among ['extended', 'paper'], got "
OUT = "must be a directory, or a path where one can be made (not a file), got "


def _no_simulation(monkeypatch):
    import lfe.study._cells

    def boom(**kwargs):
        raise AssertionError("simulated despite a bad argument")

    monkeypatch.setattr(lfe.study._cells, "simulate_repeat", boom)
    monkeypatch.setattr("lfe.study.simulate_repeat", boom)


# Issue 22: the study's arguments go through bsi_sklearn.param_validation (before: hand checks
# beside it); the command line names its options as typed, the function its parameters.
@pytest.mark.parametrize("argv, message", [
    (["--sizes", "3,600"], "--sizes " + SIZES + "[3, 600]"),
    (["--sizes", "1"], "--sizes " + SIZES + "[1]"),
    (["--sizes", "4,4"], "--sizes " + SIZES + "[4, 4]"),
    (["--sizes", ","], "--sizes " + SIZES + "[]"),
    (["--noise", "-0.1"], "--noise " + NOISE + "[-0.1]"),
    (["--noise", "0.7"], "--noise " + NOISE + "[0.7]"),
    (["--noise", "0,0.0"], "--noise " + NOISE + "[0.0, 0.0]"),
    (["--propositions", "paper,nope"], "--propositions " + SETS + "['paper', 'nope']"),
    (["--repeats", "0"], "--repeats must be an integer >= 1, got 0"),
    (["--test-size", "1"], "--test-size must be an integer in [2, 5000], got 1"),
    (["--seed", "-1"], "--seed must be an integer in [0, 4294967295], got -1"),
    (["--n-jobs", "0"], "--n-jobs must be a non-zero integer, got 0"),
    (["--verbose", "-1"], "--verbose must be an integer >= 0, got -1"),
    (["--sizes", "3,x"], "cannot read '3,x' as a comma-separated list of int"),
])
def test_bad_arguments_rejected_before_simulation(argv, message, tmp_path, monkeypatch):
    _no_simulation(monkeypatch)
    status, _, err = _run(["--quick", "--verbose", "0", "--out", str(tmp_path / "o"), *argv])
    assert status == 2
    assert err == f"bsi-lfe study: error: {message}\n"
    assert not (tmp_path / "o").exists()


def test_an_out_that_is_a_file_is_rejected(tmp_path, monkeypatch):
    _no_simulation(monkeypatch)
    (tmp_path / "f").write_text("mine")
    status, _, err = _run(["--quick", "--verbose", "0", "--out", str(tmp_path / "f")])
    assert status == 2 and err == f"bsi-lfe study: error: --out {OUT}{str(tmp_path / 'f')!r}\n"
    assert (tmp_path / "f").read_text() == "mine"


@pytest.mark.parametrize("kwargs, message", [
    ({"sizes": [3, 600]}, "sizes " + SIZES + "[3, 600]"),
    ({"sizes": (1, 4)}, "sizes " + SIZES + "[1, 4]"),
    ({"sizes": [4, 4]}, "sizes " + SIZES + "[4, 4]"),
    ({"sizes": []}, "sizes " + SIZES + "[]"),
    ({"sizes": [4.0]}, "sizes " + SIZES + "[4.0]"),
    ({"sizes": 4}, "sizes " + SIZES + "4"),
    ({"repeats": 0}, "repeats must be an integer >= 1, got 0"),
    ({"repeats": True}, "repeats must be an integer >= 1, got True"),
    ({"test_size": 5001}, "test_size must be an integer in [2, 5000], got 5001"),
    ({"noise": [float("nan")]}, "noise " + NOISE + "[nan]"),
    ({"noise": (0.04, 0.04)}, "noise " + NOISE + "[0.04, 0.04]"),
    ({"noise": [0.6]}, "noise " + NOISE + "[0.6]"),
    ({"propositions": "paper"}, "propositions " + SETS + "'paper'"),
    ({"propositions": ["paper", "paper"]}, "propositions " + SETS + "['paper', 'paper']"),
    ({"seed": 2**32}, "seed must be an integer in [0, 4294967295], got 4294967296"),
    ({"n_jobs": 0}, "n_jobs must be None or a non-zero integer, got 0"),
    ({"n_jobs": 1.5}, "n_jobs must be None or a non-zero integer, got 1.5"),
    ({"out": 3}, "out " + OUT + "3"),
    ({"verbose": -1}, "verbose must be an integer >= 0, got -1"),
])
def test_study_names_each_bad_argument(kwargs, message, tmp_path, monkeypatch):
    from bsi_sklearn.param_validation import InvalidParameterError
    from lfe.study import study

    _no_simulation(monkeypatch)
    with pytest.raises(ValueError) as caught:
        study(**{"quick": True, "out": tmp_path / "o", **kwargs})
    assert isinstance(caught.value, InvalidParameterError)
    assert str(caught.value) == f"study: {message}"
    assert not (tmp_path / "o").exists()


def test_study_arguments_are_normalised(tmp_path, monkeypatch):
    # iterables are read once: a generator of sizes is validated and used, not exhausted
    import numpy as np

    from lfe.study import study

    _no_simulation(monkeypatch)
    with pytest.raises(AssertionError, match="simulated despite"):
        study(sizes=(n for n in (8, 4)), noise=np.array([0.04]), repeats=np.int64(1),
              test_size=4, quick=True, out=tmp_path, verbose=0)
    config = json.loads((tmp_path / "config.json").read_text())
    assert (config["sizes"], config["noise"], config["repeats"]) == ([4, 8], [0.04], 1)


def test_t_interval_and_seeds():
    mean, low, high = t_interval([0.5, 0.7, 0.6])
    assert mean == pytest.approx(0.6)
    assert high - mean == pytest.approx(4.302653 * 0.1 / np.sqrt(3), rel=1e-5)
    assert np.isnan(t_interval([0.4])[1])
    assert t_interval([0.3, 0.3]) == (0.3, 0.3, 0.3)
    assert derive_seed(0, 1, 2) == derive_seed(0, 1, 2) != derive_seed(0, 2, 1)
    clean = np.array([[1, 0, 1]] * 6 + [[0, 1, 1]] * 6)
    train = draw_training_set(clean, 12, 4, seed=0)
    assert len(train) == 4 and clean[train, 0].sum() == 2  # stratified
    assert list(draw_training_set(clean, 12, 12, seed=0)) == list(range(12))


def test_dask_local_cluster_matches_local(tiny_run, tmp_path):
    distributed = pytest.importorskip("distributed")
    joblib = pytest.importorskip("joblib")
    from lfe.study import study

    out, _ = tiny_run
    config = json.loads((out / "config.json").read_text())
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=":0", silence_logs=40) as cluster, \
            distributed.Client(cluster) as client:
        with joblib.parallel_backend("dask"):
            study(sizes=config["sizes"], repeats=config["repeats"],
                  test_size=config["test_size"], quick=True, n_jobs=-1, out=tmp_path,
                  verbose=0)
        ran = client.run(lambda: "lfe.study._cells" in __import__("sys").modules)
    _same_files(out, tmp_path)
    assert len(ran) == 2 and any(ran.values())


@pytest.mark.parametrize("kind", ["EROFS", "full:1", "full:4"])
def test_a_failed_write_leaves_the_previous_study(tiny_run, tmp_path, kind):
    # Before: the tables, study.md and the figures were written one by one, in place, so a
    # disk that filled up half-way left new tables beside the previous figures.
    import errno

    from _faults import full_after, read_only, snapshot, temporaries

    out, _ = tiny_run
    copy = tmp_path / "copy"
    shutil.copytree(out, copy)
    for path in copy.iterdir():  # the outputs (not the cells nor config.json, which resume)
        if path.is_file() and path.name != "config.json":
            path.write_bytes(b"previous " + path.name.encode())
    before = snapshot(copy)
    fault = (read_only(copy, errno.EROFS) if kind == "EROFS"
             else full_after(copy, int(kind[5:])))
    with fault:
        status, _, err = _run([*TINY, "--out", str(copy)])
    assert status == 2
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, err
    assert str(copy) in err and ".tmp" not in err
    assert snapshot(copy) == before and temporaries(copy) == []


def test_best_baseline_is_the_best_of_networks_and_practitioner_rows(tiny_run):
    out, _ = tiny_run
    runs = pd.read_csv(out / "study_runs.csv")
    paired = pd.read_csv(out / "study_paired.csv")
    baselines = [r for r in RAN if r in (*PRACTITIONER, "LSTM", "Bi-LSTM", "LSTM Coupled",
                                         "Bi-LSTM Coupled")]
    for _, r in paired.iterrows():
        cell = runs[(runs["objective"] == r["objective"]) & (runs["n_train"] == r["n_train"])]
        means = cell.groupby("classifier")["f1"].mean()
        assert means[r["best_baseline"]] == pytest.approx(means[baselines].max(), abs=1e-5)
        assert means[r["best_baseline"]] >= means[r["best_network"]] - 1e-12
        diff = (cell[cell["classifier"] == r["bsi"]]["f1"].to_numpy()
                - cell[cell["classifier"] == r["best_baseline"]]["f1"].to_numpy())
        assert r["baseline_mean"] == pytest.approx(diff.mean(), abs=1e-5)  # %.6g in the CSV


def test_log_loss_is_scikit_learns_on_the_rows_probabilities(tiny_run):
    # one cell recomputed outside the study: its missions, training draw and seeds from
    # study_runs.csv, the logistic regression and BSI refitted, scored by scikit-learn
    from sklearn.metrics import brier_score_loss, log_loss

    from baselines.practitioner import TemporalLogisticRegression
    from lfe.compare import fit_bsi
    from lfe.study import simulate_repeat
    from lfe.study._cells import bsi_settings

    out, _ = tiny_run
    runs = pd.read_csv(out / "study_runs.csv")
    table = pd.read_csv(out / "study.csv")
    cell = runs[runs["repeat"] == 0]
    seeds = cell.iloc[0]
    data = simulate_repeat(n_pool=4, test_size=6, noises=[0.04], propositions=["paper"],
                           dataset_seed=int(seeds["dataset_seed"]),
                           label_seed=int(seeds["label_seed"]))
    train = draw_training_set(data["clean"], 4, 4, int(seeds["split_seed"]))
    test = np.arange(4, 10)
    props, y = data["props"]["paper"], data["labels"][0.04]
    X_train, X_test = [props[i] for i in train], [props[i] for i in test]
    model_seed = int(seeds["model_seed"])
    logistic = TemporalLogisticRegression(random_state=model_seed).fit(X_train, y[train])
    scored = 0
    for k, mo in enumerate(("MO1", "MO2", "MO3")):
        proba = logistic.predict_proba(X_test)[k]
        labels = list(logistic.classes_[k])
        p1 = proba[:, labels.index(1)] if 1 in labels else np.zeros(len(test))
        bsi = fit_bsi("BSI (Prior 2)", X_train, y[train, k], data["roles"]["paper"],
                       bsi_settings(True), model_seed)
        for name, p in (("Logistic regression", p1),
                        ("BSI (Prior 2)", None if bsi is None
                         else bsi.predict_proba(X_test)[:, 1])):
            row = cell[(cell["classifier"] == name) & (cell["objective"] == mo)].iloc[0]
            if p is None:  # BSI could not fit (no acceptable mission): no score
                assert np.isnan(row["log_loss"]) and np.isnan(row["brier"])
                continue
            scored += 1
            assert row["log_loss"] == pytest.approx(log_loss(y[test, k], p, labels=[0, 1]),
                                                    rel=1e-5)  # %.6g in the CSV
            assert row["brier"] == pytest.approx(brier_score_loss(y[test, k], p, labels=[0, 1]),
                                                 rel=1e-5, abs=1e-12)
        # the summary's mean and interval are over the repeats, as the F1's
        line = table[(table["classifier"] == "Logistic regression") & (table["objective"] == mo)
                     & (table["metric"] == "log_loss")].iloc[0]
        values = runs[(runs["classifier"] == "Logistic regression")
                      & (runs["objective"] == mo)]["log_loss"]
        np.testing.assert_allclose([line["mean"], line["ci_low"], line["ci_high"]],
                                   t_interval(values), rtol=1e-5)
    assert scored >= 3  # every logistic objective, and BSI where it fitted
    # the rows without probabilities: n/a in study.md, empty in the tables
    for name in ("MiniRocket", "Noise-free rule (ceiling)"):
        assert runs[runs["classifier"] == name][["log_loss", "brier"]].isna().all().all()
    text = (out / "study.md").read_text()
    section = text.split("## Mean log loss")[1].split("## Mean Brier")[0]
    assert "| MiniRocket | n/a | n/a | n/a |" in section
    assert "| Noise-free rule (ceiling) | n/a | n/a | n/a |" in section
    assert re.search(r"\| Logistic regression \| \d+\.\d{3} \[", section)


def test_paired_log_loss_is_against_the_lowest_baseline_with_probabilities(tiny_run):
    out, _ = tiny_run
    runs = pd.read_csv(out / "study_runs.csv")
    paired = pd.read_csv(out / "study_paired_log_loss.csv")
    assert len(paired) == (len(BSI_ROWS) + 1) * 1 * 3 and set(paired["metric"]) == {"log_loss"}
    networks = ["LSTM", "Bi-LSTM", "LSTM Coupled", "Bi-LSTM Coupled"]
    for _, r in paired.iterrows():
        cell = runs[(runs["objective"] == r["objective"]) & (runs["n_train"] == r["n_train"])]
        means = cell.groupby("classifier")["log_loss"].mean()
        # a loss: the lowest mean is the best; MiniRocket has none and is never chosen
        assert r["best_network"] == means[networks].idxmin()
        assert r["best_baseline"] == means[[*networks, "Logistic regression"]].idxmin()
        diff = (cell[cell["classifier"] == r["bsi"]]["log_loss"].to_numpy()
                - cell[cell["classifier"] == r["best_baseline"]]["log_loss"].to_numpy())
        assert r["baseline_mean"] == pytest.approx(diff.mean(), rel=1e-4, abs=1e-5)
    text = (out / "study.md").read_text()
    assert "(log loss, lower is better, paired)" in text


def test_warnings_are_counted_per_cell_and_row(tiny_run):
    out, _ = tiny_run
    for path in (out / "cells").glob("*.json"):
        stored = json.loads(path.read_text())
        assert isinstance(stored["warnings"], list)
        for row in stored["rows"]:
            assert row["warnings"] == sum(w["count"] for w in stored["warnings"]
                                          if w["classifier"] == row["classifier"])
    runs = pd.read_csv(out / "study_runs.csv")
    assert (runs["warnings"] >= 0).all()
    warned = pd.read_csv(out / "study_warnings.csv")
    assert list(warned.columns) == ["repeat", "noise", "propositions", "n_train",
                                    "classifier", "category", "message", "count"]
    assert "## Warnings raised while fitting and scoring" in (out / "study.md").read_text()


def test_a_warning_raised_in_a_cell_goes_into_its_files(tmp_path, monkeypatch):
    # Before: the study silenced ConvergenceWarning; now every warning is counted, none hidden.
    import warnings

    import baselines.practitioner as practitioner

    real = practitioner.TemporalLogisticRegression.fit

    def warning_fit(self, X, y):
        warnings.warn("a warning from the logistic row", RuntimeWarning, stacklevel=2)
        warnings.warn("a warning from the logistic row", RuntimeWarning, stacklevel=2)
        return real(self, X, y)

    monkeypatch.setattr(practitioner.TemporalLogisticRegression, "fit", warning_fit)
    status, printed, _ = _run([*TINY, "--repeats", "1", "--out", str(tmp_path)])
    assert status == 0
    (cell,) = (tmp_path / "cells").glob("*.json")
    stored = json.loads(cell.read_text())
    assert {"classifier": "Logistic regression", "category": "RuntimeWarning",
            "message": "a warning from the logistic row", "count": 2} in stored["warnings"]
    runs = pd.read_csv(tmp_path / "study_runs.csv")
    assert (runs[runs["classifier"] == "Logistic regression"]["warnings"] == 2).all()
    warned = pd.read_csv(tmp_path / "study_warnings.csv")
    row = warned[warned["classifier"] == "Logistic regression"].iloc[0]
    assert row["count"] == 2 and row["category"] == "RuntimeWarning"
    assert "Logistic regression RuntimeWarning x2" in printed
    assert "a warning from the logistic row" in (tmp_path / "study.md").read_text()
