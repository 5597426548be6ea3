"""notebooks/05_interpretability.ipynb runs top to bottom, committed without outputs.

The notebook's code cells are run as one script by this interpreter in a subprocess (no
Jupyter kernel needed, so it works wherever ``pip install -e .[test]`` was run); BSI_QUICK=1
keeps it small. tests/test_notebooks.py also runs every notebook through a real kernel.
"""

import os
import subprocess
import sys
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")

NOTEBOOK = Path(__file__).parents[2] / "notebooks" / "05_interpretability.ipynb"


def test_notebook_committed_clean():
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(nb)
    assert nb.metadata.kernelspec.name == "python3"
    for cell in nb.cells:
        if cell.cell_type == "code":
            assert cell.outputs == [] and cell.execution_count is None


def test_notebook_runs(tmp_path):
    nb = nbformat.read(NOTEBOOK, as_version=4)
    lines = ["from IPython.display import display"]
    for cell in nb.cells:
        if cell.cell_type != "code":
            continue
        src = cell.source.rstrip()
        last = src.splitlines()[-1] if src else ""
        # A bare name on the last line is what a notebook displays: display it here too.
        if last.isidentifier():
            src = src[: len(src) - len(last)] + f"display({last})"
        lines.append(src)
    script = tmp_path / "notebook.py"
    script.write_text("\n\n".join(lines), encoding="utf-8")
    env = dict(os.environ, BSI_QUICK="1", MPLBACKEND="Agg")
    proc = subprocess.run([sys.executable, str(script)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert "Always, threat 1 is avoided." in proc.stdout
    assert (tmp_path / "poi_report" / "report.md").exists()
    assert (tmp_path / "poi_report.html").stat().st_size > 10_000
    assert "MO1: Gain and maintain air superiority" in proc.stdout
    assert (tmp_path / "lfe_report" / "index.html").exists()
