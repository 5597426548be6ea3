"""The paper's synthetic-domain experiments (POI / threat navigation, Scenarios 1 to 3)."""

from __future__ import annotations

import time
from dataclasses import replace
from pathlib import Path

import numpy as np
from sklearn.utils import Bunch, check_random_state

from bsi_sklearn.datasets import make_poi_threat_demos, poi_threat_specification
from bsi_sklearn.exact import enumerate_structures
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
    decorate,
    new_figure,
    plot_band,
    priors_figure,
    save_figure,
    supervised_figure,
)
from bsi_sklearn.experiments.tables import (
    SUPERVISED_INTRO,
    markdown_table,
    priors_table,
    summary_table,
    supervised_table,
    write_outputs,
)
from bsi_sklearn.priors import log_prior_structure, n_orders_of, prior_code

__all__ = [
    "SIZES",
    "N_REPEATS",
    "make_synthetic_pools",
    "synthetic_settings",
    "synthetic_claims",
    "synthetic_figures",
    "alternative_prior_settings",
    "prior_expected_orders",
    "alternative_prior_claims",
    "run_synthetic",
]

#: Training-set sizes (positive demonstrations) of the paper's figures.
SIZES = (2, 5, 10, 15, 20, 30, 50)
#: Random draws of the training set per size.
N_REPEATS = 8
#: Held-out positives and negatives per scenario, for classification accuracy.
N_TEST = 20
#: The supervised variant adds ``ceil(NEGATIVE_RATIO * n)`` negatives to ``n`` positives.
NEGATIVE_RATIO = 0.5
#: Every setting's support is small enough (at most 1.3 million hypotheses) for exact
#: inference; the MCMC settings only apply if a custom run exceeds ``max_exact_hypotheses``.
CLASSIFIER_PARAMS = {"inference": "auto", "n_samples": 10_000, "burn_in": 100, "n_chains": 4}

QUICK = {"sizes": (2, 10), "n_repeats": 2, "n_test": 5}
_SCENARIO_N_SUBTASKS = {1: 4, 2: 5, 3: 5}
SCENARIOS = (1, 2, 3)
PRIORS_23 = ("sets_of_chains", "forest")
#: Under the paper's hyperparameters (``p_part=0.3``, ``N_new=5``, our defaults) Prior 2
#: expects more orders than Prior 3 (:func:`prior_expected_orders`), the reverse of the bias
#: toward longer chains the paper reports for Prior 3. These alternatives (chains break
#: more often; new trees are rarer) give Prior 3 that bias; the experiment reruns Priors 2
#: and 3 with them.
ALT_HYPERPARAMETERS = {"sets_of_chains": (("p_part", 0.7),), "forest": (("n_new", 0.5),)}
#: Claims comparing Priors 2 and 3, also tested under :data:`ALT_HYPERPARAMETERS`.
PRIOR_COMPARISON_CLAIMS = ("S1-P3-few", "S1-P3-orders-few", "S1-P3-misses", "S2-P3-chains",
                           "S3-equal", "S3-P3-extra")


def _domain(scenario):
    return f"scenario {scenario}"


def synthetic_settings(scenarios=SCENARIOS, supervised=True):
    """The settings of the synthetic experiments.

    Scenario 1 with Prior 1 under the CB and CI likelihoods, and every scenario with Priors 2
    and 3 under CB; each positive-only and, when ``supervised``, with negatives too.

    Examples
    --------
    >>> len(synthetic_settings()), len(synthetic_settings(scenarios=(2,), supervised=False))
    (16, 2)
    """
    settings = []
    for sup in (False, True) if supervised else (False,):
        if 1 in scenarios:
            settings += [Setting(_domain(1), "linear_chain", lik, sup) for lik in ("cb", "ci")]
        for s in scenarios:
            settings += [Setting(_domain(s), prior, "cb", sup) for prior in PRIORS_23]
    return settings


def prior_expected_orders(prior, n_subtasks, *, p_part=0.3, n_new=5.0):
    """Prior mean of the number of orders ``|W2|`` (transitively closed), by enumeration.

    Parameters
    ----------
    prior : {"linear_chain", "sets_of_chains", "forest"}
    n_subtasks : int
    p_part, n_new : float
        Hyperparameters of Prior 2 and Prior 3 (defaults: the paper's).

    Examples
    --------
    >>> round(prior_expected_orders("sets_of_chains", 4), 3)
    3.423
    >>> round(prior_expected_orders("forest", 4), 3), round(prior_expected_orders(
    ...     "forest", 4, n_new=0.5), 3)
    (0.855, 3.36)
    """
    code = prior_code(prior)
    structures = enumerate_structures(code, n_subtasks)
    log_p = np.array([log_prior_structure(s, code, float(p_part), float(n_new))
                      for s in structures])
    weights = np.exp(log_p - log_p.max())
    counts = np.array([n_orders_of(s) for s in structures])
    return float(weights @ counts / weights.sum())


def _prior_orders_text(params):
    """``"Prior 2 3.42 vs Prior 3 0.86 (4 subtasks), ..."`` under ``params`` (prior -> dict)."""
    parts = []
    for n in sorted(set(_SCENARIO_N_SUBTASKS.values())):
        p2, p3 = (prior_expected_orders(p, n, **params.get(p, {})) for p in PRIORS_23)
        parts.append(f"Prior 2 {p2:.2f} vs Prior 3 {p3:.2f} over {n} subtasks")
    return "; ".join(parts)


def prior_bias_claim(params=None):
    """The paper's claim that Prior 3 is biased toward longer chains, tested on the priors.

    Parameters
    ----------
    params : dict, default=None
        Prior name -> hyperparameters (``{"forest": {"n_new": 0.5}}``); None: the paper's.

    Returns
    -------
    claim : Claim
        Id ``"P3-prior-chains"`` (``"@alt"`` appended when ``params`` is given).

    Examples
    --------
    >>> prior_bias_claim().status
    'FALL SHORT'
    >>> prior_bias_claim({"sets_of_chains": {"p_part": 0.7}, "forest": {"n_new": 0.5}}).status
    'PASS'
    """
    alt = params is not None
    params = params or {}
    diffs = [prior_expected_orders("forest", n, **params.get("forest", {}))
             - prior_expected_orders("sets_of_chains", n, **params.get("sets_of_chains", {}))
             for n in sorted(set(_SCENARIO_N_SUBTASKS.values()))]
    label = ", ".join(f"{k}={v:g}" for v in params.values() for k, v in v.items())
    return Claim(
        "P3-prior-chains" + ("@alt" if alt else ""),
        f"synthetic, Priors 2/3 a priori ({label if alt else 'p_part=0.3, N_new=5'})",
        "Prior 3 has an a priori bias toward longer chains than Prior 2",
        "prior expected number of orders of Prior 3 > Prior 2 over 4 and 5 subtasks",
        "expected orders: " + _prior_orders_text(params), min(diffs), min(diffs) > 0)


def alternative_prior_settings(scenarios=SCENARIOS):
    """Priors 2 and 3 (CB, positive-only) under :data:`ALT_HYPERPARAMETERS`.

    Examples
    --------
    >>> [s.hyperparameters for s in alternative_prior_settings(scenarios=(1,))]
    ['p_part=0.7', 'n_new=0.5']
    """
    return [Setting(_domain(s), prior, "cb", False, ALT_HYPERPARAMETERS[prior])
            for s in scenarios for prior in PRIORS_23]


def alternative_prior_claims(results, summary):
    """The Prior 2 vs Prior 3 claims, tested on the fits under :data:`ALT_HYPERPARAMETERS`.

    Returns
    -------
    claims : list of Claim
        The claims of :data:`PRIOR_COMPARISON_CLAIMS`, their ids suffixed ``"@alt"``.
    """
    label = ", ".join(f"{k}={v:g}" for params in ALT_HYPERPARAMETERS.values()
                      for k, v in params)
    return [replace(c, id=f"{c.id}@alt", experiment=f"{c.experiment} ({label})")
            for c in synthetic_claims(results, summary) if c.id in PRIOR_COMPARISON_CLAIMS]


def make_synthetic_pools(n_repeats, n_positive, n_negative, *, n_test=N_TEST,
                         scenarios=SCENARIOS, random_state=None, verbose=0):
    """Per scenario, one pool of demonstrations per repeat and a shared held-out test set.

    Parameters
    ----------
    n_repeats : int
    n_positive, n_negative : int
        Demonstrations to draw training sets from, per repeat.
    n_test : int, default=20
        Held-out positives and negatives per scenario (the same for every repeat).
    scenarios : sequence of {1, 2, 3}
    random_state : int, RandomState instance or None
    verbose : int, default=0

    Returns
    -------
    pools : dict of str -> list of Bunch
        Keys ``"scenario 1"`` ...; see :func:`bsi_sklearn.experiments._grid.make_pool`.
    """
    rng = check_random_state(random_state)
    jobs = []
    for s in scenarios:
        test_seed = int(rng.randint(np.iinfo(np.int32).max))
        seeds = rng.randint(np.iinfo(np.int32).max, size=(n_repeats, 2))
        jobs.append((s, test_seed, seeds))
    pools = {}
    bar = progress(range(len(scenarios) * (n_repeats + 1)), total=len(scenarios) * (n_repeats + 1),
                   desc="synthetic demonstrations", verbose=verbose)
    for s, test_seed, seeds in jobs:
        if n_test:
            test = make_poi_threat_demos(s, n_demos=n_test, n_negative=n_test,
                                         random_state=test_seed)
            X_test, y_test = test.traces, test.labels
        else:
            X_test, y_test = [], []
        bar.update()
        pools[_domain(s)] = []
        for data_seed, shuffle_seed in seeds:
            data = make_poi_threat_demos(s, n_demos=n_positive, n_negative=n_negative,
                                         random_state=int(data_seed))
            pos = [t for t, y in zip(data.traces, data.labels) if y == 1]
            neg = [t for t, y in zip(data.traces, data.labels) if y == 0]
            pools[_domain(s)].append(make_pool(pos, neg, X_test, y_test, data.roles,
                                               data.specification, int(shuffle_seed)))
            bar.update()
    bar.close()
    return pools


# ---------------------------------------------------------------------------------- claims
def synthetic_claims(results, summary):
    """The paper's synthetic-domain claims, each tested on the measured results.

    Parameters
    ----------
    results : DataFrame
        Per-fit results (:func:`~bsi_sklearn.experiments._grid.run_grid`).
    summary : DataFrame
        Their aggregate (:func:`~bsi_sklearn.experiments._grid.aggregate`).

    Returns
    -------
    claims : list of Claim
        Claims whose settings were not run are left out; claims that need a training size
        the run does not have are reported as not measured.
    """
    pos = results[results["labels"] == "positive"]
    agg = summary[summary["labels"] == "positive"]
    sizes = sorted(pos["size"].unique())
    lo, hi = sizes[0], sizes[-1]
    domains = set(pos["domain"])
    claims = []

    # Over 90% similarity, at the largest training set, for every CB setting.
    cb = agg[(agg["likelihood"] == "cb") & (agg["size"] == hi)]
    for metric, what in (("expected_similarity", "expected"),
                         ("best_similarity", "best-of-top-5")):
        values = {(r.domain, PRIOR_LABELS[r.prior]): getattr(r, f"{metric}_mean")
                  for r in cb.itertuples()}
        worst = min(values, key=values.get)
        claims.append(Claim(
            f"SYN-0.9-{what.split('-')[0]}", "synthetic, all scenarios",
            "over 90% similarity between the inferred specification and the ground truth",
            f"mean {what} similarity at n={hi} above 0.9 for every scenario and prior (CB)",
            f"{what} L at n={hi}: min {values[worst]:.3f} ({worst[0]}, {worst[1]}) over "
            f"{len(values)} settings", values[worst], values[worst] > 0.9))

    if "scenario 1" in domains and "linear_chain" in set(pos["prior"]):
        s1 = {"domain": "scenario 1", "prior": "linear_chain", "labels": "positive"}
        diff = [mean_at(agg, "expected_similarity", n, likelihood="cb", **s1)
                - mean_at(agg, "expected_similarity", n, likelihood="ci", **s1) for n in sizes]
        claims.append(Claim(
            "S1-CB>CI", "synthetic, scenario 1, Prior 1",
            "the CB likelihood infers the complete specification better than CI",
            "mean expected L of CB >= CI at every size, and > at some size",
            f"CB - CI expected L per size: {_join(diff)}", min(diff),
            min(diff) >= 0 and max(diff) > 0))
        counts = {lik: [mean_at(agg, "n_formulas_99", n, likelihood=lik, **s1) for n in (lo, hi)]
                  for lik in ("cb", "ci")}
        ratio = {lik: c[1] / c[0] for lik, c in counts.items()}
        claims.append(Claim(
            "S1-peaky", "synthetic, scenario 1, Prior 1",
            "CB posteriors get peakier (fewer unique formulas) as the training set grows; "
            "not CI ones",
            f"formulas holding 99% of the mass, n={hi} over n={lo}: CB ratio < 1 and < CI "
            "ratio",
            f"CB {counts['cb'][0]:.0f} -> {counts['cb'][1]:.0f}, CI {counts['ci'][0]:.0f} -> "
            f"{counts['ci'][1]:.0f}", ratio["cb"], ratio["cb"] < 1 and ratio["cb"] < ratio["ci"]))

    s1_23 = {"domain": "scenario 1", "likelihood": "cb", "labels": "positive"}
    n_true_s1 = len(poi_threat_specification(1).orders)
    if "scenario 1" in domains and set(PRIORS_23) <= set(pos["prior"]):
        p2 = mean_at(agg, "expected_similarity", lo, prior="sets_of_chains", **s1_23)
        p3 = mean_at(agg, "expected_similarity", lo, prior="forest", **s1_23)
        claims.append(Claim(
            "S1-P3-few", "synthetic, scenario 1, Priors 2/3",
            "Prior 3 aligns better with the ground truth with fewer training examples",
            f"mean expected L of Prior 3 > Prior 2 at n={lo}",
            f"n={lo}: Prior 3 {p3:.3f}, Prior 2 {p2:.3f}", p3 - p2, p3 > p2))
        c2 = mean_at(agg, "correct_orders", lo, prior="sets_of_chains", **s1_23)
        c3 = mean_at(agg, "correct_orders", lo, prior="forest", **s1_23)
        claims.append(Claim(
            "S1-P3-orders-few", "synthetic, scenario 1, Priors 2/3",
            "Prior 3 recovers more correct orders than Prior 2 with few demonstrations "
            "(its bias toward longer chains)",
            f"mean expected correct orders of Prior 3 > Prior 2 at n={lo}",
            f"n={lo}: Prior 3 {c3:.2f}, Prior 2 {c2:.2f} (of {n_true_s1})", c3 - c2, c3 > c2))
        frac = select(pos, size=hi, prior="sets_of_chains", **s1_23)["map_is_truth"].mean()
        claims.append(Claim(
            "S1-P2-exact", "synthetic, scenario 1, Priors 2/3",
            "with a larger training set, Prior 2 recovers the exact specification",
            f"MAP of Prior 2 equals the ground truth at n={hi} in every repeat",
            f"MAP = truth in {frac:.0%} of the repeats at n={hi}", frac, frac == 1.0))
        c2 = mean_at(agg, "correct_orders", hi, prior="sets_of_chains", **s1_23)
        claims.append(Claim(
            "S1-P2-orders", "synthetic, scenario 1, Priors 2/3",
            "with more training examples, Prior 2 recovers all correct orders",
            f"mean expected correct orders of Prior 2 at n={hi} within 0.01 of the "
            f"ground truth's {n_true_s1}",
            f"n={hi}: {c2:.3f} of {n_true_s1}", c2, c2 >= n_true_s1 - 0.01))
        frac3 = select(pos, size=hi, prior="forest", **s1_23)["map_is_truth"].mean()
        c3 = mean_at(agg, "correct_orders", hi, prior="forest", **s1_23)
        claims.append(Claim(
            "S1-P3-misses", "synthetic, scenario 1, Priors 2/3",
            "with a larger training set (30), Prior 3 fails to recover the exact "
            "specification and all correct orders",
            f"at n={hi}, the MAP of Prior 3 misses the ground truth in some repeat or its "
            f"mean expected correct orders stay below {n_true_s1} - 0.01",
            f"n={hi}: MAP = truth in {frac3:.0%} of the repeats, expected correct orders "
            f"{c3:.3f} of {n_true_s1}", frac3, frac3 < 1.0 or c3 < n_true_s1 - 0.01))

    big = [n for n in sizes if n >= 10]
    for scenario, metric, cid, paper, what in (
        (2, "truth_in_top_k", "S2-top5",
         "with 10 or more demonstrations, both priors return the ground truth among the top 5",
         "ground truth in the top 5"),
        (3, "map_is_truth", "S3-MAP",
         "with 10 or more demonstrations, both priors return the ground truth as the MAP",
         "MAP = ground truth"),
    ):
        if _domain(scenario) not in domains:
            continue
        exp = f"synthetic, scenario {scenario}, Priors 2/3"
        crit = f"{what} in every fit with n >= 10 (Priors 2 and 3, every repeat)"
        if not big:
            claims.append(Claim.not_measured(cid, exp, paper, crit, "no training size >= 10"))
            continue
        fracs = {p: fraction_by_size(pos, metric, domain=_domain(scenario), prior=p,
                                     likelihood="cb", size=tuple(big)) for p in PRIORS_23}
        frac = float(np.mean([f for f, _ in fracs.values()]))
        claims.append(Claim(
            cid, exp, paper, crit,
            "; ".join(f"{PRIOR_LABELS[p]}: {what} in {t}" for p, (_, t) in fracs.items()),
            frac, frac == 1.0))

    if "scenario 2" in domains:
        s2 = {"domain": "scenario 2", "likelihood": "cb", "labels": "positive"}
        fracs = {p: select(pos, size=hi, prior=p, **s2)["map_is_truth"].mean()
                 for p in PRIORS_23}
        claims.append(Claim(
            "S2-converge", "synthetic, scenario 2, Priors 2/3",
            "given enough training examples, both priors infer the complete formula",
            f"MAP = ground truth at n={hi} in every repeat, Priors 2 and 3",
            f"n={hi}: MAP = truth in " + ", ".join(
                f"{PRIOR_LABELS[p]} {f:.0%}" for p, f in fracs.items()) + " of the repeats",
            min(fracs.values()), min(fracs.values()) == 1.0))
        n_orders = {p: sum(mean_at(agg, m, lo, prior=p, **s2)
                           for m in ("correct_orders", "incorrect_orders", "extra_orders"))
                    for p in PRIORS_23}
        diff = n_orders["forest"] - n_orders["sets_of_chains"]
        claims.append(Claim(
            "S2-P3-chains", "synthetic, scenario 2, Priors 2/3",
            "Prior 3 assigns a larger probability to longer task chains than Prior 2",
            f"mean expected number of orders (correct, incorrect and extra) of Prior 3 > "
            f"Prior 2 at n={lo}",
            f"n={lo}: Prior 3 {n_orders['forest']:.2f}, Prior 2 "
            f"{n_orders['sets_of_chains']:.2f} orders", diff, diff > 0))

    if "scenario 3" in domains:
        s3 = {"domain": "scenario 3", "likelihood": "cb", "labels": "positive"}
        gap = [abs(mean_at(agg, "expected_similarity", n, prior="forest", **s3)
                   - mean_at(agg, "expected_similarity", n, prior="sets_of_chains", **s3))
               for n in sizes]
        claims.append(Claim(
            "S3-equal", "synthetic, scenario 3, Priors 2/3",
            "both priors perform equally well at recovering the ground truth",
            "mean expected L of Priors 2 and 3 within 0.05 of each other at every size",
            "|Prior 3 - Prior 2| expected L per size: " + ", ".join(f"{g:.3f}" for g in gap),
            max(gap), max(gap) <= 0.05))
        diff = [mean_at(agg, "extra_orders", n, prior="forest", **s3)
                - mean_at(agg, "extra_orders", n, prior="sets_of_chains", **s3) for n in sizes]
        claims.append(Claim(
            "S3-P3-extra", "synthetic, scenario 3, Priors 2/3",
            "Prior 3's posterior holds more extra orders than Prior 2's (bias to long chains)",
            f"mean expected extra orders of Prior 3 > Prior 2 at n={lo}",
            f"Prior 3 - Prior 2 expected extra orders per size: {_join(diff)}", diff[0],
            diff[0] > 0))

    runtime = _runtime_claim(pos)
    if runtime is not None:
        claims.append(runtime)
    return claims


#: The paper's mean MCMC runtimes (minutes) for Scenarios 1 and 2 at 5 and 50 demonstrations.
PAPER_RUNTIME_MINUTES = {5: 10, 50: 90}


def _runtime_claim(pos):
    rows = pos[pos["domain"].isin(["scenario 1", "scenario 2"])]
    if rows.empty:
        return None
    exp = "synthetic, scenarios 1 and 2"
    paper = "inference takes on average 10 min (5 demonstrations) and 90 min (50)"
    crit = "our mean fit time per posterior below the paper's at n=5 and n=50"
    have = set(rows["size"])
    if not set(PAPER_RUNTIME_MINUTES) <= have:
        return Claim.not_measured("SYN-runtime", exp, paper, crit, "sizes 5 and 50 not run")
    secs = {n: float(rows.loc[rows["size"] == n, "fit_time"].mean())
            for n in PAPER_RUNTIME_MINUTES}
    how = "/".join(sorted(set(rows["inference"])))
    ratio = max(secs[n] / (60 * m) for n, m in PAPER_RUNTIME_MINUTES.items())
    return Claim(
        "SYN-runtime", exp, paper, crit,
        ", ".join(f"n={n}: {secs[n]:.3f} s" for n in secs)
        + f" ({how} inference, over {len(rows[rows['size'].isin(list(secs))])} fits)",
        ratio, ratio < 1)


def _join(values):
    return ", ".join(f"{v:+.3f}" for v in values)


# ---------------------------------------------------------------------------------- figures
def synthetic_figures(summary, alt_summary=None):
    """The paper's synthetic-domain figures, drawn from an aggregate of the results.

    Parameters
    ----------
    summary : DataFrame
        Aggregate of the main fits.
    alt_summary : DataFrame, default=None
        Aggregate of the fits under :data:`ALT_HYPERPARAMETERS`.

    Returns
    -------
    figures : dict of str -> matplotlib Figure
        ``"scenario1_prior1"`` (CB vs CI: similarity and number of formulas),
        ``"scenario<k>_priors23"`` (similarity; correct and extra orders),
        ``"supervised"`` (positive-only vs supervised: similarity and held-out accuracy) and
        ``"scenario<k>_priors23_alt"`` (Priors 2 and 3 under the alternative
        hyperparameters). Lines are means over the repeats, bands their interquartile range.
    """
    figures = {}
    pos = summary[summary["labels"] == "positive"]
    s1p1 = pos[(pos["domain"] == "scenario 1") & (pos["prior"] == "linear_chain")]
    if len(s1p1):
        fig, axes = new_figure(2)
        ax_sim, ax_n = axes[0]
        for lik, color in (("cb", "tab:blue"), ("ci", "tab:orange")):
            rows = s1p1[s1p1["likelihood"] == lik]
            plot_band(ax_sim, rows, "expected_similarity", label=f"{lik.upper()} expected",
                      color=color)
            plot_band(ax_sim, rows, "best_similarity", label=f"{lik.upper()} best of top 5",
                      color=color, linestyle="--", marker="s")
            plot_band(ax_n, rows, "n_formulas_99", label=f"{lik.upper()} (99% of the mass)",
                      color=color)
            plot_band(ax_n, rows, "n_specifications", label=f"{lik.upper()} (all)",
                      color=color, linestyle=":", marker="^", band=False)
        ax_sim.axhline(1.0, color="k", linestyle=":", linewidth=1)
        decorate(ax_sim, "Scenario 1, Prior 1: similarity", "similarity L")
        ax_n.set_yscale("log")
        decorate(ax_n, "Scenario 1, Prior 1: unique formulas", "formulas in the posterior")
        figures["scenario1_prior1"] = fig

    for domain in sorted(set(pos["domain"])):
        if not pos[(pos["domain"] == domain) & pos["prior"].isin(PRIORS_23)].empty:
            scenario = int(domain.split()[-1])
            figures[f"scenario{scenario}_priors23"] = priors_figure(
                summary, domain, f"Scenario {scenario}, Priors 2 and 3",
                len(poi_threat_specification(scenario).orders))
    sup = summary[summary["prior"].isin(PRIORS_23)]
    if (sup["labels"] == "supervised").any():
        figures["supervised"] = supervised_figure(summary, sorted(set(sup["domain"])))
    if alt_summary is not None:
        for domain in sorted(set(alt_summary["domain"])):
            scenario = int(domain.split()[-1])
            figures[f"scenario{scenario}_priors23_alt"] = priors_figure(
                alt_summary, domain, f"Scenario {scenario}, p_part=0.7 / N_new=0.5",
                len(poi_threat_specification(scenario).orders))
    return figures


# ---------------------------------------------------------------------------------- run
def _sections(summary, alt_summary, figure_files):
    pos = {"labels": "positive"}
    sections = []
    if ((summary["prior"] == "linear_chain") & (summary["domain"] == "scenario 1")).any():
        s1 = {"domain": "scenario 1", "prior": "linear_chain", **pos}
        cols = []
        for lik in ("cb", "ci"):
            f = {**s1, "likelihood": lik}
            cols += [(f"{lik.upper()} E[L]", f, "expected_similarity"),
                     (f"{lik.upper()} best-5 L", f, "best_similarity")]
        cols += [(f"{lik.upper()} formulas (99%)", {**s1, "likelihood": lik}, "n_formulas_99")
                 for lik in ("cb", "ci")]
        sections.append(("Scenario 1, Prior 1: CB vs CI likelihood",
                         _table(summary, cols, ".3g")))
    for domain in sorted(set(summary["domain"])):
        if (summary["prior"].isin(PRIORS_23) & (summary["domain"] == domain)).any():
            sections.append((f"{domain.capitalize()}, Priors 2 and 3 (CB)",
                             priors_table(summary, domain)))
    if (summary["labels"] == "supervised").any():
        parts = [f"**{domain.capitalize()}**\n\n" + supervised_table(summary, domain)
                 for domain in sorted(set(summary["domain"]))]
        sections.append(("Supervised variant (positives and negatives)",
                         SUPERVISED_INTRO + "\n\n" + "\n\n".join(parts)))
    if alt_summary is not None:
        text = [_alt_intro()]
        text += [f"**{domain.capitalize()}**\n\n" + priors_table(alt_summary, domain)
                 for domain in sorted(set(alt_summary["domain"]))]
        sections.append(("Priors 2 and 3 with p_part = 0.7 and N_new = 0.5 (CB)",
                         "\n\n".join(text)))
    sections.append(("Figures", "\n".join(f"![{p.stem}]({p.name})" for p in figure_files)))
    return sections


def _alt_intro():
    alt = {p: dict(v) for p, v in ALT_HYPERPARAMETERS.items()}
    return (
        "Under the paper's hyperparameters (`p_part=0.3`, `N_new=5`, the defaults used above) "
        "the expected number of orders a priori is " + _prior_orders_text({}) + ": Prior 2, "
        "not Prior 3, leans toward longer chains, the reverse of the bias the paper reports "
        "for Prior 3. These fits rerun Priors 2 and 3 on the same training sets with "
        "`p_part=0.7` (chains break more often) and `n_new=0.5` (new trees are rarer), "
        "which gives Prior 3 that bias (" + _prior_orders_text(alt) + "); the claims "
        "suffixed `@alt` are tested on them. Files: `synthetic_alt_priors_results.csv`, "
        "`synthetic_alt_priors_summary.csv`."
    )


def _table(summary, cols, floatfmt, band=True):
    return markdown_table(summary_table(summary, cols, floatfmt=floatfmt, band=band))


def run_synthetic(out=None, *, quick=False, sizes=None, n_repeats=None, scenarios=SCENARIOS,
                  supervised=True, alternative_priors=True, n_jobs=None, random_state=0,
                  verbose=0):
    """Run the synthetic-domain experiments; write tables and figures into ``out``.

    Scenario 1 with Prior 1 (CB vs CI likelihood), and Scenarios 1 to 3 with Priors 2 and 3
    (CB), at every training-set size in ``sizes``, on ``n_repeats`` independent draws of the
    demonstrations (each repeat simulates fresh demonstrations and takes nested training sets
    from them). The supervised variant adds negatives to the same positives.

    Parameters
    ----------
    out : str or Path, default=None
        Output folder; nothing is written when None.
    quick : bool, default=False
        Sizes 2 and 10 and two repeats (well under a minute), for tests and notebooks.
    sizes : sequence of int, default=None
        Training-set sizes (positives); default :data:`SIZES` (quick: 2 and 10).
    n_repeats : int, default=None
        Draws per size; default :data:`N_REPEATS` (quick: 2).
    scenarios : sequence of {1, 2, 3}, default=(1, 2, 3)
    supervised : bool, default=True
        Also run the variant with negative demonstrations.
    alternative_priors : bool, default=True
        Also fit Priors 2 and 3 under :data:`ALT_HYPERPARAMETERS` on the same data, and test
        the Prior 2 vs Prior 3 claims on them (ids suffixed ``"@alt"``).
    n_jobs : int, default=None
        Fits run in parallel threads.
    random_state : int, RandomState instance or None, default=0
    verbose : int, default=0
        Progress bars (on a terminal) when > 0.

    Returns
    -------
    run : Bunch
        ``results`` (one row per fit), ``summary`` (mean, quartiles per setting and size),
        ``claims`` (DataFrame: the paper's claims, our values, PASS / FALL SHORT),
        ``alt_results`` and ``alt_summary`` (the alternative-hyperparameter fits; None when
        not run), ``figures`` (name -> Figure), ``files`` (paths written), ``config``,
        ``elapsed``.
    """
    start = time.perf_counter()
    sizes = tuple(sorted({int(n) for n in (sizes or (QUICK["sizes"] if quick else SIZES))}))
    if sizes[0] < 1:
        raise ValueError(f"training sizes must be positive, got {sizes}")
    n_repeats = int(n_repeats or (QUICK["n_repeats"] if quick else N_REPEATS))
    if n_repeats < 1:
        raise ValueError(f"n_repeats must be at least 1, got {n_repeats}")
    scenarios = tuple(scenarios)
    for s in scenarios:
        if s not in SCENARIOS:
            raise ValueError(f"scenarios must be among {SCENARIOS}, got {s!r}")
    n_test = QUICK["n_test"] if quick else N_TEST
    rng = check_random_state(random_state)
    data_seed, fit_seed, alt_seed = rng.randint(np.iinfo(np.int32).max, size=3)
    n_neg = n_negatives(sizes[-1], NEGATIVE_RATIO) if supervised else 0
    pools = make_synthetic_pools(n_repeats, sizes[-1], n_neg, n_test=n_test,
                                 scenarios=scenarios, random_state=int(data_seed),
                                 verbose=verbose)
    settings = synthetic_settings(scenarios, supervised)
    results = run_grid(pools, settings, sizes, classifier_params=CLASSIFIER_PARAMS,
                       negative_ratio=NEGATIVE_RATIO, n_jobs=n_jobs, random_state=int(fit_seed),
                       verbose=verbose, desc="synthetic fits")
    summary = aggregate(results)
    claims = synthetic_claims(results, summary) + [prior_bias_claim()]
    alt_results = alt_summary = None
    if alternative_priors:
        alt_results = run_grid(pools, alternative_prior_settings(scenarios), sizes,
                               classifier_params=CLASSIFIER_PARAMS, n_jobs=n_jobs,
                               random_state=int(alt_seed), verbose=verbose,
                               desc="synthetic fits, alternative priors")
        alt_summary = aggregate(alt_results)
        claims += alternative_prior_claims(alt_results, alt_summary)
        claims.append(prior_bias_claim({p: dict(v) for p, v in ALT_HYPERPARAMETERS.items()}))
    figures = synthetic_figures(summary, alt_summary)
    elapsed = time.perf_counter() - start
    config = {
        "title": "Synthetic domain (POI / threat navigation): the paper's experiments",
        "sizes": list(sizes),
        "n_repeats": n_repeats,
        "scenarios": list(scenarios),
        "supervised": bool(supervised),
        "negative_ratio": NEGATIVE_RATIO,
        "n_test_per_class": n_test,
        "classifier_params": CLASSIFIER_PARAMS,
        "alternative_hyperparameters": ({p: dict(v) for p, v in ALT_HYPERPARAMETERS.items()}
                                        if alternative_priors else None),
        "inference_used": results["inference"].value_counts().to_dict(),
        "n_fits": len(results),
        "n_alt_priors_fits": len(alt_results) if alternative_priors else 0,
        "total_fit_seconds": round(float(results["fit_time"].sum()
                                         + (alt_results["fit_time"].sum()
                                            if alternative_priors else 0.0)), 2),
        "random_state": random_state,
        "n_jobs": n_jobs,
        "quick": bool(quick),
        "elapsed_seconds": round(elapsed, 1),
    }
    files = []
    if out is not None:
        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        figure_files = [save_figure(fig, out / f"synthetic_{name}.png")
                        for name, fig in figures.items()]
        files = write_outputs(out, "synthetic", results=results, summary=summary,
                              claims=claims, config=config,
                              sections=_sections(summary, alt_summary, figure_files))
        if alternative_priors:
            for name, frame in (("results", alt_results), ("summary", alt_summary)):
                path = out / f"synthetic_alt_priors_{name}.csv"
                frame.to_csv(path, index=False)
                files.append(path)
        files += figure_files
    return Bunch(results=results, summary=summary, claims=claims_frame(claims),
                 alt_results=alt_results, alt_summary=alt_summary, figures=figures,
                 files=files, config=config, elapsed=elapsed)
