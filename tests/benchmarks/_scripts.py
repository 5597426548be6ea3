"""The benchmark scripts as their tests import them: one helper instead of a loader per file.

pytest does not collect ``benchmarks/``. A script runs as ``python benchmarks/<name>.py``: its
folder is first on ``sys.path`` (its ``_checkout`` then puts this checkout before it) and it
imports its siblings by their names. Importing this module puts the folder on ``sys.path`` the
same way, so a test imports a script, or one of its siblings, by its name.
"""

import importlib
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[2] / "benchmarks"

if str(BENCH) not in sys.path:
    sys.path.insert(0, str(BENCH))


def needs(script):
    """The mark that skips a test module when ``benchmarks/<script>`` is not in this checkout."""
    return pytest.mark.skipif(not (BENCH / script).is_file(),
                              reason="benchmarks/ is not in this checkout")


def load(name):
    """``benchmarks/<name>.py`` imported by its name, as its siblings import it."""
    return importlib.import_module(name)
