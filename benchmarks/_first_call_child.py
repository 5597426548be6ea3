"""Child process of bench_first_call: time a first fit / predict in a fresh interpreter.

Prints one JSON line: seconds for the import, the first MCMC fit, the first predict_proba, the
first exact fit, and the numba compilation time of every top-level kernel compiled. With the
argument ``quickstart``: the import and the README's quick-start fit only (roles given,
``inference="auto"``, exact), the first fit a new user makes (issue 29).
"""

import json
import sys
import time

T0 = time.perf_counter()


def main():
    import numpy as np
    from numba.core import event

    from bsi_sklearn import BSIClassifier

    t_import = time.perf_counter() - T0
    X = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
         np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])]
    roles = dict(global_candidates=[0], subtasks=[1, 2])
    out = {"import_s": t_import}
    if sys.argv[1:] == ["quickstart"]:
        bad = [np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
        with event.install_recorder("numba:compile") as rec:
            t = time.perf_counter()
            BSIClassifier(**roles, random_state=0).fit(X + bad, [1, 1, 0])
            out["fit_s"] = time.perf_counter() - t
        out["first_fit_s"] = time.perf_counter() - T0
        out["compile_s"] = _top_level(rec)
        print(json.dumps(out))
        return
    with event.install_recorder("numba:compile") as rec:
        t = time.perf_counter()
        clf = BSIClassifier(**roles, inference="mcmc", n_chains=1, n_samples=100,
                            random_state=0).fit(X)
        out["mcmc_fit_s"] = time.perf_counter() - t
        t = time.perf_counter()
        clf.predict_proba(X)
        out["predict_s"] = time.perf_counter() - t
        t = time.perf_counter()
        BSIClassifier(**roles, inference="exact").fit(X)
        out["exact_fit_s"] = time.perf_counter() - t
    out["total_s"] = time.perf_counter() - T0
    out["compile_s"] = _top_level(rec)
    print(json.dumps(out))


def _top_level(rec):
    # Top-level compilations (callees compile inside their caller's event).
    depth, starts, compiled = 0, {}, {}
    for ts, ev in rec.buffer:
        name = getattr(ev.data.get("dispatcher"), "__qualname__", None) or str(
            ev.data.get("dispatcher"))
        if ev.is_start:
            if depth == 0:
                starts[name] = ts
            depth += 1
        else:
            depth -= 1
            if depth == 0 and name in starts:
                compiled[name] = compiled.get(name, 0.0) + ts - starts.pop(name)
    return compiled


if __name__ == "__main__":
    sys.exit(main())
