"""The README's Python examples run as written; its set-up commands exist and agree."""

import os
import re
from pathlib import Path

README = Path(__file__).parents[1] / "README.md"


def test_readme_python_blocks_run(capsys):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(), flags=re.S)
    assert blocks
    # The quick start runs as written (the dask example needs a cluster: tests/distributed).
    namespace = {}
    exec(compile(blocks[0], "README.md", "exec"), namespace)
    out = capsys.readouterr().out
    assert "G(0) & F(1) & F(2) & (!2 U 1)" in out


def test_readme_names_setup_main_and_test_commands():
    text = README.read_text()
    assert "pip install torch==2.13.0" in text
    assert 'pip install -e ".[test]"' in text
    assert "python -m pytest -q" in text


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
    assert venv < torch < project
    assert 'exec "$ROOT/.venv/bin/bsi-lfe" compare --out results/ "$@"' in (
        ROOT / "run").read_text()
    assert 'exec "$ROOT/.venv/bin/python" -m pytest -q "$@"' in (ROOT / "test").read_text()
    for name in ("run", "test"):
        assert '"$ROOT/scripts/ensure-venv"' in (ROOT / name).read_text()
    ci = (ROOT / ".ci" / "run").read_text()
    assert "\n./test\n" in ci and "pip install" not in ci
