"""Issue 20 on the published samples2LTL / Scarlet files: a user's fit against the screened one.

    python benchmarks/bench_roles.py --external          # the task cells, then this part
    python benchmarks/roles_external.py --every 4        # this part alone, printed

For every ``.trace`` file (``../shared/benchmarks-data``; skipped with a note when absent), the
split of ``external.py`` (stratified 70 / 30, seeded by the file's path), then two fits on the
training part, scored on the test part:

* **as a user fits**: ``NegationAugmenter`` and ``BSIClassifier(random_state=seed, n_jobs=1)``
  with every other parameter at its default (no screening; whatever roles and likelihood the
  installed classifier defaults to). Every warning is recorded and counted;
* **screened**: the project's own protocol, ``external_bsi.fit_bsi`` with ``external.Config``'s
  defaults (clauses screened on the training positives, at most 6 globals and 6 subtasks, CB).

Files are split into those the project has *seen*, meaning a test or a development benchmark of
the repository fits BSI on them one by one (``tests/test_default_map_on_published_files.py``,
``tests/benchmarks/test_external_eval.py``, ``bench_mcmc_mixing.py``, ``external.py --quick``),
and the rest. Every file was scored once by ``external.py`` (RESULTS_external.md), so the
screened protocol's settings were chosen with the aggregate over all files in view: "not seen"
means not looked at one by one, not never evaluated.
"""

from __future__ import annotations

import argparse
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

from _common import md_table  # noqa: E402
from _roles_report import t_interval  # noqa: E402
from external import (  # noqa: E402
    DEFAULT_DATA,
    Config,
    family_of,
    file_seed,
    quick_files,
    scarlet_subset,
    split_indices,
)
from external_bsi import fit_bsi  # noqa: E402

from bsi_sklearn import BSIClassifier  # noqa: E402
from bsi_sklearn.data.preprocessing import NegationAugmenter  # noqa: E402
from bsi_sklearn.io import load_trace_file  # noqa: E402

__all__ = ["seen_files", "evaluate_file", "run_external", "TARGET_UNSEEN"]

TARGET_UNSEEN = 0.88


def seen_files(data):
    """The files a test or development benchmark of the repository fits BSI on, one by one."""
    data = Path(data)
    every = sorted(data.rglob("*.trace"))
    seen = set(every[::40])                               # test_default_map_on_published_files
    samples = data / "samples2LTL" / "traces" / "finite"
    scarlet = data / "scarlet" / "All_benchmarks" / "RQ2-benchmarks" / "Varying_form"
    seen |= {samples / "perfect_class" / "universality" / "0000.trace",   # test_external_eval
             samples / "perfect_class" / "abscence" / "0000.trace",
             samples / "perfect_class" / "existence" / "0000.trace",
             scarlet / "TracesFiles" / "f-01-nw-100-ml-10-0.trace",
             scarlet / "TracesFiles" / "f-03-nw-100-ml-10-0.trace"}
    s2l = sorted(Path(data, "samples2LTL").rglob("*.trace"))
    props = {f: load_trace_file(f)[0][0].shape[1] for f in s2l}
    seen |= {f for f in scarlet_subset(s2l, 20) if props[f] <= 3}   # bench_mcmc_mixing
    seen |= set([f for f in s2l if props[f] == 7][:4])
    seen |= set(quick_files(every))                                  # external.py --quick
    return {f.resolve() for f in seen}


def _user_fit(X_tr, y_tr, X_te, y_te, seed):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")  # counted, not silenced
        t0 = time.perf_counter()
        aug = NegationAugmenter().fit(X_tr)
        clf = BSIClassifier(random_state=seed, n_jobs=1).fit(aug.transform(X_tr), y_tr)
        fit_s = time.perf_counter() - t0
    kinds = sorted({w.category.__name__ for w in caught})
    acc = float(clf.score(aug.transform(X_te), y_te)) if len(y_te) else float("nan")
    return {"user_accuracy": acc, "user_inference": clf.inference_, "user_fit_s": fit_s,
            "user_warnings": len(caught), "user_warning_kinds": ";".join(kinds),
            "user_map": clf.map_specification_.to_ltl()}


def evaluate_file(path, data, seen):
    """Both fits on one file's split; one row."""
    path = Path(path)
    rel = path.resolve().relative_to(Path(data).resolve())
    X, y, _ = load_trace_file(path)
    y = np.asarray(y)
    seed = file_seed(rel, 0)
    tr, te = split_indices(y, 0.3, seed)
    X_tr, y_tr, X_te, y_te = [X[i] for i in tr], y[tr], [X[i] for i in te], y[te]
    row = {"file": str(rel), "family": family_of(path, data), "seen": path.resolve() in seen,
           "n_props": X[0].shape[1], "n_test": len(te)}
    row.update(_user_fit(X_tr, y_tr, X_te, y_te, seed))
    t0 = time.perf_counter()
    aug, clf, _ = fit_bsi(X_tr, y_tr, Config(), random_state=seed)
    row["screened_fit_s"] = time.perf_counter() - t0
    row["screened_accuracy"] = (float(clf.score(aug.transform(X_te), y_te)) if len(te)
                                else float("nan"))
    return row


def _line(df, label):
    cells = [label, str(len(df))]
    for col in ("user_accuracy", "screened_accuracy"):
        cells.append("{:.3f} [{:.3f}, {:.3f}]".format(*t_interval(df[col])))
    cells.append("{:.3f} [{:.3f}, {:.3f}]".format(
        *t_interval(df["user_accuracy"] - df["screened_accuracy"])))
    return cells


def run_external(data=None, quick=False, every=1, verbose=1, out=HERE):
    """Every ``every``-th file (one a folder with ``quick``); the Markdown lines of the part.

    The per-file rows go to ``out/RESULTS_roles_external.csv``.
    """
    import pandas as pd
    from tqdm.auto import tqdm

    data = Path(data) if data is not None else DEFAULT_DATA
    lines = ["## Published benchmark files: as a user fits vs the screened protocol", ""]
    if not data.is_dir():
        return lines + [f"Skipped: `{data}` is absent.", ""]
    files = sorted(data.rglob("*.trace"))
    files = quick_files(files, 1) if quick else files[::every]
    seen = seen_files(data)
    t0 = time.perf_counter()
    rows = [evaluate_file(f, data, seen)
            for f in tqdm(files, desc="published files", disable=not verbose)]
    df = pd.DataFrame(rows)
    df.to_csv(Path(out) / "RESULTS_roles_external.csv", index=False)
    ok = df.dropna(subset=["user_accuracy", "screened_accuracy"])
    table = [_line(ok, "all")]
    for flag, label in ((True, "seen"), (False, "not seen")):
        part = ok[ok["seen"] == flag]
        if len(part):
            table.append(_line(part, label))
    unseen = ok[~ok["seen"]]["user_accuracy"].mean() if (~ok["seen"]).any() else float("nan")
    at_least = ok["user_accuracy"].mean() >= ok["screened_accuracy"].mean()
    lines += [
        __doc__.split("\n\n", 2)[2].strip(), "",
        f"{len(files)} files ({'--quick: one a folder' if quick else f'every {every}-th'}), "
        f"{len(ok)} with a test split; {time.perf_counter() - t0:.0f} s. Mean test accuracy "
        "per file and its 95 % interval over files (user minus screened paired by file). "
        f"User fits: inference {df['user_inference'].value_counts().to_dict()}, "
        f"{int(df['user_warnings'].sum())} warnings on {int((df['user_warnings'] > 0).sum())} "
        "files. Per-file rows: `RESULTS_roles_external.csv`.", "",
        md_table(["files", "n", "as a user fits", "screened", "user - screened"], table), "",
        f"Targets: user fit >= screened on average: "
        f"{'met' if at_least else '**missed**'} (means, see the interval above);"
        f" user fit >= {TARGET_UNSEEN} on files not seen: {unseen:.3f} "
        f"({'met' if unseen >= TARGET_UNSEEN else '**missed**'}).", ""]
    return lines


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--data", default=None)
    p.add_argument("--every", type=int, default=1)
    p.add_argument("--quick", action="store_true")
    p.add_argument("--verbose", type=int, default=1)
    p.add_argument("--out", default=str(HERE))
    a = p.parse_args()
    print("\n".join(run_external(a.data, a.quick, a.every, a.verbose, a.out)))
