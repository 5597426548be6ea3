"""Renderings of ``bsi-lfe study``: learning-curve figures and the plain-words ``study.md``."""

from __future__ import annotations

import numpy as np
import pandas as pd

from bsi_sklearn.experiments.tables import markdown_table
from lfe._probability_scores import NOT_AVAILABLE
from lfe.study._cells import (
    BSI_CV,
    BSI_ROWS,
    CEILING,
    MAJORITY,
    NETWORKS,
    PRACTITIONER,
    ROWS,
)

__all__ = ["plot_learning_curves", "study_markdown"]

#: What each proposition set can express exactly, for the commander's noise-free rules
#: (lfe/annotate.py) read against the extractor's propositions (lfe/extractor.py).
EXPRESSIBILITY = {
    "paper": "MO3 exactly (`G(friendly_attrition_below_25)`); MO1 nearly (no proposition "
             "for the fighters' air-to-air shots during the strike, only for shots at the "
             "strikers); MO2 not at all (no proposition for the time-on-target window: a "
             "hit after the window fails the rule but satisfies `F(target_hit)`).",
    "extended": "adds the time-on-target window (`tot_window_open`, `tot_window_closed`), "
                "pushes, SAM suppression and two briefing conditions. MO2 becomes "
                "approximately expressible (`target_hit` ordered before `tot_window_closed`; "
                "a hit before the window opens is not told apart), MO3 stays exact, MO1 "
                "stays approximate.",
}


def plot_learning_curves(table, objective, metric="f1"):
    """F1 against training size, one line and 95 % band per row, a panel per noise and set.

    Parameters
    ----------
    table : DataFrame
        ``study.csv``.
    objective : str
    metric : str, default="f1"

    Returns
    -------
    fig : matplotlib Figure
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    sel = table[(table["objective"] == objective) & (table["metric"] == metric)]
    noises = sorted(sel["noise"].unique())
    sets = list(dict.fromkeys(sel["propositions"]))
    fig, axes = plt.subplots(len(noises), len(sets), squeeze=False, sharey=True,
                             figsize=(5.5 * len(sets), 3.8 * len(noises)), layout="constrained")
    palette = plt.get_cmap("tab20").colors
    colors = {name: palette[(2 * i) % 20 + (2 * i) // 20] for i, name in enumerate(ROWS)}
    for i, noise in enumerate(noises):
        for j, ps in enumerate(sets):
            ax = axes[i, j]
            cell = sel[(sel["noise"] == noise) & (sel["propositions"] == ps)]
            for name in ROWS:
                line = cell[cell["classifier"] == name].sort_values("n_train")
                if line.empty:
                    continue
                style = ("--" if name in (MAJORITY, CEILING)
                         else "-" if name in (*BSI_ROWS, BSI_CV)
                         else "-." if name in PRACTITIONER else ":")
                ax.plot(line["n_train"], line["mean"], style, marker="o", ms=3,
                        color=colors[name], label=name)
                ax.fill_between(line["n_train"], line["ci_low"], line["ci_high"],
                                color=colors[name], alpha=0.12, lw=0)
            ax.set_xscale("log")
            ticks = sorted(cell["n_train"].unique())
            ax.set_xticks(ticks, [str(t) for t in ticks])
            ax.minorticks_off()
            ax.set_title(f"{objective}: noise {noise:g}, {ps} propositions", fontsize="medium")
            ax.set_xlabel("training missions")
            ax.set_ylabel("weighted F1 on the test missions" if metric == "f1" else metric)
            ax.set_ylim(0, 1.05)  # a t-interval of few repeats can reach past [0, 1]
            ax.grid(alpha=0.3)
    axes[0, -1].legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    return fig


def _fmt_ci(mean, low, high):
    if np.isnan(mean):  # a BSI row without the score in some repeat
        return NOT_AVAILABLE
    if np.isnan(low):
        return f"{mean:+.3f} (one repeat: no interval)"
    return f"{mean:+.3f} [{low:+.3f}, {high:+.3f}]"


def _protocol(c):
    return [
        f"- {c['repeats']} repeats; each simulates its own missions with "
        "`lfe.make_lfe_dataset` (its own dataset seed): a training pool of "
        f"{max(c['sizes'])} missions and a test set of {c['test_size']} fresh missions. "
        f"Training sets of {', '.join(map(str, c['sizes']))} missions are drawn from the pool, "
        "stratified on the noise-free outcomes where possible; the same missions serve every "
        "classifier, noise rate and proposition set of a repeat.",
        f"- Label noise: each commander verdict flipped with probability "
        f"{', '.join(f'{n:g}' for n in c['noise'])} (`make_lfe_dataset`'s default is 0.04); "
        "phase times carry 10 s of Gaussian error. The test labels carry the same noise.",
        "- Score: weighted F1 over both outcomes of each objective on the test set (and "
        "accuracy, in study.csv); for the rows whose model gives probabilities, the log loss "
        "and Brier score of P(label 1) on the same test set.",
        "- Intervals: 95 % Student-t intervals over the repeats (independent datasets), "
        "`mean ± t(0.975, n-1) sd / sqrt(n)`. Paired differences: BSI minus the best network "
        "(highest mean F1 of the four at that size, noise and set) and BSI minus the best "
        "baseline (highest mean F1 of the networks and the practitioner's rows), computed "
        "repeat by repeat on the same missions, with the same t-interval; *significant* when "
        "it excludes 0.",
        "- Networks (LSTM, Bi-LSTM and their phase-coupled versions): "
        f"`{c['networks']}`. Early stopping (patience 20, or 5 with --quick) chooses the "
        "number of epochs on a 20 % validation split; a fresh network with the same initial "
        "weights is then refitted on every training mission for that many epochs; "
        "mini-batches of 4; torch's deterministic algorithms, one thread.",
        "- Practitioner's rows (`baselines.practitioner`), one model per objective on the "
        "propositions: *Logistic regression* on five plain features per proposition (value "
        "at the first and at the last step, fraction of steps true, first step true, last "
        "step false), constant and perfectly correlated columns of the training set dropped, "
        "standardised, L2 penalty chosen among 13 values of C from 1e-3 to 1e3 by a 3-fold "
        "stratified cross-validation on the training set only (log-loss; C = 1 when a class "
        "has one mission); *MiniRocket* (Dempster et al. 2021, the multivariate "
        "unequal-length form; about 10,000 features, fitted on the training missions), "
        "standardised, then `RidgeClassifierCV` over 10 penalties from 1e-3 to 1e3 "
        "(leave-one-out on the training set).",
        f"- BSI: `{c['bsi']}`, the proposition set's roles; CB likelihood with Prior 2 "
        "(`sets_of_chains`) and Prior 3 (`forest`), CI likelihood with Prior 2, and a "
        f"`GridSearchCV` over `{c['grid']}` (weighted F1, 3-fold inner cross-validation on "
        "the training set only).",
        "- Majority class: the training set's most frequent outcome. Noise-free rule: the "
        "commander's rule without judgement noise, scored against the noisy test labels (the "
        "ceiling of any classifier of those labels, e.g. about 1 - noise in accuracy).",
        f"- Seeds: every seed derives from --seed {c['seed']} (dataset, labels, training-set "
        "draw, models; numpy SeedSequence) and is recorded per run in study_runs.csv.",
        "- Warnings: every warning raised while a row is fitted and scored is recorded, none "
        "is silenced; their count per cell and row is in study_runs.csv (`warnings`) and "
        "study_warnings.csv (with the messages), summed below.",
    ]


def _headline(paired, score="weighted F1", sign=1):
    """Which paired differences hold; ``sign=-1`` for a loss (BSI better below 0)."""
    lines = ["## Is BSI better than the best network, and than the best of all baselines? "
             f"({score}, paired)", ""]
    if paired["ci_low"].isna().all():
        return lines + ["One repeat only: no interval, nothing can be called significant.", ""]
    for versus, prefix, best in (("the best network", "", "best_network"),
                                 ("the best baseline", "baseline_", "best_baseline")):
        flag = paired[f"{prefix}significant"]
        better = int((flag & (sign * paired[f"{prefix}mean"] > 0)).sum())
        worse = int((flag & (sign * paired[f"{prefix}mean"] < 0)).sum())
        lines.append(f"- Against {versus}: BSI significantly better in {better}, "
                     f"significantly worse in {worse}, not significantly different in "
                     f"{len(paired) - better - worse} of {len(paired)} comparisons.")
        for _, r in paired[flag].iterrows():
            mean, low, high = (r[f"{prefix}{k}"] for k in ("mean", "ci_low", "ci_high"))
            word = "better" if sign * mean > 0 else "worse"
            lines.append(f"  - {r['bsi']} is significantly {word} than {r[best]} on "
                         f"{r['objective']} with {r['n_train']} missions (noise "
                         f"{r['noise']:g}, {r['propositions']}): {_fmt_ci(mean, low, high)}.")
    view = paired.copy()
    view["BSI - best network"] = [_fmt_ci(m, lo, hi) for m, lo, hi in
                                  zip(view["mean"], view["ci_low"], view["ci_high"])]
    view["BSI - best baseline"] = [
        _fmt_ci(m, lo, hi) for m, lo, hi in
        zip(view["baseline_mean"], view["baseline_ci_low"], view["baseline_ci_high"])]
    for column in ("significant", "baseline_significant"):
        view[column] = np.where(view[column], "yes", "no")
    view = view.rename(columns={"significant": "significant (network)",
                                "baseline_significant": "significant (baseline)"})
    return lines + ["", markdown_table(view[[
        "bsi", "objective", "n_train", "noise", "propositions", "best_network",
        "BSI - best network", "significant (network)", "best_baseline", "BSI - best baseline",
        "significant (baseline)"]]), ""]


def _warnings_section(warned):
    lines = ["## Warnings raised while fitting and scoring", ""]
    if warned is None or warned.empty:
        return lines + ["None: no row raised a warning in any cell.", ""]
    cells = ["repeat", "noise", "propositions", "n_train"]
    rows = []
    for (name, category), group in warned.groupby(["classifier", "category"], sort=False):
        example = group["message"].iloc[0].replace("|", "\\|")  # a cell of the table
        rows.append({"classifier": name, "category": category,
                     "warnings": int(group["count"].sum()),
                     "cells": len(group[cells].drop_duplicates()),
                     "distinct messages": group["message"].nunique(),
                     "first message": example if len(example) <= 200
                     else example[:197] + "..."})
    total = int(warned["count"].sum())
    return lines + [f"{total} warnings in all; per row and category (every message, per cell, "
                    "in study_warnings.csv):", "", markdown_table(pd.DataFrame(rows)), ""]


def study_markdown(table, paired, config, warned=None, paired_loss=None):
    """``study.md``: the protocol, the disclosure, the tables and which differences hold.

    Parameters
    ----------
    table, paired : DataFrame
        ``study.csv`` and ``study_paired.csv``.
    paired_loss : DataFrame, default=None
        ``study_paired_log_loss.csv`` (the same differences of the log loss; lower is
        better), when the cells scored it.
    config : dict
        The study's settings (``config.json``).
    warned : DataFrame, default=None
        ``study_warnings.csv``.

    Returns
    -------
    text : str
    """
    c = config
    lines = [
        "# bsi-lfe study: learning curves with 95 % intervals",
        "",
        f"Command: `{c['command']}`" + (" (--quick: a smoke test, not a result)"
                                         if c["quick"] else ""),
        "",
        *_headline(paired),
        *([] if paired_loss is None or paired_loss.empty
          else _headline(paired_loss, "log loss, lower is better", sign=-1)),
        "## Protocol",
        "",
        *_protocol(c),
        "",
        "## What each proposition set expresses",
        "",
    ]
    for ps in c["propositions"]:
        lines.append(f"- *{ps}*: {EXPRESSIBILITY.get(ps, '')}")
    lines += ["", *_mean_tables(table, "f1", "Mean weighted F1 [95 % interval]")]
    lines += ["Rows: " + ", ".join((*NETWORKS, *PRACTITIONER, *BSI_ROWS, BSI_CV))
              + f", {MAJORITY}, {CEILING}.", ""]
    note = [f"scikit-learn's `log_loss` (labels 0 and 1, its own clipping) and "
            "`brier_score_loss` of P(label 1) on the test missions; lower is better. "
            f"{NOT_AVAILABLE}: the row gives no probabilities (MiniRocket's ridge "
            "classifier, the noise-free rule), or some repeat had none (a BSI fit with no "
            "acceptable training mission).", ""]
    for metric, title, notes in (("log_loss", "Mean log loss [95 % interval]", note),
                                 ("brier", "Mean Brier score [95 % interval]", ())):
        if metric in set(table["metric"]):  # a study from before they were scored has none
            lines += _mean_tables(table, metric, title, notes)
    lines += _warnings_section(warned)
    return "\n".join(lines)


def _mean_tables(table, metric, title, note=()):
    """A section of ``study.md``: ``metric``'s mean [interval], a table per noise and set."""
    lines = [f"## {title}", "", *note]
    for (noise, ps), block in table[table["metric"] == metric].groupby(
            ["noise", "propositions"], sort=False):
        lines += [f"### Noise {noise:g}, {ps} propositions", ""]
        wide = block.assign(cell=[NOT_AVAILABLE if np.isnan(m)
                                  else f"{m:.3f} [{lo:.3f}, {hi:.3f}]" if not np.isnan(lo)
                                  else f"{m:.3f}" for m, lo, hi in
                                  zip(block["mean"], block["ci_low"], block["ci_high"])])
        wide = wide.pivot_table(index="classifier", columns=["objective", "n_train"],
                                values="cell", aggfunc="first", sort=False)
        wide = wide.reindex([r for r in ROWS if r in wide.index])
        wide.columns = [f"{mo} n={n}" for mo, n in wide.columns]
        lines += [markdown_table(wide.reset_index()), ""]
    return lines
