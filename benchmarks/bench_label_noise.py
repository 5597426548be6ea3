"""The learned label noise against the likelihood's epsilon, beyond the LFE missions (issue 31).

``BSIClassifier(label_noise="learned")`` (the default) and ``label_noise="likelihood"`` (the
predictive with CB's ``epsilon``) read the *same* fit, so each pair below is one fit scored
twice: the difference is the noise model's alone. The LFE missions are in
``bench_predictive.py``; here are the project's other benchmark families, each fitted as a user
fits it (``BSIClassifier(random_state=...)``, every default, no roles):

* **published files**: every ``--every``-th ``.trace`` file of ``../shared/benchmarks-data``
  (sorted by path) with at most ``--max-props`` propositions; ``NegationAugmenter`` first (so
  ``G(!p)`` is reachable), the split of ``benchmarks/external.py`` (70/30, stratified, seeded
  by the file's path); scored on the files' own test labels (5 % of them flipped in the
  ``5pc_misclass`` folders);
* **roles tasks**: the roles benchmark's errand and pick-and-place tasks
  (``benchmarks/bench_roles.py``: its seeds, sizes 20 and 40, clean and 10 % flipped training
  labels), scored on 300 fresh demonstrations' true verdicts;
* **event logs**: the event-log benchmark's generated logs (``make_process_log``: 20
  activities, 500 cases, the template and the Declare rule, 5 % noise, seeds 0-4), encoded by
  ``EventLogEncoder()``, split 70/30 as ``bench_event_logs.py`` splits, scored on the clean
  labels (as that benchmark scores) and on the observed ones (what the predictive predicts:
  the label a case is given, flips included).

Per fit: log loss (scikit-learn's, clipped at 2.2e-16), Brier score and accuracy of
``predict`` under each reading. Per family: means with Student-t 95 % intervals over the fits
(independent files, tasks or logs), the paired difference learned - epsilon, and a
reliability diagram of every test demonstration pooled (bins of width 0.1; *worst bin*: the
largest |observed - predicted| over the bins holding at least 5 % of them).

    python benchmarks/bench_label_noise.py            # about 10 minutes on one core
    python benchmarks/bench_label_noise.py --quick    # a few fits a family
    python benchmarks/bench_label_noise.py --variant likelihood="'calibrated'" --out /tmp/v

``--variant NAME=VALUE`` (repeatable; a Python literal) fits a second classifier with those
parameters beside the defaults on every case and reads it by its default predictive in place
of the ``epsilon`` reading (issue 31's candidate defaults): the difference is then the
default fit's minus the variant's, fit by fit. It writes into ``--out`` only.

Writes ``benchmarks/RESULTS_label_noise.md``, ``benchmarks/label_noise/runs.csv`` and
``reliability.csv`` (the bins), and one figure per task family,
``benchmarks/figures/reliability_{published_files,roles_tasks,event_logs}.png``
(``--figures-only`` redraws them from the recorded bins, without a fit). Every warning is
counted per fit, none is silenced.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import pandas as pd
from sklearn.metrics import accuracy_score, brier_score_loss, log_loss

HERE = Path(__file__).resolve().parent
import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

from _common import machine_info, md_table, parse_param  # noqa: E402
from _event_log_rows import _encoded, split_log  # noqa: E402
from _reliability import (  # noqa: E402
    diagonal_axes,
    draw_reliability,
    reliability_bins,
    worst_gap,
)
from bench_roles import _seeds, flip_labels  # noqa: E402
from external import file_seed, split_indices  # noqa: E402

from bsi_sklearn import BSIClassifier  # noqa: E402
from bsi_sklearn.data.preprocessing import NegationAugmenter  # noqa: E402
from bsi_sklearn.datasets.errands import make_errand_demos, make_errand_task  # noqa: E402
from bsi_sklearn.datasets.process_logs import make_process_log  # noqa: E402
from bsi_sklearn.io import load_trace_file  # noqa: E402
from lfe.study import t_interval  # noqa: E402

DATA = HERE.parent.parent / "shared" / "benchmarks-data"
READINGS = {"learned": "learned", "epsilon": "likelihood"}
#: ``--variant``'s parameters: a second fit read in place of ``epsilon`` (empty: none).
VARIANT = {}
METRICS = ("log_loss", "brier", "accuracy")
#: One reliability figure per task family: file name -> the families it pools, a panel each.
FIGURES = {"published_files": "published files", "roles_tasks": "roles tasks",
           "event_logs": "event logs"}


def _scores(clf, X_test, y_test, other=None):
    """Each reading's scores and P(acceptable) on the test set: ``{reading: (scores, p1)}``.

    With ``other`` (the ``--variant`` fit), the second reading is its default predictive.
    """
    out = {}
    for name, mode in READINGS.items():
        if other is not None and name == "epsilon":
            clf = other
        else:
            clf.set_params(label_noise=mode)  # read at prediction: one fit, both readings
        p1 = clf.predict_proba(X_test)[:, 1]
        out[name] = (dict(log_loss=log_loss(y_test, p1, labels=[0, 1]),
                          brier=brier_score_loss(y_test, p1, pos_label=1),
                          accuracy=accuracy_score(y_test, clf.predict(X_test))), p1)
    return out


def _fit(X, y, seed, params=None):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")  # counted, not silenced
        t0 = time.perf_counter()
        clf = BSIClassifier(random_state=seed, **(params or {})).fit(X, y)
        seconds = time.perf_counter() - t0
    kinds = sorted({f"{w.category.__name__}: {str(w.message)[:80]}" for w in caught})
    facts = dict(fit_s=seconds, inference=clf.inference_, n_warnings=len(caught),
                 warnings=" | ".join(kinds))
    if VARIANT and params is None:  # the second fit, its facts beside the default's
        other, more = _fit(X, y, seed, VARIANT)
        clf.variant_ = other
        facts.update({f"variant_{k}": v for k, v in more.items()})
    return clf, facts


def _rows(family, case, clf, facts, X_test, y_test, preds):
    """The fit's lines of ``runs.csv``; its test predictions appended to ``preds``."""
    y_test = np.asarray(y_test)
    rows = []
    other = getattr(clf, "variant_", None)
    for name, (scores, p1) in _scores(clf, X_test, y_test, other).items():
        rows.append(dict(family=family, case=case, reading=name, **facts, **scores))
        preds.append(pd.DataFrame(dict(family=family, case=case, reading=name, p=p1,
                                       y=y_test)))
    return rows


def published_files(every, max_props, preds, limit=None):
    if not DATA.is_dir():
        print(f"skipped: {DATA} is absent", file=sys.stderr)
        return []
    rows = []
    files = [p for p in sorted(DATA.rglob("*.trace"))][::every][:limit]
    for path in files:
        X, y, _ = load_trace_file(path)
        y = np.asarray(y)
        if X[0].shape[1] > max_props:
            continue
        rel = path.relative_to(DATA)
        seed = file_seed(rel, 0)
        train, test = split_indices(y, 0.3, seed)
        if len(test) == 0 or not y[train].any():
            continue
        aug = NegationAugmenter().fit([X[i] for i in train])
        X_tr, X_te = aug.transform([X[i] for i in train]), aug.transform([X[i] for i in test])
        clf, facts = _fit(X_tr, y[train], seed)
        rows += _rows("published files", str(rel), clf, facts, X_te, y[test], preds)
    return rows


def roles_tasks(seeds, preds, sizes=(20, 40), noises=(0.0, 0.1)):
    rows = []
    for kind in ("errand", "pick_place"):
        for seed in seeds:
            for size in sizes:
                s_task, s_train, s_test = _seeds(kind, seed, size)
                task = make_errand_task(kind, random_state=s_task)
                train = make_errand_demos(task, size, random_state=s_train)
                test = make_errand_demos(task, 300, random_state=s_test)
                for noise in noises:
                    y = flip_labels(train.y, noise, np.random.default_rng(s_train + 1))
                    if not y.any():
                        continue
                    clf, facts = _fit(train.traces, y, seed)
                    rows += _rows(f"roles tasks, {noise:.0%} flipped",
                                  f"{kind} seed {seed} n {size}", clf, facts, test.traces,
                                  test.y, preds)
    return rows


def event_logs(seeds, preds, n_activities=20, n_cases=500):
    rows = []
    for rule in ("template", "declare"):
        for seed in seeds:
            log = make_process_log(n_activities, n_cases, rule=rule, noise=0.05,
                                   random_state=seed)
            train, test = split_log(log, {})
            cases = dict(zip(log.labels.index, log.cases()))
            X_tr, X_te, _ = _encoded([cases[c] for c in train], [cases[c] for c in test],
                                     log.activities)
            clf, facts = _fit(X_tr, log.labels.loc[train].to_numpy(), 0)
            case = f"{n_activities}x{n_cases} seed {seed}"
            rows += _rows(f"event logs, {rule} rule, clean test labels", case, clf, facts,
                          X_te, log.clean_labels.loc[test].to_numpy(), preds)
            rows += _rows(f"event logs, {rule} rule, observed test labels", case, clf, facts,
                          X_te, log.labels.loc[test].to_numpy(), preds)
    return rows


def _ci(values):
    values = np.asarray(values, dtype=float)
    if len(values) < 2:
        return f"{values.mean():.3f}" if len(values) else "-"
    mean, low, high = t_interval(values)
    return f"{mean:.3f} [{low:.3f}, {high:.3f}]"


def figures(bins, folder):
    """One reliability diagram per task family (:data:`FIGURES`), a panel per family line."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    paths = []
    for name, prefix in FIGURES.items():
        families = [f for f in dict.fromkeys(bins["family"]) if f.startswith(prefix)]
        if not families:
            continue
        fig, axes = plt.subplots(1, len(families), figsize=(max(4.6 * len(families), 5.5), 5.4),
                                 squeeze=False, layout="constrained")
        for ax, family in zip(axes[0], families):
            diagonal_axes(ax, family[len(prefix):].lstrip(", ") or family, "label 1")
            for i, (reading, ls) in enumerate((("learned", "-"), ("epsilon", "--"))):
                part = bins[(bins["family"] == family) & (bins["reading"] == reading)]
                draw_reliability(ax, part, f"C{i}", ls, label=f"{reading} "
                                 f"(label_noise={READINGS[reading]!r})")
        axes[0][0].legend(fontsize=7, loc="upper left")
        fig.suptitle(f"{prefix}: reliability of BSI's P(label 1)\n(test demonstrations "
                     "pooled; marker area: their share)", fontsize="medium")
        folder.mkdir(parents=True, exist_ok=True)
        paths.append(folder / f"reliability_{name}.png")
        fig.savefig(paths[-1], dpi=100)
        plt.close(fig)
    return paths


def report(runs, command, seconds, gaps=None):
    info = machine_info()
    lines = ["# The learned label noise against epsilon: the other benchmark families "
             "(issue 31)", "",
             "Generated by `benchmarks/bench_label_noise.py` (its docstring has the protocol). "
             "`learned` is `label_noise=\"learned\"` (the default), `epsilon` is "
             "`label_noise=\"likelihood\"`; the two readings of a line are the *same* fit. "
             "Means over fits with Student-t 95 % intervals; the difference is paired, fit by "
             "fit.", "",
             *([f"**With `--variant`: the `epsilon` columns are the fit with "
                f"{', '.join(f'`{k}={v!r}`' for k, v in VARIANT.items())} (its default "
                "predictive), and `learned - epsilon` is the default fit's minus that "
                "one's.**", ""] if VARIANT else []),
             f"- Command: `{command}`",
             f"- Machine: {info['cpu']}, {info['usable_cores']} usable cores, load "
             f"{info.get('load_average')}; commit {info['commit']}",
             f"- Date: {info['date']}; run time {seconds:.0f} s wall, one process.",
             f"- Versions: python {info['python']}, numpy {info['numpy']}, scikit-learn "
             f"{info['scikit-learn']}, numba {info['numba']}.", ""]
    gaps = {} if gaps is None else gaps
    table = []
    for family, group in runs.groupby("family", sort=False):
        a = group[group.reading == "learned"].set_index("case")
        b = group[group.reading == "epsilon"].set_index("case").loc[a.index]
        table.append([family, len(a)]
                     + [_ci(a[m]) for m in METRICS] + [_ci(b[m]) for m in METRICS]
                     + [_ci(a[m] - b[m]) for m in ("log_loss", "accuracy")]
                     + [f"{a['fit_s'].median():.2f}", int(a["n_warnings"].sum())]
                     + [f"{gaps[(family, r)]:.3f}" if (family, r) in gaps else "-"
                        for r in ("learned", "epsilon")])
    lines += [md_table(["family", "fits", "log loss, learned", "Brier, learned",
                        "accuracy, learned", "log loss, epsilon", "Brier, epsilon",
                        "accuracy, epsilon", "log loss, learned - epsilon",
                        "accuracy, learned - epsilon", "median fit, s", "warnings",
                        "worst bin, learned", "worst bin, epsilon"], table),
              "", "*Worst bin*: the largest |observed - predicted| of the reliability "
              "diagram's bins (width 0.1) holding at least 5 % of the family's pooled test "
              "demonstrations.", ""]
    lines += [f"![reliability, {prefix}](figures/reliability_{name}.png)"
              for name, prefix in FIGURES.items()
              if any(f.startswith(prefix) for f in runs["family"])] + [""]
    warned = runs[(runs.n_warnings > 0) & (runs.reading == "learned")]
    if len(warned):
        lines += ["Fits that warned (the warnings' first words):", ""]
        lines += [f"- {r.family}, `{r.case}` ({r.inference}, {r.fit_s:.0f} s): {r.warnings}"
                  for r in warned.itertuples()]
        lines += [""]
    return "\n".join(lines)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--every", type=int, default=4, help="published files: every k-th")
    parser.add_argument("--max-props", type=int, default=7,
                        help="published files: at most this many propositions (14 columns "
                             "with the negations)")
    parser.add_argument("--seeds", type=int, default=5, help="roles tasks and logs")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--variant", action="append", type=parse_param, default=[],
                        metavar="NAME=VALUE",
                        help="a second fit with this BSIClassifier parameter (repeatable), "
                             "read in place of the epsilon reading (needs --out)")
    parser.add_argument("--out", default=None, help="folder (default: benchmarks/)")
    parser.add_argument("--figures-only", action="store_true",
                        help="redraw the figures from the recorded label_noise/reliability.csv "
                             "(no fit)")
    args = parser.parse_args(argv)
    if args.variant and args.out is None:
        parser.error("--variant writes into --out only")
    VARIANT.update(args.variant)
    out = Path(args.out) if args.out else HERE
    if args.figures_only:
        figures(pd.read_csv(out / "label_noise" / "reliability.csv"), out / "figures")
        return
    start = time.perf_counter()
    limit = 6 if args.quick else None
    seeds = range(1 if args.quick else args.seeds)
    runs, preds = [], []
    for name, run in (("published files", lambda: published_files(args.every, args.max_props,
                                                                    preds, limit)),
                      ("roles tasks", lambda: roles_tasks(seeds, preds)),
                      ("event logs", lambda: event_logs(seeds, preds))):
        runs += run()
        print(f"{name}: {time.perf_counter() - start:.0f} s", file=sys.stderr)
    runs = pd.DataFrame(runs)
    bins = reliability_bins(pd.concat(preds, ignore_index=True), ["family", "reading"])
    folder = out / "label_noise"
    folder.mkdir(parents=True, exist_ok=True)
    runs.to_csv(folder / "runs.csv", index=False)
    bins.to_csv(folder / "reliability.csv", index=False)
    figures(bins, out / "figures")
    command = ("python benchmarks/bench_label_noise.py " + " ".join(
        argv if argv is not None else sys.argv[1:])).strip()
    text = report(runs, command, time.perf_counter() - start,
                  worst_gap(bins, ["family", "reading"]).to_dict())
    (out / "RESULTS_label_noise.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()
