"""The README's Python examples run as written; its set-up commands exist and agree."""

import os
import re
import warnings
from pathlib import Path

import pytest
from sklearn.exceptions import ConvergenceWarning

README = Path(__file__).parents[1] / "README.md"


def _python_blocks():
    return re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)


def test_readme_quick_start_runs(capsys):
    blocks = _python_blocks()
    namespace = {"__name__": "__main__"}
    exec(compile(blocks[0], "README.md", "exec"), namespace)
    out = capsys.readouterr().out
    assert "G(0) & F(1) & F(2) & (!2 U 1)" in out


def test_readme_every_python_block_runs(capsys):
    """Every block runs as written; the dask cluster runs in threads here (starting worker
    processes costs seconds), which is the one substitution."""
    blocks = _python_blocks()
    assert len(blocks) >= 2
    # Later blocks may continue the quick start (its clf, good, bad): one namespace, in order.
    namespace = {"__name__": "__main__"}
    exec(compile(blocks[0], "README.md", "exec"), namespace)
    for block in blocks[1:]:
        if "LocalCluster(" in block:
            pytest.importorskip("distributed")
            written = "LocalCluster(n_workers=2)"
            assert written in block
            block = block.replace(written, "LocalCluster(n_workers=2, processes=False, "
                                           "dashboard_address=':0', silence_logs=40)")
        with warnings.catch_warnings():
            warnings.simplefilter("error", ConvergenceWarning)  # the README's fits are clean
            exec(compile(block, "README.md", "exec"), namespace)
    out = capsys.readouterr().out
    assert "'prior'" in out and "'p_part'" in out


def test_readme_names_setup_main_and_test_commands():
    text = README.read_text()
    assert "pip install torch==2.13.0" in text
    assert 'pip install -e ".[test]"' in text
    assert "python -m pytest -q -n 2 --dist loadfile" in text


ROOT = README.parent


def test_readme_two_commands_come_first_and_exist():
    text = README.read_text()
    setup = text[text.index("## Set up, run, test"):text.index("## Quick start")]
    first = re.search(r"```bash\n(.*?)```", setup, flags=re.S).group(1)
    assert [line.split()[0] for line in first.splitlines()] == ["./run", "./test"]
    for name in ("run", "test", "scripts/ensure-venv", ".ci/run"):
        path = ROOT / name
        assert path.is_file() and os.access(path, os.X_OK), name
        assert path.read_text().startswith("#!/usr/bin/env bash\n"), name


def test_scripts_install_cpu_torch_first_then_run_the_readme_commands():
    setup = "\n".join(line for line in (ROOT / "scripts" / "ensure-venv").read_text().splitlines()
                      if not line.lstrip().startswith("#"))
    venv = setup.index("-m venv")
    torch = setup.index("pip install torch==2.13.0")
    project = setup.index('pip install -e "$ROOT[test]"')
    assert venv < torch < project < setup.rindex("compile_kernels")  # then compiled, once
    assert '-m bsi_sklearn.compile' in setup
    assert 'exec "$ROOT/.venv/bin/bsi-lfe" compare --out results/ "$@"' in (
        ROOT / "run").read_text()
    assert ('exec "$ROOT/.venv/bin/python" -m pytest -q -n "${BSI_TEST_WORKERS:-2}" '
            '--dist loadfile "$@"') in (ROOT / "test").read_text()
    for name in ("run", "test"):
        assert '"$ROOT/scripts/ensure-venv"' in (ROOT / name).read_text()
    ci = (ROOT / ".ci" / "run").read_text()
    assert "\n./test\n" in ci and "pip install" not in ci


def test_readme_says_which_torch_build_pip_brings():
    setup = " ".join(README.read_text().split("## Quick start")[0].split())
    index = "https://download.pytorch.org/whl/cpu"
    assert "`pip install torch==2.13.0` from PyPI brings the CUDA build" in setup
    assert f"pip install torch==2.13.0 --index-url {index}" in setup
    # the index the README names is the one the set-up script uses
    assert f'TORCH_CPU_INDEX="${{TORCH_CPU_INDEX:-{index}}}"' in (
        ROOT / "scripts" / "ensure-venv").read_text()
    assert "*What `scripts/ensure-venv` does*" in setup


def test_readme_labels_the_network_rows_cpu_dependent_with_the_measurements():
    # compare's table: the four network rows change with the CPU type; the README says so
    # beside the table, names the table's CPU and quotes the differing cells as recorded
    text = README.read_text()
    section = " ".join(text.split("### One draw of the paper's protocol")[1]
                       .split("*Same missions on every machine.*")[0].split())
    results = " ".join((ROOT / "benchmarks" / "RESULTS_lfe.md").read_text().split())
    table_end = section.index("| majority class |")
    note = section[table_end:table_end + 1200]
    assert "*The network rows are CPU-dependent.*" in note
    assert "2-core Intel Xeon" in results.split("## Weighted F1")[0]
    assert "2-core Intel Xeon" in note
    recorded = "LSTM Coupled MO2 0.562, MO3 0.917; Bi-LSTM Coupled MO2 0.531"
    assert "AMD EPYC (load 1.4-1.6): 22.1 s wall" in results and recorded in results
    assert recorded in note and "AMD EPYC" in note
    # every number the section quotes for another CPU is a recorded one
    assert "0.706" not in section
