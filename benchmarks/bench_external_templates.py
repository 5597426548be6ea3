"""Issue 28: the shared published files fitted as a user fits them, with and without patterns.

    python benchmarks/bench_external_templates.py              # the recorded run
    python benchmarks/bench_external_templates.py --every 12   # every 12-th file per folder

The protocol of ``benchmarks/external.py`` without its screening: the same files
(``../shared/benchmarks-data``), the same per-file 70 / 30 split (seeded by the file's path),
and each setting fitted with the estimator's defaults on the training half:

* ``paper``: ``BSIClassifier(random_state=s)`` on the traces as read;
* ``paper+negations``: ``make_pipeline(NegationAugmenter(), BSIClassifier(random_state=s))``,
  the issue's "as a user would" row (``G(!p)`` needs the negated column);
* ``unary``: ``templates="unary"``, the catalogue's one-proposition templates (existence,
  absence, at most once, init, universality), whose candidates grow linearly with the
  propositions;
* ``declare``: ``templates="declare"``, the Declare templates of the catalogue;
* ``catalogue``: ``templates="all"``, every template of the catalogue;
* ``catalogue+ci``: the same with ``likelihood="ci", flip_prior=(1, 9)`` (the label-noise
  model that does not reward a clause for each acceptable demonstration it keeps; issue 31).

No template set was chosen on these files (``TEMPLATE_SETS``: by number of slots, by the
Declare language, everything). ``--add`` evaluates more settings into an earlier run's
``runs.csv`` (each run's command, date and commit listed in ``runs.txt``). Per fit: held-out
accuracy (``predict``, the Bayes decision), the MAP's own accuracy, fit seconds (one process
per fit, two at a time), the warnings it raised (counted, not silenced), and whether the MAP
equals the target on every trace up to length ``L`` over the propositions either mentions
(``L`` the longest that keeps the check under 300,000 traces; ``MAP == target``). Scarlet's
accuracy comes from ``benchmarks/RESULTS_external.csv`` (the same splits; Scarlet ran on every
6-th file of a folder), so its columns compare on those files only. Intervals: Student-t 95 %
over files.
"""

from __future__ import annotations

import argparse
import itertools
import sys
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from _common import machine_info, md_table  # noqa: E402
from _roles_report import t_interval  # noqa: E402
from external import (  # noqa: E402
    DEFAULT_DATA,
    family_of,
    file_seed,
    find_trace_files,
    quick_files,
    scarlet_subset,
    split_indices,
)
from sklearn.pipeline import make_pipeline  # noqa: E402

from bsi_sklearn import BSIClassifier  # noqa: E402
from bsi_sklearn.data.preprocessing import NegationAugmenter  # noqa: E402
from bsi_sklearn.io import read_trace_file  # noqa: E402
from bsi_sklearn.ltl import parse_ltl  # noqa: E402

__all__ = ["SETTINGS", "equal_on_short_traces", "evaluate", "summary", "main"]

SETTINGS = ("paper", "paper+negations", "unary", "declare", "catalogue", "catalogue+ci")
#: The template set of a setting (``TEMPLATE_SETS``).
SET_OF = {"unary": "unary", "declare": "declare", "catalogue": "all"}
MAX_TRACES = 300_000


def make_estimator(setting, seed):
    """The estimator a user writes for ``setting``."""
    if setting == "paper":
        return BSIClassifier(random_state=seed)
    if setting == "paper+negations":
        return make_pipeline(NegationAugmenter(), BSIClassifier(random_state=seed))
    if setting == "catalogue+ci":
        return BSIClassifier(templates="all", likelihood="ci", flip_prior=(1, 9),
                             random_state=seed)
    return BSIClassifier(templates=SET_OF[setting], random_state=seed)


def all_traces(n_props, length):
    """Every trace of ``length`` steps over ``n_props`` propositions, a (2^(n T), T, n) cube."""
    cells = n_props * length
    bits = (np.arange(2 ** cells)[:, None] >> np.arange(cells)[None, :]) & 1
    return bits.astype(bool).reshape(-1, length, n_props)


def equal_on_short_traces(a, b, max_traces=MAX_TRACES):
    """``(equal, L)``: do formulas ``a`` and ``b`` agree on every trace of 1..L steps?

    The traces are over the propositions either mentions (the others cannot change either's
    truth); ``L`` is the longest with at most ``max_traces`` traces in all (0: not checked).

    Examples
    --------
    >>> equal_on_short_traces(parse_ltl("G(!p)"), parse_ltl("!F(p)"))
    (True, 17)
    """
    names = sorted(a.atoms | b.atoms)
    total, length = 0, 0
    while total + 2 ** (len(names) * (length + 1)) <= max_traces:
        length += 1
        total += 2 ** (len(names) * length)
    for t in range(1, length + 1):
        cube = all_traces(len(names), t)
        if not np.array_equal(a.evaluate(cube, names), b.evaluate(cube, names)):
            return False, length
    return True, length


def _map_formula(estimator):
    clf = estimator[-1] if hasattr(estimator, "steps") else estimator
    # the negated columns "!p" read back as the negation of p: the same truth
    return clf.map_specification_, parse_ltl(clf.map_specification_.to_ltl())


def evaluate(path, data_dir, setting, seed=0):
    """One row: ``setting`` fitted on the training half of ``path``, scored on the rest."""
    path = Path(path)
    rel = path.resolve().relative_to(Path(data_dir).resolve())
    tf = read_trace_file(path)
    s = file_seed(rel, seed)
    train, test = split_indices(tf.y, 0.3, s)
    X_tr, y_tr = [tf.X[i] for i in train], tf.y[train]
    X_te, y_te = [tf.X[i] for i in test], tf.y[test]
    est = make_estimator(setting, s)
    t0 = time.perf_counter()
    with warnings.catch_warnings(record=True) as caught:
        # counted per fit (the "warnings" column), not printed hundreds of times
        warnings.simplefilter("always")
        est.fit(X_tr, y_tr)
    fit_s = time.perf_counter() - t0
    spec, formula = _map_formula(est)
    row = {"family": family_of(path, data_dir), "file": str(rel), "setting": setting,
           "n_props": tf.n_props, "n_train": len(train), "n_test": len(test),
           "fit_s": fit_s, "inference": (est[-1] if hasattr(est, "steps") else est).inference_,
           "warnings": "; ".join(sorted({w.category.__name__ for w in caught})),
           "accuracy": float(est.score(X_te, y_te)) if len(test) else np.nan,
           "map_accuracy": (float(np.mean(formula.evaluate(X_te) == y_te.astype(bool)))
                            if len(test) else np.nan),
           "map": spec.to_ltl(), "readable": spec.readable(),
           "target": None if tf.target is None else str(tf.target)}
    if tf.target is not None:
        row["map_equals_target"], row["checked_length"] = equal_on_short_traces(
            formula, tf.target)
    return row


def _child(conn, path, data_dir, setting):
    try:
        conn.send(evaluate(path, data_dir, setting))
    except Exception as exc:  # reported in the row, not lost with the child
        conn.send({"status": "error", "error": f"{type(exc).__name__}: {exc}"})
    conn.close()


def run_tasks(tasks, data_dir, n_jobs, timeout, verbose=True):
    """Each ``(file, setting)`` fitted in a forked child, ``n_jobs`` at a time, each stopped
    after ``timeout`` seconds (``status="timeout"``); the rows in the order of ``tasks``.

    Forked from a process whose kernels are compiled and loaded, so a child starts at once.
    """
    import multiprocessing as mp

    ctx = mp.get_context("fork")
    rows, running, queue = [None] * len(tasks), [], list(enumerate(tasks))
    done = 0
    while queue or running:
        while queue and len(running) < n_jobs:
            i, (path, setting) = queue.pop(0)
            recv, send = ctx.Pipe(duplex=False)
            proc = ctx.Process(target=_child, args=(send, path, data_dir, setting))
            proc.start()
            send.close()
            running.append((i, proc, recv, time.perf_counter()))
        time.sleep(0.02)
        for item in list(running):
            i, proc, recv, start = item
            path, setting = tasks[i]
            base = {"family": family_of(path, data_dir), "setting": setting,
                    "file": str(Path(path).resolve().relative_to(Path(data_dir).resolve()))}
            if recv.poll():
                rows[i] = dict(base, **{"status": "ok"}, **recv.recv())
            elif time.perf_counter() - start > timeout:
                proc.kill()
                rows[i] = dict(base, status="timeout", fit_s=np.nan)
            elif proc.is_alive():
                continue
            else:
                rows[i] = dict(base, status="error", error="the child died without a row")
            proc.join()
            recv.close()
            running.remove(item)
            done += 1
            if verbose:
                print(f"[{done}/{len(tasks)}] {setting} {base['file']}: {rows[i]['status']} "
                      f"{rows[i].get('fit_s', float('nan')):.1f} s", flush=True)
    return rows


def _t_interval(x):
    # "mean [low, high]" of _roles_report.t_interval (missing values left out)
    mean, low, high = t_interval(x)
    if np.isnan(mean):
        return "-"
    return f"{mean:.3f}" if np.isnan(low) else f"{mean:.3f} [{low:.3f}, {high:.3f}]"


def _median_s(d):
    # a fit past the limit counts as slower than every finished one
    return float(np.median(np.where(d["status"] == "ok", d["fit_s"], np.inf)))


def summary(df, scarlet):
    """The Markdown tables: per setting, per family, against Scarlet, paired differences.

    Accuracies are over the fits that finished; a fit stopped at the time limit is counted
    in ``timeouts`` and its file left out of that setting's means and of the pairs.
    """
    settings = [s for s in SETTINGS if s in set(df["setting"])]
    ok = df[df["status"] == "ok"]
    lines = ["## Per setting", "",
             "Each setting's files (`--every`), its finished fits' means; `x paper`: median fit "
             "time over the paper's on the same files (a timeout counts as slower than any "
             "finished fit).", ""]
    rows = []
    paper = df[df["setting"] == "paper"].set_index("file")
    for s in settings:
        d, o = df[df["setting"] == s], ok[ok["setting"] == s]
        same = paper.reindex(d["file"]).dropna(subset=["status"])
        rows.append([s, len(d), int((d["status"] == "timeout").sum()),
                     int((d["status"] == "error").sum()), _t_interval(o["accuracy"]),
                     f"{o['map_accuracy'].mean():.3f}", f"{o['map_equals_target'].mean():.3f}",
                     f"{_median_s(d):.2f}",
                     f"{_median_s(d) / max(_median_s(same), 1e-3):.0f}",
                     int((o["inference"] == "mcmc").sum()),
                     int((o["warnings"].fillna("") != "").sum())])
    lines += [md_table(["setting", "files", "timeouts", "errors", "accuracy [95 % CI]",
                        "MAP accuracy", "MAP == target", "median fit s", "x paper", "sampled",
                        "fits with warnings"], rows), ""]
    wide = ok.pivot_table(index="file", columns="setting", values="accuracy")
    rows = []
    for s in settings[1:]:
        if s not in wide or "paper" not in wide:
            continue
        diff = (wide[s] - wide["paper"]).dropna()
        rows.append([f"{s} - paper", len(diff), _t_interval(diff), f"{diff.min():.3f}",
                     int((diff < -0.01).sum()), int((diff > 0.01).sum())])
    lines += ["## Paired differences in held-out accuracy (file by file)", "",
              md_table(["difference", "files", "mean [95 % CI]", "worst", "files losing > 0.01",
                        "files gaining > 0.01"], rows), ""]
    lines += ["## Per family: accuracy (MAP == target), finished fits", ""]
    rows = []
    for fam, g in ok.groupby("family", sort=True):
        cells = []
        for s in settings:
            d = g[g["setting"] == s]
            cells.append(f"{d['accuracy'].mean():.3f} ({d['map_equals_target'].mean():.2f}; "
                         f"{len(d)})" if len(d) else "-")
        rows.append([fam, *cells])
    lines += [md_table(["family", *[f"{s} (files)" for s in settings]], rows), ""]
    sc = scarlet[scarlet["scarlet_status"].isin(["ok", "timeout"])
                 & scarlet["scarlet_accuracy"].notna()].set_index("file")["scarlet_accuracy"]
    rows = []
    for s in settings:
        d = df[(df["setting"] == s) & df["file"].isin(sc.index)]
        o = d[d["status"] == "ok"].set_index("file")
        diff = o["accuracy"] - sc.reindex(o.index)
        rows.append([s, len(d), len(o), f"{o['accuracy'].mean():.3f}",
                     f"{sc.reindex(o.index).mean():.3f}", _t_interval(diff)])
    lines += ["## Against Scarlet (the files where it gave a formula within 20 s)", "",
              md_table(["setting", "files", "finished", "BSI accuracy", "Scarlet accuracy",
                        "BSI - Scarlet [95 % CI]"], rows), ""]
    for shown in [s for s in ("unary", "catalogue") if s in settings]:
        lines += [f"## The most frequent MAP per target ({shown})", ""]
        rows = []
        for target, g in ok[ok["setting"] == shown].groupby("target", sort=True):
            top = g["readable"].value_counts()
            rows.append([f"`{target}`", len(g), f"{g['map_equals_target'].mean():.2f}",
                         f"`{top.index[0]}` ({top.iloc[0]})"])
        lines += [md_table(["target", "files", "MAP == target", "most frequent MAP"], rows), ""]
    return "\n".join(lines)


def main(argv=None):
    """Command-line entry point."""
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--data", type=Path, default=DEFAULT_DATA)
    p.add_argument("--every", type=int, default=1, help="every k-th file of each folder")
    p.add_argument("--quick", action="store_true", help="two files per folder")
    p.add_argument("--settings", nargs="+", default=list(SETTINGS), choices=SETTINGS)
    p.add_argument("--n-jobs", type=int, default=2)
    p.add_argument("--timeout", type=float, default=90.0, help="seconds per fit")
    p.add_argument("--out", type=Path, default=HERE / "external_templates")
    p.add_argument("--add", action="store_true",
                   help="add these settings' rows to the runs.csv already in --out")
    args = p.parse_args(argv)
    if not args.data.is_dir():
        print(f"skipped: {args.data} is absent (the shared benchmark files)")
        return 0
    files = find_trace_files(args.data)
    files = quick_files(files) if args.quick else sorted(scarlet_subset(files, args.every))
    tasks = list(itertools.product(files, args.settings))
    t0 = time.time()
    BSIClassifier(random_state=0).fit([np.eye(3, dtype=bool)] * 2, [1, 0])  # compile first
    rows = run_tasks(tasks, args.data, args.n_jobs, args.timeout)
    seconds = time.time() - t0
    df = pd.DataFrame(rows)
    args.out.mkdir(parents=True, exist_ok=True)
    runs = args.out / "runs.txt"
    if args.add and (args.out / "runs.csv").exists():
        old = pd.read_csv(args.out / "runs.csv")
        df = pd.concat([old[~old["setting"].isin(args.settings)], df], ignore_index=True)
    elif runs.exists():
        runs.unlink()
    df.to_csv(args.out / "runs.csv", index=False)
    scarlet = pd.read_csv(HERE / "RESULTS_external.csv")
    info = machine_info()
    command = "python benchmarks/bench_external_templates.py " + " ".join(argv or sys.argv[1:])
    with runs.open("a") as f:
        f.write(f"- `{command.strip()}`: {info['date']}, commit `{info['commit']}`, "
                f"{seconds:.0f} s ({len(files)} files x {len(args.settings)} settings, "
                f"{args.n_jobs} at a time; load average {info.get('load_average')} at the "
                "end)\n")
    text = ["# The published files as a user fits them, with and without patterns (issue 28)",
            "", "Runs:", "", runs.read_text(),
            f"Machine: {info['cpu']}, {info['usable_cores']} usable cores, "
            f"{info.get('memory_gib', '?')} GiB; Python {info['python']}, numpy "
            f"{info['numpy']}, scikit-learn {info['scikit-learn']}, numba {info['numba']}.",
            "", "Protocol: the module docstring of `benchmarks/bench_external_templates.py`. "
            "Per-fit rows: `benchmarks/external_templates/runs.csv`.", "",
            summary(df, scarlet)]
    (args.out / "README.md").write_text("\n".join(text) + "\n")
    print("\n".join(text))
    return 0


if __name__ == "__main__":
    sys.exit(main())
