"""BSI's defaults without roles against its rows with the extractor's roles, on the study's cells.

Issue 20's large-force-exercise target: the classifier fitted as a user without an expert fits
it (no roles, every default) must be no worse than the best BSI row with the extractor's roles,
at every training size, paired on the same missions. This script recomputes only the BSI rows
of ``bsi-lfe study`` (no networks): the same repeats (missions and labels from
:func:`lfe.study.repeat_seeds`), the same training draws and model seeds per cell as
``lfe/study/__init__.py``, the same scorer (weighted F1 on the 200 fresh test missions), and
the same intervals (:func:`lfe.study.t_interval`: Student-t over repeats, paired differences
repeat by repeat). A variant whose option this version of the classifier lacks is listed as not
available. Every warning is counted per variant, none is silenced.

Run from the repository root::

    python benchmarks/bench_lfe_defaults.py                 # the study's default cells
    python benchmarks/bench_lfe_defaults.py --quick         # 2 repeats, sizes 6 and 18

Writes ``benchmarks/RESULTS_lfe_defaults.md`` and ``benchmarks/lfe_defaults/`` (``runs.csv``:
every fit; ``paired.csv``: each variant minus the best row with roles).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import warnings
from pathlib import Path

import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)
import numpy as np
import pandas as pd
from joblib import Parallel, delayed
from sklearn.metrics import f1_score

# isort: split

from _common import machine_info, md_table  # noqa: E402

from bsi_sklearn import BSIClassifier  # noqa: E402
from bsi_sklearn.model.likelihood import LIKELIHOODS  # noqa: E402
from lfe.annotate import MISSION_OBJECTIVES  # noqa: E402
from lfe.compare import BSI_ROWS  # noqa: E402
from lfe.compare import WITHOUT_ROLES as STUDY_WITHOUT_ROLES  # noqa: E402
from lfe.study import (  # noqa: E402
    derive_seed,
    draw_training_set,
    repeat_seeds,
    simulate_repeat,
    t_interval,
)

#: BSI rows with the extractor's roles (the study's fixed rows): name -> parameters.
WITH_ROLES = {name: p for name, p in BSI_ROWS.items() if name not in STUDY_WITHOUT_ROLES}
#: The study's own row of the defaults without roles, and its name here.
STUDY_DEFAULTS = {name: "no roles, defaults" for name in STUDY_WITHOUT_ROLES}
#: Fits without the extractor's roles: name -> (parameters, what they need to exist).
#: ``roles="all"`` and the CI flip prior are left out: on the extended set the first samples
#: (about 100 s a fit) and the second is over auto's work budget everywhere (MCMC), which
#: would make this run hours long; benchmarks/bench_roles.py compares them on smaller tasks.
WITHOUT_ROLES = {
    "no roles, defaults": ({}, ()),
    "no roles, roles='infer', CI": ({"roles": "infer", "likelihood": "ci"}, ("roles",)),
    "no roles, roles='infer', calibrated": ({"roles": "infer", "likelihood": "calibrated"},
                                            ("roles", "calibrated")),
}


def available(needs):
    """Whether this classifier has every option a variant needs."""
    params = BSIClassifier().get_params()
    return all(n in params or n in LIKELIHOODS for n in needs)


def variants():
    """``{name: (parameters, with_roles)}`` of the variants this version can fit."""
    out = {name: (p, True) for name, p in WITH_ROLES.items()}
    out.update({name: (p, False) for name, (p, needs) in WITHOUT_ROLES.items()
                if available(needs)})
    return out


def _fit_score(X_train, y_train, X_test, y_test, params, seed):
    """Weighted F1 on the test missions; how the fit inferred; the warnings it raised."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")  # count every warning (recorded, not silenced)
        if not np.any(y_train == 1):
            pred, how = np.zeros(len(y_test), dtype=y_test.dtype), "none"
        else:
            clf = BSIClassifier(random_state=seed, **params).fit(X_train, y_train)
            pred, how = clf.predict(X_test), clf.inference_
    # the study's scorer (lfe.compare's weighted F1 equals this)
    return f1_score(y_test, pred, average="weighted", zero_division=0), how, len(caught)


def run_repeat(repeat, config):
    """Every cell of one repeat: one row per variant, cell and objective."""
    seeds = repeat_seeds(config["seed"], repeat)
    data = simulate_repeat(n_pool=max(config["sizes"]), test_size=config["test_size"],
                           noises=config["noise"], propositions=config["propositions"], **seeds)
    n_pool = data["n_pool"]
    test = np.arange(n_pool, len(data["clean"]))
    rows = []
    for props in config["propositions"]:
        for noise in config["noise"]:
            y = data["labels"][noise]
            for n_train in config["sizes"]:
                split_seed = derive_seed(config["seed"], repeat, 2, n_train)
                model_seed = derive_seed(config["seed"], repeat, 3, n_train)
                train = draw_training_set(data["clean"], n_pool, n_train, split_seed)
                X_train = [data["props"][props][i] for i in train]
                X_test = [data["props"][props][i] for i in test]
                for name, (params, with_roles) in config["variants"].items():
                    roles = data["roles"][props] if with_roles else {}
                    for k, mo in enumerate(MISSION_OBJECTIVES):
                        start = time.perf_counter()
                        f1, how, n_warn = _fit_score(X_train, y[train, k], X_test, y[test, k],
                                                     {**roles, **params}, model_seed)
                        rows.append(dict(variant=name, repeat=repeat, propositions=props,
                                         noise=noise, n_train=n_train, objective=mo, f1=f1,
                                         inference=how, warnings=n_warn,
                                         fit_s=time.perf_counter() - start))
    return rows


def paired(runs):
    """Each variant without roles minus the best row with roles (by mean F1), per cell."""
    keys = ["propositions", "noise", "n_train", "objective"]
    wide = runs.pivot_table(index=[*keys, "repeat"], columns="variant", values="f1")
    out = []
    for key, group in wide.groupby(level=keys, sort=False):
        best = group[list(WITH_ROLES)].mean().idxmax()
        for name in wide.columns:
            if name in WITH_ROLES:
                continue
            mean, low, high = t_interval(group[name] - group[best])
            f1, f1_low, f1_high = t_interval(group[name])
            out.append(dict(zip(keys, key), variant=name, best_with_roles=best,
                            best_f1=group[best].mean(), f1=f1, f1_low=f1_low, f1_high=f1_high,
                            diff=mean, diff_low=low, diff_high=high, n_runs=len(group),
                            worse=bool(high < 0), better=bool(low > 0)))
    return pd.DataFrame(out)


def report(runs, table, config, seconds, command, source=None):
    """The Markdown of RESULTS_lfe_defaults.md (``source``: the study folder it was read from)."""
    lines = ["# BSI without roles against BSI with the extractor's roles (the study's cells)", "",
             "Generated by `benchmarks/bench_lfe_defaults.py` (issue 20's large-force-exercise "
             "target). Only BSI rows: the study's missions, training draws, model seeds, "
             "scorer and intervals (Student-t over repeats; differences paired repeat by "
             "repeat against the best of Prior 2, Prior 3 and Prior 2 CI with the extractor's "
             "roles, chosen per cell by mean F1). `*`: the interval excludes 0.", "",
             f"- Command: `{command}`",
             "- Machine: " + ", ".join(f"{k} {v}" for k, v in machine_info().items()
                                       if k in ("date", "cpu", "usable_cores", "memory_gib",
                                                "load_average", "commit")),
             f"- Run time: {seconds:.0f} s wall; {config['repeats']} repeats, sizes "
             f"{', '.join(map(str, config['sizes']))}, noise {config['noise']}, propositions "
             f"{', '.join(config['propositions'])}, {config['test_size']} test missions.", ""]
    if source is not None:
        lines += [f"Read from the study's own runs (`{source}/study_runs.csv`): its `BSI (no "
                  "roles)` row is the defaults; how each fit was inferred and the warnings are "
                  "in the study's files (`study_warnings.csv`).", ""]
    missing = [n for n, (_, needs) in WITHOUT_ROLES.items() if not available(needs)]
    if missing and source is None:
        lines += ["Not available in this version (option missing): "
                  + ", ".join(f"`{n}`" for n in missing) + ".", ""]
    if source is None:
        how = runs.groupby("variant").agg(
            fits=("f1", "size"), warnings=("warnings", "sum"),
            sampled=("inference", lambda s: int((s == "mcmc").sum())), fit_s=("fit_s", "median"))
        lines += ["## How each variant was fitted", "",
                  md_table(["variant", "fits", "sampled by MCMC", "warnings", "median fit, s"],
                           [[v, int(r.fits), int(r.sampled), int(r.warnings), f"{r.fit_s:.3f}"]
                            for v, r in how.iterrows()]), ""]
    for name in table["variant"].unique():
        part = table[table["variant"] == name]
        lines += [f"## {name} minus the best row with roles", "",
                  f"Worse in {int(part['worse'].sum())} of {len(part)} cells, better in "
                  f"{int(part['better'].sum())}.", ""]
        rows = []
        for _, r in part.iterrows():
            star = " *" if r.worse or r.better else ""
            rows.append([r.propositions, f"{r.noise:g}", int(r.n_train), r.objective,
                         f"{r.best_with_roles}: {r.best_f1:.3f}",
                         f"{r.f1:.3f} [{r.f1_low:.3f}, {r.f1_high:.3f}]",
                         f"{r['diff']:+.3f} [{r.diff_low:+.3f}, {r.diff_high:+.3f}]{star}"])
        lines += [md_table(["propositions", "noise", "missions", "objective",
                            "best with roles, F1", f"{name}, F1", "difference"], rows), ""]
    return "\n".join(lines)


def _from_study(folder):
    """A study's own runs of the rows compared here (its no-roles row renamed) and config."""
    study = pd.read_csv(folder / "study_runs.csv")
    keep = {**{n: n for n in WITH_ROLES}, **STUDY_DEFAULTS}
    runs = study[study["classifier"].isin(keep)].rename(columns={"classifier": "variant"})
    runs["variant"] = runs["variant"].map(keep)
    config = json.loads((folder / "config.json").read_text())
    return runs, config


def _write(out, argv, runs, config, start, source=None):
    """``lfe_defaults/`` (the paired table; every fit when they were fitted here) and
    ``RESULTS_lfe_defaults.md`` under ``out``; print the Markdown."""
    table = paired(runs)
    seconds = time.perf_counter() - start
    folder = out / "lfe_defaults"
    folder.mkdir(parents=True, exist_ok=True)
    if source is None:
        runs.to_csv(folder / "runs.csv", index=False)
    table.to_csv(folder / "paired.csv", index=False)
    command = "python benchmarks/bench_lfe_defaults.py " + " ".join(argv or sys.argv[1:])
    text = report(runs, table, config, seconds, command.strip(), source=source)
    (out / "RESULTS_lfe_defaults.md").write_text(text + "\n")
    print(text)
    return 0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=10)
    parser.add_argument("--sizes", default="6,12,18,36,72")
    parser.add_argument("--noise", default="0,0.04")
    parser.add_argument("--propositions", default="paper,extended")
    parser.add_argument("--test-size", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--n-jobs", type=int, default=1)
    parser.add_argument("--quick", action="store_true",
                        help="2 repeats, sizes 6 and 18, noise 0.04, paper propositions")
    parser.add_argument("--out", default=None, help="folder (default: benchmarks/)")
    parser.add_argument("--from-study", default=None, metavar="DIR",
                        help="read the BSI rows of a finished `bsi-lfe study` (its "
                             "study_runs.csv: 'BSI (no roles)' is the defaults) instead of "
                             "fitting; the other options are then ignored")
    args = parser.parse_args(argv)
    out = Path(args.out) if args.out else Path(__file__).resolve().parent
    start = time.perf_counter()
    if args.from_study:
        source = Path(args.from_study)
        runs, config = _from_study(source)
        return _write(out, argv, runs, config, start, source=source)
    if args.quick:
        args.repeats, args.sizes, args.noise, args.propositions = 2, "6,18", "0.04", "paper"
    config = dict(repeats=args.repeats, sizes=[int(s) for s in args.sizes.split(",")],
                  noise=[float(s) for s in args.noise.split(",")],
                  propositions=args.propositions.split(","), test_size=args.test_size,
                  seed=args.seed, variants=variants())
    chunks = Parallel(n_jobs=args.n_jobs)(delayed(run_repeat)(r, config)
                                          for r in range(args.repeats))
    runs = pd.DataFrame([row for chunk in chunks for row in chunk])
    return _write(out, argv, runs, config, start)


if __name__ == "__main__":
    sys.exit(main())
