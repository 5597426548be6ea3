"""benchmarks/study_tables.py: the counts and cells against a hand-made study."""

import sys
from pathlib import Path

import pandas as pd
import pytest

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"
pytestmark = pytest.mark.skipif(not (BENCH / "study_tables.py").is_file(),
                                reason="benchmarks/ is not in this checkout")
if str(BENCH) not in sys.path:
    sys.path.insert(0, str(BENCH))


def _load():
    import study_tables

    return study_tables


def _paired():
    rows = []
    # (bsi, n_train, mean, significant, baseline_mean, baseline_significant)
    for bsi, n, m, sig, bm, bsig in [("A", 6, -0.1, True, -0.2, True),
                                     ("A", 12, 0.05, True, -0.01, False),
                                     ("B", 6, 0.02, False, 0.01, False),
                                     ("B", 12, 0.04, True, 0.03, True)]:
        rows.append(dict(bsi=bsi, best_network="LSTM", objective="MO1", n_train=n, noise=0.0,
                         propositions="paper", metric="f1", mean=m, ci_low=m - 0.01,
                         ci_high=m + 0.01, n_runs=10, significant=sig, best_baseline="LR",
                         baseline_mean=bm, baseline_ci_low=bm - 0.01,
                         baseline_ci_high=bm + 0.01, baseline_significant=bsig))
    return pd.DataFrame(rows)


def test_headline_counts_each_direction_per_row():
    lines = _load().headline(_paired())
    assert "| all | every row | 4 | 2 / 1 | 1 / 1 |" in lines
    assert "| paper | A | 2 | 1 / 1 | 0 / 1 |" in lines
    assert "| paper | B | 2 | 1 / 0 | 1 / 0 |" in lines


def test_cell_table_quotes_the_study_and_marks_significance():
    study = pd.DataFrame([dict(classifier=c, objective="MO1", n_train=n, noise=0.0,
                               propositions="paper", metric="f1", mean=v, ci_low=v - 0.1,
                               ci_high=v + 0.1, n_runs=10)
                          for c, v in (("LSTM", 0.8), ("LR", 0.9)) for n in (6, 12)])
    lines = _load().cell_table(study, _paired(), 0.0, "paper")
    assert len(lines) == 4  # head, rule, two sizes
    assert lines[2] == ("| MO1 | 6 | LSTM: 0.800 [0.700, 0.900] | LR: 0.900 [0.800, 1.000] | "
                        "-0.100 [-0.110, -0.090] * / -0.200 [-0.210, -0.190] * | "
                        "+0.020 [+0.010, +0.030] / +0.010 [+0.000, +0.020] |")


def test_readme_table_takes_prior_2_and_its_differences():
    rows = []
    for bsi, m in (("BSI (Prior 2)", 0.05), ("BSI (Prior 2, CI)", 0.07), ("BSI (no roles)", 0.0)):
        rows.append(dict(bsi=bsi, best_network="LSTM", objective="MO2", n_train=18, noise=0.04,
                         propositions="paper", metric="f1", mean=m, ci_low=m - 0.02,
                         ci_high=m + 0.02, n_runs=10, significant=m > 0.02,
                         best_baseline="LR", baseline_mean=-0.01, baseline_ci_low=-0.03,
                         baseline_ci_high=0.01, baseline_significant=False))
    study = pd.DataFrame([dict(classifier=c, objective="MO2", n_train=18, noise=0.04,
                               propositions="paper", metric="f1", mean=v, ci_low=v - 0.1,
                               ci_high=v + 0.1, n_runs=10)
                          for c, v in (("LSTM", 0.8), ("LR", 0.86), ("BSI (Prior 2)", 0.85))])
    lines = _load().readme_table(study, pd.DataFrame(rows), 0.04, "paper")
    assert lines[2] == ("| MO2 | 18 | LSTM: 0.800 [0.700, 0.900] | LR: 0.860 [0.760, 0.960] | "
                        "0.850 [0.750, 0.950] | +0.050 [+0.030, +0.070] * | "
                        "+0.070 [+0.050, +0.090] * | +0.000 [-0.020, +0.020] | "
                        "-0.010 [-0.030, +0.010] |")


def test_the_results_page_is_what_the_recorded_study_renders():
    # docs/results/study.md holds the study's full tables; it must be the recorded study's
    # rendering, not a hand-edited copy (rerun the command in the page after a new study).
    root = BENCH.parent
    page = root / "docs" / "results" / "study.md"
    folder = BENCH / "study"
    if not (folder / "study.csv").is_file():
        pytest.skip("benchmarks/study/ holds no recorded study")
    tables = _load()
    study = pd.read_csv(folder / "study.csv")
    paired = pd.read_csv(folder / "study_paired.csv")
    assert page.read_text(encoding="utf-8") == tables.results_page(study, paired,
                                                                    "benchmarks/study")
    assert "| MO2 | 36 |" in page.read_text(encoding="utf-8")
