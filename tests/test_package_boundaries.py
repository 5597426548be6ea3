"""What ``bsi_sklearn`` may load: nothing from ``lfe``, ``baselines``, torch or ``benchmarks/``."""

import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import bsi_sklearn

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = Path(bsi_sklearn.__file__).resolve().parent

SCRIPT = textwrap.dedent("""
    import importlib, pkgutil, sys
    from pathlib import Path

    import bsi_sklearn

    for info in pkgutil.walk_packages(bsi_sklearn.__path__, "bsi_sklearn."):
        if not info.name.endswith("__main__"):
            importlib.import_module(info.name)
    benchmarks = Path(sys.argv[1]).resolve()
    for name, module in sorted(sys.modules.items()):
        top = name.split(".")[0]
        if top in ("lfe", "baselines", "torch"):
            print("LOADED", name)
        file = getattr(module, "__file__", None)
        if file and benchmarks in Path(file).resolve().parents:
            print("LOADED", name, file)
    print("DONE")
""")


def test_importing_every_module_loads_nothing_outside_the_package():
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    env.setdefault("MPLBACKEND", "Agg")
    proc = subprocess.run([sys.executable, "-c", SCRIPT, str(ROOT / "benchmarks")],
                          capture_output=True, text=True, cwd=ROOT, env=env, timeout=600)
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert proc.stdout.splitlines() == ["DONE"]


def test_no_module_loads_code_by_file_path():
    pattern = re.compile(r"spec_from_file_location|SourceFileLoader|\brunpy\b|\bexec\(")
    offenders = [f"{path.relative_to(ROOT)}:{n}"
                 for path in sorted(PACKAGE.rglob("*.py"))
                 for n, line in enumerate(path.read_text().splitlines(), 1)
                 if pattern.search(line)]
    assert offenders == []
