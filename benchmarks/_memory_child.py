"""Child process of bench_memory: peak memory of one fit in a fresh interpreter.

Usage: ``python _memory_child.py '<json spec>'``; prints one JSON line. The spec names the
data (``n_demos``, ``n_steps``, ``n_subtasks``, ``n_globals``) and ``BSIClassifier``
parameters (``params``). Peak resident memory is read from ``/proc/self/status`` (``VmHWM``)
after resetting it (``/proc/self/clear_refs``) just before the fit, so the interpreter, the
imports, the input data and the numba kernels (loaded by a warm-up fit on a tiny problem) are
not counted; where the reset is not allowed, the process-wide ``ru_maxrss`` is used instead.
A second fit runs under ``tracemalloc`` for the peak of Python and NumPy allocations.
"""

import gc
import json
import resource
import sys
import time
import tracemalloc
from pathlib import Path

import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split


def _status_kib(key):
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith(key + ":"):
                return int(line.split()[1])
    except OSError:
        pass
    return None


def _reset_peak():
    try:
        Path("/proc/self/clear_refs").write_text("5")
        return True
    except OSError:
        return False


def main(spec):
    import numpy as np
    from _common import problem_roles
    from _data import make_demos

    from bsi_sklearn import BSIClassifier

    X, _, roles = make_demos(spec["n_demos"], spec["n_steps"], n_subtasks=spec["n_subtasks"],
                             n_globals=spec["n_globals"], seed=11)
    # CB, as recorded (the default until 2026-12-07): these fits are positive-only.
    kw = dict(problem_roles(roles), likelihood="cb")
    params = dict(spec.get("params", {}))
    # Warm-up on a tiny problem of the same shape: loads (or compiles) every numba kernel.
    small, _, _ = make_demos(3, 5, n_subtasks=spec["n_subtasks"], n_globals=spec["n_globals"])
    BSIClassifier(**kw, **{**params, "n_samples": 10}).fit(small)
    gc.collect()
    input_bytes = int(sum(x.nbytes for x in X))
    rss_before = _status_kib("VmRSS")
    reset = _reset_peak() and _status_kib("VmHWM") is not None
    base = rss_before if reset else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    t0 = time.perf_counter()
    clf = BSIClassifier(**kw, **params).fit(X)
    wall = time.perf_counter() - t0
    peak = _status_kib("VmHWM") if reset else resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    inference, n_hyp = clf.inference_, clf.n_hypotheses_
    del clf
    gc.collect()
    tracemalloc.start()
    BSIClassifier(**kw, **params).fit(X)
    _, traced_peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    print(json.dumps({
        "input_bytes": input_bytes,
        "rss_before_kib": rss_before,
        "peak_increase_kib": max(0, peak - base),
        "method": "VmHWM after clear_refs" if reset else "ru_maxrss (since process start)",
        "tracemalloc_peak_bytes": int(traced_peak),
        "fit_s": wall,
        "inference": inference,
        "hypotheses": int(n_hyp),
        "numpy": np.__version__,
    }))


if __name__ == "__main__":
    main(json.loads(sys.argv[1]))
