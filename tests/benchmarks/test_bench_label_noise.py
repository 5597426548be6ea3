"""benchmarks/bench_label_noise.py: one fit read both ways, and the report's paired columns."""


import numpy as np
import pandas as pd
import pytest
from _scripts import load, needs

pytestmark = needs("bench_label_noise.py")


def _load():
    return load("bench_label_noise")


def test_both_readings_come_from_one_fit(tmp_path):
    from sklearn.metrics import log_loss

    bench = _load()
    preds = []
    rows = bench.roles_tasks([0], preds, sizes=(20,), noises=(0.1,))
    by = {r["reading"]: r for r in rows if r["case"].startswith("errand")}
    assert set(by) == {"learned", "epsilon"}
    assert by["learned"]["fit_s"] == by["epsilon"]["fit_s"]  # the same fit
    assert by["learned"]["accuracy"] == by["epsilon"]["accuracy"]
    # CB's epsilon (2^-4M) leaves near-certain probabilities; the learned rate does not.
    assert by["learned"]["log_loss"] < by["epsilon"]["log_loss"]
    # the kept test predictions are the scored ones: the reliability diagram reads them
    preds = pd.concat(preds, ignore_index=True)
    for reading, row in by.items():
        mine = preds[(preds["case"] == row["case"]) & (preds["reading"] == reading)]
        assert len(mine) == 300
        assert log_loss(mine["y"], mine["p"], labels=[0, 1]) == pytest.approx(row["log_loss"])
    bins = bench.reliability_bins(preds, ["family", "reading"])
    assert set(bins["family"]) == {"roles tasks, 10% flipped"}
    assert bins.groupby("reading")["n"].sum().eq(len(preds) // 2).all()
    (path,) = bench.figures(bins, tmp_path)
    assert path.name == "reliability_roles_tasks.png"
    assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_report_pairs_the_readings_case_by_case():
    bench = _load()
    runs = pd.DataFrame([dict(family="f", case=c, reading=r, log_loss=v, brier=v / 10,
                              accuracy=0.9, fit_s=0.1, n_warnings=0, inference="exact",
                              warnings="")
                         for c, a, b in (("x", 0.2, 1.0), ("y", 0.3, 2.0), ("z", 0.4, 3.0))
                         for r, v in (("learned", a), ("epsilon", b))])
    text = bench.report(runs, "cmd", 1.0, {("f", "learned"): 0.125})
    d = np.array([-0.8, -1.7, -2.6])
    half = 4.302652729911275 * d.std(ddof=1) / np.sqrt(3)
    assert f"{d.mean():.3f} [{d.mean() - half:.3f}, {d.mean() + half:.3f}]" in text
    assert "| f | 3 | 0.300 [" in text
    # the worst bins, learned and epsilon ("-": none given)
    assert next(line for line in text.splitlines()
                if line.startswith("| f | 3")).endswith("| 0.125 | - |")


def test_a_variant_is_a_second_fit_read_in_place_of_epsilon(monkeypatch):
    from bsi_sklearn import BSIClassifier
    from bsi_sklearn.datasets.errands import make_errand_demos, make_errand_task

    bench = _load()
    monkeypatch.setattr(bench, "VARIANT", {"likelihood": "ci", "epsilon": 0.1})
    rows = bench.roles_tasks([0], [], sizes=(20,), noises=(0.0,))
    by = {r["reading"]: r for r in rows if r["case"].startswith("errand")}
    assert by["epsilon"]["variant_inference"] == by["learned"]["variant_inference"]
    # the second reading is the variant's own fit, scored by its default predictive
    s_task, s_train, s_test = bench._seeds("errand", 0, 20)
    task = make_errand_task("errand", random_state=s_task)
    train = make_errand_demos(task, 20, random_state=s_train)
    test = make_errand_demos(task, 300, random_state=s_test)
    clf = BSIClassifier(random_state=0, likelihood="ci", epsilon=0.1).fit(train.traces, train.y)
    assert by["epsilon"]["accuracy"] == pytest.approx(np.mean(clf.predict(test.traces) == test.y))
    with pytest.raises(SystemExit):  # a variant writes into --out only
        bench.main(["--variant", "likelihood='ci'"])
