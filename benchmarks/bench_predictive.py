"""The posterior predictive and its label noise, on held-out LFE missions (issue 31).

Issue 31's second part (a default that learns the label noise, if it earns it): the
probabilities of ``BSIClassifier`` read three ways from the *same* fit -- the paper's vote
(``vote="satisfaction"``, the posterior mass satisfied), the predictive with the likelihood's
``epsilon`` (``label_noise="likelihood"``) and the predictive with each formula's flip rate
learned from the training labels (``label_noise="learned"``, the default) -- under the default
likelihood (the calibrated size principle with the paper's epsilon since 2026-12-07, CB before:
the rows named ``Default``), and under ``likelihood="ci", flip_prior=(1, 9)``
(the flip prior the documentation suggests: the noise learned inside the likelihood). The
classifier is fitted as a new user fits it: ``BSIClassifier(random_state=...)``, no roles
(inferred), every other default. Missions come from the study's simulator
(:func:`lfe.study.simulate_repeat`: the paper's propositions through the extractor, the
study's two judgement-noise rates, training sets drawn stratified by
:func:`lfe.study.draw_training_set`) at a study seed not used elsewhere in the repository;
each repeat fits on 12, 36 and 72 of its missions and is scored on its own held-out missions,
one classifier per mission objective. A logistic regression on five plain features per
proposition (:class:`baselines.practitioner.TemporalLogisticRegression`, the practitioner row
of ``bsi-lfe study``) is the reference.

Reported per row, noise rate and training size: log loss (scikit-learn's, probabilities
clipped to ``[eps, 1 - eps]`` with ``eps`` the float epsilon, 2.2e-16), the log loss unclipped
(from ``predict_log_proba``; infinite when a probability is exactly 0), the Brier score and
the accuracy of ``predict``; each the mean over the three objectives in a repeat, then the
mean over repeats with a Student-t 95 % interval (:func:`lfe.study.t_interval`); paired
differences repeat by repeat; and a reliability diagram of every test mission pooled over
repeats and objectives, with the largest gap to the diagonal over the bins holding at least
5 % of them (issue 31's calibration target).

Run from the repository root (about 15 minutes on one core)::

    python benchmarks/bench_predictive.py             # 10 repeats, 12/36/72 missions, 0/4 %
    python benchmarks/bench_predictive.py --quick     # 2 repeats, for a smoke test
    python benchmarks/bench_predictive.py --templates unary --out /tmp/p   # issue 28
    python benchmarks/bench_predictive.py --variant likelihood="'calibrated'" --out /tmp/c

``--templates SET`` fits the default with ``templates=SET`` (a named set of the pattern
catalogue, issue 28) in place of the CI fit, read by its default predictive, and reports its
difference from the default fit's; ``--variant NAME=VALUE`` (repeatable) does the same for
any other parameters (issue 31's candidate defaults). Both write into ``--out`` only (the
recorded results stay as they are).

Writes ``benchmarks/RESULTS_predictive.md`` and ``benchmarks/predictive/`` (``runs.csv``: every
row, repeat, noise, size and objective; ``summary.csv``: the table; ``reliability.csv``: the
bins; ``reliability.png``: the diagram, also ``benchmarks/figures/reliability_lfe_missions.png``,
the LFE family's). ``--figures-only`` redraws both from the recorded ``reliability.csv``,
without a fit. Every warning is counted per fit, none is silenced.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)
import numpy as np
import pandas as pd
from sklearn.metrics import accuracy_score, brier_score_loss, log_loss

# isort: split

from _common import machine_info, md_table, parse_param  # noqa: E402
from _reliability import (  # noqa: E402
    N_BINS,
    diagonal_axes,
    draw_reliability,
    reliability_bins,
)
from _reliability import worst_gap as _worst_gap  # noqa: E402

from baselines.practitioner import TemporalLogisticRegression, temporal_features  # noqa: E402
from bsi_sklearn import BSIClassifier  # noqa: E402
from lfe.annotate import MISSION_OBJECTIVES  # noqa: E402
from lfe.study import (  # noqa: E402
    derive_seed,
    draw_training_set,
    repeat_seeds,
    simulate_repeat,
    t_interval,
)

#: BSI settings: name -> (parameters on top of ``random_state``, no roles: inferred; the
#: readings of each fit, below).
SETTINGS = {"Default": ({}, ("satisfaction", "predictive, epsilon", "predictive, learned")),
            "CI, flip_prior=(1, 9)": ({"likelihood": "ci", "flip_prior": (1, 9)},
                                      ("satisfaction", "predictive"))}
#: How one fit is read (parameters read at prediction time, so one fit gives every reading):
#: the paper's vote; the predictive with the likelihood's epsilon; with the flip rate learned
#: (the default); with a flip prior the two predictives coincide.
READINGS = {"satisfaction": {"vote": "satisfaction"},
            "predictive": {"vote": "predictive"},
            "predictive, epsilon": {"vote": "predictive", "label_noise": "likelihood"},
            "predictive, learned": {"vote": "predictive", "label_noise": "learned"}}
REFERENCE = "Logistic regression (reference)"
#: The rows, in the table's order.
ROWS = tuple(f"{s}, {r}" for s, (_, readings) in SETTINGS.items() for r in readings) \
    + (REFERENCE,)
#: This task family's figure in ``figures/``, the same as ``predictive/reliability.png``.
FIGURE = "reliability_lfe_missions.png"


def _scores(y, p1, log_p, pred):
    """Log loss (clipped as scikit-learn clips, and unclipped), Brier score, accuracy."""
    log_p = np.asarray(log_p, dtype=float)
    unclipped = float(-np.mean(np.where(y == 1, log_p[:, 1], log_p[:, 0])))
    return dict(log_loss=log_loss(y, p1, labels=[0, 1]), log_loss_unclipped=unclipped,
                brier=brier_score_loss(y, p1, pos_label=1), accuracy=accuracy_score(y, pred))


def _fit_bsi(X_train, y_train, X_test, params, readings, seed):
    """Every reading of one fit: ``{reading: (P(acceptable), log proba, predict)}`` and the
    fit's facts (inference, specifications, dropped mass, flip rate, warnings, seconds)."""
    start = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")  # count every warning (recorded, not silenced)
        clf = BSIClassifier(random_state=seed, **params).fit(X_train, y_train)
        out = {}
        for reading in readings:
            clf.set_params(**READINGS[reading])  # read at prediction: one fit, every reading
            with np.errstate(divide="ignore"):  # the vote's log of an exact 0 is -inf
                log_p = clf.predict_log_proba(X_test)
            out[reading] = (clf.predict_proba(X_test)[:, 1], log_p, clf.predict(X_test))
    facts = dict(inference=clf.inference_, n_specifications=len(clf.posterior_),
                 dropped_mass=clf.posterior_.dropped_mass, flip_rate=clf.flip_rate_,
                 warnings=len(caught), fit_s=time.perf_counter() - start)
    return out, facts


def _fit_reference(X_train, y_train, X_test, seed):
    """The logistic regression's P(acceptable), log proba and prediction on the test set."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        clf = TemporalLogisticRegression(random_state=seed).fit(X_train, y_train)
        est = clf.estimators_[0]  # the fitted pipeline, or the label of a one-class objective
        if hasattr(est, "predict_proba"):
            proba = est.predict_proba(temporal_features(X_test))[:, list(est.classes_).index(1)]
        else:
            proba = np.full(len(X_test), float(est == 1))
    with np.errstate(divide="ignore"):
        log_p = np.log(np.column_stack([1.0 - proba, proba]))
    return proba, log_p, (proba >= 0.5).astype(int), len(caught)


def run_repeat(repeat, config):
    """Every row of one repeat: ``(runs, predictions)``."""
    seed = config["seed"]
    n_pool = max(config["sizes"])
    data = simulate_repeat(n_pool=n_pool, test_size=config["test_size"],
                           noises=config["noise"], propositions=[config["propositions"]],
                           **repeat_seeds(seed, repeat))
    props = data["props"][config["propositions"]]
    test = np.arange(n_pool, len(data["clean"]))
    X_test = [props[i] for i in test]
    runs, preds = [], []
    for noise in config["noise"]:
        r, p = _run_noise(repeat, config, data, noise, props, test, X_test)
        runs += r
        preds += p
    return runs, preds


def _run_noise(repeat, config, data, noise, props, test, X_test):
    seed, n_pool = config["seed"], max(config["sizes"])
    y = data["labels"][noise]
    runs, preds = [], []
    for n_train in config["sizes"]:
        train = draw_training_set(data["clean"], n_pool, n_train,
                                  derive_seed(seed, repeat, 2, n_train))
        model_seed = derive_seed(seed, repeat, 3, n_train)
        X_train = [props[i] for i in train]
        for k, objective in enumerate(MISSION_OBJECTIVES):
            y_train, y_test = y[train, k], y[test, k]
            cell = dict(repeat=repeat, noise=noise, n_train=n_train, objective=objective,
                        n_acceptable_train=int(y_train.sum()))
            results = {}
            for name, (params, readings) in SETTINGS.items():
                if not np.any(y_train == 1):
                    raise RuntimeError(f"repeat {repeat}, {n_train} missions, {objective}: no "
                                       "acceptable training mission (BSI needs one)")
                out, facts = _fit_bsi(X_train, y_train, X_test, params, readings, model_seed)
                for reading, result in out.items():
                    results[f"{name}, {reading}"] = (*result, facts)
            p, log_p, pred, n_warn = _fit_reference(X_train, y_train, X_test, model_seed)
            results[REFERENCE] = (p, log_p, pred, dict(warnings=n_warn))
            for row, (p, log_p, pred, facts) in results.items():
                runs.append(dict(row=row, **cell, **_scores(y_test, p, log_p, pred), **facts))
                preds.append(pd.DataFrame(dict(row=row, repeat=repeat, noise=noise,
                                               n_train=n_train, objective=objective, p=p,
                                               y=y_test)))
    return runs, preds


KEYS = ["noise", "n_train"]


def summary(runs):
    """Per noise rate, training size and row: each metric's mean over repeats (of the mean
    over the objectives) with its 95 % interval."""
    per_repeat = runs.groupby(KEYS + ["row", "repeat"], sort=False)[
        ["log_loss", "log_loss_unclipped", "brier", "accuracy"]].mean()
    out = []
    for (noise, n_train, row), group in per_repeat.groupby(level=KEYS + ["row"], sort=False):
        entry = dict(noise=noise, n_train=n_train, row=row, n_repeats=len(group))
        for metric in group.columns:
            values = group[metric].to_numpy()
            if np.isfinite(values).all():
                entry[metric], entry[f"{metric}_low"], entry[f"{metric}_high"] = \
                    t_interval(values)
            else:
                entry[metric] = entry[f"{metric}_low"] = entry[f"{metric}_high"] = np.inf
        out.append(entry)
    table = pd.DataFrame(out)
    table["row"] = pd.Categorical(table["row"], ROWS, ordered=True)
    return table.sort_values(KEYS + ["row"]).reset_index(drop=True)


#: Paired differences: (name, row, minus row).
PAIRS = [("Default: predictive, learned - satisfaction", "Default, predictive, learned",
          "Default, satisfaction"),
         ("Default: predictive, learned - predictive, epsilon", "Default, predictive, learned",
          "Default, predictive, epsilon"),
         ("CI flip prior: predictive - satisfaction", "CI, flip_prior=(1, 9), predictive",
          "CI, flip_prior=(1, 9), satisfaction"),
         ("Default: predictive, learned - logistic regression", "Default, predictive, learned",
          REFERENCE)]


def paired(runs):
    """The :data:`PAIRS`, repeat by repeat, per noise rate, size and metric."""
    per_repeat = runs.groupby(KEYS + ["row", "repeat"])[["log_loss", "brier", "accuracy"]].mean()
    out = []
    for name, row_a, row_b in PAIRS:
        for noise, n_train in runs[KEYS].drop_duplicates().sort_values(KEYS).itertuples(
                index=False):
            a = per_repeat.loc[(noise, n_train, row_a)]
            b = per_repeat.loc[(noise, n_train, row_b)]
            entry = dict(pair=name, noise=noise, n_train=n_train)
            for metric in a.columns:
                entry[metric], entry[f"{metric}_low"], entry[f"{metric}_high"] = t_interval(
                    a[metric] - b[metric])
            out.append(entry)
    return pd.DataFrame(out)


def reliability(preds, n_bins=N_BINS):
    """Equal-width bins of P(acceptable), per row, noise rate and size, every test mission
    pooled (:func:`benchmarks._reliability.reliability_bins`)."""
    return reliability_bins(preds, ["row"] + KEYS, n_bins)


def worst_gap(bins, min_share=0.05):
    return _worst_gap(bins, ["row"] + KEYS, min_share)


#: The rows drawn in the reliability figure (the epsilon reading lies on the vote).
FIGURE_ROWS = ("Default, satisfaction", "Default, predictive, learned",
               "CI, flip_prior=(1, 9), predictive", REFERENCE)


def figure(bins, *paths):
    """The reliability diagram, a panel per noise rate and size, saved to every path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    noises, sizes = sorted(bins["noise"].unique()), sorted(bins["n_train"].unique())
    fig, axes = plt.subplots(len(noises), len(sizes), figsize=(4.6 * len(sizes),
                                                                4.6 * len(noises)),
                             squeeze=False)
    styles = {row: (f"C{i}", "--" if row.endswith("satisfaction") else "-")
              for i, row in enumerate(FIGURE_ROWS)}
    for i, noise in enumerate(noises):
        for ax, n_train in zip(axes[i], sizes):
            diagonal_axes(ax, f"{noise:.0%} noise, {n_train} training missions")
            for row in FIGURE_ROWS:
                part = bins[(bins["row"] == row) & (bins["n_train"] == n_train)
                            & (bins["noise"] == noise)]
                draw_reliability(ax, part, *styles[row], label=row)
    axes[0][0].legend(fontsize=7, loc="upper left")
    fig.suptitle("LFE missions, held out: reliability of P(acceptable) "
                 "(marker area: share of the missions)")
    fig.tight_layout()
    for path in paths:
        path.parent.mkdir(parents=True, exist_ok=True)
        fig.savefig(path, dpi=100)
    plt.close(fig)


def _ci(row, metric, digits=3):
    value = row[metric]
    if not np.isfinite(value):
        return "inf"
    return (f"{value:.{digits}f} [{row[f'{metric}_low']:.{digits}f}, "
            f"{row[f'{metric}_high']:.{digits}f}]")


def report(runs, table, diffs, gaps, config, seconds, command):
    """The Markdown of RESULTS_predictive.md."""
    info = machine_info()
    first = [f"{s}, {readings[0]}" for s, (_, readings) in SETTINGS.items()]
    bsi = runs[runs["row"].isin(first)]  # one line per fit
    how = bsi.assign(setting=bsi["row"].str.rsplit(", ", n=1).str[0]).groupby(
        ["setting"] + KEYS, sort=False).agg(
        fits=("fit_s", "size"), exact=("inference", lambda s: int((s == "exact").sum())),
        specs=("n_specifications", "median"), dropped=("dropped_mass", "max"),
        flip=("flip_rate", "mean"), warnings=("warnings", "sum"), fit_s=("fit_s", "median"))
    sizes = ", ".join(str(n) for n in config["sizes"])
    noises = " and ".join(f"{r:.0%}" for r in config["noise"])
    lines = [
        "# The posterior predictive and the label noise: held-out LFE missions (issue 31)", "",
        "Generated by `benchmarks/bench_predictive.py` (its docstring has the protocol). "
        f"Missions from the study's simulator ({config['propositions']} propositions, "
        f"{noises} judgement "
        f"noise) at study seed {config['seed']}, {config['repeats']} repeats; each fits "
        f"`BSIClassifier(random_state=...)` with no roles on {sizes} of its missions and is "
        f"scored on its {config['test_size']} held-out missions, one classifier per "
        "objective (MO1-MO3). The readings of a setting (`satisfaction`: the paper's vote; "
        "`predictive, epsilon`: `label_noise=\"likelihood\"`; `predictive, learned`: "
        "`label_noise=\"learned\"`, the default) are of the *same* fit. Means over repeats "
        "of the mean over the three objectives, Student-t 95 % intervals.", "",
        f"- Command: `{command}`",
        f"- Machine: {info['cpu']} (`lscpu | grep 'Model name'`), {info['usable_cores']} "
        f"usable cores, load {info.get('load_average')}; commit {info['commit']}",
        f"- Date: {info['date']}; run time {seconds:.0f} s wall, one process.",
        f"- Versions: python {info['python']}, numpy {info['numpy']}, scikit-learn "
        f"{info['scikit-learn']}, numba {info['numba']}.", "",
        "## Scores", "",
        "Log loss is scikit-learn's (probabilities clipped to [2.2e-16, 1 - 2.2e-16], so an "
        "exact 0 or 1 on the wrong side costs 36 nats); *unclipped* is from "
        "`predict_log_proba` (infinite when a mission gets probability exactly 0 of its "
        "label). Worst bin: the largest |observed - predicted| of the reliability diagram's "
        "bins (width 0.1) holding at least 5 % of the pooled test missions.", ""]
    rows = []
    for _, r in table.iterrows():
        rows.append([f"{r.noise:.0%}", int(r.n_train), r.row, _ci(r, "log_loss"),
                     _ci(r, "log_loss_unclipped"), _ci(r, "brier"), _ci(r, "accuracy"),
                     f"{gaps.get((r.row, r.noise, r.n_train), np.nan):.3f}"])
    lines += [md_table(["noise", "missions", "row", "log loss", "log loss, unclipped",
                        "Brier", "accuracy", "worst bin"], rows), ""]
    rows = [[d.pair, f"{d.noise:.0%}", int(d.n_train), _ci(d, "log_loss"), _ci(d, "brier"),
             _ci(d, "accuracy")] for _, d in diffs.iterrows()]
    lines += ["## Paired differences (repeat by repeat)", "",
              md_table(["difference", "noise", "missions", "log loss", "Brier", "accuracy"],
                       rows), "",
              "![reliability](predictive/reliability.png)", "",
              "The same diagram is `figures/reliability_lfe_missions.png`, beside the other "
              "task families' (`bench_label_noise.py`).", "",
              "## How the BSI fits were made", "",
              md_table(["setting", "noise", "missions", "fits", "exact",
                        "median specifications", "largest dropped mass", "mean flip_rate_",
                        "warnings", "median fit + predict, s"],
                       [[s, f"{r_:.0%}", int(n), int(r.fits), int(r.exact), f"{r.specs:,.0f}",
                         f"{r.dropped:.2g}", "-" if not np.isfinite(r.flip) else
                         f"{r.flip:.3f}", int(r.warnings), f"{r.fit_s:.2f}"]
                        for (s, r_, n), r in how.iterrows()]), "",
              "## Reading the rows", "",
              "- `predictive, epsilon` is the vote `s` moved by at most the paper's `eps` "
              "(`e^-55` for five global candidates and five subtasks): `eps + (1 - 2 eps) s`, "
              "so it coincides with the vote up to rounding. Unclipped, a mission every "
              "formula labels wrongly costs `-log eps` = 55 nats under it and infinitely "
              "many under the vote.",
              "- `predictive, learned` (the default) labels with each formula's flip rate "
              "given the training missions it misclassifies, `(1 + v) / (n + 2)` (uniform "
              "prior, `docs/likelihoods.md`); the posterior over formulas is the default's, "
              "unchanged, so the decisions are the vote's wherever the posterior's formulas "
              "misclassify equally many training missions.",
              "- With the flip prior the posterior is nearly flat: the exact enumeration lists "
              "at most 1,000,000 specifications (`inference.exact.MAX_KEPT`) and renormalises "
              "them; *largest dropped mass* is what it left out, so those rows' probabilities "
              "are over the listed specifications (`flip_rate_` is over the whole support).",
              "- `flip_rate_` is the flip rate the model needs to explain the labels, its own "
              "misfit included (no roles, few missions), not the simulator's judgement noise.",
              ""]
    return "\n".join(lines)


def add_templates(template_set):
    """The default fit with ``templates=template_set`` in place of the CI fit."""
    add_variant({"templates": template_set}, f"Default, templates={template_set!r}",
                f"templates={template_set!r} - paper's template (predictive, learned)")


def add_variant(params, name=None, pair=None):
    """A fit with ``params`` beside the defaults in place of the CI fit, read by its default
    predictive: the settings, rows, pairs (it minus the default fit) and figure's rows."""
    global ROWS, FIGURE_ROWS
    name = name or ", ".join(f"{k}={v!r}" for k, v in params.items())
    SETTINGS.pop("CI, flip_prior=(1, 9)")
    SETTINGS[name] = (dict(params), ("predictive, learned",))
    ROWS = tuple(f"{s}, {r}" for s, (_, readings) in SETTINGS.items() for r in readings) \
        + (REFERENCE,)
    PAIRS[:] = [p for p in PAIRS if not p[1].startswith("CI")]
    PAIRS.append((pair or f"{name} - default (predictive, learned)",
                  f"{name}, predictive, learned", "Default, predictive, learned"))
    PAIRS.append((f"{name} - logistic regression", f"{name}, predictive, learned", REFERENCE))
    FIGURE_ROWS = ("Default, predictive, learned", f"{name}, predictive, learned",
                   REFERENCE)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=10)
    parser.add_argument("--sizes", default="12,36,72")
    parser.add_argument("--noise", default="0,0.04", help="judgement-noise rates (the study's)")
    parser.add_argument("--test-size", type=int, default=120)
    parser.add_argument("--seed", type=int, default=2031,
                        help="study seed (the repository's study runs use 0)")
    parser.add_argument("--propositions", default="paper", choices=["paper", "extended"],
                        help="the extractor's proposition set (the study's two)")
    parser.add_argument("--quick", action="store_true", help="2 repeats")
    parser.add_argument("--templates", default=None, metavar="SET",
                        help="add the default fit with templates=SET (needs --out)")
    parser.add_argument("--variant", action="append", type=parse_param, default=[],
                        metavar="NAME=VALUE",
                        help="add a fit with this BSIClassifier parameter (a Python literal; "
                             "repeatable) in place of the CI fit (needs --out)")
    parser.add_argument("--out", default=None, help="folder (default: benchmarks/)")
    parser.add_argument("--figures-only", action="store_true",
                        help="redraw the figures from the recorded predictive/reliability.csv "
                             "(no fit)")
    args = parser.parse_args(argv)
    out = Path(args.out) if args.out else Path(__file__).resolve().parent
    if args.figures_only:
        figure(pd.read_csv(out / "predictive" / "reliability.csv"),
               out / "predictive" / "reliability.png", out / "figures" / FIGURE)
        return 0
    if args.quick:
        args.repeats = 2
    if args.templates is not None:
        if args.out is None:
            parser.error("--templates writes into --out only")
        add_templates(args.templates)
    if args.propositions != "paper" and args.out is None:
        parser.error("--propositions writes into --out only")
    if args.variant:
        if args.out is None or args.templates is not None:
            parser.error("--variant writes into --out only, without --templates")
        add_variant(dict(args.variant))
    config = dict(repeats=args.repeats, sizes=[int(s) for s in args.sizes.split(",")],
                  noise=[float(r) for r in args.noise.split(",")], test_size=args.test_size,
                  seed=args.seed, propositions=args.propositions)
    start = time.perf_counter()
    runs, preds = [], []
    for repeat in range(args.repeats):
        r, p = run_repeat(repeat, config)
        runs += r
        preds += p
        print(f"repeat {repeat + 1}/{args.repeats}: {time.perf_counter() - start:.0f} s",
              file=sys.stderr)
    runs, preds = pd.DataFrame(runs), pd.concat(preds, ignore_index=True)
    table, diffs, bins = summary(runs), paired(runs), reliability(preds)
    gaps = worst_gap(bins).to_dict()
    folder = out / "predictive"
    folder.mkdir(parents=True, exist_ok=True)
    runs.to_csv(folder / "runs.csv", index=False)
    table.to_csv(folder / "summary.csv", index=False)
    bins.to_csv(folder / "reliability.csv", index=False)
    figure(bins, folder / "reliability.png", out / "figures" / FIGURE)
    command = ("python benchmarks/bench_predictive.py " + " ".join(
        argv if argv is not None else sys.argv[1:])).strip()
    text = report(runs, table, diffs, gaps, config, time.perf_counter() - start, command)
    (out / "RESULTS_predictive.md").write_text(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
