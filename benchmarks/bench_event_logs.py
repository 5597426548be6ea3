"""Issue 27: BSI and a practitioner's classifiers on generated labelled event logs.

    python benchmarks/bench_event_logs.py                      # the grid + recovery rows
    python benchmarks/bench_event_logs.py --quick              # 1-minute smoke run (temp folder)
    python benchmarks/bench_event_logs.py --methods logreg,tree,minirocket
    python benchmarks/bench_event_logs.py --sizes 10x100,40x1000 --timeout 600
    python benchmarks/bench_event_logs.py --scaling            # BSI fit time and memory vs size

Logs: :func:`bsi_sklearn.datasets.make_process_log` (seed 0 per size, ``--noise`` 0.05), with a
rule inside BSI's template (``template``) and one outside it (``declare``). Each log is split
once, 70/30, stratified on the observed labels (``random_state=0``); every row trains on the
same 70 % with the observed (noisy) labels and is scored on the same 30 % against the clean
labels. Rows (``docs/event-log-benchmark.md`` has the protocol): BSI with its defaults on the
"occurred" encoding (``bsi_sklearn.io.EventLogEncoder``), logistic regression on activity
counts (C by 3-fold CV), a depth-4 decision tree on activity occurrence, MiniRocket on the
encoded traces, Scarlet when installed. Every row runs in its own process
(``_event_log_child.py``) with a wall-clock timeout and an address-space limit, recorded as
``timeout`` / ``memory`` instead of hanging. Recovery rows: BSI on template logs with 200
training cases, ``rule_recovered`` (the MAP's clauses, normalised, equal to the rule's) and
``rule_disagreement`` (the fraction of fresh cases of the process on which the two differ).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
import _checkout  # noqa: F401, E402 - this checkout's packages first (benchmarks/_checkout.py)

# isort: split
os.environ.setdefault("MPLBACKEND", "Agg")

import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402
from _common import machine_info, md_table, parse_param  # noqa: E402
from _event_log_rows import FRESH_CASES, LABELS, METHODS, SCARLET_DIR_ENV, run_row  # noqa: E402
from external_scarlet import DEFAULT_SCARLET_DIR, ensure_scarlet  # noqa: E402

__all__ = ["SIZES", "QUICK_SIZES", "SCALING_ACTIVITIES", "SCALING_CASES", "TARGET_SIZE",
           "target_specs", "parse_seeds", "write_target", "recovery_specs", "write_recovery",
           "parse_sizes",
           "run_isolated", "grid_specs", "run_grid", "scaling_specs", "write_outputs",
           "write_scaling", "main"]

SIZES = ((10, 100), (20, 500), (40, 1000), (100, 2000), (100, 10_000))
QUICK_SIZES = ((10, 100), (20, 200))
RULES = ("template", "declare")
RECOVERY_TRAIN = 200
SCALING_ACTIVITIES = ((10, 1000), (20, 1000), (40, 1000), (70, 1000), (100, 1000))
SCALING_CASES = ((40, 100), (40, 1000), (40, 10_000), (40, 50_000))
QUICK_SCALING = ((10, 100), (20, 100), (10, 300))
#: The size of issue 27's 30-second target, swept over log seeds by ``--target-seeds``.
TARGET_SIZE = (40, 1000)
TARGET_S = 30.0
CHILD = HERE / "_event_log_child.py"
OUT = HERE / "event_logs"


def parse_sizes(text):
    """``"10x100,40x1000"`` -> ``((10, 100), (40, 1000))``."""
    out = []
    for part in filter(None, text.split(",")):
        a, _, c = part.partition("x")
        if not (a.isdigit() and c.isdigit()):
            raise argparse.ArgumentTypeError(f"a size is ACTIVITIESxCASES, got {part!r}")
        out.append((int(a), int(c)))
    return tuple(out)


def run_isolated(spec, timeout, memory_limit_gb, scarlet_dir=None):
    """``run_row(spec)`` in a child process; a row with status ``timeout``, ``memory`` or
    ``error: ...`` when it does not finish."""
    limit = int(memory_limit_gb * 2**30)

    def _limits():  # runs in the child before exec
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    env = dict(os.environ, **({SCARLET_DIR_ENV: str(scarlet_dir)} if scarlet_dir else {}))
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(
            [sys.executable, str(CHILD), json.dumps(dict(spec, timeout=timeout))],
            capture_output=True, text=True, timeout=timeout, preexec_fn=_limits, env=env,
            cwd=HERE.parent)
    except subprocess.TimeoutExpired:
        return dict(spec, method_label=LABELS[spec["method"]], status="timeout",
                    wall_s=time.perf_counter() - t0)
    wall = time.perf_counter() - t0
    lines = proc.stdout.strip().splitlines()
    if proc.returncode == 0 and lines:
        return dict(json.loads(lines[-1]), wall_s=wall)
    err = proc.stderr.strip()
    memory = any(k in err for k in ("MemoryError", "bad_alloc", "Cannot allocate memory",
                                    "out of memory")) or proc.returncode == -9
    status = "memory" if memory else "error: " + (err.splitlines() or ["no output"])[-1][:200]
    return dict(spec, method_label=LABELS[spec["method"]], status=status, wall_s=wall)


def grid_specs(sizes, methods, noise=0.05, seed=0, recovery=True, minirocket_max_train=5000,
               bsi=None):
    """The specs of the grid (every size x rule x method) and of the recovery rows; ``bsi``:
    more ``BSIClassifier`` parameters for the BSI rows."""
    extra = {"bsi": dict(bsi)} if bsi else {}
    specs = [dict(task="grid", n_activities=a, n_cases=c, rule=rule, noise=noise, seed=seed,
                  method=m, minirocket_max_train=minirocket_max_train,
                  **(extra if m == "bsi" else {}))
             for a, c in sizes for rule in RULES for m in methods]
    if recovery and "bsi" in methods:
        specs += recovery_specs([seed], sorted({a for a, _ in sizes}), noise, bsi)
    return specs


def run_grid(specs, timeout=300, memory_limit_gb=8.0, isolate=True, scarlet_dir=None,
             verbose=1):
    """Every spec's row (in a child process each when ``isolate``); a DataFrame."""
    rows = []
    for k, spec in enumerate(specs, 1):
        if isolate:
            row = run_isolated(spec, timeout, memory_limit_gb, scarlet_dir)
        else:
            t0 = time.perf_counter()
            row = dict(run_row(spec), wall_s=time.perf_counter() - t0)
        rows.append(row)
        if verbose:
            print(f"[{k}/{len(specs)}] {spec['n_activities']}x{spec['n_cases']} {spec['rule']} "
                  f"{spec['method']}: {row.get('status')} acc={row.get('accuracy', '-')} "
                  f"fit={row.get('fit_s', '-')}", flush=True)
    return pd.DataFrame(rows)


def scaling_specs(quick=False, noise=0.05, seed=0):
    """BSI's default fit against activities (1,000 cases) and cases (40 activities)."""
    pairs = QUICK_SCALING if quick else SCALING_ACTIVITIES + SCALING_CASES
    return [dict(task="scaling", n_activities=a, n_cases=c, rule="template", noise=noise,
                 seed=seed, method="bsi") for a, c in dict.fromkeys(pairs)]


def target_specs(seeds, noise=0.05, bsi=None):
    """BSI's default fit (``bsi``: parameters beside the defaults) on the target size's logs,
    one per seed: both rule families, and the template family's log of acceptable cases only
    (the positive-only mode)."""
    a, c = TARGET_SIZE
    return [dict(task="target", n_activities=a, n_cases=c, rule=rule, noise=noise, seed=s,
                 method="bsi", positive_only=positive, **({"bsi": dict(bsi)} if bsi else {}))
            for s in seeds for rule, positive in [(r, False) for r in RULES]
            + [("template", True)]]


def recovery_specs(seeds, activities, noise=0.05, bsi=None):
    """BSI's fit (``bsi``: parameters beside the defaults) on template logs with 200 training
    cases, one per seed and size."""
    n_test = int(round(RECOVERY_TRAIN * 0.3 / 0.7))
    return [dict(task="recovery", n_activities=a, n_cases=RECOVERY_TRAIN + n_test,
                 n_train=RECOVERY_TRAIN, rule="template", noise=noise, seed=s, method="bsi",
                 **({"bsi": dict(bsi)} if bsi else {}))
            for s in seeds for a in activities]


#: The templates of the pattern rows (issue 28): the Declare clauses of the logs' rules
#: (existence is the paper's F, strong precedence its order clause).
PATTERN_TEMPLATES = ("Absence", "AtMostOnce", "Response")
#: The pattern rows' encoding: one activity a step (Declare's reading), no negated columns.
PATTERN_ENCODER = {"encoding": "current", "negations": False}


def pattern_specs(seeds, sizes, noise=0.05, bsi=None):
    """Declare logs per seed and size: BSI's defaults, BSI with the pattern templates on the
    current-activity encoding, and the practitioner's tree and logistic regression. ``bsi``:
    more ``BSIClassifier`` parameters for both BSI rows."""
    out = []
    extra = dict(bsi or {})
    for s in seeds:
        for a, c in sizes:
            base = dict(task="patterns", n_activities=a, n_cases=c, rule="declare",
                        noise=noise, seed=s)
            out += [dict(base, method="bsi", **({"bsi": extra} if extra else {})),
                    dict(base, method="bsi",
                         bsi=dict(extra, templates=list(PATTERN_TEMPLATES)),
                         encoder=dict(PATTERN_ENCODER)),
                    dict(base, method="tree"), dict(base, method="logreg")]
    return out


def write_patterns(df, out, command, seconds):
    """``patterns.csv`` and ``patterns.md`` under ``out``: every row, and per size the mean
    accuracy of each row with its 95 % interval over the seeds and paired differences."""
    from _roles_report import t_interval

    df = _save_csv(df, out / "patterns.csv")
    df["row"] = [("BSI (templates)" if isinstance(b, (dict, str)) and "templates" in b
                  else LABELS[m]) for m, b in zip(df["method"], df.get("bsi", [None] * len(df)))]
    rows, summary = [], []
    for _, r in df.iterrows():
        rows.append([f"{r['n_activities']}x{r['n_cases']}", r["seed"], r["row"], r["status"],
                     _fmt(r.get("accuracy")), _fmt(r.get("fit_s"), 2), r.get("rule_text"),
                     r.get("map") if r["method"] == "bsi" else ""])
    for (a, c), part in df.groupby(["n_activities", "n_cases"], sort=True):
        acc = part.pivot_table(index="seed", columns="row", values="accuracy")
        for name in acc.columns:
            mean, lo, hi = t_interval(acc[name].dropna().to_numpy())
            diff = (acc["BSI (templates)"] - acc[name]).dropna().to_numpy()
            dm, dlo, dhi = t_interval(diff) if name != "BSI (templates)" else (0, 0, 0)
            t = pd.to_numeric(part.loc[part["row"] == name, "fit_s"], errors="coerce")
            summary.append([f"{a}x{c}", name, len(acc[name].dropna()),
                            f"{mean:.3f} [{lo:.3f}, {hi:.3f}]",
                            "" if name == "BSI (templates)"
                            else f"{dm:+.3f} [{dlo:+.3f}, {dhi:+.3f}]",
                            _fmt(t.median(), 1), _fmt(t.max(), 1)])
    text = ["# Declare logs with pattern clauses (issues 27 and 28)", "",
            *_header(command, seconds),
            "Each log: `make_process_log(a, c, \"declare\", noise=0.05, random_state=seed)` "
            "(a rule of one or two Declare clauses: existence, absence, at most once, "
            "precedence, response), 70 % of the cases to train, accuracy on the rest against "
            "the clean labels, each row in its own process. *BSI (templates)*: "
            f"`EventLogEncoder({', '.join(f'{k}={v!r}' for k, v in PATTERN_ENCODER.items())})` "
            f"and `BSIClassifier(templates={list(PATTERN_TEMPLATES)}, random_state=0)`, "
            "every other parameter a default; *BSI (defaults)*: the default encoder and "
            "classifier. Intervals: 95 % t intervals over the logs (seeds); the difference is "
            "BSI (templates) minus the row, paired by log.", "",
            md_table(["size", "row", "logs", "mean accuracy [95 %]",
                      "BSI (templates) - row [95 %]", "median fit s", "max fit s"], summary), "",
            md_table(["size", "seed", "row", "status", "accuracy", "fit s", "rule", "MAP"],
                     rows), ""]
    (out / "patterns.md").write_text("\n".join(text))
    return [out / "patterns.csv", out / "patterns.md"]


def _save_csv(df, path):
    # The rows in COLUMNS' order (then the rest) written to path; returns them.
    path.parent.mkdir(parents=True, exist_ok=True)
    df = df.reindex(columns=COLUMNS + [c for c in df.columns if c not in COLUMNS])
    df.to_csv(path, index=False)
    return df


def write_recovery(df, out, command, seconds):
    """``recovery.csv`` and ``recovery.md`` under ``out``: every row and a summary per size."""
    df = _save_csv(df, out / "recovery.csv")
    rows, summary = [], []
    for _, r in df.iterrows():
        rows.append([r["n_activities"], r["seed"], r["status"], _fmt(r.get("accuracy")),
                     _fmt(r.get("fit_s"), 2), _fmt(r.get("rule_recovered")),
                     _fmt(r.get("rule_disagreement"), 4), r.get("rule_text"), r.get("map")])
    for a, part in df.groupby("n_activities", sort=True):
        ok = part[part["status"] == "ok"]
        dis = pd.to_numeric(ok["rule_disagreement"], errors="coerce")
        summary.append([a, len(part), len(ok), int(ok["rule_recovered"].astype(bool).sum()),
                        int((dis == 0).sum()), _fmt(dis.median(), 4), _fmt(dis.max(), 4),
                        _fmt(pd.to_numeric(ok["fit_s"]).median(), 1)])
    params = df["hyper"].dropna().iloc[0] if df["hyper"].notna().any() else "defaults"
    text = ["# Rule recovery from 200 training cases (issue 27)", "",
            *_header(command, seconds),
            f"Each row: `BSIClassifier` ({params}) on `make_process_log(a, "
            f"{RECOVERY_TRAIN + int(round(RECOVERY_TRAIN * 0.3 / 0.7))}, \"template\", "
            f"noise=0.05, random_state=seed)`, {RECOVERY_TRAIN} training cases, in its own "
            "process. `same clauses`: the MAP's normalised clauses equal the rule's; "
            f"`MAP != rule`: the fraction of {FRESH_CASES:,} fresh cases of the same process on "
            "which the MAP and the rule disagree (0: below 0.0006 at 95 %). A clause that every "
            "case of the process keeps cannot be told from its absence by any log.", "",
            md_table(["activities", "logs", "fitted", "same clauses", "MAP != rule: none",
                      "median MAP != rule", "max MAP != rule", "median fit s"], summary), "",
            md_table(["activities", "seed", "status", "accuracy", "fit s", "same clauses",
                      "MAP != rule", "rule", "MAP"], rows), ""]
    (out / "recovery.md").write_text("\n".join(text))
    return [out / "recovery.csv", out / "recovery.md"]


def parse_seeds(text):
    """``"0-9"`` or ``"0,3,5"`` as a list of ints."""
    if "-" in text:
        lo, hi = (int(x) for x in text.split("-", 1))
        return list(range(lo, hi + 1))
    return [int(x) for x in text.split(",") if x]


def write_target(df, out, command, seconds):
    """``target.csv`` and ``target.md`` under ``out``: every seed's row and a summary."""
    df = _save_csv(df, out / "target.csv")
    rows, summary = [], []
    positive = df.get("positive_only", pd.Series(False, index=df.index))
    df["log"] = [r + (", positive-only" if isinstance(p, (bool, np.bool_)) and p else "")
                 for r, p in zip(df["rule"], positive)]
    for _, r in df.iterrows():
        rows.append([r["log"], r["seed"], r["status"], _fmt(r.get("accuracy")),
                     _fmt(r.get("fit_s"), 2), _fmt(r.get("peak_rss_mib"), 0), r.get("inference")])
    for rule, part in df.groupby("log", sort=False):
        t = pd.to_numeric(part["fit_s"], errors="coerce").where(part["status"] == "ok")
        summary.append([rule, len(part), int((t <= TARGET_S).sum()), _fmt(t.median(), 1),
                        _fmt(t.max(), 1),
                        _fmt(pd.to_numeric(part["peak_rss_mib"], errors="coerce").max(), 0)])
    a, c = TARGET_SIZE
    params = df["hyper"].dropna().iloc[0] if df["hyper"].notna().any() else "defaults"
    text = [f"# Issue 27's time target over log seeds: {a} activities x {c:,} cases", "",
            *_header(command, seconds),
            f"Each row: `BSIClassifier` ({params}) on `make_process_log({a}, {c}, "
            "rule, noise=0.05, random_state=seed)` (positive-only: `positive_only=True`, "
            "every case labelled acceptable, the fit on positives only; accuracy against the "
            "clean labels), 70 % of the cases, in its own process; "
            f"target: fit <= {TARGET_S:.0f} s and <= 2 GB.", "",
            md_table(["log", "logs", f"fits <= {TARGET_S:.0f} s", "median fit s", "max fit s",
                      "max peak MiB"], summary), "",
            md_table(["log", "seed", "status", "accuracy", "fit s", "peak MiB", "engine"],
                     rows), ""]
    (out / "target.md").write_text("\n".join(text))
    return [out / "target.csv", out / "target.md"]


def _lscpu_model():
    try:
        out = subprocess.run(["lscpu"], capture_output=True, text=True, timeout=10).stdout
    except (OSError, subprocess.SubprocessError):
        return None
    for line in out.splitlines():
        if line.startswith("Model name:"):
            return line.split(":", 1)[1].strip()
    return None


def _fmt(x, digits=3):
    if x is None or (isinstance(x, float) and not np.isfinite(x)):
        return "-"
    if isinstance(x, (bool, np.bool_)):
        return "yes" if x else "no"
    if isinstance(x, (float, np.floating)):
        return f"{x:.{digits}f}"
    return str(x)


COLUMNS = ["task", "n_activities", "n_cases", "rule", "method", "method_label", "status",
           "n_train", "n_test", "accuracy", "f1_weighted", "fit_s", "encode_s", "wall_s",
           "peak_rss_mib", "rule_recovered", "rule_disagreement", "hyper", "encoding",
           "inference", "map", "rule_text", "noise", "seed", "train_positive", "test_positive"]


def _table(df):
    rows = []
    for _, r in df.iterrows():
        rows.append([r["task"], f"{r['n_activities']}x{r['n_cases']}", r["rule"],
                     r["method_label"], r["status"], _fmt(r.get("accuracy")),
                     _fmt(r.get("f1_weighted")), _fmt(r.get("fit_s"), 2),
                     _fmt(r.get("peak_rss_mib"), 0), _fmt(r.get("rule_recovered")),
                     _fmt(r.get("rule_disagreement"), 4)])
    return md_table(["task", "activities x cases", "rule", "row", "status", "accuracy",
                     "weighted F1", "fit s", "peak MiB", "rule recovered",
                     "MAP != rule, fresh cases"], rows)


def _header(command, seconds):
    info = machine_info()
    return [f"Command: `{command}`", "",
            f"Machine: {_lscpu_model() or info['cpu']}, {info['usable_cores']} usable cores, "
            f"{info.get('memory_gib', '?')} GiB; Python {info['python']}, numpy "
            f"{info['numpy']}, scikit-learn {info['scikit-learn']}, numba {info['numba']}.",
            f"Date: {info['date']}. Commit: `{info['commit']}`. Took {seconds:.0f} s.", ""]


def write_outputs(df, out, results, command, seconds, settings):
    """``event_logs.csv``, ``event_logs.md`` under ``out`` and ``results`` (RESULTS_*.md)."""
    out.mkdir(parents=True, exist_ok=True)
    df = df.reindex(columns=COLUMNS + [c for c in df.columns if c not in COLUMNS])
    df.to_csv(out / "event_logs.csv", index=False)
    table = _table(df)
    (out / "event_logs.md").write_text(table + "\n")
    text = ["# Event-log benchmark (issue 27)", "", *_header(command, seconds),
            "Protocol: `docs/event-log-benchmark.md`. Settings: "
            + ", ".join(f"{k}={v}" for k, v in settings.items()) + ".", "",
            "Accuracy and weighted F1 on the 30 % test cases against their clean labels; fit "
            "time in the child process (features and fit; BSI: the fit after encoding); peak "
            "memory is the child's `ru_maxrss` (interpreter, imports, log and fit).", "",
            table, ""]
    recovery = df[df["task"] == "recovery"]
    if len(recovery):
        text += ["Recovery rows: BSI on `rule=\"template\"` logs with 200 training cases; "
                 "`rule recovered` when the MAP's clauses, normalised "
                 "(`_event_log_rows.normalised_clauses`), equal the hidden rule's. "
                 f"`MAP != rule, fresh cases`: the fraction of {FRESH_CASES:,} fresh cases of "
                 "the same process on which the MAP and the rule disagree "
                 "(`_event_log_rows.rule_disagreement`; 0 of 5,000: below 0.0006 at 95 %): "
                 "a clause every case of the process keeps cannot be told from its absence "
                 "by any log.", ""]
    results.write_text("\n".join(text))
    return [out / "event_logs.csv", out / "event_logs.md", results]


def write_scaling(df, out, command, seconds):
    """``scaling.csv``, ``scaling.md`` and ``scaling.png`` under ``out``."""
    import matplotlib.pyplot as plt

    out.mkdir(parents=True, exist_ok=True)
    df = df.reindex(columns=COLUMNS + [c for c in df.columns if c not in COLUMNS])
    df.to_csv(out / "scaling.csv", index=False)
    fig, axes = plt.subplots(2, 2, figsize=(9, 6.5))
    ok = df[df["status"] == "ok"]
    groups = [("n_activities", ok[ok["n_cases"] == ok["n_cases"].max()] if len(ok) else ok,
               "activities (cases fixed)"),
              ("n_cases", ok[ok["n_activities"] == 40] if len(ok) else ok,
               "cases (40 activities)")]
    for col, (x, sub, label) in enumerate(groups):
        for row, (y, ylab) in enumerate([("fit_s", "fit time (s)"),
                                         ("peak_rss_mib", "peak memory (MiB)")]):
            ax = axes[row, col]
            sub = sub.sort_values(x)
            ax.plot(sub[x], sub[y], "o-")
            ax.set_xscale("log")
            ax.set_xlabel(label)
            ax.set_ylabel(ylab)
            ax.grid(True, which="both", alpha=0.3)
            if sub.empty:
                ax.text(0.5, 0.5, "no finished fit", ha="center", transform=ax.transAxes)
    fig.suptitle("BSI defaults on generated event logs (each fit in its own process)")
    fig.tight_layout()
    fig.savefig(out / "scaling.png", dpi=110)
    plt.close(fig)
    table = md_table(["activities x cases", "status", "fit s", "peak MiB"],
                     [[f"{r['n_activities']}x{r['n_cases']}", r["status"],
                       _fmt(r.get("fit_s"), 2), _fmt(r.get("peak_rss_mib"), 0)]
                      for _, r in df.iterrows()])
    (out / "scaling.md").write_text("\n".join(["# BSI scaling on event logs", "",
                                               *_header(command, seconds), table, "",
                                               "![scaling](scaling.png)", ""]))
    return [out / "scaling.csv", out / "scaling.md", out / "scaling.png"]


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help="sizes 10x100 and 20x200, 60 s timeout; a temporary folder "
                             "unless --out is given")
    parser.add_argument("--sizes", type=parse_sizes, default=None,
                        help="ACTIVITIESxCASES,... (default 10x100,20x500,40x1000,100x2000,"
                             "100x10000)")
    parser.add_argument("--methods", default=",".join(METHODS),
                        help=f"rows to run, among {','.join(METHODS)}")
    parser.add_argument("--timeout", type=float, default=None,
                        help="seconds per row (default 300; --quick 60)")
    parser.add_argument("--memory-limit", type=float, default=8.0, help="GiB per row")
    parser.add_argument("--noise", type=float, default=0.05, help="label noise of the logs")
    parser.add_argument("--seed", type=int, default=0, help="random_state of the logs")
    parser.add_argument("--no-recovery", action="store_true", help="no recovery rows")
    parser.add_argument("--minirocket-max-train", type=int, default=5000,
                        help="MiniRocket is skipped above this many training cases")
    parser.add_argument("--scaling", action="store_true",
                        help="BSI fit time and peak memory against activities and cases")
    parser.add_argument("--target-seeds", type=parse_seeds, default=None,
                        help=f"BSI on {TARGET_SIZE[0]}x{TARGET_SIZE[1]} logs of these seeds "
                             "(0-9 or 0,3,5), both rules: the 30 s target's spread")
    parser.add_argument("--recovery-seeds", type=parse_seeds, default=None,
                        help="only the recovery rows, for these seeds (0-4 or 0,3), at the "
                             "activities of --sizes (default 10, 20, 40, 100)")
    parser.add_argument("--pattern-seeds", type=parse_seeds, default=None,
                        help="Declare logs of these seeds at --sizes (default 20x500,40x1000): "
                             "BSI with and without pattern templates, tree, logistic "
                             "regression")
    parser.add_argument("--likelihood", choices=["cb", "ci", "calibrated"], default=None,
                        help="with --recovery-seeds: BSI's likelihood (default: its default)")
    parser.add_argument("--bsi", action="append", type=parse_param, default=[],
                        metavar="NAME=VALUE",
                        help="one more BSIClassifier parameter of the BSI rows "
                             "(a Python literal, e.g. p_global=0.5); repeatable")
    parser.add_argument("--scarlet-dir", default=str(DEFAULT_SCARLET_DIR))
    parser.add_argument("--install-scarlet", action="store_true",
                        help="pip-install scarlet-ltl into --scarlet-dir first (network)")
    parser.add_argument("--out", default=None, help="folder of the CSV and tables")
    args = parser.parse_args(argv)
    methods = [m for m in args.methods.split(",") if m]
    unknown = sorted(set(methods) - set(METHODS))
    if unknown:
        parser.error(f"--methods: unknown {unknown}; choose among {list(METHODS)}")
    out = Path(args.out) if args.out else (
        Path(tempfile.mkdtemp(prefix="bench_event_logs_")) if args.quick else OUT)
    results = HERE / "RESULTS_event_logs.md" if out == OUT else out / "RESULTS_event_logs.md"
    timeout = args.timeout or (60.0 if args.quick else 300.0)
    if args.install_scarlet:
        ensure_scarlet(args.scarlet_dir)
    command = "python benchmarks/bench_event_logs.py " + " ".join(argv)
    t0 = time.perf_counter()
    if args.target_seeds is not None:
        df = run_grid(target_specs(args.target_seeds, args.noise, dict(args.bsi) or None),
                      timeout, args.memory_limit)
        paths = write_target(df, out, command.strip(), time.perf_counter() - t0)
    elif args.pattern_seeds is not None:
        sizes = args.sizes or [(20, 500), (40, 1000)]
        df = run_grid(pattern_specs(args.pattern_seeds, sizes, args.noise,
                                    dict(args.bsi) or None), timeout,
                      args.memory_limit)
        paths = write_patterns(df, out, command.strip(), time.perf_counter() - t0)
    elif args.recovery_seeds is not None:
        activities = sorted({a for a, _ in args.sizes}) if args.sizes else [10, 20, 40, 100]
        bsi = dict(args.bsi, **({"likelihood": args.likelihood} if args.likelihood else {}))
        df = run_grid(recovery_specs(args.recovery_seeds, activities, args.noise, bsi or None),
                      timeout, args.memory_limit)
        paths = write_recovery(df, out, command.strip(), time.perf_counter() - t0)
    elif args.scaling:
        df = run_grid(scaling_specs(args.quick, args.noise, args.seed), timeout,
                      args.memory_limit)
        paths = write_scaling(df, out, command.strip(), time.perf_counter() - t0)
    else:
        sizes = args.sizes or (QUICK_SIZES if args.quick else SIZES)
        specs = grid_specs(sizes, methods, args.noise, args.seed, not args.no_recovery,
                           args.minirocket_max_train, dict(args.bsi) or None)
        df = run_grid(specs, timeout, args.memory_limit, scarlet_dir=args.scarlet_dir)
        settings = {"sizes": ",".join(f"{a}x{c}" for a, c in sizes), "noise": args.noise,
                    "seed": args.seed, "timeout_s": timeout,
                    "memory_limit_gib": args.memory_limit, "methods": ",".join(methods)}
        paths = write_outputs(df, out, results, command.strip(), time.perf_counter() - t0,
                              settings)
    for p in paths:
        print(f"wrote {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
