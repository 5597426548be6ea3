"""benchmarks/bench_lfe_defaults.py: the paired table against a hand count."""


import numpy as np
import pandas as pd
import pytest
from _scripts import load, needs

pytestmark = needs("bench_lfe_defaults.py")


def _load():
    return load("bench_lfe_defaults")


def test_paired_subtracts_the_best_row_with_roles_repeat_by_repeat():
    bench = _load()
    f1 = {"BSI (Prior 2)": [0.8, 0.6, 0.7], "BSI (Prior 3)": [0.5, 0.9, 0.6],
          "BSI (Prior 2, CI)": [0.1, 0.1, 0.1], "no roles, defaults": [0.9, 0.5, 0.9]}
    runs = pd.DataFrame([dict(variant=v, repeat=r, propositions="paper", noise=0.0, n_train=6,
                              objective="MO1", f1=values[r])
                         for v, values in f1.items() for r in range(3)])
    table = bench.paired(runs)
    assert len(table) == 1
    row = table.iloc[0]
    # best by mean: Prior 2 (0.70) over Prior 3 (0.667) and CI (0.1)
    assert row.best_with_roles == "BSI (Prior 2)"
    diffs = np.array([0.1, -0.1, 0.2])
    assert row["diff"] == pytest.approx(diffs.mean())
    half = 4.302652729911275 * diffs.std(ddof=1) / np.sqrt(3)  # t(0.975, 2)
    assert row.diff_low == pytest.approx(diffs.mean() - half)
    assert row.diff_high == pytest.approx(diffs.mean() + half)
    assert not row.worse and not row.better


def test_variants_list_only_options_this_classifier_has():
    bench = _load()
    names = bench.variants()
    assert set(bench.WITH_ROLES) <= set(names)
    assert "no roles, defaults" in names
    for name, (_, needed) in bench.WITHOUT_ROLES.items():
        assert (name in names) == bench.available(needed)
