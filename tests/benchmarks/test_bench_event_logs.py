"""benchmarks/bench_event_logs.py (issue 27): the rows on a tiny log, isolation, outputs."""


import pandas as pd
import pytest
from _scripts import needs

pytestmark = needs("bench_event_logs.py")


@pytest.fixture(scope="module")
def bench():
    import bench_event_logs

    return bench_event_logs


@pytest.fixture(scope="module")
def rows():
    import _event_log_rows

    return _event_log_rows


@pytest.fixture(scope="module")
def practitioner_frame(bench):
    specs = bench.grid_specs(((10, 60),), ["logreg", "tree", "minirocket"], recovery=False)
    return bench.run_grid(specs, isolate=False, verbose=0)


def test_the_practitioner_rows_run_on_a_tiny_log(practitioner_frame):
    df = practitioner_frame
    assert len(df) == 2 * 3
    assert (df["status"] == "ok").all(), df["status"].tolist()
    assert df["accuracy"].between(0, 1).all() and df["f1_weighted"].between(0, 1).all()
    assert (df["n_train"] == 42).all() and (df["n_test"] == 18).all()
    assert (df["fit_s"] > 0).all()
    assert set(df["rule"]) == {"template", "declare"}


def test_the_scores_are_against_the_clean_test_labels(rows):
    from bsi_sklearn.datasets import make_process_log

    spec = dict(n_activities=10, n_cases=60, rule="template", noise=0.3, seed=0, method="tree")
    row = rows.run_row(spec)
    log = make_process_log(10, 60, rule="template", noise=0.3, random_state=0)
    train, test = rows.split_log(log, spec)
    assert len(set(train) & set(test)) == 0 and len(train) + len(test) == 60
    assert row["test_positive"] == pytest.approx(log.clean_labels.loc[test].mean())


def test_a_row_past_its_timeout_is_recorded_not_waited_for(bench):
    spec = bench.grid_specs(((10, 60),), ["tree"], recovery=False)[0]
    row = bench.run_isolated(spec, timeout=0.05, memory_limit_gb=8.0)
    assert row["status"] == "timeout"


def test_a_row_in_its_own_process_reports_its_peak_memory(bench):
    spec = bench.grid_specs(((10, 60),), ["tree"], recovery=False)[0]
    row = bench.run_isolated(spec, timeout=120, memory_limit_gb=8.0)
    assert row["status"] == "ok" and row["peak_rss_mib"] > 10 and 0 <= row["accuracy"] <= 1


def test_a_row_over_its_memory_limit_is_recorded(bench):
    spec = bench.grid_specs(((10, 60),), ["tree"], recovery=False)[0]
    row = bench.run_isolated(spec, timeout=120, memory_limit_gb=0.05)
    assert row["status"] in ("memory", "ok") or row["status"].startswith("error")
    assert row["status"] != "ok"


def test_minirocket_traces_repeat_their_last_state(rows):
    (x,), _, name = rows._encoded([["b", "a"]], [["a"]], ["a", "b"], min_steps=9,
                                  negations=False)
    assert name == "EventLogEncoder(negations=False)" and x.shape == (9, 2)
    values = x[["a", "b"]].to_numpy(dtype=bool)
    assert values[:3].tolist() == [[False, False], [False, True], [True, True]]
    assert (values[3:] == values[2]).all()


def test_recovery_compares_normalised_clauses(rows):
    from bsi_sklearn import Specification

    norm = rows.normalised_clauses
    assert norm(Specification(orders=[("a", "b")])) == norm(
        Specification(eventuals=["a"], orders=[("a", "b")]))
    assert norm(Specification(orders=[("a", "b"), ("b", "c")])) == norm(
        Specification(eventuals=["a", "b"], orders=[("a", "b"), ("b", "c"), ("a", "c")]))
    assert norm(Specification(eventuals=["a"])) != norm(Specification(eventuals=["b"]))
    assert norm(Specification(eventuals=["a"], conditions={"a": "c"})) != norm(
        Specification(eventuals=["a"]))


def test_the_rule_never_disagrees_with_itself_on_fresh_cases(rows):
    from bsi_sklearn import Specification
    from bsi_sklearn.datasets import make_process_log

    spec = dict(n_activities=10, n_cases=60, rule="template", noise=0.3, seed=0)
    log = make_process_log(10, 60, rule="template", noise=0.3, random_state=0)
    train = log.cases()[:42]
    assert rows.rule_disagreement(log.specification(), log, spec, train, n_fresh=400) == 0.0
    # Accepting every case disagrees on exactly the fresh cases the rule rejects.
    big = make_process_log(10, 460, rule="template", noise=0.3, random_state=0)
    rejected = 1 - big.clean_labels.to_numpy()[60:].mean()
    assert big.cases()[:60] == log.cases() and 0.2 < rejected < 0.8
    assert rows.rule_disagreement(Specification(), log, spec, train, n_fresh=400) == \
        pytest.approx(rejected)


def test_the_outputs_are_written(bench, practitioner_frame, tmp_path):
    paths = bench.write_outputs(practitioner_frame, tmp_path, tmp_path / "RESULTS.md",
                                "python benchmarks/bench_event_logs.py --test", 1.0,
                                {"sizes": "10x60"})
    assert all(p.is_file() for p in paths)
    text = (tmp_path / "RESULTS.md").read_text()
    assert "Commit:" in text and "Machine:" in text and "Decision tree" in text
    assert len(pd.read_csv(tmp_path / "event_logs.csv")) == 6
    scaling = pd.DataFrame([dict(task="scaling", n_activities=a, n_cases=c, rule="template",
                                 method="bsi", method_label="BSI (defaults)", status=s,
                                 fit_s=f, peak_rss_mib=m)
                            for a, c, s, f, m in [(10, 100, "ok", 1.0, 200.0),
                                                  (40, 100, "ok", 2.0, 250.0),
                                                  (40, 1000, "timeout", None, None)]])
    paths = bench.write_scaling(scaling, tmp_path / "s", "cmd", 1.0)
    assert all(p.is_file() for p in paths)


def test_sizes_are_parsed(bench):
    assert bench.parse_sizes("10x100,40x1000") == ((10, 100), (40, 1000))
    with pytest.raises(Exception, match="ACTIVITIESxCASES"):
        bench.parse_sizes("10-100")


def test_the_negations_comparison_pairs_by_seed(rows):
    import bench_event_log_negations as neg

    specs = neg.specs(((10, 60, range(1, 3)),))
    assert len(specs) == 2 * 2 * 2 and {s["encoder"]["negations"] for s in specs} == {0, 1}
    # the BSI row passes the encoder's parameters on: one log, its negated columns or not
    off, on = (rows.run_row(dict(s, encoder={"negations": v})) for s, v in
               ((specs[0], False), (specs[0], True)))
    assert off["encoding"] == "EventLogEncoder(negations=False)"
    assert on["encoding"] == "EventLogEncoder(negations=True)"
    df = pd.DataFrame([dict(n_activities=10, n_cases=60, rule="declare", seed=seed,
                            negations=flag, status="ok", accuracy=acc, fit_s=1.0,
                            rule_recovered=rec)
                       for seed, flag, acc, rec in [(1, False, 0.5, False), (1, True, 0.9, True),
                                                    (2, False, 0.7, False), (2, True, 0.8, False),
                                                    (3, True, 1.0, True)]])  # seed 3 unpaired
    table = neg.summary(df)
    assert "| 10x60 | declare | 2 | 0.600 | 0.850 | +0.250 [" in table
    assert "| +0.100 |" in table and "| 0 / 1 of 2 |" in table
    # --option repeats: the default encoder against repeats=True, a column "repeats"
    specs = neg.specs(((10, 60, range(1, 2)),), option="repeats")
    assert [(s["encoder"], s["repeats"]) for s in specs[:2]] == [({}, False),
                                                               ({"repeats": True}, True)]
    on = rows.run_row(specs[1])
    assert on["encoding"] == "EventLogEncoder(repeats=True)" and on["status"] == "ok"
    table = neg.summary(df.rename(columns={"negations": "repeats"}), "repeats")
    assert "accuracy, with a<=1" in table and "| 10x60 | declare | 2 | 0.600 | 0.850 |" in table


def test_the_target_sweep_counts_the_fits_within_the_target(bench, tmp_path):
    assert bench.parse_seeds("0-3") == [0, 1, 2, 3] and bench.parse_seeds("2,5") == [2, 5]
    specs = bench.target_specs([0, 1])
    assert [(s["rule"], s["positive_only"], s["seed"]) for s in specs] == [
        ("template", False, 0), ("declare", False, 0), ("template", True, 0),
        ("template", False, 1), ("declare", False, 1), ("template", True, 1)]
    assert all((s["n_activities"], s["n_cases"]) == bench.TARGET_SIZE for s in specs)
    df = pd.DataFrame([dict(s, status=st, fit_s=t, accuracy=0.9, peak_rss_mib=300.0,
                            inference="mcmc")
                       for s, st, t in zip(specs, ["ok", "ok", "ok", "ok", "timeout", "ok"],
                                           [12.0, 45.0, 20.0, 29.0, None, 31.0])])
    paths = bench.write_target(df, tmp_path, "cmd", 1.0)
    text = paths[1].read_text()
    # template: 12 and 29 s, both within 30 s; declare: 45 s and a timeout, neither;
    # positive-only: 20 s and 31 s, one.
    assert "| template | 2 | 2 | 20.5 | 29.0 | 300 |" in text
    assert "| declare | 2 | 0 | 45.0 | 45.0 | 300 |" in text
    assert "| template, positive-only | 2 | 1 | 25.5 | 31.0 | 300 |" in text
    assert len(pd.read_csv(paths[0])) == 6


def test_bsi_rows_take_other_parameters(bench, rows):
    specs = bench.recovery_specs([0], [10], bsi={"likelihood": "ci"})
    assert specs[0]["bsi"] == {"likelihood": "ci"}
    assert "bsi" not in bench.recovery_specs([0], [10])[0]
    row = rows.run_row(dict(specs[0], n_cases=60, n_train=42))
    assert row["status"] == "ok" and row["hyper"] == "likelihood='ci', random_state=0"
    assert 0.0 <= row["rule_disagreement"] <= 1.0


def test_the_target_sweep_takes_other_parameters_from_the_command_line(bench):
    specs = bench.target_specs([0], bsi={"likelihood": "calibrated", "p_global": 0.2})
    assert all(s["bsi"] == {"likelihood": "calibrated", "p_global": 0.2} for s in specs)
    assert all("bsi" not in s for s in bench.target_specs([0]))
    from _common import parse_param

    assert parse_param("likelihood='ci'") == ("likelihood", "ci")
    assert parse_param("flip_prior=(1, 9)") == ("flip_prior", (1, 9))
    import argparse

    for bad in ("likelihood=ci", "p_global", "1x=2"):
        with pytest.raises(argparse.ArgumentTypeError):
            parse_param(bad)
