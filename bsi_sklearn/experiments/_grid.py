"""Fit a grid of (setting x training-set size x repeat) classifiers and aggregate the results."""

from __future__ import annotations

import math
import sys
import time
from dataclasses import asdict, dataclass

import numpy as np
import pandas as pd
from sklearn.metrics import accuracy_score, f1_score
from sklearn.utils import Bunch, check_random_state
from sklearn.utils.parallel import Parallel, delayed

from bsi_sklearn.classifier import BSIClassifier
from bsi_sklearn.metrics import classify_orders, similarity_summary

__all__ = ["Setting", "make_pool", "run_grid", "aggregate", "format_orders", "METRICS",
           "SETTING_COLUMNS"]

#: Per-fit measures that :func:`aggregate` summarises (booleans become fractions).
METRICS = (
    "expected_similarity",
    "best_similarity",
    "map_similarity",
    "map_is_truth",
    "truth_in_top_k",
    "truth_probability",
    "n_specifications",
    "n_formulas_99",
    "correct_orders",
    "incorrect_orders",
    "extra_orders",
    "map_correct_orders",
    "map_extra_orders",
    "test_accuracy",
    "test_f1",
    "fit_time",
)

#: Columns that identify a setting (one line of a figure).
SETTING_COLUMNS = ("domain", "prior", "likelihood", "labels")

_RHAT_OK = 1.05


@dataclass(frozen=True)
class Setting:
    """One classifier configuration on one domain: a line of a figure.

    Parameters
    ----------
    domain : str
        Key of the data pools the setting is fitted on (e.g. ``"scenario 2"``).
    prior : {"linear_chain", "sets_of_chains", "forest"}
    likelihood : {"cb", "ci"}, default="cb"
    supervised : bool, default=False
        False: positive demonstrations only; True: the same positives plus negatives.
    params : tuple of (str, float), default=()
        Prior hyperparameters passed to ``BSIClassifier`` (e.g. ``(("n_new", 0.5),)``);
        empty: the classifier's defaults.
    """

    domain: str
    prior: str
    likelihood: str = "cb"
    supervised: bool = False
    params: tuple = ()

    @property
    def labels(self):
        """``"positive"`` (positive-only learning) or ``"supervised"``."""
        return "supervised" if self.supervised else "positive"

    @property
    def hyperparameters(self):
        """``"default"`` or the ``params`` as ``"name=value, ..."``.

        Examples
        --------
        >>> Setting("d", "forest", params=(("n_new", 0.5),)).hyperparameters
        'n_new=0.5'
        """
        return ", ".join(f"{k}={v:g}" for k, v in self.params) or "default"


def make_pool(positives, negatives, X_test, y_test, roles, truth, random_state):
    """The demonstrations one repeat of an experiment draws its training sets from.

    Positives and negatives are shuffled once; a training set of size ``n`` takes the first
    ``n`` positives (and, when supervised, the first negatives), so the training sets of one
    repeat are nested, as when demonstrations are collected one after another.

    Parameters
    ----------
    positives, negatives : list of DataFrame
        Acceptable and unacceptable demonstrations to train on.
    X_test, y_test : list of DataFrame, array-like of int
        Held-out demonstrations and their labels, for classification accuracy.
    roles : dict
        ``global_candidates``, ``subtasks``, ``conditions`` (BSIClassifier parameters).
    truth : Specification
        The ground truth.
    random_state : int, RandomState instance or None
        Order of the shuffles.

    Returns
    -------
    pool : Bunch
    """
    rng = check_random_state(random_state)
    pos = [positives[i] for i in rng.permutation(len(positives))]
    neg = [negatives[i] for i in rng.permutation(len(negatives))]
    return Bunch(positives=pos, negatives=neg, X_test=list(X_test),
                 y_test=np.asarray(y_test, dtype=int), roles=dict(roles), truth=truth)


def n_negatives(size, ratio):
    """Negatives added to ``size`` positives in the supervised variant (at least one)."""
    return max(1, math.ceil(size * ratio))


def _fit_one(setting, pool, size, negative_ratio, seed, classifier_params, k):
    X = list(pool.positives[:size])
    y = None
    n_neg = 0
    if setting.supervised:
        n_neg = n_negatives(size, negative_ratio)
        if n_neg > len(pool.negatives):
            raise ValueError(
                f"training size {size} needs {n_neg} negatives, the pool of "
                f"{setting.domain!r} has {len(pool.negatives)}"
            )
        X += pool.negatives[:n_neg]
        y = np.r_[np.ones(size, dtype=int), np.zeros(n_neg, dtype=int)]
    clf = BSIClassifier(prior=setting.prior, likelihood=setting.likelihood, **pool.roles,
                        **{**classifier_params, **dict(setting.params)}, random_state=seed)
    start = time.perf_counter()
    clf.fit(X, y)
    fit_time = time.perf_counter() - start
    post = clf.posterior_
    summary = similarity_summary(post, pool.truth, k=k)
    map_split = classify_orders(clf.map_specification_, pool.truth)
    map_orders = map_split.counts
    cum = np.cumsum(post.probabilities)
    row = {
        **asdict(setting),
        "labels": setting.labels,
        "size": size,
        "n_negative": n_neg,
        "seed": seed,
        "inference": clf.inference_,
        "n_hypotheses": clf.n_hypotheses_,
        **summary,
        "n_formulas_99": int(min(np.searchsorted(cum, 0.99 * cum[-1]) + 1, len(cum))),
        "map_correct_orders": map_orders.correct,
        "map_extra_orders": map_orders.extra,
        "map_incorrect_orders": map_orders.incorrect,
        "map_extra_pairs": format_orders(map_split.extra),
        "map_ltl": clf.map_specification_.to_ltl(),
        "fit_time": fit_time,
        "rhat": np.nan,
        "converged": True,
    }
    if len(pool.X_test):
        y_pred = clf.predict(pool.X_test)
        row["test_accuracy"] = accuracy_score(pool.y_test, y_pred)
        row["test_f1"] = f1_score(pool.y_test, y_pred, average="weighted", zero_division=0)
    else:
        row["test_accuracy"] = row["test_f1"] = np.nan
    if clf.mcmc_diagnostics_ is not None:
        row["rhat"] = clf.mcmc_diagnostics_["rhat"]
        row["converged"] = bool(row["rhat"] <= _RHAT_OK)
    row["hyperparameters"] = setting.hyperparameters
    del row["supervised"], row["params"]
    return row


def format_orders(orders):
    """Orders as sorted ``"a<b"`` items joined by ``";"`` (``""`` for none): a CSV-safe cell.

    Examples
    --------
    >>> format_orders({("omega_fork", "omega_spoon"), ("omega_a", "omega_b")})
    'omega_a<omega_b;omega_fork<omega_spoon'
    """
    return ";".join(sorted(f"{a}<{b}" for a, b in orders))


def progress(iterable, *, total, desc, verbose):
    """A tqdm progress bar on stderr when ``verbose > 0`` and stderr is a terminal."""
    from tqdm import tqdm

    enabled = bool(verbose) and sys.stderr.isatty()
    return tqdm(iterable, total=total, desc=desc, disable=not enabled, leave=False)


def run_grid(pools, settings, sizes, *, classifier_params=None, negative_ratio=0.5, k=5,
             n_jobs=None, random_state=None, verbose=0, desc="fits"):
    """Fit every setting at every training-set size on every repeat's pool.

    Parameters
    ----------
    pools : dict of str -> list of Bunch
        Per domain, one pool (:func:`make_pool`) per repeat.
    settings : sequence of Setting
    sizes : sequence of int
        Numbers of positive demonstrations in the training sets.
    classifier_params : dict, default=None
        Extra ``BSIClassifier`` parameters (inference, n_samples, n_chains, ...).
    negative_ratio : float, default=0.5
        The supervised variant adds ``max(1, ceil(ratio * size))`` negatives to the ``size``
        positives.
    k : int, default=5
        Size of the top list for best similarity and truth-in-top-k.
    n_jobs : int, default=None
        Fits run in parallel threads (the inference kernels release the GIL).
    random_state : int, RandomState instance or None, default=None
        Source of the per-fit seeds; results do not depend on ``n_jobs``.
    verbose : int, default=0
        Progress bar when > 0 and stderr is a terminal.
    desc : str, default="fits"
        Label of the progress bar.

    Returns
    -------
    results : DataFrame
        One row per fit: setting columns, ``size``, ``repeat``, the similarity summary
        (:func:`bsi_sklearn.metrics.similarity_summary`), order counts of the MAP and its
        extra orders (``map_extra_pairs``, see :func:`format_orders`),
        ``n_formulas_99`` (fewest specifications holding 99% of the mass), held-out
        ``test_accuracy`` / ``test_f1``, ``fit_time``, ``inference``, ``rhat``.
    """
    params = dict(classifier_params or {})
    params.setdefault("n_jobs", 1)
    sizes = [int(s) for s in sizes]
    for setting in settings:
        if setting.domain not in pools:
            raise ValueError(f"no pools for the domain {setting.domain!r} of {setting}")
        for r, pool in enumerate(pools[setting.domain]):
            if max(sizes) > len(pool.positives):
                raise ValueError(
                    f"training size {max(sizes)} exceeds the {len(pool.positives)} positives "
                    f"of pool {r} of {setting.domain!r}"
                )
    n_repeats = min(len(p) for p in pools.values())
    rng = check_random_state(random_state)
    seeds = rng.randint(np.iinfo(np.int32).max, size=(len(settings), n_repeats, len(sizes)))
    tasks = [(i, r, j) for i in range(len(settings)) for r in range(n_repeats)
             for j in range(len(sizes))]
    jobs = (
        delayed(_fit_one)(settings[i], pools[settings[i].domain][r], sizes[j], negative_ratio,
                          int(seeds[i, r, j]), params, k)
        for i, r, j in tasks
    )
    # Convergence is recorded per fit (rhat, converged) and a ConvergenceWarning reaches the user.
    parallel = Parallel(n_jobs=n_jobs, backend="threading", return_as="generator")
    rows = list(progress(parallel(jobs), total=len(tasks), desc=desc, verbose=verbose))
    for row, (_, r, _) in zip(rows, tasks):
        row["repeat"] = r
    return pd.DataFrame(rows)


def aggregate(results, metrics=METRICS):
    """Mean and spread of every metric per setting and training-set size.

    Parameters
    ----------
    results : DataFrame
        The output of :func:`run_grid`.
    metrics : sequence of str, default=METRICS
        Columns to summarise; booleans are averaged as fractions.

    Returns
    -------
    summary : DataFrame
        One row per (setting, size): ``n_fits`` and, for every metric, ``<metric>_mean``,
        ``<metric>_q25``, ``<metric>_q75`` (the interquartile band), ``<metric>_min`` and
        ``<metric>_max``.

    Examples
    --------
    >>> import pandas as pd
    >>> df = pd.DataFrame({"domain": "d", "prior": "forest", "likelihood": "cb",
    ...                    "labels": "positive", "size": [2, 2, 5],
    ...                    "expected_similarity": [0.5, 0.7, 1.0]})
    >>> aggregate(df, ["expected_similarity"])[["size", "n_fits", "expected_similarity_mean"]]
       size  n_fits  expected_similarity_mean
    0     2       2                       0.6
    1     5       1                       1.0
    """
    metrics = [m for m in metrics if m in results.columns]
    keys = list(SETTING_COLUMNS) + ["size"]
    data = results[keys + metrics].copy()
    data[metrics] = data[metrics].astype(float)
    grouped = data.groupby(keys, sort=True)
    out = grouped.size().rename("n_fits").to_frame()
    for m in metrics:
        g = grouped[m]
        out[f"{m}_mean"] = g.mean()
        out[f"{m}_q25"] = g.quantile(0.25)
        out[f"{m}_q75"] = g.quantile(0.75)
        out[f"{m}_min"] = g.min()
        out[f"{m}_max"] = g.max()
    return out.reset_index()
