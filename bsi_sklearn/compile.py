"""Compile every numba kernel of the package into numba's on-disk cache, once after installing.

::

    python -m bsi_sklearn.compile        # or: bsi compile

A fresh environment otherwise compiles the kernels on their first use: the first fit waits
seconds to a minute on the compiler (issue 29), and every later process loads them from the
cache in a fraction of a second. This fills the cache ahead of time by running small
workloads through the public API (exact inference with each kind of likelihood, sampling,
prediction, monitoring, the reference enumeration, the simulated datasets), which compile
each kernel with the argument types the package itself passes. ``./run`` and ``./test`` run it
once, after they install the project (``scripts/ensure-venv``).

Workloads run in parallel processes (``--jobs``, by default one per available CPU), each
printing one line when it is done; a kernel already in the cache is loaded, not compiled, so
running it again costs a few seconds. The cache is numba's: beside the package's modules
(``__pycache__``), or ``NUMBA_CACHE_DIR`` when set (:mod:`bsi_sklearn._numba_cache`).
"""

import argparse
import os
import sys
import time

__all__ = ["WORKLOADS", "compile_all", "main", "add_arguments", "run"]


def _problem():
    # The README's quick start: three propositions, two acceptable demonstrations, one not.
    import numpy as np

    good = [np.array([[1, 0, 0], [1, 1, 0], [1, 1, 1]]),
            np.array([[1, 0, 0], [1, 0, 0], [1, 1, 0], [1, 1, 1]])]
    bad = [np.array([[1, 0, 0], [1, 0, 1], [1, 1, 1]])]
    return good + bad, [1, 1, 0], dict(global_candidates=[0], subtasks=[1, 2])


def _exact():
    """Exact inference: every likelihood kind (sums, joint tables, counts) and prior."""
    from bsi_sklearn import BSIClassifier

    X, y, roles = _problem()
    for prior, likelihood, flip in (("sets_of_chains", "cb", None), ("forest", "ci", (1, 9)),
                                    ("linear_chain", "calibrated", None)):
        BSIClassifier(prior=prior, likelihood=likelihood, flip_prior=flip, inference="exact",
                      **roles).fit(X, y)
    BSIClassifier(random_state=0).fit(X, y)  # roles read from the data, "auto"
    # 2,048 demonstrations of each label: the joint likelihood table would pass
    # _exact_kernels.MAX_CELLS, so the likelihood is read from the counts.
    bad = [X[2], X[2][::-1]]
    BSIClassifier(likelihood="ci", flip_prior=(1, 9), inference="exact", **roles).fit(
        X[:2] * 1024 + bad * 1024, [1] * 2048 + [0] * 2048)


def _mcmc():
    """Sampling: tempered chains, the beam search, the rounds and the support's completion."""
    from bsi_sklearn import BSIClassifier

    X, y, roles = _problem()
    for likelihood, flip in (("cb", None), ("ci", (1, 9))):  # the flip rate: violation rows
        BSIClassifier(inference="mcmc", likelihood=likelihood, flip_prior=flip, n_samples=200,
                      burn_in=20, random_state=0, **roles).fit(X, y)
    # n_samples="auto": rounds, and the neighbours of the visited states weighed after each
    BSIClassifier(inference="mcmc", random_state=0, **roles).fit(X, y)
    # past the closure's budget (too large a problem to reach here), the clauses' inclusion
    import numpy as np

    from bsi_sklearn.inference.stopping import inclusion_by_chain

    inclusion_by_chain(np.array([[1, 1, -1]], dtype=np.int16), np.ones(1), [np.zeros(1, int)],
                       1, 1)


def _predict():
    """Prediction, monitoring and the ungrouped reference enumeration."""
    import numpy as np

    from bsi_sklearn import BSIClassifier
    from bsi_sklearn.data.roles import resolve_roles
    from bsi_sklearn.data.traces import check_traces
    from bsi_sklearn.inference.exact import exact_posterior
    from bsi_sklearn.model import make_model
    from bsi_sklearn.model.clauses import clause_truth
    from bsi_sklearn.model.priors import enumerate_structures, log_prior_structure, n_orders_of

    X, y, roles = _problem()
    clf = BSIClassifier(**roles).fit(X, y)
    clf.predict_proba(X)
    clf.monitor_proba(X)
    monitor = clf.monitor()
    for step in X[0]:
        monitor.update(step)
    monitor.finish()
    traces = check_traces(X)
    resolved = resolve_roles(roles["global_candidates"], roles["subtasks"], None,
                             traces.n_props, traces.feature_names)
    model = make_model(prior="sets_of_chains", likelihood="cb", n_globals=1, n_subtasks=2)
    exact_posterior(clause_truth(traces, resolved), np.asarray(y), model, grouped=False)
    for parent in enumerate_structures("forest", 2):
        log_prior_structure(parent, model)
        n_orders_of(parent)


def _datasets():
    """The simulated datasets' agent (grid planning, the Dubins car)."""
    from bsi_sklearn.datasets import make_poi_threat_demos

    make_poi_threat_demos(1, n_demos=1, random_state=0)


#: ``(name, function)``: what each worker compiles, the longest first.
WORKLOADS = (("sampling", _mcmc), ("exact inference", _exact),
             ("prediction, monitoring, reference enumeration", _predict),
             ("simulated datasets", _datasets))


def _run_one(index):
    """Run one workload; ``(seconds, kernels compiled, kernels loaded from the cache)``."""
    from numba.core import event

    from bsi_sklearn._compile_progress import quiet_notice

    class Count(event.Listener):
        def __init__(self):
            self.depth = self.top = 0

        def on_start(self, ev):
            self.top += self.depth == 0
            self.depth += 1

        def on_end(self, ev):
            self.depth -= 1

    count = Count()
    start = time.perf_counter()
    hits = _cache_hits()
    with quiet_notice(), event.install_listener("numba:compile", count):
        WORKLOADS[index][1]()
    return time.perf_counter() - start, count.top, _cache_hits() - hits


def _cache_hits():
    # Kernels this process loaded from numba's cache so far.
    from numba.core.registry import CPUDispatcher

    seen = {}
    for name, module in list(sys.modules.items()):
        if name.split(".")[0] != "bsi_sklearn" or module is None:
            continue
        for value in list(vars(module).values()):
            if isinstance(value, CPUDispatcher):
                seen[id(value)] = sum(value.stats.cache_hits.values())
    return sum(seen.values())


def _cpus():
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _where():
    from numba.core import config

    return config.CACHE_DIR or "beside the package's modules (__pycache__)"


def compile_all(jobs=None, stream=None):
    """Compile (or load) every kernel; one line on ``stream`` per workload, then a summary.

    Parameters
    ----------
    jobs : int, default=None
        Processes running the workloads at once; ``None``: one per available CPU. ``1`` runs
        them in this process.
    stream : file, default=None
        Where the progress lines go (standard error by default).

    Returns
    -------
    compiled : int
        Kernels compiled (the others were loaded from the cache).
    """
    from numba.core.dispatcher import Dispatcher  # (the package, so the cache, is set up)

    stream = sys.stderr if stream is None else stream
    if getattr(Dispatcher.enable_caching, "_bsi_sklearn_skips", False):  # _numba_cache
        print("bsi_sklearn: numba has no writable cache here, so nothing can be compiled ahead "
              "(set NUMBA_CACHE_DIR to a writable folder)", file=stream, flush=True)
        return 0
    jobs = min(len(WORKLOADS), _cpus() if jobs is None else max(int(jobs), 1))
    print(f"bsi_sklearn: compiling the numba kernels into numba's cache ({jobs} "
          f"process{'es' if jobs > 1 else ''}; once after installing, about a minute)",
          file=stream, flush=True)
    start = time.perf_counter()
    total = loaded = 0

    def report(index, result):
        nonlocal total, loaded
        seconds, compiled, hits = result
        total += compiled
        loaded += hits
        print(f"  {WORKLOADS[index][0]}: {seconds:.1f} s, {compiled} compiled, {hits} loaded",
              file=stream, flush=True)

    if jobs == 1:
        for i in range(len(WORKLOADS)):
            report(i, _run_one(i))
    else:
        import multiprocessing
        from concurrent.futures import ProcessPoolExecutor, as_completed

        context = multiprocessing.get_context("spawn")  # no fork of a process that holds numba
        with ProcessPoolExecutor(jobs, mp_context=context) as pool:
            futures = {pool.submit(_run_one, i): i for i in range(len(WORKLOADS))}
            for future in as_completed(futures):
                report(futures[future], future.result())
    print(f"bsi_sklearn: done in {time.perf_counter() - start:.0f} s: {total} kernels compiled, "
          f"{loaded} loaded from the cache ({_where()})", file=stream, flush=True)
    return total


def add_arguments(parser):
    """Arguments of ``bsi compile``."""
    parser.add_argument("--jobs", type=int, default=None, metavar="N",
                        help="processes compiling at once (default: one per available CPU; "
                             "1: in this process)")


def run(args):
    """``bsi compile``: fill numba's cache; exit status 0."""
    if args.jobs is not None and args.jobs < 1:
        raise SystemExit(f"bsi compile: --jobs must be at least 1, got {args.jobs}")
    compile_all(args.jobs)
    return 0


def main(argv=None):
    """``python -m bsi_sklearn.compile [--jobs N]``."""
    parser = argparse.ArgumentParser(
        prog="python -m bsi_sklearn.compile",
        description="Compile bsi_sklearn's numba kernels into numba's cache (once after "
                    "installing).")
    add_arguments(parser)
    return run(parser.parse_args(argv))


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
