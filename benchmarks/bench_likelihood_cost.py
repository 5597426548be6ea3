"""Time of the exact engine alone, per likelihood, on the paper's problems (issue 20).

The engine (``exact_posterior``) on a precomputed clause truth, so validation and clause truth
do not blur the comparison: the dinner table (30 demonstrations, 8 of them unacceptable, its
roles) and the LFE missions without roles (18, 36, 72 missions, MO1 labels, every proposition
a global candidate and a subtask). Median of warm calls. Run it with ``PYTHONPATH`` on two
checkouts to compare them (likelihoods a checkout does not have are skipped)::

    PYTHONPATH=. python benchmarks/bench_likelihood_cost.py [--repeats 5] [--json out.json]
"""

import argparse
import json
import statistics
import time

import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

import numpy as np

from bsi_sklearn.data.roles import resolve_roles
from bsi_sklearn.data.traces import check_labels, check_traces
from bsi_sklearn.datasets import make_dinner_table_demos
from bsi_sklearn.inference.exact import ExactWorkExceeded, exact_posterior
from bsi_sklearn.model import make_model
from bsi_sklearn.model.clauses import clause_truth
from bsi_sklearn.model.likelihood import LIKELIHOODS

#: (likelihood, flip prior) of each column; the flip prior only where this checkout has it.
SETTINGS = (("cb", None), ("ci", None), ("calibrated", None), ("ci", (1.0, 9.0)))
#: Work budget of the enumerations with a flip prior (inference="auto"'s times 10): violations
#: are cheap under it, the posterior flat, and without roles the enumeration runs for many
#: minutes. The others run unbudgeted (the budget counts every hypothesis CI may list).
MAX_WORK = 1.5e9


def _problems():
    d = make_dinner_table_demos(30, n_negative=8, random_state=1)
    yield "dinner table, 30 demos", d.traces, d.labels, d.roles
    from lfe import LFEPropositionExtractor, make_lfe_dataset

    for n, seed in ((18, 2), (36, 3), (72, 1)):
        ds = make_lfe_dataset(n, random_state=seed)
        X = LFEPropositionExtractor().fit_transform(ds.scenarios)
        yield f"LFE no roles, {n} missions", X, ds.labels["MO1"].to_numpy(), {}


def _engine_input(X, y, roles):
    traces = check_traces(X)
    y01, _ = check_labels(y, traces.n_demos, None)
    r = resolve_roles(roles.get("global_candidates"), roles.get("subtasks"),
                      roles.get("conditions"), traces.n_props, traces.feature_names)
    return clause_truth(traces, r), y01, r


def _model(r, likelihood, flip_prior):
    kw = {} if flip_prior is None else {"flip_prior": flip_prior}
    return make_model(prior="sets_of_chains", likelihood=likelihood, n_globals=r.n_globals,
                      n_subtasks=r.n_subtasks, **kw)


def _median_time(fn, repeats):
    fn()
    walls = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        walls.append(time.perf_counter() - t0)
    return statistics.median(walls)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--json", default=None)
    args = parser.parse_args(argv)
    rows = []
    for name, X, y, roles in _problems():
        truth, y01, r = _engine_input(X, y, roles)
        for likelihood, flip_prior in SETTINGS:
            if likelihood not in LIKELIHOODS:
                continue
            try:
                model = _model(r, likelihood, flip_prior)
            except TypeError:  # a checkout without flip_prior
                continue
            label = likelihood if flip_prior is None else f"{likelihood}+flip{flip_prior}"
            try:
                res = exact_posterior(truth, y01, model,
                                      max_work=None if flip_prior is None else MAX_WORK)
            except ExactWorkExceeded:
                rows.append({"problem": name, "likelihood": label, "seconds": None})
                print(f"{name:28s} {label:20s} over the work budget ({MAX_WORK:.1e})",
                      flush=True)
                continue
            t = _median_time(lambda m=model, t=truth, y=y01: exact_posterior(t, y, m),
                             args.repeats)
            rows.append({"problem": name, "likelihood": label, "seconds": t,
                         "kept": len(res.log_prob),
                         "log_evidence": float(res.log_evidence),
                         "p_map": float(np.exp(res.log_prob[0]))})
            print(f"{name:28s} {label:20s} {t * 1e3:9.2f} ms  kept {len(res.log_prob):>8,}"
                  f"  p_map {rows[-1]['p_map']:.4f}", flush=True)
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(rows, fh, indent=1)


if __name__ == "__main__":
    main()
