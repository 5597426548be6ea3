"""Imported first by every benchmark script: this checkout's packages, then these helpers.

A script runs as ``python benchmarks/<name>.py`` (its folder is then ``sys.path[0]``, so this
module is found). It must measure the code of *this* checkout, not an installed copy of
``bsi_sklearn``, ``lfe`` or ``baselines``: the repository root goes first on ``sys.path``, the
benchmarks' folder (``_common``, ``_data``...) right after. This is the one place the path is
set; a script only imports this module.
"""

import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent

for _path in (str(HERE), str(ROOT)):  # ROOT ends up first, HERE second
    while _path in sys.path:
        sys.path.remove(_path)
    sys.path.insert(0, _path)
