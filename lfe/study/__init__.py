"""``bsi-lfe study``: BSI against the recurrent networks over training sizes, with 95 % intervals.

The paper's protocol (``bsi-lfe compare``: 24 missions, 4-fold cross-validation) is one draw:
it cannot say whether BSI beats the networks, at what data size, or by how much. The study
repeats the comparison on independently simulated datasets, at several training sizes, label
noise rates and proposition sets, scores every classifier on a large test set of fresh
missions, and reports means with 95 % intervals and the paired differences BSI minus the best
network. See :func:`study` and the README.
"""

from __future__ import annotations

import argparse
import io
import json
import os
import time
from numbers import Integral, Real
from pathlib import Path

import pandas as pd
from sklearn.utils.parallel import Parallel, delayed

from bsi_sklearn.io import write_atomic, write_files_atomic
from bsi_sklearn.param_validation import (
    NONZERO_INTEGER,
    Interval,
    Satisfies,
    StrOptions,
    check_options,
    is_satisfied,
    validate_params,
)
from lfe._settings import STUDY_DEFAULTS as DEFAULTS
from lfe._settings import STUDY_QUICK as QUICK
from lfe._workers import load_libraries
from lfe.annotate import MISSION_OBJECTIVES
from lfe.extractor import PROPOSITION_SETS
from lfe.study._cells import (
    ROWS,
    TIME_NOISE,
    bsi_settings,
    derive_seed,
    draw_training_set,
    network_settings,
    repeat_dataset,
    repeat_seeds,
    run_cell,
    search_grid,
    simulate_repeat,
)
from lfe.study._report import plot_learning_curves, study_markdown
from lfe.study._stats import paired_differences, summarise, t_interval

# The repeat's missions, the cells' training draws and seeds, and the intervals are public:
# a script that recomputes some rows of the study on its own cells (benchmarks/) needs them.
__all__ = ["DEFAULTS", "MAX_POOL", "QUICK", "TIME_NOISE", "derive_seed", "draw_training_set",
           "repeat_dataset", "repeat_seeds", "run", "simulate_repeat", "study", "t_interval"]

#: Largest training pool a repeat simulates (the largest allowed training size).
MAX_POOL = 500
_MAX_TEST = 5000


def _distinct_list(item, words):
    """A non-empty list of distinct values, each satisfying the constraint ``item``."""
    return Satisfies(lambda v: isinstance(v, list) and len(v) > 0 and len(set(v)) == len(v)
                     and all(is_satisfied(item, x) for x in v), words)


def _not_a_file(value):
    return isinstance(value, (str, os.PathLike)) and not (
        Path(value).exists() and not Path(value).is_dir())


#: The study's arguments (:mod:`bsi_sklearn.param_validation`), checked in this order before
#: anything is simulated; the command line checks its options against the same constraints.
_STUDY_CONSTRAINTS = {
    "sizes": [_distinct_list(
        Interval(Integral, 2, MAX_POOL, closed="both"),
        f"a non-empty list of distinct integers in [2, {MAX_POOL}] (a repeat simulates at most "
        f"{MAX_POOL} training missions)")],
    "repeats": [Interval(Integral, 1, None, closed="left")],
    "test_size": [Interval(Integral, 2, _MAX_TEST, closed="both")],
    "noise": [_distinct_list(
        Interval(Real, 0, 0.5, closed="both"),
        "a non-empty list of distinct numbers in [0, 0.5] (probabilities of flipping a "
        "verdict)")],
    "propositions": [_distinct_list(
        StrOptions(sorted(PROPOSITION_SETS)),
        f"a non-empty list of distinct proposition sets among {sorted(PROPOSITION_SETS)}")],
    "seed": [Interval(Integral, 0, 2**32 - 1, closed="both")],
    "n_jobs": [None, NONZERO_INTEGER],
    "out": [Satisfies(_not_a_file, "a directory, or a path where one can be made (not a file)")],
    "quick": "no_validation",  # read as a truth value
    "verbose": [Interval(Integral, 0, None, closed="left")],
}


def _listed(values):
    """``values`` as a list when it is a sequence or an iterator (left as given otherwise)."""
    if isinstance(values, (str, bytes)) or not hasattr(values, "__iter__"):
        return values
    return list(values)


def _cell_name(noise, propositions, n_train, repeat):
    return f"{propositions}_noise{noise:g}_n{n_train}_r{repeat}.json"


def _simulate(repeat, config, seeds):
    """One repeat's missions (:func:`lfe.study._cells.simulate_repeat`)."""
    load_libraries()  # this worker's later cells train networks
    return repeat, simulate_repeat(
        n_pool=max(config["sizes"]), test_size=config["test_size"], noises=config["noise"],
        propositions=config["propositions"], dataset_seed=seeds["dataset_seed"],
        label_seed=seeds["label_seed"])


def _slice(data, noise, propositions):
    """The part of a repeat's data one cell reads (less to send to a worker)."""
    return {"n_pool": data["n_pool"], "clean": data["clean"], "flight": data["flight"],
            "labels": {noise: data["labels"][noise]}, "phases": {noise: data["phases"][noise]},
            "props": {propositions: data["props"][propositions]},
            "roles": {propositions: data["roles"][propositions]}}


def _run_cell(data, repeat, noise, propositions, n_train, config, seeds):
    """One cell: draw its training set, fit and score every row; ``(cell, rows)``."""
    load_libraries()
    split_seed = derive_seed(config["seed"], repeat, 2, n_train)
    model_seed = derive_seed(config["seed"], repeat, 3, n_train)
    train = draw_training_set(data["clean"], data["n_pool"], n_train, split_seed)
    settings = {"networks": config["networks"], "bsi": config["bsi"], "grid": config["grid"]}
    start = time.perf_counter()
    rows, warned = run_cell(data, noise=noise, propositions=propositions, n_train=n_train,
                            train=train, model_seed=model_seed, settings=settings)
    cell = dict(repeat=repeat, noise=noise, propositions=propositions, n_train=n_train,
                **seeds, split_seed=split_seed, model_seed=model_seed,
                cell_s=time.perf_counter() - start)
    return cell, rows, warned


def study(*, sizes=None, repeats=None, test_size=None, noise=None, propositions=None, seed=0,
          n_jobs=None, out="study", quick=False, verbose=1, command=None):
    """Learning curves of BSI and the recurrent networks on simulated LFE missions.

    Each repeat simulates its own missions (:func:`lfe.make_lfe_dataset`, its own seed): a
    training pool of ``max(sizes)`` missions and ``test_size`` fresh test missions. For every
    training size, noise rate and proposition set (a *cell*), a training set drawn from the
    pool (stratified on the noise-free outcomes where possible) trains every row of the study
    -- LSTM, Bi-LSTM, LSTM Coupled, Bi-LSTM Coupled (the fair protocol
    :data:`baselines.FAIR_TRAINING`: early stopping picks the number of epochs on a validation
    split, then a refit on every training mission), what a practitioner would try first
    (:mod:`baselines.practitioner`: a logistic regression on plain temporal features of the
    propositions, and MiniRocket with a ridge classifier), BSI with
    Prior 2 and Prior 3, BSI with Prior 2 and the CI likelihood, BSI with
    ``GridSearchCV``-chosen hyperparameters (inner cross-validation on the training set only),
    the majority class, and the noise-free commander rule as a ceiling -- and the test set
    scores them (weighted F1 and accuracy per objective; the log loss and Brier score of
    P(label 1) for the rows whose model gives probabilities, "n/a" for the others, with the
    same intervals in ``study.csv`` and ``study.md``). Every warning raised while a row is
    fitted and scored is counted per cell and row (``study_warnings.csv``, the ``warnings``
    column of ``study_runs.csv``, ``study.md``), never silenced.

    The repeats are simulated first, then the cells run; each cell's results are written as
    soon as it finishes (``out/cells/*.json``), so an interrupted run keeps them, and a rerun
    with the same arguments and ``out`` resumes, simulating only the repeats with missing
    cells and running only those cells. The cells go through
    joblib, so ``with joblib.parallel_backend("dask"):`` spreads them over a dask cluster
    with the same results. Every seed derives from ``seed`` and is recorded.

    Parameters
    ----------
    sizes : sequence of int, default=None
        Training sizes (6, 12, 18, 36, 72; 4, 8 with ``quick``); at most :data:`MAX_POOL`.
    repeats : int, default=None
        Independent datasets (10; 2 with ``quick``).
    test_size : int, default=None
        Test missions per repeat (200; 12 with ``quick``).
    noise : sequence of float, default=None
        Label-noise rates in [0, 0.5] (0 and 0.04; 0.04 with ``quick``).
    propositions : sequence of str, default=None
        Proposition sets (paper and extended; paper with ``quick``).
    seed : int, default=0
        Root of every seed.
    n_jobs : int, default=None
        joblib workers over the simulations and the cells (``None`` or 1: sequential; -1:
        every core). The files do not depend on it.
    out : str or Path, default="study"
        Output directory.
    quick : bool, default=False
        Small defaults, small networks and short MCMC runs: a smoke test, not a result.
    verbose : int, default=1
        ``0`` silent; ``1`` a progress bar over the cells.
    command : str, default=None
        The command line recorded in ``study.md`` (built from the arguments when omitted).

    Returns
    -------
    paths : dict of str to Path
        ``study.csv``, ``study_paired.csv``, ``study_paired_log_loss.csv`` (the same
        differences of the log loss), ``study_runs.csv``, ``study_warnings.csv``,
        ``study.md``, ``config.json``, ``study_times.csv`` and one ``learning_curve_<MO>.png``
        per objective.

    Raises
    ------
    ValueError
        An :class:`~bsi_sklearn.param_validation.InvalidParameterError` naming the first bad
        argument and what it must be, before anything is simulated or written; or ``out``
        holds a study with other arguments.
    """
    base = QUICK if quick else DEFAULTS
    params = {
        "sizes": _listed(base["sizes"] if sizes is None else sizes),
        "repeats": base["repeats"] if repeats is None else repeats,
        "test_size": base["test_size"] if test_size is None else test_size,
        "noise": _listed(base["noise"] if noise is None else noise),
        "propositions": _listed(base["propositions"] if propositions is None else propositions),
        "seed": seed, "n_jobs": n_jobs, "out": out, "quick": quick, "verbose": verbose,
    }
    validate_params(params, _STUDY_CONSTRAINTS, "study")
    sizes = sorted(int(n) for n in params["sizes"])
    repeats, test_size, seed = (int(params[k]) for k in ("repeats", "test_size", "seed"))
    noise = [float(r) for r in params["noise"]]
    propositions, out = params["propositions"], Path(out)
    if command is None:
        command = (f"bsi-lfe study --sizes {','.join(map(str, sizes))} --repeats {repeats} "
                   f"--test-size {test_size} --noise {','.join(f'{r:g}' for r in noise)} "
                   f"--propositions {','.join(propositions)} --seed {seed}"
                   + (" --quick" if quick else ""))
    config = {"sizes": sizes, "repeats": repeats, "test_size": test_size, "noise": noise,
              "propositions": propositions, "seed": seed, "quick": bool(quick),
              "networks": network_settings(quick), "bsi": bsi_settings(quick),
              "grid": search_grid(quick), "rows": list(ROWS)}
    cells_dir = out / "cells"
    config_path = out / "config.json"
    stored = json.dumps(config, sort_keys=True)
    if config_path.exists():
        if json.dumps(json.loads(config_path.read_text()), sort_keys=True) != stored:
            raise ValueError(f"{out} holds a study with other arguments (see {config_path}); "
                             "give another --out or delete it")
    cells_dir.mkdir(parents=True, exist_ok=True)
    write_atomic(config_path, json.dumps(config, indent=1, sort_keys=True) + "\n")

    start = time.perf_counter()
    seeds = {r: repeat_seeds(seed, r) for r in range(repeats)}
    # repeat by repeat (an interrupted run keeps whole repeats), largest sets first
    todo = [(r, nz, ps, n) for r in range(repeats) for n in reversed(sizes) for nz in noise
            for ps in propositions if not (cells_dir / _cell_name(nz, ps, n, r)).exists()]
    need = sorted({r for r, *_ in todo})
    from tqdm.auto import tqdm

    with tqdm(total=len(need) + len(todo), desc="bsi-lfe study", unit="task",
              disable=not verbose) as bar:
        # 1. simulate the repeats that still have cells to run
        data = {}
        for r, sim in Parallel(n_jobs=n_jobs, return_as="generator_unordered")(
                delayed(_simulate)(r, config, seeds[r]) for r in need):
            data[r] = sim
            bar.update()
        # 2. the cells, each written as soon as it finishes
        outputs = Parallel(n_jobs=n_jobs, return_as="generator_unordered")(
            delayed(_run_cell)(_slice(data[r], nz, ps), r, nz, ps, n, config, seeds[r])
            for r, nz, ps, n in todo)
        for cell, rows, warned in outputs:
            path = cells_dir / _cell_name(cell["noise"], cell["propositions"],
                                          cell["n_train"], cell["repeat"])
            # a cell file is complete or absent, and a failed write leaves no temporary file
            write_atomic(path, json.dumps({"cell": cell, "rows": rows, "warnings": warned})
                         + "\n")
            bar.update()
        del data
    return _write(out, config, command, time.perf_counter() - start)


def _write(out, config, command, elapsed):
    """Gather every cell file into the tables, figures and summary."""
    records, times, warned = [], [], []
    for path in sorted((out / "cells").glob("*.json")):
        stored = json.loads(path.read_text())
        cell = stored["cell"]
        key = {k: cell[k] for k in ("repeat", "noise", "propositions", "n_train")}
        times.append({**key, "cell_s": cell["cell_s"]})
        warned += [{**key, **w} for w in stored.get("warnings", [])]
        for row in stored["rows"]:
            records.append({**{k: v for k, v in cell.items() if k != "cell_s"},
                            **{k: v for k, v in row.items() if k != "fit_s"}})
            times[-1][f"{row['classifier']} fit_s"] = row["fit_s"]
    runs = pd.DataFrame(records)
    order = {name: i for i, name in enumerate(ROWS)}
    mo = {m: i for i, m in enumerate(MISSION_OBJECTIVES)}
    ps_order = {p: i for i, p in enumerate(config["propositions"])}
    runs = runs.sort_values(
        ["propositions", "noise", "n_train", "repeat", "classifier", "objective"],
        key=lambda s: s.map(ps_order) if s.name == "propositions" else s.map(order)
        if s.name == "classifier" else s.map(mo) if s.name == "objective" else s,
    ).reset_index(drop=True)
    table = summarise(runs)
    paired = paired_differences(runs)
    # the log loss's differences, when the cells scored it (not those of an older study)
    paired_loss = (paired_differences(runs, "log_loss") if "log_loss" in runs.columns
                   else None)
    warned = pd.DataFrame(warned, columns=["repeat", "noise", "propositions", "n_train",
                                           "classifier", "category", "message", "count"])
    warned = warned.sort_values(
        ["propositions", "noise", "n_train", "repeat", "classifier", "category", "message"],
        key=lambda s: s.map(ps_order) if s.name == "propositions" else s.map(order)
        if s.name == "classifier" else s, kind="stable").reset_index(drop=True)
    paths = {"config.json": out / "config.json"}
    files = {}
    for name, frame in (("study.csv", table), ("study_paired.csv", paired),
                        ("study_paired_log_loss.csv", paired_loss),
                        ("study_runs.csv", runs), ("study_warnings.csv", warned)):
        if frame is None:
            continue
        paths[name] = out / name
        files[paths[name]] = frame.to_csv(index=False, float_format="%.6g")
    paths["study_times.csv"] = out / "study_times.csv"
    files[paths["study_times.csv"]] = pd.DataFrame(times).to_csv(index=False,
                                                                 float_format="%.3f")
    paths["study.md"] = out / "study.md"
    config = {**config, "command": command}
    files[paths["study.md"]] = study_markdown(table, paired, config, warned, paired_loss)
    import matplotlib.pyplot as plt

    for objective in MISSION_OBJECTIVES:
        fig = plot_learning_curves(table, objective)
        paths[f"learning_curve_{objective}.png"] = out / f"learning_curve_{objective}.png"
        png = io.BytesIO()
        try:
            fig.savefig(png, format="png", dpi=110, metadata={"Software": None})
        finally:
            plt.close(fig)
        files[paths[f"learning_curve_{objective}.png"]] = png.getvalue()
    # all or nothing: a failed write (read-only folder, full disk) leaves the previous
    # tables and figures whole, with no temporary file
    write_files_atomic(files)
    paths["elapsed"] = elapsed
    return paths


# ---------------------------------------------------------------------- command line
def _list(kind):
    def parse(text):
        try:
            return [kind(v) for v in text.split(",") if v.strip()]
        except ValueError:
            raise ValueError(f"cannot read {text!r} as a comma-separated list of "
                             f"{kind.__name__}") from None
    return parse


def _diff(row, prefix):
    flag = " *" if row[f"{prefix}significant"] else "  "
    return (f"{row[f'{prefix}mean']:+.3f} [{row[f'{prefix}ci_low']:+.3f}, "
            f"{row[f'{prefix}ci_high']:+.3f}]{flag}")


def run(args):
    """Run the study, write its files to ``--out`` and print the paired differences."""
    parsed = {
        "sizes": None if args.sizes is None else _list(int)(args.sizes),
        "noise": None if args.noise is None else _list(float)(args.noise),
        "propositions": (None if args.propositions is None
                         else [p.strip() for p in args.propositions.split(",") if p.strip()]),
    }
    # every option checked as typed (--sizes, not sizes) before anything is simulated
    check_options(argparse.Namespace(**{**vars(args), **parsed}), _STUDY_CONSTRAINTS)
    paths = study(**parsed, repeats=args.repeats, test_size=args.test_size, seed=args.seed,
                  n_jobs=args.n_jobs, out=args.out, quick=args.quick, verbose=args.verbose)
    paired = pd.read_csv(paths["study_paired.csv"])
    print("BSI minus the best network and minus the best baseline (networks and practitioner's "
          "rows), weighted F1, mean [95 % paired t-interval] over repeats")
    for _, r in paired.iterrows():
        print(f"  {r['bsi']:<19} {r['objective']} n={r['n_train']:<3} noise={r['noise']:<5g} "
              f"{r['propositions']:<9} vs {r['best_network']:<16} {_diff(r, '')}  vs "
              f"{r['best_baseline']:<19} {_diff(r, 'baseline_')}")
    print("(* interval excludes 0)")
    warned = pd.read_csv(paths["study_warnings.csv"])
    if warned.empty:
        print("no warning raised while fitting and scoring")
    else:
        counts = warned.groupby(["classifier", "category"], sort=False)["count"].sum()
        print(f"{int(counts.sum())} warnings raised while fitting and scoring (per row and "
              "cell in study_warnings.csv): " + "; ".join(
                  f"{name} {category} x{n}" for (name, category), n in counts.items()))
    print(f"files written to {Path(args.out)} in {paths['elapsed']:.1f} s")
    return 0
