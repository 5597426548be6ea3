"""``bsi-lfe compare``: the paper's LFE comparison, on --quick runs (a few seconds each)."""

import contextlib
import copy
import io
import re
import warnings
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import pytest
from sklearn.metrics import brier_score_loss, f1_score, log_loss

from lfe import make_lfe_dataset
from lfe.cli import main
from lfe.compare import (
    BSI_ROWS,
    CLASSIFIERS,
    MAJORITY,
    PAPER_F1,
    PAPER_MAP_F1,
    ROWS,
    compare,
)
from lfe.compare._protocol import _folds, weighted_f1

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
PAPER = Path(__file__).parents[2] / ".." / "shared" / "paper"
RAN = list(ROWS)
FILES = ("f1_table.csv", "f1_table.md", "f1_table.tex", "f1_bars.png", "times.csv",
         "map_f1.csv", "probabilities.csv")


@pytest.fixture(scope="module")
def quick_run(tmp_path_factory):
    """``bsi-lfe compare --quick`` (8 scenarios, 2 folds): output directory, status, stdout."""
    out = tmp_path_factory.mktemp("compare")
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        status = main(["compare", "--quick", "--out", str(out), "--verbose", "0"])
    return out, status, printed.getvalue()


@pytest.fixture(scope="module")
def quick_labels():
    """The labels of ``--quick``'s dataset, in the order of its files."""
    from lfe._settings import COMPARE_QUICK

    ds = make_lfe_dataset(COMPARE_QUICK["n_scenarios"], random_state=0)
    return ds.labels.set_axis(pd.Index(ds.scenario_ids, name="scenario_id"))


@pytest.fixture(scope="module")
def small_dataset():
    return make_lfe_dataset(n_scenarios=5, random_state=1)


@pytest.fixture(scope="module")
def small_run(small_dataset):
    return compare(small_dataset, quick=True, seed=3, verbose=0)


def test_quick_run_writes_every_file(quick_run):
    out, status, _ = quick_run
    assert status == 0
    for name in FILES:
        assert (out / name).is_file(), name
    table = pd.read_csv(out / "f1_table.csv", index_col="classifier")
    assert list(table.index) == RAN
    assert {"BSI (Prior 2, CI)", "Logistic regression", "MiniRocket", MAJORITY} <= set(RAN)
    for mo in ("MO1", "MO2", "MO3"):
        assert table[mo].between(0, 1).all()
        assert table[f"{mo} fold mean"].between(0, 1).all()
        # the paper's column is the paper's table, empty for the reference row
        np.testing.assert_allclose(table.loc[list(CLASSIFIERS), f"{mo} paper"],
                                   PAPER_F1[mo].to_numpy())
        assert table.loc[[r for r in RAN if r not in CLASSIFIERS], f"{mo} paper"].isna().all()
    md = (out / "f1_table.md").read_text(encoding="utf-8")
    for name in RAN:
        assert f"| {name} |" in md
    assert "paper" in md
    tex = (out / "f1_table.tex").read_text(encoding="utf-8")
    assert r"\begin{tabular}" in tex and r"\end{tabular}" in tex
    # two tables (F1; log loss and Brier), each two header rows and one per row
    assert tex.count(r"\begin{tabular}") == 2 and tex.count(r"\\") == 2 * (2 + len(RAN))
    png = (out / "f1_bars.png").read_bytes()
    assert png[:8] == PNG_SIGNATURE and len(png) > 10_000
    times = pd.read_csv(out / "times.csv", index_col="classifier")
    assert list(times.index) == RAN
    assert (times[["fit_s_mean", "predict_s_mean"]] >= 0).all().all()
    map_f1 = pd.read_csv(out / "map_f1.csv")
    assert list(dict.fromkeys(map_f1["classifier"])) == list(BSI_ROWS)
    assert map_f1["f1"].between(0, 1).all() and len(map_f1) == 3 * len(BSI_ROWS)
    prior2 = map_f1[map_f1["classifier"] == "BSI (Prior 2)"].set_index("objective")
    assert prior2["paper"].to_dict() == PAPER_MAP_F1["BSI (Prior 2)"]


def test_quick_run_prints_table_beside_papers(quick_run):
    printed = quick_run[2]
    assert "paper" in printed and "Shah et al." in printed
    for name in RAN:
        assert re.search(rf"^{re.escape(name)}\s+\d\.\d{{3}}", printed, re.M), name
    assert "0.674" in printed and "0.877" in printed  # the paper's BSI numbers
    assert "--quick" in printed  # a quick run says it is not the paper's setting


def test_quick_run_files_say_they_are_a_smoke_test(quick_run, small_run):
    # the --quick files look like the recorded ones: each human-read file says what it is
    out = quick_run[0]
    md = (out / "f1_table.md").read_text(encoding="utf-8")
    tex = (out / "f1_table.tex").read_text(encoding="utf-8")
    assert md.startswith("> QUICK RUN (bsi-lfe compare --quick): a smoke test, not the "
                         "recorded result.")
    assert tex.startswith("% QUICK RUN (bsi-lfe compare --quick)")
    fig = small_run.plot()
    try:
        assert "(--quick: a smoke test)" in fig.axes[0].get_title()
    finally:
        plt.close(fig)
    # a full run's files carry no such notice
    full = copy.copy(small_run)
    full.config = {**small_run.config, "quick": False}
    assert "QUICK" not in full.to_markdown() + full.to_latex()


def test_log_loss_and_brier_are_scikit_learns_on_the_saved_probabilities(quick_run,
                                                                        quick_labels):
    out = quick_run[0]
    table = pd.read_csv(out / "f1_table.csv", index_col="classifier")
    proba = pd.read_csv(out / "probabilities.csv", header=[0, 1], index_col=0)
    md = (out / "f1_table.md").read_text(encoding="utf-8")
    calibration = md.split("### Log loss and Brier score")[1].split("###")[0]
    scored = set()
    for name in RAN:
        cells = []
        for mo in ("MO1", "MO2", "MO3"):
            p1 = proba[(name, mo)].to_numpy(dtype=float)
            y = quick_labels[mo].to_numpy()
            if np.isnan(p1).any():  # no probabilities (from some fold): n/a, not a number
                assert np.isnan(table.loc[name, [f"{mo} log loss", f"{mo} Brier"]]).all()
                cells += ["n/a", "n/a"]
                continue
            scored.add(name)
            # every digit is in the file: the table's scores are exactly sklearn's
            assert table.loc[name, f"{mo} log loss"] == pytest.approx(
                log_loss(y, p1, labels=[0, 1]), rel=1e-5)
            assert table.loc[name, f"{mo} Brier"] == pytest.approx(
                brier_score_loss(y, p1, labels=[0, 1]), rel=1e-5)
            cells += [f"{table.loc[name, f'{mo} log loss']:.3f}",
                      f"{table.loc[name, f'{mo} Brier']:.3f}"]
        assert f"| {name} | {' | '.join(cells)} |" in calibration, name
    # the rows with probabilities are scored, the ridge classifier is n/a throughout
    assert {"BSI (Prior 2)", "Logistic regression", "LSTM", MAJORITY} <= scored
    assert "MiniRocket" not in scored
    assert "| MiniRocket | " + " | ".join(["n/a"] * 6) + " |" in calibration
    assert table.loc["MiniRocket", [c for c in table.columns if "log loss" in c]].isna().all()


def _assert_same_tables(a, b):
    pd.testing.assert_frame_equal(a.table, b.table, check_exact=True)
    pd.testing.assert_frame_equal(a.map_f1, b.map_f1, check_exact=True)
    pd.testing.assert_frame_equal(a.predictions, b.predictions, check_exact=True)
    # the CSV files are these tables
    assert a.table.to_csv(float_format="%.6g") == b.table.to_csv(float_format="%.6g")


def test_same_seed_same_tables(small_dataset, small_run):
    again = compare(small_dataset, quick=True, seed=3, verbose=0)
    _assert_same_tables(small_run, again)
    # the times differ from run to run, their layout does not
    assert list(again.times.index) == list(small_run.times.index)
    assert list(again.times.columns) == list(small_run.times.columns)


@pytest.mark.slow  # two worker processes import torch and numba: 5-25 s
def test_n_jobs_does_not_change_the_tables(small_dataset, small_run):
    parallel = compare(small_dataset, quick=True, seed=3, n_jobs=2, verbose=0)
    _assert_same_tables(small_run, parallel)
    assert parallel.config["n_jobs"] == 2


def test_result_is_consistent_with_its_predictions(small_dataset, small_run):
    res, labels = small_run, small_dataset.labels
    fold = res.predictions[("fold", "")].to_numpy()
    assert sorted(np.bincount(fold).tolist()) == [2, 3]  # every scenario tested exactly once
    for f, (train, test) in enumerate(res.folds):
        assert len(train) + len(test) == 5 and not set(train) & set(test)
        assert (fold[test] == f).all()
    for name in RAN:
        for mo in labels.columns:
            pred = res.predictions[(name, mo)].to_numpy()
            assert set(pred.tolist()) <= {0, 1}
            expected = f1_score(labels[mo], pred, average="weighted", zero_division=0.0)
            assert res.f1.loc[name, mo] == pytest.approx(expected)
            folds = res.f1_folds.query("classifier == @name and objective == @mo")
            assert len(folds) == 2
            assert res.table.loc[name, f"{mo} fold mean"] == pytest.approx(folds["f1"].mean())
    # the reference row predicts each training fold's most frequent outcome, with the
    # fold's base rate as its probability
    for train, test in res.folds:
        for mo in labels.columns:
            counts = np.bincount(labels[mo].to_numpy()[train], minlength=2)
            assert (res.predictions[(MAJORITY, mo)].to_numpy()[test] == counts.argmax()).all()
            np.testing.assert_allclose(res.probabilities[(MAJORITY, mo)].to_numpy()[test],
                                       counts[1] / counts.sum())
    assert res.config["n_splits"] == 2 and res.config["quick"] and res.config["seed"] == 3
    assert "5 scenarios" in repr(res)
    md, tex = res.to_markdown(), res.to_latex()
    # F1 table, log loss and Brier, fold table, MAP table (one row per objective), times
    assert md.count("| BSI (Prior 2) |") == 1 + 1 + 1 + 3 + 1
    assert tex.count("BSI (Prior 3)") == 2  # F1; log loss and Brier


def test_weighted_f1_matches_scikit_learn():
    rng = np.random.default_rng(0)
    for n in (1, 2, 6, 24):
        for _ in range(20):
            y_true, y_pred = rng.integers(0, 2, n), rng.integers(0, 2, n)
            if rng.random() < 0.3:
                y_pred[:] = y_pred[0]
            if rng.random() < 0.3:
                y_true[:] = y_true[0]
            assert weighted_f1(y_true, y_pred) == pytest.approx(
                f1_score(y_true, y_pred, average="weighted", zero_division=0.0))


def test_folds_are_stratified_and_seeded():
    labels = pd.DataFrame({"MO1": [1] * 18 + [0] * 6, "MO2": [1, 0] * 12, "MO3": [1] * 24})
    folds, split = _folds(labels, 4, seed=0)
    assert "Stratified" in split
    assert [len(te) for _, te in folds] == [6] * 4  # 18 training / 6 test, as in the paper
    for _, te in folds:
        assert labels["MO1"].to_numpy()[te].sum() == 18 // 4 or \
            labels["MO1"].to_numpy()[te].sum() == 18 // 4 + 1
    again, _ = _folds(labels, 4, seed=0)
    other, _ = _folds(labels, 4, seed=1)
    assert all((a[1] == b[1]).all() for a, b in zip(folds, again))
    assert any((a[1] != b[1]).any() for a, b in zip(folds, other))


def _labels_with_counts(counts, seed):
    """Shuffled MO1-MO3 labels with ``counts[code]`` missions of each outcome combination."""
    codes = np.random.RandomState(seed).permutation(np.repeat(np.arange(8), counts))
    bits = (codes[:, None] >> np.arange(3)) & 1
    return pd.DataFrame(bits, columns=["MO1", "MO2", "MO3"]), codes


@pytest.mark.parametrize("counts, n_splits", [
    ([2, 2, 2, 4, 2, 4, 0, 8], 4),   # the built-in 24 missions: four rare combinations
    ([1, 1, 0, 0, 1, 2, 0, 3], 2),   # --quick's 8 simulated missions
    ([6, 0, 0, 6, 0, 0, 0, 12], 4),  # no rare combination
    ([5, 0, 3, 0, 0, 0, 0, 0], 3),   # one
])
@pytest.mark.parametrize("seed", [0, 1, 7])
def test_folds_are_stratified_kfolds_without_its_warning(counts, n_splits, seed):
    from sklearn.model_selection import StratifiedKFold

    labels, codes = _labels_with_counts(counts, seed)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the split itself warns about nothing
        folds, split = _folds(labels, n_splits, seed)
    rare = min(c for c in counts if c) < n_splits
    assert ("spread as evenly as possible" in split) == rare
    # the same folds as scikit-learn's (which warns when a combination is rare), so the
    # recorded tables are reproduced
    splitter = StratifiedKFold(n_splits, shuffle=True, random_state=seed)
    with (pytest.warns(UserWarning, match="least populated class") if rare
          else contextlib.nullcontext()):
        expected = list(splitter.split(codes, codes))
    assert len(folds) == n_splits
    for (train, test), (e_train, e_test) in zip(folds, expected):
        np.testing.assert_array_equal(test, e_test)
        np.testing.assert_array_equal(train, e_train)


def test_folds_fall_back_to_kfold_when_every_combination_is_rare():
    labels, _ = _labels_with_counts([1, 2, 0, 0, 0, 0, 0, 1], 0)
    folds, split = _folds(labels, 3, seed=0)
    assert split == "KFold, shuffled"
    assert sorted(np.concatenate([te for _, te in folds]).tolist()) == list(range(4))


@pytest.mark.parametrize("argv, message", [
    (["--dataset", "no/such/dataset"], "no/such/dataset"),
    (["--folds", "1"], "--folds must be an integer >= 2, got 1"),
    (["--n-scenarios", "3", "--folds", "4"], "n_splits=4"),
    (["--dataset", "x", "--n-scenarios", "4"], "either --dataset or --n-scenarios"),
])
def test_bad_arguments_fail_clearly(argv, message, tmp_path, capsys):
    status = main(["compare", "--quick", "--out", str(tmp_path / "out"), "--verbose", "0",
                   *argv])
    assert status != 0
    assert message in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


def test_compare_rejects_bad_input():
    with pytest.raises(ValueError, match="LFEDataset"):
        compare("results", quick=True, verbose=0)
    ds = make_lfe_dataset(n_scenarios=2, random_state=0)
    with pytest.raises(ValueError, match="n_jobs"):
        compare(ds, quick=True, n_jobs=0, verbose=0)
    with pytest.raises(ValueError, match="seed"):
        compare(ds, quick=True, seed=-1, verbose=0)


@pytest.mark.skipif(not PAPER.is_dir(), reason="../shared/paper is absent")
def test_paper_numbers_are_the_papers():
    tex = "\n".join(p.read_text(encoding="utf-8") for p in PAPER.glob("*.tex"))
    for name in CLASSIFIERS:
        row = re.search(rf"^\s*{re.escape(name)}\s*&(.*)\\\\", tex, re.M)
        assert row, name
        numbers = [float(re.sub(r"[^0-9.]", "", cell)) for cell in row.group(1).split("&")]
        assert numbers == PAPER_F1.loc[name].tolist(), name
    sentence = re.search(r"F1 scores obtained were ([0-9.]+), ([0-9.]+), and ([0-9.]+)", tex)
    assert [float(v) for v in sentence.groups()] == list(PAPER_MAP_F1["BSI (Prior 2)"].values())


def test_cli_parser_does_not_import_torch():
    import subprocess
    import sys

    code = ("import sys; from lfe.cli import build_parser; build_parser(); "
            "print('torch' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stdout.strip()
    assert out == "False"


def test_practitioner_rows_share_the_folds(small_dataset, small_run):
    # the logistic row is refitted here fold by fold: the same predictions as in the table
    from baselines.practitioner import TemporalLogisticRegression
    from lfe import LFEPropositionExtractor

    props = LFEPropositionExtractor().fit_transform(small_dataset.scenarios)
    labels = small_dataset.labels[["MO1", "MO2", "MO3"]].to_numpy()
    seeds = np.random.RandomState(3).randint(np.iinfo(np.int32).max, size=2)
    for f, (train, test) in enumerate(small_run.folds):
        clf = TemporalLogisticRegression(random_state=int(seeds[f]))
        pred = clf.fit([props[i] for i in train], labels[train]).predict([props[i] for i in test])
        for k, mo in enumerate(("MO1", "MO2", "MO3")):
            np.testing.assert_array_equal(
                small_run.predictions[("Logistic regression", mo)].to_numpy()[test], pred[:, k])
