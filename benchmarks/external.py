"""BSI against Scarlet on the published samples2LTL / Scarlet ``.trace`` benchmarks.

    python benchmarks/external.py                     # every file; Scarlet on a subset
    python benchmarks/external.py --quick             # two files a folder, short timeouts
    python benchmarks/external.py --no-scarlet        # BSI only
    python benchmarks/external.py --data DIR --out benchmarks/RESULTS_external.md --n-jobs 1

For every ``.trace`` file under ``--data`` (default ``../shared/benchmarks-data`` beside the
repository): a deterministic stratified split (70 % train / 30 % test, seeded by the file's
relative path), then

* **BSI**: :class:`~bsi_sklearn.data.preprocessing.NegationAugmenter` adds ``!p`` for every
  proposition (so ``G(!p)`` is reachable), candidate clauses are screened on the training
  positives (see :func:`external_bsi.select_roles`), and :class:`~bsi_sklearn.BSIClassifier`
  is fitted on the training positives and negatives: exact enumeration when the support is at most
  ``--max-exact`` hypotheses, MCMC otherwise. Reported: test accuracy (posterior vote), the MAP
  specification, its test accuracy, fit time, and when the target lies in the BSI template
  whether the MAP specification contains the target's clauses (recovery).
* **Scarlet** (Raha et al., TACAS 2022; PyPI ``scarlet-ltl``, MIT) learns from the same training
  split in a worker process (per-file timeout); its formula is parsed
  (:func:`external_scarlet.parse_scarlet_formula`) and evaluated on the test split with
  :mod:`bsi_sklearn.ltl` under Scarlet's own finite-trace semantics (strong next).

Writes a per-file CSV and a Markdown report (``benchmarks/RESULTS_external.md``). This module
holds the settings, the splits, the evaluation of a file and the run; the screening and fit of
BSI are in ``external_bsi.py``, Scarlet's formulas and worker in ``external_scarlet.py``, the
statistics and the report in ``external_report.py``.
Scarlet is installed on demand into a private directory (``--scarlet-dir``) rather than the
project's environment: its dependency ``lark`` 1.x would overwrite the ``lark`` module of
``lark-parser`` 0.12 that ``flloat`` (a test dependency of this project) needs.
"""

from __future__ import annotations

import argparse
import shlex
import sys
import tempfile
import time
import zlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pandas as pd

HERE = Path(__file__).resolve().parent
import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split

from external_bsi import NEG, fit_bsi  # noqa: E402
from external_report import summarize, write_report  # noqa: E402
from external_scarlet import (  # noqa: E402
    DEFAULT_SCARLET_DIR,
    ScarletWorker,
    ensure_scarlet,
    evaluate_scarlet_formula,
    parse_scarlet_formula,
)

from bsi_sklearn import BSIClassifier  # noqa: E402
from bsi_sklearn.io import read_trace_file  # noqa: E402

__all__ = [
    "Config",
    "DEFAULT_DATA",
    "find_trace_files",
    "family_of",
    "split_indices",
    "file_seed",
    "evaluate_file",
    "scarlet_columns",
    "scarlet_subset",
    "quick_files",
    "run_evaluation",
    "main",
]

DEFAULT_DATA = HERE.parent / ".." / "shared" / "benchmarks-data"


@dataclass
class Config:
    """Settings of one evaluation run (every field is a command-line option)."""

    test_size: float = 0.3
    seed: int = 0
    prior: str = "sets_of_chains"
    likelihood: str = "cb"
    min_support: float = 0.9
    max_globals: int = 6
    max_subtasks: int = 6
    max_exact: int = 1_000_000
    n_samples: int = 2_000
    n_chains: int = 2
    scarlet: bool = True
    scarlet_timeout: float = 20.0
    scarlet_every: int = 6
    scarlet_thres: float = 0.0
    scarlet_noisy_thres: float = 0.05
    scarlet_dir: str = str(DEFAULT_SCARLET_DIR)
    quick: bool = False
    n_jobs: int = 1
    verbose: int = 1


# -- files and splits ---------------------------------------------------------------------


def find_trace_files(data_dir):
    """Every ``.trace`` file under ``data_dir``, sorted; ``ValueError`` when there is none."""
    data_dir = Path(data_dir)
    if not data_dir.is_dir():
        raise ValueError(
            f"benchmark data directory {str(data_dir)!r} does not exist; pass --data DIR (the "
            "folder holding samples2LTL/ and scarlet/, normally ../shared/benchmarks-data)"
        )
    files = sorted(data_dir.rglob("*.trace"))
    if not files:
        raise ValueError(f"no .trace files under {str(data_dir)!r}")
    return files


def family_of(path, data_dir):
    """Benchmark family of a file: its source and folder, e.g. ``samples2LTL/perfect/absence``.

    >>> family_of(Path("d/samples2LTL/traces/finite/perfect_class/abscence/0.trace"), "d")
    'samples2LTL/perfect_class/abscence'
    >>> family_of(Path("d/scarlet/All_benchmarks/RQ2-benchmarks/Varying_form/TracesFiles/"
    ...                "f-01.trace"), "d")
    'scarlet/Varying_form'
    """
    parts = Path(path).resolve().relative_to(Path(data_dir).resolve()).parts[:-1]
    drop = {"traces", "finite", "All_benchmarks", "RQ2-benchmarks", "TracesFiles"}
    return "/".join(p for p in parts if p not in drop)


def split_indices(y, test_size=0.3, seed=0):
    """Deterministic stratified split: ``round(test_size * n_c)`` traces of each class to test.

    A class with fewer than two traces stays wholly in training (a learner cannot be scored
    on a class it never saw, and with one trace there is nothing to split); at least one trace
    of each class stays in training.

    Returns ``(train_idx, test_idx)``, sorted arrays of indices into ``y``.

    >>> tr, te = split_indices(np.array([1] * 10 + [0] * 4), 0.3, seed=0)
    >>> len(tr), len(te), int(np.sum(np.array([1] * 10 + [0] * 4)[te]))
    (10, 4, 3)
    >>> split_indices(np.array([1, 0, 0, 0]), 0.3, seed=0)[1].tolist()
    [3]
    """
    y = np.asarray(y)
    rng = np.random.default_rng(seed)
    train, test = [], []
    for c in np.unique(y):
        idx = rng.permutation(np.flatnonzero(y == c))
        n_test = 0 if len(idx) < 2 else min(int(round(test_size * len(idx))), len(idx) - 1)
        test.extend(idx[:n_test])
        train.extend(idx[n_test:])
    return np.sort(np.asarray(train, dtype=int)), np.sort(np.asarray(test, dtype=int))


def file_seed(rel_path, seed):
    """A seed per file, independent of the order and number of files evaluated."""
    return (zlib.crc32(str(rel_path).encode()) + 7919 * seed) % (2**31 - 1)


# -- one file -------------------------------------------------------------------------------


def _accuracy(pred, y):
    return float(np.mean(np.asarray(pred, dtype=bool) == np.asarray(y, dtype=bool))) if len(
        y) else float("nan")


def evaluate_file(path, data_dir, cfg, scarlet=None):
    """Evaluate BSI (and Scarlet when a :class:`ScarletWorker` is given) on one file.

    Returns one row (dict) of the per-file table.
    """
    path = Path(path)
    rel = path.resolve().relative_to(Path(data_dir).resolve())
    tf = read_trace_file(path)
    X, y = tf.X, tf.y
    seed = file_seed(rel, cfg.seed)
    train, test = split_indices(y, cfg.test_size, seed)
    X_tr, y_tr = [X[i] for i in train], y[train]
    X_te, y_te = [X[i] for i in test], y[test]
    names = [str(n) for n in tf.feature_names]
    aug_names = names + [NEG + n for n in names]
    target = tf.target
    target_spec = target.to_specification(names=aug_names) if target is not None else None
    row = {
        "family": family_of(path, data_dir), "file": str(rel), "n_props": tf.n_props,
        "trace_length": int(np.median([len(x) for x in X])),
        "n_train_pos": int(y_tr.sum()), "n_train_neg": int(len(y_tr) - y_tr.sum()),
        "n_test_pos": int(y_te.sum()), "n_test_neg": int(len(y_te) - y_te.sum()),
        "target": None if target is None else str(target),
        "in_template": target_spec is not None,
        "target_test_accuracy": (_accuracy(target.evaluate(X_te), y_te)
                                 if target is not None and len(test) else float("nan")),
        # label noise can leave few training positives that satisfy the target
        "target_train_pos_rate": (float(target.evaluate(
            [x for x, lab in zip(X_tr, y_tr) if lab == 1]).mean())
            if target is not None and y_tr.any() else float("nan")),
    }
    augmenter, clf, info = fit_bsi(X_tr, y_tr, cfg, random_state=seed)
    Xa_te = augmenter.transform(X_te) if len(test) else []
    spec = clf.map_specification_
    row.update({
        "bsi_inference": clf.inference_, "bsi_hypotheses": int(clf.n_hypotheses_),
        "bsi_globals": " ".join(info["globals"]), "bsi_subtasks": " ".join(info["subtasks"]),
        "bsi_screened_globals": info["screened_globals"],
        "bsi_screened_subtasks": info["screened_subtasks"],
        "bsi_fit_s": info["fit_s"],
        "bsi_warnings": info["warnings"], "bsi_n_warnings": info["n_warnings"],
        "bsi_train_accuracy": float(clf.score(augmenter.transform(X_tr), y_tr)),
        "bsi_accuracy": float(clf.score(Xa_te, y_te)) if len(test) else float("nan"),
        "bsi_map": spec.to_ltl(),
        "bsi_map_accuracy": (_accuracy([spec.satisfied_by(x) for x in Xa_te], y_te)
                             if len(test) else float("nan")),
        "bsi_map_probability": float(clf.posterior_.probabilities[0]),
        "mcmc_rhat": (float(clf.mcmc_diagnostics_["rhat"]) if clf.mcmc_diagnostics_
                      else float("nan")),
    })
    if target_spec is not None:
        row["recovered"] = bool(target_spec.clauses() <= spec.clauses())
        row["recovered_exactly"] = bool(target_spec == spec)
    else:
        row["recovered"] = row["recovered_exactly"] = None
    row.update({"scarlet_status": "skipped", "scarlet_formula": None,
                "scarlet_accuracy": float("nan"), "scarlet_s": float("nan")})
    if scarlet is not None:
        row.update(scarlet_columns(path, data_dir, cfg, scarlet))
    return row


# -- the run --------------------------------------------------------------------------------


def scarlet_subset(files, every):
    """Every ``every``-th file of each folder (the first included): where Scarlet runs."""
    if every <= 1:
        return set(files)
    chosen, seen = set(), {}
    for f in sorted(files):
        k = seen.get(f.parent, 0)
        if k % every == 0:
            chosen.add(f)
        seen[f.parent] = k + 1
    return chosen


def quick_files(files, per_folder=2):
    """The first ``per_folder`` files of each folder."""
    out, seen = [], {}
    for f in sorted(files):
        seen[f.parent] = seen.get(f.parent, 0) + 1
        if seen[f.parent] <= per_folder:
            out.append(f)
    return out


def _warm_up():
    """One exact and one MCMC fit, so numba compilation is not timed on the first file."""
    rng = np.random.default_rng(0)
    X = [rng.random((5, 3)) < 0.5 for _ in range(8)]
    y = np.array([1, 0] * 4)
    # a warning of these throwaway fits is shown (once), not silenced
    BSIClassifier(inference="exact", random_state=0).fit(X, y)
    BSIClassifier(inference="mcmc", n_samples=50, n_chains=1, random_state=0).fit(X, y)


def run_evaluation(files, data_dir, cfg, scarlet_files=None):
    """Evaluate every file; Scarlet on ``scarlet_files`` (all when None) if ``cfg.scarlet``.

    BSI fits run in ``cfg.n_jobs`` processes; Scarlet runs afterwards, one file at a time, in
    its worker process. Returns the per-file DataFrame.
    """
    from joblib import Parallel, delayed
    from tqdm.auto import tqdm

    files = [Path(f) for f in files]
    _warm_up()
    bar = tqdm(total=len(files), desc="BSI", disable=not cfg.verbose)
    rows = {}
    if cfg.n_jobs == 1:
        for f in files:
            rows[f] = evaluate_file(f, data_dir, cfg)
            bar.update()
    else:
        jobs = Parallel(n_jobs=cfg.n_jobs, return_as="generator")(
            delayed(evaluate_file)(f, data_dir, cfg) for f in files)
        for f, row in zip(files, jobs):
            rows[f] = row
            bar.update()
    bar.close()
    if cfg.scarlet:
        chosen = set(files) if scarlet_files is None else set(map(Path, scarlet_files))
        site = ensure_scarlet(cfg.scarlet_dir, verbose=cfg.verbose)
        worker = ScarletWorker(site, timeout=cfg.scarlet_timeout)
        try:
            for f in tqdm([f for f in files if f in chosen], desc="Scarlet",
                          disable=not cfg.verbose):
                scarlet_row = scarlet_columns(f, data_dir, cfg, worker)
                rows[f].update(scarlet_row)
        finally:
            worker.close()
    return pd.DataFrame([rows[f] for f in files])


def scarlet_columns(path, data_dir, cfg, worker):
    """Run Scarlet on the training split of a file; the ``scarlet_*`` columns of its row."""
    tf = read_trace_file(path)
    rel = Path(path).resolve().relative_to(Path(data_dir).resolve())
    X, y = tf.X, tf.y
    train, test = split_indices(y, cfg.test_size, file_seed(rel, cfg.seed))
    arrays = [np.asarray(X[i], dtype=bool) for i in train]
    # label-noise benchmarks get Scarlet's noise option: with 0 it must fit the noise
    noisy = "misclass" in family_of(path, data_dir)
    res = worker.learn([a for a, i in zip(arrays, train) if y[i] == 1],
                       [a for a, i in zip(arrays, train) if y[i] == 0], tf.n_props,
                       thres=cfg.scarlet_noisy_thres if noisy else cfg.scarlet_thres)
    out = {"scarlet_status": res["status"], "scarlet_formula": None,
           "scarlet_accuracy": float("nan"),
           "scarlet_s": res["seconds"] if res["seconds"] is not None else float("nan")}
    if res.get("error"):
        out["scarlet_error"] = res["error"]
    if res["formula"] is not None:
        names = [str(n) for n in tf.feature_names]
        formula = parse_scarlet_formula(res["formula"],
                                        names={f"v{i}": n for i, n in enumerate(names)})
        out["scarlet_formula"] = str(formula)
        if len(test):
            out["scarlet_accuracy"] = _accuracy(
                evaluate_scarlet_formula(formula, [X[i] for i in test]), y[test])
    return out


def main(argv=None):
    """Command-line entry point."""
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--data", type=Path, default=DEFAULT_DATA,
                   help="folder of the benchmark traces (default ../shared/benchmarks-data)")
    p.add_argument("--quick", action="store_true", help="two files per folder, short timeouts")
    p.add_argument("--out", type=Path, default=None,
                   help="Markdown report, the per-file CSV beside it (.csv); default "
                        "benchmarks/RESULTS_external.md, with --quick a temporary folder")
    p.add_argument("--no-scarlet", action="store_true", help="do not run Scarlet")
    p.add_argument("--n-jobs", type=int, default=1, help="BSI fits in parallel (default 1)")
    p.add_argument("--scarlet-timeout", type=float, default=None,
                   help="seconds per file (default 20, 10 with --quick)")
    p.add_argument("--scarlet-every", type=int, default=None,
                   help="run Scarlet on every k-th file of each folder (default 6, 1 with "
                        "--quick; 1 = all)")
    p.add_argument("--scarlet-thres", type=float, default=Config.scarlet_thres,
                   help="Scarlet's loss bound on noise-free files (0: separate every trace)")
    p.add_argument("--scarlet-noisy-thres", type=float, default=Config.scarlet_noisy_thres,
                   help="Scarlet's loss bound on the label-noise (*misclass*) files")
    p.add_argument("--scarlet-dir", default=str(DEFAULT_SCARLET_DIR),
                   help="where Scarlet is (or gets) installed")
    p.add_argument("--likelihood", choices=["cb", "ci", "calibrated"], default=Config.likelihood,
                   help="BSI's likelihood (default: %(default)s, the paper's)")
    p.add_argument("--max-exact", type=int, default=Config.max_exact)
    p.add_argument("--max-subtasks", type=int, default=Config.max_subtasks)
    p.add_argument("--max-globals", type=int, default=Config.max_globals)
    p.add_argument("--min-support", type=float, default=Config.min_support)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--verbose", type=int, default=1)
    args = p.parse_args(argv)
    try:
        files = find_trace_files(args.data)
    except ValueError as exc:
        p.error(str(exc))
    cfg = Config(
        seed=args.seed, likelihood=args.likelihood, min_support=args.min_support,
        max_globals=args.max_globals,
        max_subtasks=args.max_subtasks, max_exact=args.max_exact, scarlet=not args.no_scarlet,
        scarlet_timeout=args.scarlet_timeout or (10.0 if args.quick else Config.scarlet_timeout),
        scarlet_every=args.scarlet_every or (1 if args.quick else Config.scarlet_every),
        scarlet_thres=args.scarlet_thres, scarlet_noisy_thres=args.scarlet_noisy_thres,
        scarlet_dir=args.scarlet_dir, quick=args.quick,
        n_jobs=args.n_jobs, verbose=args.verbose)
    if args.quick:
        files = quick_files(files)
    if args.out is None:
        # a --quick run must not overwrite the recorded results
        args.out = (Path(tempfile.mkdtemp(prefix="bsi-external-")) / "RESULTS_external.md"
                    if args.quick else HERE / "RESULTS_external.md")
    t0 = time.perf_counter()
    df = run_evaluation(files, args.data, cfg, scarlet_subset(files, cfg.scarlet_every))
    summary = summarize(df, cfg.min_support)
    csv_path = Path(args.out).with_suffix(".csv")
    csv_path.parent.mkdir(parents=True, exist_ok=True)
    df.to_csv(csv_path, index=False)
    command = "python benchmarks/external.py " + shlex.join(sys.argv[1:] if argv is None
                                                           else list(argv))
    try:
        shown_csv = csv_path.resolve().relative_to(HERE.parent)
    except ValueError:
        shown_csv = csv_path
    write_report(df, summary, args.out, cfg, command.strip(), time.perf_counter() - t0,
                 shown_csv)
    if cfg.verbose:
        print(summary.to_string(float_format=lambda x: f"{x:.3f}"))
        print(f"wrote {args.out} and {csv_path}")
    return df, summary


if __name__ == "__main__":
    main()
