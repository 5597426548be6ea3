"""Issue 20: the classifier without roles against the same classifier given the task's roles.

    python benchmarks/bench_roles.py                       # writes RESULTS_roles.md/.csv + figure
    python benchmarks/bench_roles.py --quick               # smoke run into a temporary folder
    python benchmarks/bench_roles.py --seeds 10 --n-jobs 2 --out /tmp/roles
    python benchmarks/bench_roles.py --external            # also the published files (long)
    python benchmarks/bench_roles.py --templates unary --only infer/cb --out /tmp/r  # issue 28

Tasks: :mod:`bsi_sklearn.datasets.errands` (errand and pick-and-place tasks drawn at random per
seed, labelled by a rule written as plain Python, demonstrated by a stochastic agent; neither
BSI's template sampler nor the paper's generators). Per cell (task kind, seed, training size,
label noise) one task is drawn, a training set of that size and 300 fresh test demonstrations;
with noise, ``round(noise * n)`` training labels chosen at random are flipped (the test set is
scored on the true verdicts). The same training set is used clean and noisy, and by every
variant, so the comparisons are paired.

Variants: roles (``given``: the task's true roles; ``all``: every proposition in every role,
the default before issue 20; ``infer``: ``roles="infer"``, the default now) x likelihood
(``cb``, ``ci``, ``calibrated``, ``ci`` with ``flip_prior``). Each is fitted with every other
default (``inference="auto"``, ``random_state`` = the seed, ``n_jobs=1``). A variant whose
option the installed classifier does not have (detected from ``BSIClassifier().get_params()``
and ``bsi_sklearn.model.likelihood.LIKELIHOODS``) is listed as not available. Every warning a fit
raises is recorded (never silenced) and counted per variant.

``--templates SET`` adds, beside every variant fitted, its twin with ``templates=SET`` (a
named set of the pattern catalogue, issue 28), named ``roles/likelihood+SET``: the paired
difference against ``infer/cb`` then measures the set. ``--only NAME,...`` fits those variants
alone (the others listed as skipped).
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

os.environ.setdefault("MPLBACKEND", "Agg")
HERE = Path(__file__).resolve().parent
import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

from _roles_report import write_outputs  # noqa: E402

from bsi_sklearn import BSIClassifier  # noqa: E402
from bsi_sklearn.datasets.errands import make_errand_demos, make_errand_task  # noqa: E402
from bsi_sklearn.model.likelihood import LIKELIHOODS  # noqa: E402

__all__ = ["Variant", "variants", "skip_variants", "with_templates", "flip_labels", "run_cell",
           "in_chains", "run_benchmark", "main", "SIZES", "NOISES", "KINDS", "FLIP_PRIOR"]

SIZES = (20, 40, 72)
NOISES = (0.0, 0.1)
KINDS = ("errand", "pick_place")
N_TEST = 300
#: Beta(a, b) prior of the flip rate for the ``ci+flip`` variant: mean 0.2, most mass below
#: 0.5. Fixed before any result, not matched to the 10 % of the noisy cells.
FLIP_PRIOR = (1.0, 4.0)


@dataclass(frozen=True)
class Variant:
    """One way of fitting: which roles, which likelihood, and whether the classifier has it."""

    roles: str          # "given", "all" or "infer"
    likelihood: str     # "cb", "ci", "calibrated" or "ci+flip"
    params: dict = field(default_factory=dict, hash=False, compare=False)
    available: bool = True
    reason: str = ""

    @property
    def name(self):
        return f"{self.roles}/{self.likelihood}"


def variants(flip_prior=FLIP_PRIOR):
    """Every variant of the benchmark, those the installed classifier lacks marked so.

    Returns
    -------
    list of Variant
        Roles ``given``, ``all``, ``infer`` x likelihoods ``cb``, ``ci``, ``calibrated``,
        ``ci+flip``, in that order.
    """
    params = BSIClassifier().get_params()
    has_roles = "roles" in params
    out = []
    for roles in ("given", "all", "infer"):
        for lik in ("cb", "ci", "calibrated", "ci+flip"):
            p, missing = {}, []
            if lik == "ci+flip":
                p["likelihood"] = "ci"
                if "flip_prior" in params:
                    p["flip_prior"] = tuple(flip_prior)
                else:
                    missing.append("no flip_prior parameter")
            elif lik in LIKELIHOODS:
                p["likelihood"] = lik
            else:
                missing.append(f"likelihood {lik!r} not in LIKELIHOODS")
            if roles in ("all", "infer") and has_roles:
                p["roles"] = roles
            elif roles == "infer":
                missing.append("no roles parameter")
            out.append(Variant(roles, lik, p, not missing, "; ".join(missing)))
    return out


def skip_variants(vlist, names):
    """``vlist`` with the variants named in ``names`` marked not fitted (``--skip``)."""
    known = {v.name for v in vlist}
    unknown = sorted(set(names) - known)
    if unknown:
        raise ValueError(f"--skip: unknown variant(s) {unknown}; known: {sorted(known)}")
    return [Variant(v.roles, v.likelihood, v.params, False, "skipped (--skip)")
            if v.name in names and v.available else v for v in vlist]


def with_templates(vlist, template_set):
    """``vlist`` and, after each variant fitted, its twin with ``templates=template_set``."""
    out = []
    for v in vlist:
        out.append(v)
        if v.available:
            out.append(Variant(v.roles, f"{v.likelihood}+{template_set}",
                               dict(v.params, templates=template_set)))
    return out


def flip_labels(y, noise, rng):
    """``y`` with ``round(noise * len(y))`` labels, chosen at random, flipped."""
    y = np.asarray(y).copy()
    k = int(round(noise * len(y)))
    if k:
        idx = rng.choice(len(y), k, replace=False)
        y[idx] = 1 - y[idx]
    return y


def in_chains(spec):
    """Whether ``spec``'s orders are disjoint chains (each subtask at most one immediate
    predecessor and one immediate successor): the orders the default prior (Prior 2, sets of
    chains) can hold. A rule with a join (two subtasks both before a third, unordered between
    themselves) is outside its support whatever the data.

    >>> from bsi_sklearn import Specification
    >>> in_chains(Specification(orders=[("a", "b"), ("b", "c")]))
    True
    >>> in_chains(Specification(orders=[("a", "c"), ("b", "c")]))
    False
    """
    closed = set(spec.orders)
    cover = [(a, b) for a, b in closed
             if not any((a, c) in closed and (c, b) in closed for _, c in closed)]
    succ = [a for a, _ in cover]
    pred = [b for _, b in cover]
    return len(succ) == len(set(succ)) and len(pred) == len(set(pred))


def _seeds(kind, seed, size):
    """Independent seeds of the task, the training set and the test set of a cell."""
    base = 100_003 * (KINDS.index(kind) + 1) + 1_009 * seed
    return base, base + 7 + size, base + 3


def _fit_one(variant, roles, X, y, X_test, y_test, seed):
    row = {"variant": variant.name, "roles": variant.roles, "likelihood": variant.likelihood,
           "available": variant.available}
    if not variant.available:
        return row
    kw = dict(variant.params, random_state=seed, n_jobs=1)
    if variant.roles == "given":
        kw.update(roles)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")  # count every warning, once per fit
        t0 = time.perf_counter()
        try:
            clf = BSIClassifier(**kw).fit(X, y)
        except (ValueError, TypeError) as exc:  # an option the classifier rejects
            row.update(error=f"{type(exc).__name__}: {exc}", fit_s=time.perf_counter() - t0)
            return row
        row["fit_s"] = time.perf_counter() - t0
    kinds = {}
    for w in caught:
        kinds[w.category.__name__] = kinds.get(w.category.__name__, 0) + 1
    pred = clf.predict(X_test)
    row.update(accuracy=float(np.mean(pred == y_test)), inference=clf.inference_,
               n_warnings=len(caught),
               warnings=";".join(f"{k}:{v}" for k, v in sorted(kinds.items())),
               map=clf.map_specification_.to_ltl(),
               map_accuracy=float(np.mean([clf.map_specification_.satisfied_by(x) == bool(t)
                                           for x, t in zip(X_test, y_test)])))
    return row


def run_cell(kind, seed, size, noises=NOISES, variant_list=None, n_test=N_TEST):
    """Fit every variant on one task and training size, clean and with flipped labels.

    Parameters
    ----------
    kind : {"errand", "pick_place"}
    seed : int
        Draws the task, its training and test demonstrations, and the flips.
    size : int
        Training demonstrations.
    noises : sequence of float
        Fractions of training labels flipped (0 = clean).
    variant_list : list of Variant, default=None
        :func:`variants` when None.
    n_test : int
        Fresh test demonstrations, scored on their true verdicts.

    Returns
    -------
    rows : list of dict
        One per (noise, variant): ``accuracy`` on the test set, ``inference``, ``n_warnings``
        and their kinds, ``fit_s``, the MAP and its accuracy; variants not available have
        ``available=False`` and no accuracy.
    """
    variant_list = variants() if variant_list is None else variant_list
    s_task, s_train, s_test = _seeds(kind, seed, size)
    task = make_errand_task(kind, random_state=s_task)
    train = make_errand_demos(task, size, random_state=s_train)
    test = make_errand_demos(task, n_test, random_state=s_test)
    rows = []
    for noise in noises:
        y = flip_labels(train.y, noise, np.random.default_rng(s_train + 1))
        for v in variant_list:
            row = {"kind": kind, "seed": seed, "n_train": size, "noise": noise,
                   "n_props": len(task.feature_names), "rule_in_chains": in_chains(
                       task.specification()), "train_pos": int(y.sum()),
                   "flipped": int(np.sum(y != train.y)), "test_pos": int(test.y.sum()),
                   "n_test": n_test}
            row.update(_fit_one(v, train.roles, train.traces, y, test.traces, test.y, seed))
            rows.append(row)
    return rows


def run_benchmark(kinds=KINDS, seeds=range(20), sizes=SIZES, noises=NOISES, n_jobs=1,
                  verbose=1, variant_list=None, n_test=N_TEST):
    """Every cell; a DataFrame with one row per (cell, noise, variant)."""
    import pandas as pd
    from joblib import Parallel, delayed
    from tqdm.auto import tqdm

    variant_list = variants() if variant_list is None else variant_list
    cells = [(k, s, n) for k in kinds for s in seeds for n in sizes]
    bar = tqdm(total=len(cells), desc="cells (kind, seed, size)", disable=not verbose)
    rows = []
    jobs = Parallel(n_jobs=n_jobs, return_as="generator")(
        delayed(run_cell)(k, s, n, noises, variant_list, n_test) for k, s, n in cells)
    for cell_rows in jobs:
        rows.extend(cell_rows)
        bar.update()
    bar.close()
    return pd.DataFrame(rows)


def _warm_up():
    """Compile the numba kernels before anything is timed."""
    task = make_errand_task("pick_place", random_state=0)
    d = make_errand_demos(task, 8, random_state=0)
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        BSIClassifier(random_state=0).fit(d.traces, d.y)
        BSIClassifier(inference="mcmc", n_samples=50, n_chains=1, random_state=0).fit(
            d.traces, d.y)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help="2 seeds, sizes 20 and 40, 60 test demonstrations; writes into "
                             "a temporary folder unless --out is given")
    parser.add_argument("--seeds", type=int, default=20, help="independent tasks per kind")
    parser.add_argument("--n-jobs", type=int, default=1, help="cells in parallel (joblib)")
    parser.add_argument("--verbose", type=int, default=1, help="0: no progress bars")
    parser.add_argument("--out", default=None, help="folder of RESULTS_roles.md/.csv, figures/")
    parser.add_argument("--flip-prior", type=float, nargs=2, default=FLIP_PRIOR,
                        metavar=("A", "B"), help="Beta prior of the ci+flip variant")
    parser.add_argument("--external", action="store_true",
                        help="also the published benchmark files (roles_external.py)")
    parser.add_argument("--external-every", type=int, default=8,
                        help="every k-th published file (default fits without screening go "
                             "to MCMC on the 5-7-proposition files: 10-25 s each)")
    parser.add_argument("--data", default=None, help="published files (default ../shared/"
                                                     "benchmarks-data)")
    parser.add_argument("--skip", default="", metavar="NAME,...",
                        help="variants not to fit, e.g. all/ci+flip (listed in the results "
                             "as skipped, with the reason)")
    parser.add_argument("--only", default="", metavar="NAME,...",
                        help="fit these variants alone (the others listed as skipped)")
    parser.add_argument("--templates", default=None, metavar="SET",
                        help="add every fitted variant's twin with templates=SET (unary, "
                             "declare, all)")
    args = parser.parse_args(argv)
    if args.out is not None:
        out = Path(args.out)
    elif args.quick:
        out = Path(tempfile.mkdtemp(prefix="bench_roles_"))
    else:
        out = HERE
    out.mkdir(parents=True, exist_ok=True)
    seeds = range(2 if args.quick else args.seeds)
    sizes = (20, 40) if args.quick else SIZES
    n_test = 60 if args.quick else N_TEST
    t0 = time.perf_counter()
    _warm_up()
    vlist = variants(args.flip_prior)
    skip = [n for n in args.skip.split(",") if n]
    if args.only:
        keep = set(args.only.split(","))
        skip += [v.name for v in vlist if v.name not in keep and v.name not in skip]
    vlist = skip_variants(vlist, skip)
    if args.templates is not None:
        vlist = with_templates(vlist, args.templates)
    df = run_benchmark(KINDS, seeds, sizes, NOISES, args.n_jobs, args.verbose, vlist, n_test)
    external = None
    if args.external:
        from roles_external import run_external

        external = run_external(args.data, quick=args.quick, every=args.external_every,
                                verbose=args.verbose, out=out)
    command = "python benchmarks/bench_roles.py " + " ".join(argv if argv is not None
                                                              else sys.argv[1:])
    paths = write_outputs(df, vlist, out, command=command.strip(),
                          seconds=time.perf_counter() - t0, quick=args.quick,
                          settings={"seeds": len(seeds), "sizes": sizes, "n_test": n_test,
                                    "flip_prior": tuple(args.flip_prior),
                                    "n_jobs": args.n_jobs}, external=external)
    if args.verbose:
        for p in paths:
            print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
