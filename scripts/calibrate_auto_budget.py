"""Calibrate ``inference="auto"``'s exact budget against its MCMC fallback's cost.

For every fit of the study's extended-set cells of one repeat (the training sets of
``bsi-lfe study``, each objective, the inner search's grid of prior x epsilon), times the exact
engine without a budget (and records its work count, ``ExactResult.work``) and the classifier's
default MCMC (and records :func:`bsi_sklearn.inference.mcmc.sampling_count`). Prints, per fit,
both times, the nanoseconds per unit of each count, and the ratio of the medians: the factor
by which a unit of the sampler's count outweighs a unit of the exact engine's
(``bsi_sklearn.inference.auto_budget.SAMPLING_TO_EXACT``), and the total CPU time auto would
spend for several factors. ``--attempts`` then times the exact attempts that fail their budget
(what auto spends before it samples), and with ``--sampling`` the default MCMC fit that follows
each (the ratio of the two is what a failed attempt costs). One process, one thread; CPU
seconds (and wall seconds for the attempts).

    python scripts/calibrate_auto_budget.py --sizes 6 12 18 36 72 --out cal.csv
    python scripts/calibrate_auto_budget.py --sizes 6 12 18 36 72 --out cal.csv \
        --attempts failed_attempts.csv
    python scripts/calibrate_auto_budget.py --out benchmarks/auto_budget/calibration.csv \
        --attempts attempts.csv --factors 24 --sampling
"""

import argparse
import time

import numpy as np
import pandas as pd

from bsi_sklearn import BSIClassifier
from bsi_sklearn.data.inferred_roles import infer_roles
from bsi_sklearn.data.traces import check_traces
from bsi_sklearn.inference.auto_budget import AUTO_EXACT_WORK, AUTO_MAX_WORK
from bsi_sklearn.inference.exact import ExactWorkExceeded, exact_posterior
from bsi_sklearn.inference.mcmc import sampling_count
from bsi_sklearn.model import make_model
from bsi_sklearn.model.clauses import clause_truth
from lfe.study import derive_seed
from lfe.study._cells import draw_training_set, repeat_seeds, search_grid, simulate_repeat


def _problem(clf, X, y):
    traces = check_traces(X)
    roles = infer_roles(traces, y, clf.global_candidates, clf.subtasks, clf.conditions)
    model = make_model(prior=clf.prior, likelihood=clf.likelihood, n_globals=roles.n_globals,
                       n_subtasks=roles.n_subtasks, p_global=clf.p_global,
                       p_eventual=clf.p_eventual, p_part=clf.p_part, n_new=clf.n_new,
                       epsilon=clf.epsilon, flip_prior=clf.flip_prior, n_demos=len(y))
    return clause_truth(traces, roles), model


def _training_sets(args):
    seeds = repeat_seeds(0, args.repeat)
    data = simulate_repeat(n_pool=max(args.sizes), test_size=1, noises=[args.noise],
                           propositions=[args.propositions], **seeds)
    props, roles = data["props"][args.propositions], data["roles"][args.propositions]

    def training(n_train, k):
        train = draw_training_set(data["clean"], data["n_pool"], n_train,
                                  derive_seed(0, args.repeat, 2, n_train))
        return [props[i] for i in train], data["labels"][args.noise][train, k]

    return training, roles


def failed_attempts(args, factors=(0.0, 24.0), sampling=False):
    """CPU seconds of every exact attempt that fails its budget, per factor (--attempts).

    Reads the fits of ``--out`` (a calibration already run with the same sizes) and, for
    each factor, times the budgeted attempt of every fit whose recorded exact work is over
    ``min(max(AUTO_EXACT_WORK, factor x sampling count), AUTO_MAX_WORK)``: what auto spends
    before it samples (CPU and wall seconds). With ``sampling``, also the classifier's default
    MCMC fit of the same data (what follows the attempt).
    """
    df = pd.read_csv(args.out)
    training, roles = _training_sets(args)
    rows = []
    for r in df.itertuples():
        eps = None if pd.isna(r.epsilon) else float(r.epsilon)
        for factor in factors:
            budget = min(max(AUTO_EXACT_WORK, factor * r.mcmc_count), AUTO_MAX_WORK)
            if not (pd.isna(r.exact_work) or r.exact_work > budget):
                continue
            X, y = training(r.n_train, r.objective)
            truth, model = _problem(BSIClassifier(prior=r.prior, epsilon=eps, **roles), X, y)
            t0, w0 = time.process_time(), time.perf_counter()
            try:
                exact_posterior(truth, y, model, tol=1e-9, max_work=budget)
            except ExactWorkExceeded:
                pass
            else:
                raise AssertionError(f"{r}: the exact work recorded was over {budget:.3g}")
            rows.append(dict(n_train=r.n_train, objective=r.objective, prior=r.prior,
                             epsilon=eps, factor=factor, attempt_s=time.process_time() - t0,
                             attempt_wall_s=time.perf_counter() - w0))
            if sampling:
                t0, w0 = time.process_time(), time.perf_counter()
                BSIClassifier(prior=r.prior, epsilon=eps, inference="mcmc", random_state=0,
                              n_jobs=1, **roles).fit(X, y)
                rows[-1].update(mcmc_s=time.process_time() - t0,
                                mcmc_wall_s=time.perf_counter() - w0)
                rows[-1]["ratio"] = rows[-1]["attempt_s"] / rows[-1]["mcmc_s"]
            print(rows[-1], flush=True)
    return pd.DataFrame(rows)


def main(argv=None):
    """Run the calibration (or, with --attempts, time the failed attempts)."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[6, 12, 18, 36, 72])
    ap.add_argument("--noise", type=float, default=0.04)
    ap.add_argument("--repeat", type=int, default=0)
    ap.add_argument("--propositions", default="extended")
    ap.add_argument("--out", default="calibrate_auto_budget.csv")
    ap.add_argument("--max-factor", type=float, default=300.0,
                    help="stop the exact engine beyond this many times the sampling count")
    ap.add_argument("--attempts", default=None, metavar="CSV",
                    help="instead: time the failed exact attempts of the fits in --out "
                         "(--factors) and write them to CSV")
    ap.add_argument("--factors", type=float, nargs="+", default=[0.0, 24.0],
                    help="with --attempts: the SAMPLING_TO_EXACT factors whose failures to time")
    ap.add_argument("--sampling", action="store_true",
                    help="with --attempts: also time the MCMC fit that follows each attempt")
    args = ap.parse_args(argv)
    if args.attempts is not None:
        failed_attempts(args, args.factors, args.sampling).to_csv(args.attempts, index=False)
        return
    training, roles = _training_sets(args)
    grid = search_grid(False)
    rows = []
    for n_train in args.sizes:
        for k in range(3):
            X, y = training(n_train, k)
            if not y.any():
                continue
            for prior in grid["prior"]:
                for eps in grid["epsilon"]:
                    clf = BSIClassifier(prior=prior, epsilon=eps, **roles)
                    truth, model = _problem(clf, X, y)
                    count = sampling_count(truth, y, model, n_chains=clf.n_chains,
                                           n_samples=clf.n_samples, burn_in=clf.burn_in)
                    t0 = time.process_time()
                    try:  # far beyond any factor considered: what it costs to find that out
                        work = exact_posterior(truth, y, model, tol=clf.tol,
                                               max_work=args.max_factor * count).work
                    except ExactWorkExceeded:
                        work = np.nan
                    t_exact = time.process_time() - t0
                    t0 = time.process_time()
                    BSIClassifier(prior=prior, epsilon=eps, inference="mcmc", random_state=0,
                                  n_jobs=1, **roles).fit(X, y)
                    t_mcmc = time.process_time() - t0
                    rows.append(dict(n_train=n_train, objective=k, prior=prior, epsilon=eps,
                                     exact_s=t_exact, exact_work=work, mcmc_s=t_mcmc,
                                     mcmc_count=count))
                    print(rows[-1], flush=True)
    df = pd.DataFrame(rows)
    df.to_csv(args.out, index=False)
    done = df[df.exact_work.notna()]
    ns_exact = 1e9 * done.exact_s / done.exact_work
    ns_mcmc = 1e9 * df.mcmc_s / df.mcmc_count
    print(f"ns per exact unit: median {ns_exact.median():.3g} "
          f"[{ns_exact.min():.3g}, {ns_exact.max():.3g}]")
    print(f"ns per sampling unit: median {ns_mcmc.median():.3g} "
          f"[{ns_mcmc.min():.3g}, {ns_mcmc.max():.3g}]")
    print(f"ratio of medians: {ns_mcmc.median() / ns_exact.median():.3g}")
    # What auto would spend with each factor: exact where it fits, else the failed attempt
    # (stopped at the budget; measured only up to --max-factor) and the sampling.
    for factor in (0, 3, 6, 12, 24, 48, 96, 200):
        budget = np.maximum(AUTO_EXACT_WORK, factor * df.mcmc_count)
        exact = df.exact_work.notna() & (df.exact_work <= budget)
        total = np.where(exact, df.exact_s, df.mcmc_s).sum()
        print(f"factor {factor:>3}: {int(exact.sum())}/{len(df)} exact, exact or sampled "
              f"{total:.1f} s (all sampled {df.mcmc_s.sum():.1f} s)")


if __name__ == "__main__":
    main()
