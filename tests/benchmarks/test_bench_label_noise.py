"""benchmarks/bench_label_noise.py: one fit read both ways, and the report's paired columns."""

import importlib.util
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "bench_label_noise.py"
pytestmark = pytest.mark.skipif(not SCRIPT.is_file(), reason="benchmarks/ is not in this checkout")


def _load():
    sys.path.insert(0, str(SCRIPT.parent))
    spec = importlib.util.spec_from_file_location("_bench_label_noise", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_both_readings_come_from_one_fit():
    bench = _load()
    rows = bench.roles_tasks(seeds=[0], sizes=(20,), noises=(0.1,))
    by = {r["reading"]: r for r in rows if r["case"].startswith("errand")}
    assert set(by) == {"learned", "epsilon"}
    assert by["learned"]["fit_s"] == by["epsilon"]["fit_s"]  # the same fit
    assert by["learned"]["accuracy"] == by["epsilon"]["accuracy"]
    # CB's epsilon (2^-4M) leaves near-certain probabilities; the learned rate does not.
    assert by["learned"]["log_loss"] < by["epsilon"]["log_loss"]


def test_report_pairs_the_readings_case_by_case():
    bench = _load()
    runs = pd.DataFrame([dict(family="f", case=c, reading=r, log_loss=v, brier=v / 10,
                              accuracy=0.9, fit_s=0.1, n_warnings=0, inference="exact",
                              warnings="")
                         for c, a, b in (("x", 0.2, 1.0), ("y", 0.3, 2.0), ("z", 0.4, 3.0))
                         for r, v in (("learned", a), ("epsilon", b))])
    text = bench.report(runs, "cmd", 1.0)
    d = np.array([-0.8, -1.7, -2.6])
    half = 4.302652729911275 * d.std(ddof=1) / np.sqrt(3)
    assert f"{d.mean():.3f} [{d.mean() - half:.3f}, {d.mean() + half:.3f}]" in text
    assert "| f | 3 | 0.300 [" in text
