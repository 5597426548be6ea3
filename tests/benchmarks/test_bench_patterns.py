"""benchmarks/bench_patterns.py: every template timed on all its instances, the table written."""


from _scripts import load, needs

from bsi_sklearn.model.patterns import TEMPLATES, instantiate

pytestmark = needs("bench_patterns.py")


def _load():
    return load("bench_patterns")


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
