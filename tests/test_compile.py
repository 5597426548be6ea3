"""The compile step (``python -m bsi_sklearn.compile``, issue 29): after it a new process
compiles nothing; and a first fit compiles each kernel once.

``./test`` runs the compile step after it installs the project, so the first test reads a
filled cache; without it the fixture compiles everything once (about a minute on 2 cores).
"""

import io
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from bsi_sklearn import compile as compile_step

ROOT = Path(__file__).resolve().parents[1]

#: A new process: the README's quick start, then sampling, prediction and monitoring; prints
#: the package's functions numba compiled and, for each, the argument types of each compilation.
CHILD = r"""
import json, sys
import numpy as np
from numba.core import event
from numba.core.registry import CPUDispatcher

compiled = []

class Record(event.Listener):
    def on_start(self, ev):
        func = getattr(ev.data.get("dispatcher"), "py_func", None)
        if getattr(func, "__module__", "").startswith("bsi_sklearn"):
            compiled.append(f"{func.__module__}.{func.__qualname__}")
    def on_end(self, ev):
        pass

with event.install_listener("numba:compile", Record()):
    from bsi_sklearn import BSIClassifier
    good = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
            np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])]
    bad = [np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
    roles = dict(global_candidates=[0], subtasks=[1, 2])
    clf = BSIClassifier(random_state=0, **roles).fit(good + bad, [1, 1, 0])
    if sys.argv[1] == "all":
        clf.predict_proba(good)
        clf.monitor_proba(good)
        BSIClassifier(inference="mcmc", n_samples=200, burn_in=20, random_state=0,
                      **roles).fit(good + bad, [1, 1, 0])
        BSIClassifier(inference="mcmc", random_state=0, **roles).fit(good + bad, [1, 1, 0])
        # An event log with flipped labels: the optimum's moves about one demonstration.
        from bsi_sklearn.datasets import make_process_log
        from bsi_sklearn.io import EventLogEncoder
        log = make_process_log(8, 80, rule="template", noise=0.1, random_state=0)
        X = EventLogEncoder().fit_transform(log.cases())
        BSIClassifier(inference="mcmc", n_samples=100, random_state=0).fit(X, log.labels)
signatures = {}
for name, module in list(sys.modules.items()):
    if name.startswith("bsi_sklearn") and module is not None:
        for key, value in vars(module).items():
            if isinstance(value, CPUDispatcher) and value.py_func.__module__ == name:
                signatures[f"{name}.{key}"] = [[str(t) for t in s] for s in value.signatures]
print(json.dumps({"compiled": compiled, "signatures": signatures}))
"""


def _child(what, env=None):
    out = subprocess.run([sys.executable, "-c", CHILD, what], capture_output=True, text=True,
                         cwd=ROOT, env={**os.environ, **(env or {})}, timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    return json.loads(out.stdout.strip().splitlines()[-1]), out.stderr


def test_after_the_compile_step_a_new_process_compiles_nothing():
    stream = io.StringIO()
    compile_step.compile_all(stream=stream)
    assert "bsi_sklearn: done in" in stream.getvalue()
    seen, err = _child("all")
    assert seen["compiled"] == []
    assert "compiling numba kernels" not in err  # and so no notice


def test_a_first_fit_compiles_each_kernel_once(tmp_path):
    # A fresh cache: the quick start compiles what it calls, each function for one set of
    # argument types (not again for a literal 0 a counter starts at), and says so in a line.
    seen, err = _child("fit", {"NUMBA_CACHE_DIR": str(tmp_path)})
    twice = {name: sigs for name, sigs in seen["signatures"].items() if len(sigs) > 1}
    assert twice == {}
    assert seen["compiled"]
    assert err.count("bsi_sklearn: compiling numba kernels on first use") == 1


def test_bsi_compile_wants_a_positive_number_of_jobs():
    from bsi_sklearn.cli import main

    with pytest.raises(SystemExit, match="--jobs must be at least 1"):
        main(["compile", "--jobs", "0"])
