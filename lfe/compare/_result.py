"""What one ``bsi-lfe compare`` run measured, and its renderings: tables, LaTeX, figure, files."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pandas as pd

from bsi_sklearn.experiments.tables import markdown_table
from lfe._probability_scores import NOT_AVAILABLE, format_score
from lfe.compare._rows import MAJORITY, PAPER_F1

__all__ = ["ComparisonResult", "format_value"]


class ComparisonResult:
    """Everything one :func:`lfe.compare.compare` run measured.

    Attributes
    ----------
    f1 : DataFrame
        Weighted F1 per classifier (rows, :data:`lfe.compare.ROWS`) and
        objective (columns), on the out-of-fold predictions of every scenario pooled, as the
        paper computes it ("predictions ... assimilated at the end").
    log_loss, brier : DataFrame
        Log loss and Brier score, laid out as :attr:`f1`, of the pooled out-of-fold
        P(label 1) (:attr:`probabilities`); ``nan`` for a row without probabilities, or with
        a fold without them.
    f1_folds : DataFrame
        Long format: ``classifier``, ``objective``, ``fold``, ``f1`` (weighted F1 on each
        test fold alone).
    table : DataFrame
        One row per classifier: per objective ``MO<k>`` (pooled, as :attr:`f1`),
        ``MO<k> fold mean``, ``MO<k> fold std`` (population std over folds) and
        ``MO<k> paper`` (:data:`lfe.compare.PAPER_F1`, empty for the reference row); then
        ``MO<k> log loss`` and ``MO<k> Brier`` (:attr:`log_loss`, :attr:`brier`).
    map_f1 : DataFrame
        One row per BSI prior and objective: the MAP specification of a fit on every scenario,
        its weighted F1 on them, the paper's value (Prior 2 only) and the inference used.
    times : DataFrame
        Per classifier: mean and std over folds of the seconds spent fitting (all three
        objectives) and predicting a test fold, and the total.
    predictions : DataFrame
        Out-of-fold predictions, index ``scenario_id``, columns ``(classifier, objective)``;
        ``fold`` gives each scenario's test fold.
    probabilities : DataFrame
        Out-of-fold P(label 1), laid out as :attr:`predictions`; ``nan`` where the row's
        model gave none.
    folds : list of tuple of ndarray
        ``(train, test)`` positions of every fold.
    config : dict
        The run's settings (sizes, seed, n_jobs, split, training parameters).
    elapsed : float
        Wall-clock seconds of the whole run.
    """

    def __init__(self, f1, f1_folds, map_f1, times, predictions, folds, config, elapsed, *,
                 log_loss, brier, probabilities):
        self.f1 = f1
        self.log_loss = log_loss
        self.brier = brier
        self.probabilities = probabilities
        self.f1_folds = f1_folds
        self.map_f1 = map_f1
        self.times = times
        self.predictions = predictions
        self.folds = folds
        self.config = config
        self.elapsed = elapsed
        self.table = _f1_table(f1, f1_folds, log_loss, brier)

    def __repr__(self):
        return (f"ComparisonResult({self.config['n_scenarios']} scenarios, "
                f"{self.config['n_splits']} folds, {self.elapsed:.1f} s)")

    # ------------------------------------------------------------------ renderings
    def to_markdown(self):
        """The tables in Markdown: F1 (ours beside the paper's), log loss, MAP F1, times.

        The log loss table holds the Brier score too.

        Returns
        -------
        text : str
        """
        objectives = list(self.f1.columns)
        main = pd.DataFrame({"classifier": self.table.index})
        for mo in objectives:
            main[f"{mo} ours"] = [f"{v:.3f}" for v in self.table[mo]]
            main[f"{mo} paper"] = [format_value(v) for v in self.table[f"{mo} paper"]]
        calibration = self._calibration_frame()
        folds = pd.DataFrame({"classifier": self.table.index})
        for mo in objectives:
            folds[mo] = [f"{m:.3f} ± {s:.3f}" for m, s in
                         zip(self.table[f"{mo} fold mean"], self.table[f"{mo} fold std"])]
        mapf = self.map_f1.copy()
        mapf["f1"] = [f"{v:.3f}" for v in mapf["f1"]]
        mapf["paper"] = [format_value(v) for v in mapf["paper"]]
        mapf["map_specification"] = [f"`{s}`" for s in mapf["map_specification"]]
        times = self.times.reset_index()
        c = self.config
        notice = _quick_notice(c, "> ")
        return "\n".join([
            *notice, *([""] if notice else []),
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
            "### Log loss and Brier score (pooled out-of-fold probabilities; lower is better)",
            "",
            "scikit-learn's `log_loss` (labels 0 and 1, its own clipping) and "
            "`brier_score_loss` of P(label 1) on every scenario's out-of-fold prediction, for "
            f"the rows whose model gives probabilities; {NOT_AVAILABLE}: the row gives none "
            "(MiniRocket's ridge classifier, or a fold where BSI had no acceptable scenario "
            "to fit).",
            "",
            markdown_table(calibration),
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
        """The F1 table as a LaTeX ``tabular`` (booktabs); the log loss and Brier as another.

        The F1 table has ours beside the paper's.

        Returns
        -------
        text : str
        """
        objectives = list(self.f1.columns)
        fitted = [name for name in self.table.index if name != MAJORITY]
        best = {mo: self.table.loc[fitted, mo].max() for mo in objectives}
        lines = [
            *_quick_notice(self.config, "% "),
            "% Weighted F1 per mission objective; 'paper': Shah et al. (2019), for reference.",
            *_latex_head(objectives, "ours & paper"),
        ]
        for name, row in self.table.iterrows():
            cells = [_latex_escape(name)]
            for mo in objectives:
                ours = f"{row[mo]:.3f}"
                if name != MAJORITY and np.isclose(row[mo], best[mo]):
                    ours = rf"\textbf{{{ours}}}"
                cells += [ours, format_value(row[f"{mo} paper"])]
            lines.append(" & ".join(cells) + r" \\")
        lines += [r"\bottomrule", r"\end{tabular}", *self._calibration_latex()]
        return "\n".join(lines) + "\n"

    def _calibration_frame(self):
        """Per classifier, ``MO<k> log loss`` and ``MO<k> Brier`` as text ("n/a": none)."""
        frame = pd.DataFrame({"classifier": self.table.index})
        for mo in self.f1.columns:
            for metric in ("log loss", "Brier"):
                frame[f"{mo} {metric}"] = [format_score(v) for v in
                                           self.table[f"{mo} {metric}"]]
        return frame

    def _calibration_latex(self):
        """The second ``tabular`` of ``f1_table.tex``: log loss and Brier, the lowest bold."""
        objectives = list(self.f1.columns)
        fitted = [name for name in self.table.index if name != MAJORITY]
        lines = [
            "",
            "% Log loss and Brier score of the pooled out-of-fold probabilities (lower is "
            f"better); {NOT_AVAILABLE}: the row gives no probabilities.",
            *_latex_head(objectives, "log loss & Brier"),
        ]
        best = {(mo, metric): self.table.loc[fitted, f"{mo} {metric}"].min()
                for mo in objectives for metric in ("log loss", "Brier")}
        for name, row in self.table.iterrows():
            cells = [_latex_escape(name)]
            for mo in objectives:
                for metric in ("log loss", "Brier"):
                    value = row[f"{mo} {metric}"]
                    text = format_score(value)
                    if name != MAJORITY and np.isclose(value, best[(mo, metric)]):
                        text = rf"\textbf{{{text}}}"
                    cells.append(text)
            lines.append(" & ".join(cells) + r" \\")
        return lines + [r"\bottomrule", r"\end{tabular}"]

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
                     f"{c['n_scenarios']} scenarios"
                     + (" (--quick: a smoke test)" if c.get("quick") else ""))
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
        ax.grid(axis="y", alpha=0.3)
        return fig

    def save(self, out):
        """Write the tables, the figure, the times and the probabilities into ``out``.

        The files: ``f1_table.{csv,md,tex}``, ``f1_bars.png``, ``times.csv``, ``map_f1.csv``
        and ``probabilities.csv``.

        ``f1_table.*`` hold the log loss and Brier beside the F1; ``probabilities.csv`` is
        :attr:`probabilities` (empty cells: the row gave none), from which they are computed.

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
            "probabilities": out / "probabilities.csv",
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
            # every digit: the scores recomputed from this file are the tables'
            paths["probabilities"]: self.probabilities.to_csv(float_format="%.17g"),
        })
        return paths


def _quick_notice(config, prefix):
    """The lines that mark a ``--quick`` run's report (none for a full run).

    Its files look like the recorded ones (``benchmarks/RESULTS_lfe.md``), so they say what
    they are: a smoke test whose numbers are not the comparison's.

    Examples
    --------
    >>> _quick_notice({"quick": True}, "% ")[0]
    '% QUICK RUN (bsi-lfe compare --quick): a smoke test, not the recorded result.'
    >>> _quick_notice({"quick": False}, "% ")
    []
    """
    if not config.get("quick"):
        return []
    return [f"{prefix}QUICK RUN (bsi-lfe compare --quick): a smoke test, not the recorded "
            "result.",
            f"{prefix}Small baselines and short MCMC runs; its numbers are not comparable "
            "with the paper's or with a full run."]


def format_value(value):
    """A table's number with three decimals; ``""`` for a missing one (``None`` or NaN)."""
    return "" if value is None or (isinstance(value, float) and np.isnan(value)) \
        else f"{value:.3f}"


def _latex_head(objectives, pair):
    """A ``tabular``'s opening: two columns per objective, named ``pair`` (``"a & b"``)."""
    return [
        r"\begin{tabular}{l" + "rr" * len(objectives) + "}",
        r"\toprule",
        " & ".join([""] + [rf"\multicolumn{{2}}{{c}}{{\textbf{{{mo}}}}}"
                           for mo in objectives]) + r" \\",
        " & ".join([r"\textbf{Classifier}"] + [pair] * len(objectives)) + r" \\",
        r"\midrule",
    ]


def _latex_escape(text):
    return str(text).replace("&", r"\&").replace("%", r"\%").replace("_", r"\_")


def _f1_table(f1, f1_folds, log_loss, brier):
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
        for mo in f1.columns:  # after every F1 column: those stay as they were
            row[f"{mo} log loss"] = log_loss.loc[name, mo]
            row[f"{mo} Brier"] = brier.loc[name, mo]
        rows[name] = row
    table = pd.DataFrame.from_dict(rows, orient="index")
    table.index.name = "classifier"
    return table

