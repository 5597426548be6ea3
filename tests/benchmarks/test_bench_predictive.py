"""benchmarks/bench_predictive.py: its scores, bins and paired differences against hand counts."""

import math

import numpy as np
import pandas as pd
import pytest
from _scripts import load, needs

pytestmark = needs("bench_predictive.py")


def _load():
    return load("bench_predictive")


def test_scores_clip_as_scikit_learn_and_keep_the_unclipped_log_loss():
    bench = _load()
    y = np.array([1, 0, 1, 0])
    p1 = np.array([1.0, 0.0, 0.75, 1.0])  # the last: certain and wrong
    with np.errstate(divide="ignore"):
        log_p = np.log(np.column_stack([1 - p1, p1]))
    s = bench._scores(y, p1, log_p, (p1 >= 0.5).astype(int))
    eps = np.finfo(float).eps
    assert s["log_loss"] == pytest.approx((-math.log(0.75) - math.log(eps)) / 4, rel=1e-6)
    assert s["log_loss_unclipped"] == math.inf
    assert s["brier"] == pytest.approx((0.0625 + 1.0) / 4)
    assert s["accuracy"] == 0.75


def test_reliability_bins_and_the_worst_gap_over_the_big_bins():
    bench = _load()
    p = np.array([0.05] * 10 + [0.95] * 9 + [0.55])
    y = np.array([0] * 9 + [1] + [1] * 6 + [0] * 3 + [1])
    preds = pd.DataFrame(dict(row="r", noise=0.04, n_train=12, p=p, y=y))
    bins = bench.reliability(preds)
    assert bins["bin"].tolist() == [0, 5, 9]
    assert bins["share"].tolist() == [0.5, 0.05, 0.45]
    assert bins["observed"].tolist() == pytest.approx([0.1, 1.0, 6 / 9])
    # the 0.55 bin holds exactly 5 %: counted, its gap 0.45 the largest
    assert bench.worst_gap(bins)[("r", 0.04, 12)] == pytest.approx(0.45)
    assert bench.worst_gap(bins, min_share=0.1)[("r", 0.04, 12)] == pytest.approx(0.95 - 6 / 9)


def test_paired_differences_are_taken_repeat_by_repeat():
    bench = _load()
    rows = []
    # Every row of the table; each pair's first row is the second's value minus 0.5, 1, 0.5.
    base = {0: 1.0, 1: 2.0, 2: 3.0}
    for noise in (0.0, 0.04):
        for row in bench.ROWS:
            for repeat, value in base.items():
                first = any(row == a for _, a, _ in bench.PAIRS)
                v = value - (0.5, 1.0, 0.5)[repeat] if first else value
                rows.append(dict(row=row, noise=noise, n_train=12, repeat=repeat,
                                 objective="MO1", log_loss=v, brier=v / 10, accuracy=0.5))
    diffs = bench.paired(pd.DataFrame(rows))
    assert len(diffs) == 2 * len(bench.PAIRS)
    d = np.array([-0.5, -1.0, -0.5])
    half = 4.302652729911275 * d.std(ddof=1) / np.sqrt(3)  # t(0.975, 2)
    # No pair's second row is another pair's first, so every difference is d.
    assert not {b for _, _, b in bench.PAIRS} & {a for _, a, _ in bench.PAIRS}
    for _, r in diffs.iterrows():
        assert r.log_loss == pytest.approx(d.mean())
        assert (r.log_loss_low, r.log_loss_high) == pytest.approx((d.mean() - half,
                                                                   d.mean() + half))
        assert r.accuracy == 0.0


def test_a_variant_takes_the_ci_fits_place_and_is_paired_with_the_default(monkeypatch):
    bench = _load()
    for name in ("SETTINGS", "PAIRS"):
        monkeypatch.setattr(bench, name, type(getattr(bench, name))(getattr(bench, name)))
    monkeypatch.setattr(bench, "ROWS", bench.ROWS)
    monkeypatch.setattr(bench, "FIGURE_ROWS", bench.FIGURE_ROWS)
    bench.add_variant({"likelihood": "calibrated", "p_global": 0.2})
    name = "likelihood='calibrated', p_global=0.2"
    assert list(bench.SETTINGS) == ["Default", name]
    assert bench.SETTINGS[name] == ({"likelihood": "calibrated", "p_global": 0.2},
                                    ("predictive, learned",))
    assert f"{name}, predictive, learned" in bench.ROWS
    assert not any(row.startswith("CI") for row in bench.ROWS)
    assert (f"{name} - default (predictive, learned)", f"{name}, predictive, learned",
            "Default, predictive, learned") in bench.PAIRS
    assert (f"{name} - logistic regression", f"{name}, predictive, learned",
            bench.REFERENCE) in bench.PAIRS


def test_variant_and_proposition_options_write_into_out_only():
    bench = _load()
    with pytest.raises(SystemExit):
        bench.main(["--variant", "p_global=0.2"])
    with pytest.raises(SystemExit):
        bench.main(["--propositions", "extended"])
    with pytest.raises(SystemExit):  # a string must be quoted as a Python literal
        bench.main(["--variant", "likelihood=calibrated", "--out", "x"])
