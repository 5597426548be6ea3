"""Statistics, tables, figure and Markdown of ``bench_roles.py`` (issue 20)."""

from __future__ import annotations

import numpy as np
import pandas as pd
from _common import fmt_s, machine_info, md_table

__all__ = ["t_interval", "cell_summary", "paired_differences", "targets", "fit_counts",
           "write_outputs", "WITHIN", "NOISE_TARGET"]

WITHIN = 0.03        # no roles within 0.03 of the given roles
NOISE_TARGET = 0.97  # pick-and-place, roles given, 10 % flips, 20-40 demonstrations


def t_interval(values, confidence=0.95):
    """``(mean, low, high)``: Student-t interval of the mean of independent values.

    >>> m, lo, hi = t_interval([0.9, 1.0, 0.95])
    >>> round(m, 3), round(lo, 3), round(hi, 3)
    (0.95, 0.826, 1.074)
    >>> t_interval([0.5])[1]
    nan
    """
    from scipy import stats

    v = np.asarray(values, dtype=float)
    v = v[~np.isnan(v)]
    if len(v) == 0:
        return float("nan"), float("nan"), float("nan")
    m = float(v.mean())
    if len(v) < 2:
        return m, float("nan"), float("nan")
    half = float(stats.t.ppf(0.5 + confidence / 2, len(v) - 1) * v.std(ddof=1) / np.sqrt(len(v)))
    return m, m - half, m + half


def _fmt(m, lo, hi):
    if np.isnan(m):
        return "-"
    if np.isnan(lo):
        return f"{m:.3f} (one draw)"
    return f"{m:.3f} [{lo:.3f}, {hi:.3f}]"


def _in_chains_text(df):
    if "rule_in_chains" not in df:
        return "not recorded"
    tasks = df.drop_duplicates(["kind", "seed"])
    return ", ".join(f"{kind} {int(g['rule_in_chains'].sum())} of {len(g)} tasks"
                     for kind, g in tasks.groupby("kind", sort=False))


def _fitted(df):
    ok = df["available"].astype(bool)
    if "accuracy" in df:
        ok &= df["accuracy"].notna()
    return df[ok]


def cell_summary(df):
    """Mean accuracy and its 95 % interval over seeds, per (kind, n_train, noise, variant)."""
    rows = []
    for key, g in _fitted(df).groupby(["kind", "n_train", "noise", "variant"], sort=False):
        m, lo, hi = t_interval(g["accuracy"])
        rows.append(dict(zip(["kind", "n_train", "noise", "variant"], key),
                         seeds=len(g), mean=m, low=lo, high=hi))
    return pd.DataFrame(rows)


def paired_differences(df, baseline_roles="given"):
    """Per cell and likelihood: accuracy of each no-roles variant minus the given-roles one,
    paired by seed, with its 95 % interval over seeds."""
    fitted = _fitted(df)
    rows = []
    for (kind, n, noise, lik), g in fitted.groupby(["kind", "n_train", "noise", "likelihood"],
                                                   sort=False):
        base = g[g["roles"] == baseline_roles].set_index("seed")["accuracy"]
        for roles in ("all", "infer"):
            other = g[g["roles"] == roles].set_index("seed")["accuracy"]
            common = base.index.intersection(other.index)
            if len(common) == 0:
                continue
            d = (other[common] - base[common]).to_numpy()
            m, lo, hi = t_interval(d)
            rows.append({"kind": kind, "n_train": n, "noise": noise, "likelihood": lik,
                         "roles": roles, "seeds": len(common), "mean": m, "low": lo,
                         "high": hi})
    # no given-roles variant fitted (--only): no pairs, the same columns
    return pd.DataFrame(rows, columns=["kind", "n_train", "noise", "likelihood", "roles",
                                       "seeds", "mean", "low", "high"])


def pooled_differences(df, reference="infer/cb"):
    """Each variant minus ``reference``, over every cell: per task (kind and seed) the mean of
    the paired differences over its sizes and noise levels, then a 95 % interval over the
    tasks (independent units; the cells of one task share it)."""
    fitted = _fitted(df)
    wide = fitted.pivot_table(index=["kind", "seed", "n_train", "noise"], columns="variant",
                              values="accuracy")
    rows = []
    for variant in wide.columns:
        if variant == reference or reference not in wide.columns:
            continue
        per_task = (wide[variant] - wide[reference]).dropna().groupby(["kind", "seed"]).mean()
        m, lo, hi = t_interval(per_task.to_numpy())
        rows.append({"variant": variant, "tasks": len(per_task), "mean": m, "low": lo,
                     "high": hi})
    return pd.DataFrame(rows)


def targets(df):
    """The issue's two task targets as rows: name, wanted, measured, met (mean), met (interval).
    """
    rows = []
    diffs = paired_differences(df)
    for (roles, lik), g in diffs.groupby(["roles", "likelihood"], sort=False):
        worst = g.loc[g["mean"].idxmin()]
        ok_mean = bool((g["mean"] >= -WITHIN).all())
        ok_ci = bool((g["low"] >= -WITHIN).all())
        rows.append([f"no roles ({roles}/{lik}) within {WITHIN} of given/{lik}, every cell "
                     f"({len(g)} cells: both kinds, sizes, clean and noisy)",
                     f">= -{WITHIN}",
                     f"{int((g['mean'] >= -WITHIN).sum())}/{len(g)} cells by the mean, "
                     f"{int((g['low'] >= -WITHIN).sum())}/{len(g)} by the interval's low end; "
                     f"worst {worst['kind']} n={worst['n_train']} noise={worst['noise']}: "
                     f"{_fmt(worst['mean'], worst['low'], worst['high'])}",
                     ok_mean, ok_ci])
    summ = cell_summary(df)
    noisy = summ[(summ["kind"] == "pick_place") & (summ["noise"] > 0)
                 & summ["n_train"].isin([20, 40]) & summ["variant"].str.startswith("given/")]
    for variant, g in noisy.groupby("variant", sort=False):
        rows.append([f"pick_place, {variant}, 10 % flipped labels, 20-40 demonstrations",
                     f">= {NOISE_TARGET}",
                     "; ".join(f"n={r.n_train}: {_fmt(r.mean, r.low, r.high)}"
                               for r in g.itertuples()),
                     bool((g["mean"] >= NOISE_TARGET).all()),
                     bool((g["low"] >= NOISE_TARGET).all())])
    return rows


def fit_counts(df):
    """Per variant: fits, exact, MCMC, errors, warnings by kind, median fit seconds."""
    rows = []
    for name, g in df.groupby("variant", sort=False):
        if not g["available"].iloc[0]:
            continue
        kinds = {}
        for text in g.get("warnings", pd.Series(dtype=str)).dropna():
            for part in filter(None, str(text).split(";")):
                k, v = part.split(":")
                kinds[k] = kinds.get(k, 0) + int(v)
        inf = g.get("inference", pd.Series(dtype=str))
        errors = int(g["error"].notna().sum()) if "error" in g else 0
        rows.append([name, len(g), int((inf == "exact").sum()), int((inf == "mcmc").sum()),
                     errors, int(g["n_warnings"].fillna(0).sum()),
                     ", ".join(f"{k} {v}" for k, v in sorted(kinds.items())) or "-",
                     fmt_s(float(g["fit_s"].median())), fmt_s(float(g["fit_s"].max()))])
    return rows


def _summary_table(df, kind):
    summ = cell_summary(df)
    diffs = paired_differences(df)
    available = set(df.loc[df["available"].astype(bool), "variant"])
    # a likelihood no variant has is named once in the header, not in every row
    liks = [lik for lik in dict.fromkeys(df["likelihood"])
            if any(f"{r}/{lik}" in available for r in ("given", "all", "infer"))]
    rows = []
    for n in sorted(df["n_train"].unique()):
        for noise in sorted(df["noise"].unique()):
            for lik in liks:
                row = [str(n), f"{noise:.0%}", lik]
                for roles in ("given", "all", "infer"):
                    name = f"{roles}/{lik}"
                    s = summ[(summ["kind"] == kind) & (summ["n_train"] == n)
                             & (summ["noise"] == noise) & (summ["variant"] == name)]
                    row.append(_fmt(*s[["mean", "low", "high"]].iloc[0]) if len(s) else
                               ("not available" if name not in available else "-"))
                for roles in ("all", "infer"):
                    d = diffs[(diffs["kind"] == kind) & (diffs["n_train"] == n)
                              & (diffs["noise"] == noise) & (diffs["likelihood"] == lik)
                              & (diffs["roles"] == roles)]
                    row.append(_fmt(*d[["mean", "low", "high"]].iloc[0]) if len(d) else "-")
                rows.append(row)
    return md_table(["n", "flipped", "likelihood", "given roles", "all (no roles)",
                     "infer (no roles)", "all - given", "infer - given"], rows)


def _figure(df, path):
    import matplotlib.pyplot as plt

    summ = cell_summary(df)
    kinds = list(dict.fromkeys(df["kind"]))
    noises = sorted(df["noise"].unique())
    fig, axes = plt.subplots(len(kinds), len(noises), figsize=(5.5 * len(noises),
                                                               3.6 * len(kinds)),
                             squeeze=False, sharey=True)
    styles = {"given": "-", "all": "--", "infer": ":"}
    liks = list(dict.fromkeys(df["likelihood"]))
    colors = {lik: f"C{i}" for i, lik in enumerate(liks)}
    for i, kind in enumerate(kinds):
        for j, noise in enumerate(noises):
            ax = axes[i][j]
            sub = summ[(summ["kind"] == kind) & (summ["noise"] == noise)]
            for k, (name, g) in enumerate(sub.groupby("variant", sort=False)):
                roles, lik = name.split("/")
                g = g.sort_values("n_train")
                x = g["n_train"].to_numpy() * (1 + 0.012 * (k - 4))  # spread the bars
                err = np.vstack([g["mean"] - g["low"], g["high"] - g["mean"]])
                ax.errorbar(x, g["mean"], yerr=np.nan_to_num(err), ls=styles[roles],
                            color=colors[lik], marker="o", ms=3, capsize=2, label=name)
            ax.set_title(f"{kind}, {noise:.0%} training labels flipped")
            ax.set_xlabel("training demonstrations")
            ax.set_ylabel("accuracy on fresh demonstrations")
            ax.grid(alpha=0.3)
    axes[0][-1].legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_outputs(df, vlist, out, command, seconds, quick, settings, external=None):
    """Write ``RESULTS_roles.csv``, ``figures/roles_accuracy.png`` and ``RESULTS_roles.md``."""
    from pathlib import Path

    out = Path(out)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    csv, png, md = (out / "RESULTS_roles.csv", out / "figures" / "roles_accuracy.png",
                    out / "RESULTS_roles.md")
    df.to_csv(csv, index=False)
    _figure(df, png)
    info = machine_info()
    missing = [v for v in vlist if not v.available]
    lines = [
        "# Roles benchmark: without roles vs the task's roles (issue 20)", "",
        f"Generated by `{command}` on {info['date']} in {seconds / 60:.1f} min (commit "
        f"{info['commit']}{', --quick: a smoke run, not a result' if quick else ''}). Machine: "
        f"{info['cpu']}, {info['usable_cores']} usable cores (shared with other jobs), load "
        f"average {info.get('load_average')} at the end; Python {info['python']}, numpy "
        f"{info['numpy']}, numba {info['numba']}, scikit-learn {info['scikit-learn']}. "
        f"Per-fit rows: `{csv.name}`.", "",
        "## Protocol", "",
        "* Tasks: `bsi_sklearn.datasets.errands` (module docstring): errand tasks (2-4 "
        "partly ordered subtasks, a conditional step `door_closed -> opened_door before "
        "entered`, a global safety proposition, a proposition true throughout, 1-2 random "
        "distractors; 7-10 propositions) and pick-and-place tasks (8 propositions, "
        "`container_closed -> opened_container before placed`), drawn per seed; labels by the "
        "task's rule in plain Python; a stochastic agent that skips, reorders, forgets the "
        "conditional step and breaks safety. **The family was fixed before any result was "
        "seen and has not been tuned since**; neither BSI's template sampler nor the paper's "
        "generators are used.",
        f"* Cells: task kind x seed ({settings['seeds']} seeds: independent tasks and data) x "
        f"training size {list(settings['sizes'])} x label noise (0, 10 % of the training "
        f"labels flipped, the same training set); {settings['n_test']} fresh test "
        "demonstrations per cell scored on their true verdicts. Accuracy is `predict` (the "
        "posterior vote).",
        "* Variants: roles `given` (the task's true roles: the safety proposition as global "
        "candidate, the subtasks and the conditional step as subtasks, its condition), `all` "
        "(every proposition in every role: `roles=\"all\"`, the default before issue 20), "
        "`infer` (`roles=\"infer\"`, the default now) x "
        "likelihood `cb`, `ci`, `calibrated`, `ci+flip` (`likelihood=\"ci\"`, "
        f"`flip_prior={tuple(settings['flip_prior'])}`, fixed beforehand); every other "
        "parameter at its default (`inference=\"auto\"`), `random_state` = seed, `n_jobs=1`.",
        "* Intervals: 95 % Student-t over seeds; differences are paired by seed (same task, "
        "same training and test sets). `(one draw)` marks a single seed.",
        "* One change to the family since it was fixed, made before any full run was read: a "
        "safety violation starts after the first step, as the family's docstring said (a new "
        "test caught the agent breaking it at step 0).",
        "* Whether the task's true rule lies in the default prior's support (Prior 2 holds "
        "orders as disjoint chains; a join such as `grasped < placed` and `opened_container "
        "< placed` is outside it, for every training set): " + _in_chains_text(df) + ". "
        "Where it is not, even the given-roles fit cannot represent the rule exactly.", ""]
    if missing:
        lines += ["Not fitted (listed, with the reason): " + ", ".join(
            f"`{v.name}` ({v.reason})" for v in missing) + ".", ""]
    lines += ["## Targets", "",
              md_table(["target", "wanted", "measured", "met (mean)", "met (95 % interval)"],
                       [[*r[:3], "met" if r[3] else "**missed**",
                         "met" if r[4] else "**missed**"] for r in targets(df)]), ""]
    for kind in dict.fromkeys(df["kind"]):
        lines += [f"## Accuracy on fresh demonstrations: {kind}", "", _summary_table(df, kind),
                  ""]
    pooled = pooled_differences(df)
    if len(pooled):
        lines += ["## Every variant against inferred roles with CB (the defaults)", "",
                  "Accuracy minus `infer/cb`'s, paired on the same task, training and test "
                  "sets; per task (kind and seed) averaged over its sizes and noise levels, "
                  "then a 95 % Student-t interval over the tasks.", "",
                  md_table(["variant", "tasks", "difference"],
                           [[r.variant, int(r.tasks), _fmt(r["mean"], r.low, r.high)]
                            for _, r in pooled.iterrows()]), ""]
    lines += ["![accuracy](figures/roles_accuracy.png)", "",
              "## Inference and warnings per variant", "",
              md_table(["variant", "fits", "exact", "MCMC", "errors", "warnings",
                        "warnings by kind", "median fit", "slowest fit"], fit_counts(df)), ""]
    if external is not None:
        lines += external
    md.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return [md, csv, png]
