"""The paper's dinner-table experiment: setting a table, with Priors 2 and 3."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
from sklearn.utils import Bunch, check_random_state

from bsi_sklearn.datasets import dinner_table_specification, make_dinner_table_demos
from bsi_sklearn.experiments._claims import (
    Claim,
    claims_frame,
    fraction_by_size,
    mean_at,
    select,
)
from bsi_sklearn.experiments._grid import (
    Setting,
    aggregate,
    make_pool,
    n_negatives,
    progress,
    run_grid,
)
from bsi_sklearn.experiments._plots import (
    PRIOR_LABELS,
    priors_figure,
    save_figure,
    supervised_figure,
)
from bsi_sklearn.experiments.tables import (
    SUPERVISED_INTRO,
    priors_table,
    supervised_table,
    write_outputs,
)
from bsi_sklearn.specification import Specification

__all__ = [
    "SIZES",
    "N_REPEATS",
    "CLASSIFIER_PARAMS",
    "dinner_settings",
    "make_dinner_pools",
    "dinner_claims",
    "dinner_figures",
    "fork_spoon_violations",
    "run_dinner",
]

DOMAIN = "dinner table"
#: Training-set sizes (positive demonstrations); the paper collected 71 demonstrations.
SIZES = (2, 5, 10, 20, 30, 40, 50, 60, 71)
#: Random draws of the demonstrations per size (a fresh simulated set of 71 per repeat).
N_REPEATS = 8
#: Held-out positives and negatives (shared by the repeats), for classification accuracy.
N_TEST = 24
#: The supervised variant adds ``ceil(NEGATIVE_RATIO * n)`` negatives to ``n`` positives.
NEGATIVE_RATIO = 0.5
#: With 1 global candidate and 8 subtasks the supports hold 2.0e8 (Prior 2) and 2.4e9
#: (Prior 3) hypotheses: ``inference="auto"`` enumerates them exactly (milliseconds once the
#: demonstrations pin the specification down) and samples with MCMC only when the posterior is
#: too flat for its work budget (a handful of demonstrations). The paper drew 10,000 samples
#: after 100 of burn-in; where we sample, it is 4 chains of that length.
CLASSIFIER_PARAMS = {"inference": "auto", "n_samples": 10_000, "burn_in": 100, "n_chains": 4}

QUICK = {"sizes": (2, 10), "n_repeats": 2, "n_test": 4,
         "classifier_params": {"inference": "auto", "n_samples": 1_000, "burn_in": 100,
                               "n_chains": 2}}
PRIORS = ("sets_of_chains", "forest")


def dinner_settings(supervised=True):
    """Priors 2 and 3 with the CB likelihood, positive-only and (optionally) supervised.

    Examples
    --------
    >>> [(s.prior, s.labels) for s in dinner_settings(supervised=False)]
    [('sets_of_chains', 'positive'), ('forest', 'positive')]
    """
    return [Setting(DOMAIN, prior, "cb", sup)
            for sup in ((False, True) if supervised else (False,)) for prior in PRIORS]


def make_dinner_pools(n_repeats, n_positive, n_negative, *, n_test=N_TEST, random_state=None,
                      verbose=0):
    """One simulated set of demonstrations per repeat, and a shared held-out test set.

    Parameters
    ----------
    n_repeats : int
    n_positive, n_negative : int
        Demonstrations to draw training sets from, per repeat (the paper: 71 positives).
    n_test : int, default=24
        Held-out positives and negatives.
    random_state : int, RandomState instance or None
    verbose : int, default=0

    Returns
    -------
    pools : dict
        ``{"dinner table": [pool, ...]}`` (see
        :func:`bsi_sklearn.experiments._grid.make_pool`); each pool also has
        ``fork_spoon_violations``, the number of its positives that place the spoon before
        the fork (:func:`fork_spoon_violations`).
    """
    rng = check_random_state(random_state)
    test_seed = int(rng.randint(np.iinfo(np.int32).max))
    seeds = rng.randint(np.iinfo(np.int32).max, size=(n_repeats, 2))
    bar = progress(range(n_repeats + 1), total=n_repeats + 1, desc="dinner demonstrations",
                   verbose=verbose)
    if n_test:
        test = make_dinner_table_demos(n_test, n_negative=n_test, random_state=test_seed)
        X_test, y_test = test.traces, test.labels
    else:
        X_test, y_test = [], []
    bar.update()
    pools = []
    for data_seed, shuffle_seed in seeds:
        data = make_dinner_table_demos(n_positive, n_negative=n_negative,
                                       random_state=int(data_seed))
        pos = [t for t, y in zip(data.traces, data.labels) if y == 1]
        neg = [t for t, y in zip(data.traces, data.labels) if y == 0]
        pool = make_pool(pos, neg, X_test, y_test, data.roles, data.specification,
                         int(shuffle_seed))
        pool.fork_spoon_violations = fork_spoon_violations(pos, data.roles["conditions"])
        pools.append(pool)
        bar.update()
    bar.close()
    return {DOMAIN: pools}


#: The habit the paper's Prior 3 MAP picked up as an extra order: fork before spoon.
FORK_SPOON = ("omega_fork", "omega_spoon")


def fork_spoon_violations(traces, conditions):
    """Number of demonstrations that violate *fork before spoon* (``pi_fork -> !spoon U fork``).

    The paper's Prior 3 MAP added this order; it was violated by 4 of its 71
    demonstrations.

    Examples
    --------
    >>> from bsi_sklearn.datasets import make_dinner_table_demos
    >>> data = make_dinner_table_demos(6, random_state=0)
    >>> fork_spoon_violations(data.traces, data.roles["conditions"]) <= 6
    True
    """
    order = Specification(orders=[FORK_SPOON], conditions=conditions)
    return sum(not order.satisfied_by(t) for t in traces)


def dinner_claims(results, summary, fork_spoon=None):
    """The paper's dinner-table claims, each tested on the measured results.

    Parameters
    ----------
    results, summary : DataFrame
        Per-fit results and their aggregate.
    fork_spoon : sequence of int, default=None
        Per repeat, the positives that place the spoon before the fork (reported beside the
        paper's 4 of 71).

    Returns
    -------
    claims : list of Claim
    """
    pos = results[(results["labels"] == "positive") & (results["likelihood"] == "cb")]
    agg = summary[(summary["labels"] == "positive") & (summary["likelihood"] == "cb")]
    sizes = sorted(pos["size"].unique())
    hi = sizes[-1]
    priors = [p for p in PRIORS if p in set(pos["prior"])]
    base = {"domain": DOMAIN}
    claims = []
    for metric, what in (("expected_similarity", "expected"),
                         ("best_similarity", "best-of-top-5")):
        values = {PRIOR_LABELS[p]: mean_at(agg, metric, hi, prior=p, **base) for p in priors}
        worst = min(values, key=values.get)
        claims.append(Claim(
            f"DIN-0.9-{what.split('-')[0]}", "dinner table",
            "over 90% similarity between the inferred specification and the ground truth",
            f"mean {what} similarity at n={hi} above 0.9 for Priors 2 and 3",
            f"{what} L at n={hi}: "
            + ", ".join(f"{k} {v:.3f}" for k, v in values.items()),
            values[worst], values[worst] > 0.9))
    if "sets_of_chains" in priors:
        frac, text = fraction_by_size(pos, "truth_in_top_k", prior="sets_of_chains", **base)
        claims.append(Claim(
            "DIN-P2-top5", "dinner table, Prior 2",
            "with Prior 2, the ground truth is among the top 5 formulas in all cases",
            "ground truth in the top 5 in every fit, at every size and repeat",
            f"ground truth in the top 5 in {text}", frac, frac == 1.0))
    if "forest" in priors:
        rows = select(pos, prior="forest", size=hi, **base)
        extra = float(rows["map_extra_orders"].mean())
        claims.append(Claim(
            "DIN-P3-extra", "dinner table, Prior 3",
            f"with Prior 3 and all {hi} demonstrations, the MAP has additional order "
            "constraints (the paper: one, fork before spoon)",
            f"mean number of extra orders of the Prior 3 MAP at n={hi} above 0",
            f"extra orders of the MAP at n={hi}: mean {extra:.2f} over {len(rows)} repeats",
            extra, extra > 0))
        pair = "<".join(FORK_SPOON)
        extras = rows["map_extra_pairs"].fillna("").astype(str)
        exactly = float((extras == pair).mean())
        has = float(extras.map(lambda cell: pair in cell.split(";")).mean())
        data = ""
        if fork_spoon is not None and len(fork_spoon):
            data = (f"; spoon placed before the fork in {np.mean(fork_spoon):.1f} of the "
                    f"{int(results['size'].max())} training positives on average (paper: 4 "
                    "of 71)")
        claims.append(Claim(
            "DIN-P3-fork-spoon", "dinner table, Prior 3",
            f"using all {hi} demonstrations, the Prior 3 MAP has exactly one additional "
            "order: fork before spoon",
            f"the Prior 3 MAP's extra orders at n={hi} are exactly fork < spoon in more than "
            "half of the repeats",
            f"n={hi}: exactly fork < spoon in {exactly:.0%}, fork < spoon among them in "
            f"{has:.0%} of the repeats{data}", exactly, exactly > 0.5))
    return claims


def dinner_figures(summary):
    """Similarity and orders for Priors 2 and 3, and the supervised comparison.

    Returns
    -------
    figures : dict of str -> matplotlib Figure
        ``"priors23"`` and, when the supervised variant ran, ``"supervised"``.
    """
    figures = {"priors23": priors_figure(summary, DOMAIN, "Dinner table, Priors 2 and 3",
                                         len(dinner_table_specification().orders))}
    if (summary["labels"] == "supervised").any():
        figures["supervised"] = supervised_figure(summary, [DOMAIN])
    return figures


def run_dinner(out=None, *, quick=False, sizes=None, n_repeats=None, supervised=True,
               classifier_params=None, n_jobs=None, random_state=0, verbose=0):
    """Run the dinner-table experiment; write tables and figures into ``out``.

    Priors 2 and 3 with the CB likelihood at every training-set size, on ``n_repeats``
    freshly simulated sets of 71 demonstrations (six participants, four meals), with nested
    training sets drawn from each. The supervised variant adds negatives to the same
    positives.

    Parameters
    ----------
    out : str or Path, default=None
        Output folder; nothing is written when None.
    quick : bool, default=False
        Sizes 2 and 10, two repeats and short chains (well under a minute).
    sizes : sequence of int, default=None
        Training-set sizes (positives); default :data:`SIZES`.
    n_repeats : int, default=None
        Draws per size; default :data:`N_REPEATS` (quick: 2).
    supervised : bool, default=True
        Also run the variant with negative demonstrations.
    classifier_params : dict, default=None
        ``BSIClassifier`` inference settings; default :data:`CLASSIFIER_PARAMS`.
    n_jobs : int, default=None
        Fits run in parallel threads (each fit's chains then run one after the other).
    random_state : int, RandomState instance or None, default=0
    verbose : int, default=0
        Progress bars (on a terminal) when > 0.

    Returns
    -------
    run : Bunch
        ``results``, ``summary``, ``claims``, ``figures``, ``files``, ``config``, ``elapsed``
        (see :func:`bsi_sklearn.experiments.run_synthetic`).
    """
    start = time.perf_counter()
    sizes = tuple(sorted({int(n) for n in (sizes or (QUICK["sizes"] if quick else SIZES))}))
    if sizes[0] < 1:
        raise ValueError(f"training sizes must be positive, got {sizes}")
    n_repeats = int(n_repeats or (QUICK["n_repeats"] if quick else N_REPEATS))
    if n_repeats < 1:
        raise ValueError(f"n_repeats must be at least 1, got {n_repeats}")
    if classifier_params is None:
        classifier_params = QUICK["classifier_params"] if quick else CLASSIFIER_PARAMS
    n_test = QUICK["n_test"] if quick else N_TEST
    rng = check_random_state(random_state)
    data_seed, fit_seed = rng.randint(np.iinfo(np.int32).max, size=2)
    n_neg = n_negatives(sizes[-1], NEGATIVE_RATIO) if supervised else 0
    pools = make_dinner_pools(n_repeats, sizes[-1], n_neg, n_test=n_test,
                              random_state=int(data_seed), verbose=verbose)
    results = run_grid(pools, dinner_settings(supervised), sizes,
                       classifier_params=classifier_params, negative_ratio=NEGATIVE_RATIO,
                       n_jobs=n_jobs, random_state=int(fit_seed), verbose=verbose,
                       desc="dinner fits")
    summary = aggregate(results)
    fork_spoon = [int(pool.fork_spoon_violations) for pool in pools[DOMAIN]]
    claims = dinner_claims(results, summary, fork_spoon)
    figures = dinner_figures(summary)
    elapsed = time.perf_counter() - start
    rhat = results["rhat"].dropna()
    config = {
        "title": "Dinner-table domain: the paper's experiment",
        "sizes": list(sizes),
        "n_repeats": n_repeats,
        "supervised": bool(supervised),
        "negative_ratio": NEGATIVE_RATIO,
        "n_test_per_class": n_test,
        "classifier_params": dict(classifier_params),
        "inference_used": results["inference"].value_counts().to_dict(),
        "max_rhat": round(float(rhat.max()), 4) if len(rhat) else None,
        "fits_with_rhat_above_1.05": int((~results["converged"]).sum()),
        "spoon_before_fork_positives_per_repeat": fork_spoon,
        "n_fits": len(results),
        "total_fit_seconds": round(float(results["fit_time"].sum()), 2),
        "random_state": random_state,
        "n_jobs": n_jobs,
        "quick": bool(quick),
        "elapsed_seconds": round(elapsed, 1),
    }
    files = []
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        figure_files = [save_figure(fig, out / f"dinner_{name}.png")
                        for name, fig in figures.items()]
        sections = [("Dinner table, Priors 2 and 3 (CB)", priors_table(summary, DOMAIN))]
        if supervised:
            sections.append(("Supervised variant (positives and negatives)",
                             SUPERVISED_INTRO + "\n\n" + supervised_table(summary, DOMAIN)))
        sections.append(("Figures", "\n".join(f"![{p.stem}]({p.name})" for p in figure_files)))
        files = write_outputs(out, "dinner", results=results, summary=summary, claims=claims,
                              config=config, sections=sections)
        files += figure_files
    return Bunch(results=results, summary=summary, claims=claims_frame(claims),
                 figures=figures, files=files, config=config, elapsed=elapsed)
