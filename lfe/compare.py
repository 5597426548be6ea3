"""``bsi-lfe compare``: BSI against the recurrent baselines on LFE missions (the paper's table).

The paper's large-force-exercise evaluation: four-fold cross-validation over the 24 missions
(18 training / 6 test scenarios per fold), six classifiers (LSTM, Bi-LSTM, LSTM Coupled,
Bi-LSTM Coupled, BSI with Prior 2 and BSI with Prior 3), weighted F1 over both outcomes per
mission objective; and the F1 of the MAP specification fitted on the whole dataset. Beside
the paper's rows, on the same folds: BSI with the CI likelihood, and what a practitioner
would try first (:mod:`baselines.practitioner`: a logistic regression on plain temporal
features, and MiniRocket).
"""

from __future__ import annotations

import io
import time
from numbers import Integral
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.dummy import DummyClassifier
from sklearn.model_selection import KFold, StratifiedKFold
from sklearn.utils.parallel import Parallel, delayed

import baselines
from baselines import FAIR_TRAINING, PAPER_BASELINES
from baselines.practitioner import (
    PRACTITIONER_BASELINES,
    make_practitioner_baseline,
)
from bsi_sklearn.classifier import BSIClassifier
from bsi_sklearn.experiments.tables import markdown_table
from bsi_sklearn.param_validation import (
    NONZERO_INTEGER,
    Interval,
    check_options,
    validate_params,
)
from lfe._cli_compare import QUICK, add_arguments
from lfe.annotate import MISSION_OBJECTIVES
from lfe.dataset import LFEDataset, load_lfe_dataset, make_lfe_dataset
from lfe.extractor import LFEPropositionExtractor
from lfe.scenario import checked_once

__all__ = [
    "BSI_PRIORS",
    "BSI_ROWS",
    "CLASSIFIERS",
    "ComparisonResult",
    "MAJORITY",
    "PAPER_F1",
    "PAPER_MAP_F1",
    "ROWS",
    "add_arguments",
    "compare",
    "run",
]

#: BSI classifiers of the comparison: name -> ``BSIClassifier(prior=...)``.
BSI_PRIORS = {"BSI (Prior 2)": "sets_of_chains", "BSI (Prior 3)": "forest"}

#: BSI rows of the comparison and of ``bsi-lfe study``: name -> ``BSIClassifier`` parameters
#: (the paper's two priors with the CB likelihood, and Prior 2 with the CI likelihood).
BSI_ROWS = {**{name: {"prior": prior} for name, prior in BSI_PRIORS.items()},
            "BSI (Prior 2, CI)": {"prior": "sets_of_chains", "likelihood": "ci"},
            "BSI (no roles)": {}}

#: BSI rows fitted as a user without an expert would: every default, and not the extractor's
#: roles (the classifier then decides which propositions play which role).
WITHOUT_ROLES = frozenset({"BSI (no roles)"})

#: The six classifiers of the paper's table, in its order.
CLASSIFIERS = (*PAPER_BASELINES, *BSI_PRIORS)

#: Reference row: always predict the training folds' most frequent outcome. The paper reports
#: that its recurrent models collapsed to exactly this; its baselines' F1 are the majority
#: class's on its data.
MAJORITY = "Majority class"

#: Every row of the comparison, in display order: the paper's six, BSI with the CI likelihood,
#: BSI without roles, the practitioner's rows and the majority class.
ROWS = (*CLASSIFIERS, "BSI (Prior 2, CI)", "BSI (no roles)", *PRACTITIONER_BASELINES, MAJORITY)

#: The paper's Table "Weighted F1 scores for both scenario outcomes for each of the
#: classifiers" (four-fold cross-validation on its 24 JSAF missions), for reference only.
PAPER_F1 = pd.DataFrame(
    [[0.533, 0.533, 0.481]] * 4 + [[0.674, 0.712, 0.877], [0.674, 0.676, 0.877]],
    index=pd.Index(CLASSIFIERS, name="classifier"), columns=list(MISSION_OBJECTIVES),
)

#: The paper's weighted F1 of the MAP specification under Prior 2 fitted on all 24 missions
#: (it gives none for Prior 3).
PAPER_MAP_F1 = {"BSI (Prior 2)": {"MO1": 0.959, "MO2": 0.918, "MO3": 0.959}}

# The paper's proposition set: 8.3 million hypotheses under Prior 2 and 34.4 million under
# Prior 3, each enumerated exactly in a few seconds.
_QUICK = QUICK  # the --quick sizes, with the command line's arguments (lfe._cli_compare)
_QUICK_BASELINE = dict(hidden_size=16, max_epochs=15, patience=5)
# inference stays "auto" (exact within its work budget); shorter chains only if it samples
_QUICK_BSI = dict(inference="auto", n_samples=300, n_chains=2, burn_in=50)


class ComparisonResult:
    """Everything one :func:`compare` run measured.

    Attributes
    ----------
    f1 : DataFrame
        Weighted F1 per classifier (rows, :data:`ROWS`) and
        objective (columns), on the out-of-fold predictions of every scenario pooled, as the
        paper computes it ("predictions ... assimilated at the end").
    f1_folds : DataFrame
        Long format: ``classifier``, ``objective``, ``fold``, ``f1`` (weighted F1 on each
        test fold alone).
    table : DataFrame
        One row per classifier: per objective ``MO<k>`` (pooled, as :attr:`f1`),
        ``MO<k> fold mean``, ``MO<k> fold std`` (population std over folds) and
        ``MO<k> paper`` (:data:`PAPER_F1`, empty for the reference row).
    map_f1 : DataFrame
        One row per BSI prior and objective: the MAP specification of a fit on every scenario,
        its weighted F1 on them, the paper's value (Prior 2 only) and the inference used.
    times : DataFrame
        Per classifier: mean and std over folds of the seconds spent fitting (all three
        objectives) and predicting a test fold, and the total.
    predictions : DataFrame
        Out-of-fold predictions, index ``scenario_id``, columns ``(classifier, objective)``;
        ``fold`` gives each scenario's test fold.
    folds : list of tuple of ndarray
        ``(train, test)`` positions of every fold.
    config : dict
        The run's settings (sizes, seed, n_jobs, split, training parameters).
    elapsed : float
        Wall-clock seconds of the whole run.
    """

    def __init__(self, f1, f1_folds, map_f1, times, predictions, folds, config, elapsed):
        self.f1 = f1
        self.f1_folds = f1_folds
        self.map_f1 = map_f1
        self.times = times
        self.predictions = predictions
        self.folds = folds
        self.config = config
        self.elapsed = elapsed
        self.table = _f1_table(f1, f1_folds)

    def __repr__(self):
        return (f"ComparisonResult({self.config['n_scenarios']} scenarios, "
                f"{self.config['n_splits']} folds, {self.elapsed:.1f} s)")

    # ------------------------------------------------------------------ renderings
    def to_markdown(self):
        """The F1 table (ours beside the paper's), the MAP-formula F1 and the times, Markdown.

        Returns
        -------
        text : str
        """
        objectives = list(self.f1.columns)
        main = pd.DataFrame({"classifier": self.table.index})
        for mo in objectives:
            main[f"{mo} ours"] = [f"{v:.3f}" for v in self.table[mo]]
            main[f"{mo} paper"] = [_fmt(v) for v in self.table[f"{mo} paper"]]
        folds = pd.DataFrame({"classifier": self.table.index})
        for mo in objectives:
            folds[mo] = [f"{m:.3f} ± {s:.3f}" for m, s in
                         zip(self.table[f"{mo} fold mean"], self.table[f"{mo} fold std"])]
        mapf = self.map_f1.copy()
        mapf["f1"] = [f"{v:.3f}" for v in mapf["f1"]]
        mapf["paper"] = [_fmt(v) for v in mapf["paper"]]
        mapf["map_specification"] = [f"`{s}`" for s in mapf["map_specification"]]
        times = self.times.reset_index()
        c = self.config
        return "\n".join([
            f"## Weighted F1 per mission objective ({c['n_splits']}-fold cross-validation, "
            f"{c['n_scenarios']} scenarios)",
            "",
            "*ours*: out-of-fold predictions of every scenario pooled, then weighted F1 (the "
            "paper's protocol); *paper*: the paper's Table of weighted F1 scores (its own 24 "
            "JSAF missions), for reference. Beside the paper's rows: BSI with the CI "
            "likelihood, a logistic regression on temporal features of the propositions and "
            "MiniRocket (`baselines.practitioner`), on the same folds.",
            "",
            markdown_table(main),
            "",
            "### Per-fold weighted F1 (mean ± std over the test folds)",
            "",
            markdown_table(folds),
            "",
            "## MAP specification fitted on every scenario: weighted F1 on them",
            "",
            markdown_table(mapf[["classifier", "objective", "f1", "paper", "inference",
                                 "map_specification"]]),
            "",
            "## Times (seconds per fold: fit on the training scenarios, predict the test ones)",
            "",
            markdown_table(times, floatfmt=".3f"),
            "",
            f"Seed {c['seed']}, n_jobs {c['n_jobs']}, folds: {c['split']}; whole run "
            f"{self.elapsed:.1f} s wall clock.",
        ]) + "\n"

    def to_latex(self):
        """The F1 table as a LaTeX ``tabular`` (booktabs), ours beside the paper's.

        Returns
        -------
        text : str
        """
        objectives = list(self.f1.columns)
        fitted = [name for name in self.table.index if name != MAJORITY]
        best = {mo: self.table.loc[fitted, mo].max() for mo in objectives}
        lines = [
            "% Weighted F1 per mission objective; 'paper': Shah et al. (2019), for reference.",
            r"\begin{tabular}{l" + "rr" * len(objectives) + "}",
            r"\toprule",
            " & ".join([""] + [rf"\multicolumn{{2}}{{c}}{{\textbf{{{mo}}}}}"
                               for mo in objectives]) + r" \\",
            " & ".join([r"\textbf{Classifier}"] + ["ours & paper"] * len(objectives)) + r" \\",
            r"\midrule",
        ]
        for name, row in self.table.iterrows():
            cells = [_latex_escape(name)]
            for mo in objectives:
                ours = f"{row[mo]:.3f}"
                if name != MAJORITY and np.isclose(row[mo], best[mo]):
                    ours = rf"\textbf{{{ours}}}"
                cells += [ours, _fmt(row[f"{mo} paper"])]
            lines.append(" & ".join(cells) + r" \\")
        lines += [r"\bottomrule", r"\end{tabular}"]
        return "\n".join(lines) + "\n"

    def plot(self, ax=None):
        """Grouped bar chart: objectives on x, one bar per classifier, the paper's values marked.

        Parameters
        ----------
        ax : matplotlib Axes, default=None
            Where to draw; a new figure when omitted.

        Returns
        -------
        fig : matplotlib Figure
        """
        import matplotlib.pyplot as plt

        if ax is None:
            fig, ax = plt.subplots(figsize=(9, 4.5), layout="constrained")
        else:
            fig = ax.figure
        objectives = list(self.f1.columns)
        names = [name for name in self.f1.index if name != MAJORITY]
        width = 0.8 / len(names)
        colors = plt.get_cmap("tab10").colors
        x = np.arange(len(objectives))
        for k, name in enumerate(names):
            pos = x - 0.4 + width * (k + 0.5)
            ax.bar(pos, self.f1.loc[name, objectives], width, color=colors[k % 10], label=name)
            paper = PAPER_F1.loc[name, objectives] if name in PAPER_F1.index else None
            if paper is not None:
                ax.scatter(pos, paper, marker="D", s=22, color="black", zorder=3,
                           label="paper (Shah et al. 2019)" if k == 0 else None)
        if MAJORITY in self.f1.index:
            for i, mo in enumerate(objectives):
                ax.hlines(self.f1.loc[MAJORITY, mo], i - 0.42, i + 0.42, colors="0.3",
                          linestyles="dashed", label=MAJORITY if i == 0 else None, zorder=4)
        ax.set_xticks(x, objectives)
        ax.set_ylim(0, 1.05)
        ax.set_ylabel("weighted F1 (out-of-fold)")
        c = self.config
        ax.set_title(f"LFE mission objectives: {c['n_splits']}-fold cross-validation, "
                     f"{c['n_scenarios']} scenarios")
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
        ax.grid(axis="y", alpha=0.3)
        return fig

    def save(self, out):
        """Write ``f1_table.{csv,md,tex}``, ``f1_bars.png``, ``times.csv`` and ``map_f1.csv``.

        Parameters
        ----------
        out : str or Path
            Output directory, created if needed.

        Returns
        -------
        paths : dict
            File kind -> path.

        Raises
        ------
        OSError
            Naming the file that could not be written; the files are written all or none.
        """
        import matplotlib.pyplot as plt

        from bsi_sklearn.io import write_files_atomic

        out = Path(out)
        out.mkdir(parents=True, exist_ok=True)
        paths = {
            "f1_csv": out / "f1_table.csv",
            "f1_md": out / "f1_table.md",
            "f1_tex": out / "f1_table.tex",
            "f1_png": out / "f1_bars.png",
            "times": out / "times.csv",
            "map_f1": out / "map_f1.csv",
        }
        fig = self.plot()
        png = io.BytesIO()
        try:
            fig.savefig(png, format="png", dpi=120)
        finally:
            plt.close(fig)
        # all or nothing: a failed write (read-only folder, full disk) leaves the previous
        # files whole, with no temporary file
        write_files_atomic({
            paths["f1_csv"]: self.table.to_csv(float_format="%.6g"),
            paths["f1_md"]: self.to_markdown(),
            paths["f1_tex"]: self.to_latex(),
            paths["f1_png"]: png.getvalue(),
            paths["times"]: self.times.to_csv(float_format="%.4f"),
            paths["map_f1"]: self.map_f1.to_csv(index=False, float_format="%.6g"),
        })
        return paths


def _fmt(value):
    return "" if value is None or (isinstance(value, float) and np.isnan(value)) \
        else f"{value:.3f}"


def _latex_escape(text):
    return str(text).replace("&", r"\&").replace("%", r"\%").replace("_", r"\_")


def _f1_table(f1, f1_folds):
    rows = {}
    stats = f1_folds.groupby(["classifier", "objective"], sort=False)["f1"]
    mean, std = stats.mean(), stats.std(ddof=0)
    for name in f1.index:
        row = {}
        for mo in f1.columns:
            row[mo] = f1.loc[name, mo]
            row[f"{mo} fold mean"] = mean[(name, mo)]
            row[f"{mo} fold std"] = std[(name, mo)]
            row[f"{mo} paper"] = PAPER_F1.loc[name, mo] if name in PAPER_F1.index else np.nan
        rows[name] = row
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index.name = "classifier"
    return table


# ---------------------------------------------------------------------- the run
def _folds(labels, n_splits, seed):
    """Shuffled folds stratified on the combination of the three outcomes, when possible."""
    codes = labels.to_numpy() @ (1 << np.arange(labels.shape[1]))
    n = len(labels)
    positions = np.arange(n)
    try:
        # Outcome combinations with fewer missions than folds are spread as evenly as possible
        # (scikit-learn warns about them; the split's description says so too).
        folds = list(StratifiedKFold(n_splits, shuffle=True, random_state=seed)
                     .split(positions, codes))
        split = "StratifiedKFold on the MO1-MO3 outcome combination, shuffled"
        rare = int(np.sum((np.bincount(codes) > 0) & (np.bincount(codes) < n_splits)))
        if rare:
            split += (f" ({rare} combination{'s' if rare > 1 else ''} with fewer missions than "
                      "folds, spread as evenly as possible)")
    except ValueError:  # every combination rarer than n_splits: plain shuffled folds
        folds = list(KFold(n_splits, shuffle=True, random_state=seed).split(positions))
        split = "KFold, shuffled"
    return [(np.sort(tr), np.sort(te)) for tr, te in folds], split


def _weighted_f1(y_true, y_pred):
    """``f1_score(average="weighted", zero_division=0)`` of 0/1 labels, without its overhead.

    The comparison scores a few hundred label pairs; scikit-learn's validation would dominate
    the quick runs. Labels present in ``y_true`` are weighted by their support.
    """
    y_true, y_pred = np.asarray(y_true), np.asarray(y_pred)
    total = 0.0
    for label in np.unique(y_true):
        tp = np.sum((y_true == label) & (y_pred == label))
        denom = np.sum(y_true == label) + np.sum(y_pred == label)
        total += np.sum(y_true == label) * (2.0 * tp / denom if denom else 0.0)
    return float(total / len(y_true)) if len(y_true) else 0.0


def _fit_bsi(name, X, y, roles, params, seed):
    """One BSI classifier fitted on one objective; ``None`` without an acceptable scenario."""
    if not np.any(y == 1):
        return None  # BSI needs an acceptable demonstration; predict "failed" throughout
    roles = {} if name in WITHOUT_ROLES else roles
    clf = BSIClassifier(random_state=seed, **roles, **params, **BSI_ROWS[name])
    return clf.fit(X, y)  # a ConvergenceWarning, if MCMC ran and did not converge, is shown


def _run_task(kind, name, fold, data, train, test, params, seed):
    """Fit one classifier on ``train`` and predict ``test``; return predictions and times.

    ``kind`` is ``"baseline"`` (a network), ``"practitioner"``, ``"bsi"``, ``"majority"`` or
    ``"map"`` (a BSI fit on every scenario, scored with its MAP specification).
    """
    y = data["labels"]

    def sub(seqs, idx):
        return [seqs[i] for i in idx]

    if kind == "baseline":
        clf = baselines.make_paper_baseline(name, random_state=seed, **params)
        X = data["coupled"] if clf.coupled else data["props"]
        start = time.perf_counter()
        clf.fit(sub(X, train), y[train], phases=sub(data["phases"], train))
        fit_s = time.perf_counter() - start
        start = time.perf_counter()
        pred = clf.predict(sub(X, test))
        return {"pred": pred, "fit_s": fit_s, "predict_s": time.perf_counter() - start}
    if kind == "practitioner":
        clf = make_practitioner_baseline(name, random_state=seed)
        start = time.perf_counter()
        clf.fit(sub(data["props"], train), y[train])
        fit_s = time.perf_counter() - start
        start = time.perf_counter()
        pred = clf.predict(sub(data["props"], test))
        return {"pred": pred, "fit_s": fit_s, "predict_s": time.perf_counter() - start}
    if kind == "majority":
        start = time.perf_counter()
        clf = DummyClassifier(strategy="most_frequent").fit(np.zeros((len(train), 1)), y[train])
        fit_s = time.perf_counter() - start
        start = time.perf_counter()
        pred = clf.predict(np.zeros((len(test), 1)))
        return {"pred": pred, "fit_s": fit_s, "predict_s": time.perf_counter() - start}
    X_train, X_test = sub(data["props"], train), sub(data["props"], test)
    preds, fit_s, predict_s, extra = [], 0.0, 0.0, []
    for k in range(y.shape[1]):
        start = time.perf_counter()
        clf = _fit_bsi(name, X_train, y[train, k], data["roles"], params, seed)
        fit_s += time.perf_counter() - start
        start = time.perf_counter()
        if clf is None:
            pred = np.zeros(len(test), dtype=y.dtype)
        elif kind == "map":
            spec = clf.map_specification_
            pred = np.array([int(spec.satisfied_by(t)) for t in X_test], dtype=y.dtype)
        else:
            pred = clf.predict(X_test)
        predict_s += time.perf_counter() - start
        preds.append(pred)
        extra.append({
            "map_specification": "" if clf is None else clf.map_specification_.to_ltl(),
            "inference": "none" if clf is None else clf.inference_,
        })
    return {"pred": np.column_stack(preds), "fit_s": fit_s, "predict_s": predict_s,
            "extra": extra}


_COMPARE_CONSTRAINTS = {
    "dataset": [None, LFEDataset],
    "n_splits": [Interval(Integral, 2, None, closed="left"), None],
    "seed": [Interval(Integral, 0, None, closed="left")],
    "n_jobs": [None, NONZERO_INTEGER],
    "quick": "no_validation",  # read as a truth value
    "verbose": [Interval(Integral, 0, None, closed="left")],
}


def compare(dataset=None, *, n_splits=None, seed=0, n_jobs=None, quick=False, verbose=1):
    """Cross-validate BSI and the paper's four recurrent baselines on LFE missions.

    Every classifier sees the same folds. The baselines (:func:`baselines.make_paper_baseline`,
    hidden size 32, Adam at 1e-2, mini-batches of 4, at most 200 epochs) are trained with the
    protocol :data:`baselines.FAIR_TRAINING`: early stopping (patience 20) chooses the number
    of epochs on a 20 % validation split of the training scenarios, then a fresh network with
    the same initial weights is refitted on every training scenario for that many epochs, so
    the networks learn from as many scenarios as BSI. They predict the three objectives at
    once; the standalone ones read the propositions, the
    coupled ones also the aircraft flight-phase fractions
    (:meth:`LFEPropositionExtractor.flight_phase_features`) and learn the commander's phase
    labels (:meth:`LFEPropositionExtractor.phase_labels`) as a second task. BSI fits one
    :class:`~bsi_sklearn.BSIClassifier` per objective (CB likelihood, the paper's proposition
    roles, the exact posterior) and predicts by posterior voting. A majority-class reference
    row is added. The MAP-formula F1 comes from BSI fitted on every scenario, its MAP
    specification's verdicts scored against the labels. On the same folds: BSI with Prior 2
    and the CI likelihood, and the practitioner's rows (:mod:`baselines.practitioner`): a
    logistic regression on five temporal features per proposition, its regularisation chosen
    by an inner cross-validation on the training folds only, and MiniRocket with a ridge
    classifier.

    Parameters
    ----------
    dataset : LFEDataset, default=None
        The missions; the built-in dataset (:func:`lfe.load_lfe_dataset`, 24 scenarios) when
        omitted, or with ``quick=True`` a simulated one of 8 scenarios (seed 0).
    n_splits : int, default=None
        Number of folds: 4 (the paper's), or 2 with ``quick=True``. The folds are shuffled
        with ``seed`` and stratified on the combination of the three outcomes (each
        combination spread over the folds as evenly as its count allows; plain shuffled
        :class:`~sklearn.model_selection.KFold` when no combination has ``n_splits``
        members), so every training fold sees both outcomes of each objective where possible.
    seed : int, default=0
        Seeds the folds, the baselines' weights, validation splits and batch order, and the
        MCMC chains (quick mode). Each fold's models get their own seed drawn from it.
    n_jobs : int, default=None
        Fits run in parallel processes (joblib; ``None`` or 1: sequentially, -1: every
        core). Each fit is deterministic and single-threaded (the baselines use one torch
        thread), so the results do not depend on ``n_jobs``.
    quick : bool, default=False
        A smoke test in seconds: 8 scenarios (unless ``dataset``), 2 folds, small baselines
        (hidden size 16, at most 15 epochs) and short MCMC runs instead of the exact
        posterior. Not the paper's result.
    verbose : int, default=1
        ``0`` silent; ``1`` a progress bar over the fits.

    Returns
    -------
    result : ComparisonResult
        The tables (``f1``, ``table``, ``map_f1``, ``times``, ``f1_folds``), the
        out-of-fold predictions and the folds; ``save(out)`` writes the files.

    Raises
    ------
    ModuleNotFoundError
        When torch (the ``bsi-sklearn[baselines]`` extra) is not installed, before any fit.

    Examples
    --------
    >>> from lfe import make_lfe_dataset
    >>> from lfe.compare import compare
    >>> ds = make_lfe_dataset(n_scenarios=4, random_state=0)
    >>> res = compare(ds, quick=True, verbose=0)
    >>> list(res.f1.columns), list(res.f1.index[:7])
    (['MO1', 'MO2', 'MO3'], ['LSTM', 'Bi-LSTM', 'LSTM Coupled', 'Bi-LSTM Coupled', \
'BSI (Prior 2)', 'BSI (Prior 3)', 'BSI (Prior 2, CI)'])
    >>> "Logistic regression" in res.f1.index
    True
    >>> sorted(set(res.map_f1["classifier"]))
    ['BSI (Prior 2)', 'BSI (Prior 2, CI)', 'BSI (Prior 3)', 'BSI (no roles)']
    >>> full = compare()   # the paper's setting: 1.5 to 4 minutes on 2 cores  # doctest: +SKIP
    """
    start_run = time.perf_counter()
    validate_params({"dataset": dataset, "n_splits": n_splits, "seed": seed, "n_jobs": n_jobs,
                     "quick": quick, "verbose": verbose}, _COMPARE_CONSTRAINTS, "compare")
    if n_splits is None:
        n_splits = _QUICK["n_splits"] if quick else 4
    if dataset is None:
        dataset = (make_lfe_dataset(_QUICK["n_scenarios"], random_state=0) if quick
                   else load_lfe_dataset())
    if n_splits > len(dataset):
        raise ValueError(
            f"n_splits={n_splits} is more than the {len(dataset)} scenarios of the dataset"
        )

    baselines.require_torch()  # the networks need torch: say so before the BSI fits, not after
    objectives = list(MISSION_OBJECTIVES)
    labels = dataset.labels[objectives]
    with checked_once(dataset.scenarios) as scenarios:  # validated once, not four times
        extractor = LFEPropositionExtractor().fit(scenarios)
        props = extractor.transform(scenarios)
        flight = extractor.flight_phase_features(scenarios)
        phases = extractor.phase_labels(scenarios, dataset.phases)
    data = {
        "props": props,
        "coupled": [pd.concat([p.astype(float), f], axis=1) for p, f in zip(props, flight)],
        "phases": phases,
        "labels": labels.to_numpy(),
        "roles": {"global_candidates": extractor.global_candidates_,
                  "subtasks": extractor.subtasks_, "conditions": extractor.conditions_},
    }
    folds, split = _folds(labels, n_splits, seed)
    fold_seeds = np.random.RandomState(seed).randint(np.iinfo(np.int32).max, size=n_splits)
    baseline_params = {**FAIR_TRAINING, **(_QUICK_BASELINE if quick else {})}
    bsi_params = dict(_QUICK_BSI) if quick else {}
    everything = np.arange(len(dataset))

    # Longest fits first, so parallel workers finish together.
    tasks = [("map", name, -1, everything, everything, bsi_params, seed) for name in BSI_ROWS]
    tasks += [("bsi", name, f, tr, te, bsi_params, int(fold_seeds[f]))
              for name in BSI_ROWS for f, (tr, te) in enumerate(folds)]
    tasks += [("baseline", name, f, tr, te, baseline_params, int(fold_seeds[f]))
              for name in PAPER_BASELINES for f, (tr, te) in enumerate(folds)]
    tasks += [("practitioner", name, f, tr, te, {}, int(fold_seeds[f]))
              for name in PRACTITIONER_BASELINES for f, (tr, te) in enumerate(folds)]
    tasks += [("majority", MAJORITY, f, tr, te, {}, 0) for f, (tr, te) in enumerate(folds)]

    jobs = (delayed(_run_task)(kind, name, f, data, tr, te, params, s)
            for kind, name, f, tr, te, params, s in tasks)
    outputs = Parallel(n_jobs=n_jobs, return_as="generator")(jobs)
    if verbose:
        from tqdm.auto import tqdm

        outputs = tqdm(outputs, total=len(tasks), desc="bsi-lfe compare", unit="fit")
    # loky may restart a worker whose memory grew and resubmit its jobs, with a UserWarning;
    # nothing is lost (the tables do not depend on n_jobs), and the user sees it.
    outputs = list(outputs)

    names = list(ROWS)
    pred = {name: np.full(labels.shape, -1, dtype=np.int64) for name in names}
    time_rows, fold_rows, map_rows = [], [], []
    for (kind, name, f, _, test, _, _), out in zip(tasks, outputs):
        if kind == "map":
            for k, mo in enumerate(objectives):
                map_rows.append({
                    "classifier": name, "objective": mo,
                    "f1": _weighted_f1(labels[mo].to_numpy(), out["pred"][:, k]),
                    "paper": PAPER_MAP_F1.get(name, {}).get(mo, np.nan),
                    "inference": out["extra"][k]["inference"],
                    "map_specification": out["extra"][k]["map_specification"],
                })
            continue
        pred[name][test] = out["pred"]
        time_rows.append({"classifier": name, "fold": f, "fit_s": out["fit_s"],
                          "predict_s": out["predict_s"]})
        for k, mo in enumerate(objectives):
            fold_rows.append({"classifier": name, "objective": mo, "fold": f,
                              "f1": _weighted_f1(labels[mo].to_numpy()[test],
                                                 out["pred"][:, k])})

    f1 = pd.DataFrame(
        [[_weighted_f1(labels[mo].to_numpy(), pred[name][:, k])
          for k, mo in enumerate(objectives)] for name in names],
        index=pd.Index(names, name="classifier"), columns=objectives,
    )
    times = (pd.DataFrame(time_rows).groupby("classifier", sort=False)
             .agg(fit_s_mean=("fit_s", "mean"), fit_s_std=("fit_s", lambda s: s.std(ddof=0)),
                  predict_s_mean=("predict_s", "mean"), fit_predict_s_total=("fit_s", "sum")))
    times["fit_predict_s_total"] += pd.DataFrame(time_rows).groupby(
        "classifier", sort=False)["predict_s"].sum()
    times = times.loc[names]
    fold_of = np.empty(len(dataset), dtype=np.int64)
    for f, (_, te) in enumerate(folds):
        fold_of[te] = f
    predictions = pd.DataFrame(
        np.column_stack([pred[name] for name in names]),
        index=pd.Index(dataset.scenario_ids, name="scenario_id"),
        columns=pd.MultiIndex.from_product([names, objectives],
                                           names=["classifier", "objective"]),
    )
    predictions[("fold", "")] = fold_of
    config = {
        "n_scenarios": len(dataset), "n_splits": n_splits, "seed": seed, "n_jobs": n_jobs,
        "quick": bool(quick), "split": split,
        "fold_sizes": [(len(tr), len(te)) for tr, te in folds],
        "baseline_params": baseline_params, "bsi_params": bsi_params,
        "dataset": dict(dataset.info),
    }
    return ComparisonResult(f1, pd.DataFrame(fold_rows), pd.DataFrame(map_rows), times,
                            predictions, folds, config, time.perf_counter() - start_run)


# ---------------------------------------------------------------------- command line
_OPTION_CONSTRAINTS = {
    "n_scenarios": [Interval(Integral, 1, None, closed="left"), None],
    "folds": [Interval(Integral, 2, None, closed="left"), None],
    "seed": [Interval(Integral, 0, None, closed="left")],
    "n_jobs": [None, NONZERO_INTEGER],
    "verbose": [Interval(Integral, 0, None, closed="left")],
}


def run(args):
    """Run the comparison, write its files to ``--out`` and print the table."""
    check_options(args, _OPTION_CONSTRAINTS)
    if args.dataset is not None and args.n_scenarios is not None:
        raise ValueError("give either --dataset or --n-scenarios, not both")
    if args.dataset is not None:
        dataset = load_lfe_dataset(args.dataset)
    elif args.n_scenarios is not None:
        dataset = make_lfe_dataset(args.n_scenarios, random_state=0)
    else:
        dataset = None
    result = compare(dataset, n_splits=args.folds, seed=args.seed, n_jobs=args.n_jobs,
                     quick=args.quick, verbose=args.verbose)
    paths = result.save(args.out)
    print(_console_table(result))
    print(f"files written to {Path(args.out)}: "
          + ", ".join(p.name for p in paths.values()))
    return 0


def _console_table(result):
    buf = io.StringIO()
    c = result.config
    print(f"Weighted F1, {c['n_splits']}-fold cross-validation on {c['n_scenarios']} scenarios"
          f"{' (--quick: a smoke test, not the paper setting)' if c['quick'] else ''}", file=buf)
    print("ours = out-of-fold predictions pooled (fold mean ± std); "
          "paper = Shah et al. 2019, Table 'Weighted F1 scores', for reference", file=buf)
    objectives = list(result.f1.columns)
    header = f"{'classifier':<19}" + "".join(f"{mo + ' ours':>22}{mo + ' paper':>10}"
                                              for mo in objectives)
    print(header, file=buf)
    print("-" * len(header), file=buf)
    t = result.table
    for name in t.index:
        line = f"{name:<19}"
        for mo in objectives:
            ours = (f"{t.loc[name, mo]:.3f} ({t.loc[name, mo + ' fold mean']:.2f}"
                    f"±{t.loc[name, mo + ' fold std']:.2f})")
            line += f"{ours:>22}{_fmt(t.loc[name, mo + ' paper']):>10}"
        print(line, file=buf)
    print("\nMAP specification fitted on every scenario (weighted F1 on them; paper: Prior 2)",
          file=buf)
    for _, row in result.map_f1.iterrows():
        paper = _fmt(row["paper"])
        print(f"  {row['classifier']:<17} {row['objective']}  {row['f1']:.3f}"
              f"{'  paper ' + paper if paper else ''}   {row['map_specification']}", file=buf)
    print("\nSeconds per fold (fit / predict):", file=buf)
    for name, row in result.times.iterrows():
        print(f"  {name:<19} {row['fit_s_mean']:8.2f} / {row['predict_s_mean']:.3f}", file=buf)
    print(f"\nWhole run: {result.elapsed:.1f} s wall clock", file=buf)
    return buf.getvalue().rstrip("\n")
