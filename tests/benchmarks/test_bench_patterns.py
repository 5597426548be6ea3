"""benchmarks/bench_patterns.py: every template timed on all its instances, the table written."""

import importlib.util
import sys
from pathlib import Path

import pytest

from bsi_sklearn.model.patterns import TEMPLATES, instantiate

ROOT = Path(__file__).resolve().parents[2]
SCRIPT = ROOT / "benchmarks" / "bench_patterns.py"
pytestmark = pytest.mark.skipif(not SCRIPT.is_file(), reason="benchmarks/ is not in this checkout")


def _load():
    sys.path.insert(0, str(SCRIPT.parent))
    spec = importlib.util.spec_from_file_location("_bench_patterns", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_quick_run_times_every_template_on_all_its_instances(tmp_path):
    out = tmp_path / "RESULTS_patterns.md"
    _load().main(["--quick", "--repeats", "1", "--out", str(out)])
    rows = [line.split(" | ") for line in out.read_text().splitlines()
            if line.startswith("| 200 x 10 x 8 |")]
    by_name = {r[1]: r for r in rows}
    assert set(by_name) == set(TEMPLATES) | {"G(x -> F(y))"}
    for name in TEMPLATES:
        assert by_name[name][3] == f"{len(instantiate(name, range(8))):,}"
    assert by_name["G(x -> F(y))"][3] == "5"  # a tenth of the 56 ordered pairs
