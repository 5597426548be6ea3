"""The README's Python examples run as written."""

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
