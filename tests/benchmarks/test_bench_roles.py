"""benchmarks/bench_roles.py (issue 20): the cell function, its statistics and its outputs."""


import numpy as np
import pandas as pd
import pytest
from _scripts import needs

pytestmark = needs("bench_roles.py")


@pytest.fixture(scope="module")
def bench():
    import bench_roles

    return bench_roles


@pytest.fixture(scope="module")
def report():
    import _roles_report

    return _roles_report


def _tiny_variants(bench):
    return [bench.Variant("given", "cb", {"likelihood": "cb"}),
            bench.Variant("all", "ci", {"likelihood": "ci"}),
            bench.Variant("infer", "calibrated", {}, available=False, reason="not here")]


def test_run_cell_counts_accuracy_by_hand(bench):
    from bsi_sklearn import BSIClassifier
    from bsi_sklearn.datasets.errands import make_errand_demos, make_errand_task

    rows = bench.run_cell("pick_place", 0, 12, noises=(0.0, 0.25),
                          variant_list=_tiny_variants(bench), n_test=15)
    assert len(rows) == 2 * 3
    assert [(r["noise"], r["variant"]) for r in rows] == [
        (0.0, "given/cb"), (0.0, "all/ci"), (0.0, "infer/calibrated"),
        (0.25, "given/cb"), (0.25, "all/ci"), (0.25, "infer/calibrated")]
    missing = [r for r in rows if not r["available"]]
    assert len(missing) == 2 and all("accuracy" not in r for r in missing)
    assert [r["flipped"] for r in rows] == [0, 0, 0, 3, 3, 3]

    # the same task and data, refitted here; the accuracy counted one test trace at a time
    s_task, s_train, s_test = bench._seeds("pick_place", 0, 12)
    task = make_errand_task("pick_place", random_state=s_task)
    train = make_errand_demos(task, 12, random_state=s_train)
    test = make_errand_demos(task, 15, random_state=s_test)
    y_noisy = bench.flip_labels(train.y, 0.25, np.random.default_rng(s_train + 1))
    for row in rows:
        if not row["available"]:
            continue
        y = train.y if row["noise"] == 0 else y_noisy
        roles = train.roles if row["roles"] == "given" else {}
        clf = BSIClassifier(likelihood=row["likelihood"], random_state=0, n_jobs=1,
                            **roles).fit(train.traces, y)
        correct = 0
        for trace, truth in zip(test.traces, test.y):
            correct += int(clf.predict([trace])[0] == truth)
        assert row["accuracy"] == correct / 15
        assert row["inference"] in {"exact", "mcmc"}
        assert row["n_warnings"] >= 0 and row["fit_s"] > 0


def test_flip_labels_flips_the_rounded_share(bench):
    y = np.array([1, 0] * 10)
    out = bench.flip_labels(y, 0.1, np.random.default_rng(0))
    assert int(np.sum(out != y)) == 2 and set(out) <= {0, 1}
    np.testing.assert_array_equal(bench.flip_labels(y, 0.0, np.random.default_rng(0)), y)


def test_variants_follow_what_the_classifier_has(bench):
    from bsi_sklearn import BSIClassifier
    from bsi_sklearn.model.likelihood import LIKELIHOODS

    params = BSIClassifier().get_params()
    vs = {v.name: v for v in bench.variants()}
    assert len(vs) == 12
    assert vs["given/cb"].available and vs["all/ci"].available
    assert vs["given/calibrated"].available == ("calibrated" in LIKELIHOODS)
    assert vs["given/ci+flip"].available == ("flip_prior" in params)
    assert vs["infer/cb"].available == ("roles" in params)
    for v in vs.values():
        assert v.available == (v.reason == "")


def _frame():
    # two seeds, one cell, given vs all: accuracies chosen so the statistics are exact
    rows = []
    for seed, (g, a) in enumerate([(1.0, 0.9), (0.8, 0.8)]):
        for roles, acc in (("given", g), ("all", a)):
            rows.append({"kind": "pick_place", "seed": seed, "n_train": 20, "noise": 0.1,
                         "variant": f"{roles}/cb", "roles": roles, "likelihood": "cb",
                         "available": True, "accuracy": acc, "inference": "exact",
                         "n_warnings": seed, "warnings": "UserWarning:1" if seed else "",
                         "fit_s": 0.5})
    rows.append({"kind": "pick_place", "seed": 0, "n_train": 20, "noise": 0.1,
                 "variant": "infer/cb", "roles": "infer", "likelihood": "cb",
                 "available": False})
    return pd.DataFrame(rows)


def test_summaries_match_a_hand_count(report):
    df = _frame()
    summ = report.cell_summary(df).set_index("variant")
    assert summ.loc["given/cb", "mean"] == pytest.approx(0.9)
    # t(0.975, 1) = 12.706; sd of (1.0, 0.8) = 0.1414; half = 12.706 * 0.1414 / sqrt 2 = 1.2706
    assert summ.loc["given/cb", "low"] == pytest.approx(0.9 - 1.2706, abs=1e-4)
    assert "infer/cb" not in summ.index
    d = report.paired_differences(df)
    assert len(d) == 1 and d.iloc[0]["mean"] == pytest.approx(-0.05)
    rows = report.targets(df)
    assert len(rows) == 2
    assert rows[0][3] is False          # -0.05 is not within 0.03
    assert rows[1][3] is False          # 0.9 < 0.97
    counts = report.fit_counts(df)
    assert [c[:6] for c in counts] == [["given/cb", 2, 2, 0, 0, 1], ["all/cb", 2, 2, 0, 0, 1]]


def test_the_table_has_one_row_per_size_noise_and_likelihood(report):
    df = _frame()
    text = report._summary_table(df, "pick_place")
    lines = text.splitlines()
    assert len(lines) == 2 + 1  # header, rule, one (size, noise, likelihood) row
    cells = [c.strip() for c in lines[2].strip("|").split("|")]
    assert len(cells) == 8
    assert cells[3] == "0.900 [-0.371, 2.171]" and cells[5] == "not available"
    assert cells[6].startswith("-0.050 [")


def test_write_outputs(tmp_path, bench, report):
    df = _frame()
    paths = report.write_outputs(df, bench.variants(), tmp_path, command="x", seconds=1.0,
                                 quick=True, settings={"seeds": 2, "sizes": (20,),
                                                       "n_test": 5, "flip_prior": (1, 4),
                                                       "n_jobs": 1})
    md, csv, png = paths
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert len(pd.read_csv(csv)) == len(df)
    text = md.read_text()
    assert "## Targets" in text and "smoke run" in text and "**missed**" in text


def test_skipped_variants_stay_listed_with_their_reason(bench):
    vlist = bench.skip_variants(bench.variants(), ["all/ci+flip"])
    names = [v.name for v in vlist]
    assert names == [v.name for v in bench.variants()]  # none dropped
    skipped = [v for v in vlist if v.name == "all/ci+flip"]
    assert len(skipped) == 1 and not skipped[0].available
    assert skipped[0].reason == "skipped (--skip)"
    assert all(v.available for v in vlist if v.name != "all/ci+flip")
    with pytest.raises(ValueError, match="unknown variant"):
        bench.skip_variants(vlist, ["all/typo"])


def test_pooled_differences_average_per_task_then_interval_over_tasks(report):
    rows = []
    acc = {("a", 0): {"infer/cb": [0.8, 0.6], "all/cb": [0.7, 0.3]},
           ("a", 1): {"infer/cb": [0.9, 0.9], "all/cb": [0.9, 0.7]},
           ("b", 0): {"infer/cb": [0.5, 0.5], "all/cb": [0.6, 0.6]}}
    for (kind, seed), by_variant in acc.items():
        for variant, values in by_variant.items():
            for n, value in zip((20, 40), values):
                rows.append({"kind": kind, "seed": seed, "n_train": n, "noise": 0.0,
                             "variant": variant, "available": True, "accuracy": value})
    table = report.pooled_differences(pd.DataFrame(rows))
    assert list(table["variant"]) == ["all/cb"]
    per_task = np.array([(-0.1 - 0.3) / 2, (0.0 - 0.2) / 2, (0.1 + 0.1) / 2])
    row = table.iloc[0]
    assert row.tasks == 3
    assert row["mean"] == pytest.approx(per_task.mean())
    half = 4.302652729911275 * per_task.std(ddof=1) / np.sqrt(3)  # t(0.975, 2)
    assert row.low == pytest.approx(per_task.mean() - half)
    assert row.high == pytest.approx(per_task.mean() + half)
